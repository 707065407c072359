//! The stepper as a component that must not be fooled: a step whose result overflows is refused
//! and changes nothing; a saved state is untrusted input, refused by field unless it is
//! physically possible, while every state the stepper itself produces restores; the initial
//! outputs include the preload's contact; and a step solved less exactly than normal says so.

mod common;

use plate_impact::contact::PdasSettings;
use plate_impact::element::ElementKind;
use plate_impact::scene::{LinearChoice, Scene};
use plate_impact::scheme::{State, StepPath, Stepper, MAX_STEP_INDEX, RESTORE_BOUND_TOLERANCE};

fn scene(name: &str, linear: LinearChoice) -> Scene {
    let mut s = common::paper_scene(name, ElementKind::Argyris);
    s.solver.linear = linear;
    s
}

fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

/// Two steppers hold the same state, bit for bit, and report the same outputs.
fn assert_same(a: &Stepper, b: &Stepper, what: &str) {
    let (sa, sb) = (a.state(), b.state());
    assert!(
        same_bits(&sa.previous, &sb.previous)
            && same_bits(&sa.current, &sb.current)
            && same_bits(&sa.base, &sb.base)
            && same_bits(&sa.forces, &sb.forces)
            && sa.step_index == sb.step_index
            && sa.active_set == sb.active_set
            && a.outputs() == b.outputs(),
        "{what}: the steppers differ"
    );
}

/// Without obstacles nothing bounds the base: z = ±1e308 m makes the forcing overflow. The step
/// is refused with a message naming what overflowed and the base value, the stepper is exactly as
/// before, and it continues bit-identically to a stepper that never saw the bad step. A pressure
/// of 1e308 Pa is refused the same way (its response overflows within two steps).
#[test]
fn a_step_that_overflows_is_refused_and_changes_nothing() {
    for linear in [LinearChoice::Modal, LinearChoice::Sparse] {
        let mut s = scene("forced-35hz", linear);
        s.obstacle.lower_enabled = false;
        s.obstacle.upper_enabled = false;
        let dt = s.solver.time_step;
        let (mut stepper, _) = state_after(&s, 20);
        let (mut twin, _) = state_after(&s, 20);
        for bad in [1e308, -1e308] {
            let err = stepper.step(bad).unwrap_err().to_string();
            println!("{linear:?}: {err}");
            assert!(err.contains("non-finite") && err.contains("1e308"), "{err}");
            assert_same(&stepper, &twin, "after the refused base");
        }
        for n in 21..=40 {
            let z = s.builtin_base(n as f64 * dt);
            stepper.step(z).unwrap();
            twin.step(z).unwrap();
        }
        assert_same(&stepper, &twin, "continuing after the refused steps");
        stepper.set_pressure(1e308).unwrap();
        let z = s.builtin_base(41.0 * dt);
        let err = match stepper.step(z) {
            Err(e) => e,
            Ok(_) => stepper.step(s.builtin_base(42.0 * dt)).unwrap_err(),
        };
        assert!(err.to_string().contains("non-finite"), "{err}");
        let outputs = stepper.outputs();
        assert!(
            [
                outputs.corner1,
                outputs.energy_total,
                outputs.energy_kinetic
            ]
            .iter()
            .all(|v| v.is_finite()),
            "{outputs:?}"
        );
        // A state whose fields are finite but whose energy overflows is refused too.
        let mut huge = stepper.state();
        for v in huge.current.iter_mut() {
            *v = 1e200;
        }
        let err = stepper.restore(&huge).unwrap_err().to_string();
        assert!(
            err.contains("current") && err.contains("finite energies"),
            "{err}"
        );
    }
}

/// A state taken after `steps` steps of `scene`.
fn state_after(scene: &Scene, steps: usize) -> (Stepper, State) {
    let mut stepper = Stepper::new(scene, 0.0).unwrap();
    for n in 1..=steps {
        stepper
            .step(scene.builtin_base(n as f64 * scene.solver.time_step))
            .unwrap();
    }
    let state = stepper.state();
    (stepper, state)
}

/// A change made to a saved state.
type Corruption = Box<dyn Fn(&mut State)>;

