//! Every FMI 3.0 function relnav's Co-Simulation FMUs implement, generic over the
//! [`Model`] (not exported: [`crate::export_fmi3`] exports them, unprefixed, for one model
//! from a shared library), and the refusal every other function of the standard returns.
//! The binding only: C arguments and pointer checks, the panic boundary, the allowed
//! states of each call, call logging, value references resolved through
//! [`super::description`] (arrays expand to their elements); the instance and its checks
//! live in [`crate::instance`], as for FMI 2.0.
//!
//! States: FMI 3.0's Instantiated, Initialization Mode, Step Mode, Terminated and the error
//! state are the generic ones ([`ModelState`]; Step Mode is `StepComplete`, Event Mode
//! `EventMode`). Event Mode is for models with it ([`crate::model::ModelInfo::has_event_mode`]
//! and an instance made with `eventModeUsed`): `fmi3UpdateDiscreteStates` applies the inputs
//! set there at the current time ([`crate::model::Model::event_update`]).
#![allow(non_snake_case, clippy::too_many_arguments)]

use super::description::{published, token_of, Published, ARRAY_VR_BASE};
use super::types::*;
use super::{Instance, Logger};
use crate::fmi2::functions::{c_arg, real_arg, slice, slice_mut, Access};
use crate::machine::{ModelState, ANY_STATE};
use crate::model::Model;
use crate::status::{error, Failure};
use crate::variables::TypeClass;
use std::ffi::{c_char, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};

use ModelState::{
    Error as ErrorState, EventMode, InitializationMode, Instantiated, StepComplete, Terminated,
};

const M_INSTANTIATED: u32 = Instantiated as u32;
const M_INIT: u32 = InitializationMode as u32;
const M_STEP: u32 = StepComplete as u32;
const M_EVENT: u32 = EventMode as u32;
const M_GET: u32 = InitializationMode as u32
    | StepComplete as u32
    | EventMode as u32
    | Terminated as u32
    | ErrorState as u32;
const M_SET: u32 =
    Instantiated as u32 | InitializationMode as u32 | StepComplete as u32 | EventMode as u32;

/// Run `f` on the instance behind `c` through its call boundary
/// ([`crate::instance::FmuInstance::call`]; `fmi3Error` for a null instance).
///
/// # Safety
/// `c` is null or a pointer returned by [`fmi3InstantiateCoSimulation`] and not yet freed.
unsafe fn guarded_with<M: Model, D, F>(
    c: fmi3Instance,
    func: &str,
    allowed: u32,
    describe: D,
    f: F,
) -> fmi3Status
where
    D: FnOnce(&Instance<M>) -> Option<String>,
    F: FnOnce(&mut Instance<M>) -> Result<(), Failure>,
{
    // SAFETY: by the caller's contract `c` is null or a live `Instance`.
    match unsafe { (c as *mut Instance<M>).as_mut() } {
        Some(inst) => inst.call(func, allowed, describe, f).into(),
        None => fmi3Status::fmi3Error,
    }
}

/// [`guarded_with`] with the call logged as `func()`.
///
/// # Safety
/// As [`guarded_with`].
unsafe fn guarded<M: Model, F>(c: fmi3Instance, func: &str, allowed: u32, f: F) -> fmi3Status
where
    F: FnOnce(&mut Instance<M>) -> Result<(), Failure>,
{
    // SAFETY: forwarded contract.
    unsafe { guarded_with::<M, _, _>(c, func, allowed, |_| Some(String::new()), f) }
}

/// A function this FMU does not offer: `fmi3Error` and a log line saying why (an error in
/// every state: the call sequence it belongs to cannot happen here).
///
/// # Safety
/// `c` live or null.
pub unsafe fn unsupported<M: Model>(c: fmi3Instance, func: &str, why: &str) -> fmi3Status {
    // SAFETY: forwarded contract.
    unsafe {
        guarded::<M, _>(c, func, ANY_STATE, |_| {
            Err(error(format!(
                "{func} is not supported by this FMU ({why})"
            )))
        })
    }
}

// ---------------------------------------------------------------- inquiry and life cycle

/// `"3.0"`.
pub extern "C" fn fmi3GetVersion() -> *const c_char {
    c"3.0".as_ptr()
}

