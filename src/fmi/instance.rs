//! One FMU instance as safe Rust: the FMI 2.0 Co-Simulation call-state machine, variables by value
//! reference, the simulation built at fmi2ExitInitializationMode, doStep substepping, input
//! interpolation, logging by category and the FMU state. `exports.rs` only translates C calls
//! into calls of these methods.
//!
//! # Rules the importer sees
//! * **Communication step.** The plate advances with internal steps Δt = `solver.time_step`.
//!   doStep(t, h) requires t to be the FMU's current time and h to be a whole multiple of Δt
//!   within a relative tolerance of 1e-9 (|h − kΔt| ≤ 1e-9 h, k ≥ 1); otherwise it returns
//!   fmi2Error naming both values and changes nothing. The FMU time is t_start + nΔt, computed from
//!   the step count n, so it never drifts; the plate's clock (and the built-in sine
//!   c sin(2πf(t − t_start))) starts at the experiment's start time.
//! * **Input.** `base.displacement` is sampled at communication points and interpolated inside a
//!   doStep as documented in [`super::input`] (continuous, second-order, no lag; input derivatives
//!   of order 1 and 2 are used when sent).
//! * **Parameters.** Fixed parameters may be set in the Instantiated and Initialization modes;
//!   the tunable `obstacle.lower`, `obstacle.upper`, `load.pressure` also between steps. A
//!   non-finite value or a value outside its own range is rejected at once (fmi2Error, message
//!   naming the variable, nothing changed); limits that tie parameters together (thickness below the
//!   shorter side, sine amplitude inside the gap) are checked at fmi2ExitInitializationMode for
//!   fixed parameters, so the order in which they are set does not matter, and at once for tunable
//!   ones during stepping.
//! * **Errors.** A call rejected without effect (wrong state, bad value, unknown value reference)
//!   returns fmi2Error and leaves the instance as it was. A failure inside doStep (base outside the
//!   gap, contact solver, numerical) returns fmi2Error and puts the instance in the Error state,
//!   from which fmi2SetFMUstate, fmi2Reset or fmi2FreeInstance continue, as FMI 2.0 prescribes.

use super::input::BaseInput;
use super::serialized;
use super::variables::{self, by_vr, vr, Causality, Kind, Variability, Variable, LOG_CATEGORIES};
use crate::error::Error;
use crate::scene::Scene;
use crate::simulation::{Simulation, State};
use serde::{Deserialize, Serialize};

/// fmi2Status.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Status {
    /// fmi2OK.
    Ok = 0,
    /// fmi2Warning.
    Warning = 1,
    /// fmi2Discard.
    Discard = 2,
    /// fmi2Error.
    Error = 3,
    /// fmi2Fatal.
    Fatal = 4,
    /// fmi2Pending.
    Pending = 5,
}

/// The FMI 2.0 Co-Simulation states (the FMU never runs a step asynchronously, so
/// stepInProgress does not occur).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Mode {
    /// After fmi2Instantiate or fmi2Reset.
    Instantiated,
    /// Between fmi2EnterInitializationMode and fmi2ExitInitializationMode.
    InitializationMode,
    /// Ready for fmi2DoStep.
    StepComplete,
    /// A step returned fmi2Discard (not used by this FMU, kept for the state table).
    StepFailed,
    /// A step was cancelled (not used: steps are synchronous).
    StepCanceled,
    /// After fmi2Terminate.
    Terminated,
    /// A call returned fmi2Error that left the simulation unusable.
    Error,
}

use Mode::*;

/// Where the host's messages go: (status, category, message).
pub type LogSink = Box<dyn FnMut(Status, &str, &str) + Send>;

/// Log categories, in the order of `<LogCategories>`.
pub const LOG_ERROR: &str = "logStatusError";
/// Warnings.
pub const LOG_WARNING: &str = "logStatusWarning";
/// Verbose call trace.
pub const LOG_ALL: &str = "logAll";
/// Contact events.
pub const LOG_CONTACT: &str = "logContact";

/// The host's logger and which categories are on.
pub struct Logger {
    sink: Option<LogSink>,
    enabled: Vec<bool>,
    initial: Vec<bool>,
}

impl Logger {
    /// Errors and warnings are always on; `logAll` and `logContact` follow `logging_on`.
    pub fn new(sink: Option<LogSink>, logging_on: bool) -> Logger {
        let enabled: Vec<bool> = LOG_CATEGORIES
            .iter()
            .map(|&c| c == LOG_ERROR || c == LOG_WARNING || logging_on)
            .collect();
        Logger {
            sink,
            initial: enabled.clone(),
            enabled,
        }
    }

    /// Whether messages of `category` reach the host.
    pub fn enabled(&self, category: &str) -> bool {
        self.sink.is_some()
            && LOG_CATEGORIES
                .iter()
                .position(|&c| c == category)
                .is_some_and(|i| self.enabled[i])
    }

    /// Sends one message if its category is on.
    pub fn log(&mut self, status: Status, category: &str, message: &str) {
        if self.enabled(category) {
            if let Some(sink) = self.sink.as_mut() {
                sink(status, category, message);
            }
        }
    }
}

