//! FMI 2.0's `modelDescription.xml`, generated from a model's [`ModelInfo`] (its variable
//! table), and the GUID derived from it; the variable table as Markdown for the
//! documentation.
//!
//! The GUID is a name-based UUID (version 5, SHA-1) of the XML text itself, with
//! placeholders where the GUID and `generationDateAndTime` go, as the FMI standard suggests
//! (a fingerprint of the relevant information in the XML): the binary computes the same
//! value from the same table, so archive and binary cannot disagree. Nothing in the XML
//! depends on the build machine or the build time: `generationDateAndTime` is the commit
//! date of the source ([`GENERATION_DATE`], set by `build.rs`), so one commit gives one
//! XML; the date is left out of the GUID, so a commit that changes nothing else keeps it
//! (a library built before the commit and an archive packed after it still match).

use crate::logging::LOG_CATEGORIES;
use crate::model::ModelInfo;
use crate::variables::{Causality, VarDef, VarType, Variability, UNITS};
use std::fmt::Write;

pub(crate) const GUID_PLACEHOLDER: &str = "@GUID@";
pub(crate) const DATE_PLACEHOLDER: &str = "@DATE@";

/// `generationDateAndTime` (UTC, `xs:dateTime`): `SOURCE_DATE_EPOCH` when set at build
/// time, else the commit date of `HEAD` (`git log -1 --format=%ct`), else
/// 1970-01-01T00:00:00Z (a source tree without git); computed by `build.rs`.
pub const GENERATION_DATE: &str = env!("RELNAV_GENERATION_DATE");

/// A variable's description as published: for a code list, followed by
/// `Codes: 1 ekf, 2 ukf, ...` (the item names stay documented in the XML itself).
pub fn published_description(v: &VarDef) -> String {
    match v.ty {
        VarType::Code(t) => format!("{}. Codes: {}", v.description, t.codes()),
        _ => v.description.to_string(),
    }
}

pub(crate) fn escape(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            '\'' => o.push_str("&apos;"),
            c => o.push(c),
        }
    }
    o
}

pub(crate) fn causality(c: Causality) -> &'static str {
    match c {
        Causality::Parameter => "parameter",
        Causality::Input => "input",
        Causality::Output => "output",
    }
}

pub(crate) fn variability(v: Variability) -> &'static str {
    match v {
        Variability::Fixed => "fixed",
        Variability::Discrete => "discrete",
        Variability::Continuous => "continuous",
    }
}

