//! Window statistics of a steady state: the time averages read from the tallies of a run's
//! windows (or forcing periods), their values over K windows, and the spread those give.

use crate::recorder::Tally;
use crate::sample::standard_error;

/// A time average read from tallies: g(Σ numerator / Σ denominator) over any set of them, g the
/// square root for an RMS, the identity otherwise; over a set of windows, the average over their
/// whole time (not the mean of their averages).
pub struct Quantity<T> {
    /// Its name in the studies' CSVs.
    pub name: &'static str,
    numerator: fn(&T) -> f64,
    denominator: fn(&T) -> f64,
    root: bool,
}

impl<T> Quantity<T> {
    /// The quantity g(Σ `numerator` / Σ `denominator`), g = √ with `root`.
    pub const fn new(
        name: &'static str,
        numerator: fn(&T) -> f64,
        denominator: fn(&T) -> f64,
        root: bool,
    ) -> Quantity<T> {
        Quantity {
            name,
            numerator,
            denominator,
            root,
        }
    }

    /// The quantity over `tallies`.
    pub fn over(&self, tallies: &[T]) -> f64 {
        let num: f64 = tallies.iter().map(self.numerator).sum();
        let den: f64 = tallies.iter().map(self.denominator).sum();
        let ratio = num / den;
        if self.root {
            ratio.sqrt()
        } else {
            ratio
        }
    }
}

/// The time averages of a steady state, from a [`Tally`] (or a record that holds one).
impl<T: AsRef<Tally>> Quantity<T> {
    /// The mean of `energy.total` over the samples, Σ E / N_samples (J).
    pub const MEAN_ENERGY: Quantity<T> = Quantity::new(
        "mean_energy_J",
        |t| t.as_ref().energy,
        |t| t.as_ref().samples as f64,
        false,
    );
    /// The RMS of the free corner u(Lx, 0) over the samples, √(Σ u² / N_samples) (m).
    pub const RMS_CORNER: Quantity<T> = Quantity::new(
        "rms_corner_m",
        |t| t.as_ref().corner_squared,
        |t| t.as_ref().samples as f64,
        true,
    );
    /// The mean of |`base.force`| over the steps, Σ |F| / N_steps (N).
    pub const MEAN_ABS_BASE_FORCE: Quantity<T> = Quantity::new(
        "mean_abs_base_force_N",
        |t| t.as_ref().base_force_abs,
        |t| t.as_ref().steps as f64,
        false,
    );
    /// The RMS of `base.force` over the steps, √(Σ F² / N_steps) (N): what loads the supporting
    /// structure.
    pub const RMS_BASE_FORCE: Quantity<T> = Quantity::new(
        "rms_base_force_N",
        |t| t.as_ref().base_force_squared,
        |t| t.as_ref().steps as f64,
        true,
    );
    /// Impacts per forcing period, Σ impacts / Σ periods.
    pub const IMPACTS_PER_PERIOD: Quantity<T> = Quantity::new(
        "impacts_per_period",
        |t| t.as_ref().impacts as f64,
        |t| t.as_ref().periods as f64,
        false,
    );
    /// The energy removed at the obstacles per forcing period, Σ contact loss / Σ periods (J).
    pub const CONTACT_LOSS_PER_PERIOD: Quantity<T> = Quantity::new(
        "contact_loss_per_period_J",
        |t| t.as_ref().contact_loss,
        |t| t.as_ref().periods as f64,
        false,
    );
}

/// The values of `read` over each of the K = ⌊N / w⌋ windows of w = `per_window` consecutive
/// tallies of `tallies` (N of them; a last, partial window is left out).
pub fn window_values<T>(tallies: &[T], per_window: usize, read: impl Fn(&[T]) -> f64) -> Vec<f64> {
    tallies.chunks_exact(per_window).map(read).collect()
}

/// The spread of a time average over K windows from its K window values x_j: the standard error
/// of their mean, √(s²/K) with s² their sample variance, the standard deviation of what one run
/// would report had its chaotic response taken another course, if the windows are independent.
/// NaN for fewer than two windows.
pub fn window_spread(values: &[f64]) -> f64 {
    if values.len() < 2 {
        return f64::NAN;
    }
    standard_error(values)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_time_average_pools_its_windows_and_its_spread_is_their_standard_error() {
        let window = |steps, force: f64, periods| Tally {
            periods,
            steps,
            base_force_abs: force * steps as f64,
            base_force_squared: force * force * steps as f64,
            impacts: periods * 2,
            ..Tally::default()
        };
        // Two windows of 10 and 30 steps at |F| = 1 and 3 N: the whole time's mean is 2.5 N, not
        // the mean of the two windows' (2 N).
        let tallies = [window(10, 1.0, 1), window(30, 3.0, 3)];
        assert_eq!(Quantity::MEAN_ABS_BASE_FORCE.over(&tallies), 2.5);
        let rms = Quantity::RMS_BASE_FORCE.over(&tallies);
        assert!((rms - (280.0f64 / 40.0).sqrt()).abs() < 1e-15);
        assert_eq!(Quantity::IMPACTS_PER_PERIOD.over(&tallies), 2.0);
        let values = window_values(&tallies, 1, |w| Quantity::MEAN_ABS_BASE_FORCE.over(w));
        assert_eq!(values, [1.0, 3.0]);
        // s² = 2, K = 2: √(2/2) = 1.
        assert_eq!(window_spread(&values), 1.0);
        assert!(window_spread(&values[..1]).is_nan());
        // Three tallies in windows of two: one window, the third tally left out.
        assert_eq!(
            window_values(&[1.0, 2.0, 4.0], 2, |w| w.iter().sum()),
            [3.0]
        );
    }
}
