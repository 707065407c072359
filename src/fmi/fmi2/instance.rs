//! The FMI 2.0 Co-Simulation instance: the generic [`instance::Instance`] with FMI 2.0's call-state
//! table ([`Fmi2`]) and the calls only FMI 2.0 has (the experiment set up before initialization,
//! input derivatives, the status queries). `exports.rs` only translates C calls into these methods.

use super::call_state::{Function, Mode};
use crate::fmi::instance::{self, Version};
use crate::fmi::model::{self, Model, StepOptions};
use crate::fmi::status::{Aftermath, Failure, Status};
use crate::fmi::variables::{Description, Kind};

/// FMI 2.0 Co-Simulation, for the generic instance.
pub struct Fmi2;

impl Version for Fmi2 {
    type Mode = Mode;
    type Function = Function;

    const INSTANTIATED: Mode = Mode::Instantiated;
    const INITIALIZATION: Mode = Mode::InitializationMode;
    const STEPPING: Mode = Mode::StepComplete;
    const TERMINATED: Mode = Mode::Terminated;
    const FAILED: Mode = Mode::Error;

    const SET_DEBUG_LOGGING: Function = Function::SetDebugLogging;
    const ENTER_INITIALIZATION_MODE: Function = Function::EnterInitializationMode;
    const EXIT_INITIALIZATION_MODE: Function = Function::ExitInitializationMode;
    const TERMINATE: Function = Function::Terminate;
    const RESET: Function = Function::Reset;
    const GET_FMU_STATE: Function = Function::GetFMUstate;
    const SET_FMU_STATE: Function = Function::SetFMUstate;
    const FREE_FMU_STATE: Function = Function::FreeFMUstate;
    const SERIALIZED_FMU_STATE_SIZE: Function = Function::SerializedFMUstateSize;
    const DESERIALIZE_FMU_STATE: Function = Function::DeSerializeFMUstate;
    const DO_STEP: Function = Function::DoStep;
    const GET_OUTPUT_DERIVATIVES: Function = Function::GetRealOutputDerivatives;

    const INSTANTIATE: (&'static str, &'static str) = ("fmi2Instantiate", "GUID");

    fn description<M: Model>() -> &'static Description {
        M::FMI2
    }

    fn getter(kind: Kind) -> Function {
        match kind {
            Kind::Integer | Kind::Enumeration => Function::GetInteger,
            Kind::Boolean => Function::GetBoolean,
            Kind::String => Function::GetString,
            Kind::Real | Kind::UInt64 => Function::GetReal,
        }
    }

    fn setter(kind: Kind) -> Function {
        match kind {
            Kind::Integer | Kind::Enumeration => Function::SetInteger,
            Kind::Boolean => Function::SetBoolean,
            Kind::String => Function::SetString,
            Kind::Real | Kind::UInt64 => Function::SetReal,
        }
    }

    /// A call refused without effect leaves the state as it was; one that failed part-way puts
    /// the instance in the Error state, from which fmi2SetFMUstate, fmi2Reset or
    /// fmi2FreeInstance continue.
    fn fails_instance(failure: &Failure) -> bool {
        failure.aftermath == Aftermath::Broken
    }
}

/// An FMI 2.0 instance driving model `M`.
pub type Instance<M> = instance::Instance<Fmi2, M>;
/// What an `fmi2FMUstate` points to.
pub type StoredState<M> = instance::StoredState<Fmi2, M>;

impl<M: Model> Instance<M> {
    /// fmi2SetupExperiment.
    pub fn setup_experiment(&mut self, start: f64, stop: Option<f64>) -> Result<(), Failure> {
        self.enter(Function::SetupExperiment)?;
        self.model_mut().setup_experiment(start, stop)
    }

    /// fmi2EnterInitializationMode (the experiment was set up before).
    pub fn enter_initialization_mode(&mut self) -> Result<(), Failure> {
        self.begin_initialization(None)
    }

    /// fmi2SetRealInputDerivatives: used by the next doStep only; all or none.
    pub fn set_real_input_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Result<(), Failure> {
        self.enter(Function::SetRealInputDerivatives)?;
        let mut items = Vec::with_capacity(vrs.len());
        for ((&vr, &order), &x) in vrs.iter().zip(orders).zip(values) {
            let v = model::variable(M::FMI2.variables, vr, &[Kind::Real])?;
            items.push((v, order, x));
        }
        self.model_mut().set_input_derivatives(&items)
    }

    /// fmi2GetDirectionalDerivative: not provided (providesDirectionalDerivative = false).
    pub fn get_directional_derivative(&mut self) -> Result<(), Failure> {
        self.enter(Function::GetDirectionalDerivative)?;
        Err(Failure::refused(
            "directional derivatives are not provided (providesDirectionalDerivative = false)",
        ))
    }

    /// fmi2DoStep: one communication step (never ended early: FMI 2.0 has no early return);
    /// fmi2Warning when a warning was logged.
    pub fn do_step(&mut self, t: f64, h: f64) -> Result<Status, Failure> {
        self.step(t, h, StepOptions::default())
            .map(|outcome| outcome.status)
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
}
