//! What a study runs: the scenes, damping models and meshes, and the list of runs the plan makes
//! of them (one entry per simulation, in the order they run).

use plate_impact::element::ElementKind;

/// Damping ratio of the first mode in the damped scenes and of every damping model.
pub const ZETA1: f64 = 0.01;

/// A forced scene of the study.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Forcing {
    pub label: &'static str,
    pub frequency: f64,
    pub amplitude: f64,
    /// Rayleigh α = 2ζ₁ω₁ (mass-proportional), the `-damped` scenes of the statistics study.
    pub damped: bool,
}

/// The damped scenes first: a study stopped early has the steady states that exist.
pub const FORCINGS: [Forcing; 4] = [
    Forcing {
        label: "forced-35hz-damped",
        frequency: 35.0,
        amplitude: 0.009,
        damped: true,
    },
    Forcing {
        label: "forced-60hz-damped",
        frequency: 60.0,
        amplitude: 0.002,
        damped: true,
    },
    Forcing {
        label: "forced-35hz",
        frequency: 35.0,
        amplitude: 0.009,
        damped: false,
    },
    Forcing {
        label: "forced-60hz",
        frequency: 60.0,
        amplitude: 0.002,
        damped: false,
    },
];

/// A damping model of the damping study: its label in `damping.csv` and the scene parameters
/// that set it, applied on the undamped forcings before the command line's.
#[derive(Clone, Debug, PartialEq)]
pub struct DampingModel {
    pub label: &'static str,
    pub settings: Vec<(&'static str, String)>,
    /// The grid runs the Δt ≥ this (s) only (with the mesh's own bound).
    dt_min: f64,
    /// The same on the study's costliest mesh, Argyris 14 × 10 (s).
    dt_min_costliest: f64,
}

impl DampingModel {
    /// The smallest Δt (s) the grid runs the model at on `mesh`, with the mesh's own bound.
    fn dt_min(&self, mesh: &MeshPlan) -> f64 {
        let own = if mesh.mesh == Mesh::new(ElementKind::Argyris, 14, 10) {
            self.dt_min_costliest
        } else {
            self.dt_min
        };
        own.max(mesh.dt_min)
    }

    /// The model's settings as `name=value` arguments.
    pub fn arguments(&self) -> Vec<String> {
        self.settings
            .iter()
            .map(|(k, v)| format!("{k}={v}"))
            .collect()
    }
}

/// The damping models of the damping study, ω₁ (rad/s) of the paper's Argyris 10 × 7 mesh and
/// f₁ = ω₁/2π; all but `beta-half` give ζ = 1 % on the first mode:
/// - `none`: the paper's undamped plate;
/// - `alpha`: mass-proportional α = 2ζω₁ (ζ_k = α/2ω_k, vanishing on the high modes);
/// - `beta`: stiffness-proportional β = 2ζ/ω₁ (ζ_k = βω_k/2, growing with the mode);
/// - `beta-half`: the same at ζ₁ = 0.5 %, for the threshold of the start-up warning only;
/// - `rayleigh-1k`, `-5k`, `-20k`: the Rayleigh pair with ζ = 1 % at f₁ and at 1, 5, 20 kHz
///   (`damping.ratio`, `damping.frequency_low`, `damping.frequency_high`);
/// - `modal`: ζ_m = 1 % on every mode (`damping.modal_ratio`).
///
/// In the grid each model runs every mesh down to Δt = 1e-6 s. `beta` and `rayleigh-5k`, the
/// models whose contact loss the study follows, run the coarse meshes further (to 1e-7 s). The
/// models that leave the high modes lightly damped at 1e-6 s (ζ_hf < 0.1: `none`, `alpha`,
/// `modal`, `rayleigh-20k`) stop at 1e-5 s on the costliest mesh, Argyris 14 × 10: refining
/// only brings in more of those modes, and the run would cost a fifth of the study.
pub fn damping_models(omega1: f64) -> Vec<DampingModel> {
    let f1 = omega1 / (2.0 * std::f64::consts::PI);
    let model =
        |label, setting: Option<(&'static str, String)>, dt_min, dt_min_costliest| DampingModel {
            label,
            settings: setting.into_iter().collect(),
            dt_min,
            dt_min_costliest,
        };
    let pair = |label, high: f64, dt_min, dt_min_costliest| DampingModel {
        label,
        settings: vec![
            ("damping.ratio", ZETA1.to_string()),
            ("damping.frequency_low", format!("{f1:.6}")),
            ("damping.frequency_high", high.to_string()),
        ],
        dt_min,
        dt_min_costliest,
    };
    let beta = |zeta: f64| {
        let value = format!("{:.6e}", 2.0 * zeta / omega1);
        Some(("damping.stiffness_proportional", value))
    };
    let alpha = format!("{:.6}", 2.0 * ZETA1 * omega1);
    vec![
        model("none", None, 1e-6, 1e-5),
        model(
            "alpha",
            Some(("damping.mass_proportional", alpha)),
            1e-6,
            1e-5,
        ),
        model("beta", beta(ZETA1), 0.0, 1e-6),
        pair("rayleigh-1k", 1e3, 1e-6, 1e-6),
        pair("rayleigh-5k", 5e3, 0.0, 1e-6),
        pair("rayleigh-20k", 2e4, 1e-6, 1e-5),
        model(
            "modal",
            Some(("damping.modal_ratio", ZETA1.to_string())),
            1e-6,
            1e-5,
        ),
        model("beta-half", beta(ZETA1 / 2.0), f64::INFINITY, f64::INFINITY),
    ]
}

/// A mesh: element and cells.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mesh {
    pub element: ElementKind,
    pub nx: usize,
    pub ny: usize,
}

