//! How a sampled external base displacement becomes a continuous base motion inside a
//! communication step.
//!
//! The caller (the FMU's host) sets the sample z_k at the communication point t_k and asks for a
//! communication step that covers the internal grid points t_k + τ, τ = Δt, 2Δt, …, H (H = kΔt, the
//! span the step actually covers on the grid, never the host's raw step size, so that round-off
//! in the host's h cannot change the result). The external base applied at t_k + τ is
//!
//!   z̃(t_k + τ) = z_k + s_k τ + ½ a_k τ² + m_k (1 − τ/H),      m_k = z̃(t_k) − z_k,
//!
//! where z̃(t_k) is the value the previous communication step applied at its end (at the first
//! step: the sample when the simulation was built), and
//! * s_k is the first derivative sent with the sample, if any, else the backward difference
//!   (z_k − z_{k−1}) / (t_k − t_{k−1}) of the last two samples (grid times), else (first step) 0;
//! * a_k is the second derivative sent with the sample, if any, else 0.
//!
//! So the applied base is continuous at every communication point (no jump, hence no infinite base
//! velocity): the mismatch m_k between what was applied and the new sample is blended out linearly
//! over the step. For a smooth input it is second-order accurate with no lag: the linear
//! extrapolation errs by at most |z''| (H τ + τ²)/2 ≤ |z''| H², and m_k, the previous step's
//! extrapolation error, is O(H²) too, so |z̃ − z| ≤ 2 max|z''| H² + O(H³) for a constant step H.
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
    /// The external base applied at the current time, z̃(t_k) (m).
    pub applied: f64,
}

/// The base motion over one communication step, from [`InputHistory::plan`].
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
    /// H = kΔt, the span of grid time the step covers (s).
    pub span: f64,
}

impl InputPlan {
    /// z̃(t_k + τ) for τ ∈ [0, H]: exactly z̃(t_k) at τ = 0 and the extrapolation at τ = H.
    pub fn at(&self, tau: f64) -> f64 {
        self.sample
            + self.slope * tau
            + 0.5 * self.curvature * tau * tau
            + self.mismatch * (1.0 - tau / self.span)
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

    /// The plan for a communication step from grid time `elapsed` (t_k − t_start, s) that covers
    /// the grid span `span` (s), with the sample taken at t_k.
    pub fn plan(&self, elapsed: f64, sample: &InputSample, span: f64) -> InputPlan {
        let slope = match (sample.slope, self.last_sample) {
            (Some(d), _) => d,
            (None, Some((t0, z0))) if elapsed > t0 => (sample.value - z0) / (elapsed - t0),
            _ => 0.0,
        };
        InputPlan {
            sample: sample.value,
            slope,
            curvature: sample.curvature.unwrap_or(0.0),
            mismatch: self.applied - sample.value,
            span,
        }
    }

    /// Records a completed communication step from grid time `elapsed` that followed `plan`.
    pub fn finish(&mut self, elapsed: f64, plan: &InputPlan) {
        self.last_sample = Some((elapsed, plan.sample));
        self.applied = plan.at(plan.span);
    }

    /// Checks a history read from an untrusted source against a simulation now at grid time
    /// `elapsed` (s): every number finite, the last sample not in the future. The error names the
    /// field and its value.
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
            let plan = input.plan(t, &sample, h);
            assert_eq!(plan.at(0.0), input.applied, "continuous at t_k");
            for i in 1..=10 {
                let tau = i as f64 * h / 10.0;
                let e = (plan.at(tau) - f(t + tau)).abs();
                if k >= 2 {
                    err = err.max(e);
                } else {
                    assert!(e <= 2.0 * 0.6 * h, "start-up error {e} is not O(H |z'|)");
                }
            }
            input.finish(t, &plan);
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
            let plan = input.plan(t, &sample, h);
            for tau in [0.25 * h, 0.5 * h, h] {
                assert!((plan.at(tau) - f(t + tau)).abs() < 1e-12);
            }
            input.finish(t, &plan);
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
