//! FMI 3.0 platform types (FMI 3.0.2, `fmi3PlatformTypes.h` and `fmi3FunctionTypes.h`),
//! written from the standard's text: only those the bindings use.
#![allow(non_camel_case_types, non_upper_case_globals, non_snake_case)]

use crate::status::Status;
use std::ffi::{c_char, c_void};

/// Opaque instance pointer handed to the master.
pub type fmi3Instance = *mut c_void;
/// The master's environment pointer, passed back to its callbacks.
pub type fmi3InstanceEnvironment = *mut c_void;
/// Opaque FMU-state pointer.
pub type fmi3FMUState = *mut c_void;
/// Value reference.
pub type fmi3ValueReference = u32;
/// 64-bit float.
pub type fmi3Float64 = f64;
/// 32-bit integer.
pub type fmi3Int32 = i32;
/// Boolean (C99 `bool`).
pub type fmi3Boolean = bool;
/// C string.
pub type fmi3String = *const c_char;
/// Byte (serialisation, binaries).
pub type fmi3Byte = u8;

/// Return status of every FMI 3.0 function.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum fmi3Status {
    /// All well.
    fmi3OK = 0,
    /// Something is not right, but the computation can continue.
    fmi3Warning = 1,
    /// The result of the step is not usable.
    fmi3Discard = 2,
    /// The instance is in error; only reset/free are meaningful now.
    fmi3Error = 3,
    /// The model is corrupted.
    fmi3Fatal = 4,
}

impl From<Status> for fmi3Status {
    fn from(s: Status) -> Self {
        match s {
            Status::Ok => Self::fmi3OK,
            Status::Warning => Self::fmi3Warning,
            Status::Discard => Self::fmi3Discard,
            Status::Error => Self::fmi3Error,
            Status::Fatal => Self::fmi3Fatal,
        }
    }
}

/// The master's logger: a plain message (not a format).
pub type fmi3LogMessageCallback =
    Option<unsafe extern "C" fn(fmi3InstanceEnvironment, fmi3Status, fmi3String, fmi3String)>;

/// The intermediate-update callback (never called: `providesIntermediateUpdate="false"`).
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

/// The clock-activation callback of scheduled execution (never called).
pub type fmi3ClockUpdateCallback = Option<unsafe extern "C" fn(fmi3InstanceEnvironment)>;
/// The lock/unlock callback of scheduled execution (never called).
pub type fmi3LockPreemptionCallback = Option<unsafe extern "C" fn()>;
