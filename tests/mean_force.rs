//! `base.mean_force` against the base work (docs/fmu.md, "Coupling both ways"): the mean over a
//! communication step of the force on the base, F̄ = ΔJ/h with J the impulse of the forces of
//! `base.force`, is the force whose work on the base's displacement Δz is the base work the
//! plate reports, ΔW = −F̄·Δz, when the base moves at one velocity; when the base's velocity
//! changes at the communication point t_k (grid index N0), the remainder is exactly
//! ½·base.force_{N0}·(z_{N0+1} − 2z_{N0} + z_{N0−1}).

mod common;

use plate_impact::element::ElementKind;
use plate_impact::scene::Scene;
use plate_impact::simulation::input::InputSample;
use plate_impact::simulation::Simulation;

/// Relative round-off of ΔW + F̄·Δz over one communication step, as a fraction of the scale of
/// the cumulative sums it is formed from, max(|W|, |s·J|): ΔW and ΔJ are differences of two
/// cumulative sums (an ulp of each), the interpolation between grid points adds one rounding of
/// each, and each internal step's work ½(z_{n+1} − z_{n−1})·G_n carries the rounding of its
/// stroke, an ulp of z (1e-18 m at 5 mm) against a stroke 2sΔt ≥ 4e-6 m, 3e-13 of the step's
/// work; over at most 12 internal steps, each with a work under 1/20 of the scale (at most
/// 8.6 kN × 3 µm against a scale of at least 0.46 J), that is 2e-13 of the scale at worst.
/// Measured: at most 2e-14 of the scale.
const IDENTITY_ROUND_OFF: f64 = 1e-12;

/// The energy scene of the paper (preload released onto the lower obstacle: repeated impacts)
/// with the built-in sine off, on the time step `dt`, with Rayleigh damping or not, with the
/// obstacle or not.
fn scene(dt: f64, damped: bool, obstacle: bool) -> Scene {
    let mut s = common::paper_scene("energy", ElementKind::Argyris);
    s.base.amplitude = 0.0;
    s.solver.time_step = dt;
    s.obstacle.lower_enabled = obstacle;
    if damped {
        s.damping.mass_proportional = 10.0;
        s.damping.stiffness_proportional = 2e-6;
    }
    s
}

/// A fixed pseudo-random factor in [0.2, 1.5] for communication step k.
fn factor(k: usize) -> f64 {
    0.2 + 1.3 * (k as f64 * 0.618_034).fract()
}

/// What a master sees over one communication step.
struct Observed {
    /// t_k, t_{k+1} (s).
    times: [f64; 2],
    /// W(t_k), W(t_{k+1}) (J).
    work: [f64; 2],
    /// base.mean_force over the step (N).
    mean_force: f64,
    /// base.force of the first internal step of the communication step, if it computed one (N).
    first_force: Option<f64>,
    /// J(t_{k+1}) (N·s).
    impulse: f64,
    /// Internal steps that reached an impact.
    impacts: u64,
}

/// One communication step of size `h` with the external sample `value` and its slope.
fn step(sim: &mut Simulation, h: f64, value: f64, slope: f64) -> Observed {
    let (t0, w0) = (sim.time(), sim.outputs().base_work);
    let end = sim.step_end(h).unwrap();
    let sample = InputSample {
        value,
        slope: Some(slope),
        curvature: None,
    };
    let (mut first_force, mut impacts) = (None, 0);
    sim.advance(&end, &sample, false, &mut |s| {
        first_force.get_or_insert(s.report.base_force);
        impacts += u64::from(s.report.impact);
    })
    .unwrap();
    Observed {
        times: [t0, sim.time()],
        work: [w0, sim.outputs().base_work],
        mean_force: sim.base_mean_force(),
        first_force,
        impulse: sim.base_impulse(),
        impacts,
    }
}

/// The base moves at one velocity s from t = 0 (the master sends x(t_k) = x₀ + s·t_k and
/// x'(t_k) = s, so the FMU's plan is that line to round-off): over every communication step after
/// the first internal step, ΔW = −F̄·Δz with Δz = s·(t_{k+1} − t_k), whatever the step (on the
/// grid, or random sizes ending between grid points), the time step, the impacts and the damping.
#[test]
fn a_base_at_constant_velocity_receives_exactly_the_mean_force_times_its_displacement() {
    let (x0, s) = (-1e-3, 0.03);
    for dt in [1e-4, 7.3e-5] {
        for damped in [false, true] {
            for obstacle in [true, false] {
                for random in [false, true] {
                    let scene = scene(dt, damped, obstacle);
                    let mut sim = Simulation::new(&scene, 0.0, x0).unwrap();
                    let (mut worst, mut scale, mut impacts, mut steps) = (0.0f64, 0.0f64, 0, 0);
                    let mut k = 0;
                    while sim.time() < 0.2 {
                        let h = if random {
                            8.0 * dt * factor(k)
                        } else {
                            3.0 * dt
                        };
                        let value = x0 + s * sim.time();
                        let o = step(&mut sim, h, value, s);
                        k += 1;
                        impacts += o.impacts;
                        scale = scale.max(o.work[1].abs()).max((s * o.impulse).abs());
                        // The start step (t_0 → t_1) has no energy identity: from t_1 on.
                        if o.times[0] < dt {
                            continue;
                        }
                        let dz = s * (o.times[1] - o.times[0]);
                        let residual = (o.work[1] - o.work[0]) + o.mean_force * dz;
                        worst = worst.max(residual.abs());
                        steps += 1;
                    }
                    println!(
                        "dt {dt:e}, damped {damped}, obstacle {obstacle}, random {random}: \
                         {steps} steps, {impacts} impacts, worst |ΔW + F̄Δz| {:.1e} of the \
                         scale {scale:.3e} J",
                        worst / scale
                    );
                    assert_eq!(obstacle, impacts >= 3, "impacts: {impacts}");
                    assert!(
                        worst <= IDENTITY_ROUND_OFF * scale,
                        "dt {dt:e}, damped {damped}, obstacle {obstacle}, random {random}: \
                         {worst:e} J of {scale:e} J"
                    );
                }
            }
        }
    }
}

