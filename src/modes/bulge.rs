//! The second stage of a two-stage tridiagonalisation: a symmetric band matrix B of lower
//! bandwidth b reduced to tridiagonal form by bulge chasing, B = Q₂ T Q₂ᵀ, with Q₂ kept as its
//! Householder reflectors.
//!
//! Sweep j makes column j tridiagonal. Its first reflector H₀ acts on rows j+1..j+b and
//! annihilates column j below the subdiagonal; applied from both sides to the diagonal block on
//! those rows, and from the right to the b rows below, it fills a triangle outside the band (a
//! bulge). The next reflector acts on those rows and annihilates the bulge's first column only,
//! and so on down the matrix: each step applies the previous reflector from the right to the next
//! block of rows, annihilates that block's first column with a new reflector, applies it from the
//! left to the rest of the block and from both sides to its diagonal block (Lang's algorithm, as
//! in LAPACK's `dsytrd_sb2st`). What a step leaves outside the band in the block's other columns
//! is the column that a later sweep annihilates, so the storage needs a lower bandwidth of 2b and
//! no more. A sweep costs about 14 b² flops per block of b rows, the reduction about 7 b n², each
//! step on blocks that stay in the cache.
//!
//! With T = Hₙ ⋯ H₁ B H₁ ⋯ Hₙ (in the order the reflectors were made), Q₂ = H₁ ⋯ Hₙ: Q₂ᵀ x applies
//! them in that order, Q₂ x in the reverse one.

use super::band::BANDWIDTH;

/// Rows below the diagonal that the working storage holds per column: the band and the bulge.
const STORED: usize = 2 * BANDWIDTH;

/// A symmetric tridiagonal T (diagonal and subdiagonal) and the reflectors of Q₂.
#[derive(Clone, Debug)]
pub struct BulgeChase {
    /// T's diagonal (n).
    pub diagonal: Vec<f64>,
    /// T's subdiagonal (n − 1).
    pub subdiagonal: Vec<f64>,
    /// Each reflector I − v vᵀ/τ in the order made: its first row, its length and its τ; v₀ = 1
    /// and v's other entries lie in `vectors` from `offset`.
    reflectors: Vec<Reflector>,
    vectors: Vec<f64>,
}

#[derive(Clone, Copy, Debug)]
struct Reflector {
    row: usize,
    length: usize,
    tau: f64,
    offset: usize,
}

/// The band in column storage with room for the bulges: entry (r, c), 0 ≤ r − c ≤ STORED, at
/// c·STORED + r, so that each column's entries are contiguous, the columns do not overlap, and a
/// block within the stored band is a column-major matrix with column stride STORED.
struct Storage {
    data: Vec<f64>,
}

impl Storage {
    fn index(r: usize, c: usize) -> usize {
        debug_assert!(r >= c && r - c <= STORED);
        c * STORED + r
    }
    fn get(&self, r: usize, c: usize) -> f64 {
        self.data[Self::index(r, c)]
    }
    fn set(&mut self, r: usize, c: usize, value: f64) {
        let i = Self::index(r, c);
        self.data[i] = value;
    }
    /// Rows `rows` of column c, contiguous (all within STORED of the diagonal).
    fn column(&mut self, c: usize, rows: std::ops::Range<usize>) -> &mut [f64] {
        let start = Self::index(rows.start, c);
        &mut self.data[start..start + rows.len()]
    }
}

