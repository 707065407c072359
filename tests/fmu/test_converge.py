"""scripts/converge (plateimpact_tools.converge, docs/converge/README.md): on a damped scene it
converges and its recommended value agrees with a finer reference run within the tolerance; on the
undamped paper scene with a small budget it says "not converged" rather than a number; and against
a separately started `dask scheduler` with `dask worker` processes it writes the runs the local
cluster does.

Scene and windows are small so that each study costs a few CPU seconds: the damped preset
forced-35hz-damped (β = 5.913e-5 s, ζ_hf = 0.296 at Δt = 1e-4 s) on the Argyris 2 × 1 mesh,
0.5 s of transient (about 5 decay times 1/(ζ₁ω₁) = 0.1 s of its first mode) and 4 windows of
0.2 s (7 forcing periods each)."""

import csv
import hashlib
import os
import shutil
import signal
import socket
import subprocess
import sys
import time

import pytest

from conftest import ROOT
from plateimpact_tools import windows
from plateimpact_tools.converge import cost
from plateimpact_tools.converge import study as converge

TOLERANCE = 0.01
WINDOWS = ["--transient", "0.5", "--window", "0.2", "--windows", "4"]
DAMPED = ["--scene", str(ROOT / "scenes" / "forced-35hz-damped.json"), "mesh.nx=2", "mesh.ny=1"]
QUANTITIES = ["mean_energy", "rms_corner"]


