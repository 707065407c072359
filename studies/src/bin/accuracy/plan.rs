//! What the accuracy study runs: its scenes, meshes and Δt levels, and the list of cases (one
//! per simulation) the plan makes of them.

use plate_impact::element::ElementKind;
use plate_impact::scene::{QpChoice, Scene};

/// Spacing of the common time grid on which corner trajectories are compared (s).
pub const GRID: f64 = 1e-4;

/// Converged natural frequencies of the 0.4 × 0.2 m plate (Hz), from `docs/elements.md` §7.
pub const REFERENCE_HZ: [f64; 6] = [53.821, 231.63, 335.41, 753.91, 941.26, 1447.8];

/// The paper's Table 1: CPU time (s) of 1 s of the `forced` scene on its 140-element meshes at
/// each Δt (s), Matlab quadprog on a 2010 laptop, which `table1.csv` is compared with.
pub const PAPER_TABLE1: [(ElementKind, f64, f64); 6] = [
    (ElementKind::Argyris, 1e-3, 80.0),
    (ElementKind::Argyris, 1e-4, 870.0),
    (ElementKind::Argyris, 1e-5, 8880.0),
    (ElementKind::Fvs, 1e-3, 120.0),
    (ElementKind::Fvs, 1e-4, 1220.0),
    (ElementKind::Fvs, 1e-5, 12220.0),
];

/// The study's scenes: the label used in the CSV and how it is built from a named scene.
/// `free` is `energy` without its obstacle; `free-smooth` is a contact-free control case whose
/// solution is smooth in time for every mode of the mesh (see [`base_motion`]).
pub const SCENES: [&str; 4] = ["free-smooth", "free", "energy", "forced-35hz"];

/// Base displacement z(t) (m) of a study scene. `free-smooth` starts at rest, undeformed, and moves
/// its base by z(t) = c (1 − cos 2πft)²/4 with c = 4 mm, f = 50 Hz (z, ż, z̈ vanish at t = 0, so no
/// mode is excited impulsively: the stiff modes follow quasi-statically). The others use the
/// scene's built-in sine (zero amplitude for `free` and `energy`).
pub fn base_motion(label: &str, scene: &Scene, t: f64) -> f64 {
    match label {
        "free-smooth" => {
            0.004 * (1.0 - (2.0 * std::f64::consts::PI * 50.0 * t).cos()).powi(2) / 4.0
        }
        _ => scene.builtin_base(t),
    }
}

pub fn build_scene(label: &str, element: ElementKind, mesh: (usize, usize), dt: f64) -> Scene {
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

pub fn strategy_name(qp: QpChoice) -> &'static str {
    match qp {
        QpChoice::Auto => "fast",
        QpChoice::Clarabel => "clarabel",
    }
}

/// One run of the study.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Case {
    pub scene: &'static str,
    pub element: ElementKind,
    pub mesh: (usize, usize),
    pub dt: f64,
    pub qp: QpChoice,
}

/// The plan of a study: meshes, Δt levels and which combinations run.
pub struct Plan {
    pub horizon: f64,
    pub meshes: Vec<(ElementKind, Vec<(usize, usize)>)>,
    /// Δt levels run on every mesh.
    pub dt_grid: Vec<f64>,
    /// Δt levels run additionally on the paper's mesh and on the finest mesh of each element.
    pub dt_sweep: Vec<f64>,
    /// The paper's 140-element meshes.
    pub paper_mesh: [(ElementKind, (usize, usize)); 2],
    pub scenes: Vec<&'static str>,
    /// Clarabel runs: (scene, element, Δt) on the paper mesh.
    pub clarabel: Vec<(&'static str, ElementKind, f64)>,
    /// Table 1: Δt levels with the fast path, and those also run with clarabel.
    pub table1_fast: Vec<f64>,
    pub table1_clarabel: Vec<f64>,
    /// Table 1 horizon (s): 1 s in the paper.
    pub table1_horizon: f64,
    /// A finer Argyris mesh than any of the study, run at the smallest Δt only, to estimate the
    /// reference's own space error.
    pub check_mesh: (usize, usize),
}

pub fn full_plan() -> Plan {
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

pub fn quick_plan() -> Plan {
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

/// Every fast and clarabel case of the plan, in the order they run: scene, element, mesh,
/// decreasing Δt (the paper's and the finest meshes also at the sweep's Δt), then the clarabel
/// cases.
pub fn cases(plan: &Plan) -> Vec<Case> {
    let mut out = Vec::new();
    for &scene in &plan.scenes {
        for (element, meshes) in &plan.meshes {
            let (finest, paper) = (plan.finest(*element), plan.paper(*element));
            for &mesh in meshes {
                let mut dts = plan.dt_grid.clone();
                if mesh == finest || mesh == paper {
                    dts.extend(&plan.dt_sweep);
                }
                dts.sort_by(|a, b| b.total_cmp(a));
                out.extend(dts.into_iter().map(|dt| Case {
                    scene,
                    element: *element,
                    mesh,
                    dt,
                    qp: QpChoice::Auto,
                }));
            }
        }
    }
    out.extend(plan.clarabel.iter().map(|&(scene, element, dt)| Case {
        scene,
        element,
        mesh: plan.paper(element),
        dt,
        qp: QpChoice::Clarabel,
    }));
    out
}

impl Plan {
    /// The finest mesh of `element`.
    pub fn finest(&self, element: ElementKind) -> (usize, usize) {
        *self
            .meshes
            .iter()
            .find(|(e, _)| *e == element)
            .expect("element")
            .1
            .last()
            .expect("meshes")
    }

    /// The paper's 140-element mesh of `element`.
    pub fn paper(&self, element: ElementKind) -> (usize, usize) {
        self.paper_mesh
            .iter()
            .find(|(e, _)| *e == element)
            .expect("paper mesh")
            .1
    }
}
