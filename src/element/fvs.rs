//! The reduced Fraeijs de Veubeke–Sanders (FVS) quadrilateral (`docs/elements.md` §4): a C¹
//! composite macro-element with 12 dofs.
//!
//! The convex quadrilateral P₀P₁P₂P₃ is split by its two diagonals into the four sub-triangles
//! Tᵢ = (C, Pᵢ, Pᵢ₊₁), where C is the intersection of the diagonals. The space is
//!
//! V = { w : w|Tᵢ ∈ P₃, w ∈ C¹(quad), ∂ₙw linear along every outer edge PᵢPᵢ₊₁ },
//!
//! whose dimension is 12, with unisolvent dofs (w, w_x, w_y) at the four vertices (Fraeijs de
//! Veubeke, "A conforming finite element for plate bending", Int. J. Solids Struct. 4 (1968);
//! Ciarlet, *The Finite Element Method for Elliptic Problems*, ch. 6, on composite C¹ elements).
//!
//! Construction: per element, in physical coordinates scaled about the centre, ξ = (x − C)/s with
//! s = maxₖ |Pₖ − C|, each basis function is four cubics (40 coefficients) fixed by 44 linear
//! conditions:
//! * 12 dofs: at vertex Pₖ, on piece Tₖ, the value and h ∂ₓw, h ∂ᵧw;
//! * 28 on the half-diagonals C→Pₖ (shared by Tₖ₋₁ and Tₖ): the jump of the two cubics vanishes at 4
//!   points (C⁰, the jump is cubic along the segment) and the jump of its normal derivative at 3
//!   points (C¹, that jump is quadratic);
//! * 4 on the outer edges: ∂ₜ∂ₜ∂ₙw = 0 on Tᵢ (a constant for a cubic), i.e. ∂ₙw is linear.
//!
//! The conditions are consistent but only of rank 40: the jumps around the interior vertex C
//! satisfy 4 identities. The system is therefore solved in the least-squares sense (Householder
//! QR), after checking that its columns are independent (so the 12 dofs determine the function)
//! and, afterwards, that the residual is at round-off level (so every condition holds).
//!
//! Along an outer edge a function of V is a cubic fixed by the end values and tangential
//! derivatives and has a linear normal derivative fixed by the end normal derivatives: two cells
//! sharing an edge therefore agree in value and gradient along it, and the assembled space is C¹.
//!
//! Approximation: V contains P₂, but not P₃ — a general cubic has a quadratic normal derivative
//! along the edges. (On an axis-parallel rectangle V also contains x³ and y³, as the tests check;
//! with four different edge directions the four conditions generically exclude every cubic.) The
//! interpolation error is therefore O(h) in the H² seminorm (energy) and the eigenvalues converge
//! like O(h²) (`tests/modes.rs`); the full 16-dof FVS element, which adds the edge-midpoint normal
//! derivatives, contains P₃.

use super::{CellBasis, Jet};
use crate::quadrature::{self, QuadPoint};
use faer::linalg::solvers::SolveLstsqCore;
use faer::Mat;

/// Number of local dofs: (w, h w_x, h w_y) at each of the four vertices.
const DOFS: usize = 12;
/// Monomials ξᵃηᵇ with a + b ≤ 3, in this order.
const EXPONENTS: [(u32, u32); 10] = [
    (0, 0),
    (1, 0),
    (0, 1),
    (2, 0),
    (1, 1),
    (0, 2),
    (3, 0),
    (2, 1),
    (1, 2),
    (0, 3),
];
const MONOMIALS: usize = EXPONENTS.len();
/// Unknowns: 10 coefficients on each of the 4 pieces.
const UNKNOWNS: usize = 4 * MONOMIALS;
/// Largest acceptable residual of the least-squares solve, relative to the size of the solution:
/// the conditions are consistent, so anything above round-off means a construction error.
const RESIDUAL_TOLERANCE: f64 = 1e-10;
/// Smallest acceptable σ_min/σ_max of the 44 × 40 condition matrix. Measured: 3e-3 to 4e-3 for
/// rectangles, 3e-4 for a quad skewed at aspect 2, far above round-off; only a nearly degenerate
/// quad falls below this.
const RANK_TOLERANCE: f64 = 1e-9;

