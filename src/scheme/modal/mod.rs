//! The contact-free part of the scheme in the M-orthonormal eigenbasis of the clamped plate.
//!
//! With w_f = Φ q, Φᵀ M_ff Φ = I, Φᵀ K_ff Φ = Ω² and, for Rayleigh damping C = αM + βK plus the
//! modal ratio ζ_m, Φᵀ C_ff Φ = diag(c_k) with c_k = α + βω_k² + 2ζ_mω_k, the β = ½ scheme (docs/scheme.md) decouples into
//! one scalar recurrence per mode k, with d_k = 1 + ½Δt²ω_k² + ½Δt c_k:
//!   d_k q_{n+1} = 2 q_n − (d_k − Δt c_k) q_{n−1} + (Φᵀ r)_k
//! (start step, undamped: (1 + ½Δt²ω_k²) q_1 = q_0 + (Φᵀ r)_k), where r is the free-dof forcing of
//! the step. All modes are kept: this is the same scheme, not a model reduction. A contact-free
//! step costs O(n) plus the bound check y = C q with C = BΦ (m × n dense), and the Delassus
//! operator W = B A⁻¹ Bᵀ = C D⁻¹ Cᵀ is precomputed.
//!
//! The bound check is screened: with the lowest l modes L and the rest H,
//! y_i = (C_L q_L)_i + (C_H q_H)_i and |(C_H q_H)_i| ≤ ‖(C_H)_i‖ ‖q_H‖ (Cauchy–Schwarz). When every
//! (C_L q_L)_i lies inside its bounds by more than that remainder (plus a round-off margin), the
//! step is proven contact-free at the cost of an m × l product instead of m × n; only steps near
//! an obstacle pay for the full product. The test runs for l = 4, 8, 16, 32 in turn
//! ([`SCREENING_LEVELS`](data::SCREENING_LEVELS)), each level adding its modes' columns to the
//! partial product of the one before, and stops at the first level that proves the step: the
//! remainder bound of a level is
//! never tighter than the next level's (Cauchy–Schwarz over the union of the blocks), so the
//! levels decide exactly what the last one alone would, and a plate away from the obstacles
//! costs an m × 4 product per step. After a prediction that every level failed, the next one
//! tries the last level first (near an obstacle the earlier levels would fail anyway): its one
//! product over the 32 columns leaves the same values bit for bit, as faer forms each row as one
//! fused multiply-add chain over the columns in order. A proof also covers the steps after it while
//! the plate has not moved far enough to reach an obstacle (`reach.rs`): at small time steps most
//! steps do no bound check at all. The contact-free step itself is one fused pass over the modes
//! (`pass.rs`).
//!
//! A prediction the screening cannot prove hands the contact solve its values: exact ones near
//! an obstacle, and stand-ins (a partial sum with its remainder bound as slack) at vertices some
//! level proves inside; the solve evaluates a stand-in in full only when its answer reaches it.
//! On a basis larger than [`DENSE_LIMIT`](crate::modes::DENSE_LIMIT), whose rows of C are long
//! (5 257 modes on Argyris 28 × 20), a vertex gets a stand-in summed over up to 512 modes
//! ([`STAND_IN_LEVELS`](data::STAND_IN_LEVELS)) with a blockwise remainder bound as its slack,
//! and keeps it even unproven when the step needs a contact solve anyway: a step with a QP then
//! reads full rows mostly at the vertices in contact.
//!
//! Files: `data.rs` holds the precomputed [`ModalData`] and its read-only field maps,
//! `screening.rs` the screening, `stand_ins.rs` the values of a prediction it cannot prove
//! inside, `remainder.rs` the bound on the rest of a partial sum, `correction.rs` the contact
//! solve and the correction of the prediction, `pass.rs` and `reach.rs` as above. A step borrows the backend through its stages, each holding what the
//! step has found so far: [`ModalBackend::predict`] gives a [`Predicted`] (with the reach's
//! distance), whose screening either proves it or gives an [`Unproven`] (with ‖q‖²), whose
//! values give a [`Valued`] (with whether any is a stand-in), whose solve gives a [`Corrected`]
//! (with q* kept for the multipliers' work).

mod correction;
mod data;
mod pass;
mod reach;
mod remainder;
mod screening;
mod stand_ins;
#[cfg(test)]
mod tests;

use super::free_system::StepForcing;
use super::sums::FieldSums;
use correction::Corrector;
pub(in crate::scheme) use data::{FreeDofData, ModalData};
use pass::{PassSums, Weights};
use screening::Screening;
use std::sync::Arc;

