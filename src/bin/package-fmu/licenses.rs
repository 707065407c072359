//! `documentation/licenses/` of both FMUs, the directory FMI 3.0 gives an FMU's licences (§2.5,
//! "Directory Licenses"; FMI 2.0 has none, and the same files do no harm there):
//!
//! * `license.txt`, the entry point: PlateImpact's licence (the repository's `LICENSE`), then every
//!   Rust package the library in `binaries/` is compiled from, with its licence and the files that
//!   state it;
//! * `third-party/<package>-<version>/<file>`: the licence files each package ships (`LICENSE*`,
//!   `COPYING*`, `NOTICE*`, …), each text once: a package whose file repeats one already copied is
//!   pointed to that copy.
//!
//! The packages are those Cargo resolves for the library on the FMUs' platforms (`cargo metadata
//! --filter-platform`, from Cargo.lock): the normal dependencies, followed through every package
//! but a procedural macro, which runs in the compiler and leaves only the code it generates (it is
//! listed, its own dependencies are not). Build and development dependencies never reach a binary.
//! A package may contribute no code to a given platform's binary (the packager's own `zip`, say):
//! the list errs on the side of naming too much.

use crate::contents::Entry;
use serde_json::Value;
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::fmt::Write;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Where the files go in the FMU.
const DIRECTORY: &str = "documentation/licenses";

/// One package the library is compiled from.
#[derive(Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Package {
    name: String,
    version: String,
    /// The SPDX expression of its manifest (`license`), or what its `license-file` says.
    license: String,
    authors: Vec<String>,
    /// A procedural macro (only the code it generates reaches the binary).
    proc_macro: bool,
    /// The directory of its sources.
    dir: PathBuf,
}

/// Whether `name` (a file of a package's root) states a licence or copyright.
fn is_license_file(name: &str) -> bool {
    let upper = name.to_ascii_uppercase();
    [
        "LICENSE",
        "LICENCE",
        "COPYING",
        "COPYRIGHT",
        "NOTICE",
        "UNLICENSE",
    ]
    .iter()
    .any(|prefix| upper.starts_with(prefix))
}

/// `cargo metadata` of the repository at `root` for the platform `triple`, parsed.
fn metadata(root: &Path, triple: &str) -> Result<Value, String> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let out = Command::new(cargo)
        .args(["metadata", "--format-version", "1", "--locked"])
        .args(["--filter-platform", triple])
        .current_dir(root)
        .output()
        .map_err(|e| format!("cannot run cargo metadata: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "cargo metadata --filter-platform {triple} failed: {}",
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    serde_json::from_slice(&out.stdout).map_err(|e| format!("cannot read cargo metadata: {e}"))
}

/// The text of `value` at `key`, or an error naming it.
fn text<'a>(value: &'a Value, key: &str) -> Result<&'a str, String> {
    value[key]
        .as_str()
        .ok_or_else(|| format!("cargo metadata: no text at {key}"))
}

