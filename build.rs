//! Reads `modelDescription/modelDescription.xml` (the single source of truth for the FMU's
//! variables; the contract is `docs/fmu.md`), checks it and writes
//! `$OUT_DIR/model_description.rs`: the value references and the variable table used by
//! `src/fmi/`. An inconsistent description fails the build with a message naming the variable at
//! fault.

#[path = "build/model_description.rs"]
mod model_description;

use std::path::PathBuf;

fn main() {
    let xml_path = "modelDescription/modelDescription.xml";
    println!("cargo:rerun-if-changed={xml_path}");
    println!("cargo:rerun-if-changed=build/model_description.rs");
    let xml =
        std::fs::read_to_string(xml_path).unwrap_or_else(|e| panic!("cannot read {xml_path}: {e}"));
    let model = match model_description::check(&xml) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("error: {xml_path} is inconsistent: {e}");
            std::process::exit(1);
        }
    };
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    std::fs::write(
        out.join("model_description.rs"),
        model_description::generate(&model),
    )
    .expect("cannot write the generated variable table");
}
