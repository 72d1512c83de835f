//! Summary metrics of a Monte Carlo campaign: what the report tables and plots show.
//!
//! Notation: a campaign ([`McResult`]) has times `t[k]`, `k = 0..K_all`, and per filter
//! ([`FilterStats`]) the mean over the runs of the squared error per axis
//! `mse[k][i]` (`i` = x, y, z, vx, vy, vz), the mean NEES `nees[k]`, the mean NIS `nis[k]`
//! over the `nis_count[k]` runs that processed a measurement at `t[k]`, and the largest
//! error norms `max_pos_err[k]`, `max_vel_err[k]` over the runs. `M = runs - failed_runs`
//! is the number of runs that contributed to a filter's statistics. The averaging set is
//! `A = { k : t[k] >= convergence_time }` with the scenario's
//! [`McResult::convergence_time`]; `|A|` is its size.
//!
//! # Definitions
//!
//! - **RMSE time series** ([`rmse_axes`], [`rmse_pos`], [`rmse_vel`]): per axis
//!   `rmse_i[k] = sqrt(mse[k][i])`; position `rmse_pos[k] = sqrt(mse[k][x] + mse[k][y] +
//!   mse[k][z])` (the root of the mean squared position-error norm), velocity likewise
//!   with vx, vy, vz. The same functions applied to the PCRLB's diagonal of `J^-1`
//!   (variances) give the bound's square roots, comparable with the RMSE.
//! - **Time-averaged RMSE** ([`Summary::rmse_pos`], [`Summary::rmse_vel`],
//!   [`Summary::rmse_axes`]): `sqrt( (1/|A|) * sum_{k in A} (mse[k][x] + mse[k][y] +
//!   mse[k][z]) )`, velocity likewise, and per axis `sqrt( (1/|A|) * sum_{k in A}
//!   mse[k][i] )`. This is the root of the time-and-run mean of the squared error (not the
//!   mean of the per-time RMSE). NaN when `A` is empty.
//! - **Maximum error** ([`Summary::max_pos_err`], [`Summary::max_vel_err`]):
//!   `max_{k in A} max_pos_err[k]` — the largest position-error norm of any run at any time
//!   of `A` \[m\]; velocity likewise \[m/s\]. NaN values are ignored; NaN when `A` is empty.
//! - **Convergence time** ([`convergence_time`]): the first `t[k]` such that for every
//!   `j >= k` up to the last time, `rmse_i[j] < threshold.0` for the three position axes
//!   and `rmse_i[j] < threshold.1` for the three velocity axes
//!   ([`McResult::convergence_threshold`]). `None` when the condition fails at the last
//!   time (never converged). A NaN RMSE counts as above the threshold.
//! - **Averaged NEES and NIS** ([`Consistency`]): a consistent filter's NEES of one run at
//!   one time is chi-square with `d = 6` degrees of freedom (NIS: `d = 3`). With `c[k]`
//!   runs contributing at time `k` (NEES: `c[k] = M`; NIS: `c[k] = nis_count[k]`) and
//!   the used times `U = { k in A : c[k] > 0 and v[k] is not NaN }` (NaN times, i.e.
//!   no measurement, are skipped; an infinite value makes the average infinite), the
//!   average is the time-and-run mean `avg = sum_{k in U} c[k] * v[k] / N` with
//!   `N = sum_{k in U} c[k]` samples (for the NEES simply the time average of `nees[k]`).
//!   If the samples were independent, `N * avg ~ chi2(d N)`, so its two-sided 95 % bounds are
//!   `[chi2inv(0.025, d N) / N, chi2inv(0.975, d N) / N]`. Successive times of one run are
//!   correlated, which makes these bounds too narrow, so a second check is reported: the
//!   per-time band `[chi2inv(0.025, d c) / c, chi2inv(0.975, d c) / c]` and the fraction
//!   of the times `k in U` whose `v[k]` lies inside the band for its own `c = c[k]`
//!   (about 0.95 for a consistent filter). [`Consistency::band`] is the band for the
//!   largest `c[k]` over `U` (normally `M`: every run processed a measurement).
//! - **Efficiency versus the PCRLB** ([`Summary::efficiency_pos`],
//!   [`Summary::efficiency_vel`]): `rmse_pos / sqrt( (1/|A|) * sum_{k in A} (Jinv[k][x] +
//!   Jinv[k][y] + Jinv[k][z]) )` with `Jinv[k]` the diagonal of the PCRLB's `J^-1` at
//!   `t[k]`; velocity likewise. For any unbiased estimator it is `>= 1` up to Monte Carlo
//!   noise (1 = efficient). `None` when the PCRLB is not defined (`Err`), its length
//!   differs from the number of times, `A` is empty or the averaged bound is not positive
//!   and finite. [`Summary::efficiency_runs_pos`] and [`Summary::efficiency_runs_vel`] are
//!   the same ratios to the bound along each run's own truth ([`McResult::pcrlb_runs`]).
//! - **Cost and failures**: [`Summary::us_per_step`] and [`Summary::failed_runs`] are
//!   copied from [`FilterStats`].
//!
//! # Chi-square quantiles
//!
//! [`chi2_inv`] uses statrs' `ChiSquared::inverse_cdf` up to `10^4` degrees of freedom.
//! Above that (campaign averages reach `6 M K ~ 10^7`), statrs' incomplete-gamma inversion
//! loses accuracy and eventually returns NaN, so the Wilson–Hilferty approximation
//! `d (1 - 2/(9d) + z_p sqrt(2/(9d)))^3` (`z_p` the standard normal quantile) is used; its
//! relative error there is below `10^-7`.

