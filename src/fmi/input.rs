//! How the sampled input `base.displacement` becomes a continuous base motion inside a doStep.
//!
//! The importer sets z_k at the communication point t_k and calls doStep(t_k, h). Inside the step
//! the external base applied at t = t_k + τ, τ ∈ (0, h], is
//!
//!   z̃(t_k + τ) = z_k + s_k τ + ½ a_k τ² + m_k (1 − τ/h),      m_k = z̃(t_k) − z_k,
//!
//! where z̃(t_k) is the value the previous doStep applied at its end (at the first step: the input
//! value when the simulation was built), and
//! * s_k is the first input derivative sent with fmi2SetRealInputDerivatives (order 1) for this
//!   step if the importer sent one, else the backward difference (z_k − z_{k−1}) / (t_k − t_{k−1})
//!   of the last two samples, else (first step) 0;
//! * a_k is the second input derivative (order 2) if sent, else 0.
//!
//! So the applied base is continuous at every communication point (no jump, hence no infinite base
//! velocity): the mismatch m_k between what was applied and the new sample is blended out linearly
//! over the step. For a smooth input it is second-order accurate with no lag: the linear
//! extrapolation errs by at most |z''| (h τ + τ²)/2 ≤ |z''| h², and m_k, the previous step's
//! extrapolation error, is O(h²) too, so |z̃ − z| ≤ 2 max|z''| h² + O(h³) for a constant step h.
//! Derivatives are used for one doStep only: they must be sent again before the next one.
//!
//! Start-up: the first doStep has a single sample and, unless the importer sends the derivative,
//! takes s_0 = 0, so z̃ errs by O(h |z'(t_0)|) over the first two steps: a bump of height O(h) and
//! width 2h. Modes with ω h ≪ 1 feel it as O(ω² |z'| h³), but modes near 1/h ring with an O(|z'| h)
//! amplitude afterwards, so for an input that starts moving the plate's response is first order in
//! h (measured: 2.2e-4 m at h = 1e-3 s, halved with h, for a 2 mm, 10 Hz sine; tests/fmu/
//! test_input.py). An input that starts at rest, or an importer that sends z'(t_0), keeps it second
//! order.

use serde::{Deserialize, Serialize};

/// Interpolation history of the base input (part of the FMU state).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct BaseInput {
    /// The last sampled communication point (t_{k−1}, z_{k−1}), once a doStep has run.
    pub last_sample: Option<(f64, f64)>,
    /// The external base applied at the current time, z̃(t_k).
    pub applied: f64,
    /// Derivatives sent for the next doStep (orders 1 and 2).
    pub derivatives: [Option<f64>; 2],
}

/// The base motion over one communication step, from [`BaseInput::plan`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepPlan {
    /// z_k.
    pub sample: f64,
    /// s_k.
    pub slope: f64,
    /// a_k.
    pub curvature: f64,
    /// m_k.
    pub mismatch: f64,
    /// h.
    pub h: f64,
}

impl StepPlan {
    /// z̃(t_k + θ h) for θ ∈ [0, 1]; exactly z̃(t_k) at θ = 0 and the extrapolation at θ = 1.
    pub fn at(&self, theta: f64) -> f64 {
        let tau = theta * self.h;
        self.sample
            + self.slope * tau
            + 0.5 * self.curvature * tau * tau
            + self.mismatch * (1.0 - theta)
    }
}

impl BaseInput {
    /// A fresh history whose applied value is `z0` (the input at initialization).
    pub fn new(z0: f64) -> BaseInput {
        BaseInput {
            last_sample: None,
            applied: z0,
            derivatives: [None, None],
        }
    }

    /// The plan for doStep(t, h) with the current sample `z`.
    pub fn plan(&self, t: f64, z: f64, h: f64) -> StepPlan {
        let slope = match (self.derivatives[0], self.last_sample) {
            (Some(d), _) => d,
            (None, Some((t0, z0))) if t > t0 => (z - z0) / (t - t0),
            _ => 0.0,
        };
        StepPlan {
            sample: z,
            slope,
            curvature: self.derivatives[1].unwrap_or(0.0),
            mismatch: self.applied - z,
            h,
        }
    }

    /// Records a completed doStep(t, ·) that followed `plan`.
    pub fn finish(&mut self, t: f64, plan: &StepPlan) {
        self.last_sample = Some((t, plan.sample));
        self.applied = plan.at(1.0);
        self.derivatives = [None, None];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Largest |z̃ − z| over [2h, 1]: the first two steps carry the start-up error (no slope yet).
    fn max_error(h: f64, f: impl Fn(f64) -> f64) -> f64 {
        let mut input = BaseInput::new(f(0.0));
        let mut err: f64 = 0.0;
        let steps = (1.0 / h).round() as usize;
        for k in 0..steps {
            let t = k as f64 * h;
            let plan = input.plan(t, f(t), h);
            assert_eq!(plan.at(0.0), input.applied, "continuous at t_k");
            for i in 1..=10 {
                let theta = i as f64 / 10.0;
                let e = (plan.at(theta) - f(t + theta * h)).abs();
                if k >= 2 {
                    err = err.max(e);
                } else {
                    assert!(e <= 2.0 * 0.6 * h, "start-up error {e} is not O(h |z'|)");
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
        let mut input = BaseInput::new(f(0.0));
        let h = 0.1;
        for k in 0..5 {
            let t = k as f64 * h;
            input.derivatives = [Some(2.0 - 6.0 * t), Some(-6.0)];
            let plan = input.plan(t, f(t), h);
            for theta in [0.25, 0.5, 1.0] {
                assert!((plan.at(theta) - f(t + theta * h)).abs() < 1e-12);
            }
            input.finish(t, &plan);
            assert_eq!(input.derivatives, [None, None], "derivatives are used once");
        }
    }
}