/// A rejected call: the status to return and the message for the log.
#[derive(Clone, Debug, PartialEq)]
pub struct Failure {
    /// fmi2Error unless stated.
    pub status: Status,
    /// What happened and what to do, for the user.
    pub message: String,
}

fn fail<T>(message: impl Into<String>) -> Result<T, Failure> {
    Err(Failure {
        status: Status::Error,
        message: message.into(),
    })
}

impl From<Error> for Failure {
    fn from(e: Error) -> Failure {
        Failure {
            status: Status::Error,
            message: e.to_string(),
        }
    }
}

/// Everything an FMU state holds: enough to continue bit-identically, in this or a fresh instance.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Snapshot {
    mode: Mode,
    scene: Scene,
    start_time: f64,
    stop_time: Option<f64>,
    input: f64,
    z0: f64,
    base: BaseInput,
    sim: Option<State>,
    last_successful_time: f64,
    last_active: usize,
}

/// The scene with its tunable parameters neutralised: two simulations with equal fixed parts can
/// exchange states.
fn fixed_part(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    s.obstacle.lower = 0.0;
    s.obstacle.upper = 0.0;
    s.load.pressure = 0.0;
    s
}

/// The value at a dotted scene path.
fn scene_get(scene: &Scene, name: &str) -> serde_json::Value {
    let mut tree = serde_json::to_value(scene).expect("a scene always serializes");
    for part in name.split('.') {
        tree = tree
            .get_mut(part)
            .map(serde_json::Value::take)
            .unwrap_or(serde_json::Value::Null);
    }
    tree
}

/// `scene` with the field at `name` replaced (not validated).
fn scene_with(scene: &Scene, name: &str, value: serde_json::Value) -> Result<Scene, Error> {
    let text = value.to_string();
    let mut tree = serde_json::to_value(scene).expect("a scene always serializes");
    let mut slot = &mut tree;
    for part in name.split('.') {
        slot = slot
            .get_mut(part)
            .ok_or_else(|| Error::invalid(name, &text, "is not a scene parameter"))?;
    }
    *slot = value;
    serde_json::from_value(tree)
        .map_err(|e| Error::invalid(name, &text, &format!("has the wrong type ({e})")))
}

/// Whether an error is about the variable `name`.
fn names(e: &Error, name: &str) -> bool {
    matches!(e, Error::InvalidParameter { name: n, .. } if n == name)
}

/// A scene in which no other parameter limits `name`: used to check one value on its own.
fn isolation_scene(name: &str) -> Scene {
    let mut s = Scene::default();
    s.plate.length = 1e300;
    s.plate.width = 1e300;
    if name == "base.amplitude" {
        s.obstacle.lower_enabled = false;
        s.obstacle.upper_enabled = false;
    }
    s
}

/// One FMU instance. It is `Send` (checked below): the importer may call it from any thread.
pub struct Instance {
    name: String,
    log: Logger,
    mode: Mode,
    scene: Scene,
    start_time: f64,
    stop_time: Option<f64>,
    input: f64,
    z0: f64,
    base: BaseInput,
    sim: Option<Simulation>,
    last_successful_time: f64,
    last_active: usize,
}

const _: () = {
    const fn assert_send<T: Send>() {}
    assert_send::<Instance>();
};

/// Start value of the input `base.displacement`.
fn input_start() -> f64 {
    match by_vr(vr::BASE_DISPLACEMENT).and_then(|v| v.start.clone()) {
        Some(variables::Start::Real(x)) => x,
        _ => 0.0,
    }
}

impl Instance {
    /// fmi2Instantiate for Co-Simulation: checks the GUID against the model description.
    pub fn new(
        name: &str,
        guid: &str,
        logging_on: bool,
        sink: Option<LogSink>,
    ) -> Result<Instance, (Option<LogSink>, String)> {
        if guid != variables::GUID {
            return Err((
                sink,
                format!(
                    "fmi2Instantiate: GUID {guid:?} does not match this FMU's {:?}: the modelDescription.xml and the binary come from different builds",
                    variables::GUID
                ),
            ));
        }
        let input = input_start();
        Ok(Instance {
            name: name.to_string(),
            log: Logger::new(sink, logging_on),
            mode: Instantiated,
            scene: Scene::default(),
            start_time: 0.0,
            stop_time: None,
            input,
            z0: input,
            base: BaseInput::new(input),
            sim: None,
            last_successful_time: 0.0,
            last_active: 0,
        })
    }

    /// The instance name given at fmi2Instantiate.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The current state of the call-state machine.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// Puts the instance in the Error state (after a panic was caught).
    pub fn set_error_mode(&mut self) {
        self.mode = Error;
    }

    /// The FMU time: t_start + nΔt once the simulation runs, else the start time.
    pub fn time(&self) -> f64 {
        match &self.sim {
            Some(sim)
                if matches!(
                    self.mode,
                    StepComplete | StepFailed | StepCanceled | Terminated | Error
                ) =>
            {
                self.start_time + sim.step_index() as f64 * sim.scene().solver.time_step
            }
            _ => self.start_time,
        }
    }

    /// Logs `message` under `category`.
    pub fn log(&mut self, status: Status, category: &str, message: &str) {
        self.log.log(status, category, message);
    }

