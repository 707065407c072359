//! The command line of a study: the exit code of a run, the value after a flag, a positive count
//! and a `key=value` scene override.
//!
//! The exit code, the positive count and the scene override are the library's examples' too
//! (`modes`, `scene`), compiled here from their one home, `examples/common/mod.rs`.

#[path = "../../examples/common/mod.rs"]
mod common;

pub use common::{exit_code, positive_integer, set_override};

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
