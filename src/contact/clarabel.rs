//! The reference contact solver: the full primal QP of [`crate::contact`] handed to Clarabel
//! (Goulart, Chen, *Clarabel: An interior-point solver for conic programs with quadratic
//! objectives*, 2024), an interior-point method with tightened tolerances ([`reference_settings`]
//! says which and why), then [`polish`]ed on its active set with a KKT certificate, which makes it
//! exact to round-off (the tolerances alone leave a few 1e-8 m on plate steps).
//!
//! Clarabel solves min ½ ξᵀ P ξ + qᵀ ξ subject to G ξ + s = h, s ≥ 0 (a nonnegative cone). Each
//! finite bound gives one row: B_i x ≤ hi_i is the row B_i with h = hi_i, and B_i x ≥ lo_i the row
//! −B_i with h = −lo_i; infinite bounds give no row. The problem is first scaled so
//! that Clarabel's absolute tolerances mean the same thing for every mesh and time step: with
//! s_x the gap scale (the largest finite |lo_i|, |hi_i|, or 1 if none) and d the largest diagonal
//! entry of A, x = s_x ξ, P = A / d and q = −b / (s_x d), so ξ, P and the bounds are all of order 1.
//! The duals z ≥ 0 of the two rows of index i then give λ_i = s_x d (z_lower − z_upper).

use ::clarabel::algebra::CscMatrix;
use ::clarabel::solver::{
    DefaultSettings, DefaultSettingsBuilder, DefaultSolution, DefaultSolver, IPSolver,
    SolverStatus, SupportedConeT,
};

use super::{add_product, BoundState, BoxQp, QpSolution};
use crate::modes::sparse_restriction;
use crate::Error;

/// Target of every accuracy tolerance in [`reference_settings`] (scaled units, see the module docs).
pub const REFERENCE_TOLERANCE: f64 = 1e-12;

/// The Clarabel settings of the reference solve. Every departure from Clarabel's defaults, and why:
///
/// * `tol_gap_abs`, `tol_gap_rel`, `tol_feas` = [`REFERENCE_TOLERANCE`] (default 1e-8). An
///   interior-point iterate stops short of the active bounds by an amount that shrinks with the
///   gap; the defaults leave about 3e-6 m on a 32-contact Argyris step, far from the
///   1e-9 m at which the fast path must agree with this reference.
/// * `tol_ktratio` = 1e-10 (default 1e-6): the κ/τ test of the homogeneous embedding must not stop
///   the solver before the gap and feasibility tests do.
/// * `max_iter` = 500 (default 200): the tight tolerances take more iterations near the end.
/// * `static_regularization_constant` = 1e-10 (default 1e-8) and iterative refinement with
///   `iterative_refinement_reltol` = 1e-15, `iterative_refinement_abstol` = 1e-15,
///   `iterative_refinement_max_iter` = 50 (defaults 1e-13, 1e-12, 10): a margin, so that the
///   regularised KKT solves are refined to round-off and cannot be what limits the accuracy.
///   Measured, they change little: the tolerances do the work.
/// * `verbose` = false: a library prints nothing.
///
/// Measured, before polishing, on the random problems of `tests/contact_qp.rs` (gap scale 1 cm, 10–60 bounds, ~20
/// active), largest |x_clarabel − x_exact|: defaults 9.6e-6 m; the four tolerances alone 2.3e-10 m;
/// these settings 2.3e-10 m; tolerances of 1e-13 1.9e-10 m and of 1e-14 3.6e-12 m (not chosen:
/// untested on plate steps, where tolerances near round-off risk an `InsufficientProgress` stop).
///
/// The reduced-accuracy tolerances stay at their defaults: a status of `AlmostSolved` is reported
/// as an error by [`solve_box_qp`], never accepted as a reference.
pub fn reference_settings() -> DefaultSettings<f64> {
    DefaultSettingsBuilder::default()
        .verbose(false)
        .max_iter(500)
        .tol_gap_abs(REFERENCE_TOLERANCE)
        .tol_gap_rel(REFERENCE_TOLERANCE)
        .tol_feas(REFERENCE_TOLERANCE)
        .tol_ktratio(1e-10)
        .static_regularization_constant(1e-10)
        .iterative_refinement_reltol(1e-15)
        .iterative_refinement_abstol(1e-15)
        .iterative_refinement_max_iter(50)
        .build()
        .expect("the reference Clarabel settings are valid")
}

