//! Builds both FMUs into `target/fmu/` (the target directory follows `CARGO_TARGET_DIR`; the
//! release builds' own can be elsewhere, `PLATE_IMPACT_CROSS_TARGET_DIR`):
//! * `PlateImpact.fmu`, FMI 2.0 Co-Simulation: `modelDescription.xml` (from
//!   `modelDescription/modelDescription.xml`) and its binaries under `binaries/linux64/` and
//!   `binaries/win64/` (FMI 2.0 §2.3);
//! * `PlateImpact-fmi3.fmu`, FMI 3.0 Co-Simulation: `modelDescription.xml` (from
//!   `modelDescription/modelDescription-fmi3.xml`) and its binaries under
//!   `binaries/<platform tuple>/` (FMI 3.0 §2.5).
//!
//! Both also carry `documentation/index.html` and, under `extra/org.fmi-standard.fmi-ls-ref/`, the
//! shipped scenes as parameter sets with their reference results ([`contents`]), and their
//! licences under `documentation/licenses/` ([`licenses`]). `package-fmu --write-docs` only
//! rewrites the variable tables of the docs from the model descriptions ([`documentation`]).
//!
//! The model descriptions are those the library was built with (`SHIPPED_FMI2_XML`,
//! `SHIPPED_FMI3_XML`: the guid and instantiationToken derived from their content by build.rs), and
//! each binary must carry both tokens, so that an FMU never pairs a description with a binary
//! built from another. Packaging stamps their `version` with the commit (`1.1.0-dev+<commit>`
//! between releases) and sets `generationDateAndTime`, after checking that the repository's
//! version, CHANGELOG.md and release tags agree ([`version`]); `--release` (what
//! `scripts/release` runs) also refuses what stands in a release's way, before any build.
//!
//! Every binary is the same cdylib (it exports the FMI 2.0 and the FMI 3.0 functions), built for
//! one platform. Two modes (docs/platforms.md):
//! * `cargo run --release --bin package-fmu`, the developer FMUs: `cargo build --release --lib`,
//!   this machine's x86_64 Linux library only, with debug info, linked against this machine's glibc;
//! * `cargo run --release --bin package-fmu -- --all-platforms` (or `PLATE_IMPACT_PLATFORMS=all`;
//!   `--release` implies it), the release FMUs: three binaries (five entries in the two FMUs) built with the `release-fmu`
//!   profile (the release profile without debug info, stripped), by cross toolchains from the
//!   package registries: x86_64 Linux and aarch64 Linux (FMI 3.0 only: FMI 2.0 has no standard
//!   folder for it) linked by zig against glibc 2.17 (`cargo zigbuild`), x86_64 Windows linked by
//!   mingw-w64; each compiled with the rustup target when it is installed, else with Debian's Rust
//!   and `-Zbuild-std`. It says what it runs and stops, naming the package to install, when a tool
//!   is missing.

#![deny(unsafe_code)]

#[path = "package-fmu/contents.rs"]
mod contents;
#[path = "package-fmu/documentation.rs"]
mod documentation;
#[path = "package-fmu/licenses.rs"]
mod licenses;
#[path = "package-fmu/version.rs"]
mod version;

use plate_impact::fmi::variables::{
    FMI2, FMI3, MODEL_IDENTIFIER, SHIPPED_FMI2_XML, SHIPPED_FMI3_XML,
};
use std::ffi::OsString;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::time::Instant;
use zip::write::SimpleFileOptions;
use zip::CompressionMethod;

/// The profile of the release binaries (Cargo.toml): release without debug info, stripped.
const RELEASE_PROFILE: &str = "release-fmu";
/// The oldest glibc the release Linux libraries run on (RHEL 7, Debian 8 and later).
const GLIBC: &str = "2.17";
/// Where Debian's `rustc-web` and `cargo-web` put the compiler used with `-Zbuild-std`.
const DEBIAN_CARGO: &str = "/usr/bin/cargo";
/// Where Debian's `rust-web-src` puts the standard library's sources that `-Zbuild-std` compiles.
const DEBIAN_RUST_SRC: &str = "/usr/lib/rustlib/src/rust/library";

