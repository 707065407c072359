"""The packaged FMU: layout, fmpy's validation, its version, whose it is (author, copyright,
licences) and its content-derived token."""

import hashlib
import re
import subprocess
import uuid
import zipfile

import pytest
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


def crate_version():
    return re.search(r'^version = "(.+)"$', (ROOT / "Cargo.toml").read_text(), re.M)[1]


def git(*args):
    """git's output in the repository, or None where Git or the checkout is missing."""
    try:
        done = subprocess.run(["git", "-C", str(ROOT), *args], capture_output=True, text=True)
    except FileNotFoundError:
        return None
    return done.stdout.strip() if done.returncode == 0 else None


def test_one_version_for_the_crate_and_both_fmus(model_description, model_description3):
    """The FMUs say the crate's version, with the checkout's commit unless they are the release
    of that version (docs/fmu.md, "Versions, builds and the token")."""
    crate = crate_version()
    assert re.fullmatch(r"\d+\.\d+\.\d+(-dev)?", crate)
    version = model_description.version
    assert model_description3.version == version
    head = git("rev-parse", "HEAD")
    if version == crate:
        # A release: the commit tagged v<crate>, or about to be (scripts/release tests the FMUs
        # of package-fmu --release before it makes the tag).
        assert not crate.endswith("-dev"), "a pre-release names its commit"
        assert head is not None and git("rev-parse", "-q", "--verify", f"v{crate}^{{commit}}") in (
            None,
            head,
        ), f"{version} without a commit: v{crate} was released from another commit"
        return
    match = re.fullmatch(
        re.escape(crate) + r"\+([0-9a-f]{12})(\.modified)?|" + re.escape(crate) + r"\+unknown",
        version,
    )
    assert match, f"{version} is not {crate}+<commit>[.modified]"
    if head is not None:
        assert match[1] == head[:12], (
            f"the FMU says commit {match[1]}, the checkout is at {head[:12]}: package it again"
        )
        date = git("log", "-1", "--format=%cd", "--date=format-local:%Y-%m-%dT%H:%M:%SZ", "HEAD")
        assert model_description.generationDateAndTime == date


@pytest.mark.parametrize("fmi", [2, 3])
def test_the_shipped_description_is_the_hand_kept_one_stamped(fmi, fmu_path, fmu3_path):
    """The packager changes only the token, the version and the generation time of the hand-kept
    description."""
    fmu, source, token = (
        (fmu_path, "modelDescription.xml", "guid")
        if fmi == 2
        else (fmu3_path, "modelDescription-fmi3.xml", "instantiationToken")
    )
    shipped = zipfile.ZipFile(fmu).read("modelDescription.xml").decode()
    kept = (ROOT / "modelDescription" / source).read_text()
    shipped = re.sub(token + r'="\{[0-9a-f-]{36}\}"', token + '="{derived-at-build-time}"', shipped)
    shipped = re.sub(r'\n  generationDateAndTime="[0-9T:Z-]+"', "", shipped)
    shipped = re.sub(r'\n  version="[^"]+"', f'\n  version="{crate_version()}"', shipped)
    assert shipped == kept


def test_both_fmus_say_whose_they_are(model_description, model_description3):
    licence = (ROOT / "LICENSE").read_text()
    holder = re.search(r"^Copyright \(c\) \d{4} (.+)$", licence, re.M)
    for md in (model_description, model_description3):
        assert md.author == holder[1]
        assert md.copyright == holder[0]
        assert md.license.startswith("MIT License: documentation/licenses/license.txt")


@pytest.mark.parametrize("fmi", [2, 3])
def test_the_fmu_carries_its_licences(fmi, fmu_path, fmu3_path):
    """documentation/licenses/license.txt, the entry point FMI 3.0 names, holds LICENSE and names
    every copied licence file, each of which the FMU carries."""
    with zipfile.ZipFile(fmu_path if fmi == 2 else fmu3_path) as z:
        names = set(z.namelist())
        index = z.read("documentation/licenses/license.txt").decode()
    assert (ROOT / "LICENSE").read_text() in index
    copied = re.findall(r"^    (third-party/\S+)$", index, re.M)
    shared = re.findall(r": the same text as (third-party/\S+)$", index, re.M)
    assert copied and shared
    assert {f"documentation/licenses/{path}" for path in copied + shared} <= names
    assert {n for n in names if n.startswith("documentation/licenses/third-party/")} == {
        f"documentation/licenses/{path}" for path in copied
    }
    for package in ("faer", "clarabel", "serde", "libm"):
        assert re.search(rf"^{package} \d+\.\d+\.\d+ \(", index, re.M), package


def test_the_documentation_page_says_which_build_it_is(fmu_path, model_description):
    page = zipfile.ZipFile(fmu_path).read("documentation/index.html").decode()
    about = page[page.index("<h2>This build</h2>") :]
    assert f"PlateImpact {model_description.version}" in about
    head = git("rev-parse", "HEAD")
    if head is not None:
        assert f"built from commit <code>{head}</code>" in about
    assert "<code>docs/README.md</code>" in about
    assert "<code>documentation/licenses/license.txt</code>" in about
