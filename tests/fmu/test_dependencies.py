"""The dependencies that `<ModelStructure>` declares are the ones measured on the packaged FMUs
(docs/fmu.md, "Dependencies").

Every output and every initial unknown of both descriptions declares `dependencies` (an absent
attribute would mean "depends on every known", which FMI importers such as OMSimulator read as
direct feedthrough and report as an algebraic loop in any feedback coupling). The test measures
them, for every variable the descriptions list, so that a new variable is covered without a change
here:

* **Outputs, at communication points.** After a few steps, each known a host may set between steps
  (every input and tunable parameter) is perturbed, and every output is read again before the next
  step: an output depends on the known when any bit of it changed. The FMU's outputs describe the
  last step, so none does; the next step then does change them (checked, so that the perturbation
  is no empty one).
* **Initial unknowns, in Initialization Mode.** Each known of initialization (every parameter and
  input; in FMI 3.0 also the structural parameters and the start time, the independent variable)
  is perturbed after a first read of every initial unknown, and they are read again. A parameter
  is set and read in the same Initialization Mode, as an importer that iterates an initialization
  loop does; structural parameters (set only in Configuration Mode) and the start time (fixed by
  fmi3EnterInitializationMode) are compared between two instances.

A dependency may show only at some parameter values (the backend choice at the size where it
switches, contact only once the preload reaches an obstacle, the damping frequencies only with a
damping ratio), so the measurement runs at several operating points, and the declared list of each
unknown must equal the union of what they measured: nothing missing (which would hide a real
feedthrough), nothing extra (which would invent one).

A Real moves by 1 % up and down (by 1e-3 from 0), an Integer to both neighbours within its range,
a Boolean to its other value, a String to the value STRING_VALUES gives; at initialization every one of these is measured (a threshold may
lie on either side), between steps the first the FMU accepts. A perturbation the FMU refuses (a
value outside the limits that tie parameters together) measures nothing. An array may become
unreadable when a known changes its size (the FMI 3.0 field when the structural sizes no longer
fit the mesh): that is a change.

`python tests/fmu/test_dependencies.py FMU` prints the measured dependencies of an FMU in the form
of the description's `<ModelStructure>`, to copy from when a variable is added."""

import math
import sys

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException

from conftest import Plate, Plate3

# Small meshes keep a set-up in milliseconds; the last point sits at the size where the backend
# switches from modal (up to 2000 free dofs: 28 x 7 Argyris cells, 1968) to sparse (29 x 7, 2038),
# so that the size and the modal ratio show their hold on `solver.backend`.
# (The FMI 3.0 field's structural sizes follow the mesh; FMI 2.0 has no such parameters.)
# The probes sit on the plate off the clamp, so that they show what the plate's deflection depends
# on.
PROBES = {
    "probe1.x": 0.3,
    "probe1.y": 0.15,
    "probe2.x": 0.2,
    "probe2.y": 0.05,
    "probe3.x": 0.35,
    "probe3.y": 0.1,
    "probe4.x": 0.4,
    "probe4.y": 0.2,
}
SMALL = {"mesh.nx": 4, "mesh.ny": 2, "mesh.vertex_rows": 3, "mesh.vertex_columns": 5} | PROBES
PRELOAD, CONTACT = "initial.preload_pressure", "contact.active_nodes"
# Every motion parameter away from its start, the base displaced.
MOVING = {
    "base.displacement": 0.002,
    "base.amplitude": 0.001,
    "base.frequency": 35.0,
    "solver.restitution": 0.5,
    "damping.stiffness_proportional": 5e-5,
    "damping.modal_ratio": 0.01,
}
POINTS = {
    "at rest": SMALL,
    # Preloaded onto an obstacle and held there by the load, so that the obstacle's level acts on
    # every step.
    "pressed onto the upper obstacle": SMALL | MOVING | {PRELOAD: 1e5, "load.pressure": 1e5},
    "pressed onto the lower obstacle": SMALL | MOVING | {PRELOAD: -1e5, "load.pressure": -1e5},
    # Pressed onto eight point stops along the free edge, of the lower obstacle and then of the
    # upper one, each carrying the plate, so that every stop's outputs show what they depend on.
    "pressed onto lower stops": SMALL
    | MOVING
    | {
        PRELOAD: -1e5,
        "load.pressure": -1e5,
        "obstacle.lower_profile": "; ".join(
            f"point(x = 0.4, y = {0.2 * k / 7}, offset = 0.005)" for k in range(8)
        ),
    },
    "pressed onto upper stops": SMALL
    | MOVING
    | {
        PRELOAD: 1e5,
        "load.pressure": 1e5,
        "obstacle.upper_profile": "; ".join(
            f"point(x = 0.4, y = {0.2 * k / 7}, offset = -0.005)" for k in range(8)
        ),
    },
    "damping ratio": SMALL
    | {"damping.ratio": 0.01, "damping.frequency_low": 50.0, "damping.frequency_high": 500.0},
    "backend switch": {
        "mesh.nx": 29,
        "mesh.ny": 7,
        "mesh.vertex_rows": 8,
        "mesh.vertex_columns": 30,
    }
    | PROBES,
}
# Another valid value of each String parameter, to perturb it by (a text has no small change).
# Another valid value of each String parameter: the clamp on a second edge, profiles that tilt the
# obstacles (the points where the preload presses the plate on an obstacle show their hold).
STRING_VALUES = {
    "plate.clamp": "xmin, ymin",
    "obstacle.lower_profile": "plane(slope_x = 0.002)",
    "obstacle.upper_profile": "plane(slope_y = -0.002)",
}
STEP = 1e-3
STEPS = 3
# A relative perturbation large enough to move every result of a set-up by more than round-off.
RELATIVE = 1e-2
ABSOLUTE = 1e-3


