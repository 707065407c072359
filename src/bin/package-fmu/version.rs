//! The version the FMUs carry, and the rules of a release (docs/fmu.md, "Versions, builds and the
//! token").
//!
//! The repository says `X.Y.Z-dev` between releases and `X.Y.Z` on the commit of release X.Y.Z:
//! the same in `Cargo.toml` and both model descriptions, and CHANGELOG.md heads that version's
//! section `## X.Y.Z (unreleased)` until the release dates it `## X.Y.Z (YYYY-MM-DD)`. Each
//! release is the Git tag `vX.Y.Z` on its commit. From these, what a build says about itself:
//!
//! * on the commit the tag `vX.Y.Z` of its release version names, unmodified, or under
//!   `package-fmu --release`, whose checks ([`release_problems`]) ensure that it will be: `X.Y.Z`;
//! * otherwise the repository's version with the commit as semantic-versioning build metadata,
//!   `1.1.0-dev+0123456789ab`, `.modified` added when the working tree differs from the commit,
//!   `+unknown` outside a Git checkout.
//!
//! The stamp goes on the shipped model descriptions (`version`, and `generationDateAndTime`, the
//! commit's time) and the documentation page, never into the library: the binary, and the token
//! derived from the hand-kept description, stay the same for every commit of the same sources.

use std::path::Path;
use std::process::Command;

/// What CHANGELOG.md says of one version.
#[derive(Debug, PartialEq)]
pub enum Section {
    /// `## X.Y.Z (YYYY-MM-DD)`, with its date.
    Released(String),
    /// `## X.Y.Z (unreleased)`.
    Unreleased,
}

/// The commit a build is made from, as Git reports it.
#[derive(Debug, Clone)]
pub struct Commit {
    /// The full hash.
    pub hash: String,
    /// The committer's time in UTC, as `xs:dateTime` (`2026-12-07T09:05:18Z`).
    pub time: String,
    /// Whether the working tree differs from the commit (a file changed, added or removed that Git
    /// does not ignore).
    pub modified: bool,
    /// The commit the release tag of the version (`vX.Y.Z` for `X.Y.Z` and `X.Y.Z-dev`) names,
    /// if that tag exists.
    pub release_tag: Option<String>,
}

/// What the FMUs say about the build they come from.
pub struct Build {
    /// The version stamped on them ([`stamped`]).
    pub version: String,
    /// The commit, when built from a Git checkout.
    pub commit: Option<Commit>,
    /// `repository` of Cargo.toml: where the source and the full documentation live, if it says.
    pub repository: &'static str,
}

impl Build {
    /// The section "This build" that ends the documentation page: the version, the commit, where
    /// the full documentation lives and the licence.
    pub fn about(&self) -> String {
        let mut out = format!("## This build\n\nPlateImpact {}", self.version);
        match &self.commit {
            Some(c) => {
                out.push_str(&format!(
                    ", built from commit `{}` of the PlateImpact repository (committed {})",
                    c.hash, c.time
                ));
                if c.modified {
                    out.push_str(" with changes to its files that were not committed");
                }
            }
            None => out.push_str(", built outside a Git checkout (its commit is unknown)"),
        }
        out.push_str(
            ". The full documentation (the model, the scheme, accuracy and speed, the studies, the \
             FMU contract `docs/fmu.md`) is the `docs/` folder of that repository, indexed by \
             `docs/README.md`",
        );
        if !self.repository.is_empty() {
            out.push_str(&format!("; the repository: [{0}]({0})", self.repository));
        }
        out.push_str(
            ".\n\nLicence: MIT (`documentation/licenses/license.txt`, which also names the \
             licence of every Rust package compiled into the binaries).\n",
        );
        out
    }
}

/// `X.Y.Z` of a version `X.Y.Z` or `X.Y.Z-pre`, if it has that form.
fn core(version: &str) -> Option<(u64, u64, u64)> {
    let numbers = version.split_once('-').map_or(version, |(core, _)| core);
    let mut parts = numbers.split('.').map(|p| {
        (!p.is_empty()
            && p.bytes().all(|b| b.is_ascii_digit())
            && (p == "0" || !p.starts_with('0')))
        .then(|| p.parse().ok())
        .flatten()
    });
    match (parts.next(), parts.next(), parts.next(), parts.next()) {
        (Some(Some(x)), Some(Some(y)), Some(Some(z)), None) => Some((x, y, z)),
        _ => None,
    }
}

