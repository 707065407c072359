//! The discrete energy of the scheme (docs/scheme.md), reported between t_n and t_{n+1}:
//!
//! E_{n+½} = ½ v_{n+½}ᵀ M v_{n+½} + ¼ (u_{n+1}ᵀ K u_{n+1} + u_nᵀ K u_n) − ½ p Fᵀ(u_{n+1} + u_n),
//!
//! with v_{n+½} = (u_{n+1} − u_n)/Δt and p the pressure of the last step. With u = z𝟙 + w and
//! K𝟙 = 0 the pieces are those of w plus the rigid motion of the base: vᵀMv = ż²𝟙ᵀM𝟙 + 2ż m₁ᵀẇ +
//! ẇᵀMẇ, uᵀKu = wᵀKw and Fᵀu = z∫1 + fᵀw.

use super::free_system::FreeSystem;
use super::sums::EnergyPieces;
use serde::{Deserialize, Serialize};

/// Energy that enters or leaves the plate over one step, or summed over steps (J), such that the
/// discrete energy changes by `base_work + load_work − contact_loss − damping_loss`
/// (docs/scheme.md §12 derives each term from the scheme).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct EnergyFlows {
    /// Work of the force the base supplies: ½(z_{n+1} − z_{n−1}) G_n.
    pub base_work: f64,
    /// Work of the load minus the change of its potential (zero for a constant pressure):
    /// ¼(p_{n+1} + p_{n−1})(L_{n+1} − L_{n−1}) − ½p_{n+1}(L_{n+1} + L_n) + ½p_n(L_n + L_{n−1})
    /// with L_k = Fᵀu_k for a 1 Pa pressure.
    pub load_work: f64,
    /// Energy removed at the obstacles: −½ f_nᵀB(u_{n+1} − u_{n−1}), ≥ 0 for every restitution e
    /// (docs/scheme.md §8, §12).
    pub contact_loss: f64,
    /// Energy removed by damping: Δwᵀ C Δw / (4Δt), Δw = w_{n+1} − w_{n−1}, ≥ 0.
    pub damping_loss: f64,
}

impl EnergyFlows {
    /// The change of the discrete energy these flows make: base + load − contact − damping.
    pub fn net(&self) -> f64 {
        self.base_work + self.load_work - self.contact_loss - self.damping_loss
    }

    /// The flows summed with `other`.
    pub fn plus(&self, other: &EnergyFlows) -> EnergyFlows {
        EnergyFlows {
            base_work: self.base_work + other.base_work,
            load_work: self.load_work + other.load_work,
            contact_loss: self.contact_loss + other.contact_loss,
            damping_loss: self.damping_loss + other.damping_loss,
        }
    }

    /// Whether every flow is finite.
    pub fn is_finite(&self) -> bool {
        [
            self.base_work,
            self.load_work,
            self.contact_loss,
            self.damping_loss,
        ]
        .iter()
        .all(|v| v.is_finite())
    }
}

/// The three energies of one level pair (J).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct DiscreteEnergy {
    /// ½ v_{n+½}ᵀ M v_{n+½}.
    pub kinetic: f64,
    /// ¼ (u_{n+1}ᵀKu_{n+1} + u_nᵀKu_n).
    pub elastic: f64,
    /// kinetic + elastic − ½ p Fᵀ(u_{n+1} + u_n).
    pub total: f64,
}

impl DiscreteEnergy {
    /// The energy between the base positions `base` = (z_n, z_{n+1}) from the pieces of
    /// (w_n, w_{n+1}), under the pressure `pressure`; `at_rest` for the initial state, whose
    /// velocity is v_0 = 0 (E_0 = ½ u₀ᵀKu₀ − p Fᵀu₀ when both fields are u₀).
    pub fn new(
        free: &FreeSystem,
        pieces: EnergyPieces,
        base: [f64; 2],
        pressure: f64,
        time_step: f64,
        at_rest: bool,
    ) -> DiscreteEnergy {
        let [z0, z1] = base;
        let (base_velocity, velocity_mass_velocity, translation_mass_velocity) = if at_rest {
            (0.0, 0.0, 0.0)
        } else {
            (
                (z1 - z0) / time_step,
                pieces.velocity_mass_velocity,
                pieces.translation_mass_velocity,
            )
        };
        let kinetic = 0.5
            * (base_velocity * base_velocity * free.total_mass
                + 2.0 * base_velocity * translation_mass_velocity
                + velocity_mass_velocity);
        let elastic = 0.25 * (pieces.stiffness_current + pieces.stiffness_previous);
        let work =
            0.5 * pressure * (free.area * (z0 + z1) + pieces.load_current + pieces.load_previous);
        DiscreteEnergy {
            kinetic,
            elastic,
            total: kinetic + elastic - work,
        }
    }
}
