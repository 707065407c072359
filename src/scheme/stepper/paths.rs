//! The paths of a step's contact solve: the decision ([`Stepper::route`]) and one function per
//! path, each leaving u_{n+1} in the next level and the contact states in the trial states.

use super::guards::ACTIVE_SET_BOUND_TOLERANCE;
use super::{StepInput, StepPath, Stepper, RESTORE_BOUND_TOLERANCE};
use crate::contact::{BoxQp, PdasReport};
use crate::error::Error;
use crate::scene::QpChoice;
use crate::scheme::backend::StepForcing;
use crate::scheme::impact::{newton_bounds, Law, VertexMotion};
use crate::scheme::reference::solve_reference;

/// How a step finds u_{n+1}, decided once per step by [`Stepper::route`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Route {
    /// No constraint, or the backend's cheap test proved the prediction within the obstacles
    /// (`solver.qp = auto` only): the bounds were not evaluated and the prediction is u_{n+1}.
    Screened,
    /// The prediction, evaluated at every constrained vertex, satisfies its bounds
    /// (`solver.qp = auto` only): it is u_{n+1}.
    Checked,
    /// `solver.qp = clarabel`: clarabel solves every step that is not screened.
    Clarabel,
    /// The prediction crosses a bound: the active-set method, with clarabel as the fallback.
    ActiveSet,
}

impl Route {
    /// Whether the step's constrained values were evaluated in full.
    pub(super) fn bounds_evaluated(self) -> bool {
        self != Route::Screened
    }
}

/// The answer of a step's path.
pub(super) struct Solved {
    pub(super) path: StepPath,
    /// The QP multipliers μ of the contact solve; `None` when the prediction is u_{n+1}.
    pub(super) multipliers: Option<Vec<f64>>,
    /// Why the answer is less exact than the normal path's, if it is.
    pub(super) warning: Option<String>,
}

impl Solved {
    /// The prediction is u_{n+1}.
    pub(super) fn unconstrained() -> Solved {
        Solved {
            path: StepPath::Unconstrained,
            multipliers: None,
            warning: None,
        }
    }
}

impl Stepper {
    /// Decides the step's path from the prediction in the next level. Unless the prediction is
    /// screened, evaluates it at the constrained vertices into `prediction` and sets this step's
    /// bounds in `lower` and `upper`: the obstacles, or Newton's law where the prediction crosses
    /// one.
    pub(super) fn route(&mut self, input: &StepInput) -> Route {
        let auto = self.scene.solver.qp == QpChoice::Auto;
        let [lower, upper] = input.obstacles;
        // A prediction within the obstacles closes no contact, so it satisfies the bounds of
        // either impact law.
        if self.prediction.is_empty()
            || (auto
                && self
                    .backend
                    .prediction_proven_within(&self.levels.next, lower, upper))
        {
            return Route::Screened;
        }
        // Newton's law reads the exact prediction of every vertex, clarabel none of it; the
        // active-set method on the position law solves from stand-ins where they are proven
        // inside (see `LinearBackend::prediction_values`).
        if auto && self.law == Law::Position {
            self.backend
                .prediction_values(&self.levels.next, lower, upper, &mut self.prediction);
        } else {
            self.backend
                .constrained_values(&self.levels.next, &mut self.prediction);
        }
        self.lower.fill(lower);
        self.upper.fill(upper);
        let feasible = self.prediction.iter().all(|&w| w >= lower && w <= upper);
        // Newton's law changes only the bounds of vertices whose prediction crosses an
        // obstacle: a step without any keeps the obstacles' bounds and costs nothing more.
        if let (false, Law::Newton(e)) = (feasible, self.law) {
            self.apply_newton_law(e, input.base_next);
        }
        match (auto, feasible) {
            (false, _) => Route::Clarabel,
            (true, true) => Route::Checked,
            (true, false) => Route::ActiveSet,
        }
    }

    /// Newton's law with restitution e as the bounds on w_{n+1} at the constrained vertices, from
    /// the prediction in `self.prediction`: [`newton_bounds`] with every position measured from the
    /// base level z_{n+1} (u − z_{n+1}: the obstacles stay at rest in that frame, so the velocities
    /// are those relative to the obstacles), which makes its test of a crossing prediction the very
    /// test w* < g1 − z_{n+1} that decided this step needs a QP. At the start step both stored
    /// levels are w_0 and both base values z_0 (released at rest, v_0 = 0): no vertex approaches,
    /// and u_1 is bounded by the obstacles, as under the position law.
    fn apply_newton_law(&mut self, e: f64, base_next: f64) {
        let lower = self.scene.lower_obstacle().map(|g| g - base_next);
        let upper = self.scene.upper_obstacle().map(|g| g - base_next);
        let [z_prev, z_curr] = self.base.map(|z| z - base_next);
        let (previous, current) =
            self.history
                .values(&*self.backend, &self.levels.previous, &self.levels.current);
        for i in 0..self.prediction.len() {
            let motion = VertexMotion {
                previous: z_prev + previous[i],
                current: z_curr + current[i],
                predicted: self.prediction[i],
            };
            [self.lower[i], self.upper[i]] = newton_bounds(e, lower, upper, motion);
        }
    }

