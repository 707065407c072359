//! Builds both FMUs: `cargo run --release --bin package-fmu`.
//!
//! Runs `cargo build --release --lib` (the cdylib, which exports the FMI 2.0 and the FMI 3.0
//! functions), then writes two zip archives into `target/fmu/`:
//! * `PlateImpact.fmu`, FMI 2.0 Co-Simulation: `modelDescription.xml` (from
//!   `modelDescription/modelDescription.xml`) and `binaries/linux64/PlateImpact.so` (FMI 2.0 §2.3);
//! * `PlateImpact-fmi3.fmu`, FMI 3.0 Co-Simulation: `modelDescription.xml` (from
//!   `modelDescription/modelDescription-fmi3.xml`) and `binaries/x86_64-linux/PlateImpact.so`
//!   (FMI 3.0 §2.5, platform tuples).
//!
//! The target directory follows `CARGO_TARGET_DIR` when set.

use plate_impact::fmi::variables::MODEL_IDENTIFIER;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use zip::write::SimpleFileOptions;
use zip::CompressionMethod;

/// One FMU to write: its file name, its model description and the binaries folder of its version.
struct Fmu {
    file: String,
    description: &'static str,
    platform: &'static str,
}

/// The shared-library name of the cdylib and the FMU platform folders (FMI 2.0, FMI 3.0) of the
/// platform we run on.
fn platform() -> Result<(&'static str, [&'static str; 2]), String> {
    if cfg!(all(target_os = "linux", target_arch = "x86_64")) {
        Ok(("libplate_impact.so", ["linux64", "x86_64-linux"]))
    } else {
        Err("package-fmu supports linux x86_64 only so far".into())
    }
}

/// Writes `fmu` into `out_dir` with the shared library `binary`.
fn write_fmu(root: &Path, out_dir: &Path, fmu: &Fmu, binary: &[u8]) -> Result<PathBuf, String> {
    let description_path = root.join(fmu.description);
    let description = std::fs::read(&description_path)
        .map_err(|e| format!("cannot read {}: {e}", description_path.display()))?;
    let path = out_dir.join(&fmu.file);
    let file = std::fs::File::create(&path)
        .map_err(|e| format!("cannot create {}: {e}", path.display()))?;
    let mut zip = zip::ZipWriter::new(file);
    let options = SimpleFileOptions::default().compression_method(CompressionMethod::Deflated);
    let entries = [
        ("modelDescription.xml".to_string(), description.as_slice()),
        (
            format!("binaries/{}/{MODEL_IDENTIFIER}.so", fmu.platform),
            binary,
        ),
    ];
    for (name, bytes) in entries {
        zip.start_file(name.as_str(), options)
            .and_then(|()| zip.write_all(bytes).map_err(Into::into))
            .map_err(|e| format!("cannot write {name} into {}: {e}", path.display()))?;
    }
    zip.finish()
        .map_err(|e| format!("cannot finish {}: {e}", path.display()))?;
    Ok(path)
}

fn run() -> Result<Vec<PathBuf>, String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .map(|t| if t.is_absolute() { t } else { root.join(t) })
        .unwrap_or_else(|| root.join("target"));
    let (library, [fmi2_platform, fmi3_platform]) = platform()?;
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let status = Command::new(cargo)
        .args(["build", "--release", "--lib"])
        .current_dir(root)
        .status()
        .map_err(|e| format!("cannot run cargo: {e}"))?;
    if !status.success() {
        return Err(format!("cargo build --release --lib failed ({status})"));
    }
    let so = target.join("release").join(library);
    let binary = std::fs::read(&so).map_err(|e| format!("cannot read {}: {e}", so.display()))?;
    let out_dir = target.join("fmu");
    std::fs::create_dir_all(&out_dir)
        .map_err(|e| format!("cannot create {}: {e}", out_dir.display()))?;
    let fmus = [
        Fmu {
            file: format!("{MODEL_IDENTIFIER}.fmu"),
            description: "modelDescription/modelDescription.xml",
            platform: fmi2_platform,
        },
        Fmu {
            file: format!("{MODEL_IDENTIFIER}-fmi3.fmu"),
            description: "modelDescription/modelDescription-fmi3.xml",
            platform: fmi3_platform,
        },
    ];
    fmus.iter()
        .map(|fmu| write_fmu(root, &out_dir, fmu, &binary))
        .collect()
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
