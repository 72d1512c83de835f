//! Every FMI 2.0 common and co-simulation function, generic over the [`Model`] (not
//! exported: [`crate::export_fmi2`] exports them, unprefixed, for one model from a shared
//! library). The binding only: C arguments and pointer checks, the panic boundary, the
//! allowed-states mask of each call, call logging, the status conversion; the instance and
//! its checks live in [`crate::instance`], the model behind [`crate::model::Model`].
#![allow(non_snake_case)]

use super::description::guid_of;
use super::types::*;
use super::{Instance, Logger};
use crate::machine::{ModelState, ANY_STATE};
use crate::model::Model;
use crate::status::{error, Failure, Status};
use crate::variables::TypeClass;
use std::ffi::{c_char, c_int, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};

use ModelState::{Error as ErrorState, InitializationMode, Instantiated, StepComplete, Terminated};

const M_INSTANTIATED: u32 = Instantiated as u32;
const M_INIT: u32 = InitializationMode as u32;
const M_STEP: u32 = StepComplete as u32;
const M_GET: u32 =
    InitializationMode as u32 | StepComplete as u32 | Terminated as u32 | ErrorState as u32;
const M_SET: u32 = Instantiated as u32 | InitializationMode as u32 | StepComplete as u32;

fn panic_text(p: &(dyn std::any::Any + Send)) -> String {
    p.downcast_ref::<&str>()
        .map(|s| (*s).to_string())
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".to_string())
}

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
    let Some(inst) = (unsafe { (c as *mut Instance<M>).as_mut() }) else {
        return fmi2Status::fmi2Error;
    };
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        if inst.logs_calls() {
            if let Some(args) = describe(inst) {
                inst.log(Status::Ok, "logCalls", &format!("{func}({args})"));
            }
        }
        inst.require(func, allowed)?;
        f(inst)
    }));
    match outcome {
        Ok(Ok(())) => fmi2Status::fmi2OK,
        Ok(Err(e)) => {
            let category = if e.status >= Status::Error {
                "logStatusError"
            } else {
                "logStatusWarning"
            };
            inst.log(e.status, category, &e.message);
            inst.note_status(e.status);
            if e.status >= Status::Error {
                inst.state = ErrorState;
            }
            e.status.into()
        }
        Err(p) => {
            let msg = format!("{func}: internal panic: {}", panic_text(p.as_ref()));
            let _ = catch_unwind(AssertUnwindSafe(|| {
                inst.log(Status::Fatal, "logStatusError", &msg)
            }));
            inst.note_status(Status::Fatal);
            inst.state = ErrorState;
            fmi2Status::fmi2Fatal
        }
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
unsafe fn slice<'a, T>(p: *const T, n: usize, what: &str) -> Result<&'a [T], Failure> {
    if n == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err(error(format!("{what} is null")));
    }
    // SAFETY: non-null, `n` elements by contract.
    Ok(unsafe { std::slice::from_raw_parts(p, n) })
}

