"""The packaged FMU: layout and fmpy's validation."""

import zipfile

from fmpy.validation import validate_fmu


def test_fmu_layout(fmu_path):
    names = set(zipfile.ZipFile(fmu_path).namelist())
    assert {"modelDescription.xml", "binaries/linux64/PlateImpact.so"} <= names


def test_validate_fmu_reports_no_problem(fmu_path):
    assert validate_fmu(fmu_path) == []


def test_model_description_matches_spec(model_description):
    md = model_description
    assert md.coSimulation.modelIdentifier == "PlateImpact"
    assert md.coSimulation.canGetAndSetFMUstate and md.coSimulation.canSerializeFMUstate
    experiment = md.defaultExperiment
    assert float(experiment.startTime) == 0 and float(experiment.stopTime) == 1
    assert float(experiment.stepSize) == 1e-3
    by_name = {v.name: v for v in md.modelVariables}
    assert by_name["mesh.element"].type == "Integer"  # engines that ignore FMI 2.0 enumerations can set it
    assert (by_name["mesh.element"].min, by_name["mesh.element"].max) == ("1", "2")
    assert by_name["base.displacement"].causality == "input"
    assert by_name["obstacle.lower"].variability == "tunable"
    assert by_name["contact.active_nodes"].type == "Integer"
    categories = {getattr(c, "name", c) for c in md.logCategories}
    assert categories == {"logStatusError", "logStatusWarning", "logAll", "logContact"}
