//! Reports of a Monte Carlo campaign: a Markdown table, CSV files and PNG plots.
//!
//! - [`markdown_table`]: one row per filter with the [`Summary`] metrics next to the
//!   paper's published figure, rows "not run" for published filters without results, the
//!   PCRLB's time-averaged root and the number of runs.
//! - [`write_csv`]: `timeseries.csv` (per-time RMSE, NEES, NIS, maximum errors and the
//!   PCRLB's root) and `summary.csv` (one row per filter).
//! - [`write_plots`]: `position_rmse.png`, `velocity_rmse.png`, `nees.png` and
//!   `position_error_axes.png`, like the papers' error-curve figures (log y-axis, the PCRLB
//!   as a dashed black line).
//!
//! Text in the PNGs is drawn with DejaVu Sans, read at run time from [`FONT_PATH`]
//! (Debian package `fonts-dejavu-core`); without it [`write_plots`] returns an error.

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::metrics::{
    chi2_mean_bounds, pcrlb_averaged, rmse_axes, rmse_pos, rmse_vel, Consistency, Summary,
};
use crate::results::McResult;

/// Font used for the text in the plots.
pub const FONT_PATH: &str = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

/// Size of the single-panel plots \[px\].
const PLOT_SIZE: (u32, u32) = (1000, 600);
/// Size of the three-panel per-axis plot \[px\].
const AXES_PLOT_SIZE: (u32, u32) = (1000, 900);

/// Line colours of the first filters, in scenario order: matplotlib's tab10 without its
/// gray, then five more of clearly different hue (black and gray are reserved for the
/// PCRLB and the NEES bands). Later filters get generated colours ([`color_of`]).
const COLORS: [RGBColor; 14] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(23, 190, 207),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(188, 189, 34),
    RGBColor(0, 0, 128),
    RGBColor(128, 0, 0),
    RGBColor(0, 128, 128),
    RGBColor(255, 0, 255),
    RGBColor(230, 171, 2),
];

/// `x` with `sig` significant digits: fixed notation for magnitudes in `[1e-3, 1e5)`,
/// scientific otherwise; "—" for NaN, "inf"/"-inf" for infinities.
pub fn fmt_sig(x: f64, sig: usize) -> String {
    if x.is_nan() {
        return "—".to_string();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf" } else { "-inf" }.to_string();
    }
    if x == 0.0 {
        return "0".to_string();
    }
    let sig = sig.max(1);
    // The exponent after rounding to `sig` digits.
    let sci = format!("{:.*e}", sig - 1, x);
    let exp: i32 = sci
        .split('e')
        .nth(1)
        .and_then(|e| e.parse().ok())
        .unwrap_or(0);
    if (-3..5).contains(&exp) {
        let decimals = (sig as i32 - 1 - exp).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        sci
    }
}

/// [`fmt_sig`] without trailing zeros after the decimal point (times, thresholds).
pub fn fmt_trim(x: f64, sig: usize) -> String {
    let s = fmt_sig(x, sig);
    let trim = |m: &str| -> String {
        if m.contains('.') {
            m.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            m.to_string()
        }
    };
    match s.split_once('e') {
        Some((m, e)) => format!("{}e{e}", trim(m)),
        None => trim(&s),
    }
}

/// The published figures of `label`, joined with "; " (None if there are none).
fn published_for(r: &McResult, label: &str) -> Option<String> {
    let texts: Vec<&str> = r
        .published
        .iter()
        .filter(|(l, _)| l == label)
        .map(|(_, t)| t.as_str())
        .collect();
    (!texts.is_empty()).then(|| texts.join("; "))
}

/// Text safe inside a Markdown table cell (no pipes, no line breaks).
fn cell(text: &str) -> String {
    text.replace('|', "\\|").replace(['\n', '\r'], " ")
}

fn fmt_consistency(c: Option<&Consistency>) -> String {
    match c {
        None => "—".to_string(),
        Some(c) => format!(
            "{} [{}, {}]; {} % of t in [{}, {}]",
            fmt_sig(c.avg, 4),
            fmt_sig(c.bounds.0, 4),
            fmt_sig(c.bounds.1, 4),
            fmt_sig(100.0 * c.in_band, 3),
            fmt_sig(c.band.0, 3),
            fmt_sig(c.band.1, 3),
        ),
    }
}

fn fmt_opt(x: Option<f64>, sig: usize) -> String {
    x.map_or_else(|| "—".to_string(), |v| fmt_sig(v, sig))
}