/// Create a Co-Simulation instance. Returns null, with the reason sent to `logMessage`, for
/// a null or empty name, a wrong instantiation token, `eventModeUsed` (this FMU has no
/// Event Mode) or required intermediate variables (it provides no intermediate update).
///
/// # Safety
/// String arguments are null or NUL-terminated; the callbacks are null or valid for the
/// instance's life.
pub unsafe fn fmi3InstantiateCoSimulation<M: Model>(
    instanceName: fmi3String,
    instantiationToken: fmi3String,
    resourcePath: fmi3String,
    visible: fmi3Boolean,
    loggingOn: fmi3Boolean,
    eventModeUsed: fmi3Boolean,
    earlyReturnAllowed: fmi3Boolean,
    _requiredIntermediateVariables: *const fmi3ValueReference,
    nRequiredIntermediateVariables: usize,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: fmi3LogMessageCallback,
    _intermediateUpdate: fmi3IntermediateUpdateCallback,
) -> fmi3Instance {
    let made = catch_unwind(AssertUnwindSafe(|| {
        let logger = Logger::new(logMessage, instanceEnvironment);
        let reject = |msg: &str| {
            logger.send(fmi3Status::fmi3Error, "logStatusError", msg);
            None
        };
        let name = if instanceName.is_null() {
            None
        } else {
            // SAFETY: non-null, NUL-terminated by contract.
            Some(unsafe { CStr::from_ptr(instanceName) }.to_owned())
        };
        let name = match name {
            Some(n) if !n.as_bytes().is_empty() => n,
            _ => return reject("fmi3InstantiateCoSimulation: instanceName is null or empty"),
        };
        let given = if instantiationToken.is_null() {
            String::new()
        } else {
            // SAFETY: non-null, NUL-terminated by contract.
            unsafe { CStr::from_ptr(instantiationToken) }
                .to_string_lossy()
                .into_owned()
        };
        let token = token_of(M::info());
        if given != token {
            return reject(&format!(
                "fmi3InstantiateCoSimulation: instantiationToken {given} does not match this binary's {token}"
            ));
        }
        if eventModeUsed && !M::info().has_event_mode {
            return reject(
                "fmi3InstantiateCoSimulation: eventModeUsed = true, but this FMU has no Event Mode (hasEventMode=\"false\")",
            );
        }
        if nRequiredIntermediateVariables > 0 {
            return reject(
                "fmi3InstantiateCoSimulation: required intermediate variables given, but this FMU provides no intermediate update",
            );
        }
        let mut inst = Instance::<M>::new(name, logger, loggingOn, token);
        inst.event_mode_used = eventModeUsed;
        inst.log_call(|| {
            format!(
                "fmi3InstantiateCoSimulation(instanceName = \"{}\", instantiationToken = \"{given}\", resourcePath = {}, visible = {visible}, loggingOn = {loggingOn}, eventModeUsed = {eventModeUsed}, earlyReturnAllowed = {earlyReturnAllowed})",
                inst.name.to_string_lossy(),
                // SAFETY: null or NUL-terminated by contract.
                unsafe { c_arg(resourcePath) },
            )
        });
        Some(Box::into_raw(Box::new(inst)))
    }));
    match made {
        Ok(Some(p)) => p.cast(),
        _ => std::ptr::null_mut(),
    }
}

/// A Co-Simulation instance of `M` named `name` as the simplest master makes it: its own
/// instantiation token, no resource path, no logger, no Event Mode, no early return (the
/// in-process benches and tests that call the functions as a master would). Null if refused.
pub fn instantiate_plain<M: Model>(name: &CStr) -> fmi3Instance {
    let Ok(token) = std::ffi::CString::new(token_of(M::info())) else {
        return std::ptr::null_mut();
    };
    // SAFETY: valid NUL-terminated strings, null pointers where the standard allows them.
    unsafe {
        fmi3InstantiateCoSimulation::<M>(
            name.as_ptr(),
            token.as_ptr(),
            std::ptr::null(),
            false,
            false,
            false,
            false,
            std::ptr::null(),
            0,
            std::ptr::null_mut(),
            None,
            None,
        )
    }
}

/// Model Exchange is not offered: null, with the reason sent to `logMessage`.
pub fn refuse_instantiation(
    func: &str,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: fmi3LogMessageCallback,
    what: &str,
) -> fmi3Instance {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        Logger::new(logMessage, instanceEnvironment).send(
            fmi3Status::fmi3Error,
            "logStatusError",
            &format!("{func}: {what} is not supported by this FMU (Co-Simulation only)"),
        )
    }));
    std::ptr::null_mut()
}

