//! The outputs at a communication point that lies between two grid points.
//!
//! A communication step that ends at t + h strictly between t_{N−1} and t_N computes the grid up
//! to t_N (the internal state runs up to one grid step ahead of the communication time, and its
//! trajectory never depends on the host's steps) and reports the outputs at t + h, with
//! θ = (t + h − t_{N−1})/Δt ∈ (0, 1):
//!
//! * every continuous output is interpolated linearly, y(t + h) = y_{N−1} + θ (y_N − y_{N−1}):
//!   the displacements, the energies, the force on the base and the works and losses summed
//!   since the start. Any linear relation that the grid values satisfy holds at t + h too, such
//!   as the energy balance ΔE = base work + load work − contact loss − damping loss, and an energy
//!   that never increases from one grid point to the next never increases from one communication
//!   point to the next. The displacement of every vertex at
//!   t + h is a convex combination of two admissible ones, so it respects the obstacles. On a
//!   smooth output the interpolation errs by at most Δt²/8·max|ÿ|: second order, as the scheme.
//! * the contact state comes from the last grid point at or before t + h, t_{N−1}:
//!   `active_nodes` and `contact_force`, the total contact force of that internal step. A force
//!   is reported only together with the vertices that carry it, never as a blend of two steps'
//!   forces.
//!
//! The displacement at every mesh vertex ([`VertexField`]) follows the same rule as the
//! displacement outputs. Their time derivatives are the slope of that interpolation,
//! (y_N − y_{N−1})/Δt, over the grid interval (t_{N−1}, t_N] that holds the communication time
//! ([`rate`]): the scheme's half-step velocity v_{N−½} = (u_N − u_{N−1})/Δt. Between grid points
//! it is the exact derivative of the reported outputs, so a host extrapolating y(t) + τ·ẏ from a
//! point between t_{N−1} and t_N lands on y_N at t_N. On a grid point it is the derivative from
//! the left, a first-order estimate of u̇(t_N) (error at most Δt/2·max|ü|; the velocity after
//! t_N depends on the base of the next step, not yet known). At an impact the velocity of a
//! vertex changes within one internal step: the rate reported at the grid point where the contact
//! closed is the approach velocity of the step that ended there (toward the obstacle; Newton's
//! law with restitution e turns it into about −e times itself), and from the next grid point on
//! it is the velocity after the impact. A host that extrapolates from the impact's grid point
//! with it predicts the vertex past the obstacle by up to h·|v| after a step h; FMI 3.0 hosts can
//! have a communication point right at each impact (early return) and re-read the rate one
//! internal step later.

use super::grid::TimeGrid;
use crate::scheme::Outputs;
use serde::{Deserialize, Serialize};

/// Where the communication point lies relative to the grid point t_N the simulation has
/// computed up to (part of a simulation's state).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum CommunicationPoint {
    /// At t_N.
    #[default]
    OnGrid,
    /// Strictly between t_{N−1} and t_N.
    Between {
        /// t − t_start (s).
        elapsed: f64,
        /// The outputs at t_{N−1} (boxed: they are far larger than the other variant).
        previous: Box<Outputs>,
    },
}

/// The outputs at θ ∈ [0, 1] of the way from the grid point with outputs `previous` to the next
/// one, with outputs `next` (module docs): continuous outputs interpolated linearly, the contact
/// state of `previous`.
pub fn interpolate(previous: &Outputs, next: &Outputs, theta: f64) -> Outputs {
    Outputs {
        contact_force: previous.contact_force,
        ..previous.zip_reals(next, |a, b| mix(a, b, theta))
    }
}

/// a + θ(b − a): the value θ of the way from a to b.
pub(crate) fn mix(a: f64, b: f64, theta: f64) -> f64 {
    a + theta * (b - a)
}

/// d/dt of a displacement at the communication time: (`current` − `previous`)/`dt`, the slope
/// over the grid interval (t_{N−1}, t_N] that holds it (module docs).
pub fn rate(previous: f64, current: f64, dt: f64) -> f64 {
    (current - previous) / dt
}

/// The displacement at every mesh vertex at the communication time (m), in the mesh's vertex
/// order, and its rate (m/s) (module docs). For the structured meshes of a scene, vertex
/// (i, j) at (x_i, y_j) = (i·Lx/nx, j·Ly/ny) is entry i + j·(nx + 1): row-major with the rows
/// along y and the columns along x.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VertexField {
    /// u at each vertex (m).
    pub displacement: Vec<f64>,
    /// du/dt at each vertex (m/s).
    pub rate: Vec<f64>,
}

impl VertexField {
    /// The field at θ ∈ (0, 1) of the way from the grid point with displacements `previous` to
    /// the next one, `current`, with `theta` = `None` for the grid point of `current` itself;
    /// `dt` the grid step (s).
    pub fn between(previous: &[f64], current: &[f64], theta: Option<f64>, dt: f64) -> VertexField {
        VertexField {
            displacement: match theta {
                None => current.to_vec(),
                Some(theta) => previous
                    .iter()
                    .zip(current)
                    .map(|(&a, &b)| mix(a, b, theta))
                    .collect(),
            },
            rate: previous
                .iter()
                .zip(current)
                .map(|(&a, &b)| rate(a, b, dt))
                .collect(),
        }
    }
}

