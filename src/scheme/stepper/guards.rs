//! The guards of a step: the contact solve's answer within its bounds, and the overflow tests that
//! refuse a step whose result or outputs are not finite. Each refusal leaves the stepper unchanged,
//! still at t_n. (The base inside the gap is checked by
//! [`check_base`](super::super::state::check_base).)

use super::workspace::Trial;
use super::Run;
use crate::error::Error;
use crate::scene::ObstacleSide;
use crate::scheme::backend::StepFields;

/// Relative tolerance of the bounds on the active-set method's answer, as a fraction of the gap
/// (g2 − g1, or |g| with one obstacle), before the step accepts it. An exact solve puts an active
/// vertex on its bound to round-off of the displacements, which stay within the gap (the stability
/// matrix asserts 1e-9 of the gap on extreme scenes and measures far less); an answer further out
/// is no solution of the step's QP (at a load of 1e20 Pa the method's own convergence test,
/// relative to the largest predicted value, can accept one), and clarabel solves the step instead.
/// Clarabel's answer is then held to [`RESTORE_BOUND_TOLERANCE`], looser because an unpolished
/// interior-point answer may lie a few 1e-8 m out, and equal to it so that every accepted step
/// leaves a state that restores.
///
/// [`RESTORE_BOUND_TOLERANCE`]: super::RESTORE_BOUND_TOLERANCE
pub(super) const ACTIVE_SET_BOUND_TOLERANCE: f64 = 1e-9;

/// A constrained vertex of a step's answer found past its bound of that step.
#[derive(Clone, Copy, Debug)]
pub(super) struct PastBound {
    side: ObstacleSide,
    /// Index among the constrained vertices.
    vertex: usize,
    /// Its displacement relative to the base, w (m).
    value: f64,
    /// Its bound: the obstacle's level relative to the base, or the impact law's bound (m).
    bound: f64,
}

impl PastBound {
    /// "constrained vertex 12 at w = … m relative to the base, past its lower bound … m (the
    /// lower obstacle or the impact law's bound) by … m, more than the tolerance of … m".
    pub(super) fn describe(&self, tolerance: f64) -> String {
        let side = match self.side {
            ObstacleSide::Lower => "lower",
            ObstacleSide::Upper => "upper",
        };
        format!(
            "constrained vertex {} at w = {:e} m relative to the base, past its {side} bound {:e} m \
             (the {side} obstacle or the impact law's bound) by {:e} m, more than the tolerance \
             of {tolerance:e} m",
            self.vertex,
            self.value,
            self.bound,
            (self.value - self.bound).abs()
        )
    }
}

impl Trial {
    /// The first constrained vertex of the next level of `fields` (the contact solve's answer)
    /// that lies past its bound of this step by more than `tolerance` (m), lower bounds first; a
    /// non-finite value counts as past.
    pub(super) fn first_past_bound(
        &mut self,
        fields: &StepFields,
        tolerance: f64,
    ) -> Option<PastBound> {
        fields
            .maps
            .constrained_values(fields.next, &mut self.solved);
        let solved = &self.solved;
        let find = |side, bound: &[f64], inside: &dyn Fn(f64, f64) -> bool| {
            (0..solved.len())
                .find(|&i| !inside(solved[i], bound[i]))
                .map(|vertex| PastBound {
                    side,
                    vertex,
                    value: solved[vertex],
                    bound: bound[vertex],
                })
        };
        find(ObstacleSide::Lower, &self.lower, &|w, lo| {
            w >= lo - tolerance
        })
        .or_else(|| {
            find(ObstacleSide::Upper, &self.upper, &|w, hi| {
                w <= hi + tolerance
            })
        })
    }
}

impl Run {
    /// Whether the outputs after a step to `base_next`, whose new field has squared norm
    /// `norm_squared` and whose contact forces sum to `force_magnitude` in absolute value, are
    /// finite for certain: each output is a sum of at most five products of at most three factors,
    /// each factor bounded by c·N ([`FieldMaps::magnitude_scale`]) or by the largest of the
    /// base and load data; below 1e100 for all of them, no output can reach 1e308.
    ///
    /// [`FieldMaps::magnitude_scale`]: crate::scheme::backend::FieldMaps::magnitude_scale
    fn outputs_provably_finite(
        &self,
        norm_squared: f64,
        base_next: f64,
        force_magnitude: f64,
    ) -> bool {
        let dt = self.scene.solver.time_step;
        let fields = self.magnitude_scale * norm_squared.max(self.current_norm_squared).max(1.0);
        let [z_prev, z_curr] = self.base;
        let data = [
            z_prev.abs(),
            z_curr.abs(),
            base_next.abs(),
            (base_next - z_curr).abs() / dt,
            self.scene.load.pressure.abs(),
            self.pressure[0].abs(),
            self.pressure[1].abs(),
            self.free.total_mass / (dt * dt),
            self.free.area,
            force_magnitude,
        ];
        fields <= 1e100 && data.iter().all(|&v| v <= 1e100)
    }

    /// Refuses a step whose energy or outputs after it (its next level in `fields`) would not be
    /// finite. Cheap when [`Run::outputs_provably_finite`] proves them finite; otherwise they are
    /// evaluated, at O(n).
    pub(super) fn guard_outputs(
        &self,
        fields: &StepFields,
        norm_squared: f64,
        base_next: f64,
        t_next: f64,
        force_magnitude: f64,
    ) -> Result<(), Error> {
        if self.outputs_provably_finite(norm_squared, base_next, force_magnitude) {
            return Ok(());
        }
        let z_curr = self.base[1];
        let p_next = self.scene.load.pressure;
        let (energy, values) = self.model(fields.maps).energy_and_values(
            fields.current,
            fields.next,
            [z_curr, base_next],
            p_next,
            false,
        );
        let reported = [
            energy.kinetic,
            energy.elastic,
            energy.total,
            force_magnitude,
        ];
        if values.iter().chain(&reported).all(|v| v.is_finite()) {
            Ok(())
        } else {
            Err(self.overflow("the energy or an output", t_next, base_next))
        }
    }

    /// The error of a step whose `what` is not finite.
    pub(super) fn overflow(&self, what: &str, t_next: f64, base_next: f64) -> Error {
        Error::Numerical(format!(
            "{what} became non-finite at t = {t_next} s (base displacement {base_next:e} m, \
             load.pressure {:e} Pa): the step is refused and the state stays at t = {} s",
            self.scene.load.pressure,
            self.time()
        ))
    }
}
