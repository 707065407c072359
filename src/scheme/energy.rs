//! The discrete energy of the scheme (docs/scheme.md), reported between t_n and t_{n+1}:
//!
//! E_{n+½} = ½ v_{n+½}ᵀ M v_{n+½} + ¼ (u_{n+1}ᵀ K u_{n+1} + u_nᵀ K u_n) − ½ p Fᵀ(u_{n+1} + u_n),
//!
//! with v_{n+½} = (u_{n+1} − u_n)/Δt and p the pressure of the last step. With u = z𝟙 + w and
//! K𝟙 = 0 the pieces are those of w plus the rigid motion of the base: vᵀMv = ż²𝟙ᵀM𝟙 + 2ż m₁ᵀẇ +
//! ẇᵀMẇ, uᵀKu = wᵀKw and Fᵀu = z∫1 + fᵀw.

use super::backend::EnergyPieces;
use super::FreeSystem;

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
