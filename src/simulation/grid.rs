//! The internal time grid of a simulation: t_n = t_start + n Δt, always computed from the step
//! count n, never accumulated, so it does not drift, and where a communication step ends on it.
//!
//! A communication step from the communication point t to t + h ends at the first grid point
//! t_N ≥ t + h ([`TimeGrid::step_end`]): the simulation computes the grid up to t_N, and t + h is
//! either t_N itself (within [`TimeGrid::snap_tolerance`], which absorbs the round-off of hosts
//! that compute h as a difference of communication points) or lies strictly between t_{N−1} and
//! t_N. The grid never depends on the host's steps.
//!
//! Two limits keep every communication step finite and every grid time meaningful:
//! * [`MAX_STEPS_PER_CALL`] internal steps per communication step at most;
//! * a grid time t must resolve the step: the spacing of doubles at |t| must not exceed
//!   Δt·[`GRID_RESOLUTION`], so consecutive grid times differ by Δt to 0.1 % at worst (with
//!   t_start = 0 and Δt = 1e-4 s this holds up to t ≈ 4.4e8 s, fourteen years).

use std::fmt;

/// The most internal steps one communication step may take. Sized so that a refused step is one
/// nobody would wait for: the fastest step measured (a 1 × 1 mesh without obstacles, 0.06 µs per
/// internal step on the 2-core development machine) would need more than an hour for it, and the
/// paper's 10 × 7 Argyris mesh (2.9 µs per step) more than two days. A synchronous communication
/// step cannot be cancelled, so anything longer is surely a wrong step size (such as h = 1e12 s).
pub const MAX_STEPS_PER_CALL: u64 = 1 << 36;

/// The largest spacing of doubles at a grid time, as a fraction of Δt (see the module docs).
pub const GRID_RESOLUTION: f64 = 1.0 / 1024.0;

/// Relative tolerance, in units of h, within which a communication point t + h counts as the grid
/// point t_N (see [`TimeGrid::snap_tolerance`]). It absorbs the round-off of hosts that compute h
/// as a difference of communication points: fmpy's t_{k+1} − t_k takes nine different values
/// around 1e-3, all of which must mean ten steps of 1e-4 s.
pub const STEP_TOLERANCE: f64 = 1e-9;

/// Why a communication step or a grid time is refused.
#[derive(Clone, Debug, PartialEq)]
pub enum GridError {
    /// h is not finite or not > 0.
    InvalidStep {
        /// The step size (s).
        step_size: f64,
    },
    /// h needs more than [`MAX_STEPS_PER_CALL`] internal steps.
    TooManySteps {
        /// The step size (s).
        step_size: f64,
        /// h/Δt.
        steps: f64,
    },
    /// A grid time where doubles are too coarse to tell internal steps apart.
    Unresolved {
        /// The time (s).
        time: f64,
        /// Δt (s).
        time_step: f64,
    },
}

impl fmt::Display for GridError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GridError::InvalidStep { step_size } => write!(
                f,
                "communicationStepSize h = {step_size} s must be finite and > 0"
            ),
            GridError::TooManySteps { step_size, steps } => write!(
                f,
                "communicationStepSize h = {step_size} s needs {steps:e} internal steps, more than the {MAX_STEPS_PER_CALL} one call may take (a call that long could not be cancelled); use shorter communication steps"
            ),
            GridError::Unresolved { time, time_step } => write!(
                f,
                "at t = {time} s doubles are {:e} s apart, too coarse for internal steps of solver.time_step = {time_step} s (at most Δt/{} is needed); start the experiment nearer to t = 0 or use a longer time step",
                spacing(*time),
                1.0 / GRID_RESOLUTION
            ),
        }
    }
}

impl std::error::Error for GridError {}

/// The distance from |t| to the next larger double.
fn spacing(t: f64) -> f64 {
    let a = t.abs();
    f64::from_bits(a.to_bits() + 1) - a
}

/// The grid t_n = start + n·step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimeGrid {
    /// t_start (s).
    pub start: f64,
    /// Δt (s).
    pub step: f64,
}

impl TimeGrid {
    /// t_n = start + n Δt (s).
    pub fn time(&self, n: u64) -> f64 {
        self.start + n as f64 * self.step
    }

