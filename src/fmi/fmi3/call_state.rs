//! The FMI 3.0 Co-Simulation call-state machine as one table: for every function that takes an
//! instance, the mask of states in which it may be called (FMI 3.0.2, "State Machine and
//! Semantics" for the common states, "State Machine for Co-Simulation" for Step and Intermediate
//! Update Mode). Every entry point looks its function up once, before it reads or changes
//! anything of the instance ([`crate::fmi::call_state`]).
//!
//! Read from the standard: the functions of the super state *FMU State Settable* (set debug
//! logging, reset, the FMU state functions) are allowed in Instantiated, Initialization, Event,
//! Step Mode and Terminated, not in Configuration, Reconfiguration or Intermediate Update Mode,
//! which the standard's figure draws outside it; getting values is allowed in Instantiated (the
//! start values) and everywhere the states list it; Model Exchange and Scheduled Execution
//! functions are not allowed in Co-Simulation; the dependency queries, for which the standard
//! names no state, are allowed where the FMU state functions are. fmi3FreeInstance always frees.

use crate::fmi::call_state::{call_functions, CallState};
use crate::fmi::model::Phase;
use serde::{Deserialize, Serialize};

/// The states of an FMI 3.0 Co-Simulation instance.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Mode {
    /// After fmi3InstantiateCoSimulation, fmi3Reset or fmi3ExitConfigurationMode.
    Instantiated,
    /// Between fmi3EnterConfigurationMode and fmi3ExitConfigurationMode before initialization:
    /// structural parameters may be set.
    ConfigurationMode,
    /// Between fmi3EnterInitializationMode and fmi3ExitInitializationMode.
    InitializationMode,
    /// Event Mode (never: `hasEventMode = false`, impacts are resolved inside the scheme).
    EventMode,
    /// Ready for fmi3DoStep.
    StepMode,
    /// Inside the importer's intermediate-update callback, during fmi3DoStep.
    IntermediateUpdateMode,
    /// Reconfiguration Mode (never: this FMU has no tunable structural parameter).
    ReconfigurationMode,
    /// After fmi3Terminate, or after any call that returned fmi3Error (FMI 3.0 has no Error
    /// state): values may be read, an FMU state restored, the instance reset or freed.
    Terminated,
}

impl CallState for Mode {
    const ALL: &'static [Mode] = &[
        Mode::Instantiated,
        Mode::ConfigurationMode,
        Mode::InitializationMode,
        Mode::EventMode,
        Mode::StepMode,
        Mode::IntermediateUpdateMode,
        Mode::ReconfigurationMode,
        Mode::Terminated,
    ];

    /// FMI 3.0's Terminated ends a run and every failure, so it is the phase that may or may not
    /// hold a simulation.
    fn phase(self) -> Phase {
        match self {
            Mode::Instantiated => Phase::Instantiated,
            Mode::ConfigurationMode => Phase::Configuration,
            Mode::InitializationMode => Phase::Initialization,
            Mode::EventMode
            | Mode::StepMode
            | Mode::IntermediateUpdateMode
            | Mode::ReconfigurationMode => Phase::Stepping,
            Mode::Terminated => Phase::Failed,
        }
    }

    /// No Event Mode, no tunable structural parameter.
    fn reachable(self) -> bool {
        !matches!(self, Mode::EventMode | Mode::ReconfigurationMode)
    }
}

impl Mode {
    const fn bit(self) -> u16 {
        1 << self as u16
    }
}

call_functions! {
    "fmi3",
    /// The FMI 3.0 functions that take an instance and return a status (fmi3FreeInstance
    /// always frees; fmi3GetVersion and the instantiation functions take no instance). Each
    /// is `fmi3` followed by its name.
    /// `Function::ALL` lists them in `fmi3Functions.h`'s order.
    ;
    SetDebugLogging,
    EnterInitializationMode,
    ExitInitializationMode,
    EnterEventMode,
    Terminate,
    Reset,
    GetFloat32,
    GetFloat64,
    GetInt8,
    GetUInt8,
    GetInt16,
    GetUInt16,
    GetInt32,
    GetUInt32,
    GetInt64,
    GetUInt64,
    GetBoolean,
    GetString,
    GetBinary,
    GetClock,
    SetFloat32,
    SetFloat64,
    SetInt8,
    SetUInt8,
    SetInt16,
    SetUInt16,
    SetInt32,
    SetUInt32,
    SetInt64,
    SetUInt64,
    SetBoolean,
    SetString,
    SetBinary,
    SetClock,
    GetNumberOfVariableDependencies,
    GetVariableDependencies,
    GetFMUState,
    SetFMUState,
    FreeFMUState,
    SerializedFMUStateSize,
    SerializeFMUState,
    DeserializeFMUState,
    GetDirectionalDerivative,
    GetAdjointDerivative,
    EnterConfigurationMode,
    ExitConfigurationMode,
    GetIntervalDecimal,
    GetIntervalFraction,
    GetShiftDecimal,
    GetShiftFraction,
    SetIntervalDecimal,
    SetIntervalFraction,
    SetShiftDecimal,
    SetShiftFraction,
    EvaluateDiscreteStates,
    UpdateDiscreteStates,
    EnterContinuousTimeMode,
    CompletedIntegratorStep,
    SetTime,
    SetContinuousStates,
    GetContinuousStateDerivatives,
    GetEventIndicators,
    GetContinuousStates,
    GetNominalsOfContinuousStates,
    GetNumberOfEventIndicators,
    GetNumberOfContinuousStates,
    EnterStepMode,
    GetOutputDerivatives,
    DoStep,
    ActivateModelPartition,
}

