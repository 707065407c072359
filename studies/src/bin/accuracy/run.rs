//! Running the accuracy study: one simulation per case and its corner trace on the common grid,
//! the lookups its errors need, the natural frequencies of its meshes, the reference's check
//! against a finer mesh, and the paper's Table 1 case.

use super::plan::{base_motion, build_scene, strategy_name, Case, Plan, GRID};
use plate_impact::element::ElementKind;
use plate_impact::scene::QpChoice;
use plate_impact::scheme::{StepPath, Stepper};
use plate_impact::system::PlateSystem;
use plate_impact_studies::element::element_name;
use plate_impact_studies::recorder::stride;
use std::collections::BTreeMap;
use std::time::Instant;

/// What a run measured.
pub struct Run {
    pub case: Case,
    pub free_dofs: usize,
    pub setup_s: f64,
    pub stepping_s: f64,
    pub steps: usize,
    pub qp_steps: usize,
    /// Contact episodes: steps that end with a vertex in contact after a step that ended with none.
    pub impacts: usize,
    /// t (s) at the end of the first step with a vertex in contact.
    pub first_contact: Option<f64>,
    /// Corner displacement on the common grid 0, GRID, …, horizon.
    pub trace: Vec<f64>,
    pub energy_end: f64,
}

/// Runs one case over `horizon` seconds. Wall time: `Stepper::new` (assembly, eigenbasis, initial
/// state) plus the step loop, including the few output evaluations needed for the trace.
pub fn run(case: Case, horizon: f64) -> Result<Run, String> {
    let mut s = build_scene(case.scene, case.element, case.mesh, case.dt);
    s.solver.qp = case.qp;
    s.stop_time = horizon;
    let steps = (horizon / case.dt).round() as usize;
    let t0 = Instant::now();
    let mut stepper =
        Stepper::new(&s, base_motion(case.scene, &s, 0.0)).map_err(|e| e.to_string())?;
    let setup_s = t0.elapsed().as_secs_f64();
    // Sample every `stride` steps (Δt ≤ GRID) or every step (Δt > GRID, interpolated below).
    let stride = stride(GRID, case.dt);
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
pub fn difference(a: &[f64], b: &[f64]) -> (f64, f64) {
    let (mut sum, mut max) = (0.0, 0.0f64);
    for (x, y) in a.iter().zip(b) {
        sum += (x - y) * (x - y);
        max = max.max((x - y).abs());
    }
    ((sum / a.len() as f64).sqrt(), max)
}

/// Runs every case of the plan, one after the other.
pub fn run_cases(plan: &Plan, cases: &[Case]) -> Result<Vec<Run>, String> {
    let mut runs = Vec::with_capacity(cases.len());
    for (i, case) in cases.iter().enumerate() {
        let r = run(*case, plan.horizon)?;
        eprintln!(
            "[{:>3}/{}] {:<11} {:<7} {:>2}×{:<2} Δt={:<7e} {:<8} {:>8.3} s ({} QP steps)",
            i + 1,
            cases.len(),
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
    Ok(runs)
}

/// A fast run's key: (scene, element, mesh, Δt bits).
type Key = (&'static str, &'static str, (usize, usize), u64);

fn key(c: &Case) -> Key {
    (c.scene, element_name(c.element), c.mesh, c.dt.to_bits())
}

/// The runs of a study and the lookups its errors need.
pub struct Results<'a> {
    pub plan: &'a Plan,
    pub runs: Vec<Run>,
    fast: BTreeMap<Key, usize>,
}

impl Results<'_> {
    pub fn new(plan: &Plan, runs: Vec<Run>) -> Results<'_> {
        let fast = runs
            .iter()
            .enumerate()
            .filter(|(_, r)| r.case.qp == QpChoice::Auto)
            .map(|(i, r)| (key(&r.case), i))
            .collect();
        Results { plan, runs, fast }
    }

    /// The fast run of `case` (its strategy ignored), if it ran.
    pub fn fast(&self, case: &Case) -> Option<&Run> {
        self.fast.get(&key(case)).map(|&i| &self.runs[i])
    }

    /// The smallest Δt run on a mesh.
    pub fn min_dt(&self, scene: &str, element: ElementKind, mesh: (usize, usize)) -> f64 {
        self.runs
            .iter()
            .filter(|r| r.case.qp == QpChoice::Auto && r.case.scene == scene)
            .filter(|r| r.case.element == element && r.case.mesh == mesh)
            .map(|r| r.case.dt)
            .fold(f64::INFINITY, f64::min)
    }

    /// The reference of `scene`: the finest Argyris mesh at its smallest Δt.
    pub fn reference(&self, scene: &'static str) -> &Run {
        let mesh = self.plan.finest(ElementKind::Argyris);
        let dt = self.min_dt(scene, ElementKind::Argyris, mesh);
        let case = Case {
            scene,
            element: ElementKind::Argyris,
            mesh,
            dt,
            qp: QpChoice::Auto,
        };
        self.fast(&case).expect("the reference ran")
    }
}

