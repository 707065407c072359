"""Communication steps of any size (docs/fmu.md, "A communication step"): the internal steps stay on
the fixed grid t_n = t_start + n dt whatever h is, the FMU reports at t + h, interpolating linearly
between the grid points around it, and a step that ends on a grid point gives the same bits as
whole steps."""

import math

import numpy as np
import pytest
from fmpy import simulate_fmu

from conftest import scene_start_values

DT = 1e-4  # solver.time_step of every scene
CONTINUOUS = [
    "corner1.displacement",
    "corner2.displacement",
    "edge_mid.displacement",
    "energy.kinetic",
    "energy.elastic",
    "energy.total",
]
CONTACT = ["contact.active_nodes", "contact.force"]
NO_OBSTACLES = {"obstacle.lower_enabled": False, "obstacle.upper_enabled": False}


def adaptive_steps(seed, horizon, scale=1e-3):
    """Step sizes of an adaptive master: scale x a factor drawn uniformly in [0.2, 1.5] each step,
    the last one shortened to end on the horizon."""
    rng = np.random.default_rng(seed)
    steps, t = [], 0.0
    while t < horizon - 1e-12:
        h = min(scale * rng.uniform(0.2, 1.5), horizon - t)
        steps.append(h)
        t += h
    return steps


def drive(plate, steps, names=("corner1.displacement",), inputs=None):
    """Steps `plate` by each h of `steps` (setting base.displacement from `inputs(t)` if given)
    and returns the communication times and the outputs there."""
    times, rows = [], []
    for h in steps:
        if inputs is not None:
            plate.set("base.displacement", inputs(plate.time))
        plate.fmu.doStep(plate.time, h)
        plate.time = plate.fmu.getRealStatus(2)  # fmi2LastSuccessfulTime: the FMU's t + h
        times.append(plate.time)
        rows.append([plate.get(n) for n in names])
    return np.array(times), np.array(rows)


def test_a_stop_time_off_the_grid_is_reached_by_interpolation(fmu_path):
    """fmpy shortens the last step to land on a stop time off the grid (`-s 0.09995`)."""
    start, _ = scene_start_values("forced-35hz")
    names = CONTINUOUS + CONTACT
    grid = simulate_fmu(
        fmu_path, stop_time=0.1, output_interval=DT, start_values=start, output=names
    )
    off = simulate_fmu(
        fmu_path, stop_time=0.09995, output_interval=1e-3, start_values=start, output=names
    )
    assert off["time"][-1] == pytest.approx(0.09995, abs=1e-15)
    # Every 1 ms point is a grid point: the same bits as the grid run there.
    for row in off[:-1]:
        n = round(row["time"] / DT)
        for name in names:
            assert row[name] == grid[n][name], (row["time"], name)
    # The last point lies halfway between t_999 and t_1000: continuous outputs interpolated, the
    # contact state of t_999. Tolerance: theta = 0.5 up to the round-off of the times (~1e-12).
    a, b, last = grid[999], grid[1000], off[-1]
    for name in CONTINUOUS:
        expected = a[name] + 0.5 * (b[name] - a[name])
        assert abs(last[name] - expected) <= 1e-9 * abs(b[name] - a[name]) + 4 * np.spacing(
            abs(a[name])
        ), name
    for name in CONTACT:
        assert last[name] == a[name], name


def test_tiny_and_half_steps_return_to_the_grid_bit_for_bit(new_plate):
    forced = {"base.amplitude": 0.009, "base.frequency": 35.0}
    whole = new_plate("whole").initialize(forced)
    _, expected = drive(whole, [1e-3] * 20)
    for name, first in [
        ("tiny", [1e-9] * 5 + [1e-3 - 5e-9]),
        ("halves", [0.5 * DT] * 20),
        ("three-halves", [1.5 * DT] * 6 + [1e-4]),
    ]:
        p = new_plate(name).initialize(forced)
        times, _ = drive(p, first)
        assert times[0] > 0 and np.all(np.diff(times) > 0), name
        assert times[-1] == pytest.approx(1e-3, abs=1e-15), name
        _, rest = drive(p, [1e-3] * 19)
        assert rest.tobytes() == expected[1:].tobytes(), name