use statrs::distribution::{ChiSquared, ContinuousCDF, Normal};

use crate::results::{FilterStats, McResult};

/// Degrees of freedom above which [`chi2_inv`] switches to Wilson–Hilferty.
const WILSON_HILFERTY_ABOVE: f64 = 1.0e4;

/// Probability of the lower end of the two-sided 95 % bounds.
const P_LO: f64 = 0.025;
/// Probability of the upper end of the two-sided 95 % bounds.
const P_HI: f64 = 0.975;

/// A chi-square consistency check of the averaged NEES or NIS (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Consistency {
    /// Degrees of freedom of one sample: 6 for the NEES, 3 for the NIS.
    pub dof: u32,
    /// Time-and-run average over the used times (count-weighted).
    pub avg: f64,
    /// Number of used times (in the averaging set, count > 0, value not NaN).
    pub times: usize,
    /// Number of samples `N` = sum of the per-time counts over the used times.
    pub samples: u64,
    /// Two-sided 95 % bounds of `avg` if all samples were independent:
    /// `chi2inv(0.025, dof N) / N`, `chi2inv(0.975, dof N) / N`.
    pub bounds: (f64, f64),
    /// Per-time 95 % band `chi2inv(0.025, dof c) / c`, `chi2inv(0.975, dof c) / c` for
    /// `c` = [`Consistency::band_count`].
    pub band: (f64, f64),
    /// The count `c` of [`Consistency::band`]: the largest per-time count over the used
    /// times.
    pub band_count: u64,
    /// Fraction (0..=1) of the used times whose value lies inside the per-time band of
    /// its own count (about 0.95 when consistent).
    pub in_band: f64,
}

/// Summary metrics of one filter over a campaign (definitions in the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// Filter label from the scenario.
    pub label: String,
    /// Filter kind name (`ekf`, `ukf`, ...).
    pub kind: String,
    /// Runs that contributed to the statistics: `runs - failed_runs`.
    pub runs_used: u32,
    /// Start of the averaging window \[s\] (the scenario's convergence time).
    pub avg_from: f64,
    /// Number of times in the averaging window.
    pub avg_times: usize,
    /// Time-averaged position RMSE over the window \[m\] (NaN if the window is empty).
    pub rmse_pos: f64,
    /// Time-averaged velocity RMSE over the window \[m/s\] (NaN if the window is empty).
    pub rmse_vel: f64,
    /// Time-averaged RMSE per axis x, y, z \[m\], vx, vy, vz \[m/s\] over the window.
    pub rmse_axes: [f64; 6],
    /// Largest position-error norm of any run in the window \[m\].
    pub max_pos_err: f64,
    /// Largest velocity-error norm of any run in the window \[m/s\].
    pub max_vel_err: f64,
    /// First time after which every axis RMSE stays below the thresholds \[s\]; `None` if
    /// never.
    pub convergence_time: Option<f64>,
    /// Averaged NEES check (6 dof); `None` when no run or no time contributes.
    pub nees: Option<Consistency>,
    /// Averaged NIS check ([`McResult::nis_dof`] dof); `None` when no measurement was
    /// processed in the window.
    pub nis: Option<Consistency>,
    /// Time-averaged position RMSE over the PCRLB's; `None` when the bound is undefined.
    pub efficiency_pos: Option<f64>,
    /// Time-averaged velocity RMSE over the PCRLB's; `None` when the bound is undefined.
    pub efficiency_vel: Option<f64>,
    /// Time-averaged position RMSE over the bound along each run's truth
    /// ([`McResult::pcrlb_runs`]); `None` when it is undefined.
    pub efficiency_runs_pos: Option<f64>,
    /// The same for the velocity.
    pub efficiency_runs_vel: Option<f64>,
    /// Mean wall-clock time of one step \[µs\] (copied).
    pub us_per_step: f64,
    /// A particle filter's moves accepted over tried (copied; NaN for the others).
    pub move_acceptance: f64,
    /// Failed or diverged runs (copied).
    pub failed_runs: u32,
    /// Recovery after each unreported burn \[s\] ([`recovery_times`]); empty when the
    /// scenario has none.
    pub recovery: Vec<Option<f64>>,
    /// With unreported burns: position and velocity RMSE \[m, m/s\] of the quiet phase,
    /// `convergence_time <= t < start of the first burn` ([`rmse_between`]); the price a
    /// filter pays while nothing goes wrong. `None` without unreported burns.
    pub quiet_rmse: Option<(f64, f64)>,
    /// With unreported burns: position and velocity RMSE \[m, m/s\] from the start of the
    /// first burn to the end ([`rmse_between`]). `None` without unreported burns.
    pub after_burn_rmse: Option<(f64, f64)>,
}

