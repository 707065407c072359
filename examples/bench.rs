//! Benchmarks (timings and ratios measured in one run; never asserted in tests).
//!
//! `cargo run --release --example bench [-- --quick | --scale | --case NAME]`
//!
//! 1. Assembly of M, K and the load for the paper's 140-element meshes and for ~10k elements.
//! 2. Stepping the `forced` scene at 35 Hz, Δt = 1e-4 s, 1 s (10⁴ steps) for both elements with
//!    the automatic (fast) path and, for scale, with clarabel on every step; beside it, the cost of
//!    the bare bound check (the dense m × n product y = Cq of the modal backend, timed with the
//!    same routine on a matrix of the same shape), which every exact method pays per step.
//! 3. Contact at scale: each case runs in a child process of its own (`--case NAME`), so that its
//!    peak resident memory (VmHWM of /proc/self/status) is its own; it prints set-up time, µs per
//!    step split into contact-free steps and steps with a QP, and the memory peaks after the
//!    set-up and after the run. `--scale` runs the size sweep (both elements, 10 × 7 to 100 × 50)
//!    instead of sections 1 and 2.
//! 4. The sparse contact path of the next phase, prototyped on the library's solvers
//!    ([`run_prototype`]), against the stepper.
//!
//! `--anatomy` times the parts of a sparse step instead (factor size, one solve, one product, and
//! the memory bandwidth that bounds a solve from below).

use faer::linalg::matmul::matmul;
use faer::sparse::linalg::matmul::sparse_dense_matmul;
use faer::sparse::SparseColMat;
use faer::ColRef;
use faer::{Accum, Col, Mat, Par};
use plate_impact::contact::delassus::DEFAULT_DELASSUS_BUDGET;
use plate_impact::contact::eliminated::EliminatedSystem;
use plate_impact::contact::sparse_contact::{SparseContact, Subproblem};
use plate_impact::contact::{BoundState, PdasSettings};
use plate_impact::element::ElementKind;
use plate_impact::scene::{QpChoice, Scene};
use plate_impact::scheme::{StepPath, Stepper};
use plate_impact::system::PlateSystem;
use std::sync::Arc;
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
    let args: Vec<String> = std::env::args().collect();
    if let Some(k) = args.iter().position(|a| a == "--case") {
        let name = args.get(k + 1).expect("--case needs a case name");
        match name.split_once(':') {
            Some((method, scene)) => run_prototype(&case(scene), method),
            None => run_case(&case(name)),
        }
        return;
    }
    if args.iter().any(|a| a == "--anatomy") {
        println!("== anatomy of a sparse step: A = M + ½Δt²K over all dofs, Δt = 1e-4 s");
        solve_anatomy();
        return;
    }
    if args.iter().any(|a| a == "--scale") {
        println!("== cost against size: forced scene at 35 Hz, Δt = 1e-4 s");
        println!("{}", CaseResult::HEADER);
        for element in ["argyris", "fvs"] {
            for (nx, ny) in [(10, 7), (20, 10), (40, 20), (60, 30), (100, 50)] {
                run_child(&format!("sweep-{element}-{nx}x{ny}"));
            }
        }
        return;
    }
    let quick = args.iter().any(|a| a == "--quick");
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

    println!("== contact at scale (each case in a child process)");
    println!("{}", CaseResult::HEADER);
    let cases: &[&str] = if quick {
        &["paper-argyris", "paper-fvs"]
    } else {
        &[
            "paper-argyris",
            "paper-fvs",
            "argyris-60x30-forced",
            "fvs-60x30-released",
            "fvs-60x30-pressed",
            "fvs-60x30-flat",
        ]
    };
    for name in cases {
        run_child(name);
    }
    println!(
        "== the sparse contact path of the next phase, prototyped here on the library's solvers \
         (each case in a child process; compared with the stepper step by step)"
    );
    println!("{}", PROTOTYPE_HEADER);
    let prototypes: &[&str] = if quick {
        &["auto:fvs-60x30-flat"]
    } else {
        &[
            "auto:fvs-60x30-flat",
            "auto:fvs-60x30-pressed",
            "auto:fvs-60x30-released",
            "auto:argyris-60x30-forced",
            "delassus:fvs-60x30-flat",
            "eliminated:fvs-60x30-flat",
            "delassus:fvs-60x30-pressed",
            "eliminated:fvs-60x30-pressed",
            "delassus:fvs-60x30-released",
            "eliminated:fvs-60x30-released",
            "delassus:argyris-60x30-forced",
            "eliminated:argyris-60x30-forced",
        ]
    };
    for name in prototypes {
        run_child(name);
    }
}

