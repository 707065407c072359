//! The sparse Cholesky factor A = Pᵀ L Lᵀ P of a symmetric positive definite A (faer's
//! supernodal factorisation), with the fill-reducing ordering P chosen once per pattern and a
//! solve workspace allocated once.
//!
//! [`CholeskyAnalysis`] is the symbolic part (ordering, elimination tree, supernodes), shared by
//! every numeric factor of matrices with the same pattern (A itself, or A with some rows and
//! columns replaced by their diagonal, [`super::eliminated`]). [`CholeskyFactor`] holds the
//! numeric values of L for one matrix and solves with them; refactoring another matrix of the
//! pattern reuses its storage.

use super::block_factor::NotPositiveDefinite;
use crate::Error;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::perm::PermRef;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::sparse::linalg::cholesky::supernodal::SupernodalLltRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::linalg::triangular_solve;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Accum, Conj, Mat, MatMut, MatRef, Par, Side};
use std::sync::Arc;

/// The fill-reducing ordering of a [`CholeskyAnalysis`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FillOrdering {
    /// faer's approximate minimum degree ordering.
    MinimumDegree,
    /// The ordering the caller proposed ([`super::ordering::nested_dissection`] for a plate).
    Proposed,
}

/// The symbolic Cholesky analysis of a sparsity pattern (module docs). Cloning shares it.
#[derive(Clone, Debug)]
pub struct CholeskyAnalysis {
    symbolic: Arc<SymbolicCholesky<usize>>,
    ordering: FillOrdering,
}

impl CholeskyAnalysis {
    /// Analyses the pattern of a symmetric A (lower triangle read) with faer's minimum degree
    /// ordering and, when `proposed` is given (`proposed[p]` = the unknown placed at position
    /// p), with that ordering too, and keeps the one whose factor L has fewer entries.
    pub fn new(
        pattern: SymbolicSparseColMatRef<'_, usize>,
        proposed: Option<&[usize]>,
    ) -> Result<CholeskyAnalysis, Error> {
        let analyse = |ordering| {
            factorize_symbolic_cholesky(pattern, Side::Lower, ordering, Default::default()).map_err(
                |e| {
                    Error::Numerical(format!(
                        "the symbolic sparse Cholesky analysis failed ({e:?})"
                    ))
                },
            )
        };
        let mut best = CholeskyAnalysis {
            symbolic: Arc::new(analyse(SymmetricOrdering::Amd)?),
            ordering: FillOrdering::MinimumDegree,
        };
        if let Some(order) = proposed {
            let n = pattern.nrows();
            let mut inverse = vec![usize::MAX; n];
            for (p, &i) in order.iter().enumerate() {
                if i < n {
                    inverse[i] = p;
                }
            }
            if order.len() != n || inverse.contains(&usize::MAX) {
                return Err(Error::Numerical(format!(
                    "the proposed fill-reducing ordering is not a permutation of the {n} unknowns"
                )));
            }
            let permutation = PermRef::new_checked(order, &inverse, n);
            let symbolic = analyse(SymmetricOrdering::Custom(permutation))?;
            if symbolic.len_val() < best.symbolic.len_val() {
                best = CholeskyAnalysis {
                    symbolic: Arc::new(symbolic),
                    ordering: FillOrdering::Proposed,
                };
            }
        }
        Ok(best)
    }

    /// The number of stored entries of L (8 bytes each).
    pub fn factor_entries(&self) -> usize {
        self.symbolic.len_val()
    }

    /// The ordering kept.
    pub fn ordering(&self) -> FillOrdering {
        self.ordering
    }

    /// The order n of the matrix.
    pub fn dim(&self) -> usize {
        self.symbolic.nrows()
    }
}

/// The numeric factor of one matrix with the pattern of a [`CholeskyAnalysis`] (module docs).
pub struct CholeskyFactor {
    analysis: CholeskyAnalysis,
    values: Vec<f64>,
    /// Workspace of the solves, sized for `workspace_columns` right-hand sides.
    workspace: MemBuffer,
    workspace_columns: usize,
}

impl CholeskyFactor {
    /// Factors `a`, whose pattern must be the analysed one (lower triangle read).
    pub fn new(
        analysis: CholeskyAnalysis,
        a: SparseColMatRef<'_, usize, f64>,
    ) -> Result<CholeskyFactor, NotPositiveDefinite> {
        let mut factor = CholeskyFactor {
            values: vec![0.0; analysis.factor_entries()],
            workspace: MemBuffer::new(analysis.symbolic.solve_in_place_scratch::<f64>(1, Par::Seq)),
            workspace_columns: 1,
            analysis,
        };
        factor.refactor(a)?;
        Ok(factor)
    }

