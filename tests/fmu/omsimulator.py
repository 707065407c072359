"""OMSimulator (the OpenModelica co-simulation environment) as an importer of the plate FMUs, for
tests/fmu/test_omsimulator.py: the binary the environment variable OMSIMULATOR names (built by hand
from its public source, docs/fmu.md "Engines tried"; no package registry ships it), SSP archives
written for it, and its CSV results read back.

An SSP here is SystemStructure.ssd with one system of components, each an FMU with an optional SSV
parameter binding, and their connections, under OMSimulator's fixed-step master
(`oms:FixedStepMaster` in its vendor annotation, the one way an SSP 1.0 file names a master for
it). A result signal filter may name the variables to record: OMSimulator records every variable
by default, and reads the FMI 3.0 array `plate.displacement` as a scalar, which the FMU refuses."""

import csv
import os
import pathlib
import re
import shutil
import subprocess
import zipfile
from xml.sax.saxutils import quoteattr

import fmpy
import numpy as np
import pytest

OMS_NAMESPACE = (
    'xmlns:oms="https://raw.githubusercontent.com/OpenModelica/OMSimulator/master/schema/oms.xsd"'
)
SSD_NAMESPACES = (
    'xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" '
    'xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" ' + OMS_NAMESPACE
)
# OMSimulator names every recorded signal model.system.component.variable.
MODEL, SYSTEM = "model", "root"


def binary():
    """The OMSimulator binary; skips the test when OMSIMULATOR names none."""
    path = os.environ.get("OMSIMULATOR")
    if not path:
        pytest.skip(
            "OMSIMULATOR does not name an OMSimulator binary (built by hand from the "
            "OpenModelica/OMSimulator source as docs/fmu.md describes; no registry ships it)"
        )
    if not pathlib.Path(path).is_file():
        pytest.fail(f"OMSIMULATOR={path} is not a file")
    return path


def signal(component, variable):
    """The name OMSimulator gives `variable` of `component` in its results."""
    return f"{MODEL}.{SYSTEM}.{component}.{variable}"


def ssd(components, connections, stop, step, recorded=None):
    """SystemStructure.ssd: `components` a list of (name, FMU file name, SSV file name or None) in
    resources/, `connections` a list of (component, output, component, input), a run from 0 to
    `stop` with communication step `step`, recording `recorded` ([(component, variable)], all
    when None) through the signal filter resources/signalFilter.xml."""
    elements = []
    for name, fmu, ssv in components:
        # The connectors a connection uses (OMSimulator connects declared connectors only).
        used = [(x, "output") for a, x, _, _ in connections if a == name] + [
            (y, "input") for _, _, b, y in connections if b == name
        ]
        connectors = (
            ""
            if not used
            else "\n        <ssd:Connectors>"
            + "".join(
                f'\n          <ssd:Connector name="{c}" kind="{kind}"><ssc:Real/></ssd:Connector>'
                for c, kind in used
            )
            + "\n        </ssd:Connectors>"
        )
        binding = (
            ""
            if ssv is None
            else f"\n        <ssd:ParameterBindings>\n          <ssd:ParameterBinding "
            f'source="resources/{ssv}"/>\n        </ssd:ParameterBindings>'
        )
        closing = "\n      " if used or ssv is not None else ""
        elements.append(
            f"      <ssd:Component name={quoteattr(name)} "
            f'type="application/x-fmu-sharedlibrary" source="resources/{fmu}">'
            f"{connectors}{binding}{closing}</ssd:Component>"
        )
    links = "".join(
        f'\n      <ssd:Connection startElement="{a}" startConnector="{x}" endElement="{b}" '
        f'endConnector="{y}"/>'
        for a, x, b, y in connections
    )
    # SSP 1.0 wants at least one connection in a <ssd:Connections>.
    links = f"\n    <ssd:Connections>{links}\n    </ssd:Connections>" if connections else ""
    filter_attribute = "" if recorded is None else ' signalFilter="resources/signalFilter.xml"'
    return f'''<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription {SSD_NAMESPACES} version="1.0" name="{MODEL}">
  <ssd:System name="{SYSTEM}">
    <ssd:Elements>
{chr(10).join(elements)}
    </ssd:Elements>{links}
    <ssd:Annotations>
      <ssc:Annotation type="org.openmodelica">
        <oms:Annotations>
          <oms:SimulationInformation>
            <oms:FixedStepMaster description="oms-ma" stepSize="{step!r}" absoluteTolerance="1e-4" relativeTolerance="1e-4"/>
          </oms:SimulationInformation>
        </oms:Annotations>
      </ssc:Annotation>
    </ssd:Annotations>
  </ssd:System>
  <ssd:DefaultExperiment startTime="0" stopTime="{stop!r}">
    <ssd:Annotations>
      <ssc:Annotation type="org.openmodelica">
        <oms:Annotations>
          <oms:SimulationInformation{filter_attribute} loggingInterval="0"/>
        </oms:Annotations>
      </ssc:Annotation>
    </ssd:Annotations>
  </ssd:DefaultExperiment>
</ssd:SystemStructureDescription>
'''


