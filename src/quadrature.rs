//! Quadrature rules on the reference triangle T̂ = {(ξ, η) : ξ, η ≥ 0, ξ + η ≤ 1}.
//!
//! The rules are collapsed (Duffy) tensor products of Gauss–Legendre rules: with ξ = s(1 − t),
//! η = s·t the Jacobian is s, so a polynomial of total degree d in (ξ, η) becomes a polynomial of
//! degree ≤ d + 1 in s and ≤ d in t. An n-point Gauss–Legendre rule is exact to degree 2n − 1, hence
//! n = ⌈(d + 2)/2⌉ points per direction make the rule exact for total degree d. These rules have
//! positive weights and interior points, and any degree is available, which is all the plate
//! elements need (degree 10 for the Argyris mass, 6 for its stiffness).

/// One quadrature point: position and weight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadPoint {
    /// Coordinates (reference or physical, depending on the rule's owner).
    pub point: [f64; 2],
    /// Weight; the weights of a rule sum to the area of its domain.
    pub weight: f64,
}

/// Gauss–Legendre nodes and weights on [0, 1], exact for polynomials of degree 2n − 1.
///
/// Nodes are the roots of the Legendre polynomial P_n, found by Newton's method from the
/// Chebyshev-like guess cos(π(i − ¼)/(n + ½)); weights w_i = 2 / ((1 − x_i²) P'_n(x_i)²), then mapped
/// from [−1, 1] to [0, 1].
pub fn gauss_legendre_unit(n: usize) -> Vec<(f64, f64)> {
    assert!(n >= 1, "a Gauss–Legendre rule needs at least one point");
    let mut rule = Vec::with_capacity(n);
    for i in 0..n {
        let mut x = libm::cos(std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5));
        let mut derivative = 0.0;
        for _ in 0..100 {
            // Three-term recurrence for P_n(x) and its derivative.
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            let pn = if n == 1 { x } else { p1 };
            let pn_minus_1 = if n == 1 { 1.0 } else { p0 };
            derivative = n as f64 * (x * pn - pn_minus_1) / (x * x - 1.0);
            let dx = pn / derivative;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        let weight = 2.0 / ((1.0 - x * x) * derivative * derivative);
        rule.push((0.5 * (1.0 + x), 0.5 * weight));
    }
    rule
}

/// A rule on the reference triangle exact for every polynomial of total degree ≤ `degree`.
/// The weights sum to ½, the area of T̂.
pub fn reference_triangle(degree: usize) -> Vec<QuadPoint> {
    let n = degree.div_ceil(2) + 1;
    let line = gauss_legendre_unit(n);
    let mut rule = Vec::with_capacity(n * n);
    for &(s, ws) in &line {
        for &(t, wt) in &line {
            rule.push(QuadPoint {
                point: [s * (1.0 - t), s * t],
                weight: ws * wt * s,
            });
        }
    }
    rule
}

/// The reference rule of [`reference_triangle`] mapped affinely onto the triangle with vertices
/// `a`, `b`, `c` (any orientation): x = a + ξ(b − a) + η(c − a), weights scaled by |det J|.
pub fn triangle(a: [f64; 2], b: [f64; 2], c: [f64; 2], degree: usize) -> Vec<QuadPoint> {
    let j = [[b[0] - a[0], c[0] - a[0]], [b[1] - a[1], c[1] - a[1]]];
    let det = (j[0][0] * j[1][1] - j[0][1] * j[1][0]).abs();
    reference_triangle(degree)
        .into_iter()
        .map(|q| QuadPoint {
            point: [
                a[0] + j[0][0] * q.point[0] + j[0][1] * q.point[1],
                a[1] + j[1][0] * q.point[0] + j[1][1] * q.point[1],
            ],
            weight: q.weight * det,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫_T̂ ξ^p η^q = p! q! / (p + q + 2)!
    fn exact_monomial(p: u32, q: u32) -> f64 {
        let fact = |k: u32| (1..=k).map(f64::from).product::<f64>();
        fact(p) * fact(q) / fact(p + q + 2)
    }

    #[test]
    fn triangle_rules_are_exact_to_their_degree() {
        for degree in 0..=12 {
            let rule = reference_triangle(degree);
            for p in 0..=degree as u32 {
                for q in 0..=(degree as u32 - p) {
                    let sum: f64 = rule
                        .iter()
                        .map(|r| r.weight * r.point[0].powi(p as i32) * r.point[1].powi(q as i32))
                        .sum();
                    let exact = exact_monomial(p, q);
                    // Round-off of a sum of ≤ 49 positive terms: a few ulps relative.
                    assert!(
                        (sum - exact).abs() <= 1e-14 * exact.max(1e-3),
                        "degree {degree}, monomial ({p},{q}): {sum} vs {exact}"
                    );
                }
            }
        }
    }

    #[test]
    fn mapped_rule_integrates_area_and_first_moment() {
        let (a, b, c) = ([0.1, 0.2], [0.5, 0.25], [0.2, 0.9]);
        let rule = triangle(a, c, b, 3);
        let area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])).abs();
        let total: f64 = rule.iter().map(|q| q.weight).sum();
        let mx: f64 = rule.iter().map(|q| q.weight * q.point[0]).sum();
        assert!((total - area).abs() < 1e-15);
        assert!((mx / area - (a[0] + b[0] + c[0]) / 3.0).abs() < 1e-15);
    }
}
