//! Stability matrix: stiff and extreme scenes that the stepper must survive, or refuse
//! with an error that names the parameter and its limit.
//!
//! Every run goes through [`run`], which checks after each step: all outputs, constrained
//! displacements and contact forces finite; every vertex within the obstacles (docs/scheme.md)
//! to 1e-9 of the gap, for every restitution e; and the energy law, for every e: with a fixed
//! base and no load, E_{n+½} never rises by more than round-off, 1e-11 of the energy scale (the
//! largest |E| seen) per step; with forcing, E stays bounded (no growth beyond a stated factor).
//! Horizons are short: the matrix is a survival test, not a convergence study.

use plate_impact::element::ElementKind;
use plate_impact::error::Error;
use plate_impact::scene::{LinearChoice, QpChoice, Scene};
use plate_impact::scheme::Stepper;
use plate_impact::system::PlateSystem;
use std::time::Instant;

/// Per-step round-off allowed on the energy law, relative to the energy scale: the sparse backend
/// measured 3e-11 at Δt = 1e-2 s (A ≈ ½Δt²K, ill-conditioned), 2e-10 on the 60 × 30 FVS mesh and
/// 9e-10 on the 60 × 30 Argyris mesh (16651 free dofs).
const ENERGY_ROUND_OFF: f64 = 5e-9;
/// Bound violation allowed, relative to the gap g2 − g1 (or |g| with one obstacle).
const BOUND_TOLERANCE: f64 = 1e-9;

/// What a run measured.
#[derive(Debug, Default)]
struct Measured {
    steps: usize,
    /// Largest bound violation over the gap.
    violation: f64,
    /// E after the first step and at the end (J).
    energy_first: f64,
    energy_last: f64,
    /// Largest |E| seen (J).
    energy_scale: f64,
    /// Largest single-step increase of E over the scale.
    worst_rise: f64,
    /// Largest E over the first and over the second half of the run (J).
    energy_max_first_half: f64,
    energy_max_second_half: f64,
    /// Most vertices in contact at once, and steps with any contact.
    most_active: usize,
    contact_steps: usize,
    constrained: usize,
    setup_seconds: f64,
    run_seconds: f64,
}

/// Sets the scene up and runs `steps` steps with base displacement z(t) = builtin(t) + extra(t).
/// Panics (fails the test) on a NaN/inf, a bound violation or a broken energy law; returns the
/// library's error unchanged when it refuses the scene or a step.
fn run(scene: &Scene, steps: usize, extra: impl Fn(f64) -> f64) -> Result<Measured, Error> {
    let base = |t: f64| scene.builtin_base(t) + extra(t);
    let clock = Instant::now();
    let mut stepper = Stepper::new(scene, base(0.0))?;
    let mut m = Measured {
        setup_seconds: clock.elapsed().as_secs_f64(),
        constrained: stepper.constrained_count(),
        ..Measured::default()
    };
    let clock = Instant::now();
    let fixed_base = scene.base.amplitude == 0.0 && (0..4).all(|k| extra(k as f64) == 0.0);
    // A constant load keeps the law (docs/scheme.md: E includes −½Fᵀ(u_{n+1} + u_n)).
    let unforced = fixed_base;
    let (g1, g2) = (scene.lower_obstacle(), scene.upper_obstacle());
    let tolerance = BOUND_TOLERANCE * scene.gap();
    let mut energies = Vec::with_capacity(steps);
    let dt = scene.solver.time_step;
    for n in 1..=steps {
        let report = stepper.step(base(n as f64 * dt))?;
        let o = stepper.outputs();
        let values = [
            o.corner1,
            o.corner2,
            o.edge_mid,
            o.energy_kinetic,
            o.energy_elastic,
            o.energy_total,
            o.contact_force,
            o.base_force,
            o.base_work,
            o.load_work,
            o.contact_loss,
            o.damping_loss,
        ];
        assert!(
            values.iter().all(|v| v.is_finite()),
            "step {n}: non-finite output {o:?}"
        );
        let next = stepper.constrained_displacements();
        assert!(
            next.iter()
                .chain(stepper.contact_forces())
                .all(|v| v.is_finite()),
            "step {n}: non-finite displacement or contact force"
        );
        for (i, &u) in next.iter().enumerate() {
            let below = g1.map_or(0.0, |g| g - u);
            let above = g2.map_or(0.0, |g| u - g);
            m.violation = m.violation.max(below.max(above) / scene.gap());
            assert!(
                below <= tolerance && above <= tolerance,
                "step {n}, vertex {i}: u = {u:e} breaks [{g1:?}, {g2:?}] by {:e} m",
                below.max(above)
            );
        }
        m.most_active = m.most_active.max(report.active);
        m.contact_steps += usize::from(report.active > 0);
        energies.push(o.energy_total);
    }
    m.run_seconds = clock.elapsed().as_secs_f64();
    m.steps = steps;
    m.energy_first = energies[0];
    m.energy_last = *energies.last().unwrap();
    m.energy_scale = energies.iter().fold(0.0, |a: f64, e| a.max(e.abs()));
    let half = energies.len() / 2;
    let max = |s: &[f64]| s.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    m.energy_max_first_half = max(&energies[..half.max(1)]);
    m.energy_max_second_half = max(&energies[half..]);
    m.worst_rise = energies.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max)
        / m.energy_scale.max(f64::MIN_POSITIVE);
    if unforced {
        assert!(
            m.worst_rise <= ENERGY_ROUND_OFF,
            "fixed base: energy rose by {:e} of its scale in one step",
            m.worst_rise
        );
    }
    Ok(m)
}

