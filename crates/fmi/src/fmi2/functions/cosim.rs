//! The co-simulation step and status functions of FMI 2.0, and the derivative functions it
//! does not support.

use super::*;

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
