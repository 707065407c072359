//! Builds the FMU: `cargo run --release --bin package-fmu`.
//!
//! Runs `cargo build --release --lib` (the cdylib), then writes `target/fmu/PlateImpact.fmu`, a zip
//! archive holding `modelDescription.xml` and `binaries/linux64/PlateImpact.so` (FMI 2.0 §2.3).
//! The target directory follows `CARGO_TARGET_DIR` when set.

use plate_impact::fmi::variables::MODEL_IDENTIFIER;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use zip::write::SimpleFileOptions;
use zip::CompressionMethod;

/// FMI platform folder and shared-library name of the cdylib for the platform we run on.
fn platform() -> Result<(&'static str, &'static str), String> {
    if cfg!(all(target_os = "linux", target_arch = "x86_64")) {
        Ok(("linux64", "libplate_impact.so"))
    } else {
        Err("package-fmu supports linux x86_64 (binaries/linux64) only so far".into())
    }
}

fn run() -> Result<PathBuf, String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .map(|t| if t.is_absolute() { t } else { root.join(t) })
        .unwrap_or_else(|| root.join("target"));
    let (platform, library) = platform()?;
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
    let description_path = root.join("modelDescription/modelDescription.xml");
    let description = std::fs::read(&description_path)
        .map_err(|e| format!("cannot read {}: {e}", description_path.display()))?;

    let out_dir = target.join("fmu");
    std::fs::create_dir_all(&out_dir)
        .map_err(|e| format!("cannot create {}: {e}", out_dir.display()))?;
    let fmu = out_dir.join(format!("{MODEL_IDENTIFIER}.fmu"));
    let file =
        std::fs::File::create(&fmu).map_err(|e| format!("cannot create {}: {e}", fmu.display()))?;
    let mut zip = zip::ZipWriter::new(file);
    let options = SimpleFileOptions::default().compression_method(CompressionMethod::Deflated);
    let entries = [
        ("modelDescription.xml".to_string(), description),
        (format!("binaries/{platform}/{MODEL_IDENTIFIER}.so"), binary),
    ];
    for (name, bytes) in &entries {
        zip.start_file(name.as_str(), options)
            .and_then(|()| zip.write_all(bytes).map_err(Into::into))
            .map_err(|e| format!("cannot write {name} into {}: {e}", fmu.display()))?;
    }
    zip.finish()
        .map_err(|e| format!("cannot finish {}: {e}", fmu.display()))?;
    Ok(fmu)
}

fn main() -> ExitCode {
    match run() {
        Ok(fmu) => {
            println!("{}", fmu.display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("package-fmu: {e}");
            ExitCode::FAILURE
        }
    }
}
