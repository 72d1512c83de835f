//! The parameter schema: every parameter of a configuration is declared once, as a row of
//! a table ([`Param`]), and every front end derives its form of it from that row: the core
//! configuration's field, default, validation and saved-state identity, the C ABI's struct
//! field (`relnav_config`, generated and checked in), the FMU variable, the Python keyword
//! argument and the scenario files' key.
//!
//! A row declares: the field's name, its type ([`Kind`], derived from the Rust type), its
//! scalar elements ([`Element`]: name, value reference, unit, description — an array
//! parameter such as `x0` is six FMU variables `x0 .. vz0`), the default of each element,
//! the domain rule ([`Rule`]), its key in a scenario's `[[filter]]` table, and its slot in a
//! saved state's configuration section. The rows are written with the [`config!`] macro,
//! which also writes the struct, so a new parameter is one row plus the code that uses it.
//!
//! Codes (the filter, the frame, ...) are [`CodeList`]s declared with [`codes!`] beside the
//! enum they belong to: the enum, its names and its descriptions are one declaration too.

use crate::numerics::num;

/// One item of a [`CodeList`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CodeItem {
    /// Lower-case name (`"ekf"`), as scenario files, Python and the FMU's descriptions
    /// write it.
    pub name: &'static str,
    /// Stable code (never renumbered).
    pub code: i32,
    /// What the item is, in one sentence.
    pub description: &'static str,
}

/// A list of named integer codes: a parameter that selects a method.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CodeList {
    /// Name of the list (`"Filter"`), used in messages.
    pub name: &'static str,
    /// The C ABI's enum type (`"relnav_filter"`).
    pub c_type: &'static str,
    /// The C ABI's prefix of the enum's constants (`"RELNAV_FILTER_"`).
    pub c_prefix: &'static str,
    /// Whether the C ABI's enum is generated from this list (false: the C ABI declares a
    /// wider enum of its own, as `relnav_hinf_form` for the H-infinity design).
    pub c_enum: bool,
    /// Items in code order.
    pub items: &'static [CodeItem],
}

impl CodeList {
    /// Smallest and largest code.
    pub fn range(&self) -> (i32, i32) {
        let codes = self.items.iter().map(|it| it.code);
        (codes.clone().min().unwrap_or(0), codes.max().unwrap_or(0))
    }

    /// The item with code `code`.
    pub fn item(&self, code: i64) -> Option<&'static CodeItem> {
        self.items.iter().find(|it| i64::from(it.code) == code)
    }

    /// The item whose code equals `value` (a code as a front end that carries integers in
    /// doubles holds it: the FMI layer's values).
    pub fn item_at(&self, value: f64) -> Option<&'static CodeItem> {
        self.items.iter().find(|it| f64::from(it.code) == value)
    }

    /// The item named `name` (ASCII case-insensitive).
    pub fn by_name(&self, name: &str) -> Option<&'static CodeItem> {
        self.items
            .iter()
            .find(|it| it.name.eq_ignore_ascii_case(name))
    }

    #[cfg(feature = "std")]
    /// `1 ekf, 2 ukf, ...`: the codes with their names.
    pub fn codes(&self) -> String {
        let parts: Vec<String> = self
            .items
            .iter()
            .map(|it| format!("{} {}", it.code, it.name))
            .collect();
        parts.join(", ")
    }

    #[cfg(feature = "std")]
    /// `ekf, ukf, ...`: the names alone.
    pub fn names(&self) -> String {
        let parts: Vec<&str> = self.items.iter().map(|it| it.name).collect();
        parts.join(", ")
    }
}

/// The type of a parameter, as every front end sees it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A real number (`double` in C, FMI Real, Python `float`).
    Real,
    /// A count (`int32_t` in C, FMI Integer, Python `int`; `usize` inside).
    Count,
    /// A 64-bit seed (`uint64_t` in C; an FMI Integer and the Python keyword carry 32 bits,
    /// whose bit pattern is kept: `-1` is `2^32 - 1`).
    Seed,
    /// A flag (`int32_t` 0 or 1 in C, FMI Boolean, Python `bool`).
    Bool,
    /// A code of a list (`int32_t` in C, FMI Integer with `min`/`max`, a name or a code in
    /// Python and in scenario files).
    Code(&'static CodeList),
}