/// The reduced FVS basis on one physical convex quadrilateral.
///
/// Local dofs (module `element` docs): for vertex k = 0…3 the dofs 3k, 3k+1, 3k+2 are
/// (w, h w_x, h w_y) at Pₖ, where h is the global dof scaling length.
#[derive(Clone, Debug)]
pub struct FvsCell {
    vertices: [[f64; 2]; 4],
    centre: [f64; 2],
    /// Scaling length s of the local coordinates ξ = (x − C)/s.
    scale: f64,
    /// Global dof scaling length h.
    h: f64,
    /// `coefficients[i][j]`: the cubic of basis function j on piece Tᵢ, in the monomials of ξ.
    coefficients: [[[f64; MONOMIALS]; DOFS]; 4],
    /// Relative residual of the least-squares construction (round-off level).
    residual: f64,
    /// σ_min/σ_max of the condition matrix.
    rank_ratio: f64,
}

impl FvsCell {
    /// Builds the 12 basis functions on the quadrilateral with counter-clockwise `vertices`,
    /// with derivative dofs scaled by `h` (see the module docs for the construction).
    ///
    /// # Panics
    /// If the quadrilateral is not strictly convex and counter-clockwise, if `h` is not positive
    /// and finite, or if the construction fails its rank or residual check (programming errors or
    /// a degenerate cell, not user input).
    pub fn new(vertices: [[f64; 2]; 4], h: f64) -> FvsCell {
        assert!(
            h.is_finite() && h > 0.0,
            "dof scaling length h = {h} must be positive"
        );
        for k in 0..4 {
            let (a, b, c) = (vertices[k], vertices[(k + 1) % 4], vertices[(k + 2) % 4]);
            let turn = cross(sub(b, a), sub(c, b));
            let size = norm(sub(b, a)) * norm(sub(c, b));
            assert!(
                turn > 1e-12 * size,
                "quadrilateral {vertices:?} is not strictly convex and counter-clockwise"
            );
        }
        let centre = diagonal_intersection(&vertices);
        let scale = vertices
            .iter()
            .map(|&p| norm(sub(p, centre)))
            .fold(0.0, f64::max);
        let local = vertices.map(|p| [(p[0] - centre[0]) / scale, (p[1] - centre[1]) / scale]);

        let (a, b) = condition_system(&local, h / scale);
        let sigma = a
            .singular_values()
            .expect("the SVD of a 44 × 40 matrix converges");
        let rank_ratio = sigma[UNKNOWNS - 1] / sigma[0];
        assert!(
            rank_ratio > RANK_TOLERANCE,
            "FVS conditions on {vertices:?} are rank deficient (σ_min/σ_max = {rank_ratio:e}): \
             the 12 dofs do not determine the function"
        );

        let mut x = b.clone();
        a.qr()
            .solve_lstsq_in_place_with_conj(faer::Conj::No, x.as_mut());
        let x = x.subrows(0, UNKNOWNS).to_owned();
        let r = &a * &x - &b;
        let max_abs = |m: faer::MatRef<'_, f64>| {
            let mut v = 0.0f64;
            for j in 0..m.ncols() {
                for i in 0..m.nrows() {
                    v = v.max(m[(i, j)].abs());
                }
            }
            v
        };
        let residual = max_abs(r.as_ref()) / (max_abs(a.as_ref()) * max_abs(x.as_ref())).max(1.0);
        assert!(
            residual < RESIDUAL_TOLERANCE,
            "FVS conditions on {vertices:?} are not satisfied: relative residual {residual:e}"
        );

