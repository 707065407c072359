//! The time stepper: the three time levels, the forcing and bounds of each step, the contact
//! solve, and what a step reports.

mod guards;
mod paths;

use super::auto;
use super::backend::{FieldSums, LinearBackend, StepForcing};
use super::energy::EnergyFlows;
use super::impact::{Law, VertexHistory};
use super::outputs::Outputs;
use super::preload::static_preload;
use super::state::{
    check_base, state_code, CheckedState, LevelOutside, Model, State, StoredLevels,
};
pub use super::state::{RESTORE_BOUND_TOLERANCE, RESTORE_FORCE_TOLERANCE};
use super::FreeSystem;
use crate::budget::{MemoryEstimate, DEFAULT_MEMORY_BUDGET};
use crate::contact::{BoundState, PdasSettings};
use crate::error::Error;
use crate::scene::{LinearChoice, ObstacleSide, Scene};
use crate::system::PlateSystem;
use paths::{Route, Solved};
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
    /// clarabel, after the active-set method did not converge or its answer failed the bound
    /// check.
    ClarabelFallback,
}

/// What one step did.
#[derive(Clone, Debug, PartialEq)]
pub struct StepReport {
    /// Vertices in contact after the step.
    pub active: usize,
    /// The solver path.
    pub path: StepPath,
    /// Whether the constrained values had to be evaluated in full: false when the backend's cheap
    /// test proved the step contact-free (the modal low-mode screening; for the sparse backend that
    /// test is itself exact), or when there is no constraint.
    pub bounds_evaluated: bool,
    /// Set when the step's result is less exact than the normal path's, saying why: the
    /// active-set method did not converge and clarabel solved the step instead, or clarabel's
    /// answer could not be polished to a KKT-certified solution.
    pub warning: Option<String>,
    /// −G_n: the force the plate exerts on its base in this step's equation, at t_n (N, positive
    /// upward); see [`Outputs::base_force`].
    pub base_force: f64,
    /// Σ_i f_i, the total contact force of this step (N, positive upward).
    pub contact_force: f64,
    /// Whether the set of vertices in contact went from empty to non-empty in this step.
    pub impact: bool,
    /// The energy that entered and left the plate in this step (J). All zero for the start step,
    /// which has no exact energy identity (its equation is not the scheme's, see
    /// docs/scheme.md §12): [`Outputs`] sums the flows from the second step on.
    pub flows: EnergyFlows,
}

/// Relative tolerance of the obstacle bounds when an obstacle is moved: 1e-12 of the gap
/// ([`Scene::gap`]), round-off of u = z + w at a vertex resting on the obstacle. A move is held to
/// far less than a restored state ([`RESTORE_BOUND_TOLERANCE`]): it is a deliberate change, and
/// whatever it accepts a restore of the state taken after it accepts too.
const MOVE_BOUND_TOLERANCE: f64 = 1e-12;

/// What a step knows once its unconstrained prediction is in the next level.
struct StepInput {
    /// z_{n+1} (m).
    base_next: f64,
    /// t_{n+1} (s).
    t_next: f64,
    forcing: StepForcing,
    /// The obstacles relative to the base at t_{n+1}, g − z_{n+1} (m): (−∞, ∞) where disabled.
    obstacles: [f64; 2],
    /// The sums of the prediction.
    sums: FieldSums,
}

