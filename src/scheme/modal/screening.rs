//! The levelled screening of a prediction (module docs of [`super`]) and, for a prediction it
//! cannot prove inside the bounds, the constrained values handed to the contact solve: exact near
//! an obstacle, a proven-inside stand-in elsewhere.

use super::data::ModalData;
use super::reach::Reach;
use super::{Predicted, Unproven, Valued};
use crate::contact::BoundState;
use crate::scheme::bounds::ObstacleBounds;
use crate::scheme::vectors::sum_of_squares;
use faer::linalg::matmul::matmul;
use faer::{Accum, ColRef, Par};

/// The screening's memory across steps and its workspace.
#[derive(Clone, Debug)]
pub(super) struct Screening {
    /// The low-mode part of the constrained values of the last prediction the levels ran on.
    pub(super) low_values: Vec<f64>,
    /// ‖q_H‖² of that prediction per screening level (H: the modes from the level's mode count
    /// on).
    high_squared: Vec<f64>,
    /// The last proof's reference and its reach.
    pub(super) reach: Reach,
    /// Whether every screening level failed on the last prediction that the reach did not
    /// cover: the next prediction then tries the last level first
    /// ([`Screening::last_level_fails`]).
    pub(super) near: bool,
    /// Per vertex: whether its value handed to the contact solve is the stand-in, the last
    /// screening level's low-mode part ŷ_i, with |y*_i − ŷ_i| ≤ `slack[i]`.
    pub(super) stand_in: Vec<bool>,
    pub(super) slack: Vec<f64>,
    /// ‖q_H‖ past the last screening level and past each stand-in level, for [`Self::values`].
    remainder_norms: Vec<f64>,
}

/// What the screening of one prediction found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Screen {
    /// The prediction lies inside the bounds at every constrained vertex.
    Proven,
    /// Not proven; ‖q‖² of the prediction, which its values need.
    Unproven { norm_squared: f64 },
}

impl Screening {
    /// No proof yet, for the data's dimensions.
    pub(super) fn new(data: &ModalData) -> Screening {
        let m = data.c.nrows();
        Screening {
            low_values: vec![0.0; m],
            high_squared: vec![f64::INFINITY; data.levels.len()],
            reach: Reach::none(data.omega_squared.len()),
            near: false,
            stand_in: vec![false; m],
            slack: vec![0.0; m],
            remainder_norms: Vec::with_capacity(1 + data.stand_in_levels.len()),
        }
    }

    /// Whether the prediction `next`, at distance² `moved_squared` from the reach's reference in
    /// the reach's norm, provably satisfies its `bounds` at every contact point: within the reach
    /// of the last proof, or proven by a screening level (which then becomes the proof).
    pub(super) fn screen(
        &mut self,
        data: &ModalData,
        moved_squared: f64,
        next: &[f64],
        bounds: ObstacleBounds,
    ) -> Screen {
        let [lower, upper] = bounds.levels;
        if self
            .reach
            .covers(moved_squared, lower, upper, &data.reach_metric)
        {
            return Screen::Proven;
        }
        let norm_squared = screening_norms(&data.levels, next, &mut self.high_squared);
        let unproven = Screen::Unproven { norm_squared };
        let total = norm_squared.sqrt();
        if self.near && self.last_level_fails(data, next, bounds, total) {
            return unproven;
        }
        let mut done = 0;
        for (level, &modes) in data.levels.iter().enumerate() {
            // y_L over this level's modes: the last level's partial product plus its new columns.
            let accum = if done == 0 {
                Accum::Replace
            } else {
                Accum::Add
            };
            matmul(
                faer::ColMut::from_slice_mut(&mut self.low_values),
                accum,
                data.c.subcols(done, modes - done),
                faer::ColRef::from_slice(&next[done..modes]),
                1.0,
                Par::Seq,
            );
            done = modes;
            let margin = screening_margin(data, level, self.high_squared[level], total, bounds);
            let proven = self
                .low_values
                .iter()
                .enumerate()
                .all(|(i, &y)| margin(i, y) >= 0.0);
            if proven {
                let margins = self
                    .low_values
                    .iter()
                    .enumerate()
                    .map(|(i, &y)| margin(i, y));
                self.reach
                    .prove(next, total, lower, upper, margins, &data.reach_metric.rows);
                self.near = false;
                return Screen::Proven;
            }
        }
        self.near = true;
        unproven
    }