/// Every corruption of a saved state is refused with a message naming the field, and the
/// stepper it was offered to is unchanged (it still continues bit-identically).
#[test]
fn a_crafted_state_is_refused_by_field_and_changes_nothing() {
    for linear in [LinearChoice::Modal, LinearChoice::Sparse] {
        let s = scene("forced-35hz", linear);
        // A state in contact: find a step after which some vertex is at an obstacle.
        let (source, good) = {
            let mut stepper = Stepper::new(&s, 0.0).unwrap();
            let mut n = 0;
            loop {
                n += 1;
                let report = stepper
                    .step(s.builtin_base(n as f64 * s.solver.time_step))
                    .unwrap();
                if report.active >= 2 {
                    break;
                }
            }
            let state = stepper.state();
            (stepper, state)
        };
        let lower_contact = good.active_set.iter().position(|&c| c == -1);
        let contact = good.active_set.iter().position(|&c| c != 0).unwrap();
        let free = good.active_set.iter().position(|&c| c == 0).unwrap();
        let (mut target, _) = state_after(&s, 7);
        let mut reference = state_after(&s, 7).0;
        let mut cases: Vec<(&str, Corruption, &str)> = vec![
            (
                "NaN field",
                Box::new(|st| st.current[3] = f64::NAN),
                "current[3]",
            ),
            (
                "infinite field",
                Box::new(|st| st.previous[0] = f64::INFINITY),
                "previous[0]",
            ),
            ("NaN base", Box::new(|st| st.base[0] = f64::NAN), "base[0]"),
            (
                "base in the obstacle",
                Box::new(|st| st.base[1] = 0.02),
                "base[1]",
            ),
            (
                "NaN pressure",
                Box::new(|st| st.pressure[1] = f64::NAN),
                "pressure[1]",
            ),
            (
                "NaN force",
                Box::new(|st| st.forces[0] = f64::NAN),
                "forces[0]",
            ),
            (
                "short field",
                Box::new(|st| {
                    st.current.pop();
                }),
                "current",
            ),
            (
                "short forces",
                Box::new(|st| {
                    st.forces.pop();
                }),
                "forces",
            ),
            (
                "contact code",
                Box::new(|st| st.active_set[0] = 7),
                "active_set[0]",
            ),
            (
                "force at a free vertex",
                Box::new(move |st| st.forces[free] = 100.0),
                "forces[",
            ),
            (
                "force of the wrong sign",
                Box::new(move |st| st.forces[contact] *= -2.0),
                "forces[",
            ),
            (
                "step index",
                Box::new(|st| st.step_index = MAX_STEP_INDEX + 1),
                "step_index",
            ),
            (
                "n = 0 not at rest",
                Box::new(|st| st.step_index = 0),
                "step_index",
            ),
            (
                "obstacle level",
                Box::new(|st| st.scene.obstacle.lower = f64::NAN),
                "obstacle.lower",
            ),
            (
                "fixed parameter",
                Box::new(|st| st.scene.material.density = 7000.0),
                "scene",
            ),
            (
                "backend",
                Box::new(move |st| {
                    st.backend = match linear {
                        LinearChoice::Modal => LinearChoice::Sparse,
                        _ => LinearChoice::Modal,
                    }
                }),
                "backend",
            ),
            (
                "field deep in the obstacle",
                Box::new(|st| {
                    for v in st.current.iter_mut() {
                        *v *= 1e3;
                    }
                }),
                "current[contact point",
            ),
        ];
        if let Some(i) = lower_contact {
            cases.push((
                "upward force off the obstacle code",
                Box::new(move |st| st.active_set[i] = 1),
                "forces[",
            ));
        }
        for (what, corrupt, field) in &cases {
            let mut bad = good.clone();
            corrupt(&mut bad);
            let err = target.restore(&bad).unwrap_err().to_string();
            println!("{linear:?} {what}: {err}");
            assert!(
                err.contains(field),
                "{what}: {field:?} missing from {err:?}"
            );
            assert_same(&target, &reference, what);
        }
        // The good state restores, and continues as its source does.
        target.restore(&good).unwrap();
        let mut source = source;
        for n in 1..=50 {
            let t = (good.step_index + n) as f64 * s.solver.time_step;
            target.step(s.builtin_base(t)).unwrap();
            source.step(s.builtin_base(t)).unwrap();
        }
        assert_same(&target, &source, "after restoring the good state");
        reference.step(0.0).unwrap();
    }
}

