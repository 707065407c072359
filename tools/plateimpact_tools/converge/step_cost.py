"""The cost model behind scripts/converge's run-cost estimate (RUN_COST of
`plateimpact_tools.converge.cost`): the packaged FMU's CPU time of its set-up, of an internal step
and of a communication step with the study's reads, per element and regime (the modal backend up
to 2000 free dofs, the modal backend above them, the sparse backend), and the power laws
c·(n/1000)^p fitted to them in the free dofs n.

    .venv/bin/python -m plateimpact_tools.converge.step_cost [--fmu target/fmu/PlateImpact.fmu]
    .venv/bin/python -m plateimpact_tools.converge.step_cost --check

Each mesh runs the preset forced-35hz-damped at Δt = 1e-4 s from the abrupt start once, in this
process's thread, reading the study's outputs after every communication step as its runs do
(`runs.run_setting`). Its CPU time: the set-up (instantiation, start values and
ExitInitializationMode, where the FMU assembles the plate and builds its backend); then, after
2000 steps left out (the first, with fewer contacts, are cheaper), blocks of 500 internal steps in
turn communicating at every step (h = Δt) and every 10 steps (h = 10Δt), 20 000 internal steps in
all on the modal backend up to 2000 free dofs, 10 000 above, 4000 on the sparse backend. The two
kinds of block give the internal step and the communication step apart (`measure`); alternating
them lets both see the same stretch of the motion. The communication step's part that does not
grow with the plate, doStep and the reads through fmpy, is that of Argyris 2 × 1
(COMMUNICATION_STEP_US); RUN_COST fits the rest. The sparse set-up is printed but the model leaves
it out (small against its steps). Above 2000 free dofs the FMU keeps the modal backend only with a
modal damping ratio: those meshes run with damping.modal_ratio = 0.01 (ζ = 1 %, the modal-damping
study's) on top of the preset's Rayleigh damping.

Without --check it measures MESHES, prints a CSV row per mesh, then RUN_COST to stderr: about
2.5 CPU minutes on a 2-core development machine. With --check it measures CHECK, meshes the fit
did not use (and Argyris 28 × 20 again, in this separate run), and prints the model's figures
beside the measured ones as a Markdown table (docs/converge/README.md): about 1.5 CPU minutes.
"""

import argparse
import hashlib
import math
import sys
import time
import uuid

from plateimpact_tools import DEFAULT_FMU, SCENES, scene_values
from plateimpact_tools.converge import runs
from plateimpact_tools.converge.cost import (
    communication_us,
    plate_size,
    regime,
    run_cost,
    setup_seconds,
    step_us,
)
from plateimpact_tools.fmu_dask import fmu_dir
from plateimpact_tools.windows import REALS

MODAL_RATIO = 0.01  # damping.modal_ratio on the meshes above 2000 free dofs
# (element, nx, ny), Argyris (1) and FVS (2): the fit's meshes, modal up to 2000 free dofs, sparse
# above, and modal above with the modal ratio (the last three of each element).
MESHES = [
    (1, 10, 7, False),
    (1, 14, 8, False),
    (1, 20, 10, False),
    (1, 21, 12, False),
    (1, 30, 15, False),
    (1, 40, 20, False),
    (1, 20, 14, True),
    (1, 24, 17, True),
    (1, 28, 20, True),
    (2, 14, 10, False),
    (2, 20, 10, False),
    (2, 30, 15, False),
    (2, 40, 20, False),
    (2, 60, 30, False),
    (2, 40, 25, True),
    (2, 44, 30, True),
    (2, 50, 34, True),
]
# The check's meshes: one per regime of Argyris not in MESHES, two more on the modal backend above
# 2000 free dofs (Argyris and FVS), and Argyris 28 × 20 (5 257 free dofs) measured again.
CHECK = [
    (1, 16, 9, False),
    (1, 24, 12, False),
    (1, 22, 15, True),
    (1, 26, 18, True),
    (1, 28, 20, True),
    (2, 48, 30, True),
]
# Whole runs for the check, as the study runs them (`runs.run_setting`, h = 1e-4 s): (element, nx,
# ny, modal ratio, Δt, simulated s), Δt below h, where the internal and communication steps count
# apart.
RUNS = [
    (1, 10, 7, False, 2.5e-5, 1.0),
    (1, 24, 12, False, 5e-5, 0.4),
    (1, 28, 20, True, 5e-5, 0.5),
]
TINY = (1, 2, 1, False)  # its communication step is the fixed part: doStep and the reads via fmpy
DT = 1e-4
SHORT = 2000  # steps left out
STEPS = {"modal": 20000, "modal-large": 10000, "sparse": 4000}  # internal steps timed
K = 10  # internal steps per communication step in every other block
BLOCK = 500  # internal steps per block


