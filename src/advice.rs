//! Whether a scene's impact statistics can be trusted: the settings in which the time averages and
//! counts of impacting runs were found unconverged in Δt and mesh (docs/accuracy/damping.md,
//! "When impact statistics converge"), which the FMU reports as a warning at initialization.
//!
//! The criterion. A mode of angular frequency ω with ωΔt ≳ 1 is not resolved by the scheme; the
//! mesh's highest modes (ω_max·Δt = 761 on the paper's Argyris 10 × 7 mesh at Δt = 1e-4 s) are far
//! beyond. Impacts feed energy into all modes, so the statistics converge only when the modes the
//! scheme does not resolve are damped out, whatever the scheme does to them: when the lightest
//! damping ratio among the modes with ω ≥ 1/Δt,
//!
//!   ζ_hf = min over ω ≥ 1/Δt of α/(2ω) + βω/2 + ζ_m
//!
//! (the scene's Rayleigh α, β and modal ratio ζ_m), reaches [`CONVERGED_HIGH_MODE_RATIO`]. For
//! stiffness-proportional damping ζ_hf ≥ β/(2Δt), so Δt ≤ β/(2ζ_min) is enough (and always is:
//! while ζ_hf < ζ_min the minimum √(αβ) of ζ lies below 1/(2β)). Without stiffness-proportional
//! damping (mass-proportional, or a light uniform modal ratio) ζ_hf stays at ζ_m (or 0) at every
//! Δt and the warning stands: refining Δt and the mesh only brings in more lightly damped modes.

use crate::scene::Scene;

/// The damping ratio ζ_hf of the modes above 1/Δt from which the forced 35 Hz scene's statistics
/// were measured converged (docs/accuracy/damping.md): with β = 5.913e-5 s (ζ₁ = 1 %) the mean
/// energy is within 0.08 % of its resolved value at ζ_hf = 0.296 (Δt = 1e-4 s) and 1.7 % off at
/// ζ_hf = 0.148 (Δt = 2e-4 s).
pub const CONVERGED_HIGH_MODE_RATIO: f64 = 0.25;

/// The section of the documentation that the warning names.
pub const DOCS_SECTION: &str =
    "docs/accuracy/damping.md, section \"When impact statistics converge\"";

/// Why a scene's impact statistics may not have converged in Δt and mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct StatisticsAdvice {
    /// ζ_hf, the lightest damping ratio among the modes with ω ≥ 1/Δt.
    pub high_mode_ratio: f64,
    /// Δt (s) of the scene.
    pub time_step: f64,
    /// β (s) of the scene's Rayleigh damping.
    pub stiffness_proportional: f64,
}

impl StatisticsAdvice {
    /// The advice for `scene`: `None` without an enabled obstacle (no impacts) or when
    /// ζ_hf ≥ [`CONVERGED_HIGH_MODE_RATIO`].
    pub fn of(scene: &Scene) -> Option<StatisticsAdvice> {
        if !(scene.obstacle.lower_enabled || scene.obstacle.upper_enabled) {
            return None;
        }
        let dt = scene.solver.time_step;
        let damping = scene.damping.coefficients();
        let high_mode_ratio = damping.lightest_ratio_above(1.0 / dt);
        (high_mode_ratio < CONVERGED_HIGH_MODE_RATIO).then_some(StatisticsAdvice {
            high_mode_ratio,
            time_step: dt,
            stiffness_proportional: damping.beta,
        })
    }

    /// The largest Δt (s) at which the scene's β alone gives ζ_hf ≥ [`CONVERGED_HIGH_MODE_RATIO`]:
    /// β/(2Δt) ≥ ζ_min, Δt ≤ β/(2ζ_min); `None` without β.
    pub fn largest_time_step(&self) -> Option<f64> {
        (self.stiffness_proportional > 0.0)
            .then(|| self.stiffness_proportional / (2.0 * CONVERGED_HIGH_MODE_RATIO))
    }