/// The base moves linearly over each communication step, with a new velocity s_k at each
/// communication point on the grid (the master sends x_k and x'_k = s_k, x continuous): ΔW + F̄·Δz
/// is then exactly ½·base.force_{N0}·δ²z_{N0}, δ²z_{N0} = z_{N0+1} − 2z_{N0} + z_{N0−1} =
/// (s_k − s_{k−1})Δt, the work of the first internal step's force on the change of the base's
/// velocity; that remainder is far beyond round-off, so no definition from the same forces makes
/// the identity exact for such a base (docs/fmu.md).
#[test]
fn a_change_of_base_velocity_leaves_exactly_the_kink_term() {
    let dt = 1e-4;
    for damped in [false, true] {
        let scene = scene(dt, damped, true);
        let h = 5.0 * dt;
        let mut sim = Simulation::new(&scene, 0.0, 0.0).unwrap();
        let (mut x, mut previous_slope) = (0.0, 0.0);
        let (mut worst, mut scale, mut kinks, mut impacts) = (0.0f64, 0.0f64, 0.0f64, 0);
        for k in 0..400 {
            let slope = 0.02 * (0.7 * k as f64).cos();
            let o = step(&mut sim, h, x, slope);
            impacts += o.impacts;
            scale = scale.max(o.work[1].abs()).max((slope * o.impulse).abs());
            x += slope * h;
            if k > 0 {
                let dz = slope * (o.times[1] - o.times[0]);
                let kink = 0.5 * o.first_force.unwrap() * (slope - previous_slope) * dt;
                let residual = (o.work[1] - o.work[0]) + o.mean_force * dz;
                worst = worst.max((residual - kink).abs());
                kinks = kinks.max(kink.abs());
            }
            previous_slope = slope;
        }
        println!(
            "damped {damped}: {impacts} impacts, worst |ΔW + F̄Δz − kink| {:.1e} of the scale \
             {scale:.3e} J; largest kink term {kinks:.3e} J",
            worst / scale
        );
        assert!(impacts >= 2, "impacts: {impacts}");
        assert!(worst <= IDENTITY_ROUND_OFF * scale, "{worst:e} J");
        assert!(
            kinks > 1e6 * IDENTITY_ROUND_OFF * scale,
            "the kink term {kinks:e} J must be far beyond round-off"
        );
    }
}

/// Before the first step the mean force is the static force on the base (the preload's
/// resultant, as `base.force`); a restored simulation reports the same mean force, bit for bit,
/// on and off the grid; and after a restart the mean force is the static one again.
#[test]
fn the_mean_force_starts_static_and_survives_a_state_round_trip() {
    let scene = scene(1e-4, false, true);
    let mut sim = Simulation::new(&scene, 0.0, 0.0).unwrap();
    assert_eq!(sim.base_mean_force(), sim.outputs().base_force);
    assert!(
        sim.base_mean_force() > 8000.0,
        "the preload's resultant, 8600 N less the obstacle's share"
    );
    for (k, h) in [3e-4, 2.5e-4, 0.3e-4, 4e-4]
        .iter()
        .cycle()
        .take(42)
        .enumerate()
    {
        step(&mut sim, *h, 0.0, 0.0);
        let state = sim.state();
        let restored = Simulation::from_state(&state).unwrap();
        assert_eq!(
            restored.base_mean_force().to_bits(),
            sim.base_mean_force().to_bits(),
            "step {k}"
        );
    }
    assert_ne!(
        sim.time(),
        sim.grid_time(),
        "the test ends between grid points"
    );
    let static_force = Simulation::new(&scene, 0.0, 0.0).unwrap().base_mean_force();
    sim.restart(&scene, 0.0, 0.0).unwrap();
    assert_eq!(sim.base_mean_force(), static_force);
}

/// A communication step refused at its first internal step (a base sample outside the gap) takes
/// no time: the mean force stays the last step's, finite, and the state stays one that restores.
#[test]
fn a_step_refused_before_its_first_grid_point_keeps_the_last_mean() {
    let scene = scene(1e-4, false, true);
    let mut sim = Simulation::new(&scene, 0.0, 0.0).unwrap();
    for refused_first in [true, false] {
        if !refused_first {
            step(&mut sim, 3e-4, 0.0, 0.0);
        }
        let (before, time) = (sim.base_mean_force(), sim.time());
        let end = sim.step_end(1e-3).unwrap();
        // Below the lower obstacle (the scene has no upper one) already at the first grid point.
        let outside = InputSample {
            value: -1.0,
            slope: None,
            curvature: None,
        };
        let err = sim.advance(&end, &outside, false, &mut |_| {}).unwrap_err();
        assert!(err.to_string().contains("obstacles"), "{err}");
        assert_eq!(sim.time(), time, "no grid point reached");
        assert_eq!(sim.base_mean_force().to_bits(), before.to_bits());
        let restored = Simulation::from_state(&sim.state()).unwrap();
        assert_eq!(restored.base_mean_force().to_bits(), before.to_bits());
    }
}
