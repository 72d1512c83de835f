//! FMI 2.0 platform types (FMI 2.0.5, `fmi2TypesPlatform.h` and `fmi2FunctionTypes.h`),
//! written from the standard's text.
#![allow(non_camel_case_types, non_upper_case_globals, non_snake_case)]

use crate::status::Status;
use std::ffi::{c_char, c_int, c_uint, c_void};

/// Opaque instance pointer handed to the master.
pub type fmi2Component = *mut c_void;
/// The master's environment pointer, passed back to its callbacks.
pub type fmi2ComponentEnvironment = *mut c_void;
/// Opaque FMU-state pointer.
pub type fmi2FMUstate = *mut c_void;
/// Value reference.
pub type fmi2ValueReference = c_uint;
/// Real.
pub type fmi2Real = f64;
/// Integer.
pub type fmi2Integer = c_int;
/// Boolean (a C int; 0 false, otherwise true).
pub type fmi2Boolean = c_int;
/// C string.
pub type fmi2String = *const c_char;
/// Byte (serialisation).
pub type fmi2Byte = c_char;

/// `fmi2True`.
pub const fmi2True: fmi2Boolean = 1;
/// `fmi2False`.
pub const fmi2False: fmi2Boolean = 0;
/// `fmi2Type` value of a co-simulation instantiation.
pub const fmi2CoSimulation: c_int = 1;

/// Return status of every FMI function.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum fmi2Status {
    /// All well.
    fmi2OK = 0,
    /// Something is not right, but the computation can continue.
    fmi2Warning = 1,
    /// The result of the step is not usable.
    fmi2Discard = 2,
    /// The instance is in error; only reset/free are meaningful now.
    fmi2Error = 3,
    /// The model is corrupted.
    fmi2Fatal = 4,
    /// Asynchronous step still running (never returned here).
    fmi2Pending = 5,
}

impl From<Status> for fmi2Status {
    fn from(s: Status) -> Self {
        match s {
            Status::Ok => Self::fmi2OK,
            Status::Warning => Self::fmi2Warning,
            Status::Discard => Self::fmi2Discard,
            Status::Error => Self::fmi2Error,
            Status::Fatal => Self::fmi2Fatal,
        }
    }
}

/// `fmi2StatusKind` values.
pub mod status_kind {
    /// `fmi2DoStepStatus`.
    pub const DO_STEP_STATUS: i32 = 0;
    /// `fmi2PendingStatus`.
    pub const PENDING_STATUS: i32 = 1;
    /// `fmi2LastSuccessfulTime`.
    pub const LAST_SUCCESSFUL_TIME: i32 = 2;
    /// `fmi2Terminated`.
    pub const TERMINATED: i32 = 3;
}

/// The master's logger: `printf`-style and variadic.
pub type fmi2CallbackLogger = Option<
    unsafe extern "C" fn(fmi2ComponentEnvironment, fmi2String, c_int, fmi2String, fmi2String, ...),
>;
/// Memory allocation callback (not used: `canNotUseMemoryManagementFunctions="true"`).
pub type fmi2CallbackAllocateMemory = Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>;
/// Memory release callback (not used).
pub type fmi2CallbackFreeMemory = Option<unsafe extern "C" fn(*mut c_void)>;
/// Asynchronous step callback (not used).
pub type fmi2StepFinished = Option<unsafe extern "C" fn(fmi2ComponentEnvironment, c_int)>;

/// The callbacks given to `fmi2Instantiate` (valid only during that call: copied).
#[repr(C)]
pub struct fmi2CallbackFunctions {
    /// Logger.
    pub logger: fmi2CallbackLogger,
    /// Allocator.
    pub allocateMemory: fmi2CallbackAllocateMemory,
    /// Deallocator.
    pub freeMemory: fmi2CallbackFreeMemory,
    /// Asynchronous step callback.
    pub stepFinished: fmi2StepFinished,
    /// Environment passed back to the logger.
    pub componentEnvironment: fmi2ComponentEnvironment,
}
