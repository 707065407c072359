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
//!
//! A second condition, on the modes the scheme does resolve. Rayleigh damping with both α and β
//! has its lightest ratio √(αβ) at ω* = √(α/β); when ω* lies above the first natural frequency ω₁,
//! the modes between are damped less than the first (a Rayleigh pair ζ = 1 % at f₁ and 5 kHz
//! leaves 0.21 % at 520 Hz). The damping study found the forced 35 Hz scene's time averages
//! mesh-dependent with every such pair even where Δt resolves the high modes (ζ_hf = 0.31: the two
//! 14 × 10 meshes 6 % apart), and converged with β alone, whose ratio grows from the first mode
//! up. So the scene also warns when ω* > ω₁, estimated by [`first_frequency_estimate`].

use crate::scene::Scene;

/// The damping ratio ζ_hf of the modes above 1/Δt from which the forced 35 Hz scene's statistics
/// were measured converged (docs/accuracy/damping.md): with β = 5.913e-5 s (ζ₁ = 1 %) the mean
/// energy is within 0.09 % of its resolved value at ζ_hf = 0.296 (Δt = 1e-4 s) and 1.7 % off at
/// ζ_hf = 0.148 (Δt = 2e-4 s).
pub const CONVERGED_HIGH_MODE_RATIO: f64 = 0.25;

/// The section of the documentation that the warning names.
pub const DOCS_SECTION: &str =
    "docs/accuracy/damping.md, section \"When impact statistics converge\"";

/// The page of the modal damping study, which the warning names for a modal ratio.
pub const MODAL_DOCS: &str = "docs/accuracy/modal_damping.md";

/// The Δt (s) of the modal damping study's findings (docs/accuracy/modal_damping.md), the smallest
/// its lines ran but for two runs at 1e-7 s: at larger Δt the time averages of the forced 35 Hz
/// scene change by several percent from one Δt to the next, on every mesh.
pub const MODAL_RATIO_TIME_STEP: f64 = 1e-6;

/// What the modal damping study found for a plate damped mode by mode
/// (docs/accuracy/modal_damping.md, "Findings"), restated for the warning.
pub const MODAL_RATIO_FINDING: &str = "ran the paper's plate with a ratio of 0.5, 1 and 2 % on \
     every mode and judged it by the rule of scripts/converge (three time steps and three meshes \
     that agree). Of its time averages one converged: forced at 60 Hz at a ratio of 1 %, the mean \
     energy (13.53 J within 0.10 J, Argyris 28 x 20 at solver.time_step = 1e-6 s). Forced at 35 Hz, \
     below the first mode, the finest meshes (Argyris 28 x 20 and FVS 28 x 20, about 5 000 and 1 800 \
     free dofs, at solver.time_step = 1e-6 s) lie within 0.2 % of each other on the mean energy at \
     1 % (9.81 J) and 0.6 % at 0.5 and 2 %, and FVS 14 x 10 within 0.1 % of them at 1 %; coarser \
     meshes are up to 19 % high. There, from 1e-5 to 1e-6 s, the mean energy still moved by 2 to \
     5 % at 0.5 and 2 % (under 1 % at 1 %) and the base force by up to 87 %, and from 1e-6 to \
     1e-7 s the time averages moved by up to 1.3 % on FVS 28 x 20 and 4.8 % on Argyris 10 x 7. \
     Impact counts converged on neither scene. Judge a time average by three time steps and three \
     meshes, as scripts/converge does.";

/// The first natural angular frequency (rad/s) of the scene's plate, estimated as a cantilever
/// beam of the plate's length with the plate's bending stiffness per unit width:
/// ω₁ ≈ (1.8751/L)²·√(D/(ρe)), D = Ee³/(12(1−ν²)). On the paper's plate 345.7 rad/s against the
/// 338.2 rad/s of its Argyris 10 × 7 mesh (the two-dimensional plate is 2 % softer); this is
/// what the band condition compares √(α/β) with, which is why an estimate is enough.
pub fn first_frequency_estimate(scene: &Scene) -> f64 {
    let (e, nu) = (scene.material.young_modulus, scene.material.poisson_ratio);
    let thickness = scene.plate.thickness;
    let rigidity = e * thickness.powi(3) / (12.0 * (1.0 - nu * nu));
    let wavenumber = 1.875_104_068_711_961 / scene.plate.length;
    wavenumber * wavenumber * (rigidity / (scene.material.density * thickness)).sqrt()
}

