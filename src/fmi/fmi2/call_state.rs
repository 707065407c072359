//! The FMI 2.0 Co-Simulation call-state machine as one table: for every function, the mask of
//! states in which it may be called (FMI 2.0.x, "State Machine of Calling Sequence from Master to
//! Slave"). Every entry point looks its function up once, before it reads or changes anything
//! of the instance ([`crate::fmi::call_state`]).

use crate::fmi::call_state::{call_functions, CallState};
use crate::fmi::model::Phase;
use serde::{Deserialize, Serialize};

/// The states of an FMI 2.0 Co-Simulation instance.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Mode {
    /// After fmi2Instantiate or fmi2Reset.
    Instantiated,
    /// Between fmi2EnterInitializationMode and fmi2ExitInitializationMode.
    InitializationMode,
    /// Ready for fmi2DoStep.
    StepComplete,
    /// An asynchronous step runs (never: this FMU steps synchronously).
    StepInProgress,
    /// A step returned fmi2Discard (never: this FMU does not discard steps).
    StepFailed,
    /// An asynchronous step was cancelled (never).
    StepCanceled,
    /// After fmi2Terminate.
    Terminated,
    /// A call returned fmi2Error that left the instance unusable.
    Error,
    /// A call returned fmi2Fatal (never: no failure of one instance affects another).
    Fatal,
}

impl CallState for Mode {
    const ALL: &'static [Mode] = &[
        Mode::Instantiated,
        Mode::InitializationMode,
        Mode::StepComplete,
        Mode::StepInProgress,
        Mode::StepFailed,
        Mode::StepCanceled,
        Mode::Terminated,
        Mode::Error,
        Mode::Fatal,
    ];

    fn phase(self) -> Phase {
        match self {
            Mode::Instantiated => Phase::Instantiated,
            Mode::InitializationMode => Phase::Initialization,
            Mode::StepComplete | Mode::StepInProgress | Mode::StepFailed | Mode::StepCanceled => {
                Phase::Stepping
            }
            Mode::Terminated => Phase::Terminated,
            Mode::Error | Mode::Fatal => Phase::Failed,
        }
    }

    /// It steps synchronously and never discards.
    fn reachable(self) -> bool {
        !matches!(
            self,
            Mode::StepInProgress | Mode::StepFailed | Mode::StepCanceled | Mode::Fatal
        )
    }
}

impl Mode {
    const fn bit(self) -> u16 {
        1 << self as u16
    }
}

call_functions! {
    "fmi2",
    /// The FMI 2.0 functions that take an instance and return a status (fmi2FreeInstance
    /// always frees; fmi2GetTypesPlatform, fmi2GetVersion and fmi2Instantiate take no
    /// instance). Each is `fmi2` followed by its name.
    /// `Function::ALL` lists them in the standard's order.
    ;
    SetDebugLogging,
    SetupExperiment,
    EnterInitializationMode,
    ExitInitializationMode,
    Terminate,
    Reset,
    GetReal,
    GetInteger,
    GetBoolean,
    GetString,
    SetReal,
    SetInteger,
    SetBoolean,
    SetString,
    GetFMUstate,
    SetFMUstate,
    FreeFMUstate,
    SerializedFMUstateSize,
    SerializeFMUstate,
    DeSerializeFMUstate,
    GetDirectionalDerivative,
    SetRealInputDerivatives,
    GetRealOutputDerivatives,
    DoStep,
    CancelStep,
    GetStatus,
    GetRealStatus,
    GetIntegerStatus,
    GetBooleanStatus,
    GetStringStatus,
}

const I: u16 = Mode::Instantiated.bit();
const N: u16 = Mode::InitializationMode.bit();
const C: u16 = Mode::StepComplete.bit();
const P: u16 = Mode::StepInProgress.bit();
const F: u16 = Mode::StepFailed.bit();
const X: u16 = Mode::StepCanceled.bit();
const T: u16 = Mode::Terminated.bit();
const E: u16 = Mode::Error.bit();

