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
//!      the next level, its multipliers μ and, used once, their work μᵀB(x − y).
//!
//!   What a stage found (the reach's distance, the prediction's norm, whether a value is a
//!   stand-in, the prediction a correction keeps) is a field of that stage, not a flag of the
//!   backend; a stage that ends the backend's part hands the caller the [`StepFields`] (the
//!   three levels and the maps), with which it may solve the step another way (clarabel).

mod stages;

use super::modal::{ModalBackend, ModalData};
use super::sparse::{self, SparseBackend};
use super::FreeSystem;
use crate::error::Error;
pub(in crate::scheme) use stages::{
    Correction, Prediction, Screened, Solve, StepFields, TimeLevels, Values,
};

/// Forcing of one step, as multipliers of the precomputed free-dof vectors f (unit load) and
/// m₁ = (M𝟙)_f (the mass matrix times the rigid translation).
#[derive(Clone, Copy, Debug)]
pub struct StepForcing {
    /// Multiplier of f: ½Δt²(p_{n+1} + p_{n−1}) (start: ½Δt²·(p_1 + p_0)/2).
    pub load: f64,
    /// Multiplier of m₁: −(z_{n+1} − 2z_n + z_{n−1}) (start: −(z_1 − z_0)).
    pub translation: f64,
    /// Whether this is the start step n = 0 → 1.
    pub start: bool,
}

/// The quadratic and linear forms of two consecutive fields that the discrete energy needs.
#[derive(Clone, Copy, Debug, Default)]
pub struct EnergyPieces {
    /// ẇᵀMẇ with ẇ = (w_n − w_{n−1})/Δt.
    pub velocity_mass_velocity: f64,
    /// m₁ᵀẇ.
    pub translation_mass_velocity: f64,
    /// w_nᵀ K w_n.
    pub stiffness_current: f64,
    /// w_{n−1}ᵀ K w_{n−1}.
    pub stiffness_previous: f64,
    /// fᵀ w_n.
    pub load_current: f64,
    /// fᵀ w_{n−1}.
    pub load_previous: f64,
}

/// The sums over a field that every step needs, formed in one pass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FieldSums {
    /// An upper bound on ‖x‖², the squared Euclidean norm in the backend's coordinates, equal to
    /// it to round-off from `FieldMaps::field_sums` (a prediction may give a looser one, see
    /// the modal backend's reach): finite exactly when every entry is finite and none is beyond
    /// ~1e154.
    pub norm_squared: f64,
    /// m₁ᵀw = 𝟙ᵀM w, the mass-weighted sum of the relative displacement (kg·m).
    pub translation: f64,
    /// For a prediction x = w_{n+1}: (x − w_{n−1})ᵀC(x − w_{n−1}) with C the damping matrix, when
    /// the backend formed it in the same pass (it then equals `FieldMaps::damping_quadratic` to
    /// round-off); `None` otherwise.
    pub damping: Option<f64>,
}

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
    /// [`FreeSystem::right_hand_side`]; for the start step (`forcing.start`) A is the undamped A₀,
    /// and so is the system that the stages' contact solve uses. The [`Prediction`] holds the
    /// prediction's [`FieldSums`] from passes the backend makes anyway: the translation bit for
    /// bit as [`FieldMaps::field_sums`] gives it, the norm as an upper bound (equal to it to
    /// round-off, or looser: the modal backend bounds it from its screening's reference), the
    /// damping quadratic when the backend formed it. An error is a failure to factor the step's
    /// matrix.
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
        Ok(match self {
            Backend::Modal(modal) => {
                let (sums, predicted) = modal.predict(previous, current, forcing, next);
                let maps = FieldMaps::Modal(predicted.data());
                Prediction::modal(
                    StepFields::new(maps, previous, current, next),
                    sums,
                    predicted,
                )
            }
            Backend::Sparse(backend) => {
                let (sums, step) = backend.predict(previous, current, forcing, next)?;
                let maps = FieldMaps::Sparse(step.free());
                Prediction::sparse(StepFields::new(maps, previous, current, next), sums, step)
            }
        })
    }
}