/// Mutable variant of [`slice`].
///
/// # Safety
/// `p` is null or points to `n` writable elements.
unsafe fn slice_mut<'a, T>(p: *mut T, n: usize, what: &str) -> Result<&'a mut [T], Failure> {
    if n == 0 {
        return Ok(&mut []);
    }
    if p.is_null() {
        return Err(error(format!("{what} is null")));
    }
    // SAFETY: non-null, `n` elements by contract.
    Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

/// A C string argument for a call log: `"text"` or `NULL`.
///
/// # Safety
/// `p` is null or NUL-terminated.
unsafe fn c_arg(p: fmi2String) -> String {
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
fn real_arg(v: fmi2Real) -> String {
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

// ---------------------------------------------------------------- get / set

/// How one FMI base type maps onto the stored `f64` values.
struct Access<T> {
    /// Function name (`fmi2GetReal` or `fmi2SetReal`, ...).
    func: &'static str,
    /// Which variable types it reads or writes.
    class: TypeClass,
    /// Stored value -> FMI value.
    get: fn(f64) -> T,
    /// FMI value -> stored value.
    set: fn(T) -> f64,
    /// FMI value for the call log.
    show: fn(T) -> String,
}

fn real_to_f64(v: fmi2Real) -> f64 {
    v
}
fn integer_from_f64(v: f64) -> fmi2Integer {
    v as fmi2Integer
}
fn boolean_from_f64(v: f64) -> fmi2Boolean {
    if v != 0.0 {
        fmi2True
    } else {
        fmi2False
    }
}
fn boolean_to_f64(v: fmi2Boolean) -> f64 {
    if v != fmi2False {
        1.0
    } else {
        0.0
    }
}

const fn real(func: &'static str) -> Access<fmi2Real> {
    Access {
        func,
        class: TypeClass::Real,
        get: real_to_f64,
        set: real_to_f64,
        show: real_arg,
    }
}
const fn integer(func: &'static str) -> Access<fmi2Integer> {
    Access {
        func,
        class: TypeClass::Integer,
        get: integer_from_f64,
        set: f64::from,
        show: integer_arg,
    }
}
const fn boolean(func: &'static str) -> Access<fmi2Boolean> {
    Access {
        func,
        class: TypeClass::Boolean,
        get: boolean_from_f64,
        set: boolean_to_f64,
        show: boolean_arg,
    }
}

/// # Safety
/// `c` live or null; `vr` and `value` hold `nvr` elements.
unsafe fn get_values<M: Model, T: Copy>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut T,
    a: Access<T>,
) -> fmi2Status {
    let Access {
        func,
        class,
        get: conv,
        show,
        ..
    } = a;
    // SAFETY: contract forwarded; pointers checked.
    unsafe {
        guarded_with::<M, _, _>(
            c,
            func,
            M_GET,
            |_| None,
            |inst| {
                let refs = slice(vr, nvr, "vr")?;
                let out = slice_mut(value, nvr, "value")?;
                for (r, o) in refs.iter().zip(out.iter_mut()) {
                    *o = conv(inst.get(*r, func, class)?);
                }
                // logged once the values are known
                inst.log_call(|| {
                    format!(
                        "{func}({})",
                        values_arg::<M, T>(vr, nvr, value.cast_const(), show)
                    )
                });
                Ok(())
            },
        )
    }
}

/// # Safety
/// `c` live or null; `vr` and `value` hold `nvr` elements.
unsafe fn set_values<M: Model, T: Copy>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const T,
    a: Access<T>,
) -> fmi2Status {
    let Access {
        func,
        class,
        set: conv,
        show,
        ..
    } = a;
    // SAFETY: contract forwarded; pointers checked.
    unsafe {
        let describe = |_: &Instance<M>| Some(values_arg::<M, T>(vr, nvr, value, show));
        guarded_with::<M, _, _>(c, func, M_SET, describe, |inst| {
            let refs = slice(vr, nvr, "vr")?;
            let vals = slice(value, nvr, "value")?;
            for (r, v) in refs.iter().zip(vals.iter()) {
                inst.set(*r, conv(*v), func, class)?;
            }
            Ok(())
        })
    }
}

/// Read Real variables.
///
/// # Safety
/// `c` live or null; `vr` and `value` hold `nvr` elements.
pub unsafe fn fmi2GetReal<M: Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Real,
) -> fmi2Status {
    // SAFETY: contract forwarded.
    unsafe { get_values::<M, _>(c, vr, nvr, value, real("fmi2GetReal")) }
}

/// Read Integer variables (codes included).
///
/// # Safety
/// `c` live or null; `vr` and `value` hold `nvr` elements.
pub unsafe fn fmi2GetInteger<M: Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Integer,
) -> fmi2Status {
    // SAFETY: contract forwarded.
    unsafe { get_values::<M, _>(c, vr, nvr, value, integer("fmi2GetInteger")) }
}

