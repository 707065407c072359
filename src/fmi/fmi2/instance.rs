//! One FMI 2.0 Co-Simulation instance as safe Rust, generic over the [`Model`] it drives: the
//! call-state table looked up once per call, value references and their types, stage-then-commit
//! sets, the logger, and the FMU state. `exports.rs` only translates C calls into these methods.

use super::call_state::{Function, Mode};
use crate::fmi::logger::{LogSink, Logger, LOG_ALL, LOG_ERROR, LOG_WARNING};
use crate::fmi::model::{self, Model, Phase, Value};
use crate::fmi::serialized;
use crate::fmi::status::{Aftermath, Failure, Status};
use crate::fmi::variables::Kind;
use serde::{Deserialize, Serialize};
use std::cell::OnceCell;

/// An FMU state: the instance's state and the model's snapshot.
#[derive(Serialize, Deserialize)]
#[serde(bound = "", deny_unknown_fields)]
pub struct Snapshot<M: Model> {
    mode: Mode,
    model: M::Snapshot,
}

impl<M: Model> Clone for Snapshot<M> {
    fn clone(&self) -> Self {
        Snapshot {
            mode: self.mode,
            model: self.model.clone(),
        }
    }
}

/// What an `fmi2FMUstate` points to: a snapshot, and its serialized bytes once asked for, so that
/// fmi2SerializedFMUstateSize and fmi2SerializeFMUstate encode it once.
pub struct StoredState<M: Model> {
    snapshot: Snapshot<M>,
    bytes: OnceCell<Vec<u8>>,
}

impl<M: Model> StoredState<M> {
    fn new(snapshot: Snapshot<M>) -> StoredState<M> {
        StoredState {
            snapshot,
            bytes: OnceCell::new(),
        }
    }
}

/// One FMU instance. It is `Send` whenever its model is: the host may call it from any thread,
/// one call at a time.
pub struct Instance<M: Model> {
    name: String,
    log: Logger,
    mode: Mode,
    model: M,
}

/// The kinds fmi2Get/SetInteger serve.
const INTEGERS: &[Kind] = &[Kind::Integer, Kind::Enumeration];

impl<M: Model> Instance<M> {
    /// fmi2Instantiate for Co-Simulation: checks the GUID against the model description.
    pub fn new(
        name: &str,
        guid: &str,
        logging_on: bool,
        sink: Option<LogSink>,
    ) -> Result<Instance<M>, (Option<LogSink>, String)> {
        if guid != M::GUID {
            return Err((
                sink,
                format!(
                    "fmi2Instantiate: GUID {guid:?} does not match this FMU's {:?}: the modelDescription.xml and the binary come from different builds",
                    M::GUID
                ),
            ));
        }
        Ok(Instance {
            name: name.to_string(),
            log: Logger::new(sink, M::LOG_CATEGORIES, logging_on),
            mode: Mode::Instantiated,
            model: M::new(),
        })
    }

    /// The instance name given at fmi2Instantiate.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The model behind the instance.
    pub fn model(&self) -> &M {
        &self.model
    }

    /// The current state of the call-state machine.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// Puts the instance in the Error state (after a panic was caught).
    pub fn set_error_mode(&mut self) {
        self.mode = Mode::Error;
    }

    /// The FMU time (s).
    pub fn time(&self) -> f64 {
        self.model.time(self.mode.phase())
    }

    /// The one lookup in the call-state table every entry point starts with.
    fn enter(&self, function: Function) -> Result<Phase, Failure> {
        function
            .check(self.mode)
            .map(|()| self.mode.phase())
            .map_err(Failure::refused)
    }

    /// Turns a call's result into its status: logs a failure under logStatusError (a discarded
    /// query under logStatusWarning), moves to the Error state when the failure broke the
    /// instance, and traces successful calls under logAll.
    pub fn finish(&mut self, function: Function, result: Result<Status, Failure>) -> Status {
        match result {
            Ok(status) => {
                if self.log.enabled(LOG_ALL) {
                    let message = format!("{}: {status:?}", function.name());
                    self.log.log(status, LOG_ALL, &message);
                }
                status
            }
            Err(f) => {
                if f.aftermath == Aftermath::Broken {
                    self.mode = Mode::Error;
                }
                let category = if f.status >= Status::Error {
                    LOG_ERROR
                } else {
                    LOG_WARNING
                };
                let message = format!("{}: {}", function.name(), f.message);
                self.log.log(f.status, category, &message);
                f.status
            }
        }
    }

    /// fmi2SetDebugLogging.
    pub fn set_debug_logging(&mut self, on: bool, categories: &[&str]) -> Result<(), Failure> {
        self.enter(Function::SetDebugLogging)?;
        self.log.switch(on, categories).map_err(Failure::refused)
    }

    /// fmi2SetupExperiment.
    pub fn setup_experiment(&mut self, start: f64, stop: Option<f64>) -> Result<(), Failure> {
        self.enter(Function::SetupExperiment)?;
        self.model.setup_experiment(start, stop)
    }