def perturbations(variable, value):
    """Candidate perturbed values of `variable` from `value`, in the order tried."""
    kind = variable.type
    if kind == "Boolean":
        return [[not value]]
    low = -math.inf if variable.min is None else float(variable.min)
    high = math.inf if variable.max is None else float(variable.max)
    if kind in ("Integer", "Int32", "UInt64"):
        return [[n] for n in (value + 1, value - 1) if low <= n <= high]
    if kind in ("Real", "Float64"):
        steps = [value * (1 + RELATIVE), value * (1 - RELATIVE)] if value else [ABSOLUTE, -ABSOLUTE]
        return [[x] for x in steps if low <= x <= high]
    if kind == "String":
        if variable.name not in STRING_VALUES:
            raise KeyError(
                f"{variable.name}: give STRING_VALUES another valid value to perturb it by"
            )
        return [[STRING_VALUES[variable.name]]]
    raise TypeError(f"{variable.name}: no perturbation for variables of type {kind}; add one here")


class Instance:
    """One instance of either FMI version, with reads that report a refusal instead of raising."""

    def __init__(self, version, unzipdir, md):
        self.version = version
        self.md = md
        self.plate = (Plate if version == 2 else Plate3)(unzipdir, md)

    def set(self, name, value):
        """Sets `name`; False when the FMU refuses the value."""
        try:
            self.plate.set(name, value)
            return True
        except FMICallException:
            return False

    def read(self, name):
        """The value of `name` as an array, or None when the FMU refuses the read."""
        try:
            return np.atleast_1d(np.asarray(self.plate.get(name), dtype=float))
        except FMICallException:
            return None

    def enter_initialization(self, start_values, start=0.0):
        """Sets the start values (structural parameters in Configuration Mode, those of variables
        the description lacks not at all) and enters Initialization Mode; False when one is
        refused."""
        causality = {v.name: v.causality for v in self.md.modelVariables}
        values = {n: v for n, v in start_values.items() if n in causality}
        structural = {n: v for n, v in values.items() if causality[n] == "structuralParameter"}
        ok = True
        if structural:
            self.plate.fmu.enterConfigurationMode()
            ok = all(self.set(n, v) for n, v in structural.items())
            self.plate.fmu.exitConfigurationMode()
        if self.version == 2:
            self.plate.fmu.setupExperiment(startTime=start, stopTime=1.0)
        ok = ok and all(self.set(n, v) for n, v in values.items() if n not in structural)
        if self.version == 2:
            self.plate.fmu.enterInitializationMode()
        else:
            self.plate.fmu.enterInitializationMode(startTime=start, stopTime=1.0)
        return ok

    def free(self):
        self.plate.free()


def knowns_at_initialization(md):
    """The knowns of Initialization Mode: inputs, variables with initial = exact (parameters and
    structural parameters) and the independent variable."""
    return [
        v
        for v in md.modelVariables
        if v.causality in ("input", "independent")
        or (v.causality in ("parameter", "structuralParameter") and v.variability != "constant")
    ]