/// The campaign as a Markdown table: a title line, one row per filter (label | the
/// paper's published figure | time-averaged position and velocity RMSE | maximum errors |
/// convergence time | averaged NEES and NIS with their 95 % bounds and the percentage of
/// times inside the per-time band | efficiency versus the PCRLB | µs per step | failed
/// runs), rows "not run" for published filters without results, then the PCRLB's
/// time-averaged root (or why it is undefined) and the number of runs. `s` is
/// [`summarize`](crate::metrics::summarize)`(r)`.
pub fn markdown_table(r: &McResult, s: &[Summary]) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "### {} (`{}`)", cell(&r.title), cell(&r.scenario));
    let _ = writeln!(out);
    let _ = writeln!(
        out,
        "Errors averaged over t ≥ {} s. Convergence time: first time after which the RMSE of \
         every axis stays below {} m (position) and {} m/s (velocity).",
        fmt_trim(r.convergence_time, 4),
        fmt_trim(r.convergence_threshold.0, 4),
        fmt_trim(r.convergence_threshold.1, 4),
    );
    let _ = writeln!(out);
    let _ = writeln!(
        out,
        "| filter | published (paper) | pos RMSE [m] | vel RMSE [m/s] | max pos err [m] | \
         max vel err [m/s] | conv. time [s] | NEES avg [95 % bounds]; % of t in per-time band | \
         NIS avg [95 % bounds]; % of t in per-time band | efficiency pos / vel vs PCRLB | \
         µs/step | failed runs |"
    );
    let _ = writeln!(
        out,
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    for x in s {
        let published = published_for(r, &x.label).map_or_else(|| "—".to_string(), |p| cell(&p));
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} / {} | {} | {} |",
            cell(&x.label),
            published,
            fmt_sig(x.rmse_pos, 4),
            fmt_sig(x.rmse_vel, 4),
            fmt_sig(x.max_pos_err, 4),
            fmt_sig(x.max_vel_err, 4),
            x.convergence_time
                .map_or_else(|| "never".to_string(), |t| fmt_trim(t, 4)),
            fmt_consistency(x.nees.as_ref()),
            fmt_consistency(x.nis.as_ref()),
            fmt_opt(x.efficiency_pos, 3),
            fmt_opt(x.efficiency_vel, 3),
            fmt_sig(x.us_per_step, 3),
            x.failed_runs,
        );
    }
    // Published filters without results (in the order of `published`, once each).
    let mut seen = BTreeSet::new();
    for (label, _) in &r.published {
        if s.iter().any(|x| &x.label == label)
            || r.filters.iter().any(|f| &f.label == label)
            || !seen.insert(label.as_str())
        {
            continue;
        }
        let published = published_for(r, label).unwrap_or_default();
        let _ = writeln!(
            out,
            "| {} | {} | not run | — | — | — | — | — | — | — | — | — |",
            cell(label),
            cell(&published),
        );
    }
    let _ = writeln!(out);
    if !r.unreported_burns.is_empty() {
        let _ = writeln!(
            out,
            "Unreported burns. Recovery: time from a burn's end until the position RMSE \
             stays below {} m up to the next burn (or the end). Quiet phase: {} s up to the \
             first burn (the cost of a filter while nothing goes wrong); after: from the first \
             burn's start to the end. Ratios are to the first UKF row (`kind = \"ukf\"`).",
            fmt_trim(r.convergence_threshold.0, 4),
            fmt_trim(r.convergence_time, 4),
        );
        let _ = writeln!(out);
        let mut head = String::from("| filter |");
        let mut rule = String::from("|---|");
        for (a, b) in &r.unreported_burns {
            let _ = write!(
                head,
                " burn {}–{} s: recovery [s] |",
                fmt_trim(*a, 4),
                fmt_trim(*b, 4)
            );
            rule.push_str("---:|");
        }
        head.push_str(
            " quiet pos / vel RMSE [m, m/s] | quiet ÷ UKF pos / vel | after first burn pos / vel \
             RMSE [m, m/s] | after ÷ UKF pos / vel |",
        );
        rule.push_str("---:|---:|---:|---:|");
        let _ = writeln!(out, "{head}");
        let _ = writeln!(out, "{rule}");
        let ukf = s.iter().find(|x| x.kind == "ukf");
        let pair = |p: Option<(f64, f64)>| {
            p.map_or_else(
                || "—".to_string(),
                |(a, b)| format!("{} / {}", fmt_sig(a, 3), fmt_sig(b, 3)),
            )
        };
        let ratio = |p: Option<(f64, f64)>, q: Option<(f64, f64)>| match (p, q) {
            (Some((a, b)), Some((c, d))) => format!("{:.2} / {:.2}", a / c, b / d),
            _ => "—".to_string(),
        };
        for x in s {
            let mut row = format!("| {} |", cell(&x.label));
            for v in &x.recovery {
                let _ = write!(
                    row,
                    " {} |",
                    v.map_or_else(|| "never".to_string(), |t| fmt_trim(t, 4))
                );
            }
            let _ = write!(
                row,
                " {} | {} | {} | {} |",
                pair(x.quiet_rmse),
                ratio(x.quiet_rmse, ukf.and_then(|u| u.quiet_rmse)),
                pair(x.after_burn_rmse),
                ratio(x.after_burn_rmse, ukf.and_then(|u| u.after_burn_rmse)),
            );
            let _ = writeln!(out, "{row}");
        }
        let _ = writeln!(out);
    }
    match pcrlb_averaged(r) {
        Ok((p, v)) => {
            let _ = writeln!(
                out,
                "PCRLB (root of the time-averaged bound, t ≥ {} s): position {} m, \
                 velocity {} m/s.",
                fmt_trim(r.convergence_time, 4),
                fmt_sig(p, 4),
                fmt_sig(v, 4),
            );
        }
        Err(reason) => {
            let _ = writeln!(out, "PCRLB: undefined ({}).", cell(&reason));
        }
    }
    let _ = writeln!(out);
    if r.interrupted {
        let _ = writeln!(out, "Runs: {} (INTERRUPTED after {} runs).", r.runs, r.runs);
    } else {
        let _ = writeln!(out, "Runs: {}.", r.runs);
    }
    out
}

