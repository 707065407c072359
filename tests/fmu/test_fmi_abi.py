"""The exported FMI 2.0 and FMI 3.0 C ABI against the official headers fmpy ships
(fmi2Functions.h, fmi2FunctionTypes.h, fmi2TypesPlatform.h, fmi3Functions.h, fmi3FunctionTypes.h,
fmi3PlatformTypes.h), without reading any Rust source.

The C headers are regular: each function has `typedef <ret> <name>TYPE(<params>);`, built from
platform typedefs, enums, one struct and function-pointer typedefs. They are translated here into
a Rust file with one `type <name>TYPE = unsafe extern "C" fn(...) -> ...;` per function, every C
type resolved down to a primitive by the explicit table `C_TO_RUST` (enums are C `int`), plus
`const _: <name>TYPE = plate_impact::fmi::fmiN::exports::<name>;`. rustc coerces a function item
to a function pointer only if every parameter and the return type are identical (`*mut T` is not
`*const T`, `bool` is not `c_int`), so compiling that file with `rustc --emit metadata` against the
crate's rlib checks every signature; a deliberately wrong header type must fail it.

The one type not resolved structurally is the struct `fmi2CallbackFunctions` (passed by pointer),
mapped to the crate's `#[repr(C)]` struct by name; its size is compared with the C compiler's.
"""

import json
import os
import pathlib
import re
import subprocess

import fmpy
import pytest

from conftest import ROOT
from test_c_host import c_compiler

HEADERS = pathlib.Path(fmpy.__file__).parent / "c-code"

# The C base types the headers build on, and their Rust spellings (on the platforms the FMU is
# built for, C enums are int-sized and C bool is one byte with Rust bool's values).
C_TO_RUST = {
    "void": "core::ffi::c_void",
    "char": "core::ffi::c_char",
    "int": "core::ffi::c_int",
    "unsigned int": "core::ffi::c_uint",
    "double": "f64",
    "float": "f32",
    "bool": "bool",
    "size_t": "usize",
    "int8_t": "i8",
    "uint8_t": "u8",
    "int16_t": "i16",
    "uint16_t": "u16",
    "int32_t": "i32",
    "uint32_t": "u32",
    "int64_t": "i64",
    "uint64_t": "u64",
    "enum": "core::ffi::c_int",
    "fmi2CallbackFunctions": "plate_impact::fmi::fmi2::exports::fmi2CallbackFunctions",
}

# The Model Exchange functions of FMI 2.0, which a Co-Simulation-only FMU need not export
# (fmi2Functions.h declares them under this heading).
FMI2_ME_HEADING = "Functions for FMI2 for Model Exchange"
FMI2_CS_HEADING = "Functions for FMI2 for Co-Simulation"


def without_comments(text):
    return re.sub(r"/\*.*?\*/", " ", text, flags=re.S)


class Header:
    """The typedefs of one FMI version's headers, as Rust types."""

    def __init__(self, texts):
        self.aliases = {}  # typedef name -> C declaration text it stands for
        self.pointers = {}  # function-pointer typedef name -> (ret, params)
        self.functions = {}  # fmiXxxTYPE name -> (ret, params)
        text = without_comments("\n".join(texts))
        for name in re.findall(r"typedef\s+enum\s*\{[^}]*\}\s*(\w+)\s*;", text):
            self.aliases[name] = "enum"
        for name in re.findall(r"typedef\s+struct\s*\{[^}]*\}\s*(\w+)\s*;", text):
            self.aliases[name] = name
        for ret, name, params in re.findall(
            r"typedef\s+([\w\s\*]+?)\s*\(\s*\*\s*(\w+)\s*\)\s*\(([^)]*)\)\s*;", text
        ):
            self.pointers[name] = (ret, params)
        for ret, name, params in re.findall(
            r"typedef\s+([\w\s\*]+?)\s*\b(\w+TYPE)\s*\(([^)]*)\)\s*;", text
        ):
            self.functions[name] = (ret, params)
        for decl, name in re.findall(r"typedef\s+([\w\s\*]+?)\s*\b(\w+)\s*;", text):
            self.aliases.setdefault(name, decl.strip())

    def base(self, words):
        """The Rust type of a C type name (one or more words)."""
        name = " ".join(words)
        if name in self.pointers:
            return self.function_pointer(*self.pointers[name])
        if name in self.aliases and self.aliases[name] != name:
            return self.declaration(self.aliases[name])
        if name in C_TO_RUST:
            return C_TO_RUST[name]
        raise KeyError(f"no Rust type for the C type {name!r}")

    def known(self, words):
        name = " ".join(words)
        return name in self.pointers or name in self.aliases or name in C_TO_RUST

    def declaration(self, decl):
        """The Rust type of a C parameter or typedef declaration (its name, if any, dropped):
        `T*` and `T x[]` are pointers, `*const` when T is const-qualified."""
        tokens = re.findall(r"\w+|\*|\[\]|\.\.\.", decl)
        if tokens == ["..."]:
            return "..."
        words = []
        while tokens and re.fullmatch(r"\w+", tokens[0]):
            words.append(tokens.pop(0))
        const = "const" in words
        words = [w for w in words if w != "const"]
        if not self.known(words):  # the last word is the parameter's name
            words.pop()
        rust = self.base(words)
        for token in tokens:
            if token in ("*", "[]"):
                rust = f"*{'const' if const else 'mut'} {rust}"
                const = False
            elif token == "const":
                const = True
        return rust

    def parameters(self, params):
        params = params.strip()
        if params in ("", "void"):
            return []
        return [self.declaration(p) for p in params.split(",")]

    def signature(self, ret, params):
        ret = self.declaration(ret)
        tail = "" if ret == C_TO_RUST["void"] else f" -> {ret}"
        return f"({', '.join(self.parameters(params))}){tail}"

    def function_pointer(self, ret, params):
        return f'Option<unsafe extern "C" fn{self.signature(ret, params)}>'

    def function_type(self, name):
        return f'unsafe extern "C" fn{self.signature(*self.functions[name + "TYPE"])}'


