"""fmpy.simulate_fmu runs the default and the paper scenes, and matches the Rust library's run."""

import io
import subprocess

import numpy as np
import pytest
from fmpy import simulate_fmu

from conftest import ROOT, scene_start_values

# FMU output -> column of `examples/scene.rs`.
OUTPUTS = {
    "corner1.displacement": "corner1",
    "corner2.displacement": "corner2",
    "edge_mid.displacement": "edge_mid",
    "energy.total": "energy_total",
    "contact.active_nodes": "active",
    "contact.force": "contact_force",
}

# Short horizons keep the suite fast; the paper's 1 s runs are the examples' business.
STOP = 0.1
STEP = 1e-3


def rust_reference(scene, stop, every):
    """Outputs of `examples/scene.rs` (the library without the FMU) every `every` steps."""
    out = subprocess.run(
        [
            "cargo",
            "run",
            "--release",
            "--quiet",
            "--example",
            "scene",
            "--",
            scene,
            f"stop_time={stop}",
            "--every",
            str(every),
        ],
        cwd=ROOT,
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    return np.genfromtxt(io.StringIO(out), delimiter=",", names=True)


@pytest.mark.parametrize(
    "scene", ["default", "forced", "forced-30hz", "forced-35hz-damped", "energy"]
)
def test_simulate_matches_the_library(fmu_path, scene):
    start_values = {} if scene == "default" else scene_start_values(scene)[0]
    result = simulate_fmu(
        fmu_path,
        start_time=0.0,
        stop_time=STOP,
        output_interval=STEP,
        start_values=start_values,
        output=list(OUTPUTS),
    )
    time_step = start_values.get("solver.time_step", 1e-4)
    reference = rust_reference(scene, STOP, round(STEP / time_step))
    assert len(result) == len(reference)
    np.testing.assert_allclose(result["time"], reference["t"], rtol=0, atol=1e-12)
    for fmu_name, column in OUTPUTS.items():
        # Same steps, same base: the FMU layer adds nothing, so the numbers are identical.
        np.testing.assert_array_equal(result[fmu_name], reference[column], err_msg=fmu_name)
    assert np.all(np.isfinite(result["corner1.displacement"]))


def test_simulate_default_experiment(fmu_path):
    result = simulate_fmu(fmu_path, output=["corner1.displacement"])
    assert result["time"][-1] == pytest.approx(1.0)
    assert len(result) == 1001


def test_nonzero_start_time_shifts_the_plate_clock(fmu_path):
    # The plate's clock starts at the experiment's start time: the same run, shifted.
    start = {"base.amplitude": 0.005}
    a = simulate_fmu(
        fmu_path,
        start_time=0.0,
        stop_time=0.05,
        output_interval=STEP,
        start_values=start,
        output=["corner1.displacement"],
    )
    b = simulate_fmu(
        fmu_path,
        start_time=0.5,
        stop_time=0.55,
        output_interval=STEP,
        start_values=start,
        output=["corner1.displacement"],
    )
    np.testing.assert_allclose(b["time"] - 0.5, a["time"], atol=1e-12)
    np.testing.assert_array_equal(a["corner1.displacement"], b["corner1.displacement"])
