//! Runs a scene and writes its trajectory as CSV, and optionally the whole displacement field.
//!
//! `cargo run --release --example scene -- <scene> [key=value ...] [--out FILE] [--every N]
//! [--from T] [--field FILE]`
//!
//! `<scene>` is `default` or a file stem of `scenes/` (`forced`, `forced-30hz`, `forced-35hz`,
//! `energy`); overrides use the FMU variable names plus `stop_time` and `solver.qp`, e.g.
//! `mesh.element=fvs mesh.nx=14 mesh.ny=10 solver.time_step=1e-5 base.frequency=35`.
//!
//! Records are taken at the steps n that are multiples of N (`--every N`, default 1; n = 0 is the
//! initial state) and have t_n ≥ T (`--from T`, default 0). Numbers are in shortest round-trip
//! form, so they are the exact f64 values.
//! * The CSV (header `t,corner1,corner2,edge_mid,energy_total,active,contact_force`, one row per
//!   record) goes to FILE with `--out`, else to stdout unless `--field` is given.
//! * `--field FILE` writes JSON for animations (`examples/plate_animation.py`): the mesh
//!   (`vertices` [x, y] in m, `cells` as vertex ids, `clamped` vertex ids on x = 0), the obstacle
//!   levels (null when absent), and one frame per record with `t` (s), `base` z(t_n) (m),
//!   `energy` (J), `u` the displacement u_n at every vertex (m; clamp vertices carry z(t_n)) and
//!   `contact` the vertices whose contact force is nonzero. The values at the vertices off the
//!   clamp are those the obstacle constraint acts on, so the scene needs at least one obstacle.
//!
//! stderr gets the wall time, the step count, how many steps needed a QP and by which path, and
//! µs per step.

mod common;

use common::{exit_code, positive_integer, set_override};
use plate_impact::scene::Scene;
use plate_impact::scheme::Stepper;
use plate_impact::system::PlateSystem;
use serde_json::{json, Value};
use std::io::Write;
use std::process::ExitCode;
use std::time::Instant;

const USAGE: &str =
    "usage: scene <scene> [key=value ...] [--out FILE] [--every N] [--from T] [--field FILE]";

fn main() -> ExitCode {
    exit_code(run())
}

/// The command line.
struct Options {
    name: String,
    scene: Scene,
    out: Option<String>,
    field: Option<String>,
    every: u64,
    from: f64,
}

fn parse() -> Result<Options, String> {
    let mut args = std::env::args().skip(1);
    let name = args.next().ok_or(USAGE)?;
    let mut options = Options {
        scene: Scene::named(&name).map_err(|e| e.to_string())?,
        name,
        out: None,
        field: None,
        every: 1,
        from: 0.0,
    };
    while let Some(arg) = args.next() {
        let mut value = |what: &str| args.next().ok_or(format!("{arg} needs {what}"));
        match arg.as_str() {
            "--out" => options.out = Some(value("a file name")?),
            "--field" => options.field = Some(value("a file name")?),
            "--every" => options.every = positive_integer("--every", args.next())?,
            "--from" => {
                options.from = value("a time in s")?
                    .parse()
                    .ok()
                    .filter(|t: &f64| t.is_finite() && *t >= 0.0)
                    .ok_or("--from needs a time ≥ 0 in s")?
            }
            _ => set_override(&mut options.scene, &arg, USAGE)?,
        }
    }
    Ok(options)
}

/// The displacement at every mesh vertex, composed from the library's public pieces: the
/// stepper's values at the obstacle-constrained vertices (every vertex off the clamp) and the
/// base displacement at the clamp vertices.
struct VertexField {
    /// Mesh vertex of each obstacle-constrained value, in the stepper's order.
    constrained_vertex: Vec<usize>,
    clamped: Vec<usize>,
    /// The JSON header: mesh and obstacles.
    header: Value,
    frames: Vec<Value>,
}

impl VertexField {
    fn new(scene: &Scene, plate: &PlateSystem) -> Result<VertexField, String> {
        let disc = &plate.disc;
        let vertex_count = disc.mesh.vertices.len();
        // The constrained indices point into the free dofs; each is the value dof of one vertex.
        let mut vertex_of_dof = vec![None; disc.dof_count];
        for v in 0..vertex_count {
            vertex_of_dof[disc.value_dof(v)] = Some(v);
        }
        let constrained_vertex = plate
            .constrained
            .iter()
            .map(|&k| vertex_of_dof[plate.free[k]].expect("constrained dofs are value dofs"))
            .collect::<Vec<_>>();
        let clamped = disc.clamped_vertices();
        if scene.lower_obstacle().is_none() && scene.upper_obstacle().is_none() {
            return Err("--field needs an obstacle (obstacle.lower_enabled or obstacle.upper_enabled = true): the library reports the field at the vertices the obstacles constrain".into());
        }
        if constrained_vertex.len() + clamped.len() != vertex_count {
            return Err(format!(
                "{} constrained and {} clamp vertices do not cover the {vertex_count} mesh vertices",
                constrained_vertex.len(),
                clamped.len()
            ));
        }
        let header = json!({
            "element": format!("{:?}", scene.mesh.element).to_lowercase(),
            "length": scene.plate.length,
            "width": scene.plate.width,
            "time_step": scene.solver.time_step,
            "base_amplitude": scene.base.amplitude,
            "base_frequency": scene.base.frequency,
            "lower": scene.lower_obstacle(),
            "upper": scene.upper_obstacle(),
            "vertices": disc.mesh.vertices,
            "cells": disc.mesh.cells,
            "clamped": clamped,
        });
        Ok(VertexField {
            constrained_vertex,
            clamped,
            header,
            frames: Vec::new(),
        })
    }

