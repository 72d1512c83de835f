//! The system kit's FMU models (`relnav_plant`, `relnav_guidance`) as the packer sees them:
//! their documentation tables are the generated ones, each model description is its own
//! (identifier, GUID) and declares exactly the table's variables, and relnav's is unchanged
//! by the kit (value references and names of the table).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use relnav_fmi::fmi2::description::{guid_of, model_description_of, variables_markdown_of};
use relnav_fmi::model::ModelInfo;

fn kit() -> [(&'static ModelInfo, &'static str); 2] {
    [
        (&relnav_models::plant::INFO, "plant"),
        (&relnav_models::guidance::INFO, "guidance"),
    ]
}

/// `docs/kit.md`'s variable tables are the generated ones (regenerate with
/// `cargo run --bin relnav-fmu -- --variables-markdown relnav_plant` / `relnav_guidance`).
#[test]
fn kit_doc_variable_tables_are_current() {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/kit.md"))
        .expect("docs/kit.md");
    for (info, tag) in kit() {
        let begin = format!(
            "<!-- {tag}-variables:begin (generated: cargo run --bin relnav-fmu -- --variables-markdown {}) -->\n",
            info.model_identifier
        );
        let start = doc.find(&begin).expect("begin marker") + begin.len();
        let end = doc
            .find(&format!("<!-- {tag}-variables:end -->"))
            .expect("end marker");
        assert_eq!(
            doc.get(start..end).unwrap_or_default(),
            variables_markdown_of(info),
            "docs/kit.md: the {tag} table is stale"
        );
    }
}

/// Each kit model has its own identifier and GUID, and its XML declares every variable of
/// its table at its value reference (and nothing of relnav's).
#[test]
fn kit_descriptions_are_their_own() {
    let relnav_guid = guid_of(&relnav_nav_model::INFO);
    for (info, _) in kit() {
        let xml = model_description_of(info);
        let id = info.model_identifier;
        assert!(xml.contains(&format!(r#"modelIdentifier="{id}""#)), "{id}");
        assert!(xml.contains(&format!(r#"modelName="{id}""#)), "{id}");
        assert_ne!(guid_of(info), relnav_guid, "{id}");
        assert!(xml.contains(&format!(r#"guid="{}""#, guid_of(info))));
        assert_eq!(
            xml.matches("<ScalarVariable ").count(),
            info.variables.len(),
            "{id}"
        );
        for v in info.variables {
            assert!(
                xml.contains(&format!(r#"name="{}" valueReference="{}""#, v.name, v.vr)),
                "{id}: {}",
                v.name
            );
        }
        assert!(!xml.contains("<Enumeration"), "{id}: codes are Integers");
        assert!(!xml.contains(r#"name="filter""#), "{id}");
    }
}

/// relnav.fmu's value references are stable (a master addresses the variables by them):
/// the first ones of the original variable table, spot-checked by name, and the table is
/// dense.
#[test]
fn relnav_value_references_are_unchanged() {
    use relnav_nav_model::VARIABLES;
    let vr_of = |n: &str| VARIABLES.iter().find(|v| v.name == n).map(|v| v.vr);
    for (name, vr) in [
        ("filter", 0),
        ("frame", 1),
        ("discretization", 2),
        ("resampler", 46),
        ("noise_model", 48),
    ] {
        assert_eq!(vr_of(name), Some(vr), "{name}");
    }
    for (i, v) in VARIABLES.iter().enumerate() {
        assert_eq!(v.vr as usize, i, "{}", v.name);
    }
    assert_eq!(relnav_nav_model::INFO.model_identifier, "relnav");
}
