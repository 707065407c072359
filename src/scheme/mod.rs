//! The β = ½ Newmark–Dumont–Paoli scheme with obstacles, base motion, load and preload
//! (docs/scheme.md).
//!
//! Unknowns are split as u = z(t)·𝟙 + w, with 𝟙 the rigid translation (value dofs 1) and w the
//! displacement relative to the base, whose clamp dofs are all zero. Because K𝟙 = 0, the scheme for
//! the free dofs of w reads, with A = M_ff + ½Δt²K_ff + ½ΔtC_ff (C = αM + βK the Rayleigh damping
//! of the relative motion, zero by default) and m₁ = (M𝟙)_f,
//!
//!   A w_{n+1} = 2 M w_n − (A − ΔtC) w_{n−1} + ½Δt²(p_{n+1} + p_{n−1}) f
//!               − m₁ (z_{n+1} − 2z_n + z_{n−1}) + Bᵀμ,
//!
//! which is the scheme for u exactly (up to the round-off of K𝟙), and the start step, undamped
//! because v_0 = 0, A₀ w_1 = M w_0 + ¼Δt²(p_1 + p_0) f − m₁ (z_1 − z_0) + Bᵀμ with
//! A₀ = M_ff + ½Δt²K_ff (F̄_0 read as (F_1 + F_0)/2). The obstacle bounds on u become g − z_{n+1}
//! on w; with restitution e > 0, Newton's impact law raises the lower bound of a vertex whose
//! contact closes in the step to u_n − e(u_n − u_{n−1}) (mirrored at the upper obstacle), still a
//! box ([`newton_bounds`], `impact.rs`). μ is the QP multiplier: the contact force at a vertex is
//! μ/Δt² (N), 2μ/Δt² after the start step (its equation is scaled by Δt²/2).
//!
//! Layout: [`Stepper`] (`stepper.rs`) owns the three time levels and runs the scheme; the linear
//! part runs in one of two backends, `modal/` (dense eigenbasis, O(n) per contact-free step) or
//! `sparse.rs` (sparse Cholesky), chosen by [`crate::scene::LinearChoice`] (`auto.rs`), each seen
//! through its read-only field maps and a step that borrows it through typed stages (prediction,
//! screening, values, correction: `backend.rs`); [`FreeSystem`] is the plate restricted to its
//! free dofs, `preload.rs` the initial static equilibrium, `energy.rs` the discrete energy,
//! [`Outputs`] what a host reads and [`State`] what it saves and restores.

mod auto;
mod backend;
mod bounds;
mod energy;
mod free_system;
mod impact;
mod modal;
mod outputs;
mod preload;
mod reference;
mod sparse;
mod state;
mod stepper;
mod sums;
mod vectors;

pub use crate::backend_choice::{resolve as resolve_linear, MODAL_AUTO_LIMIT};
pub use energy::EnergyFlows;
pub use free_system::{FreeSystem, StepForcing};
pub use impact::{
    newton_bounds, persistent_bounds, persistent_lower_bound, persistent_upper_bound, VertexMotion,
};
pub use outputs::Outputs;
pub use state::State;
pub use state::MAX_STEP_INDEX;
pub use stepper::{
    StepPath, StepReport, Stepper, RESTORE_BOUND_TOLERANCE, RESTORE_FORCE_TOLERANCE,
};
pub use sums::{EnergyPieces, FieldSums};