    /// Turns a result into a status, logging a failure under logStatusError (or logStatusWarning).
    pub fn finish(&mut self, function: &str, result: Result<(), Failure>) -> Status {
        match result {
            Ok(()) => {
                if self.log.enabled(LOG_ALL) {
                    self.log(Status::Ok, LOG_ALL, &format!("{function}: ok"));
                }
                Status::Ok
            }
            Err(f) => {
                let category = if f.status >= Status::Error {
                    LOG_ERROR
                } else {
                    LOG_WARNING
                };
                self.log(f.status, category, &format!("{function}: {}", f.message));
                f.status
            }
        }
    }

    fn require(&self, function: &str, allowed: &[Mode]) -> Result<(), Failure> {
        if allowed.contains(&self.mode) {
            Ok(())
        } else {
            fail(format!(
                "{function} is not allowed in the {:?} state (allowed in {:?})",
                self.mode, allowed
            ))
        }
    }

    /// fmi2SetDebugLogging.
    pub fn set_debug_logging(&mut self, on: bool, categories: &[&str]) -> Result<(), Failure> {
        if categories.is_empty() {
            for (i, &c) in LOG_CATEGORIES.iter().enumerate() {
                // Errors stay on unless explicitly named.
                self.log.enabled[i] = on || c == LOG_ERROR || c == LOG_WARNING;
            }
            return Ok(());
        }
        for c in categories {
            match LOG_CATEGORIES.iter().position(|k| k == c) {
                Some(i) => self.log.enabled[i] = on,
                None => {
                    return fail(format!(
                        "unknown log category {c:?}; the categories are {LOG_CATEGORIES:?}"
                    ))
                }
            }
        }
        Ok(())
    }

    /// fmi2SetupExperiment.
    pub fn setup_experiment(&mut self, start: f64, stop: Option<f64>) -> Result<(), Failure> {
        self.require("fmi2SetupExperiment", &[Instantiated])?;
        if !start.is_finite() {
            return fail(format!("startTime = {start} must be finite"));
        }
        if let Some(stop) = stop {
            if !(stop.is_finite() && stop >= start) {
                return fail(format!(
                    "stopTime = {stop} must be finite and >= startTime = {start}"
                ));
            }
        }
        self.start_time = start;
        self.stop_time = stop;
        self.last_successful_time = start;
        Ok(())
    }

    /// fmi2EnterInitializationMode.
    pub fn enter_initialization_mode(&mut self) -> Result<(), Failure> {
        self.require("fmi2EnterInitializationMode", &[Instantiated])?;
        self.mode = InitializationMode;
        Ok(())
    }

    /// Builds the simulation from the current parameters and input if it is not there yet.
    fn ensure_sim(&mut self) -> Result<&mut Simulation, Failure> {
        if self.sim.is_none() {
            self.scene.validate()?;
            let sim = Simulation::new(&self.scene, self.input)?;
            self.z0 = self.input;
            self.last_active = sim.outputs().active_nodes;
            self.sim = Some(sim);
        }
        Ok(self.sim.as_mut().expect("just built"))
    }

    /// fmi2ExitInitializationMode: validates the parameters and builds the simulation.
    pub fn exit_initialization_mode(&mut self) -> Result<(), Failure> {
        self.require("fmi2ExitInitializationMode", &[InitializationMode])?;
        self.ensure_sim()?;
        // Derivatives sent during initialization are meant for the first doStep.
        let derivatives = self.base.derivatives;
        self.base = BaseInput::new(self.input);
        self.base.derivatives = derivatives;
        self.last_successful_time = self.start_time;
        self.mode = StepComplete;
        Ok(())
    }

    /// fmi2Terminate.
    pub fn terminate(&mut self) -> Result<(), Failure> {
        self.require("fmi2Terminate", &[StepComplete, StepFailed, StepCanceled])?;
        self.mode = Terminated;
        Ok(())
    }

    /// fmi2Reset: back to the state right after fmi2Instantiate, with the start values.
    pub fn reset(&mut self) -> Result<(), Failure> {
        self.require(
            "fmi2Reset",
            &[
                Instantiated,
                InitializationMode,
                StepComplete,
                StepFailed,
                StepCanceled,
                Terminated,
                Error,
            ],
        )?;
        let input = input_start();
        self.mode = Instantiated;
        self.scene = Scene::default();
        self.start_time = 0.0;
        self.stop_time = None;
        self.input = input;
        self.z0 = input;
        self.base = BaseInput::new(input);
        self.sim = None;
        self.last_successful_time = 0.0;
        self.last_active = 0;
        self.log.enabled = self.log.initial.clone();
        Ok(())
    }

    const GET_MODES: [Mode; 6] = [
        InitializationMode,
        StepComplete,
        StepFailed,
        StepCanceled,
        Terminated,
        Error,
    ];