/// A number for the CSV files: empty for NaN, scientific for very small or large
/// magnitudes, shortest round-trip form otherwise.
fn csv_num(v: f64) -> String {
    if v.is_nan() {
        String::new()
    } else if v != 0.0 && v.is_finite() && (v.abs() < 1e-4 || v.abs() >= 1e15) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// Suffixes of the per-filter columns of `timeseries.csv`.
const TIMESERIES_COLUMNS: [&str; 12] = [
    "rmse_x",
    "rmse_y",
    "rmse_z",
    "rmse_vx",
    "rmse_vy",
    "rmse_vz",
    "rmse_pos",
    "rmse_vel",
    "nees",
    "nis",
    "max_pos_err",
    "max_vel_err",
];

/// Columns of the PCRLB in `timeseries.csv` (square roots of the bound).
const PCRLB_COLUMNS: [&str; 8] = [
    "pcrlb_x",
    "pcrlb_y",
    "pcrlb_z",
    "pcrlb_vx",
    "pcrlb_vy",
    "pcrlb_vz",
    "pcrlb_pos",
    "pcrlb_vel",
];

/// Columns of `summary.csv`.
pub const SUMMARY_COLUMNS: [&str; 35] = [
    "label",
    "kind",
    "runs_used",
    "failed_runs",
    "avg_from_s",
    "avg_times",
    "rmse_pos_m",
    "rmse_vel_mps",
    "rmse_x_m",
    "rmse_y_m",
    "rmse_z_m",
    "rmse_vx_mps",
    "rmse_vy_mps",
    "rmse_vz_mps",
    "max_pos_err_m",
    "max_vel_err_mps",
    "convergence_time_s",
    "nees_avg",
    "nees_lo",
    "nees_hi",
    "nees_band_lo",
    "nees_band_hi",
    "nees_in_band",
    "nis_avg",
    "nis_lo",
    "nis_hi",
    "nis_band_lo",
    "nis_band_hi",
    "nis_in_band",
    "efficiency_pos",
    "efficiency_vel",
    "us_per_step",
    "pcrlb_pos_m",
    "pcrlb_vel_mps",
    "published",
];

/// One cell of `summary.csv`, typed (see [`summary_fields`]).
#[derive(Debug, Clone, PartialEq)]
pub enum Field {
    /// Text (label, kind, published figure).
    Text(String),
    /// A count.
    Int(u64),
    /// A number; NaN where the value is undefined (an empty cell).
    Num(f64),
}

impl Field {
    fn opt(v: Option<f64>) -> Self {
        Field::Num(v.unwrap_or(f64::NAN))
    }

    /// The CSV text of this cell.
    fn csv(&self) -> String {
        match self {
            Field::Text(t) => t.clone(),
            Field::Int(i) => i.to_string(),
            Field::Num(v) => csv_num(*v),
        }
    }
}

fn consistency_fields(c: Option<&Consistency>) -> [Field; 6] {
    match c {
        None => std::array::from_fn(|_| Field::Num(f64::NAN)),
        Some(c) => [c.avg, c.bounds.0, c.bounds.1, c.band.0, c.band.1, c.in_band].map(Field::Num),
    }
}

/// The rows of `summary.csv` as typed values, one row per filter in the order of
/// [`SUMMARY_COLUMNS`] ([`write_csv`] writes exactly these). `s` is
/// [`summarize`](crate::metrics::summarize)`(r)`.
pub fn summary_fields(r: &McResult, s: &[Summary]) -> Vec<Vec<Field>> {
    let bound = pcrlb_averaged(r).ok();
    s.iter()
        .map(|x| {
            let mut row = vec![
                Field::Text(x.label.clone()),
                Field::Text(x.kind.clone()),
                Field::Int(u64::from(x.runs_used)),
                Field::Int(u64::from(x.failed_runs)),
                Field::Num(x.avg_from),
                Field::Int(x.avg_times as u64),
                Field::Num(x.rmse_pos),
                Field::Num(x.rmse_vel),
            ];
            row.extend(x.rmse_axes.iter().map(|v| Field::Num(*v)));
            row.push(Field::Num(x.max_pos_err));
            row.push(Field::Num(x.max_vel_err));
            row.push(Field::opt(x.convergence_time));
            row.extend(consistency_fields(x.nees.as_ref()));
            row.extend(consistency_fields(x.nis.as_ref()));
            row.push(Field::opt(x.efficiency_pos));
            row.push(Field::opt(x.efficiency_vel));
            row.push(Field::Num(x.us_per_step));
            row.push(Field::opt(bound.map(|b| b.0)));
            row.push(Field::opt(bound.map(|b| b.1)));
            row.push(Field::Text(published_for(r, &x.label).unwrap_or_default()));
            row
        })
        .collect()
}

/// The columns of `timeseries.csv`: name and one value per time (NaN where the cell is
/// empty); [`write_csv`] writes exactly these. Columns as documented there.
pub fn timeseries_columns(r: &McResult) -> Vec<(String, Vec<f64>)> {
    let n = r.t.len();
    let at = |v: &[f64], k: usize| v.get(k).copied().unwrap_or(f64::NAN);
    // per-axis RMSE (6), position and velocity RMSE of a per-time MSE series
    let rmse = |prefix: &str, v: Option<&[[f64; 6]]>, names: &[&str]| {
        let (axes, pos, vel) = match v {
            Some(v) => (rmse_axes(v), rmse_pos(v), rmse_vel(v)),
            None => (Vec::new(), Vec::new(), Vec::new()),
        };
        let mut cols: Vec<(String, Vec<f64>)> = (0..6)
            .map(|i| {
                let col = (0..n)
                    .map(|k| axes.get(k).map_or(f64::NAN, |a| a[i]))
                    .collect();
                (format!("{prefix}{}", names[i]), col)
            })
            .collect();
        cols.push((
            format!("{prefix}{}", names[6]),
            (0..n).map(|k| at(&pos, k)).collect(),
        ));
        cols.push((
            format!("{prefix}{}", names[7]),
            (0..n).map(|k| at(&vel, k)).collect(),
        ));
        cols
    };
    let mut cols = vec![("t".to_string(), r.t.clone())];
    for f in &r.filters {
        let p = format!("{}_", f.label);
        cols.extend(rmse(&p, Some(&f.mse), &TIMESERIES_COLUMNS[..8]));
        for (name, v) in [
            (TIMESERIES_COLUMNS[8], &f.nees),
            (TIMESERIES_COLUMNS[9], &f.nis),
            (TIMESERIES_COLUMNS[10], &f.max_pos_err),
            (TIMESERIES_COLUMNS[11], &f.max_vel_err),
        ] {
            cols.push((format!("{p}{name}"), (0..n).map(|k| at(v, k)).collect()));
        }
    }
    cols.extend(rmse(
        "",
        r.pcrlb.as_ref().ok().map(Vec::as_slice),
        &PCRLB_COLUMNS,
    ));
    cols
}

fn write_records(path: &Path, rows: impl Iterator<Item = Vec<String>>) -> Result<(), String> {
    let err = |e: &dyn std::fmt::Display| format!("cannot write {}: {e}", path.display());
    let mut w = csv::Writer::from_path(path).map_err(|e| err(&e))?;
    for row in rows {
        w.write_record(&row).map_err(|e| err(&e))?;
    }
    w.flush().map_err(|e| err(&e))
}

/// Writes `timeseries.csv` and `summary.csv` into `dir` (created if needed) and returns
/// their paths.
///
/// `timeseries.csv`: a header row, then one row per time: `t` \[s\]; for each filter
/// `<label>_rmse_x`, `_rmse_y`, `_rmse_z` \[m\], `_rmse_vx`, `_rmse_vy`, `_rmse_vz` \[m/s\],
/// `_rmse_pos` \[m\], `_rmse_vel` \[m/s\], `_nees`, `_nis` (empty where no measurement),
/// `_max_pos_err` \[m\], `_max_vel_err` \[m/s\]; then `pcrlb_x` .. `pcrlb_vz`, `pcrlb_pos`,
/// `pcrlb_vel`: square roots of the PCRLB (empty cells when it is undefined).
/// ([`timeseries_columns`] gives the same columns as numbers.)
///
/// `summary.csv`: a header row, then one row per filter with the [`Summary`] numbers,
/// the PCRLB's time-averaged root and the published figure (units in the column names:
/// `_m`, `_mps` \[m/s\], `_s`). ([`summary_fields`] gives the same rows as typed values.)
pub fn write_csv(r: &McResult, s: &[Summary], dir: &Path) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;

    let cols = timeseries_columns(r);
    let header: Vec<String> = cols.iter().map(|(name, _)| name.clone()).collect();
    let rows = (0..r.t.len()).map(|k| {
        cols.iter()
            .map(|(_, v)| csv_num(v.get(k).copied().unwrap_or(f64::NAN)))
            .collect()
    });
    let ts_path = dir.join("timeseries.csv");
    write_records(&ts_path, std::iter::once(header).chain(rows))?;

    let header: Vec<String> = SUMMARY_COLUMNS.iter().map(|c| (*c).to_string()).collect();
    let rows = summary_fields(r, s)
        .into_iter()
        .map(|row| row.iter().map(Field::csv).collect());
    let sum_path = dir.join("summary.csv");
    write_records(&sum_path, std::iter::once(header).chain(rows))?;
    Ok(vec![ts_path, sum_path])
}