/// Release an instance (null accepted).
///
/// # Safety
/// `c` is null or from [`fmi3InstantiateCoSimulation`], freed once.
pub unsafe fn fmi3FreeInstance<M: Model>(c: fmi3Instance) {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        if !c.is_null() {
            // SAFETY: from Box::into_raw at instantiation; freed exactly once.
            let inst = unsafe { Box::from_raw(c as *mut Instance<M>) };
            inst.log_call(|| "fmi3FreeInstance()".to_string());
            drop(inst);
        }
    }));
}

/// Enable or disable logging, for all categories (`nCategories == 0`) or the named ones.
///
/// # Safety
/// `c` live or null; `categories` holds `nCategories` C strings.
pub unsafe fn fmi3SetDebugLogging<M: Model>(
    c: fmi3Instance,
    loggingOn: fmi3Boolean,
    nCategories: usize,
    categories: *const fmi3String,
) -> fmi3Status {
    const F: &str = "fmi3SetDebugLogging";
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
                "loggingOn = {loggingOn}, nCategories = {nCategories}, categories = [{names}]"
            ))
        };
        guarded_with::<M, _, _>(c, F, ANY_STATE, describe, |inst| {
            let cats = slice(categories, nCategories, "categories")?;
            let mut names = Vec::with_capacity(cats.len());
            for p in cats {
                if p.is_null() {
                    return Err(error(format!("{F}: a category name is null")));
                }
                names.push(CStr::from_ptr(*p).to_string_lossy().into_owned());
            }
            let refs: Vec<&str> = names.iter().map(String::as_str).collect();
            inst.set_debug_logging(F, loggingOn, &refs)
        })
    }
}

/// Enter Initialization Mode with the start (and optional stop) time; the tolerance is
/// ignored (no integrator inside).
///
/// # Safety
/// `c` live or null.
pub unsafe fn fmi3EnterInitializationMode<M: Model>(
    c: fmi3Instance,
    toleranceDefined: fmi3Boolean,
    tolerance: fmi3Float64,
    startTime: fmi3Float64,
    stopTimeDefined: fmi3Boolean,
    stopTime: fmi3Float64,
) -> fmi3Status {
    const F: &str = "fmi3EnterInitializationMode";
    // SAFETY: contract forwarded.
    unsafe {
        let describe = |_: &Instance<M>| {
            Some(format!(
                "toleranceDefined = {toleranceDefined}, tolerance = {tolerance}, startTime = {startTime}, stopTimeDefined = {stopTimeDefined}, stopTime = {stopTime}"
            ))
        };
        guarded_with::<M, _, _>(c, F, M_INSTANTIATED, describe, |inst| {
            inst.setup_experiment(F, startTime, stopTimeDefined.then_some(stopTime))?;
            inst.enter_initialization();
            Ok(())
        })
    }
}

/// Exit Initialization Mode into Step Mode: the model checks its parameters together and
/// is built.
///
/// # Safety
/// `c` live or null.
pub unsafe fn fmi3ExitInitializationMode<M: Model>(c: fmi3Instance) -> fmi3Status {
    // SAFETY: contract forwarded.
    unsafe {
        guarded::<M, _>(
            c,
            "fmi3ExitInitializationMode",
            M_INIT,
            Instance::<M>::exit_initialization,
        )
    }
}

/// Terminate the simulation.
///
/// # Safety
/// `c` live or null.
pub unsafe fn fmi3Terminate<M: Model>(c: fmi3Instance) -> fmi3Status {
    // SAFETY: contract forwarded.
    unsafe {
        guarded::<M, _>(c, "fmi3Terminate", M_STEP | M_EVENT, |inst| {
            inst.terminate();
            Ok(())
        })
    }
}

/// Back to the just-instantiated state (start values, nothing built); allowed in every
/// state.
///
/// # Safety
/// `c` live or null.
pub unsafe fn fmi3Reset<M: Model>(c: fmi3Instance) -> fmi3Status {
    // SAFETY: contract forwarded.
    unsafe {
        guarded::<M, _>(c, "fmi3Reset", ANY_STATE, |inst| {
            inst.reset();
            Ok(())
        })
    }
}

