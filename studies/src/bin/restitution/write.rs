//! Writing the restitution study's CSVs: the header and the row of each, and the columns of a
//! run's summary ([`RUN_COLUMNS`]) that several of them share.

use plate_impact::element::ElementKind;
use plate_impact::scene::ImpactLaw;
use plate_impact_studies::element::element_name;
use std::fmt::Write as _;

/// The CSV name of a law.
pub fn law_name(law: ImpactLaw) -> &'static str {
    match law {
        ImpactLaw::Auto => "auto",
        ImpactLaw::Newton => "newton",
        ImpactLaw::Persistent => "persistent",
    }
}

/// The header of a run's row, and its values from [`Watch::summary`](super::watch::Watch::summary).
pub const RUN_COLUMNS: &str = "energy_first_J,energy_last_J,relative_change,worst_rise_J,\
contact_loss_J,penetration_m,turn_m,turn_closing_m,turn_other_m,fastest_arrival_m_s,held_m,\
hover_m,hover_steps,longest_hold,contact_vertex_steps,on_obstacle_vertex_steps,contact_steps,\
resolved_steps,resolves,largest_contact_work_J,work_scale_J";

/// A run's values under [`RUN_COLUMNS`], from its `Watch::summary` (watch.rs).
pub fn run_values(s: &serde_json::Value) -> String {
    let first = s["energy_first"].as_f64().unwrap_or(f64::NAN);
    let last = s["energy_last"].as_f64().unwrap_or(f64::NAN);
    let keys = [
        "worst_rise",
        "contact_loss",
        "penetration",
        "standoff",
        "turn_closing",
        "turn_other",
        "fastest_arrival",
        "held",
        "hover",
        "hover_steps",
        "longest_hold",
        "contact_vertex_steps",
        "on_obstacle_vertex_steps",
        "contact_steps",
        "resolved_steps",
        "resolves",
        "largest_contact_work",
        "work_scale",
    ];
    let rest: Vec<String> = keys.iter().map(|k| s[k].to_string()).collect();
    format!(
        "{first:e},{last:e},{:e},{}",
        (last / first - 1.0).abs(),
        rest.join(",")
    )
}

/// The header of `fmu_energy.csv`.
pub const FMU_ENERGY_HEADER: &str =
    "dt,obstacle,stop_s,energy_first_J,energy_last_J,relative_change,contact_loss_J\n";

/// A row of `fmu_energy.csv`: Δt, the obstacle, the horizon, E after the first step and at the
/// end (J), |E_end/E_first − 1| and the contact loss (J).
pub fn fmu_energy_row(csv: &mut String, dt: f64, obstacle: bool, stop: f64, values: [f64; 4]) {
    let [first, last, change, loss] = values;
    let row = format!("{dt:e},{obstacle},{stop},{first:e},{last:e},{change:e},{loss:e}");
    writeln!(csv, "{row}").expect("a String");
}

/// The header of `runs.csv`.
pub fn energy_runs_header() -> String {
    format!("law,e,dt,{RUN_COLUMNS}\n")
}

/// A row of `runs.csv`: the law, e, Δt and the run's [`run_values`].
pub fn energy_run_row(
    csv: &mut String,
    law: ImpactLaw,
    e: f64,
    dt: f64,
    summary: &serde_json::Value,
) {
    writeln!(csv, "{},{e},{dt:e},{}", law_name(law), run_values(summary)).expect("a String");
}

/// The header of `contact_loss.csv`.
pub fn contact_loss_header() -> String {
    format!("scene,law,{RUN_COLUMNS}\n")
}

/// A row of `contact_loss.csv`: the scene, the law and the run's [`run_values`].
pub fn contact_loss_row(csv: &mut String, name: &str, law: ImpactLaw, summary: &serde_json::Value) {
    writeln!(csv, "{name},{},{}", law_name(law), run_values(summary)).expect("a String");
}

/// The header of `forced.csv`.
pub const FORCED_HEADER: &str = "scene,law,quantity,mean,spread,first_window,last_window\n";

/// A row of `forced.csv`: a quantity's mean over the windows `xs`, its spread, and the first and
/// last window's value.
pub fn forced_row(
    csv: &mut String,
    (name, law, quantity): (&str, ImpactLaw, &str),
    mean: f64,
    spread: f64,
    xs: &[f64],
) {
    writeln!(
        csv,
        "{name},{},{quantity},{mean:e},{spread:e},{:e},{:e}",
        law_name(law),
        xs[0],
        xs[xs.len() - 1]
    )
    .expect("a String");
}

/// The header of `convergence.csv`.
pub fn convergence_header() -> String {
    format!(
        "series,element,nx,ny,dt,first_contact_s,energy_first_error_J,\
         corner_error_to_first_contact_m,corner_error_to_0.05s_m,corner_error_to_0.2s_m,\
         corner_error_to_1s_m,{RUN_COLUMNS}\n",
    )
}

/// A row of `convergence.csv`: the run of `setting` (series, element, nx, ny, Δt), its first
/// contact (s), its error of E(Δt) (J), its corner errors (m) and its [`run_values`] `summary`.
pub fn convergence_row(
    csv: &mut String,
    setting: &(&str, ElementKind, usize, usize, f64),
    first_contact: f64,
    energy_error: f64,
    e: [f64; 4],
    summary: &str,
) {
    let &(series, element, nx, ny, dt) = setting;
    writeln!(
        csv,
        "{series},{},{nx},{ny},{dt:e},{first_contact:e},{energy_error:e},{:e},{:e},{:e},{:e},{summary}",
        element_name(element),
        e[0],
        e[1],
        e[2],
        e[3],
    )
    .expect("a String");
}

/// The row of `convergence.csv` that compares the finest FVS mesh with the finest Argyris mesh
/// at Δt = `dt`: FVS's first contact, the gap in E(Δt), the corner errors and FVS's summary.
pub fn elements_row(
    csv: &mut String,
    dt: f64,
    first_contact: f64,
    gap: f64,
    e: [f64; 4],
    summary: &str,
) {
    writeln!(
        csv,
        "elements,fvs-argyris,,,{dt:e},{:e},{gap:e},{:e},{:e},{:e},{:e},{}",
        first_contact, e[0], e[1], e[2], e[3], summary
    )
    .expect("a String");
}
