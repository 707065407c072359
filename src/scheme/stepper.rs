//! The time stepper: the three time levels, the forcing and bounds of each step, the contact
//! solve, and what a step reports.
//!
//! [`Stepper::step`] takes the backend's stages in their order: the prediction, then the route
//! (`paths.rs`: screened, checked, clarabel or active set, and one function per path), then the
//! close (`closing.rs`: contact forces, the force on the base, energy flows), each guarded
//! (`guards.rs`), in a workspace kept from step to step (`workspace.rs`); only then is the step
//! accepted. While the stages hold the backend and the fields, the step reads the rest of the
//! stepper through its `Run`.

mod closing;
mod guards;
mod paths;
mod workspace;

use super::auto;
use super::backend::{Backend, FieldMaps, TimeLevels};
use super::bounds::ObstacleBounds;
use super::energy::EnergyFlows;
use super::free_system::FreeSystem;
use super::free_system::StepForcing;
use super::impact::{Law, VertexHistory};
use super::outputs::Outputs;
use super::preload::static_preload;
use super::state::{
    check_base, state_code, CheckedState, LevelOutside, Model, State, StoredLevels,
};
pub use super::state::{RESTORE_BOUND_TOLERANCE, RESTORE_FORCE_TOLERANCE};
use crate::budget::{MemoryEstimate, DEFAULT_MEMORY_BUDGET};
use crate::contact::{BoundState, PdasSettings};
use crate::error::Error;
use crate::obstacles::STOP_OUTPUTS;
use crate::scene::{LinearChoice, ObstacleSide, Scene};
use crate::system::{PlateSystem, OUTPUT_POINTS};
use closing::Closing;
use paths::{Route, Solved};
use serde::{Deserialize, Serialize};
use std::cell::OnceCell;
use std::sync::Arc;
use workspace::StepWorkspace;

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
    /// How many times the contact solve ran again because it had put vertices on an obstacle
    /// that the persistent law then bounded (docs/scheme.md §8); 0 under the other laws.
    pub resolves: u32,
    /// The energy that entered and left the plate in this step (J). All zero for the start step,
    /// which has no exact energy identity (its equation is not the scheme's, see
    /// docs/scheme.md §12): [`Outputs`] sums the flows from the second step on.
    pub flows: EnergyFlows,
    /// The total contact force of each of the first [`STOP_OUTPUTS`] stops in this step (N; 0
    /// for a stop that does not exist).
    pub stop_forces: [f64; STOP_OUTPUTS],
    /// Whether the set of a stop's points in contact went from empty to non-empty in this step,
    /// for the first [`STOP_OUTPUTS`] stops.
    pub stop_impacts: [bool; STOP_OUTPUTS],
}

/// The contact force (N) and the number of points in contact of each stop, from the contact
/// states and forces of the points: a point in contact with an obstacle counts for the stop of
/// that obstacle it belongs to ([`FreeSystem::point_stops`]).
fn stop_contact(
    free: &FreeSystem,
    states: &[BoundState],
    forces: &[f64],
) -> (Vec<f64>, Vec<usize>) {
    let mut force = vec![0.0; free.stop_count];
    let mut active = vec![0; free.stop_count];
    for ((state, &f), stops) in states.iter().zip(forces).zip(&free.point_stops) {
        let stop = match state {
            BoundState::AtLower => stops[0],
            BoundState::AtUpper => stops[1],
            BoundState::Free => None,
        };
        if let Some(k) = stop {
            force[k] += f;
            active[k] += 1;
        }
    }
    (force, active)
}

/// The first [`STOP_OUTPUTS`] entries of `values`, 0 past its end.
fn first_stops(values: &[f64]) -> [f64; STOP_OUTPUTS] {
    std::array::from_fn(|k| values.get(k).copied().unwrap_or(0.0))
}

/// Relative tolerance of the obstacle bounds when an obstacle is moved: 1e-12 of the gap
/// ([`Scene::gap`]), round-off of u = z + w at a vertex resting on the obstacle. A move is held to
/// far less than a restored state ([`RESTORE_BOUND_TOLERANCE`]): it is a deliberate change, and
/// whatever it accepts a restore of the state taken after it accepts too.
const MOVE_BOUND_TOLERANCE: f64 = 1e-12;

