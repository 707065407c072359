//! The constrained values that the contact solve of a prediction the screening could not prove
//! inside starts from: exact values, and stand-ins, each a partial sum ŷ_i over the lowest modes
//! with a slack r_i ≥ |y*_i − ŷ_i|; and the exact values of the stand-ins that the solve's answer
//! reaches.
//!
//! On a basis of up to [`DENSE_LIMIT`](crate::modes::DENSE_LIMIT) modes a vertex that the
//! screening's last level proves inside its bounds gets its low-mode part as a stand-in, every
//! other vertex its exact value: an m × n product becomes one over the vertices near an obstacle
//! only. On a larger basis, whose rows of C are long (5 257 modes on Argyris 28 × 20), the others
//! are summed over the modes of the stand-in levels ([`ModalData::stand_in_levels`]) until one
//! proves them inside, with the blockwise remainder bound (`remainder.rs`) as their slack, and
//! may keep a stand-in that no level proves inside: the contact solve then reads a full row only
//! at the vertices its answer reaches. A stand-in is settled ([`StandIns::settle`]) by summing it
//! on to [`ModalData::reached_level`] modes when the vertex is free and inside its bounds, in
//! case that proves it inside, and otherwise to all n modes, its exact value.

use super::data::ModalData;
use crate::contact::BoundState;
use crate::scheme::bounds::ObstacleBounds;
use faer::linalg::matmul::matmul;
use faer::{Accum, ColRef, Par};

/// The stand-ins of the values handed to the last contact solve, and the workspace that forms
/// them.
#[derive(Clone, Debug)]
pub(super) struct StandIns {
    /// Per vertex: whether its value is a stand-in ŷ_i, with |y*_i − ŷ_i| ≤ `slack[i]`.
    pub(super) stand_in: Vec<bool>,
    pub(super) slack: Vec<f64>,
    /// Per vertex: the number of modes its value sums.
    pub(super) depth: Vec<usize>,
    /// ‖q_B‖ per block of the remainder bound, of the prediction of the last values (large
    /// bases).
    q_blocks: Vec<f64>,
    /// ‖q‖ of that prediction, which scales the round-off margin of a slack.
    total: f64,
}

impl StandIns {
    /// The workspace of `m` constrained vertices.
    pub(super) fn new(m: usize) -> StandIns {
        StandIns {
            stand_in: vec![false; m],
            slack: vec![0.0; m],
            depth: vec![0; m],
            q_blocks: Vec::new(),
            total: 0.0,
        }
    }

