//! A scene: the full parameter set of one simulation (`docs/model.md` §8), with serde so that the
//! Rust library, the examples, the FMU and the Python scripts share one definition.
//!
//! Field paths match the FMU variable names: `plate.length`, `solver.time_step`, …  The named
//! scenes of the paper live as JSON files in `scenes/` (embedded here at compile time) and are
//! read by Python as well.

use crate::element::ElementKind;
use crate::error::Error;
use serde::{Deserialize, Serialize};

pub mod bounds;
pub mod clamp;
pub mod profile;
pub mod text;
pub use bounds::{Bound, Limit, BOUNDS};
pub use clamp::{Clamp, ClampedEdges, Side};
pub use profile::{Profile, Stop, StopShape};

/// Plate geometry (m) and where it is clamped. With the default clamp the span `length` runs
/// from the clamped edge x = 0 to the free edge x = Lx.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plate {
    /// Lx (m), default 0.4.
    pub length: f64,
    /// Ly (m), default 0.2.
    pub width: f64,
    /// Full thickness e (m), default 0.01.
    pub thickness: f64,
    /// The clamped part Γc of the edge ([`clamp`]'s grammar), default `xmin` (the edge x = 0).
    #[serde(default = "default_clamp")]
    pub clamp: String,
}

fn default_clamp() -> String {
    "xmin".to_string()
}

fn default_profile() -> String {
    "flat".to_string()
}

/// A point of the plate where the FMU reports the deflection and its velocity (`probe1.x`, …).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Probe {
    /// x (m), default 0.
    pub x: f64,
    /// y (m), default 0.
    pub y: f64,
}

/// Number of probe points (`probe1` … `probe4`).
pub const PROBES: usize = 4;

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
    /// The paper's position law for e = 0 (the bound g on u_{n+1}), the persistent law for e > 0.
    Auto,
    /// Newton's law on the half-step velocities at closing contacts and the obstacle at the
    /// others, for every e: the law before the persistent one, kept to compare with it.
    Newton,
    /// The persistent law for every e, e = 0 included: Newton's law at closing contacts and
    /// u_{n+1} ≥ g + e (u_{n−1} − g) at the others, which conserves the energy at e = 1.
    Persistent,
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

/// The two rigid obstacles g1(x) ≤ u ≤ g2(x) (`docs/model.md` §5): each a tunable level and a
/// profile of heights relative to it ([`profile`]), flat by default.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Obstacles {
    /// Whether the lower obstacle exists.
    pub lower_enabled: bool,
    /// Whether the upper obstacle exists.
    pub upper_enabled: bool,
    /// g1 (m), < 0, default −0.01: the lower obstacle's level (its profile's heights add to it).
    pub lower: f64,
    /// g2 (m), > 0, default 0.01: the upper obstacle's level.
    pub upper: f64,
    /// The lower obstacle's profile ([`profile`]'s grammar), default `flat`.
    #[serde(default = "default_profile")]
    pub lower_profile: String,
    /// The upper obstacle's profile, default `flat`.
    #[serde(default = "default_profile")]
    pub upper_profile: String,
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
    /// Both sides, lower first.
    pub const BOTH: [ObstacleSide; 2] = [ObstacleSide::Lower, ObstacleSide::Upper];

    /// The obstacle's parameter name, `obstacle.lower` or `obstacle.upper`.
    pub fn parameter(self) -> &'static str {
        match self {
            ObstacleSide::Lower => "obstacle.lower",
            ObstacleSide::Upper => "obstacle.upper",
        }
    }

    /// The parameter of the obstacle's profile, `obstacle.lower_profile` or
    /// `obstacle.upper_profile`.
    pub fn profile_parameter(self) -> &'static str {
        match self {
            ObstacleSide::Lower => "obstacle.lower_profile",
            ObstacleSide::Upper => "obstacle.upper_profile",
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

/// Transverse pressure during the motion, and gravity.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Load {
    /// p (Pa), positive upwards, default 0.
    pub pressure: f64,
    /// The acceleration of gravity (m/s², ≥ 0, acting in −z), default 0 (no gravity, the paper's
    /// model): the plate's weight ρe·g per unit area adds to the pressure as −ρe·g, in the
    /// preload's static equilibrium (the initial state is the sag) and during the motion.
    #[serde(default)]
    pub gravity: f64,
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

/// Damping of the motion relative to the base, w = u − z𝟙 (a plate moving rigidly with its base is
/// not damped), in one of two equivalent Rayleigh forms, plus an optional modal ratio
/// (docs/scheme.md §10). Every field defaults to 0: the paper's undamped plate, bit for bit.
///
/// * Coefficients: C = αM + βK with α = `mass_proportional`, β = `stiffness_proportional`.
/// * Engineers' form: `ratio` ζ at `frequency_low` f₁ and `frequency_high` f₂ (ω_i = 2πf_i): the
///   Rayleigh pair whose ζ(ω) = α/(2ω) + βω/2 equals ζ at both, α = 2ζω₁ω₂/(ω₁ + ω₂),
///   β = 2ζ/(ω₁ + ω₂) (between f₁ and f₂ the ratio is below ζ, outside above). Exclusive with a
///   non-zero α or β; needs 0 < f₁ < f₂ when ζ > 0.
/// * `modal_ratio` ζ_m: the same ratio added on every mode of the clamped plate, c_k = 2ζ_mω_k in
///   the M-orthonormal eigenbasis (modal backend only), so that mode k has
///   ζ_k = α/(2ω_k) + βω_k/2 + ζ_m.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Damping {
    /// α (1/s), ≥ 0.
    pub mass_proportional: f64,
    /// β (s), ≥ 0.
    pub stiffness_proportional: f64,
    /// ζ (1), ≥ 0, the ratio of the Rayleigh pair at `frequency_low` and `frequency_high`.
    pub ratio: f64,
    /// f₁ (Hz), ≥ 0; with `ratio` > 0, > 0 and < `frequency_high`.
    pub frequency_low: f64,
    /// f₂ (Hz), ≥ 0; with `ratio` > 0, > `frequency_low`.
    pub frequency_high: f64,
    /// ζ_m (1), ≥ 0, the damping ratio added on every mode (modal backend).
    pub modal_ratio: f64,
}

