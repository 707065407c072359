//! Every command the documentation shows still names something that exists: each path under
//! `examples/`, `scripts/`, `benches/`, `tools/` or `studies/` in README.md, docs/**/*.md,
//! examples/**/*.md, studies/**/*.md and the scripts, each `--example NAME` (a Cargo example
//! target), each `--bench NAME` (a Cargo bench target), each `--bin NAME` (a binary of this package
//! or of the studies' crate) and each module of the Python package (`plateimpact_tools.converge`, as in
//! `python -m plateimpact_tools.converge`). Files move (examples/ was sorted by role, the Python
//! tools moved into the package); this catches the reference left behind.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The Markdown files under `dir`, recursively.
fn markdown_under(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            markdown_under(&path, out);
        } else if path.extension().is_some_and(|e| e == "md") {
            out.push(path);
        }
    }
}

/// The documents checked: README.md, the Markdown of docs/, examples/ and studies/, and the
/// scripts.
fn documents() -> Vec<PathBuf> {
    let mut files = vec![root().join("README.md")];
    markdown_under(&root().join("docs"), &mut files);
    markdown_under(&root().join("examples"), &mut files);
    markdown_under(&root().join("studies"), &mut files);
    for entry in std::fs::read_dir(root().join("scripts")).unwrap() {
        let path = entry.unwrap().path();
        if path.is_file() && path.extension().is_none() {
            files.push(path);
        }
    }
    files.sort();
    files
}

/// A character that can continue a path written in prose or a command.
fn path_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.' | '/')
}

/// The paths under `examples/`, `scripts/`, `benches/`, `tools/` and `studies/` in `text`, each as written: relative to
/// the repository root, or starting with `../` (a Markdown link, relative to the document). A
/// trailing `.` (end of a sentence) is not part of the path.
fn mentioned_paths(text: &str) -> Vec<String> {
    let mut found = Vec::new();
    for prefix in ["examples/", "scripts/", "benches/", "tools/", "studies/"] {
        for (at, _) in text.match_indices(prefix) {
            let mut start = at;
            while text[..start].ends_with("../") {
                start -= 3;
            }
            if text[..start].chars().next_back().is_some_and(path_char) {
                continue; // part of a longer path, such as target/fmu/examples/
            }
            let end = text[at..]
                .find(|c: char| !path_char(c))
                .map_or(text.len(), |n| at + n);
            found.push(text[start..end].trim_end_matches('.').to_string());
        }
    }
    found
}

/// The dotted module names of the Python package in `text` (`plateimpact_tools.converge.study`),
/// a trailing `.` (end of a sentence) left out; `NAME` and `<…>` placeholders are not names.
fn mentioned_modules(text: &str) -> Vec<String> {
    let module_char = |c: char| c.is_ascii_alphanumeric() || matches!(c, '_' | '.');
    text.match_indices("plateimpact_tools")
        .filter(|(at, _)| !text[..*at].chars().next_back().is_some_and(path_char))
        .map(|(at, _)| {
            let end = text[at..]
                .find(|c: char| !module_char(c))
                .map_or(text.len(), |n| at + n);
            text[at..end].trim_end_matches('.').to_string()
        })
        .filter(|name| {
            !name
                .split('.')
                .any(|part| part == "NAME" || part.is_empty())
        })
        .collect()
}

/// Whether the package in `tools/` has the module `name`: a file `NAME.py` or a package
/// directory `NAME/__init__.py`.
fn module_exists(name: &str) -> bool {
    let path = root().join("tools").join(name.replace('.', "/"));
    path.with_extension("py").is_file() || path.join("__init__.py").is_file()
}

/// The names following `flag` (`--example`, `--bench`, `--bin`) in `text`.
fn flag_values(text: &str, flag: &str) -> Vec<String> {
    text.match_indices(flag)
        .filter(|(at, _)| text[at + flag.len()..].starts_with(' '))
        .filter_map(|(at, _)| {
            text[at + flag.len()..]
                .split_whitespace()
                .next()
                .map(|w| w.trim_matches(|c: char| !path_char(c)).to_string())
        })
        .filter(|name| !name.is_empty() && !name.starts_with('-') && name != "NAME")
        .collect()
}

