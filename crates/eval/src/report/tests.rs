use super::csv::{write_csv, SUMMARY_COLUMNS};
use super::plot::{color_of, fmt_tick, log_ticks, write_plots, FONT_PATH};
use super::table::markdown_table;
use super::{fmt_sig, fmt_trim};
use crate::metrics;
use crate::results::{FilterStats, McResult};
use plotters::prelude::RGBColor;
use std::path::{Path, PathBuf};

/// Every filter gets a colour of its own, none black or gray (reserved for the bound
/// and the NEES bands): all of the first 60 differ, and the first 20 (the built-in
/// scenarios have up to ten filters) differ clearly (city-block distance in RGB).
#[test]
fn every_filter_has_its_own_colour() {
    let cs: Vec<RGBColor> = (0..60).map(color_of).collect();
    for (i, a) in cs.iter().enumerate() {
        assert!(!(a.0 == a.1 && a.1 == a.2), "filter {i}: gray {a:?}");
        for (j, b) in cs.iter().enumerate().skip(i + 1) {
            let d = (i32::from(a.0) - i32::from(b.0)).abs()
                + (i32::from(a.1) - i32::from(b.1)).abs()
                + (i32::from(a.2) - i32::from(b.2)).abs();
            let min = if j < 20 { 60 } else { 1 };
            assert!(d >= min, "filters {i} and {j}: {a:?} and {b:?}");
        }
    }
}

fn unique_dir(name: &str) -> PathBuf {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_nanos())
        .unwrap_or(0);
    std::env::temp_dir().join(format!(
        "relnav-report-{name}-{}-{nanos}",
        std::process::id()
    ))
}

fn filter(label: &str, scale: f64, n: usize) -> FilterStats {
    // Decaying errors: position variance 100 e^(-k/10) + 0.01 per axis.
    let mse = (0..n)
        .map(|k| {
            let p = scale * (100.0 * (-(k as f64) / 10.0).exp() + 0.01);
            [p, p, p, p * 1e-4, p * 1e-4, p * 1e-4]
        })
        .collect();
    FilterStats {
        label: label.to_string(),
        kind: label.to_lowercase(),
        mse,
        nees: (0..n).map(|k| 5.0 + (k % 3) as f64).collect(),
        nis: (0..n)
            .map(|k| if k % 2 == 0 { 3.0 } else { f64::NAN })
            .collect(),
        nis_count: (0..n).map(|k| if k % 2 == 0 { 20 } else { 0 }).collect(),
        max_pos_err: vec![2.0; n],
        max_vel_err: vec![0.02; n],
        range_mse: (0..n)
            .map(|k| 300.0 * (-(k as f64) / 10.0).exp() + 0.03)
            .collect(),
        range_var: (0..n)
            .map(|k| 250.0 * (-(k as f64) / 10.0).exp() + 0.02)
            .collect(),
        failed_runs: 0,
        us_per_step: 1.234,
        move_acceptance: f64::NAN,
    }
}

fn campaign(n: usize) -> McResult {
    let mut ukf = filter("UKF", 0.8, n);
    // Zero, NaN and inf values must be skipped on the log axes.
    if let Some(m) = ukf.mse.get_mut(3) {
        *m = [0.0; 6];
    }
    if let Some(m) = ukf.mse.get_mut(4) {
        *m = [f64::NAN; 6];
    }
    if let Some(v) = ukf.nees.get_mut(5) {
        *v = f64::INFINITY;
    }
    ukf.failed_runs = 2;
    McResult {
        nis_dof: 3,
        scenario: "paper000".to_string(),
        title: "Paper 000: radio, 7200 s orbit".to_string(),
        t: (0..n).map(|k| k as f64).collect(),
        runs: 20,
        interrupted: false,
        filters: vec![filter("EKF", 1.0, n), ukf],
        pcrlb: Ok((0..n)
            .map(|k| {
                let p = 50.0 * (-(k as f64) / 10.0).exp() + 0.005;
                [p, p, p, p * 1e-4, p * 1e-4, p * 1e-4]
            })
            .collect()),
        pcrlb_runs: Err("not computed".to_string()),
        range_bound_runs: (0..n)
            .map(|k| 150.0 * (-(k as f64) / 10.0).exp() + 0.015)
            .collect(),
        convergence_time: 10.0,
        convergence_threshold: (1.0, 0.1),
        published: vec![
            ("EKF".to_string(), "0.52 m RMSE (Table 2)".to_string()),
            ("SIR-PF".to_string(), "0.31 m | fig. 4".to_string()),
        ],
        unreported_burns: vec![],
    }
}

