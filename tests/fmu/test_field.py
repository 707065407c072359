"""The FMI 3.0 field on a mesh other than the default, through plateimpact_tools.field.simulate:
sized in Configuration Mode, its shape the mesh's vertices, its free corner the corner output,
the same corner as the FMI 2.0 FMU's; sizes given by hand must agree with the mesh."""

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu

from plateimpact_tools.field import field_sizes, simulate

# The damped forced scene on FVS 14 × 10 (15 × 11 vertices), 50 ms: impacts from about 20 ms.
SCENE = {
    "base.amplitude": 0.009,
    "base.frequency": 35.0,
    "damping.stiffness_proportional": 5.913e-5,
    "mesh.element": 2,
    "mesh.nx": 14,
    "mesh.ny": 10,
}
STOP = 0.05


def test_the_field_takes_the_mesh_shape(fmu_path, fmu3_path):
    r = simulate(
        fmu3_path,
        SCENE,
        stop_time=STOP,
        output=["plate.displacement", "corner1.displacement", "contact.impacts"],
    )
    field = r["plate.displacement"]
    assert field.shape == (51, 11, 15)
    assert r["contact.impacts"].sum() > 0, "the window holds impacts"
    # Row j = 0 is y = 0, column i = 14 is x = Lx: the corner the output names. The output is
    # evaluated through the element, the field read at the vertex: the same value to round-off
    # (1e-15 m is about a thousand doubles apart at 5 mm).
    assert np.allclose(field[:, 0, 14], r["corner1.displacement"], rtol=0, atol=1e-15)
    # Column 0 is the clamp, which follows the base's sine (numpy's sin against the FMU's own,
    # to round-off).
    base = 0.009 * np.sin(2 * np.pi * 35.0 * r["time"])
    assert np.allclose(field[:, :, 0], base[:, None], rtol=0, atol=1e-15)
    fmi2 = simulate(fmu_path, SCENE, stop_time=STOP, output=["corner1.displacement"])
    assert (fmi2["corner1.displacement"] == r["corner1.displacement"]).all()


def test_on_the_default_mesh_it_is_simulate_fmu(fmu3_path):
    damped = {"damping.stiffness_proportional": 5.913e-5, "base.amplitude": 0.009}
    r = simulate(fmu3_path, damped, stop_time=0.01, output=["plate.displacement"])
    plain = simulate_fmu(
        fmu3_path, start_values=damped, stop_time=0.01, output=["plate.displacement"]
    )
    assert r["plate.displacement"].shape == (11, 8, 11)
    assert (r["plate.displacement"] == plain["plate.displacement"]).all()


def test_sizes_given_by_hand_must_follow_the_mesh(fmu3_path):
    md = read_model_description(fmu3_path)
    assert field_sizes(md, {}) == (8, 11)
    assert field_sizes(md, dict(SCENE, **{"mesh.vertex_rows": 11})) == (11, 15)
    with pytest.raises(ValueError, match="mesh.vertex_columns = 14, but the mesh .* has 15"):
        field_sizes(md, dict(SCENE, **{"mesh.vertex_columns": 14}))