    /// Replaces the factor by that of `a`, a matrix with the analysed pattern.
    pub fn refactor(
        &mut self,
        a: SparseColMatRef<'_, usize, f64>,
    ) -> Result<(), NotPositiveDefinite> {
        let symbolic = &*self.analysis.symbolic;
        let mut workspace = MemBuffer::new(
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
        );
        symbolic
            .factorize_numeric_llt(
                &mut self.values,
                a,
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut workspace),
                Default::default(),
            )
            .map(|_| ())
            .map_err(|_| NotPositiveDefinite)
    }

    /// Overwrites each column b of `rhs` by A⁻¹b.
    pub fn solve_in_place(&mut self, rhs: MatMut<'_, f64>) {
        let symbolic = &*self.analysis.symbolic;
        if rhs.ncols() > self.workspace_columns {
            self.workspace_columns = rhs.ncols();
            self.workspace = MemBuffer::new(
                symbolic.solve_in_place_scratch::<f64>(self.workspace_columns, Par::Seq),
            );
        }
        LltRef::new(symbolic, &self.values).solve_in_place_with_conj(
            Conj::No,
            rhs,
            Par::Seq,
            MemStack::new(&mut self.workspace),
        );
    }

    /// The analysis the factor belongs to.
    pub fn analysis(&self) -> &CholeskyAnalysis {
        &self.analysis
    }

    /// Overwrites each column b of `rhs` by L⁻¹(P b), the first half of a solve with
    /// A = Pᵀ L Lᵀ P: with R = Pᵀ L, A = R Rᵀ and this is R⁻¹ b.
    pub fn solve_lower_in_place(&self, mut rhs: MatMut<'_, f64>) {
        let symbolic = &*self.analysis.symbolic;
        if let Some(perm) = symbolic.perm() {
            permute_rows(rhs.rb_mut(), perm.arrays().0);
        }
        match symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(simplicial) => {
                let l = SparseColMatRef::new(simplicial.factor(), &self.values);
                triangular_solve::solve_lower_triangular_in_place(l, Conj::No, rhs, Par::Seq);
            }
            SymbolicCholeskyRaw::Supernodal(supernodal) => {
                let factor = SupernodalLltRef::new(supernodal, &self.values);
                let mut scratch = Mat::<f64>::zeros(0, 0);
                for s in 0..supernodal.n_supernodes() {
                    let node = factor.supernode(s);
                    let size = node.val().ncols();
                    let (top, bottom) = node.val().split_at_row(size);
                    let mut x = rhs.rb_mut().subrows_mut(node.start(), size);
                    solve_lower_triangular_in_place(top, x.rb_mut(), Par::Seq);
                    let below = scratch_block(&mut scratch, node.pattern().len(), x.ncols());
                    matmul(below, Accum::Replace, bottom, x.rb(), 1.0, Par::Seq);
                    scatter(rhs.rb_mut(), node.pattern(), scratch.as_ref(), -1.0);
                }
            }
        }
    }

    /// Overwrites each column b of `rhs` by Pᵀ(L⁻ᵀ b), the second half of a solve: R⁻ᵀ b.
    pub fn solve_lower_transpose_in_place(&self, mut rhs: MatMut<'_, f64>) {
        let symbolic = &*self.analysis.symbolic;
        match symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(simplicial) => {
                let l = SparseColMatRef::new(simplicial.factor(), &self.values);
                triangular_solve::solve_lower_triangular_transpose_in_place(
                    l,
                    Conj::No,
                    rhs.rb_mut(),
                    Par::Seq,
                );
            }
            SymbolicCholeskyRaw::Supernodal(supernodal) => {
                let factor = SupernodalLltRef::new(supernodal, &self.values);
                let mut scratch = Mat::<f64>::zeros(0, 0);
                for s in (0..supernodal.n_supernodes()).rev() {
                    let node = factor.supernode(s);
                    let size = node.val().ncols();
                    let (top, bottom) = node.val().split_at_row(size);
                    let columns = rhs.ncols();
                    let mut below = scratch_block(&mut scratch, node.pattern().len(), columns);
                    for j in 0..columns {
                        for (k, &i) in node.pattern().iter().enumerate() {
                            below[(k, j)] = rhs[(i, j)];
                        }
                    }
                    let mut x = rhs.rb_mut().subrows_mut(node.start(), size);
                    matmul(
                        x.rb_mut(),
                        Accum::Add,
                        bottom.transpose(),
                        scratch
                            .as_ref()
                            .submatrix(0, 0, node.pattern().len(), columns),
                        -1.0,
                        Par::Seq,
                    );
                    solve_upper_triangular_in_place(top.transpose(), x, Par::Seq);
                }
            }
        }
        if let Some(perm) = symbolic.perm() {
            permute_rows(rhs, perm.arrays().1);
        }
    }
}

