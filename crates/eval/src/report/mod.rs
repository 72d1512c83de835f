//! Reports of a Monte Carlo campaign: a Markdown table, CSV files and PNG plots.
//!
//! - [`markdown_table`] (`table.rs`): one row per filter with the
//!   [`Summary`](crate::metrics::Summary) metrics next to the paper's published figure,
//!   rows "not run" for published filters without results, the PCRLB's time-averaged root
//!   and the number of runs.
//! - [`write_csv`] (`csv.rs`): `timeseries.csv` (per-time RMSE, NEES, NIS, maximum errors
//!   and the PCRLB's root) and `summary.csv` (one row per filter).
//! - [`write_plots`] (`plot.rs`): `position_rmse.png`, `velocity_rmse.png`, `nees.png` and
//!   `position_error_axes.png`, like the papers' error-curve figures (log y-axis, the PCRLB
//!   as a dashed black line).
//!
//! Text in the PNGs is drawn with DejaVu Sans, read at run time from [`FONT_PATH`]
//! (Debian package `fonts-dejavu-core`); without it [`write_plots`] returns an error.

mod csv;
mod plot;
mod table;
#[cfg(test)]
mod tests;

pub use csv::{summary_fields, timeseries_columns, write_csv, Field, SUMMARY_COLUMNS};
pub use plot::{write_plots, FONT_PATH};
pub use table::markdown_table;

use crate::results::McResult;

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
pub(super) fn published_for(r: &McResult, label: &str) -> Option<String> {
    let texts: Vec<&str> = r
        .published
        .iter()
        .filter(|(l, _)| l == label)
        .map(|(_, t)| t.as_str())
        .collect();
    (!texts.is_empty()).then(|| texts.join("; "))
}
