//! The simulation driver through its own API: restarts, restores and state round trips bit for
//! bit, refused set-ups and states, the grid independent of the communication steps, energy and
//! obstacles between communication points, contacts reported once, early return at impacts and
//! the interpolated vertex field.

use super::*;

/// One communication step of size `h` with the external base sample `value`.
fn step(sim: &mut Simulation, h: f64, value: f64) -> CommunicationStep {
    let end = sim.step_end(h).unwrap();
    let sample = InputSample {
        value,
        ..InputSample::default()
    };
    sim.advance(&end, &sample, false, &mut |_| {}).unwrap()
}

/// A fixed pseudo-random factor in [0.2, 1.5] for communication step k.
fn factor(k: usize) -> f64 {
    0.2 + 1.3 * (k as f64 * 0.618_034).fract()
}

/// Bits of corner1 and the energy after each of `steps` communication steps of 3Δt (on the
/// grid) or, when `random`, of Δt × a factor in [0.6, 4.5] (mostly off the grid).
fn trace(sim: &mut Simulation, steps: usize, random: bool) -> Vec<u64> {
    (0..steps)
        .map(|k| {
            let h = if random { 3e-4 * factor(k) } else { 3e-4 };
            step(sim, h, 1e-3 * (k as f64 * 0.4).sin());
            let o = sim.outputs();
            o.corner1.to_bits() ^ o.energy_total.to_bits()
        })
        .collect()
}

fn corner_trace(sim: &mut Simulation, steps: usize) -> Vec<u64> {
    trace(sim, steps, false)
}

fn small(mut scene: Scene) -> Scene {
    scene.mesh.nx = 3;
    scene.mesh.ny = 2;
    scene
}

/// Moving the obstacles and changing the pressure keep the cached outputs and vertex field:
/// on a grid point and between two, they equal what a simulation restored from the new
/// state computes afresh.
#[test]
fn tunable_sets_keep_the_cached_outputs_valid() {
    let mut sim = Simulation::new(&small(Scene::default()), 0.0, 0.0).unwrap();
    for h in [3e-4, 1.5e-4] {
        step(&mut sim, h, 1e-3);
        let cached = (sim.outputs().clone(), sim.vertex_field().clone());
        let o = sim.scene().obstacle.clone();
        sim.set_obstacles(o.lower - 1e-3, o.upper + 1e-3).unwrap();
        sim.set_pressure(sim.scene().load.pressure + 2e4).unwrap();
        let fresh = Simulation::from_state(&sim.state()).unwrap();
        assert_eq!(fresh.scene().obstacle.lower, o.lower - 1e-3);
        assert_eq!(*fresh.outputs(), cached.0, "h = {h}");
        assert_eq!(*fresh.vertex_field(), cached.1, "h = {h}");
    }
    assert!(matches!(sim.point, CommunicationPoint::Between { .. }));
}

#[test]
fn restart_equals_a_fresh_simulation_bit_for_bit() {
    let a = small(Scene::default());
    let mut b = a.clone();
    b.load.pressure = 1e5;
    b.obstacle.lower = -0.004;
    let mut preloaded = b.clone();
    preloaded.initial.preload_pressure = -3e5;
    let mut finer = a.clone();
    finer.mesh.nx = 4;
    let mut sim = Simulation::new(&a, 0.0, 0.0).unwrap();
    corner_trace(&mut sim, 5);
    for (scene, start, external, how) in [
        (&b, 0.5, 2e-3, SetUp::Reused),
        (&a, 0.0, 0.0, SetUp::Reused),
        (&preloaded, 0.0, 0.0, SetUp::Rebuilt),
        (&preloaded, 0.0, 0.0, SetUp::Reused),
        (&preloaded, 0.0, 1e-3, SetUp::Rebuilt),
        (&finer, 0.0, 0.0, SetUp::Rebuilt),
    ] {
        assert_eq!(sim.restart(scene, start, external).unwrap(), how);
        let mut fresh = Simulation::new(scene, start, external).unwrap();
        assert_eq!(sim.outputs(), fresh.outputs());
        assert_eq!(sim.time(), start);
        assert_eq!(corner_trace(&mut sim, 40), corner_trace(&mut fresh, 40));
    }
}

#[test]
fn state_round_trip_continues_bit_identically() {
    let mut scene = small(Scene::default());
    scene.base.amplitude = 0.005;
    let mut sim = Simulation::new(&scene, 0.25, 0.0).unwrap();
    corner_trace(&mut sim, 7);
    let state = sim.state();
    let expected = corner_trace(&mut sim, 30);
    let mut other = Simulation::from_state(&state).unwrap();
    assert_eq!(other.time(), 0.25 + 21.0 * 1e-4);
    assert_eq!(corner_trace(&mut other, 30), expected);
    sim.restore(&state).unwrap();
    assert_eq!(corner_trace(&mut sim, 30), expected);
}

