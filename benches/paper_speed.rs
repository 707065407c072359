//! The stepping cost on the paper's meshes, made to compare builds in one run.
//!
//! `cargo bench --bench paper_speed [-- RUNS] [CASES]` (default 5 runs; CASES a comma-separated
//! list of `paper`, `resolved`, `fine`, `floor`, default `paper,resolved`) steps `forced-35hz` on
//! Argyris 10 × 7 and FVS 14 × 10, RUNS times each:
//!
//! * `paper`: the scene as shipped, Δt = 1e-4 s, 1 s (10 000 steps), undamped;
//! * `resolved`: the small-step regime the damping study sends users to, Δt = 1e-6 s, 0.5 s
//!   (500 000 steps), with the study's Rayleigh damping α = 6.6925 1/s, β = 6.2984e-7 s;
//! * `fine`: the same at Δt = 1e-7 s (5 000 000 steps);
//! * `floor`: `resolved` with both obstacles disabled, so that every step only advances the modes
//!   and does the stepper's bookkeeping (no vertex to check): the floor under any step of
//!   `resolved`, its screened steps included (with no constrained vertex, its hash is that of an
//!   empty list).
//!
//! It prints per case and mesh the median and the fastest µs per step over the runs, the same
//! split into steps the screening proved contact-free, contact-free steps whose constrained
//! values were evaluated, and steps with a QP (count, then µs per step), and a hash of the final
//! vertex values (equal hashes: bit-identical trajectories) with the run's base impulse, base work
//! and damping loss to 16 digits (summed from the steps' forces and flows, which a change of
//! summation order moves by round-off).
//!
//! It uses only what the first release already offered (`Scene::named`, `Stepper::new`,
//! `Stepper::step` and its `StepReport`), the damping fields and the obstacles' switches of the
//! scene, so the file can be copied into an older checkout and both builds run alternately: on a
//! shared machine only ratios measured in one session mean anything.

use plate_impact::element::ElementKind;
use plate_impact::scene::Scene;
use plate_impact::scheme::{StepPath, Stepper};
use std::time::Instant;

/// Median of a non-empty list.
fn median(mut xs: Vec<f64>) -> f64 {
    xs.sort_by(|a, b| a.total_cmp(b));
    xs[xs.len() / 2]
}

/// One benchmark case: its name, Δt (s), simulated time (s), Rayleigh damping (α 1/s, β s) and
/// whether the scene's obstacles are enabled.
struct Case {
    name: &'static str,
    time_step: f64,
    stop_time: f64,
    rayleigh: [f64; 2],
    obstacles: bool,
}

/// The damping study's Rayleigh pair: 1 % of critical at the first mode (53.83 Hz) and at 5 kHz
/// (docs/accuracy/damping.md).
const STUDY_RAYLEIGH: [f64; 2] = [6.6925, 6.2984e-7];

const CASES: [Case; 4] = [
    Case {
        name: "paper",
        time_step: 1e-4,
        stop_time: 1.0,
        rayleigh: [0.0, 0.0],
        obstacles: true,
    },
    Case {
        name: "resolved",
        time_step: 1e-6,
        stop_time: 0.5,
        rayleigh: STUDY_RAYLEIGH,
        obstacles: true,
    },
    Case {
        name: "fine",
        time_step: 1e-7,
        stop_time: 0.5,
        rayleigh: STUDY_RAYLEIGH,
        obstacles: true,
    },
    Case {
        name: "floor",
        time_step: 1e-6,
        stop_time: 0.5,
        rayleigh: STUDY_RAYLEIGH,
        obstacles: false,
    },
];

fn main() {
    // `cargo bench` passes `--bench` to a harness-less target.
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| a != "--bench")
        .collect();
    let runs: usize = args
        .iter()
        .find(|a| a.parse::<usize>().is_ok())
        .map(|a| a.parse().expect("checked"))
        .unwrap_or(5)
        .max(1);
    let wanted: Vec<&str> = args
        .iter()
        .find(|a| a.parse::<usize>().is_err())
        .map_or("paper,resolved", |a| a.as_str())
        .split(',')
        .collect();
    for name in &wanted {
        assert!(
            CASES.iter().any(|c| c.name == *name),
            "unknown case {name}: expected one of {:?}",
            CASES.map(|c| c.name)
        );
    }
    for case in CASES.iter().filter(|c| wanted.contains(&c.name)) {
        for (element, nx, ny) in [(ElementKind::Argyris, 10, 7), (ElementKind::Fvs, 14, 10)] {
            bench_mesh(case, element, nx, ny, runs);
        }
    }
}

fn bench_mesh(case: &Case, element: ElementKind, nx: usize, ny: usize, runs: usize) {
    let mut scene = Scene::named("forced-35hz").unwrap();
    scene.mesh.element = element;
    scene.mesh.nx = nx;
    scene.mesh.ny = ny;
    scene.solver.time_step = case.time_step;
    scene.stop_time = case.stop_time;
    [
        scene.damping.mass_proportional,
        scene.damping.stiffness_proportional,
    ] = case.rayleigh;
    scene.obstacle.lower_enabled = case.obstacles;
    scene.obstacle.upper_enabled = case.obstacles;
    let dt = scene.solver.time_step;
    let steps = (scene.stop_time / dt).round() as usize;
    let mut per_step = Vec::new();
    // Per kind (screened free, evaluated free, QP): count and µs per step of each run.
    let mut kinds: [(usize, Vec<f64>); 3] = Default::default();
    let mut hash = 0u64;
    let mut flows = [0.0; 3];
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
        let outputs = stepper.outputs();
        flows = [
            outputs.base_impulse,
            outputs.base_work,
            outputs.damping_loss,
        ];
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
        "{} {element:?} {nx}x{ny}: {:.3} us/step median, {fastest:.3} fastest of {runs}; \
         screened free {screened}, evaluated free {evaluated}, QP {qp}; hash {hash:016x}; \
         base impulse {:.15e} N s, base work {:.15e} J, damping loss {:.15e} J",
        case.name,
        median(per_step),
        flows[0],
        flows[1],
        flows[2]
    );
}
