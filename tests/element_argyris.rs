//! Argyris triangle: exactness on P5, duality of dofs and basis, C¹ conformity across edges with the
//! global edge orientation, and the bending energy a(u, u) (`docs/elements.md` §3).

use plate_impact::element::argyris::ArgyrisCell;
use plate_impact::element::{CellBasis, Jet};
use plate_impact::mesh::{CellShape, Mesh};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

/// A polynomial of total degree ≤ 5 in the scaled coordinates ((x − o_x)/l, (y − o_y)/l), so that
/// every coefficient matters at the scale of the cell.
struct Poly {
    coef: Vec<((i32, i32), f64)>,
    origin: [f64; 2],
    l: f64,
}

impl Poly {
    fn random(rng: &mut StdRng, degree: i32, origin: [f64; 2], l: f64) -> Poly {
        let mut coef = Vec::new();
        for d in 0..=degree {
            for b in 0..=d {
                coef.push(((d - b, b), rng.random_range(-1.0..1.0)));
            }
        }
        Poly { coef, origin, l }
    }

    fn jet(&self, p: [f64; 2]) -> Jet {
        let x = (p[0] - self.origin[0]) / self.l;
        let y = (p[1] - self.origin[1]) / self.l;
        let pw = |v: f64, e: i32| if e < 0 { 0.0 } else { v.powi(e) };
        let mut j = Jet::default();
        for &((a, b), c) in &self.coef {
            let (fa, fb) = (a as f64, b as f64);
            j.value += c * pw(x, a) * pw(y, b);
            j.grad[0] += c * fa * pw(x, a - 1) * pw(y, b) / self.l;
            j.grad[1] += c * fb * pw(x, a) * pw(y, b - 1) / self.l;
            j.hess[0] += c * fa * (fa - 1.0) * pw(x, a - 2) * pw(y, b) / (self.l * self.l);
            j.hess[1] += c * fa * fb * pw(x, a - 1) * pw(y, b - 1) / (self.l * self.l);
            j.hess[2] += c * fb * (fb - 1.0) * pw(x, a) * pw(y, b - 2) / (self.l * self.l);
        }
        j
    }
}

fn random_point(rng: &mut StdRng, t: &[[f64; 2]; 3]) -> [f64; 2] {
    let (mut u, mut v): (f64, f64) = (rng.random(), rng.random());
    if u + v > 1.0 {
        (u, v) = (1.0 - u, 1.0 - v);
    }
    [
        t[0][0] + u * (t[1][0] - t[0][0]) + v * (t[2][0] - t[0][0]),
        t[0][1] + u * (t[1][1] - t[0][1]) + v * (t[2][1] - t[0][1]),
    ]
}

fn centroid(t: &[[f64; 2]; 3]) -> [f64; 2] {
    [
        (t[0][0] + t[1][0] + t[2][0]) / 3.0,
        (t[0][1] + t[1][1] + t[2][1]) / 3.0,
    ]
}

fn diameter(t: &[[f64; 2]; 3]) -> f64 {
    (0..3)
        .map(|k| {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            (b[0] - a[0]).hypot(b[1] - a[1])
        })
        .fold(0.0, f64::max)
}

/// Σ_k d_k φ_k(p).
fn combine(cell: &ArgyrisCell, dofs: &[f64], p: [f64; 2]) -> Jet {
    let mut basis = [Jet::default(); 21];
    cell.eval(p, &mut basis);
    let mut j = Jet::default();
    for (d, b) in dofs.iter().zip(basis.iter()) {
        j.value += d * b.value;
        for i in 0..2 {
            j.grad[i] += d * b.grad[i];
        }
        for i in 0..3 {
            j.hess[i] += d * b.hess[i];
        }
    }
    j
}

/// Triangles to test on, each with its global dof scale h: the two triangles of one cell of the
/// paper's 10 × 7 structured mesh (lower-left → upper-right diagonal), a skewed triangle, a
/// flat one, and one far from the origin.
fn shapes() -> Vec<([[f64; 2]; 3], f64)> {
    let mesh = Mesh::rectangle_triangles(0.4, 0.2, 10, 7);
    let h = mesh.size();
    // Cells 2·(i + 10 j) and 2·(i + 10 j) + 1 are the lower and upper triangles of grid cell (i, j).
    let c = 2 * (3 + 10 * 2);
    let tri = |c: usize| {
        let x = mesh.cell_coordinates(c);
        [x[0], x[1], x[2]]
    };
    vec![
        (tri(c), h),
        (tri(c + 1), h),
        ([[0.1, 0.2], [0.5, 0.25], [0.2, 0.9]], 0.3),
        ([[0.0, 0.0], [1.0, 0.0], [0.8, 0.15]], 0.5),
        ([[10.0, -5.0], [10.03, -4.99], [9.995, -4.97]], 0.02),
    ]
}

