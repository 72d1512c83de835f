//! Every FMI 2.0 common and co-simulation function, generic over the [`Model`] (not
//! exported: [`crate::export_fmi2`] exports them, unprefixed, for one model from a shared
//! library). The binding only: C arguments and pointer checks, the panic boundary, the
//! allowed-states mask of each call, call logging, the status conversion; the instance and
//! its checks live in [`crate::instance`], the model behind [`crate::model::Model`].
//!
//! Here: the shared guards and argument helpers, the inquiry and life-cycle functions;
//! `values.rs` the typed gets and sets, `fmu_state.rs` the FMU-state functions, `cosim.rs`
//! the co-simulation step and status functions and the unsupported derivative functions.
#![allow(non_snake_case)]

use super::description::guid_of;
use super::types::*;
use super::{Instance, Logger};
use crate::machine::{ModelState, ANY_STATE};
use crate::model::Model;
use crate::status::{error, Failure};
use crate::variables::TypeClass;
use std::ffi::{c_char, c_int, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};

mod cosim;
mod fmu_state;
mod values;

pub use cosim::*;
pub use fmu_state::*;
pub use values::*;

use ModelState::{Error as ErrorState, InitializationMode, Instantiated, StepComplete, Terminated};

const M_INSTANTIATED: u32 = Instantiated as u32;
const M_INIT: u32 = InitializationMode as u32;
const M_STEP: u32 = StepComplete as u32;
const M_GET: u32 =
    InitializationMode as u32 | StepComplete as u32 | Terminated as u32 | ErrorState as u32;
const M_SET: u32 = Instantiated as u32 | InitializationMode as u32 | StepComplete as u32;

/// Run `f` on the instance behind `c` if the call is allowed in its state; errors are
/// logged and put the instance in the error state; panics never cross into C. The call
/// is logged under `logCalls` as `func()`; [`guarded_with`] logs its arguments.
///
/// # Safety
/// `c` is null or a pointer returned by [`fmi2Instantiate`] and not yet freed.
unsafe fn guarded<M: Model, F>(c: fmi2Component, func: &str, allowed: u32, f: F) -> fmi2Status
where
    F: FnOnce(&mut Instance<M>) -> Result<(), Failure>,
{
    // SAFETY: forwarded contract.
    unsafe { guarded_with::<M, _, _>(c, func, allowed, |_| Some(String::new()), f) }
}

/// [`guarded`], with the call logged under `logCalls` as `func(args)` where `args` is
/// `describe(instance)`, evaluated only when that category is on (`None`: `f` logs the
/// call itself, e.g. a getter once the values are known).
///
/// # Safety
/// `c` is null or a pointer returned by [`fmi2Instantiate`] and not yet freed.
unsafe fn guarded_with<M: Model, D, F>(
    c: fmi2Component,
    func: &str,
    allowed: u32,
    describe: D,
    f: F,
) -> fmi2Status
where
    D: FnOnce(&Instance<M>) -> Option<String>,
    F: FnOnce(&mut Instance<M>) -> Result<(), Failure>,
{
    // SAFETY: by the caller's contract `c` is null or a live `Instance`.
    match unsafe { (c as *mut Instance<M>).as_mut() } {
        Some(inst) => inst.call(func, allowed, describe, f).into(),
        None => fmi2Status::fmi2Error,
    }
}

/// An unsupported function: `fmi2Error` plus a log line saying why.
///
/// # Safety
/// As [`guarded`].
unsafe fn unsupported<M: Model>(c: fmi2Component, func: &str, why: &str) -> fmi2Status {
    // SAFETY: forwarded contract.
    unsafe {
        guarded::<M, _>(c, func, ANY_STATE, |_| {
            Err(error(format!(
                "{func} is not supported by this FMU ({why})"
            )))
        })
    }
}

/// Borrow `n` elements of a C array (`n == 0` accepts null).
///
/// # Safety
/// `p` is null or points to `n` readable elements.
pub(crate) unsafe fn slice<'a, T>(p: *const T, n: usize, what: &str) -> Result<&'a [T], Failure> {
    if n == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err(null_argument(what));
    }
    // SAFETY: non-null, `n` elements by contract.
    Ok(unsafe { std::slice::from_raw_parts(p, n) })
}

/// Mutable variant of [`slice`].
///
/// # Safety
/// `p` is null or points to `n` writable elements.
pub(crate) unsafe fn slice_mut<'a, T>(
    p: *mut T,
    n: usize,
    what: &str,
) -> Result<&'a mut [T], Failure> {
    if n == 0 {
        return Ok(&mut []);
    }
    if p.is_null() {
        return Err(null_argument(what));
    }
    // SAFETY: non-null, `n` elements by contract.
    Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

/// The refusal of a null array argument (out of the get/set paths).
#[cold]
#[inline(never)]
fn null_argument(what: &str) -> Failure {
    error(format!("{what} is null"))
}

