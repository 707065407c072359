"""Shared fixtures for the FMU tests: the packaged FMUs (FMI 2.0 and FMI 3.0) and thin drivers
around fmpy's FMU2Slave and FMU3Slave."""

import os
import subprocess
from ctypes import byref

import pytest
from fmpy import extract, read_model_description
from fmpy.fmi1 import calloc, free
from fmpy.fmi2 import (
    FMU2Slave,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
)
from fmpy.fmi3 import FMU3Slave
from fmpy.logging import addLoggerProxy

from plateimpact_tools import ROOT, SCENES  # noqa: F401 (the tests' names)

# (start values, stop time) of a shipped scene: the tests' name for the package's reader.
from plateimpact_tools.scene_values import scene as scene_start_values  # noqa: F401


def pytest_configure(config):
    """The marker `slow`: a test that runs whole convergence studies through the FMU (minutes on
    the 2-core machine). The full suite (`pytest tests/fmu`, scripts/test-all) runs them; a quick
    loop leaves them out with `-m "not slow"`."""
    config.addinivalue_line(
        "markers", "slow: minutes of FMU runs; the full suite runs it, -m 'not slow' skips it"
    )
    config.addinivalue_line(
        "markers",
        "fmu: needs a packaged FMU (set by the suite on every test that requests one); "
        "scripts/check runs the others, -m 'not fmu'",
    )


# The fixtures that package or read an FMU: a test that requests one, directly or through another
# fixture, is marked `fmu`.
FMU_FIXTURES = {"fmu_path", "fmu3_path"}


def pytest_collection_modifyitems(config, items):
    """Marks every test that needs a packaged FMU `fmu`, so that the tools' own tests (the rule,
    the study tables, the window statistics) run alone, with `-m 'not fmu'`, in scripts/check."""
    for item in items:
        if FMU_FIXTURES & set(getattr(item, "fixturenames", ())):
            item.add_marker(pytest.mark.fmu)


@pytest.fixture(scope="session")
def fmu_path():
    """The FMU built by `cargo run --release --bin package-fmu` (or $PLATE_IMPACT_FMU)."""
    given = os.environ.get("PLATE_IMPACT_FMU")
    if given:
        return given
    subprocess.run(
        ["cargo", "run", "--release", "--quiet", "--bin", "package-fmu"],
        cwd=ROOT,
        check=True,
    )
    return str(ROOT / "target" / "fmu" / "PlateImpact.fmu")


@pytest.fixture(scope="session")
def fmu3_path(fmu_path):
    """The FMI 3.0 FMU, built with the FMI 2.0 one (or $PLATE_IMPACT_FMU3)."""
    return os.environ.get("PLATE_IMPACT_FMU3") or str(
        ROOT / "target" / "fmu" / "PlateImpact-fmi3.fmu"
    )


@pytest.fixture(scope="session")
def model_description(fmu_path):
    return read_model_description(fmu_path)


@pytest.fixture(scope="session")
def model_description3(fmu3_path):
    return read_model_description(fmu3_path)


@pytest.fixture(scope="session")
def unzipdir(fmu_path, tmp_path_factory):
    return extract(fmu_path, unzipdir=str(tmp_path_factory.mktemp("fmu")))


@pytest.fixture(scope="session")
def unzipdir3(fmu3_path, tmp_path_factory):
    return extract(fmu3_path, unzipdir=str(tmp_path_factory.mktemp("fmu3")))


# fmpy's native logger proxy (it formats the variadic FMI 2.0 message) forwards every proxied
# callback, fmpy's own default callbacks included, to ONE Python logger: the last one installed. So
# the tests install a single logger that lives for the whole session and dispatches each message
# by the instance's componentEnvironment to its Plate's list: a freed Plate leaves no dangling
# logger behind for an instance made with fmpy's defaults (examples/shaker_coupling.py) to call.
_MESSAGES = {}


def _dispatch(env, _instance, status, category, message):
    messages = _MESSAGES.get(env)
    if messages is not None:
        messages.append((status, category.decode(), message.decode()))


_LOGGER = fmi2CallbackLoggerTYPE(_dispatch)


def reinstall_session_logger():
    """Points fmpy's logger proxy back at the session's logger. `simulate_fmu(..., logger=f)`
    installs a logger of its own that lives only as long as that call; an FMI 2.0 instance made
    later with fmpy's default callbacks would call it after it is freed (a crash, seen as a bus
    error). A test that passes a logger to simulate_fmu calls this afterwards."""
    callbacks = fmi2CallbackFunctions()
    callbacks.logger = _LOGGER
    addLoggerProxy(byref(callbacks))


