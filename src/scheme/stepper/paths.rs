//! The paths of a step's contact solve: the decision ([`Run::route`]) and one function per
//! path, each leaving u_{n+1} in the next level and the contact states in the trial states.

use super::guards::ACTIVE_SET_BOUND_TOLERANCE;
use super::workspace::Trial;
use super::{Run, StepInput, StepPath, RESTORE_BOUND_TOLERANCE};
use crate::contact::BoxQp;
use crate::error::Error;
use crate::scene::{ObstacleSide, QpChoice};
use crate::scheme::backend::{Correction, Prediction, Screened, Solve, StepFields, Values};
use crate::scheme::free_system::StepForcing;
use crate::scheme::impact::{
    newton_bounds, persistent_lower_bound, persistent_upper_bound, Law, VertexHistory, VertexMotion,
};
use crate::scheme::reference::solve_reference;

/// How a step finds u_{n+1}, decided once per step by [`Run::route`], with the stage the
/// decision leaves the step in.
pub(super) enum Route<'a> {
    /// No constraint, or the backend's cheap test proved the prediction within the obstacles
    /// (`solver.qp = auto` only): the bounds were not evaluated and the prediction is u_{n+1}.
    Screened(StepFields<'a>),
    /// The prediction, evaluated at every constrained vertex, satisfies its bounds
    /// (`solver.qp = auto` only): it is u_{n+1}.
    Checked(Values<'a>),
    /// `solver.qp = clarabel`: clarabel solves every step that is not screened.
    Clarabel(Values<'a>),
    /// The prediction crosses a bound: the active-set method, with clarabel as the fallback.
    ActiveSet(Values<'a>),
}

/// Where a step's u_{n+1} came from, with the fields it is in: what the close of the step needs.
pub(super) enum Answer<'a> {
    /// The prediction, without contact forces.
    Prediction(StepFields<'a>),
    /// The backend's correction of the prediction by its contact solve.
    Corrected(Correction<'a>),
    /// clarabel's answer, written into the next level, with its multipliers μ.
    Replaced(StepFields<'a>, Vec<f64>),
}

impl<'a> Answer<'a> {
    /// The step's fields and maps.
    pub(super) fn fields(&self) -> &StepFields<'a> {
        match self {
            Answer::Prediction(fields) | Answer::Replaced(fields, _) => fields,
            Answer::Corrected(correction) => correction.fields(),
        }
    }

    /// The QP multipliers μ of the contact solve; `None` when the prediction is u_{n+1}.
    pub(super) fn multipliers(&self) -> Option<&[f64]> {
        match self {
            Answer::Prediction(_) => None,
            Answer::Corrected(correction) => Some(correction.multipliers()),
            Answer::Replaced(_, multipliers) => Some(multipliers),
        }
    }

    /// μᵀB(w_{n+1} − w_{n−1}), the multipliers' work on the relative motion (used up once), or
    /// `None` without multipliers.
    pub(super) fn work(self) -> Option<f64> {
        match self {
            Answer::Prediction(_) => None,
            Answer::Corrected(correction) => Some(correction.work()),
            Answer::Replaced(fields, multipliers) => Some(fields.maps.multiplier_work(
                fields.next,
                fields.previous,
                &multipliers,
            )),
        }
    }
}

/// The answer of a step's path.
pub(super) struct Solved<'a> {
    pub(super) path: StepPath,
    /// Why the answer is less exact than the normal path's, if it is.
    pub(super) warning: Option<String>,
    pub(super) answer: Answer<'a>,
    /// How many times the contact solve ran again after the persistent law bounded vertices
    /// that the solve had put on an obstacle ([`Run::bound_new_contacts`]).
    pub(super) resolves: u32,
}

impl<'a> Solved<'a> {
    /// The prediction is u_{n+1}.
    pub(super) fn unconstrained(fields: StepFields<'a>) -> Solved<'a> {
        Solved {
            path: StepPath::Unconstrained,
            warning: None,
            answer: Answer::Prediction(fields),
            resolves: 0,
        }
    }
}

impl Run {
    /// Decides the step's path from its prediction. Unless the prediction is screened, evaluates
    /// it at the constrained vertices into `values` and sets this step's bounds in the trial's
    /// `lower` and `upper`: the obstacles, or the impact law's bounds where the prediction
    /// crosses one.
    pub(super) fn route<'a>(
        &self,
        input: &StepInput,
        prediction: Prediction<'a>,
        values: &'a mut [f64],
        history: &mut VertexHistory,
        trial: &mut Trial,
    ) -> Route<'a> {
        let auto = self.scene.solver.qp == QpChoice::Auto;
        let bounds = self.bounds(input);
        // A prediction within the obstacles closes no contact, so it satisfies the bounds of
        // either impact law.
        if values.is_empty() {
            return Route::Screened(prediction.keep());
        }
        let values = if auto {
            match prediction.screen(bounds) {
                Screened::Proven(fields) => return Route::Screened(fields),
                // The active-set method on the position law solves from stand-ins, which the
                // solve settles where its answer reaches them (`Unproven::solve_values`); the
                // persistent law bounds the vertices the prediction takes past an obstacle, so
                // its stand-ins are proven inside (`Unproven::values`); Newton's law reads the
                // exact prediction of every vertex.
                Screened::Unproven(unproven) => match self.law {
                    Law::Position => unproven.solve_values(values, bounds),
                    Law::Persistent(_) => unproven.values(values, bounds),
                    Law::Newton(_) => unproven.exact_values(values),
                },
            }
        } else {
            prediction.exact_values(values)
        };
        for (i, (lower, upper)) in trial.lower.iter_mut().zip(&mut trial.upper).enumerate() {
            (*lower, *upper) = (bounds.lower(i), bounds.upper(i));
        }
        let feasible = values
            .values()
            .iter()
            .enumerate()
            .all(|(i, &w)| bounds.admits(i, w));
        // The laws change only the bounds of vertices whose prediction crosses an obstacle: a
        // step without any keeps the obstacles' bounds and costs nothing more. The start step
        // keeps them under the persistent law (the plate is released at rest).
        match (feasible, self.law) {
            (false, Law::Newton(e)) => self.apply_newton_law(e, input, &values, history, trial),
            (false, Law::Persistent(e)) if !input.forcing.start => {
                let fields = values.fields();
                for (i, &w) in values.values().iter().enumerate() {
                    if w < bounds.lower(i) {
                        trial.lower[i] =
                            self.persistent_bound(e, input, fields, i, ObstacleSide::Lower);
                    } else if w > bounds.upper(i) {
                        trial.upper[i] =
                            self.persistent_bound(e, input, fields, i, ObstacleSide::Upper);
                    }
                }
            }
            _ => {}
        }
        match (auto, feasible) {
            (false, _) => Route::Clarabel(values),
            (true, true) => Route::Checked(values),
            (true, false) => Route::ActiveSet(values),
        }
    }

    /// Newton's law with restitution e as the bounds on w_{n+1} at the constrained vertices, from
    /// the prediction's exact `values`: [`newton_bounds`] with every position measured from the
    /// base level z_{n+1} (u − z_{n+1}: the obstacles stay at rest in that frame, so the velocities
    /// are those relative to the obstacles), which makes its test of a crossing prediction the very
    /// test w* < g1 − z_{n+1} that decided this step needs a QP. At the start step both stored
    /// levels are w_0 and both base values z_0 (released at rest, v_0 = 0): no vertex approaches,
    /// and u_1 is bounded by the obstacles, as under the position law.
    fn apply_newton_law(
        &self,
        e: f64,
        input: &StepInput,
        values: &Values,
        history: &mut VertexHistory,
        trial: &mut Trial,
    ) {
        let bounds = self.bounds(input);
        let [z_prev, z_curr] = self.base.map(|z| z - input.base_next);
        let fields = values.fields();
        let (previous, current) = history.values(fields.maps, fields.previous, fields.current);
        // An absent obstacle's bound is ∓∞ here.
        let present = |g: f64| g.is_finite().then_some(g);
        for (i, &predicted) in values.values().iter().enumerate() {
            let motion = VertexMotion {
                previous: z_prev + previous[i],
                current: z_curr + current[i],
                predicted,
            };
            let (lower, upper) = (present(bounds.lower(i)), present(bounds.upper(i)));
            [trial.lower[i], trial.upper[i]] = newton_bounds(e, lower, upper, motion);
        }
    }

    /// The persistent law's bound on w_{n+1} of vertex i in contact with the obstacle on `side`
    /// ([`persistent_lower_bound`], [`persistent_upper_bound`]), from w_{n−1} and w_n of `fields`
    /// at that vertex alone, every position measured from the base level z_{n+1} as in
    /// [`Run::apply_newton_law`].
    fn persistent_bound(
        &self,
        e: f64,
        input: &StepInput,
        fields: &StepFields,
        i: usize,
        side: ObstacleSide,
    ) -> f64 {
        let bounds = self.bounds(input);
        let (lower, upper) = (bounds.lower(i), bounds.upper(i));
        let [z_prev, z_curr] = self.base.map(|z| z - input.base_next);
        let previous = z_prev + fields.maps.constrained_value(fields.previous, i);
        let current = z_curr + fields.maps.constrained_value(fields.current, i);
        // A disabled obstacle's level is ∓∞ here.
        let present = |g: f64| g.is_finite().then_some(g);
        match side {
            ObstacleSide::Lower => {
                persistent_lower_bound(e, lower, present(upper), previous, current)
            }
            ObstacleSide::Upper => {
                persistent_upper_bound(e, present(lower), upper, previous, current)
            }
        }
    }

    /// After a contact solve with multipliers `mu`, under the persistent law (not at the start
    /// step): gives the law's bound to every vertex that the solve put on an obstacle's own bound
    /// with a force (it had not crossed, but the plate around it pushed it there), wherever that
    /// bound is tighter, and returns whether there was one: the solve must then run again. Each
    /// vertex is bounded by the law at most once per side, so the repetition ends. Under the
    /// other laws it returns false.
    fn bound_new_contacts(
        &self,
        input: &StepInput,
        fields: &StepFields,
        mu: &[f64],
        trial: &mut Trial,
    ) -> bool {
        let e = match self.law {
            Law::Persistent(e) if !input.forcing.start => e,
            _ => return false,
        };
        let bounds = self.bounds(input);
        let mut grew = false;
        for (i, &mu) in mu.iter().enumerate() {
            let (lower, upper) = (bounds.lower(i), bounds.upper(i));
            if mu > 0.0 && trial.lower[i] == lower {
                let bound = self.persistent_bound(e, input, fields, i, ObstacleSide::Lower);
                if bound > lower {
                    trial.lower[i] = bound;
                    grew = true;
                }
            } else if mu < 0.0 && trial.upper[i] == upper {
                let bound = self.persistent_bound(e, input, fields, i, ObstacleSide::Upper);
                if bound < upper {
                    trial.upper[i] = bound;
                    grew = true;
                }
            }
        }
        grew
    }

    /// [`Route::Clarabel`]: clarabel solves the step (again while the persistent law bounds more
    /// vertices, [`Run::bound_new_contacts`]), and its answer is checked.
    pub(super) fn clarabel_path<'a>(
        &self,
        input: &StepInput,
        mut fields: StepFields<'a>,
        trial: &mut Trial,
    ) -> Result<Solved<'a>, Error> {
        let mut resolves = 0;
        let (mu, warning) = self.clarabel_under_law(input, &mut fields, trial, &mut resolves)?;
        self.check_clarabel_answer(input, &fields, trial)?;
        Ok(Solved {
            path: StepPath::Clarabel,
            warning,
            answer: Answer::Replaced(fields, mu),
            resolves,
        })
    }

    /// [`Run::solve_with_clarabel`], again while [`Run::bound_new_contacts`] bounds more vertices,
    /// counting the repeated solves in `resolves`; the multipliers and warning of the last solve.
    fn clarabel_under_law(
        &self,
        input: &StepInput,
        fields: &mut StepFields,
        trial: &mut Trial,
        resolves: &mut u32,
    ) -> Result<(Vec<f64>, Option<String>), Error> {
        loop {
            let (mu, warning) = self.solve_with_clarabel(&input.forcing, fields, trial)?;
            if !self.bound_new_contacts(input, fields, &mu, trial) {
                return Ok((mu, warning));
            }
            *resolves += 1;
        }
    }

    /// [`Route::ActiveSet`]: the backend's exact active-set method, warm-started from the last
    /// step's contact states, whose answer is accepted when it converged and lies within its
    /// bounds to [`ACTIVE_SET_BOUND_TOLERANCE`] of the gap; otherwise
    /// [`Run::fallback_path`]. Under the persistent law it solves again, from the prediction and
    /// warm-started from its last contact states, while [`Run::bound_new_contacts`] bounds more
    /// vertices.
    pub(super) fn active_set_path<'a>(
        &self,
        input: &StepInput,
        mut values: Values<'a>,
        trial: &mut Trial,
    ) -> Result<Solved<'a>, Error> {
        let tolerance = ACTIVE_SET_BOUND_TOLERANCE * self.gap();
        trial.states.copy_from_slice(&self.states);
        let settings = &self.active_set_settings;
        let mut resolves = 0;
        let (failure, fields) = loop {
            let solve = values.solve(&trial.lower, &trial.upper, &mut trial.states, settings)?;
            let correction = match solve {
                // The method's own test keeps its y within `bound_tolerance` of the bounds, and
                // the field's constrained values agree with its y to round-off far below that
                // (about 3nε of the same scale, against its tol = 1e-11): when
                // `bound_tolerance` is below the tolerance, the check's O(mn) product (modal
                // backend) is not needed. It is above when the data's scale is over 100 times
                // the gap's, as at the huge loads whose answer may be garbage.
                Solve::Solved(correction) if correction.report().bound_tolerance <= tolerance => {
                    correction
                }
                Solve::Solved(correction) => {
                    match trial.first_past_bound(correction.fields(), tolerance) {
                        None => correction,
                        Some(past) => {
                            let reason = format!(
                                "the active-set method reported a solution with {}",
                                past.describe(tolerance)
                            );
                            break (reason, correction.reject());
                        }
                    }
                }
                Solve::Failed { report, fields } => {
                    let reason = format!(
                        "the active-set method did not converge ({:?} after {} iterations and \
                         {} safeguard iterations)",
                        report.status, report.iterations, report.safeguard_iterations
                    );
                    break (reason, fields);
                }
            };
            let (fields, mu) = (correction.fields(), correction.multipliers());
            if !self.bound_new_contacts(input, fields, mu, trial) {
                return Ok(active_set(correction, resolves));
            }
            resolves += 1;
            values = correction.retry();
        };
        self.fallback_path(input, fields, trial, failure, resolves)
    }

    /// Clarabel solves a step the active-set method failed for `reason` (after `resolves`
    /// repeated solves), with a warning saying so; its answer is checked.
    fn fallback_path<'a>(
        &self,
        input: &StepInput,
        mut fields: StepFields<'a>,
        trial: &mut Trial,
        reason: String,
        mut resolves: u32,
    ) -> Result<Solved<'a>, Error> {
        let t_next = input.t_next;
        let (mu, polish_warning) = self
            .clarabel_under_law(input, &mut fields, trial, &mut resolves)
            .map_err(|e| {
                Error::ContactSolver(format!(
                    "at t = {t_next} s (base displacement {:e} m, load.pressure {:e} Pa) {reason}, \
                     and the clarabel fallback failed too ({e}): the step is refused and the \
                     state stays at t = {} s",
                    input.base_next,
                    self.scene.load.pressure,
                    self.time()
                ))
            })?;
        let fallback = format!("at t = {t_next} s {reason}: clarabel solved the step instead");
        let warning = Some(match polish_warning {
            Some(w) => format!("{fallback}; {w}"),
            None => fallback,
        });
        self.check_clarabel_answer(input, &fields, trial)?;
        Ok(Solved {
            path: StepPath::ClarabelFallback,
            warning,
            answer: Answer::Replaced(fields, mu),
            resolves,
        })
    }

    /// Clarabel's answer is checked too (the active-set one was, to a tighter tolerance): no step
    /// is accepted with a vertex past its bounds by more than a restored state may be
    /// ([`RESTORE_BOUND_TOLERANCE`]).
    fn check_clarabel_answer(
        &self,
        input: &StepInput,
        fields: &StepFields,
        trial: &mut Trial,
    ) -> Result<(), Error> {
        let tolerance = RESTORE_BOUND_TOLERANCE * self.gap();
        match trial.first_past_bound(fields, tolerance) {
            None => Ok(()),
            Some(past) => Err(Error::ContactSolver(format!(
                "at t = {} s (base displacement {:e} m, load.pressure {:e} Pa) the contact solve \
                 left {}: the step is refused and the state stays at t = {} s",
                input.t_next,
                input.base_next,
                self.scene.load.pressure,
                past.describe(tolerance),
                self.time()
            ))),
        }
    }

    /// clarabel on the full primal QP min ½wᵀAw − bᵀw over the box of the trial's bounds, into
    /// the next level and the trial states; returns the multipliers, and a warning when the
    /// answer could not be polished.
    fn solve_with_clarabel(
        &self,
        forcing: &StepForcing,
        fields: &mut StepFields,
        trial: &mut Trial,
    ) -> Result<(Vec<f64>, Option<String>), Error> {
        let free = &*self.free;
        let mut b = vec![0.0; free.load.len()];
        free.right_hand_side(
            forcing,
            &fields.maps.to_free_dofs(fields.previous),
            &fields.maps.to_free_dofs(fields.current),
            &mut b,
        );
        let (solution, warning) = solve_reference(&BoxQp {
            a: free.system_matrix(forcing.start).as_ref(),
            b: &b,
            rows: &free.contact,
            lower: &trial.lower,
            upper: &trial.upper,
        })?;
        fields.maps.field_of_free_dofs(&solution.x, fields.next);
        trial.states = solution.states;
        Ok((solution.lambda, warning))
    }
}

/// The active-set method's answer, after `resolves` repeated solves.
fn active_set(correction: Correction, resolves: u32) -> Solved {
    Solved {
        path: StepPath::ActiveSet,
        warning: None,
        answer: Answer::Corrected(correction),
        resolves,
    }
}