/// `<UnitDefinitions>` with the units of [`UNITS`] that `used` accepts, in that list's
/// order (both versions' descriptions).
pub(crate) fn write_units(x: &mut String, used: impl Fn(&str) -> bool) {
    let _ = writeln!(x, "  <UnitDefinitions>");
    for (name, [kg, m, s, rad]) in UNITS.iter().filter(|(u, _)| used(u)) {
        let mut attrs = String::new();
        for (n, e) in [("kg", kg), ("m", m), ("s", s), ("rad", rad)] {
            if *e != 0 {
                let _ = write!(attrs, r#" {n}="{e}""#);
            }
        }
        let _ = writeln!(
            x,
            r#"    <Unit name="{}"><BaseUnit{attrs}/></Unit>"#,
            escape(name)
        );
    }
    let _ = writeln!(x, "  </UnitDefinitions>");
}

/// `<LogCategories>` of [`LOG_CATEGORIES`].
pub(crate) fn write_log_categories(x: &mut String) {
    let _ = writeln!(x, "  <LogCategories>");
    for (n, d) in LOG_CATEGORIES {
        let _ = writeln!(
            x,
            r#"    <Category name="{n}" description="{}"/>"#,
            escape(d)
        );
    }
    let _ = writeln!(x, "  </LogCategories>");
}

/// `<DefaultExperiment>` of the model.
pub(crate) fn write_default_experiment(x: &mut String, info: &ModelInfo) {
    let e = info.default_experiment;
    let _ = writeln!(
        x,
        r#"  <DefaultExperiment startTime="{}" stopTime="{}" stepSize="{}"/>"#,
        e.start, e.stop, e.step
    );
}

fn body(info: &ModelInfo) -> String {
    let mut x = String::new();
    // write! into a String cannot fail; the results are ignored deliberately.
    let _ = writeln!(x, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        x,
        r#"<fmiModelDescription fmiVersion="2.0" modelName="{}" guid="{GUID_PLACEHOLDER}" description="{}" author="relnav developers" version="{}" generationTool="relnav {}" generationDateAndTime="{DATE_PLACEHOLDER}" variableNamingConvention="flat">"#,
        info.model_identifier,
        escape(info.description),
        relnav_core::VERSION,
        relnav_core::VERSION
    );
    let _ = writeln!(
        x,
        r#"  <CoSimulation modelIdentifier="{}" needsExecutionTool="false" canHandleVariableCommunicationStepSize="true" canInterpolateInputs="false" maxOutputDerivativeOrder="0" canRunAsynchronuously="false" canBeInstantiatedOnlyOncePerProcess="false" canNotUseMemoryManagementFunctions="true" canGetAndSetFMUstate="true" canSerializeFMUstate="true" providesDirectionalDerivative="false"/>"#,
        info.model_identifier
    );
    // the units the table uses
    write_units(&mut x, |u| {
        info.variables
            .iter()
            .any(|v| matches!(v.ty, VarType::Real(w) if w == u))
    });
    write_log_categories(&mut x);
    write_default_experiment(&mut x, info);
    let _ = writeln!(x, "  <ModelVariables>");
    for v in info.variables {
        let _ = writeln!(
            x,
            r#"    <!-- index {} --><ScalarVariable name="{}" valueReference="{}" description="{}" causality="{}" variability="{}">"#,
            v.vr + 1,
            v.name,
            v.vr,
            escape(&published_description(v)),
            causality(v.causality),
            variability(v.variability)
        );
        // parameters are initial="exact" and inputs need a start; outputs are calculated
        let start = |s: String| {
            if v.causality == Causality::Output {
                String::new()
            } else {
                format!(r#" start="{s}""#)
            }
        };
        let elem = match v.ty {
            VarType::Real(u) => {
                let unit = if u.is_empty() {
                    String::new()
                } else {
                    format!(r#" unit="{}""#, escape(u))
                };
                format!(r#"<Real{unit}{}/>"#, start(format!("{}", v.start)))
            }
            VarType::Integer => format!("<Integer{}/>", start(format!("{}", v.start as i64))),
            VarType::Boolean => format!(
                "<Boolean{}/>",
                start(if v.start != 0.0 { "true" } else { "false" }.to_string())
            ),
            VarType::Code(t) => {
                let (lo, hi) = t.range();
                format!(
                    r#"<Integer min="{lo}" max="{hi}"{}/>"#,
                    start(format!("{}", v.start as i64))
                )
            }
        };
        let _ = writeln!(x, "      {elem}");
        let _ = writeln!(x, "    </ScalarVariable>");
    }
    let _ = writeln!(x, "  </ModelVariables>");
    let _ = writeln!(x, "  <ModelStructure>");
    let outputs: Vec<_> = info
        .variables
        .iter()
        .filter(|v| v.causality == Causality::Output)
        .collect();
    let _ = writeln!(x, "    <Outputs>");
    for v in &outputs {
        // dependencies="": no direct feedthrough, outputs change only in fmi2DoStep (true of
        // every model here: relnav, the plant and the guidance law)
        let _ = writeln!(
            x,
            r#"      <Unknown index="{}" dependencies=""/>"#,
            v.vr + 1
        );
    }
    let _ = writeln!(x, "    </Outputs>");
    let _ = writeln!(x, "    <InitialUnknowns>");
    for v in &outputs {
        // initial values depend on the parameters (relnav: initial estimate and sigma)
        let _ = writeln!(x, r#"      <Unknown index="{}"/>"#, v.vr + 1);
    }
    let _ = writeln!(x, "    </InitialUnknowns>");
    let _ = writeln!(x, "  </ModelStructure>");
    let _ = writeln!(x, "</fmiModelDescription>");
    x
}

/// The GUID and the XML of a body (with its GUID and date placeholders) for a given
/// `generationDateAndTime`. The GUID is a UUID v5 of the body *before* the date goes in:
/// it fingerprints the model's interface (variables, units, capabilities, description,
/// version), not the commit that built it, so a commit that changes nothing in the XML
/// but its date keeps the GUID, and a binary built before such a commit still matches an
/// archive packed after it.
pub(crate) fn finish(body: &str, date: &str) -> (String, String) {
    let id = uuid::Uuid::new_v5(&uuid::Uuid::NAMESPACE_URL, body.as_bytes());
    let guid = format!("{{{id}}}");
    let xml = body
        .replacen(GUID_PLACEHOLDER, &guid, 1)
        .replacen(DATE_PLACEHOLDER, date, 1);
    (guid, xml)
}

fn generated(info: &'static ModelInfo) -> &'static (String, String) {
    info.generated
        .fmi2
        .get_or_init(|| finish(&body(info), GENERATION_DATE))
}

/// A model's GUID, `{xxxxxxxx-...}`.
pub fn guid_of(info: &'static ModelInfo) -> &'static str {
    &generated(info).0
}

/// A model's full `modelDescription.xml` text.
pub fn model_description_of(info: &'static ModelInfo) -> &'static str {
    &generated(info).1
}

/// A model's variable table as Markdown (the README's and `docs/kit.md`'s tables; tests
/// keep them in sync).
pub fn variables_markdown_of(info: &ModelInfo) -> String {
    let mut x = String::new();
    let _ = writeln!(
        x,
        "| name | vr | causality | variability | type | unit | start | description |"
    );
    let _ = writeln!(x, "|---|---:|---|---|---|---|---|---|");
    for v in info.variables {
        let (ty, unit, start) = match v.ty {
            VarType::Real(u) => ("Real", u.to_string(), format!("{}", v.start)),
            VarType::Integer => ("Integer", String::new(), format!("{}", v.start as i64)),
            VarType::Boolean => (
                "Boolean",
                String::new(),
                if v.start != 0.0 { "true" } else { "false" }.to_string(),
            ),
            VarType::Code(t) => {
                let item = t.item_at(v.start).map(|it| it.name).unwrap_or("");
                (
                    "Integer",
                    String::new(),
                    format!("{} ({item})", v.start as i64),
                )
            }
        };
        let start = if v.causality == Causality::Output {
            "—".to_string()
        } else {
            start
        };
        let _ = writeln!(
            x,
            "| `{}` | {} | {} | {} | {ty} | {unit} | {start} | {} |",
            v.name,
            v.vr,
            causality(v.causality),
            variability(v.variability),
            published_description(v)
        );
    }
    let _ = writeln!(x);
    let _ = writeln!(
        x,
        "Codes of the Integer parameters that select a method (the C ABI's enums; a code outside the list is refused at `fmi2SetInteger`):"
    );
    let _ = writeln!(x);
    let _ = writeln!(x, "| parameter | code | name | meaning |");
    let _ = writeln!(x, "|---|---:|---|---|");
    for v in info.variables {
        if let VarType::Code(t) = v.ty {
            for it in t.items {
                let (n, code, d) = (it.name, it.code, it.description);
                let _ = writeln!(x, "| `{}` | {code} | `{n}` | {d} |", v.name);
            }
        }
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{DefaultExperiment, Generated};
    use crate::variables::{CodeItem, CodeList};

    static CODES: CodeList = CodeList {
        name: "Codes",
        c_type: "codes",
        c_prefix: "CODES_",
        c_enum: false,
        items: &[
            CodeItem {
                name: "a",
                code: 1,
                description: "first & only",
            },
            CodeItem {
                name: "c",
                code: 3,
                description: "third",
            },
        ],
    };

    crate::variables! {
        MODE = 0: "mode", Parameter, Fixed, VarType::Code(&CODES), 3.0, "A <code>";
        GAIN = 1: "gain", Input, Discrete, VarType::Real("m/s"), 0.5, "An input";
        ON = 2: "on", Input, Discrete, VarType::Boolean, 1.0, "A switch";
        FMI_STATUS = 3: "fmi_status", Output, Discrete, VarType::Integer, 0.0, "Status";
    }

    static INFO: ModelInfo = ModelInfo {
        model_identifier: "test_model",
        description: "A model \"for\" tests",
        variables: VARIABLES,
        default_experiment: DefaultExperiment {
            start: 0.0,
            stop: 10.0,
            step: 0.5,
        },
        fmi_status: vr::FMI_STATUS,
        state_code: Some(vr::MODE),
        state_name: "test",
        arrays: &[],
        has_event_mode: false,
        computed: &[],
        generated: Generated::new(),
    };

    #[test]
    fn xml_contains_every_variable_and_the_guid() {
        let xml = model_description_of(&INFO);
        let guid = guid_of(&INFO);
        assert!(xml.contains(&format!(r#"guid="{guid}""#)));
        assert!(!xml.contains(GUID_PLACEHOLDER));
        for v in VARIABLES {
            assert!(xml.contains(&format!(r#"name="{}" valueReference="{}""#, v.name, v.vr)));
        }
        assert!(xml.contains("canRunAsynchronuously"));
        assert_eq!(guid.len(), 38);
        assert!(xml.contains(&format!(r#"generationDateAndTime="{GENERATION_DATE}""#)));
        // escaped text, the used unit alone, codes as a bounded Integer
        assert!(xml.contains(r#"description="A model &quot;for&quot; tests""#));
        assert!(xml.contains(r#"A &lt;code&gt;. Codes: 1 a, 3 c"#));
        assert!(xml.contains(r#"<Unit name="m/s"><BaseUnit m="1" s="-1"/></Unit>"#));
        assert_eq!(xml.matches("<Unit ").count(), 1);
        assert!(xml.contains(r#"<Integer min="1" max="3" start="3"/>"#));
        assert!(xml.contains(r#"<Boolean start="true"/>"#));
        assert!(xml.contains(r#"<DefaultExperiment startTime="0" stopTime="10" stepSize="0.5"/>"#));
        assert!(xml.contains(r#"<Unknown index="4" dependencies=""/>"#));
        assert!(xml.contains(&format!(r#"name="on" valueReference="{}""#, vr::ON)));
        assert!(xml.contains(&format!(r#"<!-- index {} -->"#, vr::GAIN + 1)));
    }

    #[test]
    fn guid_depends_on_the_interface_not_on_the_generation_date() {
        let b = body(&INFO);
        assert_eq!(b.matches(DATE_PLACEHOLDER).count(), 1);
        let (g1, x1) = finish(&b, "2026-01-01T00:00:00Z");
        let (g2, x2) = finish(&b, "2026-12-01T21:00:00Z");
        assert_eq!(g1, g2);
        assert_ne!(x1, x2);
        assert_eq!(g1, guid_of(&INFO));
        // any change to the interface changes it
        let (g3, _) = finish(&b.replacen("relnav developers", "relnav developer", 1), "x");
        assert_ne!(g1, g3);
    }

    #[test]
    fn markdown_lists_every_variable_and_code() {
        let md = variables_markdown_of(&INFO);
        assert!(md.contains(
            "| `mode` | 0 | parameter | fixed | Integer |  | 3 (c) | A <code>. Codes: 1 a, 3 c |"
        ));
        assert!(md.contains("| `fmi_status` | 3 | output | discrete | Integer |  | — | Status |"));
        assert!(md.contains("| `mode` | 1 | `a` | first & only |"));
    }
}
