//! FMI 3.0's `modelDescription.xml`, generated from a model's [`ModelInfo`]: the variable
//! table, with the vectors of [`ModelInfo::arrays`] published as array variables, and the
//! instantiation token derived from the text as FMI 2.0's GUID is
//! ([`crate::fmi2::description`]: a UUID v5 of the body without its token and date).
//!
//! Value references: a scalar keeps its FMI 2.0 value reference (its index in the table);
//! array `k` of [`ModelInfo::arrays`] is [`ARRAY_VR_BASE`]` + k`, computed output `k` of
//! [`ModelInfo::computed`] [`COMPUTED_VR_BASE`]` + k`; the independent variable `time` is
//! [`TIME_VR`]. The table's elements of an array are not published as scalars.

use crate::fmi2::description::{
    causality, escape, finish, published_description, variability, write_default_experiment,
    write_log_categories, write_units, DATE_PLACEHOLDER, GENERATION_DATE, GUID_PLACEHOLDER,
};
use crate::model::{ArrayDef, ComputedDef, ModelInfo};
use crate::variables::{Causality, VarDef, VarType};
use std::fmt::Write;

/// Value reference of array 0 (array `k` is `ARRAY_VR_BASE + k`): above every table.
pub const ARRAY_VR_BASE: u32 = 10_000;
/// Value reference of the independent variable `time`.
pub const TIME_VR: u32 = 9_999;
/// Value reference of computed output 0 (output `k` is `COMPUTED_VR_BASE + k`).
pub const COMPUTED_VR_BASE: u32 = 20_000;