    /// fmi2EnterInitializationMode.
    pub fn enter_initialization_mode(&mut self) -> Result<(), Failure> {
        self.enter(Function::EnterInitializationMode)?;
        self.mode = Mode::InitializationMode;
        Ok(())
    }

    /// fmi2ExitInitializationMode: the model checks its parameters and sets itself up.
    pub fn exit_initialization_mode(&mut self) -> Result<(), Failure> {
        self.enter(Function::ExitInitializationMode)?;
        self.model.exit_initialization()?;
        self.mode = Mode::StepComplete;
        Ok(())
    }

    /// fmi2Terminate.
    pub fn terminate(&mut self) -> Result<(), Failure> {
        self.enter(Function::Terminate)?;
        self.mode = Mode::Terminated;
        Ok(())
    }

    /// fmi2Reset: back to the state right after fmi2Instantiate, with the start values.
    pub fn reset(&mut self) -> Result<(), Failure> {
        self.enter(Function::Reset)?;
        self.model.reset();
        self.log.reset();
        self.mode = Mode::Instantiated;
        Ok(())
    }

    /// Reads `vrs` of the given kinds into `out` through `convert`.
    fn get<T>(
        &mut self,
        function: Function,
        kinds: &[Kind],
        vrs: &[u32],
        out: &mut [T],
        convert: impl Fn(Value) -> Option<T>,
    ) -> Result<(), Failure> {
        let phase = self.enter(function)?;
        for (&vr, slot) in vrs.iter().zip(out.iter_mut()) {
            let v = model::variable(M::VARIABLES, vr, kinds)?;
            let value = self.model.get(v, phase)?;
            *slot = convert(value).ok_or_else(|| {
                Failure::refused(format!(
                    "{} has a value of another type (internal error)",
                    v.name
                ))
            })?;
        }
        Ok(())
    }

    /// fmi2GetReal.
    pub fn get_real(&mut self, vrs: &[u32], out: &mut [f64]) -> Result<(), Failure> {
        self.get(Function::GetReal, &[Kind::Real], vrs, out, |v| match v {
            Value::Real(x) => Some(x),
            _ => None,
        })
    }

    /// fmi2GetInteger (Integer and enumeration variables).
    pub fn get_integer(&mut self, vrs: &[u32], out: &mut [i32]) -> Result<(), Failure> {
        self.get(Function::GetInteger, INTEGERS, vrs, out, |v| match v {
            Value::Integer(i) => Some(i),
            _ => None,
        })
    }

    /// fmi2GetBoolean.
    pub fn get_boolean(&mut self, vrs: &[u32], out: &mut [bool]) -> Result<(), Failure> {
        self.get(
            Function::GetBoolean,
            &[Kind::Boolean],
            vrs,
            out,
            |v| match v {
                Value::Boolean(b) => Some(b),
                _ => None,
            },
        )
    }

    /// fmi2GetString / fmi2SetString: checks the call; the model has no String variables, so any
    /// value reference is refused.
    pub fn check_string(&mut self, function: Function, vrs: &[u32]) -> Result<(), Failure> {
        self.enter(function)?;
        match vrs.first() {
            None => Ok(()),
            Some(&vr) => model::variable(M::VARIABLES, vr, &[Kind::String]).map(|_| ()),
        }
    }

    fn set(
        &mut self,
        function: Function,
        kinds: &[Kind],
        values: impl Iterator<Item = (u32, Value)>,
    ) -> Result<(), Failure> {
        let phase = self.enter(function)?;
        model::set_values(&mut self.model, phase, kinds, values)
    }

