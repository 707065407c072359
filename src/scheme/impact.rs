//! The impact law: the bounds the obstacles put on u_{n+1} at a constrained vertex
//! (docs/scheme.md §8, "Restitution").
//!
//! * The paper's **position law** (e = 0): g1 ≤ u_{n+1,i} ≤ g2.
//! * **Newton's law** with restitution e ∈ [0, 1], on the half-step velocities
//!   v_{n−½} = (u_n − u_{n−1})/Δt (before) and v_{n+½} = (u_{n+1} − u_n)/Δt (after). At a vertex
//!   whose contact with the lower obstacle closes in the step, i.e. that approaches it
//!   (u_n < u_{n−1}) and whose unconstrained prediction crosses it (u*_{n+1} < g1),
//!
//!   u_{n+1} ≥ r_i = u_n − e (u_n − u_{n−1}),   i.e.   v_{n+½} ≥ −e v_{n−½},
//!
//!   and g1 ≤ u_{n+1} at every other vertex (mirrored at the upper obstacle). Where the bound is
//!   active the vertex leaves with −e times its arriving velocity. The step stays one strictly
//!   convex box QP with the same matrix. r_i lies between u_n and u_{n−1}, so a vertex never passes
//!   an obstacle, and at an active bound u_{n+1} − u_{n−1} ≤ 0 at the lower obstacle (≥ 0 at the
//!   upper): the contact force does no positive work, the discrete energy never increases, and
//!   at e = 1 an impact keeps it exactly. A contact that is not closing (the vertex at rest or
//!   receding) gets the obstacle bound and loses ½ f_i (u_{n−1,i} − g1), also at e = 1.
//! * The **persistent law** (the default for e > 0): Newton's bound at a closing contact, and at
//!   every other vertex in contact the bound u_{n+1} ≥ g1 + e (u_{n−1} − g1), which at e = 1 is
//!   the persistency bound u_{n+1} ≥ u_{n−1}. Both read
//!
//!   lo_i = u_{n−1} − (1 − e)(u_{n−1} − ℓ_i),   ℓ_i = u_n if u_n < u_{n−1}, else g1,
//!
//!   so the force of a vertex in contact does the work ½ f_i (lo_i − u_{n−1}) =
//!   −½ (1 − e) f_i (u_{n−1} − ℓ_i) ≤ 0, exactly zero at e = 1. A vertex is in contact when its
//!   prediction crosses the obstacle, or when the contact solve put it on the obstacle with a
//!   force (the stepper then gives it the law's bound and solves again), so at e = 1 no contact
//!   does work and the discrete energy is conserved.
//!
//! Newton's law reads the positions of every constrained vertex at t_{n−1} and t_n;
//! [`VertexHistory`] keeps them, evaluated only on the steps that need bounds. The persistent law
//! reads them at the vertices in contact only, one row each.

use super::backend::FieldMaps;
use crate::scene::{ImpactLaw, Solver};

/// The law a run's steps impose.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Law {
    /// The paper's bound g on u_{n+1}.
    Position,
    /// Newton's law with this restitution e ∈ [0, 1].
    Newton(f64),
    /// The persistent law with this restitution e ∈ [0, 1].
    Persistent(f64),
}

impl Law {
    /// The law of the solver settings: `auto` is the position law for e = 0 and the persistent
    /// law for e > 0; `newton` and `persistent` are those laws for every e.
    pub(crate) fn of(solver: &Solver) -> Law {
        let e = solver.restitution;
        match solver.impact_law {
            ImpactLaw::Auto if e == 0.0 => Law::Position,
            ImpactLaw::Auto | ImpactLaw::Persistent => Law::Persistent(e),
            ImpactLaw::Newton => Law::Newton(e),
        }
    }
}

/// One constrained vertex as Newton's law reads it (m). All three positions and the obstacle
/// levels passed with them are measured in one frame in which the obstacles are at rest (the
/// stepper measures them from the base level z_{n+1}: a fixed offset, so velocities are those
/// relative to the obstacles, not to the moving base).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VertexMotion {
    /// u_{n−1}.
    pub previous: f64,
    /// u_n.
    pub current: f64,
    /// u*_{n+1}, the unconstrained prediction of the step.
    pub predicted: f64,
}

