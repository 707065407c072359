//! The fast exact contact solver, in the Delassus space.
//!
//! With x* = A⁻¹ b the unconstrained step, y* = B x* its constrained values and
//! W = B A⁻¹ Bᵀ (m × m, symmetric positive definite) the Delassus operator, the QP of
//! [`crate::contact`] is equivalent to the mixed (box) linear complementarity problem
//!
//! y = y* + W λ,  lo ≤ y ≤ hi,  λ_i ≥ 0 if y_i = lo_i,  λ_i ≤ 0 if y_i = hi_i,  λ_i = 0 otherwise,
//!
//! and, equivalently, to the strictly convex box QP min ½ (y − y*)ᵀ W⁻¹ (y − y*) over lo ≤ y ≤ hi,
//! whose gradient is λ. Its solution is unique.
//!
//! [`ActiveSetSolver`] solves it by the primal–dual active-set method, which is a semismooth Newton
//! method on the complementarity function λ − max(0, λ + c (lo − y)) − min(0, λ + c (hi − y))
//! (Hintermüller, Ito, Kunisch, *The primal–dual active set strategy as a semismooth Newton method*,
//! SIAM J. Optim. 13(3), 2003): on a working set 𝒜 it solves W_𝒜𝒜 λ_𝒜 = bound_𝒜 − y*_𝒜 (a
//! [`WorkingSetSolver`]), sets λ = 0 off 𝒜, and moves to 𝒜 the indices whose y violates a bound and
//! out of 𝒜 those whose λ has the wrong sign. When the set repeats, the KKT conditions hold and the
//! answer is the exact solution of a linear system: a finite identification, then a direct solve.
//!
//! PDAS converges from any start when W is an M-matrix, and locally superlinearly (in a finite number
//! of steps near the solution) in general, but it can cycle for other SPD W. Cycling is detected
//! (a working set seen before that is not the current one). The safeguard is then the primal
//! active-set method for convex QP (Nocedal, Wright, *Numerical Optimization*, 2nd ed., Algorithm
//! 16.3) applied to the y-space QP above: feasible iterates, a strictly decreasing objective under
//! non-degeneracy, hence finite termination. Its equality-constrained subproblem is the same solve
//! on W_𝒜𝒜, so it needs nothing more from W. If it too fails (iteration limit), the status tells
//! the caller to fall back to [`crate::contact::clarabel`].
//!
//! The algorithm needs from W only the solution of the equality-constrained subproblem of a working
//! set, behind the [`WorkingSetSolver`] trait: [`DelassusWorkingSet`] does it with the LDLᵀ factor
//! of W_𝒜𝒜 kept up to date as indices enter and leave ([`super::block_factor`]), reading only the
//! columns of W indexed by the working set; [`super::eliminated`] does it in the primal variables
//! with the active dofs eliminated from A, which is cheaper when many vertices are in contact.

use super::block_factor::{ActiveBlockFactor, NotPositiveDefinite};
use super::{BoundState, Delassus};

/// The linear algebra of one PDAS iteration: for a working set 𝒜 (the active indices, increasing,
/// with the bound values they are held at), the multipliers and the constrained values
///
/// λ_𝒜 = W_𝒜𝒜⁻¹ (bound_𝒜 − y*_𝒜),  λ_i = 0 off 𝒜,  y = y* + W λ.
pub trait WorkingSetSolver {
    /// m, the number of constrained values.
    fn dim(&self) -> usize;
    /// Writes λ and y (length m) for the working set `active` held at `bound` (same length), and
    /// into `scale[i]` for each active i a positive number s_i with s_i ≤ W_ii: λ_i s_i bounds how
    /// far releasing index i would move y_i, which sets the tolerance of the sign test.
    fn solve(
        &mut self,
        active: &[usize],
        bound: &[f64],
        lambda: &mut [f64],
        y: &mut [f64],
        scale: &mut [f64],
    ) -> Result<(), NotPositiveDefinite>;
    /// One step of iterative refinement of the last [`WorkingSetSolver::solve`] (same set):
    /// λ_𝒜 += W_𝒜𝒜⁻¹ (bound_𝒜 − y_𝒜), then y = y* + W λ.
    fn refine(&mut self, active: &[usize], bound: &[f64], lambda: &mut [f64], y: &mut [f64]);
}