/// One platform of the release FMUs.
struct Platform {
    /// FMI 3.0 platform tuple, the folder under `binaries/` of the FMI 3.0 FMU.
    fmi3: &'static str,
    /// FMI 2.0 folder, where the standard has one.
    fmi2: Option<&'static str>,
    /// Rust target triple.
    triple: &'static str,
    /// What links the binary.
    linker: Linker,
}

/// What links a release binary. The compiler is the rustup target when installed, else Debian's
/// Rust with `-Zbuild-std`.
enum Linker {
    /// zig, through `cargo zigbuild --target <triple>.<GLIBC>`: links against the symbol versions
    /// of glibc `GLIBC`.
    Zig,
    /// The C cross compiler `command`, from the Debian package `package`.
    Gcc {
        command: &'static str,
        package: &'static str,
    },
}

const PLATFORMS: [Platform; 3] = [
    Platform {
        fmi3: "x86_64-linux",
        fmi2: Some("linux64"),
        triple: "x86_64-unknown-linux-gnu",
        linker: Linker::Zig,
    },
    Platform {
        fmi3: "x86_64-windows",
        fmi2: Some("win64"),
        triple: "x86_64-pc-windows-gnu",
        linker: Linker::Gcc {
            command: "x86_64-w64-mingw32-gcc",
            package: "gcc-mingw-w64-x86-64",
        },
    },
    Platform {
        fmi3: "aarch64-linux",
        fmi2: None,
        triple: "aarch64-unknown-linux-gnu",
        linker: Linker::Zig,
    },
];

/// One binary to pack: the FMU folders it goes to (FMI 2.0, if any; FMI 3.0) and its bytes.
struct Binary {
    fmi2: Option<&'static str>,
    fmi3: &'static str,
    /// `so` or `dll`.
    extension: &'static str,
    bytes: Vec<u8>,
}

/// The file name cargo gives the cdylib on `triple`.
fn cdylib_name(triple: &str) -> &'static str {
    if triple.contains("windows") {
        "plate_impact.dll"
    } else {
        "libplate_impact.so"
    }
}

/// Runs `command`, echoing it first, and fails naming it unless it succeeds.
fn run_command(mut command: Command) -> Result<(), String> {
    let shown = format!("{command:?}");
    eprintln!("package-fmu: running {shown}");
    let status = command
        .status()
        .map_err(|e| format!("cannot run {shown}: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("{shown} failed ({status})"))
    }
}

fn read(path: &Path) -> Result<Vec<u8>, String> {
    std::fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()))
}

/// `name` on `PATH`, if there.
fn on_path(name: &str, path: &OsString) -> Option<PathBuf> {
    std::env::split_paths(path)
        .map(|dir| dir.join(name))
        .find(|file| file.is_file())
}

/// The Rust target of the developer build's binary.
const HOST_TRIPLE: &str = "x86_64-unknown-linux-gnu";

/// The developer build: `cargo build --release --lib` for this machine.
fn host_binary(root: &Path, target: &Path) -> Result<Binary, String> {
    if !cfg!(all(target_os = "linux", target_arch = "x86_64")) {
        return Err("package-fmu supports x86_64 Linux hosts only".into());
    }
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let mut command = Command::new(cargo);
    command
        .args(["build", "--release", "--lib"])
        .current_dir(root);
    run_command(command)?;
    Ok(Binary {
        fmi2: Some("linux64"),
        fmi3: "x86_64-linux",
        extension: "so",
        bytes: read(&target.join("release").join(cdylib_name("")))?,
    })
}

/// The tools of the release build, found up front so that a missing one is named before any
/// build starts.
struct Tools {
    /// PATH for the builds: the project's `.venv/bin` (where scripts/python-env installs
    /// cargo-zigbuild and zig) before the caller's PATH.
    path: OsString,
    /// rustup's (or the caller's) cargo and rustc.
    cargo: OsString,
    rustc: OsString,
}

