//! The time stepper: the three time levels, the forcing and bounds of each step, the contact
//! solve, and what a step reports.

use super::auto;
use super::backend::{BackendDelassus, LinearBackend, StepForcing};
use super::energy::DiscreteEnergy;
use super::outputs::Outputs;
use super::preload::static_preload;
use super::state::{state_code, state_from_code, State};
use super::FreeSystem;
use crate::contact::{self, ActiveSetSolver, BoundState, BoxQp, PdasSettings};
use crate::error::Error;
use crate::scene::{LinearChoice, QpChoice, Scene};
use crate::system::PlateSystem;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Which method produced a step's u_{n+1}.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum StepPath {
    /// The unconstrained step satisfied every bound: it is the QP's exact solution.
    Unconstrained,
    /// The primal–dual active-set method on the Delassus operator.
    ActiveSet,
    /// clarabel, because `solver.qp = clarabel`.
    Clarabel,
    /// clarabel, after the active-set method did not converge.
    ClarabelFallback,
}

/// What one step did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepReport {
    /// Vertices in contact after the step.
    pub active: usize,
    /// The solver path.
    pub path: StepPath,
    /// Whether the constrained values had to be evaluated in full: false when the backend's cheap
    /// test proved the step contact-free (the modal low-mode screening; for the sparse backend that
    /// test is itself exact), or when there is no constraint.
    pub bounds_evaluated: bool,
}

/// The fields of the three time levels, in the backend's coordinates.
#[derive(Clone, Debug)]
struct TimeLevels {
    /// w_{n−1}.
    previous: Vec<f64>,
    /// w_n.
    current: Vec<f64>,
    /// w_{n+1} while a step is being solved.
    next: Vec<f64>,
}

impl TimeLevels {
    /// Three copies of `field` (a plate at rest).
    fn at_rest(field: Vec<f64>) -> TimeLevels {
        TimeLevels {
            previous: field.clone(),
            current: field.clone(),
            next: field,
        }
    }

    /// Shifts n−1 ← n ← n+1.
    fn accept(&mut self) {
        std::mem::swap(&mut self.previous, &mut self.current);
        std::mem::swap(&mut self.current, &mut self.next);
    }
}

/// The time stepper of one scene.
pub struct Stepper {
    scene: Scene,
    free: Arc<FreeSystem>,
    backend: Box<dyn LinearBackend>,
    linear: LinearChoice,
    levels: TimeLevels,
    step_index: u64,
    base: [f64; 2],
    pressure: [f64; 2],
    /// Constrained values of w_{n−1}, kept only when restitution e > 0 needs them for the bounds.
    restitution_previous: Vec<f64>,
    /// Constrained values of w_n, likewise.
    restitution_current: Vec<f64>,
    /// The contact state of each constrained vertex: the active-set warm start.
    states: Vec<BoundState>,
    active_set: ActiveSetSolver,
    /// Contact force at each constrained vertex after the last step (N).
    forces: Vec<f64>,
    // Workspaces for the hot path.
    prediction: Vec<f64>,
    lower: Vec<f64>,
    upper: Vec<f64>,
}

impl Stepper {
    /// Assembles the plate, chooses and builds the linear backend, computes the initial state
    /// (static equilibrium under the preload, with contact if it pushes into an obstacle, about
    /// the base position `initial_base` (m)), released at rest.
    pub fn new(scene: &Scene, initial_base: f64) -> Result<Stepper, Error> {
        let plate = PlateSystem::new(scene)?;
        Stepper::from_system(scene, &plate, initial_base)
    }

    /// As [`Stepper::new`], reusing an assembled plate of the same scene.
    pub fn from_system(
        scene: &Scene,
        plate: &PlateSystem,
        initial_base: f64,
    ) -> Result<Stepper, Error> {
        scene.validate()?;
        check_base(scene, 0.0, initial_base)?;
        let free = Arc::new(FreeSystem::new(scene, plate));
        let linear = auto::resolve(scene.solver.linear, plate.free.len());
        let w0 = static_preload(scene, &free, initial_base)?;
        let backend = auto::build(linear, scene, plate, &free)?;
        let mut field = vec![0.0; backend.dimension()];
        backend.field_of_free_dofs(&w0, &mut field);
        let m = free.constrained.len();
        // The constrained values of w_0 as the backend evaluates them, so that a state restored
        // at n = 0 or 1 continues bit-identically (restore evaluates them the same way).
        let mut constrained_w0 = vec![0.0; m];
        backend.constrained_values(&field, &mut constrained_w0);
        Ok(Stepper {
            scene: scene.clone(),
            backend,
            linear,
            levels: TimeLevels::at_rest(field),
            step_index: 0,
            base: [initial_base; 2],
            pressure: [scene.load.pressure; 2],
            restitution_previous: constrained_w0.clone(),
            restitution_current: constrained_w0,
            states: vec![BoundState::Free; m],
            active_set: ActiveSetSolver::new(),
            forces: vec![0.0; m],
            prediction: vec![0.0; m],
            lower: vec![0.0; m],
            upper: vec![0.0; m],
            free,
        })
    }