/// Every state the stepper produces restores, bit-exactly, also with restitution, a preload in
/// contact, a load, and obstacles moved between steps: the restore checks must never refuse a
/// legitimate state. Also prints how close the states come to the restore tolerances.
#[test]
fn every_state_the_stepper_produces_restores() {
    let mut cases = Vec::new();
    for linear in [LinearChoice::Modal, LinearChoice::Sparse] {
        cases.push(("forced-35hz", scene("forced-35hz", linear)));
        let mut s = scene("energy", linear);
        s.solver.restitution = 0.7;
        cases.push(("energy e = 0.7", s));
        let mut s = scene("forced-35hz", linear);
        s.initial.preload_pressure = -1e5;
        s.load.pressure = -2e4;
        s.obstacle.upper_enabled = false;
        cases.push(("preload in contact, loaded", s));
    }
    for (name, s) in cases {
        let mut stepper = Stepper::new(&s, 0.0).unwrap();
        let mut check = Stepper::new(&s, 0.0).unwrap();
        let (mut worst_bound, mut restored) = (0.0f64, 0);
        for n in 1..=1500 {
            if n == 700 {
                stepper.set_obstacles(-0.012, 0.011).unwrap();
            }
            let state = stepper.state();
            check
                .restore(&state)
                .unwrap_or_else(|e| panic!("{name}, n = {n}: {e}"));
            assert!(
                check.state() == state,
                "{name}, n = {n}: restore is not exact"
            );
            restored += 1;
            let g1 = stepper.scene().obstacle.lower;
            let below = stepper
                .constrained_displacements()
                .iter()
                .map(|u| g1 - u)
                .fold(f64::NEG_INFINITY, f64::max);
            worst_bound = worst_bound.max(below);
            stepper
                .step(s.builtin_base(n as f64 * s.solver.time_step))
                .unwrap();
        }
        let tolerance = RESTORE_BOUND_TOLERANCE * 0.02;
        println!(
            "{name} ({:?}): {restored} states restored; deepest vertex below g1 {worst_bound:.2e} m \
             (restore tolerance {tolerance:.1e} m, checked only for e = 0)",
            s.solver.linear
        );
    }
}

/// A plate pressed onto the lower obstacle by the preload and kept under the same pressure, base
/// fixed, stays in its static equilibrium: the contact forces at t0 (the static multipliers λ, in
/// N) must be the forces of every later step, the start step included (whose QP multiplier is
/// ½Δt²λ, not Δt²λ). Measured agreement ≈ 1e-10 relative; 1e-7 allows the round-off of a
/// 708-dof solve while catching any factor or unit error.
#[test]
fn initial_outputs_show_the_preload_contact() {
    for linear in [LinearChoice::Modal, LinearChoice::Sparse] {
        let mut s = scene("energy", linear);
        s.initial.preload_pressure = -1e5;
        s.load.pressure = -1e5;
        let mut stepper = Stepper::new(&s, 0.0).unwrap();
        let initial = stepper.outputs();
        let static_forces = stepper.contact_forces().to_vec();
        println!(
            "{linear:?}: at t0 {} vertices in contact, {:.3} N",
            initial.active_nodes, initial.contact_force
        );
        assert!(
            initial.active_nodes > 0,
            "the preload presses the plate onto g1"
        );
        assert!(initial.contact_force > 0.0, "the lower obstacle pushes up");
        assert!(stepper.initial_warning().is_none());
        assert_eq!(
            initial.contact_force,
            static_forces.iter().sum::<f64>(),
            "the output is the sum of the forces"
        );
        let scale = static_forces.iter().fold(0.0f64, |a, f| a.max(f.abs()));
        for n in 1..=5 {
            let report = stepper.step(0.0).unwrap();
            assert_eq!(report.active, initial.active_nodes, "step {n}");
            let worst = stepper
                .contact_forces()
                .iter()
                .zip(&static_forces)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0f64, f64::max);
            println!(
                "  step {n}: forces differ from λ by {:.2e} relative",
                worst / scale
            );
            assert!(worst <= 1e-7 * scale, "step {n}: {worst:e} N");
        }
    }
}

