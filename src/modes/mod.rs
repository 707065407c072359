//! Natural frequencies and mode shapes of the clamped plate: the generalized eigenproblem
//! K_ff φ = ω² M_ff φ on the free dofs (clamp dofs removed), solved densely.
//!
//! Method: the pencil is reduced through the stiffness, not the mass. With K_ff = L Lᵀ (SPD: the
//! clamp removes the rigid motions), C = L⁻¹ M_ff L⁻ᵀ = Q diag(μ) Qᵀ with μ_k = 1/ω_k², and
//! Φ = L⁻ᵀ Q diag(μ)^{-1/2}, so that Φᵀ K_ff Φ = Ω² and Φᵀ M_ff Φ = I.
//!
//! Why through K: the C¹ elements' pencil is strongly graded (ω² from 1e5 to 1e14 s⁻² on the
//! 140-triangle mesh, the top set by the second-derivative dofs), and the dense symmetric
//! eigensolver with vectors is accurate to a small multiple of ε‖C‖ only. Reduced through M,
//! ‖C‖ = ω²_max and the lowest, physically relevant modes lose several digits (we measured 1.6 % on
//! f₁ for a 10 × 9 Argyris mesh); reduced through K, ‖C‖ = 1/ω₁², so the low modes are accurate to
//! round-off and only the highest modes, which the time scheme barely moves (½Δt²ω² ≫ 1), carry the
//! error. Dense cost O(n³): fine up to a few thousand free dofs.

pub mod band;
pub mod bulge;
pub mod divide;

use crate::error::Error;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::sparse::{SparseColMat, SparseColMatRef, Triplet};
use faer::{Mat, Par, Side};

/// Eigenpairs of the clamped plate, sorted by increasing ω².
#[derive(Clone, Debug)]
pub struct Modes {
    /// ω_k² (rad²/s²), nondecreasing.
    pub omega_squared: Vec<f64>,
    /// M-orthonormal mode shapes, one column per mode, over the free dofs.
    pub shapes: Mat<f64>,
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

/// The submatrix A[keep, keep] of a sparse matrix, dense (see [`sparse_restriction`]).
pub fn dense_restriction(a: &SparseColMat<usize, f64>, keep: &[usize]) -> Mat<f64> {
    sparse_restriction(a.as_ref(), keep).to_dense()
}

/// All eigenpairs of K φ = ω² M φ for dense symmetric positive definite K and M.
pub fn generalized_eigen(mass: &Mat<f64>, stiffness: &Mat<f64>) -> Result<Modes, Error> {
    let n = mass.nrows();
    let llt = stiffness.llt(Side::Lower).map_err(|e| {
        Error::Numerical(format!(
            "the clamped stiffness matrix is not positive definite ({e:?})"
        ))
    })?;
    let l = llt.L();
    // C = L⁻¹ M L⁻ᵀ: solve L X = M, then L Cᵀ = Xᵀ (C symmetric).
    let mut x = mass.clone();
    solve_lower_triangular_in_place(l, x.as_mut(), Par::Seq);
    let mut c = x.transpose().to_owned();
    solve_lower_triangular_in_place(l, c.as_mut(), Par::Seq);
    let c = Mat::from_fn(n, n, |i, j| 0.5 * (c[(i, j)] + c[(j, i)]));
    let (values, u) = symmetric_eigen_qr(&c)?;
    // μ ascending ⇒ ω² descending: reverse to sort modes by increasing frequency.
    let mu: Vec<f64> = values.into_iter().rev().collect();
    if let Some(bad) = mu.iter().find(|&&m| m <= 0.0 || !m.is_finite()) {
        return Err(Error::Numerical(format!(
            "the mass matrix is not positive definite (eigenvalue {bad:e})"
        )));
    }
    let mut shapes = Mat::from_fn(n, n, |i, k| u[(i, n - 1 - k)] / mu[k].sqrt());
    solve_upper_triangular_in_place(l.transpose(), shapes.as_mut(), Par::Seq);
    Ok(Modes {
        omega_squared: mu.iter().map(|m| 1.0 / m).collect(),
        shapes,
    })
}

/// Eigen-decomposition of a dense symmetric matrix (lower triangle read): Householder
/// tridiagonalisation, then the implicit QR algorithm with eigenvectors, which is backward stable
/// (eigenvalue errors ≈ ε‖C‖). faer's default switches to divide and conquer above 128 rows, whose
/// eigenpairs we measured accurate only to about 1e-11‖C‖ on the graded plate pencils: too coarse
/// for the small end of the spectrum, so the recursion is switched off here.
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