/// Runs, prints the measurements under `name`, and fails on an error.
fn survive(name: &str, scene: &Scene, steps: usize, extra: impl Fn(f64) -> f64) -> Measured {
    let m = run(scene, steps, extra).unwrap_or_else(|e| panic!("{name}: {e}"));
    println!(
        "{name}: {} steps, {} constrained, contact in {} steps (≤ {} vertices), violation {:.1e}·gap, \
         E {:.4e} → {:.4e} J, worst rise {:.1e}·scale, max E halves {:.3e} / {:.3e} J, set-up {:.2} s, run {:.2} s",
        m.steps, m.constrained, m.contact_steps, m.most_active, m.violation, m.energy_first,
        m.energy_last, m.worst_rise, m.energy_max_first_half, m.energy_max_second_half,
        m.setup_seconds, m.run_seconds
    );
    m
}

/// With forcing the energy is bounded: after the transient, the second half of the run peaks no
/// higher than `factor` times the first half (a resonance without obstacles would grow linearly).
fn assert_bounded(name: &str, m: &Measured, factor: f64) {
    assert!(
        m.energy_max_second_half <= factor * m.energy_max_first_half.max(0.0) + 1e-300,
        "{name}: energy grows, max {:e} then {:e} J",
        m.energy_max_first_half,
        m.energy_max_second_half
    );
}

/// Expects a refusal whose message names `parameter`.
fn refused(name: &str, result: Result<Measured, Error>, words: &[&str]) -> String {
    let err = result
        .err()
        .unwrap_or_else(|| panic!("{name}: expected an error"));
    let text = err.to_string();
    println!("{name}: refused: {text}");
    for w in words {
        assert!(text.contains(w), "{name}: {w:?} missing from {text:?}");
    }
    text
}

/// A plate released from a static preload that presses it onto the upper obstacle, falling back
/// through the gap onto the lower one, fixed base and no load: E non-increasing. The preload is
/// 16 D g / Lx⁴, twice what bends the cantilever's tip (q Lx⁴ / 8D) to g.
fn drop_scene(element: ElementKind, nx: usize, ny: usize) -> Scene {
    let mut s = Scene::default();
    s.mesh.element = element;
    s.mesh.nx = nx;
    s.mesh.ny = ny;
    set_drop_preload(&mut s);
    s
}