    /// The values handed to the contact solve of the prediction `next` (‖q‖ = `total`), into
    /// `out`, from the screening's last level (its low-mode parts `low_values` and ‖q_H‖ =
    /// `high`); returns whether there is a stand-in.
    ///
    /// With `keep_unproven` (and stand-in levels), a vertex that no level proves inside its
    /// `bounds` keeps its stand-in as long as some stand-in lies past a bound by more than its
    /// slack: the prediction then needs a contact solve whatever the exact values, and the solve
    /// settles the stand-ins its answer reaches ([`Self::reached`]). Otherwise every value is
    /// exact or a stand-in proven inside, so that a caller can tell from them alone which
    /// vertices the prediction takes past a bound.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn values(
        &mut self,
        data: &ModalData,
        low_values: &[f64],
        high: f64,
        total: f64,
        next: &[f64],
        bounds: ObstacleBounds,
        keep_unproven: bool,
        out: &mut [f64],
    ) -> bool {
        let last = data.levels[data.levels.len() - 1];
        self.total = total;
        let Some(remainder) = &data.remainder else {
            // Small basis: a stand-in where the last screening level proves the vertex inside,
            // the exact value elsewhere.
            let mut stand_ins = false;
            for (i, value) in out.iter_mut().enumerate() {
                let slack =
                    data.high_row_norms[data.levels.len() - 1][i] * high + self.round_off(data, i);
                let low = low_values[i];
                let kept = low - slack >= bounds.lower(i) && low + slack <= bounds.upper(i);
                *value = low;
                self.stand_in[i] = kept;
                self.slack[i] = slack;
                self.depth[i] = if kept { last } else { next.len() };
                stand_ins |= kept;
            }
            add_exact_runs(data, &self.stand_in, next, out);
            return stand_ins;
        };
        remainder.block_norms(next, &mut self.q_blocks);
        let mut past = false;
        for (i, value) in out.iter_mut().enumerate() {
            let (lower, upper) = (bounds.lower(i), bounds.upper(i));
            *value = low_values[i];
            self.stand_in[i] = true;
            self.depth[i] = last;
            self.slack[i] = self.remainder_slack(data, i, last);
            for &level in &data.stand_in_levels {
                if self.proven(i, *value, [lower, upper]) {
                    break;
                }
                self.deepen(data, i, level, next, value);
            }
            past |= *value + self.slack[i] < lower || *value - self.slack[i] > upper;
        }
        if !(keep_unproven && past) {
            for (i, value) in out.iter_mut().enumerate() {
                let bounds = [bounds.lower(i), bounds.upper(i)];
                if !self.proven(i, *value, bounds) {
                    self.settle(data, i, false, 0.0, next, value, bounds);
                }
            }
        }
        self.stand_in.iter().any(|&s| s)
    }

    /// After a contact solve on stand-in values whose answer has y = `y` at the constrained
    /// vertices and contact states `states`: settles in `y_star` ([`Self::settle`]) every
    /// stand-in that the answer reached (the vertex is active, or y_i = ŷ_i + (Wλ)_i lies within
    /// the slack of a bound) and returns whether one of them became exact, in which case the
    /// solve must run again. A stand-in that stays one leaves the answer as it is: its λ_i is 0,
    /// and y_i moves with ŷ_i alone, inside its bounds by the new slack. When no value became
    /// exact, every stand-in vertex has λ_i = 0 and lower ≤ y*_i + (Wλ)_i ≤ upper whatever y*_i
    /// within its slack: the answer satisfies the KKT conditions of the exact QP, so it is its
    /// unique solution.
    pub(super) fn reached(
        &mut self,
        data: &ModalData,
        next: &[f64],
        y: &[f64],
        [lower, upper]: [&[f64]; 2],
        states: &[BoundState],
        y_star: &mut [f64],
    ) -> bool {
        let mut exact = false;
        for i in 0..states.len() {
            let bounds = [lower[i], upper[i]];
            if self.stand_in[i] && (states[i].is_active() || !self.proven(i, y[i], bounds)) {
                let held = states[i].is_active();
                self.settle(
                    data,
                    i,
                    held,
                    y[i] - y_star[i],
                    next,
                    &mut y_star[i],
                    bounds,
                );
                exact |= !self.stand_in[i];
            }
        }
        exact
    }

    /// Whether vertex i's value `y` lies inside `bounds` by more than its slack.
    fn proven(&self, i: usize, y: f64, [lower, upper]: [f64; 2]) -> bool {
        y - self.slack[i] >= lower && y + self.slack[i] <= upper
    }

    /// Settles the stand-in `value` of vertex i, whose answer adds `offset` to it, against its
    /// `bounds` (module docs): unless `held` on a bound or past one, it is summed on to the
    /// reached level and stays a stand-in if that proves value + `offset` inside; otherwise, or
    /// if not, it becomes the exact value.
    #[allow(clippy::too_many_arguments)]
    fn settle(
        &mut self,
        data: &ModalData,
        i: usize,
        held: bool,
        offset: f64,
        next: &[f64],
        value: &mut f64,
        [lower, upper]: [f64; 2],
    ) {
        let inside = (lower..=upper).contains(&(*value + offset));
        if let Some(level) = data
            .reached_level
            .filter(|&l| !held && inside && self.depth[i] < l)
        {
            self.deepen(data, i, level, next, value);
            if self.proven(i, *value + offset, [lower, upper]) {
                return;
            }
        }
        self.deepen(data, i, next.len(), next, value);
    }

    /// Adds vertex i's value over the modes from its depth to `to` to `value`, with the
    /// remainder bound past `to` as its slack; at `to` = n the value is exact.
    fn deepen(&mut self, data: &ModalData, i: usize, to: usize, next: &[f64], value: &mut f64) {
        *value += partial_row_sum(data, i, self.depth[i]..to, next);
        self.depth[i] = to;
        if to == next.len() {
            self.stand_in[i] = false;
            self.slack[i] = 0.0;
        } else {
            self.slack[i] = self.remainder_slack(data, i, to);
        }
    }

    /// The slack of vertex i's stand-in summed to `depth` modes: the remainder bound past it
    /// plus the round-off of both sums.
    fn remainder_slack(&self, data: &ModalData, i: usize, depth: usize) -> f64 {
        let remainder = data
            .remainder
            .as_ref()
            .expect("stand-ins past the screening need the remainder bound");
        remainder.bound(i, depth, &self.q_blocks) + self.round_off(data, i)
    }

    /// The round-off margin of vertex i's slack: 1e-12 ‖C_i‖ ‖q‖ covers the round-off of both
    /// products, n ε < 1e-12 for any mesh this backend takes.
    fn round_off(&self, data: &ModalData, i: usize) -> f64 {
        1e-12 * data.row_norms[i] * self.total
    }
}

/// Σ_{k ∈ modes} C_ik q_k: vertex i's value over a contiguous range of modes.
fn partial_row_sum(data: &ModalData, i: usize, modes: std::ops::Range<usize>, q: &[f64]) -> f64 {
    let count = modes.len();
    data.c_rows.col(i).subrows(modes.start, count).transpose()
        * ColRef::from_slice(&q[modes.start..modes.end])
}

/// (C_H q_H)_i: vertex i's value over the modes past the last screening level.
#[cfg(test)]
pub(super) fn high_mode_part(data: &ModalData, i: usize, q: &[f64]) -> f64 {
    let from = data.levels[data.levels.len() - 1];
    partial_row_sum(data, i, from..q.len(), q)
}

/// Adds the high-mode part (C_H q_H)_i to `out[i]` at every vertex that is not a `stand_in`,
/// one product per run of consecutive such vertices: near contact most vertices are, and one
/// product per vertex spent much of its time on the product's set-up rather than on the dot.
/// faer forms a row-major product row by row with the very dot kernel that [`high_mode_part`]'s
/// one-row product uses (the same accumulators in the same order over the same length, then
/// times α = 1 and added to the destination), so each value is bit-identical to
/// `out[i] + high_mode_part(data, i, q)`.
fn add_exact_runs(data: &ModalData, stand_in: &[bool], q: &[f64], out: &mut [f64]) {
    let from = data.levels[data.levels.len() - 1];
    let n = q.len();
    let mut start = 0;
    while start < out.len() {
        if stand_in[start] {
            start += 1;
            continue;
        }
        let end = (start..out.len())
            .find(|&i| stand_in[i])
            .unwrap_or(out.len());
        matmul(
            faer::ColMut::from_slice_mut(&mut out[start..end]),
            Accum::Add,
            data.c_rows
                .subcols(start, end - start)
                .subrows(from, n - from)
                .transpose(),
            ColRef::from_slice(&q[from..]),
            1.0,
            Par::Seq,
        );
        start = end;
    }
}
