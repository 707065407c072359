//! Statistics study: error against run time for the numbers users read from impact runs (time
//! averages and counts of a forced steady state, and the landmarks of a released plate), for both
//! elements, several meshes each, and Δt from the paper's 1e-3 s down to ω_max·Δt ≤ 1, where ω_max
//! is the highest natural angular frequency of the mesh (the library's, `src/modes.rs`).
//!
//! `cargo run --release --example statistics [-- --quick | --reduced] [--out DIR]`
//!
//! `--study damping` runs the damping study instead ([`damping_plan`]): the undamped forcings
//! with each damping model of [`damping_models`] (`--damping LABEL,LABEL` keeps those), written to
//! `damping.csv` (the columns of `statistics.csv` plus `damping` after `scene`),
//! `damping_meshes.csv` and `damping_meta.csv`, then `plateimpact_tools.studies.damping_plots` writes the plots
//! and the generated part of `docs/accuracy/damping.md`. The other options below apply alike;
//! with `--quick`, every model on Argyris 2 × 1 at Δt = 1e-4 and 1e-5 s on `forced-35hz` (about
//! 2 s), in a temporary directory, checks the pipeline.
//!
//! A part of the study, to share it between processes (`--out` to separate directories; the
//! CSVs are then concatenated and `python -m plateimpact_tools.studies.statistics_plots DIR` run on the result): `--forcings
//! damped` or `undamped` keeps those forced scenes only (or `--forcings LABEL,LABEL` the named
//! ones, e.g. `forced-35hz`), `--skip energy,forced,replicas` leaves out the `energy` scene, the
//! forced runs or the replica check, `--mesh argyris:10x7[,fvs:14x10]` runs those meshes only and
//! `--dt 1e-4,1e-5` those time steps only (every mesh runs every one of them, whatever the
//! damping model's smallest Δt), `--windows K` K ≥ 2
//! windows instead of the plan's (a cheaper run of a periodic steady state). Trailing
//! `name=value` arguments set scene parameters (the FMU variable names, [`Scene::set`]) of every
//! run, after the study's own settings: `damping.stiffness_proportional=5.913e-5` or
//! `damping.ratio=0.01 damping.frequency_low=53.8 damping.frequency_high=5000` with `--forcings
//! undamped` (the `-damped` forcings add their α first, which the Rayleigh pair refuses); they are
//! recorded in `statistics_meta.csv`. A partial study writes its CSVs but neither plots nor checks.
//!
//! Scenes. `forced-35hz` (base sine of 9 mm at 35 Hz, obstacles at ±10 mm) and `forced-60hz` (2 mm at
//! 60 Hz, inside the band 39–74 Hz where the frequency sweep of docs/sweep/ impacts), each undamped
//! (the paper's plate) and `-damped`: Rayleigh α = 2ζ₁ω₁, ζ₁ = 1 %, β = 0, with ω₁ of the paper's
//! 10 × 7 Argyris mesh for every run (one physical plate; every mesh's ω₁ is within 0.5 % of it).
//! They run 1 s of transient, then K = 8 windows of whole forcing periods (about 0.375 s each).
//! `energy` (the plate released from its preload onto the lower obstacle, fixed base) runs 0.3 s.
//!
//! Per forced run, over the windows: RMS and peak of the free corner u(Lx, 0) (absolute, the
//! obstacles bound it), impacts per forcing period (`StepReport::impact`: the contact set went
//! from empty to non-empty), the energy removed at the obstacles per period (Σ
//! `EnergyFlows::contact_loss`), the mean of `energy.total` and of |`base.force`|
//! (`StepReport::base_force`) and the RMS of `base.force`, √(Σ F_n²/N) over the window's N steps
//! (what loads the supporting structure). Reports and flows are read at every step; the corner and the
//! energy, which cost an output evaluation, every step up to Δt = 1e-5 s and every 1e-5 s below
//! (at least 2.9·10⁵ samples a run, so the sampling adds nothing measurable to the spread).
//! Per `energy` run: the time of the first impact, the energy at 0.1 s and 0.3 s and the impacts
//! up to 0.3 s.
//!
//! Spread: the standard deviation of what one run would report, had its chaotic response taken
//! another course. Forced runs: the standard deviation of the K window values divided by √K (the
//! standard error of the mean over the whole window, if the windows are independent; for the peak,
//! a maximum, the standard deviation of the window peaks). `energy`, a transient with no windows:
//! the standard deviation over R runs whose preload is perturbed by k·1e-9 relative (k = 0 … R−1);
//! the value is the unperturbed run's; the first impact, read on the step grid, also carries the
//! step's Δt/√12. A check compares the window estimate with R perturbed
//! forced runs on a few settings (`replica_check.csv`). Wall time: `Stepper::new` (assembly,
//! eigenbasis, initial state) and the step loop, one run, measured with `Instant`; the runs go one
//! after the other in this process.
//!
//! Output (default `docs/accuracy`, with `--quick` a temporary directory): `statistics.csv` (one
//! row per run and quantity: quantity, scene, element, nx, ny, dt, omega_max_dt, value, spread,
//! wall_s), `meshes.csv` (ω₁ and ω_max per mesh), `replica_check.csv`, `statistics_meta.csv`;
//! then `plateimpact_tools.studies.statistics_plots` writes the work-precision plots and `statistics.md`.
//! `--quick` runs a small subset (about 10 s) in a temporary directory and exits nonzero unless
//! the pipeline completes and, on the damped 35 Hz scene on the Argyris 2 × 1 mesh, the statistics
//! have converged once ω_max·Δt < 1 and the mean |base force| has not at the paper's Δt (see
//! [`quick_check`]).