/// Quantile of the chi-square distribution with `dof` degrees of freedom at probability
/// `p`. NaN unless `0 < p < 1` and `dof > 0` is finite. Exact (statrs) up to `10^4`
/// degrees of freedom, Wilson–Hilferty above (see the module docs).
pub fn chi2_inv(p: f64, dof: f64) -> f64 {
    let valid = p > 0.0 && p < 1.0 && dof > 0.0 && dof.is_finite();
    if !valid {
        return f64::NAN;
    }
    if dof <= WILSON_HILFERTY_ABOVE {
        if let Ok(c) = ChiSquared::new(dof) {
            let q = c.inverse_cdf(p);
            if q.is_finite() {
                return q;
            }
        }
    }
    let z = Normal::standard().inverse_cdf(p);
    let a = 2.0 / (9.0 * dof);
    let w = 1.0 - a + z * a.sqrt();
    dof * w.max(0.0).powi(3)
}

/// Two-sided 95 % bounds of the mean of `n` independent chi-square samples with `dof`
/// degrees of freedom: `chi2inv(0.025, dof n) / n`, `chi2inv(0.975, dof n) / n`.
pub fn chi2_mean_bounds(dof: u32, n: u64) -> (f64, f64) {
    if n == 0 {
        return (f64::NAN, f64::NAN);
    }
    let n = n as f64;
    let d = f64::from(dof) * n;
    (chi2_inv(P_LO, d) / n, chi2_inv(P_HI, d) / n)
}

/// Per-axis RMSE time series `sqrt(mse[k][i])`. Applied to the PCRLB's `J^-1` diagonal it
/// gives the bound's standard deviations.
pub fn rmse_axes(mse: &[[f64; 6]]) -> Vec<[f64; 6]> {
    mse.iter().map(|m| m.map(f64::sqrt)).collect()
}

/// Position RMSE time series `sqrt(mse_x + mse_y + mse_z)`.
pub fn rmse_pos(mse: &[[f64; 6]]) -> Vec<f64> {
    mse.iter().map(|m| pos_sq(m).sqrt()).collect()
}

/// Velocity RMSE time series `sqrt(mse_vx + mse_vy + mse_vz)`.
pub fn rmse_vel(mse: &[[f64; 6]]) -> Vec<f64> {
    mse.iter().map(|m| vel_sq(m).sqrt()).collect()
}

/// Convergence time (module docs): the first `t[k]` after which every axis RMSE
/// `sqrt(mse[j][i])`, `j >= k`, stays below `threshold.0` (position axes) and
/// `threshold.1` (velocity axes) until the last time; `None` if never. Only the common
/// length of `t` and `mse` is used.
pub fn convergence_time(t: &[f64], mse: &[[f64; 6]], threshold: (f64, f64)) -> Option<f64> {
    let below = |m: &[f64; 6]| {
        m.iter().enumerate().all(|(i, v)| {
            let thr = if i < 3 { threshold.0 } else { threshold.1 };
            v.sqrt() < thr
        })
    };
    let n = t.len().min(mse.len());
    let mut first = None;
    for (tk, m) in t.iter().zip(mse).take(n).rev() {
        if below(m) {
            first = Some(*tk);
        } else {
            break;
        }
    }
    first
}

/// Recovery after each unreported burn `[start_i, stop_i)` of `burns` (time order): the
/// time from `stop_i` to the first `t[k] >= stop_i` after which the position RMSE
/// `sqrt(mse_x + mse_y + mse_z)` stays below `threshold` up to the next burn's start (or
/// the last time); `None` if it never does. `Some(0)` means the error never left the band.
pub fn recovery_times(
    t: &[f64],
    mse: &[[f64; 6]],
    threshold: f64,
    burns: &[(f64, f64)],
) -> Vec<Option<f64>> {
    let n = t.len().min(mse.len());
    burns
        .iter()
        .enumerate()
        .map(|(i, &(_, stop))| {
            let until = burns.get(i + 1).map_or(f64::INFINITY, |b| b.0);
            let mut first = None;
            for (tk, m) in t.iter().zip(mse).take(n).rev() {
                if *tk >= until {
                    continue;
                }
                if *tk < stop || pos_sq(m).sqrt() >= threshold {
                    break;
                }
                first = Some(*tk);
            }
            first.map(|tk| tk - stop)
        })
        .collect()
}

