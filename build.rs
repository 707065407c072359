//! Reads the hand-kept model descriptions (the single source of truth for the FMU's variables; the
//! contract is `docs/fmu.md`): `modelDescription/modelDescription.xml` (FMI 2.0) and
//! `modelDescription/modelDescription-fmi3.xml` (FMI 3.0). Checks each by the rules of its
//! version, checks that both declare the same variables, and writes
//! `$OUT_DIR/model_description.rs`: the value references and both variable tables used by
//! `src/fmi/`. An inconsistent description fails the build with a message naming the variable at
//! fault. Derives each description's `guid` / `instantiationToken` from its content
//! (`build/token.rs`) and writes the descriptions as the FMUs ship them, token in place, to
//! `$OUT_DIR` (packaged by `src/bin/package-fmu.rs` from [`SHIPPED_FMI2_XML`] and
//! [`SHIPPED_FMI3_XML`] of `src/fmi/variables.rs`).

#[path = "build/dependencies.rs"]
mod dependencies;
#[path = "build/model_description.rs"]
mod model_description;
#[path = "build/model_description_fmi3.rs"]
mod model_description_fmi3;
#[path = "build/token.rs"]
mod token;

use std::path::{Path, PathBuf};

/// Ends the build with `message` about `path`.
fn fail(path: &str, message: String) -> ! {
    eprintln!("error: {path} is inconsistent: {message}");
    std::process::exit(1);
}

/// Reads `path`, checks it with `check` and derives its token (the value of `attribute`), or ends
/// the build naming what is wrong. Writes the description as its FMU ships it to `out/shipped`.
fn checked(
    path: &str,
    attribute: &str,
    check: fn(&str) -> Result<model_description::Model, String>,
    out: &Path,
    shipped: &str,
) -> model_description::Model {
    println!("cargo:rerun-if-changed={path}");
    let xml = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("cannot read {path}: {e}"));
    let mut model = check(&xml).unwrap_or_else(|e| fail(path, e));
    model.token = token::derive(&xml, attribute).unwrap_or_else(|e| fail(path, e));
    let text = token::with_token(&xml, attribute, &model.token).unwrap_or_else(|e| fail(path, e));
    std::fs::write(out.join(shipped), text).expect("cannot write the shipped model description");
    model
}

fn main() {
    // The FMU ships the library as `PlateImpact.so` (FMI names it after the model identifier):
    // that is its SONAME, so that a host linked with `-l:PlateImpact.so` finds it at run time
    // (some toolchains would otherwise record `libplate_impact.so`).
    if std::env::var("CARGO_CFG_TARGET_OS").as_deref() == Ok("linux") {
        println!("cargo:rustc-cdylib-link-arg=-Wl,-soname,PlateImpact.so");
    }
    println!("cargo:rerun-if-changed=build/dependencies.rs");
    println!("cargo:rerun-if-changed=build/model_description.rs");
    println!("cargo:rerun-if-changed=build/model_description_fmi3.rs");
    println!("cargo:rerun-if-changed=build/token.rs");
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    let fmi2 = checked(
        "modelDescription/modelDescription.xml",
        "guid",
        model_description::check,
        &out,
        "modelDescription-fmi2.xml",
    );
    let fmi3 = checked(
        "modelDescription/modelDescription-fmi3.xml",
        "instantiationToken",
        model_description_fmi3::check_fmi3,
        &out,
        "modelDescription-fmi3.xml",
    );
    if let Err(e) = model_description_fmi3::check_same_variables(&fmi2, &fmi3) {
        eprintln!("error: the FMI 2.0 and FMI 3.0 model descriptions disagree: {e}");
        std::process::exit(1);
    }
    let mut code = model_description::generate(&fmi2, &fmi3);
    for (name, version, file) in [
        ("SHIPPED_FMI2_XML", "2.0", "modelDescription-fmi2.xml"),
        ("SHIPPED_FMI3_XML", "3.0", "modelDescription-fmi3.xml"),
    ] {
        code.push_str(&format!(
            "/// The FMI {version} model description as its FMU ships it: normalised, with the token\n\
             /// derived from its content in place of the placeholder (build/token.rs).\n\
             pub const {name}: &str = include_str!(concat!(env!(\"OUT_DIR\"), \"/{file}\"));\n\n"
        ));
    }
    std::fs::write(out.join("model_description.rs"), code)
        .expect("cannot write the generated variable tables");
}