impl Mesh {
    pub const fn new(element: ElementKind, nx: usize, ny: usize) -> Mesh {
        Mesh { element, nx, ny }
    }
}

/// A mesh of a grid and the smallest Δt it runs.
#[derive(Clone, Copy, Debug)]
pub struct MeshPlan {
    pub mesh: Mesh,
    pub dt_min: f64,
}

/// The scene of a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SceneKind {
    /// The plate released from its preload onto the lower obstacle, R replicas.
    Energy,
    Forced(Forcing),
}

impl SceneKind {
    pub fn label(&self) -> &'static str {
        match self {
            SceneKind::Energy => "energy",
            SceneKind::Forced(f) => f.label,
        }
    }
}

/// Why a run is in the plan, written to the CSV's `part` column.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Part {
    /// Every (scene, model, mesh) down the Δt ladder.
    Grid,
    /// The contact loss followed to smaller Δt than the grid's.
    ContactLoss,
    /// Meshes finer than the reference's, checking it.
    FinerReference,
    /// The Δt series behind the threshold of the start-up warning (`src/advice.rs`).
    Threshold,
    /// The runs that close the rule of evidence's ladders (docs/studies.md, "One rule of
    /// evidence") where the other parts leave one open.
    Evidence,
}

impl Part {
    pub const ALL: [Part; 5] = [
        Part::Grid,
        Part::ContactLoss,
        Part::FinerReference,
        Part::Threshold,
        Part::Evidence,
    ];

    pub fn label(self) -> &'static str {
        match self {
            Part::Grid => "grid",
            Part::ContactLoss => "contact-loss",
            Part::FinerReference => "finer-reference",
            Part::Threshold => "threshold",
            Part::Evidence => "evidence",
        }
    }
}

/// One simulation of a plan.
#[derive(Clone, Debug, PartialEq)]
pub struct Run {
    pub scene: SceneKind,
    /// Index into [`Plan::dampings`]; none: the scene's own damping.
    pub damping: Option<usize>,
    pub mesh: Mesh,
    pub dt: f64,
    /// Windows K of a forced run.
    pub windows: usize,
    /// Scene parameters of this run beyond the model's (`name=value`), e.g. the backend.
    pub settings: Vec<String>,
    pub part: Part,
}