fn set_drop_preload(s: &mut Scene) {
    s.initial.preload_pressure =
        16.0 * s.bending_stiffness() * s.obstacle.upper / s.plate.length.powi(4);
}

/// Steps that cover about `periods` periods of the first mode (capped at `cap`).
fn steps_for(scene: &Scene, periods: f64, cap: usize) -> usize {
    // Cantilever: f₁ ≈ 0.56 √(D/(ρe)) / Lx².
    let f1 =
        0.56 * (scene.bending_stiffness() / scene.areal_mass()).sqrt() / scene.plate.length.powi(2);
    ((periods / f1 / scene.solver.time_step).ceil() as usize).clamp(10, cap)
}

// ---------------------------------------------------------------- stiffness

#[test]
fn young_modulus_1e6_soft() {
    let mut s = drop_scene(ElementKind::Argyris, 6, 3);
    s.material.young_modulus = 1e6;
    set_drop_preload(&mut s);
    s.solver.time_step = 1e-3;
    let m = survive("E = 1e6 Pa", &s, steps_for(&s, 3.0, 4000), |_| 0.0);
    assert!(m.contact_steps > 0);
}

#[test]
fn young_modulus_1e13_stiff() {
    for linear in [LinearChoice::Modal, LinearChoice::Sparse] {
        let mut s = drop_scene(ElementKind::Argyris, 6, 3);
        s.material.young_modulus = 1e13;
        s.solver.linear = linear;
        set_drop_preload(&mut s);
        s.solver.time_step = 1e-5;
        let m = survive(&format!("E = 1e13 Pa, {linear:?}"), &s, 2000, |_| 0.0);
        assert!(m.contact_steps > 0);
    }
}

#[test]
fn thickness_1e_4() {
    let mut s = drop_scene(ElementKind::Fvs, 8, 4);
    s.plate.thickness = 1e-4;
    set_drop_preload(&mut s);
    s.solver.time_step = 1e-3;
    let m = survive("e = 1e-4 m", &s, steps_for(&s, 3.0, 4000), |_| 0.0);
    assert!(m.contact_steps > 0);
}

#[test]
fn thickness_0_1() {
    let mut s = drop_scene(ElementKind::Argyris, 6, 3);
    s.plate.thickness = 0.1;
    set_drop_preload(&mut s);
    s.solver.time_step = 1e-5;
    let m = survive("e = 0.1 m", &s, steps_for(&s, 3.0, 4000), |_| 0.0);
    assert!(m.contact_steps > 0);
}

#[test]
fn poisson_ratio_0_and_0_499() {
    for (nu, element) in [
        (0.0, ElementKind::Argyris),
        (0.0, ElementKind::Fvs),
        (0.499, ElementKind::Argyris),
        (0.499, ElementKind::Fvs),
    ] {
        let mut s = drop_scene(element, 8, 4);
        s.material.poisson_ratio = nu;
        set_drop_preload(&mut s);
        let m = survive(&format!("ν = {nu}, {element:?}"), &s, 1500, |_| 0.0);
        assert!(m.contact_steps > 0);
    }
}

// ---------------------------------------------------------------- time steps

#[test]
fn time_step_1e_2_far_beyond_every_mode_period() {
    for linear in [LinearChoice::Modal, LinearChoice::Sparse] {
        let mut s = drop_scene(ElementKind::Argyris, 10, 7);
        s.solver.time_step = 1e-2;
        s.solver.linear = linear;
        let m = survive(&format!("Δt = 1e-2 s, {linear:?}"), &s, 300, |_| 0.0);
        assert!(m.contact_steps > 0);
        // Forced by the paper's 35 Hz sine, sampled every 10 ms.
        s.initial.preload_pressure = 0.0;
        s.base.amplitude = 0.009;
        s.base.frequency = 35.0;
        let m = survive(&format!("Δt = 1e-2 s forced, {linear:?}"), &s, 300, |_| {
            0.0
        });
        assert_bounded("Δt = 1e-2 s forced", &m, 2.0);
    }
}

