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
        /// The outputs at t_{N−1}.
        previous: Outputs,
    },
}

/// The outputs at θ ∈ [0, 1] of the way from the grid point with outputs `previous` to the next
/// one, with outputs `next` (module docs): continuous outputs interpolated linearly, the contact
/// state of `previous`.
pub fn interpolate(previous: &Outputs, next: &Outputs, theta: f64) -> Outputs {
    let mix = |a: f64, b: f64| a + theta * (b - a);
    Outputs {
        corner1: mix(previous.corner1, next.corner1),
        corner2: mix(previous.corner2, next.corner2),
        edge_mid: mix(previous.edge_mid, next.edge_mid),
        energy_kinetic: mix(previous.energy_kinetic, next.energy_kinetic),
        energy_elastic: mix(previous.energy_elastic, next.energy_elastic),
        energy_total: mix(previous.energy_total, next.energy_total),
        active_nodes: previous.active_nodes,
        contact_force: previous.contact_force,
        base_force: mix(previous.base_force, next.base_force),
        base_work: mix(previous.base_work, next.base_work),
        load_work: mix(previous.load_work, next.load_work),
        contact_loss: mix(previous.contact_loss, next.contact_loss),
        damping_loss: mix(previous.damping_loss, next.damping_loss),
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
        let o = previous;
        let values = [
            ("corner1", o.corner1),
            ("corner2", o.corner2),
            ("edge_mid", o.edge_mid),
            ("energy_kinetic", o.energy_kinetic),
            ("energy_elastic", o.energy_elastic),
            ("energy_total", o.energy_total),
            ("contact_force", o.contact_force),
            ("base_force", o.base_force),
            ("base_work", o.base_work),
            ("load_work", o.load_work),
            ("contact_loss", o.contact_loss),
            ("damping_loss", o.damping_loss),
        ];
        if let Some((name, x)) = values.iter().find(|(_, x)| !x.is_finite()) {
            return Err(format!(
                "communication point: the previous grid point's {name} = {x} is not finite"
            ));
        }
        if o.active_nodes > constrained {
            return Err(format!(
                "communication point: the previous grid point has {} vertices in contact, more than the {constrained} constrained ones",
                o.active_nodes
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
            base_work: 5.0 * x,
            load_work: 6.0 * x,
            contact_loss: 7.0 * x,
            damping_loss: 8.0 * x,
        }
    }

    #[test]
    fn continuous_outputs_are_interpolated_the_contact_state_is_the_earlier_one() {
        let (a, b) = (outputs(1.0, 2), outputs(3.0, 0));
        let mid = interpolate(&a, &b, 0.25);
        assert_eq!((mid.corner1, mid.corner2, mid.edge_mid), (1.5, -1.5, 3.0));
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
        let point = |elapsed, previous| CommunicationPoint::Between { elapsed, previous };
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
