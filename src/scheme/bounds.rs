//! The obstacles' bounds on a step's constrained values (Bw)_i, relative to the base: the level of
//! each obstacle less the base displacement, plus each contact point's height of the obstacle's
//! profile (docs/scheme.md §4),
//!
//!   g1 − z_{n+1} + h₁_i ≤ (Bw_{n+1})_i ≤ g2 − z_{n+1} + h₂_i,
//!
//! with h = −∞ or +∞ where an obstacle is absent. A profile shifts as a whole when its level is
//! tuned, so only the two levels change during a run; for flat obstacles every height is 0 and a
//! bound is the level bit for bit.

/// One step's obstacle bounds (module docs).
#[derive(Clone, Copy, Debug)]
pub(crate) struct ObstacleBounds<'a> {
    /// [g1 − z_{n+1}, g2 − z_{n+1}]: −∞ and +∞ for a disabled obstacle.
    pub(crate) levels: [f64; 2],
    /// [h₁, h₂] per contact point; `None` when every height is 0 (flat obstacles), so that the
    /// bounds of the paper's scenes are read from the levels alone, as before profiles existed.
    heights: Option<&'a [Vec<f64>; 2]>,
}

impl<'a> ObstacleBounds<'a> {
    /// The bounds `levels` plus `heights` ([h₁, h₂] per contact point).
    pub(crate) fn new(levels: [f64; 2], heights: &'a [Vec<f64>; 2]) -> Self {
        let flat = heights.iter().all(|h| h.iter().all(|&x| x == 0.0));
        ObstacleBounds {
            levels,
            heights: (!flat).then_some(heights),
        }
    }

    /// The bounds `levels` at every contact point: flat obstacles.
    pub(crate) fn flat(levels: [f64; 2]) -> Self {
        ObstacleBounds {
            levels,
            heights: None,
        }
    }

    /// The lower bound of point i.
    pub(crate) fn lower(&self, i: usize) -> f64 {
        match self.heights {
            None => self.levels[0],
            Some(h) => self.levels[0] + h[0][i],
        }
    }

    /// The upper bound of point i.
    pub(crate) fn upper(&self, i: usize) -> f64 {
        match self.heights {
            None => self.levels[1],
            Some(h) => self.levels[1] + h[1][i],
        }
    }

    /// Whether `y` lies within point i's bounds.
    pub(crate) fn admits(&self, i: usize, y: f64) -> bool {
        y >= self.lower(i) && y <= self.upper(i)
    }
}
