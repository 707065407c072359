"""The FMU reports its plate's size and linear backend (`solver.free_dofs`, `solver.backend`,
calculated parameters of both FMI versions, docs/fmu.md) so that tools need not re-derive them.
Checked against values found without the FMU: the free dofs counted on the mesh itself (its
vertices and edges, each cell's diagonal as the element's mesh draws it), the backend by the
documented rule and, on two meshes, as the library's own set-up reports them."""

import subprocess

import pytest
from fmpy.fmi1 import FMICallException

from conftest import ROOT

# Documented in docs/fmu.md (and the descriptions): the codes of solver.backend.
MODAL, SPARSE = 1, 2
# The documented rule: modal up to this many free dofs, sparse above, modal at every size with a
# modal damping ratio (docs/speed.md).
MODAL_LIMIT = 2000
# (mesh.element, nx, ny, damping.modal_ratio): both elements on both sides of the limit (Argyris
# 20 × 10 has 1951 free dofs, 21 × 10 has 2048; FVS 40 × 20 has 2520), and a modal ratio that
# keeps a mesh above the limit modal.
CASES = [
    (1, 2, 1, 0.0),
    (1, 10, 7, 0.0),
    (1, 20, 10, 0.0),
    (1, 21, 10, 0.0),
    (2, 14, 10, 0.0),
    (2, 40, 20, 0.0),
    (1, 21, 10, 0.01),
    (2, 40, 20, 0.01),
]


def counted_free_dofs(element, nx, ny):
    """Free dofs counted on the mesh: vertices (i, j) at x_i = i Lx/nx, y_j = j Ly/ny; Argyris
    cells split by the diagonal from (i, j) to (i+1, j+1), with 6 dofs per vertex (the value, 2
    first and 3 second derivatives) and 1 per edge (the normal derivative at its midpoint), the
    clamp at x = 0 holding all but w_xx at its vertices and the normal derivative of its edges;
    FVS with 3 dofs per vertex (the value and 2 first derivatives), the clamp holding all 3."""
    vertices = {(i, j) for i in range(nx + 1) for j in range(ny + 1)}
    clamped = [v for v in vertices if v[0] == 0]
    if element == 2:
        return 3 * len(vertices) - 3 * len(clamped)
    edges = set()
    for i in range(nx):
        for j in range(ny):
            a, b, c, d = (i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)
            for triangle in ((a, b, c), (a, c, d)):
                for k in range(3):
                    edges.add(frozenset((triangle[k], triangle[(k + 1) % 3])))
    clamped_edges = [e for e in edges if all(v[0] == 0 for v in e)]
    return 6 * len(vertices) + len(edges) - 5 * len(clamped) - len(clamped_edges)


def expected(element, nx, ny, modal_ratio):
    n = counted_free_dofs(element, nx, ny)
    return n, MODAL if n <= MODAL_LIMIT or modal_ratio > 0 else SPARSE


def values(element, nx, ny, modal_ratio):
    return {
        "mesh.element": element,
        "mesh.nx": nx,
        "mesh.ny": ny,
        "damping.modal_ratio": modal_ratio,
    }


def test_the_count_on_the_mesh_is_the_papers():
    """The paper's 140-triangle mesh (Argyris 10 × 7): 88 vertices and 227 edges (80 along x, 77
    along y, 70 diagonals), 8 vertices and 7 edges on the clamped side: 6·88 + 227 − (5·8 + 7)
    = 708, as docs/converge/README.md and the scene example report it."""
    assert counted_free_dofs(1, 10, 7) == 708


@pytest.mark.parametrize("case", CASES)
def test_fmi2_reports_the_free_dofs_and_the_backend(new_plate, case):
    """Read in Initialization mode, before any set-up (the modal cases above the limit would
    spend seconds on an eigenbasis); fmi2GetInteger of both at once."""
    p = new_plate()
    p.fmu.setupExperiment(startTime=0.0)
    for name, value in values(*case).items():
        p.set(name, value)
    p.fmu.enterInitializationMode()
    got = p.fmu.getInteger([p.vr("solver.free_dofs"), p.vr("solver.backend")])
    assert tuple(got) == expected(*case), case
    assert p.errors() == []


@pytest.mark.parametrize("case", CASES)
def test_fmi3_reports_the_free_dofs_and_the_backend(new_plate3, case):
    p = new_plate3()
    for name, value in values(*case).items():
        p.set(name, value)
    p.fmu.enterInitializationMode(startTime=0.0)
    assert (p.get("solver.free_dofs"), p.get("solver.backend")) == expected(*case), case
    assert p.errors() == []


def test_the_defaults_read_after_initialization(new_plate, new_plate3):
    """Both versions agree on the default plate (the paper's mesh, 708 free dofs, modal) once
    initialized, and refuse to have them set."""
    two = new_plate().initialize()
    three = new_plate3().initialize()
    for p in (two, three):
        assert (p.get("solver.free_dofs"), p.get("solver.backend")) == (708, MODAL)
    with pytest.raises(FMICallException):
        two.set("solver.free_dofs", 1)
    assert any("solver.free_dofs" in m for m in two.errors()), two.messages


@pytest.mark.parametrize("mesh", [("fvs", 5, 3), ("argyris", 21, 10)])
def test_the_library_set_up_builds_what_the_fmu_reports(new_plate, mesh):
    """The library's own set-up of the same plate (`examples/scene.rs`, which prints its backend
    and free dofs to stderr) agrees: FVS 5 × 3 modal, Argyris 21 × 10 sparse."""
    name, nx, ny = mesh
    done = subprocess.run(
        [
            "cargo",
            "run",
            "--release",
            "--quiet",
            "--example",
            "scene",
            "--",
            "forced-35hz",
            f"mesh.element={name}",
            f"mesh.nx={nx}",
            f"mesh.ny={ny}",
            "stop_time=0.001",
        ],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=True,
    )
    line = next(line for line in done.stderr.splitlines() if " backend, " in line)
    backend = line.split(": ", 1)[1].split(" backend")[0]
    free = int(line.split(" backend, ")[1].split(" free dofs")[0])
    p = new_plate().initialize(
        {"mesh.element": {"argyris": 1, "fvs": 2}[name], "mesh.nx": nx, "mesh.ny": ny}
    )
    assert p.get("solver.free_dofs") == free
    assert p.get("solver.backend") == {"modal": MODAL, "sparse": SPARSE}[backend]