/// Every assignment of the global ids {3, 8, 20} to the three local vertices: all edge
/// orientations occur.
const ID_ORDERS: [[usize; 3]; 6] = [
    [3, 8, 20],
    [3, 20, 8],
    [8, 3, 20],
    [8, 20, 3],
    [20, 3, 8],
    [20, 8, 3],
];

#[test]
fn interpolation_reproduces_quintics_with_their_derivatives() {
    let mut rng = StdRng::seed_from_u64(1);
    let mut worst: f64 = 0.0;
    for (t, h) in shapes() {
        let l = diameter(&t);
        for ids in ID_ORDERS {
            let cell = ArgyrisCell::new(t, ids, h);
            for _ in 0..4 {
                let poly = Poly::random(&mut rng, 5, centroid(&t), l);
                let dofs = cell.interpolate(&|p| poly.jet(p));
                let points: Vec<_> = (0..20).map(|_| random_point(&mut rng, &t)).collect();
                let exact: Vec<Jet> = points.iter().map(|&p| poly.jet(p)).collect();
                let approx: Vec<Jet> = points.iter().map(|&p| combine(&cell, &dofs, p)).collect();
                // Relative to the largest value, gradient, Hessian of the polynomial on the sample.
                let scale = |f: &dyn Fn(&Jet) -> f64| exact.iter().map(f).fold(0.0, f64::max);
                let sv = scale(&|j| j.value.abs());
                let sg = scale(&|j| j.grad[0].hypot(j.grad[1]));
                let sh = scale(&|j| j.hess.iter().map(|v| v.abs()).fold(0.0, f64::max));
                for (e, a) in exact.iter().zip(&approx) {
                    let ev = (e.value - a.value).abs() / sv;
                    let eg = (e.grad[0] - a.grad[0]).hypot(e.grad[1] - a.grad[1]) / sg;
                    let eh = (0..3)
                        .map(|i| (e.hess[i] - a.hess[i]).abs())
                        .fold(0.0, f64::max)
                        / sh;
                    worst = worst.max(ev).max(eg).max(eh);
                    // Round-off of the basis (cond₁ of the dof matrix 3e3–2e4 here, 1e6 on the flat
                    // triangle) times 21-term sums of O(1) terms: measured worst 8e-13 over all
                    // shapes; 1e-10 keeps a margin while an error in any dof is O(1).
                    assert!(
                        ev <= 1e-10 && eg <= 1e-10 && eh <= 1e-10,
                        "triangle {t:?}, ids {ids:?}: relative errors {ev:e}, {eg:e}, {eh:e}"
                    );
                }
            }
        }
    }
    println!("P5 reproduction: worst relative error {worst:e}");
}

#[test]
fn dofs_of_each_basis_function_are_the_unit_vectors() {
    let mut worst: f64 = 0.0;
    for (t, h) in shapes() {
        for ids in ID_ORDERS {
            let cell = ArgyrisCell::new(t, ids, h);
            for k in 0..21 {
                let dofs = cell.interpolate(&|p| {
                    let mut b = [Jet::default(); 21];
                    cell.eval(p, &mut b);
                    b[k]
                });
                for (i, d) in dofs.iter().enumerate() {
                    let err = (d - if i == k { 1.0 } else { 0.0 }).abs();
                    worst = worst.max(err);
                    // Scaled dofs of a scaled basis are O(1): round-off level, with margin.
                    assert!(err <= 1e-10, "{t:?} {ids:?}: L_{i}(φ_{k}) off by {err:e}");
                }
            }
        }
    }
    println!("duality: worst deviation {worst:e}");
}

