//! Writing the accuracy study's CSVs: every run with its errors (`runs.csv`), the reference traces
//! (`traces.csv`), the natural frequencies, the reference's check, the paper's Table 1 case beside
//! the paper's own (`table1.csv`, `paper_table1.csv`) and `meta.csv`.

use super::plan::{strategy_name, Case, Plan, GRID, PAPER_TABLE1, REFERENCE_HZ};
use super::run::{difference, MeshFrequencies, ReferenceCheck, Results, Table1Run};
use plate_impact::element::ElementKind;
use plate_impact::scene::QpChoice;
use plate_impact_studies::element::element_name;
use std::fmt::Write as _;

/// `frequencies.csv`: the lowest six natural frequencies of each mesh beside the converged ones.
pub fn frequencies_csv(meshes: &[MeshFrequencies]) -> String {
    let mut csv = String::from("element,nx,ny,h,free_dofs,mode,frequency_hz,reference_hz\n");
    for m in meshes {
        for (k, f) in m.hz.iter().enumerate() {
            writeln!(
                csv,
                "{},{},{},{},{},{},{f},{}",
                element_name(m.element),
                m.mesh.0,
                m.mesh.1,
                m.h,
                m.free_dofs,
                k + 1,
                REFERENCE_HZ[k]
            )
            .expect("write to string");
        }
    }
    csv
}

/// `runs.csv`: every run with its errors against the reference (`ref_*`), the same mesh at
/// its smallest Δt (`dt_*`), the same element's finest mesh at the same Δt (`h_*`), its
/// energy error, the clarabel runs' difference from the fast ones, and the error up to the
/// reference's first contact (`pre_*`).
pub fn runs_csv(results: &Results) -> String {
    let mut csv = String::from(
            "scene,element,nx,ny,h,free_dofs,dt,strategy,steps,qp_steps,impacts,setup_s,stepping_s,wall_s,\
             ref_rms,ref_max,dt_rms,dt_max,h_rms,h_max,energy_end,energy_rel_err,diff_vs_fast,\
             first_contact_s,pre_rms,pre_max\n",
        );
    for r in &results.runs {
        let c = &r.case;
        let rf = results.reference(c.scene);
        let (ref_rms, ref_max) = difference(&r.trace, &rf.trace);
        let dt_ref = results.min_dt(c.scene, c.element, c.mesh);
        let dt_err = (c.dt != dt_ref).then(|| {
            let other = results.fast(&Case { dt: dt_ref, ..*c }).expect("ran");
            difference(&r.trace, &other.trace)
        });
        let fine = results.plan.finest(c.element);
        let h_err = (c.mesh != fine)
            .then(|| results.fast(&Case { mesh: fine, ..*c }))
            .flatten()
            .map(|other| difference(&r.trace, &other.trace));
        // Before the reference's first contact: the error of the motion up to the first impact.
        let pre = rf.first_contact.map(|t| {
            let k = (t / GRID).floor() as usize + 1;
            difference(&r.trace[..k], &rf.trace[..k])
        });
        let diff_vs_fast = (c.qp == QpChoice::Clarabel)
            .then(|| difference(&r.trace, &results.fast(c).expect("ran").trace).1);
        writeln!(
                csv,
                "{},{},{},{},{},{},{:e},{},{},{},{},{:.6},{:.6},{:.6},{ref_rms:e},{ref_max:e},{},{},{},{},{:e},{:e},{},{},{},{}",
                c.scene,
                element_name(c.element),
                c.mesh.0,
                c.mesh.1,
                0.4 / c.mesh.0 as f64,
                r.free_dofs,
                c.dt,
                strategy_name(c.qp),
                r.steps,
                r.qp_steps,
                r.impacts,
                r.setup_s,
                r.stepping_s,
                r.setup_s + r.stepping_s,
                optional(dt_err.map(|e| e.0)),
                optional(dt_err.map(|e| e.1)),
                optional(h_err.map(|e| e.0)),
                optional(h_err.map(|e| e.1)),
                r.energy_end,
                ((r.energy_end - rf.energy_end) / rf.energy_end).abs(),
                optional(diff_vs_fast),
                optional(r.first_contact),
                optional(pre.map(|e| e.0)),
                optional(pre.map(|e| e.1)),
            )
            .expect("write to string");
    }
    csv
}

/// `traces.csv`: the reference corner trajectories on the common grid.
pub fn traces_csv(results: &Results) -> String {
    let mut traces = String::from("t");
    for &scene in &results.plan.scenes {
        write!(traces, ",{scene}").expect("write to string");
    }
    traces.push('\n');
    for k in 0..results.reference(results.plan.scenes[0]).trace.len() {
        write!(traces, "{}", k as f64 * GRID).expect("write to string");
        for &scene in &results.plan.scenes {
            write!(traces, ",{:e}", results.reference(scene).trace[k]).expect("write to string");
        }
        traces.push('\n');
    }
    traces
}

