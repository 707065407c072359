//! The working-set subproblem in the primal variables, for a sparse A: the active dofs are held at
//! their bounds and eliminated, and the others solve the reduced system.
//!
//! For the QP min ½ xᵀ A x − bᵀ x with the dofs E (the constrained dofs c_i of the working set 𝒜)
//! fixed at their bound values g, the other dofs F solve A_FF x_F = b_F − A_FE g, and the
//! multipliers are λ_i = (A x − b)_{c_i} on 𝒜: the same λ and y = B x as the Delassus subproblem
//! W_𝒜𝒜 λ_𝒜 = g − y*_𝒜, without forming any column of W.
//!
//! A_FF is factored as the matrix of A's own sparsity pattern whose rows and columns in E are
//! replaced by those of the diagonal matrix diag(A_jj): the symbolic analysis (ordering,
//! elimination tree, supernodes: a [`CholeskyAnalysis`]) of A is done once, and a change of
//! working set costs one numeric sparse Cholesky factorisation; a working set that repeats from one
//! step to the next (a plate resting on an obstacle) reuses the factor and costs two triangular
//! solves. Each solve is followed by one step of iterative refinement on the reduced system. The
//! factor is allocated on the first solve, so a system that never eliminates anything costs only
//! its vectors.
//!
//! The sign test of the active-set method needs, for each active i, a scale s_i ≤ W_ii; here
//! s_i = 1 / A_{c_i c_i}, which holds because (A⁻¹)_jj ≥ 1 / A_jj for any SPD A (Cauchy–Schwarz).
//! With it a wrong-signed λ_i is tolerated up to tol·A_ii instead of tol / W_ii: the tolerance of
//! [`super::PdasSettings::tol`] in λ is looser by the factor W_ii A_ii (of order one for the mass-
//! dominated A = M + ½Δt²K of a time step).

use super::block_factor::NotPositiveDefinite;
use super::cholesky::{CholeskyAnalysis, CholeskyFactor};
use super::WorkingSetSolver;
use crate::Error;
use faer::sparse::linalg::matmul::sparse_dense_matmul;
use faer::sparse::SparseColMat;
use faer::{Accum, ColMut, Mat, MatMut, Par};
use std::sync::Arc;

/// What an [`EliminatedSystem`] did so far.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EliminatedStats {
    /// Numeric factorisations (one per new working set, and one of A itself when needed).
    pub factorizations: usize,
    /// Right-hand sides solved with a factor.
    pub solves: usize,
}

/// A sparse SPD A whose constrained dofs a working set fixes at their bounds (module docs).
pub struct EliminatedSystem {
    a: Arc<SparseColMat<usize, f64>>,
    /// The constrained dofs c_i.
    constrained: Vec<usize>,
    analysis: CholeskyAnalysis,
    /// A with the rows and columns of the eliminated dofs replaced by diag(A_jj); allocated on the
    /// first factorisation that eliminates anything (until then the factor is A's own).
    reduced: Option<SparseColMat<usize, f64>>,
    /// The numeric factor, made on first use.
    factor: Option<CholeskyFactor>,
    /// The working set (increasing constrained indices) that `factor` eliminates, `None` before
    /// the first factorisation (and after one that failed).
    factored: Option<Vec<usize>>,
    /// Whether each dof is eliminated in the factor being made.
    eliminated: Vec<bool>,
    diagonal: Vec<f64>,
    b: Vec<f64>,
    x_star: Vec<f64>,
    x: Vec<f64>,
    residual: Mat<f64>,
    stats: EliminatedStats,
}

impl EliminatedSystem {
    /// The system of `a` (n × n, SPD, both triangles stored, with the pattern `analysis` was made
    /// for) with the constrained dofs `constrained` (distinct). Factors nothing yet: the first
    /// solve does.
    pub fn new(
        a: Arc<SparseColMat<usize, f64>>,
        analysis: CholeskyAnalysis,
        constrained: &[usize],
    ) -> Result<EliminatedSystem, Error> {
        let n = a.nrows();
        let a_ref = a.as_ref();
        let mut diagonal = vec![0.0; n];
        for (j, d) in diagonal.iter_mut().enumerate() {
            for (i, &v) in a_ref.row_idx_of_col(j).zip(a_ref.val_of_col(j)) {
                if i == j {
                    *d = v;
                }
            }
        }
        if let Some(j) = (0..n).find(|&j| !(diagonal[j] > 0.0 && diagonal[j].is_finite())) {
            return Err(Error::Numerical(format!(
                "the diagonal entry A[{j}, {j}] = {} is not positive",
                diagonal[j]
            )));
        }
        Ok(EliminatedSystem {
            a,
            constrained: constrained.to_vec(),
            analysis,
            reduced: None,
            factor: None,
            factored: None,
            eliminated: vec![false; n],
            diagonal,
            b: vec![0.0; n],
            x_star: vec![0.0; n],
            x: vec![0.0; n],
            residual: Mat::zeros(n, 1),
            stats: EliminatedStats::default(),
        })
    }