/// The packages the library is compiled from on `triple` (module docs), the root excluded.
fn packages(root: &Path, triple: &str) -> Result<Vec<Package>, String> {
    let metadata = metadata(root, triple)?;
    let by_id: HashMap<&str, &Value> = metadata["packages"]
        .as_array()
        .ok_or("cargo metadata: no packages")?
        .iter()
        .map(|p| Ok((text(p, "id")?, p)))
        .collect::<Result<_, String>>()?;
    let resolve = &metadata["resolve"];
    let nodes: HashMap<&str, &Value> = resolve["nodes"]
        .as_array()
        .ok_or("cargo metadata: no resolve graph")?
        .iter()
        .map(|n| Ok((text(n, "id")?, n)))
        .collect::<Result<_, String>>()?;
    let start = text(resolve, "root")?;
    let mut seen = BTreeSet::from([start]);
    let mut todo = vec![start];
    let mut out = Vec::new();
    while let Some(id) = todo.pop() {
        let package = by_id
            .get(id)
            .ok_or_else(|| format!("cargo metadata: no package {id}"))?;
        let proc_macro = package["targets"].as_array().is_some_and(|targets| {
            targets.iter().any(|t| {
                t["kind"]
                    .as_array()
                    .is_some_and(|k| k.iter().any(|k| k == "proc-macro"))
            })
        });
        if id != start {
            let manifest = PathBuf::from(text(package, "manifest_path")?);
            let license = match (
                package["license"].as_str(),
                package["license_file"].as_str(),
            ) {
                (Some(spdx), _) => spdx.to_string(),
                (None, Some(file)) => format!("the licence in its file {file}"),
                (None, None) => "no licence declared".to_string(),
            };
            out.push(Package {
                name: text(package, "name")?.to_string(),
                version: text(package, "version")?.to_string(),
                license,
                authors: package["authors"]
                    .as_array()
                    .map(|a| {
                        a.iter()
                            .filter_map(Value::as_str)
                            .map(String::from)
                            .collect()
                    })
                    .unwrap_or_default(),
                proc_macro,
                dir: manifest.parent().unwrap_or(Path::new(".")).to_path_buf(),
            });
        }
        if proc_macro {
            continue;
        }
        let node = nodes
            .get(id)
            .ok_or_else(|| format!("cargo metadata: no resolve node {id}"))?;
        for dep in node["deps"].as_array().into_iter().flatten() {
            let normal = dep["dep_kinds"]
                .as_array()
                .is_some_and(|kinds| kinds.iter().any(|k| k["kind"].is_null()));
            let pkg = text(dep, "pkg")?;
            if normal && seen.insert(pkg) {
                todo.push(pkg);
            }
        }
    }
    Ok(out)
}

/// The licence files in `dir`, sorted by name, with their text.
fn license_files(dir: &Path) -> Result<Vec<(String, Vec<u8>)>, String> {
    let read_dir =
        std::fs::read_dir(dir).map_err(|e| format!("cannot list {}: {e}", dir.display()))?;
    let mut files = Vec::new();
    for entry in read_dir {
        let entry = entry.map_err(|e| format!("cannot list {}: {e}", dir.display()))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if is_license_file(&name) && entry.path().is_file() {
            let bytes = std::fs::read(entry.path())
                .map_err(|e| format!("cannot read {}: {e}", entry.path().display()))?;
            files.push((name, bytes));
        }
    }
    files.sort();
    Ok(files)
}