#[path = "../common/mod.rs"]
mod common;

use common::{element_name, exit_code, positive_integer, StudyDir};
use plate_impact::element::ElementKind;
use plate_impact::scene::Scene;
use plate_impact::scheme::Stepper;
use plate_impact::system::PlateSystem;
use std::fmt::Write as _;
use std::process::ExitCode;
use std::time::Instant;

/// Outputs (corner, energy) are sampled at this interval, or every step when Δt is larger (s).
const SAMPLE_INTERVAL: f64 = 1e-5;

/// Damping ratio of the first mode in the damped scenes.
const ZETA1: f64 = 0.01;

/// Relative perturbation step of the preload between replicas of the `energy` scene.
const ENERGY_PERTURBATION: f64 = 1e-9;

/// Preload pressure step between replicas of a forced scene (Pa): 1e-4 Pa deflects the plate by
/// about 1e-11 m, as 1e-9 of the `energy` scene's preload does.
const FORCED_PERTURBATION_PA: f64 = 1e-4;

/// Times at which the `energy` scene's energy is read (s); the last is its horizon.
const ENERGY_TIMES: [f64; 2] = [0.1, 0.3];

/// A forced scene of the study.
#[derive(Clone, Copy, Debug)]
struct Forcing {
    label: &'static str,
    frequency: f64,
    amplitude: f64,
    damped: bool,
}

