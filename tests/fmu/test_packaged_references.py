"""What a user checks the FMU with, inside the FMU (docs/fmu.md, "What the FMU carries"): each
packaged FMU (FMI 2.0 and 3.0) runs every experiment of the experiments file its FMI-LS-REF
manifest names, with the parameters of the experiment's SSV parameter set, and meets the
experiment's reference result under the tolerances its documentation states (those of
test_reference.py); each parameter set is the scene file it stands for; the documentation page
lists every variable. test_schemas.py validates the same files against the published schemas."""

import io
import xml.etree.ElementTree as ET
import zipfile

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu

import reference.regenerate as regenerate
from conftest import SCENES, scene_start_values
from test_reference import assert_matches

LS_REF = "extra/org.fmi-standard.fmi-ls-ref"
SSV = "{http://ssp-standard.org/SSP1/SystemStructureParameterValues}"
MANIFEST_NS = "http://fmi-standard.org/fmi-ls-manifest"
SCENE_NAMES = sorted(p.stem for p in SCENES.glob("*.json"))
KINDS = {"Real": float, "Integer": int, "Boolean": lambda text: text == "true", "String": str}


@pytest.fixture(params=[2, 3], ids=["fmi2", "fmi3"])
def fmu(request, fmu_path, fmu3_path):
    return fmu_path if request.param == 2 else fmu3_path


def read(fmu, name):
    with zipfile.ZipFile(fmu) as z:
        return z.read(name)


def parameter_set(fmu, source):
    """{name: value} of an SSV file of the FMU's references folder."""
    root = ET.fromstring(read(fmu, f"{LS_REF}/{source}"))
    values = {}
    for parameter in root.iter(f"{SSV}Parameter"):
        (typed,) = list(parameter)
        kind = typed.tag.removeprefix(SSV)
        assert parameter.get("name") not in values
        values[parameter.get("name")] = KINDS[kind](typed.get("value"))
    return values


def experiments_file(fmu):
    """The experiments file the manifest names, as an importer finds it."""
    root = ET.fromstring(read(fmu, f"{LS_REF}/fmi-ls-manifest.xml"))
    (source,) = [
        r.get("source")
        for r in root.iter("Related")
        if r.get("type") == "application/x-ma-hs-experiments"
    ]
    return source


def experiments(fmu):
    root = ET.fromstring(read(fmu, f"{LS_REF}/{experiments_file(fmu)}"))
    return {e.get("name"): e for e in root.iter("Experiment")}


def horizon(experiment):
    """(start, stop, step) of an experiment's transient simulation."""
    simulation = experiment.find("TransientSimulation")
    return tuple(float(simulation.get(a)) for a in ("startTime", "stopTime", "stepSize"))


def test_the_manifest_names_the_layered_standard_and_every_file(fmu):
    root = ET.fromstring(read(fmu, f"{LS_REF}/fmi-ls-manifest.xml"))
    assert root.tag == "fmiReferences"
    assert root.get(f"{{{MANIFEST_NS}}}fmi-ls-name") == "org.fmi-standard.fmi-ls-ref"
    related = {r.get("source"): r.get("role") for r in root.iter("Related")}
    with zipfile.ZipFile(fmu) as z:
        names = set(z.namelist())
    for source in related:
        path = (
            source.removeprefix("../../") if source.startswith("../../") else f"{LS_REF}/{source}"
        )
        assert path in names, source
    expected = {
        "experiments.exp": "experiment/validation",
        "../../documentation/index.html": "document",
        "../../documentation/fmi-ls-ref.html": "document",
    }
    for scene in SCENE_NAMES:
        expected |= {f"{scene}.ssv": "parameter", f"{scene}.csv": "result"}
    assert related == expected


def test_each_parameter_set_is_its_scene_file(fmu):
    md = read_model_description(fmu)
    parameters = {v.name: v for v in md.modelVariables if v.causality == "parameter"}
    assert set(experiments(fmu)) == set(SCENE_NAMES)
    for scene, experiment in experiments(fmu).items():
        values = parameter_set(fmu, experiment.find("Parameters").get("source"))
        assert set(values) == set(parameters), scene
        scene_values, stop = scene_start_values(scene)
        assert horizon(experiment) == (0.0, stop, 1e-3)
        for name, variable in parameters.items():
            # The scene's value where its file gives one, else the FMU's start value.
            expected = scene_values.get(name, variable.start)
            if variable.type == "Boolean":
                expected = expected in (True, "true")
            elif variable.type == "Integer":
                expected = int(expected)
            elif variable.type != "String":
                expected = float(expected)
            assert values[name] == expected, (scene, name, values[name], expected)


@pytest.mark.parametrize("scene", SCENE_NAMES)
def test_the_fmu_meets_its_packaged_reference(fmu, scene):
    experiment = experiments(fmu)[scene]
    start = parameter_set(fmu, experiment.find("Parameters").get("source"))
    source = experiment.find("References").get("source")
    reference = np.genfromtxt(
        io.BytesIO(read(fmu, f"{LS_REF}/{source}")), delimiter=",", names=True, deletechars=""
    )
    outputs = [n for n in reference.dtype.names if n != "time"]
    assert outputs == regenerate.OUTPUTS
    start_time, stop_time, step = horizon(experiment)
    result = simulate_fmu(
        fmu,
        start_time=start_time,
        stop_time=stop_time,
        output_interval=step,
        start_values=start,
        output=outputs,
    )
    assert_matches(result, reference, scene)


def test_the_documentation_page_lists_every_variable(fmu):
    page = read(fmu, "documentation/index.html").decode()
    md = read_model_description(fmu)
    assert f"<title>PlateImpact {md.version}</title>" in page
    for v in md.modelVariables:
        assert f"<tr><td><code>{v.name}</code></td>" in page, v.name