def header_texts(version):
    names = {
        2: ["fmi2TypesPlatform.h", "fmi2FunctionTypes.h"],
        3: ["fmi3PlatformTypes.h", "fmi3FunctionTypes.h"],
    }[version]
    return [(HEADERS / name).read_text() for name in names]


def declared(version):
    """The functions fmiNFunctions.h declares (`FMIN_Export fmiNXxxTYPE fmiNXxx;`), FMI 2.0's
    Model Exchange section left out."""
    text = (HEADERS / f"fmi{version}Functions.h").read_text()
    if version == 2:
        # The headings also head the name-prefixing #defines above; the declarations come last.
        start, end = text.rindex(FMI2_ME_HEADING), text.rindex(FMI2_CS_HEADING)
        text = text[:start] + text[end:]
    found = re.findall(rf"FMI{version}_Export\s+(fmi{version}\w+)TYPE\s+(fmi{version}\w+);", text)
    assert all(t == n for t, n in found)
    return [name for _, name in found]


def rust_check(texts2, texts3):
    """The Rust file that fails to compile unless every export has its header's type."""
    lines = ["#![allow(non_camel_case_types, dead_code)]"]
    for version, texts in ((2, texts2), (3, texts3)):
        header = Header(texts)
        for name in declared(version):
            lines.append(f"pub type {name}TYPE = {header.function_type(name)};")
            lines.append(f"const _: {name}TYPE = plate_impact::fmi::fmi{version}::exports::{name};")
    return "\n".join(lines) + "\n"