/// Newton's law with restitution `restitution` = e ∈ [0, 1] as the bounds [lo, hi] on u_{n+1}
/// of one vertex, between the obstacles `lower` = g1 and `upper` = g2 (`None` when absent; the
/// bound is then ∓∞).
///
/// lo = r = u_n − e (u_n − u_{n−1}) when u_n < u_{n−1} and u*_{n+1} < g1, else lo = g1; mirrored,
/// hi = r when u_n > u_{n−1} and u*_{n+1} > g2, else hi = g2. For positions within the obstacles
/// r lies between u_n and u_{n−1}, hence within them too; it is still kept within [g1, g2], so
/// that g1 ≤ lo ≤ hi ≤ g2 for any input (a restored state may lie past an obstacle by its
/// tolerance).
pub fn newton_bounds(
    restitution: f64,
    lower: Option<f64>,
    upper: Option<f64>,
    motion: VertexMotion,
) -> [f64; 2] {
    let VertexMotion {
        previous,
        current,
        predicted,
    } = motion;
    let floor = lower.unwrap_or(f64::NEG_INFINITY);
    let ceiling = upper.unwrap_or(f64::INFINITY);
    let rebound = (current + restitution * (previous - current))
        .max(floor)
        .min(ceiling);
    let lo = if current < previous && predicted < floor {
        rebound
    } else {
        floor
    };
    let hi = if current > previous && predicted > ceiling {
        rebound
    } else {
        ceiling
    };
    [lo, hi]
}

/// The persistent law's lower bound on u_{n+1} of a vertex in contact with the lower obstacle
/// `lower` = g1, from its levels `previous` = u_{n−1} and `current` = u_n (m, in a frame in which
/// the obstacles are at rest), with restitution `restitution` = e ∈ [0, 1]:
///
/// lo = u_{n−1} − (1 − e)(u_{n−1} − ℓ),   ℓ = u_n if u_n < u_{n−1} (closing), else g1,
///
/// i.e. Newton's rebound bound u_n − e (u_n − u_{n−1}) at a closing contact and
/// g1 + e (u_{n−1} − g1) at a vertex at rest or receding; exactly u_{n−1} at e = 1. Kept within
/// [g1, `upper`] (`upper` = g2, `None` when absent), so that g1 ≤ lo ≤ g2 for any input (a
/// restored state may lie past an obstacle by its tolerance); for levels within the obstacles
/// g1 ≤ lo ≤ u_{n−1}.
pub fn persistent_lower_bound(
    restitution: f64,
    lower: f64,
    upper: Option<f64>,
    previous: f64,
    current: f64,
) -> f64 {
    let target = if current < previous { current } else { lower };
    (previous - (1.0 - restitution) * (previous - target))
        .max(lower)
        .min(upper.unwrap_or(f64::INFINITY))
}

/// The mirror of [`persistent_lower_bound`] at the upper obstacle `upper` = g2: the upper bound
/// u_{n−1} − (1 − e)(u_{n−1} − ℓ), ℓ = u_n if u_n > u_{n−1}, else g2, kept within [`lower`, g2].
/// Formed as the lower bound of the mirrored motion −u, so the two sides round alike.
pub fn persistent_upper_bound(
    restitution: f64,
    lower: Option<f64>,
    upper: f64,
    previous: f64,
    current: f64,
) -> f64 {
    -persistent_lower_bound(restitution, -upper, lower.map(|g| -g), -previous, -current)
}

