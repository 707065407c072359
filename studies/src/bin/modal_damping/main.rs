//! Modal damping study: the statistics of a plate damped mode by mode (`damping.modal_ratio` ζ,
//! the same ratio on every mode of the clamped plate), per ratio, scene, element, mesh and Δt,
//! with their spreads from windows and from perturbed replicas, the correlation time that sets the
//! windows, and where the energy sits among the modes (docs/accuracy/modal_damping.md).
//!
//! `cargo run --release -p plate_impact_studies --bin modal_damping [-- --quick | --plan] [--out DIR] [selection]`
//!
//! Without a selection the committed plan runs ([`committed_plan`](plan::committed_plan), `--plan`
//! lists its lines), then `python -m plateimpact_tools.studies.modal_damping_plots` writes the
//! plots and the generated part of the page. The study in modules: the plan (`plan.rs`, narrowed by
//! the command line of `options.rs`), the runs (`run.rs`) and the CSVs (`write.rs`).
//! A selection runs a part of it, to share the study between processes (its CSVs are then
//! concatenated and the plotting script run on the result): `--part middle,third,ratios,fine,finedt`,
//! `--scenes LABEL,…` among [`SCENES`](plan::SCENES), `--zeta 0.005,0.01`, `--keep-mesh argyris:28x20,…` keep
//! those lines of the plan; `--mesh argyris:10x7,fvs:14x10` runs those meshes instead of the
//! plan's, `--dt 1e-5,1e-6` that ladder, `--duration S`, `--transient S`, `--window S`,
//! `--replicas R`, `--max-run-cpu S`, `--no-settle` (every Δt of the ladder), `--series` (every
//! run's per-period series in `modal_damping_periods.csv`) change its settings, and trailing
//! `name=value` arguments set scene parameters of every run (the FMU variable names).
//!
//! Per run (one [`Stepper`](plate_impact::scheme::Stepper), modal backend): the scene forced from rest for `transient` s, then
//! `duration` s of steady state, recorded forcing period by forcing period: the mean of
//! `energy.total`, the mean square and peak of the free corner u(Lx, 0), the mean of |base.force|
//! and of its square, the impacts (`StepReport::impact`) and the energy removed at the obstacles,
//! and the energy of each band of natural frequencies ([`BAND_EDGES_HZ`](run::BAND_EDGES_HZ)), averaged over the period.
//! The energy of mode k between levels n−1 and n is that of the scheme's discrete energy,
//! E_k = ½((q_k,n − q_k,n−1)/Δt)² + ¼ω_k²(q_k,n² + q_k,n−1²), from the modal coordinates q of the
//! stepper's state (the modal backend's field, w = Φq with Φ M-orthonormal) and ω_k² from the
//! library's eigenbasis of the same plate (`PlateSystem::modes`); Σ_k of the elastic part equals
//! `energy.elastic`, which every run checks at its first sample.
//!
//! Statistics over the steady state's P periods: the value of a time average is the mean over all
//! of them; its spread, the standard deviation of what one run would report had its chaotic
//! response taken another course, is estimated three ways:
//! - windows: the periods cut into K windows of the whole periods nearest `window` s (chosen
//!   from the correlation times), the standard deviation of the K window values / √K;
//! - correlation: √(τ σ² / P), σ² the variance of the per-period values and τ their integrated
//!   autocorrelation time in periods (`plate_impact_studies::autocorrelation`);
//! - replicas: R more runs of the same setting from initial states perturbed by
//!   k·[`REPLICA_PERTURBATION`](run::REPLICA_PERTURBATION) on the first modal coordinate (k = 1 … R), restored into the same
//!   stepper, the standard deviation of the R + 1 run values;
//!
//! and the largest is the reported spread. A line of the plan runs its Δt ladder until the time
//! averages of [`SETTLING`](run::SETTLING) agree at two successive Δt, or until the next run's estimated CPU time
//! exceeds the line's cap (listed in the meta file as left out). Costs are CPU times of this
//! process (`/proc/self/stat`), which a machine shared with other jobs inflates less than wall
//! times.
//!
//! `--quick`: Argyris 4 × 2 at Δt = 1e-4 and 1e-5 s, 35 Hz, ζ = 1 %, 2 s, two replicas, into a
//! temporary directory; it checks the pipeline and the modal energy against `energy.elastic`.

