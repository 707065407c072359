//! The plate's model binding: the FMU variables ↔ a [`Scene`] (parameters), the external base
//! displacement (input) and the [`Outputs`](crate::simulation::Outputs), the vertex field and the
//! displacement rates of a [`Simulation`]; the experiment; the communication step (ended early at
//! an impact when the importer allows it); the FMU state and its validation. It knows nothing of
//! a particular FMI version (see [`crate::fmi::model`]); both versions' descriptions declare the
//! same variables, with the same value references, which is what it binds.
//!
//! The simulation is set up lazily: sets before the end of initialization only change the
//! parameters; the set-up runs when an output is read in Initialization mode or at the exit of
//! initialization, and a second set-up reuses the assembled plate when no fixed parameter changed
//! ([`Simulation::restart`]). Outputs are computed once per state and cached.

mod snapshot;
mod values;

pub use snapshot::PlateSnapshot;
/// The FMI value of parameter `v` in `scene`, as the FMU reports it (the element family as its
/// code): for the parameter sets shipped in the FMU (`src/bin/package-fmu/contents.rs`).
pub use values::{parameter as parameter_value, text_parameter};

use crate::advice::StatisticsAdvice;
use crate::fmi::ffi::panic_text;
use crate::fmi::logger::{Logger, LOG_WARNING};
use crate::fmi::model::{
    Array, Checked, Derivative, Model, Phase, StepOptions, StepOutcome, Value,
};
use crate::fmi::status::{Failure, Status};
use crate::fmi::variables::{self, vr, Causality, Description, Start, Variable};
use crate::scene::Scene;
use crate::simulation::grid::TimeGrid;
use crate::simulation::input::InputSample;
use crate::simulation::{InternalStep, SetUp, Simulation};
use std::cell::OnceCell;
use std::panic::{catch_unwind, AssertUnwindSafe};
use values::{first_non_finite, first_past_obstacle};

/// Log category of contact events: vertices entering or leaving contact, and the solver path.
pub const LOG_CONTACT: &str = "logContact";

/// Relative tolerance between the host's communication point and the FMU time, and between the
/// end of a step and the stop time.
const TIME_TOLERANCE: f64 = 1e-9;

/// Whether a communication time `now` lies beyond the stop time `stop` of an experiment that
/// starts at `start` with internal step `dt`: now > stop + 1e-9·max(|stop|, stop − start, Δt),
/// forgiving a host's round-off in t + h relative to the experiment's scale (any step of it has
/// h ≤ stop − start). fmi2DoStep refuses such a step and a restored FMU state such a time with
/// this one rule, so that every state a step reaches can be restored.
fn beyond_stop_time(now: f64, start: f64, stop: f64, dt: f64) -> bool {
    now > stop + TIME_TOLERANCE * stop.abs().max(stop - start).max(dt)
}

/// The staged values of a set: the parameters and the input.
pub struct Draft {
    parameters: Scene,
    input: f64,
}

/// The plate behind one FMU instance.
pub struct PlateModel {
    /// The parameters as set (tunable ones at their current values once stepping).
    parameters: Scene,
    start_time: f64,
    stop_time: Option<f64>,
    /// The external base displacement sampled at the current communication point (m).
    input: f64,
    /// Derivatives of orders 1 and 2 of the input, sent for the next communication step.
    input_derivatives: [Option<f64>; 2],
    simulation: Option<Simulation>,
    /// [`unsound_outputs`] of `simulation`, once asked for; emptied by every access that may
    /// change the simulation, so that a host reading its outputs one value reference at a time
    /// checks them once per state.
    verdict: OnceCell<Option<String>>,
    /// Whether `simulation` was set up for the current parameters, input and start time, or
    /// its set-up for them was refused.
    readiness: Readiness,
    /// How many times the plate was assembled and its backend built (the expensive set-up).
    full_set_ups: u64,
}

/// Whether the model's simulation belongs to its current parameters, input and start time.
#[derive(Clone, Debug, PartialEq)]
enum Readiness {
    /// Not set up for them: the next access that needs the simulation sets it up.
    Stale,
    /// Set up for them.
    Ready,
    /// Their set-up was refused with this failure. Kept, so that a host reading every output of
    /// a scene that cannot be set up gets the refusal at once instead of a set-up per value
    /// reference (the set-up is a function of the parameters, input and start time alone).
    Refused(Failure),
}