/// One benchmark case of section 3.
struct Case {
    name: String,
    scene: Scene,
}

/// The named cases: `paper-argyris`, `paper-fvs` (the paper's meshes on `forced-35hz`, 1 s),
/// `argyris-60x30-forced` (`forced-35hz` on Argyris 60 × 30, 0.05 s), the FVS 60 × 30 plate
/// pressed onto the lower obstacle (upper obstacle off, no base motion, 0.02 s) by a 1 MPa preload
/// and then released (`fvs-60x30-released`) or held (`fvs-60x30-pressed`), or by 10 MPa onto an
/// obstacle 1 µm below (`fvs-60x30-flat`, nearly every vertex in contact), and `sweep-ELEMENT-NXxNY` (`forced-35hz` on that mesh, 0.02 s).
fn case(name: &str) -> Case {
    let forced = |element, nx, ny, stop| {
        let mut s = mesh_scene(element, nx, ny);
        s.stop_time = stop;
        s
    };
    let scene = match name {
        "paper-argyris" => forced(ElementKind::Argyris, 10, 7, 1.0),
        "paper-fvs" => forced(ElementKind::Fvs, 14, 10, 1.0),
        "argyris-60x30-forced" => forced(ElementKind::Argyris, 60, 30, 0.05),
        "fvs-60x30-released" | "fvs-60x30-pressed" | "fvs-60x30-flat" => {
            let mut s = forced(ElementKind::Fvs, 60, 30, 0.02);
            s.base.amplitude = 0.0;
            s.obstacle.upper_enabled = false;
            s.initial.preload_pressure = -1e6;
            match name {
                // Held by the preload pressure during the motion too: a cantilever pressed onto a
                // flat obstacle 1 cm below lies on it over its last (72Dδ/p)^¼ = 5.7 cm only.
                "fvs-60x30-pressed" => s.load.pressure = -1e6,
                // The obstacle 1 µm below and 10 MPa: the contact starts 1.1 cm from the clamp,
                // so nearly every vertex is in contact.
                "fvs-60x30-flat" => {
                    s.obstacle.lower = -1e-6;
                    s.initial.preload_pressure = -1e7;
                    s.load.pressure = -1e7;
                }
                _ => {}
            }
            s
        }
        sweep => {
            let parse = || -> Option<Scene> {
                let rest = sweep.strip_prefix("sweep-")?;
                let (element, size) = rest.split_once('-')?;
                let (nx, ny) = size.split_once('x')?;
                let element = match element {
                    "argyris" => ElementKind::Argyris,
                    "fvs" => ElementKind::Fvs,
                    _ => return None,
                };
                Some(forced(element, nx.parse().ok()?, ny.parse().ok()?, 0.02))
            };
            parse().unwrap_or_else(|| panic!("unknown bench case {sweep}"))
        }
    };
    Case {
        name: name.to_string(),
        scene,
    }
}

/// Runs `bench --case name` in a child process and passes its table row through.
fn run_child(name: &str) {
    let exe = std::env::current_exe().expect("the bench knows its own path");
    let out = std::process::Command::new(exe)
        .args(["--case", name])
        .output()
        .expect("the bench can start itself");
    print!("{}", String::from_utf8_lossy(&out.stdout));
    if !out.status.success() {
        println!(
            "| {name} | failed: {} |",
            String::from_utf8_lossy(&out.stderr).trim()
        );
    }
}

/// Peak resident set size of this process so far (MiB), from VmHWM in /proc/self/status.
fn peak_memory_mib() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok())
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

/// What one case measured.
struct CaseResult;

