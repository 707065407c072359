"""The FMI 3.0 FMU through fmpy: its package and description, the same numbers as the FMI 2.0
FMU bit for bit (shipped scenes and the input path), early return at impacts, the displacement
field as an array, Configuration Mode, errors that end in Terminated, the FMU state, and the
refusal of the interface types it does not offer."""

import math
import zipfile

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.fmi3 import fmi3FMUState
from fmpy.validation import validate_fmu

import fmu_state
from conftest import SCENES, scene_start_values

SCENE_NAMES = sorted(p.stem for p in SCENES.glob("*.json"))
STEP = 1e-3
FORCED = {"base.amplitude": 0.009, "base.frequency": 35.0}


def test_package_and_description(fmu3_path, model_description3):
    names = set(zipfile.ZipFile(fmu3_path).namelist())
    # The release FMU carries more platforms (tests/fmu/test_platforms.py checks them).
    assert {"modelDescription.xml", "binaries/x86_64-linux/PlateImpact.so"} <= names
    assert validate_fmu(fmu3_path) == []
    md = model_description3
    cs = md.coSimulation
    assert md.fmiVersion == "3.0" and cs.modelIdentifier == "PlateImpact"
    assert cs.mightReturnEarlyFromDoStep and not cs.hasEventMode
    assert (
        cs.canHandleVariableCommunicationStepSize
        and cs.canGetAndSetFMUstate
        and cs.canSerializeFMUstate
    )
    # The internal step is the parameter solver.time_step: no constant may claim otherwise.
    assert cs.fixedInternalStepSize is None and int(cs.maxOutputDerivativeOrder) == 1
    field = next(v for v in md.modelVariables if v.name == "plate.displacement")
    assert field.shape == (8, 11) and field.causality == "output"


def test_both_fmus_declare_the_same_variables(model_description, model_description3):
    """What build.rs checks, seen through fmpy's reading of the packaged descriptions."""
    types = {"Real": "Float64", "Integer": "Int32", "Boolean": "Boolean", "String": "String"}
    three = {v.name: v for v in model_description3.modelVariables}
    for v in model_description.modelVariables:
        w = three[v.name]
        assert (w.valueReference, w.type, w.causality, w.variability) == (
            v.valueReference,
            types[v.type],
            v.causality,
            v.variability,
        ), v.name
        assert (w.start, w.min, w.max, w.unit) == (v.start, v.min, v.max, v.unit), v.name
    assert model_description.coSimulation.maxOutputDerivativeOrder == 1


def run(path, scene_values, stop, **options):
    outputs = [v.name for v in REFERENCE_OUTPUTS]
    return simulate_fmu(
        path,
        stop_time=stop,
        output_interval=STEP,
        start_values=scene_values,
        output=outputs,
        **options,
    )


class _Output:
    def __init__(self, name):
        self.name = name


# Every scalar output of both FMUs.
REFERENCE_OUTPUTS = [
    _Output(n)
    for n in [
        "corner1.displacement",
        "corner2.displacement",
        "edge_mid.displacement",
        "energy.kinetic",
        "energy.elastic",
        "energy.total",
        "contact.active_nodes",
        "contact.force",
        "base.force",
        "energy.base_work",
        "energy.load_work",
        "energy.contact_loss",
        "energy.damping_loss",
        "contact.impacts",
        "contact.impulse",
        "contact.peak_force",
        "base.mean_force",
    ]
]


@pytest.mark.parametrize("scene", SCENE_NAMES)
def test_fmi3_reproduces_fmi2_bit_for_bit(fmu_path, fmu3_path, scene):
    """Early return off: every output at every communication point of every shipped scene."""
    values, stop = scene_start_values(scene)
    two, three = run(fmu_path, values, stop), run(fmu3_path, values, stop)
    assert len(two) == len(three) == round(stop / STEP) + 1
    for output in REFERENCE_OUTPUTS:
        assert two[output.name].tobytes() == three[output.name].tobytes(), f"{scene}: {output.name}"


def test_both_default_experiments_give_the_same_rows(fmu_path, fmu3_path):
    """What a user gets from `simulate_fmu(fmu)` alone: the default experiment (0 to 1 s, 1 ms) in
    both versions, on the same 1 001 points with the same numbers. fmpy takes the output interval
    from fixedInternalStepSize where an FMI 3.0 FMU declares one, so the FMU must not (the
    internal step is the parameter solver.time_step): with 1e-4 declared it recorded 626 points."""
    two, three = simulate_fmu(fmu_path), simulate_fmu(fmu3_path)
    assert len(two) == len(three) == 1001
    assert two["time"].tobytes() == three["time"].tobytes()
    scalars = [n for n in two.dtype.names if n != "time"]
    outputs = [
        v.name for v in read_model_description(fmu_path).modelVariables if v.causality == "output"
    ]
    assert set(scalars) <= set(three.dtype.names) and sorted(scalars) == sorted(outputs)
    for name in scalars:
        assert two[name].tobytes() == three[name].tobytes(), name


