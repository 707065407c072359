//! A co-simulation of one scene, communication step by communication step: the model the FMU
//! drives, usable without FMI by tests and examples.
//!
//! * [`grid`]: the internal time grid t_n = t_start + nΔt, where a communication step ends on it,
//!   and the limits on a communication step;
//! * [`input`]: how a sampled external base displacement is applied on the grid;
//! * [`interpolation`]: the outputs at a communication point between two grid points;
//! * [`contact_summary`]: impacts, impulse and peak contact force over a communication step.
//!
//! A communication step may also end early, at the first grid point where the contact set goes
//! from empty to non-empty ([`Simulation::advance`] with `stop_at_impact`), so that a host gets a
//! communication point at every impact (FMI 3.0's early return).
//!
//! The base displacement of the plate is the scene's built-in sine c sin(2πf(t − t_start)) plus
//! the external signal. The internal steps always lie on the fixed grid, whatever the host's
//! communication steps: a communication step from t to t + h computes the grid up to the first
//! grid point t_N ≥ t + h (none when the grid already reaches it), with the external base planned
//! by [`input`], reports each internal step to an observer, and returns a [`CommunicationStep`]
//! summary. When t + h lies between t_{N−1} and t_N the outputs are those at t + h
//! ([`interpolation`]). What the contact did over the internal steps whose grid times lie in
//! (t, t + h] is summarised in [`contact_summary`]. Outputs are computed at most once per state,
//! on demand, and cached until the state changes.

pub mod contact_summary;
pub mod grid;
pub mod input;
pub mod interpolation;

use crate::error::Error;
use crate::scene::Scene;
use crate::scheme::Stepper;
pub use crate::scheme::{Outputs, State, StepPath, StepReport};
use crate::system::OUTPUT_POINTS;
use contact_summary::ContactSummary;
use grid::{GridError, StepEnd, TimeGrid};
use input::{InputHistory, InputSample};
pub use interpolation::VertexField;
use interpolation::{interpolate, CommunicationPoint};
use serde::{Deserialize, Serialize};
use std::cell::OnceCell;

/// What an observer of a communication step sees after each internal step.
#[derive(Clone, Copy, Debug)]
pub struct InternalStep<'a> {
    /// t_{n+1}, the grid time the step reached (s).
    pub time: f64,
    /// What the stepper reported.
    pub report: &'a StepReport,
    /// Vertices in contact before the step.
    pub previously_active: usize,
}

impl InternalStep<'_> {
    /// Why the step was solved less exactly than the normal path (the active-set method did not
    /// converge and clarabel solved it instead, or clarabel's answer could not be polished), if it was.
    pub fn degraded(&self) -> Option<&str> {
        self.report.warning.as_deref()
    }
}

/// What one communication step did, aggregated over the internal steps it computed.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CommunicationStep {
    /// Internal steps computed.
    pub internal_steps: u64,
    /// Internal steps solved less exactly than the normal path (see [`InternalStep::degraded`]).
    pub degraded_steps: u64,
    /// Whether the step ended early, at the grid point of an impact before t + h (only when
    /// asked to, see [`Simulation::advance`]).
    pub stopped_at_impact: bool,
}

/// How [`Simulation::restart`] got back to n = 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SetUp {
    /// The assembled plate and its backend were reused.
    Reused,
    /// The plate was assembled and its backend built anew.
    Rebuilt,
}

/// The serializable state of a [`Simulation`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SimulationState {
    /// t_start (s).
    pub start_time: f64,
    /// The stepper's state (scene, step count, fields, contacts).
    pub stepper: State,
    /// The interpolation history of the external base.
    pub input: InputHistory,
    /// Where the communication point lies on the grid the stepper has computed.
    pub point: CommunicationPoint,
    /// The contact over the last communication step.
    pub contact: ContactSummary,
    /// The contact of the internal step computed ahead of the communication point, not yet
    /// reported (empty when the communication point is on the grid).
    pub contact_ahead: ContactSummary,
    /// Where the last communication step started, for `base.mean_force` (none before the first).
    pub step_start: Option<StepStart>,
}

