//! The Argyris triangle: the quintic C¹ plate element of Argyris, Fried & Scharpf ("The TUBA family
//! of plate elements for the matrix displacement method", Aeronautical Journal 72, 1968), see also
//! Ciarlet, *The Finite Element Method for Elliptic Problems* (1978), §2.2 and §6.1.
//!
//! The space is P5 on the triangle (21 coefficients). Its 21 dofs, in the order and with the scaling
//! of the [module docs](super), are the value, the two first and three second derivatives at each
//! vertex, and the normal derivative at each edge midpoint. The normal of an edge is oriented by the
//! *global* ids of its end vertices, so the two cells sharing an edge use the same dof: the
//! assembled space is then C¹ (along an edge, w is the quintic fixed by the value and the first two
//! tangential derivatives at both ends, and ∂ₙw is the quartic fixed by ∂ₙw and ∂ₜ∂ₙw at both ends
//! plus ∂ₙw at the midpoint).
//!
//! Construction. Rather than mapping a reference basis (the transformation of Domínguez & Sayas,
//! ACM TOMS 35(2), 2008, and Kirby, SMAI J. Comput. Math. 4, 2018), the basis is built directly in
//! physical coordinates, which is as exact and makes the edge orientation explicit: with the
//! monomials m_j(ξ, η) = ξ^a η^b (a + b ≤ 5) of the local coordinates ξ = (x − x_c)/s,
//! η = (y − y_c)/s (x_c the centroid, s the longest edge of the cell), form the 21 × 21 matrix
//! A_ij = L_i(m_j) of the dofs L_i applied to the monomials; the basis function φ_k = Σ_j C_jk m_j
//! satisfies L_i(φ_k) = δ_ik, i.e. C = A⁻¹. Both scalings (dofs by the global `h`, monomials by the
//! cell size `s`) keep A well conditioned: cond₁(A) ≈ 3e3–2e4 on shape-regular cells (the
//! structured cells of `docs/elements.md` §1 included), growing with the aspect ratio (≈ 1e6 at
//! aspect 7).

use super::{CellBasis, Jet};
use crate::quadrature::{self, QuadPoint};

/// Number of dofs, and of monomials of P5.
const N: usize = 21;

/// Exponents (a, b) of the monomials ξ^a η^b of P5, by total degree then decreasing power of ξ.
const EXPONENTS: [(usize, usize); N] = {
    let mut e = [(0, 0); N];
    let mut idx = 0;
    let mut d = 0;
    while d <= 5 {
        let mut b = 0;
        while b <= d {
            e[idx] = (d - b, b);
            idx += 1;
            b += 1;
        }
        d += 1;
    }
    e
};

/// The Argyris basis of one physical triangle (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct ArgyrisCell {
    /// Vertex coordinates, counter-clockwise.
    vertices: [[f64; 2]; 3],
    /// Unit normal of the edge from local vertex k to k + 1, oriented by the global vertex ids.
    normals: [[f64; 2]; 3],
    /// Global dof length scale.
    h: f64,
    /// Centroid: the origin of the local coordinates.
    centre: [f64; 2],
    /// Length scale of the local coordinates (longest edge).
    s: f64,
    /// `coef[k][j]`: coefficient of monomial j in basis function k (the transpose of C = A⁻¹).
    coef: [[f64; N]; N],
}

impl ArgyrisCell {
    /// The basis of the triangle with counter-clockwise `vertices`, whose global vertex ids are
    /// `global_ids` (they orient the edges: tangent from the lower to the higher id, normal
    /// n = (t_y, −t_x)), with derivative dofs scaled by the global length `h`.
    ///
    /// # Panics
    /// If the triangle is not counter-clockwise with positive area, two global ids coincide, or
    /// `h` is not positive and finite (programming errors, not user input).
    pub fn new(vertices: [[f64; 2]; 3], global_ids: [usize; 3], h: f64) -> ArgyrisCell {
        let [p0, p1, p2] = vertices;
        let area2 = (p1[0] - p0[0]) * (p2[1] - p0[1]) - (p2[0] - p0[0]) * (p1[1] - p0[1]);
        assert!(
            area2 > 0.0,
            "triangle {vertices:?} is not counter-clockwise"
        );
        assert!(
            global_ids[0] != global_ids[1]
                && global_ids[1] != global_ids[2]
                && global_ids[0] != global_ids[2],
            "global ids {global_ids:?} are not distinct"
        );
        assert!(
            h.is_finite() && h > 0.0,
            "dof scale h = {h} is not positive"
        );
        let mut normals = [[0.0; 2]; 3];
        let mut s: f64 = 0.0;
        for k in 0..3 {
            let l = (k + 1) % 3;
            let (mut a, mut b) = (vertices[k], vertices[l]);
            if global_ids[k] > global_ids[l] {
                std::mem::swap(&mut a, &mut b);
            }
            let len = libm::hypot(b[0] - a[0], b[1] - a[1]);
            s = s.max(len);
            let t = [(b[0] - a[0]) / len, (b[1] - a[1]) / len];
            normals[k] = [t[1], -t[0]];
        }
        let centre = [(p0[0] + p1[0] + p2[0]) / 3.0, (p0[1] + p1[1] + p2[1]) / 3.0];
        let mut cell = ArgyrisCell {
            vertices,
            normals,
            h,
            centre,
            s,
            coef: [[0.0; N]; N],
        };
        cell.coef = invert(cell.dof_matrix_transposed());
        cell
    }