/// One communication step: the inputs hold at `currentCommunicationPoint`, afterwards the
/// outputs describe its end. Never returns early, never asks for event handling or the
/// end of the simulation.
///
/// # Safety
/// `c` live or null; the four out-pointers writable or null (null is refused).
pub unsafe fn fmi3DoStep<M: Model>(
    c: fmi3Instance,
    currentCommunicationPoint: fmi3Float64,
    communicationStepSize: fmi3Float64,
    noSetFMUStatePriorToCurrentPoint: fmi3Boolean,
    eventHandlingNeeded: *mut fmi3Boolean,
    terminateSimulation: *mut fmi3Boolean,
    earlyReturn: *mut fmi3Boolean,
    lastSuccessfulTime: *mut fmi3Float64,
) -> fmi3Status {
    const F: &str = "fmi3DoStep";
    // SAFETY: contract forwarded; pointers checked.
    unsafe {
        let describe = |_: &Instance<M>| {
            Some(format!(
                "currentCommunicationPoint = {currentCommunicationPoint}, communicationStepSize = {communicationStepSize}, noSetFMUStatePriorToCurrentPoint = {noSetFMUStatePriorToCurrentPoint}"
            ))
        };
        guarded_with::<M, _, _>(c, F, M_STEP, describe, |inst| {
            if eventHandlingNeeded.is_null()
                || terminateSimulation.is_null()
                || earlyReturn.is_null()
                || lastSuccessfulTime.is_null()
            {
                return Err(null_out_pointer(F));
            }
            // non-null (above), writable by the caller's contract; the flags before the
            // step, so that only one pointer lives across it
            (*eventHandlingNeeded, *terminateSimulation, *earlyReturn) = (false, false, false);
            let r = inst.do_step(F, currentCommunicationPoint, communicationStepSize);
            *lastSuccessfulTime = inst.time();
            r
        })
    }
}

/// The refusal of a `fmi3DoStep` with a null out-pointer.
#[cold]
fn null_out_pointer(func: &str) -> Failure {
    error(format!(
        "{func}: eventHandlingNeeded, terminateSimulation, earlyReturn and \
         lastSuccessfulTime must not be null"
    ))
}

/// Enter Event Mode from Step Mode (an instance made with `eventModeUsed`): the inputs set
/// there are applied at the current time by [`fmi3UpdateDiscreteStates`].
///
/// # Safety
/// `c` live or null.
pub unsafe fn fmi3EnterEventMode<M: Model>(c: fmi3Instance) -> fmi3Status {
    const F: &str = "fmi3EnterEventMode";
    // SAFETY: contract forwarded.
    unsafe { guarded::<M, _>(c, F, M_STEP, |inst| inst.enter_event_mode(F)) }
}

/// Back to Step Mode from Event Mode.
///
/// # Safety
/// `c` live or null.
pub unsafe fn fmi3EnterStepMode<M: Model>(c: fmi3Instance) -> fmi3Status {
    // SAFETY: contract forwarded.
    unsafe {
        guarded::<M, _>(c, "fmi3EnterStepMode", M_EVENT, |inst| {
            inst.enter_step_mode();
            Ok(())
        })
    }
}

/// Apply the inputs set in Event Mode at the current time (relnav: the flagged readings'
/// measurement updates, no prediction); the outputs then describe this time. Reports no
/// further update, no end of the simulation, no changed continuous states and no next
/// event time (the FMU schedules none).
///
/// # Safety
/// `c` live or null; the six out-pointers writable or null (null is refused).
pub unsafe fn fmi3UpdateDiscreteStates<M: Model>(
    c: fmi3Instance,
    discreteStatesNeedUpdate: *mut fmi3Boolean,
    terminateSimulation: *mut fmi3Boolean,
    nominalsOfContinuousStatesChanged: *mut fmi3Boolean,
    valuesOfContinuousStatesChanged: *mut fmi3Boolean,
    nextEventTimeDefined: *mut fmi3Boolean,
    nextEventTime: *mut fmi3Float64,
) -> fmi3Status {
    const F: &str = "fmi3UpdateDiscreteStates";
    // SAFETY: contract forwarded; pointers checked.
    unsafe {
        guarded::<M, _>(c, F, M_EVENT, |inst| {
            let a = slice_mut(discreteStatesNeedUpdate, 1, "discreteStatesNeedUpdate")?;
            let b = slice_mut(terminateSimulation, 1, "terminateSimulation")?;
            let n = slice_mut(
                nominalsOfContinuousStatesChanged,
                1,
                "nominalsOfContinuousStatesChanged",
            )?;
            let v = slice_mut(
                valuesOfContinuousStatesChanged,
                1,
                "valuesOfContinuousStatesChanged",
            )?;
            let d = slice_mut(nextEventTimeDefined, 1, "nextEventTimeDefined")?;
            let next = slice_mut(nextEventTime, 1, "nextEventTime")?;
            let r = inst.event_update(F);
            (a[0], b[0], n[0], v[0], d[0], next[0]) = (false, false, false, false, false, 0.0);
            r
        })
    }
}

