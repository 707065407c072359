"""Stability matrix through the FMU (docs/limits.md): extreme parameter sets either run with finite
outputs, bounds kept to 1e-9 of the gap at the reported points and the energy law, or fail with fmi2Error
at the earliest call that can know, with a message naming the parameter and its limit."""

import math

import pytest
from fmpy.fmi1 import FMICallException

OUTPUTS = [
    "corner1.displacement",
    "corner2.displacement",
    "edge_mid.displacement",
    "energy.kinetic",
    "energy.elastic",
    "energy.total",
    "contact.force",
]


def drop_preload(v):
    """16 D g / Lx^4: twice the pressure that bends the cantilever tip to the upper obstacle."""
    e = v.get("plate.thickness", 0.01)
    young = v.get("material.young_modulus", 2.1e11)
    nu = v.get("material.poisson_ratio", 0.3)
    d = young * e**3 / (12 * (1 - nu * nu))
    return 16 * d * v.get("obstacle.upper", 0.01) / v.get("plate.length", 0.4) ** 4


def run(plate, values, steps, h):
    """Runs `steps` communication steps of h; returns the list of energy.total and checks each step."""
    plate.initialize(values)
    lower = values.get("obstacle.lower", -0.01)
    upper = values.get("obstacle.upper", 0.01)
    tol = 1e-9 * (upper - lower)
    energies = []
    for _ in range(steps):
        plate.step(h)
        out = dict(zip(OUTPUTS, plate.fmu.getReal([plate.vr(n) for n in OUTPUTS])))
        assert all(math.isfinite(x) for x in out.values()), out
        for name in OUTPUTS[
            :2
        ]:  # the free corners are constrained vertices (edge_mid is one only for even ny)
            assert lower - tol <= out[name] <= upper + tol, (name, out[name])
        energies.append(out["energy.total"])
    return energies


def non_increasing(energies, rel=5e-9):
    scale = max(abs(e) for e in energies)
    rise = max((b - a for a, b in zip(energies, energies[1:])), default=0.0)
    assert rise <= rel * scale, f"energy rose by {rise / scale:e} of its scale"


def bounded(energies, factor=2.0):
    half = len(energies) // 2
    assert max(energies[half:]) <= factor * max(energies[:half])


DROPS = {
    "E=1e6": (
        {"material.young_modulus": 1e6, "solver.time_step": 1e-3, "mesh.nx": 6, "mesh.ny": 3},
        200,
        1e-2,
    ),
    "E=1e13": (
        {"material.young_modulus": 1e13, "solver.time_step": 1e-5, "mesh.nx": 6, "mesh.ny": 3},
        100,
        2e-4,
    ),
    "e=1e-4": (
        {
            "plate.thickness": 1e-4,
            "solver.time_step": 1e-3,
            "mesh.element": 2,
            "mesh.nx": 8,
            "mesh.ny": 4,
        },
        200,
        1e-2,
    ),
    "e=0.1": (
        {"plate.thickness": 0.1, "solver.time_step": 1e-5, "mesh.nx": 6, "mesh.ny": 3},
        100,
        5e-5,
    ),
    "nu=0": ({"material.poisson_ratio": 0.0, "mesh.nx": 8, "mesh.ny": 4}, 100, 1e-3),
    "nu=0.499": (
        {"material.poisson_ratio": 0.499, "mesh.element": 2, "mesh.nx": 8, "mesh.ny": 4},
        100,
        1e-3,
    ),
    "dt=1e-2": ({"solver.time_step": 1e-2}, 30, 1e-2),
    "dt=1e-7": ({"solver.time_step": 1e-7, "mesh.nx": 4, "mesh.ny": 2}, 50, 1e-6),
    "gap=1e-9": (
        {"obstacle.lower": -1e-9, "obstacle.upper": 1e-9, "mesh.nx": 6, "mesh.ny": 3},
        100,
        1e-4,
    ),
    "1x1 argyris": ({"mesh.nx": 1, "mesh.ny": 1}, 200, 1e-3),
    "1x1 fvs": ({"mesh.element": 2, "mesh.nx": 1, "mesh.ny": 1}, 200, 1e-3),
    "Lx/Ly=0.01": (
        {
            "plate.length": 0.01,
            "plate.width": 1.0,
            "plate.thickness": 1e-3,
            "solver.time_step": 1e-5,
            "mesh.nx": 1,
            "mesh.ny": 20,
        },
        100,
        2e-4,
    ),
    "Lx/Ly=100": (
        {
            "plate.length": 1.0,
            "plate.width": 0.01,
            "plate.thickness": 1e-3,
            "mesh.nx": 20,
            "mesh.ny": 1,
        },
        100,
        2e-2,
    ),
}