/// The targets of a kind (`example`, `bench`, `bin`) that Cargo.toml declares with `[[kind]]`.
fn declared_targets(kind: &str) -> BTreeSet<String> {
    let manifest = std::fs::read_to_string(root().join("Cargo.toml")).unwrap();
    let header = format!("[[{kind}]]");
    let mut names = BTreeSet::new();
    let mut inside = false;
    for line in manifest.lines().map(str::trim) {
        if line.starts_with('[') {
            inside = line == header;
        } else if let Some(value) = line.strip_prefix("name = ").filter(|_| inside) {
            names.insert(value.trim_matches('"').to_string());
        }
    }
    names
}

/// Whether Cargo has a target `name` of this kind: declared, or found where Cargo looks by itself
/// (`DIR/name.rs`, `DIR/name/main.rs`).
fn target_exists(kind: &str, dir: &str, name: &str) -> bool {
    declared_targets(kind).contains(name)
        || root().join(dir).join(format!("{name}.rs")).is_file()
        || root().join(dir).join(name).join("main.rs").is_file()
}

#[test]
fn documented_paths_and_targets_exist() {
    let mut broken = Vec::new();
    let mut checked = 0;
    for document in documents() {
        let text = std::fs::read_to_string(&document).unwrap();
        let shown = document.strip_prefix(root()).unwrap().display().to_string();
        for path in mentioned_paths(&text) {
            let base = if path.starts_with("../") {
                document.parent().unwrap()
            } else {
                root()
            };
            checked += 1;
            if !base.join(&path).exists() {
                broken.push(format!("{shown}: {path}"));
            }
        }
        for module in mentioned_modules(&text) {
            checked += 1;
            if !module_exists(&module) {
                broken.push(format!("{shown}: module {module}"));
            }
        }
        for (flag, kind, dirs) in [
            ("--example", "example", &["examples"][..]),
            ("--bench", "bench", &["benches"][..]),
            ("--bin", "bin", &["src/bin", "studies/src/bin"][..]),
        ] {
            for name in flag_values(&text, flag) {
                checked += 1;
                if !dirs.iter().any(|dir| target_exists(kind, dir, &name)) {
                    broken.push(format!("{shown}: {flag} {name}"));
                }
            }
        }
    }
    assert!(
        checked > 50,
        "only {checked} references found: is the scan still reading the documents?"
    );
    assert!(
        broken.is_empty(),
        "stale references:\n{}",
        broken.join("\n")
    );
}

#[test]
fn the_scan_finds_what_a_command_names() {
    let text = "run `cargo run --release --example scene -- x` and \
                .venv/bin/python examples/shaker_coupling.py, see [here](../examples/c/plate_host.c). \
                Not target/fmu/examples/x; `cargo bench --bench solver`; scripts/main-job; \
                `cargo run -p plate_impact_studies --bin accuracy` (../studies/README.md); \
                `python -m plateimpact_tools.studies.damping` (tools/pyproject.toml), each \
                `plateimpact_tools.studies.NAME`, not my_plateimpact_tools.x; plateimpact_tools.converge.";
    assert_eq!(
        mentioned_paths(text),
        [
            "examples/shaker_coupling.py",
            "../examples/c/plate_host.c",
            "scripts/main-job",
            "tools/pyproject.toml",
            "../studies/README.md"
        ]
    );
    assert_eq!(
        mentioned_modules(text),
        [
            "plateimpact_tools.studies.damping",
            "plateimpact_tools.converge"
        ]
    );
    assert!(module_exists("plateimpact_tools.converge"));
    assert!(module_exists("plateimpact_tools.converge.study"));
    assert!(!module_exists("plateimpact_tools.converge.nothing"));
    assert_eq!(flag_values(text, "--example"), ["scene"]);
    assert_eq!(flag_values(text, "--bench"), ["solver"]);
    assert_eq!(flag_values(text, "--bin"), ["accuracy"]);
    assert!(target_exists("bin", "studies/src/bin", "statistics"));
    assert!(target_exists("bin", "src/bin", "package-fmu"));
    assert!(!target_exists("example", "examples", "statistics"));
    assert!(target_exists("example", "examples", "scene"));
    assert!(!target_exists("example", "examples", "bench"));
    assert!(target_exists("bench", "benches", "paper_speed"));
}
