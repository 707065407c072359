//! A scene: the full parameter set of one simulation (`docs/model.md` §8), with serde so that the
//! Rust library, the examples, the FMU and the Python scripts share one definition.
//!
//! Field paths match the FMU variable names: `plate.length`, `solver.time_step`, …  The named
//! scenes of the paper live as JSON files in `scenes/` (embedded here at compile time) and are
//! read by Python as well.

use crate::element::ElementKind;
use crate::error::Error;
use serde::{Deserialize, Serialize};

/// Plate geometry (m). The span `length` runs from the clamped edge x = 0 to the free edge x = Lx.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plate {
    /// Lx (m), default 0.4.
    pub length: f64,
    /// Ly (m), default 0.2.
    pub width: f64,
    /// Full thickness e (m), default 0.01.
    pub thickness: f64,
}

/// Homogeneous isotropic material.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// E (Pa), default 2.1e11.
    pub young_modulus: f64,
    /// ν (1), default 0.3.
    pub poisson_ratio: f64,
    /// ρ (kg/m³), default 7770.
    pub density: f64,
}

/// Structured mesh of the rectangle.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSpec {
    /// Element family: triangles for Argyris, quadrilaterals for FVS.
    pub element: ElementKind,
    /// Cells along x.
    pub nx: usize,
    /// Cells along y.
    pub ny: usize,
}

/// Which solver handles the contact QP of a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum QpChoice {
    /// Accept the unconstrained step when it is feasible, else the active-set method on the
    /// Delassus operator, with clarabel as the fallback.
    Auto,
    /// clarabel on every step that has constraints (the reference).
    Clarabel,
}

/// How the linear part of a step is solved.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LinearChoice {
    /// Modal when the free dofs are few enough for a dense eigenbasis, else sparse.
    Auto,
    /// Dense M-orthonormal eigenbasis of the clamped plate: scalar recurrences per mode.
    Modal,
    /// Sparse Cholesky factorisation of A = M + ½Δt²K.
    Sparse,
}

/// Which impact law the obstacles impose (docs/scheme.md, "Restitution").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ImpactLaw {
    /// The paper's position law for e = 0 (the bound g on u_{n+1}), Newton's law on the
    /// half-step velocities for e > 0.
    Auto,
    /// Newton's law for every e, e = 0 included: to compare it with the paper's scheme.
    Newton,
}

/// Time-stepping settings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Solver {
    /// Δt (s), default 1e-4.
    pub time_step: f64,
    /// Restitution coefficient e ∈ [0, 1] of Newton's impact law, default 0 (the paper's scheme):
    /// a vertex whose contact closes in a step leaves with −e times its arriving velocity.
    pub restitution: f64,
    /// Impact law, default `auto` (a library setting, not an FMU variable).
    #[serde(default = "default_impact_law")]
    pub impact_law: ImpactLaw,
    /// Contact QP solver, default `auto`.
    #[serde(default = "default_qp")]
    pub qp: QpChoice,
    /// Linear backend, default `auto`.
    #[serde(default = "default_linear")]
    pub linear: LinearChoice,
}

fn default_impact_law() -> ImpactLaw {
    ImpactLaw::Auto
}
fn default_qp() -> QpChoice {
    QpChoice::Auto
}
fn default_linear() -> LinearChoice {
    LinearChoice::Auto
}

/// The two rigid flat obstacles g1 ≤ u ≤ g2 (`docs/model.md` §5).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Obstacles {
    /// Whether the lower obstacle exists.
    pub lower_enabled: bool,
    /// Whether the upper obstacle exists.
    pub upper_enabled: bool,
    /// g1 (m), < 0, default −0.01.
    pub lower: f64,
    /// g2 (m), > 0, default 0.01.
    pub upper: f64,
}

/// One of the two obstacles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ObstacleSide {
    /// g1, below the plate.
    Lower,
    /// g2, above the plate.
    Upper,
}

