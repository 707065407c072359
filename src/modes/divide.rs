//! All eigenpairs of a symmetric tridiagonal matrix T by divide and conquer (Cuppen's method, with
//! the eigenvectors of Gu and Eisenstat), for the large pencils of [`super`].
//!
//! Splitting T at row m with β = T[m, m−1] gives T = diag(T₁, T₂) + |β| v vᵀ with
//! v = e_{m−1} + sign(β) e_m and β subtracted from the two diagonal entries next to the split.
//! With T₁ = Q₁D₁Q₁ᵀ and T₂ = Q₂D₂Q₂ᵀ solved recursively, T = Q (D + ρ z zᵀ) Qᵀ with
//! Q = diag(Q₁, Q₂), z = Qᵀv/√2 (so ‖z‖ = 1) and ρ = 2|β|. The eigenvalues of D + ρ z zᵀ are the
//! roots of the secular equation w(λ) = 1/ρ + Σ z_i²/(d_i − λ) = 0, one in each interval between
//! consecutive d_i and the last in (d_k, d_k + ρ); its eigenvectors are (D − λI)⁻¹z normalised.
//!
//! Deflation (as LAPACK's `dlaed2`): a component with ρ|z_i| ≤ tol keeps (d_i, e_i) as an
//! eigenpair, and two d_i closer than tol/(|c s|) are rotated so that one z component vanishes;
//! tol = 8 ε max(max|d_i|, max|z_i|), so what deflation neglects is a few ε‖T‖, the accuracy of
//! every backward stable method. The rest (k pairs) go to the secular equation.
//!
//! Accuracy (Gu and Eisenstat 1995, the method of LAPACK's `dstedc`): each root is computed as
//! τ = λ − d_o from its nearer pole d_o, so that every difference d_i − λ_j = (d_i − d_o) − τ has
//! a small relative error; the z of the secular problem is then recomputed from the computed
//! roots (Löwner's formula, ẑ_i² ∝ −(d_i − λ_i) Π_{j≠i} (d_i − λ_j)/(d_i − d_j)), for which those
//! roots are exact. The eigenvectors ẑ_i/(d_i − λ_j) are then orthogonal to working precision
//! however close the roots, and the residuals are a small multiple of ε‖T‖.
//!
//! Cost: the roots O(k²) per merge; the eigenvectors Q·S, a product of the merged block's rows
//! with the k × k secular eigenvectors, split into the rows of T₁ and of T₂ (a column that comes
//! from Q₁ alone has no rows in T₂), so the merges cost about Σ n k² flops of matrix products and
//! deflation makes them cheaper.

use crate::error::Error;
use faer::linalg::matmul::matmul;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, Mat, MatMut, MatRef, Par};

/// Subproblems of at most this order are solved by faer's QR algorithm.
const LEAF: usize = 32;

/// Columns of the secular eigenvectors formed at a time.
const CHUNK: usize = 256;

/// The rows of the merged block in which a column of Q may be nonzero.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Rows {
    /// T₁'s rows only.
    First,
    /// Both (after a deflating rotation of a column of each).
    Both,
    /// T₂'s rows only.
    Second,
}

/// Eigenvalues (ascending) and orthonormal eigenvectors (columns) of the symmetric tridiagonal
/// matrix with `diagonal` (n) and `subdiagonal` (n − 1).
pub fn tridiagonal_eigen(
    diagonal: &[f64],
    subdiagonal: &[f64],
) -> Result<(Vec<f64>, Mat<f64>), Error> {
    let n = diagonal.len();
    assert_eq!(
        subdiagonal.len(),
        n.saturating_sub(1),
        "n − 1 subdiagonal entries"
    );
    let largest = diagonal
        .iter()
        .chain(subdiagonal)
        .fold(0.0f64, |a, &b| a.max(b.abs()));
    if !largest.is_finite() {
        return Err(Error::Numerical(
            "the tridiagonal matrix has a non-finite entry".into(),
        ));
    }
    if largest == 0.0 {
        return Ok((vec![0.0; n], Mat::identity(n, n)));
    }
    // Scaled by a power of two (exact) so that the largest entry lies in [1, 2).
    let scale = 2f64.powi(-(largest.log2().floor() as i32));
    let mut d: Vec<f64> = diagonal.iter().map(|x| x * scale).collect();
    let e: Vec<f64> = subdiagonal.iter().map(|x| x * scale).collect();
    let mut q = Mat::<f64>::zeros(n, n);
    let mut workspace = Mat::<f64>::zeros(n, n);
    solve(&mut d, &e, q.as_mut(), workspace.as_mut())?;
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| d[a].total_cmp(&d[b]));
    workspace.copy_from(&q);
    for (to, &from) in order.iter().enumerate() {
        q.col_mut(to).copy_from(workspace.col(from));
    }
    Ok((order.iter().map(|&i| d[i] / scale).collect(), q))
}

