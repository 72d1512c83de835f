//! Posterior Cramér–Rao lower bound (PCRLB) by Tichavský's recursion (P. Tichavský,
//! C. Muravchik, A. Nehorai, "Posterior Cramér–Rao bounds for discrete-time nonlinear
//! filtering", IEEE TSP 46(5), 1998), for additive Gaussian process noise and a
//! measurement with additive white noise of any regular density:
//!
//! ```text
//! J_0     = P_0^-1 + E[H_0^T I_v H_0]                     (if measured at t_0)
//! J_(k+1) = (F J_k^-1 F^T + Q)^-1 + E[H_(k+1)^T I_v H_(k+1)]   (measurement term only when measured)
//! ```
//!
//! `F` is the truth's (linear) transition — closed loop with feedback thrust — `Q` the
//! truth's process noise; the measurement term sums the information of every sensor that
//! measured at that time (`[sensor]` and each `[[sensors]]` entry, independent noises); for a two-body truth without J2 (`two_body_j2` with `j2 = false`,
//! any eccentricity) `F_k` is the transition of the relative motion linearised about the
//! target's Keplerian orbit from `t_k` (CW or Yamanaka–Ankersen: time-varying when
//! eccentric) and `Q_k = Gamma_k (q / h) Gamma_k^T` that of the truth's random
//! acceleration of density `q` held over each step `h` (the nonlinearity of the relative
//! motion is left out: millimetres at the scenarios' ranges), `H_k` the measurement Jacobian at the true state, `I_v` the
//! Fisher information matrix of the measurement noise, `diag(f / sigma_i^2)` with `f`
//! from [`relnav_core::noise::NoiseModel::fisher_factor`] (1 for a Gaussian). The expectation
//! is the Monte Carlo average over the campaign's truth trajectories. The prior `P_0` is
//! the truth's initial spread when the scenario draws one (`truth.initial_sigma`), else
//! the first filter's initial covariance (the filters' common prior assumption).
//!
//! The bound is undefined — and reported as such with the reason — when the noise density
//! is not regular (uniform), not white (AR(1)), or when the true orbit rate is random per
//! run (the transition itself is then uncertain).

use crate::scenario::OrbitRateError;
use crate::sim::{Prepared, PreparedSensor};
use relnav_core::dynamics::{CwModel, Discretization, Dynamics, RelativeDynamics};
use relnav_core::types::{Mat3, Mat6, State};

/// Why the bound is undefined for this scenario, or `None` when it is defined.
pub fn undefined_reason(prep: &Prepared) -> Option<String> {
    if prep.truth_sensor.is_some() && prep.noise.fisher_factor().is_none() {
        return Some(format!(
            "undefined: the {:?} measurement noise has no finite Fisher information",
            prep.noise
        ));
    }
    if let Some(s) = prep
        .sensors
        .iter()
        .find(|s| s.spec.noise.fisher_factor().is_none())
    {
        return Some(format!(
            "undefined: the {:?} noise of sensor \"{}\" has no finite Fisher information",
            s.spec.noise,
            s.spec.label()
        ));
    }
    if let crate::scenario::TruthDynamics::TwoBodyJ2 { j2: true, .. } = prep.scenario.truth.dynamics
    {
        return Some("the truth is not a linear model (nonlinear two-body motion with J2)".into());
    }
    if let OrbitRateError::Uniform { .. } = prep.scenario.truth.orbit_rate_error {
        return Some("undefined: the true orbit rate is random per run".into());
    }
    None
}

/// The measurement information `H^T I_v H` at a true state (canonical), zero when the
/// geometry is singular.
pub fn measurement_information(prep: &Prepared, x: &State) -> Mat6 {
    use relnav_core::sensors::MeasurementModel;
    let f = prep.noise.fisher_factor().unwrap_or(0.0);
    let r = x.fixed_rows::<3>(0).into_owned();
    let Some(sensor) = &prep.truth_sensor else {
        return Mat6::zeros();
    };
    match sensor.linearize(&r) {
        Ok(g) => {
            let iv = nalgebra::SMatrix::<f64, 3, 3>::from_diagonal(&nalgebra::Vector3::from_fn(
                |i, _| f / (prep.noise_sigma[i] * prep.noise_sigma[i]),
            ));
            g.h.transpose() * iv * g.h
        }
        Err(_) => Mat6::zeros(),
    }
}

