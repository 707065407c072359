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

use super::backend::{EnergyPieces, FieldSums, LinearBackend, StepForcing};
use super::free_system::{quadratic, FreeSystem};
use super::vectors::{dot, sum_of_squares};
use crate::contact::delassus::DEFAULT_DELASSUS_BUDGET;
use crate::contact::ordering::nested_dissection;
use crate::contact::sparse_contact::SparseContact;
use crate::contact::{BoundState, PdasReport, PdasSettings};
use crate::error::Error;
use faer::sparse::SparseColMat;
use std::sync::Arc;

/// The sparse backend: fields are free-dof vectors w_f.
pub struct SparseBackend {
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
    /// Whether the step being solved is the start step (whose matrix is A₀).
    start: bool,
}

impl SparseBackend {
    /// Factors A = M + ½Δt²K + ½ΔtC of `free` (ordering analysed once, see the module docs).
    pub fn new(free: Arc<FreeSystem>) -> Result<SparseBackend, Error> {
        let contact = contact_solve(&free, &free.system)?;
        let n = free.load.len();
        Ok(SparseBackend {
            contact,
            start_contact: None,
            rhs: vec![0.0; n],
            unconstrained: vec![0.0; n],
            start: false,
            free,
        })
    }

    /// The contact solve of the step being solved: on A₀ for a damped start step, else on A.
    fn step_contact(&mut self) -> Result<&mut SparseContact, Error> {
        let free = &*self.free;
        let Some(start_matrix) = free.start_system().filter(|_| self.start) else {
            return Ok(&mut self.contact);
        };
        if self.start_contact.is_none() {
            self.start_contact = Some(contact_solve(free, start_matrix)?);
        }
        Ok(self
            .start_contact
            .as_mut()
            .expect("made for this start step"))
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
        &free.constrained,
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

impl LinearBackend for SparseBackend {
    fn dimension(&self) -> usize {
        self.free.load.len()
    }

    fn predict(
        &mut self,
        previous: &[f64],
        current: &[f64],
        forcing: &StepForcing,
        next: &mut [f64],
    ) -> Result<FieldSums, Error> {
        self.start = forcing.start;
        if !forcing.start {
            // The start step is over: its system is not needed again unless the run restarts.
            self.start_contact = None;
        }
        self.free
            .right_hand_side(forcing, previous, current, &mut self.rhs);
        let rhs = std::mem::take(&mut self.rhs);
        let solved = self
            .step_contact()
            .and_then(|contact| contact.solve_unconstrained(&rhs, next));
        self.rhs = rhs;
        solved.map(|()| self.field_sums(next))
    }

    fn field_sums(&self, field: &[f64]) -> FieldSums {
        FieldSums {
            norm_squared: sum_of_squares(field),
            translation: dot(&self.free.translation_mass, field),
            damping: None,
        }
    }

    fn load_projection(&self, field: &[f64]) -> f64 {
        dot(&self.free.load, field)
    }

    fn multiplier_work(&mut self, next: &[f64], previous: &[f64], multipliers: &[f64]) -> f64 {
        multipliers
            .iter()
            .zip(&self.free.constrained)
            .filter(|(&mu, _)| mu != 0.0)
            .map(|(&mu, &d)| mu * (next[d] - previous[d]))
            .sum()
    }

    /// With ‖·‖₁ the largest column sum of absolute values, which bounds the 2-norm of a
    /// symmetric matrix: wᵀKw ≤ ‖K‖₁‖w‖², ẇᵀMẇ ≤ ‖M‖₁‖ẇ‖².
    fn magnitude_scale(&self, time_step: f64) -> f64 {
        let free = &*self.free;
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

    /// Exact: the constrained values are entries of w_{n+1}.
    fn prediction_proven_within(&mut self, next: &[f64], lower: f64, upper: f64) -> bool {
        self.free
            .constrained
            .iter()
            .all(|&d| next[d] >= lower && next[d] <= upper)
    }

    /// [`SparseContact::solve`] on the step's matrix, from b and w* of the last prediction.
    fn solve_contact(
        &mut self,
        next: &mut [f64],
        _prediction: &[f64],
        lower: &[f64],
        upper: &[f64],
        states: &mut [BoundState],
        settings: &PdasSettings,
    ) -> Result<PdasReport, Error> {
        let (rhs, mut unconstrained) = (
            std::mem::take(&mut self.rhs),
            std::mem::take(&mut self.unconstrained),
        );
        unconstrained.copy_from_slice(next);
        let report = self.step_contact().and_then(|contact| {
            contact.solve(&rhs, &unconstrained, lower, upper, states, settings, next)
        });
        (self.rhs, self.unconstrained) = (rhs, unconstrained);
        report
    }

    fn contact_multipliers(&self) -> &[f64] {
        match &self.start_contact {
            Some(contact) if self.start => contact.lambda(),
            _ => self.contact.lambda(),
        }
    }

    fn constrained_values(&self, field: &[f64], out: &mut [f64]) {
        for (o, &d) in out.iter_mut().zip(&self.free.constrained) {
            *o = field[d];
        }
    }

    fn to_free_dofs(&self, field: &[f64]) -> Vec<f64> {
        field.to_vec()
    }

    fn field_of_free_dofs(&self, w: &[f64], field: &mut [f64]) {
        field.copy_from_slice(w);
    }

    fn energy(&self, previous: &[f64], current: &[f64], time_step: f64) -> EnergyPieces {
        let free = &*self.free;
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
    fn damping_quadratic(&self, x: &[f64], y: &[f64]) -> f64 {
        let free = &*self.free;
        let difference: Vec<f64> = x.iter().zip(y).map(|(a, b)| a - b).collect();
        free.damping.alpha * quadratic(&free.mass, &difference)
            + free.damping.beta * quadratic(&free.stiffness, &difference)
    }

    fn output_values(&self, field: &[f64]) -> [f64; 3] {
        self.free.outputs.each_ref().map(|row| dot(row, field))
    }
}
