//! Helpers shared by the integration tests. Each test crate uses some of them only, hence the
//! allowance of dead code.
#![allow(dead_code)]

use plate_impact::element::ElementKind;
use plate_impact::scene::{QpChoice, Scene};
use plate_impact::scheme::{StepPath, Stepper};

/// A named scene on the paper's 140-element mesh of `element` (Argyris 10 × 7, FVS 14 × 10).
pub fn paper_scene(name: &str, element: ElementKind) -> Scene {
    let mut s = Scene::named(name).unwrap();
    s.mesh.element = element;
    if element == ElementKind::Fvs {
        s.mesh.nx = 14;
        s.mesh.ny = 10;
    }
    s
}

/// The largest difference of u_n between two steppers over the obstacle-constrained vertices (m).
pub fn largest_vertex_difference(a: &Stepper, b: &Stepper) -> f64 {
    a.constrained_displacements()
        .iter()
        .zip(b.constrained_displacements())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// How closely the fast path and the clarabel reference agree.
pub struct Agreement {
    /// Contact steps compared.
    pub compared: usize,
    /// Most vertices in contact on one of them.
    pub most_active: usize,
    /// Largest difference of u_{n+1} at the constrained vertices and the free corners (m).
    pub worst: f64,
}

/// [`fast_path_against_clarabel`] on `scene`, printed under `label`, asserting at least 10 contact
/// steps compared and u_{n+1} within 1e-9 m of clarabel's on each: clarabel polished on its
/// active set is exact to round-off (≈ 1e-13 m measured), and a wrong active set shows as
/// millimetres.
pub fn assert_fast_path_matches_clarabel(
    label: &str,
    scene: &Scene,
    steps: usize,
    max_compared: usize,
) {
    let a = fast_path_against_clarabel(scene, steps, max_compared);
    println!(
        "{label}: {} contact steps compared, up to {} contacts, worst difference {:.2e} m",
        a.compared, a.most_active, a.worst
    );
    assert!(a.compared >= 10, "{label}: too few contact steps");
    assert!(
        a.worst <= 1e-9,
        "{label}: fast path and clarabel differ by {:e} m",
        a.worst
    );
}

/// Runs `scene` with the fast path for up to `steps` steps; on each of its first `max_compared`
/// contact steps, restores the state before that step into a clarabel stepper, takes the same
/// step there and compares the results.
pub fn fast_path_against_clarabel(scene: &Scene, steps: usize, max_compared: usize) -> Agreement {
    let mut fast = Stepper::new(scene, 0.0).unwrap();
    let mut reference_scene = scene.clone();
    reference_scene.solver.qp = QpChoice::Clarabel;
    let mut reference = Stepper::new(&reference_scene, 0.0).unwrap();
    let mut agreement = Agreement {
        compared: 0,
        most_active: 0,
        worst: 0.0,
    };
    for n in 1..=steps {
        if agreement.compared >= max_compared {
            break;
        }
        let z = scene.builtin_base(n as f64 * scene.solver.time_step);
        let state = fast.state();
        let report = fast.step(z).unwrap();
        if report.path == StepPath::Unconstrained {
            continue;
        }
        reference.restore(&state).unwrap();
        reference.step(z).unwrap();
        let vertices = largest_vertex_difference(&fast, &reference);
        let (a, b) = (fast.outputs(), reference.outputs());
        let corners = (a.corner1 - b.corner1)
            .abs()
            .max((a.corner2 - b.corner2).abs());
        agreement.worst = agreement.worst.max(vertices).max(corners);
        agreement.most_active = agreement.most_active.max(report.active);
        agreement.compared += 1;
    }
    agreement
}