/// What [`DelassusWorkingSet`] keeps between solves: the factor of the active block and two
/// workspaces.
#[derive(Clone, Debug, Default)]
pub struct DelassusWorkspace {
    factor: ActiveBlockFactor,
    /// Right-hand side in the factor's order, then λ_𝒜.
    rhs: Vec<f64>,
    /// Bound value of each active index, by index.
    bound_of: Vec<f64>,
}

impl DelassusWorkspace {
    /// An empty workspace.
    pub fn new() -> Self {
        Self::default()
    }

    /// The factor of the active block and what it did.
    pub fn factor(&self) -> &ActiveBlockFactor {
        &self.factor
    }
}

/// [`WorkingSetSolver`] on a Delassus operator: the factor of W_𝒜𝒜 updated as the set changes,
/// y = y* + W λ from the columns of the active indices.
pub struct DelassusWorkingSet<'a, D: Delassus + ?Sized> {
    w: &'a mut D,
    y_star: &'a [f64],
    work: &'a mut DelassusWorkspace,
}

impl<'a, D: Delassus + ?Sized> DelassusWorkingSet<'a, D> {
    /// The subproblems of W with unconstrained values `y_star`, in `work` (whose factor starts
    /// empty: see [`super::delassus`] for why none is kept from an earlier step).
    pub fn new(w: &'a mut D, y_star: &'a [f64], work: &'a mut DelassusWorkspace) -> Self {
        work.factor.reset(w.dim());
        Self::keeping_factor(w, y_star, work)
    }

    /// As [`Self::new`], keeping the factor that `work` holds, which must be of a block of this
    /// same W (as after an earlier solve of the same step): a second solve of a step whose data
    /// changed at a few values starts from the active block the first one left.
    pub fn keeping_factor(
        w: &'a mut D,
        y_star: &'a [f64],
        work: &'a mut DelassusWorkspace,
    ) -> Self {
        if work.factor.dim() != w.dim() {
            work.factor.reset(w.dim());
        }
        work.bound_of.resize(w.dim(), 0.0);
        DelassusWorkingSet { w, y_star, work }
    }

    /// y = y* + Σ_j λ_j W e_j over the factor's indices.
    fn constrained_values(&mut self, lambda: &[f64], y: &mut [f64]) {
        y.copy_from_slice(self.y_star);
        self.w.add_columns(self.work.factor.order(), lambda, y);
    }
}

impl<D: Delassus + ?Sized> WorkingSetSolver for DelassusWorkingSet<'_, D> {
    fn dim(&self) -> usize {
        self.w.dim()
    }

    fn solve(
        &mut self,
        active: &[usize],
        bound: &[f64],
        lambda: &mut [f64],
        y: &mut [f64],
        scale: &mut [f64],
    ) -> Result<(), NotPositiveDefinite> {
        let work = &mut *self.work;
        work.factor.sync(self.w, active)?;
        for (&i, &b) in active.iter().zip(bound) {
            work.bound_of[i] = b;
            scale[i] = self.w.column(i)[i];
        }
        work.rhs.clear();
        let (y_star, bound_of) = (self.y_star, &work.bound_of);
        work.rhs
            .extend(work.factor.order().iter().map(|&i| bound_of[i] - y_star[i]));
        work.factor.solve_in_place(&mut work.rhs);
        lambda.fill(0.0);
        for (&i, &l) in work.factor.order().iter().zip(&work.rhs) {
            lambda[i] = l;
        }
        self.constrained_values(lambda, y);
        Ok(())
    }

    fn refine(&mut self, _active: &[usize], _bound: &[f64], lambda: &mut [f64], y: &mut [f64]) {
        let work = &mut *self.work;
        if work.factor.order().is_empty() {
            return;
        }
        work.rhs.clear();
        let bound_of = &work.bound_of;
        work.rhs
            .extend(work.factor.order().iter().map(|&i| bound_of[i] - y[i]));
        work.factor.solve_in_place(&mut work.rhs);
        for (&i, &d) in work.factor.order().iter().zip(&work.rhs) {
            lambda[i] += d;
        }
        // Recompute y from scratch rather than adding a correction: one rounding fewer.
        self.constrained_values(lambda, y);
    }
}