impl ObstacleSide {
    /// The obstacle's parameter name, `obstacle.lower` or `obstacle.upper`.
    pub fn parameter(self) -> &'static str {
        match self {
            ObstacleSide::Lower => "obstacle.lower",
            ObstacleSide::Upper => "obstacle.upper",
        }
    }
}

/// A displacement found past an obstacle by [`Scene::first_outside`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outside {
    /// The obstacle it is past.
    pub obstacle: ObstacleSide,
    /// That obstacle's level (m).
    pub level: f64,
    /// Its index in the slice searched.
    pub index: usize,
    /// The displacement (m).
    pub value: f64,
}

/// Transverse pressure during the motion.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Load {
    /// p (Pa), positive upwards, default 0.
    pub pressure: f64,
}

/// Initial state: static equilibrium under a preload, released at rest.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Initial {
    /// Pressure (Pa) whose static equilibrium (with contact, if it pushes into an obstacle) is u₀.
    pub preload_pressure: f64,
}

/// Built-in base motion z(t) = c sin(2π f t), added to the FMU input `base.displacement`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Base {
    /// c (m), default 0.
    pub amplitude: f64,
    /// f (Hz), default 10.
    pub frequency: f64,
}

/// Rayleigh damping C = αM + βK on the motion relative to the base, w = u − z𝟙 (a plate moving
/// rigidly with its base is not damped). Mode k of the clamped plate gets the damping ratio
/// ζ_k = α/(2ω_k) + βω_k/2. Both default to 0 (the paper's undamped plate).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Damping {
    /// α (1/s), ≥ 0.
    pub mass_proportional: f64,
    /// β (s), ≥ 0.
    pub stiffness_proportional: f64,
}

impl Damping {
    /// Whether C = 0.
    pub fn is_zero(&self) -> bool {
        self.mass_proportional == 0.0 && self.stiffness_proportional == 0.0
    }

    /// The modal damping coefficient c_k = α + βω_k² (1/s) of a mode with ω_k² = `omega_squared`:
    /// in the M-orthonormal eigenbasis C is diagonal with these entries.
    pub fn modal_coefficient(&self, omega_squared: f64) -> f64 {
        self.mass_proportional + self.stiffness_proportional * omega_squared
    }

    /// ζ = α/(2ω) + βω/2 of a mode of angular frequency ω (rad/s).
    pub fn ratio(&self, omega: f64) -> f64 {
        self.mass_proportional / (2.0 * omega) + 0.5 * self.stiffness_proportional * omega
    }
}

/// A full parameter set.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Geometry.
    pub plate: Plate,
    /// Material.
    pub material: Material,
    /// Mesh.
    pub mesh: MeshSpec,
    /// Time stepping.
    pub solver: Solver,
    /// Obstacles.
    pub obstacle: Obstacles,
    /// Load during the motion.
    pub load: Load,
    /// Initial state.
    pub initial: Initial,
    /// Built-in base motion.
    pub base: Base,
    /// Rayleigh damping; absent from a scene file means none.
    #[serde(default)]
    pub damping: Damping,
    /// Horizon (s) used by examples and as the FMU's default stop time.
    pub stop_time: f64,
}

impl Default for Scene {
    /// The FMU's start values: the steel plate of `docs/model.md` §8 on a 10 × 7 Argyris mesh, at
    /// rest between obstacles at ±0.01 m, with no load and no built-in base motion.
    fn default() -> Scene {
        Scene {
            plate: Plate {
                length: 0.4,
                width: 0.2,
                thickness: 0.01,
            },
            material: Material {
                young_modulus: 2.1e11,
                poisson_ratio: 0.3,
                density: 7770.0,
            },
            mesh: MeshSpec {
                element: ElementKind::Argyris,
                nx: 10,
                ny: 7,
            },
            solver: Solver {
                time_step: 1e-4,
                restitution: 0.0,
                impact_law: ImpactLaw::Auto,
                qp: QpChoice::Auto,
                linear: LinearChoice::Auto,
            },
            obstacle: Obstacles {
                lower_enabled: true,
                upper_enabled: true,
                lower: -0.01,
                upper: 0.01,
            },
            load: Load { pressure: 0.0 },
            initial: Initial {
                preload_pressure: 0.0,
            },
            base: Base {
                amplitude: 0.0,
                frequency: 10.0,
            },
            damping: Damping::default(),
            stop_time: 1.0,
        }
    }
}

