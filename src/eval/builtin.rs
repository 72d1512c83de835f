//! The papers' numerical examples, shipped inside the binary (the files are
//! `scenarios/*.toml`; `relnav scenarios` lists them, `--show NAME` prints one).

/// (paper, scenario name, TOML text), in reproduction order.
pub const BUILTIN: &[(&str, &str, &str)] = &[
    (
        "000",
        "paper000",
        include_str!("../../scenarios/paper000.toml"),
    ),
    (
        "000",
        "paper000_particles",
        include_str!("../../scenarios/paper000_particles.toml"),
    ),
    (
        "002",
        "paper002_no_manoeuvre",
        include_str!("../../scenarios/paper002_no_manoeuvre.toml"),
    ),
    (
        "002",
        "paper002_manoeuvre",
        include_str!("../../scenarios/paper002_manoeuvre.toml"),
    ),
    (
        "002",
        "paper002_stress_uniform",
        include_str!("../../scenarios/paper002_stress_uniform.toml"),
    ),
    (
        "002",
        "paper002_stress_laplace",
        include_str!("../../scenarios/paper002_stress_laplace.toml"),
    ),
    (
        "002",
        "paper002_stress_ar1",
        include_str!("../../scenarios/paper002_stress_ar1.toml"),
    ),
    (
        "003",
        "paper003",
        include_str!("../../scenarios/paper003.toml"),
    ),
];

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
    use crate::eval::scenario::Scenario;

    #[test]
    fn every_builtin_parses_and_round_trips() {
        for (_, name, text) in BUILTIN {
            let s = Scenario::from_toml(text).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(&s.name, name);
            let back = Scenario::from_toml(&s.to_toml().unwrap()).unwrap();
            assert_eq!(s, back);
        }
    }
}
