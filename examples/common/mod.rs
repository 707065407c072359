//! Pieces shared by the examples (`modes`, `scene`) and the studies (the crate in `studies/`,
//! whose `cli` module compiles this file too, so that each piece has one home): the exit code of
//! a run and the command-line values they parse alike (a positive count, a `key=value` scene
//! override).

// Each example compiles this module on its own and uses a part of it.
#![allow(dead_code)]

use plate_impact::scene::Scene;
use std::process::ExitCode;
use std::str::FromStr;

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