/// Read Boolean variables.
///
/// # Safety
/// `c` live or null; `vr` and `value` hold `nvr` elements.
pub unsafe fn fmi2GetBoolean<M: Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    // SAFETY: contract forwarded.
    unsafe { get_values::<M, _>(c, vr, nvr, value, boolean("fmi2GetBoolean")) }
}

/// fmi2GetString / fmi2SetString: there are no String variables, so an empty request
/// succeeds and any value reference is unknown (logged with the references asked for).
///
/// # Safety
/// `c` live or null; `vr` holds `nvr` elements.
unsafe fn no_string_variable<M: Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    fname: &'static str,
    mask: u32,
) -> fmi2Status {
    // SAFETY: contract forwarded.
    unsafe {
        let describe = |_: &Instance<M>| {
            Some(match slice(vr, nvr, "vr") {
                Ok(refs) => {
                    let labels: Vec<String> =
                        refs.iter().map(|r| Instance::<M>::var_label(*r)).collect();
                    format!("nvr = {nvr}: {}", labels.join(", "))
                }
                Err(_) => format!("nvr = {nvr}, vr = NULL"),
            })
        };
        guarded_with::<M, _, _>(c, fname, mask, describe, |_| {
            let refs = slice(vr, nvr, "vr")?;
            match refs.first() {
                None => Ok(()),
                Some(r) => Err(error(format!(
                    "{fname}: no String variable has value reference {r}"
                ))),
            }
        })
    }
}

/// There are no String variables: any value reference is unknown.
///
/// # Safety
/// `c` live or null; `vr` and `value` hold `nvr` elements.
pub unsafe fn fmi2GetString<M: Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    _value: *mut fmi2String,
) -> fmi2Status {
    // SAFETY: contract forwarded.
    unsafe { no_string_variable::<M>(c, vr, nvr, "fmi2GetString", M_GET) }
}

/// Write Real parameters (before initialisation ends) and inputs.
///
/// # Safety
/// `c` live or null; `vr` and `value` hold `nvr` elements.
pub unsafe fn fmi2SetReal<M: Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Real,
) -> fmi2Status {
    // SAFETY: contract forwarded.
    unsafe { set_values::<M, _>(c, vr, nvr, value, real("fmi2SetReal")) }
}

/// Write Integer parameters (codes included).
///
/// # Safety
/// `c` live or null; `vr` and `value` hold `nvr` elements.
pub unsafe fn fmi2SetInteger<M: Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Integer,
) -> fmi2Status {
    // SAFETY: contract forwarded.
    unsafe { set_values::<M, _>(c, vr, nvr, value, integer("fmi2SetInteger")) }
}

/// Write Boolean inputs.
///
/// # Safety
/// `c` live or null; `vr` and `value` hold `nvr` elements.
pub unsafe fn fmi2SetBoolean<M: Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Boolean,
) -> fmi2Status {
    // SAFETY: contract forwarded.
    unsafe { set_values::<M, _>(c, vr, nvr, value, boolean("fmi2SetBoolean")) }
}

/// There are no String variables: any value reference is unknown.
///
/// # Safety
/// `c` live or null; `vr` and `value` hold `nvr` elements.
pub unsafe fn fmi2SetString<M: Model>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    _value: *const fmi2String,
) -> fmi2Status {
    // SAFETY: contract forwarded.
    unsafe { no_string_variable::<M>(c, vr, nvr, "fmi2SetString", M_SET) }
}

// ---------------------------------------------------------------- FMU state

/// The refusal of a state pointer this instance did not make (or has freed).
fn unknown_state(func: &str) -> Failure {
    error(format!(
        "{func}: unknown FMU state (not made by this instance, or already freed; move a state \
         between instances with fmi2SerializeFMUstate / fmi2DeSerializeFMUstate)"
    ))
}

/// The state behind a pointer if this instance made it ([`unknown_state`] otherwise).
fn known<'a>(
    s: Option<&'a crate::state::FmuState>,
    func: &str,
) -> Result<&'a crate::state::FmuState, Failure> {
    s.ok_or_else(|| unknown_state(func))
}

