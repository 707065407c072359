"""The paper's whole model through both packaged FMUs: String parameters from fmpy start values,
the stops' and probes' outputs against the totals and the fields they sum, the natural
frequencies against the literature, gravity's sag at rest, and every bad description refused
by name with nothing applied (docs/model.md §4-§7, docs/usage.md "Profiles, clamps, probes and
stops")."""

import math

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.fmi1 import FMICallException

from conftest import scene_start_values

STUD = scene_start_values("stud-corner")[0]
PANEL = scene_start_values("clamped-panel")[0]


@pytest.fixture(params=[2, 3], ids=["fmi2", "fmi3"])
def fmu(request, fmu_path, fmu3_path):
    return fmu_path if request.param == 2 else fmu3_path


def test_a_stud_set_from_start_values_stops_the_corner(fmu):
    """The stud scene's texts through fmpy's start values: the plate hits the stud, its one stop
    carries the whole contact force at every point (the stop's own points are all the contact
    points there are), its impacts are the contact's, and the probe over the stud's centre (a
    contact point) never passes its level, 3 mm below the plate at rest, by more than round-off
    (1e-12 m: the outputs between grid points are convex combinations of admissible levels)."""
    outputs = [
        "stop1.force",
        "contact.force",
        "stop1.impacts",
        "contact.impacts",
        "probe1.displacement",
        "stop2.force",
    ]
    r = simulate_fmu(fmu, start_values=STUD, stop_time=0.3, output_interval=1e-3, output=outputs)
    assert np.sum(r["stop1.impacts"]) >= 5
    assert np.array_equal(r["stop1.impacts"], r["contact.impacts"])
    np.testing.assert_allclose(r["stop1.force"], r["contact.force"], rtol=1e-12, atol=1e-9)
    assert np.all(r["stop2.force"] == 0.0), "there is no second stop"
    level = STUD["obstacle.lower"]
    assert r["probe1.displacement"].min() >= level - 1e-12
    # Sampled every 1 ms, the probe comes within 0.1 mm of the stud (an impact lasts about 2 ms).
    assert r["probe1.displacement"].min() < level + 1e-4, "the probe over the stud reaches it"


def initializing(plate):
    """`plate` in Initialization Mode, where FMI 2.0 lets a host read parameters back."""
    plate.fmu.setupExperiment(startTime=0.0)
    plate.fmu.enterInitializationMode()
    return plate


def test_texts_read_back_as_set(new_plate):
    """fmi2GetString gives back the texts set, the defaults before."""
    plate = initializing(new_plate())
    assert plate.get("plate.clamp") == "xmin"
    assert plate.get("obstacle.lower_profile") == "flat"
    plate.set("obstacle.upper_profile", "plane(slope_x = 0.01)")
    plate.set("plate.clamp", "all")
    assert plate.get("obstacle.upper_profile") == "plane(slope_x = 0.01)"
    assert plate.get("plate.clamp") == "all"


@pytest.mark.parametrize(
    "name, text, words",
    [
        ("obstacle.lower_profile", "disc(x = 0.2, y = 0.1, radius = NaN)", ["not finite"]),
        ("obstacle.lower_profile", "bump(x = 0.1)", ["stop 1", "unknown kind"]),
        ("obstacle.upper_profile", "table(1, 2; 3)", ["row 2 of 1 values"]),
        ("plate.clamp", "left", ["naming no edge"]),
        ("plate.clamp", "", ["empty part 1", "singular"]),
    ],
)
def test_a_bad_text_is_refused_when_set_naming_it(new_plate, name, text, words):
    """A text that no plate takes is refused by the set, which changes nothing."""
    plate = initializing(new_plate())
    before = plate.get(name)
    with pytest.raises(FMICallException):
        plate.set(name, text)
    message = plate.errors()[-1]
    assert name in message and all(w in message for w in words), message
    assert plate.get(name) == before