class Plate:
    """One FMU instance driven through fmpy's low-level FMU2Slave, collecting logged messages."""

    def __init__(self, unzipdir, model_description, name="plate", logging_on=False):
        md = model_description
        self.variables = {v.name: v for v in md.modelVariables}
        self.messages = []
        key = len(_MESSAGES) + 1
        _MESSAGES[key] = self.messages
        self.callbacks = fmi2CallbackFunctions()
        self.callbacks.componentEnvironment = key
        self.callbacks.logger = _LOGGER
        self.callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        self.callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        addLoggerProxy(byref(self.callbacks))
        self.fmu = FMU2Slave(
            guid=md.guid,
            unzipDirectory=unzipdir,
            modelIdentifier=md.coSimulation.modelIdentifier,
            instanceName=name,
        )
        self.fmu.instantiate(callbacks=self.callbacks, loggingOn=logging_on)
        self.time = 0.0

    def vr(self, name):
        return self.variables[name].valueReference

    def set(self, name, value):
        kind = self.variables[name].type
        if kind == "Real":
            self.fmu.setReal([self.vr(name)], [float(value)])
        elif kind in ("Integer", "Enumeration"):
            self.fmu.setInteger([self.vr(name)], [int(value)])
        elif kind == "Boolean":
            self.fmu.setBoolean([self.vr(name)], [bool(value)])
        elif kind == "String":
            self.fmu.setString([self.vr(name)], [str(value)])
        else:
            raise TypeError(kind)

    def get(self, name):
        kind = self.variables[name].type
        if kind == "Real":
            return self.fmu.getReal([self.vr(name)])[0]
        if kind in ("Integer", "Enumeration"):
            return self.fmu.getInteger([self.vr(name)])[0]
        if kind == "String":
            return self.fmu.getString([self.vr(name)])[0].decode()
        return self.fmu.getBoolean([self.vr(name)])[0]

    def initialize(self, start_values=None, start=0.0, stop=None):
        self.fmu.setupExperiment(startTime=start, stopTime=stop)
        for name, value in (start_values or {}).items():
            self.set(name, value)
        self.fmu.enterInitializationMode()
        self.exit_status = self.fmu.exitInitializationMode()  # fmi2Status
        self.time = start
        return self

    def step(self, h):
        self.fmu.doStep(self.time, h)
        self.time += h

    def outputs(self):
        names = [
            n for n, v in self.variables.items() if v.causality == "output" and v.type == "Real"
        ]
        return self.fmu.getReal([self.vr(n) for n in names])

    def errors(self):
        return [m for s, c, m in self.messages if s >= 3]

    def free(self):
        self.fmu.freeInstance()


def instances(kind, unzipdir, model_description):
    """A factory of `kind` instances (Plate or Plate3) for a fixture, and a finalizer freeing
    every instance it made (ignoring those a test already freed)."""
    made = []

    def make(*args, **kwargs):
        p = kind(unzipdir, model_description, *args, **kwargs)
        made.append(p)
        return p

    def free_all():
        for p in made:
            try:
                p.free()
            except Exception:
                pass

    return make, free_all


@pytest.fixture
def new_plate(unzipdir, model_description):
    """Plate(name="plate", logging_on=False) instances, freed after the test."""
    make, free_all = instances(Plate, unzipdir, model_description)
    yield make
    free_all()


class Plate3:
    """One FMI 3.0 instance driven through fmpy's FMU3Slave, collecting logged messages."""

    def __init__(self, unzipdir, model_description, name="plate", early_return=False):
        md = model_description
        self.variables = {v.name: v for v in md.modelVariables}
        self.messages = []

        def log(_env, status, category, message):
            self.messages.append((status, category.decode(), message.decode()))

        self.fmu = FMU3Slave(
            guid=md.guid,
            unzipDirectory=unzipdir,
            modelIdentifier=md.coSimulation.modelIdentifier,
            instanceName=name,
        )
        self.fmu.instantiate(earlyReturnAllowed=early_return, logMessage=log)
        self.time = 0.0

    def vr(self, name):
        return self.variables[name].valueReference

    def set(self, name, value):
        setter = getattr(self.fmu, "set" + self.variables[name].type)
        setter([self.vr(name)], [value])

    def get(self, name):
        variable = self.variables[name]
        count = 1
        for d in variable.dimensions:
            count *= int(d.start) if d.start is not None else self.get(d.variable.name)
        values = getattr(self.fmu, "get" + variable.type)([self.vr(name)], nValues=count)
        return values if variable.dimensions else values[0]

    def initialize(self, start_values=None, start=0.0, stop=None):
        for name, value in (start_values or {}).items():
            self.set(name, value)
        self.fmu.enterInitializationMode(startTime=start, stopTime=stop)
        # fmpy's exitInitializationMode drops the status; its raw wrapper returns it (fmi3Status).
        self.exit_status = self.fmu.fmi3ExitInitializationMode(self.fmu.component)
        self.time = start
        return self

    def step(self, h):
        """One fmi3DoStep of h from the FMU time: (earlyReturn, lastSuccessfulTime)."""
        _, _, early, reached = self.fmu.doStep(self.time, h)
        self.time = reached
        return early, reached

    def errors(self):
        return [m for s, c, m in self.messages if s >= 3]

    def free(self):
        self.fmu.freeInstance()


@pytest.fixture
def new_plate3(unzipdir3, model_description3):
    """Plate3(name="plate", early_return=False) instances, freed after the test."""
    make, free_all = instances(Plate3, unzipdir3, model_description3)
    yield make
    free_all()