/// Writes the eigenvalues of the tridiagonal (d, e) into d (in no particular order) and its
/// eigenvectors into the columns of `q` (zero on entry), with `workspace` at least as large.
fn solve(
    d: &mut [f64],
    e: &[f64],
    mut q: MatMut<'_, f64>,
    mut workspace: MatMut<'_, f64>,
) -> Result<(), Error> {
    let s = d.len();
    if s <= LEAF {
        return leaf(d, e, q);
    }
    let m = s / 2;
    let beta = e[m - 1];
    let rho = beta.abs();
    d[m - 1] -= rho;
    d[m] -= rho;
    {
        let (d1, d2) = d.split_at_mut(m);
        let (q1, _, _, q2) = q.rb_mut().split_at_mut(m, m);
        solve(d1, &e[..m - 1], q1, workspace.rb_mut())?;
        solve(d2, &e[m..], q2, workspace.rb_mut())?;
    }
    let sign = if beta < 0.0 { -1.0 } else { 1.0 };
    merge(d, q, m, rho, sign, workspace);
    Ok(())
}

/// A small subproblem by faer's QR algorithm (the recursion of its divide and conquer off, as in
/// [`super`]'s dense implementation).
fn leaf(d: &mut [f64], e: &[f64], mut q: MatMut<'_, f64>) -> Result<(), Error> {
    let s = d.len();
    let t = Mat::from_fn(s, s, |i, j| match i.abs_diff(j) {
        0 => d[i],
        1 => e[i.min(j)],
        _ => 0.0,
    });
    let (values, vectors) = super::symmetric_eigen_qr(&t)?;
    q.copy_from(&vectors);
    d.copy_from_slice(&values);
    Ok(())
}

/// The merge of two solved halves (module docs): `d` holds D = diag(D₁, D₂) and `q` Q = diag(Q₁,
/// Q₂), the split after row `m` with |β| = `rho` and sign(β) = `sign`; on return they hold the
/// eigenpairs of the whole block.
fn merge(
    d: &mut [f64],
    mut q: MatMut<'_, f64>,
    m: usize,
    rho: f64,
    sign: f64,
    workspace: MatMut<'_, f64>,
) {
    let s = d.len();
    let half = std::f64::consts::FRAC_1_SQRT_2;
    let mut z: Vec<f64> = (0..s)
        .map(|i| {
            half * if i < m {
                q[(m - 1, i)]
            } else {
                sign * q[(m, i)]
            }
        })
        .collect();
    let rho = 2.0 * rho;
    let (kept, deflated, rows) = deflate(d, &mut z, q.rb_mut(), m, rho);
    let k = kept.len();
    let delta: Vec<f64> = kept.iter().map(|&i| d[i]).collect();
    let zeta: Vec<f64> = kept.iter().map(|&i| z[i]).collect();
    let roots: Vec<Root> = (0..k)
        .map(|j| secular_root(&delta, &zeta, rho, j))
        .collect();
    let zeta_hat = lowner(&delta, &zeta, &roots);
    // The kept columns in the order First, Both, Second, then the deflated ones, copied out.
    let mut gathered: Vec<usize> = (0..k).collect();
    gathered.sort_by_key(|&i| rows[kept[i]] as u8);
    let first = gathered
        .iter()
        .filter(|&&i| rows[kept[i]] == Rows::First)
        .count();
    let second = gathered
        .iter()
        .filter(|&&i| rows[kept[i]] == Rows::Second)
        .count();
    let mut copy = workspace.submatrix_mut(0, 0, s, s);
    for (to, &i) in gathered.iter().enumerate() {
        copy.rb_mut().col_mut(to).copy_from(q.rb().col(kept[i]));
    }
    for (to, &i) in deflated.iter().enumerate() {
        copy.rb_mut().col_mut(k + to).copy_from(q.rb().col(i));
    }
    let values: Vec<f64> = roots
        .iter()
        .map(|r| delta[r.origin] + r.tau)
        .chain(deflated.iter().map(|&i| d[i]))
        .collect();
    d.copy_from_slice(&values);
    let copy = copy.rb();
    q.rb_mut()
        .subcols_mut(k, s - k)
        .copy_from(copy.subcols(k, s - k));
    let secular = Secular {
        delta: &delta,
        zeta_hat: &zeta_hat,
        roots: &roots,
    };
    secular_vectors_product(q, copy, m, &gathered, (first, second), &secular);
}