#[test]
fn fmt_sig_is_readable() {
    assert_eq!(fmt_sig(1.23456, 4), "1.235");
    assert_eq!(fmt_sig(123.456, 4), "123.5");
    assert_eq!(fmt_sig(12345.6, 4), "12346");
    assert_eq!(fmt_sig(0.0123456, 3), "0.0123");
    assert_eq!(fmt_sig(9.9996, 4), "10.00");
    assert_eq!(fmt_sig(1.5e-5, 3), "1.50e-5");
    assert_eq!(fmt_sig(2.5e7, 3), "2.50e7");
    assert_eq!(fmt_sig(0.0, 3), "0");
    assert_eq!(fmt_sig(f64::NAN, 3), "—");
    assert_eq!(fmt_sig(f64::NEG_INFINITY, 3), "-inf");
    assert_eq!(fmt_sig(-0.5, 3), "-0.500");
    assert_eq!(fmt_trim(10.0, 4), "10");
    assert_eq!(fmt_trim(0.1, 4), "0.1");
    assert_eq!(fmt_trim(3600.7, 4), "3601");
}

#[test]
fn log_ticks_are_readable() {
    // Several decades: labels at the powers of ten, light lines at 2..9.
    let (bold, light) = log_ticks(&(0.05..2000.0));
    assert_eq!(bold, vec![0.1, 1.0, 10.0, 100.0, 1000.0]);
    assert!(light.contains(&0.05) && light.contains(&2000.0));
    // Two decades: 1-2-5.
    let (bold, _) = log_ticks(&(0.8..60.0));
    assert_eq!(bold, vec![1.0, 2.0, 5.0, 10.0, 20.0, 50.0]);
    // Less than a decade (the NEES band): linear nice ticks.
    let (bold, _) = log_ticks(&(3.2..11.0));
    assert_eq!(bold, vec![4.0, 6.0, 8.0, 10.0]);
    // Very many decades: at most about 8 labels.
    let (bold, _) = log_ticks(&(1e-30..1e30));
    assert!(bold.len() <= 9, "{bold:?}");
    assert_eq!(fmt_tick(10.0), "10");
    assert_eq!(fmt_tick(0.5), "0.5");
    assert_eq!(fmt_tick(1e-5), "1e-5");
    assert_eq!(fmt_tick(2.5e6), "2.5e6");
}

#[test]
fn markdown_has_labels_published_and_not_run_rows() {
    let r = campaign(40);
    let s = metrics::summarize(&r);
    let md = markdown_table(&r, &s);
    assert!(md.starts_with("### Paper 000: radio, 7200 s orbit (`paper000`)"));
    assert!(md.contains("| EKF | 0.52 m RMSE (Table 2) |"), "{md}");
    assert!(md.contains("| UKF | — |"), "{md}");
    // Published-only filter: a "not run" row, the pipe in its text escaped.
    assert!(
        md.contains("| SIR-PF | 0.31 m \\| fig. 4 | not run |"),
        "{md}"
    );
    assert!(md.contains("pos RMSE [m]") && md.contains("µs/step"));
    assert!(
        md.contains("PCRLB (root of the time-averaged bound"),
        "{md}"
    );
    assert!(md.contains("Runs: 20."), "{md}");
    assert!(md.contains("t ≥ 10 s"), "{md}");
    assert!(!md.contains("INTERRUPTED"));
    // Header, separator, 2 filters, 1 not run.
    assert_eq!(md.lines().filter(|l| l.starts_with('|')).count(), 5);
    // All table rows have the same number of cells.
    let cells: Vec<usize> = md
        .lines()
        .filter(|l| l.starts_with('|'))
        .map(|l| l.replace("\\|", "").matches('|').count())
        .collect();
    assert!(cells.iter().all(|c| *c == cells[0]), "{cells:?}");

    let mut r = r;
    r.interrupted = true;
    r.runs = 7;
    r.pcrlb = Err("no PCRLB for lidar".to_string());
    let s = metrics::summarize(&r);
    let md = markdown_table(&r, &s);
    assert!(md.contains("INTERRUPTED after 7 runs"), "{md}");
    assert!(
        md.contains("PCRLB: undefined (no PCRLB for lidar)."),
        "{md}"
    );
}

