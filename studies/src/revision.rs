//! The revision stamp: the commit of the code that ran, which each study writes into its meta
//! file so that its data name the code that made them.

use crate::repository;

/// The commit of the repository's checkout (`git rev-parse HEAD`), with `+modified` when the
/// work tree differs from it (`git status --porcelain` prints anything). `unknown` without git.
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
