"""The packaged FMU: layout, fmpy's validation, its version and its content-derived token."""

import hashlib
import re
import uuid
import zipfile

from fmpy.validation import validate_fmu

from conftest import ROOT


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
    assert (
        by_name["mesh.element"].type == "Integer"
    )  # engines that ignore FMI 2.0 enumerations can set it
    assert (by_name["mesh.element"].min, by_name["mesh.element"].max) == ("1", "2")
    assert by_name["base.displacement"].causality == "input"
    assert by_name["obstacle.lower"].variability == "tunable"
    assert by_name["contact.active_nodes"].type == "Integer"
    categories = {getattr(c, "name", c) for c in md.logCategories}
    assert categories == {"logStatusError", "logStatusWarning", "logAll", "logContact"}


def content_token(path):
    """The token of a hand-kept description, derived here independently of build/token.rs: SHA-256
    of the text without a byte-order mark and with LF line ends, its first 128 bits written as an
    RFC 9562 version-8 UUID in braces."""
    text = path.read_text(encoding="utf-8-sig").replace("\r\n", "\n").replace("\r", "\n")
    digest = bytearray(hashlib.sha256(text.encode()).digest()[:16])
    digest[6] = digest[6] & 0x0F | 0x80
    digest[8] = digest[8] & 0x3F | 0x80
    return f"{{{uuid.UUID(bytes=bytes(digest))}}}"


def test_the_tokens_are_derived_from_the_descriptions(model_description, model_description3):
    fmi2 = model_description.guid
    fmi3 = model_description3.instantiationToken
    assert fmi2 == content_token(ROOT / "modelDescription" / "modelDescription.xml")
    assert fmi3 == content_token(ROOT / "modelDescription" / "modelDescription-fmi3.xml")
    assert uuid.UUID(fmi2).version == uuid.UUID(fmi3).version == 8 and fmi2 != fmi3


def test_one_version_for_the_crate_and_both_fmus(model_description, model_description3):
    crate = re.search(r'^version = "(.+)"$', (ROOT / "Cargo.toml").read_text(), re.M)[1]
    assert re.fullmatch(r"\d+\.\d+\.\d+", crate)
    assert model_description.version == model_description3.version == crate