/// A scalar value of a parameter element: a real number or an integer (a count, a code, a
/// flag as 0 or 1, a seed's 64 bits).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    /// A real number.
    Real(f64),
    /// An integer.
    Int(i64),
}

impl Value {
    /// As a real number (an integer converted).
    pub fn as_f64(self) -> f64 {
        match self {
            Value::Real(v) => v,
            Value::Int(v) => v as f64,
        }
    }

    /// As an integer (`None` for a real number).
    pub fn as_int(self) -> Option<i64> {
        match self {
            Value::Int(v) => Some(v),
            Value::Real(_) => None,
        }
    }
}

impl core::fmt::Display for Value {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Value::Real(v) => f.write_str(num(*v).as_ref()),
            Value::Int(v) => write!(f, "{v}"),
        }
    }
}

/// One scalar of a parameter: an FMU variable, a Python keyword.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Element {
    /// Name (`"x0"`, `"vz0"`, `"q_pos_x"`).
    pub name: &'static str,
    /// Value reference of its FMU variable and name of its Python keyword (`None`: the
    /// C ABI alone takes it). Never renumbered; new ones are appended.
    pub id: Option<u32>,
    /// SI unit (`"m"`, `"rad/s"`; empty: dimensionless).
    pub unit: &'static str,
    /// Default.
    pub default: Value,
    /// Description; empty: the parameter's own.
    pub description: &'static str,
}

/// A lower or upper end of an interval: its value and whether it belongs to it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct End {
    /// The bound.
    pub at: f64,
    /// Whether the bound itself is allowed.
    pub closed: bool,
}

/// The domain of every element of a parameter, checked by [`Param::check`]; the message
/// names the element. Rules between parameters are the configuration's own code.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Rule {
    /// Anything its type holds (a code of its list, a flag, a seed).
    Any,
    /// A finite number.
    Finite,
    /// Finite and `> 0`.
    Positive,
    /// Finite and `>= 0`.
    NonNegative,
    /// Finite and in an interval; `why` follows the message (`": the probability ..."`).
    Interval {
        /// Lower end (`f64::NEG_INFINITY` open: none).
        lo: End,
        /// Upper end (`f64::INFINITY` open: none).
        hi: End,
        /// Why, appended to the message (may be empty).
        why: &'static str,
    },
    /// A count in `lo..=hi`.
    Count {
        /// Smallest.
        lo: i64,
        /// Largest.
        hi: i64,
    },
}

impl Rule {
    #[cfg(feature = "std")]
    /// The rule in words (`"> 0"`, `"in (0, 1]"`, `"1..=512"`), empty for [`Rule::Any`].
    pub fn words(&self) -> String {
        match self {
            Rule::Any => String::new(),
            Rule::Finite => "finite".into(),
            Rule::Positive => "> 0".into(),
            Rule::NonNegative => ">= 0".into(),
            Rule::Interval { lo, hi, .. } => interval_words(lo, hi),
            Rule::Count { lo, hi } if *hi == lo + 1 => format!("{lo} or {hi}"),
            Rule::Count { lo, hi } => format!("{lo}..={hi}"),
        }
    }