    /// Aᵀ, with A_ij = L_i(m_j) the dofs of the monomials: row j holds the dofs of monomial j.
    /// The basis coefficients are coef = Cᵀ = (A⁻¹)ᵀ = (Aᵀ)⁻¹.
    fn dof_matrix_transposed(&self) -> [[f64; N]; N] {
        let mut at_points = [[Jet::default(); N]; 6];
        for (jets, &p) in at_points.iter_mut().zip(self.dof_points().iter()) {
            self.monomial_jets(p, jets);
        }
        let mut a_t = [[0.0; N]; N];
        for (j, row) in a_t.iter_mut().enumerate() {
            *row = self.dofs(|q| at_points[q][j]);
        }
        a_t
    }

    /// The points the dofs look at: the three vertices, then the three edge midpoints (edge k from
    /// local vertex k to k + 1).
    fn dof_points(&self) -> [[f64; 2]; 6] {
        let v = self.vertices;
        let mid = |a: [f64; 2], b: [f64; 2]| [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
        [
            v[0],
            v[1],
            v[2],
            mid(v[0], v[1]),
            mid(v[1], v[2]),
            mid(v[2], v[0]),
        ]
    }

    /// The local dofs L_0 … L_20 of a field whose jet at `dof_points()[q]` is `jet(q)` (module
    /// docs for the order and the scaling).
    fn dofs(&self, jet: impl Fn(usize) -> Jet) -> [f64; N] {
        let h = self.h;
        let h2 = h * h;
        let mut out = [0.0; N];
        for k in 0..3 {
            let f = jet(k);
            out[6 * k..6 * k + 6].copy_from_slice(&[
                f.value,
                h * f.grad[0],
                h * f.grad[1],
                h2 * f.hess[0],
                h2 * f.hess[1],
                h2 * f.hess[2],
            ]);
            let m = jet(3 + k);
            let n = self.normals[k];
            out[18 + k] = h * (n[0] * m.grad[0] + n[1] * m.grad[1]);
        }
        out
    }

    /// Jets (physical derivatives) of the 21 monomials m_j at the physical point `p`.
    fn monomial_jets(&self, p: [f64; 2], out: &mut [Jet; N]) {
        let xi = (p[0] - self.centre[0]) / self.s;
        let eta = (p[1] - self.centre[1]) / self.s;
        let mut px = [1.0; 6];
        let mut py = [1.0; 6];
        for i in 1..6 {
            px[i] = px[i - 1] * xi;
            py[i] = py[i - 1] * eta;
        }
        let inv_s = 1.0 / self.s;
        let inv_s2 = inv_s * inv_s;
        // ∂ξ(ξ^a) = a ξ^(a−1); the factors vanish exactly where the lower power is not needed.
        let pow = |v: &[f64; 6], e: usize, d: usize| -> f64 {
            if e < d {
                0.0
            } else {
                let c = match d {
                    0 => 1.0,
                    1 => e as f64,
                    _ => (e * (e - 1)) as f64,
                };
                c * v[e - d]
            }
        };
        for (jet, &(a, b)) in out.iter_mut().zip(EXPONENTS.iter()) {
            *jet = Jet {
                value: px[a] * py[b],
                grad: [
                    inv_s * pow(&px, a, 1) * py[b],
                    inv_s * px[a] * pow(&py, b, 1),
                ],
                hess: [
                    inv_s2 * pow(&px, a, 2) * py[b],
                    inv_s2 * pow(&px, a, 1) * pow(&py, b, 1),
                    inv_s2 * px[a] * pow(&py, b, 2),
                ],
            };
        }
    }
}

impl CellBasis for ArgyrisCell {
    fn dof_count(&self) -> usize {
        N
    }

