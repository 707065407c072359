"""The parameter sets and experiments a packaged FMU carries, for fmpy (docs/fmu.md, "What the FMU
carries"): every shipped scene as an SSP parameter set (`<scene>.ssv`), its reference result
(`<scene>.csv`) and `experiments.exp` pairing them, under `extra/org.fmi-standard.fmi-ls-ref/`,
found through the FMI-LS-REF manifest as an importer finds them.

    from fmpy import simulate_fmu
    from plateimpact_tools.references import experiment, reference
    fmu = "target/fmu/PlateImpact.fmu"
    result = simulate_fmu(fmu, **experiment(fmu, "forced-35hz-damped"))
    expected = reference(fmu, "forced-35hz-damped")   # the same rows, every output

`parameter_set` gives a set's start values alone (Real as float, Integer as int, Boolean as bool,
String as str), `read_ssv` those of any SSV file. Either FMU (FMI 2.0 or 3.0) works: they carry
the same files.
"""

import io
import os
import pathlib
import xml.etree.ElementTree as ET
import zipfile
from collections.abc import Callable
from typing import Any

LS_REF = "extra/org.fmi-standard.fmi-ls-ref"
SSV = "{http://ssp-standard.org/SSP1/SystemStructureParameterValues}"
EXPERIMENTS_TYPE = "application/x-ma-hs-experiments"
# SSP 1.0's value elements, as Python values.
TYPES: dict[str, Callable[[str], Any]] = {
    "Real": float,
    "Integer": int,
    "Boolean": lambda text: {"true": True, "false": False}[text],
    "String": str,
}

Fmu = str | os.PathLike[str]


def _attribute(element: ET.Element, name: str) -> str:
    """The attribute `name` of `element`, which the file must give."""
    value = element.get(name)
    if value is None:
        raise ValueError(f"<{element.tag}> has no attribute {name}")
    return value


def _child(element: ET.Element, tag: str) -> ET.Element:
    """The child `tag` of `element`, which the file must have."""
    child = element.find(tag)
    if child is None:
        raise ValueError(f"<{element.tag} name={element.get('name')!r}> has no <{tag}>")
    return child


def read_ssv(source: bytes | Fmu) -> dict[str, Any]:
    """{name: value} of an SSP parameter set (`source`: its bytes, or the path of the file). A
    value element of another type, or a parameter named twice, is refused by name."""
    data = source if isinstance(source, bytes) else pathlib.Path(source).read_bytes()
    values: dict[str, Any] = {}
    for parameter in ET.fromstring(data).iter(f"{SSV}Parameter"):
        name = _attribute(parameter, "name")
        (typed,) = list(parameter)
        kind = typed.tag.removeprefix(SSV)
        if kind not in TYPES:
            raise ValueError(
                f"parameter {name}: the value type {kind} is none of {', '.join(TYPES)}"
            )
        if name in values:
            raise ValueError(f"parameter {name} is set twice")
        text = _attribute(typed, "value")
        try:
            values[name] = TYPES[kind](text)
        except (KeyError, ValueError) as e:
            raise ValueError(f"parameter {name}: {text!r} is no {kind}") from e
    return values


def _read(fmu: Fmu, name: str) -> bytes:
    with zipfile.ZipFile(fmu) as archive:
        return archive.read(name)


def _experiments(fmu: Fmu) -> dict[str, ET.Element]:
    """{scene: <Experiment> element} of the experiments file the FMU's manifest names."""
    manifest = ET.fromstring(_read(fmu, f"{LS_REF}/fmi-ls-manifest.xml"))
    (source,) = [
        _attribute(r, "source")
        for r in manifest.iter("Related")
        if r.get("type") == EXPERIMENTS_TYPE
    ]
    root = ET.fromstring(_read(fmu, f"{LS_REF}/{source}"))
    return {_attribute(e, "name"): e for e in root.iter("Experiment")}


def _experiment(fmu: Fmu, scene: str) -> ET.Element:
    experiments = _experiments(fmu)
    if scene not in experiments:
        raise KeyError(
            f"{fmu} carries no experiment {scene!r}; it carries {', '.join(sorted(experiments))}"
        )
    return experiments[scene]


def scenes(fmu: Fmu) -> list[str]:
    """The names of the experiments (one per shipped scene) the FMU carries, sorted."""
    return sorted(_experiments(fmu))


def parameter_set(fmu: Fmu, scene: str) -> dict[str, Any]:
    """The start values of the scene's parameter set in the FMU: every parameter, by name."""
    source = _attribute(_child(_experiment(fmu, scene), "Parameters"), "source")
    return read_ssv(_read(fmu, f"{LS_REF}/{source}"))


def experiment(fmu: Fmu, scene: str) -> dict[str, Any]:
    """The scene's experiment as keyword arguments of fmpy's simulate_fmu: its start values and
    its horizon and communication step (those of the reference result)."""
    simulation = _child(_experiment(fmu, scene), "TransientSimulation")
    start, stop, step = (
        float(_attribute(simulation, a)) for a in ("startTime", "stopTime", "stepSize")
    )
    return {
        "start_values": parameter_set(fmu, scene),
        "start_time": start,
        "stop_time": stop,
        "output_interval": step,
    }


def reference(fmu: Fmu, scene: str) -> Any:
    """The scene's reference result: a numpy structured array with `time` and every output."""
    import numpy as np

    source = _attribute(_child(_experiment(fmu, scene), "References"), "source")
    return np.genfromtxt(
        io.BytesIO(_read(fmu, f"{LS_REF}/{source}")), delimiter=",", names=True, deletechars=""
    )