/// The solved secular problem of a merge: the kept poles δ, Löwner's ẑ and the roots.
struct Secular<'a> {
    delta: &'a [f64],
    zeta_hat: &'a [f64],
    roots: &'a [Root],
}

/// Deflation of D + ρ z zᵀ (module docs), in ascending order of d: rotates close pairs of `d`
/// (and the columns of `q`) so that one of their z components vanishes, and returns the kept
/// indices, the deflated ones, and the rows in which each column of `q` may be nonzero.
fn deflate(
    d: &mut [f64],
    z: &mut [f64],
    mut q: MatMut<'_, f64>,
    m: usize,
    rho: f64,
) -> (Vec<usize>, Vec<usize>, Vec<Rows>) {
    let s = d.len();
    let mut rows: Vec<Rows> = (0..s)
        .map(|i| if i < m { Rows::First } else { Rows::Second })
        .collect();
    let mut order: Vec<usize> = (0..s).collect();
    order.sort_by(|&a, &b| d[a].total_cmp(&d[b]));
    let largest = |v: &[f64]| v.iter().fold(0.0f64, |a, &b| a.max(b.abs()));
    let tol = 8.0 * f64::EPSILON * largest(d).max(largest(z));
    // Deflation, in ascending order of d.
    let mut kept = Vec::with_capacity(s);
    let mut deflated = Vec::new();
    let mut candidate: Option<usize> = None;
    for &j in &order {
        if rho * z[j].abs() <= tol {
            deflated.push(j);
            continue;
        }
        if let Some(p) = candidate {
            let r = z[p].hypot(z[j]);
            let (c, sn) = (z[j] / r, -z[p] / r);
            if ((d[j] - d[p]) * c * sn).abs() <= tol {
                z[j] = r;
                z[p] = 0.0;
                rotate(q.rb_mut(), p, j, c, sn);
                let (dp, dj) = (d[p], d[j]);
                d[p] = dp * c * c + dj * sn * sn;
                d[j] = dp * sn * sn + dj * c * c;
                if rows[p] != rows[j] {
                    rows[p] = Rows::Both;
                    rows[j] = Rows::Both;
                }
                deflated.push(p);
                candidate = Some(j);
                continue;
            }
            kept.push(p);
        }
        candidate = Some(j);
    }
    kept.extend(candidate);
    (kept, deflated, rows)
}

/// The merged eigenvectors: Q's kept columns (gathered in `copy`, in the order First, Both,
/// Second, with `first` and `second` of the extreme kinds) times the secular eigenvectors
/// ẑ_i/(δ_i − λ_j) normalised, CHUNK columns at a time, by row halves: rows of T₁ (before `m`)
/// and of T₂.
fn secular_vectors_product(
    mut q: MatMut<'_, f64>,
    copy: MatRef<'_, f64>,
    m: usize,
    gathered: &[usize],
    (first, second): (usize, usize),
    secular: &Secular<'_>,
) {
    let Secular {
        delta,
        zeta_hat,
        roots,
    } = *secular;
    let (s, k) = (q.nrows(), delta.len());
    // Q's kept columns times the secular eigenvectors, CHUNK columns at a time, by row halves.
    let mut chunk = Mat::<f64>::zeros(k, CHUNK.min(k.max(1)));
    let mut position = vec![0; k];
    for (to, &i) in gathered.iter().enumerate() {
        position[i] = to;
    }
    let mut j0 = 0;
    while j0 < k {
        let width = CHUNK.min(k - j0);
        let mut block = chunk.as_mut().subcols_mut(0, width);
        for c in 0..width {
            let j = j0 + c;
            let mut column = block.rb_mut().col_mut(c);
            let mut norm = 0.0;
            for i in 0..k {
                let x = zeta_hat[i] / difference(delta, i, &roots[j]);
                column[position[i]] = x;
                norm += x * x;
            }
            let scale = 1.0 / norm.sqrt();
            for x in column.iter_mut() {
                *x *= scale;
            }
        }
        let block = block.rb();
        for (rows, inner) in [(0..m, 0..k - second), (m..s, first..k)] {
            let mut target = q.rb_mut().submatrix_mut(rows.start, j0, rows.len(), width);
            if inner.is_empty() {
                target.fill(0.0);
                continue;
            }
            matmul(
                target,
                Accum::Replace,
                copy.submatrix(rows.start, inner.start, rows.len(), inner.len()),
                block.subrows(inner.start, inner.len()),
                1.0,
                Par::Seq,
            );
        }
        j0 += width;
    }
}