        let mut coefficients = [[[0.0; MONOMIALS]; DOFS]; 4];
        for (i, piece) in coefficients.iter_mut().enumerate() {
            for (j, basis) in piece.iter_mut().enumerate() {
                for (m, c) in basis.iter_mut().enumerate() {
                    *c = x[(MONOMIALS * i + m, j)];
                }
            }
        }
        FvsCell {
            vertices,
            centre,
            scale,
            h,
            coefficients,
            residual,
            rank_ratio,
        }
    }

    /// The vertices P₀…P₃, counter-clockwise.
    pub fn vertices(&self) -> [[f64; 2]; 4] {
        self.vertices
    }

    /// The intersection C of the diagonals P₀P₂ and P₁P₃, the common vertex of the sub-triangles.
    pub fn centre(&self) -> [f64; 2] {
        self.centre
    }

    /// The sub-triangle Tᵢ = (C, Pᵢ, Pᵢ₊₁), counter-clockwise.
    pub fn sub_triangle(&self, i: usize) -> [[f64; 2]; 3] {
        [self.centre, self.vertices[i], self.vertices[(i + 1) % 4]]
    }

    /// The index i of the sub-triangle Tᵢ that contains `p`: the one whose smallest barycentric
    /// coordinate of `p` is largest (robust for points on a diagonal or slightly outside).
    pub fn piece_containing(&self, p: [f64; 2]) -> usize {
        let mut best = (0, f64::NEG_INFINITY);
        for i in 0..4 {
            let [c, a, b] = self.sub_triangle(i);
            let area = cross(sub(a, c), sub(b, c));
            let l_a = cross(sub(p, c), sub(b, c)) / area;
            let l_b = cross(sub(a, c), sub(p, c)) / area;
            let least = l_a.min(l_b).min(1.0 - l_a - l_b);
            if least > best.1 {
                best = (i, least);
            }
        }
        best.0
    }

    /// Value, gradient and Hessian of every basis function at `p`, taken from the cubic of piece
    /// Tᵢ (`piece` = i), whether or not `p` lies in Tᵢ. [`CellBasis::eval`] is this with the piece
    /// that contains `p`; calling it directly gives one-sided values on a diagonal.
    pub fn eval_on_piece(&self, piece: usize, p: [f64; 2], out: &mut [Jet]) {
        assert_eq!(out.len(), DOFS, "the FVS cell has {DOFS} basis functions");
        let q = [
            (p[0] - self.centre[0]) / self.scale,
            (p[1] - self.centre[1]) / self.scale,
        ];
        let rows = [
            monomial_derivatives(q, 0, 0),
            monomial_derivatives(q, 1, 0),
            monomial_derivatives(q, 0, 1),
            monomial_derivatives(q, 2, 0),
            monomial_derivatives(q, 1, 1),
            monomial_derivatives(q, 0, 2),
        ];
        let (s1, s2) = (1.0 / self.scale, 1.0 / (self.scale * self.scale));
        for (jet, c) in out.iter_mut().zip(&self.coefficients[piece]) {
            let d = rows.map(|row| dot(&row, c));
            *jet = Jet {
                value: d[0],
                grad: [s1 * d[1], s1 * d[2]],
                hess: [s2 * d[3], s2 * d[4], s2 * d[5]],
            };
        }
    }

    /// Relative residual of the least-squares construction and σ_min/σ_max of its 44 × 40 matrix
    /// (diagnostics: round-off level, and well away from zero).
    pub fn construction_quality(&self) -> (f64, f64) {
        (self.residual, self.rank_ratio)
    }
}

impl CellBasis for FvsCell {
    fn dof_count(&self) -> usize {
        DOFS
    }

    fn eval(&self, p: [f64; 2], out: &mut [Jet]) {
        self.eval_on_piece(self.piece_containing(p), p, out);
    }

    fn interpolate(&self, field: &dyn Fn([f64; 2]) -> Jet) -> Vec<f64> {
        self.vertices
            .iter()
            .flat_map(|&p| {
                let jet = field(p);
                [jet.value, self.h * jet.grad[0], self.h * jet.grad[1]]
            })
            .collect()
    }

    fn quadrature(&self, degree: usize) -> Vec<QuadPoint> {
        (0..4)
            .flat_map(|i| {
                let [c, a, b] = self.sub_triangle(i);
                quadrature::triangle(c, a, b, degree)
            })
            .collect()
    }
}

