//! The C ABI's configuration (`src/config_fields.rs`: the enums of the code lists, the
//! `relnav_config` struct and its element access) is generated from relnav-core's
//! parameter table and checked in, so that cbindgen sees plain Rust; this test renders it
//! again and fails when the checked-in file is stale. Regenerate with
//! `RELNAV_BLESS_CODEGEN=1 cargo test --test c_config` (then the header:
//! `RELNAV_BLESS_HEADER=1 cargo test --test header`).
#![allow(clippy::panic, clippy::unwrap_used, clippy::expect_used)] // test code

use relnav_core::nav::config::CODE_LISTS;
use relnav_core::nav::{NavConfig, PARAMS};
use relnav_core::params::{Kind, Param, Rule, Value};
use std::fmt::Write;
use std::path::PathBuf;

/// The C type of a parameter (Rust spelling, as cbindgen reads it).
fn c_type(p: &Param<NavConfig>) -> String {
    let scalar = match p.kind {
        Kind::Real => "f64",
        Kind::Count | Kind::Bool | Kind::Code(_) => "i32",
        Kind::Seed => "u64",
    };
    if p.elements.len() == 1 {
        scalar.to_string()
    } else {
        format!("[{scalar}; {}]", p.elements.len())
    }
}

fn value_words(p: &Param<NavConfig>, v: Value) -> String {
    match (p.kind, v) {
        (Kind::Code(list), Value::Int(c)) => match list.item(c) {
            Some(it) => format!("{c} ({})", it.name),
            None => format!("{c}"),
        },
        _ => v.to_string(),
    }
}

/// The doc lines of a field: its description, its elements' own where they have one,
/// the allowed values and the default.
fn field_doc(p: &Param<NavConfig>) -> Vec<String> {
    let mut doc = vec![format!("{}.", p.description.trim_end_matches('.'))];
    if p.elements.len() > 1 {
        for (i, e) in p.elements.iter().enumerate() {
            let unit = if e.unit.is_empty() {
                String::new()
            } else {
                format!(" [{}]", e.unit)
            };
            doc.push(format!("`[{i}]` {}{unit}", e.name));
        }
    } else if !p.elements[0].unit.is_empty() {
        doc.push(format!("Unit: {}.", p.elements[0].unit));
    }
    match p.kind {
        Kind::Code(list) => doc.push(format!("A `{}` code: {}.", list.c_type, list.codes())),
        Kind::Bool => doc.push("0 or 1.".into()),
        _ => {}
    }
    let words = p.rule.words();
    if !words.is_empty() && p.rule != Rule::Finite {
        doc.push(format!("Allowed: {words}."));
    }
    let defaults: Vec<String> = p
        .elements
        .iter()
        .map(|e| value_words(p, e.default))
        .collect();
    doc.push(format!("Default: {}.", defaults.join(", ")));
    doc
}