/// What a step formed after its contact solve, adopted when it is accepted.
struct Closing {
    /// The sums of w_{n+1}.
    sums: FieldSums,
    /// Σ_i f_i (N).
    contact_force: f64,
    /// −G_n (N).
    base_force: f64,
    /// J_{n+1} (N·s).
    base_impulse: f64,
    /// The step's energy flows (J).
    flows: EnergyFlows,
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
    /// The impact law of the steps.
    law: Law,
    /// w_{n−1} and w_n at the constrained vertices, for Newton's law.
    history: VertexHistory,
    /// The contact state of each constrained vertex: the active-set warm start.
    states: Vec<BoundState>,
    active_set_settings: PdasSettings,
    /// Contact force at each constrained vertex after the last step (N); at n = 0 the static
    /// contact forces of the preload.
    forces: Vec<f64>,
    /// Set when the preload's contact problem was solved less exactly than normal.
    initial_warning: Option<String>,
    /// Vertices in contact after the last step.
    active_count: usize,
    /// (m₁ᵀw_{n−1}, m₁ᵀw_n): the mass-weighted sums of the two levels, for G_n.
    mass_weighted_sums: [f64; 2],
    /// −G of the last step (N).
    base_force: f64,
    /// J_n = Σ_{j<n} (−G_j) Δt, the impulse of the force on the base since t_0 (N·s).
    base_impulse: f64,
    /// Energy flows summed since t_1.
    flows: EnergyFlows,
    // Workspaces for the hot path.
    /// ‖w_n‖² in the backend's coordinates, for the overflow test of the next step.
    current_norm_squared: f64,
    /// The backend's [`LinearBackend::magnitude_scale`] for Δt.
    magnitude_scale: f64,
    /// The contact states and forces while a step is solved, adopted when it succeeds.
    trial_states: Vec<BoundState>,
    trial_forces: Vec<f64>,
    prediction: Vec<f64>,
    /// w_{n+1} at the constrained vertices after the contact solve, for its bound check.
    solved: Vec<f64>,
    lower: Vec<f64>,
    upper: Vec<f64>,
}

impl Stepper {
    /// Assembles the plate, chooses and builds the linear backend, computes the initial state
    /// (static equilibrium under the preload, with contact if it pushes into an obstacle, about
    /// the base position `initial_base` (m)), released at rest.
    ///
    /// A scene whose estimated memory ([`MemoryEstimate`]) exceeds [`DEFAULT_MEMORY_BUDGET`] is
    /// refused before anything is assembled, with an error that names the estimate, its largest
    /// part and the budget.
    pub fn new(scene: &Scene, initial_base: f64) -> Result<Stepper, Error> {
        check_set_up(scene)?;
        let plate = PlateSystem::new(scene)?;
        Stepper::from_system(scene, &plate, initial_base)
    }

