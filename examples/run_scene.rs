//! Runs a scene with the Rust library alone and prints its outputs as CSV at every `every`-th
//! internal step: the reference the FMU tests compare `fmpy.simulate_fmu` against.
//!
//! `cargo run --release --example run_scene -- <scene name or JSON file> <stop time s> <every>`

use plate_impact::scene::Scene;
use plate_impact::simulation::Simulation;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let name = args.first().map(String::as_str).unwrap_or("default");
    let scene = if name.ends_with(".json") {
        Scene::from_json(&std::fs::read_to_string(name)?)?
    } else {
        Scene::named(name)?
    };
    let stop: f64 = args.get(1).map_or(Ok(scene.stop_time), |s| s.parse())?;
    let every: u64 = args.get(2).map_or(Ok(10), |s| s.parse())?;
    let mut sim = Simulation::new(&scene, 0.0)?;
    let steps = (stop / scene.solver.time_step).round() as u64;
    println!("time,corner1,corner2,edge_mid,energy_kinetic,energy_elastic,energy_total,active_nodes,contact_force");
    let print = |sim: &Simulation| {
        let o = sim.outputs();
        println!(
            "{:?},{:?},{:?},{:?},{:?},{:?},{:?},{},{:?}",
            sim.time(),
            o.corner1,
            o.corner2,
            o.edge_mid,
            o.energy_kinetic,
            o.energy_elastic,
            o.energy_total,
            o.active_nodes,
            o.contact_force
        );
    };
    print(&sim);
    for n in 1..=steps {
        sim.step(0.0)?;
        if n % every == 0 {
            print(&sim);
        }
    }
    Ok(())
}
