//! The exported FMI 2.0 Co-Simulation C functions: the only unsafe code of the crate, as thin as
//! possible. Every function of `fmi2Functions.h` but those of Model Exchange, each with the
//! header's signature (`tests/fmu/test_fmi_abi.py` compiles each export against the header's
//! function type translated to Rust).
//!
//! Each function checks its pointers (a null instance returns fmi2Error; a null array with a
//! non-zero length is reported through the logger), runs the safe [`Instance`] method inside
//! `catch_unwind` so that no panic crosses the C boundary, and returns its status. An
//! `fmi2Component` is a `Box<Component>` and an `fmi2FMUstate` a `Box<StoredState>`, both turned
//! into raw pointers that the host hands back; FMI forbids using them after they are freed.
//!
//! # Safety
//! Every function requires what the FMI 2.0 standard requires of its caller: an `fmi2Component`
//! returned by fmi2Instantiate and not yet freed, used by one thread at a time; arrays valid for
//! the lengths passed; NUL-terminated strings; `fmi2FMUstate` values this library allocated and
//! that were not freed. The functions are public so that tests can drive them as a host would.

// The names are the standard's; the safety contract is stated once above, not per function.
#![allow(non_snake_case, non_camel_case_types, clippy::missing_safety_doc)]

use super::call_state::Function;
use super::instance::Instance;
use crate::fmi::c_api::{self, done, guarded};
use crate::fmi::ffi::{null_argument, owned_c_str, slice, slice_mut, texts, to_cstring};
use crate::fmi::logger::{LogSink, LOG_ERROR};
use crate::fmi::plate::PlateModel;
use crate::fmi::status::{Failure, Status};
use libc::{c_char, c_int, c_uint, c_void, size_t};
use std::ffi::CString;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// The instance type behind an `fmi2Component`: the generic FMI 2.0 instance driving the plate.
pub type Component = Instance<PlateModel>;

const _: () = {
    const fn assert_send<T: Send>() {}
    assert_send::<Component>();
};

pub type fmi2Component = *mut c_void;
pub type fmi2ComponentEnvironment = *mut c_void;
pub type fmi2FMUstate = *mut c_void;
pub type fmi2ValueReference = c_uint;
pub type fmi2Real = f64;
pub type fmi2Integer = c_int;
pub type fmi2Boolean = c_int;
pub type fmi2String = *const c_char;
pub type fmi2Byte = c_char;
pub type fmi2Status = c_int;

const FMI2_TRUE: fmi2Boolean = 1;
const FMI2_FALSE: fmi2Boolean = 0;
const FMI2_CO_SIMULATION: c_int = 1;
const STATUS_KIND_DO_STEP: c_int = 0;
const STATUS_KIND_PENDING: c_int = 1;
const STATUS_KIND_LAST_SUCCESSFUL_TIME: c_int = 2;
const STATUS_KIND_TERMINATED: c_int = 3;
const ERROR: fmi2Status = Status::Error as fmi2Status;

/// The host's variadic logger: (environment, instance name, status, category, format, ...).
pub type fmi2CallbackLogger = unsafe extern "C" fn(
    fmi2ComponentEnvironment,
    fmi2String,
    fmi2Status,
    fmi2String,
    fmi2String,
    ...
);

/// `fmi2CallbackFunctions` of fmi2FunctionTypes.h.
#[repr(C)]
pub struct fmi2CallbackFunctions {
    /// The host's logger.
    pub logger: Option<fmi2CallbackLogger>,
    /// Unused: the FMU allocates with Rust's allocator (canNotUseMemoryManagementFunctions).
    pub allocate_memory: Option<unsafe extern "C" fn(size_t, size_t) -> *mut c_void>,
    /// Unused, as `allocate_memory`.
    pub free_memory: Option<unsafe extern "C" fn(*mut c_void)>,
    /// Unused: steps are synchronous.
    pub step_finished: Option<unsafe extern "C" fn(fmi2ComponentEnvironment, fmi2Status)>,
    /// Handed back to the logger.
    pub component_environment: fmi2ComponentEnvironment,
}