#[test]
fn time_step_1e_7() {
    let mut s = drop_scene(ElementKind::Argyris, 10, 7);
    s.solver.time_step = 1e-7;
    // The preload at the upper obstacle leaves it at 1e-7 s steps only after ~100 µs: start the
    // plate right at the obstacle so that contact happens within the horizon.
    let m = survive("Δt = 1e-7 s", &s, 3000, |_| 0.0);
    assert!(m.most_active > 0 || m.constrained > 0);
}

/// 10⁶ steps on the 1 × 1 FVS mesh (6 free dofs, modal): without obstacles E is conserved (no
/// drift); with them it never rises and stays bounded.
#[test]
fn a_million_steps_on_one_cell() {
    let mut s = drop_scene(ElementKind::Fvs, 1, 1);
    s.solver.time_step = 1e-4;
    s.obstacle.lower_enabled = false;
    s.obstacle.upper_enabled = false;
    let m = survive("1e6 steps, no obstacle", &s, 1_000_000, |_| 0.0);
    let drift = (m.energy_last - m.energy_first).abs() / m.energy_scale;
    println!("1e6 steps, no obstacle: relative drift {drift:.2e}");
    assert!(drift <= 1e-9, "energy drifts by {drift:e}");
    let mut s = drop_scene(ElementKind::Fvs, 1, 1);
    s.solver.time_step = 1e-4;
    let m = survive("1e6 steps, impacts", &s, 1_000_000, |_| 0.0);
    assert!(m.contact_steps > 50);
    assert!(m.energy_last <= m.energy_first * (1.0 + 1e-9));
}

// ---------------------------------------------------------------- gaps, preloads, base

/// Gap ±1e-9 m: released from the upper obstacle it bounces; under a constant −1000 Pa load (whose
/// static sag is 1e5 times the gap) it lies on the lower obstacle from the first steps on.
#[test]
fn gap_1e_9_always_in_contact() {
    for qp in [QpChoice::Auto, QpChoice::Clarabel] {
        let mut s = drop_scene(ElementKind::Argyris, 6, 3);
        s.obstacle.lower = -1e-9;
        s.obstacle.upper = 1e-9;
        s.solver.qp = qp;
        set_drop_preload(&mut s);
        let m = survive(&format!("gap 2e-9 m released, {qp:?}"), &s, 500, |_| 0.0);
        assert!(m.contact_steps > 0);
        s.initial.preload_pressure = 0.0;
        s.load.pressure = -1000.0;
        let m = survive(&format!("gap 2e-9 m pressed, {qp:?}"), &s, 500, |_| 0.0);
        assert!(m.contact_steps >= 490, "{} contact steps", m.contact_steps);
    }
}

#[test]
fn gap_1_m_never_in_contact() {
    let mut s = Scene::named("forced-35hz").unwrap();
    s.obstacle.lower = -1.0;
    s.obstacle.upper = 1.0;
    let m = survive("gap 2 m forced", &s, 3000, |_| 0.0);
    assert_eq!(m.contact_steps, 0);
    // Fixed base, released from a preload: no contact, E conserved.
    let mut s = drop_scene(ElementKind::Argyris, 10, 7);
    s.obstacle.lower = -1.0;
    s.obstacle.upper = 1.0;
    s.initial.preload_pressure = 8600.0 / 0.08;
    let m = survive("gap 2 m released", &s, 3000, |_| 0.0);
    assert_eq!(m.contact_steps, 0);
    let drift = (m.energy_last - m.energy_first).abs() / m.energy_scale;
    assert!(drift <= 1e-10, "drift {drift:e}");
}

