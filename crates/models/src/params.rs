//! A model's parameter variables from relnav-core's parameter declarations
//! ([`relnav_core::params::Param`]): the variable rows (value reference, name, unit, start =
//! default, description, code list) and the mapping from an instance's values back to the
//! configuration. Every model's table and `config_of` use these, so a parameter declared in
//! the core is an FMU variable with nothing written twice.

use relnav_core::params::{element_by_id, Kind, Param, Value};
use relnav_fmi::variables::{Causality, VarDef, VarType, Variability};

/// The FMU variable of element `i` of a declared parameter.
pub fn parameter_row<C>(p: &'static Param<C>, i: usize, id: u32) -> VarDef {
    let e = &p.elements[i];
    VarDef {
        vr: id,
        name: e.name,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        ty: match p.kind {
            Kind::Real => VarType::Real(e.unit),
            Kind::Count | Kind::Seed => VarType::Integer,
            Kind::Bool => VarType::Boolean,
            Kind::Code(list) => VarType::Code(list),
        },
        start: e.default.as_f64(),
        description: p.element_description(e),
    }
}

/// A model's table of `n` variables: the declared parameters at their value references,
/// the inputs and outputs `io` at theirs. A value reference that is neither leaves a hole
/// (the table is then shorter than `n`, which `relnav_fmi::variables::check_table` and the
/// model's test refuse).
pub fn table<C>(params: &'static [Param<C>], io: &[VarDef], n: usize) -> Vec<VarDef> {
    (0..n as u32)
        .filter_map(|id| match element_by_id(params, id) {
            Some((p, i)) => Some(parameter_row(p, i, id)),
            None => io.iter().find(|v| v.vr == id).copied(),
        })
        .collect()
}

/// Check a table built by [`table`]: no input or output takes a declared parameter's
/// value reference, and every declared element with a value reference is a parameter row
/// of its name at that index (each model's tests call it beside
/// `relnav_fmi::variables::check_table`).
pub fn check_declared<C>(
    params: &'static [Param<C>],
    io: &[VarDef],
    table: &[VarDef],
) -> Result<(), String> {
    if let Some(v) = io.iter().find(|v| element_by_id(params, v.vr).is_some()) {
        return Err(format!(
            "{}: value reference {} is a parameter's",
            v.name, v.vr
        ));
    }
    for p in params {
        for e in p.elements {
            let Some(id) = e.id else { continue };
            match table.get(id as usize) {
                Some(v) if v.name == e.name && v.causality == Causality::Parameter => {}
                _ => return Err(format!("{}: not the parameter at {id}", e.name)),
            }
        }
    }
    Ok(())
}

/// The value an FMU variable of a declared parameter holds, as its declaration takes it:
/// codes, counts and flags are the integers their `f64` holds; FMI Integers are 32-bit, so
/// a seed keeps their bit pattern.
pub fn value_of(kind: Kind, v: f64) -> Value {
    match kind {
        Kind::Real => Value::Real(v),
        Kind::Seed => Value::Int(i64::from(v as i32 as u32)),
        Kind::Bool => Value::Int(i64::from(v != 0.0)),
        Kind::Count | Kind::Code(_) => Value::Int(i64::from(v as i32)),
    }
}

/// `C::default()` with every declared parameter that has a value reference set from
/// `values` (indexed by value reference) through its declaration (an unknown code or a
/// count out of range is refused naming the parameter). The caller validates the whole.
pub fn config_from<C: Default>(params: &'static [Param<C>], values: &[f64]) -> Result<C, String> {
    let mut cfg = C::default();
    for p in params {
        for (i, e) in p.elements.iter().enumerate() {
            let Some(id) = e.id else { continue };
            let v = values.get(id as usize).copied().unwrap_or(f64::NAN);
            p.assign(&mut cfg, i, value_of(p.kind, v))?;
        }
    }
    Ok(cfg)
}

/// The value reference constants of declared parameters (`NAME = "name"`), computed from
/// the declarations at compile time; a name with no value reference does not compile.
#[macro_export]
macro_rules! param_vrs {
    ($params:expr; $( $id:ident = $name:literal ),* $(,)?) => {
        $(
            #[doc = concat!("`", $name, "` (a parameter).")]
            pub const $id: u32 = match relnav_core::params::id_of($params, $name) {
                Some(id) => id,
                None => u32::MAX,
            };
            const _: () = assert!($id != u32::MAX, concat!($name, " has no value reference"));
        )*
    };
}
