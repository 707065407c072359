//! What the restitution study runs: the `energy` scene of each case, and for each CSV of
//! docs/restitution/ its cases, the whole study's or, with `--quick`, a small subset's.

use plate_impact::element::ElementKind;
use plate_impact::scene::{ImpactLaw, Scene};

/// The `energy` scene (10 × 7 Argyris, released onto g1 = −10 mm, fixed base) with restitution
/// e, law `law`, time step Δt and horizon `stop` (s).
pub fn energy_scene(e: f64, law: ImpactLaw, dt: f64, stop: f64) -> Scene {
    let mut s = Scene::named("energy").expect("a shipped scene");
    s.solver.restitution = e;
    s.solver.impact_law = law;
    s.solver.time_step = dt;
    s.stop_time = stop;
    s
}

/// `fmu_energy.csv`'s time steps (s) and horizon (s).
pub fn fmu_energy_cases(quick: bool) -> (&'static [f64], f64) {
    if quick {
        (&[1e-4], 0.1)
    } else {
        (&[1e-4, 5e-5, 2.5e-5, 1e-5, 1e-6], 1.0)
    }
}

/// `runs.csv`'s cases (law, e, Δt) and their horizon (s).
pub fn energy_run_cases(quick: bool) -> (Vec<(ImpactLaw, f64, f64)>, f64) {
    let laws = [ImpactLaw::Auto, ImpactLaw::Newton, ImpactLaw::Persistent];
    let mut cases = Vec::new();
    if quick {
        cases.extend(laws[..2].iter().map(|&law| (law, 1.0, 1e-4)));
    } else {
        for e in [0.0, 0.25, 0.5, 0.75, 0.9, 1.0] {
            cases.extend(laws.iter().map(|&law| (law, e, 1e-4)));
        }
        for dt in [5e-5, 2.5e-5, 1e-5] {
            for e in [0.5, 0.9, 1.0] {
                cases.extend(laws[..2].iter().map(|&law| (law, e, dt)));
            }
        }
        for dt in [5e-6, 2.5e-6, 1e-6] {
            cases.extend(laws[..2].iter().map(|&law| (law, 1.0, dt)));
        }
    }
    (cases, if quick { 0.1 } else { 1.0 })
}

/// The shipped scenes without damping, run by `contact_loss.csv`.
pub const UNDAMPED_SCENES: [&str; 4] = ["energy", "forced", "forced-30hz", "forced-35hz"];

/// `contact_loss.csv`'s horizon (s).
pub fn undamped_stop(quick: bool) -> f64 {
    if quick {
        0.05
    } else {
        1.0
    }
}

/// The forced scenes of `forced.csv`.
pub const FORCED_SCENES: [&str; 4] = ["forced-35hz", "forced-30hz", "forced", "forced-35hz-damped"];

/// `forced.csv`'s windows: the transient (s), the length of a window (s) and their count.
pub fn forced_windows(quick: bool) -> (f64, f64, u32) {
    if quick {
        (0.1, 0.05, 2)
    } else {
        (1.0, 1.0, 4)
    }
}

/// The laws both impact-law comparisons run.
pub const LAWS: [ImpactLaw; 2] = [ImpactLaw::Auto, ImpactLaw::Newton];

/// `convergence.csv`'s horizon (s), the Δt of its Δt series (s) and the meshes of its mesh
/// series (Argyris, FVS).
pub fn convergence_plan(quick: bool) -> (f64, &'static [f64], Meshes) {
    if quick {
        (
            0.02,
            &[1e-4, 5e-5, 2.5e-5],
            [&[(1, 1), (2, 1)], &[(2, 2), (4, 3)]],
        )
    } else {
        (
            1.0,
            &[1e-4, 5e-5, 2.5e-5, 1e-5, 5e-6, 2.5e-6, 1e-6],
            [
                &[(2, 1), (4, 2), (6, 4), (10, 7)],
                &[(4, 3), (7, 5), (10, 7), (14, 10)],
            ],
        )
    }
}

/// The mesh of the Δt series of `element`: the paper's (Argyris 10 × 7, FVS 14 × 10), or 2 × 1
/// in quick mode.
pub fn dt_series_mesh(quick: bool, element: ElementKind) -> (usize, usize) {
    match (quick, element) {
        (true, _) => (2, 1),
        (false, ElementKind::Argyris) => (10, 7),
        (false, ElementKind::Fvs) => (14, 10),
    }
}

/// The sampling interval of `Trajectory::corner` (run.rs) (s): every Δt of the study divides it.
pub const SAMPLE: f64 = 1e-4;

/// The ends of the windows [0, T] over which corner errors are taken: the reference's first
/// contact, then 0.05, 0.2 and 1 s.
pub const HORIZONS: [f64; 3] = [0.05, 0.2, 1.0];

/// One convergence run: its series, element, mesh and Δt.
pub type Setting = (&'static str, ElementKind, usize, usize, f64);

/// The meshes (nx, ny) of the mesh series of each element.
pub type Meshes = [&'static [(usize, usize)]; 2];

/// The time step of the mesh series of `convergence` (run.rs) (s).
pub const MESH_TIME_STEP: f64 = 1e-5;
