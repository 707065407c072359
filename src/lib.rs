//! PlateImpact: a thin Kirchhoff–Love plate clamped on one edge to a moving base, free on the
//! others, vibrating between two rigid flat obstacles.
//!
//! The repository's `docs/` describe what the crate computes: `docs/model.md` (the physical
//! model and the shipped scenes), `docs/elements.md` (the C¹ elements and the discretisation),
//! `docs/scheme.md` (the time scheme and how a step is solved) and `docs/fmu.md` (the FMU
//! contract).
//!
//! Map of the crate, in the one direction its dependencies run:
//! * [`mesh`], [`quadrature`]: structured meshes of the rectangle and exact triangle rules;
//! * [`element`]: the C¹ elements (Argyris triangle, reduced FVS quadrilateral);
//! * [`obstacles`]: where the obstacles constrain the discrete plate (the contact points);
//! * [`assembly`], [`system`]: dofs, sparse M, K and load, clamp, point evaluation;
//! * [`backend_choice`], [`budget`]: the linear backend a scene runs on and its memory estimate;
//! * [`modes`]: natural frequencies and M-orthonormal mode shapes;
//! * [`contact`]: the box-constrained QP of a step (exact active set, clarabel reference);
//! * [`scheme`]: the β = ½ Newmark–Dumont–Paoli stepper with modal and sparse backends;
//! * [`simulation`]: the model the FMU drives;
//! * [`scene`]: the parameter set shared by examples, the FMU and Python;
//! * [`error`]: errors that name the parameter and the limit;
//! * [`fmi`]: the FMI 2.0 and FMI 3.0 Co-Simulation interfaces, the crate's only unsafe code.
// Unsafe code is refused everywhere but where the C ABI needs it: the FMI shell modules that
// export or call C functions allow it, each saying why (src/fmi/mod.rs).
#![deny(unsafe_code)]

pub mod advice;
pub mod assembly;
pub mod backend_choice;
pub mod budget;
pub mod contact;
pub mod element;
pub mod error;
pub mod fmi;
pub mod mesh;
pub mod modes;
pub mod obstacles;
pub mod quadrature;
pub mod scene;
pub mod scheme;
pub mod simulation;
pub mod system;

pub use error::Error;
