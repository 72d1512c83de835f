//! Estimator parameters by their FMU names, driven by the one variable table
//! (`relnav_nav_model::VARIABLES`): every variable of causality *parameter* is a keyword
//! argument with the table's name, type, start value and description; the values become a
//! validated configuration through the FMU's own mapping (`relnav_nav_model::config_of`,
//! which stores each value through its declaration in `relnav_core::nav::PARAMS`). A
//! parameter declared there with a value reference is therefore accepted here with nothing
//! to change.

use crate::errors::{invalid, nav_error};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use relnav_core::nav::NavConfig;
use relnav_fmi::variables::{Causality, VarDef, VarType};
use relnav_nav_model::{N_VARS, VARIABLES};

/// The table's parameters, in table order.
pub fn parameters() -> impl Iterator<Item = &'static VarDef> {
    VARIABLES
        .iter()
        .filter(|v| v.causality == Causality::Parameter)
}

/// Every variable at its start value, indexed by value reference.
pub fn start_values() -> [f64; N_VARS] {
    let mut values = [0.0; N_VARS];
    for v in VARIABLES.iter() {
        values[v.vr as usize] = v.start;
    }
    values
}

/// The FMI type's name: `Real`, `Integer` (code lists included: the FMU declares them as
/// Integers) or `Boolean`.
pub fn type_name(ty: &VarType) -> &'static str {
    match ty {
        VarType::Real(_) => "Real",
        VarType::Integer | VarType::Code(_) => "Integer",
        VarType::Boolean => "Boolean",
    }
}

/// The Python value of a parameter: a code list's item name, an `int` for Integer, a
/// `bool` for Boolean, a `float` for Real.
pub fn to_python<'py>(py: Python<'py>, def: &VarDef, v: f64) -> PyResult<Bound<'py, PyAny>> {
    Ok(match def.ty {
        VarType::Real(_) => PyFloat::new(py, v).into_any(),
        VarType::Integer => (v as i64).into_pyobject(py)?.into_any(),
        VarType::Boolean => PyBool::new(py, v != 0.0).to_owned().into_any(),
        VarType::Code(t) => match t.item_at(v) {
            Some(it) => PyString::new(py, it.name).into_any(),
            None => (v as i64).into_pyobject(py)?.into_any(),
        },
    })
}

fn python_type(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_else(|_| "?".into())
}

/// Convert one keyword argument to the table's `f64` representation, checking its type
/// and (for enumerations) that it names or codes an item.
fn value_of(py: Python<'_>, def: &VarDef, obj: &Bound<'_, PyAny>) -> PyResult<f64> {
    let name = def.name;
    let is_bool = obj.is_instance_of::<PyBool>();
    match def.ty {
        VarType::Real(_) => {
            if is_bool || obj.is_instance_of::<PyString>() {
                return Err(invalid(
                    py,
                    format!("{name} must be a number (got {})", python_type(obj)),
                ));
            }
            obj.extract::<f64>().map_err(|_| {
                invalid(
                    py,
                    format!("{name} must be a number (got {})", python_type(obj)),
                )
            })
        }
        VarType::Integer => {
            // ints and integer-like objects (numpy integers), not floats or bools
            if is_bool || obj.is_instance_of::<PyFloat>() || !obj.hasattr("__index__")? {
                return Err(invalid(
                    py,
                    format!("{name} must be an integer (got {})", python_type(obj)),
                ));
            }
            let i: i64 = obj
                .extract()
                .map_err(|_| invalid(py, format!("{name} must be an integer (got {obj})")))?;
            // an FMI Integer is 32-bit
            i32::try_from(i).map(f64::from).map_err(|_| {
                invalid(
                    py,
                    format!(
                        "{name} = {i} does not fit a 32-bit FMI Integer ([{}, {}])",
                        i32::MIN,
                        i32::MAX
                    ),
                )
            })
        }
        VarType::Boolean => {
            if is_bool {
                Ok(if obj.extract::<bool>()? { 1.0 } else { 0.0 })
            } else {
                Err(invalid(
                    py,
                    format!("{name} must be True or False (got {})", python_type(obj)),
                ))
            }
        }
        VarType::Code(t) => {
            if let Ok(s) = obj.cast::<PyString>() {
                let s = s.to_str()?;
                t.by_name(s).map(|it| f64::from(it.code)).ok_or_else(|| {
                    invalid(
                        py,
                        format!(
                            "{name} = {s:?} is not a {} (allowed: {})",
                            t.name,
                            t.codes()
                        ),
                    )
                })
            } else if !is_bool && obj.is_instance_of::<PyInt>() {
                let code: i64 = obj.extract()?;
                t.item(code).map(|it| f64::from(it.code)).ok_or_else(|| {
                    invalid(
                        py,
                        format!(
                            "{name} = {code} is not a {} code (allowed: {})",
                            t.name,
                            t.codes()
                        ),
                    )
                })
            } else {
                Err(invalid(
                    py,
                    format!(
                        "{name} must be a {} name or code (got {}; allowed: {})",
                        t.name,
                        python_type(obj),
                        t.codes()
                    ),
                ))
            }
        }
    }
}

