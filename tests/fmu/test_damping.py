"""Damping in engineers' terms through both FMUs (docs/fmu.md, docs/scheme.md §10): the
damping.ratio pair's alpha and beta are calculated parameters equal to the formula, a pair given
with an explicit coefficient is refused naming both, inconsistent frequencies are refused by name,
a modal ratio damps; and the warning at initialization (docs/accuracy/damping.md) is logged for
the paper's forced scene and not for the damped preset, without changing any result."""

import math

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException

from conftest import scene_start_values

WARNING = 1
DOCS = "docs/accuracy/damping.md"
SMALL = {"mesh.nx": 3, "mesh.ny": 2}


def pair(ratio, low, high):
    """alpha (1/s) and beta (s) of the Rayleigh pair with ratio zeta at low and high (Hz)."""
    w1, w2 = 2 * math.pi * low, 2 * math.pi * high
    return 2 * ratio * w1 * w2 / (w1 + w2), 2 * ratio / (w1 + w2)


def test_the_description_declares_the_damping_variables(model_description, model_description3):
    for md in (model_description, model_description3):
        by_name = {v.name: v for v in md.modelVariables}
        for name, unit in [
            ("damping.ratio", "1"),
            ("damping.frequency_low", "Hz"),
            ("damping.frequency_high", "Hz"),
            ("damping.modal_ratio", "1"),
        ]:
            v = by_name[name]
            assert (v.causality, v.variability, float(v.start), v.min) == (
                "parameter",
                "fixed",
                0.0,
                "0",
            ), name
            assert v.unit == unit, name
        for name, unit in [("damping.alpha", "1/s"), ("damping.beta", "s")]:
            v = by_name[name]
            assert (v.causality, v.variability, v.unit) == ("calculatedParameter", "fixed", unit)


@pytest.mark.parametrize("version", [2, 3])
def test_the_ratio_pair_is_readable_as_alpha_and_beta(new_plate, new_plate3, version):
    p = new_plate() if version == 2 else new_plate3()
    for name, value in {
        **SMALL,
        "damping.ratio": 0.01,
        "damping.frequency_low": 53.83,
        "damping.frequency_high": 5000.0,
    }.items():
        p.set(name, value)
    if version == 2:
        p.fmu.setupExperiment(startTime=0.0)
        p.fmu.enterInitializationMode()
    else:
        p.fmu.enterInitializationMode(startTime=0.0)
    alpha, beta = pair(0.01, 53.83, 5000.0)
    assert p.get("damping.alpha") == pytest.approx(alpha, rel=1e-14)
    assert p.get("damping.beta") == pytest.approx(beta, rel=1e-14)
    assert alpha == pytest.approx(6.692, abs=5e-4) and beta == pytest.approx(6.298e-7, abs=5e-11)
    p.fmu.exitInitializationMode()
    p.time = 0.0
    p.step(1e-2)
    assert p.get("energy.damping_loss") >= 0.0


@pytest.mark.parametrize(
    "explicit", ["damping.mass_proportional", "damping.stiffness_proportional"]
)
def test_a_pair_with_an_explicit_coefficient_is_refused_naming_both(new_plate, explicit):
    p = new_plate()
    for name, value in {
        "damping.ratio": 0.01,
        "damping.frequency_low": 50.0,
        "damping.frequency_high": 5000.0,
        explicit: 1e-6,
    }.items():
        p.set(name, value)
    p.fmu.setupExperiment(startTime=0.0)
    p.fmu.enterInitializationMode()
    with pytest.raises(FMICallException):
        p.fmu.exitInitializationMode()
    text = " ".join(p.errors())
    assert "damping.ratio" in text and explicit in text, p.messages


@pytest.mark.parametrize(
    "values,name",
    [
        ({"damping.ratio": 0.01, "damping.frequency_high": 100.0}, "damping.frequency_low"),
        (
            {
                "damping.ratio": 0.01,
                "damping.frequency_low": 100.0,
                "damping.frequency_high": 100.0,
            },
            "damping.frequency_high",
        ),
        (
            {
                "damping.ratio": 0.01,
                "damping.frequency_low": 200.0,
                "damping.frequency_high": 100.0,
            },
            "damping.frequency_high",
        ),
    ],
)
def test_inconsistent_frequencies_are_refused_by_name(new_plate, values, name):
    p = new_plate()
    for k, v in values.items():
        p.set(k, v)
    p.fmu.setupExperiment(startTime=0.0)
    p.fmu.enterInitializationMode()
    with pytest.raises(FMICallException):
        p.fmu.exitInitializationMode()
    assert name in " ".join(p.errors()), p.messages


@pytest.mark.parametrize(
    "name",
    ["damping.ratio", "damping.frequency_low", "damping.frequency_high", "damping.modal_ratio"],
)
def test_negative_values_are_refused_at_once(new_plate, name):
    p = new_plate()
    with pytest.raises(FMICallException):
        p.set(name, -1.0)
    assert name in " ".join(p.errors())


def test_a_modal_ratio_damps(new_plate):
    runs = []
    for ratio in (0.0, 0.02):
        p = new_plate().initialize({**SMALL, "base.amplitude": 0.005, "damping.modal_ratio": ratio})
        for _ in range(100):
            p.step(1e-3)
        runs.append((p.get("energy.damping_loss"), p.get("corner1.displacement")))
    assert runs[0][0] == 0.0 and runs[1][0] > 0.0
    assert runs[0][1] != runs[1][1]


def warnings(p):
    return [m for s, c, m in p.messages if s == WARNING and c == "logStatusWarning"]


@pytest.mark.parametrize("version", [2, 3])
def test_the_warning_is_logged_for_the_paper_scene_and_not_for_the_damped_preset(
    new_plate, new_plate3, version
):
    make = new_plate if version == 2 else new_plate3
    forced = make().initialize(scene_start_values("forced-35hz")[0])
    logged = warnings(forced)
    assert len(logged) == 1 and DOCS in logged[0], forced.messages
    # The advice is a message, not the call's status: strict importers (fmusim) stop at a returned
    # Warning, so exit-initialization returns OK (docs/fmu.md, "Errors and logging").
    assert forced.exit_status == 0
    damped = make().initialize(scene_start_values("forced-35hz-damped")[0])
    assert warnings(damped) == [], damped.messages
    alone = make().initialize({"obstacle.lower_enabled": False, "obstacle.upper_enabled": False})
    assert warnings(alone) == [], alone.messages


def test_the_warning_changes_no_result(new_plate):
    """The same undamped run warned (default logging) and with logging switched off entirely
    gives the same numbers, bit for bit."""
    values = {**scene_start_values("forced-35hz")[0], **SMALL}
    traces = []
    for silence in (False, True):
        p = new_plate()
        if silence:
            p.fmu.setDebugLogging(False, ["logStatusWarning"])
        p.initialize(values)
        assert (len(warnings(p)) == 0) == silence
        outputs = []
        for _ in range(50):
            p.step(1e-3)
            outputs.append(p.outputs())
        traces.append(np.array(outputs))
    np.testing.assert_array_equal(traces[0], traces[1])
