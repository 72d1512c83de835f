//! relnav's C ABI: the library C and C++ programs link (`librelnav.a`, `librelnav.so`),
//! declared in `include/relnav.h`, generated from this crate alone by cbindgen and checked
//! in. A thin shell over the safe core (`relnav-core`): every call converts and checks its
//! arguments, runs the core's navigator and turns its result into a status.
//!
//! Conventions, after rustls-ffi:
//! * Every function is `relnav_<object>_<verb>`, returns a [`relnav_status`] (or a value that
//!   cannot fail), and runs inside one panic boundary ([`boundary`]): nothing unwinds into C;
//!   a panic becomes `RELNAV_ERROR_PANIC`.
//! * Every pointer is checked; a null one gives `RELNAV_ERROR_NULL_POINTER` and names the
//!   argument in the message. Numeric inputs are checked (NaN/inf, non-positive step or
//!   mass, unknown enum codes) before anything changes: on error the estimator is untouched.
//! * A failing call stores a readable message, fetched with [`relnav_last_error`] (per
//!   thread, valid until the next failing call on that thread; a successful call leaves it).
//! * `relnav_estimator` is opaque: created by [`relnav_estimator_new`], owned by the caller,
//!   released by [`relnav_estimator_free`] (null is accepted). It may move between threads
//!   but must not be used from two threads at once.
//! * Vectors are `double` arrays of the stated length, in the configured frame, SI units,
//!   angles in radians. Matrices are row-major.
//!
//! One module per domain, after rustls-ffi: [`error`] (status codes, last-error message),
//! [`panic`] (the one panic boundary), [`ptr`] (null-checked array access), [`config`]
//! (`relnav_config` and its enums), [`estimator`] (the estimator handle and its calls),
//! [`hinf`] (the H-infinity design and the runtime filter), [`state`] (saving and
//! restoring an estimator's state).

#![allow(non_camel_case_types)]
#![cfg_attr(not(feature = "std"), no_std)]
// without std a message is a fixed buffer (no heap to box it in): errors are large
#![cfg_attr(not(feature = "std"), allow(clippy::result_large_err))]

pub mod config;
#[rustfmt::skip]
mod config_fields;
pub mod error;
pub mod estimator;
pub mod hinf;
mod panic;
mod ptr;
pub mod state;

pub use config::*;
pub use error::*;
pub use estimator::*;
pub use hinf::*;
pub use state::*;

use core::ffi::{c_char, CStr};

static VERSION_C: &CStr =
    match CStr::from_bytes_with_nul(concat!(env!("CARGO_PKG_VERSION"), "\0").as_bytes()) {
        Ok(s) => s,
        Err(_) => c"unknown",
    };

/// Library version, e.g. `"0.1.0"` (static string, never null). Cannot fail, so returns the
/// string itself.
#[no_mangle]
pub extern "C" fn relnav_version() -> *const c_char {
    VERSION_C.as_ptr()
}

/// Without `std` (the flight library, `panic = "abort"`): a panic stops in place. No panic
/// is reachable in the flight library, which `scripts/build-flight.sh` checks on a linked
/// program (no `core::panicking` symbol).
#[cfg(all(not(feature = "std"), not(test)))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo<'_>) -> ! {
    loop {}
}

/// Without `std`: the precompiled `core` of a hosted target is built for unwinding and
/// names this symbol in its unwind tables; the flight library aborts on panic, so nothing
/// calls it (not in the header: `cbindgen.toml` excludes it).
#[cfg(all(not(feature = "std"), not(test)))]
#[no_mangle]
pub extern "C" fn rust_eh_personality() {}