def corner_error(fmu_path, new_plate, steps, reference_dt=1e-6):
    """Largest |corner1 - reference| over the communication points of `steps`, the reference being
    the same plate at dt = 1e-6 s driven through the same communication points."""
    forced = dict(NO_OBSTACLES, **{"base.amplitude": 0.002, "base.frequency": 35.0})
    runs = []
    for dt in (DT, reference_dt):
        p = new_plate(f"dt{dt}").initialize(dict(forced, **{"solver.time_step": dt}))
        runs.append(drive(p, steps))
    (t, coarse), (t_ref, fine) = runs
    # The same times up to the round-off of forming them on two grids (n dt).
    assert np.max(np.abs(t - t_ref)) < 1e-13
    return float(np.max(np.abs(coarse - fine)))


def test_adaptive_master_steps_are_as_accurate_as_fixed_ones(fmu_path, new_plate):
    """The measured target: a contact-free plate driven by the built-in sine, communication steps
    of 1 ms x a factor drawn in [0.2, 1.5], within 2x the error of fixed 1 ms steps against a fine
    reference (dt = 1e-6 s) at the same times."""
    horizon = 0.5
    fixed = corner_error(fmu_path, new_plate, [1e-3] * round(horizon / 1e-3))
    for seed in (1, 2):
        adaptive = corner_error(fmu_path, new_plate, adaptive_steps(seed, horizon))
        print(
            f"seed {seed}: corner1 error {adaptive:.3e} m with adaptive steps, {fixed:.3e} m with 1 ms steps"
        )
        assert adaptive <= 2 * fixed, (adaptive, fixed)


def test_energy_never_increases_between_random_communication_points(new_plate):
    """Fixed base, no load, e = 0: the energy scene (released onto the lower obstacle)."""
    start, _ = scene_start_values("energy")
    p = new_plate().initialize(start)
    names = ["energy.total", "corner1.displacement", "corner2.displacement", "contact.active_nodes"]
    scale = abs(p.get("energy.total"))
    times, rows = drive(p, adaptive_steps(3, 0.5), names)
    energy = rows[:, 0]
    rises = np.diff(energy)
    # Round-off: the energy identity holds per grid step to ~1e-13 of the scale (docs/scheme.md).
    assert np.max(rises) <= 1e-11 * scale, np.max(rises)
    assert energy[-1] < 0.9 * scale, "no impact took energy"
    assert np.sum(rows[:, 3] > 0) > 10, "the plate never touched the obstacle"
    lower = start["obstacle.lower"]
    # The free corners are constrained vertices; their bound holds to round-off (1e-12 m).
    assert np.min(rows[:, 1:3]) >= lower - 1e-12


def test_get_set_state_between_grid_points_repeats_a_random_run(new_plate):
    p = new_plate("a").initialize({"base.amplitude": 0.009, "base.frequency": 10.0})
    steps = adaptive_steps(4, 0.2)
    signal = lambda t: 5e-4 * math.sin(37.0 * t)  # noqa: E731
    names = CONTINUOUS + CONTACT
    drive(p, steps[:60], names, signal)
    assert abs(p.time / DT - round(p.time / DT)) > 1e-6, (
        "the state must be saved between grid points"
    )
    t0 = p.time
    state = p.fmu.getFMUstate()
    data = p.fmu.serializeFMUstate(state)
    first = drive(p, steps[60:], names, signal)
    p.fmu.setFMUstate(state)
    p.time = t0
    again = drive(p, steps[60:], names, signal)
    assert first[0].tobytes() == again[0].tobytes() and first[1].tobytes() == again[1].tobytes()
    q = new_plate("b").initialize()
    q.fmu.setFMUstate(q.fmu.deSerializeFMUstate(data))
    q.time = t0
    copy = drive(q, steps[60:], names, signal)
    assert first[1].tobytes() == copy[1].tobytes()