impl Damping {
    /// Whether the damping needs the modal backend: ζ_m > 0.
    pub fn is_modal(&self) -> bool {
        self.modal_ratio > 0.0
    }

    /// The Rayleigh α (1/s) and β (s) the scheme uses: `mass_proportional` and
    /// `stiffness_proportional`, or with `ratio` ζ > 0 the pair α = 2ζω₁ω₂/(ω₁ + ω₂),
    /// β = 2ζ/(ω₁ + ω₂), ω_i = 2πf_i (for a scene that [`Scene::validate`] accepts).
    pub fn rayleigh(&self) -> (f64, f64) {
        if self.ratio > 0.0 {
            let tau = 2.0 * std::f64::consts::PI;
            let (w1, w2) = (tau * self.frequency_low, tau * self.frequency_high);
            let beta = 2.0 * self.ratio / (w1 + w2);
            (beta * w1 * w2, beta)
        } else {
            (self.mass_proportional, self.stiffness_proportional)
        }
    }

    /// The coefficients the scheme applies (see [`DampingCoefficients`]).
    pub fn coefficients(&self) -> DampingCoefficients {
        let (alpha, beta) = self.rayleigh();
        DampingCoefficients {
            alpha,
            beta,
            modal_ratio: self.modal_ratio,
        }
    }

    /// Checks each field against its range in [`BOUNDS`], then their combinations; the error names
    /// the parameters at fault.
    pub fn validate(&self) -> Result<(), Error> {
        for (name, v) in [
            ("damping.mass_proportional", self.mass_proportional),
            (
                "damping.stiffness_proportional",
                self.stiffness_proportional,
            ),
            ("damping.ratio", self.ratio),
            ("damping.frequency_low", self.frequency_low),
            ("damping.frequency_high", self.frequency_high),
            ("damping.modal_ratio", self.modal_ratio),
        ] {
            bounds::check(name, v)?;
        }
        if self.ratio == 0.0 {
            return Ok(());
        }
        for (name, v) in [
            ("damping.mass_proportional", self.mass_proportional),
            (
                "damping.stiffness_proportional",
                self.stiffness_proportional,
            ),
        ] {
            if v != 0.0 {
                return Err(Error::invalid(
                    &format!("damping.ratio and {name}"),
                    format!("{} and {v}", self.ratio),
                    &format!(
                        "sets the Rayleigh damping twice: give damping.ratio with \
                         damping.frequency_low and damping.frequency_high, or {name}, not both"
                    ),
                ));
            }
        }
        if self.frequency_low <= 0.0 {
            return Err(Error::invalid(
                "damping.frequency_low",
                self.frequency_low,
                &format!(
                    "must be > 0 Hz with damping.ratio = {} > 0 (the lower frequency of the \
                     Rayleigh pair)",
                    self.ratio
                ),
            ));
        }
        if self.frequency_high <= self.frequency_low {
            return Err(Error::invalid(
                "damping.frequency_high",
                self.frequency_high,
                &format!(
                    "must be > damping.frequency_low = {} Hz with damping.ratio = {} > 0",
                    self.frequency_low, self.ratio
                ),
            ));
        }
        Ok(())
    }
}