    /// Check one element's value; the message names it as `name`.
    pub fn check(&self, name: &str, v: Value) -> Result<(), crate::message::Message> {
        let x = v.as_f64();
        match *self {
            Rule::Any => Ok(()),
            Rule::Finite => {
                if x.is_finite() {
                    Ok(())
                } else {
                    Err(named(name, crate::msg!(" must be finite (got {v})")))
                }
            }
            Rule::Positive => {
                if x.is_finite() && x > 0.0 {
                    Ok(())
                } else {
                    Err(named(
                        name,
                        crate::msg!(" must be finite and > 0 (got {v})"),
                    ))
                }
            }
            Rule::NonNegative => {
                if x.is_finite() && x >= 0.0 {
                    Ok(())
                } else {
                    Err(named(
                        name,
                        crate::msg!(" must be finite and >= 0 (got {v})"),
                    ))
                }
            }
            Rule::Interval { lo, hi, why } => {
                let above = if lo.closed { x >= lo.at } else { x > lo.at };
                let below = if hi.closed { x <= hi.at } else { x < hi.at };
                if x.is_finite() && above && below {
                    Ok(())
                } else if hi.at == f64::INFINITY {
                    let op = if lo.closed { ">=" } else { ">" };
                    Err(named(
                        name,
                        crate::msg!(" must be finite and {op} {} (got {v}){why}", num(lo.at)),
                    ))
                } else {
                    Err(named(name, interval_message(&lo, &hi, v, why)))
                }
            }
            Rule::Count { lo, hi } => match v {
                Value::Int(i) if (lo..=hi).contains(&i) => Ok(()),
                _ if hi == lo + 1 => {
                    Err(named(name, crate::msg!(" must be {lo} or {hi} (got {v})")))
                }
                _ => Err(named(
                    name,
                    crate::msg!(" must lie in {lo}..={hi} (got {v})"),
                )),
            },
        }
    }
}

/// `name` followed by `rest` (the parameter's name stays in the message without `std`).
fn named(name: &str, rest: crate::message::Message) -> crate::message::Message {
    crate::message::Message::concat(&[name, &rest])
}

/// The refusal of an unknown code `v` for the parameter `name` of the code list `list`
/// (with `std`, the allowed codes listed).
pub fn unknown_code(name: &str, v: Value, list: &CodeList) -> crate::message::Message {
    #[cfg(feature = "std")]
    return crate::msg!("unknown {name} code {v} (allowed: {})", list.codes());
    #[cfg(not(feature = "std"))]
    return crate::message::Message::concat(&["unknown ", name, " code"]);
}

/// " must lie in (lo, hi] (got v)" and the rule's reason.
#[cfg(feature = "std")]
fn interval_message(lo: &End, hi: &End, v: Value, why: &str) -> crate::message::Message {
    crate::msg!(
        " must lie in {} (got {v}){why}",
        interval_words(lo, hi).trim_start_matches("in ")
    )
}

/// " must lie in its interval" and the rule's reason (no numbers without `std`).
#[cfg(not(feature = "std"))]
fn interval_message(_: &End, _: &End, _: Value, why: &str) -> crate::message::Message {
    crate::message::Message::concat(&[" must lie in its interval", why])
}

#[cfg(feature = "std")]
fn interval_words(lo: &End, hi: &End) -> String {
    if hi.at == f64::INFINITY {
        return format!("{} {}", if lo.closed { ">=" } else { ">" }, num(lo.at));
    }
    format!(
        "in {}{}, {}{}",
        if lo.closed { "[" } else { "(" },
        num(lo.at),
        num(hi.at),
        if hi.closed { "]" } else { ")" }
    )
}

/// Which front ends take a parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Fronts {
    /// A field of the C ABI's configuration struct (and so of the FMU and the Python
    /// package, which take every C field).
    pub c: bool,
    /// A key of a scenario file's `[[filter]]` table (its name, below).
    pub scenario: Option<&'static str>,
}

/// One declared parameter of a configuration `C` (see the module documentation).
pub struct Param<C: 'static> {
    /// The field's name (the C field, the settings' name of a scalar).
    pub name: &'static str,
    /// Type.
    pub kind: Kind,
    /// Its scalars, in order (one for a scalar parameter).
    pub elements: &'static [Element],
    /// What it is.
    pub description: &'static str,
    /// Domain of each element.
    pub rule: Rule,
    /// Front ends.
    pub fronts: Fronts,
    /// Its place in a saved state's configuration section (and so in its fingerprint):
    /// slots are numbered once and never change; `None` only for settings the results do
    /// not depend on.
    pub slot: Option<u16>,
    /// Element `i` of the parameter in a configuration.
    pub get: fn(&C, usize) -> Value,
    /// Store element `i` (the type's own check only: a code of its list, a count that
    /// fits; the [`Rule`] is checked by [`Param::check`]).
    pub set: fn(&mut C, usize, Value) -> Result<(), crate::message::Message>,
}

