//! The contact-free part of the scheme with a sparse Cholesky factorisation of
//! A_ff = M_ff + ½Δt²K_ff + ½ΔtC_ff, for meshes too large for a dense eigenbasis, and the contact
//! solve on the same factor.
//!
//! Per step: b = 2 M w_n − (A − ΔtC) w_{n−1} + r (start: b = M w_0 + r), then w_{n+1} = A⁻¹ b:
//! two sparse matrix–vector products for b, and two Cholesky solves with one more product for the
//! iterative refinement. The factor, the Delassus columns it yields and the primal elimination
//! live in one [`SparseContact`], which also picks how each contact step is solved
//! (docs/contact.md); its factor uses the nested-dissection ordering of the mesh when that fills
//! less than faer's minimum degree ordering. With damping the start step's matrix is the undamped
//! A₀ = M + ½Δt²K: its own [`SparseContact`] is made when a start step runs and dropped after it,
//! so a run holds the factor of A only.
//!
//! A step borrows the backend as a [`Step`] from [`SparseBackend::predict`] on: the step's factor
//! (A or A₀), b and the workspace of its contact solve. The field maps (free functions here, over
//! the [`FreeSystem`]) are the identity's: a field is w_f itself.

use super::bounds::ObstacleBounds;
use super::free_system::{quadratic, FreeSystem, StepForcing};
use super::sums::{EnergyPieces, FieldSums};
use super::vectors::{dot, sum_of_squares};
use crate::contact::delassus::DEFAULT_DELASSUS_BUDGET;
use crate::contact::ordering::nested_dissection;
use crate::contact::sparse_contact::SparseContact;
use crate::contact::{BoundState, PdasReport, PdasSettings};
use crate::error::Error;
use crate::system::OUTPUT_POINTS;
use faer::sparse::SparseColMat;
use std::sync::Arc;

/// The sparse backend: fields are free-dof vectors w_f.
pub(in crate::scheme) struct SparseBackend {
    free: Arc<FreeSystem>,
    /// The factor of A and the contact solve on it.
    contact: SparseContact,
    /// The same for the start step's A₀ when damping makes it differ from A, while a start step
    /// is being solved.
    start_contact: Option<SparseContact>,
    /// b of the step being solved, kept for the contact solve.
    rhs: Vec<f64>,
    /// The unconstrained prediction w* of the step being solved, while its contact is solved.
    unconstrained: Vec<f64>,
}

impl SparseBackend {
    /// Factors A = M + ½Δt²K + ½ΔtC of `free` (ordering analysed once, see the module docs).
    pub(in crate::scheme) fn new(free: Arc<FreeSystem>) -> Result<SparseBackend, Error> {
        let contact = contact_solve(&free, &free.system)?;
        let n = free.load.len();
        Ok(SparseBackend {
            contact,
            start_contact: None,
            rhs: vec![0.0; n],
            unconstrained: vec![0.0; n],
            free,
        })
    }

    /// The free system, over which the field maps work.
    pub(in crate::scheme) fn free(&self) -> &FreeSystem {
        &self.free
    }

    /// Writes the unconstrained prediction w* = A⁻¹b into `next` (A₀ for the start step, whose
    /// factor is made now and dropped at the next step), b the right-hand side from `previous`
    /// and `current` ([`FreeSystem::right_hand_side`]), and returns its sums with the step. An
    /// error is a failure to factor A₀ or to solve.
    pub(in crate::scheme) fn predict(
        &mut self,
        previous: &[f64],
        current: &[f64],
        forcing: &StepForcing,
        next: &mut [f64],
    ) -> Result<(FieldSums, Step<'_>), Error> {
        let SparseBackend {
            free,
            contact,
            start_contact,
            rhs,
            unconstrained,
        } = self;
        let free: &FreeSystem = free;
        if !forcing.start {
            // The start step is over: its system is not needed again unless the run restarts.
            *start_contact = None;
        }
        free.right_hand_side(forcing, previous, current, rhs);
        // The contact solve of the step: on A₀ for a damped start step, else on A.
        let contact = match free.start_system().filter(|_| forcing.start) {
            None => contact,
            Some(start_matrix) => {
                if start_contact.is_none() {
                    *start_contact = Some(contact_solve(free, start_matrix)?);
                }
                start_contact.as_mut().expect("made for this start step")
            }
        };
        contact.solve_unconstrained(rhs, next)?;
        let step = Step {
            free,
            contact,
            rhs,
            unconstrained,
        };
        Ok((field_sums(free, next), step))
    }
}

/// The [`SparseContact`] of the matrix `a` (A or A₀) of `free`, its factor ordered by nested
/// dissection of the mesh when that fills less than minimum degree.
fn contact_solve(
    free: &FreeSystem,
    a: &Arc<SparseColMat<usize, f64>>,
) -> Result<SparseContact, Error> {
    SparseContact::new(
        Arc::clone(a),
        &free.contact,
        DEFAULT_DELASSUS_BUDGET,
        Some(&nested_dissection(&free.nodes)),
    )
    .map_err(|e| {
        Error::Numerical(format!(
            "A = M + ½Δt²K + ½ΔtC could not be factored ({e}); check solver.time_step and the \
             material"
        ))
    })
}

/// The sparse backend borrowed for one step, through every stage: the step's factor and contact
/// solve, its b, and the workspace that keeps w* while the contact is solved.
pub(in crate::scheme) struct Step<'a> {
    free: &'a FreeSystem,
    contact: &'a mut SparseContact,
    rhs: &'a [f64],
    unconstrained: &'a mut [f64],
}

