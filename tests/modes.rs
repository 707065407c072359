//! Natural frequencies of the cantilever plate against the reference values of
//! `docs/elements.md` §7 (converged to 4–5 digits by independent methods) and the literature, and
//! their convergence under mesh refinement.

use plate_impact::element::ElementKind;
use plate_impact::scene::Scene;
use plate_impact::system::PlateSystem;

/// Converged f₁…f₆ (Hz) for the three aspect ratios (`docs/elements.md` §7).
const REFERENCE: [((f64, f64), [f64; 6]); 3] = [
    ((0.4, 0.2), [53.821, 231.63, 335.41, 753.91, 941.26, 1447.8]),
    (
        (0.2, 0.4),
        [218.64, 334.95, 637.26, 1194.0, 1366.97, 1544.2],
    ),
    ((0.2, 0.2), [217.27, 532.46, 1332.3, 1702.5, 1937.6, 3391.7]),
];

fn frequencies(element: ElementKind, lx: f64, ly: f64, nx: usize, ny: usize) -> Vec<f64> {
    let mut s = Scene::default();
    s.plate.length = lx;
    s.plate.width = ly;
    s.mesh.element = element;
    s.mesh.nx = nx;
    s.mesh.ny = ny;
    let plate = PlateSystem::new(&s).unwrap();
    plate.modes().unwrap().frequencies_hz()[..6].to_vec()
}

/// The dof counts of `docs/elements.md` §5.
#[test]
fn dof_counts_match_the_formulas() {
    let mut s = Scene::default();
    let plate = PlateSystem::new(&s).unwrap();
    assert_eq!(plate.disc.dof_count, 755);
    assert_eq!(plate.clamp.len(), 47);
    s.mesh.element = ElementKind::Fvs;
    s.mesh.nx = 14;
    s.mesh.ny = 10;
    let plate = PlateSystem::new(&s).unwrap();
    assert_eq!(plate.disc.dof_count, 495);
    assert_eq!(plate.clamp.len(), 33);
}

/// Conforming elements give upper bounds, so f_h ≥ f_ref up to the references' own accuracy
/// (5 digits: 2e-5 relative). Meshes as fine as the paper's (Argyris 10 × 7, FVS 14 × 10 on
/// 0.4 × 0.2, the same cell counts turned or squared for the other plates). Argyris: 0.02 % at
/// 10 × 7 on the 0.4 × 0.2 plate (`docs/elements.md` §7); we allow 0.05 % for the coarser cells of
/// the turned plates. FVS converges like h² (0.05–0.8 % at 14 × 10); we allow 1.5 %.
#[test]
fn frequencies_match_the_references_for_three_aspect_ratios() {
    let meshes = [[(10, 7), (14, 10)], [(7, 10), (10, 14)], [(7, 7), (10, 10)]];
    for (((lx, ly), reference), mesh) in REFERENCE.into_iter().zip(meshes) {
        for ((element, tolerance), (nx, ny)) in
            [(ElementKind::Argyris, 5e-4), (ElementKind::Fvs, 1.5e-2)]
                .into_iter()
                .zip(mesh)
        {
            let f = frequencies(element, lx, ly, nx, ny);
            for k in 0..6 {
                let relative = (f[k] - reference[k]) / reference[k];
                println!(
                    "{lx}×{ly} {element:?} {nx}×{ny} mode {}: {:.3} Hz vs {} ({relative:+.2e})",
                    k + 1,
                    f[k],
                    reference[k]
                );
                assert!(
                    relative >= -2e-5,
                    "not an upper bound: mode {} {relative:e}",
                    k + 1
                );
                assert!(relative <= tolerance, "mode {} off by {relative:e}", k + 1);
            }
        }
    }
}

/// Square cantilever, ν = 0.3: Barton's series values λ = ω a²√(ρe/D) (as quoted by the Code_Aster
/// case SDLS01) are upper bounds 0.4–0.6 % above the converged values: a fine Argyris mesh must lie
/// below them and within 1 %.
#[test]
fn square_plate_agrees_with_barton() {
    let barton = [3.492, 8.525, 21.43, 27.33, 31.11, 54.44];
    let s = Scene::default();
    let scale = 0.2f64.powi(2) * (s.areal_mass() / s.bending_stiffness()).sqrt();
    let f = frequencies(ElementKind::Argyris, 0.2, 0.2, 8, 8);
    for k in 0..6 {
        let lambda = 2.0 * std::f64::consts::PI * f[k] * scale;
        println!("mode {}: λ = {lambda:.4} (Barton {})", k + 1, barton[k]);
        assert!(lambda < barton[k] && lambda > 0.99 * barton[k]);
    }
}

/// Observed convergence orders of the frequencies over meshes halving h (4 × 2 → 16 × 8 on the
/// 0.4 × 0.2 plate). The reduced FVS is complete only to P2, so eigenvalues converge like h²: we
/// assert orders in [1.6, 2.4] for the torsion and second-torsion modes (2 and 4), measured 1.8–2.0.
/// The first bending mode converges more slowly for both elements (FVS ≈ 1.3–1.4, Argyris ≈ 2–2.4,
/// far below Argyris's smooth-solution order): its eigenfunction is singular at the two corners where
/// the clamped edge meets a free edge, which uniform meshes do not resolve. For it we assert only
/// an order above 1 (FVS) and 1.8 (Argyris). Finer Argyris meshes reach the references' 5 digits.
#[test]
fn frequencies_converge_under_refinement() {
    let reference = REFERENCE[0].1;
    let errors = |element| -> Vec<Vec<f64>> {
        [(4, 2), (8, 4), (16, 8)]
            .iter()
            .map(|&(nx, ny)| {
                let f = frequencies(element, 0.4, 0.2, nx, ny);
                (0..6)
                    .map(|k| (f[k] - reference[k]) / reference[k])
                    .collect()
            })
            .collect()
    };
    for (element, checks) in [
        (
            ElementKind::Fvs,
            vec![(0, 1.0, 2.4), (1, 1.6, 2.4), (3, 1.6, 2.4)],
        ),
        (ElementKind::Argyris, vec![(0, 1.8, 3.0)]),
    ] {
        let e = errors(element);
        for (k, low, high) in checks {
            let orders: Vec<f64> = e.windows(2).map(|w| (w[0][k] / w[1][k]).log2()).collect();
            println!(
                "{element:?} mode {}: relative errors {:.2e} {:.2e} {:.2e}, orders {:.2} {:.2}",
                k + 1,
                e[0][k],
                e[1][k],
                e[2][k],
                orders[0],
                orders[1]
            );
            for order in orders {
                assert!(
                    order >= low && order <= high,
                    "{element:?} mode {}: order {order}",
                    k + 1
                );
            }
        }
    }
}