/// A C string argument for a call log: `"text"` or `NULL`.
///
/// # Safety
/// `p` is null or NUL-terminated.
pub(crate) unsafe fn c_arg(p: fmi2String) -> String {
    if p.is_null() {
        "NULL".to_string()
    } else {
        // SAFETY: non-null, NUL-terminated by contract.
        format!("\"{}\"", unsafe { CStr::from_ptr(p) }.to_string_lossy())
    }
}

fn bool_arg(b: fmi2Boolean) -> &'static str {
    if b != fmi2False {
        "true"
    } else {
        "false"
    }
}

/// `nvr = 2: x (vr 33) = 1.5, y (vr 34) = 2` for a call log (`vr = NULL` when a
/// pointer is missing).
///
/// # Safety
/// `vr` and `value` are null or hold `nvr` elements.
unsafe fn values_arg<M: Model, T: Copy>(
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const T,
    show: fn(T) -> String,
) -> String {
    // SAFETY: forwarded contract; null is checked in `slice`.
    let (Ok(refs), Ok(vals)) = (unsafe { slice(vr, nvr, "vr") }, unsafe {
        slice(value, nvr, "value")
    }) else {
        return format!("nvr = {nvr}, vr or value = NULL");
    };
    let parts: Vec<String> = refs
        .iter()
        .zip(vals)
        .map(|(r, v)| format!("{} = {}", Instance::<M>::var_label(*r), show(*v)))
        .collect();
    format!("nvr = {nvr}: {}", parts.join(", "))
}

/// A Real for a call log: shortest round-trip decimal, in exponent form when very large
/// or small (`1e-9`, not `0.000000001`).
pub(crate) fn real_arg(v: fmi2Real) -> String {
    let a = v.abs();
    if v == 0.0 || !v.is_finite() || (1e-4..1e15).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}
fn integer_arg(v: fmi2Integer) -> String {
    format!("{v}")
}
fn boolean_arg(v: fmi2Boolean) -> String {
    bool_arg(v).to_string()
}

// ---------------------------------------------------------------- inquiry

/// `"default"`.
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    c"default".as_ptr()
}

/// `"2.0"`.
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    c"2.0".as_ptr()
}

// ---------------------------------------------------------------- life cycle

/// Create an instance (co-simulation only). Returns null, with a logged reason when a
/// logger is available, for a null/empty name, a model-exchange request or a wrong GUID.
///
/// # Safety
/// String arguments are null or NUL-terminated; `functions` is null or valid for the call.
pub unsafe fn fmi2Instantiate<M: Model>(
    instanceName: fmi2String,
    fmuType: c_int,
    fmuGUID: fmi2String,
    fmuResourceLocation: fmi2String,
    functions: *const fmi2CallbackFunctions,
    visible: fmi2Boolean,
    loggingOn: fmi2Boolean,
) -> fmi2Component {
    let made = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: null or valid for the duration of this call (FMI 2.0 sec. 2.1.5); copied.
        let f = unsafe { functions.as_ref() }?;
        let logger = Logger::new(f.logger, f.componentEnvironment);
        let name = if instanceName.is_null() {
            None
        } else {
            // SAFETY: non-null, NUL-terminated by contract.
            Some(unsafe { CStr::from_ptr(instanceName) }.to_owned())
        };
        let reject = |msg: &str| {
            logger.send(
                // every FMU here is relnav's
                name.as_deref().unwrap_or(c"relnav"),
                fmi2Status::fmi2Error,
                "logStatusError",
                msg,
            );
            None
        };
        let name = match name.clone() {
            Some(n) if !n.as_bytes().is_empty() => n,
            _ => return reject("fmi2Instantiate: instanceName is null or empty"),
        };
        if fmuType != fmi2CoSimulation {
            return reject(
                "fmi2Instantiate: only Co-Simulation (fmuType = fmi2CoSimulation) is supported",
            );
        }
        let given = if fmuGUID.is_null() {
            String::new()
        } else {
            // SAFETY: non-null, NUL-terminated by contract.
            unsafe { CStr::from_ptr(fmuGUID) }
                .to_string_lossy()
                .into_owned()
        };
        if given != guid_of(M::info()) {
            return reject(&format!(
                "fmi2Instantiate: GUID {given} does not match this binary's {}",
                guid_of(M::info())
            ));
        }
        let inst = Instance::<M>::new(name, logger, loggingOn != fmi2False, guid_of(M::info()));
        inst.log_call(|| {
            format!(
                "fmi2Instantiate(instanceName = \"{}\", fmuType = {fmuType}, fmuGUID = \"{given}\", fmuResourceLocation = {}, visible = {}, loggingOn = {})",
                inst.name.to_string_lossy(),
                // SAFETY: null or NUL-terminated by contract.
                unsafe { c_arg(fmuResourceLocation) },
                bool_arg(visible),
                bool_arg(loggingOn)
            )
        });
        Some(Box::into_raw(Box::new(inst)))
    }));
    match made {
        Ok(Some(p)) => p.cast(),
        _ => std::ptr::null_mut(),
    }
}

