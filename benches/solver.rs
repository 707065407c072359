//! Benchmarks (timings and ratios measured in one run; never asserted in tests).
//!
//! `cargo bench --bench solver [-- --quick | --scale | --crossover | --anatomy | --case NAME [--csv]
//! | --case NAME --rounds R]`
//!
//! 1. Assembly of M, K and the load for the paper's 140-element meshes and for ~10k elements.
//! 2. Stepping the `forced` scene at 35 Hz, Δt = 1e-4 s, 1 s (10⁴ steps) for both elements with
//!    the automatic (fast) path and, for scale, with clarabel on every step; beside it, the cost of
//!    the bare bound check (the dense m × n product y = Cq of the modal backend, timed with the
//!    same routine on a matrix of the same shape), which every exact method pays per step.
//! 3. Contact at scale: each case runs in a child process of its own (`--case NAME`), so that its
//!    peak resident memory (VmHWM of /proc/self/status) is its own; it prints set-up time, µs per
//!    step split into contact-free steps and steps with a QP, and the memory peaks after the
//!    set-up and after the run (`--csv`: the same as one CSV line). With `--rounds R` it sets up
//!    once and runs the case R times from the initial state (a restored state continues bit for
//!    bit, so every round takes the same steps): one line per round, then the median CPU µs of a
//!    step with a QP, beside the floor of such a step on a modal backend, the rows of C = BΦ of
//!    the vertices in contact (one row of n doubles each) read once at the rate of a streaming
//!    read of a buffer the size of C, measured in the same run; then, on a modal backend, the
//!    threads measurement: those rows' products with a vector on one thread and split between
//!    two, and the cost of starting a thread (`threaded_row_reads`).
//!
//! `--verify NAME` runs a case beside the clarabel reference (`solver.qp = clarabel`) until ten
//! steps with a QP have been compared, and prints the largest difference of the constrained
//! displacements and the largest bound violation. `--scale` runs the size sweep instead (both elements, 10 × 7 to 100 × 50, the backend `auto`
//! picks), as the CSV that `plateimpact_tools.studies.scale_plots` reads; `--crossover` runs both backends on the
//! meshes around `MODAL_AUTO_LIMIT`, where the choice between them is made. `--anatomy` times the
//! parts of a sparse step (factor size with each ordering, one solve, one product, and the memory
//! bandwidth that bounds a solve from below).

use faer::linalg::matmul::matmul;
use faer::{Accum, Col, Mat, Par};
use plate_impact::contact::cholesky::{CholeskyAnalysis, CholeskyFactor};
use plate_impact::contact::eliminated::EliminatedSystem;
use plate_impact::contact::ordering::nested_dissection;
use plate_impact::element::ElementKind;
use plate_impact::scene::{LinearChoice, QpChoice, Scene};
use plate_impact::scheme::{FreeSystem, StepPath, Stepper};
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
    if let Some(k) = args.iter().position(|a| a == "--verify") {
        let name = args.get(k + 1).expect("--verify needs a case name");
        verify_against_clarabel(&case(name), 10);
        return;
    }
    if let Some(k) = args.iter().position(|a| a == "--case") {
        let name = args.get(k + 1).expect("--case needs a case name");
        match args.iter().position(|a| a == "--rounds") {
            Some(r) => {
                let rounds = args
                    .get(r + 1)
                    .and_then(|v| v.parse().ok())
                    .expect("--rounds needs a count");
                run_rounds(&case(name), rounds);
            }
            None => run_case(&case(name), args.iter().any(|a| a == "--csv")),
        }
        return;
    }
    if args.iter().any(|a| a == "--anatomy") {
        println!("== anatomy of a sparse step: A = M + ½Δt²K over all dofs, Δt = 1e-4 s");
        solve_anatomy();
        return;
    }
    if args.iter().any(|a| a == "--scale") {
        scale_sweep();
        return;
    }
    if args.iter().any(|a| a == "--crossover") {
        crossover_sweep();
        return;
    }
    let quick = args.iter().any(|a| a == "--quick");
    bench_assembly();
    bench_stepping(quick);
    contact_at_scale(quick);
}

