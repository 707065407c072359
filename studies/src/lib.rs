//! The apparatus of the studies that regenerate docs/ (studies/README.md): one home for each
//! piece the studies share. The studies themselves are the crate's binaries (`src/bin/`), one per
//! study, each split into plan (which runs), run (the simulations) and write (the CSVs); their
//! plots and tables are the Python package's (`plateimpact_tools.studies` in tools/).

use std::path::Path;

pub mod autocorrelation;
pub mod cli;
pub mod element;
pub mod order;
pub mod output;
pub mod recorder;
pub mod revision;
pub mod sample;
pub mod windows;

/// The repository's root directory: the parent of this crate's.
pub fn repository() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("the studies crate lies in the repository")
}