/// What a step knows before its prediction: its time, base value, forcing and obstacles.
struct StepInput {
    /// z_{n+1} (m).
    base_next: f64,
    /// t_{n+1} (s).
    t_next: f64,
    forcing: StepForcing,
    /// The obstacles relative to the base at t_{n+1}, g − z_{n+1} (m): (−∞, ∞) where disabled.
    obstacles: [f64; 2],
}

/// How a step found u_{n+1}, for its report and its acceptance.
struct Decision {
    path: StepPath,
    /// Why the answer is less exact than the normal path's, if it is.
    warning: Option<String>,
    /// Whether the constrained values were evaluated in full (the step was not screened).
    bounds_evaluated: bool,
    /// Whether the step evaluated its prediction's values and kept the prediction: under
    /// Newton's law, which evaluates them exactly, they are then w_{n+1} at the vertices.
    values_kept: bool,
    /// How many times the contact solve ran again under the persistent law.
    resolves: u32,
}

/// The time stepper of one scene.
pub struct Stepper {
    /// The scene, the plate and what the steps so far left besides the fields.
    run: Run,
    /// The linear backend: its field maps and its step.
    backend: Backend,
    /// The fields of the three time levels in the backend's coordinates.
    levels: TimeLevels,
    /// w_{n−1} and w_n at the constrained vertices, for Newton's law.
    history: VertexHistory,
    /// The buffers a step works in.
    work: StepWorkspace,
    /// ω² of the lowest modes, computed on the first ask ([`Stepper::natural_frequencies`]).
    lowest_modes: OnceCell<Result<Vec<f64>, Error>>,
}

