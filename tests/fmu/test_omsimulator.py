"""Both FMUs in OMSimulator, the OpenModelica co-simulation environment, when the environment
variable OMSIMULATOR names its binary (skipped, saying why, otherwise; docs/fmu.md "Engines tried"
says how to build it): the default experiments, the paper's shipped parameter sets through an
SSP, the general model's sets, which OMSimulator cannot import, and the plate on the shaker as an
SSP with a feedback loop.

OMSimulator prints its results with 12 significant digits: fmpy's numbers printed alike must be the
same numbers, and a run of a shipped scene must also meet the FMU's packaged reference result
under its stated tolerances. The FMI 3.0 FMU runs through an SSP whose result filter records its
scalar variables, since OMSimulator reads the array `plate.displacement` as a scalar."""

import io
import xml.etree.ElementTree as ET
import zipfile

import numpy as np
import pytest
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi2 import FMU2Slave

import omsimulator as oms
from schemas import errors
from test_packaged_references import LS_REF, experiments, horizon, parameter_set
from test_reference import assert_matches

# The component's name. Not "plate": OMSimulator then reads the parameter plate.width of an SSV as
# the variable width of the component plate, and fails to set it.
PLATE = "PlateImpact"
SCENE_NAMES = ["energy", "forced", "forced-30hz", "forced-35hz", "forced-35hz-damped"]
# The shipped sets of the general model: they set String parameters away from their defaults.
GENERAL_SCENE_NAMES = ["stud-corner", "clamped-panel", "inclined-support"]
SSV = "http://ssp-standard.org/SSP1/SystemStructureParameterValues"
# OMSimulator 3.0 imports an SSV's Real, Integer and Boolean values and logs this for any other.
NO_STRINGS = "Unknown ParameterBinding-type"
# The coupled run: the example's plate damping, 0.3 s at 1 ms (about 30 impacts).
COUPLED_PLATE = {
    "damping.mass_proportional": 2 * 0.01 * 2 * np.pi * 53.8,
    "damping.stiffness_proportional": 2 * 0.05 / (2 * np.pi * 335.0),
}
COUPLED_STOP, COUPLED_STEP = 0.3, 1e-3
LOOP_MESSAGE = "Alg. loop"


@pytest.fixture(autouse=True)
def omsimulator():
    """Skips every test here, before it does any work, when OMSIMULATOR names no binary."""
    return oms.binary()


@pytest.fixture(params=[2, 3], ids=["fmi2", "fmi3"])
def fmu(request, fmu_path, fmu3_path):
    return fmu_path if request.param == 2 else fmu3_path


def scalar_outputs(fmu):
    return [
        v.name
        for v in read_model_description(fmu).modelVariables
        if v.causality == "output" and not v.dimensions
    ]


def checked(description):
    """The SSD, after the SSP 1.0 schema found nothing wrong with it."""
    assert errors("ssd", description.encode()) == [], description
    return description


def assert_printed_alike(result, component, expected, names):
    """Every column `names` of OMSimulator's `result` is fmpy's `expected` printed with %.12g."""
    for name in names:
        column = result[oms.signal(component, name)] if component else result[name]
        assert len(column) == len(expected[name]), name
        np.testing.assert_array_equal(column, oms.printed(expected[name]), err_msg=name)


def test_the_fmi2_default_experiment_runs_as_fmpy_runs_it(fmu_path, tmp_path):
    result, log = oms.run(fmu_path, tmp_path, 1.0, 1e-3)
    expected = simulate_fmu(fmu_path)
    assert len(result["time"]) == 1001 and result["time"][-1] == 1.0
    assert_printed_alike(result, None, expected, scalar_outputs(fmu_path))
    assert "impact statistics may not converge" in log