def test_the_input_path_is_the_same(fmu_path, fmu3_path):
    """A sampled base.displacement, interpolated within each step by the same rule (FMI 3.0 has no
    fmi2SetRealInputDerivatives: the slope is the backward difference of the samples in both)."""
    t = np.arange(0.0, 0.3 + STEP / 2, STEP)
    signal = np.array(
        list(zip(t, 0.003 * np.sin(2 * math.pi * 23.0 * t) * (1 + 3 * t))),
        dtype=[("time", np.float64), ("base.displacement", np.float64)],
    )
    two = run(fmu_path, {}, 0.3, input=signal)
    three = run(fmu3_path, {}, 0.3, input=signal)
    for output in REFERENCE_OUTPUTS:
        assert two[output.name].tobytes() == three[output.name].tobytes(), output.name
    assert np.max(np.abs(two["corner1.displacement"])) > 1e-3, "the input moved the plate"


def impact_times(fmu_path, stop):
    """The grid times of the impacts of forced-35hz: an FMI 2.0 run at every internal step."""
    values, _ = scene_start_values("forced-35hz")
    fine = simulate_fmu(
        fmu_path,
        stop_time=stop,
        output_interval=1e-4,
        start_values=values,
        output=["contact.impacts"],
    )
    return fine["time"][fine["contact.impacts"] > 0]


def test_early_return_gives_a_point_at_every_impact(fmu_path, fmu3_path):
    """fmpy with early_return_allowed=True: a communication point within one internal step after
    every impact (at its grid time), the same trajectory at the regular points, and the same
    impacts and impulse in total (reported with the early step instead of the regular one)."""
    values, _ = scene_start_values("forced-35hz")
    stop = 0.5
    impacts = impact_times(fmu_path, stop)
    assert len(impacts) > 20
    plain = run(fmu3_path, values, stop)
    early = run(fmu3_path, values, stop, early_return_allowed=True)
    times = early["time"]
    # Grid times from fmpy's sums and ours agree to round-off: 1e-12 s of 1e-4 s steps.
    missed = [t for t in impacts if np.min(np.abs(times - t)) > 1e-12]
    assert not missed, f"no communication point at the impacts {missed}"
    on_regular = np.abs(impacts / STEP - np.round(impacts / STEP)) < 1e-6
    assert len(early) == len(plain) + np.count_nonzero(~on_regular), "one extra point per impact"
    assert np.count_nonzero(~on_regular) > 20
    regular = np.isin(np.round(times / STEP, 6), np.round(plain["time"] / STEP, 6))
    assert regular.sum() == len(plain)
    for name in [
        "corner1.displacement",
        "edge_mid.displacement",
        "energy.total",
        "base.force",
        "contact.active_nodes",
        "contact.force",
        "energy.contact_loss",
    ]:
        assert early[name][regular].tobytes() == plain[name].tobytes(), name
    assert early["contact.impacts"].sum() == plain["contact.impacts"].sum() == len(impacts)
    # The same terms of Σ F Δt summed in other groups: round-off of the sum only.
    total = plain["contact.impulse"].sum()
    assert (
        abs(early["contact.impulse"].sum() - total)
        <= 1e-12 * np.abs(plain["contact.impulse"]).sum()
    )


def test_step_by_step_early_return(new_plate3, fmu_path):
    """FMU3Slave: fmi3DoStep reports earlyReturn with lastSuccessfulTime at the impact's grid time,
    and continues from there; with early return not allowed at instantiation it never returns
    early."""
    values, _ = scene_start_values("forced-35hz")
    impacts = list(impact_times(fmu_path, 0.1))
    for allowed in (True, False):
        plate = new_plate3(f"early-{allowed}", early_return=allowed).initialize(values)
        seen = []
        while plate.time < 0.1 - 1e-12:
            target = min(plate.time + 7e-3, 0.1)
            early, reached = plate.step(target - plate.time)
            if early:
                assert reached < target
                seen.append(reached)
            else:
                assert reached == pytest.approx(target, abs=1e-12)
        if allowed:
            assert seen == pytest.approx(impacts, abs=1e-12)
        else:
            assert seen == []


CONTACT_FREE = {
    "base.amplitude": 0.002,
    "base.frequency": 35.0,
    "obstacle.lower_enabled": False,
    "obstacle.upper_enabled": False,
}
DISPLACEMENTS = ["corner1.displacement", "corner2.displacement", "edge_mid.displacement"]


