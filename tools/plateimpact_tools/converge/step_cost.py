"""The cost model behind scripts/converge's run-cost estimate (RUN_COST of
`plateimpact_tools.converge.cost`): the packaged FMU's CPU time per internal step and its set-up,
per element and linear backend, for meshes on both sides of the switch at 2000 free dofs, and the
power laws c·(n/1000)^p fitted to them in the free dofs n.

    .venv/bin/python -m plateimpact_tools.converge.step_cost [--fmu target/fmu/PlateImpact.fmu]

Each mesh runs the preset forced-35hz-damped at Δt = h = 1e-4 s through runs.run_setting from the
abrupt start (the study's own runs, reading its outputs at every step) twice, one after the other
in this process: 2000 steps, and 2000 + E steps (E = 20 000 on the modal backend, 4000 on the
sparse one). Per internal step the CPU difference over the E steps; less the cost of one
communication step with its reads, taken as that of the Argyris 2 × 1 mesh, this is the step's own
cost. The set-up is the short run's CPU less its 2000 steps (on the sparse backend it is small
against the steps and the first steps, with fewer contacts, are cheaper: the model leaves it out).
About 3 CPU minutes on a 2-core development machine. Prints a CSV row per mesh, then RUN_COST to
stderr.
"""

import argparse
import hashlib
import math
import sys

from plateimpact_tools import DEFAULT_FMU, SCENES, scene_values
from plateimpact_tools.converge import runs
from plateimpact_tools.converge.cost import plate_size

# (element, nx, ny): Argyris (1) and FVS (2), modal up to 2000 free dofs and sparse above.
MESHES = [
    (1, 10, 7),
    (1, 14, 8),
    (1, 20, 10),
    (1, 21, 12),
    (1, 30, 15),
    (1, 40, 20),
    (2, 14, 10),
    (2, 20, 10),
    (2, 30, 15),
    (2, 40, 20),
    (2, 60, 30),
]
TINY = (1, 2, 1)  # its step is the communication step's cost: doStep and the reads through fmpy
DT = 1e-4
SHORT = 2000  # steps of the short run
EXTRA = {"modal": 20000, "sparse": 4000}  # further steps of the long run


def fit(points):
    """Least-squares c, p of log u = log c + p log(n/1000) over (n, u) points."""
    x = [math.log(n / 1000) for n, _ in points]
    y = [math.log(u) for _, u in points]
    mx, my = sum(x) / len(x), sum(y) / len(y)
    p = sum((a - mx) * (b - my) for a, b in zip(x, y)) / sum((a - mx) ** 2 for a in x)
    return math.exp(my - p * mx), p


def measure(fmu, blob, digest, scene, element, nx, ny):
    """(backend, free dofs (both as the FMU reports them), CPU s of the short run, CPU µs per
    step at h = Δt)."""
    values = dict(scene, **{"mesh.element": element, "mesh.nx": nx, "mesh.ny": ny})
    n, kind = plate_size(fmu, values)
    cpu = [
        runs.run_setting(blob, digest, values, runs.Start("abrupt"), DT, 0, steps // 2, 2)[1]
        for steps in (SHORT, SHORT + EXTRA[kind])
    ]
    return kind, n, cpu[0], 1e6 * (cpu[1] - cpu[0]) / EXTRA[kind]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fmu", default=str(DEFAULT_FMU))
    args = parser.parse_args()
    blob = open(args.fmu, "rb").read()
    digest = hashlib.sha256(blob).hexdigest()
    scene = scene_values.read(SCENES / "forced-35hz-damped.json")[0]
    scene["solver.time_step"] = DT
    overhead = measure(args.fmu, blob, digest, scene, *TINY)[3]
    print(f"# one communication step with its reads (Argyris 2 x 1): {overhead:.2f} us")
    print("element,nx,ny,free_dofs,backend,cpu_short_s,us_per_step_with_reads,us_per_step,setup_s")
    steps, setups = {}, {}
    for element, nx, ny in MESHES:
        kind, n, short, us = measure(args.fmu, blob, digest, scene, element, nx, ny)
        own = us - overhead
        setup = short - 1e-6 * SHORT * us
        steps.setdefault((element, kind), []).append((n, own))
        if kind == "modal":
            setups.setdefault((element, kind), []).append((n, setup))
        print(
            f"{element},{nx},{ny},{n},{kind},{short:.3f},{us:.2f},{own:.2f},{setup:.3f}", flush=True
        )
    print(f"COMMUNICATION_STEP_US = {overhead:.3g}", file=sys.stderr)
    print(
        "RUN_COST = {  # (element, backend): ((set-up s, p), (µs per internal step, p)), "
        "c at 1000 free dofs",
        file=sys.stderr,
    )
    for key, pts in sorted(steps.items()):
        setup = "(0.0, 0.0)"
        if key in setups:
            c, p = fit(setups[key])
            setup = f"({c:.3g}, {p:.2f})"
        c, p = fit(pts)
        print(
            f"    {key}: ({setup}, ({c:.3g}, {p:.2f})),  # {pts[0][0]}–{pts[-1][0]} free dofs",
            file=sys.stderr,
        )
    print("}", file=sys.stderr)


if __name__ == "__main__":
    main()
