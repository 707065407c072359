//! PlateImpact: a thin Kirchhoff–Love plate clamped on one edge to a moving base, free on the
//! others, vibrating between two rigid flat obstacles (see `SPEC.md`).
//!
//! Map of the crate, in the one direction its dependencies run:
//! * [`mesh`], [`quadrature`]: structured meshes of the rectangle and exact triangle rules;
//! * [`element`]: the C¹ elements (Argyris triangle, reduced FVS quadrilateral);
//! * [`scene`]: the parameter set shared by examples, the FMU and Python;
//! * [`error`]: errors that name the parameter and the limit;
//! * [`simulation`]: one running simulation (a temporary stand-in on the `fmi` branch);
//! * [`fmi`]: the FMI 2.0 Co-Simulation interface, the crate's only unsafe code.

pub mod element;
pub mod error;
pub mod fmi;
pub mod mesh;
pub mod quadrature;
pub mod scene;
pub mod simulation;

pub use error::Error;
