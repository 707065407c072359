//! The single-run modes of the restitution binary: one scene with every diagnostic (its JSON
//! summary, and with `--csv` its trajectory), and the timing of its steps for several e.

use super::watch::watch;
use super::Options;
use plate_impact::scene::Scene;
use plate_impact::scheme::{StepPath, Stepper};
use std::io::Write;
use std::time::Instant;

/// Runs the scene with every diagnostic and prints the JSON summary.
pub fn measure(options: &Options) -> Result<(), String> {
    let mut csv = match &options.csv {
        Some(path) => {
            let file = std::fs::File::create(path).map_err(|e| format!("{path}: {e}"))?;
            let mut out = std::io::BufWriter::new(file);
            writeln!(out, "t,corner1,energy_total").map_err(|e| e.to_string())?;
            Some(out)
        }
        None => None,
    };
    let (_, summary) = watch(&options.scene, |n, stepper| match csv.as_mut() {
        Some(out) if n % options.every == 0 => {
            let o = stepper.outputs();
            writeln!(
                out,
                "{},{:e},{:e}",
                stepper.time(),
                o.corner1,
                o.energy_total
            )
            .map_err(|e| e.to_string())
        }
        _ => Ok(()),
    })?;
    if let Some(mut out) = csv {
        out.flush().map_err(|e| e.to_string())?;
    }
    println!("{summary}");
    Ok(())
}

/// Times the scene's steps for each restitution, five runs each, and prints one line per e: the
/// median over the runs of the time per step, and of the mean time of each kind of step.
pub fn timing(scene: &Scene, restitutions: &[f64]) -> Result<(), String> {
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