/// Solve `qp` with Clarabel and [`reference_settings`], then [`polish`] the result: the exact
/// solution on Clarabel's active set, kept when it passes the KKT certificate.
///
/// Why polish: an interior-point solution is accurate to its tolerances measured in the objective,
/// which on the plate's stiff systems still leaves a few 1e-8 m (measured on the `forced` scene at
/// 35 Hz, even on steps whose exact solution is the unconstrained one). Clarabel identifies the
/// active set long before that; solving the equality-constrained problem on that set and checking
/// feasibility and the multipliers' signs gives the QP's exact solution to round-off, with a
/// certificate that does not depend on how the set was found.
///
/// When the polish fails (no certified set within its rounds), the interior-point answer is
/// returned with [`QpSolution::polished`] false, so that the caller can say so.
pub fn solve_box_qp(qp: &BoxQp<'_>) -> Result<QpSolution, Error> {
    let raw = solve_box_qp_with(qp, reference_settings())?;
    Ok(polish(qp, &raw.states).unwrap_or(raw))
}

/// The exact solution of `qp`, found from an approximate active set (Clarabel's), if one is found
/// within 20 corrections.
///
/// Each round puts every active row on its bound, solves for the other unknowns
/// (the unit rows fix their unknown, the others are equalities solved through their Schur
/// complement) and forms the multipliers of A x = b + Bᵀλ. A round whose inactive
/// constrained values all lie within their bounds and whose λ_i all have the sign of their bound
/// (both to 1e-12 relative) satisfies the KKT conditions: it is the unique minimiser and is
/// returned. Otherwise violated bounds join the set and wrong-signed multipliers leave it
/// (Clarabel misclassifies vertices that touch with a vanishing force), and the next round runs.
pub fn polish(qp: &BoxQp<'_>, states: &[BoundState]) -> Option<QpSolution> {
    let mut states = states.to_vec();
    for _ in 0..20 {
        match solve_on_active_set(qp, &states)? {
            Ok(solution) => return Some(solution),
            Err(corrected) => states = corrected,
        }
    }
    None
}

