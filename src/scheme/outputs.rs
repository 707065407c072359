//! What the FMU and the examples read after each step.

use crate::obstacles::STOP_OUTPUTS;
use serde::{Deserialize, Serialize};

/// What the FMU and the examples report after each step (the FMU outputs of docs/fmu.md).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Outputs {
    /// u(Lx, 0) (m).
    pub corner1: f64,
    /// u(Lx, Ly) (m).
    pub corner2: f64,
    /// u(Lx, Ly/2) (m).
    pub edge_mid: f64,
    /// ½ v_{n+½}ᵀ M v_{n+½} (J).
    pub energy_kinetic: f64,
    /// ¼ (u_{n+1}ᵀKu_{n+1} + u_nᵀKu_n) (J).
    pub energy_elastic: f64,
    /// Kinetic + elastic − ½ Fᵀ(u_{n+1} + u_n) (J).
    pub energy_total: f64,
    /// Vertices in contact after the last step.
    pub active_nodes: usize,
    /// Sum of the contact forces (N), positive upwards.
    pub contact_force: f64,
    /// −G_n: the vertical force the plate exerts on its base (N, positive upward), from the
    /// equation at t_n of the last step (t_{n+1} − Δt), while the displacements are at t_{n+1};
    /// at t_0 the static value p₀·∫1 + Σλ of the preload.
    pub base_force: f64,
    /// J_n = Σ_{j<n} (−G_j) Δt: the impulse of the force on the base over the internal steps since
    /// t_0 (N·s), the rectangle rule on the forces of `base_force`, so that over internal steps
    /// whose base moves with a constant velocity s (z_{j+1} − z_{j−1} = 2sΔt) the base work
    /// changes by −s·ΔJ exactly (docs/fmu.md, "Coupling both ways").
    pub base_impulse: f64,
    /// Work done on the plate by the base since t_1 (J).
    pub base_work: f64,
    /// Work done by `load.pressure` since t_1, net of its potential's change (J).
    pub load_work: f64,
    /// Energy removed at the obstacles since t_1 (J).
    pub contact_loss: f64,
    /// Energy removed by damping since t_1 (J).
    pub damping_loss: f64,
    /// u at the probe points `probe1` … `probe4` (m); absent from the states saved before
    /// probes existed, which read 0 and are set again by the next step.
    #[serde(default)]
    pub probe1: f64,
    /// u at `probe2` (m).
    #[serde(default)]
    pub probe2: f64,
    /// u at `probe3` (m).
    #[serde(default)]
    pub probe3: f64,
    /// u at `probe4` (m).
    #[serde(default)]
    pub probe4: f64,
    /// The total contact force of each of the first stops after the last step (N), 0 for a stop
    /// that does not exist.
    #[serde(default)]
    pub stop_forces: [f64; STOP_OUTPUTS],
}

impl Outputs {
    /// u at the probes, in order (m).
    pub fn probes(&self) -> [f64; crate::scene::PROBES] {
        [self.probe1, self.probe2, self.probe3, self.probe4]
    }
}

/// Declares the real fields of [`Outputs`], in declaration order, once for every method that
/// goes through all of them; a struct literal without `..` makes a new field fail to compile
/// until it is listed here.
macro_rules! real_fields {
    ($($field:ident),* $(,)?) => {
        impl Outputs {
            /// Every real output as (field name, value), in declaration order.
            pub fn reals(&self) -> [(&'static str, f64); [$(stringify!($field)),*].len()] {
                [$((stringify!($field), self.$field)),*]
            }

            /// The outputs whose real fields are f(self's value, `other`'s value), field by
            /// field, with the vertex count and the stops' forces of `self`.
            pub fn zip_reals(&self, other: &Outputs, f: impl Fn(f64, f64) -> f64) -> Outputs {
                Outputs {
                    $($field: f(self.$field, other.$field),)*
                    active_nodes: self.active_nodes,
                    stop_forces: self.stop_forces,
                }
            }
        }
    };
}

real_fields!(
    corner1,
    corner2,
    edge_mid,
    energy_kinetic,
    energy_elastic,
    energy_total,
    contact_force,
    base_force,
    base_impulse,
    base_work,
    load_work,
    contact_loss,
    damping_loss,
    probe1,
    probe2,
    probe3,
    probe4,
);
