"""The exported FMI 3.0 ABI against the official headers (fmpy ships fmi3Functions.h,
fmi3FunctionTypes.h and fmi3PlatformTypes.h): every function of fmi3Functions.h is exported by the
packaged library, and its Rust signature is the header's.

The Rust signatures are read from src/fmi/fmi3/exports.rs and its module exports/unoffered.rs
(whose types carry the header's type names) and written as C prototypes into a translation unit
that includes fmi3Functions.h, which declares every function already; C requires a
redeclaration to have a compatible type, so a wrong parameter or return type fails the compile
("conflicting types"), and each function is also assigned to a pointer of its fmi3XxxTYPE. A
deliberately wrong prototype must fail it.
"""

import pathlib
import re
import subprocess

import fmpy
import pytest

from conftest import ROOT
from test_c_host import c_compiler

HEADERS = pathlib.Path(fmpy.__file__).parent / "c-code"
EXPORTS = [ROOT / "src" / "fmi" / "fmi3" / "exports.rs",
           ROOT / "src" / "fmi" / "fmi3" / "exports" / "unoffered.rs"]
FLAGS = ["-std=c11", "-Wall", "-Wextra", "-Werror", "-pedantic", f"-I{HEADERS}", "-c"]


def expand_macros(text):
    """The functions written by this file's `macro_rules!`: each invocation's entries substituted
    into the macro's template (the macros here take one repetition of `$name:kind` parameters
    separated by commas, entries ending with `;`)."""
    out = [text]
    for name, params, body in re.findall(
            r"macro_rules! (\w+) \{\s*\(\$\((.*?)\)\*\) => \{\$\((.*?)\)\*\};\s*\}", text, re.S):
        names = re.findall(r"\$(\w+):\w+", params)
        invocation = re.search(rf"\n{name}! \{{(.*?)\n\}}", text, re.S)
        assert invocation, f"macro {name} is never invoked"
        for entry in invocation[1].split(";"):
            values = [v.strip() for v in entry.split(",")]
            if values == [""]:
                continue
            assert len(values) == len(names), entry
            expanded = body
            for key, value in zip(names, values):
                expanded = expanded.replace(f"${key}", value)
            out.append(expanded)
    return "\n".join(out)


def c_type(rust):
    """The C spelling of a Rust parameter or return type of EXPORTS."""
    rust = rust.strip()
    pointer = re.fullmatch(r"\*(const|mut) (.+)", rust)
    if pointer:
        inner = c_type(pointer[2])
        return f"const {inner}*" if pointer[1] == "const" else f"{inner}*"
    return {"c_char": "char", "size_t": "size_t"}.get(rust, rust)


def exported_prototypes():
    """{name: C prototype} of every `extern "C" fn fmi3…` of EXPORTS, macros expanded."""
    text = expand_macros("\n".join(path.read_text() for path in EXPORTS))
    prototypes = {}
    for name, params, ret in re.findall(
            r'pub (?:unsafe )?extern "C" fn (fmi3\w+)\((.*?)\)\s*(?:-> ([^{]+?))?\s*\{', text, re.S):
        args = [p.strip() for p in params.split(",") if p.strip()]
        c_args = []
        for arg in args:
            arg_name, arg_type = arg.split(":", 1)
            c_args.append(f"{c_type(arg_type)} {arg_name.strip()}")
        prototypes[name] = f"{c_type(ret) if ret else 'void'} {name}({', '.join(c_args) or 'void'});"
    return prototypes


def header_functions():
    """The functions fmi3Functions.h declares: `FMI3_Export fmi3XxxTYPE fmi3Xxx;`."""
    text = (HEADERS / "fmi3Functions.h").read_text()
    return re.findall(r"FMI3_Export\s+(fmi3\w+)TYPE\s+(fmi3\w+);", text)


def translation_unit(prototypes):
    lines = ['#include "fmi3Functions.h"', ""]
    lines += [prototypes[name] for _, name in header_functions()]
    lines += ["", "/* Each exported function as a pointer of its type from fmi3FunctionTypes.h. */",
              "const struct {"]
    lines += [f"    {typename}TYPE *{name};" for typename, name in header_functions()]
    lines += ["} plate_impact_fmi3_functions = {"]
    lines += [f"    {name}," for _, name in header_functions()]
    lines += ["};", ""]
    return "\n".join(lines)


def compile_unit(source, tmp_path):
    path = tmp_path / "fmi3_abi.c"
    path.write_text(source)
    return subprocess.run([c_compiler(), *FLAGS, str(path), "-o", str(tmp_path / "fmi3_abi.o")],
                          capture_output=True, text=True)


def test_every_function_of_the_header_is_exported(unzipdir3):
    declared = {name for _, name in header_functions()}
    assert len(declared) == 75
    assert set(exported_prototypes()) == declared
    library = pathlib.Path(unzipdir3) / "binaries" / "x86_64-linux" / "PlateImpact.so"
    symbols = subprocess.run(["nm", "-D", "--defined-only", str(library)], capture_output=True,
                             text=True, check=True).stdout
    exported = set(re.findall(r"\bT (fmi3\w+)$", symbols, re.M))
    assert exported == declared, sorted(declared ^ exported)


def test_every_signature_is_the_headers(tmp_path):
    done = compile_unit(translation_unit(exported_prototypes()), tmp_path)
    assert done.returncode == 0 and done.stderr == "", done.stderr


@pytest.mark.parametrize("function,wrong", [
    ("fmi3DoStep", ("fmi3Float64 communicationStepSize", "fmi3Float32 communicationStepSize")),
    ("fmi3GetFloat64", ("size_t nValues", "fmi3UInt32 nValues")),
    ("fmi3InstantiateCoSimulation", ("fmi3LogMessageCallback logMessage",
                                     "fmi3ClockUpdateCallback logMessage")),
    ("fmi3GetVersion", ("const char* fmi3GetVersion", "char* fmi3GetVersion")),
])
def test_a_wrong_signature_fails_the_compile(tmp_path, function, wrong):
    """The check bites: one parameter or return type changed, the compile fails naming it."""
    prototypes = exported_prototypes()
    old, new = wrong
    assert old in prototypes[function], prototypes[function]
    prototypes[function] = prototypes[function].replace(old, new)
    done = compile_unit(translation_unit(prototypes), tmp_path)
    assert done.returncode != 0 and function in done.stderr, done.stderr
