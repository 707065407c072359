//! The mode shapes Φ (free dofs × modes, Φᵀ M_ff Φ = I) and what the modal backend does with
//! them: Φq (a field's free-dof values), Φᵀ M_ff w (a field's modal coordinates), Φᵀv (the modal
//! load of a vector), rows of Φ (the modes' values at given dofs) and single shapes.
//!
//! Up to [`super::DENSE_LIMIT`] free dofs Φ is a dense matrix, and each operation is the dense
//! product the modal backend has always formed (the same faer call, so the same bits). Above it Φ
//! stays factored, [`super::large::FactoredShapes`]: the same operations at the same O(n²) cost
//! per vector, without ever forming the n × n product.

use super::large::FactoredShapes;
use crate::contact::ContactRows;
use faer::{Col, ColRef, Mat};

/// The mode shapes (module docs).
#[derive(Debug)]
pub struct ModeShapes(Kind);

#[derive(Debug)]
enum Kind {
    /// Φ, and M_ff for the modal coordinates.
    Dense { shapes: Mat<f64>, mass: Mat<f64> },
    /// Boxed: a few words against the two matrices of the dense kind.
    Factored(Box<FactoredShapes>),
}

impl ModeShapes {
    /// Dense shapes Φ (free dofs × modes) of the pencil with the dense mass matrix `mass`.
    pub fn dense(shapes: Mat<f64>, mass: Mat<f64>) -> ModeShapes {
        assert_eq!(shapes.nrows(), mass.nrows(), "one row of Φ per free dof");
        ModeShapes(Kind::Dense { shapes, mass })
    }

    /// Factored shapes, from [`super::large::generalized_eigen`].
    pub fn factored(shapes: FactoredShapes) -> ModeShapes {
        ModeShapes(Kind::Factored(Box::new(shapes)))
    }

    /// The number of free dofs (rows of Φ), which is also the number of modes.
    pub fn dimension(&self) -> usize {
        match &self.0 {
            Kind::Dense { shapes, .. } => shapes.nrows(),
            Kind::Factored(f) => f.dimension(),
        }
    }

    /// w = Φq: the free-dof values of the modal coordinates q.
    pub fn apply(&self, q: &[f64]) -> Vec<f64> {
        match &self.0 {
            Kind::Dense { shapes, .. } => {
                let q = Col::from_fn(q.len(), |k| q[k]);
                let w = shapes * &q;
                w.iter().copied().collect()
            }
            Kind::Factored(f) => f.apply(q),
        }
    }

    /// q = Φᵀ M_ff w: the modal coordinates of the free-dof values w (the inverse of
    /// [`Self::apply`], as Φᵀ M_ff Φ = I).
    pub fn coordinates(&self, w: &[f64]) -> Vec<f64> {
        match &self.0 {
            Kind::Dense { shapes, mass } => {
                let n = w.len();
                let w = Col::from_fn(n, |i| w[i]);
                let mw = mass * &w;
                let q = shapes.transpose() * &mw;
                (0..n).map(|k| q[k]).collect()
            }
            Kind::Factored(f) => f.coordinates(w),
        }
    }

    /// Φᵀv for a vector v over the free dofs.
    pub fn project(&self, v: &[f64]) -> Vec<f64> {
        match &self.0 {
            Kind::Dense { shapes, .. } => {
                let projected = shapes.transpose() * ColRef::from_slice(v);
                projected.iter().copied().collect()
            }
            Kind::Factored(f) => f.project(v),
        }
    }

    /// The rows `dofs` of Φ (dofs.len() × modes): row i holds every mode's value at `dofs[i]`.
    pub fn rows(&self, dofs: &[usize]) -> Mat<f64> {
        match &self.0 {
            Kind::Dense { shapes, .. } => {
                Mat::from_fn(dofs.len(), shapes.ncols(), |i, k| shapes[(dofs[i], k)])
            }
            Kind::Factored(f) => f.rows(dofs),
        }
    }

    /// BΦ for the constraint rows B (m × modes): row i holds every mode's value at contact point
    /// i. Rows that all pick one dof are [`Self::rows`] of those dofs, bit for bit; a general row
    /// is its weighted sum of rows of Φ.
    pub fn rows_of(&self, rows: &ContactRows) -> Mat<f64> {
        if let Some(dofs) = rows.selected() {
            return self.rows(dofs);
        }
        match &self.0 {
            Kind::Dense { shapes, .. } => Mat::from_fn(rows.len(), shapes.ncols(), |i, k| {
                let (dofs, weights) = rows.row(i);
                dofs.iter()
                    .zip(weights)
                    .map(|(&d, &w)| w * shapes[(d, k)])
                    .sum()
            }),
            Kind::Factored(f) => {
                let n = f.dimension();
                let mut transpose = Mat::zeros(n, rows.len());
                for i in 0..rows.len() {
                    let column = transpose
                        .col_mut(i)
                        .try_as_col_major_mut()
                        .expect("a column of a matrix is contiguous");
                    rows.add_row(i, 1.0, column.as_slice_mut());
                }
                f.project_columns(transpose.as_ref()).transpose().to_owned()
            }
        }
    }

    /// The shape φ_k of mode k over the free dofs.
    pub fn column(&self, k: usize) -> Vec<f64> {
        match &self.0 {
            Kind::Dense { shapes, .. } => shapes.col(k).iter().copied().collect(),
            Kind::Factored(f) => {
                let mut unit = vec![0.0; f.dimension()];
                unit[k] = 1.0;
                f.apply(&unit)
            }
        }
    }
}
