//! The typed gets and sets of FMI 2.0 (`fmi2Get*`, `fmi2Set*`).

use super::*;

// ---------------------------------------------------------------- get / set

/// How one FMI base type maps onto the stored `f64` values (both bindings' typed gets
/// and sets).
pub(crate) struct Access<T> {
    /// Function name (`fmi2GetReal` or `fmi3SetFloat64`, ...).
    pub(crate) func: &'static str,
    /// Which variable types it reads or writes.
    pub(crate) class: TypeClass,
    /// Stored value -> FMI value.
    pub(crate) get: fn(f64) -> T,
    /// FMI value -> stored value.
    pub(crate) set: fn(T) -> f64,
    /// FMI value for the call log.
    pub(crate) show: fn(T) -> String,
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