#[test]
fn restore_refuses_inconsistent_histories_and_grids() {
    let scene = small(Scene::default());
    let mut sim = Simulation::new(&scene, 0.0, 0.0).unwrap();
    corner_trace(&mut sim, 2);
    let good = sim.state();
    let mut future = good.clone();
    future.input.last_sample = Some((1.0, 0.0));
    let err = sim.restore(&future).unwrap_err().to_string();
    assert!(err.contains("outside"), "{err}");
    let mut far = good.clone();
    far.start_time = -1e308;
    let err = sim.restore(&far).unwrap_err().to_string();
    assert!(err.contains("too coarse"), "{err}");
    assert_eq!(sim.state(), good, "a refused restore changes nothing");
}

/// A time step whose square overflows is refused at set-up, naming the parameter; the largest
/// one whose square is finite is accepted.
#[test]
fn a_time_step_whose_square_overflows_is_refused() {
    let mut scene = small(Scene::default());
    scene.solver.time_step = 1e155;
    let err = Simulation::new(&scene, 0.0, 0.0).err().unwrap();
    assert!(err.to_string().contains("solver.time_step"), "{err}");
    scene.solver.time_step = 1e154;
    assert!(Simulation::new(&scene, 0.0, 0.0).is_ok());
}

#[test]
fn an_inaccurate_initial_state_is_refused() {
    let mut scene = small(Scene::default());
    scene.material.young_modulus = 1e-3;
    scene.initial.preload_pressure = 1e5;
    let err = Simulation::new(&scene, 0.0, 5e-3)
        .err()
        .unwrap()
        .to_string();
    assert!(err.contains("past the obstacle"), "{err}");
}

#[test]
fn observer_sees_every_internal_step_on_the_grid() {
    let scene = small(Scene::default());
    let mut sim = Simulation::new(&scene, 1.0, 0.0).unwrap();
    let mut times = Vec::new();
    let end = sim.step_end(4e-4).unwrap();
    let summary = sim
        .advance(&end, &InputSample::default(), false, &mut |s| {
            times.push(s.time)
        })
        .unwrap();
    assert_eq!(summary.internal_steps, 4);
    assert_eq!(
        times,
        (1..=4).map(|n| 1.0 + n as f64 * 1e-4).collect::<Vec<_>>()
    );
    // A step ending between t_5 and t_6 computes up to t_6; the next one, ending before t_6,
    // computes nothing.
    assert_eq!(step(&mut sim, 1.5e-4, 0.0).internal_steps, 2);
    assert_eq!((sim.step_index(), sim.time()), (6, 1.0 + 5.5e-4));
    assert_eq!(sim.grid_time(), 1.0 + 6e-4);
    assert_eq!(step(&mut sim, 0.2e-4, 0.0).internal_steps, 0);
    assert_eq!(sim.step_index(), 6);
    assert!((sim.time() - (1.0 + 5.7e-4)).abs() < 1e-15);
}

/// The built-in sine alone: the grid, and so every grid value, is the same whatever the
/// communication steps.
#[test]
fn the_internal_trajectory_does_not_depend_on_the_communication_steps() {
    let mut scene = small(Scene::default());
    scene.base.amplitude = 0.009;
    scene.base.frequency = 35.0;
    let mut fixed = Simulation::new(&scene, 0.0, 0.0).unwrap();
    let mut random = Simulation::new(&scene, 0.0, 0.0).unwrap();
    let mut k = 0;
    while random.time() < 0.2 {
        step(&mut random, 1e-3 * factor(k), 0.0);
        k += 1;
    }
    // Land on the next grid point, then bring the fixed run there in whole steps.
    let n = random.step_index();
    let rest = random.grid_time() - random.time();
    step(&mut random, rest, 0.0);
    assert_eq!(random.step_index(), n);
    assert_eq!(random.time(), random.grid_time());
    while fixed.step_index() < n {
        step(&mut fixed, 1e-4, 0.0);
    }
    assert_eq!(random.state().stepper, fixed.state().stepper);
    assert_eq!(random.outputs(), fixed.outputs());
}