    /// n Δt, the time since the start (s).
    pub fn elapsed(&self, n: u64) -> f64 {
        n as f64 * self.step
    }

    /// Whether doubles near `t` are fine enough to tell internal steps apart (module docs).
    pub fn check_resolves(&self, t: f64) -> Result<(), GridError> {
        if t.is_finite() && spacing(t) <= self.step * GRID_RESOLUTION {
            Ok(())
        } else {
            Err(GridError::Unresolved {
                time: t,
                time_step: self.step,
            })
        }
    }

    /// Within how much of a grid point (s) the communication point `target` (t + h − t_start)
    /// counts as that grid point, for a step of size `h`: [`STEP_TOLERANCE`]·h, at most
    /// Δt·[`GRID_RESOLUTION`], plus two spacings of doubles at t + h (the round-off of forming
    /// t + h and t_N). Every h that lies within [`STEP_TOLERANCE`]·h of a whole multiple of Δt from
    /// a grid point (and is below ~10⁶ Δt) is on the grid.
    pub fn snap_tolerance(&self, target: f64, h: f64) -> f64 {
        let round_off = spacing(target).max(spacing(self.start + target));
        (STEP_TOLERANCE * h).min(GRID_RESOLUTION * self.step) + 2.0 * round_off
    }

    /// Where a communication step of size `h` ends when the communication point is `from`
    /// (t − t_start, s) and the simulation has computed the grid up to index `computed` (so
    /// t_{computed−1} < t ≤ t_computed): the first grid index N with t_N ≥ t + h, and whether
    /// t + h is t_N (within [`TimeGrid::snap_tolerance`]) or lies strictly before it. N is never
    /// below `computed`: a step that ends before the last computed grid point computes nothing.
    /// Refused: h not finite and > 0, or more than [`MAX_STEPS_PER_CALL`] new internal steps.
    pub fn step_end(&self, from: f64, computed: u64, h: f64) -> Result<StepEnd, GridError> {
        if !(h.is_finite() && h > 0.0) {
            return Err(GridError::InvalidStep { step_size: h });
        }
        let target = from + h;
        let x = target / self.step;
        let too_many = |steps: f64| GridError::TooManySteps {
            step_size: h,
            steps,
        };
        // Checked on the real number first, so that h = 1e300 never reaches an integer.
        if x - computed as f64 > MAX_STEPS_PER_CALL as f64 + 1.0 {
            return Err(too_many(x - computed as f64));
        }
        let nearest = x.round();
        let end = if nearest >= computed as f64
            && (self.elapsed(nearest as u64) - target).abs() <= self.snap_tolerance(target, h)
        {
            StepEnd {
                index: nearest as u64,
                between: None,
            }
        } else {
            let mut index = (x.ceil() as u64).max(computed);
            // x is rounded: make sure t_N really lies at or after t + h.
            while self.elapsed(index) < target {
                index += 1;
            }
            StepEnd {
                index,
                between: Some(target),
            }
        };
        let steps = end.index - computed;
        if steps > MAX_STEPS_PER_CALL {
            return Err(too_many(steps as f64));
        }
        Ok(end)
    }
}

/// Where a communication step ends on the grid ([`TimeGrid::step_end`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepEnd {
    /// N: the grid index the simulation must reach, the first with t_N ≥ t + h.
    pub index: u64,
    /// t + h − t_start (s) when the communication point lies strictly between t_{N−1} and t_N;
    /// `None` when it is t_N.
    pub between: Option<f64>,
}

