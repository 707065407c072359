//! How a sampled external base displacement becomes a continuous base motion on the internal grid.
//!
//! The host sets the sample z_k at the communication point t_k and asks for a communication step
//! to t_k + h. The simulation has computed the grid up to t_M ≥ t_k (t_M = t_k when t_k is a grid
//! point; otherwise an earlier step ran ahead to the first grid point after its end) and now
//! computes the grid points t_M + σ, σ = Δt, 2Δt, …, H, up to t_N = t_M + H, the first grid point
//! at or after t_k + h ([`grid`](super::grid)). The external base applied at t_M + σ is
//!
//!   z̃(t_M + σ) = e_k(t_M + σ) + m_k (1 − σ/H),
//!   e_k(t) = z_k + s_k (t − t_k) + ½ a_k (t − t_k)²,      m_k = z̃(t_M) − e_k(t_M),
//!
//! where z̃(t_M) is the value applied at the last computed grid point (at the first step: the
//! sample when the simulation was built), and
//! * s_k is the first derivative sent with the sample, if any, else the backward difference
//!   (z_k − z_{k−1}) / (t_k − t_{k−1}) of the last two samples at their communication points,
//!   else (first step) 0;
//! * a_k is the second derivative sent with the sample, if any, else 0.
//!
//! So the applied base is continuous (no jump, hence no infinite base velocity): the mismatch m_k
//! between what was applied at t_M and the extrapolation of the new sample is blended out
//! linearly over the grid steps this communication step computes. When t_k is a grid point
//! (t_M = t_k) this is z̃(t_k + τ) = z_k + s_k τ + ½ a_k τ² + m_k (1 − τ/H). The grid span H and
//! the offsets are grid times, never the host's raw h, so round-off in the host's h cannot change
//! the result. A communication step that computes no new grid point (it ends before t_M) applies
//! nothing: it only records its sample, for the next backward difference. A communication step
//! that returns early (at an impact, [`super::Simulation::advance`]) has applied the plan up to
//! the grid point where it stopped; the next step blends out the mismatch from there.
//!
//! For a smooth input the applied base is second-order accurate with no lag: the extrapolation
//! errs by at most ½|z''| (t − t_k)² with t − t_k ≤ t_N − t_k < h + Δt, and m_k, the previous
//! extrapolation's error at t_M, is of the same order, so |z̃ − z| = O(max|z''| (h + Δt)²) (at most
//! 2 max|z''| H² + O(H³) for a constant step H = h on the grid).
//!
//! Start-up: the first step has a single sample and, unless a derivative is sent, takes s_0 = 0, so
//! z̃ errs by O(H |z'(t_0)|) over the first two steps: a bump of height O(H) and width 2H. Modes with
//! ω H ≪ 1 feel it as O(ω² |z'| H³), but modes near 1/H ring with an O(|z'| H) amplitude afterwards,
//! so for an input that starts moving the plate's response is first order in H (measured through
//! the FMU: 2.2e-4 m at H = 1e-3 s, halved with H, for a 2 mm, 10 Hz sine; `tests/fmu/test_input.py`).
//! An input that starts at rest, or a host that sends z'(t_0), keeps it second order.

use serde::{Deserialize, Serialize};

/// One sample of the external base displacement, with the derivatives the host sent for it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct InputSample {
    /// z_k (m).
    pub value: f64,
    /// dz/dt at t_k (m/s), if sent.
    pub slope: Option<f64>,
    /// d²z/dt² at t_k (m/s²), if sent.
    pub curvature: Option<f64>,
}

/// What the interpolation remembers between communication steps (part of a simulation's state).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct InputHistory {
    /// The last sample (t_{k−1} − t_start, z_{k−1}) in s and m, once a communication step has run.
    pub last_sample: Option<(f64, f64)>,
    /// The external base applied at the last computed grid point, z̃(t_M) (m).
    pub applied: f64,
}

/// The base motion over the grid steps of one communication step, from [`InputHistory::plan`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InputPlan {
    /// z_k.
    pub sample: f64,
    /// s_k.
    pub slope: f64,
    /// a_k.
    pub curvature: f64,
    /// m_k.
    pub mismatch: f64,
    /// t_M − t_k ≥ 0: how far the last computed grid point lies after the sample (s).
    pub lead: f64,
    /// H = t_N − t_M, the span of grid time the step computes (s).
    pub span: f64,
}

impl InputPlan {
    /// e_k(t_k + τ): the sample extrapolated by τ (s).
    fn extrapolated(&self, tau: f64) -> f64 {
        self.sample + self.slope * tau + 0.5 * self.curvature * tau * tau
    }