/// One round of [`polish`]: the KKT-certified solution, or the corrected active set.
///
/// The active unit rows (a vertex's value, B_i = e_dᵀ) fix their unknown at the bound, and the
/// others are solved on the reduced system: A_FF x_F = b_F − A_F𝒜 g. Active general rows (a
/// stop's own point) add the equality B_G x = g_G on the reduced system, solved through its
/// Schur complement: x_F = x₀ + Y μ with x₀ = A_FF⁻¹(b_F − A_F𝒜 g), Y = A_FF⁻¹ B_{G,F}ᵀ and
/// (B_{G,F} Y) μ = g_G − B_{G,𝒜} g − B_{G,F} x₀. The multipliers are then λ_G = μ on the general
/// rows and λ_i = (A x − b)_d − Σ_G μ_j B_{j,d} on a unit row of unknown d.
fn solve_on_active_set(
    qp: &BoxQp<'_>,
    states: &[BoundState],
) -> Option<Result<QpSolution, Vec<BoundState>>> {
    use faer::linalg::solvers::Solve;
    let n = qp.b.len();
    let bound = |i: usize| match states[i] {
        BoundState::AtLower => Some(qp.lower[i]),
        BoundState::AtUpper => Some(qp.upper[i]),
        BoundState::Free => None,
    };
    let mut fixed = vec![None; n];
    let mut general = Vec::new();
    for i in 0..states.len() {
        if let Some(g) = bound(i) {
            match qp.rows.unit(i) {
                Some(d) => fixed[d] = Some(g),
                None => general.push(i),
            }
        }
    }
    let free: Vec<usize> = (0..n).filter(|&j| fixed[j].is_none()).collect();
    let mut x: Vec<f64> = (0..n).map(|j| fixed[j].unwrap_or(0.0)).collect();
    // A_FF x_F = b_F − A_F𝒜 g: the second term is (A x)_F with x zero on F.
    let a = qp.a;
    let mut bound_part = vec![0.0; n];
    add_product(a, &x, 1.0, &mut bound_part);
    let mut rhs: Vec<f64> = free.iter().map(|&j| qp.b[j] - bound_part[j]).collect();
    let reduced = sparse_restriction(a, &free);
    let factor = reduced.sp_cholesky(faer::Side::Lower).ok()?;
    factor.solve_in_place(faer::ColMut::from_slice_mut(&mut rhs).as_mat_mut());
    let mut mu = vec![0.0; general.len()];
    if !general.is_empty() {
        // The general rows over F (positions in `free`), and their targets less the fixed part.
        let mut position = vec![usize::MAX; n];
        for (k, &j) in free.iter().enumerate() {
            position[j] = k;
        }
        let mut y = faer::Mat::<f64>::zeros(free.len(), general.len());
        let mut target = vec![0.0; general.len()];
        for (q, &i) in general.iter().enumerate() {
            let (dofs, weights) = qp.rows.row(i);
            target[q] = bound(i).expect("an active row");
            for (&d, &w) in dofs.iter().zip(weights) {
                match fixed[d] {
                    Some(g) => target[q] -= w * g,
                    None => {
                        y[(position[d], q)] += w;
                        target[q] -= w * rhs[position[d]];
                    }
                }
            }
        }
        let rows_on_free = y.clone();
        factor.solve_in_place(y.as_mut());
        let schur = rows_on_free.transpose() * &y;
        let mut mu_col = faer::Col::from_fn(general.len(), |q| target[q]);
        schur
            .llt(faer::Side::Lower)
            .ok()?
            .solve_in_place(mu_col.as_mat_mut());
        for q in 0..general.len() {
            mu[q] = mu_col[q];
            for (k, r) in rhs.iter_mut().enumerate() {
                *r += y[(k, q)] * mu[q];
            }
        }
    }
    for (k, &j) in free.iter().enumerate() {
        x[j] = rhs[k];
    }
    // λ on the constrained rows: (A x − b) less the general rows' share, at each unit row's
    // unknown; μ on the general rows.
    let mut residual: Vec<f64> = qp.b.iter().map(|b| -b).collect();
    add_product(a, &x, 1.0, &mut residual);
    for (q, &i) in general.iter().enumerate() {
        qp.rows.add_row(i, -mu[q], &mut residual);
    }
    let scale_x = qp
        .lower
        .iter()
        .chain(qp.upper)
        .filter(|v| v.is_finite())
        .fold(1e-300, |s: f64, v| s.max(v.abs()));
    let scale_lambda = residual
        .iter()
        .chain(&mu)
        .fold(1e-300, |s: f64, v| s.max(v.abs()));
    let mut lambda = vec![0.0; states.len()];
    let mut corrected = states.to_vec();
    for (i, state) in states.iter().enumerate() {
        let xi = qp.rows.value(i, &x);
        let li = match (qp.rows.unit(i), general.iter().position(|&j| j == i)) {
            (_, Some(q)) => mu[q],
            (Some(d), None) => residual[d],
            (None, None) => 0.0,
        };
        corrected[i] = match state {
            BoundState::Free if xi < qp.lower[i] - 1e-12 * scale_x => BoundState::AtLower,
            BoundState::Free if xi > qp.upper[i] + 1e-12 * scale_x => BoundState::AtUpper,
            BoundState::AtLower | BoundState::AtUpper
                if li * sign(*state) < -1e-12 * scale_lambda =>
            {
                BoundState::Free
            }
            _ => *state,
        };
        if state.is_active() {
            lambda[i] = li;
        }
    }
    if corrected != states {
        return Some(Err(corrected));
    }
    Some(Ok(QpSolution {
        x,
        lambda,
        states: corrected,
        polished: true,
    }))
}

