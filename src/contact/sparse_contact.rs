//! The contact solve of a sparse backend in one object: the factor of A for the unconstrained
//! step, the Delassus columns it yields within a memory budget, the primal elimination, and the
//! rule that picks the subproblem of each step.
//!
//! [`SparseContact`] owns two [`EliminatedSystem`]s on the same A (one symbolic analysis, with
//! the fill-reducing ordering of [`CholeskyAnalysis`]): the first keeps A's factor and serves the
//! unconstrained steps x* = A⁻¹b, the Delassus columns W e_j = B A⁻¹ Bᵀ e_j (in blocks, cached
//! by a [`DelassusCache`]) and the final correction x = A⁻¹(b + Bᵀλ); the second factors working
//! sets for the primal elimination, and is made (with the memory of a second factor) only when
//! a step first needs it. A step whose
//! warm start has at most [`SparseContact::delassus_limit`] active indices (min(m/4, 1 000)) is
//! solved on W, a larger one by elimination; so is a cold start (no warm start) whose
//! unconstrained step leaves the box at more vertices than that limit (see docs/contact.md for
//! the measurements behind the rule). Either way the answer is the QP's exact minimiser. The
//! elimination fixes unknowns, so it needs every row of B to pick one (the contact points all
//! mesh vertices); with a stop's own point among the rows every step is solved on W.

use super::cholesky::CholeskyAnalysis;
use super::delassus::{ColumnSource, DelassusCache};
use super::eliminated::EliminatedSystem;
use super::{ActiveSetSolver, BoundState, ContactRows, PdasReport, PdasSettings};
use crate::Error;
use faer::sparse::SparseColMat;
use faer::Mat;
use std::sync::Arc;

/// Largest active block solved on the Delassus operator (beyond it, or beyond a quarter of the
/// constrained vertices, the primal elimination).
pub const MAX_DELASSUS_BLOCK: usize = 1000;

/// The largest warm-start set solved on the Delassus operator for m constrained vertices:
/// min(m/4, [`MAX_DELASSUS_BLOCK`]). Measured on the FVS 60 × 30 plate: with 1 798 contacts the
/// elimination is 5× faster than the Delassus path, with up to 60 the Delassus path is faster.
pub fn delassus_limit(m: usize) -> usize {
    (m / 4).min(MAX_DELASSUS_BLOCK)
}

/// The columns of W = B A⁻¹ Bᵀ by block solves with the factor of A, without iterative
/// refinement: an error δW in W perturbs the multipliers, but the answer x = A⁻¹(b + Bᵀλ) is
/// solved refined, so it stays the exact minimiser for its λ up to (δW λ) at the active values,
/// the relative round-off of one solve times the step's contact displacement (far below the
/// 1e-12 m the steps are held to); the refinement would double the cost of every column.
pub struct InverseColumns {
    system: EliminatedSystem,
    rows: ContactRows,
    block: Mat<f64>,
}

impl ColumnSource for InverseColumns {
    fn columns(&mut self, js: &[usize], out: &mut [f64]) {
        let n = self.system.x().len();
        let m = self.rows.len();
        self.block.resize_with(n, js.len(), |_, _| 0.0);
        self.block.fill(0.0);
        for (q, &j) in js.iter().enumerate() {
            self.rows.add_row(
                j,
                1.0,
                self.block
                    .col_mut(q)
                    .try_as_col_major_mut()
                    .expect("a column")
                    .as_slice_mut(),
            );
        }
        self.system
            .solve_unconstrained_unrefined_in_place(self.block.as_mut())
            .expect("A was factored at construction and the factor is kept");
        for (q, column) in out.chunks_mut(m).enumerate() {
            let solved = self
                .block
                .col(q)
                .try_as_col_major()
                .expect("a column")
                .as_slice();
            self.rows.values(solved, column);
        }
    }
}

/// Which subproblem solved a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Subproblem {
    /// On the Delassus operator (few contacts).
    Delassus,
    /// By primal elimination (many contacts).
    Eliminated,
}

/// The contact solve of a sparse backend (module docs).
pub struct SparseContact {
    delassus: DelassusCache<InverseColumns>,
    /// The primal elimination, made on its first use.
    eliminated: Option<EliminatedSystem>,
    /// The rows B.
    rows: ContactRows,
    pdas: ActiveSetSolver,
    limit: usize,
    forced: Option<Subproblem>,
    last: Subproblem,
    y_star: Vec<f64>,
    rhs: Vec<f64>,
}

impl SparseContact {
    /// For A (n × n, SPD, both triangles) and the rows B, with Delassus columns kept within
    /// `budget_bytes`. Runs the symbolic analysis of A's pattern (with faer's minimum degree
    /// ordering and `proposed_ordering` if given, keeping the one of less fill, see
    /// [`CholeskyAnalysis::new`]) and one numeric factorisation. The elimination is offered only
    /// when every row picks one unknown (module docs).
    pub fn new(
        a: Arc<SparseColMat<usize, f64>>,
        rows: &ContactRows,
        budget_bytes: usize,
        proposed_ordering: Option<&[usize]>,
    ) -> Result<SparseContact, Error> {
        let analysis = CholeskyAnalysis::new(a.symbolic(), proposed_ordering)?;
        let selected = rows.selected();
        let mut system = EliminatedSystem::new(a, analysis, selected.unwrap_or(&[]))?;
        system.factor_unconstrained()?;
        let m = rows.len();
        let n = system.x().len();
        Ok(SparseContact {
            delassus: DelassusCache::new(
                m,
                budget_bytes,
                InverseColumns {
                    system,
                    rows: rows.clone(),
                    block: Mat::zeros(n, 0),
                },
            ),
            eliminated: None,
            rows: rows.clone(),
            pdas: ActiveSetSolver::new(),
            limit: if selected.is_some() {
                delassus_limit(m)
            } else {
                usize::MAX
            },
            forced: None,
            last: Subproblem::Delassus,
            y_star: vec![0.0; m],
            rhs: vec![0.0; n],
        })
    }

