//! Work-precision study: error against wall time for both elements, three scenes, meshes
//! from coarse to fine and Δt from 1e-3 to 1e-6 s, plus the paper's Table 1 case and clarabel on
//! every step as a second strategy.
//!
//! `cargo run --release --example accuracy [-- --quick] [--out DIR]`
//!
//! Every run happens in this process, one after the other (no threads, so that the wall times,
//! measured with `Instant` around set-up and stepping, are not disturbed by each other). The output
//! directory (default `docs/accuracy`, with `--quick` a fresh temporary directory) receives
//! `runs.csv` (one row per run), `frequencies.csv`, `table1.csv` and `traces.csv` (the reference
//! corner trajectories); then `plateimpact_tools.studies.accuracy_plots` (tools/), run with the
//! Python of `scripts/python-env`, writes the PNG plots and `README.md` there.
//!
//! Errors. The corner displacement u(Lx, 0, t) of each run is put on a common grid (every 1e-4 s,
//! piecewise-linear in time between the steps of runs with Δt > 1e-4 s) and compared with
//! - the scene's reference (finest Argyris mesh at the smallest Δt): `ref_*`, the total error;
//! - the same mesh at its smallest Δt: `dt_*`, the time error alone;
//! - the same element's finest mesh at the same Δt: `h_*`, the space error alone.
//!
//! `--quick` runs a small subset into a temporary directory and exits nonzero unless the observed
//! order in Δt of the contact-free case is within 0.2 of 2 and the whole pipeline (CSV, plots,
//! README) completes.

#[path = "../common/mod.rs"]
mod common;

use common::{element_name, exit_code, StudyDir};
use plate_impact::element::ElementKind;
use plate_impact::scene::{QpChoice, Scene};
use plate_impact::scheme::{StepPath, Stepper};
use plate_impact::system::PlateSystem;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::process::ExitCode;
use std::time::Instant;

/// Spacing of the common time grid on which corner trajectories are compared (s).
const GRID: f64 = 1e-4;

/// Converged natural frequencies of the 0.4 × 0.2 m plate (Hz), from `docs/elements.md` §7.
const REFERENCE_HZ: [f64; 6] = [53.821, 231.63, 335.41, 753.91, 941.26, 1447.8];

/// The study's scenes: the label used in the CSV and how it is built from a named scene.
/// `free` is `energy` without its obstacle; `free-smooth` is a contact-free control case whose
/// solution is smooth in time for every mode of the mesh (see [`base_motion`]).
const SCENES: [&str; 4] = ["free-smooth", "free", "energy", "forced-35hz"];

/// Base displacement z(t) (m) of a study scene. `free-smooth` starts at rest, undeformed, and moves
/// its base by z(t) = c (1 − cos 2πft)²/4 with c = 4 mm, f = 50 Hz (z, ż, z̈ vanish at t = 0, so no
/// mode is excited impulsively: the stiff modes follow quasi-statically). The others use the
/// scene's built-in sine (zero amplitude for `free` and `energy`).
fn base_motion(label: &str, scene: &Scene, t: f64) -> f64 {
    match label {
        "free-smooth" => {
            0.004 * (1.0 - (2.0 * std::f64::consts::PI * 50.0 * t).cos()).powi(2) / 4.0
        }
        _ => scene.builtin_base(t),
    }
}

fn build_scene(label: &str, element: ElementKind, mesh: (usize, usize), dt: f64) -> Scene {
    let mut s = match label {
        "free-smooth" => {
            let mut s = Scene::named("forced").expect("named scene");
            s.obstacle.lower_enabled = false;
            s.obstacle.upper_enabled = false;
            s.base.amplitude = 0.0;
            s
        }
        "free" => {
            let mut s = Scene::named("energy").expect("named scene");
            s.obstacle.lower_enabled = false;
            s
        }
        name => Scene::named(name).expect("named scene"),
    };
    s.mesh.element = element;
    (s.mesh.nx, s.mesh.ny) = mesh;
    s.solver.time_step = dt;
    s
}