    /// z̃(t_M + σ) for σ ∈ [0, H]: z̃(t_M) at σ = 0 (up to the rounding of e_k(t_M) + m_k) and the
    /// extrapolation at σ = H.
    pub fn at(&self, sigma: f64) -> f64 {
        self.extrapolated(self.lead + sigma) + self.mismatch * (1.0 - sigma / self.span)
    }
}

impl InputHistory {
    /// A fresh history whose applied value is `z0` (the sample when the simulation was built).
    pub fn new(z0: f64) -> InputHistory {
        InputHistory {
            last_sample: None,
            applied: z0,
        }
    }

    /// The plan for a communication step whose sample was taken at `sample_time` (t_k − t_start,
    /// s) and that computes the grid span `span` (H, s) from the last computed grid point
    /// `computed` (t_M − t_start ≥ t_k − t_start, s).
    pub fn plan(
        &self,
        sample_time: f64,
        sample: &InputSample,
        computed: f64,
        span: f64,
    ) -> InputPlan {
        let slope = match (sample.slope, self.last_sample) {
            (Some(d), _) => d,
            (None, Some((t0, z0))) if sample_time > t0 => (sample.value - z0) / (sample_time - t0),
            _ => 0.0,
        };
        let mut plan = InputPlan {
            sample: sample.value,
            slope,
            curvature: sample.curvature.unwrap_or(0.0),
            mismatch: 0.0,
            lead: computed - sample_time,
            span,
        };
        plan.mismatch = self.applied - plan.extrapolated(plan.lead);
        plan
    }

    /// Records a completed communication step whose sample was taken at `sample_time` and that
    /// followed `plan` over the grid span `reached` (σ of its last grid point: the plan's span H,
    /// or less when the step returned early).
    pub fn finish(&mut self, sample_time: f64, plan: &InputPlan, reached: f64) {
        self.last_sample = Some((sample_time, plan.sample));
        self.applied = plan.at(reached);
    }

    /// Records the sample `value` taken at `sample_time` by a communication step that computed
    /// no new grid point: nothing is applied, the sample serves the next backward difference.
    pub fn record(&mut self, sample_time: f64, value: f64) {
        self.last_sample = Some((sample_time, value));
    }