/// Registers DejaVu Sans as plotters' "sans-serif" once per process; the error says
/// which file and package are missing.
fn ensure_font() -> Result<(), String> {
    static FONT: OnceLock<Result<(), String>> = OnceLock::new();
    FONT.get_or_init(|| {
        let bytes = std::fs::read(FONT_PATH).map_err(|e| {
            format!(
                "cannot draw plots: font {FONT_PATH} not readable ({e}); install the Debian \
                 package fonts-dejavu-core"
            )
        })?;
        let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
        plotters::style::register_font("sans-serif", FontStyle::Normal, bytes)
            .map_err(|_| format!("cannot draw plots: {FONT_PATH} is not a valid font"))
    })
    .clone()
}

/// One line of a plot.
struct Curve {
    label: String,
    color: RGBColor,
    dashed: bool,
    points: Vec<(f64, f64)>,
}

impl Curve {
    fn new(label: &str, color: RGBColor, dashed: bool, t: &[f64], y: &[f64]) -> Self {
        Curve {
            label: label.to_string(),
            color,
            dashed,
            points: t.iter().copied().zip(y.iter().copied()).collect(),
        }
    }

    /// Runs of consecutive points drawable on a log y-axis (finite, y > 0).
    fn segments(&self) -> Vec<Vec<(f64, f64)>> {
        let mut out = Vec::new();
        let mut cur = Vec::new();
        for &(x, y) in &self.points {
            if x.is_finite() && y.is_finite() && y > 0.0 {
                cur.push((x, y));
            } else if !cur.is_empty() {
                out.push(std::mem::take(&mut cur));
            }
        }
        if !cur.is_empty() {
            out.push(cur);
        }
        out
    }
}