/// Why a scene's impact statistics may not have converged in Δt and mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct StatisticsAdvice {
    /// ζ_hf, the lightest damping ratio among the modes with ω ≥ 1/Δt.
    pub high_mode_ratio: f64,
    /// The dip of Rayleigh damping above the first mode, when it has one: (ω* = √(α/β) (rad/s),
    /// √(αβ), ω₁'s estimate (rad/s)), with ω* > ω₁.
    pub band_dip: Option<(f64, f64, f64)>,
    /// Δt (s) of the scene.
    pub time_step: f64,
    /// β (s) of the scene's Rayleigh damping.
    pub stiffness_proportional: f64,
    /// ζ_m, the scene's modal ratio.
    pub modal_ratio: f64,
}

impl StatisticsAdvice {
    /// The advice for `scene`: `None` without an enabled obstacle (no impacts), or when
    /// ζ_hf ≥ [`CONVERGED_HIGH_MODE_RATIO`] and Rayleigh damping has no dip above the first mode.
    pub fn of(scene: &Scene) -> Option<StatisticsAdvice> {
        if !(scene.obstacle.lower_enabled || scene.obstacle.upper_enabled) {
            return None;
        }
        let dt = scene.solver.time_step;
        let damping = scene.damping.coefficients();
        let high_mode_ratio = damping.lightest_ratio_above(1.0 / dt);
        let omega1 = first_frequency_estimate(scene);
        let band_dip = (damping.alpha > 0.0 && damping.beta > 0.0)
            .then(|| (damping.alpha / damping.beta).sqrt())
            .filter(|&lightest| lightest > omega1)
            .map(|lightest| (lightest, (damping.alpha * damping.beta).sqrt(), omega1));
        (high_mode_ratio < CONVERGED_HIGH_MODE_RATIO || band_dip.is_some()).then_some(
            StatisticsAdvice {
                high_mode_ratio,
                band_dip,
                time_step: dt,
                stiffness_proportional: damping.beta,
                modal_ratio: damping.modal_ratio,
            },
        )
    }

    /// The largest Δt (s) at which the scene's β alone gives ζ_hf ≥ [`CONVERGED_HIGH_MODE_RATIO`]:
    /// β/(2Δt) ≥ ζ_min, Δt ≤ β/(2ζ_min); `None` without β.
    pub fn largest_time_step(&self) -> Option<f64> {
        (self.stiffness_proportional > 0.0)
            .then(|| self.stiffness_proportional / (2.0 * CONVERGED_HIGH_MODE_RATIO))
    }

    /// What the modal damping study found for a plate damped mode by mode (empty without a modal
    /// ratio): [`MODAL_RATIO_FINDING`], and the scene's Δt against the study's finest.
    pub fn modal_ratio_finding(&self) -> String {
        if self.modal_ratio <= 0.0 {
            return String::new();
        }
        let step = if self.time_step <= MODAL_RATIO_TIME_STEP * (1.0 + 1e-9) {
            "as small as this scene's".to_string()
        } else {
            format!("this scene's is {:.3e} s", self.time_step)
        };
        format!(
            "With damping.modal_ratio = {:.3e}: the modal damping study ({MODAL_DOCS}) \
             {MODAL_RATIO_FINDING} Its findings rest on runs at solver.time_step = \
             {MODAL_RATIO_TIME_STEP:.0e} s ({step}). ",
            self.modal_ratio
        )
    }

