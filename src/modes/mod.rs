//! Natural frequencies and mode shapes of the clamped plate: the generalized eigenproblem
//! K_ff φ = ω² M_ff φ on the free dofs (clamp dofs removed), solved for every mode.
//!
//! Method: the pencil is reduced through the stiffness, not the mass. With K_ff = R Rᵀ (SPD: the
//! clamp removes the rigid motions), C = R⁻¹ M_ff R⁻ᵀ = Q diag(μ) Qᵀ with μ_k = 1/ω_k², and
//! Φ = R⁻ᵀ Q diag(μ)^{-1/2}, so that Φᵀ K_ff Φ = Ω² and Φᵀ M_ff Φ = I.
//!
//! Why through K: the C¹ elements' pencil is strongly graded (ω² from 1e5 to 1e14 s⁻² on the
//! 140-triangle mesh, the top set by the second-derivative dofs), and the dense symmetric
//! eigensolver with vectors is accurate to a small multiple of ε‖C‖ only. Reduced through M,
//! ‖C‖ = ω²_max and the lowest, physically relevant modes lose several digits (we measured 1.6 % on
//! f₁ for a 10 × 9 Argyris mesh); reduced through K, ‖C‖ = 1/ω₁², so the low modes are accurate to
//! round-off and only the highest modes, which the time scheme barely moves (½Δt²ω² ≫ 1), carry the
//! error.
//!
//! Two implementations of this method, by size (both O(n³) in the free dofs):
//! * up to [`DENSE_LIMIT`] free dofs, dense throughout: R the dense Cholesky factor, C formed by
//!   two dense triangular solves, faer's Householder tridiagonalisation and QR algorithm with
//!   eigenvectors, Φ formed as a dense matrix. Every scene that the automatic backend choice makes
//!   modal without a modal damping ratio has this size, and these bases stay as they were, bit for
//!   bit.
//! * above it ([`large`]), in the memory and time of a few thousand free dofs: R = Pᵀ L from the
//!   sparse Cholesky factor of K_ff, the two-stage tridiagonalisation of [`band`] and [`bulge`], the divide
//!   and conquer of [`divide`] for the tridiagonal eigenvectors, and Φ kept factored
//!   ([`ModeShapes`]). Its eigenpairs agree with the dense method's to a small multiple of ε‖C‖
//!   (`docs/speed.md`, fine meshes).

pub mod band;
pub mod bulge;
pub mod divide;
pub mod large;
pub mod lowest;
pub mod shapes;

pub use shapes::ModeShapes;

use crate::error::Error;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::sparse::{SparseColMat, SparseColMatRef, Triplet};
use faer::{Mat, Par, Side};

/// Largest number of free dofs solved by the dense implementation (module docs): the automatic
/// backend choice's limit for the modal backend, so that the bases it picks keep their bits.
pub const DENSE_LIMIT: usize = crate::backend_choice::MODAL_AUTO_LIMIT;

/// Eigenpairs of the clamped plate, sorted by increasing ω².
#[derive(Debug)]
pub struct Modes {
    /// ω_k² (rad²/s²), nondecreasing.
    pub omega_squared: Vec<f64>,
    /// The M-orthonormal mode shapes Φ over the free dofs, one per mode.
    pub shapes: ModeShapes,
}