/// Columns p and j of q ← (c p + s j, c j − s p).
fn rotate(mut q: MatMut<'_, f64>, p: usize, j: usize, c: f64, s: f64) {
    for r in 0..q.nrows() {
        let (x, y) = (q[(r, p)], q[(r, j)]);
        q[(r, p)] = c * x + s * y;
        q[(r, j)] = c * y - s * x;
    }
}

/// A root of the secular equation as its nearer pole δ_origin and the offset τ = λ − δ_origin.
#[derive(Clone, Copy, Debug)]
struct Root {
    origin: usize,
    tau: f64,
}

/// δ_i − λ_j, formed as (δ_i − δ_origin) − τ: a small relative error however close λ_j lies to
/// δ_i.
fn difference(delta: &[f64], i: usize, root: &Root) -> f64 {
    (delta[i] - delta[root.origin]) - root.tau
}

/// The root j of 1/ρ + Σ ζ_i²/(δ_i − λ) = 0 (δ ascending, every ζ_i ≠ 0): in (δ_j, δ_{j+1}), the
/// last in (δ_{k−1}, δ_{k−1} + ρ‖ζ‖²]. Iterates on τ from the nearer pole with the rational
/// model that matches the sums over the poles left and right of the root in value and slope
/// (the "middle way" of LAPACK's `dlaed4`), safeguarded by bisection of the bracket, until the
/// secular function is below its rounding error or the bracket holds no other number.
fn secular_root(delta: &[f64], zeta: &[f64], rho: f64, j: usize) -> Root {
    let k = delta.len();
    let inverse_rho = 1.0 / rho;
    let last = j + 1 == k;
    let (origin, mut lo, mut hi) = if last {
        (j, 0.0, rho * zeta.iter().map(|z| z * z).sum::<f64>())
    } else {
        let half = 0.5 * (delta[j + 1] - delta[j]);
        let middle: f64 = inverse_rho
            + delta
                .iter()
                .zip(zeta)
                .map(|(&d, &z)| z * z / ((d - delta[j]) - half))
                .sum::<f64>();
        if middle >= 0.0 {
            (j, 0.0, half)
        } else {
            (j + 1, -half, 0.0)
        }
    };
    let sigma: Vec<f64> = delta.iter().map(|&d| d - delta[origin]).collect();
    let mut tau = 0.5 * (lo + hi);
    for _ in 0..MAX_SECULAR_STEPS {
        // ψ over the poles up to j, φ over those after it, with their slopes.
        let (mut psi, mut dpsi, mut phi, mut dphi, mut size) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for (i, (&s, &z)) in sigma.iter().zip(zeta).enumerate() {
            let t = z / (s - tau);
            let term = z * t;
            size += term.abs();
            if i <= j {
                psi += term;
                dpsi += t * t;
            } else {
                phi += term;
                dphi += t * t;
            }
        }
        let w = inverse_rho + psi + phi;
        // Each term carries a few roundings of its own size.
        if w.abs() <= 8.0 * f64::EPSILON * (inverse_rho + size) {
            break;
        }
        if w < 0.0 {
            lo = tau;
        } else {
            hi = tau;
        }
        let left = sigma[j] - tau;
        let b = dpsi * left * left;
        let mut a = inverse_rho + psi - dpsi * left;
        let step = if last {
            // a + b/(left − η) = 0.
            left + b / a
        } else {
            let right = sigma[j + 1] - tau;
            let c = dphi * right * right;
            a += phi - dphi * right;
            // a (left − η)(right − η) + b (right − η) + c (left − η) = 0, i.e.
            // a η² − B η + left·right·w = 0.
            let big_b = a * (left + right) + b + c;
            let constant = left * right * w;
            let root = (big_b * big_b - 4.0 * a * constant).abs().sqrt();
            if big_b >= 0.0 {
                2.0 * constant / (big_b + root)
            } else if a != 0.0 {
                (big_b - root) / (2.0 * a)
            } else {
                constant / big_b
            }
        };
        let next = tau + step;
        tau = if next > lo && next < hi {
            next
        } else {
            0.5 * (lo + hi)
        };
        if tau <= lo || tau >= hi {
            // No number left between the bracket's ends.
            break;
        }
    }
    Root { origin, tau }
}

