//! Runs a scene and writes its trajectory as CSV.
//!
//! `cargo run --release --example scene -- <scene> [key=value ...] [--out FILE] [--every N]`
//!
//! `<scene>` is `default` or a file stem of `scenes/` (`forced`, `forced-30hz`, `forced-35hz`,
//! `energy`); overrides use the FMU variable names plus `stop_time` and `solver.qp`, e.g.
//! `mesh.element=fvs mesh.nx=14 mesh.ny=10 solver.time_step=1e-5 base.frequency=35`.
//! The CSV (header `t,corner1,corner2,edge_mid,energy_total,active,contact_force`, one row per
//! step, or every N-th with `--every N`, t = 0 included; numbers in shortest round-trip form, so
//! they are the exact f64 values) goes to stdout or FILE; stderr gets the wall time, the step count, how
//! many steps needed a QP and by which path, and µs per step.

use plate_impact::scene::Scene;
use plate_impact::scheme::Stepper;
use std::io::Write;
use std::process::ExitCode;
use std::time::Instant;

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

fn run() -> Result<(), String> {
    let mut args = std::env::args().skip(1);
    let name = args
        .next()
        .ok_or("usage: scene <scene> [key=value ...] [--out FILE]")?;
    let mut scene = Scene::named(&name).map_err(|e| e.to_string())?;
    let mut out_path = None;
    let mut every = 1u64;
    while let Some(arg) = args.next() {
        if arg == "--out" {
            out_path = Some(args.next().ok_or("--out needs a file name")?);
        } else if arg == "--every" {
            every = args
                .next()
                .and_then(|n| n.parse().ok())
                .filter(|&n| n > 0)
                .ok_or("--every needs a positive integer")?;
        } else {
            let (key, value) = arg
                .split_once('=')
                .ok_or_else(|| format!("expected key=value, got {arg}"))?;
            scene.set(key, value).map_err(|e| e.to_string())?;
        }
    }
    let mut out: Box<dyn Write> = match &out_path {
        Some(path) => Box::new(std::io::BufWriter::new(
            std::fs::File::create(path).map_err(|e| format!("{path}: {e}"))?,
        )),
        None => Box::new(std::io::BufWriter::new(std::io::stdout().lock())),
    };
    let setup = Instant::now();
    let mut stepper = Stepper::new(&scene, scene.builtin_base(0.0)).map_err(|e| e.to_string())?;
    let setup_time = setup.elapsed().as_secs_f64();
    let steps = (scene.stop_time / scene.solver.time_step).round() as u64;
    let write_row = |out: &mut dyn Write, stepper: &Stepper| -> Result<(), String> {
        let o = stepper.outputs();
        writeln!(
            out,
            "{},{:e},{:e},{:e},{:e},{},{:e}",
            stepper.time(),
            o.corner1,
            o.corner2,
            o.edge_mid,
            o.energy_total,
            o.active_nodes,
            o.contact_force
        )
        .map_err(|e| e.to_string())
    };
    writeln!(
        out,
        "t,corner1,corner2,edge_mid,energy_total,active,contact_force"
    )
    .map_err(|e| e.to_string())?;
    write_row(&mut out, &stepper)?;
    let mut paths = [0u64; 4];
    let mut stepping = 0.0;
    for n in 0..steps {
        let z = scene.builtin_base((n + 1) as f64 * scene.solver.time_step);
        let start = Instant::now();
        let report = stepper.step(z).map_err(|e| e.to_string())?;
        stepping += start.elapsed().as_secs_f64();
        paths[report.path as usize] += 1;
        if (n + 1) % every == 0 {
            write_row(&mut out, &stepper)?;
        }
    }
    out.flush().map_err(|e| e.to_string())?;
    let [free, active_set, clarabel, fallback] = paths;
    eprintln!(
        "scene {name}: {} backend, {} free dofs, {} constrained vertices, set-up {setup_time:.3} s",
        format!("{:?}", stepper.linear_backend()).to_lowercase(),
        stepper.free_dof_count(),
        stepper.constrained_count()
    );
    eprintln!(
        "steps {steps}, wall time {stepping:.3} s, {:.2} µs/step; contact-free steps {free}; steps needing a QP: {} (active set {active_set}, clarabel {clarabel}, clarabel fallback {fallback})",
        1e6 * stepping / steps.max(1) as f64,
        active_set + clarabel + fallback
    );
    Ok(())
}
