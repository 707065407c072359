//! Work-precision study: error against wall time for both elements, three scenes, meshes
//! from coarse to fine and Δt from 1e-3 to 1e-6 s, plus the paper's Table 1 case and clarabel on
//! every step as a second strategy.
//!
//! `cargo run --release -p plate_impact_studies --bin accuracy [-- --quick] [--out DIR]`
//!
//! The study in three steps: the plan (`plan.rs`: scenes, meshes, Δt levels and the cases they
//! make, one per simulation), the run (`run.rs`: the simulations) and the write (`write.rs`: the
//! CSVs of their results; then `python -m plateimpact_tools.studies.accuracy_plots`, the package
//! in `tools/` run with the Python of `scripts/python-env`: the plots and the tables of
//! `README.md`, whose prose is hand-written).
//!
//! Every run happens in this process, one after the other (no threads, so that the wall times,
//! measured with `Instant` around set-up and stepping, are not disturbed by each other). The output
//! directory (default `docs/accuracy`, with `--quick` a fresh temporary directory) receives
//! `runs.csv` (one row per run), `frequencies.csv`, `table1.csv`, `traces.csv` (the reference
//! corner trajectories), `reference_check.csv` and `meta.csv` (the plan, the command line and the
//! commit of the code that ran).
//!
//! Errors. The corner displacement u(Lx, 0, t) of each run is put on a common grid (every 1e-4 s,
//! piecewise-linear in time between the steps of runs with Δt > 1e-4 s) and compared with
//! - the scene's reference (finest Argyris mesh at the smallest Δt): `ref_*`, the total error;
//! - the same mesh at its smallest Δt: `dt_*`, the time error alone;
//! - the same element's finest mesh at the same Δt: `h_*`, the space error alone.
//!
//! `--quick` runs a small subset into a temporary directory and exits nonzero unless the observed
//! order in Δt of the contact-free case is within 0.2 of 2 and the whole pipeline (CSV, plots,
//! README) completes.

mod plan;
mod run;
mod write;

use plan::{cases, full_plan, quick_plan, Case, Plan};
use plate_impact::scene::QpChoice;
use plate_impact_studies::cli::exit_code;
use plate_impact_studies::element::element_name;
use plate_impact_studies::order::observed_order;
use plate_impact_studies::output::StudyDir;
use plate_impact_studies::revision::source_revision;
use run::{difference, Results};
use std::process::ExitCode;
use std::time::Instant;

fn main() -> ExitCode {
    exit_code(study())
}

/// Plan, run, write, then the quick mode's check of the contact-free orders.
fn study() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dir = StudyDir::from_args(&args, "accuracy", "accuracy")?;
    let revision = source_revision();
    let plan = if dir.quick { quick_plan() } else { full_plan() };
    let started = Instant::now();
    let frequencies = run::frequencies(&plan)?;
    dir.write("frequencies.csv", &write::frequencies_csv(&frequencies))?;
    let results = Results::new(&plan, run::run_cases(&plan, &cases(&plan))?);
    dir.write("runs.csv", &write::runs_csv(&results))?;
    dir.write("traces.csv", &write::traces_csv(&results))?;
    let checks = results.reference_checks()?;
    dir.write("reference_check.csv", &write::reference_check_csv(&checks))?;
    dir.write("table1.csv", &write::table1_csv(&run::table1(&plan)?))?;
    dir.write("paper_table1.csv", &write::paper_table1_csv(&plan))?;
    let total_s = started.elapsed().as_secs_f64();
    eprintln!("runs done in {total_s:.1} s; writing tables and plots");
    dir.write(
        "meta.csv",
        &write::meta(&results, &args, &revision, dir.quick, total_s),
    )?;
    dir.page("accuracy", "README.md")?;
    dir.plot("accuracy_plots")?;
    let mut failures = order_check(&results);
    failures.extend(dir.missing(&[
        "runs.csv",
        "frequencies.csv",
        "table1.csv",
        "paper_table1.csv",
        "traces.csv",
        "reference_check.csv",
        "meta.csv",
        "README.md",
        "work_precision.png",
        "convergence_dt.png",
        "convergence_h.png",
        "traces.png",
    ]));
    eprintln!(
        "study done in {:.1} s; output in {}",
        started.elapsed().as_secs_f64(),
        dir.path.display()
    );
    dir.finish(failures)
}

/// Contact-free orders in Δt (time error alone, paper mesh, over every Δt at least twice the
/// reference's). The smooth control case must be second order (docs/scheme.md §6); the release
/// from the static deflection excites every mode of the mesh, with amplitudes decaying only like
/// a power of the frequency, so its pre-asymptotic order is lower (about 1.3–1.5): asserted
/// above 1.2.
fn order_check(results: &Results) -> Vec<String> {
    let plan: &Plan = results.plan;
    let mut failures = Vec::new();
    for (scene, low, high) in [("free-smooth", 1.8, 2.2), ("free", 1.2, 2.2)] {
        for (element, mesh) in plan.paper_mesh {
            let dt_ref = results.min_dt(scene, element, mesh);
            let points: Vec<(f64, f64)> = results
                .runs
                .iter()
                .filter(|r| {
                    let c = &r.case;
                    c.scene == scene && c.element == element && c.mesh == mesh
                })
                .filter(|r| r.case.qp == QpChoice::Auto && r.case.dt >= 2.0 * dt_ref)
                .map(|r| {
                    let other = results
                        .fast(&Case {
                            dt: dt_ref,
                            ..r.case
                        })
                        .expect("ran");
                    (r.case.dt, difference(&r.trace, &other.trace).0)
                })
                .collect();
            let (steps, errors): (Vec<f64>, Vec<f64>) = points.iter().copied().unzip();
            let order = observed_order(&steps, &errors);
            eprintln!(
                "{scene}: order in Δt, {} {}×{}: {order:.3} (RMS corner error, {} levels)",
                element_name(element),
                mesh.0,
                mesh.1,
                points.len()
            );
            if !(low..=high).contains(&order) {
                failures.push(format!(
                    "{scene} {}: observed order {order:.3} outside [{low}, {high}]",
                    element_name(element)
                ));
            }
        }
    }
    failures
}