/// What an FMI 3.0 value reference names.
#[derive(Debug, Clone, Copy)]
pub enum Published {
    /// A scalar of the table (its value reference).
    Scalar(u32),
    /// An array ([`ModelInfo::arrays`]).
    Array(&'static ArrayDef),
    /// A computed output ([`ModelInfo::computed`]) and its index there.
    Computed(&'static ComputedDef, usize),
    /// The independent variable.
    Time,
}

/// The FMI 3.0 value reference of the array or computed output called `name`.
pub fn vr_of(info: &ModelInfo, name: &str) -> Option<u32> {
    let array = info.arrays.iter().position(|a| a.name == name);
    let computed = info.computed.iter().position(|c| c.name == name);
    array
        .map(|k| ARRAY_VR_BASE + k as u32)
        .or(computed.map(|k| COMPUTED_VR_BASE + k as u32))
}

impl Published {
    /// The number of values it holds.
    #[inline(always)]
    pub fn len(&self) -> usize {
        match self {
            Published::Scalar(_) | Published::Time => 1,
            Published::Array(a) => a.elements.len(),
            Published::Computed(c, _) => c.len(),
        }
    }

    /// Whether it holds no value (never: every published variable holds at least one).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Whether the table's variable `vr` is an element of an array (then not a scalar of FMI
/// 3.0).
pub fn in_array(info: &ModelInfo, vr: u32) -> bool {
    let rows = info.generated.in_array.get_or_init(|| {
        let mut rows = vec![false; info.variables.len()];
        for e in info.arrays.iter().flat_map(|a| a.elements) {
            if let Some(r) = rows.get_mut(*e as usize) {
                *r = true;
            }
        }
        rows
    });
    rows.get(vr as usize).copied().unwrap_or(false)
}

/// What the FMI 3.0 value reference `vr` names, if anything.
#[inline(always)]
pub fn published(info: &'static ModelInfo, vr: u32) -> Option<Published> {
    if vr == TIME_VR {
        return Some(Published::Time);
    }
    if let Some(k) = vr.checked_sub(COMPUTED_VR_BASE) {
        return info
            .computed
            .get(k as usize)
            .map(|c| Published::Computed(c, k as usize));
    }
    if let Some(k) = vr.checked_sub(ARRAY_VR_BASE) {
        return info.arrays.get(k as usize).map(Published::Array);
    }
    info.lookup(vr)
        .filter(|_| !in_array(info, vr))
        .map(|_| Published::Scalar(vr))
}

/// The unit an array publishes: its elements' when they agree, none otherwise.
pub fn array_unit(info: &ModelInfo, a: &ArrayDef) -> &'static str {
    let units: Vec<&str> = a
        .elements
        .iter()
        .filter_map(|r| match info.lookup(*r).map(|d| d.ty) {
            Some(VarType::Real(u)) => Some(u),
            _ => None,
        })
        .collect();
    match units.first() {
        Some(u) if units.iter().all(|v| v == u) => u,
        _ => "",
    }
}

/// Check a model's arrays: elements exist, are distinct and in one array only, share
/// causality, variability and type class; the tables stay below [`TIME_VR`].
pub fn check_arrays(info: &ModelInfo) -> Result<(), String> {
    if info.variables.len() >= TIME_VR as usize
        || info.arrays.len() >= (COMPUTED_VR_BASE - ARRAY_VR_BASE) as usize
    {
        return Err("the table or the arrays reach the next FMI 3.0 value references".into());
    }
    for c in info.computed {
        if c.is_empty() || info.variables.iter().any(|v| v.name == c.name) {
            return Err(format!(
                "computed output {}: empty, or a scalar has its name",
                c.name
            ));
        }
    }
    for a in info.arrays {
        let Some(first) = a.elements.first().and_then(|r| info.lookup(*r)) else {
            return Err(format!("array {}: no elements, or an unknown one", a.name));
        };
        for r in a.elements {
            let Some(d) = info.lookup(*r) else {
                return Err(format!("array {}: unknown element {r}", a.name));
            };
            let same_class = std::mem::discriminant(&crate::variables::TypeClass::of(&d.ty))
                == std::mem::discriminant(&crate::variables::TypeClass::of(&first.ty));
            if d.causality != first.causality || d.variability != first.variability || !same_class {
                return Err(format!(
                    "array {}: {} differs from {}",
                    a.name, d.name, first.name
                ));
            }
            if info
                .arrays
                .iter()
                .flat_map(|b| b.elements)
                .filter(|e| *e == r)
                .count()
                != 1
            {
                return Err(format!(
                    "array {}: {} is in more than one place",
                    a.name, d.name
                ));
            }
        }
        if info.variables.iter().any(|v| v.name == a.name) {
            return Err(format!("array {}: a scalar has that name", a.name));
        }
    }
    Ok(())
}

fn start_text(v: &VarDef) -> String {
    match v.ty {
        VarType::Real(_) => format!("{}", v.start),
        VarType::Integer | VarType::Code(_) => format!("{}", v.start as i64),
        VarType::Boolean => if v.start != 0.0 { "true" } else { "false" }.to_string(),
    }
}

fn element(ty: &VarType) -> &'static str {
    match ty {
        VarType::Real(_) => "Float64",
        VarType::Integer | VarType::Code(_) => "Int32",
        VarType::Boolean => "Boolean",
    }
}

/// One published variable: its name and value reference, the table row it takes its
/// kind from (causality, variability, type), its description and unit, its start values
/// and (arrays) its length.
struct Var<'a> {
    name: &'a str,
    vr: u32,
    row: &'a VarDef,
    description: &'a str,
    unit: &'a str,
    starts: &'a [String],
    dims: &'a [usize],
}

