//! The stepping cost on the paper's meshes, made to compare builds in one run.
//!
//! `cargo bench --bench paper_speed [-- RUNS]` (default 5 runs) steps `forced-35hz`
//! (Δt = 1e-4 s, 1 s, 10 000 steps) on Argyris 10 × 7 and FVS 14 × 10, RUNS times each, and prints
//! per mesh the median and the fastest µs per step over the runs, the same split into steps the
//! screening proved contact-free, contact-free steps whose constrained values were evaluated, and
//! steps with a QP (count, then µs per step), and a hash of the final vertex values (equal hashes:
//! bit-identical trajectories).
//!
//! It uses only what the first release already offered (`Scene::named`, `Stepper::new`,
//! `Stepper::step` and its `StepReport`), so the file can be copied into an older checkout and
//! both builds run alternately: on a shared machine only ratios measured in one session mean
//! anything.

use plate_impact::element::ElementKind;
use plate_impact::scene::Scene;
use plate_impact::scheme::{StepPath, Stepper};
use std::time::Instant;

/// Median of a non-empty list.
fn median(mut xs: Vec<f64>) -> f64 {
    xs.sort_by(|a, b| a.total_cmp(b));
    xs[xs.len() / 2]
}

fn main() {
    // `cargo bench` passes `--bench` to a harness-less target; RUNS is the first other argument.
    let runs: usize = std::env::args()
        .skip(1)
        .find(|a| a != "--bench")
        .map(|a| a.parse().expect("RUNS must be a positive integer"))
        .unwrap_or(5)
        .max(1);
    for (element, nx, ny) in [(ElementKind::Argyris, 10, 7), (ElementKind::Fvs, 14, 10)] {
        let mut scene = Scene::named("forced-35hz").unwrap();
        scene.mesh.element = element;
        scene.mesh.nx = nx;
        scene.mesh.ny = ny;
        scene.stop_time = 1.0;
        let dt = scene.solver.time_step;
        let steps = (scene.stop_time / dt).round() as usize;
        let mut per_step = Vec::new();
        // Per kind (screened free, evaluated free, QP): count and µs per step of each run.
        let mut kinds: [(usize, Vec<f64>); 3] = Default::default();
        let mut hash = 0u64;
        for _ in 0..runs {
            let mut stepper = Stepper::new(&scene, 0.0).unwrap();
            let mut time = [0.0f64; 3];
            let mut count = [0usize; 3];
            let start = Instant::now();
            for n in 1..=steps {
                let z = scene.builtin_base(n as f64 * dt);
                let t = Instant::now();
                let report = stepper.step(z).unwrap();
                let kind = match (report.path, report.bounds_evaluated) {
                    (StepPath::Unconstrained, false) => 0,
                    (StepPath::Unconstrained, true) => 1,
                    _ => 2,
                };
                time[kind] += t.elapsed().as_secs_f64();
                count[kind] += 1;
            }
            per_step.push(1e6 * start.elapsed().as_secs_f64() / steps as f64);
            for (k, (c, us)) in kinds.iter_mut().enumerate() {
                *c = count[k];
                us.push(1e6 * time[k] / count[k].max(1) as f64);
            }
            hash = stepper
                .constrained_displacements()
                .iter()
                .fold(0xcbf2_9ce4_8422_2325, |h, v| {
                    (h ^ v.to_bits()).wrapping_mul(0x0000_0100_0000_01b3)
                });
        }
        let fastest = per_step.iter().copied().fold(f64::INFINITY, f64::min);
        let [screened, evaluated, qp] = kinds.map(|(c, us)| format!("{c} at {:.2}", median(us)));
        println!(
            "{element:?} {nx}x{ny}: {:.2} us/step median, {fastest:.2} fastest of {runs}; \
             screened free {screened}, evaluated free {evaluated}, QP {qp}; hash {hash:016x}",
            median(per_step)
        );
    }
}