/// A downward preload 100 times what bends the tip to the lower obstacle presses most vertices
/// onto it; kept on as the load, the plate stays there (E constant); released, it rebounds.
#[test]
fn preload_presses_most_vertices_onto_the_obstacle() {
    let mut s = drop_scene(ElementKind::Argyris, 10, 7);
    s.initial.preload_pressure *= -50.0;
    s.load.pressure = s.initial.preload_pressure;
    let m = survive("preload held", &s, 500, |_| 0.0);
    println!(
        "preload held: {} of {} vertices in contact",
        m.most_active, m.constrained
    );
    assert!(
        2 * m.most_active > m.constrained,
        "most vertices in contact"
    );
    s.load.pressure = 0.0;
    let m = survive("preload released", &s, 3000, |_| 0.0);
    assert!(m.contact_steps > 0);
}

#[test]
fn base_amplitude_just_inside_the_gap() {
    for element in [ElementKind::Argyris, ElementKind::Fvs] {
        let mut s = Scene::named("forced-35hz").unwrap();
        s.mesh.element = element;
        if element == ElementKind::Fvs {
            s.mesh.nx = 14;
            s.mesh.ny = 10;
        }
        s.base.amplitude = 0.01 * (1.0 - 1e-6);
        let m = survive(&format!("c = (1 − 1e-6) g, {element:?}"), &s, 2000, |_| 0.0);
        assert!(m.contact_steps > 0);
        assert_bounded("c just inside", &m, 2.0);
    }
}

#[test]
fn base_outside_the_gap_is_refused() {
    let mut s = Scene::default();
    s.base.amplitude = 0.01;
    refused(
        "c = g",
        run(&s, 10, |_| 0.0),
        &["base.amplitude", "0.01", "gap"],
    );
    // An external base that leaves the gap in the middle of a run: refused at that step.
    let s = Scene::default();
    let text = refused(
        "z leaves the gap",
        run(&s, 100, |t| if t > 5e-3 { 0.02 } else { 0.0 }),
        &["base displacement", "0.02"],
    );
    assert!(text.contains("upper 0.01 m"), "{text}");
}

/// Base sine far above the highest mode of the mesh: once resolved by Δt, once sampled far
/// beyond it (the stepper sees an arbitrary sequence of base positions inside the gap).
#[test]
fn excitation_far_above_the_highest_mode() {
    let mut s = Scene::default();
    s.mesh.nx = 4;
    s.mesh.ny = 2;
    let f_max = *PlateSystem::new(&s)
        .unwrap()
        .modes()
        .unwrap()
        .frequencies_hz()
        .last()
        .unwrap();
    s.base.amplitude = 0.005;
    s.base.frequency = 10.0 * f_max;
    s.solver.time_step = 1.0 / (20.0 * s.base.frequency);
    println!("highest mode of the 4 × 2 mesh: {f_max:.3e} Hz");
    let m = survive("f = 10 f_max resolved", &s, 4000, |_| 0.0);
    assert_bounded("f = 10 f_max resolved", &m, 2.0);
    s.solver.time_step = 1e-4;
    s.base.frequency = 1000.0 * f_max * std::f64::consts::SQRT_2;
    let m = survive("f = 1400 f_max aliased", &s, 4000, |_| 0.0);
    assert_bounded("f = 1400 f_max aliased", &m, 2.0);
}

// ---------------------------------------------------------------- meshes

#[test]
fn one_cell_meshes() {
    for element in [ElementKind::Argyris, ElementKind::Fvs] {
        let s = drop_scene(element, 1, 1);
        let m = survive(&format!("1 × 1 {element:?}"), &s, 2000, |_| 0.0);
        assert!(m.contact_steps > 0);
        let mut s = Scene::named("forced-35hz").unwrap();
        s.mesh.element = element;
        s.mesh.nx = 1;
        s.mesh.ny = 1;
        let m = survive(&format!("1 × 1 {element:?} forced"), &s, 2000, |_| 0.0);
        assert_bounded("1 × 1 forced", &m, 2.0);
    }
}

