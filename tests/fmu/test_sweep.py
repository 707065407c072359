"""The frequency sweep (examples/frequency_sweep.py): Dask gives the serial answer bit for bit, and
the undamped linear plate resonates at the library's first natural frequency."""

import importlib.util
import math
import sys

import pytest

from conftest import ROOT

spec = importlib.util.spec_from_file_location("frequency_sweep",
                                              ROOT / "examples" / "frequency_sweep.py")
frequency_sweep = importlib.util.module_from_spec(spec)
sys.modules[spec.name] = frequency_sweep  # the name its tasks are pickled under
spec.loader.exec_module(frequency_sweep)

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
    with frequency_sweep.local_cluster(2) as cluster, distributed.Client(cluster) as client:
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
    rows = frequency_sweep.sweep(fmu_path, frequencies, fixed=fixed, configs=("free",),
                                 stop_time=horizon, progress=False)
    assert all(r["impacts"] == 0 and r["dissipated_per_period_J"] == 0.0 for r in rows)
    best = max(rows, key=lambda r: r["peak_corner_m"])
    assert abs(best["base.frequency"] - f1) <= resolution / 2, (best["base.frequency"], f1)
    # and the resonance stands out: the neighbours a full step away respond clearly less
    peaks = {r["base.frequency"]: r["peak_corner_m"] for r in rows}
    f_best = best["base.frequency"]
    assert peaks[f_best - resolution] < 0.7 * peaks[f_best]
    assert peaks[f_best + resolution] < 0.7 * peaks[f_best]
