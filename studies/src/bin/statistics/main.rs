//! Statistics study: error against run time for the numbers users read from impact runs (time
//! averages and counts of a forced steady state, and the landmarks of a released plate), for both
//! elements, several meshes each, and Δt from the paper's 1e-3 s down to ω_max·Δt ≤ 1, where ω_max
//! is the highest natural angular frequency of the mesh (the library's, `src/modes.rs`).
//!
//! `cargo run --release -p plate_impact_studies --bin statistics [-- --quick | --reduced] [--out DIR]`
//!
//! The study in three steps: the plan (`plan.rs`: which runs, one entry per simulation), the run
//! (`run.rs`: the simulations, each appended to the CSV as it ends) and the write (`write.rs`: the
//! CSVs' rows and the meta file; then the study's module of `plateimpact_tools.studies` in
//! `tools/`, run with the Python of `scripts/python-env`, which reads the CSVs and writes the
//! tables and plots). The command line (`options.rs`) chooses and narrows the plan.
//!
//! `--study damping` runs the damping study instead ([`plan::damping_plan`]): the undamped
//! forcings with each damping model of [`plan::damping_models`] (`--damping LABEL,LABEL` keeps
//! those) on a grid of meshes and Δt, then the parts beyond the grid (`--part LABEL,LABEL` keeps
//! those of `grid`, `contact-loss`, `finer-reference`, `threshold`), written to `damping.csv` (the
//! columns of `statistics.csv` plus `damping` after `scene`), `damping_meshes.csv` and
//! `damping_meta.csv`, then `plateimpact_tools.studies.damping_plots` writes the plots and the
//! generated tables of `docs/accuracy/damping.md`. The other options below apply alike; with
//! `--quick`, every model on Argyris 2 × 1 at Δt = 1e-4 and 1e-5 s on `forced-35hz` (about 2 s),
//! in a temporary directory, checks the pipeline.
//!
//! A part of the study, to share it between processes (`--out` to separate directories; the CSVs
//! are then concatenated and `python -m plateimpact_tools.studies.statistics_plots DIR` run on the
//! result): `--forcings damped` or `undamped` keeps those forced scenes only (or `--forcings
//! LABEL,LABEL` the named ones, e.g. `forced-35hz`), `--skip energy,forced,replicas` leaves out the
//! `energy` scene, the forced runs or the replica check, `--mesh argyris:10x7[,fvs:14x10]` runs
//! those meshes only and `--dt 1e-4,1e-5` those time steps only (every mesh runs every one of them,
//! whatever the damping model's smallest Δt), `--windows K` K ≥ 2 windows instead of the plan's (a
//! cheaper run of a periodic steady state). Trailing `name=value` arguments set scene parameters
//! (the FMU variable names, [`Scene::set`](plate_impact::scene::Scene::set)) of every run, after the study's own settings:
//! `damping.stiffness_proportional=5.913e-5` or `damping.ratio=0.01 damping.frequency_low=53.8
//! damping.frequency_high=5000` with `--forcings undamped` (the `-damped` forcings add their α
//! first, which the Rayleigh pair refuses); they are recorded in `statistics_meta.csv`. A partial
//! study writes its CSVs but neither plots nor checks.
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
//! wall_s, windows (empty for `energy`), zeta_hf (the lightest damping ratio of the modes with
//! ω ≥ 1/Δt, the start-up warning's quantity, `src/advice.rs`), part (of the plan)),
//! `meshes.csv` (ω₁ and ω_max per mesh), `replica_check.csv`, `statistics_meta.csv` (the plan's
//! settings, the command line and the commit of the code that ran: `+modified` after it when the
//! work tree differed from it); then `plateimpact_tools.studies.statistics_plots` writes the
//! work-precision plots, the data of each beside it as a CSV, and the tables of `statistics.md`
//! (its prose is hand-written; a directory without the page gets a copy of the committed one).
//! `--quick` runs a small subset (about 10 s) in a temporary directory and exits nonzero unless
//! the pipeline completes and, on the damped 35 Hz scene on the Argyris 2 × 1 mesh, the statistics
//! have converged once ω_max·Δt < 1 and the mean |base force| has not at the paper's Δt (see
//! [`quick_check`]).

mod options;
mod plan;
mod run;
mod write;

use options::{Options, Study};
use plan::SceneKind;
use plate_impact::element::ElementKind;
use plate_impact_studies::cli::exit_code;
use plate_impact_studies::element::element_name;
use plate_impact_studies::output::StudyDir;
use plate_impact_studies::revision::source_revision;
use run::{Context, Stat};
use std::process::ExitCode;
use std::time::Instant;

fn main() -> ExitCode {
    exit_code(study())
}

/// Plan, run, write.
fn study() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dir = StudyDir::from_args(&args, "statistics", "accuracy")?;
    let options = Options::parse(&args, dir.quick)?;
    let revision = source_revision();
    let started = Instant::now();
    let (alpha, omega1) = run::reference_damping()?;
    let plan = options.plan(omega1)?;
    if args.iter().any(|a| a == "--plan") {
        plan::print_plan(&plan);
        return Ok(());
    }
    let files = Files(options.study == Study::Damping);
    let context = Context {
        plan: &plan,
        alpha,
        overrides: &options.overrides,
    };
    let quick_values = run_plan(&context, &dir, &files, started)?;
    let total_s = started.elapsed().as_secs_f64();
    let meta = write::meta(&plan, &options, &args, &revision, alpha, omega1, total_s);
    dir.write(&files.name("statistics_meta.csv"), &meta)?;
    if options.partial() {
        eprintln!(
            "partial study done in {total_s:.1} s: concatenate its CSVs with the other parts', \
             then run `python -m plateimpact_tools.studies.{} DIR` on them",
            files.module()
        );
        return Ok(());
    }
    eprintln!("runs done in {total_s:.1} s; writing tables and plots");
    dir.page("accuracy", files.page())?;
    dir.plot(files.module())?;
    let mut failures = if files.0 {
        Vec::new()
    } else {
        quick_check(&quick_values)
    };
    failures.extend(dir.missing(&files.expected()));
    eprintln!(
        "study done in {:.1} s; output in {}",
        started.elapsed().as_secs_f64(),
        dir.path.display()
    );
    dir.finish(failures)
}