    /// Checks a history read from an untrusted source against a simulation whose communication
    /// point is `elapsed` (t − t_start, s): every number finite, the last sample not in the future.
    /// The error names the field and its value.
    pub fn check(&self, elapsed: f64) -> Result<(), String> {
        if !self.applied.is_finite() {
            return Err(format!(
                "input history: the applied base {} m is not finite",
                self.applied
            ));
        }
        if let Some((t, z)) = self.last_sample {
            if !(t.is_finite() && z.is_finite()) {
                return Err(format!(
                    "input history: the last sample ({t} s, {z} m) is not finite"
                ));
            }
            if !(0.0..=elapsed).contains(&t) {
                return Err(format!(
                    "input history: the last sample was taken {t} s after the start, outside [0, {elapsed}] s"
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulation::grid::TimeGrid;

    /// z̃(t_M) = `applied` again at σ = 0: the plan computes e + (z̃(t_M) − e) there, e = e_k(t_M),
    /// two roundings, so it may differ from z̃(t_M) by one ulp of the larger of |z̃(t_M)| and
    /// |z̃(t_M) − e| (the mismatch). The base is continuous: the step that applied z̃(t_M) ended
    /// there, and the plan is evaluated only at σ > 0.
    fn assert_continuous(plan: &InputPlan, applied: f64) {
        let ulp = f64::EPSILON * applied.abs().max(plan.mismatch.abs());
        let jump = (plan.at(0.0) - applied).abs();
        assert!(
            jump <= ulp,
            "z̃ jumps by {jump:e} m at σ = 0 (one ulp: {ulp:e} m)"
        );
    }

    /// Largest |z̃ − z| over [2H, 1]: the first two steps carry the start-up error (no slope yet).
    fn max_error(h: f64, f: impl Fn(f64) -> f64) -> f64 {
        let mut input = InputHistory::new(f(0.0));
        let mut err: f64 = 0.0;
        let steps = (1.0 / h).round() as usize;
        for k in 0..steps {
            let t = k as f64 * h;
            let sample = InputSample {
                value: f(t),
                ..InputSample::default()
            };
            let plan = input.plan(t, &sample, t, h);
            assert_continuous(&plan, input.applied);
            for i in 1..=10 {
                let tau = i as f64 * h / 10.0;
                let e = (plan.at(tau) - f(t + tau)).abs();
                if k >= 2 {
                    err = err.max(e);
                } else {
                    assert!(e <= 2.0 * 0.6 * h, "start-up error {e} is not O(H |z'|)");
                }
            }
            input.finish(t, &plan, plan.span);
        }
        err
    }

    #[test]
    fn sampled_sine_is_second_order_without_lag() {
        let w = 2.0 * std::f64::consts::PI * 10.0;
        let f = |t: f64| 0.009 * (w * t).sin();
        let e1 = max_error(1e-3, f);
        let e2 = max_error(5e-4, f);
        let bound = 2.0 * 0.009 * w * w * 1e-3 * 1e-3;
        assert!(e1 < bound, "error {e1} above the bound {bound}");
        let order = (e1 / e2).log2();
        assert!(order > 1.8, "observed order {order}");
    }

    /// Largest |z̃ − z| at the grid points after t = 0.1 s, for communication steps of size
    /// `scale` × a factor in [0.2, 1.5] (a fixed pseudo-random sequence) on a grid of step
    /// `scale`/10, driven as the simulation drives the plan: the grid runs ahead to the first grid
    /// point after each communication point.
    fn max_error_random_steps(scale: f64, f: impl Fn(f64) -> f64) -> f64 {
        let grid = TimeGrid {
            start: 0.0,
            step: scale / 10.0,
        };
        let mut input = InputHistory::new(f(0.0));
        let (mut t, mut computed, mut err) = (0.0, 0u64, 0.0f64);
        let mut k = 0u32;
        while t < 1.0 {
            k += 1;
            let h = scale * (0.2 + 1.3 * (f64::from(k) * 0.618_034).fract());
            let end = grid.step_end(t, computed, h).unwrap();
            let sample = InputSample {
                value: f(t),
                ..InputSample::default()
            };
            let from = grid.elapsed(computed);
            if end.index == computed {
                input.record(t, sample.value);
            } else {
                let span = (end.index - computed) as f64 * grid.step;
                let plan = input.plan(t, &sample, from, span);
                assert_continuous(&plan, input.applied);
                for i in 1..=end.index - computed {
                    let sigma = i as f64 * grid.step;
                    if from + sigma > 0.1 {
                        err = err.max((plan.at(sigma) - f(from + sigma)).abs());
                    }
                }
                input.finish(t, &plan, plan.span);
            }
            (t, computed) = (end.elapsed(&grid), end.index);
        }
        err
    }

    #[test]
    fn random_steps_off_the_grid_stay_second_order() {
        let w = 2.0 * std::f64::consts::PI * 10.0;
        let f = |t: f64| 0.009 * (w * t).sin();
        let e1 = max_error_random_steps(1e-3, f);
        let e2 = max_error_random_steps(5e-4, f);
        // |z̃ − z| = O(max|z''| (h + Δt)²), h ≤ 1.5 scale, Δt = scale/10: (1.6 scale)² ≈ 2.6 scale².
        let bound = 2.0 * 0.009 * w * w * 2.6e-6;
        assert!(e1 < bound, "error {e1} above the bound {bound}");
        let order = (e1 / e2).log2();
        assert!(order > 1.8, "observed order {order}");
    }

    #[test]
    fn exact_derivatives_reproduce_a_parabola() {
        let f = |t: f64| 1.0 + 2.0 * t - 3.0 * t * t;
        let mut input = InputHistory::new(f(0.0));
        let h = 0.1;
        for k in 0..5 {
            let t = k as f64 * h;
            let sample = InputSample {
                value: f(t),
                slope: Some(2.0 - 6.0 * t),
                curvature: Some(-6.0),
            };
            let plan = input.plan(t, &sample, t, h);
            for tau in [0.25 * h, 0.5 * h, h] {
                assert!((plan.at(tau) - f(t + tau)).abs() < 1e-12);
            }
            input.finish(t, &plan, plan.span);
        }
    }

    #[test]
    fn untrusted_histories_are_checked() {
        let good = InputHistory {
            last_sample: Some((0.5, 1e-3)),
            applied: 2e-3,
        };
        assert!(good.check(0.5).is_ok());
        assert!(good.check(0.4).unwrap_err().contains("outside"));
        let bad = InputHistory {
            applied: f64::INFINITY,
            ..good.clone()
        };
        assert!(bad.check(1.0).unwrap_err().contains("applied"));
        let bad = InputHistory {
            last_sample: Some((0.1, f64::NAN)),
            ..good
        };
        assert!(bad.check(1.0).unwrap_err().contains("not finite"));
    }
}