/// Copy the instance's complete state (`canGetAndSetFMUstate="true"`; the bytes of
/// [`crate::state`]). `*FMUstate == NULL` allocates a new state; a state this instance
/// made is overwritten in place. Allowed in every state (a state taken in the error state
/// restores the error state).
///
/// # Safety
/// `c` live or null; `FMUstate` null or writable.
pub unsafe fn fmi2GetFMUstate<M: Model>(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    // SAFETY: contract forwarded; `FMUstate` checked for null.
    unsafe {
        guarded::<M, _>(c, "fmi2GetFMUstate", ANY_STATE, |inst| {
            let out = slice_mut(FMUstate, 1, "FMUstate")?;
            let bytes = inst.save_state()?;
            out[0] = inst.states.put(out[0], bytes);
            Ok(())
        })
    }
}

/// Restore a state made by this instance (see [`crate::state`] for what is restored and
/// what is refused). A refused state leaves the instance's data unchanged.
///
/// # Safety
/// `c` live or null.
pub unsafe fn fmi2SetFMUstate<M: Model>(c: fmi2Component, FMUstate: fmi2FMUstate) -> fmi2Status {
    const F: &str = "fmi2SetFMUstate";
    // SAFETY: contract forwarded; the state pointer is only compared, never dereferenced.
    unsafe {
        guarded::<M, _>(c, F, ANY_STATE, |inst| {
            let bytes = known(inst.states.get(FMUstate), F)?.bytes().to_vec();
            inst.restore_state(&bytes, F)
        })
    }
}

/// Free a state (`*FMUstate == NULL` is ignored); `*FMUstate` is set to NULL.
///
/// # Safety
/// `c` live or null; `FMUstate` null or writable.
pub unsafe fn fmi2FreeFMUstate<M: Model>(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    const F: &str = "fmi2FreeFMUstate";
    // SAFETY: contract forwarded; `FMUstate` checked for null.
    unsafe {
        guarded::<M, _>(c, F, ANY_STATE, |inst| {
            let s = slice_mut(FMUstate, 1, "FMUstate")?;
            if !s[0].is_null() {
                if !inst.states.free(s[0]) {
                    return Err(unknown_state(F));
                }
                s[0] = std::ptr::null_mut();
            }
            Ok(())
        })
    }
}

/// Size in bytes of a state's serialised form (`canSerializeFMUstate="true"`).
///
/// # Safety
/// `c` live or null; `size` null or writable.
pub unsafe fn fmi2SerializedFMUstateSize<M: Model>(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    size: *mut usize,
) -> fmi2Status {
    const F: &str = "fmi2SerializedFMUstateSize";
    // SAFETY: contract forwarded; `size` checked for null.
    unsafe {
        guarded::<M, _>(c, F, ANY_STATE, |inst| {
            let out = slice_mut(size, 1, "size")?;
            out[0] = known(inst.states.get(FMUstate), F)?.bytes().len();
            Ok(())
        })
    }
}

/// Copy a state's serialised form into `serializedState` (`size` bytes, at least
/// [`fmi2SerializedFMUstateSize`]; the state fills the first that many).
///
/// # Safety
/// `c` live or null; `serializedState` null or `size` writable bytes.
pub unsafe fn fmi2SerializeFMUstate<M: Model>(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    serializedState: *mut fmi2Byte,
    size: usize,
) -> fmi2Status {
    const F: &str = "fmi2SerializeFMUstate";
    // SAFETY: contract forwarded; pointers checked.
    unsafe {
        guarded::<M, _>(c, F, ANY_STATE, |inst| {
            let b = known(inst.states.get(FMUstate), F)?.bytes();
            if size < b.len() {
                return Err(error(format!(
                    "{F}: the state needs {} bytes (fmi2SerializedFMUstateSize), the buffer holds {size}",
                    b.len()
                )));
            }
            let out = slice_mut(serializedState.cast::<u8>(), b.len(), "serializedState")?;
            out.copy_from_slice(b);
            Ok(())
        })
    }
}

