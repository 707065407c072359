"""The FMI 3.0 FMU's deflection field `plate.displacement` on any mesh, through fmpy.

The field's shape is fixed by the structural parameters `mesh.vertex_rows` and
`mesh.vertex_columns` (start 8 and 11, the default 10 × 7 mesh), which FMI 3.0 lets a host change
only in Configuration Mode, while the mesh is set by the ordinary parameters `mesh.nx`, `mesh.ny`.
fmpy's `simulate_fmu` sets every start value after instantiation, where the FMU refuses a
structural parameter, and it sizes the arrays it records by their start values, so on another
mesh the field cannot be read that way. `simulate` does what a host must (docs/fmu.md, "FMI
3.0"): it instantiates the FMU, sets the sizes to mesh.ny + 1 rows and mesh.nx + 1 columns in
Configuration Mode, and hands the instance to `simulate_fmu` with a model description whose field
has those sizes:

    from plateimpact_tools.field import simulate
    r = simulate("target/fmu/PlateImpact-fmi3.fmu",
                 {"mesh.element": 2, "mesh.nx": 14, "mesh.ny": 10}, stop_time=0.1,
                 output=["plate.displacement"])
    r["plate.displacement"].shape   # (101, 11, 15): rows y_j, columns x_i

With the default mesh, or the FMI 2.0 FMU (which has no field), it is `simulate_fmu` itself.
"""

import os
import shutil
from collections.abc import Mapping
from typing import Any

from fmpy import extract, instantiate_fmu, read_model_description, simulate_fmu

ROWS, COLUMNS = "mesh.vertex_rows", "mesh.vertex_columns"
# What instantiate_fmu takes of simulate_fmu's keyword arguments.
INSTANCE_OPTIONS = ("visible", "debug_logging", "logger", "fmi_call_logger", "early_return_allowed")


def field_sizes(model_description: Any, start_values: Mapping[str, Any]) -> tuple[int, int]:
    """(rows, columns) of the field for the mesh `start_values` set (their start values where
    they set none): mesh.ny + 1 and mesh.nx + 1. Sizes given among the start values must agree."""
    variables = {v.name: v for v in model_description.modelVariables}

    def value(name: str) -> int:
        return int(start_values.get(name, variables[name].start))

    sizes = value("mesh.ny") + 1, value("mesh.nx") + 1
    for name, size in zip((ROWS, COLUMNS), sizes):
        if name in start_values and int(start_values[name]) != size:
            raise ValueError(
                f"{name} = {start_values[name]}, but the mesh (mesh.nx, mesh.ny) "
                f"has {size}: leave it out, it follows the mesh"
            )
    return sizes


def simulate(
    fmu: str | os.PathLike[str], start_values: Mapping[str, Any] | None = None, **kwargs: Any
) -> Any:
    """fmpy's simulate_fmu(fmu, start_values=…, **kwargs), with the FMI 3.0 field sized to the
    mesh in Configuration Mode when it is not the default one (module docs)."""
    md = read_model_description(fmu)
    values = dict(start_values or {})
    if not md.fmiVersion.startswith("3"):
        return simulate_fmu(fmu, start_values=values, **kwargs)
    variables = {v.name: v for v in md.modelVariables}
    sizes = field_sizes(md, values)
    values.pop(ROWS, None)
    values.pop(COLUMNS, None)
    if sizes == (int(variables[ROWS].start), int(variables[COLUMNS].start)):
        return simulate_fmu(fmu, start_values=values, **kwargs)
    # fmpy's recorder reads each array's shape from the description, as of the start values.
    configured = dict(zip((ROWS, COLUMNS), sizes))
    for v in md.modelVariables:
        if v.dimensions:
            v.shape = tuple(
                int(d.start) if d.start is not None else configured[d.variable.name]
                for d in v.dimensions
            )
    unzipdir = extract(fmu)
    try:
        options = {k: kwargs[k] for k in INSTANCE_OPTIONS if k in kwargs}
        instance = instantiate_fmu(unzipdir, md, fmi_type="CoSimulation", **options)
        try:
            instance.enterConfigurationMode()
            instance.setUInt64(
                [variables[ROWS].valueReference, variables[COLUMNS].valueReference], list(sizes)
            )
            instance.exitConfigurationMode()
            return simulate_fmu(
                unzipdir, model_description=md, fmu_instance=instance, start_values=values, **kwargs
            )
        finally:
            instance.freeInstance()
    finally:
        shutil.rmtree(unzipdir, ignore_errors=True)