impl Tools {
    fn find(root: &Path) -> Result<Self, String> {
        let caller = std::env::var_os("PATH").unwrap_or_default();
        let venv = root.join(".venv").join("bin");
        let path =
            std::env::join_paths(std::iter::once(venv).chain(std::env::split_paths(&caller)))
                .map_err(|e| format!("cannot extend PATH: {e}"))?;
        let tools = Tools {
            path,
            cargo: std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()),
            rustc: std::env::var_os("RUSTC").unwrap_or_else(|| "rustc".into()),
        };
        let mut missing = Vec::new();
        if on_path("cargo-zigbuild", &tools.path).is_none() {
            missing.push(
                "cargo-zigbuild and zig (pip install cargo-zigbuild ziglang, as .ci/run does)"
                    .to_string(),
            );
        }
        let debian = Path::new(DEBIAN_CARGO).is_file() && Path::new(DEBIAN_RUST_SRC).is_dir();
        for platform in &PLATFORMS {
            if let Linker::Gcc { command, package } = platform.linker {
                if on_path(command, &tools.path).is_none() {
                    missing.push(format!("{command} (Debian: apt-get install {package})"));
                }
            }
            if !tools.has_rustup_target(platform.triple) && !debian {
                missing.push(format!(
                    "the Rust standard library for {} (rustup target add {0}, or Debian: \
                     apt-get install rustc-web cargo-web rust-web-src)",
                    platform.triple
                ));
            }
        }
        if missing.is_empty() {
            Ok(tools)
        } else {
            Err(format!(
                "--all-platforms needs tools that are not installed:\n  {}",
                missing.join("\n  ")
            ))
        }
    }

    /// Whether the caller's Rust toolchain has the standard library for `triple` (a rustup
    /// target).
    fn has_rustup_target(&self, triple: &str) -> bool {
        Command::new(&self.rustc)
            .args(["--print", "target-libdir", "--target", triple])
            .output()
            .ok()
            .filter(|out| out.status.success())
            .map(|out| PathBuf::from(String::from_utf8_lossy(&out.stdout).trim()))
            .is_some_and(|dir| dir.is_dir())
    }

    /// Builds the release binary of `platform`; returns the path of the cdylib.
    fn build(&self, root: &Path, target: &Path, platform: &Platform) -> Result<PathBuf, String> {
        let triple = platform.triple;
        let (subcommand, target_arg, linked_by) = match platform.linker {
            Linker::Zig => (
                "zigbuild",
                format!("{triple}.{GLIBC}"),
                format!("zig against glibc {GLIBC}"),
            ),
            Linker::Gcc { command, .. } => ("build", triple.to_string(), command.to_string()),
        };
        let (mut command, target_dir) = if self.has_rustup_target(triple) {
            eprintln!(
                "package-fmu: {}: the rustup target {triple}, linked by {linked_by}",
                platform.fmi3
            );
            let mut command = Command::new(&self.cargo);
            command.arg(subcommand).env("PATH", &self.path);
            (command, target.to_path_buf())
        } else {
            // Debian's rustc has no prebuilt standard library for other targets: cargo compiles
            // it from rust-web-src (-Zbuild-std, unlocked on this stable compiler by
            // RUSTC_BOOTSTRAP=1). Its cargo and rustc come first on PATH after .venv/bin (whose
            // python3 has zig for cargo-zigbuild, which runs the cargo that called it). Its own
            // target directory keeps its artifacts apart from the rustup toolchain's.
            eprintln!(
                "package-fmu: {}: Debian's Rust ({}) with -Zbuild-std (RUSTC_BOOTSTRAP=1), \
                 linked by {linked_by}",
                platform.fmi3,
                debian_rustc_version()
            );
            let mut paths: Vec<PathBuf> = std::env::split_paths(&self.path).collect();
            paths.insert(1, PathBuf::from("/usr/bin"));
            let path =
                std::env::join_paths(paths).map_err(|e| format!("cannot extend PATH: {e}"))?;
            let mut command = Command::new(DEBIAN_CARGO);
            command
                .args([subcommand, "-Zbuild-std"])
                .env("PATH", path)
                .env("RUSTC_BOOTSTRAP", "1")
                .env_remove("CARGO")
                .env_remove("RUSTC")
                .env_remove("RUSTDOC")
                .env_remove("RUSTUP_TOOLCHAIN");
            (command, target.join("build-std"))
        };
        command
            .args(["--profile", RELEASE_PROFILE, "--lib", "--target"])
            .arg(target_arg)
            .arg("--target-dir")
            .arg(&target_dir)
            .current_dir(root);
        if let Linker::Gcc {
            command: linker, ..
        } = platform.linker
        {
            let variable = format!(
                "CARGO_TARGET_{}_LINKER",
                triple.to_uppercase().replace('-', "_")
            );
            command.env(variable, linker);
        }
        let start = Instant::now();
        run_command(command)?;
        eprintln!(
            "package-fmu: {} built in {:.0} s",
            platform.fmi3,
            start.elapsed().as_secs_f64()
        );
        Ok(target_dir
            .join(triple)
            .join(RELEASE_PROFILE)
            .join(cdylib_name(triple)))
    }
}