    /// The warning's text: what was found, the ways out, and where it is documented.
    pub fn message(&self) -> String {
        let dt = self.time_step;
        let beta_needed = 2.0 * CONVERGED_HIGH_MODE_RATIO * dt;
        let remedy = match self.largest_time_step() {
            Some(largest) => format!(
                "take solver.time_step <= {largest:.3e} s \
                 (damping.stiffness_proportional/(2*{CONVERGED_HIGH_MODE_RATIO})) or \
                 damping.stiffness_proportional >= {beta_needed:.3e} s"
            ),
            None => format!(
                "add stiffness-proportional damping, damping.stiffness_proportional >= \
                 {beta_needed:.3e} s, as the scene forced-35hz-damped does"
            ),
        };
        format!(
            "impact statistics may not converge: an obstacle is enabled and the modes the scheme \
             does not resolve (omega >= 1/solver.time_step = {:.3e} rad/s) are damped down to the \
             ratio {:.3e}, below the {CONVERGED_HIGH_MODE_RATIO} from which time averages and \
             impact counts were found converged in time step and mesh. To converge, {remedy} \
             (beta = zeta_1/(pi f_1) gives mode 1 of frequency f_1 the ratio zeta_1). This warning \
             changes no result. See {DOCS_SECTION}",
            1.0 / dt,
            self.high_mode_ratio,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The paper's forced scene (undamped) warns; with β = 2ζ₁/ω₁ for ζ₁ = 1 % at its
    /// Δt = 1e-4 s it does not, and at 2e-4 s it does again; without obstacles nothing warns.
    #[test]
    fn warns_on_unconverged_settings_only() {
        let mut s = Scene::named("forced-35hz").unwrap();
        let undamped = StatisticsAdvice::of(&s).expect("undamped with obstacles");
        assert_eq!(undamped.high_mode_ratio, 0.0);
        assert_eq!(undamped.largest_time_step(), None);
        assert!(undamped.message().contains(DOCS_SECTION));
        s.damping.stiffness_proportional = 5.913e-5;
        assert_eq!(StatisticsAdvice::of(&s), None);
        s.solver.time_step = 2e-4;
        let coarse = StatisticsAdvice::of(&s).expect("Δt too large for β");
        assert!((coarse.high_mode_ratio - 0.1478).abs() < 1e-3);
        assert!((coarse.largest_time_step().unwrap() - 1.1826e-4).abs() < 1e-8);
        let text = coarse.message();
        assert!(
            text.contains("solver.time_step <= 1.183e-4 s") && text.contains(">= 1.000e-4 s"),
            "{text}"
        );
        s.obstacle.lower_enabled = false;
        s.obstacle.upper_enabled = false;
        assert_eq!(StatisticsAdvice::of(&s), None);
    }

    /// Mass-proportional damping and a light modal ratio leave the high modes lightly damped at
    /// every Δt; the Rayleigh pair of the first look (ζ = 1 % at 53.83 Hz and 5 kHz) is light at
    /// the paper's Δt.
    #[test]
    fn light_high_frequency_damping_warns() {
        let mut s = Scene::named("forced-35hz").unwrap();
        s.damping.mass_proportional = 6.77;
        s.solver.time_step = 1e-7;
        assert!(StatisticsAdvice::of(&s).is_some());
        s.damping.mass_proportional = 0.0;
        s.damping.modal_ratio = 0.05;
        assert_eq!(StatisticsAdvice::of(&s).unwrap().high_mode_ratio, 0.05);
        s.damping.modal_ratio = 0.0;
        s.solver.time_step = 1e-4;
        s.set_all(&[
            ("damping.ratio", "0.01"),
            ("damping.frequency_low", "53.83"),
            ("damping.frequency_high", "5000"),
        ])
        .unwrap();
        let pair = StatisticsAdvice::of(&s).unwrap();
        assert!((pair.high_mode_ratio - 0.00348).abs() < 1e-4, "{pair:?}");
    }
}
