"""The C host of examples/c/: its constants match modelDescription.xml, it builds warning-free
both ways (dlopen and linked) with the machine's C compiler against the FMI 2.0 headers that fmpy
ships, both builds print exactly the numbers fmpy gets from the same FMU, and what they print on
stdout and stderr is what docs/usage.md shows."""

import os
import pathlib
import re
import shutil
import subprocess

import fmpy
import pytest

from conftest import ROOT, scene_start_values

SOURCE = ROOT / "examples" / "c" / "plate_host.c"
# The official FMI 2.0 headers (fmi2Functions.h, fmi2FunctionTypes.h, fmi2TypesPlatform.h).
FMI2_HEADERS = pathlib.Path(fmpy.__file__).parent / "c-code"
FLAGS = ["-std=c11", "-Wall", "-Wextra", "-Werror", f"-I{FMI2_HEADERS}"]
# What the host does, repeated here through fmpy: communication steps of 1 ms up to 1 s.
STEP, STEPS = 1e-3, 1000


def c_compiler():
    compiler = os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc")
    if not compiler:
        pytest.fail("no C compiler (cc, gcc or $CC): on Debian, apt-get install gcc libc6-dev")
    return compiler


def compile_host(output, *extra):
    done = subprocess.run(
        [c_compiler(), *FLAGS, str(SOURCE), "-o", str(output), *extra],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, f"compiling {SOURCE.name} {' '.join(extra)}:\n{done.stderr}"
    assert done.stderr == "", f"the compiler printed:\n{done.stderr}"
    return output


@pytest.fixture(scope="module")
def hosts(unzipdir, tmp_path_factory):
    """Both builds of the host: {"dlopen": path, "linked": path}."""
    out = tmp_path_factory.mktemp("c-host")
    library_dir = pathlib.Path(unzipdir) / "binaries" / "linux64"
    return {
        "dlopen": compile_host(out / "plate_host_dlopen", "-ldl"),
        "linked": compile_host(
            out / "plate_host_linked",
            "-DPLATE_HOST_LINKED",
            f"-L{library_dir}",
            "-l:PlateImpact.so",
            f"-Wl,-rpath,{library_dir}",
        ),
    }


def run_host(host, unzipdir):
    """(the values it printed, by (final|restored, name); its stdout; its stderr)."""
    done = subprocess.run([str(host), str(unzipdir)], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, f"{host.name} failed:\n{done.stdout}\n{done.stderr}"
    values = {}
    for line in done.stdout.splitlines():
        match = re.fullmatch(r"(final|restored) (\S+) (\S+) \(.*\)", line)
        if match:
            values[match[1], match[2]] = float.fromhex(match[3])
    return values, done.stdout, done.stderr


def test_the_c_constants_match_the_model_description(model_description):
    """The host's value references are copied from modelDescription.xml: when the FMU's
    description changes, this names what the C file must follow. The GUID is not: the host reads it
    from the unzipped FMU, since the build derives it from the description's content."""
    text = SOURCE.read_text()
    declared = re.findall(r"(VR_\w+) = (\d+),\s*/\* ([\w.]+), (\w+)", text)
    assert len(declared) == 6, f"expected 6 value reference constants in {SOURCE.name}"
    variables = {v.name: v for v in model_description.modelVariables}
    stale = []
    for constant, vr, name, kind in declared:
        variable = variables.get(name)
        if variable is None:
            stale.append(f"{constant}: no variable {name} in modelDescription.xml")
            continue
        if (int(vr), kind) != (variable.valueReference, variable.type):
            stale.append(
                f"{constant} = {vr} ({kind}) but {name} is {variable.valueReference} "
                f"({variable.type}) in modelDescription.xml"
            )
        if constant != "VR_" + name.upper().replace(".", "_"):
            stale.append(f"{constant} is not named after {name}")
    if model_description.guid in text or re.search(r'"\{[0-9a-f-]{36}\}"', text):
        stale.append("a GUID is written into the source: read it from modelDescription.xml")
    assert not stale, f"{SOURCE.name} is stale:\n" + "\n".join(stale)


def test_both_c_builds_equal_fmpy_bit_for_bit(hosts, unzipdir, new_plate):
    # fmpy through the same calls, with every parameter of the forced-35hz scene file set: the
    # host sets only the base sine, so equal numbers also show that its scene is forced-35hz.
    plate = new_plate().initialize(scene_start_values("forced-35hz")[0], stop=STEPS * STEP)
    for _ in range(STEPS):
        plate.step(STEP)
    names = ["corner1.displacement", "corner2.displacement", "energy.total"]
    reference = {name: plate.get(name) for name in names}
    for build, host in hosts.items():
        values, printed, log = run_host(host, unzipdir)
        summary = printed.splitlines()[-1]
        for label in ("final", "restored"):
            for name in names:
                assert values[label, name].hex() == reference[name].hex(), (build, label, name)
        assert summary.startswith(f"PlateImpact from C ({build}): forced 35 Hz, 1000 steps")
        assert summary.endswith("run restored from t = 0.5 s repeats bit for bit"), summary
        # The deliberately rejected parameter came back through the host's logger callback.
        assert re.search(
            r"\[plate\] error logStatusError: fmi2SetReal: .*material\.poisson_ratio", log
        ), log


def test_the_host_prints_what_the_docs_show(hosts, unzipdir):
    """docs/usage.md, "From C", shows the host's stdout and stderr in two text blocks: both builds
    print them to the character (the summary names the build)."""
    text = (ROOT / "docs" / "usage.md").read_text()
    section = text[text.index("\n## From C\n") :]
    following = section.find("\n## ", 1)
    section = section if following < 0 else section[:following]
    stdout, stderr = re.findall(r"```text\n(.*?)```", section, re.S)[:2]
    for build, host in hosts.items():
        _, printed, log = run_host(host, unzipdir)
        assert printed == stdout.replace("(dlopen)", f"({build})"), build
        assert log == stderr, build