mod options;
mod plan;
mod run;
mod write;

use options::plan_of;
use plan::{scene_of, Mesh, Plate, Setting};
use plate_impact_studies::cli::exit_code;
use plate_impact_studies::output::StudyDir;
use run::{estimates, run_setting, settled, Cost, Estimate, MeshModes};
use std::process::ExitCode;
use std::time::Instant;
use write::{meta, Tables};

fn main() -> ExitCode {
    exit_code(study())
}

fn study() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dir = StudyDir::from_args(&args, "modal_damping", "accuracy")?;
    let (plan, partial) = plan_of(&args, dir.quick)?;
    if args.iter().any(|a| a == "--plan") {
        plan.print();
        return Ok(());
    }
    let started = Instant::now();
    let mut tables = Tables::new();
    let mut left_out = Vec::new();
    let mut cache: Vec<(Plate, Mesh, MeshModes)> = Vec::new();
    for (i, line) in plan.lines.iter().enumerate() {
        let plate = line.forcing.plate;
        let first = Setting {
            forcing: line.forcing,
            zeta: line.zeta,
            mesh: line.mesh,
            dt: line.ladder[0],
        };
        if !cache.iter().any(|(p, m, _)| *p == plate && *m == line.mesh) {
            let modes = MeshModes::of(&scene_of(&first, &plan.overrides)?)?;
            tables.add_mesh(plate, line.mesh, &modes);
            cache.push((plate, line.mesh, modes));
        }
        let (_, _, modes) = cache
            .iter()
            .find(|(p, m, _)| *p == plate && *m == line.mesh)
            .expect("cached above");
        let mut previous: Option<(Vec<Estimate>, Cost)> = None;
        for &dt in &line.ladder {
            let s = Setting { dt, ..first };
            let steps = (plan.transient + plan.duration) / dt;
            // The CPU time per step falls as Δt falls (fewer bound checks per step), so the last
            // run's is an upper estimate.
            let estimate = previous
                .as_ref()
                .map_or(0.0, |(_, c)| c.set_up_cpu_s + steps * c.step_us * 1e-6);
            if estimate > line.max_run_cpu {
                let what = format!(
                    "{} ζ={} {} Δt ≤ {dt:e} s (estimated {estimate:.0} CPU s)",
                    s.forcing.label,
                    s.zeta,
                    s.mesh.name()
                );
                eprintln!("left out: {what}");
                left_out.push(what);
                break;
            }
            let (runs, cost) = run_setting(&plan, line.replicas, &s, modes)?;
            tables.add(&plan, line, &s, modes, &runs, &cost);
            tables.write(&dir, plan.lines.iter().any(|l| l.series))?;
            // Written after every run too, so that a study cut short records what it ran.
            let unfinished = meta(&plan, &args, started, &left_out, false);
            dir.write("modal_damping_meta.csv", &unfinished)?;
            eprintln!(
                "[{:>3}/{}] {:<17} ζ={:<6} {:<14} Δt={:<6e} ω_max·Δt={:<9.3} {:>7.1} s, {:>6.1} CPU s, \
                 {:.2} µs/step (study {:.0} s)",
                i + 1,
                plan.lines.len(),
                s.forcing.label,
                s.zeta,
                s.mesh.name(),
                s.dt,
                modes.omega_max * s.dt,
                cost.wall_s,
                cost.cpu_s,
                cost.step_us,
                started.elapsed().as_secs_f64()
            );
            let (now, _) = estimates(&plan, &s, &runs);
            let done = previous
                .as_ref()
                .is_some_and(|(before, _)| settled(before, &now, plan.settle_tolerance));
            previous = Some((now, cost));
            if done {
                break;
            }
        }
    }
    dir.write(
        "modal_damping_meta.csv",
        &meta(&plan, &args, started, &left_out, true),
    )?;
    if partial {
        eprintln!(
            "partial study done: concatenate its CSVs with the other parts', then run \
             `python -m plateimpact_tools.studies.modal_damping_plots DIR` on them"
        );
        return Ok(());
    }
    dir.plot("modal_damping_plots")?;
    dir.finish(dir.missing(&[
        "modal_damping.csv",
        "modal_damping_bands.csv",
        "modal_damping.md",
        "modal_damping_bands.png",
    ]))
}