fn render() -> String {
    let mut s = String::new();
    let w = &mut s;
    writeln!(
        w,
        "//! Generated from relnav-core's parameter table (`relnav_core::nav::PARAMS`) by"
    )
    .unwrap();
    writeln!(
        w,
        "//! `RELNAV_BLESS_CODEGEN=1 cargo test --test c_config`: do not edit. The code lists'"
    )
    .unwrap();
    writeln!(
        w,
        "//! enums, the `relnav_config` struct (one field per parameter, in the table's order)"
    )
    .unwrap();
    writeln!(
        w,
        "//! and the access to its fields by parameter and element that `config.rs` converts with."
    )
    .unwrap();
    writeln!(w).unwrap();
    writeln!(w, "use relnav_core::params::Value;").unwrap();
    for list in CODE_LISTS {
        if !list.c_enum {
            continue;
        }
        writeln!(w).unwrap();
        writeln!(
            w,
            "/// {} codes (`relnav_config` holds them as plain integers, so that an unknown",
            list.name
        )
        .unwrap();
        writeln!(w, "/// value is reported, not undefined behaviour).").unwrap();
        writeln!(w, "#[repr(i32)]").unwrap();
        writeln!(w, "#[derive(Debug, Clone, Copy)]").unwrap();
        writeln!(w, "pub enum {} {{", list.c_type).unwrap();
        for it in list.items {
            writeln!(w, "    /// {}.", it.description.trim_end_matches('.')).unwrap();
            writeln!(
                w,
                "    {}{} = {},",
                list.c_prefix,
                it.name.to_ascii_uppercase(),
                it.code
            )
            .unwrap();
        }
        writeln!(w, "}}").unwrap();
    }
    writeln!(w).unwrap();
    writeln!(
        w,
        "/// Estimator configuration. Get the defaults (paper 000's example) from"
    )
    .unwrap();
    writeln!(
        w,
        "/// `relnav_config_default`, then change what you need. Codes and flags are plain"
    )
    .unwrap();
    writeln!(
        w,
        "/// integers, so that an unknown value is reported, not undefined behaviour."
    )
    .unwrap();
    writeln!(w, "#[repr(C)]").unwrap();
    writeln!(w, "#[derive(Debug, Clone, Copy)]").unwrap();
    writeln!(w, "pub struct relnav_config {{").unwrap();
    for p in PARAMS {
        for line in field_doc(p) {
            writeln!(w, "    /// {line}").unwrap();
        }
        writeln!(w, "    pub {}: {},", p.name, c_type(p)).unwrap();
    }
    writeln!(w, "}}").unwrap();
    writeln!(w).unwrap();
    writeln!(w, "impl relnav_config {{").unwrap();
    writeln!(w, "    /// Every field zero.").unwrap();
    writeln!(w, "    pub(crate) const ZERO: Self = Self {{").unwrap();
    for p in PARAMS {
        let zero = match (p.kind, p.elements.len()) {
            (Kind::Real, 1) => "0.0".to_string(),
            (Kind::Real, n) => format!("[0.0; {n}]"),
            (_, 1) => "0".to_string(),
            (_, n) => format!("[0; {n}]"),
        };
        writeln!(w, "        {}: {zero},", p.name).unwrap();
    }
    writeln!(w, "    }};").unwrap();
    writeln!(w).unwrap();
    writeln!(
        w,
        "    /// Element `i` of parameter `k` (its index in the table)."
    )
    .unwrap();
    writeln!(
        w,
        "    pub(crate) fn element(&self, k: usize, i: usize) -> Option<Value> {{"
    )
    .unwrap();
    writeln!(w, "        Some(match k {{").unwrap();
    for (k, p) in PARAMS.iter().enumerate() {
        let field = if p.elements.len() == 1 {
            format!("self.{}", p.name)
        } else {
            format!("*self.{}.get(i)?", p.name)
        };
        let value = match p.kind {
            Kind::Real => format!("Value::Real({field})"),
            Kind::Seed => format!("Value::Int({field} as i64)"),
            _ => format!("Value::Int(i64::from({field}))"),
        };
        writeln!(w, "            {k} => {value},").unwrap();
    }
    writeln!(w, "            _ => return None,").unwrap();
    writeln!(w, "        }})").unwrap();
    writeln!(w, "    }}").unwrap();
    writeln!(w).unwrap();
    writeln!(
        w,
        "    /// Store element `i` of parameter `k`: a real as it is, an integer saturated to"
    )
    .unwrap();
    writeln!(
        w,
        "    /// the field's type (a count beyond `i32` becomes `i32::MAX`)."
    )
    .unwrap();
    writeln!(
        w,
        "    pub(crate) fn set_element(&mut self, k: usize, i: usize, v: Value) {{"
    )
    .unwrap();
    writeln!(w, "        match k {{").unwrap();
    for (k, p) in PARAMS.iter().enumerate() {
        let target = if p.elements.len() == 1 {
            format!("self.{}", p.name)
        } else {
            format!("self.{}[i]", p.name)
        };
        let value = match p.kind {
            Kind::Real => "v.as_f64()".to_string(),
            Kind::Seed => "v.as_int().unwrap_or(0) as u64".to_string(),
            _ => {
                "v.as_int().map_or(i32::MAX, |x| i32::try_from(x).unwrap_or(i32::MAX))".to_string()
            }
        };
        if p.elements.len() == 1 {
            writeln!(w, "            {k} => {target} = {value},").unwrap();
        } else {
            writeln!(
                w,
                "            {k} if i < {} => {target} = {value},",
                p.elements.len()
            )
            .unwrap();
        }
    }
    writeln!(w, "            _ => {{}}").unwrap();
    writeln!(w, "        }}").unwrap();
    writeln!(w, "    }}").unwrap();
    writeln!(w, "}}").unwrap();
    s
}

#[test]
fn c_config_is_up_to_date() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let path = root.join("src/config_fields.rs");
    let generated = render();
    if std::env::var_os("RELNAV_BLESS_CODEGEN").is_some() {
        std::fs::write(&path, &generated).unwrap_or_else(|e| panic!("write {path:?}: {e}"));
        return;
    }
    let checked_in = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        checked_in == generated,
        "src/config_fields.rs is stale: run `RELNAV_BLESS_CODEGEN=1 cargo test --test c_config`, \
         then `RELNAV_BLESS_HEADER=1 cargo test --test header`, and commit both"
    );
}

/// Every code list the C struct names is an enum of the header, an `int32_t` in C (cbindgen
/// exports an enum only when `cbindgen.toml` includes it by name).
#[test]
fn every_code_list_is_in_the_header() {
    let header =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/include/relnav.h")).unwrap();
    for list in CODE_LISTS.iter().filter(|l| l.c_enum) {
        assert!(
            header.contains(&format!("\nenum {}\n", list.c_type))
                && header.contains(&format!("typedef int32_t {};", list.c_type)),
            "{} is not in include/relnav.h: add it to cbindgen.toml's export.include",
            list.c_type
        );
    }
}