/// Start value of the input `base.displacement`.
fn input_start() -> f64 {
    match variables::FMI2
        .by_name("base.displacement")
        .and_then(|v| v.start.clone())
    {
        Some(Start::Real(x)) => x,
        _ => 0.0,
    }
}

/// Checks that doubles resolve the internal steps at the experiment's start and stop times.
fn check_experiment(scene: &Scene, start: f64, stop: Option<f64>) -> Result<(), Failure> {
    if !start.is_finite() {
        return Err(Failure::refused(format!(
            "startTime = {start} s must be finite"
        )));
    }
    if let Some(stop) = stop {
        if !(stop.is_finite() && stop >= start) {
            return Err(Failure::refused(format!(
                "stopTime = {stop} s must be finite and >= startTime = {start} s"
            )));
        }
    }
    let grid = TimeGrid {
        start,
        step: scene.solver.time_step,
    };
    for (name, t) in [("startTime", Some(start)), ("stopTime", stop)] {
        if let Some(t) = t {
            grid.check_resolves(t)
                .map_err(|e| Failure::refused(format!("{name} = {t} s is refused: {e}")))?;
        }
    }
    Ok(())
}

impl PlateModel {
    /// Sets the simulation up for the current parameters, input and start time unless it already
    /// is (reusing the assembled plate when possible).
    fn ensure_simulation(&mut self) -> Result<&Simulation, Failure> {
        if let Readiness::Refused(failure) = &self.readiness {
            return Err(failure.clone());
        }
        if self.readiness == Readiness::Stale || self.simulation.is_none() {
            self.verdict = OnceCell::new();
            if let Err(failure) = self.set_up() {
                self.readiness = Readiness::Refused(failure.clone());
                return Err(failure);
            }
            self.readiness = Readiness::Ready;
        }
        Ok(self.simulation.as_ref().expect("set up above"))
    }

    /// Sets the simulation up for the current parameters, input and start time (the expensive
    /// part of [`PlateModel::ensure_simulation`]).
    fn set_up(&mut self) -> Result<(), Failure> {
        self.parameters.validate()?;
        check_experiment(&self.parameters, self.start_time, self.stop_time)?;
        let (scene, start, input) = (&self.parameters, self.start_time, self.input);
        let simulation = &mut self.simulation;
        // The set-up is a function of the parameters alone: a panic inside the library (a
        // geometry the elements cannot handle) leaves the model as it was and is refused.
        let set_up = catch_unwind(AssertUnwindSafe(|| match simulation {
            Some(sim) => sim.restart(scene, start, input),
            None => {
                *simulation = Some(Simulation::new(scene, start, input)?);
                Ok(SetUp::Rebuilt)
            }
        }))
        .map_err(|payload| {
            Failure::refused(format!(
                "the plate could not be set up for these parameters ({}); check that they describe a plate the elements can mesh",
                panic_text(payload.as_ref())
            ))
        });
        self.full_set_ups += u64::from(!matches!(set_up, Ok(Ok(SetUp::Reused))));
        set_up??;
        Ok(())
    }

    /// How many times this model assembled the plate and built its backend, or tried to and was
    /// refused (for tests and diagnostics: sets before the end of initialization must not each
    /// cost a set-up, nor reads of a scene that cannot be set up).
    pub fn full_set_ups(&self) -> u64 {
        self.full_set_ups
    }

    /// The simulation, to change it (which empties the cached verdict on its outputs).
    fn running_simulation(&mut self) -> Result<&mut Simulation, Failure> {
        self.verdict = OnceCell::new();
        self.simulation.as_mut().ok_or_else(never_set_up)
    }

    /// The simulation of this run in `phase`: one set up for the current parameters, input and
    /// start time, in a phase where it runs (Initialization sets it up first). The model keeps
    /// the simulation of an earlier run (after a reset, or parameters set before
    /// initialization) only to reuse its assembled plate: that one is no part of the run, even
    /// where an error ends the instance (FMI 3.0 ends every error in Terminated).
    fn run_simulation(&self, phase: Phase) -> Option<&Simulation> {
        let running = phase.running() || phase == Phase::Initialization;
        self.simulation
            .as_ref()
            .filter(|_| running && self.readiness == Readiness::Ready)
    }

