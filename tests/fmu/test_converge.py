"""scripts/converge (plateimpact_tools.converge, docs/converge/README.md) through the FMU: on a
damped scene it converges and its recommended value agrees with a finer reference run within the
tolerance; a scene with two coexisting steady states is reported with both, each with its share of
the starts and a value near a finer run of its own starts; the damped preset started from a
coarse Δt is not accepted on its plateau; undamped or only mass-damped scenes say "not converged"
rather than a number; and a separately started `dask scheduler` with `dask worker` processes
writes the runs the local cluster does. The rule and the grouping alone are tested on synthetic
ladders in test_converge_rule.py.

Scene and windows are small so that each study costs a few CPU seconds: the damped preset
forced-35hz-damped (β = 5.913e-5 s, ζ_hf = 0.296 at Δt = 1e-4 s) on the Argyris 2 × 1 mesh,
0.5 s of transient (about 5 decay times 1/(ζ₁ω₁) = 0.1 s of its first mode) and 4 windows of
0.2 s (7 forcing periods each)."""

import csv
import hashlib
import math
import os
import shutil
import signal
import socket
import subprocess
import sys
import time

import pytest

from conftest import ROOT
from plateimpact_tools import scene_values, windows
from plateimpact_tools.converge import cost
from plateimpact_tools.converge import runs as converge_runs
from plateimpact_tools.converge import study as converge

TOLERANCE = 0.01
WINDOWS = ["--transient", "0.5", "--window", "0.2", "--windows", "4"]
DAMPED = ["--scene", str(ROOT / "scenes" / "forced-35hz-damped.json"), "mesh.nx=2", "mesh.ny=1"]
QUANTITIES = ["mean_energy", "rms_corner"]