def test_the_fmi3_fmu_alone_trips_on_its_array(fmu3_path, tmp_path):
    """The importer's limit the SSP below works around: it asks for `plate.displacement` with room
    for one value, and the FMU refuses (it never writes past what it is given)."""
    (tmp_path / "run").mkdir()
    with pytest.raises(AssertionError, match="nValues = 1 is too few"):
        oms.run(fmu3_path, tmp_path / "run", 1.0, 1e-3)


def test_the_fmi3_default_experiment_runs_through_an_ssp_recording_the_scalars(fmu3_path, tmp_path):
    outputs = scalar_outputs(fmu3_path)
    md = read_model_description(fmu3_path)
    stop, step = float(md.defaultExperiment.stopTime), float(md.defaultExperiment.stepSize)
    description = checked(
        oms.ssd(
            [(PLATE, "PlateImpact.fmu", None)],
            [],
            stop,
            step,
            recorded=[(PLATE, n) for n in outputs],
        )
    )
    ssp = oms.write_ssp(
        tmp_path / "default.ssp",
        description,
        {
            "PlateImpact.fmu": fmu3_path,
            "signalFilter.xml": oms.signal_filter([(PLATE, n) for n in outputs]).encode(),
        },
    )
    result, _ = oms.run(ssp, tmp_path, stop, step)
    assert len(result["time"]) == 1001 and result["time"][-1] == 1.0
    assert_printed_alike(result, PLATE, simulate_fmu(fmu3_path), outputs)


def without_default_strings(ssv, fmu):
    """The SSV `ssv` (bytes) without its String parameters, each of which must hold the FMU's
    start value: OMSimulator 3.0 cannot import them (NO_STRINGS), and leaving them out sets the
    same values."""
    ET.register_namespace("ssv", SSV)
    root = ET.fromstring(ssv)
    starts = {v.name: v.start for v in read_model_description(fmu).modelVariables}
    parameters = root.find(f"{{{SSV}}}Parameters")
    for parameter in list(parameters):
        string = parameter.find(f"{{{SSV}}}String")
        if string is not None:
            name = parameter.get("name")
            assert string.get("value") == starts[name], (name, string.get("value"), starts[name])
            parameters.remove(parameter)
    stripped = ET.tostring(root, encoding="utf-8", xml_declaration=True)
    assert errors("ssv", stripped) == []
    return stripped


def shipped_set_ssp(fmu, scene, tmp_path, ssv_of=lambda ssv: ssv):
    """An SSP of the experiment of the FMU's own experiments file for `scene`: its SSV, through
    `ssv_of`, bound to the component without a prefix, as FMI-LS-REF applies it. (path, start,
    stop, step, SSV file name, reference CSV bytes)."""
    experiment = experiments(fmu)[scene]
    start, stop, step = horizon(experiment)
    source = experiment.find("Parameters").get("source")
    outputs = scalar_outputs(fmu)
    description = checked(
        oms.ssd(
            [(PLATE, "PlateImpact.fmu", source)],
            [],
            stop,
            step,
            recorded=[(PLATE, n) for n in outputs],
        )
    )
    with zipfile.ZipFile(fmu) as z:
        ssv = ssv_of(z.read(f"{LS_REF}/{source}"))
        reference_csv = z.read(f"{LS_REF}/{experiment.find('References').get('source')}")
    ssp = oms.write_ssp(
        tmp_path / f"{scene}.ssp",
        description,
        {
            "PlateImpact.fmu": fmu,
            source: ssv,
            "signalFilter.xml": oms.signal_filter([(PLATE, n) for n in outputs]).encode(),
        },
    )
    return ssp, start, stop, step, source, reference_csv