impl CaseResult {
    const HEADER: &'static str = "| case | backend | free dofs | constrained | assembly s | backend set-up s | \
                                  steps | µs/step | contact-free steps (µs each) | QP steps (µs each) | \
                                  most active | peak MiB after set-up | peak MiB at end |\n\
                                  |---|---|---|---|---|---|---|---|---|---|---|---|---|";
}

fn run_case(case: &Case) {
    let s = &case.scene;
    let t = Instant::now();
    let plate = PlateSystem::new(s).unwrap();
    let assembly = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let mut stepper = Stepper::from_system(s, &plate, 0.0).unwrap();
    let setup = t.elapsed().as_secs_f64();
    drop(plate);
    let memory_setup = peak_memory_mib();
    let steps = (s.stop_time / s.solver.time_step).round() as usize;
    // (count, seconds) of contact-free steps and of steps with a QP.
    let mut free = (0usize, 0.0f64);
    let mut qp = (0usize, 0.0f64);
    let mut most_active = 0;
    let t = Instant::now();
    for n in 1..=steps {
        let z = s.builtin_base(n as f64 * s.solver.time_step);
        let t_step = Instant::now();
        let report = stepper.step(z).unwrap();
        let elapsed = t_step.elapsed().as_secs_f64();
        let slot = if report.path == StepPath::Unconstrained {
            &mut free
        } else {
            &mut qp
        };
        slot.0 += 1;
        slot.1 += elapsed;
        most_active = most_active.max(report.active);
    }
    let per_step = t.elapsed().as_secs_f64() / steps as f64;
    let mean_us = |(count, time): (usize, f64)| 1e6 * time / count.max(1) as f64;
    println!(
        "| {} | {:?} | {} | {} | {:.2} | {:.2} | {steps} | {:.1} | {} ({:.1}) | {} ({:.1}) | {most_active} | {:.0} | {:.0} |",
        case.name,
        stepper.linear_backend(),
        stepper.free_dof_count(),
        stepper.constrained_count(),
        assembly,
        setup,
        1e6 * per_step,
        free.0,
        mean_us(free),
        qp.0,
        mean_us(qp),
        memory_setup,
        peak_memory_mib(),
    );
}

const PROTOTYPE_HEADER: &str =
    "| method:case | steps | µs/step | contact-free steps (µs each) | QP steps (µs each) | \
                                most active | factor work | peak MiB | max |u − u_stepper| (m) |\n\
                                |---|---|---|---|---|---|---|---|---|";

/// out ← out + α A x.
fn add_product(a: &SparseColMat<usize, f64>, x: &[f64], alpha: f64, out: &mut [f64]) {
    sparse_dense_matmul(
        faer::ColMut::from_slice_mut(out).as_mat_mut(),
        Accum::Add,
        a.as_ref(),
        ColRef::from_slice(x).as_mat(),
        alpha,
        Par::Seq,
    );
}

