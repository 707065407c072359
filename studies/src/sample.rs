//! The moments of a sample of values: its mean, its standard deviation, and the standard error of
//! its mean.

/// Mean and sample variance of `xs`: x̄ = Σx/n and s² = Σ(x − x̄)²/(n − 1) (NaN for n < 2).
pub fn mean_variance(xs: &[f64]) -> (f64, f64) {
    let n = xs.len() as f64;
    let mean = xs.iter().sum::<f64>() / n;
    let variance = xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1.0);
    (mean, variance)
}

/// Mean and sample standard deviation of `xs`: x̄ = Σx/n and s = √(Σ(x − x̄)²/(n − 1)).
pub fn mean_std(xs: &[f64]) -> (f64, f64) {
    let (mean, variance) = mean_variance(xs);
    (mean, variance.sqrt())
}

/// The standard error of the mean of the n values `xs`, √(s²/n) with s² their sample variance: the
/// standard deviation of x̄ if the values are independent.
pub fn standard_error(xs: &[f64]) -> f64 {
    let (_, variance) = mean_variance(xs);
    (variance / xs.len() as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_moments_of_a_small_sample() {
        let xs = [1.0, 2.0, 3.0, 6.0];
        let (mean, std) = mean_std(&xs);
        assert_eq!(mean, 3.0);
        // Σ(x − 3)² = 4 + 1 + 0 + 9 = 14, over n − 1 = 3.
        assert!((std - (14.0f64 / 3.0).sqrt()).abs() < 1e-15);
        assert!((standard_error(&xs) - (14.0f64 / 12.0).sqrt()).abs() < 1e-15);
        assert!(mean_std(&[1.0]).1.is_nan());
    }
}
