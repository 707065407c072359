//! Checks of C arguments, shared by every exported FMI function: null pointers, arrays of a given
//! length, strings, and the text of a caught panic.

use super::status::Failure;
use std::borrow::Cow;
use std::ffi::{c_char, CStr, CString};

/// A refusal naming a null pointer argument.
pub fn null_argument(what: &str) -> Failure {
    Failure::refused(format!("the argument {what} is a null pointer"))
}

/// Reads a C string argument; `None` if the pointer is null.
///
/// # Safety
/// `p` must be null or point to a NUL-terminated string valid for the call (FMI requires this).
pub unsafe fn c_str<'a>(p: *const c_char) -> Option<Cow<'a, str>> {
    if p.is_null() {
        None
    } else {
        // SAFETY: non-null, and NUL-terminated by the caller's contract.
        Some(unsafe { CStr::from_ptr(p) }.to_string_lossy())
    }
}

/// Reads a C string argument into an owned string; empty if the pointer is null.
///
/// # Safety
/// As for [`c_str`].
pub unsafe fn owned_c_str(p: *const c_char) -> String {
    // SAFETY: by the function's contract.
    unsafe { c_str(p) }.map_or_else(String::new, Cow::into_owned)
}

/// The texts of a C array of string arguments, each checked: a null pointer or a text that is
/// not UTF-8 is refused, naming its place.
///
/// # Safety
/// Every non-null pointer of `values` must point to a NUL-terminated string valid for the call.
pub unsafe fn texts<'a>(values: &[*const c_char]) -> Result<Vec<&'a str>, Failure> {
    values
        .iter()
        .enumerate()
        .map(|(k, &p)| {
            if p.is_null() {
                return Err(null_argument(&format!("value[{k}]")));
            }
            // SAFETY: non-null, and NUL-terminated by the caller's contract.
            unsafe { CStr::from_ptr(p) }
                .to_str()
                .map_err(|e| Failure::refused(format!("the text value[{k}] is not UTF-8 ({e})")))
        })
        .collect()
}

/// A slice from a C array of `n` elements; an empty slice for n = 0 whatever the pointer.
///
/// # Safety
/// `p` must be null or point to `n` initialised elements valid for the call.
pub unsafe fn slice<'a, T>(p: *const T, n: usize, what: &str) -> Result<&'a [T], Failure> {
    if n == 0 {
        Ok(&[])
    } else if p.is_null() {
        Err(null_argument(what))
    } else {
        // SAFETY: non-null and, by the caller's contract, valid for `n` elements.
        Ok(unsafe { std::slice::from_raw_parts(p, n) })
    }
}

/// A mutable slice from a C array of `n` elements; an empty slice for n = 0 whatever the pointer.
///
/// # Safety
/// `p` must be null or point to `n` writable elements valid for the call, not aliased.
pub unsafe fn slice_mut<'a, T>(p: *mut T, n: usize, what: &str) -> Result<&'a mut [T], Failure> {
    if n == 0 {
        Ok(&mut [])
    } else if p.is_null() {
        Err(null_argument(what))
    } else {
        // SAFETY: non-null and, by the caller's contract, valid and unaliased for `n` elements.
        Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
    }
}

/// The message of a caught panic.
pub fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into())
}

/// A C string for the host's logger: NUL characters in `s` are written as `\0`.
pub fn to_cstring(s: &str) -> CString {
    CString::new(s.replace('\0', "\\0")).expect("NULs were replaced")
}
