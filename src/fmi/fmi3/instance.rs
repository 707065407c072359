//! The FMI 3.0 Co-Simulation instance: the generic [`instance::Instance`] with FMI 3.0's
//! call-state table ([`Fmi3`]) and the calls only FMI 3.0 has (Configuration Mode, the step that
//! may return early, the functions of features this FMU does not offer, each refused with a
//! message). `exports.rs` only translates C calls into these methods.

use super::call_state::{Function, Mode};
use crate::fmi::instance::{self, Version};
use crate::fmi::model::{Model, StepOptions, StepOutcome};
use crate::fmi::status::{Failure, Status};
use crate::fmi::variables::{Description, Kind};

/// FMI 3.0 Co-Simulation, for the generic instance.
pub struct Fmi3;

impl Version for Fmi3 {
    type Mode = Mode;
    type Function = Function;

    const INSTANTIATED: Mode = Mode::Instantiated;
    const INITIALIZATION: Mode = Mode::InitializationMode;
    const STEPPING: Mode = Mode::StepMode;
    const TERMINATED: Mode = Mode::Terminated;
    const FAILED: Mode = Mode::Terminated;

    const SET_DEBUG_LOGGING: Function = Function::SetDebugLogging;
    const ENTER_INITIALIZATION_MODE: Function = Function::EnterInitializationMode;
    const EXIT_INITIALIZATION_MODE: Function = Function::ExitInitializationMode;
    const TERMINATE: Function = Function::Terminate;
    const RESET: Function = Function::Reset;
    const GET_FMU_STATE: Function = Function::GetFMUState;
    const SET_FMU_STATE: Function = Function::SetFMUState;
    const FREE_FMU_STATE: Function = Function::FreeFMUState;
    const SERIALIZED_FMU_STATE_SIZE: Function = Function::SerializedFMUStateSize;
    const DESERIALIZE_FMU_STATE: Function = Function::DeserializeFMUState;
    const DO_STEP: Function = Function::DoStep;
    const GET_OUTPUT_DERIVATIVES: Function = Function::GetOutputDerivatives;

    const INSTANTIATE: (&'static str, &'static str) =
        ("fmi3InstantiateCoSimulation", "instantiationToken");

    fn description<M: Model>() -> &'static Description {
        M::FMI3
    }

    fn getter(kind: Kind) -> Function {
        match kind {
            Kind::Integer | Kind::Enumeration => Function::GetInt32,
            Kind::UInt64 => Function::GetUInt64,
            Kind::Boolean => Function::GetBoolean,
            Kind::String => Function::GetString,
            Kind::Real => Function::GetFloat64,
        }
    }

    fn setter(kind: Kind) -> Function {
        match kind {
            Kind::Integer | Kind::Enumeration => Function::SetInt32,
            Kind::UInt64 => Function::SetUInt64,
            Kind::Boolean => Function::SetBoolean,
            Kind::String => Function::SetString,
            Kind::Real => Function::SetFloat64,
        }
    }

    /// FMI 3.0: "If any function called in super state FMU State Settable returns fmi3Error, the
    /// FMU enters state Terminated", refused calls included (a refused call still changes no
    /// value: fmi3SetFMUState or fmi3Reset continue from where it was).
    fn fails_instance(failure: &Failure) -> bool {
        failure.status >= Status::Error
    }
}

/// An FMI 3.0 instance driving model `M`.
pub type Instance<M> = instance::Instance<Fmi3, M>;
/// What an `fmi3FMUState` points to.
pub type StoredState<M> = instance::StoredState<Fmi3, M>;

impl<M: Model> Instance<M> {
    /// fmi3EnterConfigurationMode: from Instantiated into Configuration Mode, where the structural
    /// parameters may be set. Reconfiguration Mode (from Step Mode) is never entered: no
    /// structural parameter is tunable.
    pub fn enter_configuration_mode(&mut self) -> Result<(), Failure> {
        self.enter(Function::EnterConfigurationMode)?;
        if self.mode() != Mode::Instantiated {
            return Err(Failure::refused(
                "this FMU has no tunable structural parameter, so there is no Reconfiguration Mode: set mesh.vertex_rows and mesh.vertex_columns before initialization",
            ));
        }
        self.move_to(Mode::ConfigurationMode);
        Ok(())
    }

    /// fmi3ExitConfigurationMode: back to Instantiated, with the arrays resized to the structural
    /// parameters set.
    pub fn exit_configuration_mode(&mut self) -> Result<(), Failure> {
        self.enter(Function::ExitConfigurationMode)?;
        self.move_to(Mode::Instantiated);
        Ok(())
    }

    /// fmi3DoStep: one communication step, ended early at the first impact when the importer
    /// allowed early return at instantiation.
    pub fn do_step(
        &mut self,
        t: f64,
        h: f64,
        early_return_allowed: bool,
    ) -> Result<StepOutcome, Failure> {
        self.step(
            t,
            h,
            StepOptions {
                early_return: early_return_allowed,
            },
        )
    }

    /// A function of a feature this FMU does not offer (declared so in its model description):
    /// checked against the call-state table, then refused saying why.
    pub fn not_provided(&mut self, function: Function, why: &str) -> Result<(), Failure> {
        self.enter(function)?;
        Err(Failure::refused(why.to_string()))
    }
}
