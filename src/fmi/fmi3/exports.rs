//! The exported FMI 3.0 C functions: every function of `fmi3Functions.h`, with its exact C
//! signature (the types below carry the names of `fmi3PlatformTypes.h` and `fmi3FunctionTypes.h`,
//! and `tests/fmu/test_fmi_abi.py` compiles each export against the header's function type
//! translated to Rust, so a wrong signature fails that build). Those of features this FMU does not offer (Model
//! Exchange, Scheduled Execution, Event Mode, clocks, directional and adjoint derivatives,
//! per-element dependencies) are checked against the call-state table and refused with fmi3Error
//! and a message; they live in `exports/unoffered.rs`, re-exported here.
//!
//! Each function checks its pointers (a null instance returns fmi3Error; a null array with a
//! non-zero length is reported through the logger), runs the safe [`Instance`] method inside
//! `catch_unwind` so that no panic crosses the C boundary, and returns its status. An
//! `fmi3Instance` is a `Box<Component>` and an `fmi3FMUState` a `Box<StoredState>`, both turned
//! into raw pointers that the host hands back; FMI forbids using them after they are freed.
//!
//! # Safety
//! Every function requires what the FMI 3.0 standard requires of its caller: an `fmi3Instance`
//! returned by fmi3InstantiateCoSimulation and not yet freed, used by one thread at a time;
//! arrays valid for the lengths passed; NUL-terminated strings; `fmi3FMUState` values this library
//! allocated and that were not freed. The functions are public so that tests can drive them as a
//! host would.

// The names are the standard's; the safety contract is stated once above, not per function.
#![allow(non_snake_case, non_camel_case_types, clippy::missing_safety_doc)]

use super::call_state::Function;
use super::instance::Instance;
use crate::fmi::c_api::{self, done, guarded};
use crate::fmi::ffi::{null_argument, owned_c_str, slice, slice_mut, texts, to_cstring};
use crate::fmi::logger::{LogSink, LOG_ERROR};
use crate::fmi::plate::PlateModel;
use crate::fmi::status::{Failure, Status};
use libc::{c_char, c_int, c_void, size_t};
use std::panic::{catch_unwind, AssertUnwindSafe};

// The functions of the features this FMU does not offer, refused; re-exported at their paths here.
mod unoffered;
pub use unoffered::*;

pub type fmi3Instance = *mut c_void;
pub type fmi3InstanceEnvironment = *mut c_void;
pub type fmi3FMUState = *mut c_void;
pub type fmi3ValueReference = u32;
pub type fmi3Float32 = f32;
pub type fmi3Float64 = f64;
pub type fmi3Int8 = i8;
pub type fmi3UInt8 = u8;
pub type fmi3Int16 = i16;
pub type fmi3UInt16 = u16;
pub type fmi3Int32 = i32;
pub type fmi3UInt32 = u32;
pub type fmi3Int64 = i64;
pub type fmi3UInt64 = u64;
/// C `bool`, which Rust's `bool` matches in size, alignment and values.
pub type fmi3Boolean = bool;
pub type fmi3Char = c_char;
pub type fmi3String = *const fmi3Char;
pub type fmi3Byte = u8;
pub type fmi3Binary = *const fmi3Byte;
pub type fmi3Clock = bool;
/// The C enums of `fmi3FunctionTypes.h`, int-sized.
pub type fmi3Status = c_int;
pub type fmi3DependencyKind = c_int;
pub type fmi3IntervalQualifier = c_int;

/// The host's logger: (environment, status, category, message).
pub type fmi3LogMessageCallback =
    Option<unsafe extern "C" fn(fmi3InstanceEnvironment, fmi3Status, fmi3String, fmi3String)>;
/// The host's intermediate-update callback (not called: providesIntermediateUpdate = false).
pub type fmi3IntermediateUpdateCallback = Option<
    unsafe extern "C" fn(
        fmi3InstanceEnvironment,
        fmi3Float64,
        fmi3Boolean,
        fmi3Boolean,
        fmi3Boolean,
        fmi3Boolean,
        *mut fmi3Boolean,
        *mut fmi3Float64,
    ),