/// Solve `qp` with Clarabel and the given settings (see [`reference_settings`]).
///
/// The states are read from the interior-point pair of each bound row: index i is active at a
/// bound when that row's dual exceeds its slack (strict complementarity makes the split clear).
/// Errors: inconsistent dimensions, lo_i > hi_i, or any Clarabel status but `Solved` (named in
/// the message).
///
/// The problem is scaled as the module docs say (x by the largest finite bound, the objective by
/// A's largest diagonal entry); the bounds become the rows of G, whose duals and slacks give the
/// answer's multipliers and states.
pub fn solve_box_qp_with(
    qp: &BoxQp<'_>,
    settings: DefaultSettings<f64>,
) -> Result<QpSolution, Error> {
    let scale_x = bound_scale(qp)?;
    let objective = ScaledObjective::new(qp, scale_x)?;
    let rows = BoundRows::new(qp, scale_x);
    let cones = if rows.h.is_empty() {
        Vec::new()
    } else {
        vec![SupportedConeT::NonnegativeConeT(rows.h.len())]
    };
    let (p, q) = (&objective.p, &objective.q);
    let mut solver = DefaultSolver::new(p, q, &rows.g, &rows.h, &cones, settings)
        .map_err(|e| Error::ContactSolver(format!("clarabel rejected the problem: {e:?}")))?;
    solver.solve();
    let status = solver.solution.status;
    if status != SolverStatus::Solved {
        return Err(Error::ContactSolver(format!(
            "clarabel stopped with status {status:?} after {} iterations (reference solve needs \
             Solved)",
            solver.info.iterations
        )));
    }
    let sol = &solver.solution;
    let x: Vec<f64> = sol.x.iter().map(|&xi| xi * scale_x).collect();
    let (lambda, states) = rows.multipliers_and_states(sol, scale_x * objective.d);
    Ok(QpSolution {
        x,
        lambda,
        states,
        polished: false,
    })
}

/// Checks the dimensions and bounds of `qp` and returns the scale of x: the largest finite
/// |bound| (1 when there is none or all are 0).
fn bound_scale(qp: &BoxQp<'_>) -> Result<f64, Error> {
    let n = qp.b.len();
    let m = qp.rows.len();
    if qp.a.nrows() != n || qp.a.ncols() != n {
        return Err(Error::ContactSolver(format!(
            "clarabel: A is {} × {} but b has length {n}",
            qp.a.nrows(),
            qp.a.ncols()
        )));
    }
    if qp.lower.len() != m || qp.upper.len() != m {
        return Err(Error::ContactSolver(format!(
            "clarabel: {m} constraint rows but {} lower and {} upper bounds",
            qp.lower.len(),
            qp.upper.len()
        )));
    }
    let mut scale_x = 0.0_f64;
    for i in 0..m {
        let (lo, hi) = (qp.lower[i], qp.upper[i]);
        let (dofs, weights) = qp.rows.row(i);
        if dofs.iter().any(|&d| d >= n)
            || weights.iter().any(|w| !w.is_finite())
            || lo.is_nan()
            || hi.is_nan()
            || lo > hi
        {
            return Err(Error::ContactSolver(format!(
                "clarabel: constraint {i} on unknowns {dofs:?} has bounds [{lo}, {hi}]"
            )));
        }
        for v in [lo, hi] {
            if v.is_finite() {
                scale_x = scale_x.max(v.abs());
            }
        }
    }
    Ok(if scale_x == 0.0 { 1.0 } else { scale_x })
}

/// The objective ½xᵀPx + qᵀx of the scaled problem: P = A/d (its upper triangle, in Clarabel's
/// own CSC) and q = −b/(s d), with s the scale of x and d A's largest diagonal entry.
struct ScaledObjective {
    p: CscMatrix<f64>,
    q: Vec<f64>,
    /// d.
    d: f64,
}

impl ScaledObjective {
    fn new(qp: &BoxQp<'_>, scale_x: f64) -> Result<ScaledObjective, Error> {
        let a = qp.a;
        let n = qp.b.len();
        let mut d = 0.0_f64;
        for j in 0..n {
            let range = a.col_range(j);
            for (&i, &v) in a.row_idx()[range.clone()].iter().zip(&a.val()[range]) {
                if i == j {
                    d = d.max(v.abs());
                }
            }
        }
        if !(d > 0.0 && d.is_finite()) {
            return Err(Error::ContactSolver(
                "clarabel: A has no positive finite diagonal".to_string(),
            ));
        }
        let mut colptr = Vec::with_capacity(n + 1);
        let mut rowval = Vec::new();
        let mut nzval = Vec::new();
        colptr.push(0);
        for j in 0..n {
            let range = a.col_range(j);
            let mut entries: Vec<(usize, f64)> = a.row_idx()[range.clone()]
                .iter()
                .zip(&a.val()[range])
                .filter(|(&i, _)| i <= j)
                .map(|(&i, &v)| (i, v / d))
                .collect();
            entries.sort_unstable_by_key(|e| e.0);
            for (i, v) in entries {
                rowval.push(i);
                nzval.push(v);
            }
            colptr.push(rowval.len());
        }
        let p = CscMatrix::new(n, n, colptr, rowval, nzval);
        let q: Vec<f64> = qp.b.iter().map(|&bi| -bi / (scale_x * d)).collect();
        Ok(ScaledObjective { p, q, d })
    }
}

