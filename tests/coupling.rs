//! The outputs a coupled simulation needs (docs/scheme.md §11–12): the exact energy balance
//! of the scheme, E(t) − E(t_1) = base work + load work − contact loss − damping loss; the force
//! on the base against Newton's law for a plate that follows its base rigidly and against a static
//! load; and the per-step contact report.

mod common;

use plate_impact::element::ElementKind;
use plate_impact::scene::{Damping, LinearChoice, Scene};
use plate_impact::scheme::{EnergyFlows, Stepper};

/// Relative round-off of a step's contact loss, as a fraction of Σ_i |f_i| · gap: the loss
/// −½ Σ_i f_i (u_{n+1} − u_{n−1})_i is ≥ 0 in exact arithmetic for every restitution e (Newton's
/// law gives u_{n+1} − g = −e (u_{n−1} − g) at a vertex in contact, so f_i and u_{n+1} − u_{n−1}
/// have opposite signs), and each computed u lies within the obstacles, |u| ≤ gap, to a few ulps
/// of the sum of modal or nodal terms that makes it. 1e-12 allows those sums an error of 2e-12 of
/// the gap, 10⁴ ulps; a loss of the wrong sign by more is not round-off. Measured at most 8e-15 of
/// Σ|f|·gap on the 35 Hz scene for e = 0, ½ and 1.
const CONTACT_LOSS_ROUND_OFF: f64 = 1e-12;

/// Runs `scene` for `steps` steps on its built-in base, changing the pressure to `second_pressure`
/// half-way, and returns the worst |E(t_n) − E(t_1) − Σ flows| over the energy scale (the largest
/// |E| seen), with the flows summed by the stepper and by the test from the per-step reports.
/// Every step's contact loss is ≥ 0 to [`CONTACT_LOSS_ROUND_OFF`].
fn worst_balance_residual(scene: &Scene, steps: usize, second_pressure: f64) -> (f64, EnergyFlows) {
    let mut stepper = Stepper::new(scene, scene.builtin_base(0.0)).unwrap();
    let dt = scene.solver.time_step;
    stepper.step(scene.builtin_base(dt)).unwrap();
    let first = stepper.outputs();
    let (mut summed, mut scale, mut residuals) =
        (EnergyFlows::default(), first.energy_total.abs(), vec![]);
    let mut most_negative_loss = 0.0f64;
    assert_eq!(
        (
            first.base_work,
            first.load_work,
            first.contact_loss,
            first.damping_loss
        ),
        (0.0, 0.0, 0.0, 0.0),
        "the flows are summed from t_1 on"
    );
    for n in 2..=steps {
        if n == steps / 2 {
            stepper.set_pressure(second_pressure).unwrap();
        }
        let report = stepper.step(scene.builtin_base(n as f64 * dt)).unwrap();
        summed = summed.plus(&report.flows);
        let o = stepper.outputs();
        assert!(report.flows.damping_loss >= 0.0);
        let loss_scale = scene.gap()
            * stepper
                .contact_forces()
                .iter()
                .map(|f| f.abs())
                .sum::<f64>();
        let loss = report.flows.contact_loss;
        most_negative_loss = most_negative_loss.min(loss / loss_scale.max(f64::MIN_POSITIVE));
        assert!(
            loss >= -CONTACT_LOSS_ROUND_OFF * loss_scale,
            "e = {}: contact loss {loss:e} J, Σ|f|·gap = {loss_scale:e} J",
            scene.solver.restitution
        );
        assert_eq!(
            (o.base_work, o.load_work, o.contact_loss, o.damping_loss),
            (
                summed.base_work,
                summed.load_work,
                summed.contact_loss,
                summed.damping_loss
            ),
            "the outputs carry the summed flows"
        );
        scale = scale.max(o.energy_total.abs());
        residuals.push((o.energy_total - first.energy_total - summed.net()).abs());
    }
    let worst = residuals.iter().fold(0.0, |a: f64, &b| a.max(b)) / scale;
    println!(
        "e = {}: most negative contact loss {most_negative_loss:.1e} of Σ|f|·gap",
        scene.solver.restitution
    );
    (worst, summed)
}