def study(fmu_path, out, *args):
    """Runs scripts/converge; returns its last stdout line."""
    command = [
        str(ROOT / "scripts" / "converge"),
        "--out",
        str(out),
        "--fmu",
        fmu_path,
        *WINDOWS,
        *args,
    ]
    done = subprocess.run(command, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    return done.stdout.strip().splitlines()[-1]


def damped_args():
    return [
        *(a for q in QUANTITIES for a in ("--quantity", q)),
        "--tolerance",
        str(TOLERANCE),
        "--budget-seconds",
        "60",
        "--mesh",
        *DAMPED,
    ]


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
    # The reference: a setting finer than any the study ran, in mesh (4/3 per direction beyond
    # the recommended one, which closed the mesh ladder) and in Δt (/4), read at the study's
    # output interval h, the scene's (and the ladder's first) Δt. The mesh stays on the modal
    # backend: the study recommends Argyris 12 × 8, and 16 × 11 has 1708 free dofs where ×2
    # (24 × 16) or ×1.5 (18 × 12, 2083) are sparse, about 50 times the CPU per step (minutes).
    nx, ny = int(settings["mesh.nx"]), int(settings["mesh.ny"])
    dt = float(settings["solver.time_step"])
    scene = scene_values.scene("forced-35hz-damped")[0]
    h = scene["solver.time_step"]
    scene.update(
        {
            "mesh.element": 1,
            "mesh.nx": math.ceil(4 * nx / 3),
            "mesh.ny": math.ceil(4 * ny / 3),
            "solver.time_step": dt / 4,
        }
    )
    assert cost.plate_size(fmu_path, scene)[1] == "modal", scene
    reference = reference_values(fmu_path, scene, h, converge_runs.Start("abrupt"))
    for q in QUANTITIES:
        assert abs(values[q] - reference[q]) <= TOLERANCE * abs(reference[q]), (
            q,
            values[q],
            reference[q],
        )
    assert "one steady state (5 of 5 starts)" in line, line
    assert line.endswith("the FMU does not warn at these settings"), line


def reference_values(fmu_path, scene, h, start, transient=0.5, window=0.2, count=4):
    """{quantity: value} of one run of `scene` from `start` with the given windows."""
    blob = open(fmu_path, "rb").read()
    result, _ = converge_runs.run_setting(
        blob,
        hashlib.sha256(blob).hexdigest(),
        scene,
        start,
        h,
        round(transient / h),
        round(window / h),
        count,
    )
    return {q: windows.value_and_spread(q, result["windows"][q])[0] for q in result["windows"]}


def values_of(part, quantities):
    """{quantity: (value, relative bound)} from a verdict's `q = v unit ± b %` items."""
    found = {}
    for q in quantities:
        tokens = part.split(f"{q} = ")[1].split()
        found[q] = (float(tokens[0]), float(tokens[3]) / 100)
    return found


@pytest.mark.slow  # over 30 s on the loaded 2-core machine
def test_undamped_paper_scene_with_a_small_budget_is_not_converged(fmu_path, tmp_path):
    """The paper's forced 35 Hz scene (Argyris 10 × 7, no damping): its mean energy grows by tens
    of per cent at each halving of Δt (docs/accuracy/damping.md), so 3 CPU s (the first three
    settings from five starts cost about that) end the study before any three settings agree.
    The scene has no damping, so the FMU warns at every setting and its warning is the advice."""
    line = study(
        fmu_path,
        tmp_path,
        "--quantity",
        "mean_energy",
        "--quantity",
        "impact_rate",
        "--tolerance",
        str(TOLERANCE),
        "--budget-seconds",
        "3",
        "--scene",
        str(ROOT / "scenes" / "forced-35hz.json"),
    )
    assert line.startswith("not converged: "), line
    assert "budget" in line, line
    advice = line.split("advice: ")[1]
    assert advice.startswith("the FMU warns at argyris 10x7, Δt = "), advice
    assert ": impact statistics may not converge: " in advice, advice
    assert "add stiffness-proportional damping" in advice, advice
    assert "docs/accuracy/damping.md" in advice, advice
    report = (tmp_path / "report.md").read_text()
    assert "Advice:" in report and "not converged" in report
    table = report.split("## Runs")[1]
    rows = [r for r in table.splitlines() if r.startswith("| dt-1 |")]
    assert rows and all("| yes |" in r for r in rows), rows  # every setting warned
    assert len(runs(tmp_path / "runs.csv")) >= 2 * 2  # two settings at least, two quantities


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.slow  # over 30 s on the loaded 2-core machine
def test_separate_scheduler_and_workers_give_the_local_runs(fmu_path, local_study, tmp_path):
    distributed = pytest.importorskip("distributed")
    dask = shutil.which("dask", path=os.path.dirname(sys.executable)) or shutil.which("dask")
    assert dask, "the dask command line (dask.distributed) is not installed"
    address = f"tcp://127.0.0.1:{free_port()}"
    port = address.rsplit(":", 1)[1]
    processes = []
    try:
        processes.append(
            subprocess.Popen(
                [dask, "scheduler", "--host", "127.0.0.1", "--port", port, "--no-dashboard"],
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
                start_new_session=True,
            )
        )
        processes.append(
            subprocess.Popen(
                [
                    dask,
                    "worker",
                    address,
                    "--nworkers",
                    "2",
                    "--nthreads",
                    "1",
                    "--no-dashboard",
                    "--local-directory",
                    str(tmp_path / "workers"),
                ],
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
                start_new_session=True,
            )
        )
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
        scene = scene_values.scene(name)[0]
        scene.update({"mesh.element": 1, "mesh.nx": 2, "mesh.ny": 1})
        result, _ = converge_runs.run_setting(
            blob, digest, scene, converge_runs.Start("abrupt"), scene["solver.time_step"], 0, 1, 2
        )
        warnings[name] = result["warning"]
    assert warnings["forced-35hz"].startswith("impact statistics may not converge: "), warnings
    assert warnings["forced-35hz-damped"] is None, warnings


# Two coexisting steady states: the paper's plate on Argyris 4 × 2 (f₁ = 53.9 Hz), the base at
# 68 Hz with c = 2 mm, β for ζ₁ = 1 %: within the band where the project's frequency sweep found
# an impacting and a contact-free response side by side (docs/sweep/). An abrupt start, the sweep
# from below and the kick settle on two impacts per period (16.07 J), the ramp and the sweep from
# above on the quiet response (5.58 J), at every Δt from 4e-4 to 2.5e-5 s.
COEXISTING = [
    "mesh.nx=4",
    "mesh.ny=2",
    "base.amplitude=0.002",
    "base.frequency=68",
    "damping.stiffness_proportional=5.9e-5",
]


def test_coexisting_states_are_each_reported_with_their_share(fmu_path, tmp_path):
    """Both states are named on the verdict line with their shares of the five starts, each
    with its value and bound; each value agrees within the tolerance (and within its bound plus
    the reference's own error, a quarter of the bound at Δt/4 for an order ≥ 1) with a run at a
    quarter of the recommended Δt from one of its own starts."""
    line = study(
        fmu_path,
        tmp_path,
        "--quantity",
        "mean_energy",
        "--quantity",
        "rms_corner",
        "--tolerance",
        str(TOLERANCE),
        "--budget-seconds",
        "30",
        *COEXISTING,
    )
    assert line.startswith("converged: 2 steady states: A (3 of 5 starts) "), line
    a, b = line.split("; B (2 of 5 starts) ")
    b = b.split("; settings ")[0]
    dt = float(line.split("solver.time_step=")[1].split(";")[0])
    scene = {
        "mesh.element": 1,
        "mesh.nx": 4,
        "mesh.ny": 2,
        "base.amplitude": 0.002,
        "base.frequency": 68.0,
        "damping.stiffness_proportional": 5.9e-5,
        "solver.time_step": dt / 4,
    }
    for part, start in ((a, "abrupt"), (b, "ramp")):
        got = values_of(part, QUANTITIES)
        [made] = converge_runs.starts([start], scene, 0.5)
        reference = reference_values(fmu_path, scene, 1e-4, made)
        for q in QUANTITIES:
            value, bound = got[q]
            assert abs(value - reference[q]) <= TOLERANCE * abs(reference[q]), (q, part)
            assert abs(value - reference[q]) <= 1.25 * bound * abs(value), (q, part, reference)
    assert values_of(a, ["mean_energy"])["mean_energy"][0] > 15
    assert values_of(b, ["mean_energy"])["mean_energy"][0] < 6
    runs_csv = runs(tmp_path / "runs.csv")
    assert {r["start"] for r in runs_csv} == set(converge_runs.START_NAMES)
    report = (tmp_path / "report.md").read_text()
    assert "| A | 3 of 5: abrupt, sweep-up, kick |" in report, report
    assert "| B | 2 of 5: ramp, sweep-down |" in report, report


def test_the_damped_preset_from_a_coarse_step_is_not_accepted_on_its_plateau(fmu_path, tmp_path):
    """From Δt = 1e-3 s on the paper's mesh the preset's mean energy reads 9.26, 9.22 J (a pair
    within 1 %, which one passing pair used to accept) and then falls towards 8.61 J; the rule
    waits for three settings whose changes shrink. The result agrees within the tolerance with a
    run at Δt = 7.8e-6 s. One start keeps it cheap: the plateau is the ladder's, not a state's."""
    line = study(
        fmu_path,
        tmp_path,
        "--quantity",
        "mean_energy",
        "--tolerance",
        str(TOLERANCE),
        "--budget-seconds",
        "30",
        "--starts",
        "abrupt",
        "--dt",
        "1e-3",
        "--scene",
        str(ROOT / "scenes" / "forced-35hz-damped.json"),
    )
    assert line.startswith("converged: mean_energy = "), line
    value = values_of(line, ["mean_energy"])["mean_energy"][0]
    dt = float(line.split("solver.time_step=")[1].split(";")[0])
    assert dt < 1.25e-4, line
    scene = dict(scene_values.scene("forced-35hz-damped")[0], **{"solver.time_step": 7.8125e-6})
    reference = reference_values(fmu_path, scene, 1e-3, converge_runs.Start("abrupt"))
    assert abs(value - reference["mean_energy"]) <= TOLERANCE * reference["mean_energy"]
    assert value < 0.97 * 9.22


@pytest.mark.slow  # over 30 s on the loaded 2-core machine
def test_a_mass_damped_scene_from_a_coarse_step_is_not_converged(fmu_path, tmp_path):
    """α only (ζ₁ = 1 %): the stiff modes the scheme does not resolve keep their energy and the
    mean energy grows as Δt shrinks (9.5, 9.8, 9.7, 12.3, 12.9, 22.7 … J from Δt = 1e-3 s); one
    passing pair used to accept 9.73 J at 2.5e-4 s. With 5 CPU s it must end not converged, the
    FMU's warning as its advice."""
    line = study(
        fmu_path,
        tmp_path,
        "--quantity",
        "mean_energy",
        "--tolerance",
        str(TOLERANCE),
        "--budget-seconds",
        "5",
        "--starts",
        "abrupt",
        "--dt",
        "1e-3",
        "base.amplitude=0.009",
        "base.frequency=35",
        "damping.mass_proportional=6.76",
    )
    assert line.startswith("not converged: "), line
    assert "advice: the FMU warns at " in line, line


def fake_study(values, impacts, starts=("abrupt", "ramp")):
    """A Study of two starts whose Δt ladder 1e-4/2^k holds, per start, the mean energies
    `values[k][start]` (two equal windows: no spread) and impact rates `impacts[k][start]`."""
    study = converge.Study(
        "no.fmu",
        {},
        ["mean_energy"],
        TOLERANCE,
        1.0,
        transient=0.0,
        window=1e-4,
        windows=2,
        dt0=1e-4,
        mesh=False,
        start_names=starts,
        progress=False,
    )
    ladder = [(2, 1, 1e-4 / 2**k) for k in range(len(values))]
    for setting, energies, rates in zip(ladder, values, impacts):
        for k, (energy, rate) in enumerate(zip(energies, rates)):
            study.results[setting + (k,)] = {
                "windows": {q: [1.0, 1.0] for q in windows.QUANTITIES}
                | {"mean_energy": [energy] * 2, "impact_rate": [rate] * 2},
                "warning": None,
                "cpu": 0.0,
            }
    return study, ladder


def test_each_state_is_judged_on_its_own_ladder():
    """Two starts on two states at every setting, each converging: both states pass, and the
    verdict names both with their shares. When the quiet state's start impacts at the coarsest
    setting (a branch switch along the ladder), that state fails, whatever its values."""
    values = [[16.0, 5.55], [16.05, 5.57], [16.06, 5.575]]
    study, ladder = fake_study(values, [[136.0, 0.0]] * 3)
    states, verdicts = study.judge(ladder)
    assert [(s.name, s.starts) for s in states] == [("A", [0]), ("B", [1])]
    assert all(verdicts[s.name]["mean_energy"].accepted for s in states), verdicts
    study.recommended = ladder[-1]
    study.ladders.append(("dt-1", ladder))
    study.passes("dt-1", ladder)
    line = study.converged_line(ladder[-1])
    assert line.startswith(
        "converged: 2 steady states: A (1 of 2 starts) mean_energy = 16.06 J ± "
    ), line
    assert "; B (1 of 2 starts) mean_energy = 5.575 J ± " in line, line
    study, ladder = fake_study(values, [[136.0, 136.0], [136.0, 0.0], [136.0, 0.0]])
    states, verdicts = study.judge(ladder)
    assert verdicts["A"]["mean_energy"].accepted
    assert verdicts["B"]["mean_energy"].why == "its starts impact at one setting, not another"


def test_the_estimate_follows_the_backend(fmu_path):
    """From a run on Argyris 14 × 8 (modal), the estimate of 20 × 10 (1951 free dofs, modal) is
    the modal model's ratio, that of 21 × 10 (2048, just above the limit) the sparse model's over
    the modal one's: over 4 times what the modal model above the limit (src/modes/large.rs, the
    regime "modal-large") says. With a modal damping ratio 21 × 10 stays modal and its estimate
    follows that model. Halving Δt on one mesh less than doubles it (set-up and communication
    steps stay). The windows of the documented
    example: 1 s of transient and 8 of 0.2857 s, read every 1e-4 s. The sizes and backends are
    the FMU's (tests/fmu/test_calculated.py checks them)."""
    study = converge.Study(
        fmu_path,
        {},
        ["mean_energy"],
        TOLERANCE,
        120.0,
        transient=1.0,
        window=0.2857,
        windows=8,
        dt0=1e-4,
        mesh=True,
        progress=False,
    )
    for k in range(len(study.starts)):
        study.results[(14, 8, 1e-4, k)] = {"windows": {}, "warning": None, "cpu": 2.0}
    known = (14, 8, 1e-4)
    sim, h = study.simulated, study.h
    assert study.size((20, 10, 1e-4)) == (1951, "modal")
    assert study.size((21, 10, 1e-4)) == (2048, "sparse")

    def modal(nx, ny, dt):  # the modal backend's model whatever the size
        return cost.run_cost((study.size((nx, ny, dt))[0], "modal"), 1, dt, sim, h)

    assert study.estimate(known, (20, 10, 1e-4)) == pytest.approx(
        2.0 * modal(20, 10, 1e-4) / modal(14, 8, 1e-4)
    )
    above = study.estimate(known, (21, 10, 1e-4))
    _, (step, p), (reads, q) = cost.RUN_COST[(1, "sparse")]
    communication = cost.COMMUNICATION_STEP_US + reads * 2.048**q
    sparse = 1e-6 * step * 2.048**p * sim / 1e-4 + 1e-6 * communication * sim / h
    assert above == pytest.approx(2.0 * sparse / modal(14, 8, 1e-4))
    assert above > 4 * 2.0 * modal(21, 10, 1e-4) / modal(14, 8, 1e-4)
    assert above > 3 * study.estimate(known, (20, 10, 1e-4))
    study.scene["damping.modal_ratio"] = 0.01
    assert study.size((21, 10, 1e-4)) == (2048, "modal")
    assert study.estimate(known, (21, 10, 1e-4)) == pytest.approx(
        2.0 * modal(21, 10, 1e-4) / modal(14, 8, 1e-4)
    )
    assert 1.0 < study.estimate(known, (14, 8, 5e-5)) / 2.0 < 2.0