/// Release an instance (null accepted).
///
/// # Safety
/// `c` is null or from [`fmi2Instantiate`], freed once.
pub unsafe fn fmi2FreeInstance<M: Model>(c: fmi2Component) {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        if !c.is_null() {
            // SAFETY: from Box::into_raw in fmi2Instantiate; freed exactly once.
            let inst = unsafe { Box::from_raw(c as *mut Instance<M>) };
            inst.log_call(|| "fmi2FreeInstance()".to_string());
            drop(inst);
        }
    }));
}

/// Enable/disable logging, for all categories (`nCategories == 0`) or the named ones.
///
/// # Safety
/// `c` live or null; `categories` holds `nCategories` C strings.
pub unsafe fn fmi2SetDebugLogging<M: Model>(
    c: fmi2Component,
    loggingOn: fmi2Boolean,
    nCategories: usize,
    categories: *const fmi2String,
) -> fmi2Status {
    // SAFETY: contracts forwarded; pointers checked in `slice`.
    unsafe {
        let describe = |_: &Instance<M>| {
            let names = match slice(categories, nCategories, "categories") {
                Ok(cats) => cats
                    .iter()
                    .map(|p| c_arg(*p))
                    .collect::<Vec<_>>()
                    .join(", "),
                Err(_) => "NULL".to_string(),
            };
            Some(format!(
                "loggingOn = {}, nCategories = {nCategories}, categories = [{names}]",
                bool_arg(loggingOn)
            ))
        };
        guarded_with::<M, _, _>(c, "fmi2SetDebugLogging", ANY_STATE, describe, |inst| {
            let cats = slice(categories, nCategories, "categories")?;
            let mut names = Vec::with_capacity(cats.len());
            for p in cats {
                if p.is_null() {
                    return Err(error("fmi2SetDebugLogging: a category name is null".into()));
                }
                names.push(CStr::from_ptr(*p).to_string_lossy().into_owned());
            }
            let refs: Vec<&str> = names.iter().map(String::as_str).collect();
            inst.set_debug_logging("fmi2SetDebugLogging", loggingOn != fmi2False, &refs)
        })
    }
}

/// Start (and optional stop) time. The tolerance is ignored (no integrator inside).
///
/// # Safety
/// `c` live or null.
pub unsafe fn fmi2SetupExperiment<M: Model>(
    c: fmi2Component,
    toleranceDefined: fmi2Boolean,
    tolerance: fmi2Real,
    startTime: fmi2Real,
    stopTimeDefined: fmi2Boolean,
    stopTime: fmi2Real,
) -> fmi2Status {
    // SAFETY: contract forwarded.
    unsafe {
        let describe = |_: &Instance<M>| {
            Some(format!(
                "toleranceDefined = {}, tolerance = {tolerance}, startTime = {startTime}, stopTimeDefined = {}, stopTime = {stopTime}",
                bool_arg(toleranceDefined),
                bool_arg(stopTimeDefined)
            ))
        };
        guarded_with::<M, _, _>(c, "fmi2SetupExperiment", M_INSTANTIATED, describe, |inst| {
            inst.setup_experiment(
                "fmi2SetupExperiment",
                startTime,
                (stopTimeDefined != fmi2False).then_some(stopTime),
            )
        })
    }
}

/// Enter initialisation mode.
///
/// # Safety
/// `c` live or null.
pub unsafe fn fmi2EnterInitializationMode<M: Model>(c: fmi2Component) -> fmi2Status {
    // SAFETY: contract forwarded.
    unsafe {
        guarded::<M, _>(c, "fmi2EnterInitializationMode", M_INSTANTIATED, |inst| {
            inst.enter_initialization();
            Ok(())
        })
    }
}

/// Exit initialisation mode: the model checks its parameters together and is built.
///
/// # Safety
/// `c` live or null.
pub unsafe fn fmi2ExitInitializationMode<M: Model>(c: fmi2Component) -> fmi2Status {
    // SAFETY: contract forwarded.
    unsafe {
        guarded::<M, _>(
            c,
            "fmi2ExitInitializationMode",
            M_INIT,
            Instance::<M>::exit_initialization,
        )
    }
}

/// Terminate the simulation.
///
/// # Safety
/// `c` live or null.
pub unsafe fn fmi2Terminate<M: Model>(c: fmi2Component) -> fmi2Status {
    // SAFETY: contract forwarded.
    unsafe {
        guarded::<M, _>(c, "fmi2Terminate", M_STEP, |inst| {
            inst.terminate();
            Ok(())
        })
    }
}

/// Back to the just-instantiated state (start values, nothing built). Allowed in every
/// state, including after an error (FMI 2.0.5).
///
/// # Safety
/// `c` live or null.
pub unsafe fn fmi2Reset<M: Model>(c: fmi2Component) -> fmi2Status {
    // SAFETY: contract forwarded.
    unsafe {
        guarded::<M, _>(c, "fmi2Reset", ANY_STATE, |inst| {
            inst.reset();
            Ok(())
        })
    }
}