    /// As [`Stepper::new`], reusing an assembled plate of the same scene (the memory budget is
    /// checked for the rest of the set-up and the run).
    pub fn from_system(
        scene: &Scene,
        plate: &PlateSystem,
        initial_base: f64,
    ) -> Result<Stepper, Error> {
        check_set_up(scene)?;
        check_base(scene, 0.0, initial_base)?;
        let free = Arc::new(FreeSystem::new(scene, plate));
        let linear = crate::backend_choice::resolve(scene, plate.free.len());
        let preload = static_preload(scene, &free, initial_base)?;
        let backend = auto::build(linear, scene, &free)?;
        let mut field = vec![0.0; backend.dimension()];
        backend.field_of_free_dofs(&preload.displacement, &mut field);
        let m = free.constrained.len();
        let sums = backend.field_sums(&field);
        // At rest in static equilibrium, the base balances the preload and the obstacles:
        // 0 = G + p₀∫1 + Σλ.
        let base_force =
            scene.initial.preload_pressure * free.area + preload.forces.iter().sum::<f64>();
        Ok(Stepper {
            scene: scene.clone(),
            current_norm_squared: sums.norm_squared,
            active_count: preload.states.iter().filter(|s| s.is_active()).count(),
            mass_weighted_sums: [sums.translation; 2],
            base_force,
            base_impulse: 0.0,
            flows: EnergyFlows::default(),
            magnitude_scale: backend.magnitude_scale(scene.solver.time_step),
            backend,
            linear,
            levels: TimeLevels::at_rest(field),
            step_index: 0,
            base: [initial_base; 2],
            pressure: [scene.load.pressure; 2],
            law: Law::of(&scene.solver),
            history: VertexHistory::new(m),
            states: preload.states,
            active_set_settings: PdasSettings::default(),
            forces: preload.forces,
            initial_warning: preload.warning,
            trial_states: vec![BoundState::Free; m],
            trial_forces: vec![0.0; m],
            prediction: vec![0.0; m],
            solved: vec![0.0; m],
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

    /// The displacements u_{n−1} and u_n (m) at every mesh vertex, in the mesh's vertex order: the
    /// base displacement z on the clamp, z + w elsewhere (w the vertex's value dof). At n = 0 both
    /// are the initial state (released at rest).
    pub fn vertex_displacements(&self) -> [Vec<f64>; 2] {
        let free = &*self.free;
        // With an obstacle the constrained vertices are exactly those off the clamp, in the same
        // order, and the backend reads their values cheaply; without, from the free dofs.
        let constrained_are_off_clamp = free
            .constrained
            .iter()
            .eq(free.vertex_values.iter().flatten());
        [
            (&self.levels.previous, self.base[0]),
            (&self.levels.current, self.base[1]),
        ]
        .map(|(field, z)| {
            let relative: Vec<f64> = if constrained_are_off_clamp {
                let mut w = vec![0.0; free.constrained.len()];
                self.backend.constrained_values(field, &mut w);
                w
            } else {
                let w = self.backend.to_free_dofs(field);
                free.vertex_values.iter().flatten().map(|&k| w[k]).collect()
            };
            let mut relative = relative.into_iter();
            free.vertex_values
                .iter()
                .map(|k| match k {
                    Some(_) => z + relative.next().expect("one value per vertex off the clamp"),
                    None => z,
                })
                .collect()
        })
    }

    /// The displacements u_{n−1} and u_n (m) at the three output points, formed as
    /// [`Stepper::outputs`] forms u_n (bit for bit).
    pub fn output_point_displacements(&self) -> [[f64; 3]; 2] {
        [
            (&self.levels.previous, self.base[0]),
            (&self.levels.current, self.base[1]),
        ]
        .map(|(field, z)| self.backend.output_values(field).map(|w| z + w))
    }

    /// −G of the last step (N): [`Outputs::base_force`], read in O(1).
    pub fn base_force(&self) -> f64 {
        self.base_force
    }

    /// J_n = Σ_{j<n} (−G_j) Δt (N·s): the impulse of the force the plate exerts on its base over
    /// the internal steps since t_0, the rectangle rule on the forces of [`Outputs::base_force`]
    /// (the start step's included); [`Outputs::base_impulse`], read in O(1).
    pub fn base_impulse(&self) -> f64 {
        self.base_impulse
    }

    /// Contact forces f_i = μ_i/Δt² at the constrained vertices after the last step (N), with μ
    /// the QP multipliers (2μ_i/Δt² after the start step, whose equation is scaled by Δt²/2): ≥ 0
    /// on the lower obstacle, ≤ 0 on the upper one, 0 where the vertex is free. Before the first
    /// step, the static contact forces λ_i of the preload (K w₀ = p₀ f + Bᵀλ).
    pub fn contact_forces(&self) -> &[f64] {
        &self.forces
    }

    /// Vertices in contact after the last step (at n = 0, of the preload): `active_nodes` of
    /// [`Stepper::outputs`], kept up to date by every step and restore, read without the O(n)
    /// outputs.
    pub fn active_count(&self) -> usize {
        self.active_count
    }

    /// Set when the preload's contact problem was solved less exactly than normal (clarabel's
    /// answer could not be polished), saying so.
    pub fn initial_warning(&self) -> Option<&str> {
        self.initial_warning.as_deref()
    }

    /// Replaces the settings of the active-set method (default [`PdasSettings::default`]); a cap
    /// on its iterations sends the steps it cannot solve to the clarabel fallback.
    pub fn set_active_set_settings(&mut self, settings: PdasSettings) {
        self.active_set_settings = settings;
    }

    /// Changes the obstacle levels (tunable). Both stored levels must lie within the new levels,
    /// as a restored state must ([`Stepper::restore`]): both base values z_{n−1}, z_n strictly
    /// inside the gap, and every constrained vertex of u_{n−1}, u_n within the obstacles to 1e-12
    /// of the gap ([`Scene::gap`]). Moving an obstacle into the plate would make the next step push
    /// it out within one Δt, an arbitrary impulse, so that is refused; and a move that left
    /// z_{n−1} outside the gap would give a state that the stepper itself refuses to restore.
    pub fn set_obstacles(&mut self, lower: f64, upper: f64) -> Result<(), Error> {
        let mut scene = self.scene.clone();
        scene.obstacle.lower = lower;
        scene.obstacle.upper = upper;
        scene.validate()?;
        let levels = StoredLevels {
            step_index: self.step_index,
            base: self.base,
            previous: &self.levels.previous,
            current: &self.levels.current,
        };
        let tolerance = MOVE_BOUND_TOLERANCE * scene.gap();
        match self.model().first_level_outside(&scene, &levels, tolerance) {
            None => {
                self.scene = scene;
                Ok(())
            }
            Some(LevelOutside::Base { error, .. }) => Err(error),
            Some(LevelOutside::Vertex { outside, .. }) => {
                let relation = match outside.obstacle {
                    ObstacleSide::Lower => "above",
                    ObstacleSide::Upper => "below",
                };
                Err(Error::invalid(
                    outside.obstacle.parameter(),
                    outside.level,
                    &format!(
                        "must not be {relation} the plate: a vertex is at u = {} m",
                        outside.value
                    ),
                ))
            }
        }
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
    ///
    /// A step whose result is not finite (an overflow, e.g. from a base displacement of 1e308 m
    /// without obstacles) is refused with an error that names what overflowed, and so is every
    /// step that fails: the stepper is then unchanged, still at t_n. The step predicts, decides
    /// its path (screened, checked, clarabel or active set), solves the contact on that path if
    /// it must, forms the contact forces, the force on the base and the energy flows, and only
    /// then adopts the new level.
    pub fn step(&mut self, base_next: f64) -> Result<StepReport, Error> {
        let input = self.predict(base_next)?;
        let route = self.route(&input);
        let solved = match route {
            Route::Screened | Route::Checked => Solved::unconstrained(),
            Route::Clarabel => self.clarabel_path(&input)?,
            Route::ActiveSet => self.active_set_path(&input)?,
        };
        let closing = self.close(&input, solved.multipliers.as_deref())?;
        // The step succeeded: from here on nothing fails.
        Ok(self.accept(&input, route, solved, closing))
    }

    /// The step's forcing and the unconstrained prediction into the next level; refuses a base
    /// outside the gap and a prediction that overflows.
    fn predict(&mut self, base_next: f64) -> Result<StepInput, Error> {
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
        let sums = self.backend.predict(previous, current, &forcing, next)?;
        if !sums.norm_squared.is_finite() {
            return Err(self.overflow("the unconstrained displacement", t_next, base_next));
        }
        let obstacles = [
            self.scene
                .lower_obstacle()
                .map_or(f64::NEG_INFINITY, |g| g - base_next),
            self.scene
                .upper_obstacle()
                .map_or(f64::INFINITY, |g| g - base_next),
        ];
        Ok(StepInput {
            base_next,
            t_next,
            forcing,
            obstacles,
            sums,
        })
    }

    /// The contact forces from the multipliers μ of the contact solve, if any, the force on the
    /// base and the energy flows of the step; refuses the step when any of them, or an output
    /// after it, is not finite. Changes nothing but the trial forces.
    fn close(&mut self, input: &StepInput, multipliers: Option<&[f64]>) -> Result<Closing, Error> {
        let dt = self.scene.solver.time_step;
        let StepInput {
            base_next, t_next, ..
        } = *input;
        // The step's equation times Δt² is the QP's optimality condition A w − b = Bᵀμ, so
        // f = μ/Δt²; the start step's equation is multiplied by Δt²/2 (its
        // 2M(u_1 − u_0)/Δt² + K u_1 = F̄_0 + Bᵀf_0 gives b_0 = M u_0 + ½Δt²F̄_0), so there
        // f = 2μ/Δt².
        let equation_scale = if input.forcing.start { 2.0 } else { 1.0 };
        let (mut sums, mut contact_force, mut force_magnitude) = (input.sums, 0.0, 0.0);
        if let Some(mu) = multipliers {
            sums = self.backend.field_sums(&self.levels.next);
            for (f, &x) in self.trial_forces.iter_mut().zip(mu) {
                *f = equation_scale * x / (dt * dt);
            }
            contact_force = self.trial_forces.iter().sum();
            force_magnitude = self.trial_forces.iter().map(|f| f.abs()).sum();
            if !(sums.norm_squared.is_finite() && force_magnitude.is_finite()) {
                return Err(self.overflow(
                    "the displacement or the contact forces of the contact solve",
                    t_next,
                    base_next,
                ));
            }
        }
        self.guard_outputs(sums.norm_squared, base_next, t_next, force_magnitude)?;
        let base_force = -self.base_supply(base_next, sums.translation, contact_force);
        let base_impulse = self.base_impulse + base_force * dt;
        let flows = if input.forcing.start {
            EnergyFlows::default()
        } else {
            // The prediction's damping quadratic holds when the step kept the prediction.
            let damping = multipliers.map_or(input.sums.damping, |_| None);
            self.step_flows(base_next, -base_force, multipliers, damping)
        };
        if !(base_force.is_finite() && base_impulse.is_finite() && flows.is_finite()) {
            return Err(self.overflow(
                "the force on the base or an energy flow",
                t_next,
                base_next,
            ));
        }
        Ok(Closing {
            sums,
            contact_force,
            base_force,
            base_impulse,
            flows,
        })
    }

    /// Adopts a step that succeeded: the trial contact states and forces (or none, when the
    /// prediction is u_{n+1}), the new level, and the sums and totals `closing` formed.
    fn accept(
        &mut self,
        input: &StepInput,
        route: Route,
        solved: Solved,
        closing: Closing,
    ) -> StepReport {
        let active = match &solved.multipliers {
            Some(_) => {
                std::mem::swap(&mut self.forces, &mut self.trial_forces);
                std::mem::swap(&mut self.states, &mut self.trial_states);
                self.states.iter().filter(|s| s.is_active()).count()
            }
            None => {
                self.states.fill(BoundState::Free);
                self.forces.fill(0.0);
                0
            }
        };
        if let Law::Newton(_) = self.law {
            // An evaluated prediction that the step accepted unchanged is w_{n+1} at the vertices.
            let known = route == Route::Checked;
            self.history.advance(known.then_some(&self.prediction[..]));
        }
        self.levels.accept();
        let Closing { sums, .. } = closing;
        self.current_norm_squared = sums.norm_squared;
        let impact = self.active_count == 0 && active > 0;
        self.active_count = active;
        self.mass_weighted_sums = [self.mass_weighted_sums[1], sums.translation];
        self.base_force = closing.base_force;
        self.base_impulse = closing.base_impulse;
        self.flows = self.flows.plus(&closing.flows);
        self.base = [self.base[1], input.base_next];
        self.pressure = [self.pressure[1], self.scene.load.pressure];
        self.step_index += 1;
        StepReport {
            active,
            path: solved.path,
            bounds_evaluated: route.bounds_evaluated(),
            warning: solved.warning,
            base_force: closing.base_force,
            contact_force: closing.contact_force,
            impact,
            flows: closing.flows,
        }
    }

    /// G_n, the vertical force the base supplies to the plate in the step being solved, from the
    /// scheme's equation at t_n tested with the rigid translation 𝟙 (K𝟙 = 0, and 𝟙ᵀC = α(M𝟙)ᵀ is
    /// the reaction of the mass-proportional dashpots, which act from the base frame, so that G
    /// is the whole force through the base; docs/scheme.md §11):
    /// G_n = 𝟙ᵀM(u_{n+1} − 2u_n + u_{n−1})/Δt² − F̄_n∫1 − Σ_i f_i, where 𝟙ᵀMu = M_tot z + m₁ᵀw.
    /// The start step's equation 2M(u_1 − u_0)/Δt² + K u_1 = F̄_0 + Bᵀf_0 + R_0 gives
    /// G_0 = 2𝟙ᵀM(u_1 − u_0)/Δt² − F̄_0∫1 − Σ_i f_i. `mass_weighted_next` is m₁ᵀw_{n+1}.
    fn base_supply(&self, base_next: f64, mass_weighted_next: f64, contact_force: f64) -> f64 {
        let dt = self.scene.solver.time_step;
        let (m, area) = (self.free.total_mass, self.free.area);
        let [z_prev, z_curr] = self.base;
        let [s_prev, s_curr] = self.mass_weighted_sums;
        let p_next = self.scene.load.pressure;
        let (momentum_change, mean_pressure) = if self.step_index == 0 {
            (
                2.0 * (m * (base_next - z_curr) + (mass_weighted_next - s_curr)),
                0.5 * (p_next + self.pressure[1]),
            )
        } else {
            (
                m * (base_next - 2.0 * z_curr + z_prev)
                    + (mass_weighted_next - 2.0 * s_curr + s_prev),
                0.5 * (p_next + self.pressure[0]),
            )
        };
        momentum_change / (dt * dt) - mean_pressure * area - contact_force
    }

    /// The energy flows of the step being solved (not the start step), with `supply` = G_n and
    /// the QP multipliers μ of its contact solve, if any: base work
    /// ½(z_{n+1} − z_{n−1})G_n, load work net of the load potential's change, contact loss
    /// −½ f_nᵀB(u_{n+1} − u_{n−1}) and damping loss Δwᵀ C Δw / (4Δt) (see [`EnergyFlows`]), whose
    /// quadratic Δwᵀ C Δw the backend's pass may already have formed (`damping_quadratic`).
    fn step_flows(
        &mut self,
        base_next: f64,
        supply: f64,
        multipliers: Option<&[f64]>,
        damping_quadratic: Option<f64>,
    ) -> EnergyFlows {
        let dt = self.scene.solver.time_step;
        let [z_prev, z_curr] = self.base;
        let TimeLevels {
            previous,
            current,
            next,
        } = &self.levels;
        let stroke = base_next - z_prev;
        // f = μ/Δt² (2μ/Δt² at the start step, which has no flows), u = z𝟙 + w at the vertices.
        let contact_loss = match multipliers {
            Some(mu) => {
                let relative = self.backend.multiplier_work(next, previous, mu) / (dt * dt);
                -0.5 * (stroke * self.trial_forces.iter().sum::<f64>() + relative)
            }
            None => 0.0,
        };
        let [p_prev, p_curr] = self.pressure;
        let p_next = self.scene.load.pressure;
        let load_work = if p_prev == 0.0 && p_curr == 0.0 && p_next == 0.0 {
            0.0
        } else {
            // L_k = Fᵀu_k for a 1 Pa pressure = z_k∫1 + fᵀw_k.
            let area = self.free.area;
            let l_next = area * base_next + self.backend.load_projection(next);
            let l_curr = area * z_curr + self.backend.load_projection(current);
            let l_prev = area * z_prev + self.backend.load_projection(previous);
            0.25 * (p_next + p_prev) * (l_next - l_prev) - 0.5 * p_next * (l_next + l_curr)
                + 0.5 * p_curr * (l_curr + l_prev)
        };
        let damping_loss = if self.free.damping.is_zero() {
            0.0
        } else {
            damping_quadratic.unwrap_or_else(|| self.backend.damping_quadratic(next, previous))
                / (4.0 * dt)
        };
        EnergyFlows {
            base_work: 0.5 * stroke * supply,
            load_work,
            contact_loss,
            damping_loss,
        }
    }

    /// Outputs after the last step, evaluated on demand (O(n): a host that reads them at its
    /// communication points only does not pay for them at every internal step).
    pub fn outputs(&self) -> Outputs {
        let active_nodes = self.states.iter().filter(|s| s.is_active()).count();
        let contact_force = self.forces.iter().sum();
        // The pressure that acted on the last step, not one set since for the next.
        let (energy, [a, b, c]) = self.model().energy_and_values(
            &self.levels.previous,
            &self.levels.current,
            self.base,
            self.pressure[1],
            self.step_index == 0,
        );
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
            base_force: self.base_force,
            base_impulse: self.base_impulse,
            base_work: self.flows.base_work,
            load_work: self.flows.load_work,
            contact_loss: self.flows.contact_loss,
            damping_loss: self.flows.damping_loss,
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
            base_force: self.base_force,
            base_impulse: self.base_impulse,
            flows: self.flows,
        }
    }

    /// The model a state is checked against ([`Model::check`]).
    fn model(&self) -> Model<'_> {
        Model {
            scene: &self.scene,
            linear: self.linear,
            backend: &*self.backend,
            free: &self.free,
        }
    }

    /// Checks a state against this stepper ([`State`], with every check listed at
    /// [`Stepper::restore`]), for [`Stepper::adopt`].
    pub(crate) fn check_state<'s>(&self, state: &'s State) -> Result<CheckedState<'s>, Error> {
        self.model().check(state)
    }

