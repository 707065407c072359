//! FMI 3.0 Co-Simulation: its call-state table, its instance (the generic
//! [`crate::fmi::instance::Instance`] with FMI 3.0's table and calls) and its exported C functions,
//! every function of `fmi3Functions.h`. It drives the same plate binding as [`crate::fmi::fmi2`],
//! through the same generic machinery; what FMI 3.0 adds is the independent variable, the
//! displacement field as an array sized by structural parameters (Configuration Mode), and the
//! early return of fmi3DoStep at impacts.

pub mod call_state;
// The exported C functions: `no_mangle` and the raw pointers of the FMI calls.
#[allow(unsafe_code)]
pub mod exports;
pub mod instance;

#[cfg(test)]
mod tests;
