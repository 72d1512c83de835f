//! The one panic boundary every exported function runs in.

use crate::error::{relnav_status, set_last_error, Failure};
use std::panic::{catch_unwind, AssertUnwindSafe};

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