    /// φ_k(p) = Σ_j C_jk m_j(p), and likewise for its derivatives.
    fn eval(&self, p: [f64; 2], out: &mut [Jet]) {
        assert_eq!(out.len(), N, "the Argyris cell has {N} basis functions");
        let mut m = [Jet::default(); N];
        self.monomial_jets(p, &mut m);
        for (o, c) in out.iter_mut().zip(self.coef.iter()) {
            let mut jet = Jet::default();
            for (cj, mj) in c.iter().zip(m.iter()) {
                jet.value += cj * mj.value;
                jet.grad[0] += cj * mj.grad[0];
                jet.grad[1] += cj * mj.grad[1];
                jet.hess[0] += cj * mj.hess[0];
                jet.hess[1] += cj * mj.hess[1];
                jet.hess[2] += cj * mj.hess[2];
            }
            *o = jet;
        }
    }

    fn interpolate(&self, field: &dyn Fn([f64; 2]) -> Jet) -> Vec<f64> {
        let jets = self.dof_points().map(field);
        self.dofs(|q| jets[q]).to_vec()
    }

    /// The collapsed Gauss rule of [`quadrature::triangle`] on this triangle (P5 is one polynomial
    /// piece: degree 6 for the stiffness, 10 for the mass).
    fn quadrature(&self, degree: usize) -> Vec<QuadPoint> {
        let [a, b, c] = self.vertices;
        quadrature::triangle(a, b, c, degree)
    }
}

/// Inverse of the dense N × N dof matrix, by faer's LU factorisation with partial pivoting.
///
/// # Panics
/// If a pivot of U is below 1e-13 (the entries are O(1) by the scalings of the module docs, so this
/// is a degenerate triangle).
fn invert(a: [[f64; N]; N]) -> [[f64; N]; N] {
    use faer::linalg::solvers::DenseSolveCore;
    let lu = faer::Mat::from_fn(N, N, |i, j| a[i][j]).partial_piv_lu();
    let u = lu.U();
    assert!(
        (0..N).all(|i| u[(i, i)].abs() > 1e-13),
        "singular Argyris dof matrix (degenerate triangle?)"
    );
    let inverse = lu.inverse();
    std::array::from_fn(|i| std::array::from_fn(|j| inverse[(i, j)]))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ‖M‖₁, the largest column sum.
    fn norm1(m: &[[f64; N]; N]) -> f64 {
        (0..N)
            .map(|j| m.iter().map(|row| row[j].abs()).sum::<f64>())
            .fold(0.0, f64::max)
    }

    #[test]
    fn dof_matrix_is_well_conditioned_and_inverted_accurately() {
        let mesh = crate::mesh::Mesh::rectangle_triangles(0.4, 0.2, 10, 7);
        let h = mesh.size();
        let cells = [
            ([[0.12, 0.0], [0.16, 0.0], [0.16, 0.2 / 7.0]], h),
            ([[0.1, 0.2], [0.5, 0.25], [0.2, 0.9]], 0.3),
            ([[0.0, 0.0], [1.0, 0.0], [0.8, 0.15]], 0.5),
        ];
        for (t, h) in cells {
            let cell = ArgyrisCell::new(t, [5, 2, 9], h);
            let a_t = cell.dof_matrix_transposed();
            let cond = norm1(&a_t) * norm1(&cell.coef);
            // The local scalings keep the entries O(1): measured 1.6e4 (structured), 3.2e3
            // (skewed), 1.1e6 (flat, aspect 7); 1e7 flags a lost scaling, far from trouble in f64.
            println!("{t:?}: cond₁ = {cond:e}");
            assert!(cond < 1e7, "cond₁ = {cond:e}");
            // coef · Aᵀ = I up to cond · ε.
            for (i, row) in cell.coef.iter().enumerate() {
                for j in 0..N {
                    let p: f64 = row.iter().zip(&a_t).map(|(c, a)| c * a[j]).sum();
                    let err = (p - if i == j { 1.0 } else { 0.0 }).abs();
                    assert!(err < 1e-16 * cond * 100.0, "({i}, {j}): {err:e}");
                }
            }
        }
    }
}
