"""A mesh whose set-up would exceed the memory budget is refused at fmi2ExitInitializationMode,
at once and by name, from an estimate made before anything is assembled (docs/fmu.md, "Memory
budget")."""

import time

import pytest
from fmpy.fmi1 import FMICallException


def test_a_mesh_over_the_memory_budget_is_refused_at_once(new_plate):
    p = new_plate()
    p.fmu.setupExperiment(startTime=0.0)
    p.set("mesh.element", 1)  # Argyris
    p.set("mesh.nx", 400)
    p.set("mesh.ny", 400)
    p.fmu.enterInitializationMode()
    start = time.perf_counter()
    with pytest.raises(FMICallException) as e:
        p.fmu.exitInitializationMode()
    elapsed = time.perf_counter() - start
    assert e.value.status == 3  # fmi2Error
    text = " ".join(p.errors())
    for words in (
        "mesh.nx, mesh.ny",
        "400 × 400",
        "estimated",
        "largest part",
        "memory budget of 4096 MiB",
    ):
        assert words in text, f"{words!r} not in the log: {p.messages}"
    # Refused from the estimate: assembling this mesh (about 2 million dofs) would take minutes and
    # tens of GiB, the estimate microseconds; 5 s is far above any scheduling delay of a loaded host.
    assert elapsed < 5.0, f"the refusal took {elapsed:.1f} s"


def test_the_largest_paper_like_meshes_are_accepted(new_plate):
    # 100 × 50 FVS (15 300 free dofs, about 0.3 GiB estimated) is well within the budget: it sets
    # up and steps, a downward load bending it down but not through the lower obstacle.
    p = new_plate()
    p.initialize({"mesh.element": 2, "mesh.nx": 100, "mesh.ny": 50, "load.pressure": -1e3})
    p.step(1e-3)
    assert p.errors() == []
    corner = p.get("corner1.displacement")
    assert p.get("obstacle.lower") <= corner < 0.0