/// Released from a preload onto the lower obstacle with a fixed base, no load and e = 0: the
/// energy never increases between communication points of random size, the free corners
/// respect the obstacles at every communication point, and every vertex at every grid point.
#[test]
fn energy_never_increases_between_communication_points() {
    let mut scene = small(Scene::default());
    scene.obstacle.upper_enabled = false;
    scene.initial.preload_pressure = 8600.0 / (0.4 * 0.2);
    let mut sim = Simulation::new(&scene, 0.0, 0.0).unwrap();
    let scale = sim.outputs().energy_total.abs();
    let lower = scene.obstacle.lower;
    let mut energy = sim.outputs().energy_total;
    let mut between = 0;
    for k in 0..1500 {
        step(&mut sim, 1e-4 * 3.0 * factor(k), 0.0);
        let o = sim.outputs().clone();
        // Round-off: the energy identity holds per grid step to ~1e-13 of the scale.
        assert!(
            o.energy_total <= energy + 1e-12 * scale,
            "step {k}: the energy rose from {energy} J to {} J",
            o.energy_total
        );
        energy = o.energy_total;
        // Round-off of the contact solve: bounds hold to 1e-12 m.
        assert!(o.corner1 >= lower - 1e-12 && o.corner2 >= lower - 1e-12);
        let vertices = sim.stepper.constrained_displacements();
        assert!(vertices.iter().all(|&u| u >= lower - 1e-12));
        between += usize::from(sim.time() != sim.grid_time());
    }
    assert!(between > 1000, "only {between} points off the grid");
    assert!(
        energy < 0.9 * scale,
        "no impact took energy: {energy} J of {scale} J"
    );
}

/// Every internal step's contact is reported once, with the communication step that reaches
/// its grid time: random steps give the totals of single internal steps.
#[test]
fn contact_between_communication_points_is_reported_once() {
    let mut scene = small(Scene::default());
    scene.base.amplitude = 0.009;
    scene.base.frequency = 35.0;
    let totals = |random: bool| {
        let mut sim = Simulation::new(&scene, 0.0, 0.0).unwrap();
        let mut total = ContactSummary::default();
        let mut k = 0;
        while sim.time() < 0.3 - 1e-12 {
            let h = if random { 1e-3 * factor(k) } else { 1e-4 };
            let h = h.min(0.3 - sim.time());
            step(&mut sim, h, 0.0);
            total.merge(sim.contact());
            k += 1;
        }
        assert_eq!(
            sim.time(),
            sim.grid_time(),
            "the last step lands on t = 0.3 s"
        );
        total
    };
    let (fine, random) = (totals(false), totals(true));
    assert!(fine.impacts > 5, "{fine:?}");
    assert_eq!(random.impacts, fine.impacts);
    assert_eq!(random.peak_force, fine.peak_force);
    // The same terms summed in other groups: round-off only.
    assert!((random.impulse - fine.impulse).abs() <= 1e-12 * fine.impulse.abs());
}

/// The forced 35 Hz scene on the small mesh: impacts on both obstacles within 0.3 s.
fn forced_35hz() -> Scene {
    let mut scene = small(Scene::default());
    scene.base.amplitude = 0.009;
    scene.base.frequency = 35.0;
    scene
}

/// Early return: with the built-in sine as the only base motion, communication steps of random
/// size that stop at impacts have a communication point at the grid time of every impact, and
/// the grid trajectory is the one of single internal steps, bit for bit. Both ways of stopping
/// occur: after the internal step of the impact, and at once when the previous communication
/// step had computed it ahead.
#[test]
fn steps_that_stop_at_impacts_have_a_point_at_every_impact() {
    let scene = forced_35hz();
    let stop = 3000;
    let mut fine = Simulation::new(&scene, 0.0, 0.0).unwrap();
    let mut grid_bits = vec![trace_bits(fine.outputs())];
    let mut impacts = Vec::new();
    // Beyond `stop` by more than the longest communication step (15 internal steps).
    for n in 1..=stop + 20 {
        let end = fine.step_end(1e-4).unwrap();
        let mut impact = false;
        fine.advance(&end, &InputSample::default(), true, &mut |s| {
            impact |= s.report.impact
        })
        .unwrap();
        grid_bits.push(trace_bits(fine.outputs()));
        if impact && n <= stop {
            impacts.push(n);
        }
    }
    assert!(impacts.len() > 5, "{impacts:?}");
    let mut sim = Simulation::new(&scene, 0.0, 0.0).unwrap();
    let (mut reached, mut in_loop, mut at_once) = (Vec::new(), 0, 0);
    let mut k = 0;
    while sim.step_index() < stop {
        let end = sim.step_end(1e-3 * factor(k)).unwrap();
        let summary = sim
            .advance(&end, &InputSample::default(), true, &mut |_| {})
            .unwrap();
        if summary.stopped_at_impact {
            assert_eq!(
                sim.time(),
                sim.grid_time(),
                "an early return lands on the grid"
            );
            if summary.internal_steps == 0 {
                at_once += 1;
            } else {
                in_loop += 1;
            }
        }
        if sim.time() == sim.grid_time() {
            let n = sim.step_index();
            assert_eq!(
                trace_bits(sim.outputs()),
                grid_bits[n as usize],
                "grid point {n}"
            );
            reached.push(n);
        }
        k += 1;
    }
    let missed: Vec<_> = impacts.iter().filter(|n| !reached.contains(n)).collect();
    assert!(
        missed.is_empty(),
        "no communication point at the impacts {missed:?}"
    );
    assert_eq!(
        in_loop + at_once,
        impacts.len(),
        "one early return per impact"
    );
    assert!(
        in_loop > 0 && at_once > 0,
        "{in_loop} in the loop, {at_once} at once"
    );
}