impl SimulationState {
    /// Checks what an untrusted state says about its time grid, communication point, input
    /// history and contact summaries, for a plate with `constrained` constrained vertices
    /// (`usize::MAX` where the plate is not known yet): the one check of these fields, for
    /// [`Simulation::restore`] and the FMU's snapshot validation. Returns the grid, or what is
    /// wrong.
    pub fn check(&self, constrained: usize) -> Result<TimeGrid, String> {
        let grid = TimeGrid {
            start: self.start_time,
            step: self.stepper.scene.solver.time_step,
        };
        let n = self.stepper.step_index;
        grid.check_resolves(grid.start)
            .and_then(|()| grid.check_resolves(grid.time(n)))
            .map_err(|e| format!("has a time grid that {e}"))?;
        let elapsed = self.point.elapsed(&grid, n);
        self.point
            .check(&grid, n, constrained)
            .and_then(|()| self.input.check(elapsed))
            .and_then(|()| {
                self.contact
                    .check("contact of the last communication step", n)
            })
            .and_then(|()| {
                let pending = u64::from(matches!(self.point, CommunicationPoint::Between { .. }));
                self.contact_ahead
                    .check("contact of the step computed ahead", pending)
            })
            .and_then(|()| check_step_start(self.step_start, elapsed))
            .map_err(|e| format!("is inconsistent: {e}"))?;
        Ok(grid)
    }
}

/// The communication point where the last communication step started: its time and the impulse
/// of the force on the base there, J(t_k) ([`Simulation::base_mean_force`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct StepStart {
    /// t_k − t_start (s).
    pub elapsed: f64,
    /// J(t_k) (N·s).
    pub impulse: f64,
}

/// How far past an obstacle a vertex may lie, as a fraction of the gap ([`bound_tolerance`]),
/// before a state counts as a contact problem that was not solved: the dynamic steps are exact to
/// round-off (at most 7e-11 of the gap measured, on the clarabel path), and the static preload
/// problem, solved by clarabel alone, lay up to 9e-9 of the gap past an obstacle for a plate as soft
/// as E = 1e-4 Pa. Every impact law keeps every level within the obstacles (the paper's bounds
/// u_{n+1} ∈ [g1, g2] for e = 0, Newton's law's bounds between u_n and u_{n−1} for e > 0), so the
/// same tolerance holds for every e.
pub const BOUND_TOLERANCE: f64 = 1e-7;

/// [`BOUND_TOLERANCE`] × [`Scene::gap`] (m): for flat obstacles g2 − g1 with both, |g| with one,
/// 1 m with none.
pub fn bound_tolerance(scene: &Scene) -> f64 {
    BOUND_TOLERANCE * scene.gap()
}

/// Refuses an initial state with a contact point past an obstacle (a static preload problem that
/// was not solved accurately), naming the point's position and the obstacle.
fn check_initial_state(stepper: &Stepper) -> Result<(), Error> {
    let scene = stepper.scene();
    let constrained = stepper.constrained_displacements();
    match scene.first_outside(&constrained, stepper.obstacle_heights(), bound_tolerance(scene)) {
        Some(outside) => Err(Error::ContactSolver(format!(
            "the initial state (static equilibrium under initial.preload_pressure = {} Pa and load.gravity = {} m/s2) puts contact point {} at u = {} m, past the obstacle at {} m: the static contact problem was not solved accurately for these parameters (material.young_modulus = {} Pa)",
            scene.initial.preload_pressure, scene.load.gravity, outside.index, outside.value, outside.level, scene.material.young_modulus
        ))),
        None => Ok(()),
    }
}

/// One simulation of a scene, advanced by communication steps.
pub struct Simulation {
    stepper: Stepper,
    grid: TimeGrid,
    input: InputHistory,
    point: CommunicationPoint,
    contact: ContactSummary,
    contact_ahead: ContactSummary,
    step_start: Option<StepStart>,
    /// The stepper at n = 0 and the external base it was built for, for [`Simulation::restart`].
    initial: (State, f64),
    /// The outputs at the last computed grid point t_N.
    grid_outputs: OnceCell<Outputs>,
    /// The outputs at the communication point, when it lies before t_N.
    interpolated: OnceCell<Outputs>,
    /// The displacement field at the communication point and its rate.
    field: OnceCell<VertexField>,
    /// The rates of the output points at the communication point ([`Simulation::displacement_rates`]).
    rates: OnceCell<[f64; OUTPUT_POINTS]>,
}

