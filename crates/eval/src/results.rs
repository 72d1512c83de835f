//! What a Monte Carlo campaign produces: per-time statistics of every filter, accumulated
//! over the runs in a fixed order (so results do not depend on the thread count).

/// Per-time statistics of one filter over all runs. Index `k` is time `t[k]` of
/// [`McResult::t`]; the estimate scored at `t[k]` is the filtered (a posteriori) one when a
/// measurement was taken at `t[k]`, else the prediction.
#[derive(Debug, Clone, PartialEq)]
pub struct FilterStats {
    /// Label from the scenario (e.g. "EKF").
    pub label: String,
    /// Filter kind name (`ekf`, `ukf`, ...).
    pub kind: String,
    /// Mean over runs of the squared error per axis (x, y, z, vx, vy, vz), I/O frame.
    pub mse: Vec<[f64; 6]>,
    /// Mean over runs of the NEES `e^T P^-1 e` (6 dof when consistent).
    pub nees: Vec<f64>,
    /// Mean over runs of the NIS at measurement times ([`McResult::nis_dof`] dof when
    /// consistent); NaN where no measurement was processed.
    pub nis: Vec<f64>,
    /// Number of runs that contributed a NIS value at each time.
    pub nis_count: Vec<u32>,
    /// Largest position-error norm over runs at each time [m].
    pub max_pos_err: Vec<f64>,
    /// Largest velocity-error norm over runs at each time [m/s].
    pub max_vel_err: Vec<f64>,
    /// Mean over runs of the squared range error (estimated range less the true one)
    /// [m^2].
    pub range_mse: Vec<f64>,
    /// Mean over runs of the range variance the filter reports (its covariance along its
    /// estimated line of sight, as `range_sigma`) [m^2]; NaN for a filter without a
    /// covariance.
    pub range_var: Vec<f64>,
    /// Runs in which the filter failed (numerical error) or diverged; they are excluded
    /// from the statistics above.
    pub failed_runs: u32,
    /// Mean wall-clock time of one step (update + predict) [microseconds] (informative,
    /// machine dependent, not part of the deterministic results).
    pub us_per_step: f64,
    /// A particle filter's Metropolis–Hastings moves accepted over tried, over every
    /// update of the runs that did not fail (the per-step figure is relnav.fmu's
    /// `pf_acceptance`); NaN for the other filters and where no move was made.
    pub move_acceptance: f64,
}

/// The whole campaign.
#[derive(Debug, Clone, PartialEq)]
pub struct McResult {
    /// Scenario name (file stem, e.g. `paper000`).
    pub scenario: String,
    /// Human title.
    pub title: String,
    /// Times [s], starting at 0.
    pub t: Vec<f64>,
    /// Number of completed runs.
    pub runs: u32,
    /// True when the campaign was interrupted before all requested runs finished.
    pub interrupted: bool,
    /// One entry per filter, in scenario order.
    pub filters: Vec<FilterStats>,
    /// Components of the scored NIS (its chi-square degrees of freedom when consistent):
    /// 3 for `[sensor]`, else the first `[[sensors]]` entry's.
    pub nis_dof: u32,
    /// Posterior Cramér–Rao lower bound: diagonal of `J^-1` per time (variances, I/O
    /// frame), or `None` where it is not defined for the scenario (with the reason).
    pub pcrlb: Result<Vec<[f64; 6]>, String>,
    /// The same recursion along each run's own truth (its own geometry and sensor
    /// availability in the information terms), the diagonal of each run's `J^-1` averaged
    /// over the runs (I/O frame). By Jensen's inequality it is at or above
    /// [`McResult::pcrlb`]: much above where the runs' geometries differ (angles only, whose
    /// unobservable direction is each run's own line of sight) or where a range-gated
    /// sensor is present in some runs and not in others.
    pub pcrlb_runs: Result<Vec<[f64; 6]>, String>,
    /// The run-wise bound of the range: each run's `J^-1` along its own true line of
    /// sight, averaged over the runs [m^2] (empty where the bound is not defined).
    pub range_bound_runs: Vec<f64>,
    /// Time after which errors are averaged [s].
    pub convergence_time: f64,
    /// Per-axis thresholds (position [m], velocity [m/s]) for the convergence time.
    pub convergence_threshold: (f64, f64),
    /// The paper's published figures, per filter label (free text), for the table.
    pub published: Vec<(String, String)>,
    /// Time windows `[start, stop)` [s] of burns the filters are not told about (scenario
    /// thrust `reported = false`), in time order; the summary measures the recovery
    /// after each.
    pub unreported_burns: Vec<(f64, f64)>,
}
