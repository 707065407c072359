"""The reference files each packaged FMU carries validate against the published schemas
(tests/fmu/schemas.py): its FMI-LS-REF manifest, every experiments file the manifest names and
every SSV parameter set of its folder. Each schema also refuses what it should (the experiments
format of before, with the settings as attributes of `<Experiment>`; a role the manifest does not
know; an SSV value of the wrong type), so that a pass means the files were checked."""

import xml.etree.ElementTree as ET
import zipfile

import pytest

from conftest import SCENES
from schemas import errors

LS_REF = "extra/org.fmi-standard.fmi-ls-ref"
EXPERIMENTS_TYPE = "application/x-ma-hs-experiments"


@pytest.fixture(params=[2, 3], ids=["fmi2", "fmi3"])
def fmu(request, fmu_path, fmu3_path):
    return fmu_path if request.param == 2 else fmu3_path


def read(fmu, name):
    with zipfile.ZipFile(fmu) as z:
        return z.read(name)


def related(fmu):
    """(type, source) of every file the manifest names."""
    root = ET.fromstring(read(fmu, f"{LS_REF}/fmi-ls-manifest.xml"))
    return [(r.get("type"), r.get("source")) for r in root.iter("Related")]


def test_the_manifest_validates(fmu):
    assert errors("manifest", read(fmu, f"{LS_REF}/fmi-ls-manifest.xml")) == []


def test_every_experiments_file_validates(fmu):
    sources = [source for kind, source in related(fmu) if kind == EXPERIMENTS_TYPE]
    assert sources == ["experiments.exp"]
    for source in sources:
        assert errors("experiments", read(fmu, f"{LS_REF}/{source}")) == [], source


def test_every_parameter_set_validates(fmu):
    with zipfile.ZipFile(fmu) as z:
        sets = [n for n in z.namelist() if n.startswith(LS_REF) and n.endswith(".ssv")]
    assert len(sets) == len(list(SCENES.glob("*.json")))
    named = {source for kind, source in related(fmu) if kind == "application/x-ssp-parameter-set"}
    assert {n.removeprefix(f"{LS_REF}/") for n in sets} == named
    for name in sets:
        assert errors("ssv", read(fmu, name)) == [], name


def test_the_experiments_schema_refuses_the_format_of_before(fmu_path):
    """The settings as attributes of `<Experiment>`, as the experiments file had them before."""
    experiments = read(fmu_path, f"{LS_REF}/experiments.exp").decode()
    before = experiments.replace(
        'description="the scene energy">', 'description="the scene energy" startTime="0">', 1
    )
    assert before != experiments
    assert any("startTime" in e for e in errors("experiments", before.encode()))


def test_the_manifest_schema_refuses_an_unknown_role(fmu_path):
    manifest = read(fmu_path, f"{LS_REF}/fmi-ls-manifest.xml").decode()
    wrong_role = manifest.replace('role="experiment/validation"', 'role="experiment/regression"', 1)
    assert wrong_role != manifest and errors("manifest", wrong_role.encode())


def test_the_parameter_set_schema_refuses_a_value_of_the_wrong_type(fmu_path):
    parameters = read(fmu_path, f"{LS_REF}/forced.ssv").decode()
    wrong_value = parameters.replace('<ssv:Real value="0.4"/>', '<ssv:Real value="forty"/>', 1)
    assert wrong_value != parameters and errors("ssv", wrong_value.encode())