@pytest.mark.parametrize("case", list(DROPS))
def test_released_from_the_upper_obstacle(new_plate, case):
    """Fixed base, no load: released from a preload onto the upper obstacle, E never rises."""
    values, steps, h = DROPS[case]
    values = dict(values)
    values["initial.preload_pressure"] = drop_preload(values)
    energies = run(new_plate(), values, steps, h)
    non_increasing(energies)


@pytest.mark.parametrize(
    "case,values",
    [
        ("c just inside the gap", {"base.amplitude": 0.01 * (1 - 1e-6), "base.frequency": 35.0}),
        (
            "gap 1 m",
            {
                "base.amplitude": 0.009,
                "base.frequency": 35.0,
                "obstacle.lower": -1.0,
                "obstacle.upper": 1.0,
            },
        ),
        (
            "f far above the modes",
            {"base.amplitude": 0.005, "base.frequency": 2.61637777e8, "mesh.nx": 4, "mesh.ny": 2},
        ),
        (
            "restitution 0",
            {"base.amplitude": 0.009, "base.frequency": 35.0, "solver.restitution": 0.0},
        ),
    ],
)
def test_forced_energy_stays_bounded(new_plate, case, values):
    bounded(run(new_plate(), values, 200, 1e-3))


def test_preload_presses_most_vertices_onto_the_obstacle(new_plate):
    p = -50 * drop_preload({})
    plate = new_plate()
    energies = run(plate, {"initial.preload_pressure": p, "load.pressure": p}, 50, 1e-3)
    non_increasing(energies)
    assert plate.get("contact.active_nodes") > 40  # of 80 constrained vertices (10 x 7 mesh)


def test_restitution_1_keeps_the_bounds_and_the_energy_law(new_plate):
    """e = 1 (Newton's law, elastic) keeps the bounds, finite values and the energy law."""
    values = {"solver.restitution": 1.0, "initial.preload_pressure": drop_preload({})}
    energies = run(new_plate(), values, 100, 1e-3)
    non_increasing(energies)


def test_sixty_by_thirty_mesh(new_plate):
    values = {"mesh.element": 2, "mesh.nx": 60, "mesh.ny": 30}
    values["initial.preload_pressure"] = drop_preload(values)
    non_increasing(run(new_plate(), values, 10, 1e-3))


def expect_error(plate, call, *words):
    with pytest.raises(FMICallException) as e:
        call()
    assert e.value.status == 3
    text = " ".join(plate.errors())
    for w in words:
        assert w in text, f"{w!r} not in the log: {plate.messages}"


@pytest.mark.parametrize(
    "name,value,limit",
    [
        ("material.poisson_ratio", 0.5, "(-1, 0.5)"),
        ("solver.restitution", 1.01, "[0, 1]"),
        ("solver.time_step", -1e-7, "> 0"),
        ("material.young_modulus", 0.0, "> 0"),
    ],
)
def test_out_of_range_fails_at_the_set(new_plate, name, value, limit):
    p = new_plate()
    expect_error(p, lambda: p.set(name, value), name, limit)


def test_base_amplitude_at_the_gap_fails_at_initialization(new_plate):
    p = new_plate()
    p.fmu.setupExperiment(startTime=0.0)
    p.set("base.amplitude", 0.01)
    p.fmu.enterInitializationMode()
    expect_error(p, p.fmu.exitInitializationMode, "base.amplitude", "0.01")


def test_external_base_outside_the_gap_fails_at_that_step(new_plate):
    p = new_plate().initialize({"obstacle.lower": -1e-9, "obstacle.upper": 1e-9})
    p.step(1e-3)
    p.set("base.displacement", 2e-9)
    expect_error(p, lambda: p.step(1e-3), "base displacement", "not strictly between the obstacles")