@pytest.fixture(scope="module")
def rlib(fmu_path):
    """The crate's rlib and its dependency directory, as `cargo build --release --lib` leaves
    them (the FMU fixture has built them already, so this is a no-op build)."""
    out = subprocess.run(
        ["cargo", "build", "--release", "--lib", "--message-format=json"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    for line in out.splitlines():
        message = json.loads(line)
        if (
            message.get("reason") == "compiler-artifact"
            and message["target"]["name"] == "plate_impact"
        ):
            rlibs = [f for f in message["filenames"] if f.endswith(".rlib")]
            if rlibs:
                return pathlib.Path(rlibs[0])
    pytest.fail("cargo built no rlib of plate_impact")


def compile_check(source, rlib, tmp_path):
    path = tmp_path / "fmi_abi.rs"
    path.write_text(source)
    # The rustc of $RUSTC or the toolchain rustup picks in the crate, as cargo's was.
    return subprocess.run(
        [
            os.environ.get("RUSTC", "rustc"),
            "--edition",
            "2021",
            "--crate-type",
            "lib",
            "--crate-name",
            "fmi_abi",
            "--emit",
            "metadata",
            "-o",
            str(tmp_path / "libfmi_abi.rmeta"),
            "--extern",
            f"plate_impact={rlib}",
            "-L",
            f"dependency={rlib.parent / 'deps'}",
            "-L",
            f"dependency={rlib.parent}",
            str(path),
        ],
        cwd=ROOT,
        capture_output=True,
        text=True,
    )


@pytest.mark.parametrize("version,count", [(2, 34), (3, 75)])
def test_every_function_of_the_header_is_exported(version, count, unzipdir, unzipdir3):
    names = set(declared(version))
    assert len(names) == count
    # FMI 2.0 and FMI 3.0 name the platform directory differently.
    fmu, platform = (unzipdir, "linux64") if version == 2 else (unzipdir3, "x86_64-linux")
    library = pathlib.Path(fmu) / "binaries" / platform / "PlateImpact.so"
    symbols = subprocess.run(
        ["nm", "-D", "--defined-only", str(library)], capture_output=True, text=True, check=True
    ).stdout
    exported = set(re.findall(rf"\bT (fmi{version}\w+)$", symbols, re.M))
    assert exported == names, sorted(names ^ exported)


def test_no_function_type_is_missed():
    """The regexes find every fmiNXxxTYPE typedef of the headers (none skipped)."""
    for version in (2, 3):
        text = without_comments("\n".join(header_texts(version)))
        assert len(Header(header_texts(version)).functions) == text.count("TYPE") > 0


def test_every_signature_is_the_headers(rlib, tmp_path):
    done = compile_check(rust_check(header_texts(2), header_texts(3)), rlib, tmp_path)
    assert done.returncode == 0 and done.stderr == "", done.stderr


def test_the_callback_struct_has_the_c_size(rlib, tmp_path):
    """fmi2CallbackFunctions is mapped by name: its Rust size is the C compiler's."""
    program = tmp_path / "size.c"
    program.write_text(
        '#include <stdio.h>\n#include "fmi2Functions.h"\n'
        'int main(void) { printf("%zu", sizeof(fmi2CallbackFunctions)); }\n'
    )
    subprocess.run(
        [c_compiler(), f"-I{HEADERS}", str(program), "-o", str(tmp_path / "size")], check=True
    )
    c_size = int(
        subprocess.run([str(tmp_path / "size")], capture_output=True, text=True, check=True).stdout
    )
    source = (
        "const _: () = assert!(core::mem::size_of::<"
        f"{C_TO_RUST['fmi2CallbackFunctions']}>() == {c_size});\n"
    )
    done = compile_check(source, rlib, tmp_path)
    assert done.returncode == 0, done.stderr


def mutate(text, function, old, new):
    """`text` with `old` (spaces matching any white space) replaced by `new` in the typedef of
    `function`, where it must occur once."""
    typedef = re.search(rf"typedef[^;]*?\b{function}TYPE\s*\([^;]*;", text)
    pattern = r"\s+".join(map(re.escape, old.split()))
    changed, count = re.subn(pattern, lambda _: new, typedef[0])
    assert count == 1, (function, old)
    return text[: typedef.start()] + changed + text[typedef.end() :]


@pytest.mark.parametrize(
    "version,function,wrong",
    [
        (2, "fmi2DoStep", ("fmi2Real communicationStepSize", "float communicationStepSize")),
        (2, "fmi2GetReal", ("fmi2Real value[]", "const fmi2Real value[]")),
        (2, "fmi2GetBooleanStatus", ("fmi2Boolean* value", "fmi2Real* value")),
        (2, "fmi2Instantiate", ("fmi2Boolean visible", "fmi2Real visible")),
        (
            3,
            "fmi3DoStep",
            ("fmi3Float64 communicationStepSize", "fmi3Float32 communicationStepSize"),
        ),
        (3, "fmi3GetFloat64", ("size_t nValues", "fmi3UInt32 nValues")),
        (3, "fmi3GetBoolean", ("fmi3Boolean values[]", "fmi3Int32 values[]")),
        (
            3,
            "fmi3InstantiateCoSimulation",
            ("fmi3LogMessageCallback logMessage", "fmi3ClockUpdateCallback logMessage"),
        ),
        (3, "fmi3GetVersion", ("const char*", "char*")),
    ],
)
def test_a_wrong_signature_fails_the_compile(rlib, tmp_path, version, function, wrong):
    """The check bites: one type of the header changed, the compile fails naming the function."""
    texts = {2: header_texts(2), 3: header_texts(3)}
    texts[version][1] = mutate(texts[version][1], function, *wrong)
    done = compile_check(rust_check(texts[2], texts[3]), rlib, tmp_path)
    assert done.returncode != 0 and function in done.stderr, done.stderr