const I: u16 = Mode::Instantiated.bit();
const C: u16 = Mode::ConfigurationMode.bit();
const N: u16 = Mode::InitializationMode.bit();
const V: u16 = Mode::EventMode.bit();
const S: u16 = Mode::StepMode.bit();
const U: u16 = Mode::IntermediateUpdateMode.bit();
const R: u16 = Mode::ReconfigurationMode.bit();
const T: u16 = Mode::Terminated.bit();
/// The super state FMU State Settable.
const SETTABLE: u16 = I | N | V | S | T;

impl Function {
    /// The states in which the function may be called.
    pub const fn allowed(self) -> u16 {
        use Function::*;
        match self {
            SetDebugLogging | Reset => SETTABLE,
            EnterInitializationMode => I,
            ExitInitializationMode => N,
            EnterEventMode => S,
            Terminate => V | S,
            GetFloat32 | GetFloat64 | GetInt8 | GetUInt8 | GetInt16 | GetUInt16 | GetInt32
            | GetUInt32 | GetInt64 | GetUInt64 | GetBoolean | GetString | GetBinary => {
                I | N | V | S | U | T
            }
            SetFloat32 | SetFloat64 | SetInt8 | SetUInt8 | SetInt16 | SetUInt16 | SetInt32
            | SetUInt32 | SetInt64 | SetUInt64 | SetBoolean | SetString | SetBinary => {
                I | C | N | V | S | U | R
            }
            GetClock | SetClock | EvaluateDiscreteStates | UpdateDiscreteStates | EnterStepMode => {
                V
            }
            GetNumberOfVariableDependencies
            | GetVariableDependencies
            | GetFMUState
            | SetFMUState
            | FreeFMUState
            | SerializedFMUStateSize
            | SerializeFMUState
            | DeserializeFMUState => SETTABLE,
            GetDirectionalDerivative | GetAdjointDerivative => N | V | S | T,
            EnterConfigurationMode => I | V | S,
            ExitConfigurationMode => C | R,
            GetIntervalDecimal | GetIntervalFraction => N | V,
            GetShiftDecimal | GetShiftFraction | SetIntervalDecimal | SetIntervalFraction
            | SetShiftDecimal | SetShiftFraction => N,
            EnterContinuousTimeMode
            | CompletedIntegratorStep
            | SetTime
            | SetContinuousStates
            | GetContinuousStateDerivatives
            | GetEventIndicators
            | GetContinuousStates
            | GetNominalsOfContinuousStates
            | GetNumberOfEventIndicators
            | GetNumberOfContinuousStates
            | ActivateModelPartition => 0,
            GetOutputDerivatives => S | U | T,
            DoStep => S,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fmi::call_state::{assert_standard_table, CallTable};

    /// The standard's rules transcribed state by state, row by row: columns Instantiated,
    /// ConfigurationMode, InitializationMode, EventMode, StepMode, IntermediateUpdateMode,
    /// ReconfigurationMode, Terminated (see the module docs for how the standard was read).
    const STANDARD: [(&str, &str); 70] = [
        ("fmi3SetDebugLogging", "x-xxx--x"),
        ("fmi3EnterInitializationMode", "x-------"),
        ("fmi3ExitInitializationMode", "--x-----"),
        ("fmi3EnterEventMode", "----x---"),
        ("fmi3Terminate", "---xx---"),
        ("fmi3Reset", "x-xxx--x"),
        ("fmi3GetFloat32", "x-xxxx-x"),
        ("fmi3GetFloat64", "x-xxxx-x"),
        ("fmi3GetInt8", "x-xxxx-x"),
        ("fmi3GetUInt8", "x-xxxx-x"),
        ("fmi3GetInt16", "x-xxxx-x"),
        ("fmi3GetUInt16", "x-xxxx-x"),
        ("fmi3GetInt32", "x-xxxx-x"),
        ("fmi3GetUInt32", "x-xxxx-x"),
        ("fmi3GetInt64", "x-xxxx-x"),
        ("fmi3GetUInt64", "x-xxxx-x"),
        ("fmi3GetBoolean", "x-xxxx-x"),
        ("fmi3GetString", "x-xxxx-x"),
        ("fmi3GetBinary", "x-xxxx-x"),
        ("fmi3GetClock", "---x----"),
        ("fmi3SetFloat32", "xxxxxxx-"),
        ("fmi3SetFloat64", "xxxxxxx-"),
        ("fmi3SetInt8", "xxxxxxx-"),
        ("fmi3SetUInt8", "xxxxxxx-"),
        ("fmi3SetInt16", "xxxxxxx-"),
        ("fmi3SetUInt16", "xxxxxxx-"),
        ("fmi3SetInt32", "xxxxxxx-"),
        ("fmi3SetUInt32", "xxxxxxx-"),
        ("fmi3SetInt64", "xxxxxxx-"),
        ("fmi3SetUInt64", "xxxxxxx-"),
        ("fmi3SetBoolean", "xxxxxxx-"),
        ("fmi3SetString", "xxxxxxx-"),
        ("fmi3SetBinary", "xxxxxxx-"),
        ("fmi3SetClock", "---x----"),
        ("fmi3GetNumberOfVariableDependencies", "x-xxx--x"),
        ("fmi3GetVariableDependencies", "x-xxx--x"),
        ("fmi3GetFMUState", "x-xxx--x"),
        ("fmi3SetFMUState", "x-xxx--x"),
        ("fmi3FreeFMUState", "x-xxx--x"),
        ("fmi3SerializedFMUStateSize", "x-xxx--x"),
        ("fmi3SerializeFMUState", "x-xxx--x"),
        ("fmi3DeserializeFMUState", "x-xxx--x"),
        ("fmi3GetDirectionalDerivative", "--xxx--x"),
        ("fmi3GetAdjointDerivative", "--xxx--x"),
        ("fmi3EnterConfigurationMode", "x--xx---"),
        ("fmi3ExitConfigurationMode", "-x----x-"),
        ("fmi3GetIntervalDecimal", "--xx----"),
        ("fmi3GetIntervalFraction", "--xx----"),
        ("fmi3GetShiftDecimal", "--x-----"),
        ("fmi3GetShiftFraction", "--x-----"),
        ("fmi3SetIntervalDecimal", "--x-----"),
        ("fmi3SetIntervalFraction", "--x-----"),
        ("fmi3SetShiftDecimal", "--x-----"),
        ("fmi3SetShiftFraction", "--x-----"),
        ("fmi3EvaluateDiscreteStates", "---x----"),
        ("fmi3UpdateDiscreteStates", "---x----"),
        ("fmi3EnterContinuousTimeMode", "--------"),
        ("fmi3CompletedIntegratorStep", "--------"),
        ("fmi3SetTime", "--------"),
        ("fmi3SetContinuousStates", "--------"),
        ("fmi3GetContinuousStateDerivatives", "--------"),
        ("fmi3GetEventIndicators", "--------"),
        ("fmi3GetContinuousStates", "--------"),
        ("fmi3GetNominalsOfContinuousStates", "--------"),
        ("fmi3GetNumberOfEventIndicators", "--------"),
        ("fmi3GetNumberOfContinuousStates", "--------"),
        ("fmi3EnterStepMode", "---x----"),
        ("fmi3GetOutputDerivatives", "----xx-x"),
        ("fmi3DoStep", "----x---"),
        ("fmi3ActivateModelPartition", "--------"),
    ];

    #[test]
    fn masks_equal_the_standards_rules() {
        assert_standard_table(Function::ALL, &STANDARD);
    }

    #[test]
    fn refusals_name_the_state_and_the_allowed_ones() {
        let err = Function::DoStep.check(Mode::Instantiated).unwrap_err();
        assert!(
            err.contains("Instantiated") && err.contains("[StepMode]"),
            "{err}"
        );
        let err = Function::SetDebugLogging
            .check(Mode::ConfigurationMode)
            .unwrap_err();
        assert!(err.contains("ConfigurationMode"), "{err}");
    }
}
