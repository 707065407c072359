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
//!   (`vertices` [x, y] in m, `cells` as vertex ids, `clamped` the clamp's vertex ids), the
//!   obstacle levels (null when absent), profiles and clamp as given, the contact points
//!   (`points` [x, y] in m, with the obstacles' heights over them `lower_heights`,
//!   `upper_heights`, null where absent), each obstacle's level at every vertex where its
//!   profile covers the plate (`lower_surface`, `upper_surface`, null for stops), the stops
//!   (`stops`: side, shape and level), and one frame per record with `t` (s), `base` z(t_n)
//!   (m), `energy` (J), `u` the displacement u_n at every vertex (m; clamp vertices carry z(t_n)),
//!   `contact` the vertices whose contact force is nonzero and `contact_points` the contact points
//!   whose force is nonzero (indices into `points`).
//!
//! stderr gets the wall time, the step count, how many steps needed a QP and by which path, and
//! µs per step.

mod common;

use common::{exit_code, positive_integer, set_override};
use plate_impact::scene::{ObstacleSide, Profile, Scene, StopShape};
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

/// The level of an enabled obstacle whose profile covers the plate (flat, plane, table) at every
/// mesh vertex (m), `null` for stops or a disabled obstacle: the surface an animation draws.
fn surface(scene: &Scene, side: ObstacleSide, vertices: &[[f64; 2]]) -> Value {
    let (Some(level), Ok(profile)) = (scene.level(side), scene.profile(side)) else {
        return Value::Null;
    };
    let heights: Option<Vec<f64>> = vertices
        .iter()
        .map(|&p| profile.plate_height(p, scene.size()).map(|h| level + h))
        .collect();
    heights.map_or(Value::Null, |h| json!(h))
}

/// The stops of the enabled obstacles, numbered as the per-stop outputs number them: side, kind,
/// footprint (m) and level (m).
fn stops(scene: &Scene) -> Value {
    let mut out = Vec::new();
    for side in ObstacleSide::BOTH {
        let (Some(level), Ok(Profile::Stops(stops))) = (scene.level(side), scene.profile(side))
        else {
            continue;
        };
        for stop in stops {
            let shape = match stop.shape {
                StopShape::Point(p) => json!({"kind": "point", "centre": p}),
                StopShape::Disc { centre, radius } => {
                    json!({"kind": "disc", "centre": centre, "radius": radius})
                }
                StopShape::Rectangle { min, max } => {
                    json!({"kind": "rectangle", "min": min, "max": max})
                }
            };
            let side = match side {
                ObstacleSide::Lower => "lower",
                ObstacleSide::Upper => "upper",
            };
            out.push(json!({"side": side, "shape": shape, "level": level + stop.offset}));
        }
    }
    Value::Array(out)
}

/// The displacement at every mesh vertex, from the stepper, with the contact points of the
/// obstacles and which of them carry a force.
struct VertexField {
    /// The mesh vertex of each contact point, where it is one.
    point_vertex: Vec<Option<usize>>,
    /// The JSON header: mesh, clamp and obstacles.
    header: Value,
    frames: Vec<Value>,
}

impl VertexField {
    fn new(scene: &Scene, plate: &PlateSystem) -> VertexField {
        let disc = &plate.disc;
        let clamped: Vec<usize> = disc
            .clamped_vertices(&plate.clamped)
            .into_iter()
            .map(|(v, _)| v)
            .collect();
        let layout = &plate.layout;
        let [lower_heights, upper_heights] = layout.heights();
        let finite = |h: &[f64]| -> Vec<Option<f64>> {
            h.iter().map(|&h| h.is_finite().then_some(h)).collect()
        };
        let header = json!({
            "element": format!("{:?}", scene.mesh.element).to_lowercase(),
            "length": scene.plate.length,
            "width": scene.plate.width,
            "time_step": scene.solver.time_step,
            "base_amplitude": scene.base.amplitude,
            "base_frequency": scene.base.frequency,
            "lower": scene.lower_obstacle(),
            "upper": scene.upper_obstacle(),
            "lower_profile": scene.obstacle.lower_profile,
            "upper_profile": scene.obstacle.upper_profile,
            "clamp": scene.plate.clamp,
            "vertices": disc.mesh.vertices,
            "cells": disc.mesh.cells,
            "clamped": clamped,
            "points": layout.points.iter().map(|p| p.position).collect::<Vec<_>>(),
            "lower_heights": finite(&lower_heights),
            "upper_heights": finite(&upper_heights),
            "lower_surface": surface(scene, ObstacleSide::Lower, &disc.mesh.vertices),
            "upper_surface": surface(scene, ObstacleSide::Upper, &disc.mesh.vertices),
            "stops": stops(scene),
        });
        VertexField {
            point_vertex: layout.points.iter().map(|p| p.vertex).collect(),
            header,
            frames: Vec::new(),
        }
    }

    /// Records u_n at every vertex and the contact points in contact, given the base
    /// displacement z(t_n).
    fn record(&mut self, stepper: &Stepper, base: f64) {
        let [_, u] = stepper.vertex_displacements();
        let in_contact: Vec<usize> = (0..self.point_vertex.len())
            .filter(|&i| stepper.contact_forces()[i] != 0.0)
            .collect();
        let contact: Vec<usize> = in_contact
            .iter()
            .filter_map(|&i| self.point_vertex[i])
            .collect();
        self.frames.push(json!({
            "t": stepper.time(),
            "base": base,
            "energy": stepper.outputs().energy_total,
            "u": u,
            "contact": contact,
            "contact_points": in_contact,
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
    let mut field = options
        .field
        .as_ref()
        .map(|_| VertexField::new(scene, &plate));
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
