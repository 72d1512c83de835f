//! Status codes, the per-thread last-error message and the internal [`Failure`] that
//! carries both to the boundary.

use core::ffi::{c_char, CStr};
use relnav_core::message::Message;
use relnav_core::nav::{NavError, NavErrorKind};
#[cfg(feature = "std")]
use std::{cell::RefCell, ffi::CString, panic::catch_unwind};

/// Result of every fallible call. Values are stable. An `int32_t` on every target: a C
/// enum's size is the compiler's choice (one byte on arm-none-eabi, where short enums
/// are the default), a status is not.
#[repr(i32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum relnav_status {
    /// Success.
    RELNAV_OK = 0,
    /// A required pointer argument was null.
    RELNAV_ERROR_NULL_POINTER = 1,
    /// An argument is out of its domain (NaN/inf, non-positive step or mass, unknown code).
    RELNAV_ERROR_INVALID_ARGUMENT = 2,
    /// The requested filter is not implemented in this build.
    RELNAV_ERROR_NOT_IMPLEMENTED = 3,
    /// The filter could not complete the step (zero range, loss of positive definiteness).
    RELNAV_ERROR_NUMERICAL = 4,
    /// A Rust panic was caught at the boundary (a bug in relnav; please report it).
    RELNAV_ERROR_PANIC = 5,
    /// The H-infinity design has no solution (the LMI is infeasible for these inputs).
    RELNAV_ERROR_INFEASIBLE = 6,
    /// The caller's buffer is too small (`relnav_estimator_save`: the needed size is in
    /// `*len`).
    RELNAV_ERROR_BUFFER_TOO_SMALL = 7,
    /// A saved state was refused (`relnav_estimator_restore`): truncated, corrupted,
    /// another format version, or saved for another configuration; the estimator is
    /// unchanged.
    RELNAV_ERROR_INVALID_STATE = 8,
}

#[cfg(feature = "std")]
thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

#[cfg(feature = "std")]
pub(crate) fn set_last_error(msg: &str) {
    let clean: Vec<u8> = msg.bytes().filter(|b| *b != 0).collect();
    let c = CString::new(clean).unwrap_or_default();
    LAST_ERROR.with(|e| *e.borrow_mut() = c);
}

/// Without `std` (the flight library, which starts no threads): the last message in one
/// static, NUL-terminated buffer, shared by the threads of a caller that calls relnav from
/// several (documented in the header: the flight library is for one thread).
#[cfg(not(feature = "std"))]
struct LastError(core::cell::UnsafeCell<[u8; relnav_core::message::MESSAGE_CAPACITY + 1]>);

// SAFETY: the flight library is documented for one thread; the buffer is only written by
// `set_last_error` and read through the pointer `relnav_last_error` hands out.
#[cfg(not(feature = "std"))]
unsafe impl Sync for LastError {}

#[cfg(not(feature = "std"))]
static LAST_ERROR: LastError = LastError(core::cell::UnsafeCell::new(
    [0; relnav_core::message::MESSAGE_CAPACITY + 1],
));

#[cfg(not(feature = "std"))]
pub(crate) fn set_last_error(msg: &str) {
    // SAFETY: one thread (see `LastError`); no reference to the buffer outlives this call.
    let buf = unsafe { &mut *LAST_ERROR.0.get() };
    let mut n = 0;
    for (dst, b) in buf.iter_mut().zip(msg.bytes().filter(|b| *b != 0)) {
        *dst = b;
        n += 1;
    }
    let end = n.min(buf.len() - 1);
    if let Some(z) = buf.get_mut(end) {
        *z = 0;
    }
}

/// An error that crosses the boundary: status plus message.
pub(crate) struct Failure(pub(crate) relnav_status, pub(crate) Message);

impl From<NavError> for Failure {
    fn from(e: NavError) -> Self {
        let status = match e.kind {
            NavErrorKind::InvalidArgument => relnav_status::RELNAV_ERROR_INVALID_ARGUMENT,
            NavErrorKind::NotImplemented => relnav_status::RELNAV_ERROR_NOT_IMPLEMENTED,
            NavErrorKind::Numerical => relnav_status::RELNAV_ERROR_NUMERICAL,
            NavErrorKind::InvalidState => relnav_status::RELNAV_ERROR_INVALID_STATE,
        };
        Failure(status, e.message)
    }
}

/// The refusal of a call the flight library (no std) does not have; `instead`: the call
/// in the caller's storage that replaces a heap one.
#[cfg(not(feature = "std"))]
pub(crate) fn not_in_this_build(func: &str, instead: Option<&str>) -> Failure {
    let message = match instead {
        None => Message::concat(&[func, ": not in this build (the flight library)"]),
        Some(call) => Message::concat(&[
            func,
            ": not in this build (the flight library has no heap): use ",
            call,
        ]),
    };
    Failure(relnav_status::RELNAV_ERROR_NOT_IMPLEMENTED, message)
}

pub(crate) fn null(arg: &str, func: &str) -> Failure {
    Failure(
        relnav_status::RELNAV_ERROR_NULL_POINTER,
        Message::concat(&[func, ": argument `", arg, "` is null"]),
    )
}

/// A static, readable name for a status code (unknown codes give `"unknown status"`).
/// Cannot fail, so returns the name itself.
#[no_mangle]
pub extern "C" fn relnav_status_string(status: i32) -> *const c_char {
    let s: &'static CStr = match status {
        0 => c"ok",
        1 => c"null pointer argument",
        2 => c"invalid argument",
        3 => c"not implemented",
        4 => c"numerical failure",
        5 => c"internal panic",
        6 => c"infeasible design",
        7 => c"buffer too small",
        8 => c"invalid saved state",
        _ => c"unknown status",
    };
    s.as_ptr()
}

/// The message of the most recent failing call on this thread (empty string if none).
/// The pointer stays valid until the next failing call on the same thread. Cannot fail, so
/// returns the message itself.
///
/// Flight library: one buffer for the program (no threads there), and the numbers in the
/// message written as `?` (no float formatting).
#[no_mangle]
pub extern "C" fn relnav_last_error() -> *const c_char {
    #[cfg(feature = "std")]
    return catch_unwind(|| LAST_ERROR.with(|e| e.borrow().as_ptr())).unwrap_or(c"".as_ptr());
    #[cfg(not(feature = "std"))]
    return LAST_ERROR.0.get().cast::<c_char>();
}