impl Simulation {
    /// Sets the scene up (assembly, backend, static preload) at t_start = `start_time` (s), with
    /// the external base displacement `external_base` (m) there.
    /// Refused for a time step whose square overflows (above about 1.3e154 s): the scheme's
    /// matrices and forces scale with Δt², so nothing of such a step would be finite, and a saved
    /// state could not be checked.
    pub fn new(scene: &Scene, start_time: f64, external_base: f64) -> Result<Simulation, Error> {
        let dt = scene.solver.time_step;
        if !(dt * dt).is_finite() {
            return Err(Error::InvalidParameter {
                name: "solver.time_step".into(),
                value: format!("{dt} s"),
                limit: format!(
                    "its square must be finite (at most {:e} s): the scheme's matrices scale with it",
                    f64::MAX.sqrt()
                ),
            });
        }
        let z0 = scene.builtin_base(0.0) + external_base;
        let stepper = Stepper::new(scene, z0)?;
        check_initial_state(&stepper)?;
        Ok(Simulation {
            initial: (stepper.state(), external_base),
            grid: TimeGrid {
                start: start_time,
                step: scene.solver.time_step,
            },
            input: InputHistory::new(external_base),
            point: CommunicationPoint::OnGrid,
            contact: ContactSummary::default(),
            contact_ahead: ContactSummary::default(),
            step_start: None,
            grid_outputs: OnceCell::new(),
            interpolated: OnceCell::new(),
            field: OnceCell::new(),
            rates: OnceCell::new(),
            stepper,
        })
    }

    /// Puts the simulation back to n = 0 for `scene`, `start_time` and `external_base`, exactly as
    /// [`Simulation::new`] would, reusing the assembled plate and its backend when the scene's
    /// fixed part is unchanged and the initial state does not depend on what changed (no preload,
    /// or the same external base and obstacle levels): the expensive set-up runs only when needed.
    /// After an error the simulation must be restarted again or dropped.
    pub fn restart(
        &mut self,
        scene: &Scene,
        start_time: f64,
        external_base: f64,
    ) -> Result<SetUp, Error> {
        let (initial, initial_external) = &self.initial;
        let old = &initial.scene;
        let z0 = scene.builtin_base(0.0) + external_base;
        let reusable = scene.validate().is_ok()
            && old.fixed_part() == scene.fixed_part()
            && self.stepper.base_admits(scene, z0)
            && (scene.acting_preload_pressure() == 0.0
                || (*initial_external == external_base && old.obstacle == scene.obstacle));
        if !reusable {
            *self = Simulation::new(scene, start_time, external_base)?;
            return Ok(SetUp::Rebuilt);
        }
        let mut state = initial.clone();
        state.scene = scene.clone();
        state.base = [z0; 2];
        state.pressure = [scene.acting_pressure(); 2];
        self.stepper.restore(&state)?;
        check_initial_state(&self.stepper)?;
        self.initial = (state, external_base);
        self.grid.start = start_time;
        self.input = InputHistory::new(external_base);
        self.point = CommunicationPoint::OnGrid;
        self.contact = ContactSummary::default();
        self.contact_ahead = ContactSummary::default();
        self.step_start = None;
        self.invalidate_outputs();
        Ok(SetUp::Reused)
    }

    /// A simulation continuing from `state` (built for its scene, then restored).
    pub fn from_state(state: &SimulationState) -> Result<Simulation, Error> {
        let mut sim = Simulation::new(&state.stepper.scene, state.start_time, 0.0)?;
        sim.restore(state)?;
        Ok(sim)
    }

    /// The scene, tunable parameters at their current values.
    pub fn scene(&self) -> &Scene {
        self.stepper.scene()
    }

    /// The stepper, for what it reports beyond the outputs (the obstacles' heights, the contact
    /// forces).
    pub fn stepper(&self) -> &Stepper {
        &self.stepper
    }

    /// The internal time grid.
    pub fn grid(&self) -> &TimeGrid {
        &self.grid
    }

    /// N, the index of the last computed grid point.
    pub fn step_index(&self) -> u64 {
        self.stepper.step_index()
    }

    /// t_N = t_start + NΔt, the last computed grid time (s): the communication time, or up to one
    /// grid step after it.
    pub fn grid_time(&self) -> f64 {
        self.grid.time(self.stepper.step_index())
    }

    /// The communication time t (s): t_N when it lies on the grid.
    pub fn time(&self) -> f64 {
        self.grid.start + self.elapsed()
    }