/// The persistent law as the bounds [lo, hi] on u_{n+1} of one vertex whose contact is decided by
/// its prediction, between the obstacles `lower` = g1 and `upper` = g2 (`None` when absent, the
/// bound then ∓∞): [`persistent_lower_bound`] when u*_{n+1} < g1, else g1; mirrored,
/// [`persistent_upper_bound`] when u*_{n+1} > g2, else g2. (The stepper also gives the law's
/// bound to a vertex that its contact solve put on an obstacle with a force.)
pub fn persistent_bounds(
    restitution: f64,
    lower: Option<f64>,
    upper: Option<f64>,
    motion: VertexMotion,
) -> [f64; 2] {
    let levels = [motion.previous, motion.current];
    let lo = match lower {
        Some(g) if motion.predicted < g => {
            persistent_lower_bound(restitution, g, upper, levels[0], levels[1])
        }
        _ => lower.unwrap_or(f64::NEG_INFINITY),
    };
    let hi = match upper {
        Some(g) if motion.predicted > g => {
            persistent_upper_bound(restitution, lower, g, levels[0], levels[1])
        }
        _ => upper.unwrap_or(f64::INFINITY),
    };
    [lo, hi]
}

/// The values w_{n−1} and w_n at the constrained vertices (relative to the base, in the order of
/// the constrained vertices) that Newton's law reads. They are evaluated lazily from the fields,
/// on the steps that need bounds only, so that a contact-free step pays nothing for the law; a
/// step that evaluated its prediction without correcting it hands those values on.
#[derive(Clone, Debug)]
pub(crate) struct VertexHistory {
    /// w_{n−1} at the constrained vertices, valid when `known[0]`.
    previous: Vec<f64>,
    /// w_n, valid when `known[1]`.
    current: Vec<f64>,
    known: [bool; 2],
}

impl VertexHistory {
    /// A history of `m` vertices with nothing known yet.
    pub(crate) fn new(m: usize) -> VertexHistory {
        VertexHistory {
            previous: vec![0.0; m],
            current: vec![0.0; m],
            known: [false; 2],
        }
    }

    /// (w_{n−1}, w_n) at the constrained vertices, evaluating from the fields `previous` and
    /// `current` those not known. The values are exactly those of
    /// [`FieldMaps::constrained_values`] on the fields, whichever way they were obtained, so
    /// a restored state continues bit for bit.
    pub(crate) fn values(
        &mut self,
        maps: FieldMaps,
        previous: &[f64],
        current: &[f64],
    ) -> (&[f64], &[f64]) {
        if !self.known[0] {
            maps.constrained_values(previous, &mut self.previous);
        }
        if !self.known[1] {
            maps.constrained_values(current, &mut self.current);
        }
        self.known = [true; 2];
        (&self.previous, &self.current)
    }

    /// Moves on one step: w_n becomes w_{n−1}, and the new w_n is `next` when the step knows it
    /// exactly (its evaluated prediction was accepted unchanged), else unknown.
    pub(crate) fn advance(&mut self, next: Option<&[f64]>) {
        std::mem::swap(&mut self.previous, &mut self.current);
        self.known[0] = self.known[1];
        self.known[1] = match next {
            Some(values) => {
                self.current.copy_from_slice(values);
                true
            }
            None => false,
        };
    }