impl CommunicationPoint {
    /// t − t_start (s) for a simulation that has computed `grid` up to index `n`.
    pub fn elapsed(&self, grid: &TimeGrid, n: u64) -> f64 {
        match self {
            CommunicationPoint::OnGrid => grid.elapsed(n),
            CommunicationPoint::Between { elapsed, .. } => *elapsed,
        }
    }

    /// Checks a communication point read from an untrusted source, for a simulation that has
    /// computed `grid` up to index `n` and constrains `constrained` vertices: a point between two
    /// grid points needs n ≥ 1 and t_{n−1} < t < t_n, and finite outputs at t_{n−1} with at most
    /// `constrained` vertices in contact. The error names the field and its value.
    pub fn check(&self, grid: &TimeGrid, n: u64, constrained: usize) -> Result<(), String> {
        let CommunicationPoint::Between { elapsed, previous } = self else {
            return Ok(());
        };
        if n == 0 || !(grid.elapsed(n - 1) < *elapsed && *elapsed < grid.elapsed(n)) {
            return Err(format!(
                "communication point: {elapsed} s after the start is not strictly between the grid points {} s and {} s",
                grid.elapsed(n.saturating_sub(1)),
                grid.elapsed(n)
            ));
        }
        let reals = previous.reals();
        if let Some((name, x)) = reals.iter().find(|(_, x)| !x.is_finite()) {
            return Err(format!(
                "communication point: the previous grid point's {name} = {x} is not finite"
            ));
        }
        if previous.active_nodes > constrained {
            return Err(format!(
                "communication point: the previous grid point has {} vertices in contact, more than the {constrained} constrained ones",
                previous.active_nodes
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn outputs(x: f64, active: usize) -> Outputs {
        Outputs {
            corner1: x,
            corner2: -x,
            edge_mid: 2.0 * x,
            energy_kinetic: x,
            energy_elastic: 3.0 * x,
            energy_total: 4.0 * x,
            active_nodes: active,
            contact_force: 100.0 * x,
            base_force: -10.0 * x,
            base_impulse: 9.0 * x,
            base_work: 5.0 * x,
            load_work: 6.0 * x,
            contact_loss: 7.0 * x,
            damping_loss: 8.0 * x,
            probe1: 11.0 * x,
            probe2: 12.0 * x,
            probe3: 13.0 * x,
            probe4: 14.0 * x,
            stop_forces: [15.0 * x; crate::obstacles::STOP_OUTPUTS],
        }
    }

    #[test]
    fn continuous_outputs_are_interpolated_the_contact_state_is_the_earlier_one() {
        let (a, b) = (outputs(1.0, 2), outputs(3.0, 0));
        let mid = interpolate(&a, &b, 0.25);
        assert_eq!((mid.corner1, mid.corner2, mid.edge_mid), (1.5, -1.5, 3.0));
        assert_eq!(mid.probes(), [16.5, 18.0, 19.5, 21.0]);
        assert_eq!(
            mid.stop_forces, a.stop_forces,
            "the earlier step's stop forces"
        );
        assert_eq!(mid.energy_total, 6.0);
        assert_eq!(
            (mid.base_force, mid.base_work, mid.damping_loss),
            (-15.0, 7.5, 12.0)
        );
        assert_eq!((mid.active_nodes, mid.contact_force), (2, 100.0));
        assert_eq!(interpolate(&a, &b, 0.0), a);
    }

    #[test]
    fn untrusted_points_are_checked() {
        let grid = TimeGrid {
            start: 0.0,
            step: 1e-4,
        };
        let point = |elapsed, previous| CommunicationPoint::Between {
            elapsed,
            previous: Box::new(previous),
        };
        assert!(point(1.5e-4, outputs(1.0, 3)).check(&grid, 2, 3).is_ok());
        assert!(CommunicationPoint::OnGrid.check(&grid, 0, 0).is_ok());
        for (p, n, words) in [
            (point(2e-4, outputs(1.0, 0)), 2, "not strictly between"),
            (point(1e-4, outputs(1.0, 0)), 2, "not strictly between"),
            (point(0.5e-4, outputs(1.0, 0)), 0, "not strictly between"),
            (point(f64::NAN, outputs(1.0, 0)), 2, "not strictly between"),
            (point(1.5e-4, outputs(f64::INFINITY, 0)), 2, "corner1 = inf"),
            (point(1.5e-4, outputs(1.0, 4)), 2, "4 vertices"),
        ] {
            let err = p.check(&grid, n, 3).unwrap_err();
            assert!(err.contains(words), "{err}");
        }
    }
}