/// The damped scenes first: a study stopped early has the steady states that exist.
const FORCINGS: [Forcing; 4] = [
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

/// A damping model of the damping study (`--study damping`): its label in `damping.csv` and the
/// scene parameters that set it, applied on the undamped forcings before the command line's.
#[derive(Clone, Debug)]
struct DampingModel {
    label: &'static str,
    settings: Vec<(&'static str, String)>,
    /// The model runs the Δt ≥ this (s) only (with the mesh's own bound).
    dt_min: f64,
    /// The same on the study's costliest mesh, Argyris 14 × 10 (s).
    dt_min_costliest: f64,
}

impl DampingModel {
    /// The smallest Δt (s) the model runs on `mesh`, with the mesh's own bound.
    fn dt_min(&self, mesh: &MeshPlan) -> f64 {
        let own = if mesh.element == ElementKind::Argyris && mesh.mesh == (14, 10) {
            self.dt_min_costliest
        } else {
            self.dt_min
        };
        own.max(mesh.dt_min)
    }
}

/// The damping models of the damping study, all ζ = 1 % on the first mode of the paper's plate,
/// ω₁ (rad/s) of the Argyris 10 × 7 mesh, f₁ = ω₁/2π:
/// - `none`: the paper's undamped plate;
/// - `alpha`: mass-proportional α = 2ζω₁ (ζ_k = α/2ω_k, vanishing on the high modes);
/// - `beta`: stiffness-proportional β = 2ζ/ω₁ (ζ_k = βω_k/2, growing with the mode);
/// - `rayleigh-1k`, `-5k`, `-20k`: the Rayleigh pair with ζ = 1 % at f₁ and at 1, 5, 20 kHz
///   (`damping.ratio`, `damping.frequency_low`, `damping.frequency_high`);
/// - `modal`: ζ_m = 1 % on every mode (`damping.modal_ratio`).
///
/// Each model runs every mesh down to Δt = 1e-6 s. `beta` and `rayleigh-5k`, the models whose
/// contact loss the study follows, run the coarse meshes further (to the plan's 1e-7 s). The
/// models that leave the high modes lightly damped at 1e-6 s (ζ_hf < 0.1: `none`, `alpha`,
/// `modal`, `rayleigh-20k`) stop at 1e-5 s on the costliest mesh, Argyris 14 × 10: refining
/// only brings in more of those modes, and the run would cost a fifth of the study.
fn damping_models(omega1: f64) -> Vec<DampingModel> {
    let f1 = omega1 / (2.0 * std::f64::consts::PI);
    let model =
        |label, settings: Vec<(&'static str, String)>, dt_min, dt_min_costliest| DampingModel {
            label,
            settings,
            dt_min,
            dt_min_costliest,
        };
    let pair = |label, high: f64, dt_min, dt_min_costliest| {
        model(
            label,
            vec![
                ("damping.ratio", ZETA1.to_string()),
                ("damping.frequency_low", format!("{f1:.6}")),
                ("damping.frequency_high", high.to_string()),
            ],
            dt_min,
            dt_min_costliest,
        )
    };
    vec![
        model("none", vec![], 1e-6, 1e-5),
        model(
            "alpha",
            vec![(
                "damping.mass_proportional",
                format!("{:.6}", 2.0 * ZETA1 * omega1),
            )],
            1e-6,
            1e-5,
        ),
        model(
            "beta",
            vec![(
                "damping.stiffness_proportional",
                format!("{:.6e}", 2.0 * ZETA1 / omega1),
            )],
            0.0,
            1e-6,
        ),
        pair("rayleigh-1k", 1e3, 1e-6, 1e-6),
        pair("rayleigh-5k", 5e3, 0.0, 1e-6),
        pair("rayleigh-20k", 2e4, 1e-6, 1e-5),
        model(
            "modal",
            vec![("damping.modal_ratio", ZETA1.to_string())],
            1e-6,
            1e-5,
        ),
    ]
}

/// A mesh of the study and the smallest Δt it runs.
#[derive(Clone, Copy, Debug)]
struct MeshPlan {
    element: ElementKind,
    mesh: (usize, usize),
    dt_min: f64,
}

/// What the study runs.
struct Plan {
    /// `full`, `reduced`, `quick` or `damping`, recorded in `statistics_meta.csv`.
    name: &'static str,
    /// The damping models each forcing runs with (`--study damping`); none: the forcing's own.
    dampings: Vec<DampingModel>,
    forcings: Vec<Forcing>,
    meshes: Vec<MeshPlan>,
    /// Δt levels, decreasing; a mesh runs those ≥ its `dt_min`.
    ladder: Vec<f64>,
    /// Time before the first window (s).
    transient: f64,
    /// Number of windows K.
    windows: usize,
    /// Target length of a window (s): it holds round(f·this) whole periods.
    window_target: f64,
    /// Replicas R of the `energy` scene (and of each replica check).
    replicas: usize,
    /// Settings also run as R perturbed replicas, for every forcing: (element, mesh, Δt).
    replica_check: Vec<(ElementKind, (usize, usize), f64)>,
}

fn ladder(smallest: f64) -> Vec<f64> {
    [
        1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2e-5, 1e-5, 5e-6, 2e-6, 1e-6, 5e-7, 2e-7, 1e-7,
    ]
    .into_iter()
    .filter(|&dt| dt >= smallest * (1.0 - 1e-9))
    .collect()
}

/// The full study, or with `reduced` the same but the paper's meshes
/// stopped earlier: Argyris 10 × 7 at 2e-7 s (ω_max·Δt = 1.5) instead of 1e-7 s and FVS 14 × 10 at
/// 1e-6 s (2.4) instead of 5e-7 s, which saves about 40 % of the cost.
fn full_plan(reduced: bool) -> Plan {
    use ElementKind::{Argyris, Fvs};
    let mesh = |element, mesh, dt_min| MeshPlan {
        element,
        mesh,
        dt_min,
    };
    let (argyris_10x7, fvs_14x10) = if reduced { (2e-7, 1e-6) } else { (1e-7, 5e-7) };
    Plan {
        name: if reduced { "reduced" } else { "full" },
        dampings: Vec::new(),
        forcings: FORCINGS.to_vec(),
        // Each mesh down to ω_max·Δt ≤ 1 (two levels below where that is cheap), except FVS 14 × 10,
        // stopped at 5e-7 s (ω_max·Δt = 1.2) to bound the study's time.
        meshes: vec![
            mesh(Argyris, (2, 1), 1e-6),
            mesh(Argyris, (4, 2), 5e-7),
            mesh(Argyris, (6, 4), 2e-7),
            mesh(Argyris, (10, 7), argyris_10x7),
            mesh(Fvs, (4, 3), 1e-6),
            mesh(Fvs, (7, 5), 5e-7),
            mesh(Fvs, (14, 10), fvs_14x10),
        ],
        ladder: ladder(1e-7),
        transient: 1.0,
        windows: 8,
        window_target: 0.375,
        replicas: 6,
        // The paper's mesh at its Δt, a coarse mesh resolved (ω_max·Δt = 0.82), FVS between.
        replica_check: vec![
            (Argyris, (10, 7), 1e-4),
            (Argyris, (4, 2), 1e-6),
            (Fvs, (7, 5), 1e-5),
        ],
    }
}

/// The damping study: the undamped forcings with each of [`damping_models`] (set by
/// [`study`] once ω₁ is known), Argyris 2 × 1 … 14 × 10 and FVS 7 × 5, 14 × 10 at Δt = 1e-4,
/// 1e-5, 1e-6 s, the two coarsest Argyris meshes down to 1e-7 s (ω_max·Δt = 0.02 and 0.07) for
/// the models that go there. No `energy` scene, no replica check.
fn damping_plan() -> Plan {
    use ElementKind::{Argyris, Fvs};
    let mesh = |element, mesh, dt_min| MeshPlan {
        element,
        mesh,
        dt_min,
    };
    Plan {
        name: "damping",
        dampings: Vec::new(),
        forcings: vec![FORCINGS[2], FORCINGS[3]],
        meshes: vec![
            mesh(Argyris, (2, 1), 1e-7),
            mesh(Argyris, (4, 2), 1e-7),
            mesh(Argyris, (6, 4), 1e-6),
            mesh(Argyris, (10, 7), 1e-6),
            mesh(Argyris, (14, 10), 1e-6),
            mesh(Fvs, (7, 5), 1e-6),
            mesh(Fvs, (14, 10), 1e-6),
        ],
        ladder: vec![1e-4, 1e-5, 1e-6, 1e-7],
        transient: 1.0,
        windows: 8,
        window_target: 0.375,
        replicas: 0,
        replica_check: Vec::new(),
    }
}

fn quick_plan() -> Plan {
    use ElementKind::{Argyris, Fvs};
    Plan {
        name: "quick",
        dampings: Vec::new(),
        forcings: vec![FORCINGS[0]],
        meshes: vec![
            MeshPlan {
                element: Argyris,
                mesh: (2, 1),
                dt_min: 1e-6,
            },
            MeshPlan {
                element: Fvs,
                mesh: (4, 3),
                dt_min: 2e-6,
            },
        ],
        ladder: vec![1e-4, 1e-5, 2e-6, 1e-6],
        transient: 1.0,
        windows: 8,
        window_target: 0.375,
        replicas: 3,
        replica_check: vec![(Argyris, (2, 1), 1e-5)],
    }
}

/// A statistic of one run: its value and spread (see the module documentation).
#[derive(Clone, Copy, Debug)]
struct Stat {
    quantity: &'static str,
    value: f64,
    spread: f64,
}

/// Mean and sample standard deviation.
fn mean_std(xs: &[f64]) -> (f64, f64) {
    let n = xs.len() as f64;
    let mean = xs.iter().sum::<f64>() / n;
    let var = xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1.0);
    (mean, var.sqrt())
}

/// What one window of a forced run accumulates.
#[derive(Clone, Copy, Debug, Default)]
struct Window {
    steps: usize,
    impacts: usize,
    contact_loss: f64,
    base_force_abs: f64,
    base_force_squared: f64,
    samples: usize,
    energy: f64,
    corner_squared: f64,
    corner_peak: f64,
}

/// A forced run: its windows and wall time.
struct ForcedRun {
    windows: Vec<Window>,
    periods_per_window: usize,
    wall_s: f64,
}

impl ForcedRun {
    /// The statistics over all windows, with their spreads.
    fn stats(&self) -> Vec<Stat> {
        let k = self.windows.len() as f64;
        let p = self.periods_per_window as f64;
        let sum = |f: &dyn Fn(&Window) -> f64| self.windows.iter().map(f).sum::<f64>();
        let samples = sum(&|w| w.samples as f64);
        let steps = sum(&|w| w.steps as f64);
        // A time average over all windows (their lengths agree to a step) and its standard error.
        let averaged = |quantity, per_window: &dyn Fn(&Window) -> f64, total: f64| {
            let values: Vec<f64> = self.windows.iter().map(per_window).collect();
            Stat {
                quantity,
                value: total,
                spread: mean_std(&values).1 / k.sqrt(),
            }
        };
        let peaks: Vec<f64> = self.windows.iter().map(|w| w.corner_peak).collect();
        vec![
            averaged(
                "rms_corner_m",
                &|w| (w.corner_squared / w.samples as f64).sqrt(),
                (sum(&|w| w.corner_squared) / samples).sqrt(),
            ),
            Stat {
                quantity: "peak_corner_m",
                value: peaks.iter().fold(0.0, |a: f64, &b| a.max(b)),
                spread: mean_std(&peaks).1,
            },
            averaged(
                "impacts_per_period",
                &|w| w.impacts as f64 / p,
                sum(&|w| w.impacts as f64) / (k * p),
            ),
            averaged(
                "contact_loss_per_period_J",
                &|w| w.contact_loss / p,
                sum(&|w| w.contact_loss) / (k * p),
            ),
            averaged(
                "mean_energy_J",
                &|w| w.energy / w.samples as f64,
                sum(&|w| w.energy) / samples,
            ),
            averaged(
                "mean_abs_base_force_N",
                &|w| w.base_force_abs / w.steps as f64,
                sum(&|w| w.base_force_abs) / steps,
            ),
            averaged(
                "rms_base_force_N",
                &|w| (w.base_force_squared / w.steps as f64).sqrt(),
                (sum(&|w| w.base_force_squared) / steps).sqrt(),
            ),
        ]
    }
}

fn base_scene(element: ElementKind, mesh: (usize, usize), dt: f64) -> Scene {
    let mut s = Scene::named("forced-35hz").expect("named scene");
    s.mesh.element = element;
    (s.mesh.nx, s.mesh.ny) = mesh;
    s.solver.time_step = dt;
    s
}

/// Sets the `name=value` scene parameters of the command line on `scene`, validated together
/// ([`Scene::set_all`]).
fn apply(scene: &mut Scene, overrides: &[String]) -> Result<(), String> {
    let pairs: Vec<(&str, &str)> = overrides.iter().filter_map(|o| o.split_once('=')).collect();
    scene.set_all(&pairs).map_err(|e| e.to_string())
}

/// The meshes of `--mesh argyris:10x7,fvs:14x10`, each run at every Δt of the ladder.
fn parse_meshes(list: &str) -> Result<Vec<MeshPlan>, String> {
    list.split(',')
        .map(|item| {
            let usage = || format!("--mesh {item}: use ELEMENT:NXxNY, e.g. argyris:10x7");
            let (element, cells) = item.split_once(':').ok_or_else(usage)?;
            let element = match element {
                "argyris" => ElementKind::Argyris,
                "fvs" => ElementKind::Fvs,
                _ => return Err(usage()),
            };
            let (nx, ny) = cells.split_once('x').ok_or_else(usage)?;
            let cells = |n: &str| n.parse::<usize>().ok().filter(|&n| n > 0).ok_or_else(usage);
            Ok(MeshPlan {
                element,
                mesh: (cells(nx)?, cells(ny)?),
                dt_min: 0.0,
            })
        })
        .collect()
}

/// Every `stride` steps the outputs are sampled: every step up to [`SAMPLE_INTERVAL`], then
/// every interval.
fn sample_stride(dt: f64) -> usize {
    ((SAMPLE_INTERVAL / dt).round() as usize).max(1)
}

/// Runs a forced scene: transient, then `plan.windows` windows of whole periods.
#[allow(clippy::too_many_arguments)]
fn run_forced(
    plan: &Plan,
    forcing: Forcing,
    alpha: f64,
    element: ElementKind,
    mesh: (usize, usize),
    dt: f64,
    preload: f64,
    overrides: &[String],
) -> Result<ForcedRun, String> {
    let mut s = base_scene(element, mesh, dt);
    s.base.frequency = forcing.frequency;
    s.base.amplitude = forcing.amplitude;
    s.damping.mass_proportional = if forcing.damped { alpha } else { 0.0 };
    s.initial.preload_pressure = preload;
    apply(&mut s, overrides)?;
    let periods = (forcing.frequency * plan.window_target).round() as usize;
    let window_s = periods as f64 / forcing.frequency;
    // Last step of window j: bounds[j + 1]; the windows are (bounds[j], bounds[j + 1]].
    let bounds: Vec<usize> = (0..=plan.windows)
        .map(|j| ((plan.transient + j as f64 * window_s) / dt).round() as usize)
        .collect();
    let steps = *bounds.last().expect("windows");
    let stride = sample_stride(dt);
    let mut windows = vec![Window::default(); plan.windows];
    let started = Instant::now();
    let mut stepper = Stepper::new(&s, 0.0).map_err(|e| e.to_string())?;
    let mut j = 0;
    for n in 1..=steps {
        let report = stepper
            .step(s.builtin_base(n as f64 * dt))
            .map_err(|e| format!("{} step {n}: {e}", forcing.label))?;
        if n <= bounds[0] {
            continue;
        }
        if n > bounds[j + 1] {
            j += 1;
        }
        let w = &mut windows[j];
        w.steps += 1;
        w.impacts += usize::from(report.impact);
        w.contact_loss += report.flows.contact_loss;
        w.base_force_abs += report.base_force.abs();
        w.base_force_squared += report.base_force * report.base_force;
        if n % stride == 0 {
            let o = stepper.outputs();
            w.samples += 1;
            w.energy += o.energy_total;
            w.corner_squared += o.corner1 * o.corner1;
            w.corner_peak = w.corner_peak.max(o.corner1.abs());
        }
    }
    Ok(ForcedRun {
        windows,
        periods_per_window: periods,
        wall_s: started.elapsed().as_secs_f64(),
    })
}

/// What one run of the `energy` scene reports.
struct EnergyRun {
    first_impact_s: f64,
    energy_j: [f64; 2],
    impacts: usize,
    wall_s: f64,
}

fn run_energy(
    element: ElementKind,
    mesh: (usize, usize),
    dt: f64,
    perturbation: f64,
    overrides: &[String],
) -> Result<EnergyRun, String> {
    let mut s = Scene::named("energy").expect("named scene");
    s.mesh.element = element;
    (s.mesh.nx, s.mesh.ny) = mesh;
    s.solver.time_step = dt;
    s.initial.preload_pressure *= 1.0 + perturbation;
    apply(&mut s, overrides)?;
    let marks = ENERGY_TIMES.map(|t| (t / dt).round() as usize);
    let started = Instant::now();
    let mut stepper = Stepper::new(&s, 0.0).map_err(|e| e.to_string())?;
    let (mut first, mut impacts, mut energy_j) = (f64::NAN, 0, [f64::NAN; 2]);
    for n in 1..=marks[1] {
        let report = stepper
            .step(0.0)
            .map_err(|e| format!("energy step {n}: {e}"))?;
        if report.impact {
            impacts += 1;
            if first.is_nan() {
                first = n as f64 * dt;
            }
        }
        for (k, &mark) in marks.iter().enumerate() {
            if n == mark {
                energy_j[k] = stepper.outputs().energy_total;
            }
        }
    }
    Ok(EnergyRun {
        first_impact_s: first,
        energy_j,
        impacts,
        wall_s: started.elapsed().as_secs_f64(),
    })
}

/// The `energy` statistics of R replicas at time step `dt`: the unperturbed run's value, the
/// replicas' standard deviation, the unperturbed run's wall time. The first impact is read on the
/// step grid (the end of the step in which it happens), so its spread also holds the step's:
/// √(σ² + Δt²/12), the standard deviation of a time uniform within the step.
fn energy_stats(replicas: &[EnergyRun], dt: f64) -> (Vec<Stat>, f64) {
    let stat = |quantity, f: &dyn Fn(&EnergyRun) -> f64| {
        let values: Vec<f64> = replicas.iter().map(f).collect();
        Stat {
            quantity,
            value: values[0],
            spread: mean_std(&values).1,
        }
    };
    let first = stat("first_impact_s", &|r| r.first_impact_s);
    (
        vec![
            Stat {
                spread: first.spread.hypot(dt / 12f64.sqrt()),
                ..first
            },
            stat("energy_0.1s_J", &|r| r.energy_j[0]),
            stat("energy_0.3s_J", &|r| r.energy_j[1]),
            stat("impacts_to_0.3s", &|r| r.impacts as f64),
        ],
        replicas[0].wall_s,
    )
}

/// ω₁ and ω_max of a mesh (rad/s) and its free dofs, from the library's eigenbasis.
fn mesh_modes(element: ElementKind, mesh: (usize, usize)) -> Result<(f64, f64, usize), String> {
    let plate = PlateSystem::new(&base_scene(element, mesh, 1e-4)).map_err(|e| e.to_string())?;
    let modes = plate.modes().map_err(|e| e.to_string())?;
    let w2 = &modes.omega_squared;
    Ok((
        w2[0].sqrt(),
        w2.last().expect("modes").sqrt(),
        plate.free.len(),
    ))
}

/// One row of `statistics.csv` per statistic; with a damping model (the damping study), its
/// label in a column after the scene's.
#[allow(clippy::too_many_arguments)]
fn rows(
    csv: &mut String,
    scene: &str,
    damping: Option<&str>,
    element: ElementKind,
    mesh: (usize, usize),
    dt: f64,
    omega_max: f64,
    stats: &[Stat],
    wall_s: f64,
) {
    let scene = match damping {
        Some(model) => format!("{scene},{model}"),
        None => scene.to_string(),
    };
    for s in stats {
        writeln!(
            csv,
            "{},{scene},{},{},{},{dt:e},{:.6e},{:.10e},{:.4e},{wall_s:.6}",
            s.quantity,
            element_name(element),
            mesh.0,
            mesh.1,
            omega_max * dt,
            s.value,
            s.spread
        )
        .expect("write to string");
    }
}

fn main() -> ExitCode {
    exit_code(study())
}

fn study() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dir = StudyDir::from_args(&args, "statistics", "accuracy")?;
    let value_of = |flag: &str| {
        args.iter()
            .position(|a| a == flag)
            .map(|i| {
                args.get(i + 1)
                    .cloned()
                    .ok_or(format!("{flag} needs a value"))
            })
            .transpose()
    };
    let damping_study = match value_of("--study")?.as_deref() {
        None | Some("statistics") => false,
        Some("damping") => true,
        Some(other) => return Err(format!("--study {other}: use statistics or damping")),
    };
    let mut plan = if damping_study {
        let mut plan = damping_plan();
        if dir.quick {
            // The pipeline only: every model on the coarsest mesh, two Δt, one forcing.
            plan.name = "damping-quick";
            plan.forcings.truncate(1);
            plan.meshes.truncate(1);
            plan.ladder = vec![1e-4, 1e-5];
        }
        plan
    } else if dir.quick {
        quick_plan()
    } else {
        full_plan(args.iter().any(|a| a == "--reduced"))
    };
    // The files of the study: statistics.csv, meshes.csv, statistics_meta.csv, or damping.csv,
    // damping_meshes.csv, damping_meta.csv.
    let file = |name: &str| match (damping_study, name) {
        (false, _) => name.to_string(),
        (true, "statistics.csv") => "damping.csv".to_string(),
        (true, _) => format!("damping_{}", name.trim_start_matches("statistics_")),
    };
    let forcings = value_of("--forcings")?;
    if let Some(kind) = &forcings {
        match kind.as_str() {
            "damped" => plan.forcings.retain(|f| f.damped),
            "undamped" => plan.forcings.retain(|f| !f.damped),
            labels => {
                let labels: Vec<&str> = labels.split(',').collect();
                if let Some(bad) = labels
                    .iter()
                    .find(|l| !FORCINGS.iter().any(|f| f.label == **l))
                {
                    return Err(format!(
                        "--forcings {bad}: use damped, undamped or labels among {:?}",
                        FORCINGS.map(|f| f.label)
                    ));
                }
                plan.forcings = FORCINGS
                    .into_iter()
                    .filter(|f| labels.contains(&f.label))
                    .collect();
            }
        }
    }
    let meshes = value_of("--mesh")?;
    if let Some(list) = &meshes {
        plan.meshes = parse_meshes(list)?;
    }
    let windows = value_of("--windows")?;
    if windows.is_some() {
        plan.windows = positive_integer("--windows", windows.clone())?;
        if plan.windows < 2 {
            return Err("--windows needs at least 2 windows (the spread)".into());
        }
    }
    let steps = value_of("--dt")?;
    if let Some(list) = &steps {
        plan.ladder = list
            .split(',')
            .map(|dt| {
                dt.parse::<f64>()
                    .ok()
                    .filter(|dt| dt.is_finite() && *dt > 0.0)
                    .ok_or(format!("--dt {dt}: use time steps > 0 (s), e.g. 1e-4,1e-5"))
            })
            .collect::<Result<_, _>>()?;
    }
    let overrides: Vec<String> = args.iter().filter(|a| a.contains('=')).cloned().collect();
    let mut skip: Vec<String> = value_of("--skip")?
        .map(|list| list.split(',').map(str::to_string).collect())
        .unwrap_or_default();
    let skip_given = !skip.is_empty();
    if damping_study {
        skip.extend(["energy".to_string(), "replicas".to_string()]);
    }
    if let Some(bad) = skip
        .iter()
        .find(|s| !["energy", "forced", "replicas"].contains(&s.as_str()))
    {
        return Err(format!("--skip {bad}: use energy, forced and/or replicas"));
    }
    let skips = |part: &str| skip.iter().any(|s| s == part);
    let models = value_of("--damping")?;
    if models.is_some() && !damping_study {
        return Err("--damping needs --study damping".into());
    }
    let partial = forcings.is_some()
        || models.is_some()
        || windows.is_some()
        || meshes.is_some()
        || steps.is_some()
        || !overrides.is_empty()
        || skip_given;
    let started = Instant::now();

    let (omega1, _, _) = mesh_modes(ElementKind::Argyris, (10, 7))?;
    let alpha = 2.0 * ZETA1 * omega1;
    if damping_study {
        plan.dampings = damping_models(omega1);
        if let Some(list) = &models {
            let labels: Vec<&str> = list.split(',').collect();
            if let Some(bad) = labels
                .iter()
                .find(|l| !plan.dampings.iter().any(|d| d.label == **l))
            {
                let known: Vec<&str> = plan.dampings.iter().map(|d| d.label).collect();
                return Err(format!("--damping {bad}: use labels among {known:?}"));
            }
            plan.dampings.retain(|d| labels.contains(&d.label));
        }
    }
    // Each forced run's damping: a model of the damping study (its label and settings before the
    // command line's), or the forcing's own.
    let runs_of: Vec<(Option<&DampingModel>, Vec<String>)> = if plan.dampings.is_empty() {
        vec![(None, overrides.clone())]
    } else {
        plan.dampings
            .iter()
            .map(|d| {
                let settings = d.settings.iter().map(|(k, v)| format!("{k}={v}"));
                let all = settings.chain(overrides.iter().cloned()).collect();
                (Some(d), all)
            })
            .collect()
    };
    let mut meshes_csv = String::from("element,nx,ny,free_dofs,omega1_rad_s,omega_max_rad_s\n");
    let mut omega_max = Vec::new();
    for m in &plan.meshes {
        let (w1, wmax, dofs) = mesh_modes(m.element, m.mesh)?;
        writeln!(
            meshes_csv,
            "{},{},{},{dofs},{w1:.6},{wmax:.6e}",
            element_name(m.element),
            m.mesh.0,
            m.mesh.1
        )
        .expect("write to string");
        omega_max.push(wmax);
    }
    dir.write(&file("meshes.csv"), &meshes_csv)?;

    let mut csv = String::from(if damping_study {
        "quantity,scene,damping,element,nx,ny,dt,omega_max_dt,value,spread,wall_s\n"
    } else {
        "quantity,scene,element,nx,ny,dt,omega_max_dt,value,spread,wall_s\n"
    });
    // The smallest Δt of a mesh, for a damping model of the damping study unless `--dt` names
    // the time steps.
    let lowest = |m: &MeshPlan, model: Option<&DampingModel>| {
        let model = model.filter(|_| steps.is_none());
        model.map_or(m.dt_min, |d| d.dt_min(m)) * (1.0 - 1e-9)
    };
    let runs_at = |m: &MeshPlan, model| {
        let lowest = lowest(m, model);
        plan.ladder.iter().filter(|&&dt| dt >= lowest).count()
    };
    let energy_runs: usize = plan.meshes.iter().map(|m| runs_at(m, None)).sum();
    let forced_runs: usize = runs_of
        .iter()
        .flat_map(|r| plan.meshes.iter().map(|m| runs_at(m, r.0)))
        .sum();
    let total_runs = energy_runs * usize::from(!skips("energy"))
        + if skips("forced") {
            0
        } else {
            forced_runs * plan.forcings.len()
        };
    let mut done = 0;
    let mut progress = |scene: &str, m: &MeshPlan, dt: f64, wmax: f64, wall: f64| {
        done += 1;
        eprintln!(
            "[{done:>3}/{total_runs}] {scene:<24} {:<7} {:>2}×{:<2} Δt={dt:<7e} ω_max·Δt={:<8.3} {wall:>8.2} s (study {:.0} s)",
            element_name(m.element),
            m.mesh.0,
            m.mesh.1,
            wmax * dt,
            started.elapsed().as_secs_f64()
        );
    };
    // statistics.csv is rewritten after every run, so that a study stopped early keeps its runs.
    let energy_meshes = if skips("energy") {
        &[][..]
    } else {
        &plan.meshes[..]
    };
    for (m, &wmax) in energy_meshes.iter().zip(&omega_max) {
        for &dt in plan.ladder.iter().filter(|&&dt| dt >= m.dt_min) {
            let replicas = (0..plan.replicas)
                .map(|k| {
                    let perturbation = k as f64 * ENERGY_PERTURBATION;
                    run_energy(m.element, m.mesh, dt, perturbation, &overrides)
                })
                .collect::<Result<Vec<_>, _>>()?;
            let (stats, wall) = energy_stats(&replicas, dt);
            rows(
                &mut csv, "energy", None, m.element, m.mesh, dt, wmax, &stats, wall,
            );
            dir.write(&file("statistics.csv"), &csv)?;
            progress("energy", m, dt, wmax, wall);
        }
    }
    let mut quick_values = Vec::new();
    let forced = if skips("forced") {
        &[][..]
    } else {
        &plan.forcings[..]
    };
    for forcing in forced {
        for (model, settings) in &runs_of {
            for (m, &wmax) in plan.meshes.iter().zip(&omega_max) {
                let lowest = lowest(m, *model);
                for &dt in plan.ladder.iter().filter(|&&dt| dt >= lowest) {
                    let run =
                        run_forced(&plan, *forcing, alpha, m.element, m.mesh, dt, 0.0, settings)?;
                    let stats = run.stats();
                    rows(
                        &mut csv,
                        forcing.label,
                        model.map(|d| d.label),
                        m.element,
                        m.mesh,
                        dt,
                        wmax,
                        &stats,
                        run.wall_s,
                    );
                    dir.write(&file("statistics.csv"), &csv)?;
                    let label = match model {
                        Some(model) => format!("{} {}", forcing.label, model.label),
                        None => forcing.label.to_string(),
                    };
                    progress(&label, m, dt, wmax, run.wall_s);
                    if m.element == ElementKind::Argyris && m.mesh == (2, 1) {
                        quick_values.push((forcing.label, dt, stats));
                    }
                }
            }
        }
    }

    // The window estimate of the spread against R perturbed runs of the same setting.
    let mut check = String::from(
        "scene,element,nx,ny,dt,quantity,value,window_spread,replica_mean,replica_std,replicas\n",
    );
    let checked = if skips("replicas") {
        &[][..]
    } else {
        &plan.replica_check[..]
    };
    let settings = plan
        .forcings
        .iter()
        .flat_map(|f| checked.iter().map(move |&s| (*f, s)));
    for (forcing, (element, mesh, dt)) in settings {
        let label = forcing.label;
        let runs = (0..plan.replicas)
            .map(|k| {
                let preload = k as f64 * FORCED_PERTURBATION_PA;
                run_forced(
                    &plan, forcing, alpha, element, mesh, dt, preload, &overrides,
                )
                .map(|r| r.stats())
            })
            .collect::<Result<Vec<_>, _>>()?;
        for (q, s) in runs[0].iter().enumerate() {
            let values: Vec<f64> = runs.iter().map(|r| r[q].value).collect();
            let (mean, std) = mean_std(&values);
            writeln!(
                check,
                "{label},{},{},{},{dt:e},{},{:.10e},{:.4e},{mean:.10e},{std:.4e},{}",
                element_name(element),
                mesh.0,
                mesh.1,
                s.quantity,
                s.value,
                s.spread,
                plan.replicas
            )
            .expect("write to string");
        }
        eprintln!(
            "replica check: {label} {} {}×{} Δt={dt:e} (study {:.0} s)",
            element_name(element),
            mesh.0,
            mesh.1,
            started.elapsed().as_secs_f64()
        );
    }
    if !damping_study {
        dir.write("replica_check.csv", &check)?;
    }

    let total_s = started.elapsed().as_secs_f64();
    let mut meta = String::from("key,value\n");
    for (k, v) in [
        ("quick", dir.quick.to_string()),
        ("plan", plan.name.to_string()),
        ("total_s", format!("{total_s:.1}")),
        ("zeta1", ZETA1.to_string()),
        ("alpha", format!("{alpha:.6}")),
        ("omega1_reference", format!("{omega1:.6}")),
        ("transient_s", plan.transient.to_string()),
        ("windows", plan.windows.to_string()),
        ("window_target_s", plan.window_target.to_string()),
        ("replicas", plan.replicas.to_string()),
        ("energy_perturbation", ENERGY_PERTURBATION.to_string()),
        ("forced_perturbation_pa", FORCED_PERTURBATION_PA.to_string()),
        ("sample_interval_s", SAMPLE_INTERVAL.to_string()),
        ("overrides", overrides.join(" ")),
    ] {
        writeln!(meta, "{k},{v}").expect("write to string");
    }
    for d in &plan.dampings {
        let settings: Vec<String> = d.settings.iter().map(|(k, v)| format!("{k}={v}")).collect();
        writeln!(meta, "damping {},{}", d.label, settings.join(" ")).expect("write to string");
    }
    dir.write(&file("statistics_meta.csv"), &meta)?;
    if partial {
        let script = if damping_study {
            "damping_plots"
        } else {
            "statistics_plots"
        };
        eprintln!(
            "partial study done in {total_s:.1} s: concatenate its CSVs with the other parts', \
             then run `python -m plateimpact_tools.studies.{script} DIR` on them"
        );
        return Ok(());
    }
    eprintln!("runs done in {total_s:.1} s; plotting");
    if damping_study {
        dir.plot("damping_plots")?;
        let failures = dir.missing(&["damping.csv", "damping_meshes.csv", "damping_meta.csv"]);
        return dir.finish(failures);
    }
    dir.plot("statistics_plots")?;

    let mut failures = quick_check(&quick_values);
    failures.extend(dir.missing(&[
        "statistics.csv",
        "meshes.csv",
        "replica_check.csv",
        "statistics_meta.csv",
        "statistics.md",
    ]));
    eprintln!(
        "study done in {:.1} s; output in {}",
        started.elapsed().as_secs_f64(),
        dir.path.display()
    );
    dir.finish(failures)
}

