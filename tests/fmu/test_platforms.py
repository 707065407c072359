"""The release FMUs of `package-fmu --all-platforms` (docs/platforms.md): both FMUs list every
platform; the shipped binaries carry no debug info; the x86_64 Linux library needs at most glibc
2.17 and the Windows DLL only system DLLs; and the C host of examples/c/, built for each platform,
gives the same trajectory over each binary: bit for bit on Windows (under Wine) as on x86_64
Linux, within a stated round-off tolerance on aarch64 Linux (under qemu-aarch64).

These run where the FMUs were packaged with PLATE_IMPACT_PLATFORMS=all (as .ci/run does); the
developer FMUs carry this machine's library only, so they are skipped there, saying so."""

import os
import pathlib
import re
import shutil
import subprocess
import zipfile

import fmpy
import pytest

from conftest import ROOT

pytestmark = pytest.mark.skipif(
    os.environ.get("PLATE_IMPACT_PLATFORMS") != "all",
    reason="the developer FMUs carry this machine's binary only: "
    "PLATE_IMPACT_PLATFORMS=all scripts/test-all (as .ci/run) tests the release FMUs",
)

SOURCE = ROOT / "examples" / "c" / "plate_host.c"
WIN32 = pathlib.Path(__file__).resolve().parent / "win32"
FMI2_HEADERS = pathlib.Path(fmpy.__file__).parent / "c-code"
FLAGS = ["-std=c11", "-Wall", "-Wextra", "-Werror", f"-I{FMI2_HEADERS}"]

FMI2_BINARIES = {"binaries/linux64/PlateImpact.so", "binaries/win64/PlateImpact.dll"}
FMI3_BINARIES = {
    "binaries/x86_64-linux/PlateImpact.so",
    "binaries/x86_64-windows/PlateImpact.dll",
    "binaries/aarch64-linux/PlateImpact.so",
}
# The glibc both Linux libraries are linked against (cargo zigbuild --target ...-gnu.2.17):
# RHEL 7, Ubuntu 14.04 (x86_64) or 18.04 (aarch64), Debian 8 and later.
GLIBC_MAX = (2, 17)
# What the Windows DLL may import: DLLs that every Windows 10 and later has (Rust's standard
# library takes ProcessPrng from bcryptprimitives.dll, msvcrt.dll is the C runtime of mingw-w64).
SYSTEM_DLLS = {
    "kernel32.dll",
    "ntdll.dll",
    "bcryptprimitives.dll",
    "msvcrt.dll",
    "ws2_32.dll",
    "userenv.dll",
    "advapi32.dll",
    "api-ms-win-core-synch-l1-2-0.dll",
}
# aarch64 against x86_64, each output's largest difference over the 1000 points, relative to the
# output's largest |value|. Measured: 1.5e-9 (corners) and 5.9e-9 (energy); docs/platforms.md:
# faer's NEON kernels sum in another order than its AVX2 ones, from the first step, and the same
# x86_64 library on a processor without AVX2 (qemu-x86_64 -cpu qemu64) differs from itself by
# 5.4e-9 and 2.1e-8 the same way. The contact steps amplify last-bit differences as a 1e-15 m
# shift of the base does (1.2e-8 of the energy's scale, tests/fmu/test_reference.py). 1e-7 is 17 x
# the largest aarch64 difference, 5 x the no-AVX2 one, and far below what a real fault does (a
# wrong element or scheme moves the corners by millimetres, 0.1 of their scale).
AARCH64_RTOL = 1e-7


def tool(name, package):
    """The path of the command `name`, or a failure naming the Debian package to install."""
    found = shutil.which(name)
    if not found:
        pytest.fail(f"{name} is not installed (Debian: apt-get install {package}; .ci/run does)")
    return found


def run(command, **kwargs):
    done = subprocess.run([str(c) for c in command], capture_output=True, text=True, **kwargs)
    assert done.returncode == 0, (
        f"{' '.join(map(str, command))} failed:\n{done.stdout}\n{done.stderr}"
    )
    return done


def elf_sections(path):
    return re.findall(
        r"^\s*\d+\s+(\S+)", run([tool("objdump", "binutils"), "-h", path]).stdout, re.MULTILINE
    )