    /// Forgets both levels (after a restore).
    pub(crate) fn forget(&mut self) {
        self.known = [false; 2];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const G1: f64 = -0.01;
    const G2: f64 = 0.01;
    /// Rounding of r = u_n + e (u_{n−1} − u_n) from values near 0.01 m: a difference and a sum, each
    /// rounded to half an ulp (1.7e-18 m at 0.01 m), with room to spare.
    const ROUNDING: f64 = 4e-18;

    /// A law's bounds between G1 and G2 for one motion.
    fn law(
        rule: fn(f64, Option<f64>, Option<f64>, VertexMotion) -> [f64; 2],
        e: f64,
        [previous, current, predicted]: [f64; 3],
    ) -> [f64; 2] {
        let motion = VertexMotion {
            previous,
            current,
            predicted,
        };
        rule(e, Some(G1), Some(G2), motion)
    }

    fn bounds(e: f64, previous: f64, current: f64, predicted: f64) -> [f64; 2] {
        law(newton_bounds, e, [previous, current, predicted])
    }

    #[test]
    fn a_closing_contact_gets_the_rebound_bound() {
        // Arriving at −1 mm per step, 0.5 mm above g1, predicted 0.5 mm below it.
        let [lo, hi] = bounds(0.5, -0.0085, -0.0095, -0.0105);
        // r = u_n − e (u_n − u_{n−1}) = −0.0095 + 0.5·0.001: leaves at half the speed.
        assert!((lo - -0.009).abs() <= ROUNDING, "{lo}");
        assert_eq!(hi, G2);
        // e = 1: back to u_{n−1} (to the rounding of u_n + (u_{n−1} − u_n)); e = 0: stops at u_n.
        assert!((bounds(1.0, -0.0085, -0.0095, -0.0105)[0] - -0.0085).abs() <= ROUNDING);
        assert_eq!(bounds(0.0, -0.0085, -0.0095, -0.0105)[0], -0.0095);
        // Mirrored at the upper obstacle.
        let [lo, hi] = bounds(0.5, 0.0085, 0.0095, 0.0105);
        assert_eq!(lo, G1);
        assert!((hi - 0.009).abs() <= ROUNDING, "{hi}");
    }

    #[test]
    fn other_vertices_keep_the_obstacle_bound() {
        // Approaching but predicted above g1: no contact closes.
        assert_eq!(bounds(0.5, -0.0085, -0.0095, -0.0099), [G1, G2]);
        // Predicted below g1 but receding or at rest: the position law.
        assert_eq!(bounds(0.5, -0.0095, -0.0085, -0.0105), [G1, G2]);
        assert_eq!(bounds(0.5, -0.0095, -0.0095, -0.0105), [G1, G2]);
        // No obstacle: no bound, whatever the motion.
        let free = newton_bounds(
            1.0,
            None,
            None,
            VertexMotion {
                previous: 1.0,
                current: 0.0,
                predicted: -1.0,
            },
        );
        assert_eq!(free, [f64::NEG_INFINITY, f64::INFINITY]);
    }

    /// The two facts the energy argument rests on, over a grid of motions and e: g1 ≤ lo ≤ hi ≤
    /// g2, and where lo is a rebound bound it lies between u_n and u_{n−1} (so an active lower
    /// bound has u_{n+1} − u_{n−1} ≤ 0), mirrored for hi.
    #[test]
    fn bounds_stay_within_the_obstacles_and_below_the_previous_level() {
        let levels: Vec<f64> = (0..=20).map(|k| G1 + (G2 - G1) * k as f64 / 20.0).collect();
        let predictions = [-0.02, -0.0100001, 0.0, 0.0100001, 0.02];
        for e in [0.0, 0.25, 0.5, 0.9, 1.0] {
            for &previous in &levels {
                for &current in &levels {
                    for &predicted in &predictions {
                        let [lo, hi] = bounds(e, previous, current, predicted);
                        assert!(G1 <= lo && lo <= hi && hi <= G2);
                        if lo > G1 {
                            assert!(current <= lo && lo <= previous + ROUNDING);
                        }
                        if hi < G2 {
                            assert!(previous - ROUNDING <= hi && hi <= current);
                        }
                    }
                }
            }
        }
        // A level past an obstacle (a restored state within its tolerance) still gives a box
        // within the obstacles.
        assert_eq!(bounds(1.0, G2 + 1e-9, G1 + 1e-3, -0.02), [G2, G2]);
    }

    fn persistent(e: f64, previous: f64, current: f64, predicted: f64) -> [f64; 2] {
        law(persistent_bounds, e, [previous, current, predicted])
    }

    #[test]
    fn the_persistent_law_is_newtons_at_closing_contacts_and_persistency_at_the_others() {
        // Closing (arriving at −1 mm per step, predicted below g1): Newton's rebound bound.
        for e in [0.0, 0.3, 0.5, 0.9] {
            let [lo, hi] = persistent(e, -0.0085, -0.0095, -0.0105);
            let newton = bounds(e, -0.0085, -0.0095, -0.0105)[0];
            assert!(
                (lo - newton).abs() <= ROUNDING,
                "e = {e}: {lo} against {newton}"
            );
            assert_eq!(hi, G2);
        }
        // At e = 1 exactly u_{n−1}, whatever the motion: closing, at rest, receding.
        for current in [-0.0095, -0.0085, -0.0075] {
            assert_eq!(persistent(1.0, -0.0085, current, -0.0105)[0], -0.0085);
            assert_eq!(persistent(1.0, 0.0085, -current, 0.0105)[1], 0.0085);
        }
        // Receding or at rest: g1 + e (u_{n−1} − g1), 1.5 mm above g1 here; at e = 0 the obstacle.
        let [lo, hi] = persistent(0.5, -0.0085, -0.0075, -0.0105);
        assert!((lo - (G1 + 0.5 * 0.0015)).abs() <= ROUNDING, "{lo}");
        assert_eq!(hi, G2);
        assert_eq!(persistent(0.0, -0.0085, -0.0085, -0.0105)[0], G1);
        // Mirrored at the upper obstacle, with the same roundings.
        let lower = persistent(0.37, -0.0085, -0.0091, -0.0105)[0];
        let upper = persistent(0.37, 0.0085, 0.0091, 0.0105)[1];
        assert_eq!(upper, -lower);
        // No crossing: the obstacles.
        assert_eq!(persistent(1.0, -0.0085, -0.0095, -0.0099), [G1, G2]);
    }

    /// The facts the energy argument rests on, over a grid of motions and e: g1 ≤ lo ≤ hi ≤ g2;
    /// where lo is the law's, g1 ≤ lo ≤ u_{n−1} (an active bound does no positive work,
    /// f (lo − u_{n−1}) ≤ 0) and at e = 1 lo = u_{n−1} exactly (it does none); lo grows with e
    /// (the work removed, ½ f (u_{n−1} − lo), falls with e); mirrored for hi.
    #[test]
    fn persistent_bounds_do_no_work_at_e_1_and_never_positive_work() {
        let levels: Vec<f64> = (0..=20).map(|k| G1 + (G2 - G1) * k as f64 / 20.0).collect();
        let restitutions = [0.0, 0.25, 0.5, 0.9, 1.0];
        for &previous in &levels {
            for &current in &levels {
                let mut last = [f64::NEG_INFINITY, f64::INFINITY];
                for e in restitutions {
                    let [lo, hi] = persistent(e, previous, current, -0.02);
                    assert!(G1 <= lo && lo <= hi && hi <= G2);
                    assert!(lo <= previous && lo >= last[0], "{e} {previous} {current}");
                    let [lo_up, hi_up] = persistent(e, previous, current, 0.02);
                    assert_eq!(lo_up, G1);
                    assert!(
                        hi_up >= previous && hi_up <= last[1],
                        "{e} {previous} {current}"
                    );
                    if e == 1.0 {
                        assert_eq!([lo, hi_up], [previous, previous]);
                    }
                    last = [lo, hi_up];
                }
            }
        }
        // A level past an obstacle (a restored state within its tolerance) still gives a box
        // within the obstacles.
        assert_eq!(persistent(1.0, G1 - 1e-9, G1, -0.02), [G1, G2]);
        assert_eq!(persistent(1.0, G2 + 1e-9, G1 + 1e-3, -0.02), [G2, G2]);
    }

    #[test]
    fn law_of_the_settings() {
        let mut solver = crate::scene::Scene::default().solver;
        assert_eq!(Law::of(&solver), Law::Position);
        solver.restitution = 0.8;
        assert_eq!(Law::of(&solver), Law::Persistent(0.8));
        solver.impact_law = ImpactLaw::Newton;
        assert_eq!(Law::of(&solver), Law::Newton(0.8));
        solver.restitution = 0.0;
        assert_eq!(Law::of(&solver), Law::Newton(0.0));
        solver.impact_law = ImpactLaw::Persistent;
        assert_eq!(Law::of(&solver), Law::Persistent(0.0));
    }
}