/// Random global dofs (6 per vertex, then 1 per edge) on `mesh`; checks that on every interior edge
/// the two cells' functions have the same value and gradient at several points. Returns the worst
/// relative mismatch of the value and of h ∂ₙw.
fn check_c1(mesh: &Mesh, h: f64, rng: &mut StdRng) -> (f64, f64) {
    let nv = mesh.vertices.len();
    let global: Vec<f64> = (0..6 * nv + mesh.edges.len())
        .map(|_| rng.random_range(-1.0..1.0))
        .collect();
    let cells: Vec<(ArgyrisCell, Vec<f64>)> = (0..mesh.cells.len())
        .map(|c| {
            let v = &mesh.cells[c];
            let x = mesh.cell_coordinates(c);
            let cell = ArgyrisCell::new([x[0], x[1], x[2]], [v[0], v[1], v[2]], h);
            let mut local = Vec::with_capacity(21);
            for &vk in v {
                local.extend_from_slice(&global[6 * vk..6 * vk + 6]);
            }
            for &e in &mesh.cell_edges[c] {
                local.push(global[6 * nv + e]);
            }
            (cell, local)
        })
        .collect();
    let mut owners = vec![Vec::new(); mesh.edges.len()];
    for (c, edges) in mesh.cell_edges.iter().enumerate() {
        for &e in edges {
            owners[e].push(c);
        }
    }
    let (mut scale_v, mut scale_n, mut err_v, mut err_n) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let mut interior = 0;
    for (e, own) in owners.iter().enumerate() {
        if own.len() != 2 {
            continue;
        }
        interior += 1;
        let [a, b] = mesh.edges[e].map(|v| mesh.vertices[v]);
        let len = (b[0] - a[0]).hypot(b[1] - a[1]);
        let n = [(b[1] - a[1]) / len, -(b[0] - a[0]) / len];
        for s in [0.0, 0.13, 0.3, 0.5, 0.71, 0.9, 1.0] {
            let p = [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])];
            let [j0, j1] = [0, 1].map(|i| {
                let (cell, d) = &cells[own[i]];
                combine(cell, d, p)
            });
            let dn = |j: &Jet| h * (n[0] * j.grad[0] + n[1] * j.grad[1]);
            scale_v = scale_v.max(j0.value.abs());
            scale_n = scale_n.max(dn(&j0).abs());
            err_v = err_v.max((j0.value - j1.value).abs());
            err_n = err_n.max((dn(&j0) - dn(&j1)).abs());
        }
    }
    assert!(interior > 0, "no interior edge");
    (err_v / scale_v, err_n / scale_n)
}

// The tolerance of the C¹ checks: both sides are 21-term sums of O(1) scaled dofs times O(1)
// scaled basis functions built from a dof matrix with cond₁ ≈ 3e3–2e4, so a mismatch that is not
// a bug is ~1e-14 (measured); a wrong orientation (element-local normals) gives O(1).
const C1_TOL: f64 = 1e-10;

#[test]
fn two_triangles_sharing_an_edge_are_c1() {
    let mut rng = StdRng::seed_from_u64(2);
    // Quadrilateral P0 P1 P3 P2 cut along P1–P2; ids chosen so the shared edge runs against one
    // of the cells' local orders, and permuted to cover the other orientations.
    let points = [[0.0, 0.0], [1.0, 0.1], [0.3, 0.8], [1.2, 0.9]];
    for perm in [[0, 1, 2, 3], [3, 2, 1, 0], [1, 3, 0, 2], [2, 0, 3, 1]] {
        // Vertex perm[i] of the list gets the coordinates of point i.
        let mut vertices = vec![[0.0; 2]; 4];
        for (i, &g) in perm.iter().enumerate() {
            vertices[g] = points[i];
        }
        let cells = vec![
            vec![perm[0], perm[1], perm[2]],
            vec![perm[1], perm[3], perm[2]],
        ];
        let mesh = Mesh::new(vertices, CellShape::Triangle, cells);
        let (ev, en) = check_c1(&mesh, 0.7, &mut rng);
        println!("pair {perm:?}: value {ev:e}, normal derivative {en:e}");
        assert!(ev <= C1_TOL && en <= C1_TOL, "ids {perm:?}: {ev:e}, {en:e}");
    }
}

