//! A first guess of the active set of the box LCP y = y* + Wλ ([`super::active_set`]), for the
//! primal–dual active-set method to start from: a few projected Gauss–Seidel sweeps over the
//! indices the unconstrained values y* take past a bound, deepest first.
//!
//! Started from the last step's active set, the method adds at its first iteration every index
//! that the solve on that set leaves past a bound. When a plate moves into an obstacle those are
//! far more than the answer holds: holding the deepest vertices pulls their neighbours back
//! (W couples them), so most of the added ones leave again over the next iterations, each of
//! which factors a block of that size. Gauss–Seidel takes the indices one at a time: λ_i is set
//! to what puts y_i on the bound it crosses (or to 0), and the y of the other candidates moves
//! with it before their turn comes, so that a vertex pulled back by a deeper one is not held. On
//! Argyris 28 × 20, three sweeps leave the method 3.4 iterations on a step's first solve
//! instead of 7.4 (docs/speed.md). A column of W is read only once its λ moves: of the 120
//! candidates of such a step 44, on average, ever are. The guess only chooses where the method
//! starts: its answer is the method's, exact whatever the guess.

use super::{BoundState, Delassus};

/// The Gauss–Seidel sweeps of a first guess.
pub const SWEEPS: usize = 3;

/// The workspace of [`FirstGuess::guess`], kept between steps so that a guess allocates
/// nothing once the candidate sets stop growing.
#[derive(Clone, Debug, Default)]
pub struct FirstGuess {
    /// The candidates, in increasing order.
    candidates: Vec<usize>,
    /// Their places in `candidates`, deepest first: the order of the sweeps.
    order: Vec<usize>,
    /// How far past its bound each candidate's y* lies, by index (for the order).
    depth: Vec<f64>,
    /// W restricted to the candidates, column-major, and whether each column is gathered yet.
    block: Vec<f64>,
    gathered: Vec<bool>,
    /// W_ii of the candidates.
    diagonal: Vec<f64>,
    /// λ and y at the candidates.
    lambda: Vec<f64>,
    y: Vec<f64>,
}

impl FirstGuess {
    /// An empty workspace.
    pub fn new() -> Self {
        Self::default()
    }

    /// Writes into `states` the guess (module docs) for the box LCP with unconstrained values
    /// `y_star`, bounds `lower` ≤ y ≤ `upper` and Delassus operator `w`: [`SWEEPS`] projected
    /// Gauss–Seidel sweeps from λ = 0 over the indices whose y* lies past a bound, in decreasing
    /// order of how far, each index at the bound its λ holds it on and every other index free.
    /// Leaves `states` as it is when no y* lies past a bound.
    pub fn guess<D: Delassus + ?Sized>(
        &mut self,
        w: &mut D,
        y_star: &[f64],
        lower: &[f64],
        upper: &[f64],
        states: &mut [BoundState],
    ) {
        self.depth.clear();
        self.depth.extend(
            y_star
                .iter()
                .zip(lower.iter().zip(upper))
                .map(|(&y, (&lo, &hi))| (lo - y).max(y - hi)),
        );
        self.candidates.clear();
        self.candidates
            .extend((0..y_star.len()).filter(|&i| self.depth[i] > 0.0));
        if self.candidates.is_empty() {
            return;
        }
        let k = self.candidates.len();
        // The block in the indices' order, each column gathered when its λ first changes (its
        // old contents are never read).
        if self.block.len() < k * k {
            self.block.resize(k * k, 0.0);
        }
        self.gathered.clear();
        self.gathered.resize(k, false);
        self.diagonal.clear();
        for &j in &self.candidates {
            self.diagonal.push(w.column(j)[j]);
        }
        // The sweeps' order: deepest first.
        self.order.clear();
        self.order.extend(0..k);
        let (depth, candidates) = (&self.depth, &self.candidates);
        self.order.sort_unstable_by(|&a, &b| {
            depth[candidates[b]]
                .total_cmp(&depth[candidates[a]])
                .then(a.cmp(&b))
        });
        self.lambda.clear();
        self.lambda.resize(k, 0.0);
        self.y.clear();
        self.y.extend(self.candidates.iter().map(|&i| y_star[i]));
        for _ in 0..SWEEPS {
            for &p in &self.order {
                let i = self.candidates[p];
                let (lambda, y, w_ii) = (self.lambda[p], self.y[p], self.diagonal[p]);
                // The λ_i that puts y_i on its lower bound, or on its upper one; else 0.
                let at_lower = lambda + (lower[i] - y) / w_ii;
                let at_upper = lambda + (upper[i] - y) / w_ii;
                let next = if at_lower > 0.0 {
                    at_lower
                } else if at_upper < 0.0 {
                    at_upper
                } else {
                    0.0
                };
                let change = next - lambda;
                if change != 0.0 {
                    self.lambda[p] = next;
                    let column = &mut self.block[p * k..(p + 1) * k];
                    if !self.gathered[p] {
                        self.gathered[p] = true;
                        let source = w.column(i);
                        for (c, &j) in column.iter_mut().zip(&self.candidates) {
                            *c = source[j];
                        }
                    }
                    for (y, &w_qp) in self.y.iter_mut().zip(&*column) {
                        *y += w_qp * change;
                    }
                }
            }
        }
        states.fill(BoundState::Free);
        for (&i, &lambda) in self.candidates.iter().zip(&self.lambda) {
            if lambda > 0.0 {
                states[i] = BoundState::AtLower;
            } else if lambda < 0.0 {
                states[i] = BoundState::AtUpper;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::{solve_box_lcp, DenseDelassus, PdasSettings};

    /// With one index far past its bound, the guess holds that index and leaves free its
    /// neighbour, which the deep one's λ pulls back inside; the method then confirms the guess
    /// in one iteration.
    #[test]
    fn a_deep_index_pulls_its_neighbour_back() {
        // W = [[2, 1], [1, 2]]: holding index 0 at 0 from y*_0 = −1 takes λ_0 = 1/2 and
        // moves y_1 by +1/2, from −0.1 to 0.4.
        let mut w = DenseDelassus::new(2, vec![2.0, 1.0, 1.0, 2.0]);
        let (y_star, lower, upper) = ([-1.0, -0.1], [0.0, 0.0], [1.0, 1.0]);
        let mut states = [BoundState::Free; 2];
        FirstGuess::new().guess(&mut w, &y_star, &lower, &upper, &mut states);
        assert_eq!(states, [BoundState::AtLower, BoundState::Free]);
        let solution = solve_box_lcp(
            &mut w,
            &y_star,
            &lower,
            &upper,
            &states,
            &PdasSettings::default(),
        );
        assert_eq!(solution.states, states);
        assert_eq!(solution.report.iterations, 1);
    }
}