fn strategy_name(qp: QpChoice) -> &'static str {
    match qp {
        QpChoice::Auto => "fast",
        QpChoice::Clarabel => "clarabel",
    }
}

/// One run of the study.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Case {
    scene: &'static str,
    element: ElementKind,
    mesh: (usize, usize),
    dt: f64,
    qp: QpChoice,
}

/// What a run measured.
struct Run {
    case: Case,
    free_dofs: usize,
    setup_s: f64,
    stepping_s: f64,
    steps: usize,
    qp_steps: usize,
    /// Contact episodes: steps that end with a vertex in contact after a step that ended with none.
    impacts: usize,
    /// t (s) at the end of the first step with a vertex in contact.
    first_contact: Option<f64>,
    /// Corner displacement on the common grid 0, GRID, …, horizon.
    trace: Vec<f64>,
    energy_end: f64,
}

/// Runs one case over `horizon` seconds. Wall time: `Stepper::new` (assembly, eigenbasis, initial
/// state) plus the step loop, including the few output evaluations needed for the trace.
fn run(case: Case, horizon: f64) -> Result<Run, String> {
    let mut s = build_scene(case.scene, case.element, case.mesh, case.dt);
    s.solver.qp = case.qp;
    s.stop_time = horizon;
    let steps = (horizon / case.dt).round() as usize;
    let t0 = Instant::now();
    let mut stepper =
        Stepper::new(&s, base_motion(case.scene, &s, 0.0)).map_err(|e| e.to_string())?;
    let setup_s = t0.elapsed().as_secs_f64();
    // Sample every `stride` steps (Δt ≤ GRID) or every step (Δt > GRID, interpolated below).
    let stride = if case.dt < GRID {
        (GRID / case.dt).round() as usize
    } else {
        1
    };
    let mut samples = vec![stepper.outputs().corner1];
    let mut qp_steps = 0;
    let (mut impacts, mut in_contact, mut first_contact) = (0, false, None);
    let t1 = Instant::now();
    for n in 1..=steps {
        let report = stepper
            .step(base_motion(case.scene, &s, n as f64 * case.dt))
            .map_err(|e| format!("{case:?} step {n}: {e}"))?;
        if report.path != StepPath::Unconstrained {
            qp_steps += 1;
        }
        if report.active > 0 && !in_contact {
            impacts += 1;
            first_contact.get_or_insert(n as f64 * case.dt);
        }
        in_contact = report.active > 0;
        if n % stride == 0 {
            samples.push(stepper.outputs().corner1);
        }
    }
    let energy_end = stepper.outputs().energy_total;
    let stepping_s = t1.elapsed().as_secs_f64();
    let sample_dt = case.dt * stride as f64;
    let grid_points = (horizon / GRID).round() as usize;
    let trace = (0..=grid_points)
        .map(|k| {
            let x = k as f64 * GRID / sample_dt;
            let i = (x.floor() as usize).min(samples.len() - 2);
            let theta = x - i as f64;
            (1.0 - theta) * samples[i] + theta * samples[i + 1]
        })
        .collect();
    Ok(Run {
        case,
        free_dofs: stepper.free_dof_count(),
        setup_s,
        stepping_s,
        steps,
        qp_steps,
        impacts,
        first_contact,
        trace,
        energy_end,
    })
}

/// (RMS, max) of the difference of two traces.
fn difference(a: &[f64], b: &[f64]) -> (f64, f64) {
    let (mut sum, mut max) = (0.0, 0.0f64);
    for (x, y) in a.iter().zip(b) {
        sum += (x - y) * (x - y);
        max = max.max((x - y).abs());
    }
    ((sum / a.len() as f64).sqrt(), max)
}

