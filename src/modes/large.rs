//! The eigenpairs of a pencil above [`super::DENSE_LIMIT`] free dofs, by the method of [`super`]
//! (reduction through the stiffness), in the time of matrix products and the memory of two dense
//! n × n matrices at rest and three at the peak of the set-up:
//!
//! 1. K_ff = Pᵀ L Lᵀ P, sparse (faer's supernodal Cholesky with a fill-reducing ordering P), so
//!    that R = Pᵀ L and C = R⁻¹ M_ff R⁻ᵀ = L⁻¹ P M_ff Pᵀ L⁻ᵀ, formed in one dense matrix: M_ff
//!    made dense, solved with L from the left, transposed in place and solved again;
//! 2. C = Q₁ B Q₁ᵀ with B banded ([`reduce_to_band`], matrix products), then B = Q₂ T Q₂ᵀ with T
//!    tridiagonal ([`chase`], in the cache): a two-stage tridiagonalisation, because the classic
//!    one-stage reduction reads the trailing matrix from memory once per column (2n³/3 values),
//!    which measured 18–23 s on 5 257 free dofs against 8 s for both stages here. The n × n
//!    matrix is dropped after the first stage (Q₁'s and Q₂'s reflectors hold n²/2 values each);
//! 3. T = Z diag(μ) Zᵀ by [`tridiagonal_eigen`] (Z the second n × n matrix, and a third as its
//!    workspace while it runs), the columns of Z then reversed so that ω² = 1/μ ascends;
//! 4. Φ = Pᵀ L⁻ᵀ Q₁ Q₂ Z diag(μ)^{-1/2} is kept as these factors ([`FactoredShapes`]): Φq is a
//!    product with Z, the reflectors and a sparse triangular solve, O(n²), and the rows of Φ at
//!    m dofs are (Φᵀ Bᵀ)ᵀ = (diag(μ)^{-1/2} Zᵀ Q₂ᵀ Q₁ᵀ L⁻¹ P Bᵀ)ᵀ, products with m columns,
//!    O(m n²). Forming Φ itself would cost the products Q₁ Q₂ Z, 4n³ flops, and the sparse
//!    solves with n columns.

use super::band::{reduce_to_band, BandReduction};
use super::bulge::{chase, BulgeChase};
use super::divide::tridiagonal_eigen;
use crate::contact::cholesky::{CholeskyAnalysis, CholeskyFactor};
use crate::error::Error;
use faer::linalg::matmul::matmul;
use faer::sparse::SparseColMat;
use faer::{Accum, Col, ColMut, Mat, MatRef, Par};

/// Φ = Pᵀ L⁻ᵀ Q₁ Q₂ Z diag(s) with s_k = μ_k^{-1/2} = ω_k (module docs), and M_ff for the modal
/// coordinates Φᵀ M_ff w.
pub struct FactoredShapes {
    /// K_ff = Pᵀ L Lᵀ P.
    factor: CholeskyFactor,
    /// M_ff.
    mass: SparseColMat<usize, f64>,
    /// Q₁, from C to the band.
    band: BandReduction,
    /// Q₂, from the band to T.
    chase: BulgeChase,
    /// Z, columns in the order of the modes.
    vectors: Mat<f64>,
    /// s_k = μ_k^{-1/2}.
    scale: Vec<f64>,
}

impl std::fmt::Debug for FactoredShapes {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "FactoredShapes {{ {} free dofs, {} factor entries }}",
            self.dimension(),
            self.factor.analysis().factor_entries()
        )
    }
}

