"""The frequency sweep (plateimpact_tools.studies.frequency_sweep): Dask gives the serial answer bit for bit, the
undamped linear plate resonates at the library's first natural frequency, and the continuation
sweep drives a continuous base and finds the linear plate's unique steady state up and down."""

import math

import pytest

from plateimpact_tools.fmu_dask import local_cluster
from plateimpact_tools.studies import frequency_sweep

# A coarse mesh keeps every run a few hundredths of a second: Argyris 4 x 2 (103 free dofs) has
# f1 = 53.89 Hz against 53.83 Hz on the paper's 10 x 7, so the same physics at a fraction of the cost.
COARSE = {"mesh.element": 1, "mesh.nx": 4, "mesh.ny": 2}


def test_dask_sweep_equals_serial_bit_for_bit(fmu_path):
    distributed = pytest.importorskip("distributed")
    # With obstacles and c = 5 mm the plate hits them at all four frequencies (so the contact QP
    # path runs, not only the linear recurrence); 0.2 s gives 6 to 12 whole periods in the last
    # half, enough for every summary column to be a number rather than NaN.
    fixed = dict(COARSE, **{"base.amplitude": 0.005, "solver.time_step": 1e-4})
    frequencies = [30.0, 40.0, 50.0, 60.0]
    kwargs = dict(fixed=fixed, configs=("obstacles",), stop_time=0.2, progress=False)
    serial = frequency_sweep.sweep(fmu_path, frequencies, **kwargs)
    with local_cluster(2) as cluster, distributed.Client(cluster) as client:
        parallel = frequency_sweep.sweep(fmu_path, frequencies, client=client, **kwargs)
    assert [r["base.frequency"] for r in parallel] == frequencies
    assert all(r["impacts"] > 0 for r in serial)
    for a, b in zip(serial, parallel):
        assert a["trajectory_sha256"] == b["trajectory_sha256"]  # every output sample, every bit
        for key, value in a.items():
            assert isinstance(value, (str, int, tuple)) or not math.isnan(value)
            assert b[key] == value, key


def test_free_plate_resonates_at_first_natural_frequency(fmu_path):
    """Undamped and without obstacles the plate is linear. Driven from rest at a detuning Δf from
    the first mode, that mode's response is a beat with envelope |sin(π Δf t)/(π Δf)|, growing
    linearly in time at resonance (Δf = 0). Over a horizon T with a frequency step δf ≤ 1/T, the
    grid point nearest f1 (|Δf| ≤ δf/2) reaches at least 2/π of T in the last half, while every
    other point (|Δf| ≥ δf/2 on the other side of f1, or ≥ δf) stays below it, so the largest peak
    lies at the grid point nearest to f1.
    The β = ½ scheme lengthens the period: its discrete resonance is f1·(1 − 5/24·(2π f1 Δt)²),
    0.05 Hz low at Δt = 2e-4 s, well inside δf/2 = 0.5 Hz; 2e-4 s rather than the default 1e-4 s
    halves the cost. The other modes (f2 = 232 Hz) and the rigid base motion add a bounded,
    non-growing part, small against the resonant growth at c = 0.1 mm."""
    f1 = frequency_sweep.natural_frequencies(COARSE)[0]
    horizon, resolution = 1.0, 1.0  # T·δf = 1
    frequencies = [46.0 + resolution * i for i in range(17)]  # 46 ... 62 Hz, f1 inside
    fixed = dict(COARSE, **{"base.amplitude": 1e-4, "solver.time_step": 2e-4})
    rows = frequency_sweep.sweep(
        fmu_path, frequencies, fixed=fixed, configs=("free",), stop_time=horizon, progress=False
    )
    assert all(r["impacts"] == 0 and r["dissipated_per_period_J"] == 0.0 for r in rows)
    best = max(rows, key=lambda r: r["peak_corner_m"])
    assert abs(best["base.frequency"] - f1) <= resolution / 2, (best["base.frequency"], f1)
    # and the resonance stands out: the neighbours a full step away respond clearly less
    peaks = {r["base.frequency"]: r["peak_corner_m"] for r in rows}
    f_best = best["base.frequency"]
    assert peaks[f_best - resolution] < 0.7 * peaks[f_best]
    assert peaks[f_best + resolution] < 0.7 * peaks[f_best]


