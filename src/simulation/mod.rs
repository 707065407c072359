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

/// [`BOUND_TOLERANCE`] × [`Scene::gap`] (m): g2 − g1 with both obstacles, |g| with one, 1 m with
/// none.
pub fn bound_tolerance(scene: &Scene) -> f64 {
    BOUND_TOLERANCE * scene.gap()
}

/// Refuses an initial state with a vertex past an obstacle (a static preload problem that was not
/// solved accurately), naming the vertex position and the obstacle.
fn check_initial_state(stepper: &Stepper) -> Result<(), Error> {
    let scene = stepper.scene();
    let constrained = stepper.constrained_displacements();
    match scene.first_outside(&constrained, bound_tolerance(scene)) {
        Some(outside) => Err(Error::ContactSolver(format!(
            "the initial state (static equilibrium under initial.preload_pressure = {} Pa) puts a vertex at u = {} m, past the obstacle at {} m: the static contact problem was not solved accurately for these parameters (material.young_modulus = {} Pa)",
            scene.initial.preload_pressure, outside.value, outside.level, scene.material.young_modulus
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
        let inside = scene.lower_obstacle().is_none_or(|g| z0 > g)
            && scene.upper_obstacle().is_none_or(|g| z0 < g);
        let reusable = scene.validate().is_ok()
            && inside
            && old.fixed_part() == scene.fixed_part()
            && (scene.initial.preload_pressure == 0.0
                || (*initial_external == external_base && old.obstacle == scene.obstacle));
        if !reusable {
            *self = Simulation::new(scene, start_time, external_base)?;
            return Ok(SetUp::Rebuilt);
        }
        let mut state = initial.clone();
        state.scene = scene.clone();
        state.base = [z0; 2];
        state.pressure = [scene.load.pressure; 2];
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

    /// d/dt of the displacement outputs `corner1`, `corner2`, `edge_mid` at the communication
    /// time (m/s): the slope of their interpolation, (y_N − y_{N−1})/Δt over the grid interval
    /// (t_{N−1}, t_N] that holds the communication time ([`interpolation`]); 0 at t_start.
    pub fn displacement_rates(&self) -> [f64; 3] {
        let [previous, current] = self.stepper.output_point_displacements();
        let dt = self.grid.step;
        [0, 1, 2].map(|k| interpolation::rate(previous[k], current[k], dt))
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
                    CommunicationPoint::Between { previous, .. } => Some(previous.clone()),
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
            (Some(elapsed), Some(previous)) => CommunicationPoint::Between { elapsed, previous },
            _ => CommunicationPoint::OnGrid,
        };
        self.interpolated = OnceCell::new();
        self.field = OnceCell::new();
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
mod tests {
    use super::*;

    /// One communication step of size `h` with the external base sample `value`.
    fn step(sim: &mut Simulation, h: f64, value: f64) -> CommunicationStep {
        let end = sim.step_end(h).unwrap();
        let sample = InputSample {
            value,
            ..InputSample::default()
        };
        sim.advance(&end, &sample, false, &mut |_| {}).unwrap()
    }

    /// A fixed pseudo-random factor in [0.2, 1.5] for communication step k.
    fn factor(k: usize) -> f64 {
        0.2 + 1.3 * (k as f64 * 0.618_034).fract()
    }

    /// Bits of corner1 and the energy after each of `steps` communication steps of 3Δt (on the
    /// grid) or, when `random`, of Δt × a factor in [0.6, 4.5] (mostly off the grid).
    fn trace(sim: &mut Simulation, steps: usize, random: bool) -> Vec<u64> {
        (0..steps)
            .map(|k| {
                let h = if random { 3e-4 * factor(k) } else { 3e-4 };
                step(sim, h, 1e-3 * (k as f64 * 0.4).sin());
                let o = sim.outputs();
                o.corner1.to_bits() ^ o.energy_total.to_bits()
            })
            .collect()
    }

    fn corner_trace(sim: &mut Simulation, steps: usize) -> Vec<u64> {
        trace(sim, steps, false)
    }

    fn small(mut scene: Scene) -> Scene {
        scene.mesh.nx = 3;
        scene.mesh.ny = 2;
        scene
    }

    /// Moving the obstacles and changing the pressure keep the cached outputs and vertex field:
    /// on a grid point and between two, they equal what a simulation restored from the new
    /// state computes afresh.
    #[test]
    fn tunable_sets_keep_the_cached_outputs_valid() {
        let mut sim = Simulation::new(&small(Scene::default()), 0.0, 0.0).unwrap();
        for h in [3e-4, 1.5e-4] {
            step(&mut sim, h, 1e-3);
            let cached = (sim.outputs().clone(), sim.vertex_field().clone());
            let o = sim.scene().obstacle.clone();
            sim.set_obstacles(o.lower - 1e-3, o.upper + 1e-3).unwrap();
            sim.set_pressure(sim.scene().load.pressure + 2e4).unwrap();
            let fresh = Simulation::from_state(&sim.state()).unwrap();
            assert_eq!(fresh.scene().obstacle.lower, o.lower - 1e-3);
            assert_eq!(*fresh.outputs(), cached.0, "h = {h}");
            assert_eq!(*fresh.vertex_field(), cached.1, "h = {h}");
        }
        assert!(matches!(sim.point, CommunicationPoint::Between { .. }));
    }

    #[test]
    fn restart_equals_a_fresh_simulation_bit_for_bit() {
        let a = small(Scene::default());
        let mut b = a.clone();
        b.load.pressure = 1e5;
        b.obstacle.lower = -0.004;
        let mut preloaded = b.clone();
        preloaded.initial.preload_pressure = -3e5;
        let mut finer = a.clone();
        finer.mesh.nx = 4;
        let mut sim = Simulation::new(&a, 0.0, 0.0).unwrap();
        corner_trace(&mut sim, 5);
        for (scene, start, external, how) in [
            (&b, 0.5, 2e-3, SetUp::Reused),
            (&a, 0.0, 0.0, SetUp::Reused),
            (&preloaded, 0.0, 0.0, SetUp::Rebuilt),
            (&preloaded, 0.0, 0.0, SetUp::Reused),
            (&preloaded, 0.0, 1e-3, SetUp::Rebuilt),
            (&finer, 0.0, 0.0, SetUp::Rebuilt),
        ] {
            assert_eq!(sim.restart(scene, start, external).unwrap(), how);
            let mut fresh = Simulation::new(scene, start, external).unwrap();
            assert_eq!(sim.outputs(), fresh.outputs());
            assert_eq!(sim.time(), start);
            assert_eq!(corner_trace(&mut sim, 40), corner_trace(&mut fresh, 40));
        }
    }

    #[test]
    fn state_round_trip_continues_bit_identically() {
        let mut scene = small(Scene::default());
        scene.base.amplitude = 0.005;
        let mut sim = Simulation::new(&scene, 0.25, 0.0).unwrap();
        corner_trace(&mut sim, 7);
        let state = sim.state();
        let expected = corner_trace(&mut sim, 30);
        let mut other = Simulation::from_state(&state).unwrap();
        assert_eq!(other.time(), 0.25 + 21.0 * 1e-4);
        assert_eq!(corner_trace(&mut other, 30), expected);
        sim.restore(&state).unwrap();
        assert_eq!(corner_trace(&mut sim, 30), expected);
    }

    #[test]
    fn restore_refuses_inconsistent_histories_and_grids() {
        let scene = small(Scene::default());
        let mut sim = Simulation::new(&scene, 0.0, 0.0).unwrap();
        corner_trace(&mut sim, 2);
        let good = sim.state();
        let mut future = good.clone();
        future.input.last_sample = Some((1.0, 0.0));
        let err = sim.restore(&future).unwrap_err().to_string();
        assert!(err.contains("outside"), "{err}");
        let mut far = good.clone();
        far.start_time = -1e308;
        let err = sim.restore(&far).unwrap_err().to_string();
        assert!(err.contains("too coarse"), "{err}");
        assert_eq!(sim.state(), good, "a refused restore changes nothing");
    }

    /// A time step whose square overflows is refused at set-up, naming the parameter; the largest
    /// one whose square is finite is accepted.
    #[test]
    fn a_time_step_whose_square_overflows_is_refused() {
        let mut scene = small(Scene::default());
        scene.solver.time_step = 1e155;
        let err = Simulation::new(&scene, 0.0, 0.0).err().unwrap();
        assert!(err.to_string().contains("solver.time_step"), "{err}");
        scene.solver.time_step = 1e154;
        assert!(Simulation::new(&scene, 0.0, 0.0).is_ok());
    }

    #[test]
    fn an_inaccurate_initial_state_is_refused() {
        let mut scene = small(Scene::default());
        scene.material.young_modulus = 1e-3;
        scene.initial.preload_pressure = 1e5;
        let err = Simulation::new(&scene, 0.0, 5e-3)
            .err()
            .unwrap()
            .to_string();
        assert!(err.contains("past the obstacle"), "{err}");
    }

    #[test]
    fn observer_sees_every_internal_step_on_the_grid() {
        let scene = small(Scene::default());
        let mut sim = Simulation::new(&scene, 1.0, 0.0).unwrap();
        let mut times = Vec::new();
        let end = sim.step_end(4e-4).unwrap();
        let summary = sim
            .advance(&end, &InputSample::default(), false, &mut |s| {
                times.push(s.time)
            })
            .unwrap();
        assert_eq!(summary.internal_steps, 4);
        assert_eq!(
            times,
            (1..=4).map(|n| 1.0 + n as f64 * 1e-4).collect::<Vec<_>>()
        );
        // A step ending between t_5 and t_6 computes up to t_6; the next one, ending before t_6,
        // computes nothing.
        assert_eq!(step(&mut sim, 1.5e-4, 0.0).internal_steps, 2);
        assert_eq!((sim.step_index(), sim.time()), (6, 1.0 + 5.5e-4));
        assert_eq!(sim.grid_time(), 1.0 + 6e-4);
        assert_eq!(step(&mut sim, 0.2e-4, 0.0).internal_steps, 0);
        assert_eq!(sim.step_index(), 6);
        assert!((sim.time() - (1.0 + 5.7e-4)).abs() < 1e-15);
    }

    /// The built-in sine alone: the grid, and so every grid value, is the same whatever the
    /// communication steps.
    #[test]
    fn the_internal_trajectory_does_not_depend_on_the_communication_steps() {
        let mut scene = small(Scene::default());
        scene.base.amplitude = 0.009;
        scene.base.frequency = 35.0;
        let mut fixed = Simulation::new(&scene, 0.0, 0.0).unwrap();
        let mut random = Simulation::new(&scene, 0.0, 0.0).unwrap();
        let mut k = 0;
        while random.time() < 0.2 {
            step(&mut random, 1e-3 * factor(k), 0.0);
            k += 1;
        }
        // Land on the next grid point, then bring the fixed run there in whole steps.
        let n = random.step_index();
        let rest = random.grid_time() - random.time();
        step(&mut random, rest, 0.0);
        assert_eq!(random.step_index(), n);
        assert_eq!(random.time(), random.grid_time());
        while fixed.step_index() < n {
            step(&mut fixed, 1e-4, 0.0);
        }
        assert_eq!(random.state().stepper, fixed.state().stepper);
        assert_eq!(random.outputs(), fixed.outputs());
    }

    /// Released from a preload onto the lower obstacle with a fixed base, no load and e = 0: the
    /// energy never increases between communication points of random size, the free corners
    /// respect the obstacles at every communication point, and every vertex at every grid point.
    #[test]
    fn energy_never_increases_between_communication_points() {
        let mut scene = small(Scene::default());
        scene.obstacle.upper_enabled = false;
        scene.initial.preload_pressure = 8600.0 / (0.4 * 0.2);
        let mut sim = Simulation::new(&scene, 0.0, 0.0).unwrap();
        let scale = sim.outputs().energy_total.abs();
        let lower = scene.obstacle.lower;
        let mut energy = sim.outputs().energy_total;
        let mut between = 0;
        for k in 0..1500 {
            step(&mut sim, 1e-4 * 3.0 * factor(k), 0.0);
            let o = sim.outputs().clone();
            // Round-off: the energy identity holds per grid step to ~1e-13 of the scale.
            assert!(
                o.energy_total <= energy + 1e-12 * scale,
                "step {k}: the energy rose from {energy} J to {} J",
                o.energy_total
            );
            energy = o.energy_total;
            // Round-off of the contact solve: bounds hold to 1e-12 m.
            assert!(o.corner1 >= lower - 1e-12 && o.corner2 >= lower - 1e-12);
            let vertices = sim.stepper.constrained_displacements();
            assert!(vertices.iter().all(|&u| u >= lower - 1e-12));
            between += usize::from(sim.time() != sim.grid_time());
        }
        assert!(between > 1000, "only {between} points off the grid");
        assert!(
            energy < 0.9 * scale,
            "no impact took energy: {energy} J of {scale} J"
        );
    }

    /// Every internal step's contact is reported once, with the communication step that reaches
    /// its grid time: random steps give the totals of single internal steps.
    #[test]
    fn contact_between_communication_points_is_reported_once() {
        let mut scene = small(Scene::default());
        scene.base.amplitude = 0.009;
        scene.base.frequency = 35.0;
        let totals = |random: bool| {
            let mut sim = Simulation::new(&scene, 0.0, 0.0).unwrap();
            let mut total = ContactSummary::default();
            let mut k = 0;
            while sim.time() < 0.3 - 1e-12 {
                let h = if random { 1e-3 * factor(k) } else { 1e-4 };
                let h = h.min(0.3 - sim.time());
                step(&mut sim, h, 0.0);
                total.merge(sim.contact());
                k += 1;
            }
            assert_eq!(
                sim.time(),
                sim.grid_time(),
                "the last step lands on t = 0.3 s"
            );
            total
        };
        let (fine, random) = (totals(false), totals(true));
        assert!(fine.impacts > 5, "{fine:?}");
        assert_eq!(random.impacts, fine.impacts);
        assert_eq!(random.peak_force, fine.peak_force);
        // The same terms summed in other groups: round-off only.
        assert!((random.impulse - fine.impulse).abs() <= 1e-12 * fine.impulse.abs());
    }

    /// The forced 35 Hz scene on the small mesh: impacts on both obstacles within 0.3 s.
    fn forced_35hz() -> Scene {
        let mut scene = small(Scene::default());
        scene.base.amplitude = 0.009;
        scene.base.frequency = 35.0;
        scene
    }

    /// Early return: with the built-in sine as the only base motion, communication steps of random
    /// size that stop at impacts have a communication point at the grid time of every impact, and
    /// the grid trajectory is the one of single internal steps, bit for bit. Both ways of stopping
    /// occur: after the internal step of the impact, and at once when the previous communication
    /// step had computed it ahead.
    #[test]
    fn steps_that_stop_at_impacts_have_a_point_at_every_impact() {
        let scene = forced_35hz();
        let stop = 3000;
        let mut fine = Simulation::new(&scene, 0.0, 0.0).unwrap();
        let mut grid_bits = vec![trace_bits(fine.outputs())];
        let mut impacts = Vec::new();
        // Beyond `stop` by more than the longest communication step (15 internal steps).
        for n in 1..=stop + 20 {
            let end = fine.step_end(1e-4).unwrap();
            let mut impact = false;
            fine.advance(&end, &InputSample::default(), true, &mut |s| {
                impact |= s.report.impact
            })
            .unwrap();
            grid_bits.push(trace_bits(fine.outputs()));
            if impact && n <= stop {
                impacts.push(n);
            }
        }
        assert!(impacts.len() > 5, "{impacts:?}");
        let mut sim = Simulation::new(&scene, 0.0, 0.0).unwrap();
        let (mut reached, mut in_loop, mut at_once) = (Vec::new(), 0, 0);
        let mut k = 0;
        while sim.step_index() < stop {
            let end = sim.step_end(1e-3 * factor(k)).unwrap();
            let summary = sim
                .advance(&end, &InputSample::default(), true, &mut |_| {})
                .unwrap();
            if summary.stopped_at_impact {
                assert_eq!(
                    sim.time(),
                    sim.grid_time(),
                    "an early return lands on the grid"
                );
                if summary.internal_steps == 0 {
                    at_once += 1;
                } else {
                    in_loop += 1;
                }
            }
            if sim.time() == sim.grid_time() {
                let n = sim.step_index();
                assert_eq!(
                    trace_bits(sim.outputs()),
                    grid_bits[n as usize],
                    "grid point {n}"
                );
                reached.push(n);
            }
            k += 1;
        }
        let missed: Vec<_> = impacts.iter().filter(|n| !reached.contains(n)).collect();
        assert!(
            missed.is_empty(),
            "no communication point at the impacts {missed:?}"
        );
        assert_eq!(
            in_loop + at_once,
            impacts.len(),
            "one early return per impact"
        );
        assert!(
            in_loop > 0 && at_once > 0,
            "{in_loop} in the loop, {at_once} at once"
        );
    }

    /// Bits of corner1 and the energy of some outputs.
    fn trace_bits(o: &Outputs) -> u64 {
        o.corner1.to_bits() ^ o.energy_total.to_bits().rotate_left(1)
    }

    /// The vertex field: on the grid its free corners are the corner outputs and the clamp carries
    /// the base; between grid points it and the displacement outputs are interpolated, and their
    /// rates are the slope of that interpolation, so extrapolating with them lands on the next
    /// grid point; with and without obstacles (the two ways the vertex values are read).
    #[test]
    fn the_vertex_field_and_the_rates_follow_the_interpolation() {
        let (nx, ny) = (3, 2);
        let (corner1, corner2) = (nx, nx + ny * (nx + 1));
        for obstacles in [true, false] {
            let mut scene = small(Scene::default());
            scene.base.amplitude = 0.004;
            scene.base.frequency = 35.0;
            scene.obstacle.lower_enabled = obstacles;
            scene.obstacle.upper_enabled = obstacles;
            let mut sim = Simulation::new(&scene, 0.0, 0.0).unwrap();
            assert_eq!(sim.displacement_rates(), [0.0; 3], "released at rest");
            assert!(sim.vertex_field().rate.iter().all(|&r| r == 0.0));
            for k in 0..40 {
                step(&mut sim, 1e-4 * (0.3 + 2.0 * factor(k)), 0.0);
                let o = sim.outputs().clone();
                let field = sim.vertex_field().clone();
                let rates = sim.displacement_rates();
                assert_eq!(field.displacement.len(), (nx + 1) * (ny + 1));
                // Two functionals of the same field (the point evaluation at the corner and
                // the vertex value): equal to round-off, 1e-12 of the 4 mm amplitude.
                let close = |a: f64, b: f64| (a - b).abs() <= 4e-15;
                assert!(
                    close(field.displacement[corner1], o.corner1),
                    "{k}: corner1"
                );
                assert!(
                    close(field.displacement[corner2], o.corner2),
                    "{k}: corner2"
                );
                // Their difference over Δt = 1e-4 s.
                let rate_gap = (field.rate[corner1] - rates[0]).abs();
                assert!(rate_gap <= 8e-11, "{k}: rates differ by {rate_gap} m/s");
                // The clamp follows the base: every clamp vertex has the same value.
                let clamp: Vec<f64> = (0..=ny).map(|j| field.displacement[j * (nx + 1)]).collect();
                assert!(clamp.iter().all(|&z| z == clamp[0]), "{clamp:?}");
                let (t, t_grid) = (sim.time(), sim.grid_time());
                if t != t_grid {
                    let ahead = t_grid - t;
                    let predicted = [
                        o.corner1 + rates[0] * ahead,
                        field.displacement[corner2] + field.rate[corner2] * ahead,
                    ];
                    step(&mut sim, ahead, 0.0);
                    assert_eq!(sim.time(), sim.grid_time(), "snapped onto t_N");
                    let landed = [
                        sim.outputs().corner1,
                        sim.vertex_field().displacement[corner2],
                    ];
                    for (p, l) in predicted.iter().zip(landed) {
                        // Round-off of (a + (b − a)θ) + (b − a)(1 − θ): a few ulps of 4 mm.
                        assert!((p - l).abs() <= 4e-15, "{k}: predicted {p}, landed {l}");
                    }
                    assert_eq!(
                        sim.displacement_rates(),
                        rates,
                        "the same slope from the left"
                    );
                }
            }
        }
    }

    #[test]
    fn state_round_trip_between_grid_points_continues_bit_identically() {
        let mut scene = small(Scene::default());
        scene.base.amplitude = 0.005;
        let mut sim = Simulation::new(&scene, 0.25, 0.0).unwrap();
        trace(&mut sim, 8, true);
        assert_ne!(
            sim.time(),
            sim.grid_time(),
            "the test needs a point between"
        );
        let state = sim.state();
        let expected = trace(&mut sim, 30, true);
        let mut other = Simulation::from_state(&state).unwrap();
        assert_eq!(trace(&mut other, 30, true), expected);
        sim.restore(&state).unwrap();
        assert_eq!(trace(&mut sim, 30, true), expected);
        // A crafted point outside its grid interval is refused, naming it.
        let mut crafted = state.clone();
        if let CommunicationPoint::Between { elapsed, .. } = &mut crafted.point {
            *elapsed += 1e-4;
        }
        let err = sim.restore(&crafted).unwrap_err().to_string();
        assert!(err.contains("communication point"), "{err}");
    }
}
