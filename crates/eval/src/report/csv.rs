//! The campaign's CSV files, `timeseries.csv` and `summary.csv` ([`write_csv`]), and the
//! same columns and rows as values ([`timeseries_columns`], [`summary_fields`]).

use super::published_for;
use crate::metrics::{pcrlb_averaged, rmse_axes, rmse_pos, rmse_vel, Consistency, Summary};
use crate::results::McResult;
use std::path::{Path, PathBuf};

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
const TIMESERIES_COLUMNS: [&str; 14] = [
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
    "range_rmse",
    "range_sigma",
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

const RUN_BOUND_COLUMNS: [&str; 8] = [
    "run_bound_x",
    "run_bound_y",
    "run_bound_z",
    "run_bound_vx",
    "run_bound_vy",
    "run_bound_vz",
    "run_bound_pos",
    "run_bound_vel",
];

/// Columns of `summary.csv`.
pub const SUMMARY_COLUMNS: [&str; 40] = [
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
    "efficiency_runs_pos",
    "efficiency_runs_vel",
    "us_per_step",
    "move_acceptance",
    "pcrlb_pos_m",
    "pcrlb_vel_mps",
    "run_bound_pos_m",
    "run_bound_vel_mps",
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
    let runs = crate::metrics::run_bound_averaged(r).ok();
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
            row.push(Field::opt(x.efficiency_runs_pos));
            row.push(Field::opt(x.efficiency_runs_vel));
            row.push(Field::Num(x.us_per_step));
            row.push(Field::opt(
                (!x.move_acceptance.is_nan()).then_some(x.move_acceptance),
            ));
            row.push(Field::opt(bound.map(|b| b.0)));
            row.push(Field::opt(bound.map(|b| b.1)));
            row.push(Field::opt(runs.map(|b| b.0)));
            row.push(Field::opt(runs.map(|b| b.1)));
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
        for (name, v) in [
            (TIMESERIES_COLUMNS[12], &f.range_mse),
            (TIMESERIES_COLUMNS[13], &f.range_var),
        ] {
            cols.push((
                format!("{p}{name}"),
                (0..n).map(|k| at(v, k).sqrt()).collect(),
            ));
        }
    }
    cols.extend(rmse(
        "",
        r.pcrlb.as_ref().ok().map(Vec::as_slice),
        &PCRLB_COLUMNS,
    ));
    cols.extend(rmse(
        "",
        r.pcrlb_runs.as_ref().ok().map(Vec::as_slice),
        &RUN_BOUND_COLUMNS,
    ));
    cols.push((
        "run_bound_range".to_string(),
        (0..n).map(|k| at(&r.range_bound_runs, k).sqrt()).collect(),
    ));
    cols
}

fn write_records(path: &Path, rows: impl Iterator<Item = Vec<String>>) -> Result<(), String> {
    let err = |e: &dyn std::fmt::Display| format!("cannot write {}: {e}", path.display());
    let mut w = ::csv::Writer::from_path(path).map_err(|e| err(&e))?;
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
/// `pcrlb_vel`: square roots of the PCRLB (empty cells when it is undefined); then
/// `run_bound_x` .. `run_bound_vel`, those of the bound along each run's truth.
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