/// Reduces the band (`columns[c][d]` = B[c + d, c], as [`super::band::BandColumns`]) to
/// tridiagonal form.
pub fn chase(columns: &[[f64; BANDWIDTH + 1]]) -> BulgeChase {
    let n = columns.len();
    let b = BANDWIDTH;
    let mut a = Storage {
        data: vec![0.0; n * (STORED + 1)],
    };
    for (c, column) in columns.iter().enumerate() {
        for (d, &x) in column.iter().enumerate() {
            if c + d < n {
                a.set(c + d, c, x);
            }
        }
    }
    let mut reflectors = Vec::new();
    let mut vectors = Vec::new();
    let mut scratch = Scratch::new();
    for j in 0..n.saturating_sub(2) {
        // Step 0: column j below the subdiagonal.
        let mut rows = j + 1..(j + b + 1).min(n);
        let Some(h) = householder(a.column(j, rows.clone())) else {
            continue;
        };
        two_sided(&mut a, rows.start, &h, &mut scratch);
        let mut current = record(&mut reflectors, &mut vectors, rows.start, &h);
        // The chase: the block of rows below, from the right, then its first column.
        loop {
            let next = rows.end..(rows.end + b).min(n);
            if next.is_empty() {
                break;
            }
            let v = &vectors[current.offset..current.offset + current.length];
            right(
                &mut a,
                next.clone(),
                rows.clone(),
                v,
                current.tau,
                &mut scratch,
            );
            let Some(g) = householder(a.column(rows.start, next.clone())) else {
                break;
            };
            left(&mut a, next.clone(), rows.start + 1..rows.end, &g);
            two_sided(&mut a, next.start, &g, &mut scratch);
            current = record(&mut reflectors, &mut vectors, next.start, &g);
            rows = next;
        }
    }
    let diagonal = (0..n).map(|i| a.get(i, i)).collect();
    let subdiagonal = (0..n.saturating_sub(1)).map(|i| a.get(i + 1, i)).collect();
    BulgeChase {
        diagonal,
        subdiagonal,
        reflectors,
        vectors,
    }
}

/// A reflector I − v vᵀ/τ with v₀ = 1.
struct Householder {
    v: Vec<f64>,
    tau: f64,
}

/// The reflector that maps the column segment x to β e₀, with x overwritten by β e₀; `None` when
/// x has a single entry.
fn householder(x: &mut [f64]) -> Option<Householder> {
    if x.len() < 2 {
        return None;
    }
    let (head, tail) = x.split_at_mut(1);
    let info = faer::linalg::householder::make_householder_in_place(
        &mut head[0],
        faer::ColMut::from_slice_mut(&mut *tail),
    );
    let v = std::iter::once(1.0).chain(tail.iter().copied()).collect();
    tail.fill(0.0);
    Some(Householder { v, tau: info.tau })
}

fn record(
    reflectors: &mut Vec<Reflector>,
    vectors: &mut Vec<f64>,
    row: usize,
    h: &Householder,
) -> Reflector {
    let r = Reflector {
        row,
        length: h.v.len(),
        tau: h.tau,
        offset: vectors.len(),
    };
    vectors.extend_from_slice(&h.v);
    reflectors.push(r);
    r
}

/// Work vectors of the steps.
struct Scratch {
    p: Vec<f64>,
}

impl Scratch {
    fn new() -> Scratch {
        Scratch {
            p: vec![0.0; BANDWIDTH],
        }
    }
}

/// S ← H S H for the symmetric diagonal block S on rows `start..start + h.v.len()` (lower
/// triangle stored): p = S v/τ, w = p − ½(vᵀp/τ) v, S −= v wᵀ + w vᵀ.
fn two_sided(a: &mut Storage, start: usize, h: &Householder, scratch: &mut Scratch) {
    let l = h.v.len();
    let v = &h.v;
    let p = &mut scratch.p[..l];
    p.fill(0.0);
    for c in 0..l {
        let column = a.column(start + c, start + c..start + l);
        let (diagonal, below) = column.split_first().expect("a nonempty column");
        p[c] += diagonal * v[c] + dot(below, &v[c + 1..]);
        for (p, &s) in p[c + 1..].iter_mut().zip(below.iter()) {
            *p += s * v[c];
        }
    }
    let inverse_tau = 1.0 / h.tau;
    for x in p.iter_mut() {
        *x *= inverse_tau;
    }
    let half = 0.5 * inverse_tau * dot(p, v);
    for (x, &vi) in p.iter_mut().zip(v) {
        *x -= half * vi;
    }
    for c in 0..l {
        let (vc, wc) = (v[c], p[c]);
        let column = a.column(start + c, start + c..start + l);
        for ((s, &vr), &wr) in column.iter_mut().zip(&v[c..]).zip(&p[c..]) {
            *s -= vr * wc + wr * vc;
        }
    }
}

