//! An independent reference for the spectra: the Ritz method on the whole rectangle with products
//! of Legendre polynomials, each multiplied by the factor that clamps it where the plate is
//! clamped ((1 + ξ)², (1 − ξ)² or (1 − ξ²)² along a direction with one or two clamped ends),
//! the construction of Young's and Leissa's tables with polynomials in place of beam functions.
//! The basis is separable, so M and K are Kronecker sums of one-dimensional integrals taken
//! exactly by Gauss–Legendre rules. Conforming, so its frequencies are upper bounds that fall as
//! the number of polynomials grows; it shares nothing with the finite elements but the rule.

use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::{Mat, Par, Side};
use plate_impact::quadrature::gauss_legendre_unit;

/// Which ends of one direction of the rectangle are clamped: (at 0, at the length).
pub type Ends = (bool, bool);

/// The 1-D integrals of one direction, each N × N: ∫ b_i b_k, ∫ b_i' b_k', ∫ b_i'' b_k'' and
/// ∫ b_i'' b_k, in physical units on (0, `length`).
struct Direction {
    values: Mat<f64>,
    slopes: Mat<f64>,
    curvatures: Mat<f64>,
    mixed: Mat<f64>,
}

/// The clamping factor c(ξ) and its first two derivatives.
fn factor(ends: Ends, xi: f64) -> [f64; 3] {
    let (p, m) = (1.0 + xi, 1.0 - xi);
    match ends {
        (false, false) => [1.0, 0.0, 0.0],
        (true, false) => [p * p, 2.0 * p, 2.0],
        (false, true) => [m * m, -2.0 * m, 2.0],
        // (1 − ξ²)² = 1 − 2ξ² + ξ⁴.
        (true, true) => {
            let s = 1.0 - xi * xi;
            [s * s, -4.0 * xi * s, 12.0 * xi * xi - 4.0]
        }
    }
}

impl Direction {
    fn new(length: f64, ends: Ends, count: usize) -> Direction {
        let rule = gauss_legendre_unit(count + 4);
        let (jacobian, derivative) = (0.5 * length, 2.0 / length);
        let mut d = Direction {
            values: Mat::zeros(count, count),
            slopes: Mat::zeros(count, count),
            curvatures: Mat::zeros(count, count),
            mixed: Mat::zeros(count, count),
        };
        for &(t, weight) in &rule {
            let xi = 2.0 * t - 1.0;
            // The rule integrates over [0, 1]: dξ = 2 dt.
            let w = 2.0 * weight * jacobian;
            // Legendre P_i, P_i', P_i'' by their recurrences.
            let mut p = vec![[0.0; 3]; count];
            for i in 0..count {
                p[i] = match i {
                    0 => [1.0, 0.0, 0.0],
                    1 => [xi, 1.0, 0.0],
                    _ => {
                        let n = (i - 1) as f64;
                        let value =
                            ((2.0 * n + 1.0) * xi * p[i - 1][0] - n * p[i - 2][0]) / (n + 1.0);
                        let slope = p[i - 2][1] + (2.0 * n + 1.0) * p[i - 1][0];
                        let curvature = p[i - 2][2] + (2.0 * n + 1.0) * p[i - 1][1];
                        [value, slope, curvature]
                    }
                };
            }
            let c = factor(ends, xi);
            let b: Vec<[f64; 3]> = p
                .iter()
                .map(|q| {
                    [
                        c[0] * q[0],
                        derivative * (c[1] * q[0] + c[0] * q[1]),
                        derivative * derivative * (c[2] * q[0] + 2.0 * c[1] * q[1] + c[0] * q[2]),
                    ]
                })
                .collect();
            for i in 0..count {
                for k in 0..count {
                    d.values[(i, k)] += w * b[i][0] * b[k][0];
                    d.slopes[(i, k)] += w * b[i][1] * b[k][1];
                    d.curvatures[(i, k)] += w * b[i][2] * b[k][2];
                    d.mixed[(i, k)] += w * b[i][2] * b[k][0];
                }
            }
        }
        d
    }
}

/// The frequency parameters λ = ω a²√(ρe/D) (a = `size[0]`) of the plate of `size` clamped at
/// the ends `x_ends` of x and `y_ends` of y, free elsewhere, from `count` × `count` polynomials,
/// ascending.
pub fn frequency_parameters(
    size: [f64; 2],
    x_ends: Ends,
    y_ends: Ends,
    count: usize,
    poisson_ratio: f64,
) -> Vec<f64> {
    let x = Direction::new(size[0], x_ends, count);
    let y = Direction::new(size[1], y_ends, count);
    let n = count * count;
    // Unknown (i, j) of X_i(x) Y_j(y) at i + count j; ρe = D = 1.
    let index = |i: usize, j: usize| i + count * j;
    let nu = poisson_ratio;
    let mut mass = Mat::<f64>::zeros(n, n);
    let mut stiffness = Mat::<f64>::zeros(n, n);
    for j in 0..count {
        for i in 0..count {
            for l in 0..count {
                for k in 0..count {
                    let (r, c) = (index(i, j), index(k, l));
                    mass[(r, c)] = x.values[(i, k)] * y.values[(j, l)];
                    stiffness[(r, c)] = x.curvatures[(i, k)] * y.values[(j, l)]
                        + x.values[(i, k)] * y.curvatures[(j, l)]
                        + nu * (x.mixed[(i, k)] * y.mixed[(l, j)]
                            + x.mixed[(k, i)] * y.mixed[(j, l)])
                        + 2.0 * (1.0 - nu) * x.slopes[(i, k)] * y.slopes[(j, l)];
                }
            }
        }
    }
    // M = L Lᵀ, then the symmetric C = L⁻¹ K L⁻ᵀ has the eigenvalues ω².
    let llt = mass
        .llt(Side::Lower)
        .expect("the Ritz mass matrix is positive definite");
    let mut c = stiffness;
    solve_lower_triangular_in_place(llt.L(), c.as_mut(), Par::Seq);
    let mut c = c.transpose().to_owned();
    solve_lower_triangular_in_place(llt.L(), c.as_mut(), Par::Seq);
    let c = Mat::from_fn(n, n, |i, j| 0.5 * (c[(i, j)] + c[(j, i)]));
    let omega_squared = c
        .self_adjoint_eigenvalues(Side::Lower)
        .expect("a symmetric eigenproblem");
    omega_squared
        .iter()
        .map(|w2| w2.sqrt() * size[0] * size[0])
        .collect()
}