    /// The scene, with tunable parameters at their current values.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The linear backend that runs (`Modal` or `Sparse`, never `Auto`).
    pub fn linear_backend(&self) -> LinearChoice {
        self.linear
    }

    /// n.
    pub fn step_index(&self) -> u64 {
        self.step_index
    }

    /// t_n = n Δt (s).
    pub fn time(&self) -> f64 {
        self.step_index as f64 * self.scene.solver.time_step
    }

    /// Number of free dofs.
    pub fn free_dof_count(&self) -> usize {
        self.backend.dimension()
    }

    /// Number of obstacle-constrained vertices (0 without obstacles).
    pub fn constrained_count(&self) -> usize {
        self.free.constrained.len()
    }

    /// Displacements u_n at the obstacle-constrained vertices (m).
    pub fn constrained_displacements(&self) -> Vec<f64> {
        let mut w = vec![0.0; self.free.constrained.len()];
        self.backend
            .constrained_values(&self.levels.current, &mut w);
        w.iter().map(|w| self.base[1] + w).collect()
    }

    /// Contact forces f_i = μ_i/Δt² at the constrained vertices after the last step (N): ≥ 0 on the
    /// lower obstacle, ≤ 0 on the upper one, 0 where the vertex is free.
    pub fn contact_forces(&self) -> &[f64] {
        &self.forces
    }

    /// Changes the obstacle levels (tunable). The base and every constrained vertex must lie
    /// within the new levels (to 1e-12 of the gap): moving an obstacle into the plate would make
    /// the next step push it out within one Δt, an arbitrary impulse, so that is refused.
    pub fn set_obstacles(&mut self, lower: f64, upper: f64) -> Result<(), Error> {
        let mut scene = self.scene.clone();
        scene.obstacle.lower = lower;
        scene.obstacle.upper = upper;
        scene.validate()?;
        check_base(&scene, self.time(), self.base[1])?;
        let tolerance = 1e-12 * (upper - lower).abs().min(1.0);
        let u = self.constrained_displacements();
        if let Some(g) = scene.lower_obstacle() {
            if let Some(v) = u.iter().find(|&&v| v < g - tolerance) {
                return Err(Error::invalid(
                    "obstacle.lower",
                    lower,
                    &format!("must not be above the plate: a vertex is at u = {v} m"),
                ));
            }
        }
        if let Some(g) = scene.upper_obstacle() {
            if let Some(v) = u.iter().find(|&&v| v > g + tolerance) {
                return Err(Error::invalid(
                    "obstacle.upper",
                    upper,
                    &format!("must not be below the plate: a vertex is at u = {v} m"),
                ));
            }
        }
        self.scene = scene;
        Ok(())
    }

    /// Changes the pressure during the motion (tunable), applied from the next step on.
    pub fn set_pressure(&mut self, pressure: f64) -> Result<(), Error> {
        if !pressure.is_finite() {
            return Err(Error::invalid("load.pressure", pressure, "must be finite"));
        }
        self.scene.load.pressure = pressure;
        Ok(())
    }