/// The block on rows `rows` and columns `columns` ← itself times I − v vᵀ/τ (v over `columns`).
fn right(
    a: &mut Storage,
    rows: std::ops::Range<usize>,
    columns: std::ops::Range<usize>,
    v: &[f64],
    tau: f64,
    scratch: &mut Scratch,
) {
    let y = &mut scratch.p[..rows.len()];
    y.fill(0.0);
    for (k, c) in columns.clone().enumerate() {
        for (y, &x) in y.iter_mut().zip(a.column(c, rows.clone()).iter()) {
            *y += x * v[k];
        }
    }
    let inverse_tau = 1.0 / tau;
    for (k, c) in columns.enumerate() {
        let scale = v[k] * inverse_tau;
        for (x, &y) in a.column(c, rows.clone()).iter_mut().zip(y.iter()) {
            *x -= scale * y;
        }
    }
}

/// The block on rows `rows` and columns `columns` ← (I − v vᵀ/τ) times itself (v over `rows`).
fn left(
    a: &mut Storage,
    rows: std::ops::Range<usize>,
    columns: std::ops::Range<usize>,
    g: &Householder,
) {
    let inverse_tau = 1.0 / g.tau;
    for c in columns {
        let column = a.column(c, rows.clone());
        let d = dot(column, &g.v) * inverse_tau;
        for (x, &v) in column.iter_mut().zip(&g.v) {
            *x -= d * v;
        }
    }
}

/// xᵀy over the shorter length, in four interleaved partial sums (vectorisable).
fn dot(x: &[f64], y: &[f64]) -> f64 {
    let l = x.len().min(y.len());
    let (x, y) = (&x[..l], &y[..l]);
    let mut sums = [0.0; 4];
    let (xc, yc) = (x.chunks_exact(4), y.chunks_exact(4));
    let (xr, yr) = (xc.remainder(), yc.remainder());
    for (a, b) in xc.zip(yc) {
        for k in 0..4 {
            sums[k] += a[k] * b[k];
        }
    }
    let tail: f64 = xr.iter().zip(yr).map(|(a, b)| a * b).sum();
    (sums[0] + sums[1]) + (sums[2] + sums[3]) + tail
}

impl BulgeChase {
    /// The order n.
    pub fn dimension(&self) -> usize {
        self.diagonal.len()
    }

    /// target ← Q₂ᵀ target (the reflectors in the order made).
    pub fn apply_q_transpose(&self, target: faer::MatMut<'_, f64>) {
        self.apply(target, true);
    }

    /// target ← Q₂ target (the reflectors in reverse order).
    pub fn apply_q(&self, target: faer::MatMut<'_, f64>) {
        self.apply(target, false);
    }

    /// Applies each reflector to every column of `target`, [`GROUP`] columns at a time, copied
    /// row by row into a scratch matrix: a reflector then updates a few rows of contiguous
    /// values, and the group stays in the cache while all the reflectors pass over it.
    fn apply(&self, mut target: faer::MatMut<'_, f64>, transpose: bool) {
        assert_eq!(target.nrows(), self.dimension(), "one row per unknown");
        let n = target.nrows();
        let mut rows = vec![0.0; n * GROUP];
        let mut j0 = 0;
        while j0 < target.ncols() {
            let g = GROUP.min(target.ncols() - j0);
            for i in 0..n {
                for k in 0..g {
                    rows[i * GROUP + k] = target[(i, j0 + k)];
                }
            }
            let arch = pulp::Arch::new();
            let mut one = |r: &Reflector| {
                arch.dispatch(RowReflector {
                    v: &self.vectors[r.offset..r.offset + r.length],
                    inverse_tau: 1.0 / r.tau,
                    rows: &mut rows[r.row * GROUP..(r.row + r.length) * GROUP],
                })
            };
            if transpose {
                self.reflectors.iter().for_each(&mut one);
            } else {
                self.reflectors.iter().rev().for_each(&mut one);
            }
            for i in 0..n {
                for k in 0..g {
                    target[(i, j0 + k)] = rows[i * GROUP + k];
                }
            }
            j0 += g;
        }
    }
}