/// `--scale`: cost against size, `forced-35hz` at Δt = 1e-4 s for 0.05 s on meshes from 10 × 7
/// to 100 × 50, with the backend `auto` picks, as CSV.
fn scale_sweep() {
    println!("{}", CaseResult::CSV_HEADER);
    for element in ["argyris", "fvs"] {
        for (nx, ny) in [
            (10, 7),
            (14, 10),
            (20, 10),
            (30, 15),
            (40, 20),
            (60, 30),
            (80, 40),
            (100, 50),
        ] {
            run_child(&format!("sweep-{element}-{nx}x{ny}"), true);
        }
    }
}

/// `--crossover`: both backends on the meshes around `MODAL_AUTO_LIMIT`, as CSV.
fn crossover_sweep() {
    println!("{}", CaseResult::CSV_HEADER);
    for (element, sizes) in [
        (
            "argyris",
            &[(10, 7), (14, 10), (20, 10), (24, 12), (28, 14)][..],
        ),
        (
            "fvs",
            &[(20, 10), (30, 15), (36, 18), (40, 20), (50, 25)][..],
        ),
    ] {
        for (nx, ny) in sizes {
            for backend in ["modal", "sparse"] {
                run_child(&format!("sweep-{element}-{nx}x{ny}-{backend}"), true);
            }
        }
    }
}

/// Section 1: assembly of M, K and the load (median of 5 runs).
fn bench_assembly() {
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
}