impl<'a> Step<'a> {
    /// The free system, over which the field maps work.
    pub(in crate::scheme) fn free(&self) -> &'a FreeSystem {
        self.free
    }

    /// Whether the prediction `next` satisfies its `bounds` at every contact point: exact, the
    /// constrained values being sparse rows of w.
    pub(in crate::scheme) fn proven_within(&self, next: &[f64], bounds: ObstacleBounds) -> bool {
        let rows = &self.free.contact;
        (0..rows.len()).all(|i| bounds.admits(i, rows.value(i, next)))
    }

    /// [`SparseContact::solve`] on the step's matrix from b and w* = `next`, into `next`.
    pub(in crate::scheme) fn solve(
        &mut self,
        next: &mut [f64],
        lower: &[f64],
        upper: &[f64],
        states: &mut [BoundState],
        settings: &PdasSettings,
    ) -> Result<PdasReport, Error> {
        self.unconstrained.copy_from_slice(next);
        self.contact.solve(
            self.rhs,
            self.unconstrained,
            lower,
            upper,
            states,
            settings,
            next,
        )
    }

    /// The multipliers μ (length m) of the last solve.
    pub(in crate::scheme) fn multipliers(&self) -> &[f64] {
        self.contact.lambda()
    }

    /// Puts the prediction w* that the last solve kept back into `next`, to solve again.
    pub(in crate::scheme) fn restore_prediction(&self, next: &mut [f64]) {
        next.copy_from_slice(self.unconstrained);
    }
}

// The field maps of free-dof vectors ([`FieldMaps`](super::backend::FieldMaps) documents each).

pub(in crate::scheme) fn dimension(free: &FreeSystem) -> usize {
    free.load.len()
}

pub(in crate::scheme) fn field_sums(free: &FreeSystem, field: &[f64]) -> FieldSums {
    FieldSums {
        norm_squared: sum_of_squares(field),
        translation: dot(&free.translation_mass, field),
        damping: None,
    }
}

pub(in crate::scheme) fn load_projection(free: &FreeSystem, field: &[f64]) -> f64 {
    dot(&free.load, field)
}

/// Σ_i μ_i B_i(x − y) over the non-zero μ_i (at a vertex, (x − y)_{d_i} with d_i its free dof).
pub(in crate::scheme) fn multiplier_work(
    free: &FreeSystem,
    next: &[f64],
    previous: &[f64],
    multipliers: &[f64],
) -> f64 {
    let rows = &free.contact;
    multipliers
        .iter()
        .enumerate()
        .filter(|(_, &mu)| mu != 0.0)
        .map(|(i, &mu)| match rows.unit(i) {
            Some(d) => mu * (next[d] - previous[d]),
            None => mu * (rows.value(i, next) - rows.value(i, previous)),
        })
        .sum()
}

/// With ‖·‖₁ the largest column sum of absolute values, which bounds the 2-norm of a
/// symmetric matrix: wᵀKw ≤ ‖K‖₁‖w‖², ẇᵀMẇ ≤ ‖M‖₁‖ẇ‖².
pub(in crate::scheme) fn magnitude_scale(free: &FreeSystem, time_step: f64) -> f64 {
    let one_norm = |a: &SparseColMat<usize, f64>| {
        (0..a.ncols())
            .map(|j| a.val_of_col(j).iter().map(|v| v.abs()).sum::<f64>())
            .fold(0.0, f64::max)
    };
    let norm = |v: &[f64]| sum_of_squares(v).sqrt();
    let output_norm = free.outputs.iter().map(|r| norm(r)).fold(0.0, f64::max);
    [
        4.0 * one_norm(&free.mass) / (time_step * time_step),
        4.0 * norm(&free.translation_mass) / (time_step * time_step),
        2.0 * norm(&free.translation_mass) / time_step,
        one_norm(&free.stiffness),
        norm(&free.load),
        output_norm,
    ]
    .into_iter()
    .fold(1.0, f64::max)
}

pub(in crate::scheme) fn constrained_values(free: &FreeSystem, field: &[f64], out: &mut [f64]) {
    free.contact.values(field, out);
}

pub(in crate::scheme) fn constrained_value(free: &FreeSystem, field: &[f64], i: usize) -> f64 {
    free.contact.value(i, field)
}

pub(in crate::scheme) fn energy(
    free: &FreeSystem,
    previous: &[f64],
    current: &[f64],
    time_step: f64,
) -> EnergyPieces {
    let v: Vec<f64> = current
        .iter()
        .zip(previous)
        .map(|(a, b)| (a - b) / time_step)
        .collect();
    EnergyPieces {
        velocity_mass_velocity: quadratic(&free.mass, &v),
        translation_mass_velocity: dot(&free.translation_mass, &v),
        stiffness_current: quadratic(&free.stiffness, current),
        stiffness_previous: quadratic(&free.stiffness, previous),
        load_current: dot(&free.load, current),
        load_previous: dot(&free.load, previous),
    }
}

/// α (x − y)ᵀM(x − y) + β (x − y)ᵀK(x − y).
pub(in crate::scheme) fn damping_quadratic(free: &FreeSystem, x: &[f64], y: &[f64]) -> f64 {
    let difference: Vec<f64> = x.iter().zip(y).map(|(a, b)| a - b).collect();
    free.damping.alpha * quadratic(&free.mass, &difference)
        + free.damping.beta * quadratic(&free.stiffness, &difference)
}

pub(in crate::scheme) fn output_values(free: &FreeSystem, field: &[f64]) -> [f64; OUTPUT_POINTS] {
    free.outputs.each_ref().map(|row| dot(row, field))
}
