//! The first stage of a two-stage tridiagonalisation: a dense symmetric matrix reduced to a band,
//! A = Q₁ B Q₁ᵀ with B of lower bandwidth [`BANDWIDTH`], by matrix products only.
//!
//! Panel k holds the columns k..k+b (b = [`BANDWIDTH`]); its rows below the band, k+b.., are
//! factored A[k+b.., k..k+b] = H R by Householder QR (faer's blocked QR, one block factor T per
//! panel: H = I − V T⁻¹ Vᵀ), R stays in the band and the trailing matrix A₂₂ = A[k+b.., k+b..]
//! becomes Hᵀ A₂₂ H = A₂₂ − W Vᵀ − V Wᵀ with X = A₂₂ V T⁻¹, W = X − ½ V (T⁻ᵀ Vᵀ X). Each panel
//! costs two products with the lower triangle of A₂₂ (A₂₂ V and the rank-2b update), 4r²b flops
//! for r trailing rows, 4n³/3 in all, at the speed of matrix products: where a one-stage
//! reduction reads the trailing matrix once per column (a memory-bound matrix–vector product,
//! about 2n³/3 values streamed from memory on a few thousand rows), this one reads it about three
//! times per panel of b columns.
//!
//! The panels' reflectors are copied out as they are made (V with its unit diagonal, n²/2 values
//! in all, and T), so that the n × n matrix can be dropped once the band is read from it; Q₁ is
//! applied to vectors panel by panel with faer's blocked routines.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::householder::{
    apply_block_householder_on_the_left_in_place_scratch,
    apply_block_householder_on_the_left_in_place_with_conj,
    apply_block_householder_transpose_on_the_left_in_place_scratch,
    apply_block_householder_transpose_on_the_left_in_place_with_conj,
};
use faer::linalg::matmul::matmul;
use faer::linalg::matmul::triangular::{self, BlockStructure};
use faer::linalg::qr::no_pivoting::factor::{qr_in_place, qr_in_place_scratch};
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, Conj, Mat, MatMut, Par};

/// The band's lower bandwidth b, also the panel width.
pub const BANDWIDTH: usize = 32;

/// A band matrix B of lower bandwidth [`BANDWIDTH`], column by column: `columns[c][d]` =
/// B[c + d, c] for d = 0..=b (entries past the matrix's last row are 0).
pub type BandColumns = Vec<[f64; BANDWIDTH + 1]>;

/// Q₁ = H₀ H₁ ⋯, one block reflector H_k = I − V T⁻¹ Vᵀ per panel.
#[derive(Clone, Debug)]
pub struct BandReduction {
    panels: Vec<Panel>,
}

/// A panel's block reflector, acting on rows `row..`.
#[derive(Clone, Debug)]
struct Panel {
    row: usize,
    /// V (rows × width), unit lower trapezoidal.
    basis: Mat<f64>,
    /// T (width × width), upper triangular.
    factor: Mat<f64>,
}

/// Reduces the symmetric `a` (its lower triangle is read and overwritten) to a band (module
/// docs): the band B and Q₁ with A = Q₁ B Q₁ᵀ.
pub fn reduce_to_band(mut a: MatMut<'_, f64>) -> (BandColumns, BandReduction) {
    let n = a.nrows();
    assert_eq!(a.ncols(), n, "a square matrix");
    let b = BANDWIDTH;
    let mut panels = Vec::new();
    let mut x = Mat::<f64>::zeros(n, b);
    let mut small = Mat::<f64>::zeros(b, b);
    let mut k = 0;
    while k + b < n {
        let rows = n - k - b;
        let width = b.min(rows);
        let mut t = Mat::<f64>::zeros(width, width);
        {
            let panel = a.rb_mut().submatrix_mut(k + b, k, rows, b);
            let mut buffer = MemBuffer::new(qr_in_place_scratch::<f64>(
                rows,
                b,
                width,
                Par::Seq,
                Default::default(),
            ));
            qr_in_place(
                panel,
                t.as_mut(),
                Par::Seq,
                MemStack::new(&mut buffer),
                Default::default(),
            );
        }
        // V with its unit diagonal and zeros above.
        let v = Mat::from_fn(rows, width, |i, j| match i.cmp(&j) {
            std::cmp::Ordering::Less => 0.0,
            std::cmp::Ordering::Equal => 1.0,
            std::cmp::Ordering::Greater => a[(k + b + i, k + j)],
        });
        let mut trailing = a.rb_mut().submatrix_mut(k + b, k + b, rows, rows);
        // X = A₂₂ V T⁻¹ (A₂₂ from its lower triangle), then W = X − ½ V (T⁻ᵀ Vᵀ X).
        let mut x = x.as_mut().submatrix_mut(0, 0, rows, width);
        triangular::matmul(
            x.rb_mut(),
            BlockStructure::Rectangular,
            Accum::Replace,
            trailing.rb(),
            BlockStructure::TriangularLower,
            v.as_ref(),
            BlockStructure::Rectangular,
            1.0,
            Par::Seq,
        );
        triangular::matmul(
            x.rb_mut(),
            BlockStructure::Rectangular,
            Accum::Add,
            trailing.rb().transpose(),
            BlockStructure::StrictTriangularUpper,
            v.as_ref(),
            BlockStructure::Rectangular,
            1.0,
            Par::Seq,
        );
        solve_lower_triangular_in_place(t.transpose(), x.rb_mut().transpose_mut(), Par::Seq);
        let mut m = small.as_mut().submatrix_mut(0, 0, width, width);
        matmul(
            m.rb_mut(),
            Accum::Replace,
            v.transpose(),
            x.rb(),
            1.0,
            Par::Seq,
        );
        solve_lower_triangular_in_place(t.transpose(), m.rb_mut(), Par::Seq);
        matmul(x.rb_mut(), Accum::Add, v.as_ref(), m.rb(), -0.5, Par::Seq);
        // A₂₂ −= W Vᵀ + V Wᵀ, lower triangle.
        for (p, q) in [(x.rb(), v.as_ref()), (v.as_ref(), x.rb())] {
            triangular::matmul(
                trailing.rb_mut(),
                BlockStructure::TriangularLower,
                Accum::Add,
                p,
                BlockStructure::Rectangular,
                q.transpose(),
                BlockStructure::Rectangular,
                -1.0,
                Par::Seq,
            );
        }
        panels.push(Panel {
            row: k + b,
            basis: v,
            factor: t,
        });
        k += b;
    }
    let columns = (0..n)
        .map(|c| {
            let mut column = [0.0; BANDWIDTH + 1];
            // Below the R block of column c's panel lie the reflectors, not B.
            let panel_rows = c - c % b + b;
            for (d, entry) in column.iter_mut().enumerate() {
                let row = c + d;
                if row < n && (row < panel_rows || row - panel_rows <= c % b) {
                    *entry = a[(row, c)];
                }
            }
            column
        })
        .collect();
    (columns, BandReduction { panels })
}

