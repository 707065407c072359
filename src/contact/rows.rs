//! The constraint rows B of the contact problem (m × n over the unknowns), stored row by row:
//! row i gives the value y_i = B_i x at contact point i. A mesh vertex's row picks one unknown
//! (its value dof, weight 1): a *unit* row, which every operation here treats as the selection
//! it is (`x[d]`, not `1·x[d]` summed), so that problems whose rows are all unit rows — the flat
//! obstacles at the mesh vertices — compute exactly what they computed before general rows
//! existed. A stop's own point has a general row, the element's basis functions at the point.

/// The rows B (module docs).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ContactRows {
    /// Row i's entries are `dofs[starts[i]..starts[i + 1]]`, with `weights` alike.
    starts: Vec<usize>,
    dofs: Vec<usize>,
    weights: Vec<f64>,
    /// Row i's unknown when it is a unit row.
    units: Vec<Option<usize>>,
    /// The unknowns of the rows when every row is a unit row, else empty.
    selection: Vec<usize>,
}

impl ContactRows {
    /// Rows from (unknowns, weights) pairs; a row of one unknown with weight 1 is a unit row.
    ///
    /// # Panics
    /// If a row's unknowns and weights differ in length (a programming error).
    pub fn new<'a>(rows: impl IntoIterator<Item = (&'a [usize], &'a [f64])>) -> ContactRows {
        let mut out = ContactRows {
            starts: vec![0],
            ..ContactRows::default()
        };
        for (dofs, weights) in rows {
            assert_eq!(dofs.len(), weights.len(), "one weight per unknown");
            out.dofs.extend_from_slice(dofs);
            out.weights.extend_from_slice(weights);
            out.starts.push(out.dofs.len());
            out.units.push(match (dofs, weights) {
                ([d], [w]) if *w == 1.0 => Some(*d),
                _ => None,
            });
        }
        if out.units.iter().all(Option::is_some) {
            out.selection = out.units.iter().flatten().copied().collect();
        }
        out
    }

    /// The unit rows of `dofs`: row i picks `x[dofs[i]]`.
    pub fn selection(dofs: &[usize]) -> ContactRows {
        ContactRows::new(dofs.iter().map(|d| (std::slice::from_ref(d), &[1.0][..])))
    }

    /// m, the number of rows.
    pub fn len(&self) -> usize {
        self.units.len()
    }

    /// Whether there is no row.
    pub fn is_empty(&self) -> bool {
        self.units.is_empty()
    }

    /// Row i's unknowns and weights.
    pub fn row(&self, i: usize) -> (&[usize], &[f64]) {
        let range = self.starts[i]..self.starts[i + 1];
        (&self.dofs[range.clone()], &self.weights[range])
    }

    /// Row i's unknown, when it is a unit row.
    pub fn unit(&self, i: usize) -> Option<usize> {
        self.units[i]
    }

    /// The unknowns the rows pick, when every row is a unit row (B is then a selection, which
    /// the primal elimination of the sparse backend needs).
    pub fn selected(&self) -> Option<&[usize]> {
        (self.selection.len() == self.len()).then_some(&self.selection[..])
    }

    /// y_i = B_i x.
    pub fn value(&self, i: usize, x: &[f64]) -> f64 {
        match self.units[i] {
            Some(d) => x[d],
            None => {
                let (dofs, weights) = self.row(i);
                dofs.iter().zip(weights).map(|(&d, &w)| w * x[d]).sum()
            }
        }
    }

    /// y = B x into `out` (length m).
    pub fn values(&self, x: &[f64], out: &mut [f64]) {
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.value(i, x);
        }
    }

    /// out ← out + c B_iᵀ.
    pub fn add_row(&self, i: usize, c: f64, out: &mut [f64]) {
        match self.units[i] {
            Some(d) => out[d] += c,
            None => {
                let (dofs, weights) = self.row(i);
                for (&d, &w) in dofs.iter().zip(weights) {
                    out[d] += c * w;
                }
            }
        }
    }

    /// out ← out + Bᵀ c (length n), skipping the rows whose c_i is 0.
    pub fn add_transpose(&self, c: &[f64], out: &mut [f64]) {
        for (i, &ci) in c.iter().enumerate() {
            if ci != 0.0 {
                self.add_row(i, ci, out);
            }
        }
    }

    /// B_i as a dense vector of length n.
    pub fn dense_row(&self, i: usize, n: usize) -> Vec<f64> {
        let mut row = vec![0.0; n];
        self.add_row(i, 1.0, &mut row);
        row
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_and_general_rows_apply_and_transpose() {
        let rows = ContactRows::new([
            (&[2usize][..], &[1.0][..]),
            (&[0usize, 3][..], &[0.25, 0.75][..]),
        ]);
        assert_eq!(rows.len(), 2);
        assert_eq!(rows.unit(0), Some(2));
        assert_eq!(rows.unit(1), None);
        assert_eq!(rows.selected(), None);
        let x = [4.0, 5.0, 6.0, 8.0];
        let mut y = [0.0; 2];
        rows.values(&x, &mut y);
        assert_eq!(y, [6.0, 7.0]);
        let mut out = [0.0; 4];
        rows.add_transpose(&[2.0, 4.0], &mut out);
        assert_eq!(out, [1.0, 0.0, 2.0, 3.0]);
        assert_eq!(rows.dense_row(1, 4), vec![0.25, 0.0, 0.0, 0.75]);
        let picked = ContactRows::selection(&[3, 1]);
        assert_eq!(picked.selected(), Some(&[3usize, 1][..]));
        assert!(ContactRows::selection(&[]).is_empty());
    }
}