/// The plan of a study: meshes, Δt levels and which combinations run.
struct Plan {
    horizon: f64,
    meshes: Vec<(ElementKind, Vec<(usize, usize)>)>,
    /// Δt levels run on every mesh.
    dt_grid: Vec<f64>,
    /// Δt levels run additionally on the paper's mesh and on the finest mesh of each element.
    dt_sweep: Vec<f64>,
    /// The paper's 140-element meshes.
    paper_mesh: [(ElementKind, (usize, usize)); 2],
    scenes: Vec<&'static str>,
    /// Clarabel runs: (scene, element, Δt) on the paper mesh.
    clarabel: Vec<(&'static str, ElementKind, f64)>,
    /// Table 1: Δt levels with the fast path, and those also run with clarabel.
    table1_fast: Vec<f64>,
    table1_clarabel: Vec<f64>,
    /// Table 1 horizon (s): 1 s in the paper.
    table1_horizon: f64,
    /// A finer Argyris mesh than any of the study, run at the smallest Δt only, to estimate the
    /// reference's own space error.
    check_mesh: (usize, usize),
}

fn full_plan() -> Plan {
    use ElementKind::{Argyris, Fvs};
    Plan {
        horizon: 0.1,
        meshes: vec![
            (Argyris, vec![(4, 3), (6, 4), (8, 6), (10, 7), (14, 10)]),
            (Fvs, vec![(7, 5), (10, 7), (14, 10), (20, 14), (28, 20)]),
        ],
        dt_grid: vec![1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2e-5, 1e-5, 5e-6, 2e-6, 1e-6],
        dt_sweep: vec![],
        paper_mesh: [(Argyris, (10, 7)), (Fvs, (14, 10))],
        scenes: SCENES.to_vec(),
        // With obstacles every step is constrained, and clarabel costs about 25 ms a step: 1e-4 s
        // over the horizon is 1000 such steps (25 s), 1e-5 s would be 4 min a run.
        clarabel: vec![
            ("energy", Argyris, 1e-3),
            ("energy", Argyris, 1e-4),
            ("energy", Fvs, 1e-3),
            ("forced-35hz", Argyris, 1e-3),
            ("forced-35hz", Argyris, 1e-4),
            ("forced-35hz", Fvs, 1e-3),
        ],
        table1_fast: vec![1e-3, 1e-4, 1e-5],
        // 1 s at 1e-4 would take about 4 min per element with clarabel: the README extrapolates.
        table1_clarabel: vec![1e-3],
        table1_horizon: 1.0,
        check_mesh: (20, 14),
    }
}

fn quick_plan() -> Plan {
    use ElementKind::{Argyris, Fvs};
    Plan {
        horizon: 0.02,
        meshes: vec![
            (Argyris, vec![(4, 3), (6, 4), (8, 6)]),
            (Fvs, vec![(7, 5), (10, 7), (14, 10)]),
        ],
        dt_grid: vec![1e-3, 1e-4],
        dt_sweep: vec![5e-4, 2e-4, 5e-5, 2e-5, 1e-5, 5e-6, 2e-6],
        paper_mesh: [(Argyris, (6, 4)), (Fvs, (10, 7))],
        scenes: vec!["free-smooth", "free", "energy"],
        clarabel: vec![("energy", Argyris, 1e-3)],
        table1_fast: vec![1e-3],
        table1_clarabel: vec![1e-3],
        table1_horizon: 0.05,
        check_mesh: (10, 7),
    }
}

fn cases(plan: &Plan) -> Vec<Case> {
    let mut out = Vec::new();
    for &scene in &plan.scenes {
        for (element, meshes) in &plan.meshes {
            let finest = *meshes.last().expect("meshes");
            let paper = plan
                .paper_mesh
                .iter()
                .find(|(e, _)| e == element)
                .expect("paper mesh")
                .1;
            for &mesh in meshes {
                let mut dts = plan.dt_grid.clone();
                if mesh == finest || mesh == paper {
                    dts.extend(&plan.dt_sweep);
                }
                dts.sort_by(|a, b| b.partial_cmp(a).expect("finite"));
                for dt in dts {
                    out.push(Case {
                        scene,
                        element: *element,
                        mesh,
                        dt,
                        qp: QpChoice::Auto,
                    });
                }
            }
        }
    }
    for &(scene, element, dt) in &plan.clarabel {
        let mesh = plan
            .paper_mesh
            .iter()
            .find(|(e, _)| *e == element)
            .expect("paper mesh")
            .1;
        out.push(Case {
            scene,
            element,
            mesh,
            dt,
            qp: QpChoice::Clarabel,
        });
    }
    out
}

/// Least-squares slope of log(err) against log(x).
fn slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (lx, ly): (Vec<f64>, Vec<f64>) = points.iter().map(|(x, y)| (x.ln(), y.ln())).unzip();
    let mx = lx.iter().sum::<f64>() / n;
    let my = ly.iter().sum::<f64>() / n;
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

fn main() -> ExitCode {
    exit_code(study())
}

fn study() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dir = StudyDir::from_args(&args, "accuracy", "accuracy")?;
    let quick = dir.quick;
    let plan = if quick { quick_plan() } else { full_plan() };
    let started = Instant::now();