/// Position and velocity RMSE over `from <= t[k] < to`:
/// `(sqrt(mean(mse_x + mse_y + mse_z)), sqrt(mean(mse_vx + mse_vy + mse_vz)))`, NaN when no
/// time falls in the interval. Only the common length of `t` and `mse` is used.
pub fn rmse_between(t: &[f64], mse: &[[f64; 6]], from: f64, to: f64) -> (f64, f64) {
    let window: Vec<usize> = t
        .iter()
        .take(mse.len())
        .enumerate()
        .filter(|(_, tk)| **tk >= from && **tk < to)
        .map(|(k, _)| k)
        .collect();
    (
        mean_over(&window, mse, pos_sq).sqrt(),
        mean_over(&window, mse, vel_sq).sqrt(),
    )
}

/// Indices `k` of the averaging window `t[k] >= convergence_time`.
pub fn averaging_window(r: &McResult) -> Vec<usize> {
    r.t.iter()
        .enumerate()
        .filter(|(_, tk)| **tk >= r.convergence_time)
        .map(|(k, _)| k)
        .collect()
}

/// The PCRLB's time-averaged square roots over the averaging window:
/// `(sqrt(mean(Jxx + Jyy + Jzz)), sqrt(mean(Jvxvx + Jvyvy + Jvzvz)))` [m, m/s], or the
/// reason it is not available (undefined for the scenario, wrong length, empty window).
pub fn pcrlb_averaged(r: &McResult) -> Result<(f64, f64), String> {
    bound_averaged(r, &r.pcrlb)
}

/// [`pcrlb_averaged`] of the bound along each run's truth ([`McResult::pcrlb_runs`]).
pub fn run_bound_averaged(r: &McResult) -> Result<(f64, f64), String> {
    bound_averaged(r, &r.pcrlb_runs)
}

fn bound_averaged(r: &McResult, j: &Result<Vec<[f64; 6]>, String>) -> Result<(f64, f64), String> {
    let j = j.as_ref().map_err(Clone::clone)?;
    if j.len() != r.t.len() {
        return Err(format!(
            "the PCRLB has {} times, the results {}",
            j.len(),
            r.t.len()
        ));
    }
    let window = averaging_window(r);
    if window.is_empty() {
        return Err(format!("no time at or after {} s", r.convergence_time));
    }
    let pos = mean_over(&window, j, pos_sq);
    let vel = mean_over(&window, j, vel_sq);
    Ok((pos.sqrt(), vel.sqrt()))
}

/// Summary metrics of every filter of `r`, in the order of `r.filters`.
pub fn summarize(r: &McResult) -> Vec<Summary> {
    let window = averaging_window(r);
    let bound = pcrlb_averaged(r).ok();
    let runs = run_bound_averaged(r).ok();
    r.filters
        .iter()
        .map(|f| summarize_filter(r, f, &window, bound, runs))
        .collect()
}

fn summarize_filter(
    r: &McResult,
    f: &FilterStats,
    window: &[usize],
    bound: Option<(f64, f64)>,
    runs: Option<(f64, f64)>,
) -> Summary {
    let rmse_pos = mean_over(window, &f.mse, pos_sq).sqrt();
    let rmse_vel = mean_over(window, &f.mse, vel_sq).sqrt();
    let mut rmse_axes = [f64::NAN; 6];
    for (i, a) in rmse_axes.iter_mut().enumerate() {
        *a = mean_over(window, &f.mse, |m| m.get(i).copied().unwrap_or(f64::NAN)).sqrt();
    }
    let runs_used = r.runs.saturating_sub(f.failed_runs);
    let m = u64::from(runs_used);
    let nees = consistency(
        6,
        window
            .iter()
            .filter_map(|&k| f.nees.get(k).map(|v| (*v, m))),
    );
    let nis = consistency(
        r.nis_dof,
        window.iter().filter_map(|&k| {
            let v = f.nis.get(k)?;
            let c = f.nis_count.get(k)?;
            Some((*v, u64::from(*c)))
        }),
    );
    let ratio = |rmse: f64, b: f64| {
        let e = rmse / b;
        (b > 0.0 && e.is_finite()).then_some(e)
    };
    Summary {
        label: f.label.clone(),
        kind: f.kind.clone(),
        runs_used,
        avg_from: r.convergence_time,
        avg_times: window.len(),
        rmse_pos,
        rmse_vel,
        rmse_axes,
        max_pos_err: max_over(window, &f.max_pos_err),
        max_vel_err: max_over(window, &f.max_vel_err),
        convergence_time: convergence_time(&r.t, &f.mse, r.convergence_threshold),
        nees,
        nis,
        efficiency_pos: bound.and_then(|(b, _)| ratio(rmse_pos, b)),
        efficiency_vel: bound.and_then(|(_, b)| ratio(rmse_vel, b)),
        efficiency_runs_pos: runs.and_then(|(b, _)| ratio(rmse_pos, b)),
        efficiency_runs_vel: runs.and_then(|(_, b)| ratio(rmse_vel, b)),
        us_per_step: f.us_per_step,
        move_acceptance: f.move_acceptance,
        failed_runs: f.failed_runs,
        recovery: recovery_times(&r.t, &f.mse, r.convergence_threshold.0, &r.unreported_burns),
        quiet_rmse: r
            .unreported_burns
            .first()
            .map(|b| rmse_between(&r.t, &f.mse, r.convergence_time, b.0)),
        after_burn_rmse: r
            .unreported_burns
            .first()
            .map(|b| rmse_between(&r.t, &f.mse, b.0, f64::INFINITY)),
    }
}