#[test]
fn structured_and_perturbed_meshes_are_c1() {
    let mut rng = StdRng::seed_from_u64(3);
    let mesh = Mesh::rectangle_triangles(0.4, 0.2, 5, 3);
    let (ev, en) = check_c1(&mesh, mesh.size(), &mut rng);
    println!("structured 5 × 3: value {ev:e}, normal derivative {en:e}");
    assert!(ev <= C1_TOL && en <= C1_TOL, "structured: {ev:e}, {en:e}");

    // The same topology with interior vertices moved: cells no longer congruent.
    let mut vertices = mesh.vertices.clone();
    for v in vertices.iter_mut() {
        if v[0] > 0.0 && v[0] < 0.4 && v[1] > 0.0 && v[1] < 0.2 {
            v[0] += rng.random_range(-0.012..0.012);
            v[1] += rng.random_range(-0.012..0.012);
        }
    }
    let perturbed = Mesh::new(vertices, CellShape::Triangle, mesh.cells.clone());
    let (ev, en) = check_c1(&perturbed, perturbed.size(), &mut rng);
    println!("perturbed 5 × 3: value {ev:e}, normal derivative {en:e}");
    assert!(ev <= C1_TOL && en <= C1_TOL, "perturbed: {ev:e}, {en:e}");
}

const D: f64 = 19_230.8;
const NU: f64 = 0.3;

/// The bending energy density of `docs/model.md` §3 for the Hessian [w_xx, w_xy, w_yy] pair (w, v):
/// D [(1 − ν)(w_xx v_xx + 2 w_xy v_xy + w_yy v_yy) + ν Δw Δv].
fn density(hw: [f64; 3], hv: [f64; 3]) -> f64 {
    D * ((1.0 - NU) * (hw[0] * hv[0] + 2.0 * hw[1] * hv[1] + hw[2] * hv[2])
        + NU * (hw[0] + hw[2]) * (hv[0] + hv[2]))
}

/// Two ways of computing a(u_h, u_h) for the interpolant u_h of `u`, cell by cell with eval() and
/// the degree-6 rule (the Hessians are P3):
/// * `direct`: ∫ density(H, H) with H = Σ_k d_k ∇²φ_k at each point;
/// * `matrix`: Σ_e d_eᵀ K_e d_e with the element stiffness K_ij = ∫ density(∇²φ_i, ∇²φ_j);
///
/// and, for each, the size of the terms that cancel in it (the scale of its round-off).
struct Energies {
    direct: f64,
    direct_scale: f64,
    matrix: f64,
    matrix_scale: f64,
}

fn bending_energy(mesh: &Mesh, u: &dyn Fn([f64; 2]) -> Jet) -> Energies {
    let h = mesh.size();
    let mut e = Energies {
        direct: 0.0,
        direct_scale: 0.0,
        matrix: 0.0,
        matrix_scale: 0.0,
    };
    let mut b = [Jet::default(); 21];
    for c in 0..mesh.cells.len() {
        let v = &mesh.cells[c];
        let x = mesh.cell_coordinates(c);
        let cell = ArgyrisCell::new([x[0], x[1], x[2]], [v[0], v[1], v[2]], h);
        let d = cell.interpolate(u);
        let mut k = [[0.0; 21]; 21];
        for q in cell.quadrature(6) {
            cell.eval(q.point, &mut b);
            let mut hu = [0.0; 3];
            let mut hu_abs = [0.0; 3];
            for (dk, bk) in d.iter().zip(&b) {
                for i in 0..3 {
                    hu[i] += dk * bk.hess[i];
                    hu_abs[i] += (dk * bk.hess[i]).abs();
                }
            }
            e.direct += q.weight * density(hu, hu);
            e.direct_scale += q.weight * density(hu_abs, hu_abs);
            for i in 0..21 {
                for j in 0..21 {
                    k[i][j] += q.weight * density(b[i].hess, b[j].hess);
                }
            }
        }
        let norm_k = k.iter().flatten().map(|v| v * v).sum::<f64>().sqrt();
        let norm_d2 = d.iter().map(|v| v * v).sum::<f64>();
        for i in 0..21 {
            for j in 0..21 {
                e.matrix += d[i] * k[i][j] * d[j];
            }
        }
        e.matrix_scale += norm_k * norm_d2;
    }
    e
}

fn test_meshes() -> Vec<(Mesh, f64)> {
    let structured = Mesh::rectangle_triangles(0.4, 0.2, 10, 7);
    let skewed = Mesh::new(
        vec![[0.0, 0.0], [1.0, 0.1], [0.3, 0.8], [1.2, 0.9], [0.6, -0.5]],
        CellShape::Triangle,
        vec![vec![0, 1, 2], vec![1, 3, 2], vec![0, 4, 1]],
    );
    let area = |m: &Mesh| {
        (0..m.cells.len())
            .map(|c| {
                let x = m.cell_coordinates(c);
                0.5 * ((x[1][0] - x[0][0]) * (x[2][1] - x[0][1])
                    - (x[2][0] - x[0][0]) * (x[1][1] - x[0][1]))
            })
            .sum::<f64>()
    };
    let (a0, a1) = (area(&structured), area(&skewed));
    vec![(structured, a0), (skewed, a1)]
}

