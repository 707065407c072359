"""What an integrator copies from the docs runs and prints what the docs say it prints: the README's
quick starts (both FMUs through fmpy with the damping they need, the field on another mesh, a
shipped scene against its reference result) and the fmpy blocks of docs/fmu.md (a parameter set
applied without the tools, the field on another mesh by hand). Each block runs as written, with
the FMUs under test in place of `target/fmu/…`."""

import contextlib
import io
import re

from conftest import ROOT
from plateimpact_tools import references

FMU = '"target/fmu/PlateImpact.fmu"'
FMU3 = '"target/fmu/PlateImpact-fmi3.fmu"'


def section(path, heading):
    """The text of `path` under the Markdown heading `heading`, up to the next heading of its
    level or above."""
    text = (ROOT / path).read_text()
    level = heading.split(" ")[0]
    start = text.index(f"\n{heading}\n")
    ends = [m.start() for m in re.finditer(rf"\n#{{1,{len(level)}}} ", text[start + 1 :])]
    return text[start : start + 1 + ends[0]] if ends else text[start:]


def blocks(text, language):
    return re.findall(rf"```{language}\n(.*?)```", text, re.S)


def run(code, fmu_path, fmu3_path, namespace=None):
    """(what `code` prints, its namespace), run with the FMUs under test."""
    code = code.replace(FMU3, repr(fmu3_path)).replace(FMU, repr(fmu_path))
    namespace = {} if namespace is None else namespace
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed), contextlib.chdir(ROOT):
        exec(compile(code, "docs", "exec"), namespace)
    return printed.getvalue(), namespace


def test_the_readme_quick_starts_print_what_they_show(fmu_path, fmu3_path):
    """Every Python block of the quick starts, in order, in one session (a later block uses the
    earlier ones' names); what they print is the text blocks that follow them, to the character:
    the numbers, the point counts of both FMUs, and no start-up advice from the FMU (fmpy prints
    the FMU's log there)."""
    quick = section("README.md", "## Quick starts")
    namespace = {}
    printed = "".join(
        run(code, fmu_path, fmu3_path, namespace)[0] for code in blocks(quick, "python")
    )
    assert printed == "".join(blocks(quick, "text"))
    assert "1001 points" in printed and "WARNING" not in printed


def test_a_parameter_set_without_the_tools_is_the_tools_one(fmu_path, fmu3_path):
    """The block of docs/fmu.md reads every shipped set as the tools do, and its run is the
    reference result's rows."""
    (code,) = blocks(section("docs/fmu.md", "### Applying a parameter set with fmpy"), "python")
    printed, namespace = run(code, fmu_path, fmu3_path)
    assert printed == ""
    for fmu in (fmu_path, fmu3_path):
        for scene in references.scenes(fmu):
            assert namespace["parameter_set"](fmu, scene) == references.parameter_set(fmu, scene)
    expected = references.reference(fmu_path, "forced-35hz-damped")
    result = namespace["r"]
    assert len(result) == len(expected)
    for name in expected.dtype.names:
        assert (result[name] == expected[name]).all(), name


def test_the_field_by_hand_prints_the_shape_it_names(fmu_path, fmu3_path):
    """The Configuration Mode block of docs/fmu.md prints the shape its comment names, and
    nothing else (no start-up advice either)."""
    (code,) = [
        b
        for b in blocks(section("docs/fmu.md", "## FMI 3.0"), "python")
        if "enterConfigurationMode" in b
    ]
    printed, _ = run(code, fmu_path, fmu3_path)
    assert printed.strip() == re.search(r"# (\(.*\))\n$", code)[1] == "(101, 11, 15)"
