//! The observed order of convergence of a series of runs.

/// The observed order p of errors e_i at steps x_i (Δt, or a mesh size): the least-squares slope
/// of ln e against ln x, p = Σ(ln x_i − m_x)(ln e_i − m_e) / Σ(ln x_i − m_x)², m the means, so
/// that e ≈ C x^p. An error of exactly zero has no logarithm and its point is left out; an error
/// that is not a number makes the order NaN.
pub fn observed_order(x: &[f64], errors: &[f64]) -> f64 {
    let (lx, le): (Vec<f64>, Vec<f64>) = x
        .iter()
        .zip(errors)
        .filter(|(_, e)| **e != 0.0)
        .map(|(x, e)| (x.ln(), e.ln()))
        .unzip();
    let n = lx.len() as f64;
    let mx = lx.iter().sum::<f64>() / n;
    let me = le.iter().sum::<f64>() / n;
    let sxy: f64 = lx.iter().zip(&le).map(|(x, e)| (x - mx) * (e - me)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_power_law_has_its_exponent_as_order() {
        let x = [1e-3, 5e-4, 2e-4, 1e-4];
        let e: Vec<f64> = x.iter().map(|x| 3.0 * x * x).collect();
        assert!((observed_order(&x, &e) - 2.0).abs() < 1e-12);
        // A zero error is left out; a NaN one poisons the fit.
        let with_zero = [e[0], e[1], e[2], 0.0];
        assert!((observed_order(&x, &with_zero) - 2.0).abs() < 1e-12);
        assert!(observed_order(&x, &[e[0], f64::NAN, e[2], e[3]]).is_nan());
    }
}
