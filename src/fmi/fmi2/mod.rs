//! FMI 2.0 Co-Simulation: its call-state table, its instance and its exported C functions. Only
//! this module knows FMI 2.0; an FMI 3.0 interface would sit beside it on the same generic
//! machinery ([`crate::fmi::model`], logger, serialized states) and the same plate binding.

pub mod call_state;
pub mod exports;
pub mod instance;

#[cfg(test)]
mod tests;