    /// Advances one step to t_{n+1}; the base displacement there is `base_next` (m), absolute.
    pub fn step(&mut self, base_next: f64) -> Result<StepReport, Error> {
        let dt = self.scene.solver.time_step;
        let t_next = (self.step_index + 1) as f64 * dt;
        check_base(&self.scene, t_next, base_next)?;
        let start = self.step_index == 0;
        let [z_prev, z_curr] = self.base;
        let p_next = self.scene.load.pressure;
        let forcing = if start {
            StepForcing {
                load: 0.25 * dt * dt * (p_next + self.pressure[1]),
                translation: -(base_next - z_curr),
                start,
            }
        } else {
            StepForcing {
                load: 0.5 * dt * dt * (p_next + self.pressure[0]),
                translation: -(base_next - 2.0 * z_curr + z_prev),
                start,
            }
        };
        let TimeLevels {
            previous,
            current,
            next,
        } = &mut self.levels;
        self.backend.predict(previous, current, &forcing, next);
        let m = self.prediction.len();
        let e = self.scene.solver.restitution;
        let auto = self.scene.solver.qp == QpChoice::Auto;
        let lower = self
            .scene
            .lower_obstacle()
            .map_or(f64::NEG_INFINITY, |g| g - base_next);
        let upper = self
            .scene
            .upper_obstacle()
            .map_or(f64::INFINITY, |g| g - base_next);
        let proven = m == 0
            || (auto
                && e == 0.0
                && self
                    .backend
                    .prediction_proven_within(&self.levels.next, lower, upper));
        let (path, multipliers) = if proven {
            (StepPath::Unconstrained, None)
        } else {
            self.backend
                .constrained_values(&self.levels.next, &mut self.prediction);
            self.fill_bounds(base_next, if start { z_curr } else { z_prev });
            let feasible = (0..m).all(|i| {
                self.prediction[i] >= self.lower[i] && self.prediction[i] <= self.upper[i]
            });
            if feasible && auto {
                (StepPath::Unconstrained, None)
            } else if !auto {
                (
                    StepPath::Clarabel,
                    Some(self.solve_with_clarabel(&forcing)?),
                )
            } else {
                match self.solve_with_active_set() {
                    Some(mu) => (StepPath::ActiveSet, Some(mu)),
                    None => (
                        StepPath::ClarabelFallback,
                        Some(self.solve_with_clarabel(&forcing)?),
                    ),
                }
            }
        };
        let active = match &multipliers {
            Some(mu) => {
                for (f, &x) in self.forces.iter_mut().zip(mu) {
                    *f = x / (dt * dt);
                }
                self.states.iter().filter(|s| s.is_active()).count()
            }
            None => {
                self.states.fill(BoundState::Free);
                self.forces.fill(0.0);
                0
            }
        };
        if e != 0.0 {
            std::mem::swap(
                &mut self.restitution_previous,
                &mut self.restitution_current,
            );
            self.backend
                .constrained_values(&self.levels.next, &mut self.restitution_current);
        }
        self.levels.accept();
        self.base = [z_curr, base_next];
        self.pressure = [self.pressure[1], p_next];
        self.step_index += 1;
        Ok(StepReport {
            active,
            path,
            bounds_evaluated: !proven,
        })
    }

    /// Bounds on w_{n+1} at the constrained vertices: [(1+e)g1 − e u_{n−1} − z_{n+1}, …] with
    /// u_{n−1} = z_{n−1} + w_{n−1} (e = 0: exactly g − z_{n+1}). At the start step
    /// u_{−1} := u_1 − 2Δt v_0 = u_1 (v_0 = 0, docs/scheme.md), so the constraint is on u_1 itself:
    /// e = 0.
    fn fill_bounds(&mut self, base_next: f64, base_previous: f64) {
        let e = if self.step_index == 0 {
            0.0
        } else {
            self.scene.solver.restitution
        };
        let lower = self.scene.lower_obstacle();
        let upper = self.scene.upper_obstacle();
        for i in 0..self.prediction.len() {
            let u_prev = base_previous + self.restitution_previous[i];
            let shift = |g: f64| {
                if e == 0.0 {
                    g - base_next
                } else {
                    (1.0 + e) * g - e * u_prev - base_next
                }
            };
            self.lower[i] = lower.map_or(f64::NEG_INFINITY, shift);
            self.upper[i] = upper.map_or(f64::INFINITY, shift);
        }
    }

    /// The exact active-set method on the Delassus operator, warm-started from the last step's
    /// contact states; `None` when it does not converge (the caller falls back to clarabel).
    fn solve_with_active_set(&mut self) -> Option<Vec<f64>> {
        let mut delassus = BackendDelassus {
            backend: &mut *self.backend,
            dim: self.prediction.len(),
        };
        let report = self.active_set.solve(
            &mut delassus,
            &self.prediction,
            &self.lower,
            &self.upper,
            &mut self.states,
            &PdasSettings::default(),
        );
        if !report.status.is_solved() {
            self.states.fill(BoundState::Free);
            return None;
        }
        let mu = self.active_set.lambda().to_vec();
        let active: Vec<usize> = (0..mu.len())
            .filter(|&i| self.states[i].is_active())
            .collect();
        self.backend.correct(&mut self.levels.next, &active, &mu);
        Some(mu)
    }

