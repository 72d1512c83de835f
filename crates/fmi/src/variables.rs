//! The types of a model's variable table and the [`variables!`](crate::variables!) macro
//! that writes one. One table per model drives everything the bindings derive from it:
//! the model description, the get/set dispatch (value reference = index in the table), the
//! start values, the FMU state's parameter fingerprint. The tables themselves live with
//! their models.

/// FMI causality.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Causality {
    /// Fixed before initialisation.
    Parameter,
    /// Set by the master before each step.
    Input,
    /// Computed by the FMU.
    Output,
}

/// FMI variability.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Variability {
    /// Constant after initialisation.
    Fixed,
    /// Changes only at communication points (held in between).
    Discrete,
    /// A continuous quantity sampled at communication points.
    Continuous,
}

/// A list of named integer codes (the C ABI's enums: filter, frame, ...): relnav-core's
/// declaration of the list, used as it is.
///
/// Declared in `modelDescription.xml` as an FMI **Integer** with `min`/`max` and the
/// codes with their names in the description, not as an FMI Enumeration: libcosim
/// ignores Enumeration variables and Ecos drops them (`../shared/docs/fmi-masters.md`),
/// so an Enumeration could be set from fmpy only. A code outside the list is refused when
/// it is set.
pub use relnav_core::params::{CodeItem, CodeList};