/// The damping as the scheme applies it: Rayleigh C = αM + βK on the free dofs plus, in the
/// M-orthonormal eigenbasis of the clamped plate, 2ζ_mω_k on mode k, so that mode k has the modal
/// coefficient c_k = α + βω_k² + 2ζ_mω_k and the damping ratio ζ_k = α/(2ω_k) + βω_k/2 + ζ_m.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DampingCoefficients {
    /// α (1/s).
    pub alpha: f64,
    /// β (s).
    pub beta: f64,
    /// ζ_m (1).
    pub modal_ratio: f64,
}

impl DampingCoefficients {
    /// Whether C = 0.
    pub fn is_zero(&self) -> bool {
        self.alpha == 0.0 && self.beta == 0.0 && self.modal_ratio == 0.0
    }

    /// The modal damping coefficient c_k = α + βω_k² + 2ζ_mω_k (1/s) of a mode with
    /// ω_k² = `omega_squared`: in the M-orthonormal eigenbasis C is diagonal with these entries.
    /// Without a modal ratio it is α + βω_k², bit for bit.
    pub fn modal_coefficient(&self, omega_squared: f64) -> f64 {
        let rayleigh = self.alpha + self.beta * omega_squared;
        if self.modal_ratio > 0.0 {
            rayleigh + 2.0 * self.modal_ratio * omega_squared.max(0.0).sqrt()
        } else {
            rayleigh
        }
    }

    /// ζ = α/(2ω) + βω/2 + ζ_m of a mode of angular frequency ω (rad/s).
    pub fn ratio(&self, omega: f64) -> f64 {
        self.alpha / (2.0 * omega) + 0.5 * self.beta * omega + self.modal_ratio
    }

    /// The smallest damping ratio ζ(ω) among the modes with ω ≥ `omega` (rad/s): ζ is convex in
    /// ω with its minimum at √(α/β), so the infimum is ζ(max(ω, √(α/β))), and ζ_m without β.
    pub fn lightest_ratio_above(&self, omega: f64) -> f64 {
        if self.beta > 0.0 {
            self.ratio(omega.max((self.alpha / self.beta).sqrt()))
        } else {
            self.modal_ratio
        }
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
    /// Damping; absent from a scene file (or any of its fields) means none.
    #[serde(default)]
    pub damping: Damping,
    /// Probe points, each at (0, 0) unless placed.
    #[serde(default)]
    pub probe1: Probe,
    /// The second probe.
    #[serde(default)]
    pub probe2: Probe,
    /// The third probe.
    #[serde(default)]
    pub probe3: Probe,
    /// The fourth probe.
    #[serde(default)]
    pub probe4: Probe,
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
                clamp: default_clamp(),
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
                lower_profile: default_profile(),
                upper_profile: default_profile(),
            },
            load: Load {
                pressure: 0.0,
                gravity: 0.0,
            },
            initial: Initial {
                preload_pressure: 0.0,
            },
            base: Base {
                amplitude: 0.0,
                frequency: 10.0,
            },
            damping: Damping::default(),
            probe1: Probe::default(),
            probe2: Probe::default(),
            probe3: Probe::default(),
            probe4: Probe::default(),
            stop_time: 1.0,
        }
    }
}

