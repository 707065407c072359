//! The time scheme against the laws of docs/scheme.md: energy conservation without contact, energy decay
//! with contact, bounds and force signs, fast path = clarabel, second order in Δt, symmetry.

mod common;

use plate_impact::element::ElementKind;
use plate_impact::scene::{LinearChoice, Scene};
use plate_impact::scheme::{StepPath, Stepper};

fn scene(name: &str, element: ElementKind) -> Scene {
    common::paper_scene(name, element)
}

fn run_energy(stepper: &mut Stepper, steps: usize) -> Vec<f64> {
    let mut energies = vec![stepper.outputs().energy_total];
    for _ in 0..steps {
        let z = stepper
            .scene()
            .builtin_base(stepper.time() + stepper.scene().solver.time_step);
        stepper.step(z).unwrap();
        energies.push(stepper.outputs().energy_total);
    }
    energies
}

/// Without contact, fixed base, no load: E_{n+½} is conserved. The scheme conserves it exactly in
/// exact arithmetic; in floating point each step adds round-off of order ε·cond, so over 10⁴ steps
/// a relative drift of 1e-10 leaves a margin of about 100 over what we measure.
#[test]
fn energy_is_conserved_without_contact() {
    for element in [ElementKind::Argyris, ElementKind::Fvs] {
        for linear in [LinearChoice::Modal, LinearChoice::Sparse] {
            let mut s = scene("energy", element);
            s.obstacle.lower_enabled = false;
            s.solver.linear = linear;
            let mut stepper = Stepper::new(&s, 0.0).unwrap();
            let energies = run_energy(&mut stepper, 10_000);
            let reference = energies[1];
            let drift = energies[1..]
                .iter()
                .map(|e| (e - reference).abs())
                .fold(0.0, f64::max)
                / reference.abs();
            println!(
                "{element:?} {linear:?}: E = {reference:.6e} J, max relative drift {drift:.2e}"
            );
            assert!(drift <= 1e-10, "{element:?} {linear:?}: drift {drift:e}");
        }
    }
}

/// With contact and a fixed base, E_{n+½} never increases (take w = u_{n−1} in the inequality):
/// allowed increase per step is round-off, 1e-12 of the initial energy.
#[test]
fn energy_never_increases_with_contact() {
    for element in [ElementKind::Argyris, ElementKind::Fvs] {
        let mut stepper = Stepper::new(&scene("energy", element), 0.0).unwrap();
        let mut qp_steps = 0;
        let mut energies = vec![stepper.outputs().energy_total];
        for _ in 0..5000 {
            let report = stepper.step(0.0).unwrap();
            qp_steps += usize::from(report.path != StepPath::Unconstrained);
            energies.push(stepper.outputs().energy_total);
        }
        let tolerance = 1e-12 * energies[1].abs();
        let worst = energies[1..]
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(f64::NEG_INFINITY, f64::max);
        println!("{element:?}: {qp_steps} contact steps, E {:.4} → {:.4} J, worst increase {worst:.2e} J", energies[1], energies.last().unwrap());
        assert!(qp_steps > 50, "the scene must have impacts");
        assert!(
            worst <= tolerance,
            "{element:?}: energy rose by {worst:e} J"
        );
        assert!(
            *energies.last().unwrap() < 0.9 * energies[1],
            "impacts dissipate energy"
        );
    }
}

/// Every step satisfies every bound (to 1e-12 m: the active-set solve puts active vertices on the
/// bound up to round-off of a few ulps of 0.01 m) and the forces have the right signs.
#[test]
fn bounds_hold_and_forces_have_the_right_signs() {
    for element in [ElementKind::Argyris, ElementKind::Fvs] {
        let mut s = scene("forced-35hz", element);
        s.stop_time = 0.3;
        let mut stepper = Stepper::new(&s, 0.0).unwrap();
        let (g1, g2) = (s.obstacle.lower, s.obstacle.upper);
        let (mut lower_hits, mut upper_hits) = (0, 0);
        for n in 1..=3000 {
            stepper
                .step(s.builtin_base(n as f64 * s.solver.time_step))
                .unwrap();
            for (u, f) in stepper
                .constrained_displacements()
                .iter()
                .zip(stepper.contact_forces())
            {
                assert!(*u >= g1 - 1e-12 && *u <= g2 + 1e-12, "step {n}: u = {u}");
                if *f > 0.0 {
                    lower_hits += 1;
                    assert!(
                        (u - g1).abs() <= 1e-12,
                        "upward force off the lower obstacle: u = {u}"
                    );
                } else if *f < 0.0 {
                    upper_hits += 1;
                    assert!(
                        (u - g2).abs() <= 1e-12,
                        "downward force off the upper obstacle: u = {u}"
                    );
                }
            }
        }
        println!("{element:?}: {lower_hits} lower and {upper_hits} upper vertex contacts");
        assert!(
            lower_hits > 0 && upper_hits > 0,
            "the 35 Hz scene hits both obstacles"
        );
    }
}