/// Section 2: stepping the forced scene with the fast path and with clarabel, beside the bare
/// bound check.
fn bench_stepping(quick: bool) {
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

/// Section 3: the contact cases, each in a child process.
fn contact_at_scale(quick: bool) {
    println!("== contact at scale (each case in a child process)");
    println!("{}", CaseResult::HEADER);
    let cases: &[&str] = if quick {
        &["paper-argyris", "paper-fvs", "fvs-60x30-all"]
    } else {
        &[
            "paper-argyris",
            "paper-fvs",
            "argyris-60x30-forced",
            "fvs-60x30-released",
            "fvs-60x30-pressed",
            "fvs-60x30-flat",
            "fvs-60x30-all",
        ]
    };
    for name in cases {
        run_child(name, false);
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
/// and then released (`fvs-60x30-released`) or held (`fvs-60x30-pressed`), by 10 MPa onto an
/// obstacle 1 µm below (`fvs-60x30-flat`, 1 798 of the 1 860 vertices in contact) or 10 nm below
/// (`fvs-60x30-all`, every vertex in contact), and `sweep-ELEMENT-NXxNY[-BACKEND]`
/// (`forced-35hz` on that mesh for 0.05 s, with the backend `auto` picks or the one named), and
/// `SCENE:DT:BACKEND[:flat]`, a shipped scene of local stops (`stud-corner`, `clamped-panel`) at
/// the time step DT (s) on the backend `modal`, `sparse` or `auto`, for min(its stop time,
/// 20 000 steps); with `:flat` its stop replaced by a flat obstacle, every vertex off the clamp a
/// contact point, at the same level or twice the base amplitude below the plate if that is lower
/// (docs/speed.md, "Local stops").
fn case(name: &str) -> Case {
    if name.contains(':') {
        return Case {
            name: name.to_string(),
            scene: stop_scene(name).unwrap_or_else(|| panic!("unknown bench case {name}")),
        };
    }
    let forced = |element, nx, ny, stop| {
        let mut s = mesh_scene(element, nx, ny);
        s.stop_time = stop;
        s
    };
    let scene = match name {
        "paper-argyris" => forced(ElementKind::Argyris, 10, 7, 1.0),
        "paper-fvs" => forced(ElementKind::Fvs, 14, 10, 1.0),
        "argyris-60x30-forced" => forced(ElementKind::Argyris, 60, 30, 0.05),
        "fvs-60x30-released" | "fvs-60x30-pressed" | "fvs-60x30-flat" | "fvs-60x30-all" => {
            let mut s = forced(ElementKind::Fvs, 60, 30, 0.02);
            s.base.amplitude = 0.0;
            s.obstacle.upper_enabled = false;
            s.initial.preload_pressure = -1e6;
            // A cantilever pressed onto a flat obstacle δ below by a pressure p lies on it except
            // over about (72Dδ/p)^¼ from the clamp.
            let mut press = |pressure: f64, depth: f64| {
                s.obstacle.lower = -depth;
                s.initial.preload_pressure = -pressure;
                s.load.pressure = -pressure;
            };
            match name {
                // Held by the preload pressure during the motion too: 1 MPa onto the obstacle
                // 1 cm below, in contact over the last 5.7 cm only (272 vertices).
                "fvs-60x30-pressed" => press(1e6, 0.01),
                // 10 MPa onto an obstacle 1 µm below: in contact from 1.1 cm off the clamp on,
                // 1 798 vertices.
                "fvs-60x30-flat" => press(1e7, 1e-6),
                // 10 MPa onto an obstacle 10 nm below: (72Dδ/p)^¼ = 6 mm is less than one cell
                // (6.7 mm), so all 1 860 vertices are in contact.
                "fvs-60x30-all" => press(1e7, 1e-8),
                _ => {}
            }
            s
        }
        sweep => {
            let parse = || -> Option<Scene> {
                let rest = sweep.strip_prefix("sweep-")?;
                let mut parts = rest.split('-');
                let element = match parts.next()? {
                    "argyris" => ElementKind::Argyris,
                    "fvs" => ElementKind::Fvs,
                    _ => return None,
                };
                let (nx, ny) = parts.next()?.split_once('x')?;
                let mut s = forced(element, nx.parse().ok()?, ny.parse().ok()?, 0.05);
                s.solver.linear = match parts.next() {
                    None => LinearChoice::Auto,
                    Some("modal") => LinearChoice::Modal,
                    Some("sparse") => LinearChoice::Sparse,
                    Some(_) => return None,
                };
                Some(s)
            };
            parse().unwrap_or_else(|| panic!("unknown bench case {sweep}"))
        }
    };
    Case {
        name: name.to_string(),
        scene,
    }
}

/// The scene of a case `SCENE:DT:BACKEND[:flat]` ([`case`]), `None` when the name is not one.
fn stop_scene(name: &str) -> Option<Scene> {
    let parts: Vec<&str> = name.split(':').collect();
    let (scene, dt, backend) = (parts.first()?, parts.get(1)?, parts.get(2)?);
    if !["stud-corner", "clamped-panel"].contains(scene) {
        return None;
    }
    let mut s = Scene::named(scene).ok()?;
    s.solver.time_step = dt.parse().ok()?;
    s.stop_time = s.stop_time.min(20_000.0 * s.solver.time_step);
    s.solver.linear = match *backend {
        "auto" => LinearChoice::Auto,
        "modal" => LinearChoice::Modal,
        "sparse" => LinearChoice::Sparse,
        _ => return None,
    };
    match parts.get(3) {
        None => {}
        Some(&"flat") => {
            s.obstacle.lower_profile = "flat".to_string();
            // A flat obstacle lies under the clamp too, where the base must not reach it.
            s.obstacle.lower = s.obstacle.lower.min(-2.0 * s.base.amplitude);
        }
        Some(_) => return None,
    }
    s.validate().ok()?;
    Some(s)
}

/// Runs `bench --case name` (with `--csv` if `csv`) in a child process and passes its output
/// through.
fn run_child(name: &str, csv: bool) {
    let exe = std::env::current_exe().expect("the bench knows its own path");
    let mut args = vec!["--case", name];
    if csv {
        args.push("--csv");
    }
    let out = std::process::Command::new(exe)
        .args(args)
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

/// CPU seconds this thread has run (clock_gettime with CLOCK_THREAD_CPUTIME_ID): on a loaded
/// machine the wall clock also counts the other processes' turns, this does not. The cases run
/// single-threaded, so it is also the process's.
fn cpu_seconds() -> f64 {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `t` is a valid timespec for the call to fill.
    let status = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut t) };
    if status == 0 {
        t.tv_sec as f64 + 1e-9 * t.tv_nsec as f64
    } else {
        f64::NAN
    }
}

/// What one case measured.
struct CaseResult;

impl CaseResult {
    /// The markdown header of the same columns as [`Self::CSV_HEADER`].
    const HEADER: &'static str = "| case | element | nx | ny | backend | free dofs | constrained | \
                                  assembly s | backend set-up s | steps | µs/step | contact-free \
                                  steps | µs each | steps with a QP | µs each | most active | peak \
                                  MiB after set-up | peak MiB at end | set-up CPU s | contact-free CPU \
                                  µs | QP CPU µs | Σ active | u at the outputs (end) |\n\
                                  |---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|";
    /// The columns of one case.
    const CSV_HEADER: &'static str = "case,element,nx,ny,backend,free_dofs,constrained,assembly_s,\
                                      setup_s,steps,us_per_step,free_steps,free_us,qp_steps,qp_us,\
                                      most_active,peak_setup_mib,peak_end_mib,setup_cpu_s,free_cpu_us,\
                                      qp_cpu_us,active_sum,outputs_end";
}

fn run_case(case: &Case, csv: bool) {
    let s = &case.scene;
    let t = Instant::now();
    let plate = PlateSystem::new(s).unwrap();
    let assembly = t.elapsed().as_secs_f64();
    let (t, cpu) = (Instant::now(), cpu_seconds());
    let mut stepper = Stepper::from_system(s, &plate, 0.0).unwrap();
    let setup = t.elapsed().as_secs_f64();
    let setup_cpu = cpu_seconds() - cpu;
    drop(plate);
    let memory_setup = peak_memory_mib();
    let t = Instant::now();
    let RunTotals {
        steps,
        free,
        qp,
        most_active,
        active_sum,
    } = run_steps(&mut stepper, s);
    let per_step = t.elapsed().as_secs_f64() / steps as f64;
    let mean_us = |count: usize, time: f64| 1e6 * time / count.max(1) as f64;
    let outputs = stepper.output_point_displacements()[1].map(|u| format!("{u:.15e}"));
    let fields = [
        case.name.clone(),
        format!("{:?}", s.mesh.element),
        s.mesh.nx.to_string(),
        s.mesh.ny.to_string(),
        format!("{:?}", stepper.linear_backend()),
        stepper.free_dof_count().to_string(),
        stepper.constrained_count().to_string(),
        format!("{assembly:.3}"),
        format!("{setup:.3}"),
        steps.to_string(),
        format!("{:.2}", 1e6 * per_step),
        free.0.to_string(),
        format!("{:.2}", mean_us(free.0, free.1)),
        qp.0.to_string(),
        format!("{:.2}", mean_us(qp.0, qp.1)),
        most_active.to_string(),
        format!("{memory_setup:.1}"),
        format!("{:.1}", peak_memory_mib()),
        format!("{setup_cpu:.3}"),
        format!("{:.2}", mean_us(free.0, free.2)),
        format!("{:.2}", mean_us(qp.0, qp.2)),
        active_sum.to_string(),
        outputs.join(" "),
    ];
    if csv {
        println!("{}", fields.join(","));
    } else {
        println!("| {} |", fields.join(" | "));
    }
}

/// What the steps of one run of a case did.
struct RunTotals {
    steps: usize,
    /// (count, seconds, CPU seconds) of the contact-free steps.
    free: (usize, f64, f64),
    /// The same of the steps with a QP.
    qp: (usize, f64, f64),
    /// The largest active set.
    most_active: usize,
    /// The sum of the active-set sizes over the steps.
    active_sum: usize,
}

/// Steps `stepper` through the scene `s` from its state at t = 0 to `s.stop_time`, timing each
/// step (wall and CPU) and sorting it into contact-free steps and steps with a QP.
fn run_steps(stepper: &mut Stepper, s: &Scene) -> RunTotals {
    let steps = (s.stop_time / s.solver.time_step).round() as usize;
    let mut totals = RunTotals {
        steps,
        free: (0, 0.0, 0.0),
        qp: (0, 0.0, 0.0),
        most_active: 0,
        active_sum: 0,
    };
    for n in 1..=steps {
        let z = s.builtin_base(n as f64 * s.solver.time_step);
        let (t_step, cpu) = (Instant::now(), cpu_seconds());
        let report = stepper.step(z).unwrap();
        let elapsed = t_step.elapsed().as_secs_f64();
        let elapsed_cpu = cpu_seconds() - cpu;
        let slot = if report.path == StepPath::Unconstrained {
            &mut totals.free
        } else {
            &mut totals.qp
        };
        slot.0 += 1;
        slot.1 += elapsed;
        slot.2 += elapsed_cpu;
        totals.most_active = totals.most_active.max(report.active);
        totals.active_sum += report.active;
    }
    totals
}

/// `--case NAME --rounds R`: sets the case up once and runs it `rounds` times from its initial
/// state; prints each round (the steps it took, CPU µs per step of each kind, the outputs at the
/// end) and the median CPU µs of a step with a QP beside its floor (module docs).
fn run_rounds(case: &Case, rounds: usize) {
    let s = &case.scene;
    let cpu = cpu_seconds();
    let mut stepper = Stepper::new(s, 0.0).unwrap();
    let setup_cpu = cpu_seconds() - cpu;
    let initial = stepper.state();
    let (m, n) = (stepper.constrained_count(), stepper.free_dof_count());
    let row_bytes = 8 * n;
    let bandwidth = stream_read_bandwidth(m * row_bytes);
    println!(
        "{}: {:?} backend, {n} free dofs, {m} constrained, set-up {setup_cpu:.2} CPU s; streaming \
         read of {:.1} MB (the size of C = BΦ): {:.1} GB/s",
        case.name,
        stepper.linear_backend(),
        (m * row_bytes) as f64 / 1e6,
        bandwidth / 1e9
    );
    let mut qp_us = Vec::with_capacity(rounds);
    let mut floor_us = 0.0;
    let (mut contact_rows, mut largest_active) = (0.0, 0);
    for round in 1..=rounds {
        stepper.restore(&initial).unwrap();
        let t = run_steps(&mut stepper, s);
        let cpu_us = |(count, _, cpu): (usize, f64, f64)| 1e6 * cpu / count.max(1) as f64;
        let rows_per_qp = t.active_sum as f64 / t.qp.0.max(1) as f64;
        floor_us = 1e6 * rows_per_qp * row_bytes as f64 / bandwidth;
        (contact_rows, largest_active) = (rows_per_qp, t.most_active);
        let outputs = stepper.output_point_displacements()[1].map(|u| format!("{u:.15e}"));
        println!(
            "round {round}: {} steps with a QP at {:.1} CPU µs ({:.1} wall), {} contact-free at \
             {:.2} CPU µs; largest active set {}, Σ active {}; outputs at the end {}",
            t.qp.0,
            cpu_us(t.qp),
            1e6 * t.qp.1 / t.qp.0.max(1) as f64,
            t.free.0,
            cpu_us(t.free),
            t.most_active,
            t.active_sum,
            outputs.join(" ")
        );
        qp_us.push(cpu_us(t.qp));
    }
    let median_us = median(qp_us);
    print!("median over {rounds} rounds: {median_us:.1} CPU µs per step with a QP");
    if stepper.linear_backend() == LinearChoice::Modal {
        print!(
            "; floor {floor_us:.1} µs (the rows of its vertices in contact read once: {:.2} MB at \
             {:.1} GB/s); ratio {:.2}",
            floor_us * 1e-6 * bandwidth / 1e6,
            bandwidth / 1e9,
            median_us / floor_us
        );
    }
    println!();
    if stepper.linear_backend() == LinearChoice::Modal {
        // The rows a step with a QP needs on average, and as many as its largest active set.
        for rows in [contact_rows.round() as usize, largest_active] {
            let [one, two, spawn] = threaded_row_reads(m, n, rows);
            println!(
                "threads: {rows} rows of C times q: 1 thread {:.1} µs, 2 threads {:.1} µs \
                 (ratio {:.2}); spawning and joining a thread alone {:.1} µs (wall, medians)",
                1e6 * one,
                1e6 * two,
                two / one,
                1e6 * spawn
            );
        }
    }
}

/// Wall seconds of the dot products (faer's, as the stand-ins' partial sums) of `rows` rows of
/// an m × n buffer (row-major, the layout of C's rows in the modal data) with a vector of n, on one thread and split between two (the
/// second a scoped thread started per call, as a step without a pool of its own would start
/// it), and of starting and joining that thread alone: the measurement behind the threads
/// decision in docs/speed.md. The rows are spread over the buffer, as the vertices in contact
/// are over the plate, and split by index, so each row's sum is the one-thread sum.
fn threaded_row_reads(m: usize, n: usize, rows: usize) -> [f64; 3] {
    let c = vec![1.0_f64; m * n];
    let q = vec![1.0_f64; n];
    let rows = rows.clamp(1, m);
    let chosen: Vec<usize> = (0..rows).map(|k| k * m / rows).collect();
    let dots = |rows: &[usize], out: &mut [f64]| {
        for (o, &i) in out.iter_mut().zip(rows) {
            *o = faer::RowRef::from_slice(&c[i * n..(i + 1) * n]) * faer::ColRef::from_slice(&q);
        }
    };
    let mut out = vec![0.0; chosen.len()];
    let reps = 2000;
    let one = time_median(reps, || {
        dots(&chosen, &mut out);
        std::hint::black_box(&out);
    });
    let half = chosen.len() / 2;
    let two = time_median(reps, || {
        let (first, second) = out.split_at_mut(half);
        std::thread::scope(|scope| {
            scope.spawn(|| dots(&chosen[half..], second));
            dots(&chosen[..half], first);
        });
        std::hint::black_box(&out);
    });
    let spawn = time_median(reps, || {
        std::thread::scope(|scope| drop(scope.spawn(|| ())))
    });
    [one, two, spawn]
}

/// Bytes per second of a streaming read of a buffer of `bytes` bytes (summed with eight
/// independent partial sums, so that the adds do not wait on each other; the median of several
/// passes after a first one that brings it into whatever cache holds it).
fn stream_read_bandwidth(bytes: usize) -> f64 {
    let buffer = vec![1.0_f64; bytes.div_ceil(64) * 8];
    let pass = || {
        let mut partial = [0.0_f64; 8];
        for chunk in buffer.chunks_exact(8) {
            for (p, v) in partial.iter_mut().zip(chunk) {
                *p += v;
            }
        }
        std::hint::black_box(partial);
    };
    pass();
    let passes = (2_000_000_000 / buffer.len().max(1)).clamp(5, 200);
    (buffer.len() * 8) as f64 / time_median(passes, pass)
}

/// Runs `case` with the fast path and with clarabel on every constrained step side by side until
/// `qp_steps` steps with a QP have been compared (or the case ends), and prints the largest
/// difference of the displacements at the constrained vertices over all steps, and the largest
/// violation of an obstacle by the fast path.
fn verify_against_clarabel(case: &Case, qp_steps: usize) {
    let s = &case.scene;
    let plate = PlateSystem::new(s).unwrap();
    let mut fast = Stepper::from_system(s, &plate, 0.0).unwrap();
    let mut reference_scene = s.clone();
    reference_scene.solver.qp = QpChoice::Clarabel;
    let mut reference = Stepper::from_system(&reference_scene, &plate, 0.0).unwrap();
    let steps = (s.stop_time / s.solver.time_step).round() as usize;
    let (mut compared, mut worst, mut violation, mut most_active) = (0, 0.0_f64, 0.0_f64, 0);
    // The largest force difference, relative to the largest reference force of that step.
    let mut force_difference = 0.0_f64;
    for n in 1..=steps {
        let z = s.builtin_base(n as f64 * s.solver.time_step);
        let report = fast.step(z).unwrap();
        reference.step(z).unwrap();
        let (u, v) = (
            fast.constrained_displacements(),
            reference.constrained_displacements(),
        );
        for (a, b) in u.iter().zip(&v) {
            worst = worst.max((a - b).abs());
        }
        for &a in &u {
            let below = s.lower_obstacle().map_or(0.0, |g| g - a);
            let above = s.upper_obstacle().map_or(0.0, |g| a - g);
            violation = violation.max(below).max(above);
        }
        let (f, g) = (fast.contact_forces(), reference.contact_forces());
        let scale = g.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
        if scale > 0.0 {
            let d = f
                .iter()
                .zip(g)
                .fold(0.0_f64, |a, (x, y)| a.max((x - y).abs()));
            force_difference = force_difference.max(d / scale);
        }
        most_active = most_active.max(report.active);
        let done = n == steps || {
            compared += usize::from(report.path != StepPath::Unconstrained);
            compared == qp_steps
        };
        if done {
            println!(
                "{}: {n} steps, {compared} with a QP (up to {most_active} contacts): largest \
                 |u − u_clarabel| {worst:.1e} m, largest bound violation {violation:.1e} m, \
                 largest force difference {force_difference:.1e} of the step's largest force",
                case.name
            );
            return;
        }
    }
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
    // Bandwidth: a streaming read of 256 MiB, the way a triangular solve streams its factor.
    let bandwidth = stream_read_bandwidth(256 << 20);
    println!(
        "memory read bandwidth (one core, summing 256 MiB): {:.1} GB/s",
        bandwidth / 1e9
    );
    println!(
        "| mesh | free dofs | nnz(A) | ordering | nnz(L) | L MiB | numeric factorisation ms | \
         one solve ms | streaming L twice ms | 32 solves ms | product A·x ms | refined solve ms |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|"
    );
    for (element, nx, ny) in [
        (ElementKind::Fvs, 60, 30),
        (ElementKind::Argyris, 60, 30),
        (ElementKind::Fvs, 100, 50),
        (ElementKind::Argyris, 100, 50),
    ] {
        let s = mesh_scene(element, nx, ny);
        let plate = PlateSystem::new(&s).unwrap();
        let free = FreeSystem::new(&s, &plate);
        let a = &free.system;
        let n = a.nrows();
        let nested = nested_dissection(&free.nodes);
        for (name, proposed) in [
            ("minimum degree", None),
            ("nested dissection", Some(&nested[..])),
        ] {
            // With a proposed ordering the analysis keeps the smaller factor of the two; report
            // the proposed one's own size.
            let analysis = CholeskyAnalysis::new(a.symbolic(), proposed).unwrap();
            if proposed.is_some()
                && analysis.ordering() != plate_impact::contact::cholesky::FillOrdering::Proposed
            {
                println!(
                    "| {element:?} {nx}×{ny} | {n} | | {name} | more fill than minimum degree | |"
                );
                continue;
            }
            let entries = analysis.factor_entries();
            let factor_time = time_median(3, || {
                std::hint::black_box(
                    CholeskyFactor::new(analysis.clone(), a.as_ref().as_ref()).unwrap(),
                );
            });
            let mut factor = CholeskyFactor::new(analysis.clone(), a.as_ref().as_ref()).unwrap();
            let mut x: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
            let solve = time_median(21, || {
                factor.solve_in_place(faer::ColMut::from_slice_mut(&mut x).as_mat_mut());
            });
            let mut block = Mat::<f64>::from_fn(n, 32, |i, j| ((i + j) as f64).sin());
            let block_solve = time_median(5, || factor.solve_in_place(block.as_mut()));
            let mut y = vec![0.0; n];
            let product = time_median(21, || {
                plate_impact::contact::add_product(a.as_ref().as_ref(), &x, 1.0, &mut y)
            });
            // What a step pays: the solve with one step of iterative refinement.
            let mut system = EliminatedSystem::new(Arc::clone(a), analysis, &[]).unwrap();
            let refined = time_median(21, || system.solve_unconstrained(&y, &mut x).unwrap());
            println!(
                "| {element:?} {nx}×{ny} | {n} | {} | {name} | {entries} | {:.1} | {:.1} | {:.2} | {:.2} | {:.1} | {:.3} | {:.2} |",
                a.compute_nnz(),
                (entries * 8) as f64 / (1 << 20) as f64,
                1e3 * factor_time,
                1e3 * solve,
                1e3 * 2.0 * (entries * 8) as f64 / bandwidth,
                1e3 * block_solve,
                1e3 * product,
                1e3 * refined,
            );
        }
    }
}
