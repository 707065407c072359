//! Reductions over dense vectors, each in one fixed summation order (so that results repeat bit
//! for bit).

/// aᵀb, summed in index order.
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Σ x_k², with four partial sums so that the additions do not wait on each other.
pub(crate) fn sum_of_squares(x: &[f64]) -> f64 {
    let mut partial = [0.0; 4];
    let chunks = x.chunks_exact(4);
    let rest: f64 = chunks.remainder().iter().map(|v| v * v).sum();
    for chunk in chunks {
        for (p, v) in partial.iter_mut().zip(chunk) {
            *p += v * v;
        }
    }
    partial.iter().sum::<f64>() + rest
}
