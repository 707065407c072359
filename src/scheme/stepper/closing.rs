//! The close of a step once its answer is in the next level: the contact forces, the force on
//! the base and its impulse, and the energy flows, each refused when not finite.

use super::paths::Answer;
use super::{Run, StepInput};
use crate::error::Error;
use crate::scheme::energy::EnergyFlows;
use crate::scheme::sums::FieldSums;

/// What a step formed after its contact solve, adopted when it is accepted.
pub(super) struct Closing {
    /// The sums of w_{n+1}.
    pub(super) sums: FieldSums,
    /// Σ_i f_i (N).
    pub(super) contact_force: f64,
    /// −G_n (N).
    pub(super) base_force: f64,
    /// J_{n+1} (N·s).
    pub(super) base_impulse: f64,
    /// The step's energy flows (J).
    pub(super) flows: EnergyFlows,
}

impl Run {
    /// The contact forces (into `trial_forces`) from the multipliers μ of the answer, if any, the
    /// force on the base and the energy flows of the step, `prediction` being the sums of its
    /// prediction; refuses the step when any of them, or an output after it, is not finite.
    pub(super) fn close(
        &self,
        input: &StepInput,
        prediction: FieldSums,
        answer: Answer,
        trial_forces: &mut [f64],
    ) -> Result<Closing, Error> {
        let dt = self.scene.solver.time_step;
        let StepInput {
            base_next, t_next, ..
        } = *input;
        // The step's equation times Δt² is the QP's optimality condition A w − b = Bᵀμ, so
        // f = μ/Δt²; the start step's equation is multiplied by Δt²/2 (its
        // 2M(u_1 − u_0)/Δt² + K u_1 = F̄_0 + Bᵀf_0 gives b_0 = M u_0 + ½Δt²F̄_0), so there
        // f = 2μ/Δt².
        let equation_scale = if input.forcing.start { 2.0 } else { 1.0 };
        let (mut sums, mut contact_force, mut force_magnitude) = (prediction, 0.0, 0.0);
        if let Some(mu) = answer.multipliers() {
            let fields = answer.fields();
            sums = fields.maps.field_sums(fields.next);
            for (f, &x) in trial_forces.iter_mut().zip(mu) {
                *f = equation_scale * x / (dt * dt);
            }
            contact_force = trial_forces.iter().sum();
            force_magnitude = trial_forces.iter().map(|f| f.abs()).sum();
            if !(sums.norm_squared.is_finite() && force_magnitude.is_finite()) {
                return Err(self.overflow(
                    "the displacement or the contact forces of the contact solve",
                    t_next,
                    base_next,
                ));
            }
        }
        let fields = answer.fields();
        self.guard_outputs(
            fields,
            sums.norm_squared,
            base_next,
            t_next,
            force_magnitude,
        )?;
        let base_force = -self.base_supply(base_next, sums.translation, contact_force);
        let base_impulse = self.base_impulse + base_force * dt;
        let flows = if input.forcing.start {
            EnergyFlows::default()
        } else {
            // The prediction's damping quadratic holds when the step kept the prediction.
            let damping = match answer {
                Answer::Prediction(_) => prediction.damping,
                _ => None,
            };
            self.step_flows(base_next, -base_force, answer, contact_force, damping)
        };
        if !(base_force.is_finite() && base_impulse.is_finite() && flows.is_finite()) {
            return Err(self.overflow(
                "the force on the base or an energy flow",
                t_next,
                base_next,
            ));
        }
        Ok(Closing {
            sums,
            contact_force,
            base_force,
            base_impulse,
            flows,
        })
    }