/// Make a state from serialised bytes (of this FMU, possibly of another instance or
/// process). The bytes are checked here — length, CRC-32, magic, format version, GUID,
/// structure — and refused with a logged reason; whether the state fits this instance's
/// parameters is checked by [`fmi2SetFMUstate`]. `*FMUstate == NULL` allocates a new
/// state; a state this instance made is overwritten.
///
/// # Safety
/// `c` live or null; `serializedState` null or `size` readable bytes; `FMUstate` null or
/// writable.
pub unsafe fn fmi2DeSerializeFMUstate<M: Model>(
    c: fmi2Component,
    serializedState: *const fmi2Byte,
    size: usize,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    const F: &str = "fmi2DeSerializeFMUstate";
    // SAFETY: contract forwarded; pointers checked.
    unsafe {
        guarded::<M, _>(c, F, ANY_STATE, |inst| {
            let out = slice_mut(FMUstate, 1, "FMUstate")?;
            if serializedState.is_null() {
                return Err(error(format!("{F}: serializedState is null")));
            }
            let bytes = slice(serializedState.cast::<u8>(), size, "serializedState")?;
            inst.check_state(bytes, F)?;
            out[0] = inst.states.put(out[0], bytes.to_vec());
            Ok(())
        })
    }
}

// ---------------------------------------------------------------- unsupported: derivatives

/// Unsupported (`providesDirectionalDerivative="false"`).
///
/// # Safety
/// `c` live or null.
pub unsafe fn fmi2GetDirectionalDerivative<M: Model>(
    c: fmi2Component,
    _vu: *const fmi2ValueReference,
    _nu: usize,
    _vk: *const fmi2ValueReference,
    _nk: usize,
    _dvk: *const fmi2Real,
    _dvu: *mut fmi2Real,
) -> fmi2Status {
    // SAFETY: contract forwarded.
    unsafe {
        unsupported::<M>(
            c,
            "fmi2GetDirectionalDerivative",
            "providesDirectionalDerivative=\"false\"",
        )
    }
}

/// Unsupported (`canInterpolateInputs="false"`).
///
/// # Safety
/// `c` live or null.
pub unsafe fn fmi2SetRealInputDerivatives<M: Model>(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _nvr: usize,
    _order: *const fmi2Integer,
    _value: *const fmi2Real,
) -> fmi2Status {
    // SAFETY: contract forwarded.
    unsafe {
        unsupported::<M>(
            c,
            "fmi2SetRealInputDerivatives",
            "canInterpolateInputs=\"false\"",
        )
    }
}

/// Unsupported (`maxOutputDerivativeOrder="0"`).
///
/// # Safety
/// `c` live or null.
pub unsafe fn fmi2GetRealOutputDerivatives<M: Model>(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _nvr: usize,
    _order: *const fmi2Integer,
    _value: *mut fmi2Real,
) -> fmi2Status {
    // SAFETY: contract forwarded.
    unsafe {
        unsupported::<M>(
            c,
            "fmi2GetRealOutputDerivatives",
            "maxOutputDerivativeOrder=\"0\"",
        )
    }
}

// ---------------------------------------------------------------- co-simulation

/// One communication step from `currentCommunicationPoint` over
/// `communicationStepSize`: the inputs hold at the step's start, the outputs afterwards
/// describe its end.
///
/// # Safety
/// `c` live or null.
pub unsafe fn fmi2DoStep<M: Model>(
    c: fmi2Component,
    currentCommunicationPoint: fmi2Real,
    communicationStepSize: fmi2Real,
    noSetFMUStatePriorToCurrentPoint: fmi2Boolean,
) -> fmi2Status {
    // SAFETY: contract forwarded.
    unsafe {
        let describe = |_: &Instance<M>| {
            Some(format!(
                "currentCommunicationPoint = {currentCommunicationPoint}, communicationStepSize = {communicationStepSize}, noSetFMUStatePriorToCurrentPoint = {}",
                bool_arg(noSetFMUStatePriorToCurrentPoint)
            ))
        };
        guarded_with::<M, _, _>(c, "fmi2DoStep", M_STEP, describe, |inst| {
            inst.do_step(
                "fmi2DoStep",
                currentCommunicationPoint,
                communicationStepSize,
            )
        })
    }
}