def test_base_schedule_is_continuous_and_switches_at_crests():
    """The continuation's base: z continuous at every frequency change, which happens at the grid
    time nearest a crest, so the base velocity jumps by at most c·2π·|Δf|·πfΔt (|cos φ| ≤ πfΔt
    there); each dwell lasts the requested periods to within half a period (crests are half a
    period apart) and one step."""
    c, dt = 0.002, 1e-4
    schedule = frequency_sweep.BaseSchedule(c, dt)
    schedule.tune(40.0)
    z0, v0, _ = schedule.at(0)
    # starts at a crest, at rest (cos(π/2) is 6e-17 in doubles)
    assert z0 == c and abs(v0) <= 1e-15 * c * 2 * math.pi * 40.0
    previous = None
    for f, periods in [(40.0, 60), (41.0, 61), (47.5, 70), (90.0, 135), (89.0, 133), (30.0, 45)]:
        schedule.tune(f)
        if previous is not None:
            z_end, v_end, f_old = previous
            z, v, _ = schedule.at(0)
            assert abs(z - z_end) <= 1e-15 * c  # the same phase: the same position
            assert abs(v - v_end) <= c * 2 * math.pi * abs(f - f_old) * math.pi * f_old * dt + 1e-15
        steps = schedule.dwell_steps(periods)
        assert abs(steps * dt * f - periods) <= 0.5 + f * dt
        z, v, _ = schedule.at(steps)
        assert abs(math.cos(schedule.phase + 2 * math.pi * f * steps * dt)) <= math.pi * f * dt
        previous = (z, v, f)
        schedule.advance(steps)


def test_branches_differ_only_beyond_tolerance_and_spread():
    """The hysteresis finder: a gap in RMS counts only beyond both 3 % of the mean and 3σ of the
    difference, or when one branch impacts and the other does not. Rows are built by hand, so the
    thresholds are tested exactly: 5 % apart with σ = 1 % each (3σ of the difference = 4.2 %)
    differs; 5 % apart with σ = 2 % each (8.5 %) is chaotic scatter; 2.9 % apart with no spread is
    within the 3 % tolerance; equal RMS with impacts on one branch only differs."""

    def row(rms, spread, impacts=1.0):
        return {"rms_corner_m": rms, "rms_corner_spread_m": spread, "impacts_per_period": impacts}

    differ = frequency_sweep.branches_differ
    assert differ(row(1.025, 0.01), row(0.975, 0.01))
    assert not differ(row(1.025, 0.02), row(0.975, 0.02))
    assert not differ(row(1.0145, 0.0), row(0.9855, 0.0))
    assert differ(row(1.0, 0.0, impacts=0.0), row(1.0, 0.0))


def test_continuation_reaches_the_steady_state_of_runs_from_rest(fmu_path):
    """Without obstacles the damped plate is linear and has one steady state per frequency, so
    the continuation sweep, up and down, must find the same peak as runs from rest with the
    built-in sine. With ζ₁ = 5 % from α every mode's transient decays like exp(−αt/2) =
    exp(−17 t/s): after 1 s of settling (and of the runs from rest) it is 4e-8 of its start.
    What remains: the peak is sampled on the Δt grid at a different phase in the two runs, which
    lowers it by at most 1 − cos(πfΔt) ≤ 1.8e-4 at 60 Hz, and the input the continuation drives is
    extrapolated over each step to O((2πfΔt)³/6) ≈ 1e-5 of c. Tolerance 1e-3 of the peak."""
    f1 = frequency_sweep.natural_frequencies(COARSE, count=1)[0]
    fixed = dict(
        COARSE,
        **{"damping.mass_proportional": 2 * 0.05 * 2 * math.pi * f1, "solver.time_step": 1e-4},
    )
    frequencies = [40.0, 52.0, 60.0]
    rows = frequency_sweep.continuation(
        fmu_path,
        frequencies,
        amplitude=0.002,
        fixed=fixed,
        configs=("free",),
        settle=1.0,
        measure=0.5,
        progress=False,
    )
    from_rest = frequency_sweep.sweep(
        fmu_path,
        frequencies,
        fixed=dict(fixed, **{"base.amplitude": 0.002}),
        configs=("free",),
        stop_time=2.0,
        progress=False,
    )
    assert [r["direction"] for r in rows] == ["up"] * 3 + ["down"] * 3
    assert all(r["impacts_per_period"] == 0 and r["dissipated_per_period_J"] == 0 for r in rows)
    for reference in from_rest:
        f = reference["base.frequency"]
        for r in (r for r in rows if r["base.frequency"] == f):
            assert r["peak_corner_m"] == pytest.approx(reference["peak_corner_m"], rel=1e-3), (
                f,
                r["direction"],
            )
    assert frequency_sweep.hysteresis(rows) == {("free", ()): []}


def test_dask_continuation_equals_serial(fmu_path):
    """A continuation sweep is one instance per configuration: on a cluster it must give the serial
    rows exactly. Short dwells keep it cheap; c = 5 mm makes the plate impact at both frequencies."""
    distributed = pytest.importorskip("distributed")
    kwargs = dict(amplitude=0.005, fixed=dict(COARSE), settle=0.1, measure=0.1, progress=False)
    serial = frequency_sweep.continuation(fmu_path, [50.0, 60.0], **kwargs)
    with local_cluster(2) as cluster, distributed.Client(cluster) as client:
        parallel = frequency_sweep.continuation(fmu_path, [50.0, 60.0], client=client, **kwargs)
    assert parallel == serial
    assert any(r["impacts_per_period"] > 0 for r in serial if r["config"] == "obstacles")
