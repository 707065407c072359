//! The narrow interface between the stepper and a linear backend.
//!
//! The stepper owns the fields of the three time levels (w_{n−1}, w_n and the next w_{n+1}) in the
//! backend's coordinates, and everything else of the scheme: forcing, bounds, contact, outputs.
//! A backend only maps fields: it predicts the unconstrained w_{n+1}, solves the step's contact
//! problem from that prediction by the path that suits its linear algebra, reads constrained
//! vertex values, energy pieces and output values of a field, and converts fields to and from
//! free-dof vectors.

use crate::contact::{BoundState, PdasReport, PdasSettings};
use crate::error::Error;

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
    /// it to round-off from [`LinearBackend::field_sums`] (a prediction may give a looser one,
    /// see the modal backend's reach): finite exactly when every entry is finite and none is
    /// beyond ~1e154.
    pub norm_squared: f64,
    /// m₁ᵀw = 𝟙ᵀM w, the mass-weighted sum of the relative displacement (kg·m).
    pub translation: f64,
    /// For a prediction x = w_{n+1}: (x − w_{n−1})ᵀC(x − w_{n−1}) with C the damping matrix, when
    /// the backend formed it in the same pass (it then equals
    /// [`LinearBackend::damping_quadratic`] to round-off); `None` otherwise.
    pub damping: Option<f64>,
}

/// The linear part of the scheme in one set of coordinates (see the module docs). A field is a
/// slice of length [`LinearBackend::dimension`]; "the constrained values" of a field are the
/// relative displacements w at the obstacle-constrained vertices, in their order.
pub trait LinearBackend: Send {
    /// Length of a field.
    fn dimension(&self) -> usize;
    /// Writes the unconstrained prediction A⁻¹b into `next`, b being the right-hand side of the
    /// step from `previous` (w_{n−1}) and `current` (w_n), see
    /// [`FreeSystem::right_hand_side`](super::FreeSystem::right_hand_side); for the start step
    /// (`forcing.start`) A is the undamped A₀, and so is the system that
    /// [`LinearBackend::solve_contact`] then uses. Returns the
    /// prediction's [`FieldSums`] from passes the backend makes anyway: the translation bit for
    /// bit as [`LinearBackend::field_sums`] gives it, the norm as an upper bound (equal to it to
    /// round-off, or looser: the modal backend bounds it from its screening's reference), the
    /// damping quadratic when the backend formed it. An error is a failure to factor the step's
    /// matrix.
    fn predict(
        &mut self,
        previous: &[f64],
        current: &[f64],
        forcing: &StepForcing,
        next: &mut [f64],
    ) -> Result<FieldSums, Error>;
    /// The [`FieldSums`] of a field.
    fn field_sums(&self, field: &[f64]) -> FieldSums;
    /// fᵀw, the work-conjugate of a 1 Pa pressure (m³).
    fn load_projection(&self, field: &[f64]) -> f64;
    /// μᵀB(x − y) for the QP multipliers μ of the step just solved, whose solution is `next` = x
    /// (y = `previous`). A backend may use (and use up) what its last
    /// [`LinearBackend::solve_contact`] left, so call it at most once, right after the step's solve.
    fn multiplier_work(&mut self, next: &[f64], previous: &[f64], multipliers: &[f64]) -> f64;
    /// A constant c ≥ 1 such that, for fields x, y, z of squared norm at most N ≥ 1 and
    /// ẇ = (x − y)/Δt, each of ẇᵀMẇ, |m₁ᵀẇ|, |m₁ᵀ(x − 2y + z)|/Δt², xᵀKx, |fᵀx| and the
    /// output values of x is at most c·N. The stepper uses it to prove cheaply that the outputs of
    /// a step cannot overflow.
    fn magnitude_scale(&self, time_step: f64) -> f64;
    /// Whether the last prediction `next` provably satisfies lower ≤ w ≤ upper at every
    /// constrained vertex, without computing those values exactly (a cheap screening test).
    /// `false` means "not proven", not "violated": the caller then evaluates the values.
    fn prediction_proven_within(&mut self, next: &[f64], lower: f64, upper: f64) -> bool;
    /// After [`LinearBackend::prediction_proven_within`] failed on `next`: the constrained values
    /// that the contact solve of this step starts from, exact at every vertex the backend cannot
    /// prove inside `lower` ≤ w ≤ `upper`, and at the others possibly a stand-in value inside the
    /// bounds, which the backend's [`LinearBackend::solve_contact`] replaces by the exact value
    /// wherever the solution reaches it. A caller that needs every value exact (or reads them
    /// past the contact solve) uses [`LinearBackend::constrained_values`]. By default all exact.
    fn prediction_values(&mut self, next: &[f64], _lower: f64, _upper: f64, out: &mut [f64]) {
        self.constrained_values(next, out);
    }
    /// Solves the step's QP (docs/scheme.md §3) from the last prediction `next` = w* = A⁻¹b, whose
    /// constrained values are `prediction` (y* = Bw*): min ½wᵀAw − bᵀw over
    /// `lower` ≤ Bw ≤ `upper`, warm-started from the contact states `states`, which it updates.
    /// When the report's status [is solved](crate::contact::PdasStatus::is_solved), `next` is the
    /// exact minimiser w = A⁻¹(b + Bᵀμ) and [`LinearBackend::contact_multipliers`] gives μ;
    /// otherwise `next` is unspecified and the caller solves the step another way. An error is a
    /// failure of the linear algebra (a factorisation that lost positive definiteness).
    fn solve_contact(
        &mut self,
        next: &mut [f64],
        prediction: &[f64],
        lower: &[f64],
        upper: &[f64],
        states: &mut [BoundState],
        settings: &PdasSettings,
    ) -> Result<PdasReport, Error>;
    /// The multipliers μ (length m) of the last solved [`LinearBackend::solve_contact`].
    fn contact_multipliers(&self) -> &[f64];
    /// The constrained values of a field.
    fn constrained_values(&self, field: &[f64], out: &mut [f64]);
    /// A field as a free-dof vector w_f.
    fn to_free_dofs(&self, field: &[f64]) -> Vec<f64>;
    /// The field of a free-dof vector w_f.
    fn field_of_free_dofs(&self, w: &[f64], field: &mut [f64]);
    /// Energy pieces of two consecutive fields.
    fn energy(&self, previous: &[f64], current: &[f64], time_step: f64) -> EnergyPieces;
    /// (x − y)ᵀ C (x − y) for the Rayleigh damping matrix C of the free dofs.
    fn damping_quadratic(&self, x: &[f64], y: &[f64]) -> f64;
    /// A field's relative displacement w at the three output points.
    fn output_values(&self, field: &[f64]) -> [f64; 3];
}