    /// Near an obstacle, where every level would fail: forms the last level's low-mode part
    /// ŷ = C_L q_L in `low_values` with one product and returns whether some vertex is not
    /// proven inside by it. When it returns true, the levels would all have failed (each
    /// level's remainder bound is never tighter than the last one's) and `low_values` holds what
    /// they would have left there bit for bit: faer forms a column-major matrix–vector product
    /// as one fused multiply-add chain per row over the columns in order, starting from zero, so
    /// the levels' products over the blocks 4, 4, 8, 16 (the first replacing, the others adding)
    /// and this one over the 32 columns make the same chain. When it returns false the caller
    /// runs the levels from the start, so the proof and the reach it sets are those of the
    /// levels.
    fn last_level_fails(
        &mut self,
        data: &ModalData,
        next: &[f64],
        bounds: ObstacleBounds,
        total: f64,
    ) -> bool {
        let last = data.levels.len() - 1;
        let modes = data.levels[last];
        matmul(
            faer::ColMut::from_slice_mut(&mut self.low_values),
            Accum::Replace,
            data.c.subcols(0, modes),
            faer::ColRef::from_slice(&next[..modes]),
            1.0,
            Par::Seq,
        );
        let margin = screening_margin(data, last, self.high_squared[last], total, bounds);
        self.low_values
            .iter()
            .enumerate()
            .any(|(i, &y)| margin(i, y) < 0.0)
    }

    /// After a failed screening of `next` (whose ‖q‖² is `norm_squared`): the values handed to
    /// the contact solve, into `out`; returns whether there is a stand-in. A vertex that the
    /// screening's last level proves inside its `bounds` gets its low-mode part ŷ_i as a
    /// stand-in (inside the bounds by more than the slack r_i that bounds |y*_i − ŷ_i|). On a
    /// basis of up to [`DENSE_LIMIT`](crate::modes::DENSE_LIMIT) modes every other vertex gets its exact value
    /// ŷ_i + (C_H q_H)_i: an m × n product becomes one over the vertices near an obstacle only.
    /// On a larger basis, whose rows of C are long, the others are summed over the modes of the
    /// stand-in levels ([`ModalData::stand_in_levels`]) until one proves them inside. With
    /// `keep_unproven`, and when some stand-in lies past a bound by more than its slack (the
    /// prediction then needs a contact solve whatever the exact values), every vertex gets a
    /// stand-in: the deepest level's partial sum with its remainder bound as slack, even past a
    /// bound, and the contact solve pays a row of C only for the vertices its answer reaches
    /// ([`Screening::reached_stand_ins`]), at the price of solving again. Otherwise the
    /// vertices no level proves inside get their exact values, so that the values lie within
    /// the bounds exactly where the prediction does.
    pub(super) fn values(
        &mut self,
        data: &ModalData,
        norm_squared: f64,
        next: &[f64],
        bounds: ObstacleBounds,
        keep_unproven: bool,
        out: &mut [f64],
    ) -> bool {
        let last = data.levels.len() - 1;
        let total = norm_squared.sqrt();
        let high = &mut self.remainder_norms;
        high.clear();
        high.push(self.high_squared[last].sqrt());
        high.extend(
            data.stand_in_levels
                .iter()
                .map(|&from| sum_of_squares(&next[from..]).sqrt()),
        );
        // First whether each stand-in is proven inside, then whether it is kept.
        let mut past = false;
        for (i, value) in out.iter_mut().enumerate() {
            let round_off = 1e-12 * data.row_norms[i] * total;
            let (lower, upper) = (bounds.lower(i), bounds.upper(i));
            let inside = |y: f64, slack: f64| y - slack >= lower && y + slack <= upper;
            let low = self.low_values[i];
            let (mut stand_in, mut slack) =
                (low, data.high_row_norms[last][i] * high[0] + round_off);
            let mut proven = inside(stand_in, slack);
            let mut done = data.levels[last];
            for (level, &modes) in data.stand_in_levels.iter().enumerate() {
                if proven {
                    break;
                }
                stand_in += partial_row_sum(data, i, done..modes, next);
                done = modes;
                slack = data.stand_in_row_norms[level][i] * high[level + 1] + round_off;
                proven = inside(stand_in, slack);
            }
            *value = stand_in;
            self.stand_in[i] = proven;
            self.slack[i] = slack;
            past |= stand_in + slack < lower || stand_in - slack > upper;
        }
        let deep = !data.stand_in_levels.is_empty() && keep_unproven && past;
        let mut stand_ins = false;
        for (i, value) in out.iter_mut().enumerate() {
            let kept = self.stand_in[i] || deep;
            if !kept {
                *value = self.low_values[i];
            }
            self.stand_in[i] = kept;
            stand_ins |= kept;
        }
        // The exact values, one product per run of consecutive vertices that need one: near
        // contact most vertices do, and one product per vertex spent much of its time on the
        // product's set-up rather than on the dot.
        let mut start = 0;
        while start < out.len() {
            if self.stand_in[start] {
                start += 1;
                continue;
            }
            let end = (start..out.len())
                .find(|&i| self.stand_in[i])
                .unwrap_or(out.len());
            add_high_mode_parts(data, start..end, next, &mut out[start..end]);
            start = end;
        }
        stand_ins
    }

