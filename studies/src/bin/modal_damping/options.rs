//! The command line of the modal damping study: `--quick`, the committed plan, or a part of it
//! (see the study's documentation in main.rs).

use super::plan::{committed_plan, quick_plan, Line, Mesh, Plan, SCENES};
use plate_impact_studies::cli::flag_value;
use plate_impact_studies::element::parse_mesh_cells;

/// The meshes of `--mesh argyris:10x7,fvs:14x10`.
pub fn parse_meshes(list: &str) -> Result<Vec<Mesh>, String> {
    list.split(',')
        .map(|item| {
            let (element, nx, ny) = parse_mesh_cells(item)?;
            Ok(Mesh { element, nx, ny })
        })
        .collect()
}

/// A comma-separated list of positive numbers, for `flag`.
pub fn parse_numbers(flag: &str, list: &str) -> Result<Vec<f64>, String> {
    list.split(',')
        .map(|v| {
            v.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite() && *x > 0.0)
                .ok_or(format!("{flag} {v}: use numbers > 0"))
        })
        .collect()
}

/// The plan of the command line: `--quick`, the committed plan, or a part of it; and whether it
/// is a part.
pub fn plan_of(args: &[String], quick: bool) -> Result<(Plan, bool), String> {
    let value_of = |flag: &str| flag_value(args, flag);
    let number = |flag: &str| -> Result<Option<f64>, String> {
        value_of(flag)?
            .map(|v| parse_numbers(flag, &v).map(|x| x[0]))
            .transpose()
    };
    let mut plan = if quick {
        quick_plan()
    } else {
        committed_plan()
    };
    let mut partial = false;
    if let Some(list) = value_of("--part")? {
        let parts: Vec<&str> = list.split(',').collect();
        if let Some(bad) = parts
            .iter()
            .find(|p| !plan.lines.iter().any(|l| l.part == **p))
        {
            return Err(format!(
                "--part {bad}: use middle, third, ratios, fine or finedt"
            ));
        }
        plan.lines.retain(|l| parts.contains(&l.part));
        partial = true;
    }
    if let Some(list) = value_of("--scenes")? {
        let labels: Vec<&str> = list.split(',').collect();
        if let Some(bad) = labels
            .iter()
            .find(|l| !SCENES.iter().any(|s| s.label == **l))
        {
            return Err(format!(
                "--scenes {bad}: use labels among {:?}",
                SCENES.map(|s| s.label)
            ));
        }
        plan.lines.retain(|l| labels.contains(&l.forcing.label));
        partial = true;
    }
    if let Some(list) = value_of("--zeta")? {
        let zetas = parse_numbers("--zeta", &list)?;
        plan.lines.retain(|l| zetas.contains(&l.zeta));
        partial = true;
    }
    if let Some(list) = value_of("--keep-mesh")? {
        // The plan's lines on the named meshes only.
        let meshes = parse_meshes(&list)?;
        plan.lines.retain(|l| meshes.contains(&l.mesh));
        partial = true;
    }
    if let Some(list) = value_of("--mesh")? {
        // The named meshes replace the plan's, for every scene and ratio kept.
        let meshes = parse_meshes(&list)?;
        let mut kept: Vec<Line> = Vec::new();
        for line in &plan.lines {
            if !kept
                .iter()
                .any(|k| k.forcing.label == line.forcing.label && k.zeta == line.zeta)
            {
                kept.extend(meshes.iter().map(|&mesh| Line {
                    mesh,
                    ..line.clone()
                }));
            }
        }
        plan.lines = kept;
        partial = true;
    }
    if let Some(list) = value_of("--dt")? {
        let ladder = parse_numbers("--dt", &list)?;
        plan.lines
            .iter_mut()
            .for_each(|l| l.ladder = ladder.clone());
        partial = true;
    }
    if let Some(d) = number("--duration")? {
        plan.duration = d;
        partial = true;
    }
    if let Some(w) = number("--window")? {
        plan.window = w;
        partial = true;
    }
    if let Some(c) = number("--max-run-cpu")? {
        plan.lines.iter_mut().for_each(|l| l.max_run_cpu = c);
        partial = true;
    }
    if let Some(t) = value_of("--transient")? {
        plan.transient = t
            .parse()
            .map_err(|_| format!("--transient {t}: use seconds ≥ 0"))?;
        partial = true;
    }
    if let Some(r) = value_of("--replicas")? {
        let r = r
            .parse()
            .map_err(|_| format!("--replicas {r}: use a count ≥ 0"))?;
        plan.lines.iter_mut().for_each(|l| l.replicas = r);
        partial = true;
    }
    if args.iter().any(|a| a == "--no-settle") {
        plan.settle_tolerance = 0.0;
        partial = true;
    }
    if args.iter().any(|a| a == "--series") {
        plan.lines.iter_mut().for_each(|l| l.series = true);
    }
    plan.overrides = args.iter().filter(|a| a.contains('=')).cloned().collect();
    let partial = !quick && (partial || !plan.overrides.is_empty());
    Ok((plan, partial))
}
