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
mod scheme;
mod statistics;
mod studies;

use std::path::Path;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// A checked document and the function that makes its claims.
type Document = (&'static str, fn() -> claims::Claims);

/// The documents whose prose is checked.
const DOCUMENTS: [Document; 9] = [
    ("README.md", readme::claims),
    ("docs/studies.md", studies::claims),
    ("docs/accuracy/README.md", accuracy::claims),
    ("docs/accuracy/statistics.md", statistics::claims),
    ("docs/accuracy/damping.md", damping::claims),
    ("docs/accuracy/modal_damping.md", modal_damping::claims),
    ("docs/limits.md", limits::claims),
    ("docs/scheme.md", scheme::claims),
    ("docs/testing.md", share_claims),
];

/// Every Markdown page of the documentation: README.md and docs/**/*.md.
fn pages() -> Vec<String> {
    fn walk(dir: &Path, out: &mut Vec<String>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "md") {
                let relative = path.strip_prefix(root()).unwrap();
                out.push(relative.to_string_lossy().replace('\\', "/"));
            }
        }
    }
    let mut out = vec!["README.md".to_string()];
    walk(&root().join("docs"), &mut out);
    out.sort();
    out
}

/// How the numbers of the whole documentation's prose are covered: those of the checked parts
/// of the checked documents as their claims cover them, every other number as unchecked (in
/// `total`, not in `claimed` or `inputs`).
fn documentation_tally() -> claims::Tally {
    let mut sum = claims::Tally::default();
    for page in pages() {
        let markdown = std::fs::read_to_string(root().join(&page)).unwrap();
        let whole = claims::unchecked_tally(&markdown);
        let checked = DOCUMENTS
            .iter()
            .filter(|(name, _)| *name == page && *name != "docs/testing.md")
            .map(|(_, claims)| claims().tally())
            .next()
            .unwrap_or_default();
        sum.claimed += checked.claimed;
        sum.inputs += checked.inputs;
        sum.meshes += whole.meshes;
        sum.total += whole.total;
    }
    sum
}

/// docs/testing.md's section on how much of the documentation is checked.
fn share_claims() -> claims::Claims {
    let mut c = claims::Claims::new("docs/testing.md");
    c.only_section(
        "How much of the documentation is checked",
        "the rest of the page is the tiers, their scripts and their measured times (one \
         measurement each, on the machine and load it names)",
    );
    let t = documentation_tally();
    let pct = |n: usize| 100.0 * n as f64 / t.total as f64;
    let unchecked = t.total - t.claimed - t.inputs - t.meshes;
    c.value(
        "Of the {8.6} thousand numbers in the prose",
        t.total as f64 / 1000.0,
    );
    c.value("{9} % are checked against committed data", pct(t.claimed));
    c.value("{12} % are inputs", pct(t.inputs));
    c.value("{13} % are sides of mesh names", pct(t.meshes));
    c.value("the other {66} %", pct(unchecked));
    c
}

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
fn testing_share() {
    check("docs/testing.md");
}

#[test]
fn scheme() {
    check("docs/scheme.md");
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