/// Settings of [`ActiveSetSolver::solve`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PdasSettings {
    /// Most PDAS iterations (linear solves) before giving up on PDAS.
    pub max_iter: usize,
    /// Relative tolerance of the KKT conditions. With s the gap scale (the largest finite |lo_i|,
    /// |hi_i|, |y*_i|), a free y_i may exceed a bound by tol·s, and an active λ_i may have the wrong
    /// sign by tol·s / W_ii (releasing it would move y_i by less than tol·s). Must cover the round-off
    /// of the solve, about cond(W_𝒜𝒜)·ε.
    pub tol: f64,
    /// Run the primal active-set safeguard when PDAS cycles or reaches `max_iter`.
    pub safeguard: bool,
    /// Most safeguard iterations; 0 means 10 m + 50.
    pub safeguard_max_iter: usize,
}

impl Default for PdasSettings {
    /// `max_iter` 100, `tol` 1e-11, safeguard on with the default limit.
    fn default() -> Self {
        PdasSettings {
            max_iter: 100,
            tol: 1e-11,
            safeguard: true,
            safeguard_max_iter: 0,
        }
    }
}

/// How [`ActiveSetSolver::solve`] ended. Only the two `Solved*` statuses carry a solution; on any
/// other the caller must fall back (to [`crate::contact::clarabel`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PdasStatus {
    /// PDAS identified the active set; λ and y are exact up to round-off.
    Solved,
    /// PDAS cycled or ran out of iterations, and the primal active-set safeguard found the solution.
    SolvedBySafeguard,
    /// PDAS revisited an earlier working set (W is not an M-matrix), and the safeguard was off or
    /// failed. No solution.
    Cycled,
    /// PDAS (and the safeguard, if on) reached its iteration limit. No solution.
    MaxIterations,
    /// A submatrix W_𝒜𝒜 was not numerically positive definite. No solution.
    NotPositiveDefinite,
    /// Bad data: lengths differ, lo_i > hi_i, or a NaN / infinite y*. No solution.
    InvalidInput,
}

impl PdasStatus {
    /// True when λ and y hold the solution.
    pub fn is_solved(self) -> bool {
        matches!(self, PdasStatus::Solved | PdasStatus::SolvedBySafeguard)
    }
}

/// What one [`ActiveSetSolver::solve`] did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PdasReport {
    /// The outcome.
    pub status: PdasStatus,
    /// PDAS iterations (one working-set solve each).
    pub iterations: usize,
    /// Safeguard iterations (0 when it did not run).
    pub safeguard_iterations: usize,
    /// Number of active indices at the end.
    pub active: usize,
    /// tol·s of [`PdasSettings::tol`] (the units of y): when the status is solved, every value
    /// of the answer's y lies within it of its bounds (active ones on them).
    pub bound_tolerance: f64,
}

/// The owned result of [`solve_box_lcp`].
#[derive(Clone, Debug, PartialEq)]
pub struct LcpSolution {
    /// λ, length m (valid when the status is solved).
    pub lambda: Vec<f64>,
    /// y = y* + W λ, with y_i set exactly to its bound on active indices.
    pub y: Vec<f64>,
    /// The final states.
    pub states: Vec<BoundState>,
    /// Status and iteration counts.
    pub report: PdasReport,
}

/// One-shot convenience over [`ActiveSetSolver`]: solve from the warm start `states` (all
/// [`BoundState::Free`] for a cold start) and return owned vectors.
pub fn solve_box_lcp<D: Delassus + ?Sized>(
    w: &mut D,
    y_star: &[f64],
    lower: &[f64],
    upper: &[f64],
    states: &[BoundState],
    settings: &PdasSettings,
) -> LcpSolution {
    let mut solver = ActiveSetSolver::new();
    let mut states = states.to_vec();
    let report = solver.solve(w, y_star, lower, upper, &mut states, settings);
    LcpSolution {
        lambda: solver.lambda().to_vec(),
        y: solver.y().to_vec(),
        states,
        report,
    }
}