/// What the quick mode asserts (checked in the full study too), on the damped 35 Hz scene on the
/// Argyris 2 × 1 mesh (ω_max = 2.2e5 rad/s), the one setting cheap enough to resolve:
/// - convergence: at Δt = 2e-6 and 1e-6 s (ω_max·Δt = 0.44 and 0.22) the RMS corner, the mean
///   energy and the mean |base force| agree within 3σ of their difference;
/// - the hypothesis the study tests: at the paper's Δt = 1e-4 s (ω_max·Δt = 22) the mean |base
///   force| differs from the resolved one by more than 3σ (the committed study: 8.8σ).
///
/// σ is the window spread, the standard deviation of a run's value. Any change of round-off sends
/// a chaotic response on another course, so a correct change of the library moves these values
/// by about σ: 3σ keeps the chance that such a change fails the agreement near 0.3 %.
fn quick_check(values: &[(&'static str, f64, Vec<Stat>)]) -> Vec<String> {
    let stat = |dt: f64, quantity: &str| {
        values
            .iter()
            .find(|(label, d, _)| *label == "forced-35hz-damped" && *d == dt)
            .and_then(|(_, _, stats)| stats.iter().find(|s| s.quantity == quantity))
            .copied()
    };
    let mut failures = Vec::new();
    let sigmas = |a: Stat, b: Stat| (a.value - b.value).abs() / a.spread.hypot(b.spread);
    for quantity in ["rms_corner_m", "mean_energy_J", "mean_abs_base_force_N"] {
        match (stat(2e-6, quantity), stat(1e-6, quantity)) {
            (Some(a), Some(b)) => {
                let z = sigmas(a, b);
                eprintln!("check: {quantity} at Δt = 2e-6 and 1e-6 s differ by {z:.2}σ");
                if z > 3.0 {
                    failures.push(format!(
                        "{quantity} has not converged on Argyris 2×1: {} at Δt = 2e-6 s and {} at \
                         1e-6 s differ by {z:.2}σ > 3σ",
                        a.value, b.value
                    ));
                }
            }
            _ => failures.push(format!("{quantity}: the Argyris 2×1 runs are missing")),
        }
    }
    let quantity = "mean_abs_base_force_N";
    match (stat(1e-4, quantity), stat(1e-6, quantity)) {
        (Some(a), Some(b)) => {
            let z = sigmas(a, b);
            eprintln!("check: {quantity} at Δt = 1e-4 and 1e-6 s differ by {z:.2}σ");
            if z <= 3.0 {
                failures.push(format!(
                    "{quantity} at the paper's Δt = 1e-4 s ({}) should differ from the resolved \
                     Δt = 1e-6 s ({}) by more than 3σ, but differs by {z:.2}σ",
                    a.value, b.value
                ));
            }
        }
        _ => failures.push(format!("{quantity}: the Argyris 2×1 runs are missing")),
    }
    failures
}