/// Row i of each column of `x` ← its row `from[i]`.
fn permute_rows(mut x: MatMut<'_, f64>, from: &[usize]) {
    let mut column = vec![0.0; x.nrows()];
    for j in 0..x.ncols() {
        for (c, &f) in column.iter_mut().zip(from) {
            *c = x[(f, j)];
        }
        for (i, &c) in column.iter().enumerate() {
            x[(i, j)] = c;
        }
    }
}

/// The top-left `rows` × `columns` block of `scratch`, grown as needed.
fn scratch_block(scratch: &mut Mat<f64>, rows: usize, columns: usize) -> MatMut<'_, f64> {
    if scratch.nrows() < rows || scratch.ncols() < columns {
        *scratch = Mat::zeros(rows.max(scratch.nrows()), columns.max(scratch.ncols()));
    }
    scratch.as_mut().submatrix_mut(0, 0, rows, columns)
}

/// x[rows[k], j] += alpha · values[k, j] for the leading block of `values`.
fn scatter(mut x: MatMut<'_, f64>, rows: &[usize], values: MatRef<'_, f64>, alpha: f64) {
    for j in 0..x.ncols() {
        for (k, &i) in rows.iter().enumerate() {
            x[(i, j)] += alpha * values[(k, j)];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::{SparseColMat, Triplet};

    /// A diagonally dominant matrix coupling each point of an s × s grid to those within `reach`
    /// rows and columns: SPD, with a factor that faer stores simplicial for a small, sparse grid
    /// and supernodal for a larger, denser one.
    fn grid_matrix(s: usize, reach: usize) -> SparseColMat<usize, f64> {
        let index = |x: usize, y: usize| x * s + y;
        let mut entries = Vec::new();
        for x in 0..s {
            for y in 0..s {
                for u in x.saturating_sub(reach)..(x + reach + 1).min(s) {
                    for v in y.saturating_sub(reach)..(y + reach + 1).min(s) {
                        let w = if (u, v) == (x, y) {
                            2.0 * ((2 * reach + 1) * (2 * reach + 1)) as f64
                        } else {
                            -1.0 - 0.1 * ((u + v + x + y) % 3) as f64
                        };
                        entries.push(Triplet::new(index(u, v), index(x, y), w));
                    }
                }
            }
        }
        SparseColMat::try_new_from_triplets(s * s, s * s, &entries).unwrap()
    }

    /// The two halves R⁻¹ and R⁻ᵀ (A = R Rᵀ) compose to the solve, and R⁻¹AR⁻ᵀ = I, for both of
    /// faer's storage of the factor.
    #[test]
    fn the_halves_of_a_solve_compose_to_the_solve() {
        let mut kinds = Vec::new();
        for (s, reach) in [(6, 1), (30, 3)] {
            let a = grid_matrix(s, reach);
            let n = a.nrows();
            let analysis = CholeskyAnalysis::new(a.symbolic(), None).unwrap();
            kinds.push(matches!(
                analysis.symbolic.raw(),
                SymbolicCholeskyRaw::Supernodal(_)
            ));
            let mut factor = CholeskyFactor::new(analysis, a.as_ref()).unwrap();
            let b = Mat::from_fn(n, 3, |i, j| ((i * 7 + j * 3) % 11) as f64 - 5.0);
            let mut solved = b.clone();
            factor.solve_in_place(solved.as_mut());
            let mut halves = b.clone();
            factor.solve_lower_in_place(halves.as_mut());
            factor.solve_lower_transpose_in_place(halves.as_mut());
            // Both are backward stable solves with a diagonally dominant A (κ < 100).
            for j in 0..3 {
                for i in 0..n {
                    assert!((solved[(i, j)] - halves[(i, j)]).abs() < 1e-12, "s = {s}");
                }
            }
            // R⁻¹ A R⁻ᵀ = I: columns of A solved from the left, then the transpose.
            let mut x = a.to_dense();
            factor.solve_lower_in_place(x.as_mut());
            let mut y = x.transpose().to_owned();
            factor.solve_lower_in_place(y.as_mut());
            for j in 0..n {
                for i in 0..n {
                    let expected = if i == j { 1.0 } else { 0.0 };
                    assert!((y[(i, j)] - expected).abs() < 1e-12, "s = {s}");
                }
            }
        }
        assert_eq!(
            kinds,
            [false, true],
            "one simplicial, one supernodal factor"
        );
    }
}
