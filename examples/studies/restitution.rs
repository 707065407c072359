//! What Newton's impact law does in a scene: the measurements behind docs/restitution/ (run by
//! `plateimpact_tools.studies.restitution`), and the per-step cost of the law.
//!
//! `cargo run --release --example restitution -- <scene> [key=value ...] [--csv FILE] [--every N]`
//!
//! runs the scene (`default` or a file stem of `scenes/`; overrides as for the `scene` example,
//! e.g. `solver.restitution=0.5 solver.time_step=1e-5 solver.impact_law=newton`) and prints one
//! JSON object on stdout:
//! * `energy_first`, `energy_last`, `energy_max` (J): E_{n+½} after the first step, after the last,
//!   and its largest value after the first step; `worst_rise` (J): the largest E_{n+½} − E_{n−½};
//! * `penetration` (m): how far any constrained vertex went past an obstacle at any step (≤ 0: it
//!   never did; then minus the closest approach);
//! * `standoff` (m): the largest height above its obstacle at which a vertex that carries a contact
//!   force turns (the nearer of u_n and u_{n+1} to the obstacle): Newton's law turns a vertex at
//!   u_n, at most |v_{n−½}|·Δt before the obstacle; 0 under the position law, whose contacts sit on
//!   the obstacle;
//! * `contact_steps`: steps that needed a QP.
//!
//! With `--csv FILE` the trajectory goes to FILE (`t,corner1,energy_total`, every N-th step with
//! `--every N`, n = 0 first).
//!
//! `cargo run --release --example restitution -- --timing E1,E2,... <scene> [key=value ...]`
//!
//! instead times the scene's steps for each restitution E1, E2, … in one process (five runs each,
//! medians), split into steps proven contact-free by the screening, steps checked free in full,
//! and steps needing a QP; it prints one line per e.

#[path = "../common/mod.rs"]
mod common;

use common::{exit_code, positive_integer, set_override};
use plate_impact::scene::Scene;
use plate_impact::scheme::{StepPath, Stepper};
use serde_json::json;
use std::io::Write;
use std::process::ExitCode;
use std::time::Instant;

const USAGE: &str =
    "usage: restitution [--timing E1,E2,...] <scene> [key=value ...] [--csv FILE] [--every N]";

fn main() -> ExitCode {
    exit_code(run())
}

/// The command line.
struct Options {
    scene: Scene,
    timing: Option<Vec<f64>>,
    csv: Option<String>,
    every: u64,
}

fn parse() -> Result<Options, String> {
    let mut args = std::env::args().skip(1).peekable();
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
    let options = parse()?;
    match &options.timing {
        Some(restitutions) => timing(&options.scene, restitutions),
        None => measure(&options),
    }
}