    /// Records u_n at every vertex, given the base displacement z(t_n).
    fn record(&mut self, stepper: &Stepper, base: f64) {
        let mut u = vec![0.0; self.constrained_vertex.len() + self.clamped.len()];
        for &v in &self.clamped {
            u[v] = base;
        }
        for (&v, value) in self
            .constrained_vertex
            .iter()
            .zip(stepper.constrained_displacements())
        {
            u[v] = value;
        }
        let contact: Vec<usize> = self
            .constrained_vertex
            .iter()
            .zip(stepper.contact_forces())
            .filter(|(_, &f)| f != 0.0)
            .map(|(&v, _)| v)
            .collect();
        self.frames.push(json!({
            "t": stepper.time(),
            "base": base,
            "energy": stepper.outputs().energy_total,
            "u": u,
            "contact": contact,
        }));
    }

    fn write(mut self, path: &str) -> Result<(), String> {
        self.header["frames"] = Value::Array(self.frames);
        let file = std::fs::File::create(path).map_err(|e| format!("{path}: {e}"))?;
        let mut out = std::io::BufWriter::new(file);
        serde_json::to_writer(&mut out, &self.header).map_err(|e| format!("{path}: {e}"))?;
        out.flush().map_err(|e| format!("{path}: {e}"))
    }
}

fn write_row(out: &mut dyn Write, stepper: &Stepper) -> Result<(), String> {
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
}

fn run() -> Result<(), String> {
    let options = parse()?;
    let scene = &options.scene;
    let mut csv: Option<Box<dyn Write>> = match (&options.out, &options.field) {
        (Some(path), _) => Some(Box::new(std::io::BufWriter::new(
            std::fs::File::create(path).map_err(|e| format!("{path}: {e}"))?,
        ))),
        (None, None) => Some(Box::new(std::io::BufWriter::new(std::io::stdout().lock()))),
        (None, Some(_)) => None,
    };
    let setup = Instant::now();
    let plate = PlateSystem::new(scene).map_err(|e| e.to_string())?;
    let mut stepper =
        Stepper::from_system(scene, &plate, scene.builtin_base(0.0)).map_err(|e| e.to_string())?;
    let setup_time = setup.elapsed().as_secs_f64();
    let mut field = match &options.field {
        Some(_) => Some(VertexField::new(scene, &plate)?),
        None => None,
    };
    if let Some(out) = csv.as_mut() {
        writeln!(
            out,
            "t,corner1,corner2,edge_mid,energy_total,active,contact_force"
        )
        .map_err(|e| e.to_string())?;
    }
    let dt = scene.solver.time_step;
    let steps = (scene.stop_time / dt).round() as u64;
    // Record at step n when n is a multiple of N and t_n ≥ T (half a step of slack for round-off).
    let mut record = |stepper: &Stepper, base: f64| -> Result<(), String> {
        if stepper.step_index() % options.every != 0 || stepper.time() < options.from - 0.5 * dt {
            return Ok(());
        }
        if let Some(out) = csv.as_mut() {
            write_row(out, stepper)?;
        }
        if let Some(field) = field.as_mut() {
            field.record(stepper, base);
        }
        Ok(())
    };
    record(&stepper, scene.builtin_base(0.0))?;
    let mut paths = [0u64; 4];
    let mut stepping = 0.0;
    for n in 0..steps {
        let z = scene.builtin_base((n + 1) as f64 * dt);
        let start = Instant::now();
        let report = stepper.step(z).map_err(|e| e.to_string())?;
        stepping += start.elapsed().as_secs_f64();
        paths[report.path as usize] += 1;
        record(&stepper, z)?;
    }
    if let Some(mut out) = csv {
        out.flush().map_err(|e| e.to_string())?;
    }
    if let (Some(field), Some(path)) = (field, &options.field) {
        field.write(path)?;
    }
    let [free, active_set, clarabel, fallback] = paths;
    eprintln!(
        "scene {}: {} backend, {} free dofs, {} constrained vertices, set-up {setup_time:.3} s",
        options.name,
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