>;
/// Scheduled Execution's clock callback (Scheduled Execution is not offered).
pub type fmi3ClockUpdateCallback = Option<unsafe extern "C" fn(fmi3InstanceEnvironment)>;
/// Scheduled Execution's preemption callbacks (Scheduled Execution is not offered).
pub type fmi3LockPreemptionCallback = Option<unsafe extern "C" fn()>;
/// See [`fmi3LockPreemptionCallback`].
pub type fmi3UnlockPreemptionCallback = Option<unsafe extern "C" fn()>;

// The sizes fmi3PlatformTypes.h gives its types (the signatures are checked against the header
// by tests/fmu/test_fmi_abi.py, the sizes here).
const _: () = {
    use std::mem::size_of;
    assert!(size_of::<fmi3ValueReference>() == 4 && size_of::<fmi3Float32>() == 4);
    assert!(size_of::<fmi3Float64>() == 8 && size_of::<fmi3Int8>() == 1);
    assert!(size_of::<fmi3UInt8>() == 1 && size_of::<fmi3Int16>() == 2);
    assert!(size_of::<fmi3UInt16>() == 2 && size_of::<fmi3Int32>() == 4);
    assert!(size_of::<fmi3UInt32>() == 4 && size_of::<fmi3Int64>() == 8);
    assert!(size_of::<fmi3UInt64>() == 8 && size_of::<fmi3Boolean>() == 1);
    assert!(size_of::<fmi3Byte>() == 1 && size_of::<fmi3Clock>() == 1);
    assert!(size_of::<fmi3Status>() == size_of::<c_int>());
};

const ERROR: fmi3Status = Status::Error as fmi3Status;

/// Why the functions of Event Mode are refused.
const NO_EVENT_MODE: &str =
    "this FMU has no Event Mode (hasEventMode = false): impacts are resolved inside the scheme, and fmi3DoStep returns early at them when the importer allows it";
/// The instance behind an `fmi3Instance`: the generic FMI 3.0 instance driving the plate, and
/// what the importer chose at instantiation.
pub struct Component {
    instance: Instance<PlateModel>,
    /// `earlyReturnAllowed` of fmi3InstantiateCoSimulation.
    early_return_allowed: bool,
}

const _: () = {
    const fn assert_send<T: Send>() {}
    assert_send::<Component>();
};

/// The host's logger callback, bound to one instance.
struct HostLogger {
    logger: unsafe extern "C" fn(fmi3InstanceEnvironment, fmi3Status, fmi3String, fmi3String),
    environment: fmi3InstanceEnvironment,
}

// SAFETY: the environment pointer is opaque to us and only handed back to the host's logger;
// FMI 3.0 lets the host call an instance from any thread (one at a time), and the logger must then
// accept calls from that thread, so moving the pointer with the instance is what FMI requires.
unsafe impl Send for HostLogger {}

impl HostLogger {
    fn send(&self, status: Status, category: &str, message: &str) {
        let category = to_cstring(category);
        let message = to_cstring(message);
        // SAFETY: `logger` came from fmi3InstantiateCoSimulation and FMI requires it to stay
        // callable for the life of the instance; both strings are valid NUL-terminated CStrings
        // alive for the call (the host copies what it keeps).
        unsafe {
            (self.logger)(
                self.environment,
                status as fmi3Status,
                category.as_ptr(),
                message.as_ptr(),
            );
        }
    }
}

/// Runs `body` on the instance behind `c`: null check, panic barrier, status and logging.
fn call(
    c: fmi3Instance,
    function: Function,
    body: impl FnOnce(&mut Instance<PlateModel>, bool) -> Result<Status, Failure>,
) -> fmi3Status {
    if c.is_null() {
        return ERROR;
    }
    // SAFETY: a non-null fmi3Instance is, by the FMI contract, a pointer this library returned
    // from fmi3InstantiateCoSimulation (Box::into_raw) and not yet passed to fmi3FreeInstance;
    // the host does not call one instance from two threads at once, so this is the only
    // reference.
    let component = unsafe { &mut *(c as *mut Component) };
    let early_return_allowed = component.early_return_allowed;
    guarded(&mut component.instance, function, |inst| {
        body(inst, early_return_allowed)
    }) as fmi3Status
}