/// `rustc --version` of Debian's compiler, for the log.
fn debian_rustc_version() -> String {
    Command::new("/usr/bin/rustc")
        .arg("--version")
        .output()
        .map(|out| String::from_utf8_lossy(&out.stdout).trim().to_string())
        .unwrap_or_else(|e| format!("rustc --version failed: {e}"))
}

/// The release builds, one binary per platform, under the cargo target directory `target`.
fn release_binaries(root: &Path, target: &Path) -> Result<Vec<Binary>, String> {
    let tools = Tools::find(root)?;
    PLATFORMS
        .iter()
        .map(|platform| {
            let path = tools.build(root, target, platform)?;
            Ok(Binary {
                fmi2: platform.fmi2,
                fmi3: platform.fmi3,
                extension: if platform.triple.contains("windows") {
                    "dll"
                } else {
                    "so"
                },
                bytes: read(&path)?,
            })
        })
        .collect()
}

/// Checks that every binary carries the tokens of both model descriptions (the instantiation
/// functions compare the importer's token with them): a binary built from other descriptions, or a
/// stale one, would refuse every instantiation.
fn check_tokens(binaries: &[Binary]) -> Result<(), String> {
    for binary in binaries {
        for token in [FMI2.token, FMI3.token] {
            let found = binary
                .bytes
                .windows(token.len())
                .any(|w| w == token.as_bytes());
            if !found {
                return Err(format!(
                    "the {} binary does not carry the token {token} of this build's model \
                     descriptions: it was built from other sources",
                    binary.fmi3
                ));
            }
        }
    }
    Ok(())
}

/// Writes the FMU `file` into `out_dir`: the model description `description`, the binaries, each
/// under `binaries/<folder>/` where `folder` gives it one, and the `extra` files.
fn write_fmu(
    out_dir: &Path,
    file: &str,
    description: &str,
    binaries: &[Binary],
    folder: impl Fn(&Binary) -> Option<&'static str>,
    extra: &[contents::Entry],
) -> Result<PathBuf, String> {
    let path = out_dir.join(file);
    let out = std::fs::File::create(&path)
        .map_err(|e| format!("cannot create {}: {e}", path.display()))?;
    let mut zip = zip::ZipWriter::new(out);
    let options = SimpleFileOptions::default().compression_method(CompressionMethod::Deflated);
    let mut entries = vec![("modelDescription.xml".to_string(), description.as_bytes())];
    for binary in binaries {
        if let Some(folder) = folder(binary) {
            entries.push((
                format!("binaries/{folder}/{MODEL_IDENTIFIER}.{}", binary.extension),
                &binary.bytes,
            ));
        }
    }
    for (name, bytes) in extra {
        entries.push((name.clone(), bytes));
    }
    for (name, bytes) in entries {
        zip.start_file(name.as_str(), options)
            .and_then(|()| zip.write_all(bytes).map_err(Into::into))
            .map_err(|e| format!("cannot write {name} into {}: {e}", path.display()))?;
    }
    zip.finish()
        .map_err(|e| format!("cannot finish {}: {e}", path.display()))?;
    Ok(path)
}

/// What the command line asks for.
struct Options {
    /// The release FMUs: `--all-platforms` or `PLATE_IMPACT_PLATFORMS=all`.
    all_platforms: bool,
    /// `--release`: the FMUs of a release, which `version::release_problems` must allow; implies
    /// `--all-platforms`.
    release: bool,
    /// `--write-docs`: rewrite the variable tables of the docs, package nothing.
    write_docs: bool,
}