/// The modal backend: fields are modal coordinates q (w_f = Φ q).
#[derive(Clone, Debug)]
pub(in crate::scheme) struct ModalBackend {
    data: Arc<ModalData>,
    /// The screening's reach and workspace.
    screening: Screening,
    /// The contact solve's workspace and active-set method.
    corrector: Corrector,
}

impl ModalBackend {
    /// A backend over the precomputed modal data.
    pub(in crate::scheme) fn new(data: Arc<ModalData>) -> ModalBackend {
        ModalBackend {
            screening: Screening::new(&data),
            corrector: Corrector::new(data.c.nrows(), data.dimension()),
            data,
        }
    }

    /// The precomputed data, whose methods are the backend's field maps.
    pub(in crate::scheme) fn data(&self) -> &ModalData {
        &self.data
    }

    /// The backend's part of a step, the start step's when `start`.
    fn step(&mut self, start: bool) -> Step<'_> {
        Step {
            data: &self.data,
            screening: &mut self.screening,
            corrector: &mut self.corrector,
            start,
        }
    }

    /// Writes the unconstrained prediction q_{n+1} of every mode's recurrence (module docs) from
    /// `previous` = q_{n−1} and `current` = q_n into `next`, in one fused pass that also forms
    /// the prediction's sums: the translation, the damping quadratic when there is damping, and an
    /// upper bound on ‖q‖² from the distance to the reach's reference.
    pub(in crate::scheme) fn predict(
        &mut self,
        previous: &[f64],
        current: &[f64],
        forcing: &StepForcing,
        next: &mut [f64],
    ) -> (FieldSums, Predicted<'_>) {
        let step = self.step(forcing.start);
        let data = step.data;
        let (current_weight, previous_weight) = if forcing.start {
            (1.0, 0.0)
        } else {
            (2.0, 1.0)
        };
        let weights = Weights {
            current: current_weight,
            previous: previous_weight,
            load: forcing.load,
            translation: forcing.translation,
        };
        let PassSums {
            translation,
            damping,
            moved_squared,
        } = pass::advance(
            &data.recurrence(forcing.start),
            weights,
            previous,
            current,
            step.screening.reach.reference(),
            next,
        );
        let sums = FieldSums {
            norm_squared: step
                .screening
                .reach
                .norm_squared_bound(moved_squared, &data.reach_metric),
            translation,
            damping: data.system(forcing.start).damped.then_some(damping),
        };
        let predicted = Predicted {
            step,
            moved_squared,
        };
        (sums, predicted)
    }
}

/// The backend borrowed for one step: its data, its screening and contact solve, and which system
/// the step has.
pub(in crate::scheme) struct Step<'a> {
    data: &'a ModalData,
    screening: &'a mut Screening,
    corrector: &'a mut Corrector,
    /// Whether this is the start step, whose Delassus operator and correction are those of the
    /// undamped start system.
    start: bool,
}

/// A step whose prediction is in the next level.
pub(in crate::scheme) struct Predicted<'a> {
    step: Step<'a>,
    /// ‖q_{n+1} − q_s‖_w², the prediction's distance² to the reach's reference.
    moved_squared: f64,
}

impl<'a> Predicted<'a> {
    /// The backend's data, whose methods are its field maps.
    pub(in crate::scheme) fn data(&self) -> &'a ModalData {
        self.step.data
    }

    /// On to the contact solve without screening, from values the caller evaluated exactly.
    pub(in crate::scheme) fn exact(self) -> Valued<'a> {
        Valued {
            step: self.step,
            stand_ins: false,
        }
    }
}

/// A step whose prediction every screening level failed to prove inside its bounds; the low-mode
/// values and norms of the last level are in the screening's workspace.
pub(in crate::scheme) struct Unproven<'a> {
    step: Step<'a>,
    /// ‖q_{n+1}‖².
    norm_squared: f64,
}

/// A step whose prediction's constrained values are formed, ready for the contact solve.
pub(in crate::scheme) struct Valued<'a> {
    step: Step<'a>,
    /// Whether some value is a stand-in (the screening's `stand_ins` say which).
    stand_ins: bool,
}

/// A step whose contact solve corrected the prediction; the active-set method holds μ and the
/// corrector q*.
pub(in crate::scheme) struct Corrected<'a> {
    step: Step<'a>,
    /// Whether the values it started from had stand-ins (see [`Valued`]).
    stand_ins: bool,
}