/// The contact steps of a sparse backend as the next phase will wire them, through
/// [`SparseContact`], on the full dof vector with the clamp dofs eliminated (held at w = 0): the
/// prediction x* = A⁻¹ b, and on a step that leaves the box the QP by the subproblem `method`
/// names: `delassus` (PDAS on W with columns from the bounded cache, the active block's factor
/// updated and kept across steps, then x = A⁻¹(b + Bᵀλ)), `eliminated` (PDAS in the primal
/// variables, one sparse factorisation per new working set, reused while the set repeats) or
/// `auto` (the rule of [`SparseContact`]). Restitution 0, as in the cases above. Each step's
/// constrained displacements are compared with those of the library's stepper on the same scene.
fn run_prototype(case: &Case, method: &str) {
    let s = &case.scene;
    let plate = PlateSystem::new(s).unwrap();
    let dt = s.solver.time_step;
    let a = &plate.mass + &(&plate.stiffness * faer::Scale(0.5 * dt * dt));
    let constrained: Vec<usize> = plate.constrained.iter().map(|&i| plate.free[i]).collect();
    let m = constrained.len();
    let n = a.nrows();
    let mut m1 = vec![0.0; n];
    add_product(&plate.mass, &plate.translation, 1.0, &mut m1);
    // w_0 from the stepper's static preload (free-dof coordinates of its sparse backend).
    let reference_state = Stepper::from_system(s, &plate, 0.0).unwrap().state();
    let mut current = vec![0.0; n];
    for (k, &d) in plate.free.iter().enumerate() {
        current[d] = reference_state.current[k];
    }
    let mut previous = current.clone();
    let a = Arc::new(a);
    let mut contact = SparseContact::new(
        a.clone(),
        &plate.clamp,
        &constrained,
        DEFAULT_DELASSUS_BUDGET,
    )
    .unwrap();
    match method {
        "delassus" => contact.force(Subproblem::Delassus),
        "eliminated" => contact.force(Subproblem::Eliminated),
        "auto" => {}
        other => panic!("unknown method {other}"),
    }
    let mut states = vec![BoundState::Free; m];
    let (mut b, mut x_star, mut next) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let (mut lower, mut upper) = (vec![0.0; m], vec![0.0; m]);
    let steps = (s.stop_time / dt).round() as usize;
    let mut trajectory = Vec::with_capacity(steps);
    let (mut free, mut constrained_steps) = ((0usize, 0.0f64), (0usize, 0.0f64));
    let mut most_active = 0;
    let mut bases = [0.0, 0.0];
    let settings = PdasSettings::default();
    let t = Instant::now();
    for step in 1..=steps {
        let t_step = Instant::now();
        let z = s.builtin_base(step as f64 * dt);
        let p = s.load.pressure;
        let start = step == 1;
        let [z_prev, z_curr] = bases;
        // The scheme's forcing (start step: v_0 = 0, the load read as (p_1 + p_0)/2).
        let (load, base) = if start {
            (0.25 * dt * dt * 2.0 * p, -(z - z_curr))
        } else {
            (0.5 * dt * dt * 2.0 * p, -(z - 2.0 * z_curr + z_prev))
        };
        for ((bi, &f), &mi) in b.iter_mut().zip(&plate.unit_load).zip(&m1) {
            *bi = load * f + base * mi;
        }
        if start {
            add_product(&plate.mass, &current, 1.0, &mut b);
        } else {
            add_product(&plate.mass, &current, 2.0, &mut b);
            add_product(&a, &previous, -1.0, &mut b);
        }
        contact.solve_unconstrained(&b, &mut x_star).unwrap();
        lower.fill(s.lower_obstacle().map_or(f64::NEG_INFINITY, |g| g - z));
        upper.fill(s.upper_obstacle().map_or(f64::INFINITY, |g| g - z));
        let feasible = (0..m).all(|i| {
            let y = x_star[constrained[i]];
            y >= lower[i] && y <= upper[i]
        });
        if feasible {
            next.copy_from_slice(&x_star);
            states.fill(BoundState::Free);
        } else {
            let report = contact
                .solve(
                    &b,
                    &x_star,
                    &lower,
                    &upper,
                    &mut states,
                    &settings,
                    &mut next,
                )
                .unwrap();
            assert!(report.status.is_solved(), "{report:?}");
        }
        std::mem::swap(&mut previous, &mut current);
        std::mem::swap(&mut current, &mut next);
        bases = [z_curr, z];
        let elapsed = t_step.elapsed().as_secs_f64();
        let slot = if feasible {
            &mut free
        } else {
            &mut constrained_steps
        };
        slot.0 += 1;
        slot.1 += elapsed;
        most_active = most_active.max(states.iter().filter(|s| s.is_active()).count());
        trajectory.push(
            constrained
                .iter()
                .map(|&c| z + current[c])
                .collect::<Vec<f64>>(),
        );
    }
    let per_step = t.elapsed().as_secs_f64() / steps as f64;
    let memory = peak_memory_mib();
    let (c, f) = (
        contact.delassus().stats(),
        contact.active_set().factor().stats(),
    );
    let work = format!(
        "{} columns in {} solves, {} full factorisations, {} appended, {} deleted, {} reused; \
         {} sparse factorisations",
        c.computed,
        c.blocks,
        f.full,
        f.appended,
        f.deleted,
        f.reused,
        contact.eliminated().stats().factorizations - 1
    );
    // The library's stepper on the same scene, for the trajectory check.
    let mut reference = Stepper::from_system(s, &plate, 0.0).unwrap();
    let mut worst = 0.0_f64;
    for (step, expected) in trajectory.iter().enumerate() {
        reference
            .step(s.builtin_base((step + 1) as f64 * dt))
            .unwrap();
        for (u, v) in reference.constrained_displacements().iter().zip(expected) {
            worst = worst.max((u - v).abs());
        }
    }
    let mean_us = |(count, time): (usize, f64)| 1e6 * time / count.max(1) as f64;
    println!(
        "| {method}:{} | {steps} | {:.1} | {} ({:.1}) | {} ({:.1}) | {most_active} | {work} | {memory:.0} | {worst:.1e} |",
        case.name,
        1e6 * per_step,
        free.0,
        mean_us(free),
        constrained_steps.0,
        mean_us(constrained_steps),
    );
}