    /// A second system on the same A, analysis and constrained dofs, with no factor yet: one can
    /// keep A's factor for unconstrained solves while the other factors working sets.
    pub fn share(&self) -> EliminatedSystem {
        EliminatedSystem {
            a: Arc::clone(&self.a),
            constrained: self.constrained.clone(),
            analysis: self.analysis.clone(),
            reduced: None,
            factor: None,
            factored: None,
            eliminated: vec![false; self.eliminated.len()],
            diagonal: self.diagonal.clone(),
            b: vec![0.0; self.b.len()],
            x_star: vec![0.0; self.x_star.len()],
            x: vec![0.0; self.x.len()],
            residual: Mat::zeros(self.x.len(), 1),
            stats: EliminatedStats::default(),
        }
    }

    /// The analysis of A's pattern.
    pub fn analysis(&self) -> &CholeskyAnalysis {
        &self.analysis
    }

    /// The constrained dofs.
    pub fn constrained(&self) -> &[usize] {
        &self.constrained
    }

    /// Sets the QP of the step: its linear term `b` and its unconstrained minimiser `x_star`
    /// (length n), from which the working-set solves start.
    pub fn set_step(&mut self, b: &[f64], x_star: &[f64]) {
        self.b.copy_from_slice(b);
        self.x_star.copy_from_slice(x_star);
    }

    /// x of the last working-set solve (length n): the QP's minimiser once the active-set method
    /// has identified the set.
    pub fn x(&self) -> &[f64] {
        &self.x
    }

    /// Counts of factorisations and solves.
    pub fn stats(&self) -> EliminatedStats {
        self.stats
    }

    /// x = A⁻¹ b, with no constrained dof eliminated: the unconstrained step. Factors A if the
    /// factor holds a working set or there is none yet.
    pub fn solve_unconstrained(&mut self, b: &[f64], x: &mut [f64]) -> Result<(), Error> {
        x.copy_from_slice(b);
        self.factor_unconstrained()?;
        self.solve_reduced(ColMut::from_slice_mut(x).as_mat_mut());
        Ok(())
    }

    /// x = A⁻¹ b in place on the columns of `b` (n × r) by one solve with the factor, without the
    /// refinement step: several right-hand sides stream the factor once, e.g. a block of columns
    /// of A⁻¹ Bᵀ for the Delassus operator. The solve is backward stable; on the plates its
    /// residual is 2 to 4 times that of the refined solve, whose own residual is the round-off of
    /// forming b − Ax.
    pub fn solve_unconstrained_unrefined_in_place(
        &mut self,
        b: MatMut<'_, f64>,
    ) -> Result<(), Error> {
        self.factor_unconstrained()?;
        self.stats.solves += b.ncols();
        self.factor
            .as_mut()
            .expect("factored just above")
            .solve_in_place(b);
        Ok(())
    }

    /// Makes the factor that of A itself (nothing eliminated), unless it already is: an A that
    /// is not numerically positive definite is reported here.
    pub fn factor_unconstrained(&mut self) -> Result<(), Error> {
        if self.factored.as_deref() != Some(&[]) {
            self.refactor(&[]).map_err(|_| not_positive_definite())?;
        }
        Ok(())
    }

