"""The cost model behind the study's budget estimates: a run's CPU seconds from the size of its
plate and the linear backend the FMU builds for it, both as the FMU reports them (its calculated
parameters `solver.free_dofs` and `solver.backend`, read in Initialization mode: no set-up)."""

import functools
import hashlib
from pathlib import Path
from typing import Any

from plateimpact_tools.fmu_dask import fmu_dir

# The codes of `solver.backend` (docs/fmu.md).
BACKENDS = {1: "modal", 2: "sparse"}

# Above this many free dofs the modal backend takes other paths (docs/speed.md, "Fine modal
# meshes"): the eigenpairs by src/modes/large.rs instead of the dense eigensolver (DENSE_LIMIT of
# src/modes/mod.rs, = MODAL_AUTO_LIMIT of src/backend_choice.rs), the steps with stand-ins
# (src/scheme/modal/). The FMU reaches them only with a modal damping ratio; the auto choice is
# sparse there.
DENSE_LIMIT = 2000

# The cost model of a run (`run_cost`), per (mesh.element, regime) (`regime`): its set-up (s, p),
# its internal step (µs, p) and the part of its communication step with the study's reads that
# grows with the plate (µs, p), each c·(n/1000)^p in the free dofs n; the rest of a communication
# step is COMMUNICATION_STEP_US, that of Argyris 2 × 1. Measured through the FMU on the preset
# forced-35hz-damped at Δt = 1e-4 s, above 2000 free dofs on the modal backend with
# damping.modal_ratio = 0.01 (`.venv/bin/python -m plateimpact_tools.converge.step_cost`, commit
# 0388242, 7 December 2026, a 2-core development machine at a load average of about 1.5 with
# another job; CPU time): Argyris set-up 0.19 → 3.7 s from 10 × 7 to 20 × 10 (708 → 1951 free
# dofs, dense eigensolver), 2.4 → 15.4 s from 20 × 14 to 28 × 20 (2675 → 5257,
# src/modes/large.rs), internal step 2.0 → 9.1 µs and 13.6 → 40.5 µs, 710 µs on 21 × 12 (2428,
# sparse) and 2815 µs on 40 × 20 (7501); FVS set-up 0.13 → 1.8 s from 14 × 10 to 30 × 15
# (462 → 1440) and 5.7 → 23 s from 40 × 25 to 50 × 34 (3120 → 5250), internal step 2.7 → 20 µs
# and 66 → 185 µs, 607 µs on 40 × 20 (2520, sparse). A communication step costs 5.7 µs on
# Argyris 2 × 1, 14 µs on 10 × 7, 32 µs on 20 × 10, 85 µs on 28 × 20 and 264 µs on 21 × 12
# (sparse); FVS 12 µs on 14 × 10, 158 µs on 50 × 34. The growing law is half of it or more on
# every mesh fitted (51 % on FVS 14 × 10, 60 % on Argyris 10 × 7, 93 % on 28 × 20), so it
# stays. It is doStep's: without reads (blocks alternated with the fit's, once) a communication
# step costs 9 µs on 10 × 7, 65 µs on 28 × 20, 222 µs on 21 × 12 (every doStep forms and checks
# the outputs at its end, `unsound_outputs` in src/fmi/plate/mod.rs), while the reads, served
# from the FMU's cache since cc0e905, cost 4–5 µs through fmpy on every mesh (before it each read
# recomputed the output points' rates: 340 µs per communication step on 28 × 20). The sparse
# set-up is small against its steps and left out. Only ratios of the model enter the estimate
# (`Study.estimate`), so a slower machine scales both sides.
RUN_COST = {
    (1, "modal"): ((0.522, 2.92), (3.24, 1.49), (12.3, 1.09)),  # 708–1951 free dofs
    (1, "modal-large"): ((0.166, 2.73), (2.81, 1.62), (11.2, 1.17)),  # 2675–5257
    (1, "sparse"): ((0.0, 0.0), (242.0, 1.22), (98.9, 1.08)),  # 2428–7501
    (2, "modal"): ((0.727, 2.34), (10.1, 1.78), (16.2, 1.32)),  # 462–1440
    (2, "modal-large"): ((0.264, 2.69), (7.01, 1.97), (10.1, 1.62)),  # 3120–5250
    (2, "sparse"): ((0.0, 0.0), (195.0, 1.23), (64.5, 1.21)),  # 2520–5580
}
COMMUNICATION_STEP_US = 5.69  # doStep and the reads through fmpy, on Argyris 2 × 1


@functools.cache
def _plate_size(fmu_path: str, start_values: tuple[tuple[str, Any], ...]) -> tuple[int, str]:
    from fmpy import read_model_description
    from fmpy.fmi2 import FMU2Slave
    from fmpy.simulation import apply_start_values

    blob = open(fmu_path, "rb").read()
    directory = fmu_dir(blob, hashlib.sha256(blob).hexdigest())
    md = read_model_description(directory)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    fmu = FMU2Slave(
        guid=md.guid,
        unzipDirectory=directory,
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="plate-size",
    )
    try:
        fmu.instantiate()
        fmu.setupExperiment(startTime=0.0)
        unknown = apply_start_values(fmu, md, dict(start_values))
        if unknown:
            raise ValueError(f"not variables of the FMU: {sorted(unknown)}")
        fmu.enterInitializationMode()
        n, code = fmu.getInteger([vr["solver.free_dofs"], vr["solver.backend"]])
    finally:
        fmu.freeInstance()
    return n, BACKENDS[code]


def plate_size(fmu_path: str | Path, start_values: dict[str, Any]) -> tuple[int, str]:
    """(free dofs, "modal" or "sparse") of the plate the start values describe, as the FMU at
    `fmu_path` reports them; asked once per distinct set of start values."""
    return _plate_size(str(fmu_path), tuple(sorted(start_values.items())))


def regime(size: tuple[int, str]) -> str:
    """The regime of RUN_COST a plate of `size` (free dofs, backend) runs in: the backend, and on
    the modal one "modal-large" above DENSE_LIMIT free dofs."""
    free, backend = size
    return "modal-large" if backend == "modal" and free > DENSE_LIMIT else backend


def setup_seconds(size: tuple[int, str], element: int) -> float:
    """The model's CPU seconds of the set-up of a plate of `element` and `size` (RUN_COST)."""
    (c, p), _, _ = RUN_COST[(element, regime(size))]
    return c * (size[0] / 1000) ** p


def step_us(size: tuple[int, str], element: int) -> float:
    """The model's CPU µs of an internal step of a plate of `element` and `size` (RUN_COST)."""
    _, (c, p), _ = RUN_COST[(element, regime(size))]
    return c * (size[0] / 1000) ** p


def communication_us(size: tuple[int, str], element: int) -> float:
    """The model's CPU µs of a communication step with the study's reads of a plate of `element`
    and `size`: COMMUNICATION_STEP_US and the part that grows with the plate (RUN_COST)."""
    _, _, (c, p) = RUN_COST[(element, regime(size))]
    return COMMUNICATION_STEP_US + c * (size[0] / 1000) ** p


def run_cost(size: tuple[int, str], element: int, dt: float, simulated: float, h: float) -> float:
    """The model's CPU seconds (RUN_COST) of a run of `simulated` seconds at Δt = `dt` of a plate
    of `element` whose `size` is (free dofs, backend) (`plate_size`), outputs read every `h`: the
    set-up, simulated/Δt internal steps and simulated/h communication steps."""
    return (
        setup_seconds(size, element)
        + 1e-6 * step_us(size, element) * simulated / dt
        + 1e-6 * communication_us(size, element) * simulated / h
    )