/// `X.Y.Z` of `version` as text.
fn core_text(version: &str) -> &str {
    version.split_once('-').map_or(version, |(core, _)| core)
}

/// Whether `version` is a pre-release (`X.Y.Z-dev`), which no release may carry.
pub fn is_pre_release(version: &str) -> bool {
    version.contains('-')
}

/// Every section of CHANGELOG.md (its `## ` headings), in order; an error names a heading of
/// another form.
pub fn sections(changelog: &str) -> Result<Vec<(String, Section)>, String> {
    changelog
        .lines()
        .filter_map(|line| line.strip_prefix("## "))
        .map(|heading| {
            let form = || {
                format!(
                    "CHANGELOG.md: the heading `## {heading}` is neither `## X.Y.Z (YYYY-MM-DD)` \
                     (released) nor `## X.Y.Z (unreleased)`"
                )
            };
            let (version, rest) = heading.split_once(" (").ok_or_else(form)?;
            let state = rest.strip_suffix(')').ok_or_else(form)?;
            if core(version).is_none() || is_pre_release(version) {
                return Err(form());
            }
            let date = state.as_bytes();
            let is_date = date.len() == 10
                && date.iter().enumerate().all(|(i, b)| match i {
                    4 | 7 => *b == b'-',
                    _ => b.is_ascii_digit(),
                });
            let section = match state {
                "unreleased" => Section::Unreleased,
                _ if is_date => Section::Released(state.to_string()),
                _ => return Err(form()),
            };
            Ok((version.to_string(), section))
        })
        .collect()
}

/// Checks that CHANGELOG.md and the release tags agree with the repository's `version`: its first
/// section is that version's (unreleased for `X.Y.Z-dev`, dated for `X.Y.Z`), every other one is
/// dated and the versions fall from each section to the next; and no release tag contradicts it
/// (`vX.Y.Z` may exist only on the commit of release `X.Y.Z`, so a commit after a release must
/// say a later version).
pub fn check_repository(
    version: &str,
    changelog: &str,
    commit: Option<&Commit>,
) -> Result<(), String> {
    let Some(numbers) = core(version) else {
        return Err(format!(
            "the version {version} of Cargo.toml is not X.Y.Z or X.Y.Z-dev"
        ));
    };
    let sections = sections(changelog)?;
    let Some((first, state)) = sections.first() else {
        return Err("CHANGELOG.md has no section `## X.Y.Z (...)`".into());
    };
    let plain = core_text(version);
    let expected = if is_pre_release(version) {
        format!("## {plain} (unreleased)")
    } else {
        format!("## {plain} (YYYY-MM-DD)")
    };
    let matches = first == plain && (is_pre_release(version) == (*state == Section::Unreleased));
    if !matches {
        return Err(format!(
            "Cargo.toml says {version}, so CHANGELOG.md must begin with the section `{expected}`; \
             it begins with `## {first} ({})`",
            match state {
                Section::Released(date) => date.as_str(),
                Section::Unreleased => "unreleased",
            }
        ));
    }
    let mut previous = numbers;
    for (v, state) in &sections[1..] {
        if *state == Section::Unreleased {
            return Err(format!(
                "CHANGELOG.md: only the first section may be unreleased, not {v}'s"
            ));
        }
        let this = core(v).expect("sections() checked the form");
        if this >= previous {
            return Err(format!(
                "CHANGELOG.md: the section of {v} follows a section of a version not above it"
            ));
        }
        previous = this;
    }
    if let Some(Commit {
        hash,
        release_tag: Some(tagged),
        ..
    }) = commit
    {
        if is_pre_release(version) {
            return Err(format!(
                "{plain} is released (tag v{plain} on commit {tagged}), yet Cargo.toml says \
                 {version}: a commit after a release says a later version, X.Y.Z-dev"
            ));
        }
        if tagged != hash {
            return Err(format!(
                "{version} was released from commit {tagged} (tag v{version}); this commit \
                 {hash} comes after it and must say a later version, X.Y.Z-dev, with a new \
                 `## X.Y.Z (unreleased)` section in CHANGELOG.md"
            ));
        }
    }
    Ok(())
}