/// A call of a function this FMU does not offer: refused with `why`.
fn not_provided(c: fmi3Instance, function: Function, why: &str) -> fmi3Status {
    call(c, function, |inst, _| {
        done(inst.not_provided(function, why))
    })
}

/// A get or set of a type this FMU has no variable of: with value references, refused naming
/// what they are; without, checked and done.
///
/// # Safety
/// `vrs` must be null or point to `n` value references.
unsafe fn absent_type(
    c: fmi3Instance,
    function: Function,
    vrs: *const fmi3ValueReference,
    n: size_t,
) -> fmi3Status {
    call(c, function, |inst, _| {
        // SAFETY: by the function's contract.
        let vrs = unsafe { slice(vrs, n, "valueReferences")? };
        done(inst.check_absent_kind(function, &[], vrs))
    })
}

#[no_mangle]
pub extern "C" fn fmi3GetVersion() -> *const c_char {
    c"3.0".as_ptr()
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetDebugLogging(
    instance: fmi3Instance,
    loggingOn: fmi3Boolean,
    nCategories: size_t,
    categories: *const fmi3String,
) -> fmi3Status {
    call(instance, Function::SetDebugLogging, |inst, _| {
        // SAFETY: FMI passes `nCategories` NUL-terminated strings (the array may be null when 0).
        unsafe { c_api::set_debug_logging(inst, loggingOn, nCategories, categories) }
    })
}

/// Sends `message` to the host's logger, if any, as an error under logStatusError.
fn report(logger: fmi3LogMessageCallback, environment: fmi3InstanceEnvironment, message: &str) {
    if let Some(logger) = logger {
        HostLogger {
            logger,
            environment,
        }
        .send(Status::Error, LOG_ERROR, message);
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
    instanceName: fmi3String,
    instantiationToken: fmi3String,
    _resourcePath: fmi3String,
    _visible: fmi3Boolean,
    loggingOn: fmi3Boolean,
    eventModeUsed: fmi3Boolean,
    earlyReturnAllowed: fmi3Boolean,
    requiredIntermediateVariables: *const fmi3ValueReference,
    nRequiredIntermediateVariables: size_t,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: fmi3LogMessageCallback,
    _intermediateUpdate: fmi3IntermediateUpdateCallback,
) -> fmi3Instance {
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        let fail = |message: &str| {
            report(
                logMessage,
                instanceEnvironment,
                &format!("fmi3InstantiateCoSimulation: {message}"),
            );
            std::ptr::null_mut()
        };
        // SAFETY: FMI passes NUL-terminated strings (or null, checked inside).
        let name = unsafe { owned_c_str(instanceName) };
        if name.trim().is_empty() {
            return fail("instanceName must be a non-empty string");
        }
        if eventModeUsed {
            return fail(NO_EVENT_MODE);
        }
        if nRequiredIntermediateVariables > 0 {
            return fail(&format!(
                "requiredIntermediateVariables lists {nRequiredIntermediateVariables} variables, but this FMU provides no intermediate update (providesIntermediateUpdate = false)"
            ));
        }
        let _ = requiredIntermediateVariables;
        // SAFETY: as for the name.
        let token = unsafe { owned_c_str(instantiationToken) };
        let sink: Option<LogSink> = logMessage.map(|logger| {
            let host = HostLogger {
                logger,
                environment: instanceEnvironment,
            };
            Box::new(move |status: Status, category: &str, message: &str| {
                host.send(status, category, message)
            }) as LogSink
        });
        match Instance::<PlateModel>::new(&name, &token, loggingOn, sink) {
            Ok(instance) => Box::into_raw(Box::new(Component {
                instance,
                early_return_allowed: earlyReturnAllowed,
            })) as fmi3Instance,
            Err(_logged) => std::ptr::null_mut(),
        }
    }));
    outcome.unwrap_or(std::ptr::null_mut())
}