// ---------------------------------------------------------------- get / set

fn identity(v: f64) -> f64 {
    v
}
fn int32_from(v: f64) -> fmi3Int32 {
    v as fmi3Int32
}
fn bool_from(v: f64) -> fmi3Boolean {
    v != 0.0
}
fn bool_to(v: fmi3Boolean) -> f64 {
    if v {
        1.0
    } else {
        0.0
    }
}

/// The most values a computed output may hold (the covariance holds 36; checked by
/// [`super::description::check_arrays`]).
pub(crate) const MAX_COMPUTED: usize = 64;

/// `name (vr r)` or `name[i] (vr r)` for messages.
fn label_of<M: Model>(r: fmi3ValueReference, i: usize) -> String {
    match published(M::info(), r) {
        Some(Published::Scalar(v)) => Instance::<M>::var_label(v),
        Some(Published::Array(a)) => format!("{}[{i}] (vr {r})", a.name),
        Some(Published::Computed(c, _)) => format!("{}[{i}] (vr {r})", c.name),
        Some(Published::Time) => format!("time (vr {r})"),
        None => format!("vr {r} (unknown)"),
    }
}

/// The computed output `k` into `dst` (its length), converted by `get`: out of the step
/// cycle's hot path.
#[cold]
#[inline(never)]
fn computed_into<M: Model, T>(inst: &Instance<M>, k: usize, dst: &mut [T], get: fn(f64) -> T) {
    let mut buf = [0.0; MAX_COMPUTED];
    let n = dst.len().min(MAX_COMPUTED);
    inst.computed(k, &mut buf[..n]);
    for (o, v) in dst.iter_mut().zip(&buf) {
        *o = get(*v);
    }
}

/// The refusal of a get or set whose `nValues` is not the count of values its known
/// references hold (an unknown one is refused before).
fn count_mismatch<M: Model>(refs: &[fmi3ValueReference], nValues: usize, func: &str) -> Failure {
    let info = M::info();
    let n: usize = refs
        .iter()
        .filter_map(|&r| published(info, r))
        .map(|p| p.len())
        .sum();
    error(format!(
        "{func}: nValues = {nValues}, but the {} value references hold {n} values",
        refs.len()
    ))
}

fn unknown_reference(r: fmi3ValueReference, func: &str) -> Failure {
    error(format!("{func}: unknown value reference {r}"))
}

/// Each value of the (known) `refs` in order: `(value reference, element index)`.
fn elements<M: Model>(refs: &[fmi3ValueReference]) -> impl Iterator<Item = (u32, usize)> + '_ {
    let info = M::info();
    refs.iter().flat_map(move |&r| {
        let n = published(info, r).map_or(0, |p| p.len());
        (0..n).map(move |i| (r, i))
    })
}

/// `func(nValueReferences = n: name = value, ...)` for the call log.
fn values_log<M: Model, T: Copy>(
    func: &str,
    refs: &[fmi3ValueReference],
    vals: &[T],
    show: fn(T) -> String,
) -> String {
    let parts: Vec<String> = elements::<M>(refs)
        .zip(vals)
        .map(|((r, i), v)| format!("{} = {}", label_of::<M>(r, i), show(*v)))
        .collect();
    format!(
        "{func}(nValueReferences = {}: {})",
        refs.len(),
        parts.join(", ")
    )
}

/// A value type of the get functions: how a run of stored values reaches the master's
/// buffer (a plain copy for Float64, element by element through the conversion otherwise).
trait Run: Copy {
    fn read_run(dst: &mut [Self], src: &[f64], conv: fn(f64) -> Self);
}

