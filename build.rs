//! Reads the hand-kept model descriptions (the single source of truth for the FMU's variables; the
//! contract is `docs/fmu.md`): `modelDescription/modelDescription.xml` (FMI 2.0) and
//! `modelDescription/modelDescription-fmi3.xml` (FMI 3.0). Checks each by the rules of its
//! version, checks that both declare the same variables, and writes
//! `$OUT_DIR/model_description.rs`: the value references and both variable tables used by
//! `src/fmi/`. An inconsistent description fails the build with a message naming the variable at
//! fault.

#[path = "build/model_description.rs"]
mod model_description;
#[path = "build/model_description_fmi3.rs"]
mod model_description_fmi3;

use std::path::PathBuf;

/// Reads `path` and checks it with `check`, or ends the build naming what is wrong.
fn checked(
    path: &str,
    check: fn(&str) -> Result<model_description::Model, String>,
) -> model_description::Model {
    println!("cargo:rerun-if-changed={path}");
    let xml = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("cannot read {path}: {e}"));
    check(&xml).unwrap_or_else(|e| {
        eprintln!("error: {path} is inconsistent: {e}");
        std::process::exit(1);
    })
}

fn main() {
    // The FMU ships the library as `PlateImpact.so` (FMI names it after the model identifier):
    // that is its SONAME, so that a host linked with `-l:PlateImpact.so` finds it at run time
    // (some toolchains would otherwise record `libplate_impact.so`).
    if std::env::var("CARGO_CFG_TARGET_OS").as_deref() == Ok("linux") {
        println!("cargo:rustc-cdylib-link-arg=-Wl,-soname,PlateImpact.so");
    }
    println!("cargo:rerun-if-changed=build/model_description.rs");
    println!("cargo:rerun-if-changed=build/model_description_fmi3.rs");
    let fmi2 = checked(
        "modelDescription/modelDescription.xml",
        model_description::check,
    );
    let fmi3 = checked(
        "modelDescription/modelDescription-fmi3.xml",
        model_description_fmi3::check_fmi3,
    );
    if let Err(e) = model_description_fmi3::check_same_variables(&fmi2, &fmi3) {
        eprintln!("error: the FMI 2.0 and FMI 3.0 model descriptions disagree: {e}");
        std::process::exit(1);
    }
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    std::fs::write(
        out.join("model_description.rs"),
        model_description::generate(&fmi2, &fmi3),
    )
    .expect("cannot write the generated variable tables");
}
