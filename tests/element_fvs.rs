//! Properties of the reduced FVS quadrilateral (`docs/elements.md` §4): cubic reproduction, C¹
//! inside the macro-element and between elements, exact per-sub-triangle quadrature, and the
//! bending energy.

// Index loops over the small fixed arrays (vertices, jet components, 12 × 12 matrices) read like
// the formulas they implement.
#![allow(clippy::needless_range_loop)]

use plate_impact::element::fvs::FvsCell;
use plate_impact::element::{CellBasis, Jet};
use plate_impact::mesh::{CellShape, Mesh};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

/// A rectangle like a cell of the 14 × 10 mesh of the 0.4 × 0.2 plate, a unit square away from the
/// origin, a general convex quadrilateral, and a skewed one (aspect about 2). Each with its h.
fn quads() -> Vec<([[f64; 2]; 4], f64)> {
    vec![
        (
            [
                [0.0, 0.0],
                [0.4 / 14.0, 0.0],
                [0.4 / 14.0, 0.02],
                [0.0, 0.02],
            ],
            0.4 / 14.0,
        ),
        ([[1.0, 1.0], [2.0, 1.0], [2.0, 2.0], [1.0, 2.0]], 1.0),
        ([[0.1, 0.0], [1.0, 0.2], [1.3, 0.9], [-0.1, 0.7]], 1.2),
        ([[0.0, 0.0], [2.0, 0.0], [1.2, 0.8], [0.1, 0.9]], 2.0),
    ]
}

/// A cubic c₀ + c₁X + … + c₉Y³ in X = (x − x₀)/L, Y = (y − y₀)/L, with its jet.
struct Cubic {
    c: [f64; 10],
    origin: [f64; 2],
    length: f64,
}

impl Cubic {
    fn random(rng: &mut StdRng, origin: [f64; 2], length: f64) -> Cubic {
        Cubic {
            c: std::array::from_fn(|_| rng.random_range(-1.0..1.0)),
            origin,
            length,
        }
    }

    fn jet(&self, p: [f64; 2]) -> Jet {
        let (l, c) = (self.length, &self.c);
        let x = (p[0] - self.origin[0]) / l;
        let y = (p[1] - self.origin[1]) / l;
        let value = c[0]
            + c[1] * x
            + c[2] * y
            + c[3] * x * x
            + c[4] * x * y
            + c[5] * y * y
            + c[6] * x * x * x
            + c[7] * x * x * y
            + c[8] * x * y * y
            + c[9] * y * y * y;
        let fx = c[1]
            + 2.0 * c[3] * x
            + c[4] * y
            + 3.0 * c[6] * x * x
            + 2.0 * c[7] * x * y
            + c[8] * y * y;
        let fy = c[2]
            + c[4] * x
            + 2.0 * c[5] * y
            + c[7] * x * x
            + 2.0 * c[8] * x * y
            + 3.0 * c[9] * y * y;
        let fxx = 2.0 * c[3] + 6.0 * c[6] * x + 2.0 * c[7] * y;
        let fxy = c[4] + 2.0 * c[7] * x + 2.0 * c[8] * y;
        let fyy = 2.0 * c[5] + 2.0 * c[8] * x + 6.0 * c[9] * y;
        Jet {
            value,
            grad: [fx / l, fy / l],
            hess: [fxx / (l * l), fxy / (l * l), fyy / (l * l)],
        }
    }
}

/// Σ dofs[j] φ_j at p, from `eval` or from one piece.
fn combine(basis: &[Jet], dofs: &[f64]) -> Jet {
    let mut u = Jet::default();
    for (phi, d) in basis.iter().zip(dofs) {
        u.value += d * phi.value;
        for k in 0..2 {
            u.grad[k] += d * phi.grad[k];
        }
        for k in 0..3 {
            u.hess[k] += d * phi.hess[k];
        }
    }
    u
}

fn eval_combination(cell: &FvsCell, dofs: &[f64], p: [f64; 2]) -> Jet {
    let mut basis = vec![Jet::default(); 12];
    cell.eval(p, &mut basis);
    combine(&basis, dofs)
}

