//! What the independent computations share: the plate's matrices as dense ones, a contact point's
//! row built from the element's basis here (not by the library's contact rows), and the box QP of
//! a few rows with lower bounds solved by enumerating its active sets.

use faer::linalg::solvers::Llt;
use faer::linalg::solvers::Solve;
use faer::{Mat, Side};
use plate_impact::assembly::Discretization;
use plate_impact::element::Jet;
use plate_impact::system::PlateSystem;

/// The dense copy of a sparse matrix restricted to `keep` (rows and columns).
pub fn dense_restriction(a: &faer::sparse::SparseColMat<usize, f64>, keep: &[usize]) -> Mat<f64> {
    let full = a.to_dense();
    Mat::from_fn(keep.len(), keep.len(), |i, j| full[(keep[i], keep[j])])
}

/// The row u ↦ u(p) over all dofs, from the basis of the cell that holds `p`: the cell found by
/// testing every cell (p on the left of, or on, each counter-clockwise edge, to 1e-12 of the
/// cell's size), its basis evaluated at `p`, the values scattered to the cell's global dofs.
pub fn point_row(disc: &Discretization, p: [f64; 2]) -> Vec<f64> {
    let mesh = &disc.mesh;
    let holds = |c: usize| {
        let xs: Vec<[f64; 2]> = mesh.cells[c].iter().map(|&v| mesh.vertices[v]).collect();
        let n = xs.len();
        (0..n).all(|k| {
            let (a, b) = (xs[k], xs[(k + 1) % n]);
            let size = (b[0] - a[0]).hypot(b[1] - a[1]);
            let cross = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
            cross >= -1e-12 * size * size
        })
    };
    let c = (0..mesh.cells.len())
        .find(|&c| holds(c))
        .expect("the point lies on the plate");
    let basis = disc.cell_basis(c);
    let mut jets = vec![Jet::default(); basis.dof_count()];
    basis.eval(p, &mut jets);
    let mut row = vec![0.0; disc.dof_count];
    for (&d, jet) in disc.cell_dofs(c).iter().zip(&jets) {
        row[d] += jet.value;
    }
    row
}

/// The entries of `v` (over all dofs) at the `free` dofs.
pub fn free_part(v: &[f64], free: &[usize]) -> Vec<f64> {
    free.iter().map(|&d| v[d]).collect()
}

/// The minimiser of ½ xᵀAx − bᵀx subject to r_i·x ≥ g_i (a few rows), given the factor of A
/// and the unconstrained minimiser x* = A⁻¹b: x = x* + A⁻¹Rᵀμ with the multipliers μ ≥ 0. Every
/// subset S of the rows is tried, smallest first: μ_S solves W_SS μ_S = g_S − R_S x*
/// (W = R A⁻¹ Rᵀ), and S is the answer when μ_S ≥ 0 and every row holds, both to 1e-12 of their
/// scales (the KKT conditions, which for a strictly convex QP only its minimiser satisfies).
/// Returns (x, μ).
pub fn solve_few_rows(
    factor: &Llt<f64>,
    x_star: &[f64],
    rows: &[Vec<f64>],
    bounds: &[f64],
) -> (Vec<f64>, Vec<f64>) {
    let (n, m) = (x_star.len(), rows.len());
    assert!(m <= 16, "enumeration is for a few rows");
    let y_star: Vec<f64> = rows
        .iter()
        .map(|r| r.iter().zip(x_star).map(|(a, b)| a * b).sum())
        .collect();
    if y_star.iter().zip(bounds).all(|(y, g)| y >= g) {
        // The empty set: x* itself, with no need of W.
        return (x_star.to_vec(), vec![0.0; m]);
    }
    let rt = Mat::from_fn(n, m, |i, j| rows[j][i]);
    let solved = factor.solve(&rt);
    let w = Mat::from_fn(m, m, |i, j| {
        (0..n).map(|k| rows[i][k] * solved[(k, j)]).sum::<f64>()
    });
    let gap_scale = bounds
        .iter()
        .chain(&y_star)
        .fold(1e-300, |s: f64, v| s.max(v.abs()));
    let mut subsets: Vec<u32> = (0..1u32 << m).collect();
    subsets.sort_by_key(|s| s.count_ones());
    for set in subsets {
        let active: Vec<usize> = (0..m).filter(|&i| set >> i & 1 == 1).collect();
        let k = active.len();
        let mut mu = vec![0.0; m];
        if k > 0 {
            let w_ss = Mat::from_fn(k, k, |a, b| w[(active[a], active[b])]);
            let Ok(llt) = w_ss.llt(Side::Lower) else {
                continue;
            };
            let rhs = Mat::from_fn(k, 1, |a, _| bounds[active[a]] - y_star[active[a]]);
            let solution = llt.solve(&rhs);
            for (a, &i) in active.iter().enumerate() {
                mu[i] = solution[(a, 0)];
            }
        }
        let force_scale = mu.iter().fold(1e-300, |s: f64, v| s.max(v.abs()));
        if mu.iter().any(|&v| v < -1e-12 * force_scale) {
            continue;
        }
        let y: Vec<f64> = (0..m)
            .map(|i| y_star[i] + (0..m).map(|j| w[(i, j)] * mu[j]).sum::<f64>())
            .collect();
        if (0..m).all(|i| y[i] >= bounds[i] - 1e-12 * gap_scale) {
            let mut x = x_star.to_vec();
            for (i, xi) in x.iter_mut().enumerate() {
                *xi += (0..m).map(|j| solved[(i, j)] * mu[j]).sum::<f64>();
            }
            return (x, mu);
        }
    }
    panic!("no active set satisfies the KKT conditions");
}

/// The rows at `points` over the free dofs of `plate`, and over all dofs.
pub fn rows_at(plate: &PlateSystem, points: &[[f64; 2]]) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let full: Vec<Vec<f64>> = points.iter().map(|&p| point_row(&plate.disc, p)).collect();
    let free = full.iter().map(|r| free_part(r, &plate.free)).collect();
    (free, full)
}
