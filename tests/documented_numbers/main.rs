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
mod limits;
mod modal_damping;
mod readme;
mod statistics;
mod studies;

use std::path::Path;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// A checked document and the function that makes its claims.
type Document = (&'static str, fn() -> claims::Claims);

/// The documents whose prose is checked.
const DOCUMENTS: [Document; 7] = [
    ("README.md", readme::claims),
    ("docs/studies.md", studies::claims),
    ("docs/accuracy/README.md", accuracy::claims),
    ("docs/accuracy/statistics.md", statistics::claims),
    ("docs/accuracy/damping.md", damping::claims),
    ("docs/accuracy/modal_damping.md", modal_damping::claims),
    ("docs/limits.md", limits::claims),
];

/// Checks the claims of `document`.
fn check(document: &str) {
    let (name, claims) = DOCUMENTS
        .iter()
        .find(|(name, _)| *name == document)
        .expect("a listed document");
    let claims = claims();
    assert_eq!(claims.document, *name, "the module claims another document");
    claims.check();
}

#[test]
fn every_study_document_has_its_claims() {
    let checked: Vec<&str> = DOCUMENTS.iter().map(|(name, _)| *name).collect();
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
        "documents without claims (add a module to tests/documented_numbers/ and list it in \
         DOCUMENTS): {missing:?}"
    );
}

#[test]
fn readme() {
    check("README.md");
}

#[test]
fn studies() {
    check("docs/studies.md");
}

#[test]
fn accuracy() {
    check("docs/accuracy/README.md");
}

#[test]
fn statistics() {
    check("docs/accuracy/statistics.md");
}

#[test]
fn damping() {
    check("docs/accuracy/damping.md");
}

#[test]
fn modal_damping() {
    check("docs/accuracy/modal_damping.md");
}

#[test]
fn limits() {
    check("docs/limits.md");
}

/// The start-up warning's finding for a modal ratio restates the study's numbers.
#[test]
fn modal_ratio_warning() {
    let warning = plate_impact::advice::MODAL_RATIO_FINDING;
    for number in modal_damping::warning_numbers() {
        assert!(
            warning.contains(&number),
            "the modal-ratio warning should state {number:?}: {warning}"
        );
    }
}