#[no_mangle]
pub unsafe extern "C" fn fmi3FreeInstance(instance: fmi3Instance) {
    if instance.is_null() {
        return;
    }
    // SAFETY: `instance` came from Box::into_raw in fmi3InstantiateCoSimulation and FMI forbids
    // using it after this call, so ownership returns to a Box exactly once.
    let component = unsafe { Box::from_raw(instance as *mut Component) };
    let _ = catch_unwind(AssertUnwindSafe(move || drop(component)));
}

#[no_mangle]
pub unsafe extern "C" fn fmi3EnterInitializationMode(
    instance: fmi3Instance,
    _toleranceDefined: fmi3Boolean,
    _tolerance: fmi3Float64,
    startTime: fmi3Float64,
    stopTimeDefined: fmi3Boolean,
    stopTime: fmi3Float64,
) -> fmi3Status {
    call(instance, Function::EnterInitializationMode, |inst, _| {
        let stop = stopTimeDefined.then_some(stopTime);
        done(inst.begin_initialization(Some((startTime, stop))))
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3ExitInitializationMode(instance: fmi3Instance) -> fmi3Status {
    call(instance, Function::ExitInitializationMode, |inst, _| {
        inst.exit_initialization_mode()
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3Terminate(instance: fmi3Instance) -> fmi3Status {
    call(instance, Function::Terminate, |inst, _| {
        done(inst.terminate())
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3Reset(instance: fmi3Instance) -> fmi3Status {
    call(instance, Function::Reset, |inst, _| done(inst.reset()))
}

/// Declares the get and set functions of the types this FMU has variables of: `$values` is the
/// C array of values (`*mut` for a get, which writes them; `*const` for a set) and `$as_slice`
/// the check that makes it a slice ([`slice_mut`] or [`slice`]).
macro_rules! value_functions {
    ($($name:ident, $function:ident, $values:ty, $as_slice:ident, $method:ident;)*) => {$(
        #[no_mangle]
        pub unsafe extern "C" fn $name(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: size_t,
            values: $values,
            nValues: size_t,
        ) -> fmi3Status {
            call(instance, Function::$function, |inst, _| {
                // SAFETY: FMI passes `nValueReferences` value references and `nValues` values
                // (room for them in a get).
                let (vrs, values) = unsafe {
                    (
                        slice(valueReferences, nValueReferences, "valueReferences")?,
                        $as_slice(values, nValues, "values")?,
                    )
                };
                done(inst.$method(vrs, values))
            })
        }
    )*};
}

value_functions! {
    fmi3GetFloat64, GetFloat64, *mut fmi3Float64, slice_mut, get_real;
    fmi3GetInt32, GetInt32, *mut fmi3Int32, slice_mut, get_integer;
    fmi3GetUInt64, GetUInt64, *mut fmi3UInt64, slice_mut, get_uint64;
    fmi3GetBoolean, GetBoolean, *mut fmi3Boolean, slice_mut, get_boolean;
    fmi3SetFloat64, SetFloat64, *const fmi3Float64, slice, set_real;
    fmi3SetInt32, SetInt32, *const fmi3Int32, slice, set_integer;
    fmi3SetUInt64, SetUInt64, *const fmi3UInt64, slice, set_uint64;
    fmi3SetBoolean, SetBoolean, *const fmi3Boolean, slice, set_boolean;
}

/// Declares the get and set functions of the types this FMU has no variable of.
macro_rules! absent_types {
    ($($name:ident, $function:ident, $values:ty;)*) => {$(
        #[no_mangle]
        pub unsafe extern "C" fn $name(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: size_t,
            _values: $values,
            _nValues: size_t,
        ) -> fmi3Status {
            // SAFETY: FMI passes `nValueReferences` value references.
            unsafe { absent_type(instance, Function::$function, valueReferences, nValueReferences) }
        }
    )*};
}

absent_types! {
    fmi3GetFloat32, GetFloat32, *mut fmi3Float32;
    fmi3GetInt8, GetInt8, *mut fmi3Int8;
    fmi3GetUInt8, GetUInt8, *mut fmi3UInt8;
    fmi3GetInt16, GetInt16, *mut fmi3Int16;
    fmi3GetUInt16, GetUInt16, *mut fmi3UInt16;
    fmi3GetUInt32, GetUInt32, *mut fmi3UInt32;
    fmi3GetInt64, GetInt64, *mut fmi3Int64;
    fmi3SetFloat32, SetFloat32, *const fmi3Float32;
    fmi3SetInt8, SetInt8, *const fmi3Int8;
    fmi3SetUInt8, SetUInt8, *const fmi3UInt8;
    fmi3SetInt16, SetInt16, *const fmi3Int16;
    fmi3SetUInt16, SetUInt16, *const fmi3UInt16;
    fmi3SetUInt32, SetUInt32, *const fmi3UInt32;
    fmi3SetInt64, SetInt64, *const fmi3Int64;
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetString(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    values: *mut fmi3String,
    nValues: size_t,
) -> fmi3Status {
    call(instance, Function::GetString, |inst, _| {
        // SAFETY: FMI passes `nValueReferences` value references and room for `nValues` values.
        let (vrs, values) = unsafe {
            (
                slice(valueReferences, nValueReferences, "valueReferences")?,
                slice_mut(values, nValues, "values")?,
            )
        };
        if values.len() != vrs.len() {
            return Err(Failure::refused(format!(
                "nValues = {nValues}, but the {} String variables asked for hold one value each",
                vrs.len()
            )));
        }
        // The texts stay in the instance until its next String get (FMI: the host copies them).
        for (out, text) in values.iter_mut().zip(inst.get_string(vrs)?) {
            *out = text.as_ptr();
        }
        Ok(Status::Ok)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetString(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    values: *const fmi3String,
    nValues: size_t,
) -> fmi3Status {
    call(instance, Function::SetString, |inst, _| {
        // SAFETY: FMI passes `nValueReferences` value references and `nValues` NUL-terminated
        // texts.
        let (vrs, values) = unsafe {
            (
                slice(valueReferences, nValueReferences, "valueReferences")?,
                slice(values, nValues, "values")?,
            )
        };
        // SAFETY: as above, for each text.
        let texts = unsafe { texts(values)? };
        done(inst.set_string(vrs, &texts))
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetBinary(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    _valueSizes: *mut size_t,
    _values: *mut fmi3Binary,
    _nValues: size_t,
) -> fmi3Status {
    // SAFETY: FMI passes `nValueReferences` value references.
    unsafe {
        absent_type(
            instance,
            Function::GetBinary,
            valueReferences,
            nValueReferences,
        )
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetBinary(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    _valueSizes: *const size_t,
    _values: *const fmi3Binary,
    _nValues: size_t,
) -> fmi3Status {
    // SAFETY: FMI passes `nValueReferences` value references.
    unsafe {
        absent_type(
            instance,
            Function::SetBinary,
            valueReferences,
            nValueReferences,
        )
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetClock(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    _values: *mut fmi3Clock,
) -> fmi3Status {
    // SAFETY: FMI passes `nValueReferences` value references.
    unsafe {
        absent_type(
            instance,
            Function::GetClock,
            valueReferences,
            nValueReferences,
        )
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetClock(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    _values: *const fmi3Clock,
) -> fmi3Status {
    // SAFETY: FMI passes `nValueReferences` value references.
    unsafe {
        absent_type(
            instance,
            Function::SetClock,
            valueReferences,
            nValueReferences,
        )
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetFMUState(
    instance: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    call(instance, Function::GetFMUState, |inst, _| {
        // SAFETY: `FMUState` points to the host's fmi3FMUState variable (FMI contract).
        unsafe { c_api::get_fmu_state(inst, FMUState) }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetFMUState(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
) -> fmi3Status {
    call(instance, Function::SetFMUState, |inst, _| {
        // SAFETY: a non-null fmi3FMUState is a live state of this library (FMI contract).
        unsafe { c_api::set_fmu_state(inst, FMUState) }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3FreeFMUState(
    instance: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    call(instance, Function::FreeFMUState, |inst, _| {
        // SAFETY: `FMUState` points to the host's fmi3FMUState variable, which FMI forbids
        // using after this call.
        unsafe { c_api::free_fmu_state(inst, FMUState) }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
    size: *mut size_t,
) -> fmi3Status {
    call(instance, Function::SerializedFMUStateSize, |inst, _| {
        let function = Function::SerializedFMUStateSize;
        // SAFETY: a non-null fmi3FMUState is a live state of this library and `size` the host's
        // size_t (FMI contract).
        unsafe { c_api::serialized_size(inst, function, FMUState, size) }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SerializeFMUState(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
    serializedState: *mut fmi3Byte,
    size: size_t,
) -> fmi3Status {
    call(instance, Function::SerializeFMUState, |inst, _| {
        let function = Function::SerializeFMUState;
        // SAFETY: a non-null fmi3FMUState is a live state of this library and the buffer holds
        // `size` writable bytes (FMI contract).
        unsafe { c_api::serialize(inst, function, FMUState, serializedState, size) }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3DeserializeFMUState(
    instance: fmi3Instance,
    serializedState: *const fmi3Byte,
    size: size_t,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    call(instance, Function::DeserializeFMUState, |inst, _| {
        // SAFETY: FMI passes `size` readable bytes (any content: they are checked) and the host's
        // fmi3FMUState variable.
        unsafe { c_api::deserialize(inst, serializedState, size, FMUState) }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3EnterConfigurationMode(instance: fmi3Instance) -> fmi3Status {
    call(instance, Function::EnterConfigurationMode, |inst, _| {
        done(inst.enter_configuration_mode())
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3ExitConfigurationMode(instance: fmi3Instance) -> fmi3Status {
    call(instance, Function::ExitConfigurationMode, |inst, _| {
        done(inst.exit_configuration_mode())
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetOutputDerivatives(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    orders: *const fmi3Int32,
    values: *mut fmi3Float64,
    nValues: size_t,
) -> fmi3Status {
    call(instance, Function::GetOutputDerivatives, |inst, _| {
        // SAFETY: FMI passes `nValueReferences` value references and orders, and room for
        // `nValues` values.
        let (vrs, orders, values) = unsafe {
            (
                slice(valueReferences, nValueReferences, "valueReferences")?,
                slice(orders, nValueReferences, "orders")?,
                slice_mut(values, nValues, "values")?,
            )
        };
        done(inst.output_derivatives(vrs, orders, values))
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3DoStep(
    instance: fmi3Instance,
    currentCommunicationPoint: fmi3Float64,
    communicationStepSize: fmi3Float64,
    _noSetFMUStatePriorToCurrentPoint: fmi3Boolean,
    eventHandlingNeeded: *mut fmi3Boolean,
    terminateSimulation: *mut fmi3Boolean,
    earlyReturn: *mut fmi3Boolean,
    lastSuccessfulTime: *mut fmi3Float64,
) -> fmi3Status {
    call(instance, Function::DoStep, |inst, early_return_allowed| {
        let outputs = [
            ("eventHandlingNeeded", eventHandlingNeeded.is_null()),
            ("terminateSimulation", terminateSimulation.is_null()),
            ("earlyReturn", earlyReturn.is_null()),
            ("lastSuccessfulTime", lastSuccessfulTime.is_null()),
        ];
        if let Some((name, _)) = outputs.iter().find(|(_, null)| *null) {
            return Err(null_argument(name));
        }
        let outcome = inst.do_step(
            currentCommunicationPoint,
            communicationStepSize,
            early_return_allowed,
        )?;
        // SAFETY: the four output arguments are non-null and point to the host's variables.
        unsafe {
            *eventHandlingNeeded = false;
            *terminateSimulation = false;
            *earlyReturn = outcome.early_return;
            *lastSuccessfulTime = inst.time();
        }
        Ok(outcome.status)
    })
}