/// Median seconds of `reps` runs of `f`.
fn time_median(reps: usize, mut f: impl FnMut()) -> f64 {
    median(
        (0..reps)
            .map(|_| {
                let t = Instant::now();
                f();
                t.elapsed().as_secs_f64()
            })
            .collect(),
    )
}

fn solve_anatomy() {
    use faer::linalg::solvers::Solve;
    use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, SymmetricOrdering};
    // Bandwidth: summing a 256 MiB array with eight independent partial sums (so that the adds
    // do not wait on each other), the way a triangular solve streams its factor.
    let big = vec![1.0_f64; 32 << 20];
    let read = time_median(5, || {
        let mut partial = [0.0_f64; 8];
        for chunk in big.chunks_exact(8) {
            for (p, v) in partial.iter_mut().zip(chunk) {
                *p += v;
            }
        }
        std::hint::black_box(partial);
    });
    let bandwidth = (big.len() * 8) as f64 / read;
    drop(big);
    println!(
        "memory read bandwidth (one core, summing 256 MiB): {:.1} GB/s",
        bandwidth / 1e9
    );
    println!(
        "| mesh | dofs | nnz(A) | nnz(L) | L MiB | numeric factorisation ms | one solve ms | \
         streaming L twice ms | product A·x ms | refined solve ms |\n|---|---|---|---|---|---|---|---|---|---|"
    );
    for (element, nx, ny) in [
        (ElementKind::Fvs, 60, 30),
        (ElementKind::Argyris, 60, 30),
        (ElementKind::Fvs, 100, 50),
        (ElementKind::Argyris, 100, 50),
    ] {
        let s = mesh_scene(element, nx, ny);
        let plate = PlateSystem::new(&s).unwrap();
        let dt = s.solver.time_step;
        let a = &plate.mass + &(&plate.stiffness * faer::Scale(0.5 * dt * dt));
        let n = a.nrows();
        let symbolic = factorize_symbolic_cholesky(
            a.symbolic(),
            faer::Side::Lower,
            SymmetricOrdering::Amd,
            Default::default(),
        )
        .unwrap();
        let entries = symbolic.len_val();
        let factor_time = time_median(3, || {
            std::hint::black_box(a.sp_cholesky(faer::Side::Lower).unwrap());
        });
        let llt = a.sp_cholesky(faer::Side::Lower).unwrap();
        let mut x: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        let solve = time_median(21, || {
            llt.solve_in_place(faer::ColMut::from_slice_mut(&mut x).as_mat_mut());
        });
        let mut y = vec![0.0; n];
        let product = time_median(21, || add_product(&a, &x, 1.0, &mut y));
        // What a step pays: the solve with one step of iterative refinement, clamp eliminated.
        let mut system = EliminatedSystem::new(Arc::new(a.clone()), &plate.clamp, &[]).unwrap();
        let refined = time_median(21, || system.solve_unconstrained(&y, &mut x).unwrap());
        println!(
            "| {element:?} {nx}×{ny} | {n} | {} | {entries} | {:.1} | {:.1} | {:.2} | {:.2} | {:.3} | {:.2} |",
            a.compute_nnz(),
            (entries * 8) as f64 / (1 << 20) as f64,
            1e3 * factor_time,
            1e3 * solve,
            1e3 * 2.0 * (entries * 8) as f64 / bandwidth,
            1e3 * product,
            1e3 * refined,
        );
    }
}
