//! Running the accuracy study: one simulation per case, its corner trace on the common grid,
//! and the CSVs of the runs: every run with its errors (`runs.csv`), the natural frequencies, the
//! reference traces, the reference's self-convergence check and the paper's Table 1 case.

use super::plan::{base_motion, build_scene, strategy_name, Case, Plan, GRID, REFERENCE_HZ};
use plate_impact::element::ElementKind;
use plate_impact::scene::QpChoice;
use plate_impact::scheme::{StepPath, Stepper};
use plate_impact::system::PlateSystem;
use plate_impact_studies::element::element_name;
use plate_impact_studies::recorder::stride;
use std::collections::BTreeMap;
use std::fmt::Write as _;
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

/// The natural frequencies of every mesh of the plan and the check mesh (`frequencies.csv`; one
/// eigen-decomposition each, not timed as a run).
pub fn frequencies_csv(plan: &Plan) -> Result<String, String> {
    let mut csv = String::from("element,nx,ny,h,free_dofs,mode,frequency_hz,reference_hz\n");
    for (element, meshes) in &plan.meshes {
        let mut meshes = meshes.clone();
        if *element == ElementKind::Argyris {
            meshes.push(plan.check_mesh);
        }
        for mesh in meshes {
            let s = build_scene("free", *element, mesh, 1e-4);
            let plate = PlateSystem::new(&s).map_err(|e| e.to_string())?;
            let modes = plate.modes().map_err(|e| e.to_string())?;
            for (k, f) in modes.frequencies_hz().iter().take(6).enumerate() {
                writeln!(
                    csv,
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
    Ok(csv)
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

    /// `runs.csv`: every run with its errors against the reference (`ref_*`), the same mesh at
    /// its smallest Δt (`dt_*`), the same element's finest mesh at the same Δt (`h_*`), its
    /// energy error, the clarabel runs' difference from the fast ones, and the error up to the
    /// reference's first contact (`pre_*`).
    pub fn runs_csv(&self) -> String {
        let mut csv = String::from(
            "scene,element,nx,ny,h,free_dofs,dt,strategy,steps,qp_steps,impacts,setup_s,stepping_s,wall_s,\
             ref_rms,ref_max,dt_rms,dt_max,h_rms,h_max,energy_end,energy_rel_err,diff_vs_fast,\
             first_contact_s,pre_rms,pre_max\n",
        );
        for r in &self.runs {
            let c = &r.case;
            let rf = self.reference(c.scene);
            let (ref_rms, ref_max) = difference(&r.trace, &rf.trace);
            let dt_ref = self.min_dt(c.scene, c.element, c.mesh);
            let dt_err = (c.dt != dt_ref).then(|| {
                let other = self.fast(&Case { dt: dt_ref, ..*c }).expect("ran");
                difference(&r.trace, &other.trace)
            });
            let fine = self.plan.finest(c.element);
            let h_err = (c.mesh != fine)
                .then(|| self.fast(&Case { mesh: fine, ..*c }))
                .flatten()
                .map(|other| difference(&r.trace, &other.trace));
            // Before the reference's first contact: the error of the motion up to the first impact.
            let pre = rf.first_contact.map(|t| {
                let k = (t / GRID).floor() as usize + 1;
                difference(&r.trace[..k], &rf.trace[..k])
            });
            let diff_vs_fast = (c.qp == QpChoice::Clarabel)
                .then(|| difference(&r.trace, &self.fast(c).expect("ran").trace).1);
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
                optional(dt_err.map(|e| e.0)),
                optional(dt_err.map(|e| e.1)),
                optional(h_err.map(|e| e.0)),
                optional(h_err.map(|e| e.1)),
                r.energy_end,
                ((r.energy_end - rf.energy_end) / rf.energy_end).abs(),
                optional(diff_vs_fast),
                optional(r.first_contact),
                optional(pre.map(|e| e.0)),
                optional(pre.map(|e| e.1)),
            )
            .expect("write to string");
        }
        csv
    }

    /// `traces.csv`: the reference corner trajectories on the common grid.
    pub fn traces_csv(&self) -> String {
        let mut traces = String::from("t");
        for &scene in &self.plan.scenes {
            write!(traces, ",{scene}").expect("write to string");
        }
        traces.push('\n');
        for k in 0..self.reference(self.plan.scenes[0]).trace.len() {
            write!(traces, "{}", k as f64 * GRID).expect("write to string");
            for &scene in &self.plan.scenes {
                write!(traces, ",{:e}", self.reference(scene).trace[k]).expect("write to string");
            }
            traces.push('\n');
        }
        traces
    }

    /// `reference_check.csv`: the reference's time error (against the next larger Δt on its
    /// mesh), its space error (against the finer check mesh at the same Δt, run here) and the
    /// other element's finest mesh, per scene.
    pub fn reference_check_csv(&self) -> Result<String, String> {
        let mut check = String::from(
            "scene,check_wall_s,time_dt,time_rms,time_max,space_rms,space_max,fvs_rms,fvs_max\n",
        );
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
            writeln!(
                check,
                "{scene},{wall:.6},{},{},{},{:e},{:e},{},{}",
                optional(twice.map(|e| e.0)),
                optional(twice.map(|e| e.1 .0)),
                optional(twice.map(|e| e.1 .1)),
                space.0,
                space.1,
                optional(other.map(|e| e.0)),
                optional(other.map(|e| e.1)),
            )
            .expect("write to string");
        }
        Ok(check)
    }
}

/// A number in the CSV's `{:e}` form, or an empty cell.
fn optional(x: Option<f64>) -> String {
    x.map(|x| format!("{x:e}")).unwrap_or_default()
}

/// `table1.csv`: the paper's Table 1 case (140 elements, the `forced` scene at 10 Hz, 1 s) with
/// the fast path and with clarabel on every step.
pub fn table1_csv(plan: &Plan) -> Result<String, String> {
    let mut table1 = String::from("element,nx,ny,dt,strategy,steps,qp_steps,wall_s\n");
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
            writeln!(
                table1,
                "{name},{},{},{dt:e},{strategy},{},{},{wall:.6}",
                mesh.0, mesh.1, r.steps, r.qp_steps
            )
            .expect("write to string");
        }
    }
    Ok(table1)
}