/// Bits of corner1 and the energy of some outputs.
fn trace_bits(o: &Outputs) -> u64 {
    o.corner1.to_bits() ^ o.energy_total.to_bits().rotate_left(1)
}

/// The vertex field: on the grid its free corners are the corner outputs and the clamp carries
/// the base; between grid points it and the displacement outputs are interpolated, and their
/// rates are the slope of that interpolation, so extrapolating with them lands on the next
/// grid point; with and without obstacles (the two ways the vertex values are read).
#[test]
fn the_vertex_field_and_the_rates_follow_the_interpolation() {
    let (nx, ny) = (3, 2);
    let (corner1, corner2) = (nx, nx + ny * (nx + 1));
    for obstacles in [true, false] {
        let mut scene = small(Scene::default());
        scene.base.amplitude = 0.004;
        scene.base.frequency = 35.0;
        scene.obstacle.lower_enabled = obstacles;
        scene.obstacle.upper_enabled = obstacles;
        let mut sim = Simulation::new(&scene, 0.0, 0.0).unwrap();
        assert_eq!(
            sim.displacement_rates(),
            [0.0; crate::system::OUTPUT_POINTS],
            "released at rest"
        );
        assert!(sim.vertex_field().rate.iter().all(|&r| r == 0.0));
        for k in 0..40 {
            step(&mut sim, 1e-4 * (0.3 + 2.0 * factor(k)), 0.0);
            let o = sim.outputs().clone();
            let field = sim.vertex_field().clone();
            let rates = sim.displacement_rates();
            assert_eq!(field.displacement.len(), (nx + 1) * (ny + 1));
            // Two functionals of the same field (the point evaluation at the corner and
            // the vertex value): equal to round-off, 1e-12 of the 4 mm amplitude.
            let close = |a: f64, b: f64| (a - b).abs() <= 4e-15;
            assert!(
                close(field.displacement[corner1], o.corner1),
                "{k}: corner1"
            );
            assert!(
                close(field.displacement[corner2], o.corner2),
                "{k}: corner2"
            );
            // Their difference over Δt = 1e-4 s.
            let rate_gap = (field.rate[corner1] - rates[0]).abs();
            assert!(rate_gap <= 8e-11, "{k}: rates differ by {rate_gap} m/s");
            // The clamp follows the base: every clamp vertex has the same value.
            let clamp: Vec<f64> = (0..=ny).map(|j| field.displacement[j * (nx + 1)]).collect();
            assert!(clamp.iter().all(|&z| z == clamp[0]), "{clamp:?}");
            let (t, t_grid) = (sim.time(), sim.grid_time());
            if t != t_grid {
                let ahead = t_grid - t;
                let predicted = [
                    o.corner1 + rates[0] * ahead,
                    field.displacement[corner2] + field.rate[corner2] * ahead,
                ];
                step(&mut sim, ahead, 0.0);
                assert_eq!(sim.time(), sim.grid_time(), "snapped onto t_N");
                let landed = [
                    sim.outputs().corner1,
                    sim.vertex_field().displacement[corner2],
                ];
                for (p, l) in predicted.iter().zip(landed) {
                    // Round-off of (a + (b − a)θ) + (b − a)(1 − θ): a few ulps of 4 mm.
                    assert!((p - l).abs() <= 4e-15, "{k}: predicted {p}, landed {l}");
                }
                assert_eq!(
                    sim.displacement_rates(),
                    rates,
                    "the same slope from the left"
                );
            }
        }
    }
}

#[test]
fn state_round_trip_between_grid_points_continues_bit_identically() {
    let mut scene = small(Scene::default());
    scene.base.amplitude = 0.005;
    let mut sim = Simulation::new(&scene, 0.25, 0.0).unwrap();
    trace(&mut sim, 8, true);
    assert_ne!(
        sim.time(),
        sim.grid_time(),
        "the test needs a point between"
    );
    let state = sim.state();
    let expected = trace(&mut sim, 30, true);
    let mut other = Simulation::from_state(&state).unwrap();
    assert_eq!(trace(&mut other, 30, true), expected);
    sim.restore(&state).unwrap();
    assert_eq!(trace(&mut sim, 30, true), expected);
    // A crafted point outside its grid interval is refused, naming it.
    let mut crafted = state.clone();
    if let CommunicationPoint::Between { elapsed, .. } = &mut crafted.point {
        *elapsed += 1e-4;
    }
    let err = sim.restore(&crafted).unwrap_err().to_string();
    assert!(err.contains("communication point"), "{err}");
}