/// The host's logger callback, bound to one instance.
struct HostLogger {
    logger: fmi2CallbackLogger,
    environment: fmi2ComponentEnvironment,
    instance_name: CString,
}

// SAFETY: the environment pointer is opaque to us and only handed back to the host's logger;
// FMI 2.0 lets the host call an instance from any thread (one at a time), and the logger must then
// accept calls from that thread, so moving the pointer with the instance is what FMI requires.
unsafe impl Send for HostLogger {}

impl HostLogger {
    fn send(&self, status: Status, category: &str, message: &str) {
        let category = to_cstring(category);
        let message = to_cstring(message);
        // SAFETY: `logger` came from the host's fmi2CallbackFunctions and FMI requires it to stay
        // callable for the life of the instance; every string is a valid NUL-terminated CString
        // alive for the call, and the format "%s" consumes exactly the one string argument, so
        // a '%' in the message is never interpreted.
        unsafe {
            (self.logger)(
                self.environment,
                self.instance_name.as_ptr(),
                status as fmi2Status,
                category.as_ptr(),
                c"%s".as_ptr(),
                message.as_ptr(),
            );
        }
    }
}

/// Runs `body` on the instance behind `c`: null check, panic barrier, status and logging.
fn call(
    c: fmi2Component,
    function: Function,
    body: impl FnOnce(&mut Component) -> Result<Status, Failure>,
) -> fmi2Status {
    if c.is_null() {
        return ERROR;
    }
    // SAFETY: a non-null fmi2Component is, by the FMI contract, a pointer this library returned
    // from fmi2Instantiate (Box::into_raw) and not yet passed to fmi2FreeInstance; the host does
    // not call one instance from two threads at once, so this is the only reference.
    let inst = unsafe { &mut *(c as *mut Component) };
    guarded(inst, function, body) as fmi2Status
}

#[no_mangle]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    c"default".as_ptr()
}

