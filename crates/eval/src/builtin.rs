//! The papers' numerical examples, shipped inside the binary (the files are
//! `scenarios/*.toml`; `relnav scenarios` lists them, `--show NAME` prints one).

/// (paper, scenario name, TOML text), in reproduction order; `"eccentric"` groups issue
/// 34's eccentric-orbit scenarios (no paper: the elliptic model against CW and the PCRLB),
/// `"sensors"` the multi-sensor ones (camera, relative GNSS, radio and lidar).
pub const BUILTIN: &[(&str, &str, &str)] = &[
    (
        "000",
        "paper000",
        include_str!("../../../scenarios/paper000.toml"),
    ),
    (
        "000",
        "paper000_particles",
        include_str!("../../../scenarios/paper000_particles.toml"),
    ),
    (
        "002",
        "paper002_no_manoeuvre",
        include_str!("../../../scenarios/paper002_no_manoeuvre.toml"),
    ),
    (
        "002",
        "paper002_manoeuvre",
        include_str!("../../../scenarios/paper002_manoeuvre.toml"),
    ),
    (
        "001",
        "model_error_burns",
        include_str!("../../../scenarios/model_error_burns.toml"),
    ),
    (
        "001",
        "model_error_j2",
        include_str!("../../../scenarios/model_error_j2.toml"),
    ),
    (
        "001",
        "model_error_quiet",
        include_str!("../../../scenarios/model_error_quiet.toml"),
    ),
    (
        "002",
        "paper002_stress_uniform",
        include_str!("../../../scenarios/paper002_stress_uniform.toml"),
    ),
    (
        "002",
        "paper002_stress_laplace",
        include_str!("../../../scenarios/paper002_stress_laplace.toml"),
    ),
    (
        "002",
        "paper002_stress_ar1",
        include_str!("../../../scenarios/paper002_stress_ar1.toml"),
    ),
    (
        "002",
        "paper002_quiet_radio",
        include_str!("../../../scenarios/paper002_quiet_radio.toml"),
    ),
    (
        "002",
        "paper002_quiet_radio_delta",
        include_str!("../../../scenarios/paper002_quiet_radio_delta.toml"),
    ),
    (
        "003",
        "paper003",
        include_str!("../../../scenarios/paper003.toml"),
    ),
    (
        "eccentric",
        "eccentric_leo",
        include_str!("../../../scenarios/eccentric_leo.toml"),
    ),
    (
        "eccentric",
        "eccentric_e01",
        include_str!("../../../scenarios/eccentric_e01.toml"),
    ),
    (
        "eccentric",
        "eccentric_e05",
        include_str!("../../../scenarios/eccentric_e05.toml"),
    ),
    (
        "eccentric",
        "eccentric_proba3",
        include_str!("../../../scenarios/eccentric_proba3.toml"),
    ),
    (
        "sensors",
        "sensors_gnss_leo",
        include_str!("../../../scenarios/sensors_gnss_leo.toml"),
    ),
    (
        "sensors",
        "sensors_gnss_camera_leo",
        include_str!("../../../scenarios/sensors_gnss_camera_leo.toml"),
    ),
    (
        "sensors",
        "sensors_handover",
        include_str!("../../../scenarios/sensors_handover.toml"),
    ),
    (
        "sensors",
        "sensors_handover_rate_error",
        include_str!("../../../scenarios/sensors_handover_rate_error.toml"),
    ),
    (
        "sensors",
        "sensors_angles_only",
        include_str!("../../../scenarios/sensors_angles_only.toml"),
    ),
    (
        "sensors",
        "pf_lidar_wide_prior",
        include_str!("../../../scenarios/pf_lidar_wide_prior.toml"),
    ),
];

/// Paper 001's Mars approach (its own problem, not a relative-navigation scenario):
/// (paper, name, TOML text of a [`crate::mars::MarsScenario`]).
pub const MARS: &[(&str, &str, &str)] = &[(
    "001",
    "paper001_mars",
    include_str!("../../../scenarios/paper001_mars.toml"),
)];

/// Parse a Mars-approach file (strict keys).
pub fn parse_mars(text: &str) -> Result<crate::mars::MarsScenario, String> {
    toml::from_str(text).map_err(|e| e.to_string())
}

/// The text of the built-in scenario `name`, if there is one.
pub fn by_name(name: &str) -> Option<&'static str> {
    BUILTIN
        .iter()
        .find(|(_, n, _)| *n == name)
        .map(|(_, _, t)| *t)
}

/// The built-in scenarios of one paper (`"all"` for every paper).
pub fn for_paper(paper: &str) -> Vec<(&'static str, &'static str)> {
    BUILTIN
        .iter()
        .filter(|(p, _, _)| paper == "all" || *p == paper)
        .map(|(_, n, t)| (*n, *t))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::Scenario;

    #[test]
    fn every_builtin_parses_and_round_trips() {
        for (_, name, text) in BUILTIN {
            let s = Scenario::from_toml(text).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(&s.name, name);
            let back = Scenario::from_toml(&s.to_toml().unwrap()).unwrap();
            assert_eq!(s, back);
        }
        for (_, name, text) in MARS {
            let s = parse_mars(text).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(&s.name, name);
        }
    }

    /// The files beside the built-in ones (too long to run by `reproduce`) parse too, and
    /// each is named after its file.
    #[test]
    fn every_scenario_file_parses() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios");
        let mut n = 0;
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_none_or(|e| e != "toml") {
                continue;
            }
            let text = std::fs::read_to_string(&path).unwrap();
            let stem = path.file_stem().unwrap().to_str().unwrap();
            let name = if text.contains("problem = \"mars_approach\"") {
                parse_mars(&text).map(|s| s.name)
            } else {
                Scenario::from_toml(&text).map(|s| s.name)
            };
            assert_eq!(name.unwrap_or_else(|e| panic!("{stem}: {e}")), stem);
            n += 1;
        }
        assert!(n > BUILTIN.len(), "{n} files");
    }
}