impl Run for f64 {
    #[inline(always)]
    fn read_run(dst: &mut [f64], src: &[f64], _: fn(f64) -> f64) {
        dst.copy_from_slice(src);
    }
}

macro_rules! run_by_element {
    ($($t:ty),*) => {$(
        impl Run for $t {
            #[inline(always)]
            fn read_run(dst: &mut [$t], src: &[f64], conv: fn(f64) -> $t) {
                for (o, v) in dst.iter_mut().zip(src) {
                    *o = conv(*v);
                }
            }
        }
    )*};
}
run_by_element!(i32, bool);

/// # Safety
/// `c` live or null; `vr` holds `nvr` and `value` `nValues` elements.
unsafe fn get_values<M: Model, T: Run>(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    nvr: usize,
    value: *mut T,
    nValues: usize,
    a: Access<T>,
) -> fmi3Status {
    let Access {
        func,
        class,
        get,
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
                let refs = slice(vr, nvr, "valueReferences")?;
                let out = slice_mut(value, nValues, "values")?;
                // the master's usual read: arrays that are each one slice of the values
                let arrays = refs.iter().map(|r| r.wrapping_sub(ARRAY_VR_BASE) as usize);
                if inst.read_runs(arrays, out, |d, s| T::read_run(d, s, get), class) {
                    inst.log_call(|| values_log::<M, T>(func, refs, out, show));
                    return Ok(());
                }
                let info = M::info();
                let mut at = 0;
                for &r in refs {
                    // each reference resolved once, its values written where they go
                    let p = published(info, r).ok_or_else(|| unknown_reference(r, func))?;
                    let n = p.len();
                    let Some(dst) = out.get_mut(at..at + n) else {
                        return Err(count_mismatch::<M>(refs, nValues, func));
                    };
                    match p {
                        Published::Scalar(v) => dst[0] = get(inst.get(v, func, class)?),
                        Published::Array(a) => {
                            for (o, &e) in dst.iter_mut().zip(a.elements) {
                                *o = get(inst.get(e, func, class)?);
                            }
                        }
                        Published::Time | Published::Computed(..) if class != TypeClass::Real => {
                            let what = label_of::<M>(r, 0);
                            return Err(error(format!("{func}: {what} is a Float64")));
                        }
                        Published::Time => dst[0] = get(inst.time()),
                        Published::Computed(_, k) => computed_into(inst, k, dst, get),
                    }
                    at += n;
                }
                if at != nValues {
                    return Err(count_mismatch::<M>(refs, nValues, func));
                }
                inst.log_call(|| values_log::<M, T>(func, refs, out, show));
                Ok(())
            },
        )
    }
}

/// The master's usual write, when it is one: every reference an array that is one slice of
/// the values and takes plain stores now, and `vals` holds their values. Writes them and
/// says whether it did (otherwise nothing is written).
#[inline(always)]
fn set_runs<M: Model, T: Copy>(
    inst: &mut Instance<M>,
    refs: &[fmi3ValueReference],
    vals: &[T],
    set: fn(T) -> f64,
    class: TypeClass,
) -> bool {
    if let [r] = refs {
        // one array: checked and written at once
        let k = r.wrapping_sub(ARRAY_VR_BASE) as usize;
        return match inst.array_run_mut(k, class) {
            Some(dst) if dst.len() == vals.len() => {
                for (x, v) in dst.iter_mut().zip(vals) {
                    *x = set(*v);
                }
                true
            }
            _ => false,
        };
    }
    // every reference and the count checked before anything is written
    let mut total = 0;
    for &r in refs {
        match inst.array_run_mut(r.wrapping_sub(ARRAY_VR_BASE) as usize, class) {
            Some(dst) => total += dst.len(),
            None => return false,
        }
    }
    if total != vals.len() {
        return false;
    }
    let mut rest = vals;
    for &r in refs {
        if let Some(dst) = inst.array_run_mut(r.wrapping_sub(ARRAY_VR_BASE) as usize, class) {
            let Some((now, later)) = rest.split_at_checked(dst.len()) else {
                break; // not reached: the counts were checked above
            };
            for (x, v) in dst.iter_mut().zip(now) {
                *x = set(*v);
            }
            rest = later;
        }
    }
    true
}