    /// [`Route::Clarabel`]: clarabel solves the step, and its answer is checked.
    pub(super) fn clarabel_path(&mut self, input: &StepInput) -> Result<Solved, Error> {
        let (mu, warning) = self.solve_with_clarabel(&input.forcing)?;
        self.check_clarabel_answer(input)?;
        Ok(Solved {
            path: StepPath::Clarabel,
            multipliers: Some(mu),
            warning,
        })
    }

    /// [`Route::ActiveSet`]: the active-set method, whose answer is accepted when it converged
    /// and lies within its bounds to [`ACTIVE_SET_BOUND_TOLERANCE`] of the gap; otherwise
    /// [`Stepper::fallback_path`].
    pub(super) fn active_set_path(&mut self, input: &StepInput) -> Result<Solved, Error> {
        let tolerance = ACTIVE_SET_BOUND_TOLERANCE * self.scene.gap();
        let failure = match self.solve_with_active_set()? {
            // The method's own test keeps its y within `solved_within` of the bounds, and the
            // field's constrained values agree with its y to round-off far below that (about 3nε
            // of the same scale, against its tol = 1e-11): when `solved_within` is below the
            // tolerance, the check's O(mn) product (modal backend) is not needed. It is above
            // when the data's scale is over 100 times the gap's, as at the huge loads whose
            // answer may be garbage.
            Ok((mu, solved_within)) if solved_within <= tolerance => return Ok(active_set(mu)),
            Ok((mu, _)) => match self.first_past_bound(tolerance) {
                None => return Ok(active_set(mu)),
                Some(past) => format!(
                    "the active-set method reported a solution with {}",
                    past.describe(tolerance)
                ),
            },
            Err(report) => format!(
                "the active-set method did not converge ({:?} after {} iterations and {} \
                 safeguard iterations)",
                report.status, report.iterations, report.safeguard_iterations
            ),
        };
        self.fallback_path(input, failure)
    }

    /// Clarabel solves a step the active-set method failed for `reason`, with a warning saying
    /// so; its answer is checked.
    fn fallback_path(&mut self, input: &StepInput, reason: String) -> Result<Solved, Error> {
        let t_next = input.t_next;
        let (mu, polish_warning) = self.solve_with_clarabel(&input.forcing).map_err(|e| {
            Error::ContactSolver(format!(
                "at t = {t_next} s (base displacement {:e} m, load.pressure {:e} Pa) {reason}, \
                 and the clarabel fallback failed too ({e}): the step is refused and the state \
                 stays at t = {} s",
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
        self.check_clarabel_answer(input)?;
        Ok(Solved {
            path: StepPath::ClarabelFallback,
            multipliers: Some(mu),
            warning,
        })
    }

    /// Clarabel's answer is checked too (the active-set one was, to a tighter tolerance): no step
    /// is accepted with a vertex past its bounds by more than a restored state may be
    /// ([`RESTORE_BOUND_TOLERANCE`]).
    fn check_clarabel_answer(&mut self, input: &StepInput) -> Result<(), Error> {
        let tolerance = RESTORE_BOUND_TOLERANCE * self.scene.gap();
        match self.first_past_bound(tolerance) {
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

    /// The backend's exact active-set method, warm-started from the last step's contact states,
    /// into the trial states and the next level: the multipliers and the report's
    /// [`PdasReport::bound_tolerance`], or the report when it does not converge (the caller falls
    /// back to clarabel).
    fn solve_with_active_set(&mut self) -> Result<Result<(Vec<f64>, f64), PdasReport>, Error> {
        self.trial_states.copy_from_slice(&self.states);
        let report = self.backend.solve_contact(
            &mut self.levels.next,
            &self.prediction,
            &self.lower,
            &self.upper,
            &mut self.trial_states,
            &self.active_set_settings,
        )?;
        Ok(if report.status.is_solved() {
            Ok((
                self.backend.contact_multipliers().to_vec(),
                report.bound_tolerance,
            ))
        } else {
            Err(report)
        })
    }

    /// clarabel on the full primal QP min ½wᵀAw − bᵀw over the box, into the trial states;
    /// returns the multipliers, and a warning when the answer could not be polished.
    fn solve_with_clarabel(
        &mut self,
        forcing: &StepForcing,
    ) -> Result<(Vec<f64>, Option<String>), Error> {
        let free = &*self.free;
        let mut b = vec![0.0; free.load.len()];
        free.right_hand_side(
            forcing,
            &self.backend.to_free_dofs(&self.levels.previous),
            &self.backend.to_free_dofs(&self.levels.current),
            &mut b,
        );
        let (solution, warning) = solve_reference(&BoxQp {
            a: free.system_matrix(forcing.start).as_ref(),
            b: &b,
            constrained: &free.constrained,
            lower: &self.lower,
            upper: &self.upper,
        })?;
        self.backend
            .field_of_free_dofs(&solution.x, &mut self.levels.next);
        self.trial_states = solution.states;
        Ok((solution.lambda, warning))
    }
}

/// The active-set method's answer with multipliers `mu`.
fn active_set(mu: Vec<f64>) -> Solved {
    Solved {
        path: StepPath::ActiveSet,
        multipliers: Some(mu),
        warning: None,
    }
}