    /// clarabel on the full primal QP min ½wᵀAw − bᵀw over the box; returns the multipliers.
    fn solve_with_clarabel(&mut self, forcing: &StepForcing) -> Result<Vec<f64>, Error> {
        let free = &*self.free;
        let mut b = vec![0.0; free.load.len()];
        free.right_hand_side(
            forcing,
            &self.backend.to_free_dofs(&self.levels.previous),
            &self.backend.to_free_dofs(&self.levels.current),
            &mut b,
        );
        let solution = contact::clarabel::solve_box_qp(&BoxQp {
            a: free.system.as_ref(),
            b: &b,
            constrained: &free.constrained,
            lower: &self.lower,
            upper: &self.upper,
        })?;
        self.backend
            .field_of_free_dofs(&solution.x, &mut self.levels.next);
        self.states = solution.states;
        Ok(solution.lambda)
    }

    /// Outputs after the last step, evaluated on demand (O(n): a host that reads them at its
    /// communication points only does not pay for them at every internal step).
    pub fn outputs(&self) -> Outputs {
        let active_nodes = self.states.iter().filter(|s| s.is_active()).count();
        let contact_force = self.forces.iter().sum();
        let dt = self.scene.solver.time_step;
        let pieces = self
            .backend
            .energy(&self.levels.previous, &self.levels.current, dt);
        // The pressure that acted on the last step, not one set since for the next.
        let energy = DiscreteEnergy::new(
            &self.free,
            pieces,
            self.base,
            self.pressure[1],
            dt,
            self.step_index == 0,
        );
        let [a, b, c] = self.backend.output_values(&self.levels.current);
        let z = self.base[1];
        Outputs {
            corner1: z + a,
            corner2: z + b,
            edge_mid: z + c,
            energy_kinetic: energy.kinetic,
            energy_elastic: energy.elastic,
            energy_total: energy.total,
            active_nodes,
            contact_force,
        }
    }

    /// The dynamic state, for FMU get/set/serialize.
    pub fn state(&self) -> State {
        State {
            scene: self.scene.clone(),
            backend: self.linear,
            step_index: self.step_index,
            base: self.base,
            pressure: self.pressure,
            previous: self.levels.previous.clone(),
            current: self.levels.current.clone(),
            active_set: self.states.iter().map(|s| state_code(*s)).collect(),
            forces: self.forces.clone(),
        }
    }

    /// Restores a state taken from a stepper of a scene with the same fixed parameters.
    pub fn restore(&mut self, state: &State) -> Result<(), Error> {
        let mut fixed = state.scene.clone();
        fixed.obstacle.lower = self.scene.obstacle.lower;
        fixed.obstacle.upper = self.scene.obstacle.upper;
        fixed.load.pressure = self.scene.load.pressure;
        fixed.stop_time = self.scene.stop_time;
        // The QP choice changes how a step is solved, not what it computes: a state moves freely
        // between the fast path and the clarabel reference.
        fixed.solver.qp = self.scene.solver.qp;
        let m = self.free.constrained.len();
        let n = self.backend.dimension();
        if fixed != self.scene
            || state.backend != self.linear
            || state.previous.len() != n
            || state.current.len() != n
            || state.forces.len() != m
            || state.active_set.len() != m
        {
            return Err(Error::invalid(
                "FMU state",
                "<state>",
                "was taken from a model with other fixed parameters",
            ));
        }
        let states = state
            .active_set
            .iter()
            .map(|&c| state_from_code(c))
            .collect::<Option<Vec<_>>>()
            .ok_or_else(|| Error::invalid("FMU state", "<state>", "holds an invalid active set"))?;
        self.levels.previous.copy_from_slice(&state.previous);
        self.levels.current.copy_from_slice(&state.current);
        self.levels.next.copy_from_slice(&state.current);
        let qp = self.scene.solver.qp;
        self.scene = state.scene.clone();
        self.scene.solver.qp = qp;
        self.step_index = state.step_index;
        self.base = state.base;
        self.pressure = state.pressure;
        self.backend
            .constrained_values(&self.levels.previous, &mut self.restitution_previous);
        self.backend
            .constrained_values(&self.levels.current, &mut self.restitution_current);
        self.states = states;
        self.forces = state.forces.clone();
        Ok(())
    }
}

/// The base must stay strictly inside the gap (docs/model.md).
fn check_base(scene: &Scene, time: f64, base: f64) -> Result<(), Error> {
    let (lower, upper) = (scene.lower_obstacle(), scene.upper_obstacle());
    let inside =
        base.is_finite() && lower.is_none_or(|g| base > g) && upper.is_none_or(|g| base < g);
    if inside {
        Ok(())
    } else {
        Err(Error::BaseOutsideGap {
            time,
            base,
            lower,
            upper,
        })
    }
}