/// 60 × 30: `auto` picks the sparse backend (more than `MODAL_AUTO_LIMIT` free dofs).
#[test]
fn sixty_by_thirty_meshes() {
    for element in [ElementKind::Fvs, ElementKind::Argyris] {
        let s = drop_scene(element, 60, 30);
        let clock = Instant::now();
        let stepper = Stepper::new(&s, 0.0).unwrap();
        println!(
            "60 × 30 {element:?}: {} free dofs, {:?} backend, set-up {:.2} s",
            stepper.free_dof_count(),
            stepper.linear_backend(),
            clock.elapsed().as_secs_f64()
        );
        assert_eq!(stepper.linear_backend(), LinearChoice::Sparse);
        let m = survive(&format!("60 × 30 {element:?}"), &s, 300, |_| 0.0);
        assert!(m.contact_steps > 0);
    }
}

#[test]
fn aspect_ratio_0_01() {
    for (element, nx, ny) in [(ElementKind::Argyris, 1, 20), (ElementKind::Fvs, 1, 30)] {
        let mut s = drop_scene(element, nx, ny);
        s.plate.length = 0.01;
        s.plate.width = 1.0;
        s.plate.thickness = 1e-3;
        set_drop_preload(&mut s);
        s.solver.time_step = 1e-5;
        let m = survive(&format!("Lx/Ly = 0.01 {element:?}"), &s, 2000, |_| 0.0);
        assert!(m.contact_steps > 0);
    }
}

#[test]
fn aspect_ratio_100() {
    for (element, nx, ny) in [(ElementKind::Argyris, 20, 1), (ElementKind::Fvs, 30, 1)] {
        let mut s = drop_scene(element, nx, ny);
        s.plate.length = 1.0;
        s.plate.width = 0.01;
        s.plate.thickness = 1e-3;
        set_drop_preload(&mut s);
        s.solver.time_step = 1e-4;
        let m = survive(
            &format!("Lx/Ly = 100 {element:?}"),
            &s,
            steps_for(&s, 3.0, 5000),
            |_| 0.0,
        );
        assert!(m.contact_steps > 0);
    }
}

// ---------------------------------------------------------------- restitution

/// e = 0 (the paper's position law) and e = 1 (Newton's law, elastic): with a fixed base E never
/// rises ([`run`] checks every step) and every vertex stays within the obstacles, for both; forced,
/// the energy stays bounded. (e = 1 loses energy only where a contact is not a closing one, which
/// the position law then handles.)
#[test]
fn restitution_0_and_1() {
    for e in [0.0, 1.0] {
        let mut s = drop_scene(ElementKind::Argyris, 10, 7);
        s.solver.restitution = e;
        let m = survive(&format!("restitution {e}, released"), &s, 3000, |_| 0.0);
        assert!(m.contact_steps > 0);
        let growth = m.energy_last / m.energy_first;
        println!("restitution {e}: E_last / E_first = {growth:.4}");
        assert!(growth <= 1.0 + 1e-9);
        let mut s = Scene::named("forced-35hz").unwrap();
        s.solver.restitution = e;
        let m = survive(&format!("restitution {e}, forced"), &s, 3000, |_| 0.0);
        assert_bounded("restitution forced", &m, if e == 0.0 { 2.0 } else { 2.5 });
    }
}

// ---------------------------------------------------------------- refusals

#[test]
fn out_of_range_parameters_are_refused_by_name() {
    type Change = fn(&mut Scene);
    let cases: [(&str, Change); 6] = [
        ("material.poisson_ratio", |s| s.material.poisson_ratio = 0.5),
        ("solver.time_step", |s| s.solver.time_step = 0.0),
        ("solver.restitution", |s| s.solver.restitution = 1.01),
        ("plate.thickness", |s| s.plate.thickness = 0.3),
        ("mesh.nx", |s| s.mesh.nx = 0),
        ("material.young_modulus", |s| {
            s.material.young_modulus = -1.0
        }),
    ];
    for (name, change) in cases {
        let mut s = Scene::default();
        change(&mut s);
        refused(name, run(&s, 1, |_| 0.0), &[name, "must"]);
    }
}