/// The balance holds to round-off over 0.5 s of the forced scene at 35 Hz (impacts on both
/// obstacles) with a load of 3 kPa changed to −2 kPa half-way, for both backends, undamped and
/// damped. Per step the identity is exact in exact arithmetic (the scheme multiplied by
/// u_{n+1} − u_{n−1}); what remains is the round-off of each step's solve summed over 5000 steps:
/// [`MODAL_BALANCE_ROUND_OFF`] and [`SPARSE_BALANCE_ROUND_OFF`] of the energy scale.
/// The modal backend advances each mode by a scalar recurrence, round-off ε per step and mode:
/// measured at most 8.5e-14 of the energy scale over 5000 steps, 1e-12 leaves a factor 12.
const MODAL_BALANCE_ROUND_OFF: f64 = 1e-12;

/// The sparse backend solves with a Cholesky factor of A, backward stable to about ε·cond(A) per
/// step (cond(A) ~ 1 + ½Δt²ω_max² is large for the stiff high modes of a fine mesh): measured at
/// most 5e-12 of the energy scale over 5000 steps, 1e-10 leaves a factor 20.
const SPARSE_BALANCE_ROUND_OFF: f64 = 1e-10;

#[test]
fn the_energy_balance_closes() {
    for linear in [LinearChoice::Modal, LinearChoice::Sparse] {
        // Undamped, Rayleigh, and (modal backend) Rayleigh plus a modal ratio, whose dashpots
        // the base carries as well: the base force is Newton's law for the whole plate.
        let rayleigh = Damping {
            mass_proportional: 10.0,
            stiffness_proportional: 2e-6,
            ..Damping::default()
        };
        let modal = Damping {
            modal_ratio: 0.02,
            ..rayleigh.clone()
        };
        let dampings = match linear {
            LinearChoice::Modal => vec![Damping::default(), rayleigh, modal],
            _ => vec![Damping::default(), rayleigh],
        };
        for damping in dampings {
            let mut s = common::paper_scene("forced-35hz", ElementKind::Argyris);
            s.solver.linear = linear;
            s.load.pressure = 3000.0;
            s.damping = damping;
            let damped = !s.damping.coefficients().is_zero();
            let modal_ratio = s.damping.modal_ratio;
            let (worst, flows) = worst_balance_residual(&s, 5000, -2000.0);
            println!(
                "{linear:?}, damped {damped} (modal ratio {modal_ratio}): worst residual {worst:.2e} of the energy scale; \
                 since t_1: base work {:.4} J, load work {:.3e} J, contact loss {:.4} J, damping \
                 loss {:.4} J",
                flows.base_work, flows.load_work, flows.contact_loss, flows.damping_loss
            );
            let round_off = match linear {
                LinearChoice::Sparse => SPARSE_BALANCE_ROUND_OFF,
                _ => MODAL_BALANCE_ROUND_OFF,
            };
            assert!(
                worst <= round_off,
                "{linear:?} damped {damped} (modal ratio {modal_ratio}): residual {worst:e}"
            );
            assert!(flows.contact_loss > 0.0 && flows.base_work > 0.0);
            assert!(flows.load_work != 0.0, "the pressure change puts energy in");
            assert_eq!(damped, flows.damping_loss > 0.0);
        }
    }
}