/// The colour of filter `i`: every filter its own. The palette first; beyond it hues
/// stepped by the golden angle (137.5 degrees, so no two coincide) at three lightness
/// levels, fully saturated (never black or gray).
fn color_of(i: usize) -> RGBColor {
    if let Some(c) = COLORS.get(i) {
        return *c;
    }
    let k = i - COLORS.len();
    let hue = (20.0 + k as f64 * 137.507_764_050_037_85).rem_euclid(360.0);
    let lightness = [0.35, 0.55, 0.7][k % 3];
    hsl_to_rgb(hue, 1.0, lightness)
}

/// HSL (hue in degrees, saturation and lightness in [0, 1]) to 8-bit RGB.
fn hsl_to_rgb(h: f64, s: f64, l: f64) -> RGBColor {
    let c = (1.0 - (2.0 * l - 1.0).abs()) * s;
    let hp = h / 60.0;
    let x = c * (1.0 - (hp.rem_euclid(2.0) - 1.0).abs());
    let (r, g, b) = match hp as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let m = l - c / 2.0;
    let to8 = |v: f64| ((v + m) * 255.0).round().clamp(0.0, 255.0) as u8;
    RGBColor(to8(r), to8(g), to8(b))
}

/// Time axis range: the finite times (a unit range around a single time).
fn time_range(t: &[f64]) -> Result<Range<f64>, String> {
    let (lo, hi) = t
        .iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    if !lo.is_finite() {
        return Err("cannot draw plots: no finite times".to_string());
    }
    Ok(if hi > lo { lo..hi } else { lo..lo + 1.0 })
}