/// The fast path (active set on the Delassus operator) and clarabel solve the same QP: on the first
/// 40 contact steps of each run, from the same state, u_{n+1} agrees to 1e-9 m. clarabel alone,
/// with its tolerances at 1e-12, leaves a few 1e-8 m on these steps; polished on its active set
/// with a KKT certificate (src/contact/clarabel.rs) it is exact to round-off, and we measure
/// ≈ 1e-13 m, so 1e-9 m is a loose bound that still catches any wrong active set (millimetres).
#[test]
fn fast_path_matches_clarabel_on_contact_steps() {
    for (name, element) in [
        ("forced-35hz", ElementKind::Argyris),
        ("forced-35hz", ElementKind::Fvs),
        ("energy", ElementKind::Argyris),
        ("energy", ElementKind::Fvs),
    ] {
        common::assert_fast_path_matches_clarabel(
            &format!("{name} {element:?}"),
            &scene(name, element),
            4000,
            40,
        );
    }
}

/// The same on a modal basis above the dense limit (Argyris 18 × 12, 2 083 free dofs), whose
/// steps with a QP start every vertex from a partial-sum stand-in and correct q from the rows of
/// C (src/scheme/modal/): the same 1e-9 m bound over 10 contact steps (a stand-in that hid a
/// contact would show as millimetres).
#[test]
fn fast_path_matches_clarabel_on_a_large_modal_basis() {
    let mut s = scene("forced-35hz", ElementKind::Argyris);
    (s.mesh.nx, s.mesh.ny) = (18, 12);
    s.solver.linear = LinearChoice::Modal;
    common::assert_fast_path_matches_clarabel("Argyris 18×12 modal", &s, 4000, 10);
}

/// Second-order convergence in Δt without contact. The base follows the smooth start
/// z(t) = c (1 − cos 2πft)²/4 (z, ż, z̈ zero at t = 0, so no mode is hit impulsively and the stiff
/// modes follow quasi-statically), f = 50 Hz near the first mode. Corner displacement at
/// t = 0.02 s for Δt = 4, 2, 1 × 1e-5 s against Δt = 1.25e-6 s: observed orders within 0.1 of 2.
#[test]
fn second_order_in_time_without_contact() {
    let horizon = 0.02;
    let base = |t: f64| 0.004 * (1.0 - (2.0 * std::f64::consts::PI * 50.0 * t).cos()).powi(2) / 4.0;
    let corner_at = |dt: f64| {
        let mut s = scene("forced", ElementKind::Argyris);
        s.obstacle.lower_enabled = false;
        s.obstacle.upper_enabled = false;
        s.base.amplitude = 0.0;
        s.solver.time_step = dt;
        let mut stepper = Stepper::new(&s, 0.0).unwrap();
        let steps = (horizon / dt).round() as usize;
        for n in 1..=steps {
            stepper.step(base(n as f64 * dt)).unwrap();
        }
        stepper.outputs().corner1
    };
    let reference = corner_at(1.25e-6);
    let errors: Vec<f64> = [4e-5, 2e-5, 1e-5]
        .iter()
        .map(|&dt| (corner_at(dt) - reference).abs())
        .collect();
    for pair in errors.windows(2) {
        let order = (pair[0] / pair[1]).log2();
        println!("errors {:.3e} → {:.3e}: order {order:.3}", pair[0], pair[1]);
        assert!((order - 2.0).abs() <= 0.1, "observed order {order}");
    }
}

/// The plate and the loads are symmetric about y = Ly/2: on the symmetric quadrilateral mesh the
/// two free corners move identically up to round-off amplified by the impacts (1e-9 m).
#[test]
fn symmetric_scene_gives_equal_corners() {
    let s = scene("forced-35hz", ElementKind::Fvs);
    let mut stepper = Stepper::new(&s, 0.0).unwrap();
    let mut worst = 0.0f64;
    for n in 1..=3000 {
        stepper
            .step(s.builtin_base(n as f64 * s.solver.time_step))
            .unwrap();
        worst = worst.max((stepper.outputs().corner1 - stepper.outputs().corner2).abs());
    }
    println!("worst corner asymmetry {worst:.2e} m");
    assert!(worst <= 1e-9);
}