impl BandReduction {
    /// target ← Q₁ target (the panels' reflectors in reverse order).
    pub fn apply_q(&self, mut target: MatMut<'_, f64>) {
        for panel in self.panels.iter().rev() {
            panel.apply(target.rb_mut(), false);
        }
    }

    /// target ← Q₁ᵀ target (the panels' reflectors transposed, in order).
    pub fn apply_q_transpose(&self, mut target: MatMut<'_, f64>) {
        for panel in &self.panels {
            panel.apply(target.rb_mut(), true);
        }
    }
}

impl Panel {
    fn apply(&self, target: MatMut<'_, f64>, transpose: bool) {
        let (rows, width, columns) = (self.basis.nrows(), self.basis.ncols(), target.ncols());
        let target = target.subrows_mut(self.row, rows);
        if transpose {
            let mut buffer = MemBuffer::new(
                apply_block_householder_transpose_on_the_left_in_place_scratch::<f64>(
                    rows, width, columns,
                ),
            );
            apply_block_householder_transpose_on_the_left_in_place_with_conj(
                self.basis.as_ref(),
                self.factor.as_ref(),
                Conj::No,
                target,
                Par::Seq,
                MemStack::new(&mut buffer),
            );
        } else {
            let mut buffer = MemBuffer::new(
                apply_block_householder_on_the_left_in_place_scratch::<f64>(rows, width, columns),
            );
            apply_block_householder_on_the_left_in_place_with_conj(
                self.basis.as_ref(),
                self.factor.as_ref(),
                Conj::No,
                target,
                Par::Seq,
                MemStack::new(&mut buffer),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A = Q₁ B Q₁ᵀ with Q₁ orthogonal and B banded, for sizes around the bandwidth and several
    /// panels, on a pseudo-random symmetric matrix (full rank, so no reflector degenerates).
    #[test]
    fn reduction_reproduces_the_matrix() {
        let b = BANDWIDTH;
        for n in [1, 2, b, b + 1, b + 2, 2 * b + 5, 5 * b + 3] {
            let a = Mat::from_fn(n, n, |i, j| {
                let (i, j) = (i.max(j), i.min(j));
                let hash = ((i * 2_654_435_761 + j * 40_503) % 1_000_003) as f64 / 1_000_003.0;
                hash - 0.5 + if i == j { 2.0 } else { 0.0 }
            });
            let mut reduced = a.clone();
            let (columns, q1) = reduce_to_band(reduced.as_mut());
            let mut q = Mat::<f64>::identity(n, n);
            q1.apply_q(q.as_mut());
            let full = Mat::from_fn(n, n, |i, j| {
                let (r, c) = (i.max(j), i.min(j));
                if r - c <= b {
                    columns[c][r - c]
                } else {
                    0.0
                }
            });
            let back = &q * &full * q.transpose();
            let orthogonality = q.transpose() * &q - Mat::<f64>::identity(n, n);
            let mut transposed = Mat::<f64>::identity(n, n);
            q1.apply_q_transpose(transposed.as_mut());
            // Backward stable: errors of a few n ε relative to ‖A‖ ≈ 1.
            let tolerance = 1e-13;
            for i in 0..n {
                for j in 0..n {
                    assert!((back[(i, j)] - a[(i, j)]).abs() < tolerance, "n = {n}");
                    assert!(orthogonality[(i, j)].abs() < tolerance, "n = {n}");
                    assert!(
                        (transposed[(i, j)] - q[(j, i)]).abs() < tolerance,
                        "n = {n}"
                    );
                }
            }
        }
    }
}