/// # Safety
/// `c` live or null; `vr` holds `nvr` and `value` `nValues` elements.
unsafe fn set_values<M: Model, T: Copy>(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    nvr: usize,
    value: *const T,
    nValues: usize,
    a: Access<T>,
) -> fmi3Status {
    let Access {
        func,
        class,
        set,
        show,
        ..
    } = a;
    // SAFETY: contract forwarded; pointers checked.
    unsafe {
        guarded_with::<M, _, _>(
            c,
            func,
            M_SET,
            |_| None,
            |inst| {
                let refs = slice(vr, nvr, "valueReferences")?;
                let vals = slice(value, nValues, "values")?;
                if set_runs(inst, refs, vals, set, class) {
                    inst.log_call(|| values_log::<M, T>(func, refs, vals, show));
                    return Ok(());
                }
                let info = M::info();
                // every reference known and the count right before anything is set
                let mut total = 0;
                for &r in refs {
                    total += published(info, r)
                        .ok_or_else(|| unknown_reference(r, func))?
                        .len();
                }
                if total != nValues {
                    return Err(count_mismatch::<M>(refs, nValues, func));
                }
                inst.log_call(|| values_log::<M, T>(func, refs, vals, show));
                let mut at = 0;
                for &r in refs {
                    let Some(p) = published(info, r) else {
                        continue;
                    };
                    match p {
                        Published::Scalar(t) => inst.set(t, set(vals[at]), func, class)?,
                        Published::Array(a) => {
                            for (&e, v) in a.elements.iter().zip(&vals[at..]) {
                                inst.set(e, set(*v), func, class)?;
                            }
                        }
                        Published::Time | Published::Computed(..) => {
                            let what = label_of::<M>(r, 0);
                            return Err(error(format!("{func}: {what} cannot be set")));
                        }
                    }
                    at += p.len();
                }
                Ok(())
            },
        )
    }
}

macro_rules! get_set {
    ($get:ident, $set:ident, $t:ty, $class:expr, $from:expr, $to:expr, $show:expr) => {
        #[doc = concat!("`", stringify!($get), "`: scalars and arrays (an array's elements in order).")]
        ///
        /// # Safety
        /// `c` live or null; `vr` holds `nvr` and `value` `nValues` elements.
        pub unsafe fn $get<M: Model>(
            c: fmi3Instance,
            vr: *const fmi3ValueReference,
            nvr: usize,
            value: *mut $t,
            nValues: usize,
        ) -> fmi3Status {
            let a = Access {
                func: stringify!($get),
                class: $class,
                get: $from,
                set: $to,
                show: $show,
            };
            // SAFETY: contract forwarded.
            unsafe { get_values::<M, $t>(c, vr, nvr, value, nValues, a) }
        }

        #[doc = concat!("`", stringify!($set), "`: scalars and arrays (an array's elements in order).")]
        ///
        /// # Safety
        /// `c` live or null; `vr` holds `nvr` and `value` `nValues` elements.
        pub unsafe fn $set<M: Model>(
            c: fmi3Instance,
            vr: *const fmi3ValueReference,
            nvr: usize,
            value: *const $t,
            nValues: usize,
        ) -> fmi3Status {
            let a = Access {
                func: stringify!($set),
                class: $class,
                get: $from,
                set: $to,
                show: $show,
            };
            // SAFETY: contract forwarded.
            unsafe { set_values::<M, $t>(c, vr, nvr, value, nValues, a) }
        }
    };
}

get_set!(
    fmi3GetFloat64,
    fmi3SetFloat64,
    fmi3Float64,
    TypeClass::Real,
    identity,
    identity,
    real_arg
);
get_set!(
    fmi3GetInt32,
    fmi3SetInt32,
    fmi3Int32,
    TypeClass::Integer,
    int32_from,
    f64::from,
    |v: fmi3Int32| format!("{v}")
);
get_set!(
    fmi3GetBoolean,
    fmi3SetBoolean,
    fmi3Boolean,
    TypeClass::Boolean,
    bool_from,
    bool_to,
    |v: fmi3Boolean| format!("{v}")
);

// ---------------------------------------------------------------- FMU state

/// How a state moves between instances, for the messages that refuse a handle.
const TRANSFER: &str = "fmi3SerializeFMUState / fmi3DeserializeFMUState";

