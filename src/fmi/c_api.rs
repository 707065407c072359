//! What the exported C functions of both FMI versions share: the panic barrier around every call,
//! the FMU-state handles (a `Box<StoredState>` behind the host's pointer), the serialized bytes,
//! and the category list of set-debug-logging. Each version's `exports.rs` checks its own
//! pointers, finds its instance, and calls these with its own C types.

use super::call_state::CallTable;
use super::ffi::{c_str, null_argument, panic_text, slice, slice_mut};
use super::instance::{Instance, StoredState, Version};
use super::model::Model;
use super::status::{Failure, Status};
use std::ffi::{c_char, c_void};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Runs `body` on `inst` behind a panic barrier and turns its result into a status (logging it):
/// a caught panic puts the instance in its failed state and returns an error.
pub fn guarded<V: Version, M: Model>(
    inst: &mut Instance<V, M>,
    function: V::Function,
    body: impl FnOnce(&mut Instance<V, M>) -> Result<Status, Failure>,
) -> Status {
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        let result = body(&mut *inst);
        inst.finish(function, result)
    }));
    match outcome {
        Ok(status) => status,
        Err(payload) => {
            let text = panic_text(payload.as_ref());
            catch_unwind(AssertUnwindSafe(|| {
                let failure = Failure::broken(format!(
                    "internal error ({text}); the instance is now in the {:?} state: restore an FMU state, reset or free it",
                    V::FAILED
                ));
                inst.set_error_mode();
                inst.finish(function, Err(failure))
            }))
            .unwrap_or(Status::Error)
        }
    }
}

/// A call that returns nothing but its success.
pub fn done(result: Result<(), Failure>) -> Result<Status, Failure> {
    result.map(|()| Status::Ok)
}

/// Set debug logging with the host's `n` category names at `categories` (null when n = 0).
///
/// # Safety
/// `categories` must be null or point to `n` NUL-terminated strings valid for the call.
pub unsafe fn set_debug_logging<V: Version, M: Model>(
    inst: &mut Instance<V, M>,
    on: bool,
    n: usize,
    categories: *const *const c_char,
) -> Result<Status, Failure> {
    // SAFETY: by the function's contract.
    let pointers = unsafe { slice(categories, n, "categories") }?;
    let mut names = Vec::with_capacity(pointers.len());
    for &p in pointers {
        // SAFETY: each entry is a NUL-terminated category name by the function's contract.
        let name = unsafe { c_str(p) }.ok_or_else(|| null_argument("categories[i]"))?;
        names.push(name.into_owned());
    }
    let refs: Vec<&str> = names.iter().map(String::as_str).collect();
    done(inst.set_debug_logging(on, &refs))
}

/// Stores `state` in the host's FMU-state variable at `slot`: a new box if it holds null, else in
/// place (FMI: a non-null state is updated).
///
/// # Safety
/// `slot` must point to the host's FMU-state variable, holding null or a live state of this
/// library for the same version.
unsafe fn store<V: Version, M: Model>(slot: *mut *mut c_void, state: StoredState<V, M>) {
    // SAFETY: by the function's contract.
    unsafe {
        let slot = &mut *slot;
        if slot.is_null() {
            *slot = Box::into_raw(Box::new(state)) as *mut c_void;
        } else {
            *(*slot as *mut StoredState<V, M>) = state;
        }
    }
}

/// The state behind a non-null FMU-state pointer.
///
/// # Safety
/// `state` must be null or a live state allocated by this library for the same version; it is
/// only read.
unsafe fn stored<'a, V: Version, M: Model>(
    state: *mut c_void,
) -> Result<&'a StoredState<V, M>, Failure> {
    if state.is_null() {
        return Err(null_argument("FMUstate"));
    }
    // SAFETY: non-null, and by the contract a live state of this library.
    Ok(unsafe { &*(state as *const StoredState<V, M>) })
}

/// Get FMU state into the host's variable at `slot`.
///
/// # Safety
/// `slot` must be null or as for `store`.
pub unsafe fn get_fmu_state<V: Version, M: Model>(
    inst: &mut Instance<V, M>,
    slot: *mut *mut c_void,
) -> Result<Status, Failure> {
    if slot.is_null() {
        return Err(null_argument("FMUstate"));
    }
    let state = inst.get_state()?;
    // SAFETY: `slot` is non-null and, by the contract, the host's FMU-state variable.
    unsafe { store(slot, state) };
    Ok(Status::Ok)
}