def fit(points):
    """Least-squares c, p of log u = log c + p log(n/1000) over (n, u) points."""
    x = [math.log(n / 1000) for n, _ in points]
    y = [math.log(u) for _, u in points]
    mx, my = sum(x) / len(x), sum(y) / len(y)
    p = sum((a - mx) * (b - my) for a, b in zip(x, y)) / sum((a - mx) ** 2 for a in x)
    return math.exp(my - p * mx), p


def timed_run(directory, values, steps):
    """One abrupt-start run of `values` that reads the study's outputs after every communication
    step (as `runs.run_setting`): SHORT internal steps communicating at each, then blocks of BLOCK
    internal steps, communicating at each internal step and every K in turn, `steps` in all.
    Returns this thread's CPU: seconds of the set-up (instantiation to ExitInitializationMode), and
    µs per internal step in the blocks of each kind (every step, every K)."""
    from fmpy import read_model_description
    from fmpy.fmi2 import FMU2Slave
    from fmpy.simulation import apply_start_values

    md = read_model_description(directory)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    real_vrs = [vr[name] for name in REALS]
    impacts_vr = [vr["contact.impacts"]]
    start = time.thread_time()
    fmu = FMU2Slave(
        guid=md.guid,
        unzipDirectory=directory,
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName=f"step-cost-{uuid.uuid4().hex}",
    )
    done = 0  # internal steps

    def advance(internal, every):
        nonlocal done
        for _ in range(internal // every):
            fmu.doStep(currentCommunicationPoint=done * DT, communicationStepSize=every * DT)
            fmu.getReal(real_vrs)
            fmu.getInteger(impacts_vr)
            done += every

    try:
        fmu.instantiate(callbacks=runs.stderr_callbacks())
        fmu.setupExperiment(startTime=0.0)
        unknown = apply_start_values(fmu, md, values)
        if unknown:
            raise ValueError(f"not variables of the FMU: {sorted(unknown)}")
        fmu.enterInitializationMode()
        fmu.exitInitializationMode()
        setup = time.thread_time() - start
        advance(SHORT, 1)
        cpu = [0.0, 0.0]
        blocks = steps // (2 * BLOCK)
        for _ in range(blocks):
            for kind, every in enumerate((1, K)):
                t = time.thread_time()
                advance(BLOCK, every)
                cpu[kind] += time.thread_time() - t
        fmu.terminate()
    finally:
        fmu.freeInstance()
    return setup, 1e6 * cpu[0] / (blocks * BLOCK), 1e6 * cpu[1] / (blocks * BLOCK)


def measure(fmu, directory, scene, element, nx, ny, modal_ratio):
    """((free dofs, backend) as the FMU reports them, CPU s of the set-up, CPU µs of an internal
    step, CPU µs of a communication step with its reads). From the two kinds of blocks of
    `timed_run`: communicating at every step costs a = s + c per internal step, every K steps
    b = s + c/K, so s = (K·b − a)/(K − 1) and c = K·(a − b)/(K − 1)."""
    values = dict(scene, **{"mesh.element": element, "mesh.nx": nx, "mesh.ny": ny})
    if modal_ratio:
        values["damping.modal_ratio"] = MODAL_RATIO
    size = plate_size(fmu, values)
    setup, a, b = timed_run(directory, values, STEPS[regime(size)])
    return size, setup, (K * b - a) / (K - 1), K * (a - b) / (K - 1)


def name(element, nx, ny):
    return f"{['Argyris', 'FVS'][element - 1]} {nx} × {ny}"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fmu", default=str(DEFAULT_FMU))
    parser.add_argument(
        "--check",
        action="store_true",
        help="measure the meshes of CHECK and print them beside the model's figures",
    )
    args = parser.parse_args()
    blob = open(args.fmu, "rb").read()
    directory = fmu_dir(blob, hashlib.sha256(blob).hexdigest())
    scene = scene_values.read(SCENES / "forced-35hz-damped.json")[0]
    scene["solver.time_step"] = DT
    fixed = measure(args.fmu, directory, scene, *TINY)[3]
    print(f"# a communication step with its reads on Argyris 2 x 1: {fixed:.2f} us")
    if args.check:
        check(args.fmu, directory, scene)
        return
    print("element,nx,ny,free_dofs,regime,setup_s,step_us,communication_us")
    laws = {}
    for element, nx, ny, modal_ratio in MESHES:
        size, setup, step, communication = measure(
            args.fmu, directory, scene, element, nx, ny, modal_ratio
        )
        key, n = (element, regime(size)), size[0]
        for points, value in zip(laws.setdefault(key, ([], [], [])), (setup, step, communication)):
            points.append((n, value))
        print(f"{element},{nx},{ny},{n},{key[1]},{setup:.3f},{step:.2f},{communication:.2f}")
        sys.stdout.flush()
    print(f"COMMUNICATION_STEP_US = {fixed:.3g}", file=sys.stderr)
    print(
        "RUN_COST = {  # (element, regime): ((set-up s, p), (µs per internal step, p), "
        "(µs per communication step beyond COMMUNICATION_STEP_US, p)), c at 1000 free dofs",
        file=sys.stderr,
    )
    for key, (setups, steps, communications) in sorted(laws.items()):
        setup = "(0.0, 0.0)" if key[1] == "sparse" else "({:.3g}, {:.2f})".format(*fit(setups))
        reads = "({:.3g}, {:.2f})".format(*fit([(n, c - fixed) for n, c in communications]))
        step = "({:.3g}, {:.2f})".format(*fit(steps))
        print(
            f"    {key}: ({setup}, {step}, {reads}),  # {steps[0][0]}–{steps[-1][0]} free dofs",
            file=sys.stderr,
        )
    print("}", file=sys.stderr)


def check(fmu, directory, scene):
    """The Markdown table of CHECK: the model's set-up, internal step and communication step
    (RUN_COST) beside the measured ones."""
    print(
        "| mesh | free dofs | regime | set-up s: model | measured | internal step µs: model "
        "| measured | communication step µs: model | measured |"
    )
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for element, nx, ny, modal_ratio in CHECK:
        size, setup, step, communication = measure(
            fmu, directory, scene, element, nx, ny, modal_ratio
        )
        print(
            f"| {name(element, nx, ny)} | {size[0]} | {regime(size)} "
            f"| {setup_seconds(size, element):.3g} | {setup:.3g} "
            f"| {step_us(size, element):.3g} | {step:.3g} "
            f"| {communication_us(size, element):.3g} | {communication:.3g} |"
        )
        sys.stdout.flush()
    print()
    print("| run (h = 1e-4 s) | free dofs | regime | CPU s: model (`run_cost`) | measured |")
    print("| --- | --- | --- | --- | --- |")
    blob = open(fmu, "rb").read()
    digest = hashlib.sha256(blob).hexdigest()
    for element, nx, ny, modal_ratio, dt, simulated in RUNS:
        values = dict(scene, **{"mesh.element": element, "mesh.nx": nx, "mesh.ny": ny})
        values["solver.time_step"] = dt
        if modal_ratio:
            values["damping.modal_ratio"] = MODAL_RATIO
        size = plate_size(fmu, values)
        half = round(simulated / DT / 2)
        cpu = runs.run_setting(blob, digest, values, runs.Start("abrupt"), DT, 0, half, 2)[1]
        print(
            f"| {name(element, nx, ny)}, Δt = {dt:g} s, {simulated:g} s | {size[0]} "
            f"| {regime(size)} | {run_cost(size, element, dt, simulated, DT):.3g} | {cpu:.3g} |"
        )
        sys.stdout.flush()


if __name__ == "__main__":
    main()
