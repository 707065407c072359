//! Natural frequencies and mode shapes of the clamped plate (the steel plate of docs/model.md
//! unless overridden).
//!
//! `cargo run --release --example modes -- <argyris|fvs> <nx> <ny> [Lx Ly] [name=value ...]
//! [--shapes FILE [--refine K]]`
//!
//! prints the dof count and the six lowest natural frequencies, one per line as `mode <k>: <f> Hz`.
//! `name=value` sets any other scene parameter by its FMU name (e.g. `plate.thickness=0.008`), so
//! a caller such as `plateimpact_tools.studies.frequency_sweep` gets the frequencies of exactly the plate it runs.
//!
//! `--shapes FILE` also writes the six shapes as JSON (`examples/mode_shapes.py` plots them):
//! `frequencies_hz`, the sampling grid `x` and `y` (m) and, per mode, `shapes[k][j][i]` = φ_k(x_i,
//! y_j). The grid has K points per cell side (`--refine K`, default 1: the mesh vertices), and the
//! values are the C¹ finite element field there, so K > 1 shows the field between the vertices.
//! Each shape is scaled to max |φ| = 1 on the grid, with its largest-magnitude value positive
//! (the eigenvectors are M-orthonormal and of arbitrary sign).

mod common;

use common::{exit_code, positive_integer, set_override};
use plate_impact::element::ElementKind;
use plate_impact::modes::Modes;
use plate_impact::scene::Scene;
use plate_impact::system::PlateSystem;
use serde_json::json;
use std::process::ExitCode;

/// How many modes are printed and written.
const MODE_COUNT: usize = 6;

const USAGE: &str =
    "usage: modes <argyris|fvs> <nx> <ny> [Lx Ly] [name=value ...] [--shapes FILE [--refine K]]";

fn main() -> ExitCode {
    exit_code(run())
}

fn run() -> Result<(), String> {
    let mut positional = Vec::new();
    let mut overrides = Vec::new();
    let mut shapes_path = None;
    let mut refine = 1usize;
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--shapes" => shapes_path = Some(args.next().ok_or("--shapes needs a file name")?),
            "--refine" => refine = positive_integer("--refine", args.next())?,
            _ if arg.contains('=') => overrides.push(arg),
            _ => positional.push(arg),
        }
    }
    let (Some(element), Some(nx), Some(ny)) = (
        positional.first().and_then(|s| ElementKind::parse(s)),
        positional.get(1).and_then(|s| s.parse().ok()),
        positional.get(2).and_then(|s| s.parse().ok()),
    ) else {
        return Err(USAGE.into());
    };
    let mut scene = Scene::default();
    scene.mesh.element = element;
    scene.mesh.nx = nx;
    scene.mesh.ny = ny;
    if let (Some(lx), Some(ly)) = (
        positional.get(3).and_then(|s| s.parse().ok()),
        positional.get(4).and_then(|s| s.parse().ok()),
    ) {
        scene.plate.length = lx;
        scene.plate.width = ly;
    }
    for arg in &overrides {
        set_override(&mut scene, arg, USAGE)?;
    }
    let start = std::time::Instant::now();
    let plate = PlateSystem::new(&scene).map_err(|e| e.to_string())?;
    let assembled = start.elapsed();
    let modes = plate.modes().map_err(|e| e.to_string())?;
    println!(
        "dofs: {} (free {}, clamped {})",
        plate.disc.dof_count,
        plate.free.len(),
        plate.clamp.len()
    );
    let frequencies = modes.frequencies_hz();
    for (k, f) in frequencies.iter().take(MODE_COUNT).enumerate() {
        println!("mode {}: {f:.4} Hz", k + 1);
    }
    eprintln!(
        "assembly {:.3} s, eigen {:.3} s",
        assembled.as_secs_f64(),
        (start.elapsed() - assembled).as_secs_f64()
    );
    if let Some(path) = shapes_path {
        let (x, y, shapes) = sample_shapes(&scene, &plate, &modes, refine);
        let document = json!({
            "element": format!("{element:?}").to_lowercase(),
            "nx": nx,
            "ny": ny,
            "refine": refine,
            "length": scene.plate.length,
            "width": scene.plate.width,
            "frequencies_hz": &frequencies[..shapes.len()],
            "x": x,
            "y": y,
            "shapes": shapes,
        });
        std::fs::write(&path, document.to_string()).map_err(|e| format!("{path}: {e}"))?;
    }
    Ok(())
}

/// The lowest [`MODE_COUNT`] shapes on the grid of `refine` points per cell side, each scaled to
/// max |φ| = 1 with its largest-magnitude value positive: (x, y, shapes[k][j][i]).
fn sample_shapes(
    scene: &Scene,
    plate: &PlateSystem,
    modes: &Modes,
    refine: usize,
) -> (Vec<f64>, Vec<f64>, Vec<Vec<Vec<f64>>>) {
    let line = |length: f64, cells: usize| -> Vec<f64> {
        let n = cells * refine;
        (0..=n).map(|i| length * i as f64 / n as f64).collect()
    };
    let x = line(scene.plate.length, scene.mesh.nx);
    let y = line(scene.plate.width, scene.mesh.ny);
    // u ↦ u(x_i, y_j) once per grid point, applied to every mode.
    let functionals: Vec<Vec<_>> = y
        .iter()
        .map(|&yj| {
            x.iter()
                .map(|&xi| {
                    plate
                        .disc
                        .point_functional([xi, yj])
                        .expect("grid points lie on the plate")
                })
                .collect()
        })
        .collect();
    let count = MODE_COUNT.min(modes.omega_squared.len());
    let shapes = (0..count)
        .map(|k| {
            // The mode over all dofs: its free-dof values, and 0 on the clamp (base at rest).
            let mut u = vec![0.0; plate.disc.dof_count];
            for (&d, phi) in plate.free.iter().zip(modes.shapes.column(k)) {
                u[d] = phi;
            }
            let values: Vec<Vec<f64>> = functionals
                .iter()
                .map(|row| row.iter().map(|f| f.apply(&u)).collect())
                .collect();
            let peak =
                values
                    .iter()
                    .flatten()
                    .copied()
                    .fold(0.0, |a: f64, b| if b.abs() > a.abs() { b } else { a });
            values
                .into_iter()
                .map(|row| row.into_iter().map(|v| v / peak).collect())
                .collect()
        })
        .collect();
    (x, y, shapes)
}