    /// G_n, the vertical force the base supplies to the plate in the step being solved, from the
    /// scheme's equation at t_n tested with the rigid translation 𝟙 (K𝟙 = 0, and 𝟙ᵀC = α(M𝟙)ᵀ is
    /// the reaction of the mass-proportional dashpots, which act from the base frame, so that G
    /// is the whole force through the base; docs/scheme.md §11):
    /// G_n = 𝟙ᵀM(u_{n+1} − 2u_n + u_{n−1})/Δt² − F̄_n∫1 − Σ_i f_i, where 𝟙ᵀMu = M_tot z + m₁ᵀw.
    /// The start step's equation 2M(u_1 − u_0)/Δt² + K u_1 = F̄_0 + Bᵀf_0 + R_0 gives
    /// G_0 = 2𝟙ᵀM(u_1 − u_0)/Δt² − F̄_0∫1 − Σ_i f_i. `mass_weighted_next` is m₁ᵀw_{n+1}.
    fn base_supply(&self, base_next: f64, mass_weighted_next: f64, contact_force: f64) -> f64 {
        let dt = self.scene.solver.time_step;
        let (m, area) = (self.free.total_mass, self.free.area);
        let [z_prev, z_curr] = self.base;
        let [s_prev, s_curr] = self.mass_weighted_sums;
        let p_next = self.scene.load.pressure;
        let (momentum_change, mean_pressure) = if self.step_index == 0 {
            (
                2.0 * (m * (base_next - z_curr) + (mass_weighted_next - s_curr)),
                0.5 * (p_next + self.pressure[1]),
            )
        } else {
            (
                m * (base_next - 2.0 * z_curr + z_prev)
                    + (mass_weighted_next - 2.0 * s_curr + s_prev),
                0.5 * (p_next + self.pressure[0]),
            )
        };
        momentum_change / (dt * dt) - mean_pressure * area - contact_force
    }

    /// The energy flows of the step being solved (not the start step), with `supply` = G_n, its
    /// answer and the sum of its contact forces: base work ½(z_{n+1} − z_{n−1})G_n, load work net
    /// of the load potential's change, contact loss −½ f_nᵀB(u_{n+1} − u_{n−1}) and damping loss
    /// Δwᵀ C Δw / (4Δt) (see [`EnergyFlows`]), whose quadratic Δwᵀ C Δw the backend's pass may
    /// already have formed (`damping_quadratic`).
    fn step_flows(
        &self,
        base_next: f64,
        supply: f64,
        answer: Answer,
        contact_force: f64,
        damping_quadratic: Option<f64>,
    ) -> EnergyFlows {
        let dt = self.scene.solver.time_step;
        let [z_prev, z_curr] = self.base;
        let fields = answer.fields();
        let (maps, previous, current, next) =
            (fields.maps, fields.previous, fields.current, &*fields.next);
        let stroke = base_next - z_prev;
        let [p_prev, p_curr] = self.pressure;
        let p_next = self.scene.load.pressure;
        let load_work = if p_prev == 0.0 && p_curr == 0.0 && p_next == 0.0 {
            0.0
        } else {
            // L_k = Fᵀu_k for a 1 Pa pressure = z_k∫1 + fᵀw_k.
            let area = self.free.area;
            let l_next = area * base_next + maps.load_projection(next);
            let l_curr = area * z_curr + maps.load_projection(current);
            let l_prev = area * z_prev + maps.load_projection(previous);
            0.25 * (p_next + p_prev) * (l_next - l_prev) - 0.5 * p_next * (l_next + l_curr)
                + 0.5 * p_curr * (l_curr + l_prev)
        };
        let damping_loss = if self.free.damping.is_zero() {
            0.0
        } else {
            damping_quadratic.unwrap_or_else(|| maps.damping_quadratic(next, previous)) / (4.0 * dt)
        };
        // f = μ/Δt² (2μ/Δt² at the start step, which has no flows), u = z𝟙 + w at the vertices;
        // the work of the multipliers comes last, as a correction's uses up what its solve kept.
        let contact_loss = match answer.work() {
            Some(work) => -0.5 * (stroke * contact_force + work / (dt * dt)),
            None => 0.0,
        };
        EnergyFlows {
            base_work: 0.5 * stroke * supply,
            load_work,
            contact_loss,
            damping_loss,
        }
    }
}