/// The named scenes shipped in `scenes/`, as (name, JSON text).
pub const NAMED_SCENES: [(&str, &str); 4] = [
    ("forced", include_str!("../scenes/forced.json")),
    ("forced-30hz", include_str!("../scenes/forced-30hz.json")),
    ("forced-35hz", include_str!("../scenes/forced-35hz.json")),
    ("energy", include_str!("../scenes/energy.json")),
];

/// Largest number of cells along one side of a structured mesh: beyond it the dense parts of the
/// setup (point location, Delassus operator) would take minutes, which no FMU host expects.
pub const MAX_CELLS_PER_SIDE: usize = 400;

impl Scene {
    /// Parses a scene from JSON (every field required, unknown fields rejected) and validates it.
    pub fn from_json(text: &str) -> Result<Scene, Error> {
        let scene: Scene = serde_json::from_str(text).map_err(|e| {
            Error::invalid(
                "scene",
                "<json>",
                &format!("is not a valid scene file ({e})"),
            )
        })?;
        scene.validate()?;
        Ok(scene)
    }

    /// One of the [`NAMED_SCENES`], or the FMU defaults for `default`.
    pub fn named(name: &str) -> Result<Scene, Error> {
        if name == "default" {
            return Ok(Scene::default());
        }
        let (_, text) = NAMED_SCENES
            .iter()
            .find(|(n, _)| *n == name)
            .ok_or_else(|| {
                let names: Vec<&str> = NAMED_SCENES.iter().map(|(n, _)| *n).collect();
                Error::invalid(
                    "scene",
                    name,
                    &format!("must be default or one of {names:?}"),
                )
            })?;
        Scene::from_json(text)
    }

    /// The value of one parameter by its dotted name (`plate.length`, `mesh.element`, `stop_time`…),
    /// as it appears in the scene's JSON. This and [`Scene::with`] are the crate's only dotted-path
    /// access to a scene: the FMU's variable binding, [`Scene::set`] and the examples go through them.
    pub fn get(&self, key: &str) -> Result<serde_json::Value, Error> {
        let mut tree = serde_json::to_value(self).expect("a scene always serializes");
        for part in key.split('.') {
            tree = tree
                .get_mut(part)
                .map(serde_json::Value::take)
                .ok_or_else(|| Error::invalid(key, "?", "is not a scene parameter"))?;
        }
        Ok(tree)
    }

    /// A copy of the scene with one parameter replaced by a JSON value. The type is checked (serde),
    /// the range is not: call [`Scene::validate`] on the result.
    pub fn with(&self, key: &str, value: serde_json::Value) -> Result<Scene, Error> {
        let text = value.to_string();
        let mut tree = serde_json::to_value(self).expect("a scene always serializes");
        let mut slot = &mut tree;
        for part in key.split('.') {
            slot = slot
                .get_mut(part)
                .ok_or_else(|| Error::invalid(key, &text, "is not a scene parameter"))?;
        }
        *slot = value;
        serde_json::from_value(tree)
            .map_err(|e| Error::invalid(key, &text, &format!("has the wrong type ({e})")))
    }

    /// Sets one parameter by its dotted FMU-style name (`mesh.nx`, `solver.qp`, `stop_time`…) from
    /// text: numbers, booleans and enumeration names are accepted as they would be written in JSON
    /// (enumerations without quotes). The scene is validated afterwards.
    pub fn set(&mut self, key: &str, value: &str) -> Result<(), Error> {
        let parsed = serde_json::from_str(value)
            .unwrap_or_else(|_| serde_json::Value::String(value.to_string()));
        let updated = self.with(key, parsed)?;
        updated.validate()?;
        *self = updated;
        Ok(())
    }