/// What stops a release of `version` from this checkout, every reason at once (empty when
/// nothing does): a pre-release version, an undated CHANGELOG.md section, no commit or a modified
/// one, its tag on another commit, no `repository` in Cargo.toml.
pub fn release_problems(
    version: &str,
    changelog: &str,
    commit: Option<&Commit>,
    repository: &str,
) -> Vec<String> {
    let mut problems = Vec::new();
    if is_pre_release(version) {
        problems.push(format!(
            "{version} is a pre-release: a release sets X.Y.Z in Cargo.toml and both model \
             descriptions, and dates its CHANGELOG.md section `## X.Y.Z (YYYY-MM-DD)`"
        ));
    } else {
        match sections(changelog) {
            Err(e) => problems.push(e),
            Ok(sections) => match sections.iter().find(|(v, _)| v == version) {
                Some((_, Section::Released(_))) => {}
                Some((_, Section::Unreleased)) => problems.push(format!(
                    "CHANGELOG.md's section of {version} is not released: head it \
                     `## {version} (YYYY-MM-DD)` with the date of the release"
                )),
                None => problems.push(format!(
                    "CHANGELOG.md has no section `## {version} (YYYY-MM-DD)`"
                )),
            },
        }
    }
    match commit {
        None => problems.push(
            "no Git commit: a release is built from a Git checkout, whose commit it tags".into(),
        ),
        Some(commit) => {
            if commit.modified {
                problems.push(
                    "the working tree differs from the commit: a release is a commit's".into(),
                );
            }
            if let Some(tagged) = commit.release_tag.as_ref().filter(|t| **t != commit.hash) {
                problems.push(format!(
                    "the tag v{} already names commit {tagged}: that version is released",
                    core_text(version)
                ));
            }
        }
    }
    if repository.is_empty() {
        problems.push(
            "Cargo.toml names no `repository`: a release says where its source and full \
             documentation live"
                .into(),
        );
    }
    problems
}

/// The version a build says it is (module docs): `version` on its release commit (`release`: the
/// release build, whose checks passed), else `version` with the commit as build metadata.
pub fn stamped(version: &str, commit: Option<&Commit>, release: bool) -> String {
    match commit {
        _ if release => version.to_string(),
        Some(c)
            if !is_pre_release(version)
                && !c.modified
                && c.release_tag.as_deref() == Some(c.hash.as_str()) =>
        {
            version.to_string()
        }
        Some(c) => format!(
            "{version}+{}{}",
            &c.hash[..12],
            if c.modified { ".modified" } else { "" }
        ),
        None => format!("{version}+unknown"),
    }
}

/// `git args…` in `root`: its output without the final line end, or `None` when Git is missing
/// or fails (outside a checkout, an unknown tag).
fn git(root: &Path, args: &[&str]) -> Option<String> {
    let out = Command::new("git")
        .arg("-C")
        .arg(root)
        .args(args)
        .env("TZ", "UTC")
        .output()
        .ok()
        .filter(|out| out.status.success())?;
    Some(String::from_utf8_lossy(&out.stdout).trim_end().to_string())
}