impl Run {
    /// Whether `other` is the same simulation (whatever part asked for it).
    fn same_as(&self, other: &Run) -> bool {
        Run {
            part: other.part,
            ..self.clone()
        } == *other
    }
}

/// What a study runs.
pub struct Plan {
    /// `full`, `reduced`, `quick`, `damping` or `damping-quick`, recorded in the meta file.
    pub name: &'static str,
    /// The damping models of the damping study; empty: each forcing's own damping.
    pub dampings: Vec<DampingModel>,
    pub runs: Vec<Run>,
    /// Time before the first window (s).
    pub transient: f64,
    /// Target length of a window (s): it holds round(f·this) whole periods.
    pub window_target: f64,
    /// Replicas R of an `energy` run (and of each replica check).
    pub replicas: usize,
    /// Forced settings also run as R perturbed replicas: (forcing, mesh, Δt).
    pub replica_check: Vec<(Forcing, Mesh, f64)>,
}

impl Plan {
    /// Adds `run` unless the plan already has the same simulation.
    fn push(&mut self, run: Run) {
        if !self.runs.iter().any(|r| r.same_as(&run)) {
            self.runs.push(run);
        }
    }

    /// Every mesh the runs use, in order of first use.
    pub fn meshes(&self) -> Vec<Mesh> {
        let mut meshes: Vec<Mesh> = Vec::new();
        for r in &self.runs {
            if !meshes.contains(&r.mesh) {
                meshes.push(r.mesh);
            }
        }
        meshes
    }

    /// The damping model of `run`, if any.
    pub fn damping_of(&self, run: &Run) -> Option<&DampingModel> {
        run.damping.map(|d| &self.dampings[d])
    }
}

/// The Δt levels of the statistics study ≥ `smallest` (s), decreasing.
fn ladder(smallest: f64) -> Vec<f64> {
    [
        1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2e-5, 1e-5, 5e-6, 2e-6, 1e-6, 5e-7, 2e-7, 1e-7,
    ]
    .into_iter()
    .filter(|&dt| dt >= smallest * (1.0 - 1e-9))
    .collect()
}

/// The grid of a plan: scenes × damping models × meshes × the Δt of `ladder` each mesh (and
/// model) runs.
pub struct Grid {
    pub scenes: Vec<SceneKind>,
    pub meshes: Vec<MeshPlan>,
    pub ladder: Vec<f64>,
    pub windows: usize,
    /// `--dt` given: every model runs every Δt of the ladder its mesh allows.
    pub ladder_given: bool,
}

impl Grid {
    /// The runs of the grid with the damping models `dampings` (each scene's own damping when
    /// empty), in the order scene, model, mesh, Δt.
    fn runs(&self, dampings: &[DampingModel]) -> Vec<Run> {
        let models: Vec<Option<usize>> = if dampings.is_empty() {
            vec![None]
        } else {
            (0..dampings.len()).map(Some).collect()
        };
        let mut runs = Vec::new();
        for &scene in &self.scenes {
            // The energy scene has no damping model.
            let models = if scene == SceneKind::Energy {
                &[None][..]
            } else {
                &models[..]
            };
            for &model in models {
                for m in &self.meshes {
                    let lowest = match (model, self.ladder_given) {
                        (Some(d), false) => dampings[d].dt_min(m),
                        _ => m.dt_min,
                    } * (1.0 - 1e-9);
                    for &dt in self.ladder.iter().filter(|&&dt| dt >= lowest) {
                        runs.push(Run {
                            scene,
                            damping: model,
                            mesh: m.mesh,
                            dt,
                            windows: self.windows,
                            settings: Vec::new(),
                            part: Part::Grid,
                        });
                    }
                }
            }
        }
        runs
    }
}