def signal_filter(recorded):
    """resources/signalFilter.xml: OMSimulator records only these (component, variable) pairs (it
    escapes the names itself before it matches them as patterns)."""
    lines = "".join(
        f'\n  <oms:Variable name="{signal(c, v)}" type="Real" kind="output"/>' for c, v in recorded
    )
    return (
        f'<?xml version="1.0" encoding="UTF-8"?>\n<oms:SignalFilter version="1.0" '
        f"{OMS_NAMESPACE}>{lines}\n</oms:SignalFilter>\n"
    )


def write_ssp(path, description, resources):
    """An SSP archive at `path`: SystemStructure.ssd from `description` and `resources`, a dict of
    file name in resources/ to a file path or to bytes."""
    with zipfile.ZipFile(path, "w") as z:
        z.writestr("SystemStructure.ssd", description)
        for name, source in resources.items():
            if isinstance(source, bytes):
                z.writestr(f"resources/{name}", source)
            else:
                z.write(source, f"resources/{name}")
    return path


def run(model, workdir, stop, step):
    """Runs OMSimulator on `model` (an FMU or an SSP) in `workdir` from 0 to `stop` with
    communication step `step` (its command line's --stopTime replaces an SSP's stop time, 1 s
    unless given; an SSP's step is its master's), without event rows: (the result as
    {signal: array}, the log). Fails on a non-zero exit or an error in the log."""
    result = pathlib.Path(workdir) / "result.csv"
    command = [
        binary(),
        str(model),
        f"--resultFile={result}",
        "--emitEvents=false",
        f"--tempDir={workdir}",
        "--mode=cs",
        f"--stopTime={stop!r}",
        f"--stepSize={step!r}",
    ]
    done = subprocess.run(command, capture_output=True, text=True, timeout=600, cwd=workdir)
    log = done.stdout + done.stderr
    assert done.returncode == 0, f"OMSimulator exited with {done.returncode}:\n{log}"
    errors = [line for line in log.splitlines() if line.startswith("error:")]
    assert not errors, log
    with open(result, newline="") as f:
        rows = list(csv.reader(f))
    header = [name.strip().strip('"') for name in rows[0]]
    table = np.array([[float(x) for x in row] for row in rows[1:]])
    return {name: table[:, i] for i, name in enumerate(header)}, log


def printed(values):
    """`values` as OMSimulator's CSV writer prints them (%.12g) and reads back."""
    return np.array([float(f"{x:.12g}") for x in np.asarray(values, dtype=float)])


def shaker_fmu(directory):
    """The shaker FMU of tests/fmu/shaker/, built with the C compiler against the FMI 2.0 headers
    fmpy ships, packed at `directory`/Shaker.fmu."""
    compiler = shutil.which("cc")
    if compiler is None:
        pytest.skip("no C compiler (cc) to build the shaker FMU")
    source = pathlib.Path(__file__).parent / "shaker"
    library = pathlib.Path(directory) / "Shaker.so"
    subprocess.run(
        [
            compiler,
            "-std=c11",
            "-Wall",
            "-Wextra",
            "-Werror",
            "-O2",
            "-shared",
            "-fPIC",
            f"-I{pathlib.Path(fmpy.__file__).parent / 'c-code'}",
            str(source / "shaker.c"),
            "-o",
            str(library),
            "-lm",
        ],
        check=True,
    )
    fmu = pathlib.Path(directory) / "Shaker.fmu"
    with zipfile.ZipFile(fmu, "w") as z:
        z.write(source / "modelDescription.xml", "modelDescription.xml")
        z.write(library, "binaries/linux64/Shaker.so")
    return fmu


def without_dependencies(fmu, path):
    """A copy of `fmu` at `path` whose model description declares no dependencies, as before
    they were declared (the token stays: it is the text of the guid attribute, not recomputed)."""
    with zipfile.ZipFile(fmu) as source, zipfile.ZipFile(path, "w") as copy:
        for item in source.infolist():
            data = source.read(item.filename)
            if item.filename == "modelDescription.xml":
                data = re.sub(rb' dependencies="[^"]*"', b"", data)
            copy.writestr(item, data)
    return path
