//! Writing the statistics (or damping) study's CSVs: a row per run and statistic
//! (`statistics.csv`, `damping.csv`), the meshes' ω₁ and ω_max, the replica check and the meta file.

use super::options::Options;
use super::plan::{Mesh, Plan, Run, SceneKind, ZETA1};
use super::run::{Outcome, Stat, ENERGY_PERTURBATION, FORCED_PERTURBATION_PA};
use plate_impact_studies::element::element_name;
use plate_impact_studies::recorder::SAMPLE_INTERVAL;
use plate_impact_studies::sample::mean_std;
use std::fmt::Write as _;

/// The header of `meshes.csv`.
pub const MESHES_HEADER: &str = "element,nx,ny,free_dofs,omega1_rad_s,omega_max_rad_s\n";

/// A row of `meshes.csv`: ω₁, ω_max (rad/s) and the free dofs of `mesh`.
pub fn mesh_row(csv: &mut String, mesh: Mesh, w1: f64, wmax: f64, dofs: usize) {
    let name = element_name(mesh.element);
    writeln!(
        csv,
        "{name},{},{},{dofs},{w1:.6},{wmax:.6e}",
        mesh.nx, mesh.ny
    )
    .expect("write to string");
}

/// The header of the study's CSV; with damping models (the damping study), a `damping` column
/// after the scene's.
pub fn header(with_damping: bool) -> &'static str {
    if with_damping {
        "quantity,scene,damping,element,nx,ny,dt,omega_max_dt,value,spread,wall_s,windows,zeta_hf,part\n"
    } else {
        "quantity,scene,element,nx,ny,dt,omega_max_dt,value,spread,wall_s,windows,zeta_hf,part\n"
    }
}

/// One CSV row per statistic of `outcome`; `windows` is empty for the `energy` scene.
pub fn rows(csv: &mut String, plan: &Plan, run: &Run, omega_max: f64, outcome: &Outcome) {
    let scene = match plan.damping_of(run) {
        Some(model) => format!("{},{}", run.scene.label(), model.label),
        None if plan.dampings.is_empty() => run.scene.label().to_string(),
        None => format!("{},", run.scene.label()),
    };
    let windows = match run.scene {
        SceneKind::Forced(_) => run.windows.to_string(),
        SceneKind::Energy => String::new(),
    };
    let m = run.mesh;
    for s in &outcome.stats {
        writeln!(
            csv,
            "{},{scene},{},{},{},{:e},{:.6e},{:.10e},{:.4e},{:.6},{windows},{:.6e},{}",
            s.quantity,
            element_name(m.element),
            m.nx,
            m.ny,
            run.dt,
            omega_max * run.dt,
            s.value,
            s.spread,
            outcome.wall_s,
            outcome.zeta_hf,
            run.part.label()
        )
        .expect("write to string");
    }
}

/// The rows of `replica_check.csv` for `run`: each statistic's window estimate of the spread
/// against the replicas' standard deviation.
pub fn replica_rows(csv: &mut String, run: &Run, stats: &[Vec<Stat>]) {
    let m = run.mesh;
    for (q, s) in stats[0].iter().enumerate() {
        let values: Vec<f64> = stats.iter().map(|r| r[q].value).collect();
        let (mean, std) = mean_std(&values);
        writeln!(
            csv,
            "{},{},{},{},{:e},{},{:.10e},{:.4e},{mean:.10e},{std:.4e},{}",
            run.scene.label(),
            element_name(m.element),
            m.nx,
            m.ny,
            run.dt,
            s.quantity,
            s.value,
            s.spread,
            stats.len()
        )
        .expect("write to string");
    }
}

/// The meta file: the plan's settings, the command line and the commit of the code that ran.
pub fn meta(
    plan: &Plan,
    options: &Options,
    args: &[String],
    revision: &str,
    alpha: f64,
    omega1: f64,
    total_s: f64,
) -> String {
    let mut meta = String::from("key,value\n");
    let windows = plan
        .runs
        .iter()
        .find(|r| matches!(r.scene, SceneKind::Forced(_)))
        .map_or(8, |r| r.windows);
    for (k, v) in [
        ("quick", options.quick.to_string()),
        ("plan", plan.name.to_string()),
        ("runs", plan.runs.len().to_string()),
        ("command", args.join(" ")),
        ("commit", revision.to_string()),
        ("total_s", format!("{total_s:.1}")),
        ("zeta1", ZETA1.to_string()),
        ("alpha", format!("{alpha:.6}")),
        ("omega1_reference", format!("{omega1:.6}")),
        ("transient_s", plan.transient.to_string()),
        ("windows", windows.to_string()),
        ("window_target_s", plan.window_target.to_string()),
        ("replicas", plan.replicas.to_string()),
        ("energy_perturbation", ENERGY_PERTURBATION.to_string()),
        ("forced_perturbation_pa", FORCED_PERTURBATION_PA.to_string()),
        ("sample_interval_s", SAMPLE_INTERVAL.to_string()),
        ("overrides", options.overrides.join(" ")),
    ] {
        writeln!(meta, "{k},{}", csv_field(&v)).expect("write to string");
    }
    for d in &plan.dampings {
        writeln!(meta, "damping {},{}", d.label, d.arguments().join(" ")).expect("write to string");
    }
    meta
}

/// `value` as a CSV field: quoted (with its quotes doubled) when it holds a comma or a quote.
fn csv_field(value: &str) -> String {
    if value.contains([',', '"']) {
        format!("\"{}\"", value.replace('"', "\"\""))
    } else {
        value.to_string()
    }
}