def study(fmu_path, out, *args):
    """Runs scripts/converge; returns its last stdout line."""
    command = [str(ROOT / "scripts" / "converge"), "--out", str(out), "--fmu", fmu_path, *WINDOWS,
               *args]
    done = subprocess.run(command, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    return done.stdout.strip().splitlines()[-1]


def damped_args():
    return [*(a for q in QUANTITIES for a in ("--quantity", q)), "--tolerance", str(TOLERANCE),
            "--budget-seconds", "60", "--mesh", *DAMPED]


def runs(path):
    """runs.csv without its CPU time column, the one thing that depends on where runs ran."""
    with open(path) as f:
        rows = list(csv.DictReader(f))
    for row in rows:
        del row["cpu_s"]
    return rows


@pytest.fixture(scope="module")
def local_study(fmu_path, tmp_path_factory):
    out = tmp_path_factory.mktemp("converge-local")
    return study(fmu_path, out, *damped_args()), out


def test_damped_scene_converges_to_a_finer_reference(fmu_path, local_study):
    line, out = local_study
    assert line.startswith("converged: "), line
    settings = dict(item.split("=") for item in line.split("settings ")[1].split(";")[0].split())
    values = {q: float(line.split(f"{q} = ")[1].split()[0]) for q in QUANTITIES}
    for name in ("report.md", "runs.csv", "work_precision.png"):
        assert (out / name).stat().st_size > 0
    # The reference: a setting finer than any the study ran, in mesh (×2) and in Δt (/4), read
    # at the study's output interval h, the scene's (and the ladder's first) Δt.
    nx, ny = int(settings["mesh.nx"]), int(settings["mesh.ny"])
    dt = float(settings["solver.time_step"])
    scene = converge.load_scene(ROOT / "scenes" / "forced-35hz-damped.json")
    h = scene["solver.time_step"]
    scene.update({"mesh.element": 1, "mesh.nx": 2 * nx, "mesh.ny": 2 * ny,
                  "solver.time_step": dt / 4})
    blob = open(fmu_path, "rb").read()
    result, _ = converge.run_setting(blob, hashlib.sha256(blob).hexdigest(), scene, h,
                                     round(0.5 / h), round(0.2 / h), 4)
    for q in QUANTITIES:
        reference, _ = windows.value_and_spread(q, result["windows"][q])
        assert abs(values[q] - reference) <= TOLERANCE * abs(reference), (q, values[q], reference)


def test_undamped_paper_scene_with_a_small_budget_is_not_converged(fmu_path, tmp_path):
    """The paper's forced 35 Hz scene (Argyris 10 × 7, no damping): its mean energy grows by tens
    of per cent at each halving of Δt (docs/accuracy/damping.md), so 3 CPU s (a run costs about
    0.4 s at Δt = 1e-4 s, doubling at each halving) end the study before any pair agrees. The
    scene has no damping, so the FMU warns at every setting and its warning is the advice."""
    line = study(fmu_path, tmp_path, "--quantity", "mean_energy", "--quantity", "impact_rate",
                 "--tolerance", str(TOLERANCE), "--budget-seconds", "3",
                 "--scene", str(ROOT / "scenes" / "forced-35hz.json"))
    assert line.startswith("not converged: "), line
    assert "budget" in line, line
    advice = line.split("advice: ")[1]
    assert advice.startswith("the FMU warns at argyris 10x7, Δt = "), advice
    assert ": impact statistics may not converge: " in advice, advice
    assert "add stiffness-proportional damping" in advice, advice
    assert "docs/accuracy/damping.md" in advice, advice
    report = (tmp_path / "report.md").read_text()
    assert "Advice:" in report and "not converged" in report
    rows = [r for r in report.splitlines() if r.startswith("| dt-1 |")]
    assert rows and all("| yes |" in r for r in rows), rows  # every setting warned
    assert len(runs(tmp_path / "runs.csv")) >= 2 * 2  # two settings at least, two quantities


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_separate_scheduler_and_workers_give_the_local_runs(fmu_path, local_study, tmp_path):
    distributed = pytest.importorskip("distributed")
    dask = shutil.which("dask", path=os.path.dirname(sys.executable)) or shutil.which("dask")
    assert dask, "the dask command line (dask.distributed) is not installed"
    address = f"tcp://127.0.0.1:{free_port()}"
    port = address.rsplit(":", 1)[1]
    processes = []
    try:
        processes.append(subprocess.Popen(
            [dask, "scheduler", "--host", "127.0.0.1", "--port", port, "--no-dashboard"],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True))
        processes.append(subprocess.Popen(
            [dask, "worker", address, "--nworkers", "2", "--nthreads", "1", "--no-dashboard",
             "--local-directory", str(tmp_path / "workers")],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True))
        deadline = time.monotonic() + 120
        while True:  # the scheduler takes a moment to listen
            try:
                with distributed.Client(address, timeout=10) as client:
                    client.wait_for_workers(2, timeout=max(1, deadline - time.monotonic()))
                break
            except OSError:
                if time.monotonic() > deadline:
                    raise
                time.sleep(0.5)
        line = study(fmu_path, tmp_path / "out", *damped_args(), "--scheduler", address)
    finally:
        for process in reversed(processes):
            os.killpg(process.pid, signal.SIGTERM)
        for process in processes:
            try:
                process.wait(timeout=30)
            except subprocess.TimeoutExpired:
                os.killpg(process.pid, signal.SIGKILL)
                process.wait()
    local_line, local_out = local_study
    assert line.split("; cost")[0] == local_line.split("; cost")[0]
    assert runs(tmp_path / "out" / "runs.csv") == runs(local_out / "runs.csv")


def test_a_run_returns_the_fmus_warning(fmu_path):
    """The FMU's own advice, captured from its logger: the undamped paper scene warns at
    initialization, the damped preset at its Δt = 1e-4 s (ζ_hf = 0.296 ≥ 0.25) does not. On the
    Argyris 2 × 1 mesh (neither criterion depends on it), two windows of one step each: the
    warning comes before any step."""
    blob = open(fmu_path, "rb").read()
    digest = hashlib.sha256(blob).hexdigest()
    warnings = {}
    for name in ("forced-35hz", "forced-35hz-damped"):
        scene = converge.load_scene(ROOT / "scenes" / f"{name}.json")
        scene.update({"mesh.element": 1, "mesh.nx": 2, "mesh.ny": 1})
        result, _ = converge.run_setting(blob, digest, scene, scene["solver.time_step"], 0, 1, 2)
        warnings[name] = result["warning"]
    assert warnings["forced-35hz"].startswith("impact statistics may not converge: "), warnings
    assert warnings["forced-35hz-damped"] is None, warnings


def fake_study(quantity, values):
    """A Study whose ladder of Δt = 1e-4 / 2^k holds runs with the windows `values[k]` (no FMU)."""
    study = converge.Study("no.fmu", {}, [quantity], TOLERANCE, 1.0, transient=0.0, window=1e-4,
                           windows=2, dt0=1e-4, mesh=False, replicas=1, progress=False)
    ladder = [(2, 1, 1e-4 / 2 ** k) for k in range(len(values))]
    for setting, windows in zip(ladder, values):
        study.results[setting + (0,)] = {"windows": {quantity: windows}, "warning": None,
                                         "cpu": 0.0}
    return study, ladder


def test_a_count_must_agree_over_one_more_level():
    """Periodic windows (spread 0): 140, 70, 70 impacts per second pass at the last pair, but a
    count needs the pair before too, where it changed by half; a mean energy of the same numbers
    passes; 70, 70, 70 passes as a count, and a ladder of two settings cannot settle a count."""
    study, ladder = fake_study("impact_rate", [[140.0, 140.0], [70.0, 70.0], [70.0, 70.0]])
    assert study.check(ladder[-2], ladder[-1], "impact_rate")[0]
    assert not study.settled(ladder, "impact_rate")
    assert not study.settled(ladder[:2], "impact_rate")
    study, ladder = fake_study("mean_energy", [[140.0, 140.0], [70.0, 70.0], [70.0, 70.0]])
    assert study.settled(ladder, "mean_energy")
    study, ladder = fake_study("impact_rate", [[70.0, 70.0]] * 3)
    assert study.settled(ladder, "impact_rate")
    assert not study.settled(ladder[1:], "impact_rate")
    assert study.span == 3


def test_the_estimate_follows_the_backend(fmu_path):
    """From a run on Argyris 14 × 8 (modal), the estimate of 20 × 10 (1951 free dofs, modal) is
    the modal model's ratio, that of 21 × 10 (2048, just above the limit) the sparse model's over
    the modal one's: over 5 times what the modal model carried past the limit would say. With a
    modal damping ratio 21 × 10 stays modal and so does its estimate. Halving Δt on one mesh less
    than doubles it (set-up and communication steps stay). The windows of the documented
    example: 1 s of transient and 8 of 0.2857 s, read every 1e-4 s. The sizes and backends are
    the FMU's (tests/fmu/test_calculated.py checks them)."""
    study = converge.Study(fmu_path, {}, ["mean_energy"], TOLERANCE, 120.0, transient=1.0,
                           window=0.2857, windows=8, dt0=1e-4, mesh=True, replicas=1,
                           progress=False)
    study.results[(14, 8, 1e-4, 0)] = {"windows": {}, "warning": None, "cpu": 2.0}
    known = (14, 8, 1e-4)
    sim, h = study.simulated, study.h
    assert study.size((20, 10, 1e-4)) == (1951, "modal")
    assert study.size((21, 10, 1e-4)) == (2048, "sparse")

    def modal(nx, ny, dt):  # the modal model whatever the size
        return cost.run_cost((study.size((nx, ny, dt))[0], "modal"), 1, dt, sim, h)

    assert study.estimate(known, (20, 10, 1e-4)) == pytest.approx(
        2.0 * modal(20, 10, 1e-4) / modal(14, 8, 1e-4))
    above = study.estimate(known, (21, 10, 1e-4))
    (_, _), (step, p) = cost.RUN_COST[(1, "sparse")]
    sparse = 1e-6 * step * 2.048 ** p * sim / 1e-4 + 1e-6 * cost.COMMUNICATION_STEP_US * sim / h
    assert above == pytest.approx(2.0 * sparse / modal(14, 8, 1e-4))
    assert above > 5 * 2.0 * modal(21, 10, 1e-4) / modal(14, 8, 1e-4)
    assert above > 5 * study.estimate(known, (20, 10, 1e-4))
    study.scene["damping.modal_ratio"] = 0.01
    assert study.size((21, 10, 1e-4)) == (2048, "modal")
    assert study.estimate(known, (21, 10, 1e-4)) == pytest.approx(
        2.0 * modal(21, 10, 1e-4) / modal(14, 8, 1e-4))
    assert 1.0 < study.estimate(known, (14, 8, 5e-5)) / 2.0 < 2.0