#[no_mangle]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    c"2.0".as_ptr()
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: fmi2Component,
    logging_on: fmi2Boolean,
    n_categories: size_t,
    categories: *const fmi2String,
) -> fmi2Status {
    call(c, Function::SetDebugLogging, |inst| {
        // SAFETY: FMI passes `n_categories` NUL-terminated strings (the array may be null when 0).
        unsafe {
            c_api::set_debug_logging(inst, logging_on != FMI2_FALSE, n_categories, categories)
        }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Instantiate(
    instance_name: fmi2String,
    fmu_type: c_int,
    fmu_guid: fmi2String,
    _fmu_resource_location: fmi2String,
    functions: *const fmi2CallbackFunctions,
    _visible: fmi2Boolean,
    logging_on: fmi2Boolean,
) -> fmi2Component {
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        if functions.is_null() {
            return std::ptr::null_mut();
        }
        // SAFETY: non-null and, by the FMI contract, a valid fmi2CallbackFunctions for this call;
        // only the logger and the environment are copied out of it.
        let callbacks = unsafe { &*functions };
        // SAFETY: FMI passes NUL-terminated strings (or null, checked inside).
        let name = unsafe { owned_c_str(instance_name) };
        let host = callbacks.logger.map(|logger| HostLogger {
            logger,
            environment: callbacks.component_environment,
            instance_name: to_cstring(&name),
        });
        let report = |host: &Option<HostLogger>, message: &str| {
            if let Some(h) = host {
                h.send(Status::Error, LOG_ERROR, message);
            }
        };
        if name.is_empty() {
            report(
                &host,
                "fmi2Instantiate: instanceName must be a non-empty string",
            );
            return std::ptr::null_mut();
        }
        if fmu_type != FMI2_CO_SIMULATION {
            report(
                &host,
                "fmi2Instantiate: this FMU supports Co-Simulation only (fmuType = fmi2CoSimulation)",
            );
            return std::ptr::null_mut();
        }
        // SAFETY: as for the name.
        let guid = unsafe { owned_c_str(fmu_guid) };
        let sink: Option<LogSink> = host.map(|h| {
            Box::new(move |status: Status, category: &str, message: &str| {
                h.send(status, category, message)
            }) as LogSink
        });
        match Component::new(&name, &guid, logging_on != FMI2_FALSE, sink) {
            Ok(inst) => Box::into_raw(Box::new(inst)) as fmi2Component,
            Err(_logged) => std::ptr::null_mut(),
        }
    }));
    outcome.unwrap_or(std::ptr::null_mut())
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: fmi2Component) {
    if c.is_null() {
        return;
    }
    // SAFETY: `c` came from Box::into_raw in fmi2Instantiate and FMI forbids using it after this
    // call, so ownership returns to a Box exactly once.
    let inst = unsafe { Box::from_raw(c as *mut Component) };
    let _ = catch_unwind(AssertUnwindSafe(move || drop(inst)));
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: fmi2Component,
    _tolerance_defined: fmi2Boolean,
    _tolerance: fmi2Real,
    start_time: fmi2Real,
    stop_time_defined: fmi2Boolean,
    stop_time: fmi2Real,
) -> fmi2Status {
    call(c, Function::SetupExperiment, |inst| {
        let stop = (stop_time_defined != FMI2_FALSE).then_some(stop_time);
        done(inst.setup_experiment(start_time, stop))
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: fmi2Component) -> fmi2Status {
    call(c, Function::EnterInitializationMode, |inst| {
        done(inst.enter_initialization_mode())
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: fmi2Component) -> fmi2Status {
    call(c, Function::ExitInitializationMode, |inst| {
        inst.exit_initialization_mode()
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Terminate(c: fmi2Component) -> fmi2Status {
    call(c, Function::Terminate, |inst| done(inst.terminate()))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
    call(c, Function::Reset, |inst| done(inst.reset()))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: size_t,
    value: *mut fmi2Real,
) -> fmi2Status {
    call(c, Function::GetReal, |inst| {
        // SAFETY: FMI passes arrays of `nvr` elements for both arguments.
        let (vr, value) = unsafe { (slice(vr, nvr, "vr")?, slice_mut(value, nvr, "value")?) };
        done(inst.get_real(vr, value))
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetInteger(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: size_t,
    value: *mut fmi2Integer,
) -> fmi2Status {
    call(c, Function::GetInteger, |inst| {
        // SAFETY: FMI passes arrays of `nvr` elements for both arguments.
        let (vr, value) = unsafe { (slice(vr, nvr, "vr")?, slice_mut(value, nvr, "value")?) };
        done(inst.get_integer(vr, value))
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetBoolean(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: size_t,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    call(c, Function::GetBoolean, |inst| {
        // SAFETY: FMI passes arrays of `nvr` elements for both arguments.
        let (vr, value) = unsafe { (slice(vr, nvr, "vr")?, slice_mut(value, nvr, "value")?) };
        let mut flags = vec![false; vr.len()];
        inst.get_boolean(vr, &mut flags)?;
        for (out, f) in value.iter_mut().zip(flags) {
            *out = if f { FMI2_TRUE } else { FMI2_FALSE };
        }
        Ok(Status::Ok)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: size_t,
    value: *mut fmi2String,
) -> fmi2Status {
    call(c, Function::GetString, |inst| {
        // SAFETY: FMI passes arrays of `nvr` elements for both arguments.
        let (vr, value) = unsafe { (slice(vr, nvr, "vr")?, slice_mut(value, nvr, "value")?) };
        // The texts stay in the instance until its next String get (FMI: the host copies them).
        for (out, text) in value.iter_mut().zip(inst.get_string(vr)?) {
            *out = text.as_ptr();
        }
        Ok(Status::Ok)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: size_t,
    value: *const fmi2Real,
) -> fmi2Status {
    call(c, Function::SetReal, |inst| {
        // SAFETY: FMI passes arrays of `nvr` elements for both arguments.
        let (vr, value) = unsafe { (slice(vr, nvr, "vr")?, slice(value, nvr, "value")?) };
        done(inst.set_real(vr, value))
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetInteger(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: size_t,
    value: *const fmi2Integer,
) -> fmi2Status {
    call(c, Function::SetInteger, |inst| {
        // SAFETY: FMI passes arrays of `nvr` elements for both arguments.
        let (vr, value) = unsafe { (slice(vr, nvr, "vr")?, slice(value, nvr, "value")?) };
        done(inst.set_integer(vr, value))
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetBoolean(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: size_t,
    value: *const fmi2Boolean,
) -> fmi2Status {
    call(c, Function::SetBoolean, |inst| {
        // SAFETY: FMI passes arrays of `nvr` elements for both arguments.
        let (vr, value) = unsafe { (slice(vr, nvr, "vr")?, slice(value, nvr, "value")?) };
        let flags: Vec<bool> = value.iter().map(|&b| b != FMI2_FALSE).collect();
        done(inst.set_boolean(vr, &flags))
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: size_t,
    value: *const fmi2String,
) -> fmi2Status {
    call(c, Function::SetString, |inst| {
        // SAFETY: FMI passes arrays of `nvr` elements for both arguments, each text
        // NUL-terminated.
        let (vr, value) = unsafe { (slice(vr, nvr, "vr")?, slice(value, nvr, "value")?) };
        // SAFETY: as above, for each text.
        let texts = unsafe { texts(value)? };
        done(inst.set_string(vr, &texts))
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetFMUstate(c: fmi2Component, state: *mut fmi2FMUstate) -> fmi2Status {
    call(c, Function::GetFMUstate, |inst| {
        // SAFETY: `state` points to the host's fmi2FMUstate variable (FMI contract).
        unsafe { c_api::get_fmu_state(inst, state) }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetFMUstate(c: fmi2Component, state: fmi2FMUstate) -> fmi2Status {
    call(c, Function::SetFMUstate, |inst| {
        // SAFETY: a non-null fmi2FMUstate is a live state of this library (FMI contract).
        unsafe { c_api::set_fmu_state(inst, state) }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeFMUstate(
    c: fmi2Component,
    state: *mut fmi2FMUstate,
) -> fmi2Status {
    call(c, Function::FreeFMUstate, |inst| {
        // SAFETY: `state` points to the host's fmi2FMUstate variable, which FMI forbids using
        // after this call.
        unsafe { c_api::free_fmu_state(inst, state) }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: fmi2Component,
    state: fmi2FMUstate,
    size: *mut size_t,
) -> fmi2Status {
    call(c, Function::SerializedFMUstateSize, |inst| {
        // SAFETY: a non-null fmi2FMUstate is a live state of this library and `size` the host's
        // size_t (FMI contract).
        unsafe { c_api::serialized_size(inst, Function::SerializedFMUstateSize, state, size) }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: fmi2Component,
    state: fmi2FMUstate,
    serialized_state: *mut fmi2Byte,
    size: size_t,
) -> fmi2Status {
    call(c, Function::SerializeFMUstate, |inst| {
        let (function, buffer) = (Function::SerializeFMUstate, serialized_state as *mut u8);
        // SAFETY: a non-null fmi2FMUstate is a live state of this library and the buffer holds
        // `size` writable bytes (FMI contract).
        unsafe { c_api::serialize(inst, function, state, buffer, size) }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: fmi2Component,
    serialized_state: *const fmi2Byte,
    size: size_t,
    state: *mut fmi2FMUstate,
) -> fmi2Status {
    call(c, Function::DeSerializeFMUstate, |inst| {
        let bytes = serialized_state as *const u8;
        // SAFETY: FMI passes `size` readable bytes (any content: they are checked) and the host's
        // fmi2FMUstate variable.
        unsafe { c_api::deserialize(inst, bytes, size, state) }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: fmi2Component,
    _v_unknown_ref: *const fmi2ValueReference,
    _n_unknown: size_t,
    _v_known_ref: *const fmi2ValueReference,
    _n_known: size_t,
    _dv_known: *const fmi2Real,
    _dv_unknown: *mut fmi2Real,
) -> fmi2Status {
    call(c, Function::GetDirectionalDerivative, |inst| {
        done(inst.get_directional_derivative())
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: size_t,
    order: *const fmi2Integer,
    value: *const fmi2Real,
) -> fmi2Status {
    call(c, Function::SetRealInputDerivatives, |inst| {
        // SAFETY: FMI passes three arrays of `nvr` elements.
        let (vr, order, value) = unsafe {
            (
                slice(vr, nvr, "vr")?,
                slice(order, nvr, "order")?,
                slice(value, nvr, "value")?,
            )
        };
        done(inst.set_real_input_derivatives(vr, order, value))
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: size_t,
    order: *const fmi2Integer,
    value: *mut fmi2Real,
) -> fmi2Status {
    call(c, Function::GetRealOutputDerivatives, |inst| {
        // SAFETY: FMI passes three arrays of `nvr` elements.
        let (vr, order, value) = unsafe {
            (
                slice(vr, nvr, "vr")?,
                slice(order, nvr, "order")?,
                slice_mut(value, nvr, "value")?,
            )
        };
        done(inst.output_derivatives(vr, order, value))
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2DoStep(
    c: fmi2Component,
    current_communication_point: fmi2Real,
    communication_step_size: fmi2Real,
    _no_set_fmu_state_prior_to_current_point: fmi2Boolean,
) -> fmi2Status {
    call(c, Function::DoStep, |inst| {
        inst.do_step(current_communication_point, communication_step_size)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
    call(c, Function::CancelStep, |inst| done(inst.cancel_step()))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetStatus(
    c: fmi2Component,
    kind: c_int,
    _value: *mut fmi2Status,
) -> fmi2Status {
    call(c, Function::GetStatus, |inst| {
        let what = if kind == STATUS_KIND_DO_STEP {
            "fmi2DoStepStatus"
        } else {
            "this status kind"
        };
        done(inst.status_not_available(Function::GetStatus, what))
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealStatus(
    c: fmi2Component,
    kind: c_int,
    value: *mut fmi2Real,
) -> fmi2Status {
    call(c, Function::GetRealStatus, |inst| {
        if kind != STATUS_KIND_LAST_SUCCESSFUL_TIME {
            return done(inst.status_not_available(Function::GetRealStatus, "this status kind"));
        }
        if value.is_null() {
            return Err(null_argument("value"));
        }
        let t = inst.last_successful_time()?;
        // SAFETY: `value` is non-null and points to the host's fmi2Real.
        unsafe { *value = t };
        Ok(Status::Ok)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetIntegerStatus(
    c: fmi2Component,
    _kind: c_int,
    _value: *mut fmi2Integer,
) -> fmi2Status {
    call(c, Function::GetIntegerStatus, |inst| {
        done(inst.status_not_available(Function::GetIntegerStatus, "an integer status"))
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: fmi2Component,
    kind: c_int,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    call(c, Function::GetBooleanStatus, |inst| {
        if kind != STATUS_KIND_TERMINATED {
            return done(inst.status_not_available(Function::GetBooleanStatus, "this status kind"));
        }
        if value.is_null() {
            return Err(null_argument("value"));
        }
        let terminated = inst.terminated_early()?;
        // SAFETY: `value` is non-null and points to the host's fmi2Boolean.
        unsafe { *value = if terminated { FMI2_TRUE } else { FMI2_FALSE } };
        Ok(Status::Ok)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetStringStatus(
    c: fmi2Component,
    kind: c_int,
    _value: *mut fmi2String,
) -> fmi2Status {
    call(c, Function::GetStringStatus, |inst| {
        let what = if kind == STATUS_KIND_PENDING {
            "fmi2PendingStatus"
        } else {
            "this status kind"
        };
        done(inst.status_not_available(Function::GetStringStatus, what))
    })
}