/// Log y range covering the drawable points of all curves (a default range if none).
fn log_range(curves: &[Curve]) -> Range<f64> {
    let (lo, hi) = curves
        .iter()
        .flat_map(|c| c.segments().into_iter().flatten())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (_, y)| {
            (a.min(y), b.max(y))
        });
    if !(lo.is_finite() && hi.is_finite()) {
        return 0.1..10.0;
    }
    let (lo, hi) = if hi > lo {
        (lo, hi)
    } else {
        (lo / 2.0, hi * 2.0)
    };
    (lo / 1.25)..(hi * 1.25)
}

/// A "nice" step (1, 2 or 5 times a power of ten) near `raw` (> 0).
fn nice_step(raw: f64) -> f64 {
    let p = 10f64.powf(raw.log10().floor());
    let m = raw / p;
    let n = if m <= 1.0 {
        1.0
    } else if m <= 2.0 {
        2.0
    } else if m <= 5.0 {
        5.0
    } else {
        10.0
    };
    n * p
}

/// Labelled (bold) and unlabelled (light) tick values of a log axis over `range`
/// (finite, `0 < start < end`): powers of ten over many decades, 1-2-5 over a few, nice
/// linear steps within less than a decade.
fn log_ticks(range: &Range<f64>) -> (Vec<f64>, Vec<f64>) {
    let (lo, hi) = (range.start, range.end);
    let inside = |v: &f64| *v >= lo * (1.0 - 1e-12) && *v <= hi * (1.0 + 1e-12);
    let decades = (hi / lo).log10();
    let (mut bold, mut light) = (Vec::new(), Vec::new());
    if !(decades.is_finite() && decades > 0.0) {
        return (bold, light);
    }
    if decades <= 1.0 {
        let step = nice_step((hi - lo) / 5.0);
        let first = (lo / step).ceil() as i64;
        let last = (hi / step).floor() as i64;
        bold.extend((first..=last).map(|i| i as f64 * step).filter(|v| *v > 0.0));
        let fine = step / 5.0;
        let first = (lo / fine).ceil() as i64;
        let last = (hi / fine).floor() as i64;
        light.extend((first..=last).map(|i| i as f64 * fine).filter(|v| *v > 0.0));
        return (bold, light);
    }
    let e_lo = lo.log10().floor() as i32;
    let e_hi = hi.log10().ceil() as i32;
    let every = (decades / 8.0).ceil().max(1.0) as i32;
    for e in e_lo..=e_hi {
        let p = 10f64.powi(e);
        for m in 1..10 {
            let v = f64::from(m) * p;
            if !inside(&v) {
                continue;
            }
            let is_bold = if decades > 2.5 {
                m == 1 && e.rem_euclid(every) == 0
            } else {
                matches!(m, 1 | 2 | 5)
            };
            if is_bold {
                bold.push(v);
            } else if decades <= 8.0 || m == 1 {
                light.push(v);
            }
        }
    }
    (bold, light)
}

/// A tick label: three significant digits without trailing zeros.
fn fmt_tick(v: f64) -> String {
    fmt_trim(v, 3)
}

fn draw_err(what: &str, e: impl std::fmt::Display) -> String {
    format!("cannot draw {what}: {e}")
}