impl<C> core::fmt::Debug for Param<C> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Param")
            .field("name", &self.name)
            .field("kind", &self.kind)
            .field("elements", &self.elements)
            .field("rule", &self.rule)
            .finish()
    }
}

impl<C> Param<C> {
    /// The description of element `e` (its own, else the parameter's).
    pub fn element_description(&self, e: &Element) -> &'static str {
        if e.description.is_empty() {
            self.description
        } else {
            e.description
        }
    }

    /// Check every element of this parameter in `c` against its [`Rule`].
    pub fn check(&self, c: &C) -> Result<(), crate::message::Message> {
        for (i, e) in self.elements.iter().enumerate() {
            self.rule.check(e.name, (self.get)(c, i))?;
        }
        Ok(())
    }

    /// Store element `i` of this parameter in `c` as a front end hands it over: a count
    /// outside its rule (a negative C `int`) is refused with the rule's message, anything
    /// the type cannot hold (an unknown code, a flag other than 0 or 1) with the type's.
    /// The other rules are checked when the whole configuration is validated.
    pub fn assign(&self, c: &mut C, i: usize, v: Value) -> Result<(), crate::message::Message> {
        if let (Kind::Count, Some(e)) = (self.kind, self.elements.get(i)) {
            self.rule.check(e.name, v)?;
        }
        (self.set)(c, i, v)
    }

    #[cfg(feature = "std")]
    /// The name a saved state gives element `i`: the field's name, with `[i]` for an array.
    pub fn setting_name(&self, i: usize) -> String {
        if self.elements.len() == 1 {
            self.name.to_string()
        } else {
            format!("{}[{i}]", self.name)
        }
    }
}

/// A Rust type that a parameter can have: how its elements read and write as [`Value`]s.
pub trait Field: Sized {
    /// The type as the front ends see it.
    const KIND: Kind;
    /// A placeholder the declared default then overwrites.
    const ZERO: Self;
    /// Element `i`.
    fn get(&self, i: usize) -> Value;
    /// Store element `i`, refusing what the type cannot hold (`name` names it).
    fn set(&mut self, i: usize, v: Value, name: &str) -> Result<(), crate::message::Message>;
}

impl Field for f64 {
    const KIND: Kind = Kind::Real;
    const ZERO: Self = 0.0;
    fn get(&self, _: usize) -> Value {
        Value::Real(*self)
    }
    fn set(&mut self, _: usize, v: Value, _: &str) -> Result<(), crate::message::Message> {
        *self = v.as_f64();
        Ok(())
    }
}

impl<const N: usize> Field for [f64; N] {
    const KIND: Kind = Kind::Real;
    const ZERO: Self = [0.0; N];
    fn get(&self, i: usize) -> Value {
        Value::Real(<[f64]>::get(self, i).copied().unwrap_or(f64::NAN))
    }
    fn set(&mut self, i: usize, v: Value, _: &str) -> Result<(), crate::message::Message> {
        if let Some(x) = <[f64]>::get_mut(self, i) {
            *x = v.as_f64();
        }
        Ok(())
    }
}

impl Field for usize {
    const KIND: Kind = Kind::Count;
    const ZERO: Self = 0;
    fn get(&self, _: usize) -> Value {
        Value::Int(i64::try_from(*self).unwrap_or(i64::MAX))
    }
    /// A negative or fractional count is refused here; its range is the [`Rule`]'s.
    fn set(&mut self, _: usize, v: Value, name: &str) -> Result<(), crate::message::Message> {
        match v {
            Value::Int(i) => {
                *self = usize::try_from(i)
                    .map_err(|_| crate::msg!("{name} must be a count >= 0 (got {i})"))?;
                Ok(())
            }
            Value::Real(x) => Err(crate::msg!("{name} must be an integer (got {})", num(x))),
        }
    }
}