/// Set FMU state from the host's pointer.
///
/// # Safety
/// `state` must be as for `stored`.
pub unsafe fn set_fmu_state<V: Version, M: Model>(
    inst: &mut Instance<V, M>,
    state: *mut c_void,
) -> Result<Status, Failure> {
    // SAFETY: by the function's contract.
    let state = unsafe { stored::<V, M>(state) }?;
    done(inst.set_state(state))
}

/// Free FMU state: frees the state in the host's variable at `slot` (if any) and nulls it.
///
/// # Safety
/// `slot` must be null or point to the host's FMU-state variable, holding null or a live state of
/// this library for the same version that is not used after this call.
pub unsafe fn free_fmu_state<V: Version, M: Model>(
    inst: &mut Instance<V, M>,
    slot: *mut *mut c_void,
) -> Result<Status, Failure> {
    inst.free_state()?;
    if slot.is_null() {
        return Ok(Status::Ok);
    }
    // SAFETY: `slot` points to the host's variable; a non-null value is a Box this library
    // leaked, which FMI forbids using after this call, so it is freed once and the variable nulled.
    unsafe {
        let slot = &mut *slot;
        if !slot.is_null() {
            drop(Box::from_raw(*slot as *mut StoredState<V, M>));
            *slot = std::ptr::null_mut();
        }
    }
    Ok(Status::Ok)
}

/// The serialized size of a state, written to `size`.
///
/// # Safety
/// `state` as for `stored`; `size` null or writable.
pub unsafe fn serialized_size<V: Version, M: Model>(
    inst: &mut Instance<V, M>,
    function: V::Function,
    state: *mut c_void,
    size: *mut usize,
) -> Result<Status, Failure> {
    if size.is_null() {
        return Err(null_argument("size"));
    }
    // SAFETY: by the function's contract.
    let state = unsafe { stored::<V, M>(state) }?;
    let n = inst.serialized(function, state)?.len();
    // SAFETY: `size` is non-null and writable by the contract.
    unsafe { *size = n };
    Ok(Status::Ok)
}

/// Serializes a state into the host's buffer of `size` bytes.
///
/// # Safety
/// `state` as for `stored`; `buffer` null or writable for `size` bytes.
pub unsafe fn serialize<V: Version, M: Model>(
    inst: &mut Instance<V, M>,
    function: V::Function,
    state: *mut c_void,
    buffer: *mut u8,
    size: usize,
) -> Result<Status, Failure> {
    // SAFETY: by the function's contract.
    let state = unsafe { stored::<V, M>(state) }?;
    let bytes = inst.serialized(function, state)?;
    if size < bytes.len() {
        return Err(Failure::refused(format!(
            "the buffer holds {size} bytes, the serialized state needs {} (ask {})",
            bytes.len(),
            V::SERIALIZED_FMU_STATE_SIZE.name()
        )));
    }
    // SAFETY: the host's buffer holds `size` >= bytes.len() writable bytes.
    let out = unsafe { slice_mut(buffer, bytes.len(), "serializedState")? };
    out.copy_from_slice(bytes);
    Ok(Status::Ok)
}

/// Deserializes `size` bytes into a new state in the host's variable at `slot`.
///
/// # Safety
/// `bytes` null or readable for `size` bytes (any content: it is checked); `slot` as for
/// [`get_fmu_state`].
pub unsafe fn deserialize<V: Version, M: Model>(
    inst: &mut Instance<V, M>,
    bytes: *const u8,
    size: usize,
    slot: *mut *mut c_void,
) -> Result<Status, Failure> {
    if slot.is_null() {
        return Err(null_argument("FMUstate"));
    }
    // SAFETY: by the function's contract.
    let bytes = unsafe { slice(bytes, size, "serializedState")? };
    let state = inst.deserialize_state(bytes)?;
    // SAFETY: `slot` is non-null and, by the contract, the host's FMU-state variable.
    unsafe { store(slot, state) };
    Ok(Status::Ok)
}
