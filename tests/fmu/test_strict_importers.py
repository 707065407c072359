"""The default experiment runs to the end in importers that stop at any status but OK.

The start-up advice (impact statistics may not converge with these settings, docs/fmu.md "Errors
and logging") is a logged message of status Warning under logStatusWarning while
ExitInitializationMode returns OK, so a strict importer goes on. Through fmpy, every FMI call of the
default experiment must return OK in both FMI versions, the advice logged once. The same experiment
in fmusim (the modelica Reference-FMUs' simulator, which ends a run at any other status) runs when
the environment variable FMUSIM names its binary; docs/fmu.md ("Engines tried") says how it was
built and what it gave."""

import csv
import math
import os
import pathlib
import subprocess

import pytest
from fmpy import read_model_description, simulate_fmu

from conftest import reinstall_session_logger, scene_start_values

ADVICE = "impact statistics may not converge"


@pytest.fixture(params=[2, 3], ids=["fmi2", "fmi3"])
def fmu(request, fmu_path, fmu3_path):
    return fmu_path if request.param == 2 else fmu3_path


def test_the_default_experiment_returns_ok_from_every_call(fmu):
    calls, messages = [], []

    def logger(*args):  # FMI 2.0 passes (env, instance, ...), FMI 3.0 (env, ...)
        status, category, message = args[-3:]
        messages.append((status, category.decode(), message.decode()))

    try:
        result = simulate_fmu(fmu, fmi_call_logger=calls.append, logger=logger, debug_logging=False)
    finally:
        reinstall_session_logger()
    md = read_model_description(fmu)
    stop = float(md.defaultExperiment.stopTime)
    assert result["time"][-1] == pytest.approx(stop, abs=1e-12)
    statuses = [
        line.rsplit(" -> ", 1)[1]
        for line in calls
        if " -> " in line and not line.rsplit(" -> ", 1)[1].startswith("0x")
    ]
    assert statuses and set(statuses) == {"OK"}, [c for c in calls if not c.endswith("OK")]
    advice = [m for s, c, m in messages if c == "logStatusWarning" and m.startswith(ADVICE)]
    assert len(advice) == 1 and all(s == 1 for s, c, m in messages if m in advice), messages


def fmusim():
    binary = os.environ.get("FMUSIM")
    if not binary:
        pytest.skip(
            "FMUSIM does not name an fmusim binary (the modelica Reference-FMUs' "
            "simulator, built by hand as docs/fmu.md describes; no registry ships it)"
        )
    if not pathlib.Path(binary).is_file():
        pytest.fail(f"FMUSIM={binary} is not a file")
    return binary


def run_fmusim(binary, fmu, out, start_values):
    command = [binary, "--output-file", str(out)]
    for name, value in start_values.items():
        command += ["--start-value", name, str(value).lower()]
    done = subprocess.run(command + [str(fmu)], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, f"fmusim failed:\n{done.stdout}\n{done.stderr}"
    with open(out, newline="") as f:
        rows = list(csv.DictReader(f))
    return rows, done.stdout + done.stderr


def test_fmusim_runs_the_default_experiment_to_the_end(fmu, tmp_path):
    binary = fmusim()
    rows, log = run_fmusim(binary, fmu, tmp_path / "default.csv", {})
    assert len(rows) == 1001 and float(rows[-1]["time"]) == pytest.approx(1.0)
    assert ADVICE in log


def test_fmusim_gives_fmpys_numbers_with_damping(fmu, tmp_path):
    """The damped 35 Hz preset for 0.1 s: fmusim prints 16 significant digits, fmpy's values
    rounded alike are the same numbers."""
    binary = fmusim()
    start = {
        k: v for k, v in scene_start_values("forced-35hz-damped")[0].items() if k != "mesh.element"
    }  # argyris, the default
    rows, _ = run_fmusim(binary, fmu, tmp_path / "damped.csv", {**start})
    rows = [r for r in rows if float(r["time"]) <= 0.1 + 1e-12]
    result = simulate_fmu(fmu, stop_time=0.1, output_interval=1e-3, start_values=start)
    assert len(rows) == len(result) == 101
    # The scalar outputs (the FMI 3.0 field plate.displacement is an array).
    names = [
        n
        for n in result.dtype.names
        if n != "time" and n in rows[0] and result.dtype[n].shape == ()
    ]
    assert len(names) == 17, names
    for row, expected in zip(rows, result):
        for name in names:
            printed = float(row[name])
            value = float(expected[name])
            # %.16g keeps 16 significant digits: the two agree to within a rounding of the 16th.
            assert math.isclose(printed, float(f"{value:.16g}"), rel_tol=1e-15, abs_tol=0), (
                row["time"],
                name,
                printed,
                value,
            )