def knowns_between_steps(md):
    """What a host may set at a communication point: inputs and tunable parameters."""
    return [
        v
        for v in md.modelVariables
        if v.causality == "input" or (v.causality == "parameter" and v.variability == "tunable")
    ]


def changed(before, after):
    """Whether a read changed: another value, another size, or readable before and refused now."""
    if before is None:
        return False
    return after is None or before.shape != after.shape or not np.array_equal(before, after)


def readable(values, names, md):
    """Whether every scalar among `names` was read: a refused scalar means the perturbation made
    the parameters inconsistent, which measures nothing."""
    shapes = variable_shapes(md)
    return all(values[n] is not None for n in names if not shapes[n])


def variable_shapes(md):
    """{name: the variable's <Dimension> list} (empty for a scalar)."""
    return {v.name: v.dimensions for v in md.modelVariables}


def measure_initial_unknowns(version, unzipdir, md, point):
    """{unknown: set of known names} measured at `point` (a dict of start values)."""
    # Arrays last: a refused read ends an FMI 3.0 instance (Terminated), and only an array's read
    # may be refused when a perturbation is valid.
    unknowns = sorted(
        (u.variable.name for u in md.initialUnknowns),
        key=lambda name: bool(variable_shapes(md)[name]),
    )
    found = {u: set() for u in unknowns}
    reference = None
    for known in knowns_at_initialization(md):
        if known.causality == "independent":
            candidates = [[0.25]]  # the start time, from 0
        else:
            candidates = perturbations(known, point.get(known.name, start_value(known)))
        for (value,) in candidates:
            instance = Instance(version, unzipdir, md)
            if known.causality in ("independent", "structuralParameter"):
                # Fixed before Initialization Mode: compared with an instance without the change.
                if reference is None:
                    first = Instance(version, unzipdir, md)
                    assert first.enter_initialization(point), (version, point)
                    reference = {u: first.read(u) for u in unknowns}
                    first.free()
                before = reference
                if known.causality == "independent":
                    instance.enter_initialization(point, start=value)
                else:
                    instance.enter_initialization(point | {known.name: value})
            else:
                assert instance.enter_initialization(point), (version, point)
                before = {u: instance.read(u) for u in unknowns}
                if not instance.set(known.name, value):
                    instance.free()
                    continue
            after = {u: instance.read(u) for u in unknowns}
            instance.free()
            assert readable(before, unknowns, md), (version, point, before)
            if readable(after, unknowns, md):
                for u in unknowns:
                    if changed(before[u], after[u]):
                        found[u].add(known.name)
    return found


def contact_edge(version, unzipdir, md, point, sign):
    """`point` with the preloads, of sign `sign`, just short of and just past the one that brings
    a first vertex into contact (bisection to 1e-9 of it): there whatever moves the initial
    deflection, however little and either way, changes the contact set, which no small
    perturbation does elsewhere."""

    def touching(preload):
        instance = Instance(version, unzipdir, md)
        assert instance.enter_initialization(point | {PRELOAD: preload}), preload
        (nodes,) = instance.read(CONTACT)
        instance.free()
        return nodes > 0

    low, high = 0.0, sign * 1e5
    assert not touching(low) and touching(high), (version, point)
    while abs(high - low) > 1e-9 * abs(high):
        middle = (low + high) / 2
        low, high = (low, middle) if touching(middle) else (middle, high)
    return point | {PRELOAD: low}, point | {PRELOAD: high}


def initialization_points(version, unzipdir, md):
    """The operating points of the initial unknowns: POINTS and the edges of contact with each
    obstacle from a displaced base."""
    edges = {}
    for sign in (1, -1):
        short, past = contact_edge(
            version, unzipdir, md, SMALL | {"base.displacement": 0.002}, sign
        )
        edges |= {f"short of contact ({sign:+d})": short, f"just in contact ({sign:+d})": past}
    return POINTS | edges


def start_value(variable):
    """The start value of a known, by type (None for the independent variable, which has none)."""
    if variable.start is None:
        return None
    if variable.type == "Boolean":
        return variable.start in (True, "true")
    if variable.type == "String":
        return variable.start
    if variable.type in ("Real", "Float64"):
        return float(variable.start)
    return int(variable.start)


