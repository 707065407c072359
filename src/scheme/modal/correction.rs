//! The modal contact solve: the active-set method on the precomputed Delassus operator
//! W = C D⁻¹ Cᵀ from the prediction's values (on a large basis from a first guess of the active
//! set, [`crate::contact::first_guess`]), repeated while its answer reaches a stand-in
//! ([`StandIns::reached`](super::stand_ins::StandIns::reached)), then the
//! correction q_{n+1} = q* + D⁻¹Cᵀμ and the multipliers' work μᵀC(q_{n+1} − q_{n−1}) from it.

use super::{Corrected, Valued};
use crate::contact::first_guess::FirstGuess;
use crate::contact::{ActiveSetSolver, BoundState, PdasReport, PdasSettings};

/// The contact solve's workspace and the active-set method, whose factor of the active block
/// carries over from step to step.
#[derive(Clone, Debug)]
pub(super) struct Corrector {
    /// The contact solve's y*: the values handed to it, with the stand-ins it reached replaced
    /// by the exact values.
    y_star: Vec<f64>,
    /// q* = the prediction, kept by a solve that corrected it (then q_{n+1} − q* = D⁻¹Cᵀμ).
    unconstrained: Vec<f64>,
    /// The active-set method on W, with the factor of its active block.
    active_set: ActiveSetSolver,
    /// The first guess of the active set (large bases).
    first_guess: FirstGuess,
}

impl Corrector {
    /// The workspace of `m` constrained vertices and `n` modes.
    pub(super) fn new(m: usize, n: usize) -> Corrector {
        Corrector {
            y_star: Vec::with_capacity(m),
            unconstrained: vec![0.0; n],
            active_set: ActiveSetSolver::new(),
            first_guess: FirstGuess::new(),
        }
    }
}

impl<'a> Valued<'a> {
    /// Solves the step's QP from the prediction `next` = q* whose constrained values (with
    /// stand-ins) are `values`: the active-set method on the precomputed W, then
    /// q_{n+1} = q* + D⁻¹Cᵀμ, a sum over the active columns of D⁻¹Cᵀ, written into `next`.
    /// Returns the report and, when it [is solved](crate::contact::PdasStatus::is_solved), the
    /// corrected stage; otherwise `next` is unchanged.
    pub(in crate::scheme) fn solve(
        self,
        next: &mut [f64],
        values: &[f64],
        lower: &[f64],
        upper: &[f64],
        states: &mut [BoundState],
        settings: &PdasSettings,
    ) -> (PdasReport, Option<Corrected<'a>>) {
        let Valued { step, stand_ins } = self;
        let system = step.data.system(step.start);
        let Corrector {
            y_star,
            unconstrained,
            active_set,
            first_guess,
        } = &mut *step.corrector;
        y_star.clear();
        y_star.extend_from_slice(values);
        // A large basis starts the method from a first guess of the active set instead of the
        // last step's, and solves again from the factor its first solve left; a small basis
        // keeps its bits.
        let large = step.data.remainder.is_some();
        if large {
            first_guess.guess(&mut &system.delassus, y_star, lower, upper, states);
        }
        let mut again = false;
        let report = loop {
            let solve = if again && large {
                ActiveSetSolver::solve_again
            } else {
                ActiveSetSolver::solve
            };
            again = true;
            let report = solve(
                active_set,
                &mut &system.delassus,
                y_star,
                lower,
                upper,
                states,
                settings,
            );
            if !(report.status.is_solved()
                && stand_ins
                && step.screening.stand_ins.reached(
                    step.data,
                    next,
                    active_set.y(),
                    [lower, upper],
                    states,
                    y_star,
                ))
            {
                break report;
            }
        };
        if !report.status.is_solved() {
            return (report, None);
        }
        unconstrained.copy_from_slice(next);
        let multipliers = active_set.lambda();
        let active = states
            .iter()
            .enumerate()
            .filter(|(_, s)| s.is_active())
            .map(|(i, _)| i);
        let contiguous = |column: faer::ColRef<'a, f64>| {
            column
                .try_as_col_major()
                .expect("owned matrices are column-major")
                .as_slice()
        };
        match &system.c_t_scaled {
            Some(scaled) => add_columns(
                next,
                active.map(|i| (multipliers[i], contiguous(scaled.col(i)))),
                None,
            ),
            None => add_columns(
                next,
                active.map(|i| (multipliers[i], contiguous(step.data.c_rows.col(i)))),
                Some(&system.inverse_d),
            ),
        }
        (report, Some(Corrected { step, stand_ins }))
    }
}