    /// The scene with what may change during a run neutralised: the tunable obstacle levels and
    /// load pressure, and the horizon `stop_time`. Two simulations whose fixed parts are equal
    /// assemble the same plate and may exchange states.
    pub fn fixed_part(&self) -> Scene {
        let mut s = self.clone();
        s.obstacle.lower = 0.0;
        s.obstacle.upper = 0.0;
        s.load.pressure = 0.0;
        s.stop_time = 0.0;
        s
    }

    /// [`Scene::fixed_part`] with the QP choice `solver.qp` neutralised as well: the QP choice
    /// changes how a step is solved, not what it computes, so a stepper restores a state whose
    /// scene has the same `fixed_part_ignoring_qp` as its own, whichever QP solver wrote it.
    pub fn fixed_part_ignoring_qp(&self) -> Scene {
        let mut s = self.fixed_part();
        s.solver.qp = QpChoice::Auto;
        s
    }

    /// The length that scales the obstacle tolerances (m): g2 − g1 with both obstacles, |g| with
    /// one (its distance from the plate's starting level u = 0, which [`Scene::validate`] keeps
    /// > 0), and 1 m without any.
    pub fn gap(&self) -> f64 {
        match (self.lower_obstacle(), self.upper_obstacle()) {
            (Some(g1), Some(g2)) => g2 - g1,
            (Some(g), None) | (None, Some(g)) => g.abs(),
            (None, None) => 1.0,
        }
    }

    /// The first of the displacements `u` (m, absolute: base plus plate) that lies past an enabled
    /// obstacle by more than `tolerance` (m): u_i < g1 − tolerance or u_i > g2 + tolerance. The
    /// one test of "a vertex outside the obstacles" shared by the stepper, the simulation and the
    /// FMU; `tolerance` is theirs to choose, usually a fraction of [`Scene::gap`].
    pub fn first_outside(&self, u: &[f64], tolerance: f64) -> Option<Outside> {
        let (lower, upper) = (self.lower_obstacle(), self.upper_obstacle());
        u.iter().enumerate().find_map(|(index, &value)| {
            let below = lower
                .filter(|&g| value < g - tolerance)
                .map(|level| (ObstacleSide::Lower, level));
            let above = upper
                .filter(|&g| value > g + tolerance)
                .map(|level| (ObstacleSide::Upper, level));
            below.or(above).map(|(obstacle, level)| Outside {
                obstacle,
                level,
                index,
                value,
            })
        })
    }

    /// Bending stiffness D = E e³ / (12 (1 − ν²)) (N·m).
    pub fn bending_stiffness(&self) -> f64 {
        let m = &self.material;
        m.young_modulus * self.plate.thickness.powi(3)
            / (12.0 * (1.0 - m.poisson_ratio * m.poisson_ratio))
    }

    /// Mass per unit area ρ e (kg/m²).
    pub fn areal_mass(&self) -> f64 {
        self.material.density * self.plate.thickness
    }

    /// Built-in base displacement c sin(2π f t) (m). The sine is the pure-Rust `libm` one, not the
    /// platform's math library, so that every platform computes the same bits (docs/platforms.md).
    pub fn builtin_base(&self, t: f64) -> f64 {
        self.base.amplitude * libm::sin(2.0 * std::f64::consts::PI * self.base.frequency * t)
    }

    /// Enabled lower obstacle level, if any.
    pub fn lower_obstacle(&self) -> Option<f64> {
        self.obstacle.lower_enabled.then_some(self.obstacle.lower)
    }

    /// Enabled upper obstacle level, if any.
    pub fn upper_obstacle(&self) -> Option<f64> {
        self.obstacle.upper_enabled.then_some(self.obstacle.upper)
    }

