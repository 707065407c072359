//! The contact problem of one time step (docs/scheme.md): a strictly convex QP with bounds on m
//! linear values of the unknowns,
//!
//! min ½ xᵀ A x − bᵀ x   subject to   lo_i ≤ B_i x ≤ hi_i   (i = 0..m),
//!
//! with A sparse symmetric positive definite, B the rows of the contact points ([`rows`]: at a
//! mesh vertex the row picks its value dof, so that the constraints are bounds on those
//! unknowns; at a stop's own point the row is the element's basis there), and any lo_i = −∞ or
//! hi_i = +∞ (an absent obstacle). The KKT conditions read
//!
//! A x = b + Bᵀ λ,  λ_i ≥ 0 where B_i x = lo_i (the lower obstacle pushes up),
//! λ_i ≤ 0 where B_i x = hi_i, λ_i = 0 where lo_i < B_i x < hi_i.
//!
//! Two solvers, one exact each:
//! * [`active_set`]: the fast path, in the Delassus space y = B x. Given the unconstrained solution
//!   x* = A⁻¹ b, y* = B x* and W = B A⁻¹ Bᵀ, it solves the box LCP y = y* + W λ by a primal–dual
//!   active-set (semismooth Newton) method warm-started from the previous step (or from a
//!   first guess of the new active set, [`first_guess`]), with a primal active-set safeguard. Each iteration solves the subproblem of one working set, either on W
//!   ([`delassus`]: columns of W, precomputed or cached within a memory budget, and the factor of
//!   the active block updated as indices enter and leave, [`block_factor`]; the caller then sets
//!   x = x* + A⁻¹ Bᵀ λ) or in the primal variables with the active dofs eliminated from a sparse A
//!   ([`eliminated`], which returns x itself). [`sparse_contact`] puts the factor of A, the cached
//!   columns, the elimination and the rule that chooses between them in one object for a sparse
//!   backend.
//! * [`clarabel`]: the reference, the full primal QP handed to the Clarabel interior-point solver with
//!   tightened tolerances ([`clarabel::reference_settings`]), then polished on its active set with a
//!   KKT certificate ([`clarabel::polish`]).

pub mod active_set;
pub mod block_factor;
pub mod cholesky;
pub mod clarabel;
pub mod delassus;
pub mod eliminated;
pub mod first_guess;
pub mod ordering;
pub mod rows;
pub mod sparse_contact;

pub use active_set::{
    solve_box_lcp, ActiveSetSolver, DelassusWorkingSet, LcpSolution, PdasReport, PdasSettings,
    PdasStatus, WorkingSetSolver,
};
pub use delassus::{Delassus, DelassusCache, DenseDelassus};
pub use rows::ContactRows;

use faer::sparse::linalg::matmul::sparse_dense_matmul;
use faer::sparse::SparseColMatRef;
use faer::{Accum, ColMut, ColRef, Par};

/// out ← out + α A x for a sparse A (faer's sparse × dense product).
pub fn add_product(a: SparseColMatRef<'_, usize, f64>, x: &[f64], alpha: f64, out: &mut [f64]) {
    sparse_dense_matmul(
        ColMut::from_slice_mut(out).as_mat_mut(),
        Accum::Add,
        a,
        ColRef::from_slice(x).as_mat(),
        alpha,
        Par::Seq,
    );
}

/// Where a constrained value sits relative to its bounds lo_i ≤ y_i ≤ hi_i: the working-set label
/// of one index in the active-set methods, and the contact state of one vertex.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum BoundState {
    /// Strictly between the bounds (or treated so): λ_i = 0.
    #[default]
    Free,
    /// On the lower bound y_i = lo_i, with λ_i ≥ 0 (lower obstacle pushes up).
    AtLower,
    /// On the upper bound y_i = hi_i, with λ_i ≤ 0 (upper obstacle pushes down).
    AtUpper,
}

impl BoundState {
    /// True for [`BoundState::AtLower`] and [`BoundState::AtUpper`].
    pub fn is_active(self) -> bool {
        self != BoundState::Free
    }
}

/// A box-constrained QP in the primal variables: min ½ xᵀ A x − bᵀ x subject to
/// `lower[i] ≤ B_i x ≤ upper[i]` (see the module docs).
#[derive(Clone, Copy, Debug)]
pub struct BoxQp<'a> {
    /// A, n × n, symmetric positive definite, both triangles stored.
    pub a: SparseColMatRef<'a, usize, f64>,
    /// b, length n.
    pub b: &'a [f64],
    /// The rows B, m of them over unknowns < n, linearly independent.
    pub rows: &'a ContactRows,
    /// lo, length m; `f64::NEG_INFINITY` for no lower bound.
    pub lower: &'a [f64],
    /// hi, length m; `f64::INFINITY` for no upper bound.
    pub upper: &'a [f64],
}

/// The solution of a [`BoxQp`]: the minimiser, the multipliers and the contact states.
#[derive(Clone, Debug, PartialEq)]
pub struct QpSolution {
    /// Whether x is the exact minimiser certified by the KKT conditions on its active set
    /// ([`clarabel::polish`]); false for an interior-point answer whose polish failed, which is
    /// accurate only to the solver's tolerances (a few 1e-8 m on plate steps).
    pub polished: bool,
    /// x, length n.
    pub x: Vec<f64>,
    /// λ, length m, with A x = b + Bᵀ λ and the signs of the module docs.
    pub lambda: Vec<f64>,
    /// The state of each constrained value, length m.
    pub states: Vec<BoundState>,
}