/// The commit checked out at `root` and what Git says of it for `version`, or `None` outside a
/// Git checkout of `root` itself (a source archive, even one unpacked inside another checkout)
/// or without Git.
pub fn commit(root: &Path, version: &str) -> Option<Commit> {
    let top = git(root, &["rev-parse", "--show-toplevel"])?;
    if Path::new(&top).canonicalize().ok()? != root.canonicalize().ok()? {
        return None;
    }
    let hash = git(root, &["rev-parse", "--verify", "HEAD"])?;
    let time = git(
        root,
        &[
            "log",
            "-1",
            "--format=%cd",
            "--date=format-local:%Y-%m-%dT%H:%M:%SZ",
            "HEAD",
        ],
    )?;
    let modified = !git(root, &["status", "--porcelain"])?.is_empty();
    let tag = format!("refs/tags/v{}^{{commit}}", core_text(version));
    let release_tag = git(root, &["rev-parse", "--quiet", "--verify", &tag]);
    Some(Commit {
        hash,
        time,
        modified,
        release_tag,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const HASH: &str = "0123456789abcdef0123456789abcdef01234567";
    const OTHER: &str = "fedcba9876543210fedcba9876543210fedcba98";

    fn commit(modified: bool, release_tag: Option<&str>) -> Commit {
        Commit {
            hash: HASH.into(),
            time: "2026-12-07T09:05:18Z".into(),
            modified,
            release_tag: release_tag.map(Into::into),
        }
    }

    const CHANGELOG: &str =
        "# Changelog\n\n## 1.1.0 (unreleased)\n\n* new\n\n## 1.0.0 (2026-12-04)\n\n* first\n";
    const RELEASED: &str =
        "# Changelog\n\n## 1.1.0 (2026-12-20)\n\n* new\n\n## 1.0.0 (2026-12-04)\n\n* first\n";

    #[test]
    fn a_build_between_releases_names_its_commit() {
        assert_eq!(
            stamped("1.1.0-dev", Some(&commit(false, None)), false),
            "1.1.0-dev+0123456789ab"
        );
        assert_eq!(
            stamped("1.1.0-dev", Some(&commit(true, None)), false),
            "1.1.0-dev+0123456789ab.modified"
        );
        assert_eq!(stamped("1.1.0-dev", None, false), "1.1.0-dev+unknown");
    }

    #[test]
    fn only_the_tagged_or_checked_release_commit_says_the_bare_version() {
        assert_eq!(
            stamped("1.1.0", Some(&commit(false, Some(HASH))), false),
            "1.1.0"
        );
        assert_eq!(stamped("1.1.0", Some(&commit(false, None)), true), "1.1.0");
        // The release commit before its tag, modified, or another commit that says 1.1.0.
        assert_eq!(
            stamped("1.1.0", Some(&commit(false, None)), false),
            "1.1.0+0123456789ab"
        );
        assert_eq!(
            stamped("1.1.0", Some(&commit(true, Some(HASH))), false),
            "1.1.0+0123456789ab.modified"
        );
        assert_eq!(
            stamped("1.1.0", Some(&commit(false, Some(OTHER))), false),
            "1.1.0+0123456789ab"
        );
    }

    #[test]
    fn the_changelog_headings_are_read_or_refused_by_name() {
        assert_eq!(
            sections(RELEASED).unwrap(),
            vec![
                ("1.1.0".into(), Section::Released("2026-12-20".into())),
                ("1.0.0".into(), Section::Released("2026-12-04".into())),
            ]
        );
        assert_eq!(sections(CHANGELOG).unwrap()[0].1, Section::Unreleased);
        for bad in [
            "## Unreleased",
            "## 1.1.0",
            "## 1.1.0 (soon)",
            "## 1.1.0 (2026-12-2)",
            "## 1.1 (2026-12-20)",
            "## 1.1.0-dev (unreleased)",
            "## 01.1.0 (2026-12-20)",
        ] {
            let e = sections(bad).unwrap_err();
            assert!(e.contains(bad), "{e}");
        }
    }

    #[test]
    fn the_changelog_must_begin_with_the_version_of_cargo_toml() {
        check_repository("1.1.0-dev", CHANGELOG, None).unwrap();
        check_repository("1.1.0", RELEASED, Some(&commit(false, None))).unwrap();
        check_repository("1.1.0", RELEASED, Some(&commit(false, Some(HASH)))).unwrap();
        let refused = [
            ("1.1.0-dev", RELEASED, "(unreleased)"),
            ("1.1.0", CHANGELOG, "(YYYY-MM-DD)"),
            ("1.2.0-dev", CHANGELOG, "## 1.2.0 (unreleased)"),
            ("1.1", CHANGELOG, "not X.Y.Z"),
            (
                "1.1.0-dev",
                "## 1.1.0 (unreleased)\n## 1.0.0 (unreleased)\n",
                "only the first",
            ),
            (
                "1.1.0-dev",
                "## 1.1.0 (unreleased)\n## 1.2.0 (2026-12-04)\n",
                "not above it",
            ),
            ("1.1.0-dev", "# Changelog\n", "no section"),
        ];
        for (version, changelog, message) in refused {
            let e = check_repository(version, changelog, None).unwrap_err();
            assert!(e.contains(message), "{version}: {e}");
        }
    }

    #[test]
    fn a_commit_after_a_release_must_say_a_later_version() {
        let e = check_repository("1.1.0", RELEASED, Some(&commit(false, Some(OTHER)))).unwrap_err();
        assert!(e.contains("was released from commit fedcba98"), "{e}");
        let e = check_repository("1.1.0-dev", CHANGELOG, Some(&commit(false, Some(OTHER))))
            .unwrap_err();
        assert!(e.contains("1.1.0 is released (tag v1.1.0"), "{e}");
    }

    #[test]
    fn a_release_is_refused_naming_every_reason() {
        let url = "https://example.org/plate-impact";
        assert!(release_problems("1.1.0", RELEASED, Some(&commit(false, None)), url).is_empty());
        assert!(
            release_problems("1.1.0", RELEASED, Some(&commit(false, Some(HASH))), url).is_empty()
        );
        let all = release_problems("1.1.0", CHANGELOG, Some(&commit(true, Some(OTHER))), "");
        assert_eq!(all.len(), 4, "{all:?}");
        for (problem, words) in all.iter().zip([
            "section of 1.1.0 is not released",
            "differs from the commit",
            "v1.1.0 already names commit fedcba98",
            "names no `repository`",
        ]) {
            assert!(problem.contains(words), "{problem}");
        }
        let dev = release_problems("1.1.0-dev", CHANGELOG, None, url);
        assert!(dev[0].contains("1.1.0-dev is a pre-release"), "{dev:?}");
        assert!(dev[1].contains("no Git commit"), "{dev:?}");
        let missing = release_problems("1.2.0", RELEASED, Some(&commit(false, None)), url);
        assert!(missing[0].contains("no section `## 1.2.0"), "{missing:?}");
    }

    #[test]
    fn git_gives_the_commit_its_time_changes_and_release_tag() {
        let dir = std::env::temp_dir().join(format!("plate-impact-version-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        assert!(
            super::commit(&dir, "1.0.0").is_none(),
            "outside a Git checkout"
        );
        let git = |args: &[&str]| {
            let done = Command::new("git")
                .arg("-C")
                .arg(&dir)
                .args(["-c", "user.name=t", "-c", "user.email=t@example.org"])
                .args(["-c", "commit.gpgsign=false", "-c", "tag.gpgsign=false"])
                .args(args)
                .env("GIT_AUTHOR_DATE", "2026-12-07T10:11:12+02:00")
                .env("GIT_COMMITTER_DATE", "2026-12-07T10:11:12+02:00")
                .output()
                .unwrap();
            assert!(done.status.success(), "git {args:?}: {done:?}");
        };
        git(&["init", "-q"]);
        std::fs::write(dir.join("file"), "one").unwrap();
        git(&["add", "file"]);
        git(&["commit", "-q", "-m", "one"]);
        let first = super::commit(&dir, "1.0.0").unwrap();
        assert_eq!(first.hash.len(), 40);
        assert_eq!(
            first.time, "2026-12-07T08:11:12Z",
            "the committer's time in UTC"
        );
        assert!(!first.modified && first.release_tag.is_none());
        // An annotated tag names its commit; a -dev version looks for the tag of its X.Y.Z.
        git(&["tag", "-a", "v1.0.0", "-m", "release"]);
        for version in ["1.0.0", "1.0.0-dev"] {
            let tagged = super::commit(&dir, version).unwrap();
            assert_eq!(tagged.release_tag.as_deref(), Some(first.hash.as_str()));
        }
        assert!(super::commit(&dir, "1.1.0").unwrap().release_tag.is_none());
        std::fs::write(dir.join("other"), "untracked").unwrap();
        assert!(super::commit(&dir, "1.0.0").unwrap().modified);
        // Sources unpacked inside another checkout are not that checkout's commit.
        std::fs::create_dir_all(dir.join("unpacked")).unwrap();
        assert!(super::commit(&dir.join("unpacked"), "1.0.0").is_none());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn this_repository_says_one_version_everywhere() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let version = env!("CARGO_PKG_VERSION");
        let changelog = std::fs::read_to_string(root.join("CHANGELOG.md")).unwrap();
        check_repository(version, &changelog, super::commit(root, version).as_ref()).unwrap();
    }
}