/// All eigenpairs of K φ = ω² M φ (sparse, symmetric positive definite): ω² ascending and Φ
/// factored (module docs).
pub fn generalized_eigen(
    mass: &SparseColMat<usize, f64>,
    stiffness: &SparseColMat<usize, f64>,
) -> Result<(Vec<f64>, FactoredShapes), Error> {
    let n = stiffness.nrows();
    let not_definite = |what: &str| {
        Error::Numerical(format!(
            "the clamped {what} matrix is not positive definite"
        ))
    };
    let analysis = CholeskyAnalysis::new(stiffness.symbolic(), None)?;
    let factor =
        CholeskyFactor::new(analysis, stiffness.as_ref()).map_err(|_| not_definite("stiffness"))?;
    // C = L⁻¹ P M Pᵀ L⁻ᵀ: X = L⁻¹ P M, then L⁻¹ P Xᵀ (M symmetric), in one matrix.
    let mut reduced = mass.to_dense();
    factor.solve_lower_in_place(reduced.as_mut());
    transpose_in_place(reduced.as_mut());
    factor.solve_lower_in_place(reduced.as_mut());
    // The symmetric part, of which the tridiagonalisation reads the lower triangle.
    for j in 0..n {
        for i in j + 1..n {
            reduced[(i, j)] = 0.5 * (reduced[(i, j)] + reduced[(j, i)]);
        }
    }
    let (columns, band) = reduce_to_band(reduced.as_mut());
    drop(reduced);
    let chase = chase(&columns);
    let (mut mu, mut vectors) = tridiagonal_eigen(&chase.diagonal, &chase.subdiagonal)?;
    if let Some(bad) = mu.iter().find(|&&m| m <= 0.0 || !m.is_finite()) {
        return Err(Error::Numerical(format!(
            "the mass matrix is not positive definite (eigenvalue {bad:e})"
        )));
    }
    // μ ascending ⇒ ω² descending: reverse to sort modes by increasing frequency.
    mu.reverse();
    for k in 0..n / 2 {
        let (mut a, mut b) = vectors.as_mut().two_cols_mut(k, n - 1 - k);
        for i in 0..n {
            std::mem::swap(&mut a[i], &mut b[i]);
        }
    }
    let shapes = FactoredShapes {
        factor,
        mass: mass.clone(),
        band,
        chase,
        vectors,
        scale: mu.iter().map(|m| 1.0 / m.sqrt()).collect(),
    };
    Ok((mu.iter().map(|m| 1.0 / m).collect(), shapes))
}

/// Transposes a square matrix in place.
fn transpose_in_place(mut a: faer::MatMut<'_, f64>) {
    let n = a.nrows();
    for j in 0..n {
        for i in j + 1..n {
            let (x, y) = (a[(i, j)], a[(j, i)]);
            a[(i, j)] = y;
            a[(j, i)] = x;
        }
    }
}

impl FactoredShapes {
    /// The number of free dofs, which is also the number of modes.
    pub fn dimension(&self) -> usize {
        self.scale.len()
    }

    /// Φq = Pᵀ L⁻ᵀ Q₁ Q₂ Z diag(s) q.
    pub fn apply(&self, q: &[f64]) -> Vec<f64> {
        let n = self.dimension();
        let scaled = Col::from_fn(n, |k| self.scale[k] * q[k]);
        let mut w: Vec<f64> = (&self.vectors * &scaled).iter().copied().collect();
        let mut column = ColMut::from_slice_mut(&mut w);
        self.chase.apply_q(column.as_mut().as_mat_mut());
        self.band.apply_q(column.as_mut().as_mat_mut());
        self.factor
            .solve_lower_transpose_in_place(column.as_mat_mut());
        w
    }

    /// Φᵀ V = diag(s) Zᵀ Q₂ᵀ Q₁ᵀ L⁻¹ P V for the columns of V (free dofs × r): modes × r.
    pub fn project_columns(&self, v: MatRef<'_, f64>) -> Mat<f64> {
        let mut x = v.to_owned();
        self.factor.solve_lower_in_place(x.as_mut());
        self.band.apply_q_transpose(x.as_mut());
        self.chase.apply_q_transpose(x.as_mut());
        let mut projected = Mat::<f64>::zeros(self.dimension(), v.ncols());
        matmul(
            projected.as_mut(),
            Accum::Replace,
            self.vectors.transpose(),
            x.as_ref(),
            1.0,
            Par::Seq,
        );
        for (k, &s) in self.scale.iter().enumerate() {
            for j in 0..v.ncols() {
                projected[(k, j)] *= s;
            }
        }
        projected
    }

    /// Φᵀv.
    pub fn project(&self, v: &[f64]) -> Vec<f64> {
        let projected = self.project_columns(faer::ColRef::from_slice(v).as_mat());
        projected.col(0).iter().copied().collect()
    }

    /// Φᵀ M_ff w.
    pub fn coordinates(&self, w: &[f64]) -> Vec<f64> {
        let mw = &self.mass * faer::ColRef::from_slice(w);
        self.project(&mw.iter().copied().collect::<Vec<f64>>())
    }

    /// The rows `dofs` of Φ: (Φᵀ Bᵀ)ᵀ with B the rows of the identity at `dofs`.
    pub fn rows(&self, dofs: &[usize]) -> Mat<f64> {
        let unit = Mat::from_fn(self.dimension(), dofs.len(), |i, j| {
            if dofs[j] == i {
                1.0
            } else {
                0.0
            }
        });
        self.project_columns(unit.as_ref()).transpose().to_owned()
    }
}