/// The closest parameter names to a misspelt one (for the error message).
fn suggestions(key: &str) -> Vec<&'static str> {
    fn distance(a: &str, b: &str) -> usize {
        let b: Vec<char> = b.chars().collect();
        let mut prev: Vec<usize> = (0..=b.len()).collect();
        for (i, ca) in a.chars().enumerate() {
            let mut cur = vec![i + 1; b.len() + 1];
            for (j, cb) in b.iter().enumerate() {
                let sub = prev[j] + usize::from(ca != *cb);
                cur[j + 1] = sub.min(prev[j + 1] + 1).min(cur[j] + 1);
            }
            prev = cur;
        }
        prev[b.len()]
    }
    let mut d: Vec<(usize, &'static str)> = parameters()
        .map(|v| (distance(&key.to_ascii_lowercase(), v.name), v.name))
        .filter(|(d, _)| *d <= 2)
        .collect();
    d.sort();
    d.into_iter().take(3).map(|(_, n)| n).collect()
}

/// The table values with the keyword arguments applied (unknown names and ill-typed
/// values raise `InvalidArgumentError`).
pub fn values_from_kwargs(
    py: Python<'_>,
    kwargs: Option<&Bound<'_, PyDict>>,
) -> PyResult<[f64; N_VARS]> {
    let mut values = start_values();
    let Some(kwargs) = kwargs else {
        return Ok(values);
    };
    for (k, obj) in kwargs.iter() {
        let key: String = k.extract()?;
        let def = parameters().find(|v| v.name == key).ok_or_else(|| {
            let near = suggestions(&key);
            let hint = if near.is_empty() {
                String::new()
            } else {
                format!("; did you mean {}?", near.join(" or "))
            };
            invalid(
                py,
                format!(
                    "unknown parameter {key:?}{hint} (the parameters are the FMU's: {})",
                    parameters().map(|v| v.name).collect::<Vec<_>>().join(", ")
                ),
            )
        })?;
        values[def.vr as usize] = value_of(py, def, &obj)?;
    }
    Ok(values)
}

/// The validated library configuration of these values (the FMU's mapping).
pub fn config(py: Python<'_>, values: &[f64; N_VARS]) -> PyResult<NavConfig> {
    relnav_nav_model::config_of(values).map_err(|e| nav_error(py, e))
}

/// `relnav.parameters()`: one dict per parameter of the variable table, in table order.
#[pyfunction]
pub fn parameters_table(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let list = PyList::empty(py);
    for v in parameters() {
        let d = PyDict::new(py);
        d.set_item("name", v.name)?;
        d.set_item("value_reference", v.vr)?;
        d.set_item("type", type_name(&v.ty))?;
        d.set_item(
            "unit",
            match v.ty {
                VarType::Real(u) => u,
                _ => "",
            },
        )?;
        d.set_item("default", to_python(py, v, v.start)?)?;
        d.set_item("description", v.description)?;
        if let VarType::Code(t) = v.ty {
            let items = PyList::empty(py);
            for it in t.items {
                let (n, c, desc) = (it.name, it.code, it.description);
                items.append(PyTuple::new(
                    py,
                    [
                        n.into_pyobject(py)?.into_any(),
                        c.into_pyobject(py)?.into_any(),
                        desc.into_pyobject(py)?.into_any(),
                    ],
                )?)?;
            }
            d.set_item("items", items)?;
        }
        list.append(d)?;
    }
    Ok(list)
}
