//! What the impact laws do in a scene: the measurements behind docs/restitution/ (the single runs
//! are plotted by `plateimpact_tools.studies.restitution`), and the per-step cost of the laws.
//!
//! `cargo run --release -p plate_impact_studies --bin restitution -- <scene> [key=value ...] [--csv FILE] [--every N]`
//!
//! runs the scene (`default` or a file stem of `scenes/`; overrides as for the `scene` example,
//! e.g. `solver.restitution=0.5 solver.time_step=1e-5 solver.impact_law=newton`) and prints one
//! JSON object on stdout ([`Watch::summary`](watch::Watch::summary): energies, where contacts act, contact loss, QPs).
//! With `--csv FILE` the trajectory goes to FILE (`t,corner1,energy_total`, every N-th step with
//! `--every N`, n = 0 first).
//!
//! `cargo run --release -p plate_impact_studies --bin restitution -- --timing E1,E2,... <scene> [key=value ...]`
//!
//! instead times the scene's steps for each restitution E1, E2, … in one process (five runs each,
//! medians), split into steps proven contact-free by the screening, steps checked free in full,
//! and steps needing a QP; it prints one line per e.
//!
//! `cargo run --release -p plate_impact_studies --bin restitution -- --study [--quick] [--out DIR]`
//!
//! runs the study of docs/restitution/ and writes its CSVs there ([`study`]); `--quick` runs a
//! small subset into a temporary directory to check the pipeline.
//!
//! The study in modules: its cases (`plan.rs`), the simulations (`run.rs`; `fmu.rs` through the
//! FMU, `watch.rs` what a run observes) and the CSVs' headers and rows (`write.rs`); the single-run
//! and timing modes are `single.rs`.

mod fmu;
mod plan;
mod run;
mod single;
mod watch;
mod write;

use plate_impact::scene::Scene;
use plate_impact_studies::cli::{exit_code, positive_integer, set_override};
use plate_impact_studies::output::StudyDir;
use run::{convergence, energy_runs, fmu_energy, forced_statistics, undamped_scenes};
use single::{measure, timing};
use std::process::ExitCode;

const USAGE: &str = "usage: restitution [--timing E1,E2,...] <scene> [key=value ...] [--csv FILE] \
                     [--every N] | restitution --study [--quick] [--out DIR]";

fn main() -> ExitCode {
    exit_code(run())
}

/// The command line of a single run or a timing.
struct Options {
    scene: Scene,
    timing: Option<Vec<f64>>,
    csv: Option<String>,
    every: u64,
}

fn parse(args: &[String]) -> Result<Options, String> {
    let mut args = args.iter().cloned().peekable();
    let timing = if args.peek().map(String::as_str) == Some("--timing") {
        args.next();
        let list = args.next().ok_or("--timing needs a list E1,E2,...")?;
        let values: Result<Vec<f64>, _> = list.split(',').map(str::parse).collect();
        Some(values.map_err(|e| format!("--timing {list}: {e}"))?)
    } else {
        None
    };
    let name = args.next().ok_or(USAGE)?;
    let mut options = Options {
        scene: Scene::named(&name).map_err(|e| e.to_string())?,
        timing,
        csv: None,
        every: 1,
    };
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--csv" => options.csv = Some(args.next().ok_or("--csv needs a file name")?),
            "--every" => options.every = positive_integer("--every", args.next())?,
            _ => set_override(&mut options.scene, &arg, USAGE)?,
        }
    }
    Ok(options)
}

fn run() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("--study") {
        return study(&StudyDir::from_args(&args, "restitution", "restitution")?);
    }
    let options = parse(&args)?;
    match &options.timing {
        Some(restitutions) => timing(&options.scene, restitutions),
        None => measure(&options),
    }
}

/// The study of docs/restitution/, into `dir`:
/// * `fmu_energy.csv`: the `energy` scene at e = 1 through the FMU at four Δt ([`fmu_energy`]);
/// * `runs.csv`: the `energy` scene under each law against e and Δt ([`energy_runs`]);
/// * `contact_loss.csv`: every shipped scene without damping at e = 1 ([`undamped_scenes`]);
/// * `forced.csv`: the forced scenes' statistics at e = 1 under both laws ([`forced_statistics`]);
/// * `convergence.csv`: the `energy` scene at e = 1 against Δt and mesh ([`convergence`]).
fn study(dir: &StudyDir) -> Result<(), String> {
    let files = [
        ("fmu_energy.csv", fmu_energy(dir.quick)?),
        ("runs.csv", energy_runs(dir.quick)?),
        ("contact_loss.csv", undamped_scenes(dir.quick)?),
        ("forced.csv", forced_statistics(dir.quick)?),
        ("convergence.csv", convergence(dir.quick)?),
    ];
    for (name, text) in &files {
        dir.write(name, text)?;
    }
    let names: Vec<&str> = files.iter().map(|(name, _)| *name).collect();
    println!("wrote {} into {}", names.join(", "), dir.path.display());
    dir.finish(dir.missing(&names))
}