/// Bound on the iterations of [`secular_root`]: bisection alone halves the bracket to adjacent
/// numbers well within it; the rational steps converge in a handful.
const MAX_SECULAR_STEPS: usize = 2200;

/// ẑ of Löwner's formula for the computed roots (module docs), with the signs of ζ.
fn lowner(delta: &[f64], zeta: &[f64], roots: &[Root]) -> Vec<f64> {
    let k = delta.len();
    (0..k)
        .map(|i| {
            let mut product = -difference(delta, i, &roots[i]);
            for (j, root) in roots.iter().enumerate() {
                if j != i {
                    product *= difference(delta, i, root) / (delta[i] - delta[j]);
                }
            }
            product.max(0.0).sqrt().copysign(zeta[i])
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Residual ‖T Z − Z Λ‖ and orthogonality ‖ZᵀZ − I‖ (largest entries) of an eigensolution.
    fn errors(d: &[f64], e: &[f64], values: &[f64], z: &Mat<f64>) -> (f64, f64) {
        let n = d.len();
        let mut residual = 0.0f64;
        for j in 0..n {
            for i in 0..n {
                let mut t = d[i] * z[(i, j)];
                if i > 0 {
                    t += e[i - 1] * z[(i - 1, j)];
                }
                if i + 1 < n {
                    t += e[i] * z[(i + 1, j)];
                }
                residual = residual.max((t - values[j] * z[(i, j)]).abs());
            }
        }
        let gram = z.transpose() * z - Mat::<f64>::identity(n, n);
        let orthogonality = (0..n)
            .flat_map(|j| (0..n).map(move |i| (i, j)))
            .fold(0.0f64, |a, (i, j)| a.max(gram[(i, j)].abs()));
        (residual, orthogonality)
    }

    /// Matrices that exercise the deflations and the secular equation: random, graded over
    /// twelve orders of magnitude (like the plate pencils), with clusters of equal eigenvalues
    /// (Wilkinson's W⁺ has pairs agreeing to many digits), and glued copies of one block.
    #[test]
    fn eigenpairs_are_accurate_and_orthogonal() {
        let cases: Vec<(&str, Vec<f64>, Vec<f64>)> = vec![
            (
                "pseudo-random",
                (0..300)
                    .map(|i| ((i * 7919 % 1000) as f64 / 500.0) - 1.0)
                    .collect(),
                (0..299)
                    .map(|i| ((i * 104_729 % 997) as f64 / 997.0) - 0.5)
                    .collect(),
            ),
            (
                "graded",
                (0..300)
                    .map(|i| 10f64.powf(-12.0 * i as f64 / 299.0))
                    .collect(),
                (0..299)
                    .map(|i| 0.3 * 10f64.powf(-12.0 * (i as f64 + 0.5) / 299.0))
                    .collect(),
            ),
            (
                "Wilkinson",
                (0..201).map(|i| (100.0 - i as f64).abs()).collect(),
                vec![1.0; 200],
            ),
            (
                "glued",
                (0..260).map(|i| 1.0 + (i % 65) as f64 * 0.01).collect(),
                (0..259)
                    .map(|i| if i % 65 == 64 { 1e-10 } else { 0.5 })
                    .collect(),
            ),
            ("identity", vec![1.0; 100], vec![0.0; 99]),
        ];
        for (name, d, e) in cases {
            let (values, z) = tridiagonal_eigen(&d, &e).unwrap();
            assert!(values.windows(2).all(|w| w[0] <= w[1]), "{name}: sorted");
            let (residual, orthogonality) = errors(&d, &e, &values, &z);
            let norm = d.iter().chain(&e).fold(0.0f64, |a, &b| a.max(b.abs()));
            println!(
                "{name}: residual {:.1e} ‖T‖, orthogonality {orthogonality:.1e}",
                residual / norm
            );
            // Backward stable: a small multiple of ε‖T‖ and of ε, as the QR algorithm gives.
            assert!(residual <= 1e-14 * norm, "{name}: residual {residual:e}");
            assert!(
                orthogonality <= 1e-13,
                "{name}: orthogonality {orthogonality:e}"
            );
        }
    }
}