def glibc_versions(path):
    """The GLIBC symbol versions the library needs (objdump -T), as (major, minor) tuples."""
    text = run([tool("objdump", "binutils"), "-T", path]).stdout
    return {tuple(int(x) for x in v.split(".")[:2]) for v in re.findall(r"GLIBC_([\d.]+)", text)}


def soname(path):
    text = run([tool("objdump", "binutils"), "-p", path]).stdout
    match = re.search(r"^\s*SONAME\s+(\S+)", text, re.MULTILINE)
    return match and match[1]


def test_both_fmus_list_every_platform(fmu_path, fmu3_path):
    with zipfile.ZipFile(fmu_path) as z:
        assert {n for n in z.namelist() if n.startswith("binaries/")} == FMI2_BINARIES
    with zipfile.ZipFile(fmu3_path) as z:
        assert {n for n in z.namelist() if n.startswith("binaries/")} == FMI3_BINARIES
    # fmpy reads both and knows the x86_64 platforms (it has no name for aarch64-linux).
    for path, version in [(fmu_path, "2.0"), (fmu3_path, "3.0")]:
        assert fmpy.read_model_description(path).fmiVersion == version
        assert sorted(fmpy.supported_platforms(path)) == ["linux64", "win64"], path


def test_the_linux_libraries_need_at_most_glibc_2_17_and_carry_no_debug_info(unzipdir, unzipdir3):
    x86_64 = pathlib.Path(unzipdir) / "binaries" / "linux64" / "PlateImpact.so"
    # Both FMUs carry the same x86_64 library.
    assert (
        x86_64.read_bytes()
        == (pathlib.Path(unzipdir3) / "binaries" / "x86_64-linux" / "PlateImpact.so").read_bytes()
    )
    aarch64 = pathlib.Path(unzipdir3) / "binaries" / "aarch64-linux" / "PlateImpact.so"
    for library in (x86_64, aarch64):
        versions = glibc_versions(library)
        assert versions and max(versions) <= GLIBC_MAX, (library, sorted(versions))
        sections = elf_sections(library)
        assert ".text" in sections and ".dynsym" in sections, library
        assert not [s for s in sections if s.startswith(".debug") or s == ".symtab"], sections
        # A host linked with -l:PlateImpact.so records this name and finds the file by it.
        assert soname(library) == "PlateImpact.so", library


def test_the_windows_dll_imports_only_system_dlls_and_carries_no_debug_info(unzipdir, unzipdir3):
    dll = pathlib.Path(unzipdir) / "binaries" / "win64" / "PlateImpact.dll"
    assert (
        dll.read_bytes()
        == (
            pathlib.Path(unzipdir3) / "binaries" / "x86_64-windows" / "PlateImpact.dll"
        ).read_bytes()
    )
    objdump = tool("x86_64-w64-mingw32-objdump", "binutils-mingw-w64-x86-64")
    headers = run([objdump, "-p", dll]).stdout
    imports = {name.lower() for name in re.findall(r"DLL Name: (\S+)", headers)}
    assert "kernel32.dll" in imports and imports <= SYSTEM_DLLS, sorted(imports)
    exports = set(re.findall(r"^\s*\[\s*\d+\]\s+(fmi[23]\w+)", headers, re.MULTILINE))
    assert {"fmi2Instantiate", "fmi2DoStep", "fmi3InstantiateCoSimulation", "fmi3DoStep"} <= exports
    sections = re.findall(r"^\s*\d+\s+(\S+)", run([objdump, "-h", dll]).stdout, re.MULTILINE)
    assert ".text" in sections and not [s for s in sections if s.startswith(".debug")], sections


def parse_host(stdout):
    """The host's points (k, y1, y2, y3), exact, and its summary line."""
    points = [
        tuple([int(m[1])] + [float.fromhex(x) for x in m[2].split()])
        for m in re.finditer(r"^point (\d+) (\S+ \S+ \S+)$", stdout, re.MULTILINE)
    ]
    assert len(points) == 1000, stdout[-2000:]
    assert [p[0] for p in points] == list(range(1, 1001))
    summary = stdout.splitlines()[-1]
    assert summary.endswith("run restored from t = 0.5 s repeats bit for bit"), summary
    return points, summary