/// The two linear backends run the same scheme: on the contact-heavy 35 Hz scene the modal one
/// (eigenbasis, screened bound check) and the sparse one (Cholesky, exact bound check) stay within
/// 1e-9 m of each other over 4000 steps (measured ≈ 1e-12 m: eigenbasis round-off, amplified by
/// the impacts). A screening that wrongly accepted a violating step would show here as a missed
/// contact, i.e. millimetres.
#[test]
fn modal_and_sparse_backends_agree_on_a_contact_scene() {
    for element in [ElementKind::Argyris, ElementKind::Fvs] {
        let mut s = scene("forced-35hz", element);
        s.solver.linear = LinearChoice::Modal;
        let mut modal = Stepper::new(&s, 0.0).unwrap();
        s.solver.linear = LinearChoice::Sparse;
        let mut sparse = Stepper::new(&s, 0.0).unwrap();
        let (mut worst, mut screened) = (0.0f64, 0);
        for n in 1..=4000 {
            let z = s.builtin_base(n as f64 * s.solver.time_step);
            let report = modal.step(z).unwrap();
            sparse.step(z).unwrap();
            screened += usize::from(!report.bounds_evaluated);
            let diff = common::largest_vertex_difference(&modal, &sparse);
            worst = worst.max(diff);
        }
        println!("{element:?}: {screened} of 4000 steps screened, worst difference {worst:.2e} m");
        assert!(
            screened > 1000,
            "the screening should prove most contact-free steps"
        );
        assert!(worst <= 1e-9, "{element:?}: backends differ by {worst:e} m");
    }
}

/// Tunable parameters between steps: a new pressure acts from the next step on, so reading the
/// outputs right after setting it must give the same numbers (they describe the last step); an
/// obstacle moved into the plate is refused with the parameter's name, and a valid move is taken.
#[test]
fn tunable_parameters_take_effect_cleanly() {
    let mut s = scene("energy", ElementKind::Argyris);
    s.obstacle.upper_enabled = true;
    s.obstacle.upper = 0.03;
    let mut stepper = Stepper::new(&s, 0.0).unwrap();
    for _ in 0..10 {
        stepper.step(0.0).unwrap();
    }
    let before = stepper.outputs();
    stepper.set_pressure(5e4).unwrap();
    assert_eq!(stepper.outputs(), before, "outputs changed without a step");
    // The plate is lifted by the preload: its corners are far above 5 mm.
    assert!(before.corner1 > 0.005);
    let err = stepper.set_obstacles(-0.01, 0.005).unwrap_err();
    assert!(err.to_string().contains("obstacle.upper"), "{err}");
    assert_eq!(
        stepper.scene().obstacle.upper,
        s.obstacle.upper,
        "a refused move changes nothing"
    );
    stepper.set_obstacles(-0.02, 0.04).unwrap();
    assert_eq!(stepper.scene().obstacle.lower, -0.02);
    stepper.step(0.0).unwrap();
}

/// The small-step regime, where one screening proof covers many steps (the modal backend's reach,
/// src/scheme/modal/reach.rs): over 0.04 s of the damped forced 35 Hz scene at Δt = 1e-6 s on
/// both paper meshes (the first impacts), every step the screening accepted without evaluating the
/// bounds has every constrained vertex inside the obstacles when evaluated exactly, most steps are
/// accepted that way, and the modal run stays within 1e-7 m of the sparse backend's, which checks
/// every bound exactly: the two differ by round-off that the impacts amplify (9.9e-9 m after 0.1 s
/// on Argyris), while a wrongly accepted step would miss a contact by a good part of the 5 mm gap.
#[test]
fn screening_over_many_steps_accepts_only_contact_free_steps() {
    for element in [ElementKind::Argyris, ElementKind::Fvs] {
        let mut s = scene("forced-35hz", element);
        s.solver.time_step = 1e-6;
        s.damping.mass_proportional = 6.6925;
        s.damping.stiffness_proportional = 6.2984e-7;
        s.solver.linear = LinearChoice::Modal;
        let mut modal = Stepper::new(&s, 0.0).unwrap();
        s.solver.linear = LinearChoice::Sparse;
        let mut sparse = Stepper::new(&s, 0.0).unwrap();
        let (lower, upper) = (s.obstacle.lower, s.obstacle.upper);
        let (mut screened, mut contacts, mut worst) = (0, 0, 0.0f64);
        let steps = 40_000;
        for n in 1..=steps {
            let z = s.builtin_base(n as f64 * s.solver.time_step);
            let report = modal.step(z).unwrap();
            contacts += usize::from(report.active > 0);
            if !report.bounds_evaluated {
                screened += 1;
                let u = modal.constrained_displacements();
                assert!(
                    u.iter().all(|&u| u >= lower && u <= upper),
                    "{element:?}: step {n} accepted unchecked with a vertex past an obstacle"
                );
            }
            sparse.step(z).unwrap();
            worst = worst.max(common::largest_vertex_difference(&modal, &sparse));
        }
        println!(
            "{element:?}: {screened} of {steps} steps screened, {contacts} with contact, \
             worst difference to sparse {worst:.2e} m"
        );
        assert!(contacts > 100, "{element:?}: the run should impact");
        assert!(
            screened > steps * 8 / 10,
            "{element:?}: the reach should cover most steps"
        );
        assert!(worst <= 1e-7, "{element:?}: backends differ by {worst:e} m");
    }
}
