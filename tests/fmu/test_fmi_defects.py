"""The defects found by running the FMU in several engines, each reproduced through the C API
(fmpy's FMU2Slave): the FMU must refuse without effect, fail cleanly, or give the same bits."""

import math
import time

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.fmi1 import FMICallException

import fmu_state

ERROR = 3


def refused(plate, call, *words):
    with pytest.raises(FMICallException) as e:
        call()
    assert e.value.status == ERROR
    text = " ".join(plate.errors())
    for w in words:
        assert w in text, f"{w!r} not in the log: {plate.messages}"
    plate.messages.clear()


def values(plate):
    """Every variable the host can read now, as exact bits."""
    out = {}
    for name in plate.variables:
        try:
            out[name] = plate.get(name)
        except FMICallException:
            out[name] = None
    return out


def test_a_refused_multi_value_set_changes_nothing(new_plate):
    p = new_plate()
    p.fmu.setupExperiment(startTime=0.0)
    p.fmu.enterInitializationMode()
    before = values(p)
    refused(
        p,
        lambda: p.fmu.setReal([p.vr("load.pressure"), p.vr("energy.kinetic")], [7770.0, 1.0]),
        "energy.kinetic",
    )
    refused(
        p, lambda: p.fmu.setInteger([p.vr("mesh.nx"), p.vr("mesh.element")], [5, 3]), "mesh.element"
    )
    refused(
        p, lambda: p.fmu.setBoolean([p.vr("obstacle.lower_enabled"), 9999], [False, True]), "9999"
    )
    assert values(p) == before
    p.fmu.exitInitializationMode()
    p.step(1e-3)
    before = values(p)
    refused(
        p,
        lambda: p.fmu.setReal([p.vr("obstacle.upper"), p.vr("load.pressure")], [1e308, math.nan]),
        "load.pressure",
    )
    refused(
        p,
        lambda: p.fmu.setReal([p.vr("base.displacement"), p.vr("plate.width")], [1e-3, 0.3]),
        "plate.width",
    )
    assert values(p) == before


def test_a_step_that_overflows_is_an_error_not_garbage(new_plate):
    p = new_plate().initialize({"obstacle.lower_enabled": False, "obstacle.upper_enabled": False})
    p.set("base.displacement", 1e308)
    refused(p, lambda: p.step(1e-3), "non-finite")
    for name, v in p.variables.items():
        if v.causality == "output" and v.type == "Real":
            try:
                assert math.isfinite(p.get(name)), name
            except FMICallException:
                pass  # refused: fine, never a non-finite value with OK
    refused(p, lambda: p.fmu.doStep(p.time, 1e-3), "Error")  # the Error state
    p.fmu.reset()
    p.initialize().step(1e-3)


def crafted(plate, edit):
    data = plate.fmu.serializeFMUstate(plate.fmu.getFMUstate())
    payload, crate_version = fmu_state.decode(data)
    edited = edit(payload)
    return fmu_state.encode(edited if edited is not None else payload, crate_version), bytes(data)


@pytest.mark.parametrize(
    "field,edit,words",
    [
        ("start_time", lambda s: s["model"].update(start_time=-1e308), "too coarse"),
        (
            "poisson_ratio",
            lambda s: s["model"]["parameters"]["material"].update(poisson_ratio=0.7),
            "material.poisson_ratio",
        ),
        (
            "field value",
            lambda s: s["model"]["simulation"]["stepper"]["current"].__setitem__(0, -1e308),
            "current[contact point",
        ),
        (
            "step count",
            lambda s: json_text(s, '"step_index":', "-9223372036854775809"),
            "invalid payload",
        ),
        ("mode", lambda s: s.update(mode="StepCanceled"), "never enters"),
    ],
)
def test_crafted_states_with_good_checksums_are_refused(new_plate, field, edit, words):
    p = new_plate().initialize({"base.amplitude": 0.005})
    for _ in range(5):
        p.step(1e-3)
    data, original = crafted(p, edit)
    before = values(p)
    with pytest.raises(FMICallException) as e:
        p.fmu.setFMUstate(p.fmu.deSerializeFMUstate(data))
    assert e.value.status == ERROR
    assert any(words in m for m in p.errors()), (field, p.messages)
    assert values(p) == before
    assert bytes(p.fmu.serializeFMUstate(p.fmu.getFMUstate())) == original


def json_text(payload, key, raw):
    """The payload as JSON text with the value after `key` replaced by the raw text `raw` (for
    numbers no JSON library writes, such as integers beyond 64 bits)."""
    import json
    import re

    return re.sub(re.escape(key) + r"\d+", key + raw, json.dumps(payload, separators=(",", ":")))


@pytest.mark.parametrize("h", [1e300, 1e12])
def test_a_huge_step_is_refused_at_once(new_plate, h):
    p = new_plate().initialize()
    start = time.perf_counter()
    refused(p, lambda: p.fmu.doStep(0.0, h), "internal steps")
    assert time.perf_counter() - start < 1.0  # at once: 1 s is the budget of a refusal, not a run
    p.step(1e-3)


def test_a_start_time_whose_grid_cannot_advance_is_refused(new_plate):
    p = new_plate()
    refused(p, lambda: p.fmu.setupExperiment(startTime=-1e308), "startTime", "too coarse")
    p.initialize().step(1e-3)


def test_ulp_jitter_of_the_step_size_gives_the_same_bits(new_plate):
    def run(jitter):
        p = new_plate(f"jitter{jitter}").initialize()
        out = []
        for k in range(300):
            t = k * 1e-3
            h = (k + 1) * 1e-3 - t if jitter else 1e-3
            p.set("base.displacement", 2e-3 * math.sin(60.0 * t))
            p.fmu.doStep(p.fmu.getRealStatus(2) if k else 0.0, h)
            out.append(p.get("corner1.displacement"))
        return np.array(out)

    assert run(True).tobytes() == run(False).tobytes()


def test_the_element_can_be_set_as_an_integer(fmu_path):
    # The FVS element, reachable in engines that only set Integers.
    a = simulate_fmu(
        fmu_path,
        stop_time=0.02,
        start_values={"mesh.element": 2, "base.amplitude": 0.005},
        output=["corner1.displacement"],
    )
    b = simulate_fmu(
        fmu_path,
        stop_time=0.02,
        start_values={"mesh.element": 1, "base.amplitude": 0.005},
        output=["corner1.displacement"],
    )
    assert not np.array_equal(a["corner1.displacement"], b["corner1.displacement"])