    /// The warning's text: what was found, the ways out, and where it is documented.
    pub fn message(&self) -> String {
        let band = match self.band_dip {
            Some((lightest, ratio, omega1)) => format!(
                "the Rayleigh damping (damping.alpha, damping.beta) is lightest, ratio {ratio:.3e}, \
                 at omega = sqrt(alpha/beta) = {lightest:.3e} rad/s, above the first natural \
                 frequency (about {omega1:.3e} rad/s): the modes between are damped less than the \
                 first, and with such damping time averages were found to depend on the mesh; \
                 stiffness-proportional damping alone (damping.stiffness_proportional, no \
                 damping.ratio pair) damps every mode above the first more than the first. "
            ),
            None => String::new(),
        };
        let modal = self.modal_ratio_finding();
        if self.high_mode_ratio >= CONVERGED_HIGH_MODE_RATIO {
            return format!(
                "impact statistics may not converge: an obstacle is enabled and {band}{modal}This \
                 warning changes no result. See {DOCS_SECTION}"
            );
        }
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
             ratio {:.3e}, below {CONVERGED_HIGH_MODE_RATIO}: the project found time averages \
             converged in time step and mesh only above it (a necessary condition, not a \
             sufficient one: impact counts did not converge even there). To come within it, \
             {remedy} \
             (beta = zeta_1/(pi f_1) gives mode 1 of frequency f_1 the ratio zeta_1). {band}{modal}This \
             warning changes no result. See {DOCS_SECTION}",
            1.0 / dt,
            self.high_mode_ratio,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

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
    /// every Δt; the Rayleigh pair ζ = 1 % at 53.83 Hz and 5 kHz is light at
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

    /// The band condition: the 5 kHz Rayleigh pair at Δt = 1e-6 s resolves the high modes
    /// (ζ_hf ≈ 0.31) but dips to √(αβ) = 0.21 % at 520 Hz, above the first mode: it warns, naming
    /// the dip. β alone, or with an α whose √(α/β) stays below ω₁, does not.
    #[test]
    fn rayleigh_dip_above_the_first_mode_warns() {
        let mut s = Scene::named("forced-35hz").unwrap();
        s.solver.time_step = 1e-6;
        s.set_all(&[
            ("damping.ratio", "0.01"),
            ("damping.frequency_low", "53.83"),
            ("damping.frequency_high", "5000"),
        ])
        .unwrap();
        let pair = StatisticsAdvice::of(&s).expect("the pair dips above the first mode");
        assert!(pair.high_mode_ratio > CONVERGED_HIGH_MODE_RATIO, "{pair:?}");
        let (lightest, ratio, omega1) = pair.band_dip.unwrap();
        // √(ω_low ω_high) for the pair; ζ·2√(ω_l ω_h)/(ω_l + ω_h) at the dip.
        let (low, high) = (2.0 * PI * 53.83, 2.0 * PI * 5000.0);
        assert!(
            (lightest / (low * high).sqrt() - 1.0).abs() < 1e-9,
            "{lightest}"
        );
        assert!((ratio / (0.02 * (low * high).sqrt() / (low + high)) - 1.0).abs() < 1e-9);
        assert!(
            pair.message().contains("sqrt(alpha/beta)"),
            "{}",
            pair.message()
        );
        // The estimate within 3 % of the Argyris 10 × 7 mesh's ω₁ = 338.23 rad/s.
        assert!((omega1 / 338.23 - 1.0).abs() < 0.03, "{omega1}");
        let mut beta_only = Scene::named("forced-35hz").unwrap();
        beta_only.damping.stiffness_proportional = 5.913e-5;
        assert_eq!(StatisticsAdvice::of(&beta_only), None);
        // α = βω₁²/4 puts the minimum at ω₁/2: no dip above the first mode.
        beta_only.damping.mass_proportional = 5.913e-5 * 338.23f64.powi(2) / 4.0;
        assert_eq!(StatisticsAdvice::of(&beta_only), None);
    }

    /// A modal ratio names the modal damping study, its finding and its finest Δt, against the
    /// scene's; other damping does not.
    #[test]
    fn a_modal_ratio_names_its_study() {
        let mut s = Scene::named("forced-35hz").unwrap();
        assert!(!StatisticsAdvice::of(&s)
            .unwrap()
            .message()
            .contains(MODAL_DOCS));
        s.damping.modal_ratio = 0.01;
        let coarse = StatisticsAdvice::of(&s).unwrap().message();
        assert!(coarse.contains(MODAL_DOCS), "{coarse}");
        assert!(coarse.contains(MODAL_RATIO_FINDING), "{coarse}");
        assert!(coarse.contains("solver.time_step = 1e-6 s"), "{coarse}");
        assert!(coarse.contains("this scene's is 1.000e-4 s"), "{coarse}");
        assert!(coarse.contains(DOCS_SECTION), "{coarse}");
        s.solver.time_step = 1e-6;
        let fine = StatisticsAdvice::of(&s).unwrap().message();
        assert!(fine.contains("as small as this scene's"), "{fine}");
    }
}
