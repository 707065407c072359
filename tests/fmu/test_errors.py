"""Bad input never crashes the host: every case returns an error status and logs why."""

import math

import pytest
from fmpy.fmi1 import FMICallException


def expect_error(plate, call, *words):
    with pytest.raises(FMICallException) as e:
        call()
    assert e.value.status == 3
    text = " ".join(plate.errors())
    for w in words:
        assert w in text, f"{w!r} not in the log: {plate.messages}"
    plate.messages.clear()


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf])
@pytest.mark.parametrize(
    "name",
    [
        "plate.length",
        "material.poisson_ratio",
        "solver.time_step",
        "obstacle.lower",
        "load.pressure",
        "base.amplitude",
    ],
)
def test_non_finite_parameters(new_plate, name, value):
    p = new_plate()
    expect_error(p, lambda: p.set(name, value), name)
    p.initialize()  # the rejected value changed nothing
    p.step(1e-3)


@pytest.mark.parametrize(
    "name,value",
    [
        ("plate.length", -0.4),
        ("plate.thickness", 0.0),
        ("material.poisson_ratio", 0.5),
        ("material.density", -1.0),
        ("solver.time_step", 0.0),
        ("solver.restitution", 1.5),
        ("solver.restitution", -0.25),
        ("mesh.nx", 0),
        ("mesh.ny", 100000),
        ("mesh.element", 3),
        ("damping.mass_proportional", -1.0),
        ("damping.stiffness_proportional", -1e-9),
        ("obstacle.lower", 0.01),
        ("obstacle.upper", -0.01),
        ("base.amplitude", -0.001),
    ],
)
def test_out_of_range_parameters(new_plate, name, value):
    p = new_plate()
    expect_error(p, lambda: p.set(name, value), name)
    p.initialize().step(1e-3)


def test_inconsistent_parameters_fail_at_initialization(new_plate):
    p = new_plate()
    p.fmu.setupExperiment(startTime=0.0)
    p.set("plate.thickness", 0.3)  # thicker than the 0.2 m width
    p.fmu.enterInitializationMode()
    expect_error(p, p.fmu.exitInitializationMode, "plate.thickness")


@pytest.mark.parametrize("value", [math.nan, math.inf])
def test_non_finite_input(new_plate, value):
    p = new_plate().initialize()
    expect_error(p, lambda: p.set("base.displacement", value), "base.displacement")
    p.step(1e-3)


def test_tunable_parameters_during_stepping(new_plate):
    p = new_plate().initialize()
    p.step(1e-3)
    p.set("load.pressure", 1000.0)
    p.set("obstacle.lower", -0.02)
    assert p.get("obstacle.lower") == -0.02
    expect_error(p, lambda: p.set("obstacle.upper", math.nan), "obstacle.upper")
    expect_error(p, lambda: p.set("obstacle.upper", -0.001), "obstacle.upper")
    expect_error(p, lambda: p.set("plate.length", 0.5), "plate.length", "fixed")
    expect_error(p, lambda: p.set("mesh.nx", 12), "mesh.nx")
    p.step(1e-3)


def test_base_leaving_the_gap(new_plate):
    p = new_plate().initialize()
    p.step(1e-3)
    p.set("base.displacement", 0.02)
    expect_error(p, lambda: p.step(1e-3), "base displacement")
    # The instance is in the Error state: stepping is refused, reset recovers.
    expect_error(p, lambda: p.fmu.doStep(p.time, 1e-3), "Error")
    p.fmu.reset()
    p.initialize().step(1e-3)


def test_bad_communication_steps(new_plate):
    p = new_plate().initialize()
    expect_error(p, lambda: p.fmu.doStep(0.0, -1e-3), "communicationStepSize")
    expect_error(p, lambda: p.fmu.doStep(0.0, math.nan), "communicationStepSize")
    expect_error(p, lambda: p.fmu.doStep(0.5, 1e-3), "currentCommunicationPoint")
    p.fmu.doStep(0.0, 1.5e-4)  # any finite h > 0 is fine
    expect_error(p, lambda: p.fmu.doStep(0.0, 1e-3), "currentCommunicationPoint", "0.00015")


def test_calls_in_the_wrong_state(new_plate):
    p = new_plate()
    expect_error(p, lambda: p.fmu.doStep(0.0, 1e-3), "fmi2DoStep")
    expect_error(p, p.fmu.exitInitializationMode, "fmi2ExitInitializationMode")
    expect_error(p, p.fmu.terminate, "fmi2Terminate")
    expect_error(p, lambda: p.fmu.getReal([p.vr("corner1.displacement")]), "fmi2GetReal")
    p.initialize()
    expect_error(p, p.fmu.enterInitializationMode, "fmi2EnterInitializationMode")
    expect_error(p, lambda: p.fmu.setupExperiment(startTime=0.0), "fmi2SetupExperiment")
    expect_error(p, lambda: p.set("corner1.displacement", 1.0), "corner1.displacement")
    expect_error(p, lambda: p.fmu.getReal([999]), "999")
    expect_error(p, lambda: p.fmu.getInteger([p.vr("plate.length")]), "plate.length")
    p.step(1e-3)
    p.fmu.terminate()
    expect_error(p, lambda: p.fmu.doStep(p.time, 1e-3), "Terminated")
    assert p.get("corner1.displacement") is not None  # values stay readable
    p.fmu.reset()
    p.initialize().step(1e-3)


def test_directional_derivative_is_refused_with_a_message(new_plate):
    p = new_plate().initialize()
    vr_out, vr_in = p.vr("corner1.displacement"), p.vr("base.displacement")
    expect_error(p, lambda: p.fmu.getDirectionalDerivative([vr_out], [vr_in], [1.0]), "directional")


def test_debug_logging_categories(new_plate):
    p = new_plate()
    with pytest.raises(FMICallException):
        p.fmu.setDebugLogging(True, ["noSuchCategory"])
    p.fmu.setDebugLogging(True, ["logContact"])
    p.initialize({"load.pressure": 3e5})
    for _ in range(100):
        p.step(1e-3)
    assert any(c == "logContact" for _, c, _ in p.messages), p.messages
    assert not any(c == "logAll" for _, c, _ in p.messages)
    p.fmu.setDebugLogging(True, [])
    p.step(1e-3)
    assert any(c == "logAll" for _, c, _ in p.messages)


def test_last_successful_time(new_plate):
    from fmpy.fmi2 import fmi2LastSuccessfulTime

    p = new_plate().initialize()
    p.step(1e-3)
    p.step(1e-3)
    assert p.fmu.getRealStatus(fmi2LastSuccessfulTime) == pytest.approx(2e-3, abs=1e-15)
