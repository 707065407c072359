"""What a user checks the FMU with, inside the FMU (docs/fmu.md, "What the FMU carries"): each
packaged FMU (FMI 2.0 and 3.0) runs every experiment of its FMI-LS-REF folder, with the parameters
of the experiment's SSV parameter set, and meets the experiment's reference result under the
tolerances its documentation states (those of test_reference.py); each parameter set is the scene
file it stands for; the documentation page lists every variable."""

import io
import xml.etree.ElementTree as ET
import zipfile

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu

from conftest import SCENES, scene_start_values
from test_reference import assert_matches

LS_REF = "extra/org.fmi-standard.fmi-ls-ref"
SSV = "{http://ssp-standard.org/SSP1/SystemStructureParameterValues}"
MANIFEST_NS = "http://fmi-standard.org/fmi-ls-manifest"
SCENE_NAMES = sorted(p.stem for p in SCENES.glob("*.json"))
KINDS = {"Real": float, "Integer": int, "Boolean": lambda text: text == "true"}


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


def experiments(fmu):
    root = ET.fromstring(read(fmu, f"{LS_REF}/experiments.xml"))
    return {e.get("name"): e for e in root.iter("Experiment")}


def test_the_manifest_names_the_layered_standard_and_every_file(fmu):
    root = ET.fromstring(read(fmu, f"{LS_REF}/fmi-ls-manifest.xml"))
    assert root.tag == "fmiReferences"
    assert root.get(f"{{{MANIFEST_NS}}}fmi-ls-name") == "org.fmi-standard.fmi-ls-ref"
    related = {r.get("source"): r.get("role") for r in root.iter("Related")}
    with zipfile.ZipFile(fmu) as z:
        names = set(z.namelist())
    for source in related:
        path = "documentation/index.html" if source.startswith("../../") else f"{LS_REF}/{source}"
        assert path in names, source
    expected = {
        "experiments.xml": "experiment/validation",
        "../../documentation/index.html": "document",
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
        assert float(experiment.get("stopTime")) == stop
        for name, variable in parameters.items():
            # The scene's value where its file gives one, else the FMU's start value.
            expected = scene_values.get(name, variable.start)
            if variable.type == "Boolean":
                expected = expected in (True, "true")
            elif variable.type == "Integer":
                expected = int(expected)
            else:
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
    assert len(outputs) == 17
    result = simulate_fmu(
        fmu,
        start_time=float(experiment.get("startTime")),
        stop_time=float(experiment.get("stopTime")),
        output_interval=float(experiment.get("stepSize")),
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