@pytest.mark.parametrize(
    "values, words",
    [
        ({"obstacle.lower_profile": "point(x = 5, y = 0)"}, ["outside the plate"]),
        (
            {"obstacle.lower_profile": "point(x = 0.39, y = 0.01, offset = 0.02)"},
            ["obstacle.lower_profile", "below the plate at rest"],
        ),
        ({"plate.clamp": "ymin(0.105, 0.115)"}, ["covers no edge of the 10 × 7 mesh"]),
        ({"plate.clamp": "ymin(0.1, 0.5)"}, ["0 ≤ from < to ≤ 0.4"]),
        ({"probe1.x": 0.5}, ["probe1.x", "must lie on the plate"]),
    ],
)
def test_a_description_the_plate_refuses_fails_initialization_naming_it(new_plate, values, words):
    """What depends on the plate (a stop on it, a segment on its edge, the obstacle away from the
    plate at rest) is checked when initialization ends, with an error naming the parameter."""
    plate = new_plate()
    with pytest.raises(FMICallException):
        plate.initialize(values)
    message = " ".join(plate.errors())
    assert all(w in message for w in words), message


def test_the_fully_clamped_panel_has_leissas_frequency(new_plate):
    """mode1.frequency of the 2 mm panel clamped all round against Leissa's λ = ω a²√(ρe/D) = 98.31
    for the clamped plate of aspect ratio 2 (a the longer side; the value of an independent Ritz
    solution, docs/model.md §9): Argyris 10 × 7 lies 2e-6 to 3.2e-5 above it (conforming, an
    upper bound), so 1e-4 with the reference's own 3e-5 leaves room and a wrong clamp (a free
    edge moves λ₁ by tens of percent) fails."""
    plate = new_plate().initialize(PANEL)
    e, young, nu, rho = 0.002, 2.1e11, 0.3, 7770.0
    d = young * e**3 / (12 * (1 - nu**2))
    leissa = 98.31 / (2 * math.pi * 0.4**2) * math.sqrt(d / (rho * e))
    f1 = plate.get("mode1.frequency")
    assert 0 <= f1 / leissa - 1 < 1e-4, (f1, leissa)
    frequencies = [plate.get(f"mode{k}.frequency") for k in range(1, 7)]
    assert frequencies == sorted(frequencies)
    assert plate.get("plate.clamped_length") == pytest.approx(1.2, rel=1e-15)


def test_gravity_starts_the_plate_in_its_sag_at_rest(new_plate):
    """With load.gravity the initial state is the static sag: the plate stays there (nothing
    moves over 0.1 s, to round-off), the base carries the weight ρe·g·LxLy at rest, and the free
    corner hangs below the base by the cantilever's sag (a beam estimate qL⁴/(8D) of 3.2 mm for
    this aluminium plate; the plate, which also bends across, sags 3.4 mm)."""
    values = {
        "material.young_modulus": 7e10,
        "material.poisson_ratio": 0.33,
        "material.density": 2700.0,
        "plate.thickness": 0.002,
        "load.gravity": 9.80665,
        "obstacle.lower_enabled": False,
        "obstacle.upper_enabled": False,
    }
    plate = new_plate().initialize(values)
    weight = 2700.0 * 0.002 * 9.80665 * 0.4 * 0.2
    assert plate.get("base.force") == pytest.approx(-weight, rel=1e-12)
    sag = plate.get("corner1.displacement")
    assert -3.6e-3 < sag < -3.2e-3, sag
    for _ in range(100):
        plate.step(1e-3)
    assert plate.get("corner1.displacement") == pytest.approx(sag, rel=1e-9)


def test_a_state_carries_its_profile_into_another_instance(new_plate):
    """An FMU state is the whole instance, parameters included (docs/fmu.md, "FMU state"): the
    stud scene's state, set into an instance set up with flat obstacles, makes it the stud
    scene's, profile and all, and it continues bit for bit as the stud instance does; nothing is
    half applied (the library's stepper, which keeps its plate, refuses such a state naming the
    profile: tests/general_model)."""
    stud = new_plate().initialize(STUD)
    stud.step(0.01)
    state = stud.fmu.serializeFMUstate(stud.fmu.getFMUstate())
    flat_values = {**STUD, "obstacle.lower_profile": "flat", "obstacle.lower": -0.01}
    flat = new_plate(name="flat").initialize(flat_values)
    flat.fmu.setFMUstate(flat.fmu.deSerializeFMUstate(state))
    flat.time = stud.time
    assert flat.get("obstacle.lower_profile") == STUD["obstacle.lower_profile"]
    assert flat.get("obstacle.lower") == STUD["obstacle.lower"]
    for _ in range(20):
        stud.step(1e-3)
        flat.step(1e-3)
        assert flat.outputs() == stud.outputs()
