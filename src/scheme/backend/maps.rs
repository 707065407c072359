//! The read-only face of a backend: maps of fields in its coordinates, which a step's stages
//! hand on alongside the fields they borrow.

use crate::scheme::free_system::FreeSystem;
use crate::scheme::modal::ModalData;
use crate::scheme::sparse;
use crate::scheme::sums::{EnergyPieces, FieldSums};
use crate::system::OUTPUT_POINTS;

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
    /// `next` = x and `previous` = y alone (a [`Correction`](super::Correction) forms it from what its solve kept).
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

    /// The constrained value of vertex `i` of a field alone (one row of
    /// [`FieldMaps::constrained_values`], equal to its entry to round-off): what an impact law
    /// reads at the few vertices in contact.
    pub(in crate::scheme) fn constrained_value(self, field: &[f64], i: usize) -> f64 {
        match self {
            FieldMaps::Modal(data) => data.constrained_value(field, i),
            FieldMaps::Sparse(free) => sparse::constrained_value(free, field, i),
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
    pub(in crate::scheme) fn output_values(self, field: &[f64]) -> [f64; OUTPUT_POINTS] {
        match self {
            FieldMaps::Modal(data) => data.output_values(field),
            FieldMaps::Sparse(free) => sparse::output_values(free, field),
        }
    }
}