/// Copy the instance's complete state (the bytes of [`crate::state`]); `*FMUState ==
/// NULL` makes a new state, a state this instance made is overwritten.
///
/// # Safety
/// `c` live or null; `FMUState` null or writable.
pub unsafe fn fmi3GetFMUState<M: Model>(
    c: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    // SAFETY: contract forwarded; `FMUState` checked for null.
    unsafe {
        guarded::<M, _>(c, "fmi3GetFMUState", ANY_STATE, |inst| {
            let out = slice_mut(FMUState, 1, "FMUState")?;
            inst.get_fmu_state(&mut out[0])
        })
    }
}

/// Restore a state made by this instance (refused states leave its data unchanged).
///
/// # Safety
/// `c` live or null.
pub unsafe fn fmi3SetFMUState<M: Model>(c: fmi3Instance, FMUState: fmi3FMUState) -> fmi3Status {
    const F: &str = "fmi3SetFMUState";
    // SAFETY: contract forwarded; the state pointer is only compared, never dereferenced.
    unsafe {
        guarded::<M, _>(c, F, ANY_STATE, |inst| {
            inst.set_fmu_state(FMUState, F, TRANSFER)
        })
    }
}

/// Free a state (`*FMUState == NULL` is ignored); `*FMUState` is set to NULL.
///
/// # Safety
/// `c` live or null; `FMUState` null or writable.
pub unsafe fn fmi3FreeFMUState<M: Model>(
    c: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    const F: &str = "fmi3FreeFMUState";
    // SAFETY: contract forwarded; `FMUState` checked for null.
    unsafe {
        guarded::<M, _>(c, F, ANY_STATE, |inst| {
            let s = slice_mut(FMUState, 1, "FMUState")?;
            inst.free_fmu_state(&mut s[0], F, TRANSFER)
        })
    }
}

/// Size in bytes of a state's serialised form.
///
/// # Safety
/// `c` live or null; `size` null or writable.
pub unsafe fn fmi3SerializedFMUStateSize<M: Model>(
    c: fmi3Instance,
    FMUState: fmi3FMUState,
    size: *mut usize,
) -> fmi3Status {
    const F: &str = "fmi3SerializedFMUStateSize";
    // SAFETY: contract forwarded; `size` checked for null.
    unsafe {
        guarded::<M, _>(c, F, ANY_STATE, |inst| {
            let out = slice_mut(size, 1, "size")?;
            out[0] = inst.fmu_state_size(FMUState, F, TRANSFER)?;
            Ok(())
        })
    }
}

/// Copy a state's serialised form into `serializedState` (`size` bytes, at least
/// [`fmi3SerializedFMUStateSize`]).
///
/// # Safety
/// `c` live or null; `serializedState` null or `size` writable bytes.
pub unsafe fn fmi3SerializeFMUState<M: Model>(
    c: fmi3Instance,
    FMUState: fmi3FMUState,
    serializedState: *mut fmi3Byte,
    size: usize,
) -> fmi3Status {
    const F: &str = "fmi3SerializeFMUState";
    // SAFETY: contract forwarded; pointers checked.
    unsafe {
        guarded::<M, _>(c, F, ANY_STATE, |inst| {
            let b = inst.serialized_fmu_state(
                FMUState,
                size,
                F,
                TRANSFER,
                "fmi3SerializedFMUStateSize",
            )?;
            let out = slice_mut(serializedState, b.len(), "serializedState")?;
            out.copy_from_slice(b);
            Ok(())
        })
    }
}

/// Make a state from serialised bytes (checked: length, CRC-32, magic, format version,
/// token, structure); whether it fits this instance's parameters is checked by
/// [`fmi3SetFMUState`].
///
/// # Safety
/// `c` live or null; `serializedState` null or `size` readable bytes; `FMUState` null or
/// writable.
pub unsafe fn fmi3DeserializeFMUState<M: Model>(
    c: fmi3Instance,
    serializedState: *const fmi3Byte,
    size: usize,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    const F: &str = "fmi3DeserializeFMUState";
    // SAFETY: contract forwarded; pointers checked.
    unsafe {
        guarded::<M, _>(c, F, ANY_STATE, |inst| {
            let out = slice_mut(FMUState, 1, "FMUState")?;
            if serializedState.is_null() {
                return Err(error(format!("{F}: serializedState is null")));
            }
            let bytes = slice(serializedState, size, "serializedState")?;
            inst.deserialize_fmu_state(bytes, &mut out[0], F)
        })
    }
}