    /// The simulation whose outputs may be read in `phase` (set up first in Initialization mode),
    /// refused when they are unsound.
    fn readable_simulation(&mut self, phase: Phase) -> Result<&Simulation, Failure> {
        if phase == Phase::Initialization {
            self.ensure_simulation()?;
        }
        let sim = self.run_simulation(phase).ok_or_else(never_set_up)?;
        match self.verdict.get_or_init(|| unsound_outputs(sim)) {
            Some(message) => Err(Failure::refused(message.clone())),
            None => Ok(sim),
        }
    }
}

/// The refusal of a call that needs the simulation of this run before one was set up.
fn never_set_up() -> Failure {
    Failure::refused(
        "the simulation is not available: it was not set up for this run (initialization sets it up)",
    )
}

/// The shape of the displacement field of `sim`: (ny + 1) rows along y × (nx + 1) columns along
/// x, the mesh's vertex order.
fn field_shape(sim: &Simulation) -> Vec<u64> {
    let mesh = &sim.scene().mesh;
    vec![mesh.ny as u64 + 1, mesh.nx as u64 + 1]
}

/// `values` of output `name` at the time of `sim`, or a refusal naming the first that is not
/// finite.
fn finite<'a>(sim: &Simulation, name: &str, values: &'a [f64]) -> Result<&'a [f64], Failure> {
    match values.iter().position(|x| !x.is_finite()) {
        None => Ok(values),
        Some(k) => Err(Failure::refused(format!(
            "{name}[{k}] = {} at t = {} s is not finite",
            values[k],
            sim.time()
        ))),
    }
}

/// Logs what the host should know of one internal step: vertices entering or leaving contact
/// under logContact, and under logStatusWarning a step solved less exactly than the normal path.
fn report_internal_step(log: &mut Logger, step: &InternalStep) {
    if step.report.active != step.previously_active && log.enabled(LOG_CONTACT) {
        let message = format!(
            "t = {} s: {} vertices in contact (was {}), path {:?}",
            step.time, step.report.active, step.previously_active, step.report.path
        );
        log.log(Status::Ok, LOG_CONTACT, &message);
    }
    if let Some(why) = step.degraded() {
        let message = format!("t = {} s: {why}", step.time);
        log.log(Status::Warning, LOG_WARNING, &message);
    }
}

/// What the last communication step of `sim` reports besides its outputs.
fn last_step(sim: &Simulation) -> values::LastStep {
    let rates = sim.displacement_rates();
    values::LastStep {
        contact: *sim.contact(),
        base_mean_force: sim.base_mean_force(),
        probe_velocities: std::array::from_fn(|k| rates[3 + k]),
    }
}

/// Why the outputs of `sim` may not be reported with fmi2OK, if they may not: an output that is
/// not finite (the simulation overflowed), or a free corner past an obstacle (a contact problem
/// that was not solved, such as under a pressure of 1e308 Pa).
fn unsound_outputs(sim: &Simulation) -> Option<String> {
    let (outputs, t) = (sim.outputs(), sim.time());
    if let Some((name, x)) = first_non_finite(outputs, &last_step(sim)) {
        return Some(format!(
            "the output {name} = {x} at t = {t} s is not finite: the simulation overflowed (a base displacement or load far beyond the plate's scale?)"
        ));
    }
    first_past_obstacle(outputs, sim.scene(), sim.stepper().corner_heights()).map(|(name, u, g)| {
        format!(
            "the output {name} = {u} m at t = {t} s lies past the obstacle at {g} m: the contact problem was not solved (a load or base displacement far beyond the plate's scale?)"
        )
    })
}

impl Model for PlateModel {
    type Draft = Draft;
    type Snapshot = PlateSnapshot;

    const FMI2: &'static Description = &variables::FMI2;
    const FMI3: &'static Description = &variables::FMI3;

    fn new() -> PlateModel {
        PlateModel {
            parameters: Scene::default(),
            start_time: 0.0,
            stop_time: None,
            input: input_start(),
            input_derivatives: [None, None],
            simulation: None,
            verdict: OnceCell::new(),
            readiness: Readiness::Stale,
            full_set_ups: 0,
        }
    }

