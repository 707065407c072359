//! The static obstacle problem with a local stop: the plate preloaded onto a stud.

use super::independent::{dense_restriction, free_part, rows_at, solve_few_rows};
use super::plates::preloaded;
use faer::linalg::solvers::Solve;
use faer::{Mat, Side};
use plate_impact::element::ElementKind;
use plate_impact::scene::Scene;
use plate_impact::scheme::Stepper;
use plate_impact::system::PlateSystem;

/// The library's initial state of `scene` against the same static QP solved here: K_ff and f
/// restricted to the free dofs, the rows of the layout's contact points built from the basis
/// (independent.rs), the minimiser of ½wᵀK_ff w − p₀fᵀw over r_i·w ≥ g1 − z + h_i found by
/// enumerating active sets. Returns (largest |Δw| / max |w|, largest |Δλ| / Σλ, Σλ (N)).
fn against_independent(scene: &Scene) -> (f64, f64, f64) {
    let stepper = Stepper::new(scene, 0.0).unwrap();
    let library_w = stepper.state().current;
    let library_forces = stepper.contact_forces().to_vec();
    let plate = PlateSystem::new(scene).unwrap();
    let points: Vec<[f64; 2]> = plate.layout.points.iter().map(|p| p.position).collect();
    let heights: Vec<f64> = plate
        .layout
        .points
        .iter()
        .map(|p| p.lower.unwrap().h)
        .collect();
    let (rows, _) = rows_at(&plate, &points);
    let k = dense_restriction(&plate.stiffness, &plate.free);
    let p0 = scene.initial.preload_pressure;
    let b = free_part(&plate.unit_load, &plate.free);
    let factor = k.llt(Side::Lower).unwrap();
    let b = Mat::from_fn(b.len(), 1, |i, _| p0 * b[i]);
    let x_star = factor.solve(&b);
    let x_star: Vec<f64> = (0..x_star.nrows()).map(|i| x_star[(i, 0)]).collect();
    let bounds: Vec<f64> = heights.iter().map(|h| scene.obstacle.lower + h).collect();
    let (w, mu) = solve_few_rows(&factor, &x_star, &rows, &bounds);
    let size = w.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    let dw = w
        .iter()
        .zip(&library_w)
        .fold(0.0f64, |s, (a, b)| s.max((a - b).abs()));
    let total: f64 = mu.iter().sum();
    let dl = mu
        .iter()
        .zip(&library_forces)
        .fold(0.0f64, |s, (a, b)| s.max((a - b).abs()));
    (dw / size, dl / total, total)
}

/// A point stud between vertices (one general row) and a disc stud (its centre, its circle and
/// the vertex inside it: general rows and a unit row, several active), both elements: the
/// library's preloaded state (sparse Cholesky, then clarabel polished through the Schur
/// complement of its general rows) is the QP's solution found here by other means, to round-off.
/// Both are exact solutions of the same linear systems, cond(K_ff) ≈ 1e6 (docs/elements.md §2):
/// 1e-9 relative in w and in the forces leaves a margin of 100 over what round-off of that
/// condition gives, and a wrong active set or a wrong row moves both by percents.
#[test]
fn the_preloaded_stud_is_the_independent_qp_solution() {
    for profile in [
        "point(x = 0.33, y = 0.13)",
        "disc(x = 0.31, y = 0.11, radius = 0.02)",
    ] {
        for (element, nx, ny) in [(ElementKind::Argyris, 8, 4), (ElementKind::Fvs, 16, 8)] {
            let scene = preloaded(profile, element, nx, ny);
            let (dw, dl, total) = against_independent(&scene);
            println!(
                "{profile} {element:?} {nx}×{ny}: reaction {total:.3} N, |Δw| {dw:.1e} of max |w|, |Δλ| {dl:.1e} of the reaction"
            );
            assert!(total > 100.0, "the plate rests on the stud");
            assert!(dw <= 1e-9 && dl <= 1e-9, "{profile} {element:?}");
        }
    }
}