fn options() -> Result<Options, String> {
    let mut all = match std::env::var("PLATE_IMPACT_PLATFORMS").as_deref() {
        Ok("all") => true,
        Ok("" | "host") | Err(_) => false,
        Ok(other) => {
            return Err(format!(
                "PLATE_IMPACT_PLATFORMS={other}: expected `all` or `host`"
            ))
        }
    };
    let mut write_docs = false;
    let mut release = false;
    for arg in std::env::args().skip(1) {
        match arg.as_str() {
            "--all-platforms" => all = true,
            "--release" => release = true,
            "--write-docs" => write_docs = true,
            _ => {
                return Err(format!(
                    "unknown argument {arg} (the arguments are --all-platforms, --release and \
                     --write-docs)"
                ))
            }
        }
    }
    Ok(Options {
        all_platforms: all || release,
        release,
        write_docs,
    })
}

/// Rewrites the variable table of each of [`documentation::TABLE_FILES`] from the model
/// descriptions; returns the files.
fn write_docs(root: &Path) -> Result<Vec<PathBuf>, String> {
    let table = documentation::variable_table(&FMI2, &FMI3);
    documentation::TABLE_FILES
        .iter()
        .map(|file| {
            let path = root.join(file);
            let text =
                std::fs::read_to_string(&path).map_err(|e| format!("cannot read {file}: {e}"))?;
            std::fs::write(&path, documentation::with_table(file, &text, &table)?)
                .map_err(|e| format!("cannot write {file}: {e}"))?;
            Ok(path)
        })
        .collect()
}

/// The attributes of `<fmiModelDescription>` that say whose the FMU is: present in both model
/// descriptions, and the same.
const IDENTITY: [&str; 3] = ["author", "copyright", "license"];

/// The value of the attribute `name` of `<fmiModelDescription>` in `xml`, if declared.
fn root_attribute<'a>(xml: &'a str, name: &str) -> Option<&'a str> {
    let start = xml.find("<fmiModelDescription")?;
    let tag = &xml[start..start + xml[start..].find('>')?];
    let pattern = format!("{name}=\"");
    let at = tag
        .match_indices(&pattern)
        .map(|(i, _)| i)
        .find(|&i| tag[..i].ends_with(char::is_whitespace))?;
    let value = &tag[at + pattern.len()..];
    value.find('"').map(|end| &value[..end])
}

/// The model description `xml` (FMI `fmi`) as the FMU ships it: `version` stamped with the build
/// (`build.version`, module `version`) and `generationDateAndTime` the commit's time, when known.
/// Checks that the hand-kept file declares the crate's version (one version for the library and
/// both FMUs), says whose the FMU is ([`IDENTITY`]), and leaves the generation time to the build.
fn shipped_description(xml: &str, fmi: &str, build: &version::Build) -> Result<String, String> {
    let crate_version = env!("CARGO_PKG_VERSION");
    let declared = format!("\n  version=\"{crate_version}\"\n");
    if root_attribute(xml, "version") != Some(crate_version) || !xml.contains(&declared) {
        return Err(format!(
            "the FMI {fmi} model description does not declare version=\"{crate_version}\" on a \
             line of its own, the crate's version (Cargo.toml): set the same version in all three"
        ));
    }
    for name in IDENTITY {
        if root_attribute(xml, name).is_none_or(str::is_empty) {
            return Err(format!(
                "the FMI {fmi} model description does not say its {name}: every FMU names its \
                 author, copyright and license"
            ));
        }
    }
    if root_attribute(xml, "generationDateAndTime").is_some() {
        return Err(format!(
            "the FMI {fmi} model description declares generationDateAndTime: the build sets it \
             (the commit's time)"
        ));
    }
    let mut stamped = format!("\n  version=\"{}\"\n", build.version);
    if let Some(commit) = &build.commit {
        stamped.push_str(&format!("  generationDateAndTime=\"{}\"\n", commit.time));
    }
    Ok(xml.replacen(&declared, &stamped, 1))
}