#[test]
fn csv_files_have_headers_and_rows() {
    let n = 25;
    let r = campaign(n);
    let s = metrics::summarize(&r);
    let dir = unique_dir("csv");
    let paths = write_csv(&r, &s, &dir).unwrap();
    assert_eq!(
        paths,
        vec![dir.join("timeseries.csv"), dir.join("summary.csv")]
    );

    let mut rd = ::csv::Reader::from_path(dir.join("timeseries.csv")).unwrap();
    let header = rd.headers().unwrap().clone();
    assert_eq!(header.len(), 1 + 2 * 14 + 8 + 8 + 1);
    assert_eq!(header.get(0), Some("t"));
    assert_eq!(header.get(1), Some("EKF_rmse_x"));
    assert_eq!(header.get(7), Some("EKF_rmse_pos"));
    assert_eq!(header.get(13), Some("EKF_range_rmse"));
    assert_eq!(header.get(14), Some("EKF_range_sigma"));
    assert_eq!(header.get(15), Some("UKF_rmse_x"));
    assert_eq!(header.get(29), Some("pcrlb_x"));
    assert_eq!(header.get(36), Some("pcrlb_vel"));
    assert_eq!(header.get(37), Some("run_bound_x"));
    assert_eq!(header.get(44), Some("run_bound_vel"));
    assert_eq!(header.get(45), Some("run_bound_range"));
    let rows: Vec<::csv::StringRecord> = rd.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), n);
    assert!(rows.iter().all(|row| row.len() == header.len()));
    // Row 0: t = 0, EKF x RMSE = sqrt(100.01), pos = sqrt(300.03), NIS 3.
    let r0 = &rows[0];
    assert_eq!(r0.get(0), Some("0"));
    let x: f64 = r0.get(1).unwrap().parse().unwrap();
    assert!((x - 100.01_f64.sqrt()).abs() < 1e-12);
    let pos: f64 = r0.get(7).unwrap().parse().unwrap();
    assert!((pos - 300.03_f64.sqrt()).abs() < 1e-12);
    assert_eq!(r0.get(10), Some("3"));
    // Row 1: no measurement -> empty NIS cell.
    assert_eq!(rows[1].get(10), Some(""));
    // the range columns: roots of the mean squared error and of the mean reported variance
    let range: f64 = r0.get(13).unwrap().parse().unwrap();
    assert!((range - 300.03_f64.sqrt()).abs() < 1e-12);
    let sigma: f64 = r0.get(14).unwrap().parse().unwrap();
    assert!((sigma - 250.02_f64.sqrt()).abs() < 1e-12);

    let mut rd = ::csv::Reader::from_path(dir.join("summary.csv")).unwrap();
    let header = rd.headers().unwrap().clone();
    assert_eq!(header.len(), SUMMARY_COLUMNS.len());
    assert_eq!(header.get(0), Some("label"));
    let rows: Vec<::csv::StringRecord> = rd.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), 2);
    assert_eq!(rows[0].get(0), Some("EKF"));
    assert_eq!(rows[1].get(0), Some("UKF"));
    assert_eq!(rows[1].get(2), Some("18"));
    // no moves: an empty acceptance cell
    assert_eq!(rows[0].get(34), Some(""));
    assert_eq!(rows[0].get(39), Some("0.52 m RMSE (Table 2)"));

    // Undefined PCRLB: empty bound cells, same shape.
    let mut r = r;
    r.pcrlb = Err("undefined".to_string());
    write_csv(&r, &s, &dir).unwrap();
    let mut rd = ::csv::Reader::from_path(dir.join("timeseries.csv")).unwrap();
    let rows: Vec<::csv::StringRecord> = rd.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), n);
    assert_eq!(rows[0].get(29), Some(""));
    assert_eq!(rows[0].len(), 46);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn plots_are_png_files() {
    let r = campaign(60);
    let dir = unique_dir("png");
    let out = write_plots(&r, &dir);
    if !Path::new(FONT_PATH).exists() {
        assert!(out.unwrap_err().contains("fonts-dejavu-core"));
        return;
    }
    let paths = out.unwrap();
    let names: Vec<String> = paths
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names,
        [
            "position_rmse.png",
            "velocity_rmse.png",
            "nees.png",
            "position_error_axes.png",
            "range.png"
        ]
    );
    for p in &paths {
        let bytes = std::fs::read(p).unwrap();
        assert!(bytes.starts_with(b"\x89PNG\r\n\x1a\n"), "{}", p.display());
        assert!(bytes.len() > 5000, "{} is suspiciously small", p.display());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn plots_survive_degenerate_input() {
    if !Path::new(FONT_PATH).exists() {
        return;
    }
    // One time, all values zero or NaN, undefined PCRLB, no filters failing... and
    // a filter whose runs all failed.
    let mut f = filter("EKF", 1.0, 1);
    f.mse = vec![[0.0; 6]];
    f.nees = vec![f64::NAN];
    f.failed_runs = 20;
    let mut r = campaign(1);
    r.filters = vec![f];
    r.pcrlb = Err("undefined".to_string());
    let dir = unique_dir("degenerate");
    assert_eq!(write_plots(&r, &dir).unwrap().len(), 5);
    // No times at all: an error, not a panic.
    r.t.clear();
    assert!(write_plots(&r, &dir)
        .unwrap_err()
        .contains("no finite times"));
    std::fs::remove_dir_all(&dir).unwrap();
}