impl<'a> Corrected<'a> {
    /// Back to the stage before the solve, to solve again with other bounds: q* into `next`,
    /// and into `values` the solve's y* (the values it started from, with the stand-ins it
    /// reached replaced by exact values, as the screening now marks them).
    pub(in crate::scheme) fn retry(self, next: &mut [f64], values: &mut [f64]) -> Valued<'a> {
        let Corrected { step, stand_ins } = self;
        next.copy_from_slice(&step.corrector.unconstrained);
        values.copy_from_slice(&step.corrector.y_star);
        Valued { step, stand_ins }
    }

    /// The multipliers μ (length m) of the solve.
    pub(in crate::scheme) fn multipliers(&self) -> &[f64] {
        self.step.corrector.active_set.lambda()
    }

    /// μᵀC(x − y) with x = `next` = q_{n+1} of the solve and y = `previous`:
    /// (Cᵀμ)ᵀ(x − y) = Σ_k d_k (q_{n+1} − q*)_k (x − y)_k, one contiguous pass, which uses up q*.
    pub(in crate::scheme) fn work(self, next: &[f64], previous: &[f64]) -> f64 {
        let step = self.step;
        let d = &step.data.system(step.start).d;
        let unconstrained = &mut step.corrector.unconstrained;
        // Cᵀμ = D(q_{n+1} − q*), formed in place of q*.
        for ((star, &x), &d) in unconstrained.iter_mut().zip(next).zip(d) {
            *star = d * (x - *star);
        }
        let scaled = faer::ColRef::from_slice(unconstrained).transpose();
        scaled * faer::ColRef::from_slice(next) - scaled * faer::ColRef::from_slice(previous)
    }
}

/// q += Σ μ_i s ⊙ c_i over the pairs (μ_i, c_i), s = `scale` (1 when `None`), four columns per
/// pass over q: each q_k receives the same additions in the same order as one pass per column
/// would give it (Rust contracts no a + b·c into a fused multiply-add), so without a scale q is
/// bit-identical to it, with a quarter of the loads and stores of q.
fn add_columns<'c>(
    q: &mut [f64],
    mut columns: impl Iterator<Item = (f64, &'c [f64])>,
    scale: Option<&[f64]>,
) {
    loop {
        match [
            columns.next(),
            columns.next(),
            columns.next(),
            columns.next(),
        ] {
            [Some((m0, c0)), Some((m1, c1)), Some((m2, c2)), Some((m3, c3))] => {
                let columns = c0.iter().zip(c1).zip(c2.iter().zip(c3));
                match scale {
                    None => {
                        for (q, ((&a, &b), (&c, &d))) in q.iter_mut().zip(columns) {
                            *q = *q + m0 * a + m1 * b + m2 * c + m3 * d;
                        }
                    }
                    Some(s) => {
                        for ((q, &s), ((&a, &b), (&c, &d))) in q.iter_mut().zip(s).zip(columns) {
                            *q += s * (m0 * a + m1 * b + m2 * c + m3 * d);
                        }
                    }
                }
            }
            rest => {
                for (m, c) in rest.into_iter().flatten() {
                    match scale {
                        None => q.iter_mut().zip(c).for_each(|(q, &c)| *q += m * c),
                        Some(s) => q
                            .iter_mut()
                            .zip(c.iter().zip(s))
                            .for_each(|(q, (&c, &s))| *q += s * (m * c)),
                    }
                }
                return;
            }
        }
    }
}