    fn reset(&mut self) {
        *self = PlateModel {
            simulation: self.simulation.take(),
            full_set_ups: self.full_set_ups,
            ..PlateModel::new()
        };
    }

    fn setup_experiment(&mut self, start: f64, stop: Option<f64>) -> Result<(), Failure> {
        check_experiment(&self.parameters, start, stop)?;
        self.start_time = start;
        self.stop_time = stop;
        self.readiness = Readiness::Stale;
        Ok(())
    }

    fn exit_initialization(&mut self, log: &mut Logger) -> Result<Status, Failure> {
        self.readable_simulation(Phase::Initialization)?;
        // The advice changes no result: a message of status Warning under logStatusWarning, while
        // the call succeeds (strict importers such as fmusim stop at a returned Warning).
        if let Some(advice) = StatisticsAdvice::of(&self.parameters) {
            log.log(Status::Warning, LOG_WARNING, &advice.message());
        }
        Ok(Status::Ok)
    }

    fn time(&self, phase: Phase) -> f64 {
        match self.run_simulation(phase) {
            Some(sim) if phase.running() => sim.time(),
            _ => self.start_time,
        }
    }

    fn get(&mut self, v: &Variable, phase: Phase) -> Result<Value, Failure> {
        match v.causality {
            Causality::Output => {
                let sim = self.readable_simulation(phase)?;
                values::output(sim.outputs(), &last_step(sim), v)
            }
            Causality::Input => Ok(Value::Real(self.input)),
            Causality::CalculatedParameter => match values::frequency_index(v) {
                Some(k) => {
                    let sim = self.readable_simulation(phase)?;
                    let frequencies = sim.stepper().natural_frequencies(k + 1)?;
                    let f = frequencies.get(k).copied().ok_or_else(|| {
                        Failure::refused(format!(
                            "{}: the plate as set up has only {} modes (free dofs)",
                            v.name,
                            frequencies.len()
                        ))
                    })?;
                    Ok(Value::Real(f))
                }
                None => values::calculated(&self.parameters, v),
            },
            _ => values::parameter(&self.parameters, v),
        }
    }

    fn get_string(&mut self, v: &Variable, _: Phase) -> Result<String, Failure> {
        values::text_parameter(&self.parameters, v).map(str::to_string)
    }