    /// t − t_start (s).
    fn elapsed(&self) -> f64 {
        self.point.elapsed(&self.grid, self.stepper.step_index())
    }

    /// The outputs at the communication time, computed on the first call after each change.
    pub fn outputs(&self) -> &Outputs {
        match &self.point {
            CommunicationPoint::OnGrid => self.grid_outputs(),
            CommunicationPoint::Between { elapsed, previous } => self
                .interpolated
                .get_or_init(|| interpolate(previous, self.grid_outputs(), self.theta(*elapsed))),
        }
    }

    /// θ = (t − t_{N−1})/Δt for a communication point `elapsed` (t − t_start) between t_{N−1}
    /// and t_N.
    fn theta(&self, elapsed: f64) -> f64 {
        let n = self.stepper.step_index();
        (elapsed - self.grid.elapsed(n - 1)) / self.grid.step
    }

    /// J(t), the impulse of the force on the base since t_start at the communication time (N·s):
    /// [`Outputs::base_impulse`], interpolated between grid points as every continuous output
    /// ([`interpolation`]), bit for bit, in O(1).
    pub fn base_impulse(&self) -> f64 {
        match &self.point {
            CommunicationPoint::OnGrid => self.stepper.base_impulse(),
            CommunicationPoint::Between { elapsed, previous } => interpolation::mix(
                previous.base_impulse,
                self.stepper.base_impulse(),
                self.theta(*elapsed),
            ),
        }
    }

    /// `base.mean_force`: the mean over the last communication step [t_k, t_{k+1}] of the force
    /// the plate exerts on its base (N, positive upward), its impulse over the step divided by the
    /// step, (J(t_{k+1}) − J(t_k))/(t_{k+1} − t_k), with J the rectangle rule on the forces of
    /// `base.force` (those of the internal steps that reach (t_k, t_{k+1}], interpolated as the
    /// work between grid points). Before the first step, the static force at t_start, as
    /// `base.force`. With the base work W: over a communication step whose internal steps see a
    /// base moving at one velocity (z_{n+1} − z_{n−1} = 2sΔt for every internal step n of it),
    /// ΔW = −s·ΔJ = −`base.mean_force`·Δz exactly; otherwise the remainder is
    /// ½·base.force_{N0}·(z_{N0+1} − 2z_{N0} + z_{N0−1}) per change of base velocity at a grid
    /// point N0 (docs/fmu.md, "Coupling both ways").
    pub fn base_mean_force(&self) -> f64 {
        match self.step_start {
            None => self.stepper.base_force(),
            Some(start) => (self.base_impulse() - start.impulse) / (self.elapsed() - start.elapsed),
        }
    }

    /// The contact over the internal steps of the last communication step (zero before the first).
    pub fn contact(&self) -> &ContactSummary {
        &self.contact
    }

    /// d/dt of the displacement outputs `corner1`, `corner2`, `edge_mid` and of the probes at the
    /// communication time (m/s): the slope of their interpolation, (y_N − y_{N−1})/Δt over the
    /// grid interval (t_{N−1}, t_N] that holds the communication time ([`interpolation`]); 0 at
    /// t_start. Computed on the first call after each change: a host reads them with every
    /// output, and each costs two products of the field with the output points' rows.
    pub fn displacement_rates(&self) -> [f64; OUTPUT_POINTS] {
        *self.rates.get_or_init(|| {
            let [previous, current] = self.stepper.output_point_displacements();
            let dt = self.grid.step;
            std::array::from_fn(|k| interpolation::rate(previous[k], current[k], dt))
        })
    }

    /// The displacement at every mesh vertex at the communication time, and its rate, computed on
    /// the first call after each change ([`interpolation`] gives the rule).
    pub fn vertex_field(&self) -> &VertexField {
        self.field.get_or_init(|| {
            let [previous, current] = self.stepper.vertex_displacements();
            let theta = match &self.point {
                CommunicationPoint::OnGrid => None,
                CommunicationPoint::Between { elapsed, .. } => {
                    let n = self.stepper.step_index();
                    Some((elapsed - self.grid.elapsed(n - 1)) / self.grid.step)
                }
            };
            VertexField::between(&previous, &current, theta, self.grid.step)
        })
    }