def measure_outputs(version, unzipdir, md, point):
    """({output: set of known names} measured at a communication point of `point`, the knowns whose
    perturbation changed an output after the next step)."""
    outputs = sorted(
        (u.variable.name for u in md.outputs), key=lambda name: bool(variable_shapes(md)[name])
    )
    found = {o: set() for o in outputs}
    effective = set()
    for known in knowns_between_steps(md):
        current = point.get(known.name, start_value(known))
        for (value,) in perturbations(known, current):
            perturbed, twin = Instance(version, unzipdir, md), Instance(version, unzipdir, md)
            for instance in (perturbed, twin):
                assert instance.enter_initialization(point)
                instance.plate.fmu.exitInitializationMode()
                instance.plate.time = 0.0
                for _ in range(STEPS):
                    instance.plate.step(STEP)
            before = {o: perturbed.read(o) for o in outputs}
            if not perturbed.set(known.name, value):
                perturbed.free(), twin.free()
                continue
            after = {o: perturbed.read(o) for o in outputs}
            for o in outputs:
                if changed(before[o], after[o]):
                    found[o].add(known.name)
            for instance in (perturbed, twin):
                instance.plate.step(STEP)
            if any(changed(twin.read(o), perturbed.read(o)) for o in outputs):
                effective.add(known.name)
            perturbed.free(), twin.free()
            break
    return found, effective


def declared(unknowns):
    """{unknown: set of known names} of a `<ModelStructure>` list as fmpy reads it (None where an
    unknown declares no `dependencies`)."""
    return {
        u.variable.name: (None if u.dependencies is None else {d.name for d in u.dependencies})
        for u in unknowns
    }


def union(measurements):
    result = {}
    for measured in measurements:
        for unknown, knowns in measured.items():
            result.setdefault(unknown, set()).update(knowns)
    return result


@pytest.fixture(params=[2, 3], ids=["fmi2", "fmi3"])
def described(request, unzipdir, model_description, unzipdir3, model_description3):
    if request.param == 2:
        return 2, unzipdir, model_description
    return 3, unzipdir3, model_description3


def test_every_output_and_initial_unknown_declares_its_dependencies(described):
    _, _, md = described
    for kind, unknowns in (("output", md.outputs), ("initial unknown", md.initialUnknowns)):
        missing = [u for u, d in declared(unknowns).items() if d is None]
        assert not missing, f"these {kind}s declare no dependencies: {missing}"


def test_outputs_depend_on_what_was_measured_between_steps(described):
    version, unzipdir, md = described
    runs = [measure_outputs(version, unzipdir, md, point) for point in POINTS.values()]
    measured = union(found for found, _ in runs)
    assert measured == declared(md.outputs)
    # Each perturbation did change the outputs one step later, at one point at least: the
    # measurement above is not empty because the FMU ignored the value.
    effective = set().union(*(e for _, e in runs))
    assert effective == {v.name for v in knowns_between_steps(md)}, effective


def test_initial_unknowns_depend_on_what_was_measured(described):
    version, unzipdir, md = described
    measured = union(
        measure_initial_unknowns(version, unzipdir, md, point)
        for point in initialization_points(version, unzipdir, md).values()
    )
    expected = declared(md.initialUnknowns)
    wrong = {
        u: {
            "declared only": sorted(expected[u] - measured[u]),
            "measured only": sorted(measured[u] - expected[u]),
        }
        for u in expected
        if expected[u] != measured[u]
    }
    assert not wrong, wrong


def main(fmu):
    """Prints the measured dependencies of `fmu` as its `<ModelStructure>` would declare them."""
    md = read_model_description(fmu)
    version = int(md.fmiVersion[0])
    unzipdir = extract(fmu)
    outputs = union(measure_outputs(version, unzipdir, md, p)[0] for p in POINTS.values())
    initial = union(
        measure_initial_unknowns(version, unzipdir, md, p)
        for p in initialization_points(version, unzipdir, md).values()
    )
    position = {v.name: i + 1 for i, v in enumerate(md.modelVariables)}
    reference = {v.name: v.valueReference for v in md.modelVariables}
    key = position if version == 2 else reference

    def listed(knowns):
        return " ".join(str(k) for k in sorted(key[n] for n in knowns))

    for title, measured in (("Output", outputs), ("InitialUnknown", initial)):
        for unknown, knowns in measured.items():
            print(f'{title} {unknown} ({key[unknown]}): dependencies="{listed(knowns)}"')


if __name__ == "__main__":
    main(sys.argv[1])
