//! Natural frequencies of the clamped steel plate of SPEC §4.
//!
//! `cargo run --release --example modes -- <argyris|fvs> <nx> <ny> [Lx Ly] [name=value ...]`
//! prints the dof count and the six lowest natural frequencies, one per line as `mode <k>: <f> Hz`.
//! `name=value` sets any other scene parameter by its FMU name (e.g. `plate.thickness=0.008`), so
//! a caller such as `examples/frequency_sweep.py` gets the frequencies of exactly the plate it runs.

use plate_impact::element::ElementKind;
use plate_impact::scene::Scene;
use plate_impact::system::PlateSystem;
use std::process::ExitCode;

fn main() -> ExitCode {
    let (overrides, args): (Vec<String>, Vec<String>) =
        std::env::args().skip(1).partition(|a| a.contains('='));
    let usage = "usage: modes <argyris|fvs> <nx> <ny> [Lx Ly] [name=value ...]";
    let (Some(element), Some(nx), Some(ny)) = (
        args.first().and_then(|s| ElementKind::parse(s)),
        args.get(1).and_then(|s| s.parse().ok()),
        args.get(2).and_then(|s| s.parse().ok()),
    ) else {
        eprintln!("{usage}");
        return ExitCode::FAILURE;
    };
    let mut scene = Scene::default();
    scene.mesh.element = element;
    scene.mesh.nx = nx;
    scene.mesh.ny = ny;
    if let (Some(lx), Some(ly)) = (
        args.get(3).and_then(|s| s.parse().ok()),
        args.get(4).and_then(|s| s.parse().ok()),
    ) {
        scene.plate.length = lx;
        scene.plate.width = ly;
    }
    for arg in &overrides {
        let (key, value) = arg.split_once('=').expect("partitioned on '='");
        if let Err(e) = scene.set(key, value) {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    }
    let run = || -> Result<(), plate_impact::Error> {
        let start = std::time::Instant::now();
        let plate = PlateSystem::new(&scene)?;
        let assembled = start.elapsed();
        let modes = plate.modes()?;
        println!(
            "dofs: {} (free {}, clamped {})",
            plate.disc.dof_count,
            plate.free.len(),
            plate.clamp.len()
        );
        for (k, f) in modes.frequencies_hz().iter().take(6).enumerate() {
            println!("mode {}: {f:.4} Hz", k + 1);
        }
        eprintln!(
            "assembly {:.3} s, eigen {:.3} s",
            assembled.as_secs_f64(),
            (start.elapsed() - assembled).as_secs_f64()
        );
        Ok(())
    };
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