/// The active-set solver with its reusable workspace (see the module docs). Keep one per run:
/// after the first steps `solve` allocates little unless the active set grows past its largest
/// size so far. The factor of the active block is updated within a solve only.
#[derive(Clone, Debug, Default)]
pub struct ActiveSetSolver {
    lambda: Vec<f64>,
    y: Vec<f64>,
    /// Active indices of the current working set, in increasing order.
    active: Vec<usize>,
    /// Their bound values.
    bound: Vec<f64>,
    /// The factor of W_𝒜𝒜 and workspaces used by [`ActiveSetSolver::solve`].
    delassus: DelassusWorkspace,
    /// The scale s_i ≤ W_ii of each active index (see [`WorkingSetSolver::solve`]).
    diag: Vec<f64>,
    /// Hashes of the working sets visited by PDAS in this solve.
    history: Vec<u64>,
    /// Safeguard: the feasible iterate.
    y_iter: Vec<f64>,
}

impl ActiveSetSolver {
    /// An empty workspace.
    pub fn new() -> Self {
        Self::default()
    }

    /// The factor of the active block and what it did (for benchmarks and tests).
    pub fn factor(&self) -> &ActiveBlockFactor {
        &self.delassus.factor
    }

    /// λ of the last solve (length m).
    pub fn lambda(&self) -> &[f64] {
        &self.lambda
    }

    /// y = y* + W λ of the last solve (length m), exactly on the bound at active indices.
    pub fn y(&self) -> &[f64] {
        &self.y
    }

    /// Solve the box LCP y = y* + W λ, lo ≤ y ≤ hi with complementarity (module docs) on the
    /// Delassus operator `w`, through [`DelassusWorkingSet`].
    ///
    /// `states` is the warm start on entry (the last step's active set; all
    /// [`BoundState::Free`] for a cold start) and the final active set on exit. An entry that
    /// names a missing bound (infinite) is read as free. λ and y are read with [`Self::lambda`]
    /// and [`Self::y`]; they are the solution only when the returned status
    /// [`PdasStatus::is_solved`].
    pub fn solve<D: Delassus + ?Sized>(
        &mut self,
        w: &mut D,
        y_star: &[f64],
        lower: &[f64],
        upper: &[f64],
        states: &mut [BoundState],
        settings: &PdasSettings,
    ) -> PdasReport {
        self.solve_delassus(w, y_star, [lower, upper], states, settings, false)
    }

    /// As [`Self::solve`], on the same operator `w` as the last solve, starting from the factor
    /// of the active block that solve left ([`DelassusWorkingSet::keeping_factor`]): for a solve
    /// again within one step, whose data changed at a few values only. The factor is then
    /// updated, not formed again, and it depends on nothing but the step's own data.
    pub fn solve_again<D: Delassus + ?Sized>(
        &mut self,
        w: &mut D,
        y_star: &[f64],
        lower: &[f64],
        upper: &[f64],
        states: &mut [BoundState],
        settings: &PdasSettings,
    ) -> PdasReport {
        self.solve_delassus(w, y_star, [lower, upper], states, settings, true)
    }

    /// [`Self::solve`], or [`Self::solve_again`] when `keep_factor`.
    fn solve_delassus<D: Delassus + ?Sized>(
        &mut self,
        w: &mut D,
        y_star: &[f64],
        [lower, upper]: [&[f64]; 2],
        states: &mut [BoundState],
        settings: &PdasSettings,
        keep_factor: bool,
    ) -> PdasReport {
        let mut work = std::mem::take(&mut self.delassus);
        let report = {
            let mut subproblems = if keep_factor {
                DelassusWorkingSet::keeping_factor(w, y_star, &mut work)
            } else {
                DelassusWorkingSet::new(w, y_star, &mut work)
            };
            self.solve_with(&mut subproblems, y_star, lower, upper, states, settings)
        };
        self.delassus = work;
        report
    }