    /// After a contact solve on stand-in values whose answer has y = `y` at the constrained
    /// vertices and contact states `states`: replaces in `y_star` by its exact value y*_i every
    /// stand-in that the answer reached (the vertex is active, or y_i = ŷ_i + (Wλ)_i lies within
    /// the slack of a bound) and returns whether there was one, in which case the solve must run
    /// again. When there was none, every stand-in vertex has λ_i = 0 and
    /// lower ≤ y*_i + (Wλ)_i ≤ upper whatever y*_i within its slack: the answer satisfies the KKT
    /// conditions of the exact QP, so it is its unique solution.
    pub(super) fn reached_stand_ins(
        &mut self,
        data: &ModalData,
        next: &[f64],
        y: &[f64],
        [lower, upper]: [&[f64]; 2],
        states: &[BoundState],
        y_star: &mut [f64],
    ) -> bool {
        let mut reached = false;
        for i in 0..states.len() {
            if self.stand_in[i]
                && (states[i].is_active()
                    || y[i] - self.slack[i] < lower[i]
                    || y[i] + self.slack[i] > upper[i])
            {
                y_star[i] = self.low_values[i] + high_mode_part(data, i, next);
                self.stand_in[i] = false;
                reached = true;
            }
        }
        reached
    }
}

impl<'a> Predicted<'a> {
    /// The screening of the prediction `next` against the `bounds` of every contact point:
    /// `None` when it proves the prediction inside them, otherwise the stage from which its
    /// values are formed.
    pub(in crate::scheme) fn screen(
        self,
        next: &[f64],
        bounds: ObstacleBounds,
    ) -> Option<Unproven<'a>> {
        let Predicted {
            step,
            moved_squared,
        } = self;
        match step
            .screening
            .screen(step.data, moved_squared, next, bounds)
        {
            Screen::Proven => None,
            Screen::Unproven { norm_squared } => Some(Unproven { step, norm_squared }),
        }
    }
}