    /// The outputs at the last computed grid point t_N.
    fn grid_outputs(&self) -> &Outputs {
        self.grid_outputs.get_or_init(|| self.stepper.outputs())
    }

    fn invalidate_outputs(&mut self) {
        self.grid_outputs = OnceCell::new();
        self.interpolated = OnceCell::new();
        self.field = OnceCell::new();
        self.rates = OnceCell::new();
    }

    /// Where a communication step of size `h` (s) from the communication time ends on the grid;
    /// refused (nothing changes) for h not finite and > 0, or beyond the step cap.
    pub fn step_end(&self, h: f64) -> Result<StepEnd, GridError> {
        self.grid
            .step_end(self.elapsed(), self.stepper.step_index(), h)
    }

    /// Advances the communication time to `end` (from [`Simulation::step_end`]): computes the grid
    /// up to t_N with the external base planned from `sample`, the sample at the communication
    /// time (see [`input`]), calling `observer` after each internal step. With `stop_at_impact`,
    /// the step ends early at the first grid point before t + h where the contact set goes from
    /// empty to non-empty (an impact): after the internal step that reached it, or at once when
    /// that grid point was computed ahead by the previous step; the communication time is then
    /// that grid point and [`CommunicationStep::stopped_at_impact`] is set. Without it, or without
    /// such an impact, the step is the same, bit for bit. On an error the steps before it stay
    /// taken and the communication time is the last grid point reached; `base.mean_force` is then
    /// the mean up to that point, or stays the last step's when no time passed.
    pub fn advance(
        &mut self,
        end: &StepEnd,
        sample: &InputSample,
        stop_at_impact: bool,
        observer: &mut dyn FnMut(&InternalStep),
    ) -> Result<CommunicationStep, Error> {
        let start = StepStart {
            elapsed: self.elapsed(),
            impulse: self.base_impulse(),
        };
        let last = self.step_start.replace(start);
        let result = self.advance_from(end, sample, stop_at_impact, observer);
        if self.elapsed() == start.elapsed {
            // A step that failed before its first grid point: no step to average over.
            self.step_start = last;
        }
        result
    }

    /// [`Simulation::advance`] once the start of the step is recorded.
    fn advance_from(
        &mut self,
        end: &StepEnd,
        sample: &InputSample,
        stop_at_impact: bool,
        observer: &mut dyn FnMut(&InternalStep),
    ) -> Result<CommunicationStep, Error> {
        let n0 = self.stepper.step_index();
        let sample_time = self.elapsed();
        let mut summary = CommunicationStep::default();
        // The step computed ahead (at t_{n0}) belongs to this communication step if it reaches
        // t_{n0}; it does unless it ends before t_{n0} again.
        let reaches_ahead = end.index > n0 || end.between.is_none();
        self.contact = if reaches_ahead {
            std::mem::take(&mut self.contact_ahead)
        } else {
            ContactSummary::default()
        };
        // An impact at t_{n0}, computed ahead, and a step that goes beyond it: end there.
        let impact_ahead = stop_at_impact && end.index > n0 && self.contact.impacts > 0;
        if end.index == n0 || impact_ahead {
            self.input.record(sample_time, sample.value);
            let (end, previous) = if impact_ahead {
                (StepEnd::on_grid(n0), None)
            } else {
                let previous = match &self.point {
                    CommunicationPoint::Between { previous, .. } => Some((**previous).clone()),
                    CommunicationPoint::OnGrid => None,
                };
                (*end, previous)
            };
            self.move_point(&end, previous);
            summary.stopped_at_impact = impact_ahead;
            return Ok(summary);
        }
        let dt = self.grid.step;
        let computed = self.grid.elapsed(n0);
        let steps = end.index - n0;
        let plan = self
            .input
            .plan(sample_time, sample, computed, steps as f64 * dt);
        let mut previously_active = self.stepper.active_count();
        // The outputs at t_{N−1}, needed when the communication point lies before t_N.
        let mut previous = None;
        self.point = CommunicationPoint::OnGrid;
        self.interpolated = OnceCell::new();
        self.field = OnceCell::new();
        self.rates = OnceCell::new();
        let mut reached = steps;
        for i in 1..=steps {
            let ahead = i == steps && end.between.is_some();
            if ahead {
                previous = Some(self.grid_outputs().clone());
            }
            let n = n0 + i;
            let base = self.scene().builtin_base(self.grid.elapsed(n)) + plan.at(i as f64 * dt);
            self.grid_outputs = OnceCell::new();
            let report = self.stepper.step(base)?;
            let contact = if ahead {
                &mut self.contact_ahead
            } else {
                &mut self.contact
            };
            contact.add(report.contact_force, report.impact, dt);
            contact.add_stops(&report.stop_forces, &report.stop_impacts, dt);
            let step = InternalStep {
                time: self.grid.time(n),
                report: &report,
                previously_active,
            };
            summary.internal_steps += 1;
            summary.degraded_steps += u64::from(step.degraded().is_some());
            observer(&step);
            previously_active = report.active;
            // t_n < t + h for every step before the last.
            if stop_at_impact && report.impact && i < steps {
                reached = i;
                summary.stopped_at_impact = true;
                break;
            }
        }
        self.input.finish(sample_time, &plan, reached as f64 * dt);
        let end = if summary.stopped_at_impact {
            StepEnd::on_grid(n0 + reached)
        } else {
            *end
        };
        self.move_point(&end, previous);
        Ok(summary)
    }