    /// Checks every parameter against its range; the error names the parameter and the limit.
    pub fn validate(&self) -> Result<(), Error> {
        let positive = |name: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(Error::invalid(name, v, "must be finite and > 0"))
            }
        };
        let finite = |name: &str, v: f64| {
            if v.is_finite() {
                Ok(())
            } else {
                Err(Error::invalid(name, v, "must be finite"))
            }
        };
        positive("plate.length", self.plate.length)?;
        positive("plate.width", self.plate.width)?;
        positive("plate.thickness", self.plate.thickness)?;
        let shorter_side = self.plate.length.min(self.plate.width);
        if self.plate.thickness > shorter_side {
            return Err(Error::invalid(
                "plate.thickness",
                self.plate.thickness,
                &format!("must not exceed the shorter side {shorter_side} m (Kirchhoff–Love is a thin-plate model)"),
            ));
        }
        positive("material.young_modulus", self.material.young_modulus)?;
        let nu = self.material.poisson_ratio;
        if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
            return Err(Error::invalid(
                "material.poisson_ratio",
                nu,
                "must lie in (-1, 0.5) for a stable isotropic material",
            ));
        }
        positive("material.density", self.material.density)?;
        for (name, n) in [("mesh.nx", self.mesh.nx), ("mesh.ny", self.mesh.ny)] {
            if n == 0 || n > MAX_CELLS_PER_SIDE {
                return Err(Error::invalid(
                    name,
                    n,
                    &format!("must lie in [1, {MAX_CELLS_PER_SIDE}]"),
                ));
            }
        }
        positive("solver.time_step", self.solver.time_step)?;
        let e = self.solver.restitution;
        if !(0.0..=1.0).contains(&e) {
            return Err(Error::invalid(
                "solver.restitution",
                e,
                "must lie in [0, 1]",
            ));
        }
        finite("obstacle.lower", self.obstacle.lower)?;
        finite("obstacle.upper", self.obstacle.upper)?;
        if self.obstacle.lower_enabled && self.obstacle.lower >= 0.0 {
            return Err(Error::invalid(
                "obstacle.lower",
                self.obstacle.lower,
                "must be < 0 (the plate starts at u = 0 between the obstacles)",
            ));
        }
        if self.obstacle.upper_enabled && self.obstacle.upper <= 0.0 {
            return Err(Error::invalid(
                "obstacle.upper",
                self.obstacle.upper,
                "must be > 0 (the plate starts at u = 0 between the obstacles)",
            ));
        }
        finite("load.pressure", self.load.pressure)?;
        finite("initial.preload_pressure", self.initial.preload_pressure)?;
        let c = self.base.amplitude;
        if !(c.is_finite() && c >= 0.0) {
            return Err(Error::invalid(
                "base.amplitude",
                c,
                "must be finite and >= 0",
            ));
        }
        let f = self.base.frequency;
        if !(f.is_finite() && f >= 0.0) {
            return Err(Error::invalid(
                "base.frequency",
                f,
                "must be finite and >= 0",
            ));
        }
        let half_gap = [self.lower_obstacle().map(|g| -g), self.upper_obstacle()]
            .into_iter()
            .flatten()
            .fold(f64::INFINITY, f64::min);
        if c > 0.0 && c >= half_gap {
            return Err(Error::invalid(
                "base.amplitude",
                c,
                &format!(
                    "must be < {half_gap} m so that the base sine stays strictly inside the gap"
                ),
            ));
        }
        for (name, v) in [
            ("damping.mass_proportional", self.damping.mass_proportional),
            (
                "damping.stiffness_proportional",
                self.damping.stiffness_proportional,
            ),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Error::invalid(name, v, "must be finite and >= 0"));
            }
        }
        positive("stop_time", self.stop_time)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn named_scenes_parse_and_validate() {
        for (name, _) in NAMED_SCENES {
            Scene::named(name).unwrap();
        }
        Scene::default().validate().unwrap();
    }

    #[test]
    fn set_changes_one_field_and_rejects_bad_values_by_name() {
        let mut s = Scene::default();
        s.set("mesh.element", "fvs").unwrap();
        s.set("mesh.nx", "14").unwrap();
        s.set("solver.qp", "clarabel").unwrap();
        s.set("solver.impact_law", "newton").unwrap();
        assert_eq!(s.mesh.element, ElementKind::Fvs);
        assert_eq!(s.solver.impact_law, ImpactLaw::Newton);
        assert_eq!(s.mesh.nx, 14);
        assert_eq!(s.solver.qp, QpChoice::Clarabel);
        let err = s.set("material.poisson_ratio", "0.5").unwrap_err();
        assert!(err.to_string().contains("material.poisson_ratio"), "{err}");
        assert!(s.set("plate.colour", "1").is_err());
        assert_eq!(
            s.material.poisson_ratio, 0.3,
            "a rejected value leaves the scene unchanged"
        );
    }

    #[test]
    fn damping_defaults_to_none_and_refuses_negative_values_by_name() {
        let s = Scene::named("forced").unwrap();
        assert!(
            s.damping.is_zero(),
            "scene files without damping parse as undamped"
        );
        let mut s = Scene::default();
        s.set("damping.mass_proportional", "3.5").unwrap();
        s.set("damping.stiffness_proportional", "1e-5").unwrap();
        assert_eq!(s.damping.mass_proportional, 3.5);
        for (name, value) in [
            ("damping.mass_proportional", "-1"),
            ("damping.stiffness_proportional", "-1e-9"),
        ] {
            let err = s.set(name, value).unwrap_err();
            assert!(err.to_string().contains(name), "{err}");
        }
        assert_eq!(s.damping.stiffness_proportional, 1e-5);
    }

    #[test]
    fn the_gap_and_the_first_value_outside_follow_the_enabled_obstacles() {
        let mut s = Scene::default();
        (s.obstacle.lower, s.obstacle.upper) = (-0.01, 0.03);
        assert_eq!(s.gap(), 0.04);
        let u = [0.0, 0.031, -0.02];
        let outside = s.first_outside(&u, 1e-6).unwrap();
        assert_eq!(
            (
                outside.obstacle,
                outside.level,
                outside.index,
                outside.value
            ),
            (ObstacleSide::Upper, 0.03, 1, 0.031)
        );
        assert!(s.first_outside(&u, 0.011).is_none(), "within the tolerance");
        s.obstacle.upper_enabled = false;
        assert_eq!(s.gap(), 0.01, "one obstacle: its distance from u = 0");
        let outside = s.first_outside(&u, 1e-6).unwrap();
        assert_eq!((outside.obstacle, outside.index), (ObstacleSide::Lower, 2));
        s.obstacle.lower_enabled = false;
        assert_eq!(s.gap(), 1.0);
        assert!(s.first_outside(&u, 0.0).is_none());
    }

    #[test]
    fn the_fixed_part_ignoring_qp_neutralises_the_qp_choice_only_beyond_the_fixed_part() {
        let s = Scene::default();
        let mut other = s.clone();
        other.solver.qp = QpChoice::Clarabel;
        other.load.pressure = 5.0;
        assert_ne!(s.fixed_part(), other.fixed_part());
        assert_eq!(s.fixed_part_ignoring_qp(), other.fixed_part_ignoring_qp());
        other.solver.time_step *= 2.0;
        assert_ne!(s.fixed_part_ignoring_qp(), other.fixed_part_ignoring_qp());
    }

    #[test]
    fn base_amplitude_must_stay_inside_the_gap() {
        let mut s = Scene::default();
        assert!(s.set("base.amplitude", "0.0099").is_ok());
        let err = s.set("base.amplitude", "0.01").unwrap_err();
        assert!(err.to_string().contains("base.amplitude"));
    }
}