    fn get_array(&mut self, v: &Variable, phase: Phase) -> Result<Array<'_>, Failure> {
        if v.vr != vr::PLATE_DISPLACEMENT {
            return Err(Failure::refused(format!(
                "{} has no array binding (internal error)",
                v.name
            )));
        }
        let sim = self.readable_simulation(phase)?;
        Ok(Array {
            shape: field_shape(sim),
            values: finite(sim, v.name, &sim.vertex_field().displacement)?,
        })
    }

    fn output_derivative(
        &mut self,
        v: &Variable,
        order: i32,
        phase: Phase,
    ) -> Result<Derivative<'_>, Failure> {
        let point = values::displacement_point(v);
        if v.vr != vr::PLATE_DISPLACEMENT && point.is_none() {
            return Err(Failure::refused(format!(
                "{} has no derivative: this FMU gives d/dt of the displacement outputs only ({})",
                v.name,
                values::DISPLACEMENT_OUTPUTS.join(", ")
            )));
        }
        if order != 1 {
            return Err(Failure::refused(format!(
                "the derivative of order {order} of {} is not provided: order 1 only (maxOutputDerivativeOrder = 1)",
                v.name
            )));
        }
        let sim = self.readable_simulation(phase)?;
        Ok(match point {
            Some(k) => Derivative::Scalar(sim.displacement_rates()[k]),
            None => Derivative::Array(Array {
                shape: field_shape(sim),
                values: finite(sim, v.name, &sim.vertex_field().rate)?,
            }),
        })
    }

    fn draft(&self) -> Draft {
        Draft {
            parameters: self.parameters.clone(),
            input: self.input,
        }
    }

    fn stage(
        &self,
        draft: &mut Draft,
        v: &Variable,
        value: Value,
        _: Phase,
    ) -> Result<(), Failure> {
        match (v.causality, value) {
            (Causality::Input, Value::Real(x)) if x.is_finite() => draft.input = x,
            (Causality::Input, Value::Real(x)) => {
                return Err(crate::Error::invalid(v.name, x, "must be finite").into())
            }
            (Causality::Parameter, _) => {
                draft.parameters = values::with_parameter(&draft.parameters, v, value)?
            }
            _ => {
                return Err(Failure::refused(format!(
                    "{} cannot take the value {value:?}",
                    v.name
                )))
            }
        }
        Ok(())
    }

    fn stage_string(
        &self,
        draft: &mut Draft,
        v: &Variable,
        text: &str,
        _: Phase,
    ) -> Result<(), Failure> {
        if v.causality != Causality::Parameter {
            return Err(Failure::refused(format!(
                "{} cannot take a text (internal error)",
                v.name
            )));
        }
        draft.parameters = values::with_text_parameter(&draft.parameters, v, text)?;
        Ok(())
    }

    fn commit(&mut self, draft: Draft, phase: Phase) -> Result<(), Failure> {
        if phase == Phase::Stepping {
            let (new, old) = (&draft.parameters, &self.parameters);
            let obstacles_moved = new.obstacle.lower != old.obstacle.lower
                || new.obstacle.upper != old.obstacle.upper;
            let pressure_changed = new.load.pressure != old.load.pressure;
            let (lower, upper, pressure) =
                (new.obstacle.lower, new.obstacle.upper, new.load.pressure);
            let sim = self.running_simulation()?;
            // The only fallible part comes first; the pressure was checked finite when staged.
            if obstacles_moved {
                sim.set_obstacles(lower, upper)?;
            }
            if pressure_changed {
                sim.set_pressure(pressure)?;
            }
        } else if draft.parameters != self.parameters || draft.input != self.input {
            self.readiness = Readiness::Stale;
        }
        self.parameters = draft.parameters;
        self.input = draft.input;
        Ok(())
    }

    fn set_input_derivatives(&mut self, items: &[(&Variable, i32, f64)]) -> Result<(), Failure> {
        let mut derivatives = self.input_derivatives;
        for &(v, order, x) in items {
            if v.vr != vr::BASE_DISPLACEMENT {
                return Err(Failure::refused(format!("{} is not an input", v.name)));
            }
            if !(1..=2).contains(&order) {
                return Err(Failure::refused(format!(
                    "order {order} of {} is not supported (1 or 2)",
                    v.name
                )));
            }
            if !x.is_finite() {
                return Err(crate::Error::invalid(
                    &format!("der({}, {order})", v.name),
                    x,
                    "must be finite",
                )
                .into());
            }
            derivatives[(order - 1) as usize] = Some(x);
        }
        self.input_derivatives = derivatives;
        Ok(())
    }

    fn do_step(
        &mut self,
        t: f64,
        h: f64,
        options: StepOptions,
        log: &mut Logger,
    ) -> Result<StepOutcome, Failure> {
        let stop_time = self.stop_time;
        let sample = InputSample {
            value: self.input,
            slope: self.input_derivatives[0],
            curvature: self.input_derivatives[1],
        };
        let sim = self.running_simulation()?;
        let now = sim.time();
        let end = sim
            .step_end(h)
            .map_err(|e| Failure::refused(e.to_string()))?;
        if !(t.is_finite() && (t - now).abs() <= TIME_TOLERANCE * now.abs().max(h)) {
            return Err(Failure::refused(format!(
                "currentCommunicationPoint = {t} s differs from the FMU time {now} s (where the last step ended)"
            )));
        }
        let grid = sim.grid();
        let grid_end = grid.time(end.index);
        grid.check_resolves(grid_end).map_err(|e| {
            Failure::refused(format!("the step to t = {grid_end} s is refused: {e}"))
        })?;
        let end_time = grid.start + end.elapsed(grid);
        if let Some(stop) = stop_time {
            if beyond_stop_time(end_time, grid.start, stop, grid.step) {
                return Err(Failure::refused(format!(
                    "the step to t = {end_time} s goes beyond stopTime = {stop} s set by fmi2SetupExperiment"
                )));
            }
        }
        let mut observer = |step: &InternalStep| report_internal_step(log, step);
        let summary = sim.advance(&end, &sample, options.early_return, &mut observer);
        let at = sim.time();
        let summary = summary.map_err(|e| {
            Failure::broken(format!(
                "the step from t = {now} s failed at t = {at} s: {e}. The instance is now in the Error state: restore an FMU state, or reset"
            ))
        })?;
        if let Some(message) = unsound_outputs(sim) {
            return Err(Failure::broken(format!(
                "{message}. The instance is now in the Error state: restore an FMU state, or reset"
            )));
        }
        self.verdict = OnceCell::from(None);
        self.input_derivatives = [None, None];
        Ok(StepOutcome {
            status: if summary.degraded_steps > 0 {
                Status::Warning
            } else {
                Status::Ok
            },
            early_return: summary.stopped_at_impact,
        })
    }

    fn snapshot(&self, phase: Phase) -> PlateSnapshot {
        PlateSnapshot {
            parameters: self.parameters.clone(),
            start_time: self.start_time,
            stop_time: self.stop_time,
            input: self.input,
            input_derivatives: self.input_derivatives,
            simulation: self
                .run_simulation(phase)
                .filter(|_| phase.running())
                .map(Simulation::state),
        }
    }

    fn validate(snapshot: &PlateSnapshot, phase: Phase) -> Result<(), Failure> {
        snapshot.validate(phase)
    }

    fn restore(&mut self, checked: Checked<'_, PlateSnapshot>) -> Result<(), Failure> {
        let snap = checked.snapshot();
        self.verdict = OnceCell::new();
        match &snap.simulation {
            None => self.readiness = Readiness::Stale,
            Some(state) => {
                let fixed = state.stepper.scene.fixed_part();
                match &mut self.simulation {
                    Some(sim) if sim.scene().fixed_part() == fixed => {
                        let old = sim.state();
                        sim.restore(state)?;
                        if let Some(message) = unsound_outputs(sim) {
                            sim.restore(&old).map_err(|e| {
                                Failure::broken(format!(
                                    "{message}; restoring the previous state failed too: {e}"
                                ))
                            })?;
                            return Err(Failure::refused(format!(
                                "the FMU state is refused: {message}"
                            )));
                        }
                    }
                    _ => {
                        let sim = Simulation::from_state(state)?;
                        if let Some(message) = unsound_outputs(&sim) {
                            return Err(Failure::refused(format!(
                                "the FMU state is refused: {message}"
                            )));
                        }
                        self.simulation = Some(sim);
                        self.full_set_ups += 1;
                    }
                }
                self.readiness = Readiness::Ready;
            }
        }
        self.parameters = snap.parameters.clone();
        self.start_time = snap.start_time;
        self.stop_time = snap.stop_time;
        self.input = snap.input;
        self.input_derivatives = snap.input_derivatives;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fmi::logger::LogSink;
    use crate::simulation::{StepPath, StepReport};
    use std::sync::{Arc, Mutex};

    /// Regression: a step solved less exactly than the normal path was silent.
    #[test]
    fn degraded_steps_are_logged_as_warnings() {
        let seen = Arc::new(Mutex::new(Vec::new()));
        let s = seen.clone();
        let sink: LogSink = Box::new(move |status, category, message| {
            s.lock()
                .unwrap()
                .push((status, category.to_string(), message.to_string()))
        });
        let mut log = Logger::new(Some(sink), variables::FMI2.log_categories, false);
        let report = StepReport {
            active: 3,
            path: StepPath::ClarabelFallback,
            bounds_evaluated: true,
            warning: Some(
                "the active-set method did not converge; clarabel solved the step".into(),
            ),
            base_force: 0.0,
            contact_force: 50.0,
            impact: true,
            flows: Default::default(),
            resolves: 0,
            stop_forces: Default::default(),
            stop_impacts: Default::default(),
        };
        let step = InternalStep {
            time: 0.25,
            report: &report,
            previously_active: 0,
        };
        report_internal_step(&mut log, &step);
        let seen = seen.lock().unwrap();
        assert_eq!(seen.len(), 1, "logContact is off: only the warning");
        let (status, category, message) = &seen[0];
        assert_eq!((*status, category.as_str()), (Status::Warning, LOG_WARNING));
        assert!(
            message.contains("t = 0.25 s") && message.contains("clarabel"),
            "{message}"
        );
    }
}