impl StepEnd {
    /// t + h − t_start (s): exactly N Δt when the step ends on the grid.
    pub fn elapsed(&self, grid: &TimeGrid) -> f64 {
        self.between.unwrap_or_else(|| grid.elapsed(self.index))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GRID: TimeGrid = TimeGrid {
        start: 0.0,
        step: 1e-4,
    };

    fn on_grid(index: u64) -> Result<StepEnd, GridError> {
        Ok(StepEnd {
            index,
            between: None,
        })
    }

    #[test]
    fn whole_multiples_land_on_the_grid() {
        assert_eq!(GRID.step_end(0.0, 0, 1e-3), on_grid(10));
        // The nine values fmpy passes as t_{k+1} − t_k around 1e-3 all mean ten steps, from every
        // grid point they are used at (the fmpy time is k·1e-3, the grid time 10k·1e-4).
        for k in 1..2000u32 {
            let h = f64::from(k + 1) * 1e-3 - f64::from(k) * 1e-3;
            let n = 10 * u64::from(k);
            assert_eq!(
                GRID.step_end(GRID.elapsed(n), n, h),
                on_grid(n + 10),
                "h = {h}"
            );
        }
        // Far from the start the round-off of t + h exceeds 1e-9 h; still on the grid.
        let n = 4_000_000_000_000;
        let from = GRID.elapsed(n);
        assert_eq!(GRID.step_end(from, n, 3e-4), on_grid(n + 3));
        for h in [0.0, -1e-3, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                GRID.step_end(0.0, 0, h),
                Err(GridError::InvalidStep { .. })
            ));
        }
    }

    #[test]
    fn other_steps_end_before_the_next_grid_point() {
        let between = |index, target| {
            Ok(StepEnd {
                index,
                between: Some(target),
            })
        };
        assert_eq!(GRID.step_end(0.0, 0, 1.5e-4), between(2, 1.5e-4));
        assert_eq!(GRID.step_end(0.0, 0, 0.5e-4), between(1, 0.5e-4));
        assert_eq!(GRID.step_end(0.0, 0, 1e-9), between(1, 1e-9));
        // From between t_1 and t_2, with t_2 already computed: nothing new to compute...
        assert_eq!(
            GRID.step_end(1.5e-4, 2, 0.2e-4),
            between(2, 1.5e-4 + 0.2e-4)
        );
        // ...until the step reaches t_2 (snapped onto it) or goes beyond it.
        assert_eq!(GRID.step_end(1.5e-4, 2, 0.5e-4), on_grid(2));
        assert_eq!(GRID.step_end(1.5e-4, 2, 1e-4), between(3, 1.5e-4 + 1e-4));
        // fmpy's last step to a stop time off the grid.
        let from = GRID.elapsed(9990);
        let end = GRID.step_end(from, 9990, 0.99995 - 0.999).unwrap();
        assert_eq!(end.index, 10000);
        assert!((end.elapsed(&GRID) - 0.99995).abs() < 1e-15);
        // Random steps: t_{N−1} < t + h ≤ t_N whenever t + h is off the grid.
        let (mut from, mut computed) = (0.0, 0);
        for k in 0..10_000u32 {
            let h = 1e-4 * (0.01 + 3.0 * ((f64::from(k) * 0.618_034).fract()));
            let end = GRID.step_end(from, computed, h).unwrap();
            if let Some(target) = end.between {
                assert!(GRID.elapsed(end.index - 1) < target && target < GRID.elapsed(end.index));
            }
            assert!(end.index >= computed);
            (from, computed) = (end.elapsed(&GRID), end.index);
        }
    }

    #[test]
    fn huge_steps_are_refused_at_once() {
        for h in [1e300, 1e12] {
            let err = GRID.step_end(0.0, 0, h).unwrap_err();
            assert!(matches!(err, GridError::TooManySteps { .. }));
            assert!(err.to_string().contains("68719476736"), "{err}");
        }
        let largest = MAX_STEPS_PER_CALL as f64 * 1e-4;
        assert_eq!(
            GRID.step_end(0.0, 0, largest).map(|e| e.index),
            Ok(MAX_STEPS_PER_CALL)
        );
        assert!(GRID.step_end(0.0, 0, largest + 1e-4).is_err());
    }

    #[test]
    fn coarse_grid_times_are_refused() {
        assert!(GRID.check_resolves(0.0).is_ok());
        assert!(GRID.check_resolves(-1.0).is_ok());
        assert!(GRID.check_resolves(4e8).is_ok());
        // Beyond 2^42 Δt the spacing of doubles exceeds Δt/1024.
        assert!(GRID.check_resolves(1e9).is_err());
        let err = GRID.check_resolves(-1e308).unwrap_err();
        assert!(err.to_string().contains("too coarse"), "{err}");
        assert!(GRID.check_resolves(f64::NAN).is_err());
        // t + Δt == t there: the grid could not advance at all.
        assert_eq!(-1e308 + 1e-4, -1e308);
    }
}