    /// Moves the communication point to `end`, which lies between grid points when `previous`, the
    /// outputs at t_{N−1}, are given: a step that ends between grid points either computed them or
    /// ends in the interval of the point it started from, whose outputs at t_{N−1} it passes on.
    fn move_point(&mut self, end: &StepEnd, previous: Option<Outputs>) {
        self.point = match (end.between, previous) {
            (Some(elapsed), Some(previous)) => CommunicationPoint::Between {
                elapsed,
                previous: Box::new(previous),
            },
            _ => CommunicationPoint::OnGrid,
        };
        self.interpolated = OnceCell::new();
        self.field = OnceCell::new();
        self.rates = OnceCell::new();
    }

    /// Moves the obstacles (tunable); see [`Stepper::set_obstacles`]. The cached outputs and
    /// field stay: they are functions of the computed levels, forces and flows, which a move
    /// does not change.
    pub fn set_obstacles(&mut self, lower: f64, upper: f64) -> Result<(), Error> {
        self.stepper.set_obstacles(lower, upper)
    }

    /// Changes the pressure from the next step on (tunable). The cached outputs and field stay:
    /// the energies use the pressure of the last step, not the one set for the next.
    pub fn set_pressure(&mut self, pressure: f64) -> Result<(), Error> {
        self.stepper.set_pressure(pressure)
    }

    /// The state, enough to continue bit-identically.
    pub fn state(&self) -> SimulationState {
        SimulationState {
            start_time: self.grid.start,
            stepper: self.stepper.state(),
            input: self.input.clone(),
            point: self.point.clone(),
            contact: self.contact,
            contact_ahead: self.contact_ahead,
            step_start: self.step_start,
        }
    }

    /// Continues from `state`, taken from a simulation with the same fixed parameters. The state
    /// is untrusted: its grid, communication point, input history and contact summaries are
    /// checked here, the stepper's fields by [`Stepper::restore`]; nothing changes unless
    /// everything checks out.
    pub fn restore(&mut self, state: &SimulationState) -> Result<(), Error> {
        let grid = state
            .check(self.stepper.constrained_count())
            .map_err(|limit| Error::invalid("FMU state", "<state>", &limit))?;
        self.stepper.restore(&state.stepper)?;
        self.grid = grid;
        self.input = state.input.clone();
        self.point = state.point.clone();
        self.contact = state.contact;
        self.contact_ahead = state.contact_ahead;
        self.step_start = state.step_start;
        self.invalidate_outputs();
        Ok(())
    }
}

/// Checks the start of the last communication step read from an untrusted source, for a
/// communication point `elapsed` (t − t_start, s): finite, and strictly before that point, at
/// or after the start.
fn check_step_start(start: Option<StepStart>, elapsed: f64) -> Result<(), String> {
    let Some(s) = start else { return Ok(()) };
    if !(s.elapsed.is_finite() && s.impulse.is_finite()) {
        return Err(format!(
            "the last communication step's start ({} s, impulse {} N s) is not finite",
            s.elapsed, s.impulse
        ));
    }
    if !(0.0 <= s.elapsed && s.elapsed < elapsed) {
        return Err(format!(
            "the last communication step started {} s after the start, outside [0, {elapsed}) s",
            s.elapsed
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests;