@pytest.fixture(scope="module")
def linux_points(unzipdir, tmp_path_factory):
    """The host on x86_64 Linux over binaries/linux64 (the glibc 2.17 library)."""
    host = tmp_path_factory.mktemp("host-linux") / "plate_host"
    run([tool("cc", "gcc"), *FLAGS, SOURCE, "-o", host, "-ldl"])
    return parse_host(run([host, unzipdir, "--trajectory"], timeout=300).stdout)


def test_the_windows_dll_under_wine_gives_the_linux_trajectory_bit_for_bit(
    unzipdir, linux_points, tmp_path_factory
):
    wine = tool("wine", "wine64")
    out = tmp_path_factory.mktemp("host-windows")
    mingw = tool("x86_64-w64-mingw32-gcc", "gcc-mingw-w64-x86-64")
    # The unchanged host over the test-only dlfcn.h shim; ProcessPrng's stub next to it.
    run([mingw, *FLAGS, f"-I{WIN32}", SOURCE, "-o", out / "plate_host.exe"])
    run(
        [
            mingw,
            "-std=c11",
            "-Wall",
            "-Wextra",
            "-Werror",
            "-shared",
            WIN32 / "bcryptprimitives.c",
            "-o",
            out / "bcryptprimitives.dll",
            "-lbcrypt",
        ]
    )
    env = dict(
        os.environ,
        WINEPREFIX=str(out / "wineprefix"),
        WINEDEBUG="-all",
        WINEDLLOVERRIDES="bcryptprimitives=n",
    )
    # Wine maps the Unix root to drive Z:.
    done = run(
        [
            wine,
            out / "plate_host.exe",
            "Z:" + str(pathlib.Path(unzipdir).resolve()),
            "--trajectory",
        ],
        env=env,
        timeout=600,
    )
    points, summary = parse_host(done.stdout)
    reference, linux_summary = linux_points
    differing = [(p, q) for p, q in zip(points, reference) if p != q]
    assert not differing, f"{len(differing)} of 1000 points differ, first: {differing[0]}"
    assert summary == linux_summary


def test_the_aarch64_library_under_qemu_agrees_with_x86_64(
    unzipdir, unzipdir3, linux_points, tmp_path_factory
):
    qemu = tool("qemu-aarch64", "qemu-user")
    gcc = tool("aarch64-linux-gnu-gcc", "gcc-aarch64-linux-gnu")
    out = tmp_path_factory.mktemp("host-aarch64")
    host = out / "plate_host"
    # The FMI 2.0 host over the FMI 3.0 FMU's aarch64 binary (the same library: it exports both),
    # placed beside the FMI 2.0 description, whose guid the host reads and the library checks.
    fmu = out / "fmu"
    (fmu / "binaries" / "aarch64-linux").mkdir(parents=True)
    shutil.copy(pathlib.Path(unzipdir) / "modelDescription.xml", fmu)
    shutil.copy(
        pathlib.Path(unzipdir3) / "binaries" / "aarch64-linux" / "PlateImpact.so",
        fmu / "binaries" / "aarch64-linux",
    )
    run(
        [
            gcc,
            *FLAGS,
            '-DPLATE_HOST_BINARY="binaries/aarch64-linux/PlateImpact.so"',
            SOURCE,
            "-o",
            host,
            "-ldl",
        ]
    )
    done = run([qemu, "-L", "/usr/aarch64-linux-gnu", host, fmu, "--trajectory"], timeout=1200)
    points, _ = parse_host(done.stdout)
    reference, _ = linux_points
    for column, name in enumerate(
        ["corner1.displacement", "corner2.displacement", "energy.total"], start=1
    ):
        scale = max(abs(q[column]) for q in reference)
        worst = max(abs(p[column] - q[column]) for p, q in zip(points, reference)) / scale
        assert worst <= AARCH64_RTOL, f"{name}: aarch64 differs by {worst:.2e} of its scale"