/// The information `H^T I_v H` of a `[[sensors]]` entry's reading at a true state
/// (canonical): each sensor's information adds, as its noise is independent of the others'.
pub fn sensor_information(s: &PreparedSensor, x: &State) -> Mat6 {
    let f = s.spec.noise.fisher_factor().unwrap_or(0.0);
    s.geometry.information(x, &s.scales, f)
}

/// Run the recursion given the Monte Carlo mean of `H^T I_v H` at each time (zero where
/// nothing was measured). Returns the diagonal of `J_k^-1` in the I/O frame per time.
pub fn recursion(prep: &Prepared, mean_info: &[Mat6]) -> Result<Vec<[f64; 6]>, String> {
    let frame = prep.scenario.io_frame();
    Ok(bounds(prep, mean_info)?
        .iter()
        .map(|c| {
            let b = frame.cov_from_canonical(c);
            std::array::from_fn(|i| b[(i, i)])
        })
        .collect())
}

/// [`recursion`]'s `J_k^-1` whole, in the canonical frame (the bound of any linear
/// function of the state: one run's range along its own line of sight).
pub fn bounds(prep: &Prepared, mean_info: &[Mat6]) -> Result<Vec<Mat6>, String> {
    if let Some(r) = undefined_reason(prep) {
        return Err(r);
    }
    let s = &prep.scenario;
    let frame = s.io_frame();
    let delta = match s.truth.orbit_rate_error {
        OrbitRateError::Fixed { delta } => delta,
        _ => 0.0,
    };
    // the transition and noise of the step from t_k
    let step: Box<dyn Fn(usize) -> (Mat6, Mat6)> = match s.truth.dynamics {
        crate::scenario::TruthDynamics::Cw => {
            let model = CwModel::new(prep.n0 * (1.0 + delta));
            let mut f = model.phi(prep.dt);
            if let Some(k) = &prep.feedback {
                f += model.gamma(prep.dt) * k;
            }
            let q = prep.truth_q;
            Box::new(move |_| (f, q))
        }
        crate::scenario::TruthDynamics::TwoBodyJ2 { .. } => {
            let model = Dynamics::of_orbit(prep.n0, s.orbit.eccentricity, s.orbit.true_anomaly0);
            let (dt, var) = (prep.dt, s.truth.accel_psd / prep.dt);
            Box::new(move |k| {
                let d = model.step(k as f64 * dt, dt, &Mat3::zeros(), Discretization::Exact);
                (d.phi, d.gamma * d.gamma.transpose() * var)
            })
        }
    };
    let p0 = if s.truth.initial_sigma.iter().all(|v| *v > 0.0) {
        frame.cov_to_canonical(&Mat6::from_diagonal(&State::from_fn(|i, _| {
            s.truth.initial_sigma[i].powi(2)
        })))
    } else {
        prep.filters.first().map(|f| f.p0).ok_or("no filter")?
    };
    let inv = |m: &Mat6, what: &str| -> Result<Mat6, String> {
        let sym = (m + m.transpose()) * 0.5;
        sym.cholesky()
            .map(|c| c.inverse())
            .ok_or_else(|| format!("PCRLB: {what} is not positive definite"))
    };
    let mut out = Vec::with_capacity(mean_info.len());
    let mut j = inv(&p0, "P0")? + mean_info.first().copied().unwrap_or_else(Mat6::zeros);
    for (k, info) in mean_info.iter().enumerate() {
        if k > 0 {
            let (f, q) = step(k - 1);
            let jinv = inv(&j, "J")?;
            let pred = f * jinv * f.transpose() + q;
            j = inv(&pred, "the predicted bound")? + info;
        }
        out.push(inv(&j, "J")?);
    }
    Ok(out)
}
