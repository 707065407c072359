//! Every number the prose of README.md, docs/studies.md and docs/accuracy/*.md states follows
//! from the committed data: each is claimed (a module per document here ties it to a value
//! computed from the CSVs beside the document, with the tolerance its written digits give) or
//! named as an input, and the claims hold. A rerun of a study that moves a number fails here
//! until the prose follows; a new number fails until it is claimed. How to claim: docs/studies.md,
//! "Numbers in the prose".

mod claims;
mod data;
mod prose;
mod study;

mod accuracy;
mod damping;
mod readme;
mod statistics;
mod studies;

use std::path::Path;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The documents whose prose is checked, each with its claims.
fn documents() -> Vec<claims::Claims> {
    vec![
        readme::claims(),
        studies::claims(),
        accuracy::claims(),
        statistics::claims(),
        damping::claims(),
    ]
}

#[test]
fn every_study_document_has_its_claims() {
    let checked: Vec<&str> = documents().iter().map(|c| c.document).collect();
    let mut expected = vec!["README.md".to_string(), "docs/studies.md".to_string()];
    for entry in std::fs::read_dir(root().join("docs/accuracy")).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().to_string();
        if name.ends_with(".md") {
            expected.push(format!("docs/accuracy/{name}"));
        }
    }
    let missing: Vec<&String> = expected
        .iter()
        .filter(|e| !checked.contains(&e.as_str()))
        .collect();
    assert!(
        missing.is_empty(),
        "documents without claims (add a module to tests/documented_numbers/): {missing:?}"
    );
}

#[test]
fn readme() {
    readme::claims().check();
}

#[test]
fn studies() {
    studies::claims().check();
}

#[test]
fn accuracy() {
    accuracy::claims().check();
}

#[test]
fn statistics() {
    statistics::claims().check();
}

#[test]
fn damping() {
    damping::claims().check();
}