/// Draws `curves` into `area` with a linear time axis and a log y-axis.
fn draw_log_panel(
    area: &DrawingArea<BitMapBackend<'_>, Shift>,
    what: &str,
    caption: Option<&str>,
    y_desc: &str,
    x_range: Range<f64>,
    curves: &[Curve],
    legend: bool,
) -> Result<(), String> {
    let y_range = log_range(curves);
    let mut builder = ChartBuilder::on(area);
    builder
        .margin(10)
        .x_label_area_size(45)
        .y_label_area_size(80);
    if let Some(c) = caption {
        builder.caption(c, ("sans-serif", 24));
    }
    let (bold, light) = log_ticks(&y_range);
    let y_axis = y_range
        .log_scale()
        .with_key_points(bold)
        .with_light_points(light);
    let mut chart = builder
        .build_cartesian_2d(x_range, y_axis)
        .map_err(|e| draw_err(what, e))?;
    chart
        .configure_mesh()
        .x_desc("time [s]")
        .y_desc(y_desc)
        .y_label_formatter(&|v| fmt_tick(*v))
        .x_label_formatter(&|v| fmt_tick(*v))
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .draw()
        .map_err(|e| draw_err(what, e))?;
    for c in curves {
        let style = c.color.stroke_width(2);
        // Unlabelled curves (the upper band line) get no legend entry.
        let mut labelled = c.label.is_empty();
        for seg in c.segments() {
            let anno = if c.dashed {
                chart.draw_series(DashedLineSeries::new(seg, 8, 5, style))
            } else {
                chart.draw_series(LineSeries::new(seg, style))
            }
            .map_err(|e| draw_err(what, e))?;
            if !labelled {
                let color = c.color;
                anno.label(c.label.as_str()).legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                });
                labelled = true;
            }
        }
    }
    if legend {
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 14))
            .draw()
            .map_err(|e| draw_err(what, e))?;
    }
    Ok(())
}

