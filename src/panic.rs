//! The one panic boundary every exported function runs in.

use crate::error::{relnav_status, set_last_error, Failure};
#[cfg(feature = "std")]
use std::panic::{catch_unwind, AssertUnwindSafe};

#[cfg(feature = "std")]
fn panic_message(p: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = p.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = p.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic payload".to_string()
    }
}

/// The one panic boundary: runs `f`, turns an error into a status plus last-error message
/// and a panic into `RELNAV_ERROR_PANIC`.
#[cfg(feature = "std")]
pub(crate) fn boundary<F: FnOnce() -> Result<(), Failure>>(func: &str, f: F) -> relnav_status {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(Ok(())) => relnav_status::RELNAV_OK,
        Ok(Err(Failure(status, msg))) => {
            set_last_error(&msg);
            status
        }
        Err(p) => {
            set_last_error(&format!(
                "{func}: internal panic: {}",
                panic_message(p.as_ref())
            ));
            relnav_status::RELNAV_ERROR_PANIC
        }
    }
}

/// Without `std` (the flight library, built with `panic = "abort"`): nothing unwinds, so
/// the boundary turns an error into a status plus last-error message; that no panic is
/// reachable at all is checked on the linked program (`scripts/build-flight.sh`).
#[cfg(not(feature = "std"))]
pub(crate) fn boundary<F: FnOnce() -> Result<(), Failure>>(func: &str, f: F) -> relnav_status {
    let _ = func;
    match f() {
        Ok(()) => relnav_status::RELNAV_OK,
        Err(Failure(status, msg)) => {
            set_last_error(&msg);
            status
        }
    }
}