impl<'a> Unproven<'a> {
    /// The values of the prediction `next` that the contact solve starts from, into `out`:
    /// [`Screening::values`] for the bounds the screening failed on, keeping stand-ins that no
    /// level proves inside when `keep_unproven`.
    pub(in crate::scheme) fn values(
        self,
        next: &[f64],
        bounds: ObstacleBounds,
        keep_unproven: bool,
        out: &mut [f64],
    ) -> Valued<'a> {
        let Unproven { step, norm_squared } = self;
        let stand_ins =
            step.screening
                .values(step.data, norm_squared, next, bounds, keep_unproven, out);
        Valued { step, stand_ins }
    }

    /// On to the contact solve from values the caller evaluated exactly.
    pub(in crate::scheme) fn exact(self) -> Valued<'a> {
        Valued {
            step: self.step,
            stand_ins: false,
        }
    }
}

/// Writes ‖q_H‖² per screening level `levels` into `high` (summed from the last level down) and
/// returns ‖q‖² (summed as [`ModalData::field_sums`] sums it).
pub(super) fn screening_norms(levels: &[usize], q: &[f64], high: &mut [f64]) -> f64 {
    let last = levels.len() - 1;
    let mut tail = sum_of_squares(&q[levels[last]..]);
    high[last] = tail;
    for j in (0..last).rev() {
        tail += sum_of_squares(&q[levels[j]..levels[j + 1]]);
        high[j] = tail;
    }
    sum_of_squares(&q[..levels[last]]) + high[last]
}

/// Point i's screening margin at `level`, as a function of (i, y_i) with y_i its low-mode value
/// C_{i,L} q_L: the distance of y_i to the nearer of its `bounds` less the slack
/// g_i^L ‖q_H‖ + 1e-12 ‖C_i‖ ‖q‖ (the remainder bound, with `high_squared` = ‖q_H‖², plus the
/// round-off of both products, n ε < 1e-12 for any mesh this backend takes; `total` = ‖q‖).
/// Non-negative when the level proves the vertex inside the bounds.
fn screening_margin<'a>(
    data: &'a ModalData,
    level: usize,
    high_squared: f64,
    total: f64,
    bounds: ObstacleBounds<'a>,
) -> impl Fn(usize, f64) -> f64 + 'a {
    let high = high_squared.sqrt();
    let weights = &data.high_row_norms[level];
    move |i, y| {
        let slack = weights[i] * high + 1e-12 * data.row_norms[i] * total;
        (y - slack - bounds.lower(i)).min(bounds.upper(i) - y - slack)
    }
}

/// Σ_{k ∈ modes} C_ik q_k: vertex i's value over a contiguous range of modes.
fn partial_row_sum(data: &ModalData, i: usize, modes: std::ops::Range<usize>, q: &[f64]) -> f64 {
    let count = modes.len();
    data.c_rows.col(i).subrows(modes.start, count).transpose()
        * ColRef::from_slice(&q[modes.start..modes.end])
}

/// (C_H q_H)_i: vertex i's value over the modes past the last screening level.
pub(super) fn high_mode_part(data: &ModalData, i: usize, q: &[f64]) -> f64 {
    let from = data.levels[data.levels.len() - 1];
    let n = q.len();
    data.c_rows.col(i).subrows(from, n - from).transpose() * ColRef::from_slice(&q[from..])
}

/// Adds (C_H q_H)_i to `out[i - rows.start]` for the vertices i in `rows`: one row-major
/// product over the rows, which faer forms row by row with the very dot kernel that
/// [`high_mode_part`]'s one-row product uses (the same accumulators in the same order over the
/// same length, then times α = 1 and added to the destination), so each value is bit-identical
/// to `out[i] + high_mode_part(data, i, q)`.
fn add_high_mode_parts(data: &ModalData, rows: std::ops::Range<usize>, q: &[f64], out: &mut [f64]) {
    let from = data.levels[data.levels.len() - 1];
    let n = q.len();
    let count = rows.len();
    matmul(
        faer::ColMut::from_slice_mut(out),
        Accum::Add,
        data.c_rows
            .subcols(rows.start, count)
            .subrows(from, n - from)
            .transpose(),
        ColRef::from_slice(&q[from..]),
        1.0,
        Par::Seq,
    );
}