    /// As [`Self::solve`], with the subproblems solved by `subproblems`, whose unconstrained
    /// values are `y_star`.
    ///
    /// Kept in one piece (~105 lines): the PDAS iteration and its refinement and safeguard
    /// hand-offs share the iterate and the report; split, each piece would return them all.
    pub fn solve_with<S: WorkingSetSolver + ?Sized>(
        &mut self,
        w: &mut S,
        y_star: &[f64],
        lower: &[f64],
        upper: &[f64],
        states: &mut [BoundState],
        settings: &PdasSettings,
    ) -> PdasReport {
        let m = w.dim();
        self.lambda.clear();
        self.lambda.resize(m, 0.0);
        self.y.clear();
        self.y.extend_from_slice(&y_star[..m.min(y_star.len())]);
        self.y.resize(m, 0.0);
        self.diag.clear();
        self.diag.resize(m, 0.0);
        self.history.clear();
        let mut report = PdasReport {
            status: PdasStatus::InvalidInput,
            iterations: 0,
            safeguard_iterations: 0,
            active: 0,
            bound_tolerance: f64::INFINITY,
        };
        if y_star.len() != m || lower.len() != m || upper.len() != m || states.len() != m {
            return report;
        }
        // The largest |y*_i|, |lower_i| and |upper_i| (finite bounds), in three running maxima:
        // the maximum of numbers that are not NaN does not depend on the order it is taken in, so
        // this is the one running maximum's value without its chain of dependent steps.
        let mut scales = [0.0_f64; 3];
        for i in 0..m {
            let (lo, hi, ys) = (lower[i], upper[i], y_star[i]);
            if !ys.is_finite() || lo.is_nan() || hi.is_nan() || lo > hi {
                return report;
            }
            if lo == f64::INFINITY || hi == f64::NEG_INFINITY {
                return report;
            }
            scales[0] = scales[0].max(ys.abs());
            if lo.is_finite() {
                scales[1] = scales[1].max(lo.abs());
            }
            if hi.is_finite() {
                scales[2] = scales[2].max(hi.abs());
            }
            // A warm-start label on a missing bound means nothing: read it as free.
            if (states[i] == BoundState::AtLower && !lo.is_finite())
                || (states[i] == BoundState::AtUpper && !hi.is_finite())
            {
                states[i] = BoundState::Free;
            }
        }
        let scale = scales[0].max(scales[1]).max(scales[2]);
        let tol_y = settings.tol * scale.max(f64::MIN_POSITIVE);
        report.bound_tolerance = tol_y;

        // PDAS proper.
        let mut hash = hash_states(states);
        self.history.push(hash);
        let mut fell_back = PdasStatus::MaxIterations;
        while report.iterations < settings.max_iter {
            report.iterations += 1;
            if self.solve_working_set(w, lower, upper, states).is_err() {
                report.status = PdasStatus::NotPositiveDefinite;
                return report;
            }
            let mut changed = self.update_set(lower, upper, states, tol_y);
            if !changed {
                // Identified: refine λ once against round-off, then confirm.
                self.refine(w);
                changed = self.update_set(lower, upper, states, tol_y);
                if !changed {
                    self.snap_to_bounds(lower, upper, states);
                    report.status = PdasStatus::Solved;
                    report.active = self.active.len();
                    return report;
                }
            }
            hash = hash_states(states);
            if self.history.contains(&hash) {
                fell_back = PdasStatus::Cycled;
                break;
            }
            self.history.push(hash);
        }
        report.status = fell_back;
        if !settings.safeguard {
            return report;
        }
        let limit = if settings.safeguard_max_iter == 0 {
            10 * m + 50
        } else {
            settings.safeguard_max_iter
        };
        match self.primal_active_set(w, y_star, lower, upper, states, tol_y, limit) {
            (Some(status), it) => {
                report.safeguard_iterations = it;
                if status == PdasStatus::SolvedBySafeguard {
                    report.active = self.active.len();
                    report.status = status;
                } else if status == PdasStatus::NotPositiveDefinite {
                    report.status = status;
                }
            }
            (None, it) => report.safeguard_iterations = it,
        }
        report
    }

