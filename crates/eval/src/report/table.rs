//! The campaign as a Markdown table ([`markdown_table`]).

use super::{fmt_sig, fmt_trim, published_for};
use crate::metrics::{pcrlb_averaged, Consistency, Summary};
use crate::results::McResult;
use std::collections::BTreeSet;
use std::fmt::Write as _;

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
         pos / vel vs run-wise bound | µs/step | moves accepted | failed runs |"
    );
    let _ = writeln!(
        out,
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    for x in s {
        let published = published_for(r, &x.label).map_or_else(|| "—".to_string(), |p| cell(&p));
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} / {} | {} / {} | {} | {} | {} |",
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
            fmt_opt(x.efficiency_runs_pos, 3),
            fmt_opt(x.efficiency_runs_vel, 3),
            fmt_sig(x.us_per_step, 3),
            if x.move_acceptance.is_nan() {
                "—".to_string()
            } else {
                fmt_sig(x.move_acceptance, 3)
            },
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
            "| {} | {} | not run | — | — | — | — | — | — | — | — | — | — | — |",
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
    if let Ok((p, v)) = crate::metrics::run_bound_averaged(r) {
        let _ = writeln!(
            out,
            "Run-wise bound (the same recursion along each run's own truth, averaged over the \
             runs; at or above the PCRLB): position {} m, velocity {} m/s.",
            fmt_sig(p, 4),
            fmt_sig(v, 4),
        );
    }
    let _ = writeln!(out);
    if r.interrupted {
        let _ = writeln!(out, "Runs: {} (INTERRUPTED after {} runs).", r.runs, r.runs);
    } else {
        let _ = writeln!(out, "Runs: {}.", r.runs);
    }
    out
}