/// With the active-set method capped at one iteration and no safeguard, the steps it cannot solve
/// go to clarabel, each with a warning; their results equal the normal path's from the same state
/// (to 1e-9 m, the agreement the two exact solvers have everywhere). With the default settings no
/// step of the run warns.
#[test]
fn a_fallback_step_warns_and_agrees_with_the_normal_path() {
    for linear in [LinearChoice::Modal, LinearChoice::Sparse] {
        let s = scene("forced-35hz", linear);
        let mut capped = Stepper::new(&s, 0.0).unwrap();
        capped.set_active_set_settings(PdasSettings {
            max_iter: 1,
            safeguard: false,
            ..PdasSettings::default()
        });
        let mut normal = Stepper::new(&s, 0.0).unwrap();
        let (mut fallbacks, mut worst) = (0, 0.0f64);
        for n in 1..=1500 {
            let z = s.builtin_base(n as f64 * s.solver.time_step);
            normal.restore(&capped.state()).unwrap();
            let report = capped.step(z).unwrap();
            let normal_report = normal.step(z).unwrap();
            assert!(
                normal_report.warning.is_none(),
                "step {n}: {normal_report:?}"
            );
            match report.path {
                StepPath::ClarabelFallback => {
                    fallbacks += 1;
                    let warning = report.warning.expect("a fallback step warns");
                    assert!(warning.contains("did not converge"), "{warning}");
                    let diff = common::largest_vertex_difference(&capped, &normal);
                    worst = worst.max(diff);
                }
                _ => assert!(report.warning.is_none(), "step {n}: {report:?}"),
            }
        }
        println!("{linear:?}: {fallbacks} fallback steps, worst difference {worst:.2e} m");
        assert!(fallbacks > 5, "the cap must send steps to the fallback");
        assert!(
            worst <= 1e-9,
            "fallback and normal path differ by {worst:e} m"
        );
    }
}

/// An obstacle may not move to where the plate was one step ago: the scheme's velocity
/// (u_n − u_{n−1})/Δt involves that level, and a restored state is checked on both levels.
#[test]
fn an_obstacle_may_not_move_into_the_previous_level() {
    let mut s = scene("energy", LinearChoice::Auto);
    s.obstacle.upper_enabled = true;
    s.obstacle.upper = 0.05;
    let mut stepper = Stepper::new(&s, 0.0).unwrap();
    stepper.step(0.0).unwrap();
    // The preload lifted the plate; released, it falls: the previous level is above the current.
    let top = |u: &[f64]| u.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let before = top(&stepper.constrained_displacements());
    stepper.step(0.0).unwrap();
    let now = top(&stepper.constrained_displacements());
    assert!(now < before, "the plate falls");
    let level = 0.5 * (now + before);
    let err = stepper.set_obstacles(-0.01, level).unwrap_err().to_string();
    assert!(err.contains("obstacle.upper"), "{err}");
    stepper.set_obstacles(-0.01, before + 1e-6).unwrap();
}

/// A move that would leave the base of the previous level outside the gap is refused: the state
/// taken after it would be one the stepper refuses to restore. A 1×1 plate lifted by a preload
/// steps to z = −5 mm and back to 0; raising the lower obstacle to −3 mm clears every vertex of
/// both levels and the current base, but not z_{n−1} = −5 mm. A move that clears both bases is
/// taken, and the state after it restores.
#[test]
fn an_obstacle_may_not_move_past_the_previous_base() {
    let mut s = Scene::default();
    (s.mesh.nx, s.mesh.ny) = (1, 1);
    s.initial.preload_pressure = 3e4;
    let mut stepper = Stepper::new(&s, 0.0).unwrap();
    stepper.step(-0.005).unwrap();
    stepper.step(0.0).unwrap();
    let lowest = stepper
        .constrained_displacements()
        .into_iter()
        .fold(f64::INFINITY, f64::min);
    assert!(lowest > -0.003, "the plate is above −3 mm: {lowest} m");
    let err = stepper.set_obstacles(-0.003, 0.01).unwrap_err().to_string();
    assert!(err.contains("z = -0.005 m"), "{err}");
    assert_eq!(
        stepper.scene().obstacle.lower,
        s.obstacle.lower,
        "a refused move changes nothing"
    );
    stepper.set_obstacles(-0.006, 0.01).unwrap();
    let state = stepper.state();
    stepper.restore(&state).unwrap();
}