/// Consistency check from `(value, count)` per time (module docs); times with a zero
/// count or a NaN value are skipped.
fn consistency(dof: u32, values: impl Iterator<Item = (f64, u64)>) -> Option<Consistency> {
    let mut times = 0usize;
    let mut samples = 0u64;
    let mut weighted = 0.0;
    let mut inside = 0usize;
    let mut band_count = 0u64;
    for (v, c) in values {
        if c == 0 || v.is_nan() {
            continue;
        }
        times += 1;
        samples += c;
        weighted += c as f64 * v;
        band_count = band_count.max(c);
        let (lo, hi) = chi2_mean_bounds(dof, c);
        if v >= lo && v <= hi {
            inside += 1;
        }
    }
    if times == 0 {
        return None;
    }
    Some(Consistency {
        dof,
        avg: weighted / samples as f64,
        times,
        samples,
        bounds: chi2_mean_bounds(dof, samples),
        band: chi2_mean_bounds(dof, band_count),
        band_count,
        in_band: inside as f64 / times as f64,
    })
}

fn pos_sq(m: &[f64; 6]) -> f64 {
    m[0] + m[1] + m[2]
}

fn vel_sq(m: &[f64; 6]) -> f64 {
    m[3] + m[4] + m[5]
}

/// Mean of `g(series[k])` over the window; NaN if the window is empty or an index is out
/// of range.
fn mean_over(window: &[usize], series: &[[f64; 6]], g: impl Fn(&[f64; 6]) -> f64) -> f64 {
    if window.is_empty() {
        return f64::NAN;
    }
    let mut sum = 0.0;
    for &k in window {
        match series.get(k) {
            Some(m) => sum += g(m),
            None => return f64::NAN,
        }
    }
    sum / window.len() as f64
}