/// FMI base type of a variable.
#[derive(Debug, Clone, Copy)]
pub enum VarType {
    /// Real with a unit (empty string: dimensionless, no unit attribute).
    Real(&'static str),
    /// Integer.
    Integer,
    /// Boolean.
    Boolean,
    /// Integer restricted to the codes of a list (FMI Integer with `min`/`max`).
    Code(&'static CodeList),
}

/// One FMU variable.
#[derive(Debug, Clone, Copy)]
pub struct VarDef {
    /// Value reference (= index in the model's table).
    pub vr: u32,
    /// Name.
    pub name: &'static str,
    /// Causality.
    pub causality: Causality,
    /// Variability.
    pub variability: Variability,
    /// Type.
    pub ty: VarType,
    /// Start value (Integer/code/Boolean stored exactly as f64); unused for outputs.
    pub start: f64,
    /// Description.
    pub description: &'static str,
}

/// The base type class a typed get or set reads or writes (each FMI version has one get
/// and one set function per class: FMI 2.0's `fmi2GetReal`, `fmi2SetInteger`, ...).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum TypeClass {
    /// Real (64-bit float).
    Real = 1,
    /// Integer (32-bit; Integer and code variables).
    Integer = 2,
    /// Boolean.
    Boolean = 3,
}

impl TypeClass {
    /// The class of a variable type.
    pub const fn of(ty: &VarType) -> Self {
        match ty {
            VarType::Real(_) => Self::Real,
            VarType::Integer | VarType::Code(_) => Self::Integer,
            VarType::Boolean => Self::Boolean,
        }
    }
}

/// The units a table may use, as (name, exponents of kg, m, s, rad): a model description
/// declares those its table uses, in this order.
pub const UNITS: &[(&str, [i32; 4])] = &[
    ("N", [1, 1, -2, 0]),
    ("kg", [1, 0, 0, 0]),
    ("m", [0, 1, 0, 0]),
    ("m/s", [0, 1, -1, 0]),
    ("rad", [0, 0, 0, 1]),
    ("rad/s", [0, 0, -1, 1]),
    ("m2/s", [0, 2, -1, 0]),
    ("m2/s3", [0, 2, -3, 0]),
    ("s", [0, 0, 1, 0]),
    ("N.s", [1, 1, -1, 0]),
];

/// Writes a model's variable table: a module `vr` of value-reference constants by name
/// and `pub static VARIABLES: &[VarDef]` (value reference = index), from rows
/// `ID = vr: "name", Causality, Variability, type, start, "description";`.
#[macro_export]
macro_rules! variables {
    ($( $id:ident = $vr:literal : $name:literal, $caus:ident, $var:ident, $ty:expr, $start:expr, $desc:literal; )*) => {
        /// Value references by name (generated from the table).
        pub mod vr {
            $(
                #[doc = $desc]
                pub const $id: u32 = $vr;
            )*
        }
        /// Every variable of the model; the value reference is the index.
        pub static VARIABLES: &[$crate::variables::VarDef] = &[
            $( $crate::variables::VarDef {
                vr: $vr,
                name: $name,
                causality: $crate::variables::Causality::$caus,
                variability: $crate::variables::Variability::$var,
                ty: $ty,
                start: $start,
                description: $desc,
            }, )*
        ];
    };
}

/// Every variable at its start value (outputs at their table value until the model writes
/// them).
pub fn start_values(vars: &[VarDef]) -> Vec<f64> {
    vars.iter().map(|v| v.start).collect()
}

/// Check a variable table (each model's tests call it): value reference = index, unique
/// names, declared units, code lists with ascending, distinct codes and start values in
/// their list (codes need not be contiguous: relnav's `hinf_design` has 1 and 3), fixed
/// parameters, and the `fmi_status` output every model publishes. The error names the
/// first violation.
pub fn check_table(vars: &[VarDef]) -> Result<(), String> {
    for (i, v) in vars.iter().enumerate() {
        if v.vr as usize != i {
            return Err(format!("{}: value reference {} at index {i}", v.name, v.vr));
        }
        if vars.iter().filter(|w| w.name == v.name).count() != 1 {
            return Err(format!("{}: the name is not unique", v.name));
        }
        if let VarType::Real(u) = v.ty {
            if !(u.is_empty() || UNITS.iter().any(|(n, _)| *n == u)) {
                return Err(format!("{}: unit {u} is not declared in UNITS", v.name));
            }
        }
        if let VarType::Code(t) = v.ty {
            if t.item_at(v.start).is_none() {
                return Err(format!("{}: start value {} is not a code", v.name, v.start));
            }
            // min/max in the model description bound the codes; a gap is refused at set
            if !t.items.windows(2).all(|w| w[0].code < w[1].code) {
                return Err(format!("{}: the codes are not ascending", t.name));
            }
        }
        // outputs change only in a step; inputs need a start value
        if v.causality == Causality::Parameter && v.variability != Variability::Fixed {
            return Err(format!("{}: a parameter must be fixed", v.name));
        }
    }
    if !vars
        .iter()
        .any(|v| v.name == "fmi_status" && v.causality == Causality::Output)
    {
        return Err("every model publishes fmi_status".to_string());
    }
    Ok(())
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A code list with a gap (codes 1 and 3), shared by the layer's tests.
    pub(crate) static CODES: CodeList = CodeList {
        name: "Codes",
        c_type: "codes",
        c_prefix: "CODES_",
        c_enum: false,
        items: &[
            CodeItem {
                name: "a",
                code: 1,
                description: "first",
            },
            CodeItem {
                name: "c",
                code: 3,
                description: "third",
            },
        ],
    };

    crate::variables! {
        MODE = 0: "mode", Parameter, Fixed, VarType::Code(&CODES), 3.0, "A code";
        GAIN = 1: "gain", Input, Discrete, VarType::Real("m/s"), 0.5, "An input";
        FMI_STATUS = 2: "fmi_status", Output, Discrete, VarType::Integer, 0.0, "Status";
    }

    #[test]
    fn the_macro_writes_a_dense_table() {
        assert_eq!(check_table(VARIABLES), Ok(()));
        assert_eq!((vr::MODE, vr::GAIN, vr::FMI_STATUS), (0, 1, 2));
        assert_eq!(start_values(VARIABLES), [3.0, 0.5, 0.0]);
        assert_eq!(CODES.range(), (1, 3));
        assert_eq!(CODES.codes(), "1 a, 3 c");
        assert!(CODES.item_at(2.0).is_none());
        assert_eq!(TypeClass::of(&VARIABLES[0].ty), TypeClass::Integer);
    }

    #[test]
    fn check_table_names_the_violation() {
        let bad = [VarDef {
            vr: 1,
            name: "x",
            causality: Causality::Output,
            variability: Variability::Continuous,
            ty: VarType::Real("furlong"),
            start: 0.0,
            description: "",
        }];
        assert!(check_table(&bad).is_err_and(|e| e.contains("value reference 1")));
        let bad = [VarDef { vr: 0, ..bad[0] }];
        assert!(check_table(&bad).is_err_and(|e| e.contains("furlong")));
        let bad = [VarDef {
            ty: VarType::Real("m"),
            ..bad[0]
        }];
        assert!(check_table(&bad).is_err_and(|e| e.contains("fmi_status")));
    }
}