    /// Always use `choice` instead of the rule (for comparisons). The elimination needs rows
    /// that each pick one unknown.
    ///
    /// # Panics
    /// When `choice` is the elimination and a row is general (a programming error).
    pub fn force(&mut self, choice: Subproblem) {
        assert!(
            choice == Subproblem::Delassus || self.rows.selected().is_some(),
            "the elimination needs unit rows"
        );
        self.forced = Some(choice);
    }

    /// The largest warm start, or number of values outside the box on a cold start, solved on the
    /// Delassus operator ([`delassus_limit`]).
    pub fn delassus_limit(&self) -> usize {
        self.limit
    }

    /// x = A⁻¹ b, the unconstrained step, with one step of iterative refinement.
    pub fn solve_unconstrained(&mut self, b: &[f64], x: &mut [f64]) -> Result<(), Error> {
        self.delassus.source_mut().system.solve_unconstrained(b, x)
    }

    /// Solves the QP min ½ xᵀAx − bᵀx over lower ≤ Bx ≤ upper, from its unconstrained minimiser
    /// `x_star` = A⁻¹b, warm-started from `states` (updated), into `x`. The result is the exact
    /// minimiser when the report's status [is solved](super::PdasStatus::is_solved); else the
    /// caller falls back (to clarabel).
    #[allow(clippy::too_many_arguments)]
    pub fn solve(
        &mut self,
        b: &[f64],
        x_star: &[f64],
        lower: &[f64],
        upper: &[f64],
        states: &mut [BoundState],
        settings: &PdasSettings,
        x: &mut [f64],
    ) -> Result<PdasReport, Error> {
        self.rows.values(x_star, &mut self.y_star);
        // Elimination when the warm start is large, or on a cold start when many values lie
        // outside the box. The rule reads the step's data only, not what the cache holds: the
        // path, hence the round-off, of a step must not depend on the steps before it (a restored
        // state continues bit for bit).
        let warm = states.iter().filter(|s| s.is_active()).count();
        let outside = if warm == 0 {
            (0..self.y_star.len())
                .filter(|&i| self.y_star[i] < lower[i] || self.y_star[i] > upper[i])
                .count()
        } else {
            0
        };
        self.last = self.forced.unwrap_or(if warm.max(outside) <= self.limit {
            Subproblem::Delassus
        } else {
            Subproblem::Eliminated
        });
        let report = match self.last {
            Subproblem::Delassus => {
                let report = self.pdas.solve(
                    &mut self.delassus,
                    &self.y_star,
                    lower,
                    upper,
                    states,
                    settings,
                );
                if report.status.is_solved() {
                    self.rhs.copy_from_slice(b);
                    self.rows.add_transpose(self.pdas.lambda(), &mut self.rhs);
                    self.solve_unconstrained_into(x)?;
                }
                report
            }
            Subproblem::Eliminated => {
                let source = &self.delassus.source().system;
                let eliminated = self.eliminated.get_or_insert_with(|| source.share());
                eliminated.set_step(b, x_star);
                let report =
                    self.pdas
                        .solve_with(eliminated, &self.y_star, lower, upper, states, settings);
                if states.iter().any(|s| s.is_active()) {
                    x.copy_from_slice(eliminated.x());
                } else {
                    x.copy_from_slice(x_star);
                }
                report
            }
        };
        Ok(report)
    }

    /// x = A⁻¹ (self.rhs).
    fn solve_unconstrained_into(&mut self, x: &mut [f64]) -> Result<(), Error> {
        let rhs = std::mem::take(&mut self.rhs);
        let result = self.solve_unconstrained(&rhs, x);
        self.rhs = rhs;
        result
    }

    /// λ of the last [`Self::solve`] (length m): A x = b + Bᵀλ.
    pub fn lambda(&self) -> &[f64] {
        self.pdas.lambda()
    }

    /// The subproblem of the last [`Self::solve`].
    pub fn last_subproblem(&self) -> Subproblem {
        self.last
    }

    /// The Delassus cache (its statistics).
    pub fn delassus(&self) -> &DelassusCache<InverseColumns> {
        &self.delassus
    }

    /// The primal elimination (its statistics), once a step has used it.
    pub fn eliminated(&self) -> Option<&EliminatedSystem> {
        self.eliminated.as_ref()
    }

    /// The analysis of A's pattern (its ordering and the size of the factor).
    pub fn analysis(&self) -> &CholeskyAnalysis {
        self.delassus.source().system.analysis()
    }

    /// The active-set solver (its factor statistics).
    pub fn active_set(&self) -> &ActiveSetSolver {
        &self.pdas
    }
}