/// The statistics study's grid, full or with `reduced` the same but the paper's meshes stopped
/// earlier: Argyris 10 × 7 at 2e-7 s (ω_max·Δt = 1.5) instead of 1e-7 s and FVS 14 × 10 at
/// 1e-6 s (2.4) instead of 5e-7 s, which saves about 40 % of the cost. Each mesh runs down to
/// ω_max·Δt ≤ 1 (two levels below where that is cheap), except FVS 14 × 10, stopped at 5e-7 s
/// (ω_max·Δt = 1.2) to bound the study's time.
pub fn statistics_grid(reduced: bool) -> Grid {
    use ElementKind::{Argyris, Fvs};
    let (argyris_10x7, fvs_14x10) = if reduced { (2e-7, 1e-6) } else { (1e-7, 5e-7) };
    let mesh = |element, nx, ny, dt_min| MeshPlan {
        mesh: Mesh::new(element, nx, ny),
        dt_min,
    };
    let mut scenes = vec![SceneKind::Energy];
    scenes.extend(FORCINGS.map(SceneKind::Forced));
    Grid {
        scenes,
        meshes: vec![
            mesh(Argyris, 2, 1, 1e-6),
            mesh(Argyris, 4, 2, 5e-7),
            mesh(Argyris, 6, 4, 2e-7),
            mesh(Argyris, 10, 7, argyris_10x7),
            mesh(Fvs, 4, 3, 1e-6),
            mesh(Fvs, 7, 5, 5e-7),
            mesh(Fvs, 14, 10, fvs_14x10),
        ],
        ladder: ladder(1e-7),
        windows: 8,
        ladder_given: false,
    }
}

/// The quick statistics grid: the damped 35 Hz scene and `energy` on two coarse meshes.
pub fn quick_grid() -> Grid {
    use ElementKind::{Argyris, Fvs};
    Grid {
        scenes: vec![SceneKind::Energy, SceneKind::Forced(FORCINGS[0])],
        meshes: vec![
            MeshPlan {
                mesh: Mesh::new(Argyris, 2, 1),
                dt_min: 1e-6,
            },
            MeshPlan {
                mesh: Mesh::new(Fvs, 4, 3),
                dt_min: 2e-6,
            },
        ],
        ladder: vec![1e-4, 1e-5, 2e-6, 1e-6],
        windows: 8,
        ladder_given: false,
    }
}

/// The statistics study (full, reduced or quick) over `grid`.
pub fn statistics_plan(name: &'static str, grid: &Grid, quick: bool) -> Plan {
    use ElementKind::{Argyris, Fvs};
    let replica_check = if quick {
        vec![(FORCINGS[0], Mesh::new(Argyris, 2, 1), 1e-5)]
    } else {
        // The paper's mesh at its Δt, a coarse mesh resolved (ω_max·Δt = 0.82), FVS between.
        let settings = [
            (Mesh::new(Argyris, 10, 7), 1e-4),
            (Mesh::new(Argyris, 4, 2), 1e-6),
            (Mesh::new(Fvs, 7, 5), 1e-5),
        ];
        grid.scenes
            .iter()
            .filter_map(|s| match s {
                SceneKind::Forced(f) => Some(*f),
                SceneKind::Energy => None,
            })
            .flat_map(|f| settings.iter().map(move |&(m, dt)| (f, m, dt)))
            .collect()
    };
    Plan {
        name,
        dampings: Vec::new(),
        runs: grid.runs(&[]),
        transient: 1.0,
        window_target: 0.375,
        replicas: if quick { 3 } else { 6 },
        replica_check,
    }
}

