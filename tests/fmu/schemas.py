"""The published XML schemas of the files the FMUs carry and the tests write, loaded with lxml
(libxml2's XML Schema 1.0 validator).

* SSP 1.0 (`ssv`: SystemStructureParameterValues, `ssd`: SystemStructureDescription, with
  SystemStructureCommon): the copies fmpy ships, identical to modelica/ssp-standard at v1.0.1.
* FMI-LS-REF (`manifest`: fmi3LayeredStandardReferenceManifest.xsd) and MA-HS-Experiments
  (`experiments`: maHarmonizedSpecificationExperiments.xsd): drafts that no package registry
  ships. They are read from the directory the environment variable PLATE_IMPACT_SCHEMAS names
  (docs/fmu.md, "What the FMU carries", says which commits), and a test that needs one is skipped,
  saying so, when it is not set.

Both drafts import the FMI 3.0 schemas of annotations and of layered-standard manifests from
modelica/fmi-standard by URL; those come from fmpy's copies (FMI 3.0.1, the same declarations as
the URL's), so that validation never touches the network. The MA-HS-Experiments draft pulls
fmi3Annotation.xsd in with an `xs:import` without a namespace, which XML Schema 1.0 forbids in a
schema without a target namespace (both schemas have none): libxml2 and the xmlschema package
refuse to load it. FMI-LS-REF had the same line and corrected it upstream to an `xs:include`, which
merges a schema of the same (absent) namespace; the loader makes that one correction in memory."""

import os
import pathlib
import re

import fmpy
import pytest
from lxml import etree

FMPY = pathlib.Path(fmpy.__file__).parent
FMI_STANDARD_URL = "https://raw.githubusercontent.com/modelica/fmi-standard/main/schema/"
DRAFTS = {
    "manifest": "fmi3LayeredStandardReferenceManifest.xsd",
    "experiments": "maHarmonizedSpecificationExperiments.xsd",
}
SSP = {"ssv": "SystemStructureParameterValues.xsd", "ssd": "SystemStructureDescription.xsd"}


class _FmiStandard(etree.Resolver):
    """Resolves the drafts' imports of modelica/fmi-standard's schemas to fmpy's copies."""

    def resolve(self, url, public_id, context):
        if url.startswith(FMI_STANDARD_URL):
            return self.resolve_filename(
                str(FMPY / "schema" / "fmi3" / url.removeprefix(FMI_STANDARD_URL)), context
            )
        return None


def schema_path(kind):
    """The schema file of `kind` (ssv, ssd, manifest, experiments); skips the test when a draft's
    directory is not given."""
    if kind in SSP:
        return FMPY / "ssp" / "schema" / SSP[kind]
    directory = os.environ.get("PLATE_IMPACT_SCHEMAS")
    if not directory:
        pytest.skip(
            f"PLATE_IMPACT_SCHEMAS does not name the directory of the draft schema "
            f"{DRAFTS[kind]} (no package registry ships it; docs/fmu.md says which commit)"
        )
    path = pathlib.Path(directory) / DRAFTS[kind]
    if not path.is_file():
        pytest.fail(f"PLATE_IMPACT_SCHEMAS={directory} holds no {DRAFTS[kind]}")
    return path


# An xs:import with a schemaLocation and no namespace (the draft's one line, module docs).
IMPORT_WITHOUT_NAMESPACE = re.compile(r"<xs:import(?![^>]*\bnamespace=)(?=[^>]*\bschemaLocation=)")


def validator(kind):
    """An lxml XMLSchema for `kind`, its imports resolved offline."""
    parser = etree.XMLParser(no_network=True)
    parser.resolvers.add(_FmiStandard())
    path = schema_path(kind)
    text = IMPORT_WITHOUT_NAMESPACE.sub("<xs:include", path.read_text())
    return etree.XMLSchema(etree.fromstring(text.encode(), parser, base_url=str(path)))


def errors(kind, document):
    """The schema's complaints about `document` (bytes), one line each; empty when it is valid."""
    schema = validator(kind)
    if schema.validate(etree.fromstring(document)):
        return []
    return [f"line {e.line}: {e.message}" for e in schema.error_log]
