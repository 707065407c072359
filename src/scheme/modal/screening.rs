//! The levelled screening of a prediction (module docs of [`super`]), which hands a prediction
//! it cannot prove inside the bounds on to its values (`stand_ins.rs`).

use super::data::ModalData;
use super::reach::Reach;
use super::stand_ins::StandIns;
use super::{Predicted, Unproven, Valued};
use crate::scheme::bounds::ObstacleBounds;
use crate::scheme::vectors::sum_of_squares;
use faer::linalg::matmul::matmul;
use faer::{Accum, Par};

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
    /// The values of the last prediction that the screening left unproven, with their
    /// stand-ins.
    pub(super) stand_ins: StandIns,
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
            stand_ins: StandIns::new(m),
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
    /// the contact solve, into `out` ([`StandIns::values`], from the last level's low-mode parts);
    /// returns whether there is a stand-in.
    pub(super) fn values(
        &mut self,
        data: &ModalData,
        norm_squared: f64,
        next: &[f64],
        bounds: ObstacleBounds,
        keep_unproven: bool,
        out: &mut [f64],
    ) -> bool {
        let high = self.high_squared[data.levels.len() - 1].sqrt();
        self.stand_ins.values(
            data,
            &self.low_values,
            high,
            norm_squared.sqrt(),
            next,
            bounds,
            keep_unproven,
            out,
        )
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
    /// level proves inside when `keep_unproven` ([`StandIns::values`]).
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