    // Natural frequencies per mesh (one extra eigen-decomposition each, not timed as a run).
    let mut freq_csv = String::from("element,nx,ny,h,free_dofs,mode,frequency_hz,reference_hz\n");
    let with_check = plan.meshes.iter().map(|(element, meshes)| {
        let mut meshes = meshes.clone();
        if *element == ElementKind::Argyris {
            meshes.push(plan.check_mesh);
        }
        (element, meshes)
    });
    for (element, meshes) in with_check {
        for mesh in meshes {
            let s = build_scene("free", *element, mesh, 1e-4);
            let plate = PlateSystem::new(&s).map_err(|e| e.to_string())?;
            let modes = plate.modes().map_err(|e| e.to_string())?;
            for (k, f) in modes.frequencies_hz().iter().take(6).enumerate() {
                writeln!(
                    freq_csv,
                    "{},{},{},{},{},{},{f},{}",
                    element_name(*element),
                    mesh.0,
                    mesh.1,
                    s.plate.length / mesh.0 as f64,
                    plate.free.len(),
                    k + 1,
                    REFERENCE_HZ[k]
                )
                .expect("write to string");
            }
        }
    }
    dir.write("frequencies.csv", &freq_csv)?;

    let all = cases(&plan);
    let mut runs: Vec<Run> = Vec::with_capacity(all.len());
    for (i, case) in all.iter().enumerate() {
        let r = run(*case, plan.horizon)?;
        eprintln!(
            "[{:>3}/{}] {:<11} {:<7} {:>2}×{:<2} Δt={:<7e} {:<8} {:>8.3} s ({} QP steps)",
            i + 1,
            all.len(),
            case.scene,
            element_name(case.element),
            case.mesh.0,
            case.mesh.1,
            case.dt,
            strategy_name(case.qp),
            r.setup_s + r.stepping_s,
            r.qp_steps
        );
        runs.push(r);
    }