/// Unsupported: steps are synchronous (`canRunAsynchronuously="false"`).
///
/// # Safety
/// `c` live or null.
pub unsafe fn fmi2CancelStep<M: Model>(c: fmi2Component) -> fmi2Status {
    // SAFETY: contract forwarded.
    unsafe { unsupported::<M>(c, "fmi2CancelStep", "steps are synchronous") }
}

/// Unsupported: steps are synchronous, there is no pending status.
///
/// # Safety
/// `c` live or null.
pub unsafe fn fmi2GetStatus<M: Model>(
    c: fmi2Component,
    _s: c_int,
    _value: *mut c_int,
) -> fmi2Status {
    // SAFETY: contract forwarded.
    unsafe { unsupported::<M>(c, "fmi2GetStatus", "steps are synchronous") }
}

/// `fmi2LastSuccessfulTime`: the time of the last completed step.
///
/// # Safety
/// `c` live or null; `value` writable or null.
pub unsafe fn fmi2GetRealStatus<M: Model>(
    c: fmi2Component,
    s: c_int,
    value: *mut fmi2Real,
) -> fmi2Status {
    // SAFETY: contract forwarded; pointer checked.
    unsafe {
        guarded_with::<M, _, _>(
            c,
            "fmi2GetRealStatus",
            M_GET,
            |_| Some(format!("s = {s}")),
            |inst| {
                if s != status_kind::LAST_SUCCESSFUL_TIME {
                    return Err(error(format!(
                        "fmi2GetRealStatus: status kind {s} is not supported"
                    )));
                }
                let out = slice_mut(value, 1, "value")?;
                out[0] = inst.time();
                Ok(())
            },
        )
    }
}

/// Unsupported: no Integer status exists in FMI 2.0 co-simulation.
///
/// # Safety
/// `c` live or null.
pub unsafe fn fmi2GetIntegerStatus<M: Model>(
    c: fmi2Component,
    _s: c_int,
    _value: *mut fmi2Integer,
) -> fmi2Status {
    // SAFETY: contract forwarded.
    unsafe {
        unsupported::<M>(
            c,
            "fmi2GetIntegerStatus",
            "no Integer status kinds are defined",
        )
    }
}

/// `fmi2Terminated`: always false (the FMU never asks to end the simulation).
///
/// # Safety
/// `c` live or null; `value` writable or null.
pub unsafe fn fmi2GetBooleanStatus<M: Model>(
    c: fmi2Component,
    s: c_int,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    // SAFETY: contract forwarded; pointer checked.
    unsafe {
        guarded_with::<M, _, _>(
            c,
            "fmi2GetBooleanStatus",
            M_GET,
            |_| Some(format!("s = {s}")),
            |_| {
                if s != status_kind::TERMINATED {
                    return Err(error(format!(
                        "fmi2GetBooleanStatus: status kind {s} is not supported"
                    )));
                }
                let out = slice_mut(value, 1, "value")?;
                out[0] = fmi2False;
                Ok(())
            },
        )
    }
}

/// Unsupported: steps are synchronous, there is no pending status text.
///
/// # Safety
/// `c` live or null.
pub unsafe fn fmi2GetStringStatus<M: Model>(
    c: fmi2Component,
    _s: c_int,
    _value: *mut fmi2String,
) -> fmi2Status {
    // SAFETY: contract forwarded.
    unsafe { unsupported::<M>(c, "fmi2GetStringStatus", "steps are synchronous") }
}