    /// Restores a state taken from a stepper of a scene with the same fixed parameters.
    ///
    /// The state is untrusted input: it is refused, with an error naming the field, unless its
    /// fixed parameters and backend match this stepper's and its tunable ones are valid, its
    /// dimensions match, every number is finite, its contact codes are in range and its contact
    /// forces have their signs ([`State`] and [`RESTORE_FORCE_TOLERANCE`]), both base values lie
    /// strictly inside the gap, every constrained vertex of both levels lies within the obstacles
    /// to [`RESTORE_BOUND_TOLERANCE`] of the gap (every impact law keeps every level within
    /// them), and its energies and outputs are finite. Nothing changes unless all of it holds.
    pub fn restore(&mut self, state: &State) -> Result<(), Error> {
        let checked = self.check_state(state)?;
        self.adopt(checked);
        Ok(())
    }

    /// Adopts a state that [`Stepper::check_state`] accepted. The qp choice stays this
    /// stepper's: a state moves freely between the fast path and the clarabel reference.
    pub(crate) fn adopt(&mut self, checked: CheckedState) {
        let CheckedState { state, states } = checked;
        self.levels.previous.copy_from_slice(&state.previous);
        self.levels.current.copy_from_slice(&state.current);
        self.levels.next.copy_from_slice(&state.current);
        let sums = self.backend.field_sums(&self.levels.current);
        self.current_norm_squared = sums.norm_squared;
        self.mass_weighted_sums = [
            self.backend.field_sums(&self.levels.previous).translation,
            sums.translation,
        ];
        self.active_count = states.iter().filter(|s| s.is_active()).count();
        self.base_force = state.base_force;
        self.base_impulse = state.base_impulse;
        self.flows = state.flows;
        let qp = self.scene.solver.qp;
        self.scene = state.scene.clone();
        self.scene.solver.qp = qp;
        self.step_index = state.step_index;
        self.base = state.base;
        self.pressure = state.pressure;
        self.history.forget();
        self.states = states;
        self.forces.copy_from_slice(&state.forces);
    }
}

/// The checks a scene must pass before anything is set up: its parameters, then its estimated
/// memory against [`DEFAULT_MEMORY_BUDGET`] (docs/contact.md, "Memory").
fn check_set_up(scene: &Scene) -> Result<(), Error> {
    scene.validate()?;
    MemoryEstimate::of(scene).check(DEFAULT_MEMORY_BUDGET)
}