@pytest.mark.parametrize("scene", SCENE_NAMES)
def test_each_shipped_parameter_set_runs_through_an_ssp(fmu, scene, tmp_path):
    """The experiment of the FMU's own experiments file, its String parameters (the defaults)
    left out: the result meets the packaged reference and is fmpy's."""
    ssp, start, stop, step, source, reference_csv = shipped_set_ssp(
        fmu, scene, tmp_path, lambda ssv: without_default_strings(ssv, fmu)
    )
    outputs = scalar_outputs(fmu)
    result, _ = oms.run(ssp, tmp_path, stop, step)
    reference = np.genfromtxt(io.BytesIO(reference_csv), delimiter=",", names=True, deletechars="")
    named = np.zeros(len(result["time"]), dtype=reference.dtype)
    named["time"] = result["time"]
    for name in reference.dtype.names[1:]:
        named[name] = result[oms.signal(PLATE, name)]
    assert_matches(named, reference, scene)
    expected = simulate_fmu(
        fmu,
        start_time=start,
        stop_time=stop,
        output_interval=step,
        start_values=parameter_set(fmu, source),
        output=outputs,
    )
    assert_printed_alike(result, PLATE, expected, outputs)


@pytest.mark.parametrize("scene", GENERAL_SCENE_NAMES)
def test_the_general_model_sets_need_strings_that_omsimulator_cannot_import(
    fmu_path, scene, tmp_path
):
    """The limit docs/fmu.md states: the shipped sets of the general model give `plate.clamp` or
    an obstacle's profile as ssv:String, which OMSimulator 3.0 refuses to import, so it cannot
    run those scenes from an SSV (fmpy and the C API can)."""
    ssp, _, stop, step, _, _ = shipped_set_ssp(fmu_path, scene, tmp_path)
    with pytest.raises(AssertionError, match=NO_STRINGS):
        oms.run(ssp, tmp_path, stop, step)


def coupled_ssp(plate_fmu, shaker, tmp_path, name):
    """The plate on the shaker: shaker.position drives base.displacement, base.mean_force pushes
    back on the shaker; the plate damped as in examples/shaker_coupling.py."""
    recorded = [(PLATE, n) for n in scalar_outputs(plate_fmu)] + [("shaker", "position")]
    ssv = (
        '<?xml version="1.0" encoding="UTF-8"?>\n<ssv:ParameterSet '
        'xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="1.0" '
        'name="damping">\n  <ssv:Parameters>\n'
        + "".join(
            f'    <ssv:Parameter name="{n}"><ssv:Real value="{v!r}"/></ssv:Parameter>\n'
            for n, v in COUPLED_PLATE.items()
        )
        + "  </ssv:Parameters>\n</ssv:ParameterSet>\n"
    )
    assert errors("ssv", ssv.encode()) == []
    description = checked(
        oms.ssd(
            [(PLATE, "PlateImpact.fmu", "damping.ssv"), ("shaker", "Shaker.fmu", None)],
            [
                ("shaker", "position", PLATE, "base.displacement"),
                (PLATE, "base.mean_force", "shaker", "force"),
            ],
            COUPLED_STOP,
            COUPLED_STEP,
            recorded=recorded,
        )
    )
    return oms.write_ssp(
        tmp_path / name,
        description,
        {
            "PlateImpact.fmu": plate_fmu,
            "Shaker.fmu": shaker,
            "damping.ssv": ssv.encode(),
            "signalFilter.xml": oms.signal_filter(recorded).encode(),
        },
    )