def test_output_derivatives_are_the_same_in_both_versions(new_plate, new_plate3):
    """d/dt of the displacement outputs through fmi2GetRealOutputDerivatives and
    fmi3GetOutputDerivatives: the same bits at every point, 1 ms steps (on the grid) and 1.5 ms
    steps (every other point between grid points)."""
    for h in (1e-3, 1.5e-3):
        two = new_plate(f"d2-{h}").initialize(CONTACT_FREE)
        three = new_plate3(f"d3-{h}").initialize(CONTACT_FREE)
        vrs2 = [two.vr(n) for n in DISPLACEMENTS]
        vrs3 = [three.vr(n) for n in DISPLACEMENTS]
        for _ in range(60):
            two.step(h)
            three.step(h)
            r2 = two.fmu.getRealOutputDerivatives(vrs2, [1, 1, 1])
            r3 = three.fmu.getOutputDerivatives(vrs3, [1, 1, 1])
            assert np.array(r2).tobytes() == np.array(r3).tobytes()
            assert np.max(np.abs(r3)) > 0 or three.time < 2e-3


def rates(new_plate3, values, stop, h):
    """corner1's time and rate at every h up to `stop`."""
    plate = new_plate3(f"rates-{values['solver.time_step']}").initialize(values)
    vr = plate.vr("corner1.displacement")
    times, out = [], []
    for k in range(1, round(stop / h) + 1):
        plate.step(k * h - plate.time)
        times.append(plate.time)
        out.append(plate.fmu.getOutputDerivatives([vr], [1])[0])
    return np.array(times), np.array(out)


def test_output_derivatives_converge_to_the_velocity(new_plate3):
    """The rate at a grid point is the slope over the last internal step, a first-order estimate
    of the velocity. Against an analytic velocity: a nearly rigid plate (E = 1e13 Pa, 0.1 m thick,
    first mode near 3.7 kHz, its start-up ringing damped by stiffness-proportional damping, which
    leaves the rigid motion alone) follows its base z = c sin(ωt), so its corner moves with
    z'(t) = cω cos(ωt). The rate errs by Δt/2·|z''| (the left slope of a sine) plus the plate's
    own flexible velocity, measured below 1.5e-6 m/s, and the error halves with Δt."""
    c, f = 0.002, 10.0
    w = 2 * math.pi * f
    rigid = {
        "base.amplitude": c,
        "base.frequency": f,
        "obstacle.lower_enabled": False,
        "obstacle.upper_enabled": False,
        "material.young_modulus": 1e13,
        "plate.thickness": 0.1,
        "damping.stiffness_proportional": 1e-4,
    }
    errors = {}
    for dt in (1e-4, 5e-5):
        times, measured = rates(new_plate3, dict(rigid, **{"solver.time_step": dt}), 0.1, 1e-3)
        late = times >= 5e-3  # after the damped start-up ringing
        errors[dt] = np.max(np.abs(measured - c * w * np.cos(w * times))[late])
        assert errors[dt] <= 0.5 * dt * w * w * c + 2e-6, (dt, errors[dt])
        left_slope = (c * np.sin(w * times) - c * np.sin(w * (times - dt))) / dt
        assert np.max(np.abs(measured - left_slope)[late]) < 2e-6
    ratio = errors[1e-4] / errors[5e-5]
    assert 1.9 < ratio < 2.1, f"error ratio {ratio}: not first order"


def test_fmpy_records_the_field(fmu3_path):
    """plate.displacement as fmpy records it: 8 × 11 vertex values per point, row-major with rows
    along y; its free corners are the corner outputs, its clamp column the base sine, every
    vertex within the obstacles."""
    stop = 0.2
    result = simulate_fmu(
        fmu3_path,
        stop_time=stop,
        output_interval=STEP,
        start_values=FORCED,
        output=["plate.displacement", "corner1.displacement", "corner2.displacement"],
    )
    field = result["plate.displacement"]
    assert field.shape == (round(stop / STEP) + 1, 8, 11)
    # Two functionals of the same field (vertex value, point evaluation): round-off of 9 mm.
    np.testing.assert_allclose(field[:, 0, 10], result["corner1.displacement"], rtol=0, atol=1e-15)
    np.testing.assert_allclose(field[:, 7, 10], result["corner2.displacement"], rtol=0, atol=1e-15)
    base = 0.009 * np.sin(2 * math.pi * 35.0 * result["time"])
    # The clamp carries the built-in sine, evaluated at the grid times the FMU computes: 1e-15 m.
    np.testing.assert_allclose(field[:, :, 0], base[:, None] * np.ones((1, 8)), rtol=0, atol=1e-15)
    # Vertices within the obstacles: the contact solve is exact to round-off (1e-9 of the gap).
    assert np.all(np.abs(field) <= 0.01 + 2e-11)
    assert np.max(np.abs(field[:, :, 10])) > 0.009, "the free edge reaches the obstacles"