/// Columns of a target that [`BulgeChase::apply_q`] updates together.
const GROUP: usize = 32;

/// One reflector I − v vᵀ/τ applied to `rows` (v.len() rows of [`GROUP`] values, row-major):
/// d = Σ_i v_i row_i, then row_i −= (v_i/τ) d, a register of values at a time under
/// [`pulp::Arch::dispatch`].
struct RowReflector<'a> {
    v: &'a [f64],
    inverse_tau: f64,
    rows: &'a mut [f64],
}

impl pulp::WithSimd for RowReflector<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, simd: S) {
        // A row fills at most GROUP registers (one value each without SIMD).
        let mut d = [simd.splat_f64s(0.0); GROUP];
        let mut width = 0;
        for (row, &vi) in self.rows.chunks_exact(GROUP).zip(self.v) {
            let (row, _) = S::as_simd_f64s(row);
            width = row.len();
            let vi = simd.splat_f64s(vi);
            for (d, &x) in d.iter_mut().zip(row) {
                *d = simd.mul_add_e_f64s(vi, x, *d);
            }
        }
        let d = &d[..width];
        for (row, &vi) in self.rows.chunks_exact_mut(GROUP).zip(self.v) {
            let (row, _) = S::as_mut_simd_f64s(row);
            let scale = simd.splat_f64s(-vi * self.inverse_tau);
            for (x, &d) in row.iter_mut().zip(d) {
                *x = simd.mul_add_e_f64s(scale, d, *x);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::Mat;

    /// B = Q₂ T Q₂ᵀ with Q₂ orthogonal, for sizes around the bandwidth and several sweeps.
    #[test]
    fn chase_reproduces_the_band() {
        let b = BANDWIDTH;
        for n in [1, 2, 3, b, b + 1, b + 2, 2 * b + 1, 3 * b + 7] {
            let columns: Vec<[f64; BANDWIDTH + 1]> = (0..n)
                .map(|c| {
                    let mut column = [0.0; BANDWIDTH + 1];
                    for (d, x) in column.iter_mut().enumerate() {
                        if c + d < n {
                            *x = ((c * 7 + d * 13) % 17) as f64 / 17.0 - 0.4
                                + if d == 0 { 2.0 } else { 0.0 };
                        }
                    }
                    column
                })
                .collect();
            let band = Mat::from_fn(n, n, |i, j| {
                let (r, c) = (i.max(j), i.min(j));
                if r - c <= b {
                    columns[c][r - c]
                } else {
                    0.0
                }
            });
            let t = chase(&columns);
            let tri = Mat::from_fn(n, n, |i, j| match i.abs_diff(j) {
                0 => t.diagonal[i],
                1 => t.subdiagonal[i.min(j)],
                _ => 0.0,
            });
            let mut q = Mat::<f64>::identity(n, n);
            t.apply_q(q.as_mut());
            let mut qt = Mat::<f64>::identity(n, n);
            t.apply_q_transpose(qt.as_mut());
            let back = &q * &tri * q.transpose();
            let orthogonality = q.transpose() * &q - Mat::<f64>::identity(n, n);
            // Backward stable: errors of a few n ε relative to ‖B‖ ≈ 3.
            let tolerance = 1e-13;
            for i in 0..n {
                for j in 0..n {
                    assert!(
                        (back[(i, j)] - band[(i, j)]).abs() < tolerance,
                        "n = {n}: ({i}, {j}) {} vs {}",
                        back[(i, j)],
                        band[(i, j)]
                    );
                    assert!(orthogonality[(i, j)].abs() < tolerance, "n = {n}");
                    assert!((qt[(i, j)] - q[(j, i)]).abs() < tolerance, "n = {n}");
                }
            }
        }
    }
}