/// Largest value over the window ignoring NaN; NaN if there is none.
fn max_over(window: &[usize], series: &[f64]) -> f64 {
    let m = window
        .iter()
        .filter_map(|&k| series.get(k))
        .filter(|v| !v.is_nan())
        .fold(f64::NEG_INFINITY, |a, &b| a.max(b));
    if m == f64::NEG_INFINITY {
        f64::NAN
    } else {
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn filter(label: &str, mse: Vec<[f64; 6]>) -> FilterStats {
        let n = mse.len();
        FilterStats {
            label: label.to_string(),
            kind: "ekf".to_string(),
            mse,
            nees: vec![6.0; n],
            nis: vec![3.0; n],
            nis_count: vec![10; n],
            max_pos_err: vec![1.0; n],
            max_vel_err: vec![0.1; n],
            range_mse: vec![1.0; n],
            range_var: vec![1.0; n],
            failed_runs: 0,
            us_per_step: 2.5,
            move_acceptance: f64::NAN,
        }
    }

    fn result(t: Vec<f64>, filters: Vec<FilterStats>) -> McResult {
        McResult {
            nis_dof: 3,
            scenario: "test".to_string(),
            title: "Test".to_string(),
            t,
            runs: 10,
            interrupted: false,
            filters,
            pcrlb: Err("not computed".to_string()),
            pcrlb_runs: Err("not computed".to_string()),
            range_bound_runs: Vec::new(),
            convergence_time: 0.0,
            convergence_threshold: (1.0, 0.1),
            published: vec![],
            unreported_burns: vec![],
        }
    }

    /// The RMSE over an interval is the root of the mean of the summed squares over the
    /// times inside `[from, to)`; an empty interval is NaN.
    #[test]
    fn rmse_between_averages_inside_the_interval() {
        let t: Vec<f64> = (0..6).map(f64::from).collect();
        let mse: Vec<[f64; 6]> = (0..6)
            .map(|k| {
                let v = f64::from(k);
                [v, 2.0 * v, 0.0, 0.1 * v, 0.0, 0.0]
            })
            .collect();
        let (p, v) = rmse_between(&t, &mse, 2.0, 4.0);
        assert!((p - ((6.0 + 9.0) / 2.0_f64).sqrt()).abs() < 1e-15);
        assert!((v - ((0.2 + 0.3) / 2.0_f64).sqrt()).abs() < 1e-15);
        let (p, _) = rmse_between(&t, &mse, 4.0, f64::INFINITY);
        assert!((p - ((12.0 + 15.0) / 2.0_f64).sqrt()).abs() < 1e-15);
        assert!(rmse_between(&t, &mse, 7.0, 9.0).0.is_nan());
    }

    #[test]
    fn recovery_after_each_burn_until_the_next() {
        let t: Vec<f64> = (0..10).map(f64::from).collect();
        // position RMSE per time (x only), threshold 1
        let e = [0.5, 0.5, 3.0, 3.0, 0.5, 2.0, 2.0, 0.5, 0.5, 0.5];
        let mse: Vec<[f64; 6]> = e.iter().map(|v| [v * v, 0.0, 0.0, 0.0, 0.0, 0.0]).collect();
        // burn 1 ends at 2: error above 1 at 2, 3, below from 4 up to burn 2's start (5)
        // burn 2 ends at 6: above at 6, below from 7 on
        let r = recovery_times(&t, &mse, 1.0, &[(1.0, 2.0), (5.0, 6.0)]);
        assert_eq!(r, vec![Some(2.0), Some(1.0)]);
        // never recovering before the next burn, and a burn the error never notices
        let r = recovery_times(&t, &mse, 1.0, &[(1.0, 2.0), (6.5, 7.0)]);
        assert_eq!(r, vec![None, Some(0.0)]);
        let r = recovery_times(&t, &mse, 1.0, &[(3.5, 4.0)]);
        assert_eq!(r, vec![Some(3.0)]);
        let r = recovery_times(&t, &mse, 0.1, &[(1.0, 2.0)]);
        assert_eq!(r, vec![None]);
    }

    #[test]
    fn chi2_quantiles_match_tables() {
        // Textbook values (e.g. NIST/SEMATECH tables).
        assert!((chi2_inv(0.975, 6.0) - 14.449_375).abs() < 1e-5);
        assert!((chi2_inv(0.025, 6.0) - 1.237_344).abs() < 1e-5);
        assert!((chi2_inv(0.975, 3.0) - 9.348_404).abs() < 1e-5);
        assert!((chi2_inv(0.025, 3.0) - 0.215_795).abs() < 1e-5);
        assert!((chi2_inv(0.95, 1.0) - 3.841_459).abs() < 1e-5);
        assert!(chi2_inv(0.0, 6.0).is_nan());
        assert!(chi2_inv(0.5, 0.0).is_nan());
        assert!(chi2_inv(f64::NAN, 3.0).is_nan());
    }

    #[test]
    fn chi2_quantile_continuous_at_the_switch_and_sane_for_huge_dof() {
        // Both methods agree near the switch to Wilson-Hilferty.
        let below = chi2_inv(0.975, WILSON_HILFERTY_ABOVE);
        let above = chi2_inv(0.975, WILSON_HILFERTY_ABOVE * (1.0 + 1e-12));
        assert!((below - above).abs() / below < 1e-7, "{below} {above}");
        // Huge dof: mean d, std sqrt(2d): 97.5 % quantile ~ d + 1.96 sqrt(2d).
        let d = 4.32e7;
        let q = chi2_inv(0.975, d);
        let approx = d + 1.959_964 * (2.0 * d).sqrt();
        assert!((q - approx).abs() / (2.0 * d).sqrt() < 1e-2, "{q} {approx}");
        let (lo, hi) = chi2_mean_bounds(6, 7_200_000);
        assert!(lo < 6.0 && hi > 6.0 && hi - lo < 0.01, "{lo} {hi}");
    }

    #[test]
    fn constant_mse_gives_known_rmse() {
        // mse: x 1, y 4, z 4 -> pos sqrt(9) = 3; v 0.01 each -> vel sqrt(0.03).
        let m = [1.0, 4.0, 4.0, 0.01, 0.01, 0.01];
        let f = filter("EKF", vec![m; 5]);
        let axes = rmse_axes(&f.mse);
        assert_eq!(axes.len(), 5);
        assert_eq!(axes[2], [1.0, 2.0, 2.0, 0.1, 0.1, 0.1]);
        assert_eq!(rmse_pos(&f.mse), vec![3.0; 5]);
        assert!(rmse_vel(&f.mse)
            .iter()
            .all(|v| (v - 0.03_f64.sqrt()).abs() < 1e-15));
        let r = result(vec![0.0, 1.0, 2.0, 3.0, 4.0], vec![f]);
        let s = summarize(&r);
        assert_eq!(s.len(), 1);
        let s = &s[0];
        assert_eq!(s.label, "EKF");
        assert_eq!(s.rmse_pos, 3.0);
        assert!((s.rmse_vel - 0.03_f64.sqrt()).abs() < 1e-15);
        assert!((s.rmse_axes[4] - 0.1).abs() < 1e-15);
        assert_eq!(s.avg_times, 5);
        assert_eq!(s.runs_used, 10);
        assert_eq!(s.us_per_step, 2.5);
        assert_eq!(s.failed_runs, 0);
        assert_eq!(s.efficiency_pos, None);
    }

    #[test]
    fn time_average_is_root_of_mean_square_after_convergence_time() {
        // pos mse sums: t=0: 300 (excluded), t=1: 3, t=2: 12, t=3: 27 (x=y=z = 1, 4, 9).
        // mean over t >= 1 = (3 + 12 + 27) / 3 = 14 -> sqrt(14).
        let mse = vec![
            [100.0, 100.0, 100.0, 1.0, 1.0, 1.0],
            [1.0, 1.0, 1.0, 0.0, 0.0, 0.0],
            [4.0, 4.0, 4.0, 0.0, 0.0, 0.0],
            [9.0, 9.0, 9.0, 0.0, 0.0, 0.03],
        ];
        let mut f = filter("UKF", mse);
        f.max_pos_err = vec![50.0, 2.0, 7.0, 3.0];
        f.max_vel_err = vec![5.0, 0.2, f64::NAN, 0.1];
        let mut r = result(vec![0.0, 1.0, 2.0, 3.0], vec![f]);
        r.convergence_time = 1.0;
        let s = &summarize(&r)[0];
        assert_eq!(s.avg_times, 3);
        assert!((s.rmse_pos - 14.0_f64.sqrt()).abs() < 1e-12);
        assert!((s.rmse_vel - 0.01_f64.sqrt()).abs() < 1e-12);
        // x axis: mean of 1, 4, 9 = 14/3.
        assert!((s.rmse_axes[0] - (14.0_f64 / 3.0).sqrt()).abs() < 1e-12);
        assert_eq!(s.max_pos_err, 7.0);
        assert_eq!(s.max_vel_err, 0.2);
    }

    #[test]
    fn empty_window_gives_nan_not_panic() {
        let f = filter("EKF", vec![[1.0; 6]; 3]);
        let mut r = result(vec![0.0, 1.0, 2.0], vec![f]);
        r.convergence_time = 10.0;
        let s = &summarize(&r)[0];
        assert!(s.rmse_pos.is_nan() && s.max_pos_err.is_nan());
        assert_eq!(s.nees, None);
        assert_eq!(s.nis, None);
    }

    #[test]
    fn convergence_time_is_first_time_staying_below() {
        // Position RMSE per axis: 10, 5, 2, 0.5, 0.4, 0.3 (threshold 1 m) -> drops below
        // at t = 3 and stays; velocity always below 0.1.
        let t: Vec<f64> = (0..6).map(f64::from).collect();
        let mse: Vec<[f64; 6]> = [10.0, 5.0, 2.0, 0.5, 0.4, 0.3]
            .iter()
            .map(|e: &f64| {
                let p = e * e;
                [p, p, p, 1e-4, 1e-4, 1e-4]
            })
            .collect();
        assert_eq!(convergence_time(&t, &mse, (1.0, 0.1)), Some(3.0));
        // A relapse above the threshold at t = 4 moves it to t = 5.
        let mut relapse = mse.clone();
        relapse[4][1] = 1.5 * 1.5;
        assert_eq!(convergence_time(&t, &relapse, (1.0, 0.1)), Some(5.0));
        // A velocity axis above its threshold at the end: never.
        let mut vel = mse.clone();
        vel[5][5] = 0.2 * 0.2;
        assert_eq!(convergence_time(&t, &vel, (1.0, 0.1)), None);
        // Below from the start.
        assert_eq!(convergence_time(&t, &mse, (100.0, 0.1)), Some(0.0));
        // NaN counts as above; empty input never converges.
        let mut nan = mse.clone();
        nan[5][0] = f64::NAN;
        assert_eq!(convergence_time(&t, &nan, (1.0, 0.1)), None);
        assert_eq!(convergence_time(&[], &[], (1.0, 0.1)), None);
        // Through summarize (thresholds from the result).
        let r = result(t, vec![filter("EKF", mse)]);
        assert_eq!(summarize(&r)[0].convergence_time, Some(3.0));
    }

    #[test]
    fn nees_exactly_six_is_inside_band_and_bounds() {
        // M = 10 runs, 4 times: N = 40 samples, 240 dof.
        let f = filter("EKF", vec![[1.0; 6]; 4]);
        let r = result(vec![0.0, 1.0, 2.0, 3.0], vec![f]);
        let s = &summarize(&r)[0];
        let nees = s.nees.as_ref().unwrap();
        assert_eq!(nees.dof, 6);
        assert_eq!(nees.avg, 6.0);
        assert_eq!(nees.times, 4);
        assert_eq!(nees.samples, 40);
        assert_eq!(nees.band_count, 10);
        assert_eq!(nees.in_band, 1.0);
        assert!(nees.bounds.0 < 6.0 && 6.0 < nees.bounds.1);
        // Per-time band for M = 10: chi2inv(0.025, 60)/10 = 4.0482, chi2inv(0.975, 60)/10
        // = 8.3298 (tables: 40.482, 83.298).
        assert!((nees.band.0 - 4.0482).abs() < 1e-4, "{:?}", nees.band);
        assert!((nees.band.1 - 8.3298).abs() < 1e-4, "{:?}", nees.band);
        // Average bounds: chi2inv(0.025, 240)/40 = 198.98/40, chi2inv(0.975, 240)/40 =
        // 284.80/40.
        assert!(
            (nees.bounds.0 * 40.0 - 198.98).abs() < 0.01,
            "{:?}",
            nees.bounds
        );
        assert!(
            (nees.bounds.1 * 40.0 - 284.80).abs() < 0.01,
            "{:?}",
            nees.bounds
        );
    }

    #[test]
    fn nees_fraction_in_band_and_failed_runs() {
        // M = 10 - 9 = 1 run: per-time band chi2inv(0.025, 6) .. chi2inv(0.975, 6) =
        // 1.2373 .. 14.449. Values 0.5 (out), 6 (in), 20 (out), 14 (in) -> 50 %.
        let mut f = filter("EKF", vec![[1.0; 6]; 4]);
        f.nees = vec![0.5, 6.0, 20.0, 14.0];
        f.failed_runs = 9;
        let r = result(vec![0.0, 1.0, 2.0, 3.0], vec![f]);
        let s = &summarize(&r)[0];
        assert_eq!(s.runs_used, 1);
        let nees = s.nees.as_ref().unwrap();
        assert_eq!(nees.in_band, 0.5);
        assert!((nees.avg - 40.5 / 4.0).abs() < 1e-12);
        assert!((nees.band.1 - 14.449_375).abs() < 1e-5);
        // All runs failed: no NEES check.
        let mut f = filter("EKF", vec![[1.0; 6]; 2]);
        f.failed_runs = 10;
        let r = result(vec![0.0, 1.0], vec![f]);
        assert_eq!(summarize(&r)[0].nees, None);
    }

    #[test]
    fn nis_weighted_by_counts_and_nan_skipped() {
        // Times: t0 no measurement (NaN, count 0); t1 NIS 2 over 10 runs; t2 NIS 5 over 5
        // runs. Average = (10*2 + 5*5) / 15 = 3; N = 15.
        let mut f = filter("EKF", vec![[1.0; 6]; 3]);
        f.nis = vec![f64::NAN, 2.0, 5.0];
        f.nis_count = vec![0, 10, 5];
        let r = result(vec![0.0, 1.0, 2.0], vec![f]);
        let nis = summarize(&r)[0].nis.clone().unwrap();
        assert_eq!(nis.dof, 3);
        assert_eq!(nis.times, 2);
        assert_eq!(nis.samples, 15);
        assert!((nis.avg - 3.0).abs() < 1e-12);
        assert_eq!(nis.band_count, 10);
        // Band for c = 10: chi2inv(0.025, 30)/10 = 1.6791, chi2inv(0.975, 30)/10 = 4.6979.
        assert!((nis.band.0 - 1.6791).abs() < 1e-4, "{:?}", nis.band);
        assert!((nis.band.1 - 4.6979).abs() < 1e-4, "{:?}", nis.band);
        // t1: 2 inside [1.679, 4.698]; t2: 5 against c = 5 band
        // chi2inv(0.975, 15)/5 = 27.488/5 = 5.4976 -> inside. Both in.
        assert_eq!(nis.in_band, 1.0);
        let (lo, hi) = nis.bounds;
        assert!((lo * 15.0 - chi2_inv(0.025, 45.0)).abs() < 1e-9);
        assert!((hi * 15.0 - chi2_inv(0.975, 45.0)).abs() < 1e-9);
    }

    #[test]
    fn efficiency_against_pcrlb() {
        // MSE pos sum 4 + 4 + 4 = 12 vs bound 1 + 1 + 1 = 3: RMSE ratio sqrt(12/3) = 2.
        // Velocity: 0.03 vs 0.03 -> 1.
        let f = filter("EKF", vec![[4.0, 4.0, 4.0, 0.01, 0.01, 0.01]; 3]);
        let mut r = result(vec![0.0, 1.0, 2.0], vec![f]);
        r.pcrlb = Ok(vec![[1.0, 1.0, 1.0, 0.01, 0.01, 0.01]; 3]);
        let s = &summarize(&r)[0];
        assert!((s.efficiency_pos.unwrap() - 2.0).abs() < 1e-12);
        assert!((s.efficiency_vel.unwrap() - 1.0).abs() < 1e-12);
        let (bp, bv) = pcrlb_averaged(&r).unwrap();
        assert!((bp - 3.0_f64.sqrt()).abs() < 1e-12);
        assert!((bv - 0.03_f64.sqrt()).abs() < 1e-12);
        // The bound's square roots through the same helpers.
        let pcrlb = r.pcrlb.as_ref().unwrap();
        assert_eq!(rmse_axes(pcrlb)[0][0], 1.0);
        // Wrong length: no efficiency, a reason.
        r.pcrlb = Ok(vec![[1.0; 6]; 2]);
        assert!(pcrlb_averaged(&r).unwrap_err().contains("2 times"));
        assert_eq!(summarize(&r)[0].efficiency_pos, None);
        // Undefined bound: the reason is passed through.
        r.pcrlb = Err("no PCRLB for this sensor".to_string());
        assert_eq!(
            pcrlb_averaged(&r).unwrap_err(),
            "no PCRLB for this sensor".to_string()
        );
        assert_eq!(summarize(&r)[0].efficiency_vel, None);
    }
}