/// The damping study's grid: the undamped forcings, Argyris 2 × 1 … 14 × 10 and FVS 7 × 5,
/// 14 × 10 at Δt = 1e-4, 1e-5, 1e-6 s, the two coarsest Argyris meshes down to 1e-7 s
/// (ω_max·Δt = 0.02 and 0.07) for the models that go there.
pub fn damping_grid() -> Grid {
    use ElementKind::{Argyris, Fvs};
    let mesh = |element, nx, ny, dt_min| MeshPlan {
        mesh: Mesh::new(element, nx, ny),
        dt_min,
    };
    Grid {
        scenes: vec![
            SceneKind::Forced(FORCINGS[2]),
            SceneKind::Forced(FORCINGS[3]),
        ],
        meshes: vec![
            mesh(Argyris, 2, 1, 1e-7),
            mesh(Argyris, 4, 2, 1e-7),
            mesh(Argyris, 6, 4, 1e-6),
            mesh(Argyris, 10, 7, 1e-6),
            mesh(Argyris, 14, 10, 1e-6),
            mesh(Fvs, 7, 5, 1e-6),
            mesh(Fvs, 14, 10, 1e-6),
        ],
        ladder: vec![1e-4, 1e-5, 1e-6, 1e-7],
        windows: 8,
        ladder_given: false,
    }
}

/// The damping study: the grid (every model but `beta-half`), then the runs of `parts` beyond
/// it, each run once (a run another part already has is not repeated):
/// - contact loss: `beta` and `rayleigh-5k` below the grid's smallest Δt on the fine meshes, on
///   both forcings (`beta` at 1e-7 s on FVS 7 × 5 and 14 × 10, and with 2 windows, its response
///   being periodic, on Argyris 6 × 4 and 10 × 7 and at 5e-8 s on FVS 14 × 10; `rayleigh-5k` on
///   FVS 14 × 10 at 5e-7 s and with 2 windows at 1e-7 s, and on Argyris 14 × 10 at 5e-7 s at
///   35 Hz);
/// - finer reference: `beta` at Δt = 1e-6 s on Argyris 20 × 14 (2 675 free dofs, the modal
///   backend named: `auto` would pick the sparse one, 100× slower per step) and FVS 20 × 14 and
///   28 × 20, both forcings: whether the reference, Argyris 14 × 10, has converged in the mesh;
/// - threshold: the 35 Hz forcing on Argyris 10 × 7 with `beta` from Δt = 1e-3 to 1e-6 s,
///   `beta-half` from 2e-4 to 1e-6 s, `rayleigh-5k` from 1e-4 to 2e-7 s and `modal` from 1e-4
///   to 1e-6 s: ζ_hf on both sides of the threshold of `src/advice.rs`;
/// - evidence: `beta` at 35 Hz on Argyris 14 × 10 at 1e-7 s and on Argyris 20 × 14 (modal, as
///   above) at 1e-5 and 1e-7 s, which give the finer meshes' settings a Δt ladder (1e-5, 1e-6,
///   1e-7 s) beside their mesh ladders: the grid's ladders there start at 1e-4 s, whose 35 Hz base
///   force is 5 to 9 % off.
pub fn damping_plan(grid: &Grid, dampings: Vec<DampingModel>, parts: &[Part]) -> Plan {
    let in_grid: Vec<DampingModel> = dampings
        .iter()
        .filter(|d| d.label != "beta-half")
        .cloned()
        .collect();
    let mut plan = Plan {
        name: "damping",
        dampings,
        runs: Vec::new(),
        transient: 1.0,
        window_target: 0.375,
        replicas: 0,
        replica_check: Vec::new(),
    };
    let index = |label: &str| plan.dampings.iter().position(|d| d.label == label);
    let grid_runs: Vec<Run> = grid
        .runs(&in_grid)
        .into_iter()
        .map(|r| Run {
            damping: r.damping.and_then(|d| index(in_grid[d].label)),
            ..r
        })
        .collect();
    let extra: Vec<Run> = parts
        .iter()
        .flat_map(|&part| extra_runs(part, &|label| index(label)))
        .collect();
    if parts.contains(&Part::Grid) {
        for r in grid_runs {
            plan.push(r);
        }
    }
    for r in extra {
        plan.push(r);
    }
    plan
}