/// The natural frequencies of a mesh.
pub struct MeshFrequencies {
    pub element: ElementKind,
    pub mesh: (usize, usize),
    /// The cell length Lx/nx (m).
    pub h: f64,
    pub free_dofs: usize,
    /// The lowest six (Hz).
    pub hz: Vec<f64>,
}

/// The natural frequencies of every mesh of the plan and the check mesh (one eigen-decomposition
/// each, not timed as a run).
pub fn frequencies(plan: &Plan) -> Result<Vec<MeshFrequencies>, String> {
    let mut out = Vec::new();
    for (element, meshes) in &plan.meshes {
        let mut meshes = meshes.clone();
        if *element == ElementKind::Argyris {
            meshes.push(plan.check_mesh);
        }
        for mesh in meshes {
            let s = build_scene("free", *element, mesh, 1e-4);
            let plate = PlateSystem::new(&s).map_err(|e| e.to_string())?;
            let modes = plate.modes().map_err(|e| e.to_string())?;
            out.push(MeshFrequencies {
                element: *element,
                mesh,
                h: s.plate.length / mesh.0 as f64,
                free_dofs: plate.free.len(),
                hz: modes.frequencies_hz().iter().take(6).copied().collect(),
            });
        }
    }
    Ok(out)
}

/// The check of a scene's reference: its time error (against the next larger Δt on its mesh),
/// its space error (against the finer check mesh at the same Δt, run here) and its difference
/// from the other element's finest mesh, each as (RMS, max) of the corner traces' difference.
pub struct ReferenceCheck {
    pub scene: &'static str,
    /// Wall time of the check mesh's run (s).
    pub wall: f64,
    /// The next larger Δt and the difference from its run.
    pub time: Option<(f64, (f64, f64))>,
    pub space: (f64, f64),
    pub fvs: Option<(f64, f64)>,
}

impl Results<'_> {
    /// The check of every scene's reference.
    pub fn reference_checks(&self) -> Result<Vec<ReferenceCheck>, String> {
        let mut checks = Vec::new();
        for &scene in &self.plan.scenes {
            let rf = self.reference(scene);
            let c = rf.case;
            let coarser = self
                .runs
                .iter()
                .filter(|r| r.case.qp == QpChoice::Auto && r.case.dt > c.dt)
                .filter(|r| r.case.scene == c.scene && r.case.element == c.element)
                .filter(|r| r.case.mesh == c.mesh)
                .min_by(|a, b| a.case.dt.total_cmp(&b.case.dt));
            let twice = coarser.map(|r| (r.case.dt, difference(&rf.trace, &r.trace)));
            let mesh = self.plan.check_mesh;
            let finer = run(Case { mesh, ..c }, self.plan.horizon)?;
            let wall = finer.setup_s + finer.stepping_s;
            eprintln!(
                "check: {scene} argyris {}×{} Δt={:e}: {wall:.3} s",
                mesh.0, mesh.1, c.dt
            );
            let space = difference(&rf.trace, &finer.trace);
            let fvs_mesh = self.plan.finest(ElementKind::Fvs);
            let other = self
                .fast(&Case {
                    element: ElementKind::Fvs,
                    mesh: fvs_mesh,
                    dt: self.min_dt(scene, ElementKind::Fvs, fvs_mesh),
                    ..c
                })
                .map(|r| difference(&rf.trace, &r.trace));
            checks.push(ReferenceCheck {
                scene,
                wall,
                time: twice,
                space,
                fvs: other,
            });
        }
        Ok(checks)
    }
}

/// A run of the paper's Table 1 case.
pub struct Table1Run {
    pub element: ElementKind,
    pub mesh: (usize, usize),
    pub dt: f64,
    pub qp: QpChoice,
    pub steps: usize,
    pub qp_steps: usize,
    /// Set-up and stepping (s).
    pub wall: f64,
}

/// The paper's Table 1 case (140 elements, the `forced` scene at 10 Hz, 1 s) with the fast path
/// and with clarabel on every step.
pub fn table1(plan: &Plan) -> Result<Vec<Table1Run>, String> {
    let mut runs = Vec::new();
    for (element, mesh) in plan.paper_mesh {
        let fast = plan.table1_fast.iter().map(|&dt| (dt, QpChoice::Auto));
        let clarabel = plan
            .table1_clarabel
            .iter()
            .map(|&dt| (dt, QpChoice::Clarabel));
        for (dt, qp) in fast.chain(clarabel) {
            let case = Case {
                scene: "forced",
                element,
                mesh,
                dt,
                qp,
            };
            let r = run(case, plan.table1_horizon)?;
            let wall = r.setup_s + r.stepping_s;
            let (name, strategy) = (element_name(element), strategy_name(qp));
            eprintln!(
                "table 1: {name} {}×{} Δt={dt:e} {strategy}: {wall:.3} s",
                mesh.0, mesh.1
            );
            runs.push(Table1Run {
                element,
                mesh,
                dt,
                qp,
                steps: r.steps,
                qp_steps: r.qp_steps,
                wall,
            });
        }
    }
    Ok(runs)
}