/// One single-panel PNG of `curves`.
fn single_plot(
    path: &Path,
    title: &str,
    y_desc: &str,
    x_range: Range<f64>,
    curves: &[Curve],
) -> Result<(), String> {
    let what = path.display().to_string();
    let root = BitMapBackend::new(path, PLOT_SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(|e| draw_err(&what, e))?;
    draw_log_panel(&root, &what, Some(title), y_desc, x_range, curves, true)?;
    root.present().map_err(|e| draw_err(&what, e))
}

/// The filters' RMSE curves (`pick` chooses the series) and the PCRLB's root, dashed.
fn rmse_curves(r: &McResult, pick: impl Fn(&[[f64; 6]]) -> Vec<f64>) -> Vec<Curve> {
    let mut curves: Vec<Curve> = r
        .filters
        .iter()
        .enumerate()
        .map(|(i, f)| Curve::new(&f.label, color_of(i), false, &r.t, &pick(&f.mse)))
        .collect();
    if let Ok(j) = &r.pcrlb {
        curves.push(Curve::new("PCRLB", BLACK, true, &r.t, &pick(j)));
    }
    curves
}

/// The three-panel plot of the x, y and z RMSE (with the PCRLB) into `path`.
fn axes_plot(r: &McResult, path: &Path, x_range: Range<f64>) -> Result<(), String> {
    let what = path.display().to_string();
    let root = BitMapBackend::new(path, AXES_PLOT_SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(|e| draw_err(&what, e))?;
    let body = root
        .titled(&r.title, ("sans-serif", 24))
        .map_err(|e| draw_err(&what, e))?;
    let panels = body.split_evenly((3, 1));
    for (axis, (panel, name)) in panels.iter().zip(["x", "y", "z"]).enumerate() {
        let pick = |v: &[[f64; 6]]| -> Vec<f64> {
            rmse_axes(v)
                .iter()
                .map(|a| a.get(axis).copied().unwrap_or(f64::NAN))
                .collect()
        };
        let curves = rmse_curves(r, pick);
        let y_desc = format!("{name} RMSE [m]");
        draw_log_panel(
            panel,
            &what,
            None,
            &y_desc,
            x_range.clone(),
            &curves,
            axis == 0,
        )?;
    }
    root.present().map_err(|e| draw_err(&what, e))
}

/// Writes the PNG plots into `dir` (created if needed) and returns their paths:
///
/// - `position_rmse.png`, `velocity_rmse.png`: RMSE versus time, one line per filter,
///   the PCRLB's root as a dashed black line "PCRLB" (when defined), log y-axis;
/// - `nees.png`: mean NEES versus time with the per-time 95 % band
///   `chi2inv(0.025, 6M)/M .. chi2inv(0.975, 6M)/M` as two dashed lines (one band per
///   distinct number `M` of runs used by the filters), log y-axis;
/// - `position_error_axes.png`: three stacked panels, x, y and z RMSE with the PCRLB.
///
/// The title is the scenario title. Non-finite and non-positive values are left out
/// (lines break there). Errors (missing font [`FONT_PATH`], unwritable directory, no
/// finite times) are returned, never panicked.
pub fn write_plots(r: &McResult, dir: &Path) -> Result<Vec<PathBuf>, String> {
    ensure_font()?;
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let x_range = time_range(&r.t)?;
    let mut paths = Vec::new();

    let p = dir.join("position_rmse.png");
    let curves = rmse_curves(r, rmse_pos);
    single_plot(&p, &r.title, "position RMSE [m]", x_range.clone(), &curves)?;
    paths.push(p);

    let p = dir.join("velocity_rmse.png");
    let curves = rmse_curves(r, rmse_vel);
    single_plot(
        &p,
        &r.title,
        "velocity RMSE [m/s]",
        x_range.clone(),
        &curves,
    )?;
    paths.push(p);

    let p = dir.join("nees.png");
    let mut curves: Vec<Curve> = r
        .filters
        .iter()
        .enumerate()
        .map(|(i, f)| Curve::new(&f.label, color_of(i), false, &r.t, &f.nees))
        .collect();
    let counts: BTreeSet<u32> = r
        .filters
        .iter()
        .map(|f| r.runs.saturating_sub(f.failed_runs))
        .filter(|m| *m > 0)
        .collect();
    let ends = [x_range.start, x_range.end];
    for (i, m) in counts.iter().rev().enumerate() {
        let (lo, hi) = chi2_mean_bounds(6, u64::from(*m));
        let color = if i == 0 {
            BLACK
        } else {
            RGBColor(128, 128, 128)
        };
        curves.push(Curve::new(
            &format!("95 % band (M = {m})"),
            color,
            true,
            &ends,
            &[lo, lo],
        ));
        curves.push(Curve::new("", color, true, &ends, &[hi, hi]));
    }
    single_plot(&p, &r.title, "mean NEES [-]", x_range.clone(), &curves)?;
    paths.push(p);

    let p = dir.join("position_error_axes.png");
    axes_plot(r, &p, x_range)?;
    paths.push(p);

    Ok(paths)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics;
    use crate::results::FilterStats;

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
            failed_runs: 0,
            us_per_step: 1.234,
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

        let mut rd = csv::Reader::from_path(dir.join("timeseries.csv")).unwrap();
        let header = rd.headers().unwrap().clone();
        assert_eq!(header.len(), 1 + 2 * 12 + 8);
        assert_eq!(header.get(0), Some("t"));
        assert_eq!(header.get(1), Some("EKF_rmse_x"));
        assert_eq!(header.get(7), Some("EKF_rmse_pos"));
        assert_eq!(header.get(13), Some("UKF_rmse_x"));
        assert_eq!(header.get(25), Some("pcrlb_x"));
        assert_eq!(header.get(32), Some("pcrlb_vel"));
        let rows: Vec<csv::StringRecord> = rd.records().map(Result::unwrap).collect();
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

        let mut rd = csv::Reader::from_path(dir.join("summary.csv")).unwrap();
        let header = rd.headers().unwrap().clone();
        assert_eq!(header.len(), SUMMARY_COLUMNS.len());
        assert_eq!(header.get(0), Some("label"));
        let rows: Vec<csv::StringRecord> = rd.records().map(Result::unwrap).collect();
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0].get(0), Some("EKF"));
        assert_eq!(rows[1].get(0), Some("UKF"));
        assert_eq!(rows[1].get(2), Some("18"));
        assert_eq!(rows[0].get(34), Some("0.52 m RMSE (Table 2)"));

        // Undefined PCRLB: empty bound cells, same shape.
        let mut r = r;
        r.pcrlb = Err("undefined".to_string());
        write_csv(&r, &s, &dir).unwrap();
        let mut rd = csv::Reader::from_path(dir.join("timeseries.csv")).unwrap();
        let rows: Vec<csv::StringRecord> = rd.records().map(Result::unwrap).collect();
        assert_eq!(rows.len(), n);
        assert_eq!(rows[0].get(25), Some(""));
        assert_eq!(rows[0].len(), 33);
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
                "position_error_axes.png"
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
        assert_eq!(write_plots(&r, &dir).unwrap().len(), 4);
        // No times at all: an error, not a panic.
        r.t.clear();
        assert!(write_plots(&r, &dir)
            .unwrap_err()
            .contains("no finite times"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
