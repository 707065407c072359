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
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};
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
}