    /// For the working set `states`: λ_𝒜 = W_𝒜𝒜⁻¹ (bound_𝒜 − y*_𝒜), λ = 0 elsewhere,
    /// y = y* + W λ (by `w`).
    fn solve_working_set<S: WorkingSetSolver + ?Sized>(
        &mut self,
        w: &mut S,
        lower: &[f64],
        upper: &[f64],
        states: &[BoundState],
    ) -> Result<(), NotPositiveDefinite> {
        self.active.clear();
        self.bound.clear();
        for (i, s) in states.iter().enumerate() {
            match s {
                BoundState::Free => {}
                BoundState::AtLower => {
                    self.active.push(i);
                    self.bound.push(lower[i]);
                }
                BoundState::AtUpper => {
                    self.active.push(i);
                    self.bound.push(upper[i]);
                }
            }
        }
        w.solve(
            &self.active,
            &self.bound,
            &mut self.lambda,
            &mut self.y,
            &mut self.diag,
        )
    }

    /// One step of iterative refinement of λ_𝒜 on the current working set.
    fn refine<S: WorkingSetSolver + ?Sized>(&mut self, w: &mut S) {
        w.refine(&self.active, &self.bound, &mut self.lambda, &mut self.y);
    }

    /// The PDAS update (c → 0⁺ in the complementarity function): a free index whose y leaves the
    /// box enters at the bound it crossed; an active index whose λ has the wrong sign leaves.
    /// Returns whether the set changed.
    fn update_set(
        &self,
        lower: &[f64],
        upper: &[f64],
        states: &mut [BoundState],
        tol_y: f64,
    ) -> bool {
        let mut changed = false;
        for i in 0..states.len() {
            let next = match states[i] {
                BoundState::Free => {
                    if self.y[i] < lower[i] - tol_y {
                        BoundState::AtLower
                    } else if self.y[i] > upper[i] + tol_y {
                        BoundState::AtUpper
                    } else {
                        BoundState::Free
                    }
                }
                BoundState::AtLower => {
                    if self.lambda[i] * self.diag[i] < -tol_y {
                        BoundState::Free
                    } else {
                        BoundState::AtLower
                    }
                }
                BoundState::AtUpper => {
                    if self.lambda[i] * self.diag[i] > tol_y {
                        BoundState::Free
                    } else {
                        BoundState::AtUpper
                    }
                }
            };
            if next != states[i] {
                states[i] = next;
                changed = true;
            }
        }
        changed
    }

    fn snap_to_bounds(&mut self, lower: &[f64], upper: &[f64], states: &[BoundState]) {
        for (i, s) in states.iter().enumerate() {
            match s {
                BoundState::Free => {}
                BoundState::AtLower => self.y[i] = lower[i],
                BoundState::AtUpper => self.y[i] = upper[i],
            }
        }
    }