    /// fmi2SetReal: every value is checked before any is applied.
    pub fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), Failure> {
        let items = vrs.iter().zip(values).map(|(&r, &x)| (r, Value::Real(x)));
        self.set(Function::SetReal, &[Kind::Real], items)
    }

    /// fmi2SetInteger (Integer and enumeration variables): all values or none.
    pub fn set_integer(&mut self, vrs: &[u32], values: &[i32]) -> Result<(), Failure> {
        let items = vrs
            .iter()
            .zip(values)
            .map(|(&r, &x)| (r, Value::Integer(x)));
        self.set(Function::SetInteger, INTEGERS, items)
    }

    /// fmi2SetBoolean: all values or none.
    pub fn set_boolean(&mut self, vrs: &[u32], values: &[bool]) -> Result<(), Failure> {
        let items = vrs
            .iter()
            .zip(values)
            .map(|(&r, &b)| (r, Value::Boolean(b)));
        self.set(Function::SetBoolean, &[Kind::Boolean], items)
    }

    /// fmi2SetRealInputDerivatives: used by the next doStep only; all or none.
    pub fn set_real_input_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Result<(), Failure> {
        let function = Function::SetRealInputDerivatives;
        self.enter(function)?;
        let mut items = Vec::with_capacity(vrs.len());
        for ((&vr, &order), &x) in vrs.iter().zip(orders).zip(values) {
            let v = model::variable(M::VARIABLES, vr, &[Kind::Real])?;
            items.push((v, order, x));
        }
        self.model.set_input_derivatives(&items)
    }

    /// fmi2GetRealOutputDerivatives: not provided (maxOutputDerivativeOrder = 0).
    pub fn get_real_output_derivatives(&mut self) -> Result<(), Failure> {
        self.enter(Function::GetRealOutputDerivatives)?;
        Err(Failure::refused(
            "output derivatives are not provided (maxOutputDerivativeOrder = 0)",
        ))
    }

    /// fmi2GetDirectionalDerivative: not provided (providesDirectionalDerivative = false).
    pub fn get_directional_derivative(&mut self) -> Result<(), Failure> {
        self.enter(Function::GetDirectionalDerivative)?;
        Err(Failure::refused(
            "directional derivatives are not provided (providesDirectionalDerivative = false)",
        ))
    }

    /// fmi2DoStep: one communication step; fmi2Warning when a warning was logged.
    pub fn do_step(&mut self, t: f64, h: f64) -> Result<Status, Failure> {
        self.enter(Function::DoStep)?;
        self.model.do_step(t, h, &mut self.log)
    }

    /// fmi2CancelStep: steps are synchronous, so there is never one to cancel.
    pub fn cancel_step(&mut self) -> Result<(), Failure> {
        self.enter(Function::CancelStep)?;
        Err(Failure::refused("no step is in progress"))
    }

    /// fmi2GetRealStatus(fmi2LastSuccessfulTime): the end of the last completed step.
    pub fn last_successful_time(&mut self) -> Result<f64, Failure> {
        self.enter(Function::GetRealStatus)?;
        Ok(self.time())
    }

    /// fmi2GetBooleanStatus(fmi2Terminated): this FMU never asks to end the simulation early.
    pub fn terminated_early(&mut self) -> Result<bool, Failure> {
        self.enter(Function::GetBooleanStatus)?;
        Ok(false)
    }

    /// Status queries this FMU cannot answer (it never returns fmi2Pending): fmi2Discard.
    pub fn status_not_available(&mut self, function: Function, what: &str) -> Result<(), Failure> {
        self.enter(function)?;
        Err(Failure::discarded(format!(
            "{what} is not available: this FMU never returns fmi2Pending"
        )))
    }

    /// fmi2GetFMUstate: a copy of everything needed to continue from here.
    pub fn get_state(&mut self) -> Result<StoredState<M>, Failure> {
        let phase = self.enter(Function::GetFMUstate)?;
        Ok(StoredState::new(Snapshot {
            mode: self.mode,
            model: self.model.snapshot(phase),
        }))
    }

    /// Checks an untrusted snapshot completely.
    fn validate(snapshot: &Snapshot<M>) -> Result<(), Failure> {
        if !snapshot.mode.reachable() {
            return Err(Failure::refused(format!(
                "the FMU state is refused: it claims the {:?} state, which this FMU never enters",
                snapshot.mode
            )));
        }
        M::validate(&snapshot.model, snapshot.mode.phase())
    }

    /// fmi2SetFMUstate: continues from `state`, in this or any instance of this FMU; a refused
    /// state changes nothing.
    pub fn set_state(&mut self, state: &StoredState<M>) -> Result<(), Failure> {
        self.enter(Function::SetFMUstate)?;
        let snapshot = &state.snapshot;
        Self::validate(snapshot)?;
        self.model.restore(&snapshot.model, snapshot.mode.phase())?;
        self.mode = snapshot.mode;
        Ok(())
    }

    /// fmi2FreeFMUstate: checks the call (the caller frees the state).
    pub fn free_state(&mut self) -> Result<(), Failure> {
        self.enter(Function::FreeFMUstate).map(|_| ())
    }

    /// fmi2SerializedFMUstateSize and fmi2SerializeFMUstate: the bytes of `state`, encoded on the
    /// first request only.
    pub fn serialized<'a>(
        &mut self,
        function: Function,
        state: &'a StoredState<M>,
    ) -> Result<&'a [u8], Failure> {
        self.enter(function)?;
        if state.bytes.get().is_none() {
            let bytes = serialized::encode(&state.snapshot).map_err(Failure::refused)?;
            let _ = state.bytes.set(bytes);
        }
        Ok(state.bytes.get().expect("set above"))
    }

    /// fmi2DeSerializeFMUstate: decodes and validates the bytes completely before anything uses
    /// them.
    pub fn deserialize_state(&mut self, bytes: &[u8]) -> Result<StoredState<M>, Failure> {
        self.enter(Function::DeSerializeFMUstate)?;
        let snapshot: Snapshot<M> = serialized::decode(bytes).map_err(Failure::refused)?;
        Self::validate(&snapshot)?;
        Ok(StoredState::new(snapshot))
    }
}