    fn variable(vr: u32, kinds: &[Kind], function: &str) -> Result<&'static Variable, Failure> {
        match by_vr(vr) {
            Some(v) if kinds.contains(&v.kind) => Ok(v),
            Some(v) => fail(format!(
                "{function}: value reference {vr} is {} of type {:?}, use the matching function",
                v.name, v.kind
            )),
            None => fail(format!(
                "{function}: {vr} is not a value reference of this FMU"
            )),
        }
    }

    /// The value of an output; in Initialization mode the simulation is built to compute it.
    fn output(&mut self, v: &Variable) -> Result<f64, Failure> {
        if self.mode == InitializationMode {
            self.ensure_sim()?;
        }
        let sim = match &self.sim {
            Some(sim) => sim,
            None => {
                return fail(format!(
                    "{} is not available: the simulation could not be set up",
                    v.name
                ))
            }
        };
        let o = sim.outputs();
        Ok(match v.vr {
            vr::CORNER1_DISPLACEMENT => o.corner1,
            vr::CORNER2_DISPLACEMENT => o.corner2,
            vr::EDGE_MID_DISPLACEMENT => o.edge_mid,
            vr::ENERGY_KINETIC => o.energy_kinetic,
            vr::ENERGY_ELASTIC => o.energy_elastic,
            vr::ENERGY_TOTAL => o.energy_total,
            vr::CONTACT_FORCE => o.contact_force,
            vr::CONTACT_ACTIVE_NODES => o.active_nodes as f64,
            _ => return fail(format!("{} has no output mapping (internal error)", v.name)),
        })
    }

    /// The scene whose parameter values the getters report (the running one once stepping).
    fn current_scene(&self) -> &Scene {
        match &self.sim {
            Some(sim) if self.mode != Instantiated && self.mode != InitializationMode => {
                sim.scene()
            }
            _ => &self.scene,
        }
    }

    fn get_number(&mut self, v: &'static Variable) -> Result<f64, Failure> {
        match v.causality {
            Causality::Output => self.output(v),
            Causality::Input => Ok(self.input),
            _ => {
                let value = scene_get(self.current_scene(), v.name);
                if v.kind == Kind::Enumeration {
                    let kind: crate::element::ElementKind =
                        serde_json::from_value(value).map_err(|e| Failure {
                            status: Status::Error,
                            message: format!("{}: {e}", v.name),
                        })?;
                    return Ok(variables::element_code(kind) as f64);
                }
                value.as_f64().ok_or_else(|| Failure {
                    status: Status::Error,
                    message: format!("{} is not a number in the scene (internal error)", v.name),
                })
            }
        }
    }

    /// fmi2GetReal.
    pub fn get_real(&mut self, vrs: &[u32], values: &mut [f64]) -> Result<(), Failure> {
        self.require("fmi2GetReal", &Self::GET_MODES)?;
        for (r, out) in vrs.iter().zip(values.iter_mut()) {
            let v = Self::variable(*r, &[Kind::Real], "fmi2GetReal")?;
            *out = self.get_number(v)?;
        }
        Ok(())
    }

    /// fmi2GetInteger (Integer and enumeration variables).
    pub fn get_integer(&mut self, vrs: &[u32], values: &mut [i32]) -> Result<(), Failure> {
        self.require("fmi2GetInteger", &Self::GET_MODES)?;
        for (r, out) in vrs.iter().zip(values.iter_mut()) {
            let v = Self::variable(*r, &[Kind::Integer, Kind::Enumeration], "fmi2GetInteger")?;
            let x = self.get_number(v)?;
            *out = x.clamp(i32::MIN as f64, i32::MAX as f64) as i32;
        }
        Ok(())
    }

    /// fmi2GetBoolean.
    pub fn get_boolean(&mut self, vrs: &[u32], values: &mut [bool]) -> Result<(), Failure> {
        self.require("fmi2GetBoolean", &Self::GET_MODES)?;
        for (r, out) in vrs.iter().zip(values.iter_mut()) {
            let v = Self::variable(*r, &[Kind::Boolean], "fmi2GetBoolean")?;
            *out = scene_get(self.current_scene(), v.name)
                .as_bool()
                .unwrap_or(false);
        }
        Ok(())
    }

    /// fmi2GetString / fmi2SetString: this FMU has no String variables.
    pub fn check_string(&self, function: &str, vrs: &[u32]) -> Result<(), Failure> {
        self.require(
            function,
            &[
                Instantiated,
                InitializationMode,
                StepComplete,
                StepFailed,
                StepCanceled,
                Terminated,
                Error,
            ],
        )?;
        match vrs.first() {
            None => Ok(()),
            Some(r) => Self::variable(*r, &[Kind::String], function).map(|_| ()),
        }
    }

    /// Checks that `v` may be set now.
    fn settable(&self, v: &Variable, function: &str) -> Result<(), Failure> {
        let ok = match (v.causality, self.mode) {
            (Causality::Parameter, Instantiated | InitializationMode) => true,
            (Causality::Parameter, StepComplete) => v.variability == Variability::Tunable,
            (Causality::Input, Instantiated | InitializationMode | StepComplete) => true,
            _ => false,
        };
        if ok {
            return Ok(());
        }
        match v.causality {
            Causality::Parameter if v.variability == Variability::Fixed => fail(format!(
                "{function}: {} is a fixed parameter: set it before fmi2ExitInitializationMode (state now {:?})",
                v.name, self.mode
            )),
            Causality::Parameter | Causality::Input => fail(format!(
                "{function}: {} cannot be set in the {:?} state",
                v.name, self.mode
            )),
            _ => fail(format!(
                "{function}: {} is an {:?}, it cannot be set",
                v.name, v.causality
            )),
        }
    }

    /// Sets one parameter to a JSON value (see the module docs for when limits are checked).
    fn set_parameter(&mut self, v: &Variable, value: serde_json::Value) -> Result<(), Failure> {
        if self.mode == StepComplete {
            let sim = self
                .sim
                .as_mut()
                .expect("a simulation runs in StepComplete");
            let updated = scene_with(sim.scene(), v.name, value)?;
            updated.validate()?;
            match v.vr {
                vr::OBSTACLE_LOWER | vr::OBSTACLE_UPPER => {
                    sim.set_obstacles(updated.obstacle.lower, updated.obstacle.upper)?
                }
                vr::LOAD_PRESSURE => sim.set_pressure(updated.load.pressure)?,
                _ => return fail(format!("{} is not tunable (internal error)", v.name)),
            }
            self.scene = updated;
            return Ok(());
        }
        let updated = scene_with(&self.scene, v.name, value.clone())?;
        if let Err(e) = scene_with(&isolation_scene(v.name), v.name, value)?.validate() {
            if names(&e, v.name) {
                return Err(e.into());
            }
        }
        self.scene = updated;
        self.sim = None;
        Ok(())
    }

    /// fmi2SetReal.
    pub fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), Failure> {
        self.require(
            "fmi2SetReal",
            &[Instantiated, InitializationMode, StepComplete],
        )?;
        for (r, &x) in vrs.iter().zip(values) {
            let v = Self::variable(*r, &[Kind::Real], "fmi2SetReal")?;
            self.settable(v, "fmi2SetReal")?;
            if !x.is_finite() {
                return Err(Error::invalid(v.name, x, "must be finite").into());
            }
            if v.causality == Causality::Input {
                self.input = x;
                if self.mode != StepComplete {
                    self.sim = None;
                }
            } else {
                self.set_parameter(v, serde_json::Value::from(x))?;
            }
        }
        Ok(())
    }

    /// fmi2SetInteger (Integer and enumeration variables).
    pub fn set_integer(&mut self, vrs: &[u32], values: &[i32]) -> Result<(), Failure> {
        self.require(
            "fmi2SetInteger",
            &[Instantiated, InitializationMode, StepComplete],
        )?;
        for (r, &x) in vrs.iter().zip(values) {
            let v = Self::variable(*r, &[Kind::Integer, Kind::Enumeration], "fmi2SetInteger")?;
            self.settable(v, "fmi2SetInteger")?;
            let value = if v.kind == Kind::Enumeration {
                let kind = variables::element_from_code(i64::from(x)).ok_or_else(|| {
                    Failure::from(Error::invalid(v.name, x, "must be 1 (argyris) or 2 (fvs)"))
                })?;
                serde_json::to_value(kind).expect("an element kind serializes")
            } else if x < 0 {
                return Err(Error::invalid(v.name, x, "must be a positive integer").into());
            } else {
                serde_json::Value::from(x)
            };
            self.set_parameter(v, value)?;
        }
        Ok(())
    }

    /// fmi2SetBoolean.
    pub fn set_boolean(&mut self, vrs: &[u32], values: &[bool]) -> Result<(), Failure> {
        self.require(
            "fmi2SetBoolean",
            &[Instantiated, InitializationMode, StepComplete],
        )?;
        for (r, &x) in vrs.iter().zip(values) {
            let v = Self::variable(*r, &[Kind::Boolean], "fmi2SetBoolean")?;
            self.settable(v, "fmi2SetBoolean")?;
            self.set_parameter(v, serde_json::Value::from(x))?;
        }
        Ok(())
    }

    /// fmi2SetRealInputDerivatives: derivatives of `base.displacement` of order 1 or 2, used by
    /// the next doStep only.
    pub fn set_real_input_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Result<(), Failure> {
        self.require(
            "fmi2SetRealInputDerivatives",
            &[Instantiated, InitializationMode, StepComplete],
        )?;
        for ((&r, &order), &x) in vrs.iter().zip(orders).zip(values) {
            let v = Self::variable(r, &[Kind::Real], "fmi2SetRealInputDerivatives")?;
            if v.causality != Causality::Input {
                return fail(format!(
                    "fmi2SetRealInputDerivatives: {} is not an input",
                    v.name
                ));
            }
            if !(1..=2).contains(&order) {
                return fail(format!(
                    "fmi2SetRealInputDerivatives: order {order} of {} is not supported (1 or 2)",
                    v.name
                ));
            }
            if !x.is_finite() {
                return Err(Error::invalid(
                    &format!("der({}, {order})", v.name),
                    x,
                    "must be finite",
                )
                .into());
            }
            self.base.derivatives[(order - 1) as usize] = Some(x);
        }
        Ok(())
    }

    /// fmi2GetRealOutputDerivatives: not provided (maxOutputDerivativeOrder = 0).
    pub fn get_real_output_derivatives(&mut self) -> Result<(), Failure> {
        self.require(
            "fmi2GetRealOutputDerivatives",
            &[StepComplete, StepFailed, StepCanceled, Terminated, Error],
        )?;
        fail("output derivatives are not provided (maxOutputDerivativeOrder = 0)")
    }

    /// fmi2GetDirectionalDerivative: not provided (providesDirectionalDerivative = false).
    pub fn get_directional_derivative(&mut self) -> Result<(), Failure> {
        self.require("fmi2GetDirectionalDerivative", &Self::GET_MODES)?;
        fail("directional derivatives are not provided (providesDirectionalDerivative = false)")
    }

    /// fmi2DoStep: advances from t to t + h with internal steps of Δt (see the module docs).
    pub fn do_step(&mut self, t: f64, h: f64) -> Result<(), Failure> {
        self.require("fmi2DoStep", &[StepComplete])?;
        let now = self.time();
        if !(t.is_finite() && h.is_finite() && h > 0.0) {
            return fail(format!(
                "currentCommunicationPoint = {t} s and communicationStepSize = {h} s must be finite, the step > 0"
            ));
        }
        if (t - now).abs() > 1e-9 * now.abs().max(h) {
            return fail(format!(
                "currentCommunicationPoint = {t} s differs from the FMU time {now} s (where the last step ended)"
            ));
        }
        let dt = self
            .sim
            .as_ref()
            .expect("a simulation runs")
            .scene()
            .solver
            .time_step;
        let k = (h / dt).round();
        if k < 1.0 || (k * dt - h).abs() > 1e-9 * h {
            return fail(format!(
                "communicationStepSize h = {h} s is not a whole multiple of solver.time_step Δt = {dt} s (h/Δt = {}); use h = k·Δt",
                h / dt
            ));
        }
        if let Some(stop) = self.stop_time {
            if now + h > stop + 1e-9 * stop.abs().max(h) {
                return fail(format!(
                    "the step to t = {} s goes beyond stopTime = {stop} s set by fmi2SetupExperiment",
                    now + h
                ));
            }
        }
        let k = k as u64;
        let plan = self.base.plan(now, self.input, h);
        let contact_log = self.log.enabled(LOG_CONTACT);
        for i in 1..=k {
            let theta = i as f64 / k as f64;
            let sim = self.sim.as_mut().expect("a simulation runs");
            match sim.step(plan.at(theta)) {
                Ok(report) => {
                    if contact_log && report.active != self.last_active {
                        let t_step = self.start_time
                            + sim.step_index() as f64 * sim.scene().solver.time_step;
                        let message = format!(
                            "t = {t_step} s: {} vertices in contact (was {}), contact force {} N, path {:?}",
                            report.active,
                            self.last_active,
                            sim.outputs().contact_force,
                            report.path
                        );
                        self.log(Status::Ok, LOG_CONTACT, &message);
                    }
                    self.last_active = report.active;
                }
                Err(e) => {
                    self.mode = Error;
                    self.last_successful_time = self.time();
                    let at = self.time();
                    return fail(format!(
                        "the step from t = {at} s failed: {e}. The instance is now in the Error state: restore an FMU state, or reset"
                    ));
                }
            }
        }
        self.base.finish(now, &plan);
        self.last_successful_time = self.time();
        Ok(())
    }

    /// fmi2CancelStep: steps are synchronous, so there is never one to cancel.
    pub fn cancel_step(&mut self) -> Result<(), Failure> {
        fail(format!(
            "fmi2CancelStep is not allowed in the {:?} state: this FMU runs doStep synchronously (no step in progress)",
            self.mode
        ))
    }

    /// fmi2GetRealStatus(fmi2LastSuccessfulTime).
    pub fn last_successful_time(&self) -> Result<f64, Failure> {
        self.require(
            "fmi2GetRealStatus",
            &[StepComplete, StepFailed, StepCanceled, Terminated, Error],
        )?;
        Ok(self.last_successful_time)
    }

    /// Status queries this FMU cannot answer (no asynchronous steps): fmi2Discard.
    pub fn status_not_available(&self, function: &str, what: &str) -> Result<(), Failure> {
        self.require(
            function,
            &[StepComplete, StepFailed, StepCanceled, Terminated, Error],
        )?;
        Err(Failure {
            status: Status::Discard,
            message: format!("{what} is not available: this FMU never returns fmi2Pending"),
        })
    }

    const STATE_MODES: [Mode; 7] = [
        Instantiated,
        InitializationMode,
        StepComplete,
        StepFailed,
        StepCanceled,
        Terminated,
        Error,
    ];

    /// fmi2GetFMUstate: a copy of everything needed to continue from here.
    pub fn get_state(&self) -> Result<Snapshot, Failure> {
        self.require("fmi2GetFMUstate", &Self::STATE_MODES)?;
        Ok(Snapshot {
            mode: self.mode,
            scene: self.scene.clone(),
            start_time: self.start_time,
            stop_time: self.stop_time,
            input: self.input,
            z0: self.z0,
            base: self.base.clone(),
            sim: match self.mode {
                Instantiated | InitializationMode => None,
                _ => self.sim.as_ref().map(Simulation::state),
            },
            last_successful_time: self.last_successful_time,
            last_active: self.last_active,
        })
    }

    /// fmi2SetFMUstate: continues from `snap`, in this or any instance of this FMU. The
    /// simulation is rebuilt only if the snapshot's fixed parameters differ from the running ones.
    pub fn set_state(&mut self, snap: &Snapshot) -> Result<(), Failure> {
        self.require("fmi2SetFMUstate", &Self::STATE_MODES)?;
        let needs_simulation = matches!(snap.mode, Mode::StepComplete | Mode::Terminated);
        if needs_simulation && snap.sim.is_none() {
            return Err(Failure {
                status: Status::Error,
                message: "fmi2SetFMUstate: the state claims a running simulation but holds none"
                    .into(),
            });
        }
        // Nothing of this instance changes until the snapshot has been restored completely.
        match &snap.sim {
            None => self.sim = None,
            Some(state) => {
                let reusable = self
                    .sim
                    .as_ref()
                    .is_some_and(|s| fixed_part(s.scene()) == fixed_part(&snap.scene));
                if reusable {
                    // Stepper::restore checks everything before it changes anything.
                    self.sim.as_mut().expect("reusable").restore(state)?;
                } else {
                    snap.scene.validate()?;
                    let mut sim = Simulation::new(&snap.scene, snap.z0)?;
                    sim.restore(state)?;
                    self.sim = Some(sim);
                }
            }
        }
        self.mode = snap.mode;
        self.scene = snap.scene.clone();
        self.start_time = snap.start_time;
        self.stop_time = snap.stop_time;
        self.input = snap.input;
        self.z0 = snap.z0;
        self.base = snap.base.clone();
        self.last_successful_time = snap.last_successful_time;
        self.last_active = snap.last_active;
        Ok(())
    }

    /// fmi2SerializeFMUstate (and the size query): the bytes of `snap` (see [`serialized`]).
    pub fn serialize_state(&self, snap: &Snapshot) -> Result<Vec<u8>, Failure> {
        self.require("fmi2SerializeFMUstate", &Self::STATE_MODES)?;
        serialized::encode(snap).map_err(|message| Failure {
            status: Status::Error,
            message,
        })
    }

    /// fmi2DeSerializeFMUstate: checks the bytes completely before anything is used.
    pub fn deserialize_state(&self, bytes: &[u8]) -> Result<Snapshot, Failure> {
        self.require("fmi2DeSerializeFMUstate", &Self::STATE_MODES)?;
        let snap: Snapshot = serialized::decode(bytes).map_err(|message| Failure {
            status: Status::Error,
            message,
        })?;
        snap.scene.validate()?;
        Ok(snap)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::{Arc, Mutex};

    type Messages = Arc<Mutex<Vec<(Status, String, String)>>>;

    fn instance() -> (Instance, Messages) {
        let messages: Messages = Arc::default();
        let m = messages.clone();
        let sink: LogSink =
            Box::new(move |s, c, msg| m.lock().unwrap().push((s, c.to_string(), msg.to_string())));
        let inst = Instance::new("test", variables::GUID, false, Some(sink))
            .ok()
            .unwrap();
        (inst, messages)
    }

    fn initialized() -> (Instance, Messages) {
        let (mut inst, m) = instance();
        inst.setup_experiment(0.0, None).unwrap();
        inst.enter_initialization_mode().unwrap();
        inst.exit_initialization_mode().unwrap();
        (inst, m)
    }

    fn corner(inst: &mut Instance) -> f64 {
        let mut v = [0.0];
        inst.get_real(&[vr::CORNER1_DISPLACEMENT], &mut v).unwrap();
        v[0]
    }

    #[test]
    fn wrong_guid_is_refused() {
        assert!(Instance::new("x", "{nope}", false, None).is_err());
    }

    #[test]
    fn every_variable_can_be_read_after_initialization() {
        let (mut inst, _) = initialized();
        for v in variables::VARIABLES {
            match v.kind {
                Kind::Real => inst.get_real(&[v.vr], &mut [0.0]).unwrap(),
                Kind::Integer | Kind::Enumeration => inst.get_integer(&[v.vr], &mut [0]).unwrap(),
                Kind::Boolean => inst.get_boolean(&[v.vr], &mut [false]).unwrap(),
                Kind::String => unreachable!("no String variables"),
            }
        }
    }

    #[test]
    fn step_must_be_a_multiple_of_the_internal_step() {
        let (mut inst, _) = initialized();
        let err = inst.do_step(0.0, 1.5e-4).unwrap_err();
        assert!(
            err.message.contains("0.00015") && err.message.contains("0.0001"),
            "{}",
            err.message
        );
        assert_eq!(inst.mode(), StepComplete, "a rejected step changes nothing");
        inst.do_step(0.0, 3e-4).unwrap();
        assert!((inst.time() - 3e-4).abs() < 1e-15);
        assert!(
            inst.do_step(0.0, 1e-4).is_err(),
            "wrong communication point"
        );
    }

    #[test]
    fn parameters_follow_the_state_machine() {
        let (mut inst, _) = instance();
        let err = inst
            .set_real(&[vr::MATERIAL_POISSON_RATIO], &[0.5])
            .unwrap_err();
        assert!(
            err.message.contains("material.poisson_ratio"),
            "{}",
            err.message
        );
        let err = inst.set_real(&[vr::PLATE_LENGTH], &[f64::NAN]).unwrap_err();
        assert!(err.message.contains("plate.length"));
        // Cross limits are checked at exit, whatever the order of the sets.
        inst.set_real(&[vr::BASE_AMPLITUDE], &[0.015]).unwrap();
        inst.set_real(&[vr::OBSTACLE_LOWER, vr::OBSTACLE_UPPER], &[-0.02, 0.02])
            .unwrap();
        inst.enter_initialization_mode().unwrap();
        inst.exit_initialization_mode().unwrap();
        let err = inst.set_real(&[vr::PLATE_LENGTH], &[0.5]).unwrap_err();
        assert!(err.message.contains("fixed parameter"), "{}", err.message);
        inst.set_real(&[vr::LOAD_PRESSURE], &[100.0]).unwrap();
        let err = inst.set_real(&[vr::OBSTACLE_UPPER], &[0.001]).unwrap_err();
        assert!(err.message.contains("base.amplitude"), "{}", err.message);
        let mut p = [0.0];
        inst.get_real(&[vr::LOAD_PRESSURE], &mut p).unwrap();
        assert_eq!(p[0], 100.0);
        assert!(inst.set_real(&[vr::CORNER1_DISPLACEMENT], &[1.0]).is_err());
    }

    #[test]
    fn inconsistent_parameters_fail_at_exit_naming_the_parameter() {
        let (mut inst, _) = instance();
        inst.set_real(&[vr::BASE_AMPLITUDE], &[0.015]).unwrap();
        inst.enter_initialization_mode().unwrap();
        let err = inst.exit_initialization_mode().unwrap_err();
        assert!(err.message.contains("base.amplitude"), "{}", err.message);
        assert_eq!(inst.mode(), InitializationMode);
    }

    #[test]
    fn state_round_trip_is_bit_identical() {
        let (mut inst, _) = instance();
        inst.set_real(&[vr::BASE_AMPLITUDE], &[0.005]).unwrap();
        inst.enter_initialization_mode().unwrap();
        inst.exit_initialization_mode().unwrap();
        let h = 1e-3;
        let mut t = 0.0;
        for k in 0..20 {
            inst.set_real(&[vr::BASE_DISPLACEMENT], &[1e-3 * (k as f64 * 0.3).sin()])
                .unwrap();
            inst.do_step(t, h).unwrap();
            t = inst.time();
        }
        let snap = inst.get_state().unwrap();
        let bytes = inst.serialize_state(&snap).unwrap();
        let run = |inst: &mut Instance| {
            let mut out = Vec::new();
            for k in 0..30 {
                let t = inst.time();
                inst.set_real(&[vr::BASE_DISPLACEMENT], &[2e-3 * (k as f64 * 0.7).cos()])
                    .unwrap();
                inst.do_step(t, h).unwrap();
                out.push(corner(inst).to_bits());
            }
            out
        };
        let first = run(&mut inst);
        inst.set_state(&snap).unwrap();
        assert_eq!(run(&mut inst), first);
        let (mut fresh, _) = instance();
        let snap2 = fresh.deserialize_state(&bytes).unwrap();
        assert_eq!(snap2, snap);
        fresh.set_state(&snap2).unwrap();
        assert_eq!(run(&mut fresh), first);
    }

    #[test]
    fn base_outside_gap_is_an_error_then_reset_recovers() {
        let (mut inst, messages) = initialized();
        inst.set_real(&[vr::BASE_DISPLACEMENT], &[0.02]).unwrap();
        let err = inst.do_step(0.0, 1e-3).unwrap_err();
        let status = inst.finish("fmi2DoStep", Err(err));
        assert_eq!(status, Status::Error);
        assert_eq!(inst.mode(), Error);
        assert!(messages
            .lock()
            .unwrap()
            .iter()
            .any(|(s, c, m)| *s == Status::Error
                && c == LOG_ERROR
                && m.contains("base displacement")));
        assert!(inst.do_step(inst.time(), 1e-3).is_err());
        inst.reset().unwrap();
        inst.enter_initialization_mode().unwrap();
        inst.exit_initialization_mode().unwrap();
        inst.do_step(0.0, 1e-3).unwrap();
    }

    #[test]
    fn derivatives_sent_during_initialization_reach_the_first_step() {
        let (mut inst, _) = instance();
        inst.enter_initialization_mode().unwrap();
        inst.set_real_input_derivatives(&[vr::BASE_DISPLACEMENT], &[1], &[0.5])
            .unwrap();
        inst.exit_initialization_mode().unwrap();
        let plan = inst.base.plan(0.0, 0.0, 1e-3);
        assert_eq!(plan.slope, 0.5);
        assert!(inst
            .set_real_input_derivatives(&[vr::BASE_DISPLACEMENT], &[3], &[1.0])
            .is_err());
        assert!(inst
            .set_real_input_derivatives(&[vr::PLATE_LENGTH], &[1], &[1.0])
            .is_err());
    }

    #[test]
    fn logging_categories() {
        let (mut inst, messages) = initialized();
        assert!(inst.set_debug_logging(true, &["logNothing"]).is_err());
        inst.set_debug_logging(true, &[LOG_CONTACT]).unwrap();
        inst.set_real(&[vr::LOAD_PRESSURE], &[2e5]).unwrap();
        let mut t = 0.0;
        for _ in 0..200 {
            inst.do_step(t, 1e-3).unwrap();
            t = inst.time();
        }
        let log = messages.lock().unwrap();
        assert!(
            log.iter().any(|(_, c, _)| c == LOG_CONTACT),
            "no contact event logged"
        );
        assert!(!log.iter().any(|(_, c, _)| c == LOG_ALL));
    }
}