/// A stepper's scene, plate and settings, and what its steps so far left apart from the fields:
/// all that a step reads while the backend's stages hold the fields, changed only when a step is
/// accepted (or by the tunable setters and a restore).
struct Run {
    scene: Scene,
    free: Arc<FreeSystem>,
    linear: LinearChoice,
    step_index: u64,
    base: [f64; 2],
    pressure: [f64; 2],
    /// The impact law of the steps.
    law: Law,
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
    /// Points in contact of each stop after the last step.
    stop_active: Vec<usize>,
    /// (m₁ᵀw_{n−1}, m₁ᵀw_n): the mass-weighted sums of the two levels, for G_n.
    mass_weighted_sums: [f64; 2],
    /// −G of the last step (N).
    base_force: f64,
    /// J_n = Σ_{j<n} (−G_j) Δt, the impulse of the force on the base since t_0 (N·s).
    base_impulse: f64,
    /// Energy flows summed since t_1.
    flows: EnergyFlows,
    /// ‖w_n‖² in the backend's coordinates, for the overflow test of the next step.
    current_norm_squared: f64,
    /// The backend's [`FieldMaps::magnitude_scale`] for Δt.
    magnitude_scale: f64,
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
        let free = Arc::new(FreeSystem::new(scene, plate));
        check_base(scene, free.clamp_heights, 0.0, initial_base)?;
        let linear = crate::backend_choice::resolve(scene, plate.free.len());
        let preload = static_preload(scene, &free, initial_base)?;
        let backend = auto::build(linear, scene, &free)?;
        let maps = backend.maps();
        let mut field = vec![0.0; maps.dimension()];
        maps.field_of_free_dofs(&preload.displacement, &mut field);
        let m = free.contact.len();
        let sums = maps.field_sums(&field);
        let magnitude_scale = maps.magnitude_scale(scene.solver.time_step);
        // At rest in static equilibrium, the base balances the preload (with the weight) and the
        // obstacles: 0 = G + p₀∫1 + Σλ.
        let base_force =
            scene.acting_preload_pressure() * free.area + preload.forces.iter().sum::<f64>();
        let run = Run {
            scene: scene.clone(),
            current_norm_squared: sums.norm_squared,
            active_count: preload.states.iter().filter(|s| s.is_active()).count(),
            stop_active: stop_contact(&free, &preload.states, &preload.forces).1,
            mass_weighted_sums: [sums.translation; 2],
            base_force,
            base_impulse: 0.0,
            flows: EnergyFlows::default(),
            magnitude_scale,
            linear,
            step_index: 0,
            base: [initial_base; 2],
            pressure: [scene.acting_pressure(); 2],
            law: Law::of(&scene.solver),
            states: preload.states,
            active_set_settings: PdasSettings::default(),
            forces: preload.forces,
            initial_warning: preload.warning,
            free,
        };
        Ok(Stepper {
            run,
            backend,
            levels: TimeLevels::at_rest(field),
            history: VertexHistory::new(m),
            work: StepWorkspace::new(m),
            lowest_modes: OnceCell::new(),
        })
    }

    /// The scene, with tunable parameters at their current values.
    pub fn scene(&self) -> &Scene {
        &self.run.scene
    }

    /// The linear backend that runs (`Modal` or `Sparse`, never `Auto`).
    pub fn linear_backend(&self) -> LinearChoice {
        self.run.linear
    }

    /// n.
    pub fn step_index(&self) -> u64 {
        self.run.step_index
    }

    /// t_n = n Δt (s).
    pub fn time(&self) -> f64 {
        self.run.time()
    }

    /// Number of free dofs.
    pub fn free_dof_count(&self) -> usize {
        self.backend.maps().dimension()
    }

    /// Number of contact points (0 without obstacles).
    pub fn constrained_count(&self) -> usize {
        self.run.free.contact.len()
    }

    /// The natural frequencies f_k = ω_k/2π (Hz) of the `count` lowest modes of the plate as set
    /// up, clamped and without contact (fewer when it has fewer dofs), computed on the first ask
    /// by subspace iteration ([`crate::modes::lowest`]) on every backend, so that they depend on
    /// the plate and its mesh only, not on which backend a size or a modal damping ratio selects.
    /// An error when the iteration does not converge.
    pub fn natural_frequencies(&self, count: usize) -> Result<Vec<f64>, Error> {
        let free = &self.run.free;
        let lowest = self.lowest_modes.get_or_init(|| {
            crate::modes::lowest::lowest_omega_squared(
                &free.mass,
                &free.stiffness,
                crate::system::FREQUENCIES,
            )
        });
        Ok(lowest
            .clone()?
            .iter()
            .take(count)
            .map(|w2| w2.max(0.0).sqrt() / std::f64::consts::TAU)
            .collect())
    }

    /// The obstacles' heights over the contact points, [h₁, h₂] relative to the levels (−∞ and +∞
    /// where an obstacle is absent), in the order of [`Stepper::constrained_displacements`].
    pub fn obstacle_heights(&self) -> [&[f64]; 2] {
        let [lower, upper] = &self.run.free.heights;
        [lower, upper]
    }

    /// The obstacles' heights [h₁, h₂] over the corners (Lx, 0) and (Lx, Ly), where they are
    /// contact points (−∞ and +∞ where not), for a check of the reported corners.
    pub fn corner_heights(&self) -> [&[f64]; 2] {
        let [lower, upper] = &self.run.free.corner_heights;
        [lower, upper]
    }

    /// Whether the base displacement `z` (m) lies strictly inside the gap over the clamp for the
    /// obstacle levels of `scene` (a scene with this stepper's fixed part).
    pub fn base_admits(&self, scene: &Scene, z: f64) -> bool {
        check_base(scene, self.run.free.clamp_heights, 0.0, z).is_ok()
    }

    /// Displacements u_n at the contact points (m).
    pub fn constrained_displacements(&self) -> Vec<f64> {
        let mut w = vec![0.0; self.run.free.contact.len()];
        self.backend
            .maps()
            .constrained_values(&self.levels.current, &mut w);
        w.iter().map(|w| self.run.base[1] + w).collect()
    }

    /// The displacements u_{n−1} and u_n (m) at every mesh vertex, in the mesh's vertex order: the
    /// base displacement z on the clamp, z + w elsewhere (w the vertex's value dof). At n = 0 both
    /// are the initial state (released at rest).
    pub fn vertex_displacements(&self) -> [Vec<f64>; 2] {
        let free = &*self.run.free;
        let maps = self.backend.maps();
        // With flat obstacles the contact points are exactly the vertices off the clamp, in the
        // same order, and the backend reads their values cheaply; otherwise, from the free dofs.
        let constrained_are_off_clamp = free
            .contact
            .selected()
            .is_some_and(|dofs| dofs.iter().eq(free.vertex_values.iter().flatten()));
        [
            (&self.levels.previous, self.run.base[0]),
            (&self.levels.current, self.run.base[1]),
        ]
        .map(|(field, z)| {
            let relative: Vec<f64> = if constrained_are_off_clamp {
                let mut w = vec![0.0; free.contact.len()];
                maps.constrained_values(field, &mut w);
                w
            } else {
                let w = maps.to_free_dofs(field);
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
    pub fn output_point_displacements(&self) -> [[f64; OUTPUT_POINTS]; 2] {
        [
            (&self.levels.previous, self.run.base[0]),
            (&self.levels.current, self.run.base[1]),
        ]
        .map(|(field, z)| self.backend.maps().output_values(field).map(|w| z + w))
    }

    /// −G of the last step (N): [`Outputs::base_force`], read in O(1).
    pub fn base_force(&self) -> f64 {
        self.run.base_force
    }

    /// J_n = Σ_{j<n} (−G_j) Δt (N·s): the impulse of the force the plate exerts on its base over
    /// the internal steps since t_0, the rectangle rule on the forces of [`Outputs::base_force`]
    /// (the start step's included); [`Outputs::base_impulse`], read in O(1).
    pub fn base_impulse(&self) -> f64 {
        self.run.base_impulse
    }

    /// Contact forces f_i = μ_i/Δt² at the constrained vertices after the last step (N), with μ
    /// the QP multipliers (2μ_i/Δt² after the start step, whose equation is scaled by Δt²/2): ≥ 0
    /// on the lower obstacle, ≤ 0 on the upper one, 0 where the vertex is free. Before the first
    /// step, the static contact forces λ_i of the preload (K w₀ = p₀ f + Bᵀλ).
    pub fn contact_forces(&self) -> &[f64] {
        &self.run.forces
    }

    /// The total contact force of each stop after the last step (N), the lower obstacle's stops
    /// first ([`crate::obstacles::ObstacleLayout::stops`]); empty without stops.
    pub fn stop_forces(&self) -> Vec<f64> {
        stop_contact(&self.run.free, &self.run.states, &self.run.forces).0
    }

    /// Vertices in contact after the last step (at n = 0, of the preload): `active_nodes` of
    /// [`Stepper::outputs`], kept up to date by every step and restore, read without the O(n)
    /// outputs.
    pub fn active_count(&self) -> usize {
        self.run.active_count
    }

    /// Set when the preload's contact problem was solved less exactly than normal (clarabel's
    /// answer could not be polished), saying so.
    pub fn initial_warning(&self) -> Option<&str> {
        self.run.initial_warning.as_deref()
    }

    /// Replaces the settings of the active-set method (default [`PdasSettings::default`]); a cap
    /// on its iterations sends the steps it cannot solve to the clarabel fallback.
    pub fn set_active_set_settings(&mut self, settings: PdasSettings) {
        self.run.active_set_settings = settings;
    }

    /// Changes the obstacle levels (tunable). Both stored levels must lie within the new levels,
    /// as a restored state must ([`Stepper::restore`]): both base values z_{n−1}, z_n strictly
    /// inside the gap, and every constrained vertex of u_{n−1}, u_n within the obstacles to 1e-12
    /// of the gap ([`Scene::gap`]). Moving an obstacle into the plate would make the next step push
    /// it out within one Δt, an arbitrary impulse, so that is refused; and a move that left
    /// z_{n−1} outside the gap would give a state that the stepper itself refuses to restore.
    pub fn set_obstacles(&mut self, lower: f64, upper: f64) -> Result<(), Error> {
        let mut scene = self.run.scene.clone();
        scene.obstacle.lower = lower;
        scene.obstacle.upper = upper;
        scene.validate()?;
        let levels = StoredLevels {
            step_index: self.run.step_index,
            base: self.run.base,
            previous: &self.levels.previous,
            current: &self.levels.current,
        };
        let tolerance = MOVE_BOUND_TOLERANCE * scene.gap_from(self.run.free.nearest_heights);
        match self.model().first_level_outside(&scene, &levels, tolerance) {
            None => {
                self.run.scene = scene;
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
                    match outside.obstacle {
                        ObstacleSide::Lower => lower,
                        ObstacleSide::Upper => upper,
                    },
                    &format!(
                        "must not put the obstacle {relation} the plate: contact point {} is at \
                         u = {} m, where the obstacle would be at {} m",
                        outside.index, outside.value, outside.level
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
        self.run.scene.load.pressure = pressure;
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
        let Stepper {
            run,
            backend,
            levels,
            history,
            work,
            ..
        } = self;
        let input = run.step_input(base_next)?;
        let prediction = backend.predict(levels, &input.forcing)?;
        let sums = prediction.sums();
        if !sums.norm_squared.is_finite() {
            let what = "the unconstrained displacement";
            return Err(run.overflow(what, input.t_next, base_next));
        }
        let route = run.route(
            &input,
            prediction,
            &mut work.values,
            history,
            &mut work.trial,
        );
        let bounds_evaluated = !matches!(route, Route::Screened(_));
        // An evaluated prediction that the step accepts unchanged is w_{n+1} at the vertices.
        let values_kept = matches!(route, Route::Checked(_));
        let solved = match route {
            Route::Screened(fields) => Solved::unconstrained(fields),
            Route::Checked(values) => Solved::unconstrained(values.keep()),
            Route::Clarabel(values) => run.clarabel_path(&input, values.keep(), &mut work.trial)?,
            Route::ActiveSet(values) => run.active_set_path(&input, values, &mut work.trial)?,
        };
        let Solved {
            path,
            warning,
            answer,
            resolves,
        } = solved;
        let closing = run.close(&input, sums, answer, &mut work.trial.forces)?;
        // The step succeeded: from here on nothing fails.
        let decision = Decision {
            path,
            warning,
            bounds_evaluated,
            values_kept,
            resolves,
        };
        Ok(self.accept(&input, decision, closing))
    }

    /// Adopts a step that succeeded: the trial contact states and forces (or none, when the
    /// prediction is u_{n+1}), the new level, and the sums and totals `closing` formed.
    fn accept(&mut self, input: &StepInput, decision: Decision, closing: Closing) -> StepReport {
        let Stepper {
            run,
            levels,
            history,
            work,
            ..
        } = self;
        let active = match decision.path {
            StepPath::Unconstrained => {
                run.states.fill(BoundState::Free);
                run.forces.fill(0.0);
                0
            }
            _ => {
                std::mem::swap(&mut run.forces, &mut work.trial.forces);
                std::mem::swap(&mut run.states, &mut work.trial.states);
                run.states.iter().filter(|s| s.is_active()).count()
            }
        };
        if let Law::Newton(_) = run.law {
            history.advance(decision.values_kept.then_some(&work.values[..]));
        }
        levels.accept();
        let Closing { sums, .. } = closing;
        run.current_norm_squared = sums.norm_squared;
        let impact = run.active_count == 0 && active > 0;
        run.active_count = active;
        let (mut stop_forces, mut stop_impacts) = ([0.0; STOP_OUTPUTS], [false; STOP_OUTPUTS]);
        if run.free.stop_count > 0 {
            let (forces, now) = stop_contact(&run.free, &run.states, &run.forces);
            stop_forces = first_stops(&forces);
            for (k, impact) in stop_impacts.iter_mut().enumerate().take(now.len()) {
                *impact = run.stop_active[k] == 0 && now[k] > 0;
            }
            run.stop_active = now;
        }
        run.mass_weighted_sums = [run.mass_weighted_sums[1], sums.translation];
        run.base_force = closing.base_force;
        run.base_impulse = closing.base_impulse;
        run.flows = run.flows.plus(&closing.flows);
        run.base = [run.base[1], input.base_next];
        run.pressure = [run.pressure[1], run.scene.acting_pressure()];
        run.step_index += 1;
        StepReport {
            active,
            path: decision.path,
            bounds_evaluated: decision.bounds_evaluated,
            warning: decision.warning,
            base_force: closing.base_force,
            contact_force: closing.contact_force,
            impact,
            resolves: decision.resolves,
            flows: closing.flows,
            stop_forces,
            stop_impacts,
        }
    }

    /// Outputs after the last step, evaluated on demand (O(n): a host that reads them at its
    /// communication points only does not pay for them at every internal step).
    pub fn outputs(&self) -> Outputs {
        let active_nodes = self.run.states.iter().filter(|s| s.is_active()).count();
        let contact_force = self.run.forces.iter().sum();
        // The pressure that acted on the last step, not one set since for the next.
        let (energy, [a, b, c, p1, p2, p3, p4]) = self.model().energy_and_values(
            &self.levels.previous,
            &self.levels.current,
            self.run.base,
            self.run.pressure[1],
            self.run.step_index == 0,
        );
        let z = self.run.base[1];
        Outputs {
            corner1: z + a,
            corner2: z + b,
            edge_mid: z + c,
            energy_kinetic: energy.kinetic,
            energy_elastic: energy.elastic,
            energy_total: energy.total,
            active_nodes,
            contact_force,
            base_force: self.run.base_force,
            base_impulse: self.run.base_impulse,
            base_work: self.run.flows.base_work,
            load_work: self.run.flows.load_work,
            contact_loss: self.run.flows.contact_loss,
            damping_loss: self.run.flows.damping_loss,
            probe1: z + p1,
            probe2: z + p2,
            probe3: z + p3,
            probe4: z + p4,
            stop_forces: first_stops(&self.stop_forces()),
        }
    }

    /// The dynamic state, for FMU get/set/serialize.
    pub fn state(&self) -> State {
        State {
            scene: self.run.scene.clone(),
            backend: self.run.linear,
            step_index: self.run.step_index,
            base: self.run.base,
            pressure: self.run.pressure,
            previous: self.levels.previous.clone(),
            current: self.levels.current.clone(),
            active_set: self.run.states.iter().map(|s| state_code(*s)).collect(),
            forces: self.run.forces.clone(),
            base_force: self.run.base_force,
            base_impulse: self.run.base_impulse,
            flows: self.run.flows,
        }
    }

    /// The model a state is checked against ([`Model::check`]).
    fn model(&self) -> Model<'_> {
        self.run.model(self.backend.maps())
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
        let maps = self.backend.maps();
        let sums = maps.field_sums(&self.levels.current);
        self.run.current_norm_squared = sums.norm_squared;
        self.run.mass_weighted_sums = [
            maps.field_sums(&self.levels.previous).translation,
            sums.translation,
        ];
        self.run.active_count = states.iter().filter(|s| s.is_active()).count();
        self.run.stop_active = stop_contact(&self.run.free, &states, &state.forces).1;
        self.run.base_force = state.base_force;
        self.run.base_impulse = state.base_impulse;
        self.run.flows = state.flows;
        let qp = self.run.scene.solver.qp;
        self.run.scene = state.scene.clone();
        self.run.scene.solver.qp = qp;
        self.run.step_index = state.step_index;
        self.run.base = state.base;
        self.run.pressure = state.pressure;
        self.history.forget();
        self.run.states = states;
        self.run.forces.copy_from_slice(&state.forces);
    }
}

impl Run {
    /// t_n = n Δt (s).
    fn time(&self) -> f64 {
        self.step_index as f64 * self.scene.solver.time_step
    }

    /// The obstacles' bounds of the step `input` at every contact point.
    fn bounds(&self, input: &StepInput) -> ObstacleBounds<'_> {
        if self.free.flat {
            ObstacleBounds::flat(input.obstacles)
        } else {
            ObstacleBounds::new(input.obstacles, &self.free.heights)
        }
    }

    /// [`Scene::gap`] of the running scene, without parsing its profiles.
    fn gap(&self) -> f64 {
        self.scene.gap_from(self.free.nearest_heights)
    }

    /// The model a state is checked against ([`Model::check`]), with the backend's field maps.
    fn model<'a>(&'a self, maps: FieldMaps<'a>) -> Model<'a> {
        Model {
            scene: &self.scene,
            linear: self.linear,
            maps,
            free: &self.free,
        }
    }

    /// The step to `base_next`: its time, forcing and obstacles relative to the base; refuses a
    /// base outside the gap.
    fn step_input(&self, base_next: f64) -> Result<StepInput, Error> {
        let dt = self.scene.solver.time_step;
        let t_next = (self.step_index + 1) as f64 * dt;
        check_base(&self.scene, self.free.clamp_heights, t_next, base_next)?;
        let start = self.step_index == 0;
        let [z_prev, z_curr] = self.base;
        let p_next = self.scene.acting_pressure();
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
        })
    }
}

/// The checks a scene must pass before anything is set up: its parameters, then its estimated
/// memory against [`DEFAULT_MEMORY_BUDGET`] (docs/contact.md, "Memory").
fn check_set_up(scene: &Scene) -> Result<(), Error> {
    scene.validate()?;
    MemoryEstimate::of(scene)?.check(DEFAULT_MEMORY_BUDGET)
}
