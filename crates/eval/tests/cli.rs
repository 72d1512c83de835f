//! The `relnav` CLI end to end: a small campaign writes its table, CSV and plots; a bad
//! scenario file gives an error naming the key.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)] // test code

use std::process::Command;

fn tmp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("relnav-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn reproduce_writes_table_csv_and_plots() {
    let out = tmp("reproduce");
    let o = Command::new(env!("CARGO_BIN_EXE_relnav"))
        .args(["reproduce", "--paper", "003", "--runs", "2", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let table = String::from_utf8_lossy(&o.stdout);
    assert!(
        table.contains("| EKF |") && table.contains("PCRLB"),
        "{table}"
    );
    let dir = out.join("paper003");
    for f in ["timeseries.csv", "summary.csv"] {
        assert!(dir.join(f).is_file(), "{f}");
    }
    // plots need the DejaVu font (scripts/setup.sh installs fonts-dejavu-core)
    if std::path::Path::new(relnav_eval::report::FONT_PATH).exists() {
        let png = std::fs::read(dir.join("position_rmse.png")).unwrap();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    }
    let _ = std::fs::remove_dir_all(&out);
}

/// `reproduce --paper 001` prints paper 001's Tables 3-5 beside the published values and
/// the model-error scenarios.
#[test]
fn reproduce_paper_001_prints_the_tables() {
    let out = tmp("p001");
    let o = Command::new(env!("CARGO_BIN_EXE_relnav"))
        .args([
            "reproduce",
            "--paper",
            "001",
            "--runs",
            "1",
            "--no-plots",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let t = String::from_utf8_lossy(&o.stdout);
    for want in [
        "**Table 3**",
        "**Table 4**",
        "**Table 5**",
        "92.2212 km",
        "| AQUKF N = 300 |",
        "model_error_burns",
        "model_error_j2",
        "model_error_quiet",
        "| AQUKF, NIS-gated (library default) |",
        "| IMM (3 modes) |",
        "quiet ÷ UKF pos / vel",
    ] {
        assert!(t.contains(want), "missing {want}:\n{t}");
    }
    assert!(out.join("paper001_mars").join("tables.md").is_file());
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn bad_scenario_names_the_key() {
    let dir = tmp("bad");
    let (_, text) = relnav_eval::builtin::for_paper("000")[0];
    let path = dir.join("bad.toml");
    std::fs::write(&path, text.replace("sigma_angle_deg", "sigma_angel_deg")).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_relnav"))
        .arg("simulate")
        .arg(&path)
        .output()
        .unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("sigma_angel_deg") && err.contains("bad.toml"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