fn variable(x: &mut String, p: &Var<'_>) {
    let v = p.row;
    let tag = element(&v.ty);
    let unit = if p.unit.is_empty() {
        String::new()
    } else {
        format!(r#" unit="{}""#, escape(p.unit))
    };
    let range = match v.ty {
        VarType::Code(t) => {
            let (lo, hi) = t.range();
            format!(r#" min="{lo}" max="{hi}""#)
        }
        _ => String::new(),
    };
    let start = if v.causality == Causality::Output {
        String::new()
    } else {
        format!(r#" start="{}""#, p.starts.join(" "))
    };
    let head = format!(
        r#"    <{tag} name="{}" valueReference="{}" description="{}" causality="{}" variability="{}"{unit}{range}{start}"#,
        p.name,
        p.vr,
        escape(p.description),
        causality(v.causality),
        variability(v.variability),
    );
    if p.dims.is_empty() {
        let _ = writeln!(x, "{head}/>");
    } else {
        let _ = writeln!(x, "{head}>");
        for n in p.dims {
            let _ = writeln!(x, r#"      <Dimension start="{n}"/>"#);
        }
        let _ = writeln!(x, "    </{tag}>");
    }
}

fn body(info: &'static ModelInfo) -> String {
    let mut x = String::new();
    let _ = writeln!(x, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        x,
        r#"<fmiModelDescription fmiVersion="3.0" modelName="{}" instantiationToken="{GUID_PLACEHOLDER}" description="{}" author="relnav developers" version="{}" generationTool="relnav {}" generationDateAndTime="{DATE_PLACEHOLDER}" variableNamingConvention="flat">"#,
        info.model_identifier,
        escape(info.description),
        relnav_core::VERSION,
        relnav_core::VERSION
    );
    let _ = writeln!(
        x,
        r#"  <CoSimulation modelIdentifier="{}" needsExecutionTool="false" canBeInstantiatedOnlyOncePerProcess="false" canGetAndSetFMUState="true" canSerializeFMUState="true" providesDirectionalDerivatives="false" providesAdjointDerivatives="false" providesPerElementDependencies="false" canHandleVariableCommunicationStepSize="true" maxOutputDerivativeOrder="0" providesIntermediateUpdate="false" mightReturnEarlyFromDoStep="false" canReturnEarlyAfterIntermediateUpdate="false" hasEventMode="{}" providesEvaluateDiscreteStates="false"/>"#,
        info.model_identifier, info.has_event_mode
    );
    // the units the published variables use (an array's where its elements agree)
    write_units(&mut x, |u| {
        info.variables
            .iter()
            .filter(|v| !in_array(info, v.vr))
            .any(|v| matches!(v.ty, VarType::Real(w) if w == u))
            || info.arrays.iter().any(|a| array_unit(info, a) == u)
            || info.computed.iter().any(|c| c.unit == u)
    });
    write_log_categories(&mut x);
    write_default_experiment(&mut x, info);
    let _ = writeln!(x, "  <ModelVariables>");
    let _ = writeln!(
        x,
        r#"    <Float64 name="time" valueReference="{TIME_VR}" causality="independent" variability="continuous" description="Simulation time"/>"#
    );
    let mut outputs = Vec::new();
    for v in info.variables.iter().filter(|v| !in_array(info, v.vr)) {
        let unit = match v.ty {
            VarType::Real(u) => u,
            _ => "",
        };
        variable(
            &mut x,
            &Var {
                name: v.name,
                vr: v.vr,
                row: v,
                description: &published_description(v),
                unit,
                starts: &[start_text(v)],
                dims: &[],
            },
        );
        if v.causality == Causality::Output {
            outputs.push(v.vr);
        }
    }
    for (k, a) in info.arrays.iter().enumerate() {
        let vr = ARRAY_VR_BASE + k as u32;
        let Some(first) = a.elements.first().and_then(|r| info.lookup(*r)) else {
            continue;
        };
        let starts: Vec<String> = a
            .elements
            .iter()
            .filter_map(|r| info.lookup(*r))
            .map(start_text)
            .collect();
        variable(
            &mut x,
            &Var {
                name: a.name,
                vr,
                row: first,
                description: a.description,
                unit: array_unit(info, a),
                starts: &starts,
                dims: &[a.elements.len()],
            },
        );
        if first.causality == Causality::Output {
            outputs.push(vr);
        }
    }
    for (k, c) in info.computed.iter().enumerate() {
        let vr = COMPUTED_VR_BASE + k as u32;
        let _ = writeln!(
            x,
            r#"    <Float64 name="{}" valueReference="{vr}" description="{}" causality="output" variability="continuous"{}>"#,
            c.name,
            escape(c.description),
            if c.unit.is_empty() {
                String::new()
            } else {
                format!(r#" unit="{}""#, escape(c.unit))
            }
        );
        for n in c.dims {
            let _ = writeln!(x, r#"      <Dimension start="{n}"/>"#);
        }
        let _ = writeln!(x, "    </Float64>");
        outputs.push(vr);
    }
    let _ = writeln!(x, "  </ModelVariables>");
    let _ = writeln!(x, "  <ModelStructure>");
    for r in &outputs {
        // no direct feedthrough: the outputs change only in a step
        let _ = writeln!(x, r#"    <Output valueReference="{r}" dependencies=""/>"#);
    }
    for r in &outputs {
        let _ = writeln!(x, r#"    <InitialUnknown valueReference="{r}"/>"#);
    }
    let _ = writeln!(x, "  </ModelStructure>");
    let _ = writeln!(x, "</fmiModelDescription>");
    x
}

fn generated(info: &'static ModelInfo) -> &'static (String, String) {
    info.generated
        .fmi3
        .get_or_init(|| finish(&body(info), GENERATION_DATE))
}

/// A model's FMI 3.0 instantiation token, `{xxxxxxxx-...}`.
pub fn token_of(info: &'static ModelInfo) -> &'static str {
    &generated(info).0
}

/// A model's full FMI 3.0 `modelDescription.xml` text.
pub fn model_description_of(info: &'static ModelInfo) -> &'static str {
    &generated(info).1
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{DefaultExperiment, Generated};
    use crate::variables::tests::CODES;
    use crate::variables::{VarType, Variability};

    crate::variables! {
        MODE = 0: "mode", Parameter, Fixed, VarType::Code(&CODES), 3.0, "A <code>";
        UX = 1: "ux", Input, Discrete, VarType::Real("m"), 0.5, "Input x";
        UY = 2: "uy", Input, Discrete, VarType::Real("m"), -1.0, "Input y";
        OUT_P = 3: "p", Output, Continuous, VarType::Real("m"), 0.0, "Position";
        OUT_V = 4: "v", Output, Continuous, VarType::Real("m/s"), 0.0, "Velocity";
        ON = 5: "on", Input, Discrete, VarType::Boolean, 1.0, "A switch";
        FMI_STATUS = 6: "fmi_status", Output, Discrete, VarType::Integer, 0.0, "Status";
    }

    static ARRAYS: &[ArrayDef] = &[
        ArrayDef {
            name: "u",
            elements: &[vr::UX, vr::UY],
            description: "Inputs",
        },
        ArrayDef {
            name: "state",
            elements: &[vr::OUT_P, vr::OUT_V],
            description: "Position [m] and velocity [m/s]",
        },
    ];

    static COMPUTED: &[ComputedDef] = &[ComputedDef {
        name: "cov",
        dims: &[2, 2],
        unit: "m2/s",
        description: "A matrix",
    }];

    static INFO: ModelInfo = ModelInfo {
        model_identifier: "test_model",
        description: "A model for tests",
        variables: VARIABLES,
        default_experiment: DefaultExperiment {
            start: 0.0,
            stop: 10.0,
            step: 0.5,
        },
        fmi_status: vr::FMI_STATUS,
        state_code: Some(vr::MODE),
        state_name: "test",
        arrays: ARRAYS,
        has_event_mode: true,
        computed: COMPUTED,
        generated: Generated::new(),
    };

    #[test]
    fn arrays_replace_their_elements_and_scalars_keep_their_references() {
        assert_eq!(check_arrays(&INFO), Ok(()));
        let xml = model_description_of(&INFO);
        let token = token_of(&INFO);
        assert!(xml.contains(&format!(r#"instantiationToken="{token}""#)));
        assert!(xml.contains(r#"fmiVersion="3.0""#));
        // the array of inputs: its elements' unit and start values, its length
        assert!(xml.contains(
            r#"<Float64 name="u" valueReference="10000" description="Inputs" causality="input" variability="discrete" unit="m" start="0.5 -1">"#
        ));
        // mixed units: none on the array; outputs have no start
        assert!(xml.contains(
            r#"<Float64 name="state" valueReference="10001" description="Position [m] and velocity [m/s]" causality="output" variability="continuous">"#
        ));
        for hidden in ["ux", "uy", "p", "v"] {
            assert!(!xml.contains(&format!(r#"name="{hidden}""#)), "{hidden}");
        }
        assert!(xml.contains(r#"<Int32 name="mode" valueReference="0" description="A &lt;code&gt;. Codes: 1 a, 3 c" causality="parameter" variability="fixed" min="1" max="3" start="3"/>"#));
        assert!(xml.contains(r#"<Boolean name="on" valueReference="5" description="A switch" causality="input" variability="discrete" start="true"/>"#));
        assert!(xml.contains(r#"<Output valueReference="10001" dependencies=""/>"#));
        assert!(xml.contains(r#"<Output valueReference="6" dependencies=""/>"#));
        assert!(xml.contains(r#"causality="independent""#));
        // a computed output: its own reference, two dimensions, its unit declared
        assert!(xml.contains(
            r#"<Float64 name="cov" valueReference="20000" description="A matrix" causality="output" variability="continuous" unit="m2/s">"#
        ));
        assert_eq!(xml.matches(r#"<Dimension start="2"/>"#).count(), 4);
        assert!(xml.contains(r#"<Output valueReference="20000" dependencies=""/>"#));
        assert!(xml.contains(r#"<Unit name="m2/s">"#));
        // m is used by the array u, m/s by no published variable
        assert!(xml.contains(r#"<Unit name="m">"#));
        assert!(!xml.contains(r#"<Unit name="m/s">"#));
    }

    #[test]
    fn value_references_resolve_to_what_they_publish() {
        assert!(matches!(published(&INFO, 0), Some(Published::Scalar(0))));
        assert!(matches!(
            published(&INFO, vr::ON),
            Some(Published::Scalar(5))
        ));
        assert!(published(&INFO, vr::UX).is_none());
        assert!(matches!(published(&INFO, 10_001), Some(Published::Array(a)) if a.name == "state"));
        assert!(published(&INFO, 10_002).is_none());
        assert!(published(&INFO, 7).is_none());
        assert!(matches!(published(&INFO, TIME_VR), Some(Published::Time)));
        assert!(
            matches!(published(&INFO, 20_000), Some(Published::Computed(c, 0)) if c.len() == 4)
        );
        assert!(published(&INFO, 20_001).is_none());
        assert_eq!(vr_of(&INFO, "state"), Some(10_001));
        assert_eq!(vr_of(&INFO, "cov"), Some(20_000));
        assert_eq!(vr_of(&INFO, "mode"), None);
    }

    #[test]
    fn check_arrays_names_the_violation() {
        static MIXED: &[ArrayDef] = &[ArrayDef {
            name: "bad",
            elements: &[vr::UX, vr::OUT_P],
            description: "",
        }];
        static TWICE: &[ArrayDef] = &[
            ArrayDef {
                name: "a1",
                elements: &[vr::UX],
                description: "",
            },
            ArrayDef {
                name: "a2",
                elements: &[vr::UX],
                description: "",
            },
        ];
        static NAMED: &[ArrayDef] = &[ArrayDef {
            name: "mode",
            elements: &[vr::UX],
            description: "",
        }];
        for (arrays, why) in [
            (MIXED, "p differs from ux"),
            (TWICE, "in more than one place"),
            (NAMED, "a scalar has that name"),
        ] {
            let info: &'static ModelInfo = Box::leak(Box::new(ModelInfo {
                model_identifier: "t",
                description: "",
                variables: VARIABLES,
                default_experiment: INFO.default_experiment,
                fmi_status: vr::FMI_STATUS,
                state_code: None,
                state_name: "t",
                arrays,
                has_event_mode: false,
                computed: &[],
                generated: Generated::new(),
            }));
            assert!(check_arrays(info).is_err_and(|e| e.contains(why)), "{why}");
        }
        assert_eq!(
            VARIABLES[vr::UX as usize].variability,
            Variability::Discrete
        );
    }
}