/// The bounds of the scaled problem as the rows Gx ≤ h, one per finite bound (B_i x ≤ hi/s and
/// −B_i x ≤ −lo/s), and which row belongs to which constrained index.
struct BoundRows {
    g: CscMatrix<f64>,
    h: Vec<f64>,
    /// The row of index i's upper bound, `usize::MAX` when infinite.
    upper_row: Vec<usize>,
    /// The row of index i's lower bound, `usize::MAX` when infinite.
    lower_row: Vec<usize>,
}

impl BoundRows {
    fn new(qp: &BoxQp<'_>, scale_x: f64) -> BoundRows {
        let m = qp.rows.len();
        let mut triplets_i = Vec::new();
        let mut triplets_j = Vec::new();
        let mut triplets_v = Vec::new();
        let mut h = Vec::new();
        let mut upper_row = vec![usize::MAX; m];
        let mut lower_row = vec![usize::MAX; m];
        for i in 0..m {
            let (dofs, weights) = qp.rows.row(i);
            for (slot, bound, sign) in [
                (&mut upper_row[i], qp.upper[i], 1.0),
                (&mut lower_row[i], qp.lower[i], -1.0),
            ] {
                if bound.is_finite() {
                    *slot = h.len();
                    for (&d, &w) in dofs.iter().zip(weights) {
                        triplets_i.push(h.len());
                        triplets_j.push(d);
                        triplets_v.push(sign * w);
                    }
                    h.push(sign * bound / scale_x);
                }
            }
        }
        let g =
            CscMatrix::new_from_triplets(h.len(), qp.b.len(), triplets_i, triplets_j, triplets_v);
        BoundRows {
            g,
            h,
            upper_row,
            lower_row,
        }
    }

    /// The multipliers λ_i = scale·(z_lower − z_upper) (`scale` undoes the problem's scaling,
    /// s d) and the contact states of the solution `sol`: index i is active at the bound whose
    /// dual exceeds its slack and the other dual (its slack is zero to the solver's accuracy).
    fn multipliers_and_states(
        &self,
        sol: &DefaultSolution<f64>,
        scale: f64,
    ) -> (Vec<f64>, Vec<BoundState>) {
        let m = self.lower_row.len();
        let mut lambda = vec![0.0; m];
        let mut states = vec![BoundState::Free; m];
        // The value of a bound's row in `v`, or `absent` when the bound is infinite.
        let row = |rows: &[usize], i: usize, v: &[f64], absent: f64| {
            if rows[i] == usize::MAX {
                absent
            } else {
                v[rows[i]]
            }
        };
        for i in 0..m {
            let zl = row(&self.lower_row, i, &sol.z, 0.0);
            let zu = row(&self.upper_row, i, &sol.z, 0.0);
            lambda[i] = scale * (zl - zu);
            // Active when its slack is zero to the solver's accuracy and the dual is the larger.
            let sl = row(&self.lower_row, i, &sol.s, f64::INFINITY);
            let su = row(&self.upper_row, i, &sol.s, f64::INFINITY);
            states[i] = if zl > sl && zl > zu {
                BoundState::AtLower
            } else if zu > su && zu > zl {
                BoundState::AtUpper
            } else {
                BoundState::Free
            };
        }
        (lambda, states)
    }
}

/// +1 for the lower bound (λ ≥ 0), −1 for the upper (λ ≤ 0).
fn sign(state: BoundState) -> f64 {
    if state == BoundState::AtUpper {
        -1.0
    } else {
        1.0
    }
}