/// The 44 × 40 condition matrix A and the 44 × 12 right-hand sides B (identity in the dof rows)
/// in local coordinates, where `local` are the vertices in ξ and `dof_scale` = h/s converts
/// ∂_ξ into h ∂ₓ.
fn condition_system(local: &[[f64; 2]; 4], dof_scale: f64) -> (Mat<f64>, Mat<f64>) {
    let mut rows: Vec<([f64; UNKNOWNS], Option<usize>)> = Vec::with_capacity(44);
    let on_piece = |piece: usize, row: [f64; MONOMIALS]| {
        let mut full = [0.0; UNKNOWNS];
        full[MONOMIALS * piece..MONOMIALS * (piece + 1)].copy_from_slice(&row);
        full
    };
    let jump = |after: usize, before: usize, row: [f64; MONOMIALS]| {
        let mut full = [0.0; UNKNOWNS];
        for m in 0..MONOMIALS {
            full[MONOMIALS * after + m] = row[m];
            full[MONOMIALS * before + m] = -row[m];
        }
        full
    };
    // Vertex dofs, imposed on piece Tₖ (Tₖ₋₁ follows by continuity along C→Pₖ).
    for (k, &p) in local.iter().enumerate() {
        rows.push((on_piece(k, monomial_derivatives(p, 0, 0)), Some(3 * k)));
        let dx = monomial_derivatives(p, 1, 0).map(|v| dof_scale * v);
        let dy = monomial_derivatives(p, 0, 1).map(|v| dof_scale * v);
        rows.push((on_piece(k, dx), Some(3 * k + 1)));
        rows.push((on_piece(k, dy), Some(3 * k + 2)));
    }
    // C⁰ and C¹ across the half-diagonal C→Pₖ between Tₖ₋₁ and Tₖ (C is the origin of ξ).
    for (k, &p) in local.iter().enumerate() {
        let before = (k + 3) % 4;
        let length = norm(p);
        let normal = [-p[1] / length, p[0] / length];
        for t in [0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0] {
            rows.push((jump(k, before, directional(scale(p, t), &[])), None));
        }
        for t in [0.0, 0.5, 1.0] {
            rows.push((jump(k, before, directional(scale(p, t), &[normal])), None));
        }
    }
    // ∂ₜ∂ₜ∂ₙw = 0 on each outer edge PᵢPᵢ₊₁ of Tᵢ.
    for (i, &a) in local.iter().enumerate() {
        let b = local[(i + 1) % 4];
        let e = sub(b, a);
        let length = norm(e);
        let tangent = [e[0] / length, e[1] / length];
        let normal = [tangent[1], -tangent[0]];
        let mid = scale([a[0] + b[0], a[1] + b[1]], 0.5);
        rows.push((
            on_piece(i, directional(mid, &[tangent, tangent, normal])),
            None,
        ));
    }
    let a = Mat::from_fn(rows.len(), UNKNOWNS, |r, c| rows[r].0[c]);
    let b = Mat::from_fn(rows.len(), DOFS, |r, j| {
        if rows[r].1 == Some(j) {
            1.0
        } else {
            0.0
        }
    });
    (a, b)
}

/// ∂ξ^dx ∂η^dy of every monomial ξᵃηᵇ at q.
fn monomial_derivatives(q: [f64; 2], dx: u32, dy: u32) -> [f64; MONOMIALS] {
    EXPONENTS.map(|(a, b)| {
        if a < dx || b < dy {
            return 0.0;
        }
        let falling = |n: u32, k: u32| (n - k + 1..=n).map(f64::from).product::<f64>();
        falling(a, dx) * falling(b, dy) * q[0].powi((a - dx) as i32) * q[1].powi((b - dy) as i32)
    })
}

/// The derivative of every monomial along the given directions, in turn, at q: multilinear
/// expansion ∂_{d₁}…∂_{d_m} = Σ over (i₁…i_m) ∈ {ξ, η}^m of d₁[i₁]…d_m[i_m] ∂_{i₁}…∂_{i_m}.
fn directional(q: [f64; 2], dirs: &[[f64; 2]]) -> [f64; MONOMIALS] {
    let mut out = [0.0; MONOMIALS];
    for choice in 0..1u32 << dirs.len() {
        let mut weight = 1.0;
        let mut dy = 0;
        for (bit, d) in dirs.iter().enumerate() {
            let axis = ((choice >> bit) & 1) as usize;
            weight *= d[axis];
            dy += axis as u32;
        }
        let d = monomial_derivatives(q, dirs.len() as u32 - dy, dy);
        for (o, v) in out.iter_mut().zip(d) {
            *o += weight * v;
        }
    }
    out
}

/// Intersection of the diagonals P₀P₂ and P₁P₃: P₀ + s(P₂ − P₀) = P₁ + t(P₃ − P₁), 0 < s, t < 1
/// for a strictly convex quadrilateral.
fn diagonal_intersection(v: &[[f64; 2]; 4]) -> [f64; 2] {
    let (d0, d1) = (sub(v[2], v[0]), sub(v[3], v[1]));
    let r = sub(v[1], v[0]);
    // Cramer's rule on s d0 − t d1 = r.
    let s = cross(r, d1) / cross(d0, d1);
    [v[0][0] + s * d0[0], v[0][1] + s * d0[1]]
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

fn scale(a: [f64; 2], t: f64) -> [f64; 2] {
    [t * a[0], t * a[1]]
}

fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

fn norm(a: [f64; 2]) -> f64 {
    libm::hypot(a[0], a[1])
}

fn dot(a: &[f64; MONOMIALS], b: &[f64; MONOMIALS]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
