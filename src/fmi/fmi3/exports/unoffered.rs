//! The exported FMI 3.0 functions of the features this FMU does not offer: Model Exchange,
//! Scheduled Execution, Event Mode, clocks (their intervals and shifts; fmi3GetClock and
//! fmi3SetClock are the parent's, as the get and set of a type without variables), directional
//! and adjoint derivatives and per-element dependencies. The two instantiations return null after
//! telling the host's logger why; every other function is checked against the call-state table
//! and refused with fmi3Error and a message. The parent module re-exports them all, so that they
//! keep their paths (`fmi3::exports::fmi3SetTime`); its safety contract and lint allowances (the
//! standard's names) hold here too.

use super::{
    fmi3Boolean, fmi3ClockUpdateCallback, fmi3DependencyKind, fmi3Float64, fmi3Instance,
    fmi3InstanceEnvironment, fmi3IntervalQualifier, fmi3LockPreemptionCallback,
    fmi3LogMessageCallback, fmi3Status, fmi3String, fmi3UInt64, fmi3UnlockPreemptionCallback,
    fmi3ValueReference, not_provided, report, NO_EVENT_MODE,
};
use crate::fmi::fmi3::call_state::Function;
use libc::size_t;
use std::panic::catch_unwind;

/// Why the clock functions are refused.
const NO_CLOCKS: &str = "this FMU has no clocks";

