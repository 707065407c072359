//! Pieces shared by the examples: the exit code of a run, the command-line values they parse
//! alike (a positive count, a `key=value` scene override) and, for the studies (`accuracy`,
//! `statistics`), the output directory chosen from the command line, writing its files, checking
//! them, the plotting script run with the project's Python, and the element names of their CSVs.

// Each example compiles this module on its own and uses a part of it.
#![allow(dead_code)]

use plate_impact::element::ElementKind;
use plate_impact::scene::Scene;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::str::FromStr;

/// The value after `flag` in `args`, if the flag is there.
pub fn flag_value(args: &[String], flag: &str) -> Result<Option<String>, String> {
    args.iter()
        .position(|a| a == flag)
        .map(|i| {
            args.get(i + 1)
                .cloned()
                .ok_or(format!("{flag} needs a value"))
        })
        .transpose()
}

/// The element and cells of a mesh given as `ELEMENT:NXxNY` on a command line (`argyris:10x7`).
pub fn parse_mesh_cells(item: &str) -> Result<(ElementKind, usize, usize), String> {
    let usage = || format!("--mesh {item}: use ELEMENT:NXxNY, e.g. argyris:10x7");
    let (element, cells) = item.split_once(':').ok_or_else(usage)?;
    let element = match element {
        "argyris" => ElementKind::Argyris,
        "fvs" => ElementKind::Fvs,
        _ => return Err(usage()),
    };
    let (nx, ny) = cells.split_once('x').ok_or_else(usage)?;
    let cells = |n: &str| n.parse::<usize>().ok().filter(|&n| n > 0).ok_or_else(usage);
    Ok((element, cells(nx)?, cells(ny)?))
}

/// The CSV name of an element.
pub fn element_name(e: ElementKind) -> &'static str {
    match e {
        ElementKind::Argyris => "argyris",
        ElementKind::Fvs => "fvs",
    }
}

/// The exit code of a run: success, or its error message on stderr and failure.
pub fn exit_code(outcome: Result<(), String>) -> ExitCode {
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

/// The value of `option` (e.g. `--every`), the next command-line argument: a whole number > 0.
pub fn positive_integer<T: FromStr + PartialOrd + From<u8>>(
    option: &str,
    value: Option<String>,
) -> Result<T, String> {
    value
        .and_then(|v| v.parse().ok())
        .filter(|n| *n > T::from(0))
        .ok_or_else(|| format!("{option} needs a positive integer"))
}

/// Sets the scene parameter of a `key=value` argument (the FMU variable names, see
/// [`Scene::set`]); anything else is refused with `usage`.
pub fn set_override(scene: &mut Scene, arg: &str, usage: &str) -> Result<(), String> {
    let (key, value) = arg
        .split_once('=')
        .ok_or_else(|| format!("expected key=value, got {arg}; {usage}"))?;
    scene.set(key, value).map_err(|e| e.to_string())
}

/// Where a study writes, and whether it runs in quick mode.
pub struct StudyDir {
    /// The output directory (created).
    pub path: PathBuf,
    /// `--quick`: a small subset that checks the pipeline and a few assertions.
    pub quick: bool,
    /// A temporary directory of a quick run, removed by [`StudyDir::finish`].
    temporary: bool,
}

impl StudyDir {
    /// Reads `--quick` and `--out DIR` from `args`. The directory is DIR when given; otherwise a
    /// fresh temporary directory `<name>-quick-<pid>` in quick mode, else `docs/<docs>` of the
    /// repository. It is created.
    pub fn from_args(args: &[String], name: &str, docs: &str) -> Result<StudyDir, String> {
        let quick = args.iter().any(|a| a == "--quick");
        let out = match args.iter().position(|a| a == "--out") {
            Some(i) => Some(args.get(i + 1).ok_or("--out needs a directory")?),
            None => None,
        };
        let path: PathBuf = match out {
            Some(dir) => dir.into(),
            None if quick => {
                std::env::temp_dir().join(format!("{name}-quick-{}", std::process::id()))
            }
            None => repository().join("docs").join(docs),
        };
        std::fs::create_dir_all(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        Ok(StudyDir {
            path,
            quick,
            temporary: quick && out.is_none(),
        })
    }

    /// Writes `text` to the file `name` of the directory.
    pub fn write(&self, name: &str, text: &str) -> Result<(), String> {
        let path = self.path.join(name);
        std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Runs `python -m plateimpact_tools.studies.<module> DIR [--quick]` (the package in `tools/`)
    /// with the Python of `scripts/python-env`.
    pub fn plot(&self, module: &str) -> Result<(), String> {
        let root = repository();
        let env = std::process::Command::new(root.join("scripts/python-env"))
            .output()
            .map_err(|e| format!("scripts/python-env: {e}"))?;
        if !env.status.success() {
            return Err(format!(
                "scripts/python-env failed: {}",
                String::from_utf8_lossy(&env.stderr)
            ));
        }
        let python = String::from_utf8_lossy(&env.stdout).trim().to_string();
        let mut command = std::process::Command::new(python);
        command
            .arg("-m")
            .arg(format!("plateimpact_tools.studies.{module}"))
            .arg(&self.path);
        if self.quick {
            command.arg("--quick");
        }
        let status = command.status().map_err(|e| format!("{module}: {e}"))?;
        if status.success() {
            Ok(())
        } else {
            Err(format!("{module} exited with {status}"))
        }
    }

    /// Makes sure the directory holds the hand-written page `name` of docs/`docs`, whose
    /// generated tables the write step fills: a directory other than docs/`docs` (a quick run's,
    /// or `--out`) gets a copy of the committed page when it has none.
    pub fn page(&self, docs: &str, name: &str) -> Result<(), String> {
        let target = self.path.join(name);
        if target.exists() {
            return Ok(());
        }
        let source = repository().join("docs").join(docs).join(name);
        std::fs::copy(&source, &target)
            .map(|_| ())
            .map_err(|e| format!("{}: {e}", source.display()))
    }

    /// One message per file of `names` that is missing or empty.
    pub fn missing(&self, names: &[&str]) -> Vec<String> {
        names
            .iter()
            .filter(|name| std::fs::metadata(self.path.join(name)).map_or(0, |m| m.len()) == 0)
            .map(|name| format!("{name} missing or empty"))
            .collect()
    }

    /// Ends a study: with `failures`, an error that lists them (a quick run's directory is kept
    /// to inspect); without, a quick run's temporary directory is removed.
    pub fn finish(&self, failures: Vec<String>) -> Result<(), String> {
        if !failures.is_empty() {
            return Err(failures.join("; "));
        }
        if self.temporary {
            std::fs::remove_dir_all(&self.path)
                .map_err(|e| format!("{}: {e}", self.path.display()))?;
        }
        Ok(())
    }
}

/// The commit of the repository's checkout (`git rev-parse HEAD`), with `+modified` when the
/// work tree differs from it (`git status --porcelain` prints anything): what a study records
/// in its meta file, so its data name the code that made them. `unknown` without git.
pub fn source_revision() -> String {
    let git = |args: &[&str]| {
        std::process::Command::new("git")
            .arg("-C")
            .arg(repository())
            .args(args)
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    match (git(&["rev-parse", "HEAD"]), git(&["status", "--porcelain"])) {
        (Some(commit), Some(status)) if status.is_empty() => commit,
        (Some(commit), Some(_)) => format!("{commit}+modified"),
        _ => "unknown".to_string(),
    }
}

/// The repository's root directory.
fn repository() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}
