//! Where a study writes: its output directory chosen from the command line, writing its files,
//! the hand-written page its write step fills, the write step itself (the study's module of
//! `plateimpact_tools.studies`, run with the project's Python), and the check of what it left.

use crate::repository;
use std::path::PathBuf;

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