/// The file names of the statistics study, or of the damping study (`.0`): `damping.csv` for
/// `statistics.csv`, `damping_meshes.csv` for `meshes.csv` and so on.
struct Files(bool);

impl Files {
    fn name(&self, name: &str) -> String {
        match (self.0, name) {
            (false, _) => name.to_string(),
            (true, "statistics.csv") => "damping.csv".to_string(),
            (true, _) => format!("damping_{}", name.trim_start_matches("statistics_")),
        }
    }

    /// The write step: its module of `plateimpact_tools.studies`.
    fn module(&self) -> &'static str {
        if self.0 {
            "damping_plots"
        } else {
            "statistics_plots"
        }
    }

    /// The hand-written page whose tables the write step fills.
    fn page(&self) -> &'static str {
        if self.0 {
            "damping.md"
        } else {
            "statistics.md"
        }
    }

    /// The files a whole study must leave.
    fn expected(&self) -> Vec<&'static str> {
        if self.0 {
            vec!["damping.csv", "damping_meshes.csv", "damping_meta.csv"]
        } else {
            vec![
                "statistics.csv",
                "meshes.csv",
                "replica_check.csv",
                "statistics_meta.csv",
                "statistics.md",
            ]
        }
    }
}

/// The statistics the quick check reads: (forcing, Δt, statistics) of the forced runs on
/// Argyris 2 × 1.
type QuickValues = Vec<(&'static str, f64, Vec<Stat>)>;

/// Runs the plan one simulation after the other: the meshes' modes (`meshes.csv`), every run
/// (the CSV rewritten after each, so that a study stopped early keeps its runs), then the
/// replica check (`replica_check.csv`, the statistics study only).
fn run_plan(
    context: &Context,
    dir: &StudyDir,
    files: &Files,
    started: Instant,
) -> Result<QuickValues, String> {
    let plan = context.plan;
    let mut meshes_csv = String::from(write::MESHES_HEADER);
    let mut omega_max = Vec::new();
    let meshes = plan.meshes();
    for &m in &meshes {
        let (w1, wmax, dofs) = run::mesh_modes(m)?;
        write::mesh_row(&mut meshes_csv, m, w1, wmax, dofs);
        omega_max.push(wmax);
    }
    dir.write(&files.name("meshes.csv"), &meshes_csv)?;
    let mut csv = String::from(write::header(!plan.dampings.is_empty()));
    let mut quick_values = Vec::new();
    for (done, r) in plan.runs.iter().enumerate() {
        let wmax = omega_max[meshes.iter().position(|m| *m == r.mesh).expect("mesh")];
        let outcome = context.run(r)?;
        write::rows(&mut csv, plan, r, wmax, &outcome);
        dir.write(&files.name("statistics.csv"), &csv)?;
        let label = match plan.damping_of(r) {
            Some(model) => format!("{} {}", r.scene.label(), model.label),
            None => r.scene.label().to_string(),
        };
        eprintln!(
            "[{:>3}/{}] {label:<24} {:<7} {:>2}×{:<2} Δt={:<7e} ω_max·Δt={:<8.3} {:>8.2} s (study {:.0} s)",
            done + 1,
            plan.runs.len(),
            element_name(r.mesh.element),
            r.mesh.nx,
            r.mesh.ny,
            r.dt,
            wmax * r.dt,
            outcome.wall_s,
            started.elapsed().as_secs_f64()
        );
        if let SceneKind::Forced(f) = r.scene {
            if r.mesh == plan::Mesh::new(ElementKind::Argyris, 2, 1) {
                quick_values.push((f.label, r.dt, outcome.stats));
            }
        }
    }
    if plan.dampings.is_empty() {
        dir.write("replica_check.csv", &replica_check(context, started)?)?;
    }
    Ok(quick_values)
}

/// The window estimate of the spread against R perturbed runs of the same setting, for each
/// setting of the plan's replica check: the rows of `replica_check.csv`.
fn replica_check(context: &Context, started: Instant) -> Result<String, String> {
    let plan = context.plan;
    let mut check = String::from(
        "scene,element,nx,ny,dt,quantity,value,window_spread,replica_mean,replica_std,replicas\n",
    );
    for &(forcing, mesh, dt) in &plan.replica_check {
        let r = plan::Run {
            scene: SceneKind::Forced(forcing),
            damping: None,
            mesh,
            dt,
            windows: plan.runs.first().map_or(8, |r| r.windows),
            settings: Vec::new(),
            part: plan::Part::Grid,
        };
        write::replica_rows(&mut check, &r, &context.replicas(&r)?);
        eprintln!(
            "replica check: {} {} {}×{} Δt={dt:e} (study {:.0} s)",
            forcing.label,
            element_name(mesh.element),
            mesh.nx,
            mesh.ny,
            started.elapsed().as_secs_f64()
        );
    }
    Ok(check)
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