/// With a constant pressure the load work is the work of the load minus the change of its
/// potential, zero to round-off (1e-12 of the energy scale over 2000 steps), and the balance
/// closes to the modal backend's round-off.
#[test]
fn a_constant_load_does_no_net_work() {
    let mut s = common::paper_scene("forced-35hz", ElementKind::Argyris);
    s.solver.linear = LinearChoice::Modal;
    s.load.pressure = 5000.0;
    let (worst, flows) = worst_balance_residual(&s, 2000, 5000.0);
    println!(
        "load work {:.2e} J, balance residual {worst:.2e}",
        flows.load_work
    );
    assert!(flows.load_work.abs() <= 1e-12 * flows.base_work.abs().max(1.0));
    assert!(worst <= MODAL_BALANCE_ROUND_OFF, "residual {worst:e}");
}

/// The impact laws keep every contact's loss −½ f_i (u_{n+1} − u_{n−1}) ≥ 0 for every restitution,
/// e = 1 included (docs/scheme.md §8): over 0.3 s of the forced scene at 35 Hz with e = ½ and
/// e = 1, no step's contact loss is negative beyond round-off ([`CONTACT_LOSS_ROUND_OFF`]), and the
/// balance still closes. At e = 1 the default (persistent) law removes nothing, so the summed loss
/// is zero to round-off: measured −3e-13 J here (−1.4e-12 J over 1 s of this scene in
/// docs/restitution/contact_loss.csv), held to 1e-10 J either side, about 1e-13 of the work scale
/// Σ|f|·gap of these contacts (~1e3 J) and far below what one contact dropped onto the obstacle
/// loses (Newton's law: 0.65 J over 1 s of this scene). At e = ½ it is strictly positive.
#[test]
fn the_contact_loss_is_non_negative_for_every_restitution() {
    for e in [0.5, 1.0] {
        let mut s = common::paper_scene("forced-35hz", ElementKind::Argyris);
        s.solver.linear = LinearChoice::Modal;
        s.solver.restitution = e;
        let (worst, flows) = worst_balance_residual(&s, 3000, 0.0);
        println!(
            "e = {e}: contact loss since t_1 {:.4e} J, balance residual {worst:.2e}",
            flows.contact_loss
        );
        if e == 1.0 {
            assert!(flows.contact_loss.abs() <= 1e-10, "e = {e}: {flows:?}");
        } else {
            assert!(flows.contact_loss > 0.0, "e = {e}: {flows:?}");
        }
        assert!(
            worst <= MODAL_BALANCE_ROUND_OFF,
            "e = {e}: residual {worst:e}"
        );
    }
}

/// z(t) = c (1 − cos ωt)²/4: z, ż and z̈ vanish at t = 0, so a plate at rest follows it without
/// being kicked, and z̈(t) = ½cω²(sin²ωt + cos ωt − cos²ωt).
fn smooth_base(c: f64, omega: f64, t: f64) -> (f64, f64) {
    let (s, co) = ((omega * t).sin(), (omega * t).cos());
    (
        c * (1.0 - co).powi(2) / 4.0,
        0.5 * c * omega * omega * (s * s + co - co * co),
    )
}

