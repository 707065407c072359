//! FMI 2.0 Co-Simulation: its call-state table, its instance (the generic
//! [`crate::fmi::instance::Instance`] with FMI 2.0's table and calls) and its exported C functions.
//! Only this module knows FMI 2.0; [`crate::fmi::fmi3`] sits beside it on the same generic
//! machinery and the same plate binding.

pub mod call_state;
// The exported C functions: `no_mangle` and the raw pointers of the FMI calls.
#[allow(unsafe_code)]
pub mod exports;
pub mod instance;

#[cfg(test)]
mod tests;