impl Field for u64 {
    const KIND: Kind = Kind::Seed;
    const ZERO: Self = 0;
    fn get(&self, _: usize) -> Value {
        Value::Int(*self as i64)
    }
    /// The 64 bits of the integer (a negative `i64` is the seed with those bits).
    fn set(&mut self, _: usize, v: Value, name: &str) -> Result<(), crate::message::Message> {
        match v {
            Value::Int(i) => {
                *self = i as u64;
                Ok(())
            }
            Value::Real(x) => Err(crate::msg!("{name} must be an integer (got {})", num(x))),
        }
    }
}

impl Field for bool {
    const KIND: Kind = Kind::Bool;
    const ZERO: Self = false;
    fn get(&self, _: usize) -> Value {
        Value::Int(i64::from(*self))
    }
    fn set(&mut self, _: usize, v: Value, name: &str) -> Result<(), crate::message::Message> {
        match v {
            Value::Int(0) => *self = false,
            Value::Int(1) => *self = true,
            other => return Err(crate::msg!("{name} must be 0 or 1 (got {other})")),
        }
        Ok(())
    }
}

/// Declare an enum of stable codes with its [`CodeList`] and [`Field`] implementation:
///
/// ```ignore
/// codes! {
///     /// Doc of the enum.
///     #[derive(Default)]
///     pub enum FilterKind: FILTER_CODES = "Filter", "relnav_filter", "RELNAV_FILTER_", true {
///         /// Extended Kalman filter.
///         #[default]
///         Ekf = 1, "ekf", "Extended Kalman filter (Joseph form)";
///         ...
///     }
/// }
/// ```
///
/// writes the enum (`#[repr(i32)]`, `Debug, Clone, Copy, PartialEq, Eq`), `ALL` (every
/// variant in code order), `from_code`, `code`, `name`, the `CodeList` constant and
/// `Field`.
#[macro_export]
macro_rules! codes {
    (
        $(#[$meta:meta])*
        $vis:vis enum $name:ident : $list:ident = $lname:literal, $ctype:literal, $cprefix:literal, $cenum:literal {
            $(
                $(#[$vmeta:meta])*
                $variant:ident = $code:literal, $iname:literal, $idesc:literal;
            )+
        }
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        #[repr(i32)]
        $vis enum $name {
            $(
                $(#[$vmeta])*
                $variant = $code,
            )+
        }

        #[doc = concat!("The codes of [`", stringify!($name), "`], with their names and descriptions.")]
        $vis const $list: $crate::params::CodeList = $crate::params::CodeList {
            name: $lname,
            c_type: $ctype,
            c_prefix: $cprefix,
            c_enum: $cenum,
            items: &[
                $( $crate::params::CodeItem { name: $iname, code: $code, description: $idesc }, )+
            ],
        };

        impl $name {
            /// Every variant, in code order.
            pub const ALL: [$name; [$( stringify!($variant) ),+].len()] = [ $( $name::$variant, )+ ];

            /// The variant with the stable code `code`.
            pub fn from_code(code: i32) -> Option<Self> {
                match code {
                    $( $code => Some($name::$variant), )+
                    _ => None,
                }
            }

            /// The stable code.
            pub fn code(self) -> i32 {
                self as i32
            }

            /// The lower-case name.
            pub fn name(self) -> &'static str {
                match self {
                    $( $name::$variant => $iname, )+
                }
            }

            /// The variant named `name` (ASCII case-insensitive).
            pub fn from_name(name: &str) -> Option<Self> {
                Self::ALL.iter().copied().find(|v| v.name().eq_ignore_ascii_case(name))
            }
        }

        impl $crate::params::Field for $name {
            const KIND: $crate::params::Kind = $crate::params::Kind::Code(&$list);
            const ZERO: Self = $name::ALL[0];
            fn get(&self, _: usize) -> $crate::params::Value {
                $crate::params::Value::Int(i64::from(*self as i32))
            }
            fn set(&mut self, _: usize, v: $crate::params::Value, name: &str) -> Result<(), $crate::message::Message> {
                let code = v.as_int().and_then(|c| i32::try_from(c).ok());
                *self = code
                    .and_then(Self::from_code)
                    .ok_or_else(|| $crate::params::unknown_code(name, v, &$list))?;
                Ok(())
            }
        }
    };
}

/// Declare a configuration struct and its parameter table in one go:
///
/// ```ignore
/// config! {
///     /// Doc of the struct.
///     pub struct NavConfig, PARAMS;
///     /// Target mean motion (the field's documentation).
///     mean_motion: f64 {
///         elements: [("mean_motion", 3, "rad/s", 0.00087, "")],
///         rule: Rule::Positive, c: true, scenario: None, slot: Some(2),
///         description: "Mean motion of the target's circular orbit (> 0)",
///     },
/// }
/// ```
///
/// writes the struct (fields in declaration order, which is also the C struct's order),
/// its `Default` (the elements' defaults) and `PARAMS: &[Param]`.
/// An element is `(name, value reference or -, unit, default, description or "")`; the default
/// is a literal: a real for `f64` fields, an integer for counts, codes, seeds and flags.
#[macro_export]
macro_rules! config {
    (
        $(#[$smeta:meta])*
        $vis:vis struct $name:ident, $table:ident;
        $(
            $(#[$fmeta:meta])*
            $field:ident : $ty:ty {
                elements: [ $( ($ename:literal, $eid:tt, $eunit:literal, $edef:expr, $edesc:literal) ),+ $(,)? ],
                rule: $rule:expr,
                c: $c:literal,
                scenario: $scen:expr,
                slot: $slot:expr,
                description: $desc:literal $(,)?
            }
        ),* $(,)?
    ) => {
        $(#[$smeta])*
        #[derive(Debug, Clone, Copy, PartialEq)]
        $vis struct $name {
            $(
                #[doc = $desc]
                $(#[$fmeta])*
                pub $field: $ty,
            )*
        }

        /// Every parameter of the configuration, in declaration order.
        $vis const $table: &[$crate::params::Param<$name>] = &[
            $(
                $crate::params::Param {
                    name: stringify!($field),
                    kind: <$ty as $crate::params::Field>::KIND,
                    elements: &[
                        $(
                            $crate::params::Element {
                                name: $ename,
                                id: $crate::config!(@id $eid),
                                unit: $eunit,
                                default: $crate::config!(@value <$ty as $crate::params::Field>::KIND, $edef),
                                description: $edesc,
                            },
                        )+
                    ],
                    description: $desc,
                    rule: $rule,
                    fronts: $crate::params::Fronts { c: $c, scenario: $scen },
                    slot: $slot,
                    get: |c, i| $crate::params::Field::get(&c.$field, i),
                    set: |c, i, v| $crate::params::Field::set(&mut c.$field, i, v, stringify!($field)),
                },
            )*
        ];

        impl Default for $name {
            /// The declared defaults of every parameter.
            fn default() -> Self {
                let mut c = Self {
                    $( $field: <$ty as $crate::params::Field>::ZERO, )*
                };
                for p in $table {
                    for (i, e) in p.elements.iter().enumerate() {
                        // a default the type cannot hold fails the schema's own test
                        let _ = (p.set)(&mut c, i, e.default);
                    }
                }
                c
            }
        }
    };
    (@id -) => { None };
    (@id $n:literal) => { Some($n) };
    (@value $kind:expr, $v:expr) => {
        match $kind {
            $crate::params::Kind::Real => $crate::params::Value::Real($v as f64),
            _ => $crate::params::Value::Int($v as i64),
        }
    };
}

/// An interval rule's end that belongs to the interval.
pub const fn closed(at: f64) -> End {
    End { at, closed: true }
}

/// An interval rule's end that does not.
pub const fn open(at: f64) -> End {
    End { at, closed: false }
}

/// The value reference of the element named `name` in a parameter table, at compile time
/// (the front ends' named constants; `None`: no element of that name has one).
pub const fn id_of<C>(table: &[Param<C>], name: &str) -> Option<u32> {
    let mut k = 0;
    while k < table.len() {
        let elements = table[k].elements;
        let mut i = 0;
        while i < elements.len() {
            if let Some(id) = elements[i].id {
                if str_eq(elements[i].name, name) {
                    return Some(id);
                }
            }
            i += 1;
        }
        k += 1;
    }
    None
}

/// `a == b` in a `const fn`.
const fn str_eq(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// A parameter table's element with value reference `id`, and its parameter and index.
pub fn element_by_id<C>(table: &'static [Param<C>], id: u32) -> Option<(&'static Param<C>, usize)> {
    table.iter().find_map(|p| {
        p.elements
            .iter()
            .position(|e| e.id == Some(id))
            .map(|i| (p, i))
    })
}

/// A parameter table's element named `name`, and its parameter and index.
pub fn element_by_name<C>(
    table: &'static [Param<C>],
    name: &str,
) -> Option<(&'static Param<C>, usize)> {
    table.iter().find_map(|p| {
        p.elements
            .iter()
            .position(|e| e.name == name)
            .map(|i| (p, i))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rule_messages() {
        let m = |r: Rule, v: Value| r.check("p", v).err().unwrap_or_default();
        assert_eq!(
            m(Rule::Positive, Value::Real(-1.0)),
            "p must be finite and > 0 (got -1)"
        );
        assert_eq!(
            m(Rule::NonNegative, Value::Real(f64::NAN)),
            "p must be finite and >= 0 (got NaN)"
        );
        assert_eq!(
            m(
                Rule::Interval {
                    lo: open(0.0),
                    hi: closed(1.0),
                    why: ": why"
                },
                Value::Real(2.0)
            ),
            "p must lie in (0, 1] (got 2): why"
        );
        assert_eq!(
            m(
                Rule::Interval {
                    lo: closed(1.0),
                    hi: open(f64::INFINITY),
                    why: ""
                },
                Value::Real(0.5)
            ),
            "p must be finite and >= 1 (got 0.5)"
        );
        assert_eq!(
            m(Rule::Count { lo: 1, hi: 512 }, Value::Int(0)),
            "p must lie in 1..=512 (got 0)"
        );
        assert_eq!(
            m(Rule::Count { lo: 2, hi: 3 }, Value::Int(5)),
            "p must be 2 or 3 (got 5)"
        );
        assert!(Rule::Interval {
            lo: open(0.0),
            hi: open(1.0),
            why: ""
        }
        .check("p", Value::Real(0.5))
        .is_ok());
        assert!(Rule::Positive
            .check("p", Value::Real(f64::INFINITY))
            .is_err());
        assert_eq!(
            Rule::Interval {
                lo: open(0.0),
                hi: closed(1.0),
                why: ""
            }
            .words(),
            "in (0, 1]"
        );
        assert_eq!(Rule::Count { lo: 2, hi: 3 }.words(), "2 or 3");
    }

    #[test]
    fn bool_and_count_fields_refuse_what_they_cannot_hold() {
        let mut b = false;
        assert_eq!(
            b.set(0, Value::Int(2), "pf_move").err().as_deref(),
            Some("pf_move must be 0 or 1 (got 2)")
        );
        let mut n = 0usize;
        assert!(n.set(0, Value::Int(-1), "particles").is_err());
        assert!(n.set(0, Value::Int(7), "particles").is_ok() && n == 7);
        let mut s = 0u64;
        assert!(s.set(0, Value::Int(-1), "seed").is_ok() && s == u64::MAX);
    }
}
