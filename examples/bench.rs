//! Benchmarks (timings and ratios measured in one run; never asserted in tests).
//!
//! `cargo run --release --example bench [-- --quick]`
//!
//! 1. Assembly of M, K and the load for the paper's 140-element meshes and for ~10k elements.
//! 2. Stepping the `forced` scene at 35 Hz, Δt = 1e-4 s, 1 s (10⁴ steps) for both elements with
//!    the automatic (fast) path and, for scale, with clarabel on every step; beside it, the cost of
//!    the bare bound check (the dense m × n product y = Cq of the modal backend, timed with the
//!    same routine on a matrix of the same shape), which every exact method pays per step.

use faer::linalg::matmul::matmul;
use faer::{Accum, Col, Mat, Par};
use plate_impact::element::ElementKind;
use plate_impact::scene::{QpChoice, Scene};
use plate_impact::scheme::{StepPath, Stepper};
use plate_impact::system::PlateSystem;
use std::time::Instant;

fn median(mut xs: Vec<f64>) -> f64 {
    xs.sort_by(|a, b| a.partial_cmp(b).unwrap());
    xs[xs.len() / 2]
}

fn mesh_scene(element: ElementKind, nx: usize, ny: usize) -> Scene {
    let mut s = Scene::named("forced-35hz").unwrap();
    s.mesh.element = element;
    s.mesh.nx = nx;
    s.mesh.ny = ny;
    s
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    println!("== assembly (median of 5 runs)");
    for (element, nx, ny) in [
        (ElementKind::Argyris, 10, 7),
        (ElementKind::Fvs, 14, 10),
        (ElementKind::Argyris, 71, 70),
        (ElementKind::Fvs, 100, 100),
    ] {
        let s = mesh_scene(element, nx, ny);
        let times: Vec<f64> = (0..5)
            .map(|_| {
                let t = Instant::now();
                let plate = PlateSystem::new(&s).unwrap();
                std::hint::black_box(&plate);
                t.elapsed().as_secs_f64()
            })
            .collect();
        let plate = PlateSystem::new(&s).unwrap();
        println!(
            "{element:?} {nx}×{ny}: {} cells, {} dofs, {:.2} ms",
            plate.disc.mesh.cells.len(),
            plate.disc.dof_count,
            1e3 * median(times)
        );
    }

    println!("== stepping: forced scene at 35 Hz, Δt = 1e-4 s");
    let stop = if quick { 0.2 } else { 1.0 };
    for (element, nx, ny) in [(ElementKind::Argyris, 10, 7), (ElementKind::Fvs, 14, 10)] {
        let mut s = mesh_scene(element, nx, ny);
        s.stop_time = stop;
        let steps = (s.stop_time / s.solver.time_step).round() as usize;
        let run = |qp: QpChoice, steps: usize| {
            let mut s = s.clone();
            s.solver.qp = qp;
            let mut stepper = Stepper::new(&s, 0.0).unwrap();
            // Steps proven free by the screening, free after the full check, needing a QP:
            // count and time of each.
            let mut kinds = [(0usize, 0.0f64); 3];
            let t = Instant::now();
            for n in 1..=steps {
                let z = s.builtin_base(n as f64 * s.solver.time_step);
                let t_step = Instant::now();
                let report = stepper.step(z).unwrap();
                let kind = match (report.path, report.bounds_evaluated) {
                    (StepPath::Unconstrained, false) => 0,
                    (StepPath::Unconstrained, true) => 1,
                    _ => 2,
                };
                kinds[kind].0 += 1;
                kinds[kind].1 += t_step.elapsed().as_secs_f64();
            }
            (t.elapsed().as_secs_f64() / steps as f64, kinds, stepper)
        };
        let fast: Vec<_> = (0..3).map(|_| run(QpChoice::Auto, steps)).collect();
        let per_step = median(fast.iter().map(|r| r.0).collect());
        let (kinds, stepper) = (fast[0].1, &fast[0].2);
        let mean_us = |(count, time): (usize, f64)| 1e6 * time / count.max(1) as f64;
        let (m, n) = (stepper.constrained_count(), stepper.free_dof_count());
        // The bare bound check: y = C q with C of shape m × n.
        let c = Mat::from_fn(m, n, |i, k| ((i * 7 + k * 13) % 17) as f64 - 8.0);
        let q = Col::from_fn(n, |k| (k as f64).sin());
        let mut y = Col::<f64>::zeros(m);
        let reps = 20_000;
        let t = Instant::now();
        for _ in 0..reps {
            matmul(
                y.as_mut(),
                Accum::Replace,
                c.as_ref(),
                q.as_ref(),
                1.0,
                Par::Seq,
            );
            std::hint::black_box(&y);
        }
        let check = t.elapsed().as_secs_f64() / reps as f64;
        let clarabel_steps = if quick { 200 } else { 1000 };
        let (reference, _, _) = run(QpChoice::Clarabel, clarabel_steps);
        println!(
            "{element:?} {nx}×{ny} ({:?} backend, {n} free dofs, {m} constrained): {:.2} µs/step over {steps} steps \
             (screened free {} at {:.2} µs, checked free {} at {:.2} µs, QP {} at {:.2} µs); \
             bare bound check {:.2} µs = {:.0} % of a step; clarabel every step {:.1} µs/step \
             (first {clarabel_steps} steps) = {:.0}× the fast path",
            stepper.linear_backend(),
            1e6 * per_step,
            kinds[0].0,
            mean_us(kinds[0]),
            kinds[1].0,
            mean_us(kinds[1]),
            kinds[2].0,
            mean_us(kinds[2]),
            1e6 * check,
            100.0 * check / per_step,
            1e6 * reference,
            reference / per_step
        );
    }
}
