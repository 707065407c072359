//! The integrated autocorrelation time of a series of per-period values, and the spread of their
//! mean that it gives.

use crate::sample::mean_std;

/// The integrated autocorrelation time τ = 1 + 2 Σ_{t=1}^{M} ρ(t) of a series (in its samples),
/// with Sokal's window: the smallest M ≥ 5τ(M) (A. Sokal, *Monte Carlo methods in statistical
/// mechanics*, 1997, §3), so that the variance of the mean of N samples is τσ²/N. ρ(t) is the
/// autocovariance at lag t over the variance, each with the series' own mean. A series without
/// variance (a periodic response) has τ = 1; a series too short for the window (M reaches N/4)
/// returns the τ reached there, flagged `false`.
pub fn integrated_time(xs: &[f64]) -> (f64, bool) {
    let n = xs.len();
    let mean = xs.iter().sum::<f64>() / n as f64;
    let centred: Vec<f64> = xs.iter().map(|x| x - mean).collect();
    let variance = centred.iter().map(|x| x * x).sum::<f64>() / n as f64;
    if variance <= (1e-12 * mean.abs()).powi(2) || n < 8 {
        return (1.0, variance == 0.0 || n >= 8);
    }
    let mut tau = 1.0;
    for lag in 1..n / 4 {
        let covariance = centred[..n - lag]
            .iter()
            .zip(&centred[lag..])
            .map(|(a, b)| a * b)
            .sum::<f64>()
            / n as f64;
        tau += 2.0 * covariance / variance;
        if lag as f64 >= 5.0 * tau {
            return (tau.max(1.0 / n as f64), true);
        }
    }
    (tau.max(1.0 / n as f64), false)
}

/// The correlation estimate of the spread of a series' mean.
#[derive(Clone, Copy, Debug)]
pub struct Correlation {
    /// The integrated autocorrelation time τ in samples ([`integrated_time`]; NaN for a series
    /// with a value that is not finite).
    pub tau: f64,
    /// Whether Sokal's window closed within the series.
    pub resolved: bool,
    /// √(τ s² / N), s the series' sample standard deviation and N its length: the standard
    /// deviation of the mean of N correlated samples (NaN where τ is).
    pub spread: f64,
}

/// The correlation estimate of the spread of the mean of `series`.
pub fn correlation(series: &[f64]) -> Correlation {
    if !series.iter().all(|x| x.is_finite()) {
        return Correlation {
            tau: f64::NAN,
            resolved: false,
            spread: f64::NAN,
        };
    }
    let (tau, resolved) = integrated_time(series);
    Correlation {
        tau,
        resolved,
        spread: (tau * mean_std(series).1.powi(2) / series.len() as f64).sqrt(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Uniform values in [−½, ½) from a fixed linear congruential generator: a deterministic
    /// series without memory.
    fn uniform(count: usize) -> Vec<f64> {
        let mut state: u64 = 12345;
        (0..count)
            .map(|_| {
                state = state
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
            })
            .collect()
    }

    #[test]
    fn independent_values_have_a_time_near_one_and_a_constant_series_exactly_one() {
        let (tau, resolved) = integrated_time(&uniform(20_000));
        assert!(resolved);
        assert!((tau - 1.0).abs() < 0.1, "τ = {tau}");
        assert_eq!(integrated_time(&[2.0; 50]), (1.0, true));
    }

    #[test]
    fn a_correlated_series_has_the_time_of_its_process() {
        // AR(1) with coefficient a has τ = (1 + a)/(1 − a) = 3 for a = 0.5.
        let a = 0.5;
        let mut x = 0.0;
        let xs: Vec<f64> = uniform(200_000)
            .into_iter()
            .map(|u| {
                x = a * x + u;
                x
            })
            .collect();
        let c = correlation(&xs);
        assert!(c.resolved);
        assert!((c.tau - 3.0).abs() < 0.3, "τ = {}", c.tau);
        let naive = mean_std(&xs).1 / (xs.len() as f64).sqrt();
        assert!((c.spread / naive - 3f64.sqrt()).abs() < 0.1);
        assert!(correlation(&[1.0, f64::NAN]).spread.is_nan());
    }
}