#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateModelExchange(
    _instanceName: fmi3String,
    _instantiationToken: fmi3String,
    _resourcePath: fmi3String,
    _visible: fmi3Boolean,
    _loggingOn: fmi3Boolean,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: fmi3LogMessageCallback,
) -> fmi3Instance {
    refuse_instantiation(
        "fmi3InstantiateModelExchange",
        instanceEnvironment,
        logMessage,
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateScheduledExecution(
    _instanceName: fmi3String,
    _instantiationToken: fmi3String,
    _resourcePath: fmi3String,
    _visible: fmi3Boolean,
    _loggingOn: fmi3Boolean,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: fmi3LogMessageCallback,
    _clockUpdate: fmi3ClockUpdateCallback,
    _lockPreemption: fmi3LockPreemptionCallback,
    _unlockPreemption: fmi3UnlockPreemptionCallback,
) -> fmi3Instance {
    refuse_instantiation(
        "fmi3InstantiateScheduledExecution",
        instanceEnvironment,
        logMessage,
    )
}

/// The refusal of an interface type this FMU does not offer: tells the host's logger that
/// `function` is not available, the FMU being Co-Simulation only, and returns no instance.
fn refuse_instantiation(
    function: &str,
    environment: fmi3InstanceEnvironment,
    logger: fmi3LogMessageCallback,
) -> fmi3Instance {
    let _ = catch_unwind(|| {
        let message = format!(
            "{function}: this FMU supports Co-Simulation only (fmi3InstantiateCoSimulation)"
        );
        report(logger, environment, &message)
    });
    std::ptr::null_mut()
}

#[no_mangle]
pub unsafe extern "C" fn fmi3EnterEventMode(instance: fmi3Instance) -> fmi3Status {
    not_provided(instance, Function::EnterEventMode, NO_EVENT_MODE)
}

/// Why the dependency queries are refused.
const NO_DEPENDENCIES: &str =
    "per-element dependencies are not provided (providesPerElementDependencies = false)";

#[no_mangle]
pub unsafe extern "C" fn fmi3GetNumberOfVariableDependencies(
    instance: fmi3Instance,
    _valueReference: fmi3ValueReference,
    _nDependencies: *mut size_t,
) -> fmi3Status {
    not_provided(
        instance,
        Function::GetNumberOfVariableDependencies,
        NO_DEPENDENCIES,
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetVariableDependencies(
    instance: fmi3Instance,
    _dependent: fmi3ValueReference,
    _elementIndicesOfDependent: *mut size_t,
    _independents: *mut fmi3ValueReference,
    _elementIndicesOfIndependents: *mut size_t,
    _dependencyKinds: *mut fmi3DependencyKind,
    _nDependencies: size_t,
) -> fmi3Status {
    not_provided(instance, Function::GetVariableDependencies, NO_DEPENDENCIES)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetDirectionalDerivative(
    instance: fmi3Instance,
    _unknowns: *const fmi3ValueReference,
    _nUnknowns: size_t,
    _knowns: *const fmi3ValueReference,
    _nKnowns: size_t,
    _seed: *const fmi3Float64,
    _nSeed: size_t,
    _sensitivity: *mut fmi3Float64,
    _nSensitivity: size_t,
) -> fmi3Status {
    not_provided(
        instance,
        Function::GetDirectionalDerivative,
        "directional derivatives are not provided (providesDirectionalDerivatives = false)",
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetAdjointDerivative(
    instance: fmi3Instance,
    _unknowns: *const fmi3ValueReference,
    _nUnknowns: size_t,
    _knowns: *const fmi3ValueReference,
    _nKnowns: size_t,
    _seed: *const fmi3Float64,
    _nSeed: size_t,
    _sensitivity: *mut fmi3Float64,
    _nSensitivity: size_t,
) -> fmi3Status {
    not_provided(
        instance,
        Function::GetAdjointDerivative,
        "adjoint derivatives are not provided (providesAdjointDerivatives = false)",
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetIntervalDecimal(
    instance: fmi3Instance,
    _valueReferences: *const fmi3ValueReference,
    _nValueReferences: size_t,
    _intervals: *mut fmi3Float64,
    _qualifiers: *mut fmi3IntervalQualifier,
) -> fmi3Status {
    not_provided(instance, Function::GetIntervalDecimal, NO_CLOCKS)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetIntervalFraction(
    instance: fmi3Instance,
    _valueReferences: *const fmi3ValueReference,
    _nValueReferences: size_t,
    _counters: *mut fmi3UInt64,
    _resolutions: *mut fmi3UInt64,
    _qualifiers: *mut fmi3IntervalQualifier,
) -> fmi3Status {
    not_provided(instance, Function::GetIntervalFraction, NO_CLOCKS)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetShiftDecimal(
    instance: fmi3Instance,
    _valueReferences: *const fmi3ValueReference,
    _nValueReferences: size_t,
    _shifts: *mut fmi3Float64,
) -> fmi3Status {
    not_provided(instance, Function::GetShiftDecimal, NO_CLOCKS)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetShiftFraction(
    instance: fmi3Instance,
    _valueReferences: *const fmi3ValueReference,
    _nValueReferences: size_t,
    _counters: *mut fmi3UInt64,
    _resolutions: *mut fmi3UInt64,
) -> fmi3Status {
    not_provided(instance, Function::GetShiftFraction, NO_CLOCKS)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetIntervalDecimal(
    instance: fmi3Instance,
    _valueReferences: *const fmi3ValueReference,
    _nValueReferences: size_t,
    _intervals: *const fmi3Float64,
) -> fmi3Status {
    not_provided(instance, Function::SetIntervalDecimal, NO_CLOCKS)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetIntervalFraction(
    instance: fmi3Instance,
    _valueReferences: *const fmi3ValueReference,
    _nValueReferences: size_t,
    _counters: *const fmi3UInt64,
    _resolutions: *const fmi3UInt64,
) -> fmi3Status {
    not_provided(instance, Function::SetIntervalFraction, NO_CLOCKS)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetShiftDecimal(
    instance: fmi3Instance,
    _valueReferences: *const fmi3ValueReference,
    _nValueReferences: size_t,
    _shifts: *const fmi3Float64,
) -> fmi3Status {
    not_provided(instance, Function::SetShiftDecimal, NO_CLOCKS)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetShiftFraction(
    instance: fmi3Instance,
    _valueReferences: *const fmi3ValueReference,
    _nValueReferences: size_t,
    _counters: *const fmi3UInt64,
    _resolutions: *const fmi3UInt64,
) -> fmi3Status {
    not_provided(instance, Function::SetShiftFraction, NO_CLOCKS)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3EvaluateDiscreteStates(instance: fmi3Instance) -> fmi3Status {
    not_provided(instance, Function::EvaluateDiscreteStates, NO_EVENT_MODE)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3UpdateDiscreteStates(
    instance: fmi3Instance,
    _discreteStatesNeedUpdate: *mut fmi3Boolean,
    _terminateSimulation: *mut fmi3Boolean,
    _nominalsOfContinuousStatesChanged: *mut fmi3Boolean,
    _valuesOfContinuousStatesChanged: *mut fmi3Boolean,
    _nextEventTimeDefined: *mut fmi3Boolean,
    _nextEventTime: *mut fmi3Float64,
) -> fmi3Status {
    not_provided(instance, Function::UpdateDiscreteStates, NO_EVENT_MODE)
}

/// Why the Model Exchange functions are refused.
const CO_SIMULATION_ONLY: &str = "this FMU supports Co-Simulation only";

#[no_mangle]
pub unsafe extern "C" fn fmi3EnterContinuousTimeMode(instance: fmi3Instance) -> fmi3Status {
    not_provided(
        instance,
        Function::EnterContinuousTimeMode,
        CO_SIMULATION_ONLY,
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3CompletedIntegratorStep(
    instance: fmi3Instance,
    _noSetFMUStatePriorToCurrentPoint: fmi3Boolean,
    _enterEventMode: *mut fmi3Boolean,
    _terminateSimulation: *mut fmi3Boolean,
) -> fmi3Status {
    not_provided(
        instance,
        Function::CompletedIntegratorStep,
        CO_SIMULATION_ONLY,
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetTime(instance: fmi3Instance, _time: fmi3Float64) -> fmi3Status {
    not_provided(instance, Function::SetTime, CO_SIMULATION_ONLY)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetContinuousStates(
    instance: fmi3Instance,
    _continuousStates: *const fmi3Float64,
    _nContinuousStates: size_t,
) -> fmi3Status {
    not_provided(instance, Function::SetContinuousStates, CO_SIMULATION_ONLY)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetContinuousStateDerivatives(
    instance: fmi3Instance,
    _derivatives: *mut fmi3Float64,
    _nContinuousStates: size_t,
) -> fmi3Status {
    not_provided(
        instance,
        Function::GetContinuousStateDerivatives,
        CO_SIMULATION_ONLY,
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetEventIndicators(
    instance: fmi3Instance,
    _eventIndicators: *mut fmi3Float64,
    _nEventIndicators: size_t,
) -> fmi3Status {
    not_provided(instance, Function::GetEventIndicators, CO_SIMULATION_ONLY)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetContinuousStates(
    instance: fmi3Instance,
    _continuousStates: *mut fmi3Float64,
    _nContinuousStates: size_t,
) -> fmi3Status {
    not_provided(instance, Function::GetContinuousStates, CO_SIMULATION_ONLY)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetNominalsOfContinuousStates(
    instance: fmi3Instance,
    _nominals: *mut fmi3Float64,
    _nContinuousStates: size_t,
) -> fmi3Status {
    not_provided(
        instance,
        Function::GetNominalsOfContinuousStates,
        CO_SIMULATION_ONLY,
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetNumberOfEventIndicators(
    instance: fmi3Instance,
    _nEventIndicators: *mut size_t,
) -> fmi3Status {
    not_provided(
        instance,
        Function::GetNumberOfEventIndicators,
        CO_SIMULATION_ONLY,
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetNumberOfContinuousStates(
    instance: fmi3Instance,
    _nContinuousStates: *mut size_t,
) -> fmi3Status {
    not_provided(
        instance,
        Function::GetNumberOfContinuousStates,
        CO_SIMULATION_ONLY,
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3EnterStepMode(instance: fmi3Instance) -> fmi3Status {
    not_provided(instance, Function::EnterStepMode, NO_EVENT_MODE)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3ActivateModelPartition(
    instance: fmi3Instance,
    _clockReference: fmi3ValueReference,
    _activationTime: fmi3Float64,
) -> fmi3Status {
    not_provided(
        instance,
        Function::ActivateModelPartition,
        "this FMU supports Co-Simulation only (no Scheduled Execution)",
    )
}