/// The read-only maps of fields in one backend's coordinates (see the module docs).
#[derive(Clone, Copy)]
pub(in crate::scheme) enum FieldMaps<'a> {
    /// Modal coordinates q, w_f = Φq.
    Modal(&'a ModalData),
    /// Free-dof vectors w_f.
    Sparse(&'a FreeSystem),
}

impl FieldMaps<'_> {
    /// Length of a field.
    pub(in crate::scheme) fn dimension(self) -> usize {
        match self {
            FieldMaps::Modal(data) => data.dimension(),
            FieldMaps::Sparse(free) => sparse::dimension(free),
        }
    }

    /// The [`FieldSums`] of a field.
    pub(in crate::scheme) fn field_sums(self, field: &[f64]) -> FieldSums {
        match self {
            FieldMaps::Modal(data) => data.field_sums(field),
            FieldMaps::Sparse(free) => sparse::field_sums(free, field),
        }
    }

    /// fᵀw, the work-conjugate of a 1 Pa pressure (m³).
    pub(in crate::scheme) fn load_projection(self, field: &[f64]) -> f64 {
        match self {
            FieldMaps::Modal(data) => data.load_projection(field),
            FieldMaps::Sparse(free) => sparse::load_projection(free, field),
        }
    }

    /// μᵀB(x − y) for multipliers μ (length m) of the constrained vertices, formed from the fields
    /// `next` = x and `previous` = y alone (a [`Correction`] forms it from what its solve kept).
    pub(in crate::scheme) fn multiplier_work(
        self,
        next: &[f64],
        previous: &[f64],
        multipliers: &[f64],
    ) -> f64 {
        match self {
            FieldMaps::Modal(data) => data.multiplier_work(next, previous, multipliers),
            FieldMaps::Sparse(free) => sparse::multiplier_work(free, next, previous, multipliers),
        }
    }

    /// A constant c ≥ 1 such that, for fields x, y, z of squared norm at most N ≥ 1 and
    /// ẇ = (x − y)/Δt, each of ẇᵀMẇ, |m₁ᵀẇ|, |m₁ᵀ(x − 2y + z)|/Δt², xᵀKx, |fᵀx| and the
    /// output values of x is at most c·N. The stepper uses it to prove cheaply that the outputs of
    /// a step cannot overflow.
    pub(in crate::scheme) fn magnitude_scale(self, time_step: f64) -> f64 {
        match self {
            FieldMaps::Modal(data) => data.magnitude_scale(time_step),
            FieldMaps::Sparse(free) => sparse::magnitude_scale(free, time_step),
        }
    }

    /// The constrained values of a field, into `out`.
    pub(in crate::scheme) fn constrained_values(self, field: &[f64], out: &mut [f64]) {
        match self {
            FieldMaps::Modal(data) => data.constrained_values(field, out),
            FieldMaps::Sparse(free) => sparse::constrained_values(free, field, out),
        }
    }

    /// A field as a free-dof vector w_f.
    pub(in crate::scheme) fn to_free_dofs(self, field: &[f64]) -> Vec<f64> {
        match self {
            FieldMaps::Modal(data) => data.to_free_dofs(field),
            FieldMaps::Sparse(_) => field.to_vec(),
        }
    }

    /// The field of a free-dof vector w_f, into `field`.
    pub(in crate::scheme) fn field_of_free_dofs(self, w: &[f64], field: &mut [f64]) {
        match self {
            FieldMaps::Modal(data) => data.field_of_free_dofs(w, field),
            FieldMaps::Sparse(_) => field.copy_from_slice(w),
        }
    }

    /// Energy pieces of two consecutive fields.
    pub(in crate::scheme) fn energy(
        self,
        previous: &[f64],
        current: &[f64],
        time_step: f64,
    ) -> EnergyPieces {
        match self {
            FieldMaps::Modal(data) => data.energy(previous, current, time_step),
            FieldMaps::Sparse(free) => sparse::energy(free, previous, current, time_step),
        }
    }

    /// (x − y)ᵀ C (x − y) for the damping matrix C of the free dofs.
    pub(in crate::scheme) fn damping_quadratic(self, x: &[f64], y: &[f64]) -> f64 {
        match self {
            FieldMaps::Modal(data) => data.damping_quadratic(x, y),
            FieldMaps::Sparse(free) => sparse::damping_quadratic(free, x, y),
        }
    }

    /// A field's relative displacement w at the three output points.
    pub(in crate::scheme) fn output_values(self, field: &[f64]) -> [f64; 3] {
        match self {
            FieldMaps::Modal(data) => data.output_values(field),
            FieldMaps::Sparse(free) => sparse::output_values(free, field),
        }
    }
}
