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

# The cost model of a run (`run_cost`), per (mesh.element, backend): its set-up, (s, p), and its
# internal step, (µs, p), each c·(n/1000)^p in the free dofs n; plus a communication step with the
# study's reads. Measured through the FMU on the preset forced-35hz-damped at Δt = h = 1e-4 s
# (`python -m plateimpact_tools.converge.step_cost`; a 2-core development machine, load average
# about 2): per internal step 6.6 → 35 µs from Argyris 10 × 7 to 20 × 10 (708 → 1951 free dofs,
# modal), 1655 µs on 21 × 12 (2428, sparse), 3224 on 30 × 15 and 6002 on 40 × 20; FVS 12 → 70 µs
# from 14 × 10 to 30 × 15 (462 → 1440, modal), 1360 on 40 × 20 (2520, sparse) and 3224 on 60 × 30.
# The modal set-up (the eigen-decomposition) grows like n^2.7 and takes 4.9 s at 1951 free dofs;
# the sparse one is small against its steps and left out. Only ratios of the model enter the
# estimate (`Study.estimate`), so a slower machine scales both sides.
RUN_COST = {
    (1, "modal"): ((0.738, 2.74), (11.6, 1.64)),
    (1, "sparse"): ((0.0, 0.0), (605.0, 1.14)),
    (2, "modal"): ((1.13, 2.22), (37.2, 1.62)),
    (2, "sparse"): ((0.0, 0.0), (499.0, 1.09)),
}
COMMUNICATION_STEP_US = 9.23  # doStep and the reads through fmpy, on Argyris 2 × 1


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


def run_cost(size: tuple[int, str], element: int, dt: float, simulated: float, h: float) -> float:
    """The model's CPU seconds (RUN_COST) of a run of `simulated` seconds at Δt = `dt` of a plate
    of `element` whose `size` is (free dofs, backend) (`plate_size`), outputs read every `h`: the
    set-up, simulated/Δt internal steps and simulated/h communication steps."""
    free, backend = size
    (setup, p_setup), (step, p_step) = RUN_COST[(element, backend)]
    n = free / 1000
    return (
        setup * n**p_setup
        + 1e-6 * step * n**p_step * simulated / dt
        + 1e-6 * COMMUNICATION_STEP_US * simulated / h
    )