/// Checks that both model descriptions say the same of whose the FMU is ([`IDENTITY`]).
fn check_same_identity(fmi2: &str, fmi3: &str) -> Result<(), String> {
    for name in IDENTITY {
        let (a, b) = (root_attribute(fmi2, name), root_attribute(fmi3, name));
        if a != b {
            return Err(format!(
                "the model descriptions disagree on {name}: {a:?} (FMI 2.0), {b:?} (FMI 3.0)"
            ));
        }
    }
    Ok(())
}

/// Where the release builds keep their cargo target directories: `PLATE_IMPACT_CROSS_TARGET_DIR`
/// when set (CI points it at a cache outside the clone, reused by later runs on the same machine:
/// cargo's fingerprints decide what is rebuilt, docs/testing.md), else the target directory; a
/// relative path is relative to the repository root, as for `CARGO_TARGET_DIR`.
fn cross_target_dir(root: &Path, target: &Path) -> PathBuf {
    std::env::var_os("PLATE_IMPACT_CROSS_TARGET_DIR")
        .filter(|dir| !dir.is_empty())
        .map(|dir| root.join(dir))
        .unwrap_or_else(|| target.to_path_buf())
}

/// What the FMUs will say about this build: the crate's version stamped with the commit, after
/// checking that CHANGELOG.md and the release tags agree with it, and for a release that nothing
/// stands in its way.
fn build(root: &Path, release: bool) -> Result<version::Build, String> {
    let crate_version = env!("CARGO_PKG_VERSION");
    let changelog = std::fs::read_to_string(root.join("CHANGELOG.md"))
        .map_err(|e| format!("cannot read CHANGELOG.md: {e}"))?;
    let commit = version::commit(root, crate_version);
    version::check_repository(crate_version, &changelog, commit.as_ref())?;
    let repository = env!("CARGO_PKG_REPOSITORY");
    if release {
        let problems =
            version::release_problems(crate_version, &changelog, commit.as_ref(), repository);
        if !problems.is_empty() {
            return Err(format!(
                "cannot release {crate_version}:\n  {}",
                problems.join("\n  ")
            ));
        }
    }
    Ok(version::Build {
        version: version::stamped(crate_version, commit.as_ref(), release),
        commit,
        repository,
    })
}

fn run() -> Result<Vec<PathBuf>, String> {
    let options = options()?;
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    if options.write_docs {
        return write_docs(root);
    }
    let build = build(root, options.release)?;
    eprintln!("package-fmu: PlateImpact {}", build.version);
    let fmi2 = shipped_description(SHIPPED_FMI2_XML, "2.0", &build)?;
    let fmi3 = shipped_description(SHIPPED_FMI3_XML, "3.0", &build)?;
    check_same_identity(&fmi2, &fmi3)?;
    // The extra files first: a stale docs table stops packaging before any build.
    let mut extra = contents::entries(root, &build)?;
    let triples: Vec<&str> = if options.all_platforms {
        PLATFORMS.iter().map(|p| p.triple).collect()
    } else {
        vec![HOST_TRIPLE]
    };
    extra.extend(licenses::entries(root, &build.version, &triples)?);
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .map(|t| if t.is_absolute() { t } else { root.join(t) })
        .unwrap_or_else(|| root.join("target"));
    let binaries = if options.all_platforms {
        release_binaries(root, &cross_target_dir(root, &target))?
    } else {
        vec![host_binary(root, &target)?]
    };
    check_tokens(&binaries)?;
    let out_dir = target.join("fmu");
    std::fs::create_dir_all(&out_dir)
        .map_err(|e| format!("cannot create {}: {e}", out_dir.display()))?;
    Ok(vec![
        write_fmu(
            &out_dir,
            &format!("{MODEL_IDENTIFIER}.fmu"),
            &fmi2,
            &binaries,
            |b| b.fmi2,
            &extra,
        )?,
        write_fmu(
            &out_dir,
            &format!("{MODEL_IDENTIFIER}-fmi3.fmu"),
            &fmi3,
            &binaries,
            |b| Some(b.fmi3),
            &extra,
        )?,
    ])
}

fn main() -> ExitCode {
    match run() {
        Ok(fmus) => {
            for fmu in fmus {
                println!("{}", fmu.display());
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("package-fmu: {e}");
            ExitCode::FAILURE
        }
    }
}