/// Every file of `documentation/licenses/` for the library of `version` built for `triples`, read
/// from the repository at `root` and the package sources Cargo keeps.
pub fn entries(root: &Path, version: &str, triples: &[&str]) -> Result<Vec<Entry>, String> {
    let mut all = BTreeMap::new();
    for triple in triples {
        for package in packages(root, triple)? {
            all.insert((package.name.clone(), package.version.clone()), package);
        }
    }
    let own = std::fs::read_to_string(root.join("LICENSE"))
        .map_err(|e| format!("cannot read LICENSE: {e}"))?;
    let mut index = format!(
        "PlateImpact {version}: licences\n\n\
         PlateImpact is distributed under the MIT License:\n\n{own}\n\
         The library in binaries/ is compiled from PlateImpact's sources, the Rust standard library\n\
         (MIT OR Apache-2.0, https://www.rust-lang.org/policies/licenses) and the Rust packages\n\
         below: every package Cargo.lock resolves for the library on the platforms\n\
         \x20   {}\n\
         (a package may contribute no code to one platform's binary). Each is used under its\n\
         licence; the files that state it are copied under third-party/ as the package ships them.\n\
         Where a package ships no text of the licence it declares, that licence's standard text\n\
         applies with the package's authors as the copyright holders (the MIT License's text is\n\
         PlateImpact's above).\n\n",
        triples.join(", ")
    );
    let mut entries = Vec::new();
    let mut copied: HashMap<Vec<u8>, String> = HashMap::new();
    for package in all.values() {
        let Package {
            name,
            version,
            license,
            authors,
            proc_macro,
            dir,
        } = package;
        let _ = write!(index, "{name} {version} ({license})");
        if !authors.is_empty() {
            let _ = write!(index, " by {}", authors.join(", "));
        }
        if *proc_macro {
            index.push_str(", a procedural macro: the code it generates");
        }
        index.push_str(":\n");
        let files = license_files(dir)?;
        if files.is_empty() {
            index.push_str("    ships no licence file\n");
        }
        for (file, bytes) in files {
            let path = format!("third-party/{name}-{version}/{file}");
            match copied.get(&bytes) {
                Some(first) => {
                    let _ = writeln!(index, "    {file}: the same text as {first}");
                }
                None => {
                    let _ = writeln!(index, "    {path}");
                    entries.push((format!("{DIRECTORY}/{path}"), bytes.clone()));
                    copied.insert(bytes, path);
                }
            }
        }
    }
    entries.insert(0, (format!("{DIRECTORY}/license.txt"), index.into_bytes()));
    Ok(entries)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn licence_files_are_told_by_name() {
        for name in [
            "LICENSE",
            "LICENSE-MIT",
            "license-apache-2.0",
            "COPYING",
            "LICENSE.md",
        ] {
            assert!(is_license_file(name), "{name}");
        }
        for name in ["Cargo.toml", "README.md", "src"] {
            assert!(!is_license_file(name), "{name}");
        }
    }

    #[test]
    fn the_licences_name_every_package_and_copy_every_text_once() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let triples = ["x86_64-unknown-linux-gnu", "x86_64-pc-windows-gnu"];
        let files = entries(root, "9.9.9", &triples).unwrap();
        let (first, index) = &files[0];
        assert_eq!(first, "documentation/licenses/license.txt");
        let index = String::from_utf8(index.clone()).unwrap();
        let own = std::fs::read_to_string(root.join("LICENSE")).unwrap();
        assert!(index.starts_with("PlateImpact 9.9.9: licences\n"));
        assert!(index.contains(&own));
        // The solvers the library links, and a package of x86_64 only.
        for listed in [
            "faer 0.24.4 (MIT) by sarah quiñones",
            "\nclarabel 0.11.1 (Apache-2.0) by Paul Goulart",
            "\nprivate-gemm-x86 ",
        ] {
            assert!(index.contains(listed), "{listed} not in\n{index}");
        }
        let serde_derive = index
            .lines()
            .find(|line| line.starts_with("serde_derive "))
            .unwrap();
        assert!(
            serde_derive.ends_with(", a procedural macro: the code it generates:"),
            "{serde_derive}"
        );
        // A procedural macro's own dependencies run in the compiler only; build dependencies never
        // reach a binary.
        for absent in ["\nsyn ", "\nquote ", "\nsha2 ", "\nquick-xml "] {
            assert!(!index.contains(absent), "{absent:?} in\n{index}");
        }
        // Every copied file is named in the index, and no text is copied twice.
        let mut texts = BTreeSet::new();
        for (path, bytes) in &files[1..] {
            let relative = path.strip_prefix("documentation/licenses/").unwrap();
            assert!(index.contains(&format!("    {relative}\n")), "{relative}");
            assert!(texts.insert(bytes), "{relative} repeats a text");
        }
        assert!(
            index.contains(": the same text as third-party/"),
            "identical licence texts are shared"
        );
        // The platforms decide: aarch64 has no x86_64 kernels.
        let arm = entries(root, "9.9.9", &["aarch64-unknown-linux-gnu"]).unwrap();
        let arm = String::from_utf8(arm[0].1.clone()).unwrap();
        assert!(arm.contains("\nfaer 0.24.4 ") && !arm.contains("\nprivate-gemm-x86 "));
    }
}