/// The named scenes shipped in `scenes/`, as (name, JSON text). `forced-35hz-damped` is
/// `forced-35hz` with stiffness-proportional damping β = 2ζ₁/ω₁ = 5.913e-5 s, ζ₁ = 1 % on the
/// first mode of the paper's mesh (ω₁ = 338.23 rad/s, 53.83 Hz): the high modes damped enough
/// for its impact statistics to converge at Δt = 1e-4 s (docs/accuracy/damping.md). The last three
/// use the paper's whole model (docs/model.md §8): `stud-corner`, the damped plate shaken at
/// 35 Hz onto a stud under a free corner; `clamped-panel`, a 2 mm panel clamped on all four edges
/// (f₁ = 307.7 Hz), shaken at 250 Hz onto a stud under its centre; `inclined-support`, the
/// `energy` release onto an inclined lower support.
pub const NAMED_SCENES: [(&str, &str); 8] = [
    ("forced", include_str!("../scenes/forced.json")),
    ("forced-30hz", include_str!("../scenes/forced-30hz.json")),
    ("forced-35hz", include_str!("../scenes/forced-35hz.json")),
    (
        "forced-35hz-damped",
        include_str!("../scenes/forced-35hz-damped.json"),
    ),
    ("energy", include_str!("../scenes/energy.json")),
    ("stud-corner", include_str!("../scenes/stud-corner.json")),
    (
        "clamped-panel",
        include_str!("../scenes/clamped-panel.json"),
    ),
    (
        "inclined-support",
        include_str!("../scenes/inclined-support.json"),
    ),
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
        Scene::slot(&mut tree, key)
            .map(serde_json::Value::take)
            .ok_or_else(|| Error::invalid(key, "?", "is not a scene parameter"))
    }

    /// The value of parameter `key` (dotted) in the JSON tree of a scene, for [`Scene::get`],
    /// [`Scene::with`] and a caller that reads or writes many parameters of one tree.
    pub fn slot<'a>(
        tree: &'a mut serde_json::Value,
        key: &str,
    ) -> Option<&'a mut serde_json::Value> {
        key.split('.')
            .try_fold(tree, |slot, part| slot.get_mut(part))
    }

    /// A copy of the scene with one parameter replaced by a JSON value. The type is checked (serde),
    /// the range is not: call [`Scene::validate`] on the result.
    pub fn with(&self, key: &str, value: serde_json::Value) -> Result<Scene, Error> {
        let text = value.to_string();
        let mut tree = serde_json::to_value(self).expect("a scene always serializes");
        *Scene::slot(&mut tree, key)
            .ok_or_else(|| Error::invalid(key, &text, "is not a scene parameter"))? = value;
        serde_json::from_value(tree)
            .map_err(|e| Error::invalid(key, &text, &format!("has the wrong type ({e})")))
    }

    /// Sets one parameter by its dotted FMU-style name (`mesh.nx`, `solver.qp`, `stop_time`…) from
    /// text: numbers, booleans and enumeration names are accepted as they would be written in JSON
    /// (enumerations without quotes). The scene is validated afterwards.
    pub fn set(&mut self, key: &str, value: &str) -> Result<(), Error> {
        self.set_all(&[(key, value)])
    }

    /// Sets several parameters as [`Scene::set`] does, validating once after the last, so that
    /// parameters valid only together (`damping.ratio` and its two frequencies) can be given in
    /// any order. On an error the scene is unchanged.
    pub fn set_all(&mut self, pairs: &[(&str, &str)]) -> Result<(), Error> {
        let mut updated = self.clone();
        for &(key, value) in pairs {
            let parsed = serde_json::from_str(value)
                .unwrap_or_else(|_| serde_json::Value::String(value.to_string()));
            updated = updated.with(key, parsed)?;
        }
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

    /// The dotted name of the first parameter whose value differs between `self` and `other`, in
    /// alphabetical order of the names, with both values as JSON: what a message names when two
    /// scenes must agree (a restored state's fixed parameters and the running model's).
    pub fn first_difference(&self, other: &Scene) -> Option<(String, String, String)> {
        fn walk(
            a: &serde_json::Value,
            b: &serde_json::Value,
            path: &str,
        ) -> Option<(String, String, String)> {
            match (a, b) {
                (serde_json::Value::Object(x), serde_json::Value::Object(y)) => {
                    x.iter().find_map(|(key, value)| {
                        let name = if path.is_empty() {
                            key.clone()
                        } else {
                            format!("{path}.{key}")
                        };
                        walk(value, y.get(key).unwrap_or(&serde_json::Value::Null), &name)
                    })
                }
                _ if a != b => Some((path.to_string(), a.to_string(), b.to_string())),
                _ => None,
            }
        }
        let tree = |s: &Scene| serde_json::to_value(s).expect("a scene always serializes");
        walk(&tree(self), &tree(other), "")
    }

    /// The length that scales the obstacle tolerances (m): the room the plate at rest has, from
    /// u = 0 to the nearest point of each enabled obstacle, summed over both (g2 − g1 for flat
    /// obstacles), that of the one with one obstacle, and 1 m without any ([`Scene::validate`]
    /// keeps it > 0). A profile that does not parse counts as flat: the scene is then invalid,
    /// and its validation says why.
    pub fn gap(&self) -> f64 {
        self.gap_from(self.nearest_heights())
    }

    /// [`Scene::gap`] from the profiles' heights nearest to the plate at rest,
    /// [`Scene::nearest_heights`], which a run computes once (only the levels are tunable).
    pub fn gap_from(&self, [lower, upper]: [f64; 2]) -> f64 {
        let room = [
            self.lower_obstacle().map(|g| -(g + lower)),
            self.upper_obstacle().map(|g| g + upper),
        ];
        match room {
            [Some(a), Some(b)] => a + b,
            [Some(a), None] | [None, Some(a)] => a,
            [None, None] => 1.0,
        }
    }

    /// Per side, the height of its profile nearest to the plate at rest anywhere on the plate
    /// ([`Profile::nearest`]): 0 for a flat obstacle, and for a profile that does not parse
    /// (the scene is then invalid, and its validation says why).
    pub fn nearest_heights(&self) -> [f64; 2] {
        ObstacleSide::BOTH.map(|side| {
            self.profile(side)
                .map_or(0.0, |p| p.nearest(side, self.size()).0)
        })
    }

    /// The first of the displacements `u` (m, absolute: base plus plate) at contact points whose
    /// obstacle heights are `heights` = [h₁, h₂] (relative to the levels; −∞ and +∞ where an
    /// obstacle is absent) that lies past an enabled obstacle by more than `tolerance` (m):
    /// u_i < g1 + h₁_i − tolerance or u_i > g2 + h₂_i + tolerance. The one test of "a point outside
    /// the obstacles" shared by the stepper, the simulation and the FMU; `tolerance` is theirs to
    /// choose, usually a fraction of [`Scene::gap`]. With flat obstacles (every height 0) the
    /// levels are g1 and g2 bit for bit.
    pub fn first_outside(
        &self,
        u: &[f64],
        [lower_heights, upper_heights]: [&[f64]; 2],
        tolerance: f64,
    ) -> Option<Outside> {
        let (lower, upper) = (self.lower_obstacle(), self.upper_obstacle());
        u.iter().enumerate().find_map(|(index, &value)| {
            let below = lower
                .map(|g| g + lower_heights[index])
                .filter(|&g| value < g - tolerance)
                .map(|level| (ObstacleSide::Lower, level));
            let above = upper
                .map(|g| g + upper_heights[index])
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

    /// [Lx, Ly] (m).
    pub fn size(&self) -> [f64; 2] {
        [self.plate.length, self.plate.width]
    }

    /// The clamped part of the edge, parsed from `plate.clamp`.
    pub fn clamp(&self) -> Result<Clamp, Error> {
        Clamp::parse(&self.plate.clamp, self.size())
    }

    /// The clamp on the scene's mesh ([`Clamp::on_mesh`]): an error when it is empty there.
    pub fn clamped_edges(&self) -> Result<ClampedEdges, Error> {
        self.clamp()?
            .on_mesh(self.size(), [self.mesh.nx, self.mesh.ny])
    }

    /// The profile of one obstacle, parsed from `obstacle.lower_profile` or
    /// `obstacle.upper_profile`.
    pub fn profile(&self, side: ObstacleSide) -> Result<Profile, Error> {
        let text = match side {
            ObstacleSide::Lower => &self.obstacle.lower_profile,
            ObstacleSide::Upper => &self.obstacle.upper_profile,
        };
        Profile::parse(text, side.profile_parameter(), self.size())
    }

    /// Whether both profiles are `flat`: the obstacles of the paper and of every scene before
    /// profiles existed.
    pub fn has_flat_obstacles(&self) -> bool {
        ObstacleSide::BOTH
            .into_iter()
            .all(|side| matches!(self.profile(side), Ok(Profile::Flat)))
    }

    /// The level of an enabled obstacle (`obstacle.lower` or `obstacle.upper`), `None` when it is
    /// disabled.
    pub fn level(&self, side: ObstacleSide) -> Option<f64> {
        match side {
            ObstacleSide::Lower => self.lower_obstacle(),
            ObstacleSide::Upper => self.upper_obstacle(),
        }
    }

    /// The probe points, in order.
    pub fn probes(&self) -> [Probe; PROBES] {
        [self.probe1, self.probe2, self.probe3, self.probe4]
    }

    /// The weight of the plate per unit area, ρe·g (Pa), which acts as the pressure −ρe·g
    /// (`load.gravity`, 0 by default).
    pub fn weight_pressure(&self) -> f64 {
        self.areal_mass() * self.load.gravity
    }

    /// The pressure that acts during the motion: `load.pressure` less the weight, p − ρe·g (Pa);
    /// `load.pressure` bit for bit without gravity.
    pub fn acting_pressure(&self) -> f64 {
        self.load.pressure - self.weight_pressure()
    }

    /// The pressure whose static equilibrium is the initial state: `initial.preload_pressure`
    /// less the weight, p₀ − ρe·g (Pa), so that with gravity the plate starts at rest in its sag.
    pub fn acting_preload_pressure(&self) -> f64 {
        self.initial.preload_pressure - self.weight_pressure()
    }

    /// The heights (relative to the levels) of each enabled obstacle nearest to the plate's rest
    /// position over the clamped part of the edge on the scene's mesh: the base must stay
    /// strictly between g1 + h₁ and g2 + h₂ there. `None` for an obstacle that is disabled or lies
    /// over no clamped point. For flat obstacles both are 0.
    pub fn clamp_heights(&self) -> Result<[Option<f64>; 2], Error> {
        let segments = self.clamped_edges()?.segments();
        let tolerance = 1e-9 * self.cell_size();
        let mut heights = [None, None];
        for (k, side) in ObstacleSide::BOTH.into_iter().enumerate() {
            if self.level(side).is_some() {
                heights[k] =
                    self.profile(side)?
                        .nearest_over(side, &segments, self.size(), tolerance);
            }
        }
        Ok(heights)
    }

    /// The shorter side of the mesh's cells, min(Lx/nx, Ly/ny) (m).
    pub fn cell_size(&self) -> f64 {
        (self.plate.length / self.mesh.nx as f64).min(self.plate.width / self.mesh.ny as f64)
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

    /// Checks every parameter against its own range in [`BOUNDS`] (in the table's order), then the
    /// limits that tie parameters together; the error names the parameter and the limit.
    pub fn validate(&self) -> Result<(), Error> {
        for bound in &BOUNDS {
            bound.check((bound.value)(self))?;
        }
        let shorter_side = self.plate.length.min(self.plate.width);
        if self.plate.thickness > shorter_side {
            return Err(Error::invalid(
                "plate.thickness",
                self.plate.thickness,
                &format!("must not exceed the shorter side {shorter_side} m (Kirchhoff–Love is a thin-plate model)"),
            ));
        }
        self.clamped_edges()?;
        self.validate_obstacles()?;
        let [lx, ly] = self.size();
        for (k, probe) in self.probes().iter().enumerate() {
            if !((0.0..=lx).contains(&probe.x) && (0.0..=ly).contains(&probe.y)) {
                return Err(Error::invalid(
                    &format!("probe{}.x, probe{}.y", k + 1, k + 1),
                    format!("({}, {})", probe.x, probe.y),
                    &format!("must lie on the plate [0, {lx}] × [0, {ly}] m"),
                ));
            }
        }
        let c = self.base.amplitude;
        let [lower, upper] = self.clamp_heights()?;
        let half_gap = [
            self.lower_obstacle().zip(lower).map(|(g, h)| -(g + h)),
            self.upper_obstacle().zip(upper).map(|(g, h)| g + h),
        ]
        .into_iter()
        .flatten()
        .fold(f64::INFINITY, f64::min);
        if c > 0.0 && c >= half_gap {
            return Err(Error::invalid(
                "base.amplitude",
                c,
                &format!(
                    "must be < {half_gap} m so that the base sine stays strictly inside the gap \
                     over the clamped edge"
                ),
            ));
        }
        self.damping.validate()?;
        if self.damping.is_modal() && self.solver.linear == LinearChoice::Sparse {
            return Err(Error::invalid(
                "damping.modal_ratio and solver.linear",
                format!("{} and sparse", self.damping.modal_ratio),
                "needs the modal backend (solver.linear = modal or auto): the sparse backend has \
                 no eigenbasis to damp mode by mode",
            ));
        }
        Ok(())
    }
}

impl Scene {
    /// Checks both profiles: each parses (on a disabled obstacle too: a bad value is refused
    /// wherever it is set), and each enabled obstacle lies strictly away from the plate at rest
    /// everywhere, g1 + h₁ < 0 < g2 + h₂ (the paper's g₁(x) ≤ −g < 0 < g ≤ g₂(x)): a plate that
    /// starts touching or crossing an obstacle is refused, naming where.
    fn validate_obstacles(&self) -> Result<(), Error> {
        for side in ObstacleSide::BOTH {
            let profile = self.profile(side)?;
            let Some(level) = self.level(side) else {
                continue;
            };
            let (h, place) = profile.nearest(side, self.size());
            let at = level + h;
            let (crosses, relation) = match side {
                ObstacleSide::Lower => (at >= 0.0, "below"),
                ObstacleSide::Upper => (at <= 0.0, "above"),
            };
            if crosses {
                return Err(Error::invalid(
                    &format!("{} and {}", side.parameter(), side.profile_parameter()),
                    format!("{level} and {h:+} m"),
                    &format!(
                        "puts the obstacle at {at} m {place}: it must lie strictly {relation} the \
                         plate at rest (u = 0) everywhere"
                    ),
                ));
            }
        }
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
            s.damping == Damping::default() && s.damping.coefficients().is_zero(),
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

    /// The Rayleigh pair of `damping.ratio`: ζ at both frequencies, by the formula of
    /// [`DampingCoefficients::ratio`]; between them less, outside more.
    #[test]
    fn the_ratio_pair_gives_the_ratio_at_both_frequencies() {
        let mut s = Scene::default();
        let err = s
            .clone()
            .set("damping.ratio", "0.01")
            .unwrap_err()
            .to_string();
        assert!(err.contains("damping.frequency_low"), "{err}");
        s.set_all(&[
            ("damping.ratio", "0.01"),
            ("damping.frequency_low", "53.83"),
            ("damping.frequency_high", "5000"),
        ])
        .unwrap();
        let c = s.damping.coefficients();
        let omega = |f: f64| 2.0 * std::f64::consts::PI * f;
        for f in [53.83, 5000.0] {
            assert!((c.ratio(omega(f)) - 0.01).abs() < 1e-15, "{f} Hz");
        }
        assert!(c.ratio(omega(500.0)) < 0.01 && c.ratio(omega(20.0)) > 0.01);
        assert!(c.ratio(omega(2e4)) > 0.01);
        // The pair ζ = 1 % at f₁ = ω₁/2π of the paper's mesh and 5 kHz: α = 6.692 1/s, β = 6.298e-7 s.
        assert!((c.alpha - 6.692).abs() < 5e-4 && (c.beta - 6.298e-7).abs() < 5e-11);
        assert_eq!(c.modal_ratio, 0.0);
    }

    /// Every inconsistent combination is an error naming the parameters at fault, never a clamp.
    #[test]
    fn damping_combinations_are_checked_by_name() {
        let pair = |ratio: &str, low: &str, high: &str| {
            let mut s = Scene::default();
            s.damping.ratio = ratio.parse().unwrap();
            s.damping.frequency_low = low.parse().unwrap();
            s.damping.frequency_high = high.parse().unwrap();
            s
        };
        for (scene, names) in [
            (pair("0.01", "0", "100"), vec!["damping.frequency_low"]),
            (pair("0.01", "100", "100"), vec!["damping.frequency_high"]),
            (pair("0.01", "200", "100"), vec!["damping.frequency_high"]),
            (pair("-0.01", "10", "100"), vec!["damping.ratio"]),
            (pair("0.01", "-10", "100"), vec!["damping.frequency_low"]),
            (pair("NaN", "10", "100"), vec!["damping.ratio"]),
            (
                Scene {
                    damping: Damping {
                        mass_proportional: 1.0,
                        ..pair("0.01", "10", "100").damping
                    },
                    ..Scene::default()
                },
                vec!["damping.ratio", "damping.mass_proportional"],
            ),
            (
                Scene {
                    damping: Damping {
                        stiffness_proportional: 1e-6,
                        ..pair("0.01", "10", "100").damping
                    },
                    ..Scene::default()
                },
                vec!["damping.ratio", "damping.stiffness_proportional"],
            ),
            (
                Scene {
                    damping: Damping {
                        modal_ratio: -1.0,
                        ..Damping::default()
                    },
                    ..Scene::default()
                },
                vec!["damping.modal_ratio"],
            ),
        ] {
            let err = scene.validate().unwrap_err().to_string();
            for name in names {
                assert!(err.contains(name), "{err} should name {name}");
            }
        }
        // Frequencies alone (ζ = 0) do nothing and are accepted, as are α and β with ζ = 0.
        pair("0", "200", "100").validate().unwrap();
        let mut s = Scene::default();
        s.damping.modal_ratio = 0.02;
        s.validate().unwrap();
        s.solver.linear = LinearChoice::Sparse;
        let err = s.validate().unwrap_err().to_string();
        assert!(
            err.contains("damping.modal_ratio") && err.contains("solver.linear"),
            "{err}"
        );
    }

    /// The smallest ratio above a frequency: ζ is convex in ω with its minimum at √(α/β).
    #[test]
    fn the_lightest_ratio_above_a_frequency() {
        let c = DampingCoefficients {
            alpha: 100.0,
            beta: 1e-6,
            modal_ratio: 0.0,
        };
        let turn = (c.alpha / c.beta).sqrt();
        assert_eq!(c.lightest_ratio_above(1.0), c.ratio(turn));
        assert_eq!(c.lightest_ratio_above(2.0 * turn), c.ratio(2.0 * turn));
        let mass_only = DampingCoefficients {
            alpha: 100.0,
            beta: 0.0,
            modal_ratio: 0.01,
        };
        assert_eq!(mass_only.lightest_ratio_above(1e4), 0.01);
    }

    #[test]
    fn the_gap_and_the_first_value_outside_follow_the_enabled_obstacles() {
        let mut s = Scene::default();
        (s.obstacle.lower, s.obstacle.upper) = (-0.01, 0.03);
        assert_eq!(s.gap(), 0.04);
        let u = [0.0, 0.031, -0.02];
        let zeros = [0.0; 3];
        let flat = [&zeros[..], &zeros[..]];
        let outside = s.first_outside(&u, flat, 1e-6).unwrap();
        assert_eq!(
            (
                outside.obstacle,
                outside.level,
                outside.index,
                outside.value
            ),
            (ObstacleSide::Upper, 0.03, 1, 0.031)
        );
        assert!(
            s.first_outside(&u, flat, 0.011).is_none(),
            "within the tolerance"
        );
        // Heights move each point's levels: 0.031 lies under an upper obstacle 0.002 higher there,
        // and a lower obstacle absent under the last point leaves it free.
        let upper = [0.0, 0.002, 0.0];
        let lower = [0.0, 0.0, f64::NEG_INFINITY];
        assert!(s.first_outside(&u, [&lower, &upper], 1e-6).is_none());
        s.obstacle.upper_enabled = false;
        assert_eq!(s.gap(), 0.01, "one obstacle: its distance from u = 0");
        let outside = s.first_outside(&u, flat, 1e-6).unwrap();
        assert_eq!((outside.obstacle, outside.index), (ObstacleSide::Lower, 2));
        s.obstacle.lower_enabled = false;
        assert_eq!(s.gap(), 1.0);
        assert!(s.first_outside(&u, flat, 0.0).is_none());
    }

    #[test]
    fn the_first_difference_names_the_parameter_and_both_values() {
        let s = Scene::default();
        assert_eq!(s.first_difference(&s), None);
        let mut other = s.clone();
        other.obstacle.lower_profile = "point(x=0.1, y=0.1)".to_string();
        other.stop_time = 2.0;
        assert_eq!(
            s.first_difference(&other),
            Some((
                "obstacle.lower_profile".to_string(),
                "\"flat\"".to_string(),
                "\"point(x=0.1, y=0.1)\"".to_string()
            ))
        );
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

    /// The obstacle levels keep their sign with the obstacle disabled too, as the model
    /// descriptions' `max` and `min` declare and the FMU checks each value set.
    #[test]
    fn a_disabled_obstacle_keeps_its_sign() {
        let mut s = Scene::default();
        s.obstacle.upper_enabled = false;
        s.obstacle.upper = -0.01;
        let err = s.validate().unwrap_err().to_string();
        assert!(err.contains("obstacle.upper = -0.01"), "{err}");
    }

    #[test]
    fn base_amplitude_must_stay_inside_the_gap() {
        let mut s = Scene::default();
        assert!(s.set("base.amplitude", "0.0099").is_ok());
        let err = s.set("base.amplitude", "0.01").unwrap_err();
        assert!(err.to_string().contains("base.amplitude"));
    }
}