    /// Factors the reduced matrix of the working set `active` (increasing constrained indices).
    fn refactor(&mut self, active: &[usize]) -> Result<(), NotPositiveDefinite> {
        self.factored = None;
        let matrix = if active.is_empty() {
            self.a.as_ref().as_ref()
        } else {
            self.eliminated.fill(false);
            for &i in active {
                self.eliminated[self.constrained[i]] = true;
            }
            // `reduced` is a copy of A: same pattern, same storage order of the values.
            let reduced = self.reduced.get_or_insert_with(|| (*self.a).clone());
            let (eliminated, diagonal) = (&self.eliminated, &self.diagonal);
            let source = self.a.as_ref().as_ref();
            let target = reduced.val_mut();
            for j in 0..source.ncols() {
                let range = source.col_range(j);
                let rows = &source.row_idx()[range.clone()];
                let values = &source.val()[range.clone()];
                for ((&i, &v), t) in rows.iter().zip(values).zip(&mut target[range]) {
                    *t = if !(eliminated[i] || eliminated[j]) {
                        v
                    } else if i == j {
                        diagonal[j]
                    } else {
                        0.0
                    };
                }
            }
            reduced.as_ref()
        };
        match &mut self.factor {
            Some(factor) => factor.refactor(matrix)?,
            None => self.factor = Some(CholeskyFactor::new(self.analysis.clone(), matrix)?),
        }
        self.factored = Some(active.to_vec());
        self.stats.factorizations += 1;
        Ok(())
    }

    /// x ← reduced⁻¹ x for each column of x, with one step of iterative refinement
    /// (r = x − reduced·x̂, x̂ += reduced⁻¹ r).
    fn solve_reduced(&mut self, mut x: MatMut<'_, f64>) {
        let factor = self.factor.as_mut().expect("factored before any solve");
        self.residual.resize_with(x.nrows(), x.ncols(), |_, _| 0.0);
        self.residual.copy_from(x.as_ref());
        factor.solve_in_place(x.as_mut());
        let matrix = match (&self.reduced, self.factored.as_deref()) {
            (Some(reduced), Some(set)) if !set.is_empty() => reduced.as_ref(),
            _ => self.a.as_ref().as_ref(),
        };
        sparse_dense_matmul(
            self.residual.as_mut(),
            Accum::Add,
            matrix,
            x.as_ref(),
            -1.0,
            Par::Seq,
        );
        factor.solve_in_place(self.residual.as_mut());
        x += &self.residual;
        self.stats.solves += x.ncols();
    }
}

fn not_positive_definite() -> Error {
    Error::Numerical("A is not numerically positive definite".to_string())
}

impl WorkingSetSolver for EliminatedSystem {
    fn dim(&self) -> usize {
        self.constrained.len()
    }

    fn solve(
        &mut self,
        active: &[usize],
        bound: &[f64],
        lambda: &mut [f64],
        y: &mut [f64],
        scale: &mut [f64],
    ) -> Result<(), NotPositiveDefinite> {
        lambda.fill(0.0);
        let mut x = std::mem::take(&mut self.x);
        if active.is_empty() {
            x.copy_from_slice(&self.x_star);
        } else {
            if self.factored.as_deref() != Some(active) {
                self.refactor(active)?;
            }
            // b_F − A_FE g_E on the free rows; A_jj g_j on the eliminated ones.
            x.copy_from_slice(&self.b);
            let a = self.a.as_ref();
            for (&i, &g) in active.iter().zip(bound) {
                let j = self.constrained[i];
                for (r, &v) in a.row_idx_of_col(j).zip(a.val_of_col(j)) {
                    x[r] -= v * g;
                }
            }
            for (&i, &g) in active.iter().zip(bound) {
                let j = self.constrained[i];
                x[j] = self.diagonal[j] * g;
            }
            self.solve_reduced(ColMut::from_slice_mut(&mut x).as_mat_mut());
            for (&i, &g) in active.iter().zip(bound) {
                x[self.constrained[i]] = g;
            }
            // λ_i = (A x − b)_{c_i}: A is symmetric, so row c_i is column c_i.
            let a = self.a.as_ref();
            for &i in active {
                let j = self.constrained[i];
                let ax: f64 = a
                    .row_idx_of_col(j)
                    .zip(a.val_of_col(j))
                    .map(|(r, &v)| v * x[r])
                    .sum();
                lambda[i] = ax - self.b[j];
                scale[i] = 1.0 / self.diagonal[j];
            }
        }
        for (yi, &c) in y.iter_mut().zip(&self.constrained) {
            *yi = x[c];
        }
        self.x = x;
        Ok(())
    }

    /// Nothing more: every solve is already refined.
    fn refine(&mut self, _active: &[usize], _bound: &[f64], _lambda: &mut [f64], _y: &mut [f64]) {}
}