#[test]
fn bending_energy_vanishes_on_affine_fields() {
    for (mesh, _) in test_meshes() {
        for (c0, cx, cy) in [(1.0, 0.0, 0.0), (0.3, 2.0, -3.0), (-1.0, 0.5, 7.0)] {
            let u = move |p: [f64; 2]| Jet {
                value: c0 + cx * p[0] + cy * p[1],
                grad: [cx, cy],
                hess: [0.0; 3],
            };
            let e = bending_energy(&mesh, &u);
            println!(
                "affine ({c0}, {cx}, {cy}): direct {:e} (relative {:e}), matrix {:e} (relative {:e})",
                e.direct,
                e.direct / e.direct_scale,
                e.matrix,
                e.matrix.abs() / e.matrix_scale
            );
            // Exact zero in exact arithmetic. Direct: ≥ 0 and the Hessian is a 21-term sum that
            // cancels, so it is (ε · that sum's size)²: 1e-20 of the squared size is generous.
            // Matrix: 441 products per cell bounded by ‖K_e‖‖d_e‖²; 1e-12 of that bound is a few
            // hundred ulps.
            assert!(
                e.direct <= 1e-20 * e.direct_scale,
                "affine field has energy {:e} (scale {:e})",
                e.direct,
                e.direct_scale
            );
            assert!(
                e.matrix.abs() <= 1e-12 * e.matrix_scale,
                "affine field has dᵀKd = {:e} (scale {:e})",
                e.matrix,
                e.matrix_scale
            );
        }
    }
}

#[test]
fn bending_energy_of_a_quadratic_is_the_closed_form() {
    for (mesh, area) in test_meshes() {
        for (a, b, c) in [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.7, -1.3, 2.1)] {
            // u = a x² + b xy + c y² + x − 2y + 3: u_xx = 2a, u_xy = b, u_yy = 2c, constant, so
            // a(u, u) = D |Ω| [(1 − ν)(4a² + 2b² + 4c²) + ν (2a + 2c)²].
            let u = move |p: [f64; 2]| Jet {
                value: a * p[0] * p[0] + b * p[0] * p[1] + c * p[1] * p[1] + p[0] - 2.0 * p[1]
                    + 3.0,
                grad: [
                    2.0 * a * p[0] + b * p[1] + 1.0,
                    b * p[0] + 2.0 * c * p[1] - 2.0,
                ],
                hess: [2.0 * a, b, 2.0 * c],
            };
            let exact = D
                * area
                * ((1.0 - NU) * (4.0 * a * a + 2.0 * b * b + 4.0 * c * c)
                    + NU * (2.0 * a + 2.0 * c).powi(2));
            let e = bending_energy(&mesh, &u);
            let rel = (e.direct - exact).abs() / exact;
            let rel_matrix = (e.matrix - exact).abs() / exact;
            println!(
                "quadratic ({a}, {b}, {c}): direct relative error {rel:e}, dᵀKd relative error \
                 {rel_matrix:e} (round-off bound {:e})",
                e.matrix_scale / exact * f64::EPSILON
            );
            // P2 ⊂ P5 is reproduced exactly and the rule is exact for the P0 integrand, so only
            // round-off remains: the Hessian of the interpolant is a 21-term sum whose terms are
            // up to ~1e3 times larger than the result on the 10 × 7 mesh (value dofs O(1), basis
            // Hessians O(1/h²)), i.e. ~1e-13 relative.
            assert!(rel <= 1e-10, "quadratic: {} vs {exact} ({rel:e})", e.direct);
            // dᵀKd squares that cancellation (the affine part of u carries no energy but large
            // dofs): the attainable accuracy is ε Σ‖K_e‖‖d_e‖², about 1e-8 relative on 10 × 7.
            assert!(
                (e.matrix - exact).abs() <= 1e-12 * e.matrix_scale,
                "quadratic: dᵀKd = {} vs {exact}",
                e.matrix
            );
        }
    }
}