    // Errors. Keys into the fast runs: (scene, element, mesh, Δt bits).
    let key = |c: &Case| (c.scene, element_name(c.element), c.mesh, c.dt.to_bits());
    let fast: BTreeMap<_, usize> = runs
        .iter()
        .enumerate()
        .filter(|(_, r)| r.case.qp == QpChoice::Auto)
        .map(|(i, r)| (key(&r.case), i))
        .collect();
    let min_dt = |scene: &str, element: ElementKind, mesh: (usize, usize)| {
        runs.iter()
            .filter(|r| {
                r.case.qp == QpChoice::Auto
                    && r.case.scene == scene
                    && r.case.element == element
                    && r.case.mesh == mesh
            })
            .map(|r| r.case.dt)
            .fold(f64::INFINITY, f64::min)
    };
    let finest = |element: ElementKind| {
        *plan
            .meshes
            .iter()
            .find(|(e, _)| *e == element)
            .expect("element")
            .1
            .last()
            .expect("meshes")
    };
    let reference = |scene: &'static str| {
        let mesh = finest(ElementKind::Argyris);
        let dt = min_dt(scene, ElementKind::Argyris, mesh);
        fast[&(scene, "argyris", mesh, dt.to_bits())]
    };
    let mut csv = String::from(
        "scene,element,nx,ny,h,free_dofs,dt,strategy,steps,qp_steps,impacts,setup_s,stepping_s,wall_s,\
         ref_rms,ref_max,dt_rms,dt_max,h_rms,h_max,energy_end,energy_rel_err,diff_vs_fast,\
         first_contact_s,pre_rms,pre_max\n",
    );
    let fmt_opt = |x: Option<f64>| x.map(|x| format!("{x:e}")).unwrap_or_default();
    for r in &runs {
        let c = &r.case;
        let rf = &runs[reference(c.scene)];
        let (ref_rms, ref_max) = difference(&r.trace, &rf.trace);
        let dt_ref = min_dt(c.scene, c.element, c.mesh);
        let dt_err = (c.dt != dt_ref).then(|| {
            difference(
                &r.trace,
                &runs[fast[&key(&Case { dt: dt_ref, ..*c })]].trace,
            )
        });
        let fine = finest(c.element);
        let h_err = (c.mesh != fine)
            .then(|| fast.get(&key(&Case { mesh: fine, ..*c })))
            .flatten()
            .map(|&j| difference(&r.trace, &runs[j].trace));
        // Before the reference's first contact: the error of the motion up to the first impact.
        let pre = rf.first_contact.map(|t| {
            let k = (t / GRID).floor() as usize + 1;
            difference(&r.trace[..k], &rf.trace[..k])
        });
        let diff_vs_fast = (c.qp == QpChoice::Clarabel)
            .then(|| difference(&r.trace, &runs[fast[&key(c)]].trace).1);
        writeln!(
            csv,
            "{},{},{},{},{},{},{:e},{},{},{},{},{:.6},{:.6},{:.6},{ref_rms:e},{ref_max:e},{},{},{},{},{:e},{:e},{},{},{},{}",
            c.scene,
            element_name(c.element),
            c.mesh.0,
            c.mesh.1,
            0.4 / c.mesh.0 as f64,
            r.free_dofs,
            c.dt,
            strategy_name(c.qp),
            r.steps,
            r.qp_steps,
            r.impacts,
            r.setup_s,
            r.stepping_s,
            r.setup_s + r.stepping_s,
            fmt_opt(dt_err.map(|e| e.0)),
            fmt_opt(dt_err.map(|e| e.1)),
            fmt_opt(h_err.map(|e| e.0)),
            fmt_opt(h_err.map(|e| e.1)),
            r.energy_end,
            ((r.energy_end - rf.energy_end) / rf.energy_end).abs(),
            fmt_opt(diff_vs_fast),
            fmt_opt(r.first_contact),
            fmt_opt(pre.map(|e| e.0)),
            fmt_opt(pre.map(|e| e.1)),
        )
        .expect("write to string");
    }
    dir.write("runs.csv", &csv)?;

    // Reference trajectories, for the plot of what is being compared.
    let mut traces = String::from("t");
    for &scene in &plan.scenes {
        write!(traces, ",{scene}").expect("write to string");
    }
    traces.push('\n');
    for k in 0..runs[reference(plan.scenes[0])].trace.len() {
        write!(traces, "{}", k as f64 * GRID).expect("write to string");
        for &scene in &plan.scenes {
            write!(traces, ",{:e}", runs[reference(scene)].trace[k]).expect("write to string");
        }
        traces.push('\n');
    }
    dir.write("traces.csv", &traces)?;

    // Self-convergence of the reference: its time error (against twice its Δt), its space error
    // (against the finer check mesh at the same Δt), and the other element's finest mesh.
    let mut check = String::from(
        "scene,check_wall_s,time_dt,time_rms,time_max,space_rms,space_max,fvs_rms,fvs_max\n",
    );
    for &scene in &plan.scenes {
        let rf = &runs[reference(scene)];
        let c = rf.case;
        // The next larger Δt on the reference mesh.
        let coarser = runs
            .iter()
            .filter(|r| r.case.qp == QpChoice::Auto && r.case.dt > c.dt)
            .filter(|r| r.case.scene == c.scene && r.case.element == c.element)
            .filter(|r| r.case.mesh == c.mesh)
            .min_by(|a, b| a.case.dt.total_cmp(&b.case.dt));
        let twice = coarser.map(|r| (r.case.dt, difference(&rf.trace, &r.trace)));
        let finer = run(
            Case {
                mesh: plan.check_mesh,
                ..c
            },
            plan.horizon,
        )?;
        eprintln!(
            "check: {scene} argyris {}×{} Δt={:e}: {:.3} s",
            plan.check_mesh.0,
            plan.check_mesh.1,
            c.dt,
            finer.setup_s + finer.stepping_s
        );
        let space = difference(&rf.trace, &finer.trace);
        let fvs_mesh = finest(ElementKind::Fvs);
        let other = fast
            .get(&key(&Case {
                element: ElementKind::Fvs,
                mesh: fvs_mesh,
                dt: min_dt(scene, ElementKind::Fvs, fvs_mesh),
                ..c
            }))
            .map(|&j| difference(&rf.trace, &runs[j].trace));
        writeln!(
            check,
            "{scene},{:.6},{},{},{},{:e},{:e},{},{}",
            finer.setup_s + finer.stepping_s,
            fmt_opt(twice.map(|e| e.0)),
            fmt_opt(twice.map(|e| e.1 .0)),
            fmt_opt(twice.map(|e| e.1 .1)),
            space.0,
            space.1,
            fmt_opt(other.map(|e| e.0)),
            fmt_opt(other.map(|e| e.1)),
        )
        .expect("write to string");
    }
    dir.write("reference_check.csv", &check)?;

    // The paper's Table 1: 140 elements, forced scene at 10 Hz, 1 s.
    let mut table1 = String::from("element,nx,ny,dt,strategy,steps,qp_steps,wall_s\n");
    for (element, mesh) in plan.paper_mesh {
        let strategies = plan
            .table1_fast
            .iter()
            .map(|&dt| (dt, QpChoice::Auto))
            .chain(
                plan.table1_clarabel
                    .iter()
                    .map(|&dt| (dt, QpChoice::Clarabel)),
            );
        for (dt, qp) in strategies {
            let case = Case {
                scene: "forced",
                element,
                mesh,
                dt,
                qp,
            };
            let r = run(case, plan.table1_horizon)?;
            let wall = r.setup_s + r.stepping_s;
            eprintln!(
                "table 1: {} {}×{} Δt={dt:e} {}: {wall:.3} s",
                element_name(element),
                mesh.0,
                mesh.1,
                strategy_name(qp)
            );
            writeln!(
                table1,
                "{},{},{},{dt:e},{},{},{},{wall:.6}",
                element_name(element),
                mesh.0,
                mesh.1,
                strategy_name(qp),
                r.steps,
                r.qp_steps
            )
            .expect("write to string");
        }
    }
    dir.write("table1.csv", &table1)?;
    let total_s = started.elapsed().as_secs_f64();
    eprintln!("runs done in {total_s:.1} s; plotting");

    // What the plotting script needs to describe the study.
    let list = |xs: &[f64]| {
        xs.iter()
            .map(|x| format!("{x:e}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    let meshes = |element: ElementKind| {
        plan.meshes
            .iter()
            .find(|(e, _)| *e == element)
            .expect("element")
            .1
            .iter()
            .map(|(nx, ny)| format!("{nx}×{ny}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    let rm = finest(ElementKind::Argyris);
    let impacts: Vec<String> = plan
        .scenes
        .iter()
        .map(|&scene| format!("{scene} {} impacts", runs[reference(scene)].impacts))
        .collect();
    let mut meta = String::from("key,value\n");
    for (k, v) in [
        ("quick", quick.to_string()),
        ("horizon", plan.horizon.to_string()),
        ("total_s", format!("{total_s:.1}")),
        ("meshes_argyris", meshes(ElementKind::Argyris)),
        ("meshes_fvs", meshes(ElementKind::Fvs)),
        ("dt_grid", list(&plan.dt_grid)),
        ("dt_sweep", list(&plan.dt_sweep)),
        (
            "paper_mesh_argyris",
            format!("{}x{}", plan.paper_mesh[0].1 .0, plan.paper_mesh[0].1 .1),
        ),
        (
            "paper_mesh_fvs",
            format!("{}x{}", plan.paper_mesh[1].1 .0, plan.paper_mesh[1].1 .1),
        ),
        (
            "reference",
            format!(
                "Argyris {}×{} at Δt = {:e} s",
                rm.0,
                rm.1,
                min_dt(plan.scenes[0], ElementKind::Argyris, rm)
            ),
        ),
        (
            "check_mesh",
            format!("{}×{}", plan.check_mesh.0, plan.check_mesh.1),
        ),
        ("impacts", impacts.join("; ")),
    ] {
        writeln!(meta, "{k},\"{v}\"").expect("write to string");
    }
    dir.write("meta.csv", &meta)?;

    dir.plot("accuracy_plots")?;

    // Contact-free orders in Δt (time error alone, paper mesh, over every Δt at least twice the
    // reference's). The smooth control case must be second order (docs/scheme.md §6); the release
    // from the static deflection excites every mode of the mesh, with amplitudes decaying only like
    // a power of the frequency, so its pre-asymptotic order is lower (about 1.3–1.5): asserted
    // above 1.2.
    let mut failures = Vec::new();
    for (scene, low, high) in [("free-smooth", 1.8, 2.2), ("free", 1.2, 2.2)] {
        for (element, mesh) in plan.paper_mesh {
            let dt_ref = min_dt(scene, element, mesh);
            let points: Vec<(f64, f64)> = runs
                .iter()
                .filter(|r| {
                    let c = &r.case;
                    c.scene == scene
                        && c.element == element
                        && c.mesh == mesh
                        && c.qp == QpChoice::Auto
                        && c.dt >= 2.0 * dt_ref
                })
                .map(|r| {
                    let other = &runs[fast[&key(&Case {
                        dt: dt_ref,
                        ..r.case
                    })]];
                    (r.case.dt, difference(&r.trace, &other.trace).0)
                })
                .collect();
            let order = slope(&points);
            eprintln!(
                "{scene}: order in Δt, {} {}×{}: {order:.3} (RMS corner error, {} levels)",
                element_name(element),
                mesh.0,
                mesh.1,
                points.len()
            );
            if !(low..=high).contains(&order) {
                failures.push(format!(
                    "{scene} {}: observed order {order:.3} outside [{low}, {high}]",
                    element_name(element)
                ));
            }
        }
    }
    failures.extend(dir.missing(&[
        "runs.csv",
        "frequencies.csv",
        "table1.csv",
        "traces.csv",
        "reference_check.csv",
        "meta.csv",
        "README.md",
        "work_precision.png",
        "convergence_dt.png",
        "convergence_h.png",
        "traces.png",
    ]));
    eprintln!(
        "study done in {:.1} s; output in {}",
        started.elapsed().as_secs_f64(),
        dir.path.display()
    );
    dir.finish(failures)
}