fn eval_piece_combination(cell: &FvsCell, piece: usize, dofs: &[f64], p: [f64; 2]) -> Jet {
    let mut basis = vec![Jet::default(); 12];
    cell.eval_on_piece(piece, p, &mut basis);
    combine(&basis, dofs)
}

/// A uniformly random point of sub-triangle `piece`.
fn random_point(rng: &mut StdRng, cell: &FvsCell, piece: usize) -> [f64; 2] {
    let [c, a, b] = cell.sub_triangle(piece);
    let (mut s, mut t): (f64, f64) = (rng.random(), rng.random());
    if s + t > 1.0 {
        (s, t) = (1.0 - s, 1.0 - t);
    }
    [
        c[0] + s * (a[0] - c[0]) + t * (b[0] - c[0]),
        c[1] + s * (a[1] - c[1]) + t * (b[1] - c[1]),
    ]
}

fn lerp(a: [f64; 2], b: [f64; 2], t: f64) -> [f64; 2] {
    [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
}

fn max_abs(values: impl IntoIterator<Item = f64>) -> f64 {
    values.into_iter().fold(0.0, |m, v| m.max(v.abs()))
}

#[test]
fn construction_is_well_posed_and_exact() {
    for (vertices, h) in quads() {
        let cell = FvsCell::new(vertices, h);
        let (residual, rank_ratio) = cell.construction_quality();
        println!("{vertices:?}: residual {residual:.1e}, σ_min/σ_max {rank_ratio:.1e}");
        // The 44 conditions are consistent: the residual is round-off of a 44 × 40 QR solve.
        assert!(residual < 1e-13, "residual {residual:e}");
        // Full column rank with a wide margin: the 12 dofs determine the 40 coefficients.
        assert!(rank_ratio > 1e-4, "σ_min/σ_max {rank_ratio:e}");
    }
}

#[test]
fn basis_is_dual_to_the_dofs() {
    for (vertices, h) in quads() {
        let cell = FvsCell::new(vertices, h);
        for j in 0..12 {
            let phi_j = |p: [f64; 2]| {
                let mut out = vec![Jet::default(); 12];
                cell.eval(p, &mut out);
                out[j]
            };
            let dofs = cell.interpolate(&phi_j);
            for (i, d) in dofs.iter().enumerate() {
                let expected = if i == j { 1.0 } else { 0.0 };
                // Dofs of O(1) basis functions recovered through O(1) coefficients: round-off.
                assert!((d - expected).abs() < 1e-12, "dof {i} of φ_{j} = {d}");
            }
        }
    }
}

/// Interpolates each polynomial on the cell and returns the worst relative errors of value,
/// gradient and Hessian at random points, each relative to the size of that quantity on the cell.
fn reproduction_errors(rng: &mut StdRng, cell: &FvsCell, polys: &[Cubic]) -> [f64; 3] {
    let mut worst = [0.0f64; 3];
    for f in polys {
        let dofs = cell.interpolate(&|p| f.jet(p));
        let points: Vec<[f64; 2]> = (0..40).map(|k| random_point(rng, cell, k % 4)).collect();
        let exact: Vec<Jet> = points.iter().map(|&p| f.jet(p)).collect();
        let scale = [
            max_abs(exact.iter().map(|j| j.value)),
            max_abs(exact.iter().flat_map(|j| j.grad)),
            max_abs(exact.iter().flat_map(|j| j.hess)),
        ];
        for (&p, e) in points.iter().zip(&exact) {
            let u = eval_combination(cell, &dofs, p);
            let err = [
                (u.value - e.value).abs(),
                max_abs((0..2).map(|k| u.grad[k] - e.grad[k])),
                max_abs((0..3).map(|k| u.hess[k] - e.hess[k])),
            ];
            for k in 0..3 {
                worst[k] = worst[k].max(err[k] / scale[k]);
            }
        }
    }
    worst
}

#[test]
fn quadratics_are_reproduced_with_their_derivatives() {
    let mut rng = StdRng::seed_from_u64(1);
    for (vertices, h) in quads() {
        let cell = FvsCell::new(vertices, h);
        let polys: Vec<Cubic> = (0..20)
            .map(|_| {
                let mut f = Cubic::random(&mut rng, vertices[0], h);
                f.c[6..].fill(0.0);
                f
            })
            .collect();
        let worst = reproduction_errors(&mut rng, &cell, &polys);
        println!(
            "{vertices:?}: P2 relative errors {:.1e} {:.1e} {:.1e}",
            worst[0], worst[1], worst[2]
        );
        // P₂ ⊂ V and the interpolant is unique, so only round-off remains (O(1) coefficients in
        // scaled coordinates; the Hessian loses most through the 1/s² factor).
        assert!(worst.iter().all(|&e| e <= 1e-10), "{worst:?}");
    }
}

#[test]
fn cubics_of_the_space_are_reproduced_on_rectangles() {
    // On an axis-parallel rectangle, ∂ₙ of x³ and y³ is constant or zero along every edge, so
    // P₂ + span{x³, y³} ⊂ V. (x²y, xy² have quadratic normal derivatives on two of the edges.)
    let mut rng = StdRng::seed_from_u64(11);
    for (vertices, h) in &quads()[..2] {
        let cell = FvsCell::new(*vertices, *h);
        let polys: Vec<Cubic> = (0..20)
            .map(|_| {
                let mut f = Cubic::random(&mut rng, vertices[0], *h);
                f.c[7] = 0.0;
                f.c[8] = 0.0;
                f
            })
            .collect();
        let worst = reproduction_errors(&mut rng, &cell, &polys);
        println!(
            "{vertices:?}: P2 + x³, y³ relative errors {:.1e} {:.1e} {:.1e}",
            worst[0], worst[1], worst[2]
        );
        // Round-off, as for P₂.
        assert!(worst.iter().all(|&e| e <= 1e-10), "{worst:?}");
    }
}

#[test]
fn general_cubics_keep_their_edge_value_and_get_a_linear_normal_derivative() {
    // A general cubic is NOT in the reduced space (its ∂ₙ is quadratic along the edges), so it is
    // not reproduced; but on each outer edge the interpolant's value is the cubic's (a cubic
    // Hermite trace fixed by the end data) and its ∂ₙ is the linear interpolant of the cubic's ∂ₙ
    // at the two ends. Those are the traces that make the assembled space C¹.
    let mut rng = StdRng::seed_from_u64(12);
    for (vertices, h) in quads() {
        let cell = FvsCell::new(vertices, h);
        let mut worst = [0.0f64; 2];
        let mut interior_error = 0.0f64;
        for _ in 0..20 {
            let f = Cubic::random(&mut rng, vertices[0], h);
            let dofs = cell.interpolate(&|p| f.jet(p));
            let scale = max_abs(vertices.iter().map(|&p| f.jet(p).value));
            let slope = max_abs(vertices.iter().flat_map(|&p| f.jet(p).grad));
            for k in 0..4 {
                let (a, b) = (vertices[k], vertices[(k + 1) % 4]);
                let t = [b[0] - a[0], b[1] - a[1]];
                let len = t[0].hypot(t[1]);
                let n = [t[1] / len, -t[0] / len];
                let dn = |j: &Jet| j.grad[0] * n[0] + j.grad[1] * n[1];
                let (dn_a, dn_b) = (dn(&f.jet(a)), dn(&f.jet(b)));
                for step in 0..=8 {
                    let s = step as f64 / 8.0;
                    let p = lerp(a, b, s);
                    let u = eval_combination(&cell, &dofs, p);
                    worst[0] = worst[0].max((u.value - f.jet(p).value).abs() / scale);
                    let linear = (1.0 - s) * dn_a + s * dn_b;
                    worst[1] = worst[1].max((dn(&u) - linear).abs() / slope);
                }
            }
            let p = random_point(&mut rng, &cell, 0);
            interior_error = interior_error
                .max((eval_combination(&cell, &dofs, p).value - f.jet(p).value).abs() / scale);
        }
        println!(
            "{vertices:?}: edge value {:.1e}, edge ∂ₙ vs linear {:.1e}, interior error {interior_error:.1e}",
            worst[0], worst[1]
        );
        // Exact relations: round-off only.
        assert!(worst[0] <= 1e-10 && worst[1] <= 1e-10, "{worst:?}");
        // The element really is reduced: generic cubics are not reproduced inside.
        assert!(interior_error > 1e-4);
    }
}

#[test]
fn value_and_gradient_are_continuous_across_the_half_diagonals() {
    let mut rng = StdRng::seed_from_u64(2);
    for (vertices, h) in quads() {
        let cell = FvsCell::new(vertices, h);
        let dofs: Vec<f64> = (0..12).map(|_| rng.random_range(-1.0..1.0)).collect();
        let centre = cell.centre();
        let mut worst = [0.0f64; 2];
        let mut hessian_jump = 0.0f64;
        for k in 0..4 {
            let before = (k + 3) % 4;
            for step in 0..=10 {
                let p = lerp(centre, vertices[k], step as f64 / 10.0);
                let a = eval_piece_combination(&cell, k, &dofs, p);
                let b = eval_piece_combination(&cell, before, &dofs, p);
                // dof-sized quantities: value, h ∇u.
                worst[0] = worst[0].max((a.value - b.value).abs());
                worst[1] = worst[1].max(h * max_abs((0..2).map(|i| a.grad[i] - b.grad[i])));
                hessian_jump =
                    hessian_jump.max(h * h * max_abs((0..3).map(|i| a.hess[i] - b.hess[i])));
            }
        }
        println!(
            "{vertices:?}: jumps value {:.1e}, h∇ {:.1e}, h²∇² {hessian_jump:.1e}",
            worst[0], worst[1]
        );
        // O(1) dofs, O(1) basis coefficients: the jumps are round-off.
        assert!(worst[0] < 1e-12 && worst[1] < 1e-12, "{worst:?}");
        // The Hessian does jump: the element is not a single cubic (sanity of the test).
        assert!(hessian_jump > 1e-3);
    }
}

/// Assembles random vertex dofs on a mesh of FVS cells and checks that value and gradient agree
/// from both cells along every interior edge. Returns the worst relative jumps.
fn edge_jumps(mesh: &Mesh, seed: u64) -> [f64; 2] {
    let mut rng = StdRng::seed_from_u64(seed);
    let h = mesh.size();
    let global: Vec<f64> = (0..3 * mesh.vertices.len())
        .map(|_| rng.random_range(-1.0..1.0))
        .collect();
    let cells: Vec<FvsCell> = (0..mesh.cells.len())
        .map(|c| {
            let xs = mesh.cell_coordinates(c);
            FvsCell::new([xs[0], xs[1], xs[2], xs[3]], h)
        })
        .collect();
    let global = &global;
    let local = |c: usize| -> Vec<f64> {
        mesh.cells[c]
            .iter()
            .flat_map(|&v| (0..3).map(move |i| global[3 * v + i]))
            .collect()
    };
    let mut users = vec![Vec::new(); mesh.edges.len()];
    for c in 0..mesh.cells.len() {
        for k in 0..4 {
            users[mesh.cell_edges[c][k]].push(c);
        }
    }
    let mut worst = [0.0f64; 2];
    let mut interior = 0;
    for (e, u) in users.iter().enumerate() {
        if u.len() != 2 {
            continue;
        }
        interior += 1;
        let [a, b] = mesh.edges[e];
        let (pa, pb) = (mesh.vertices[a], mesh.vertices[b]);
        let t = [pb[0] - pa[0], pb[1] - pa[1]];
        let len = t[0].hypot(t[1]);
        let n = [t[1] / len, -t[0] / len];
        for step in 0..=12 {
            let p = lerp(pa, pb, step as f64 / 12.0);
            let u0 = eval_combination(&cells[u[0]], &local(u[0]), p);
            let u1 = eval_combination(&cells[u[1]], &local(u[1]), p);
            let dn = |j: &Jet| j.grad[0] * n[0] + j.grad[1] * n[1];
            worst[0] = worst[0].max((u0.value - u1.value).abs());
            // Normal derivative and the full gradient, made dof-sized by h.
            let grad_jump = max_abs((0..2).map(|i| u0.grad[i] - u1.grad[i]));
            worst[1] = worst[1]
                .max(h * (dn(&u0) - dn(&u1)).abs())
                .max(h * grad_jump);
        }
    }
    assert!(interior > 0);
    // Relative to the dofs, which are O(1).
    let scale = max_abs(global.iter().copied());
    [worst[0] / scale, worst[1] / scale]
}

#[test]
fn assembled_space_is_c1_on_a_rectangle_mesh() {
    let mesh = Mesh::rectangle_quads(0.4, 0.2, 5, 3);
    let worst = edge_jumps(&mesh, 3);
    println!(
        "rectangle mesh: value jump {:.1e}, h ∂ₙ jump {:.1e}",
        worst[0], worst[1]
    );
    // Both sides interpolate the same edge data exactly: round-off only.
    assert!(worst[0] <= 1e-10 && worst[1] <= 1e-10, "{worst:?}");
}

#[test]
fn assembled_space_is_c1_between_general_quads() {
    let vertices = vec![
        [0.0, 0.0],
        [1.0, 0.1],
        [1.3, 1.0],
        [-0.1, 0.8],
        [2.1, -0.2],
        [2.3, 1.2],
        [1.2, 2.0],
    ];
    let cells = vec![vec![0, 1, 2, 3], vec![1, 4, 5, 2], vec![3, 2, 5, 6]];
    let mesh = Mesh::new(vertices, CellShape::Quadrilateral, cells);
    let worst = edge_jumps(&mesh, 4);
    println!(
        "general quads: value jump {:.1e}, h ∂ₙ jump {:.1e}",
        worst[0], worst[1]
    );
    // As above: round-off only.
    assert!(worst[0] <= 1e-10 && worst[1] <= 1e-10, "{worst:?}");
}

/// a(u, u) = D ∫ [(1 − ν)(u_xx² + 2u_xy² + u_yy²) + ν(Δu)²] (`docs/model.md` §3) with the cell's
/// rule.
fn bending_energy(cell: &FvsCell, dofs: &[f64], d: f64, nu: f64) -> f64 {
    cell.quadrature(2)
        .iter()
        .map(|q| {
            let [xx, xy, yy] = eval_combination(cell, dofs, q.point).hess;
            q.weight
                * d
                * ((1.0 - nu) * (xx * xx + 2.0 * xy * xy + yy * yy) + nu * (xx + yy).powi(2))
        })
        .sum()
}

fn area(v: &[[f64; 2]; 4]) -> f64 {
    0.5 * (0..4)
        .map(|k| v[k][0] * v[(k + 1) % 4][1] - v[(k + 1) % 4][0] * v[k][1])
        .sum::<f64>()
}

#[test]
fn bending_energy_vanishes_on_linears_and_is_exact_on_quadratics() {
    let (d, nu) = (1.923e4, 0.3);
    let mut rng = StdRng::seed_from_u64(5);
    for (vertices, h) in quads() {
        let cell = FvsCell::new(vertices, h);
        let [a, b, c]: [f64; 3] = std::array::from_fn(|_| rng.random_range(-1.0..1.0));
        let quadratic = Jet {
            hess: [2.0 * a / (h * h), b / (h * h), 2.0 * c / (h * h)],
            ..Jet::default()
        };
        let [xx, xy, yy] = quadratic.hess;
        // Energy scale of a unit quadratic on this cell, to make the checks relative.
        let exact = d
            * area(&vertices)
            * ((1.0 - nu) * (xx * xx + 2.0 * xy * xy + yy * yy) + nu * (xx + yy).powi(2));
        let origin = vertices[0];
        let quad_dofs = cell.interpolate(&|p| {
            let (x, y) = ((p[0] - origin[0]) / h, (p[1] - origin[1]) / h);
            Jet {
                value: a * x * x + b * x * y + c * y * y,
                grad: [(2.0 * a * x + b * y) / h, (b * x + 2.0 * c * y) / h],
                hess: quadratic.hess,
            }
        });
        let energy = bending_energy(&cell, &quad_dofs, d, nu);
        let [g0, gx, gy]: [f64; 3] = std::array::from_fn(|_| rng.random_range(-1.0..1.0));
        let linear_dofs = cell.interpolate(&|p| Jet {
            value: g0 + (gx * (p[0] - origin[0]) + gy * (p[1] - origin[1])) / h,
            grad: [gx / h, gy / h],
            hess: [0.0; 3],
        });
        let zero = bending_energy(&cell, &linear_dofs, d, nu);
        println!(
            "{vertices:?}: quadratic rel. error {:.1e}, linear {:.1e}",
            (energy - exact).abs() / exact,
            zero.abs() / exact
        );
        // Quadratics are reproduced and their Hessians are constant: the degree-2 rule is exact,
        // leaving round-off (squared Hessians, hence a bit above the Hessian's own 1e-13).
        assert!((energy - exact).abs() <= 1e-10 * exact);
        assert!(zero.abs() <= 1e-20 * exact);
    }
}

#[test]
fn stiffness_kernel_is_exactly_the_linears() {
    let (d, nu) = (1.0, 0.3);
    for (vertices, h) in quads() {
        let cell = FvsCell::new(vertices, h);
        let mut k = faer::Mat::<f64>::zeros(12, 12);
        let mut basis = vec![Jet::default(); 12];
        for q in cell.quadrature(2) {
            cell.eval(q.point, &mut basis);
            for i in 0..12 {
                for j in 0..12 {
                    let ([a, b, c], [e, f, g]) = (basis[i].hess, basis[j].hess);
                    k[(i, j)] += q.weight
                        * d
                        * ((1.0 - nu) * (a * e + 2.0 * b * f + c * g) + nu * (a + c) * (e + g));
                }
            }
        }
        let eig = k
            .self_adjoint_eigenvalues(faer::Side::Lower)
            .expect("eigenvalues of a 12 × 12 symmetric matrix");
        let top = eig[11];
        println!(
            "{vertices:?}: λ/λ_max = {:?}",
            eig.iter().map(|l| l / top).collect::<Vec<_>>()
        );
        // Three rigid motions (1, x, y) span the kernel: their eigenvalues are round-off
        // (1e-12 of the largest); every other mode has a positive energy well above that.
        assert!(eig[..3].iter().all(|l| l.abs() < 1e-12 * top), "{eig:?}");
        assert!(eig[3] > 1e-4 * top, "{eig:?}");
    }
}

#[test]
fn quadrature_is_exact_for_piecewise_polynomials() {
    // φ_i φ_j is a piecewise sextic: degree 6 per sub-triangle must match a much higher degree.
    for (vertices, h) in quads() {
        let cell = FvsCell::new(vertices, h);
        let mass = |degree: usize| {
            let mut m = [[0.0; 12]; 12];
            let mut basis = vec![Jet::default(); 12];
            for q in cell.quadrature(degree) {
                cell.eval(q.point, &mut basis);
                for i in 0..12 {
                    for j in 0..12 {
                        m[i][j] += q.weight * basis[i].value * basis[j].value;
                    }
                }
            }
            m
        };
        let (m6, m14) = (mass(6), mass(14));
        let total: f64 = cell.quadrature(0).iter().map(|q| q.weight).sum();
        // Area exact to round-off.
        assert!((total - area(&vertices)).abs() < 1e-14 * total);
        let scale = max_abs(m14.iter().flatten().copied());
        let diff = max_abs((0..144).map(|k| m6[k / 12][k % 12] - m14[k / 12][k % 12]));
        // Two exact rules for the same polynomial differ by round-off only.
        assert!(diff < 1e-13 * scale, "{diff:e} vs {scale:e}");
    }
}