    /// The safeguard: primal active set method on min ½ (y − y*)ᵀ W⁻¹ (y − y*), lo ≤ y ≤ hi,
    /// from y = clip(y*). Returns the status (`None`: iteration limit) and the iteration count.
    ///
    /// Kept in one piece (~110 lines): the textbook loop (subproblem step, multiplier test,
    /// blocking bound) shares the working set, the step and the iterate across its phases.
    #[allow(clippy::too_many_arguments)]
    fn primal_active_set<S: WorkingSetSolver + ?Sized>(
        &mut self,
        w: &mut S,
        y_star: &[f64],
        lower: &[f64],
        upper: &[f64],
        states: &mut [BoundState],
        tol_y: f64,
        limit: usize,
    ) -> (Option<PdasStatus>, usize) {
        let m = y_star.len();
        // Feasible start, the working set made of the bounds it sits on.
        self.y_iter.clear();
        for i in 0..m {
            let yi = y_star[i].clamp(lower[i], upper[i]);
            states[i] = if yi == lower[i] && y_star[i] < lower[i] {
                BoundState::AtLower
            } else if yi == upper[i] && y_star[i] > upper[i] {
                BoundState::AtUpper
            } else {
                BoundState::Free
            };
            self.y_iter.push(yi);
        }
        let mut it = 0;
        while it < limit {
            it += 1;
            if self.solve_working_set(w, lower, upper, states).is_err() {
                return (Some(PdasStatus::NotPositiveDefinite), it);
            }
            // Step p = ŷ − y on the free indices (p = 0 on the working set).
            let mut step = 0.0_f64;
            for (i, s) in states.iter().enumerate() {
                if *s == BoundState::Free {
                    step = step.max((self.y[i] - self.y_iter[i]).abs());
                }
            }
            if step <= tol_y {
                // At the subproblem minimiser: optimal unless some multiplier has the wrong sign.
                self.refine(w);
                let mut worst = None;
                let mut worst_val = tol_y;
                for &i in &self.active {
                    let v = match states[i] {
                        BoundState::AtLower => -self.lambda[i] * self.diag[i],
                        BoundState::AtUpper => self.lambda[i] * self.diag[i],
                        BoundState::Free => 0.0,
                    };
                    if v > worst_val {
                        worst_val = v;
                        worst = Some(i);
                    }
                }
                let feasible = (0..m).all(|i| {
                    states[i] != BoundState::Free
                        || (self.y[i] >= lower[i] - tol_y && self.y[i] <= upper[i] + tol_y)
                });
                match worst {
                    None if feasible => {
                        self.snap_to_bounds(lower, upper, states);
                        return (Some(PdasStatus::SolvedBySafeguard), it);
                    }
                    None => {}
                    Some(i) => states[i] = BoundState::Free,
                }
                for i in 0..m {
                    self.y_iter[i] = self.y[i].clamp(lower[i], upper[i]);
                }
                continue;
            }
            // Longest feasible step along p, and the bound that blocks it.
            let mut alpha = 1.0_f64;
            let mut blocking = None;
            for i in 0..m {
                if states[i] != BoundState::Free {
                    continue;
                }
                let p = self.y[i] - self.y_iter[i];
                let (a, s) = if p < 0.0 && lower[i].is_finite() {
                    (
                        ((lower[i] - self.y_iter[i]) / p).max(0.0),
                        BoundState::AtLower,
                    )
                } else if p > 0.0 && upper[i].is_finite() {
                    (
                        ((upper[i] - self.y_iter[i]) / p).max(0.0),
                        BoundState::AtUpper,
                    )
                } else {
                    continue;
                };
                if a < alpha {
                    alpha = a;
                    blocking = Some((i, s));
                }
            }
            for i in 0..m {
                let p = self.y[i] - self.y_iter[i];
                self.y_iter[i] = (self.y_iter[i] + alpha * p).clamp(lower[i], upper[i]);
            }
            if let Some((i, s)) = blocking {
                states[i] = s;
                self.y_iter[i] = if s == BoundState::AtLower {
                    lower[i]
                } else {
                    upper[i]
                };
            }
        }
        (None, it)
    }
}

/// FNV-1a over the states: identifies a working set for cycle detection. A collision can only
/// cause a premature fallback, never a wrong answer.
fn hash_states(states: &[BoundState]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for s in states {
        h ^= *s as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::DenseDelassus;

    #[test]
    fn one_contact_by_hand() {
        // W = [[2, 1], [1, 2]], y* = [-1, 0.5], lo = [0, -inf], hi = [inf, 1]:
        // λ_0 = 1/2, y = [0, 1].
        let mut w = DenseDelassus::new(2, vec![2.0, 1.0, 1.0, 2.0]);
        let sol = solve_box_lcp(
            &mut w,
            &[-1.0, 0.5],
            &[0.0, f64::NEG_INFINITY],
            &[f64::INFINITY, 1.0],
            &[BoundState::Free; 2],
            &PdasSettings::default(),
        );
        assert_eq!(sol.report.status, PdasStatus::Solved);
        assert!((sol.lambda[0] - 0.5).abs() < 1e-15 && sol.lambda[1] == 0.0);
        assert_eq!(sol.states, [BoundState::AtLower, BoundState::Free]);
        assert!((sol.y[1] - 1.0).abs() < 1e-15);
    }
}