impl Function {
    /// The states in which the function may be called.
    pub const fn allowed(self) -> u16 {
        use Function::*;
        match self {
            SetDebugLogging => I | N | C | P | F | X | T | E,
            SetupExperiment | EnterInitializationMode => I,
            ExitInitializationMode => N,
            Terminate => C | F,
            Reset
            | GetFMUstate
            | SetFMUstate
            | FreeFMUstate
            | SerializedFMUstateSize
            | SerializeFMUstate
            | DeSerializeFMUstate => I | N | C | F | X | T | E,
            GetReal | GetInteger | GetBoolean | GetString | GetDirectionalDerivative => {
                N | C | F | X | T | E
            }
            SetReal | SetInteger | SetBoolean | SetString | SetRealInputDerivatives => I | N | C,
            GetRealOutputDerivatives => C | F | X | T | E,
            DoStep => C,
            CancelStep => P,
            GetStatus | GetRealStatus | GetIntegerStatus | GetBooleanStatus | GetStringStatus => {
                C | P | F | T
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fmi::call_state::{assert_standard_table, CallTable};

    /// The table of the FMI 2.0 standard (Co-Simulation), transcribed row by row: columns
    /// instantiated, initializationMode, stepComplete, stepInProgress, stepFailed, stepCanceled,
    /// terminated, error, fatal. Where the standard allows a get "for debugging only" (footnotes 7
    /// and 8), the call is allowed.
    const STANDARD: [(&str, &str); 30] = [
        ("fmi2SetDebugLogging", "xxxxxxxx-"),
        ("fmi2SetupExperiment", "x--------"),
        ("fmi2EnterInitializationMode", "x--------"),
        ("fmi2ExitInitializationMode", "-x-------"),
        ("fmi2Terminate", "--x-x----"),
        ("fmi2Reset", "xxx-xxxx-"),
        ("fmi2GetReal", "-xx-xxxx-"),
        ("fmi2GetInteger", "-xx-xxxx-"),
        ("fmi2GetBoolean", "-xx-xxxx-"),
        ("fmi2GetString", "-xx-xxxx-"),
        ("fmi2SetReal", "xxx------"),
        ("fmi2SetInteger", "xxx------"),
        ("fmi2SetBoolean", "xxx------"),
        ("fmi2SetString", "xxx------"),
        ("fmi2GetFMUstate", "xxx-xxxx-"),
        ("fmi2SetFMUstate", "xxx-xxxx-"),
        ("fmi2FreeFMUstate", "xxx-xxxx-"),
        ("fmi2SerializedFMUstateSize", "xxx-xxxx-"),
        ("fmi2SerializeFMUstate", "xxx-xxxx-"),
        ("fmi2DeSerializeFMUstate", "xxx-xxxx-"),
        ("fmi2GetDirectionalDerivative", "-xx-xxxx-"),
        ("fmi2SetRealInputDerivatives", "xxx------"),
        ("fmi2GetRealOutputDerivatives", "--x-xxxx-"),
        ("fmi2DoStep", "--x------"),
        ("fmi2CancelStep", "---x-----"),
        ("fmi2GetStatus", "--xxx-x--"),
        ("fmi2GetRealStatus", "--xxx-x--"),
        ("fmi2GetIntegerStatus", "--xxx-x--"),
        ("fmi2GetBooleanStatus", "--xxx-x--"),
        ("fmi2GetStringStatus", "--xxx-x--"),
    ];

    #[test]
    fn masks_equal_the_standards_table() {
        assert_standard_table(Function::ALL, &STANDARD);
    }

    #[test]
    fn refusals_name_the_state_and_the_allowed_ones() {
        let err = Function::DoStep.check(Mode::Instantiated).unwrap_err();
        assert!(
            err.contains("Instantiated") && err.contains("[StepComplete]"),
            "{err}"
        );
    }
}