def test_configuration_mode_resizes_the_field(new_plate3):
    """Another mesh: the field is refused (naming the structural parameters) until they are set
    in Configuration Mode; then it has the mesh's shape."""
    mesh = {"mesh.element": 2, "mesh.nx": 14, "mesh.ny": 10}
    plate = new_plate3("unsized").initialize(mesh)
    with pytest.raises(FMICallException):
        plate.get("plate.displacement")
    assert any("mesh.vertex_rows = 8" in m and "[11, 15]" in m for m in plate.errors()), (
        plate.messages
    )
    plate = new_plate3("sized")
    plate.fmu.enterConfigurationMode()
    plate.fmu.setUInt64([plate.vr("mesh.vertex_rows"), plate.vr("mesh.vertex_columns")], [11, 15])
    plate.fmu.exitConfigurationMode()
    plate.initialize(dict(mesh, **FORCED))
    plate.step(5e-3)
    field = np.array(plate.get("plate.displacement")).reshape(11, 15)
    assert field[0, 14] == pytest.approx(plate.get("corner1.displacement"), abs=1e-15)


def test_an_error_ends_in_terminated_and_reset_continues(new_plate3):
    plate = new_plate3("errors").initialize(FORCED)
    plate.step(1e-3)
    with pytest.raises(FMICallException) as e:
        plate.set("obstacle.lower", 0.5)
    assert e.value.status == 3
    assert any("obstacle.lower" in m for m in plate.errors()), plate.messages
    with pytest.raises(FMICallException):
        plate.step(1e-3)
    assert any("not allowed in the Terminated state" in m for m in plate.errors())
    plate.fmu.reset()
    plate.initialize()
    plate.step(1e-3)


def deserialized(plate, data):
    """A new FMU state in `plate` from serialized bytes."""
    state = fmi3FMUState()
    plate.fmu.deserializeFMUState(data, state)
    return state


def test_fmu_state_round_trips(new_plate3):
    """Get/set and serialize into a fresh instance: the run continues bit for bit; the bytes have
    the FMI 2.0 layout with the sizes of the structural parameters; corrupt bytes are refused."""

    def run(plate, steps):
        out = []
        for k in range(steps):
            plate.set("base.displacement", 5e-4 * math.sin(0.37 * k))
            plate.step(1.5e-3)
            out.append(plate.get("corner1.displacement"))
        return np.array(out)

    a = new_plate3("a", early_return=True).initialize(FORCED)
    run(a, 40)
    t0 = a.time
    state = a.fmu.getFMUState()
    data = a.fmu.serializeFMUState(state)
    payload, _ = fmu_state.decode(data)
    assert payload["mode"] == "StepMode" and payload["sizes"] == [8, 11]
    expected = run(a, 60)
    a.fmu.setFMUState(state)
    a.time = t0
    assert run(a, 60).tobytes() == expected.tobytes()
    b = new_plate3("b", early_return=True)
    b.fmu.setFMUState(deserialized(b, data))
    b.time = t0
    assert run(b, 60).tobytes() == expected.tobytes()
    with pytest.raises(FMICallException):
        deserialized(b, data[:-1])
    assert any("serialized FMU state" in m for m in b.errors())


def test_the_interface_types_not_offered_are_refused_with_a_message(fmu3_path, tmp_path):
    """fmi3InstantiateModelExchange and fmi3InstantiateScheduledExecution return no instance and
    tell the host's logger (status fmi3Error) that the FMU is Co-Simulation only; without a logger
    they return none all the same. Straight through ctypes: fmpy instantiates only what the model
    description offers."""
    import ctypes

    with zipfile.ZipFile(fmu3_path) as z:
        z.extract("binaries/x86_64-linux/PlateImpact.so", tmp_path)
    lib = ctypes.CDLL(str(tmp_path / "binaries" / "x86_64-linux" / "PlateImpact.so"))
    logger_type = ctypes.CFUNCTYPE(
        None, ctypes.c_void_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_char_p
    )
    logged = []
    logger = logger_type(
        lambda _env, status, category, message: logged.append(
            (status, category.decode(), message.decode())
        )
    )
    for name, callbacks in [
        ("fmi3InstantiateModelExchange", []),
        ("fmi3InstantiateScheduledExecution", [None, None, None]),
    ]:
        function = getattr(lib, name)
        function.restype = ctypes.c_void_p
        logged.clear()
        assert function(b"refused", b"token", None, False, False, None, logger, *callbacks) is None
        assert logged == [
            (
                3,
                "logStatusError",
                f"{name}: this FMU supports Co-Simulation only (fmi3InstantiateCoSimulation)",
            )
        ]
        assert function(b"refused", b"token", None, False, False, None, None, *callbacks) is None
