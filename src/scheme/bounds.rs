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
    /// [h₁, h₂] per contact point.
    pub(crate) heights: &'a [Vec<f64>; 2],
}

impl ObstacleBounds<'_> {
    /// The lower bound of point i.
    pub(crate) fn lower(&self, i: usize) -> f64 {
        self.levels[0] + self.heights[0][i]
    }

    /// The upper bound of point i.
    pub(crate) fn upper(&self, i: usize) -> f64 {
        self.levels[1] + self.heights[1][i]
    }

    /// Whether `y` lies within point i's bounds.
    pub(crate) fn admits(&self, i: usize, y: f64) -> bool {
        y >= self.lower(i) && y <= self.upper(i)
    }
}