impl Modes {
    /// Natural frequencies f_k = ω_k / 2π (Hz).
    pub fn frequencies_hz(&self) -> Vec<f64> {
        self.omega_squared
            .iter()
            .map(|&w2| w2.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
            .collect()
    }
}

/// The submatrix A[keep, keep] of a sparse matrix, sparse: entry (k, l) is `A[keep[k], keep[l]]`.
/// `keep` must hold distinct indices below A's order. faer builds it from A's entries with the
/// dropped rows and columns given negative indices, which it ignores.
pub fn sparse_restriction(
    a: SparseColMatRef<'_, usize, f64>,
    keep: &[usize],
) -> SparseColMat<usize, f64> {
    let mut position = vec![-1_isize; a.nrows()];
    for (k, &d) in keep.iter().enumerate() {
        position[d] = k as isize;
    }
    let entries: Vec<Triplet<isize, isize, f64>> = a
        .triplet_iter()
        .map(|t| Triplet::new(position[t.row], position[t.col], *t.val))
        .collect();
    SparseColMat::try_new_from_nonnegative_triplets(keep.len(), keep.len(), &entries)
        .expect("restricted indices lie below keep.len()")
}

/// All eigenpairs of K φ = ω² M φ for sparse symmetric positive definite K and M, by the dense
/// implementation up to [`DENSE_LIMIT`] unknowns and by [`large`] above (module docs).
pub fn generalized_eigen(
    mass: &SparseColMat<usize, f64>,
    stiffness: &SparseColMat<usize, f64>,
) -> Result<Modes, Error> {
    if mass.nrows() > DENSE_LIMIT {
        let (omega_squared, shapes) = large::generalized_eigen(mass, stiffness)?;
        return Ok(Modes {
            omega_squared,
            shapes: ModeShapes::factored(shapes),
        });
    }
    let mass = mass.to_dense();
    let (omega_squared, shapes) = dense_generalized_eigen(&mass, stiffness)?;
    Ok(Modes {
        omega_squared,
        shapes: ModeShapes::dense(shapes, mass),
    })
}

/// The dense implementation: ω² and Φ (module docs). Intermediate matrices are dropped or
/// overwritten as soon as they are used, which changes no value.
fn dense_generalized_eigen(
    mass: &Mat<f64>,
    stiffness: &SparseColMat<usize, f64>,
) -> Result<(Vec<f64>, Mat<f64>), Error> {
    let n = mass.nrows();
    let llt = stiffness.to_dense().llt(Side::Lower).map_err(|e| {
        Error::Numerical(format!(
            "the clamped stiffness matrix is not positive definite ({e:?})"
        ))
    })?;
    let l = llt.L();
    // C = L⁻¹ M L⁻ᵀ: solve L X = M, then L Cᵀ = Xᵀ (C symmetric).
    let mut c = {
        let mut x = mass.clone();
        solve_lower_triangular_in_place(l, x.as_mut(), Par::Seq);
        x.transpose().to_owned()
    };
    solve_lower_triangular_in_place(l, c.as_mut(), Par::Seq);
    // The symmetric part, of which the eigensolver reads the lower triangle.
    for j in 0..n {
        for i in j + 1..n {
            c[(i, j)] = 0.5 * (c[(i, j)] + c[(j, i)]);
        }
    }
    let (values, mut u) = symmetric_eigen_qr(&c)?;
    drop(c);
    // μ ascending ⇒ ω² descending: reverse to sort modes by increasing frequency.
    let mu: Vec<f64> = values.into_iter().rev().collect();
    if let Some(bad) = mu.iter().find(|&&m| m <= 0.0 || !m.is_finite()) {
        return Err(Error::Numerical(format!(
            "the mass matrix is not positive definite (eigenvalue {bad:e})"
        )));
    }
    // Φ = L⁻ᵀ U diag(μ)^{-1/2}, the columns of U reversed in place.
    for k in 0..n / 2 {
        let (mut a, mut b) = u.as_mut().two_cols_mut(k, n - 1 - k);
        for i in 0..n {
            std::mem::swap(&mut a[i], &mut b[i]);
        }
    }
    for (k, m) in mu.iter().enumerate() {
        let scale = m.sqrt();
        for x in u.col_mut(k).iter_mut() {
            *x /= scale;
        }
    }
    solve_upper_triangular_in_place(l.transpose(), u.as_mut(), Par::Seq);
    Ok((mu.iter().map(|m| 1.0 / m).collect(), u))
}

/// Eigen-decomposition of a dense symmetric matrix (lower triangle read): Householder
/// tridiagonalisation, then the implicit QR algorithm with eigenvectors, which is backward stable
/// (eigenvalue errors ≈ ε‖C‖). faer's default switches to divide and conquer above 128 rows, whose
/// eigenpairs we measured accurate only to about 1e-10‖C‖ on the graded plate pencils (residuals
/// of 2e-10‖C‖ on Argyris 14 × 10): too coarse for the small end of the spectrum, so the
/// recursion is switched off here ([`divide`] is a divide and conquer that keeps ε‖C‖).
pub(super) fn symmetric_eigen_qr(c: &Mat<f64>) -> Result<(Vec<f64>, Mat<f64>), Error> {
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::linalg::evd::{self, ComputeEigenvectors, SelfAdjointEvdParams};
    let n = c.nrows();
    let mut params: SelfAdjointEvdParams = faer::auto!(f64);
    params.recursion_threshold = usize::MAX;
    let mut values = faer::diag::Diag::<f64>::zeros(n);
    let mut vectors = Mat::<f64>::zeros(n, n);
    let mut buffer = MemBuffer::new(evd::self_adjoint_evd_scratch::<f64>(
        n,
        ComputeEigenvectors::Yes,
        Par::Seq,
        params.into(),
    ));
    evd::self_adjoint_evd(
        c.as_ref(),
        values.as_mut(),
        Some(vectors.as_mut()),
        Par::Seq,
        MemStack::new(&mut buffer),
        params.into(),
    )
    .map_err(|e| {
        Error::Numerical(format!(
            "the symmetric eigensolver did not converge ({e:?})"
        ))
    })?;
    Ok(((0..n).map(|k| values[k]).collect(), vectors))
}
