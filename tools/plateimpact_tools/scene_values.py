"""FMU start values from the scene files (scenes/*.json) or a user's file of them, and from
`name=value` text. One reader for the tests, the examples, the studies and scripts/converge.

A file holds start values by the variable names of modelDescription.xml, flat
({"solver.time_step": 1e-4}) or grouped as scenes/*.json are ({"solver": {"time_step": 1e-4}}),
in JSON or (by its `.toml` suffix) TOML. The scene files also hold the experiment's stop time and
settings of the library that the FMU has no variable for (LIBRARY_ONLY): those are no start
values. The element family is given by name in the scene files, by its code to the FMU.
"""

import json
import pathlib
from collections.abc import Iterator
from typing import Any

from plateimpact_tools import SCENES

# mesh.element: the FMU's Integer codes of the element families the scene files name.
ELEMENT = {"argyris": 1, "fvs": 2}
# Keys of the scene files that are no FMU variables: the experiment's stop time and the library's
# own choices (contact solver, linear backend, impact law), which the FMU makes by itself.
LIBRARY_ONLY = ("stop_time", "solver.qp", "solver.linear", "solver.impact_law")


def flatten(tree: dict[str, Any], prefix: str = "") -> Iterator[tuple[str, Any]]:
    """(dotted name, value) for every leaf of a grouped tree of values."""
    for key, value in tree.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict):
            yield from flatten(value, name + ".")
        else:
            yield name, value


def read(path: str | pathlib.Path) -> tuple[dict[str, Any], float | None]:
    """(start values, stop time or None) of a JSON or TOML file of start values (module docs);
    `mesh.element` by its code."""
    path = pathlib.Path(path)
    text = path.read_text()
    if path.suffix == ".toml":
        import tomllib

        data = tomllib.loads(text)
    else:
        data = json.loads(text)
    flat = dict(flatten(data))
    stop = flat.get("stop_time")
    values = {name: value for name, value in flat.items() if name not in LIBRARY_ONLY}
    if "mesh.element" in values:
        values["mesh.element"] = ELEMENT.get(values["mesh.element"], values["mesh.element"])
    return values, stop


def scene(name: str) -> tuple[dict[str, Any], float | None]:
    """(start values, stop time) of the shipped scene `name` (scenes/NAME.json)."""
    return read(SCENES / f"{name}.json")


def parse_value(name: str, text: str, variables: dict[str, Any]) -> Any:
    """The start value `text` of the FMU variable `name` as its type wants it (`variables`: name
    -> fmpy ScalarVariable); `mesh.element` also takes the element's name."""
    kind = variables[name].type if name in variables else None
    if kind is None:
        raise SystemExit(f"{name} is not a variable of the FMU")
    if kind == "Boolean":
        if str(text).lower() not in ("true", "false", "1", "0"):
            raise SystemExit(f"{name} is Boolean: true or false, not {text}")
        return str(text).lower() in ("true", "1")
    if kind == "Enumeration" or name == "mesh.element":
        return ELEMENT[text] if text in ELEMENT else int(text)
    if kind == "Integer":
        return int(text)
    if kind == "String":
        return str(text)
    return float(text)