/// Runs the scene with every diagnostic and prints the JSON summary.
fn measure(options: &Options) -> Result<(), String> {
    let scene = &options.scene;
    let dt = scene.solver.time_step;
    let steps = (scene.stop_time / dt).round() as u64;
    let mut stepper = Stepper::new(scene, scene.builtin_base(0.0)).map_err(|e| e.to_string())?;
    let mut csv = match &options.csv {
        Some(path) => {
            let file = std::fs::File::create(path).map_err(|e| format!("{path}: {e}"))?;
            let mut out = std::io::BufWriter::new(file);
            writeln!(out, "t,corner1,energy_total").map_err(|e| e.to_string())?;
            Some(out)
        }
        None => None,
    };
    let (lower, upper) = (scene.lower_obstacle(), scene.upper_obstacle());
    // Signed distance past the obstacles: > 0 inside an obstacle.
    let past = |u: f64| {
        let below = lower.map_or(f64::NEG_INFINITY, |g| g - u);
        let above = upper.map_or(f64::NEG_INFINITY, |g| u - g);
        below.max(above)
    };
    let (mut penetration, mut standoff) = (f64::NEG_INFINITY, 0.0f64);
    let (mut energy_first, mut energy_max, mut worst_rise) =
        (0.0, f64::NEG_INFINITY, f64::NEG_INFINITY);
    let mut energy = 0.0;
    let mut contact_steps = 0u64;
    let mut current = stepper.constrained_displacements();
    for n in 0..=steps {
        if n > 0 {
            let report = stepper
                .step(scene.builtin_base(n as f64 * dt))
                .map_err(|e| e.to_string())?;
            contact_steps += u64::from(report.path != StepPath::Unconstrained);
            let next = stepper.constrained_displacements();
            for ((&u, &u_before), &f) in next.iter().zip(&current).zip(stepper.contact_forces()) {
                penetration = penetration.max(past(u));
                if f != 0.0 {
                    // Where the vertex turned: the nearer of its two levels to the obstacle.
                    standoff = standoff.max(-past(u).max(past(u_before)));
                }
            }
            current = next;
            let new_energy = stepper.outputs().energy_total;
            if n == 1 {
                energy_first = new_energy;
            } else {
                worst_rise = f64::max(worst_rise, new_energy - energy);
            }
            energy = new_energy;
            energy_max = f64::max(energy_max, energy);
        }
        if let Some(out) = csv.as_mut() {
            if n % options.every == 0 {
                let o = stepper.outputs();
                writeln!(
                    out,
                    "{},{:e},{:e}",
                    stepper.time(),
                    o.corner1,
                    o.energy_total
                )
                .map_err(|e| e.to_string())?;
            }
        }
    }
    if let Some(mut out) = csv {
        out.flush().map_err(|e| e.to_string())?;
    }
    let summary = json!({
        "restitution": scene.solver.restitution,
        "impact_law": scene.solver.impact_law,
        "time_step": dt,
        "steps": steps,
        "energy_first": energy_first,
        "energy_last": energy,
        "energy_max": energy_max,
        "worst_rise": worst_rise,
        "penetration": penetration,
        "standoff": standoff,
        "contact_steps": contact_steps,
    });
    println!("{summary}");
    Ok(())
}

/// Times the scene's steps for each restitution, five runs each, and prints one line per e: the
/// median over the runs of the time per step, and of the mean time of each kind of step.
fn timing(scene: &Scene, restitutions: &[f64]) -> Result<(), String> {
    const RUNS: usize = 5;
    let dt = scene.solver.time_step;
    let steps = (scene.stop_time / dt).round() as u64;
    let median = |mut xs: Vec<f64>| {
        xs.sort_by(f64::total_cmp);
        xs[xs.len() / 2]
    };
    for &e in restitutions {
        let mut s = scene.clone();
        s.set("solver.restitution", &e.to_string())
            .map_err(|e| e.to_string())?;
        // Per run: the time per step, and the count and total time of the steps screened free,
        // checked free and needing a QP (the counts are the same in every run).
        let mut runs = Vec::new();
        for _ in 0..RUNS {
            let mut stepper = Stepper::new(&s, s.builtin_base(0.0)).map_err(|e| e.to_string())?;
            let mut kinds = [(0u64, 0.0f64); 3];
            let clock = Instant::now();
            for n in 1..=steps {
                let z = s.builtin_base(n as f64 * dt);
                let t = Instant::now();
                let report = stepper.step(z).map_err(|e| e.to_string())?;
                let kind = match (report.path, report.bounds_evaluated) {
                    (StepPath::Unconstrained, false) => 0,
                    (StepPath::Unconstrained, true) => 1,
                    _ => 2,
                };
                kinds[kind].0 += 1;
                kinds[kind].1 += t.elapsed().as_secs_f64();
            }
            runs.push((clock.elapsed().as_secs_f64() / steps as f64, kinds));
        }
        let per_step = median(runs.iter().map(|r| r.0).collect());
        let kind = |k: usize| {
            let count = runs[0].1[k].0;
            let mean = median(
                runs.iter()
                    .map(|r| 1e6 * r.1[k].1 / count.max(1) as f64)
                    .collect(),
            );
            (count, mean)
        };
        let [(screened, t0), (checked, t1), (qp, t2)] = [kind(0), kind(1), kind(2)];
        println!(
            "e = {e}: {:.2} µs/step over {steps} steps (median of {RUNS} runs); screened free \
             {screened} at {t0:.2} µs, checked free {checked} at {t1:.2} µs, QP {qp} at {t2:.2} µs",
            1e6 * per_step
        );
    }
    Ok(())
}