/// The runs of a part of the damping study beyond its grid (see [`damping_plan`]); `model` gives
/// a damping label's index, `None` for a model the plan leaves out (its runs are dropped).
fn extra_runs(part: Part, model: &dyn Fn(&str) -> Option<usize>) -> Vec<Run> {
    use ElementKind::{Argyris, Fvs};
    let [_, _, f35, f60] = FORCINGS.map(SceneKind::Forced);
    let run = |scene, label: &str, mesh: (ElementKind, usize, usize), dt, windows| {
        model(label).map(|d| Run {
            scene,
            damping: Some(d),
            mesh: Mesh::new(mesh.0, mesh.1, mesh.2),
            dt,
            windows,
            settings: Vec::new(),
            part,
        })
    };
    let mut runs = Vec::new();
    match part {
        Part::Grid => {}
        Part::ContactLoss => {
            for scene in [f35, f60] {
                runs.extend([
                    run(scene, "beta", (Fvs, 7, 5), 1e-7, 8),
                    run(scene, "beta", (Fvs, 14, 10), 1e-7, 8),
                    run(scene, "beta", (Argyris, 6, 4), 1e-7, 2),
                    run(scene, "beta", (Argyris, 10, 7), 1e-7, 2),
                    run(scene, "beta", (Fvs, 14, 10), 5e-8, 2),
                    run(scene, "rayleigh-5k", (Fvs, 14, 10), 5e-7, 8),
                    run(scene, "rayleigh-5k", (Fvs, 14, 10), 1e-7, 2),
                ]);
            }
            runs.push(run(f35, "rayleigh-5k", (Argyris, 14, 10), 5e-7, 8));
        }
        Part::FinerReference => {
            for scene in [f35, f60] {
                let modal = run(scene, "beta", (Argyris, 20, 14), 1e-6, 8).map(|r| Run {
                    settings: vec!["solver.linear=modal".to_string()],
                    ..r
                });
                runs.extend([
                    modal,
                    run(scene, "beta", (Fvs, 20, 14), 1e-6, 8),
                    run(scene, "beta", (Fvs, 28, 20), 1e-6, 8),
                ]);
            }
        }
        Part::Evidence => {
            let modal = |dt| {
                run(f35, "beta", (Argyris, 20, 14), dt, 8).map(|r| Run {
                    settings: vec!["solver.linear=modal".to_string()],
                    ..r
                })
            };
            runs.extend([
                run(f35, "beta", (Argyris, 14, 10), 1e-7, 8),
                modal(1e-5),
                modal(1e-7),
            ]);
        }
        Part::Threshold => {
            let series: [(&str, &[f64]); 4] = [
                ("beta", &[1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 1e-5, 1e-6]),
                ("beta-half", &[2e-4, 1e-4, 5e-5, 2e-5, 1e-6]),
                ("rayleigh-5k", &[1e-4, 1e-5, 1e-6, 5e-7, 2e-7]),
                ("modal", &[1e-4, 1e-5, 1e-6]),
            ];
            for (label, steps) in series {
                for &dt in steps {
                    runs.push(run(f35, label, (Argyris, 10, 7), dt, 8));
                }
            }
        }
    }
    runs.into_iter().flatten().collect()
}

/// A mesh of `--mesh argyris:10x7`.
pub fn parse_mesh(item: &str) -> Result<Mesh, String> {
    let (element, nx, ny) = plate_impact_studies::element::parse_mesh_cells(item)?;
    Ok(Mesh::new(element, nx, ny))
}

/// One line per run of `plan` (`--plan`: what a study would run, without running it).
pub fn print_plan(plan: &Plan) {
    for (k, r) in plan.runs.iter().enumerate() {
        let model = plan.damping_of(r).map_or("", |d| d.label);
        println!(
            "{:>3} {:<15} {:<19} {model:<12} {:<7} {:>2}x{:<2} dt={:<6e} windows={} {}",
            k + 1,
            r.part.label(),
            r.scene.label(),
            plate_impact_studies::element::element_name(r.mesh.element),
            r.mesh.nx,
            r.mesh.ny,
            r.dt,
            r.windows,
            r.settings.join(" ")
        );
    }
}