/// A very stiff plate (E = 1e13 Pa, first mode near f₁ = 370 Hz) on a base moving smoothly at
/// 10 Hz follows it nearly rigidly, so the force it exerts on the base is −m z̈ with m = ρ e Lx Ly:
/// within 0.5 % of the largest m z̈ at every step of 0.2 s. base.force belongs to
/// t_n = t_{n+1} − Δt. The bound: z̈ = ½cω²(cos ωt − cos 2ωt) has harmonics at f = 10 and 20 Hz,
/// each half of the peak; the plate's quasi-static bending under them adds (f/f₁)² of each to the
/// force, ½((10/370)² + (20/370)²) ≈ 0.18 % of the peak if the first mode carried the whole mass,
/// and the scheme's O((ωΔt)²) error is below 1e-4: measured 0.18 %, 0.5 % leaves a factor 3.
#[test]
fn a_rigid_plate_pushes_its_base_with_minus_m_times_the_acceleration() {
    for linear in [LinearChoice::Modal, LinearChoice::Sparse] {
        let mut s = common::paper_scene("forced", ElementKind::Argyris);
        s.base.amplitude = 0.0;
        s.obstacle.lower_enabled = false;
        s.obstacle.upper_enabled = false;
        s.material.young_modulus = 1e13;
        s.solver.linear = linear;
        let mass = s.material.density * s.plate.thickness * s.plate.length * s.plate.width;
        let (c, omega) = (2e-3, 2.0 * std::f64::consts::PI * 10.0);
        let dt = s.solver.time_step;
        let mut stepper = Stepper::new(&s, 0.0).unwrap();
        let peak = mass * 0.5 * c * omega * omega * 2.0;
        let mut worst = 0.0f64;
        for n in 1..=2000 {
            let (z, _) = smooth_base(c, omega, n as f64 * dt);
            let report = stepper.step(z).unwrap();
            let (_, acceleration) = smooth_base(c, omega, (n - 1) as f64 * dt);
            worst = worst.max((report.base_force + mass * acceleration).abs());
            assert_eq!(report.base_force, stepper.outputs().base_force);
        }
        println!(
            "{linear:?}: m = {mass:.4} kg, largest m z̈ ≈ {peak:.1} N, worst |base.force + m z̈| \
             {worst:.3e} N ({:.3} %)",
            100.0 * worst / peak
        );
        assert!(worst <= 0.005 * peak, "{linear:?}: {worst:e} N");
    }
}

/// A constant upward pressure p on a fixed base: the plate swings about its static deflection and
/// the force it exerts on the base averages p·Lx·Ly (the base holds the whole load), within 2 %
/// over 1 s (about 54 periods of the first mode; the swing's share of the average is below 1 %).
/// At t_0, with the same pressure as a preload, the static value is exact.
#[test]
fn a_constant_pressure_loads_the_base_with_its_resultant() {
    for linear in [LinearChoice::Modal, LinearChoice::Sparse] {
        let mut s = common::paper_scene("energy", ElementKind::Argyris);
        s.initial.preload_pressure = 0.0;
        s.obstacle.lower_enabled = false;
        s.load.pressure = 2e4;
        s.solver.linear = linear;
        let resultant = s.load.pressure * s.plate.length * s.plate.width;
        let mut stepper = Stepper::new(&s, 0.0).unwrap();
        let steps = 10_000;
        let mut sum = 0.0;
        for _ in 0..steps {
            sum += stepper.step(0.0).unwrap().base_force;
        }
        let average = sum / steps as f64;
        println!(
            "{linear:?}: p·Lx·Ly = {resultant:.1} N, time-averaged base.force {average:.2} N ({:+.3} %)",
            100.0 * (average / resultant - 1.0)
        );
        assert!((average / resultant - 1.0).abs() <= 0.02, "{average}");
        s.initial.preload_pressure = s.load.pressure;
        let at_rest = Stepper::new(&s, 0.0).unwrap().outputs().base_force;
        assert!(
            (at_rest / resultant - 1.0).abs() <= 1e-12,
            "static base force {at_rest} N"
        );
    }
}

/// Each report says whether the contact set went from empty to non-empty, and carries the step's
/// total contact force, which is also the contact.force output.
#[test]
fn steps_report_impacts_and_their_contact_force() {
    let s = common::paper_scene("forced-35hz", ElementKind::Argyris);
    let mut stepper = Stepper::new(&s, 0.0).unwrap();
    let (mut previous_active, mut impacts) = (0, 0);
    for n in 1..=3000 {
        let report = stepper
            .step(s.builtin_base(n as f64 * s.solver.time_step))
            .unwrap();
        assert_eq!(report.impact, previous_active == 0 && report.active > 0);
        assert_eq!(report.contact_force, stepper.outputs().contact_force);
        impacts += usize::from(report.impact);
        previous_active = report.active;
    }
    println!("{impacts} impacts");
    assert!(impacts >= 5, "the 35 Hz scene impacts repeatedly");
}