def jacobi(plate_fmu, shaker_fmu, tmp_path):
    """The coupled run of OMSimulator's fixed-step master, through fmpy: both FMUs step from t_k
    on the inputs set from each other's outputs at t_k. {name: array} of the plate's scalar
    outputs and the shaker's position."""
    slaves = {}
    for key, path in (("plate", plate_fmu), ("shaker", shaker_fmu)):
        md = read_model_description(str(path))
        slave = FMU2Slave(
            guid=md.guid,
            unzipDirectory=extract(str(path), str(tmp_path / key)),
            modelIdentifier=md.coSimulation.modelIdentifier,
            instanceName=key,
        )
        slaves[key] = (slave, {v.name: v.valueReference for v in md.modelVariables})
    (plate, p), (shaker, s) = slaves["plate"], slaves["shaker"]
    outputs = scalar_outputs(plate_fmu)
    for slave in (plate, shaker):
        slave.instantiate()
        slave.setupExperiment(startTime=0.0, stopTime=COUPLED_STOP)
    plate.setReal([p[n] for n in COUPLED_PLATE], list(COUPLED_PLATE.values()))
    for slave in (plate, shaker):
        slave.enterInitializationMode()
        slave.exitInitializationMode()
    steps = round(COUPLED_STOP / COUPLED_STEP)
    out = {n: np.empty(steps + 1) for n in outputs + ["position"]}

    kinds = {v.name: v.type for v in read_model_description(str(plate_fmu)).modelVariables}
    reals = [n for n in outputs if kinds[n] == "Real"]
    integers = [n for n in outputs if kinds[n] == "Integer"]

    def exchange(k):
        values = dict(zip(reals, plate.getReal([p[n] for n in reals])))
        values |= dict(zip(integers, plate.getInteger([p[n] for n in integers])))
        values["position"] = shaker.getReal([s["position"]])[0]
        for name in out:
            out[name][k] = values[name]
        plate.setReal([p["base.displacement"]], [values["position"]])
        shaker.setReal([s["force"]], [values["base.mean_force"]])

    exchange(0)
    time = 0.0
    for k in range(steps):
        # The master's clock as OMSimulator keeps it: the next point is the last plus the step,
        # and a component steps by their difference (k h would differ in the last bits, and so
        # would the plate's backward difference of its input over the step).
        following = time + COUPLED_STEP
        for slave in (plate, shaker):
            slave.doStep(currentCommunicationPoint=time, communicationStepSize=following - time)
        time = following
        exchange(k + 1)
    for slave in (plate, shaker):
        slave.terminate()
        slave.freeInstance()
    return out


def test_the_plate_on_the_shaker_runs_without_an_algebraic_loop(fmu_path, tmp_path):
    """The feedback of examples/shaker_coupling.py in OMSimulator: the shaker's position drives
    the plate's base, the plate's mean force drives the shaker, and the shaker's output declares
    no dependencies (as if it fed its input through). The plate's outputs declare none either, so
    the loop has its delay in the plate and OMSimulator finds no algebraic loop; the run is the
    fixed-step master's exchange at every communication point, which fmpy repeats, and the plate
    strikes the obstacles."""
    shaker = oms.shaker_fmu(tmp_path)
    result, log = oms.run(
        coupled_ssp(fmu_path, shaker, tmp_path, "coupled.ssp"), tmp_path, COUPLED_STOP, COUPLED_STEP
    )
    assert LOOP_MESSAGE not in log, log
    expected = jacobi(fmu_path, shaker, tmp_path)
    assert len(result["time"]) == round(COUPLED_STOP / COUPLED_STEP) + 1
    assert_printed_alike(result, PLATE, expected, scalar_outputs(fmu_path))
    np.testing.assert_array_equal(
        result[oms.signal("shaker", "position")], oms.printed(expected["position"])
    )
    # The shaker moves the base by millimetres and the plate strikes its obstacles.
    assert np.max(np.abs(expected["position"])) > 1e-3
    assert np.sum(expected["contact.impacts"]) >= 10


def test_without_declared_dependencies_the_feedback_is_an_algebraic_loop(fmu_path, tmp_path):
    """The same system with the plate's description as it was, without dependencies: every output
    then depends on `base.displacement`, and OMSimulator reports the loop."""
    shaker = oms.shaker_fmu(tmp_path)
    plate = oms.without_dependencies(fmu_path, tmp_path / "PlateImpact-undeclared.fmu")
    _, log = oms.run(coupled_ssp(plate, shaker, tmp_path, "loop.ssp"), tmp_path, 0.01, COUPLED_STEP)
    assert LOOP_MESSAGE in log, log