/// `reference_check.csv`: each scene's [`ReferenceCheck`].
pub fn reference_check_csv(checks: &[ReferenceCheck]) -> String {
    let mut check = String::from(
        "scene,check_wall_s,time_dt,time_rms,time_max,space_rms,space_max,fvs_rms,fvs_max\n",
    );
    for c in checks {
        let (scene, wall, twice, space, other) = (c.scene, c.wall, c.time, c.space, c.fvs);
        writeln!(
            check,
            "{scene},{wall:.6},{},{},{},{:e},{:e},{},{}",
            optional(twice.map(|e| e.0)),
            optional(twice.map(|e| e.1 .0)),
            optional(twice.map(|e| e.1 .1)),
            space.0,
            space.1,
            optional(other.map(|e| e.0)),
            optional(other.map(|e| e.1)),
        )
        .expect("write to string");
    }
    check
}

/// A number in the CSV's `{:e}` form, or an empty cell.
fn optional(x: Option<f64>) -> String {
    x.map(|x| format!("{x:e}")).unwrap_or_default()
}

/// `table1.csv`: the runs of the paper's Table 1 case.
pub fn table1_csv(runs: &[Table1Run]) -> String {
    let mut table1 = String::from("element,nx,ny,dt,strategy,steps,qp_steps,wall_s\n");
    for r in runs {
        let (name, strategy) = (element_name(r.element), strategy_name(r.qp));
        writeln!(
            table1,
            "{name},{},{},{:e},{strategy},{},{},{:.6}",
            r.mesh.0, r.mesh.1, r.dt, r.steps, r.qp_steps, r.wall
        )
        .expect("write to string");
    }
    table1
}

/// `paper_table1.csv`: [`PAPER_TABLE1`] on the plan's paper meshes.
pub fn paper_table1_csv(plan: &Plan) -> String {
    let mut csv = String::from("element,nx,ny,dt,cpu_s\n");
    for (element, dt, cpu_s) in PAPER_TABLE1 {
        let (nx, ny) = plan.paper(element);
        let name = element_name(element);
        csv.push_str(&format!("{name},{nx},{ny},{dt:e},{cpu_s}\n"));
    }
    csv
}

/// `meta.csv`: what the write step needs to describe the study, the command line and the commit
/// of the code that ran.
pub fn meta(
    results: &Results,
    args: &[String],
    revision: &str,
    quick: bool,
    total_s: f64,
) -> String {
    let plan = results.plan;
    let list = |xs: &[f64]| {
        let items: Vec<String> = xs.iter().map(|x| format!("{x:e}")).collect();
        items.join(" ")
    };
    let meshes = |element: ElementKind| {
        let (_, meshes) = plan
            .meshes
            .iter()
            .find(|(e, _)| *e == element)
            .expect("element");
        let names: Vec<String> = meshes.iter().map(|(nx, ny)| format!("{nx}×{ny}")).collect();
        names.join(" ")
    };
    let cells = |(nx, ny): (usize, usize)| format!("{nx}x{ny}");
    let reference = results.reference(plan.scenes[0]).case;
    let impacts: Vec<String> = plan
        .scenes
        .iter()
        .map(|&scene| format!("{scene} {} impacts", results.reference(scene).impacts))
        .collect();
    let mut meta = String::from("key,value\n");
    for (k, v) in [
        ("quick", quick.to_string()),
        ("command", args.join(" ")),
        ("commit", revision.to_string()),
        ("horizon", plan.horizon.to_string()),
        ("total_s", format!("{total_s:.1}")),
        ("meshes_argyris", meshes(ElementKind::Argyris)),
        ("meshes_fvs", meshes(ElementKind::Fvs)),
        ("dt_grid", list(&plan.dt_grid)),
        ("dt_sweep", list(&plan.dt_sweep)),
        (
            "paper_mesh_argyris",
            cells(plan.paper(ElementKind::Argyris)),
        ),
        ("paper_mesh_fvs", cells(plan.paper(ElementKind::Fvs))),
        (
            "reference",
            format!(
                "Argyris {}×{} at Δt = {:e} s",
                reference.mesh.0, reference.mesh.1, reference.dt
            ),
        ),
        (
            "check_mesh",
            format!("{}×{}", plan.check_mesh.0, plan.check_mesh.1),
        ),
        ("impacts", impacts.join("; ")),
    ] {
        writeln!(meta, "{k},\"{}\"", v.replace('"', "\"\"")).expect("write to string");
    }
    meta
}
