//! The internal time grid of a simulation: t_n = t_start + n Δt, always computed from the step
//! count n, never accumulated, so it does not drift.
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

/// Relative tolerance on a communication step size h = kΔt: |h − kΔt| ≤ 1e-9 h. It absorbs the
/// round-off of hosts that compute h as a difference of communication points.
pub const STEP_TOLERANCE: f64 = 1e-9;

/// Why a communication step or a grid time is refused.
#[derive(Clone, Debug, PartialEq)]
pub enum GridError {
    /// h is not finite or not > 0.
    InvalidStep {
        /// The step size (s).
        step_size: f64,
    },
    /// h is not a whole multiple of Δt within [`STEP_TOLERANCE`].
    NotAMultiple {
        /// The step size (s).
        step_size: f64,
        /// Δt (s).
        time_step: f64,
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
            GridError::NotAMultiple {
                step_size,
                time_step,
            } => write!(
                f,
                "communicationStepSize h = {step_size} s is not a whole multiple of solver.time_step Δt = {time_step} s (h/Δt = {}); use h = k·Δt",
                step_size / time_step
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

    /// The number k of internal steps in a communication step h = kΔt: 1 ≤ k ≤
    /// [`MAX_STEPS_PER_CALL`], |h − kΔt| ≤ [`STEP_TOLERANCE`]·h.
    pub fn steps_in(&self, h: f64) -> Result<u64, GridError> {
        if !(h.is_finite() && h > 0.0) {
            return Err(GridError::InvalidStep { step_size: h });
        }
        let k = (h / self.step).round();
        if k > MAX_STEPS_PER_CALL as f64 {
            return Err(GridError::TooManySteps {
                step_size: h,
                steps: h / self.step,
            });
        }
        if k < 1.0 || (k * self.step - h).abs() > STEP_TOLERANCE * h {
            return Err(GridError::NotAMultiple {
                step_size: h,
                time_step: self.step,
            });
        }
        Ok(k as u64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GRID: TimeGrid = TimeGrid {
        start: 0.0,
        step: 1e-4,
    };

    #[test]
    fn whole_multiples_within_the_tolerance() {
        assert_eq!(GRID.steps_in(1e-3), Ok(10));
        // The nine values fmpy passes as t_{k+1} − t_k around 1e-3 all mean ten steps.
        for k in 1..2000u32 {
            let h = f64::from(k + 1) * 1e-3 - f64::from(k) * 1e-3;
            assert_eq!(GRID.steps_in(h), Ok(10), "h = {h}");
        }
        assert!(matches!(
            GRID.steps_in(1.5e-4),
            Err(GridError::NotAMultiple { .. })
        ));
        assert!(matches!(
            GRID.steps_in(4e-5),
            Err(GridError::NotAMultiple { .. })
        ));
        for h in [0.0, -1e-3, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                GRID.steps_in(h),
                Err(GridError::InvalidStep { .. })
            ));
        }
    }

    #[test]
    fn huge_steps_are_refused_at_once() {
        for h in [1e300, 1e12] {
            let err = GRID.steps_in(h).unwrap_err();
            assert!(matches!(err, GridError::TooManySteps { .. }));
            assert!(err.to_string().contains("68719476736"), "{err}");
        }
        let largest = MAX_STEPS_PER_CALL as f64 * 1e-4;
        assert_eq!(GRID.steps_in(largest), Ok(MAX_STEPS_PER_CALL));
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
