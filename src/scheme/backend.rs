//! The linear backends behind the stepper, and the two faces each shows it.
//!
//! The stepper owns the fields of the three time levels (w_{n−1}, w_n and the next w_{n+1}) in the
//! backend's coordinates ([`TimeLevels`]), and everything else of the scheme: forcing, bounds,
//! contact, outputs. A [`Backend`] (modal or sparse) only maps fields, through two faces:
//!
//! * its **field maps** ([`FieldMaps`], from [`Backend::maps`]): read-only maps of a field, namely
//!   its dimension, sums, constrained vertex values, energy pieces, projections and output
//!   values, and the conversions to and from free-dof vectors;
//! * its **step** ([`Backend::predict`]), which borrows the backend and the time levels for one
//!   step through typed stages, so that the order of a step is the only order that compiles:
//!
//!   1. [`Prediction`]: the unconstrained w_{n+1} in the next level, with its sums;
//!   2. [`Prediction::screen`]: a cheap proof that it satisfies the bounds, which ends the
//!      backend's part, or an [`Unproven`](stages::Unproven) stage;
//!   3. [`Unproven::values`](stages::Unproven::values): the values y* = Bw* the contact solve
//!      starts from, exact wherever the backend cannot prove them inside the bounds
//!      ([`Prediction::exact_values`] and
//!      [`Unproven::exact_values`](stages::Unproven::exact_values) evaluate them all exactly): a
//!      [`Values`] stage, which may end there;
//!   4. [`Values::solve`]: the contact solve, whose [`Correction`] holds the exact minimiser in
//!      the next level, its multipliers μ and, used once, their work μᵀB(x − y); or
//!      [`Correction::retry`] back to a [`Values`] stage, to solve again with the tighter bounds
//!      an impact law gave the vertices the solve pushed onto an obstacle.
//!
//!   What a stage found (the reach's distance, the prediction's norm, whether a value is a
//!   stand-in, the prediction a correction keeps) is a field of that stage, not a flag of the
//!   backend; a stage that ends the backend's part hands the caller the [`StepFields`] (the
//!   three levels and the maps), with which it may solve the step another way (clarabel).

mod maps;
mod stages;

use super::free_system::StepForcing;
use super::modal::ModalBackend;
use super::sparse::SparseBackend;
use crate::error::Error;
pub(in crate::scheme) use maps::FieldMaps;
use stages::Engine;
pub(in crate::scheme) use stages::{
    Correction, Prediction, Screened, Solve, StepFields, TimeLevels, Values,
};

/// The linear part of the scheme in one set of coordinates: a field is a slice of length
/// [`FieldMaps::dimension`]; "the constrained values" of a field are the relative displacements
/// w at the obstacle-constrained vertices, in their order.
// One backend per stepper, held inline: the variants' difference in size (the sparse backend's
// factors keep more bookkeeping) costs a few kilobytes once, a box an indirection every step.
#[allow(clippy::large_enum_variant)]
pub(in crate::scheme) enum Backend {
    /// Dense eigenbasis, O(n) per contact-free step (`modal/`).
    Modal(ModalBackend),
    /// Sparse Cholesky (`sparse.rs`).
    Sparse(SparseBackend),
}

impl Backend {
    /// The read-only maps of fields in this backend's coordinates.
    pub(in crate::scheme) fn maps(&self) -> FieldMaps<'_> {
        match self {
            Backend::Modal(modal) => FieldMaps::Modal(modal.data()),
            Backend::Sparse(sparse) => FieldMaps::Sparse(sparse.free()),
        }
    }

    /// Writes the unconstrained prediction A⁻¹b into the next level of `levels`, b being the
    /// right-hand side of the step from w_{n−1} and w_n, see
    /// [`FreeSystem::right_hand_side`](super::FreeSystem::right_hand_side); for the start step (`forcing.start`) A is the undamped A₀,
    /// and so is the system that the stages' contact solve uses. The [`Prediction`] holds the
    /// prediction's [`FieldSums`](super::FieldSums) from passes the backend makes anyway: the translation bit for
    /// bit as [`FieldMaps::field_sums`] gives it, the norm as an upper bound (equal to it to
    /// round-off, or looser: the modal backend bounds it from its screening's reference), the
    /// damping quadratic when the backend formed it. An error is a failure to factor the step's
    /// matrix.
    // One call site, on every step: inlined there, the Prediction needs no move out of a frame.
    #[inline]
    pub(in crate::scheme) fn predict<'a>(
        &'a mut self,
        levels: &'a mut TimeLevels,
        forcing: &StepForcing,
    ) -> Result<Prediction<'a>, Error> {
        let TimeLevels {
            previous,
            current,
            next,
        } = levels;
        let (previous, current): (&[f64], &[f64]) = (previous, current);
        let (maps, sums, engine) = match self {
            Backend::Modal(modal) => {
                let (sums, predicted) = modal.predict(previous, current, forcing, next);
                (
                    FieldMaps::Modal(predicted.data()),
                    sums,
                    Engine::Modal(predicted),
                )
            }
            Backend::Sparse(sparse) => {
                let (sums, step) = sparse.predict(previous, current, forcing, next)?;
                (FieldMaps::Sparse(step.free()), sums, Engine::Sparse(step))
            }
        };
        let fields = StepFields::new(maps, previous, current, next);
        Ok(Prediction::new(fields, sums, engine))
    }
}
