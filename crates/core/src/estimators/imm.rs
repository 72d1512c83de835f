//! Interacting multiple-model filter, IMM (Blom & Bar-Shalom 1988; Bar-Shalom, Li &
//! Kirubarajan, *Estimation with Applications to Tracking and Navigation*, 2001, sec. 11.6):
//! the standard answer to manoeuvres the filter is not told about.
//!
//! `r` = 2 or 3 CW models that differ only in their process noise: mode 1 is the nominal
//! model (the caller's `Q`, quiet), modes 2 and 3 add a white acceleration of density
//! `accel_psd[j]` [m^2/s^3] per axis, exactly discretised (Van Loan for CW; the unit matrix
//! is cached per step size): `Q_j = Q + accel_psd[j] Qd_VanLoan(I3, h)`. Each mode is an
//! [`Ekf`] (the exact CW transition makes the time update linear; the measurement update is
//! the EKF's). The mode switches as a Markov chain with, over a step of `h` seconds,
//!
//! ```text
//! pi_jj = p_j^h,   pi_jk = (1 - p_j^h) / (r - 1)   (k != j)
//! ```
//!
//! with `p_j` the probability of staying in mode `j` for one second (so the mean sojourn is
//! `-1 / ln p_j` seconds whatever the step). One cycle, split between the navigator's
//! prediction and update:
//!
//! ```text
//! predict:  c_j = sum_i pi_ij mu_i                        (predicted mode probabilities)
//!           mu_i|j = pi_ij mu_i / c_j                      (mixing probabilities)
//!           x0_j = sum_i mu_i|j x_i,  P0_j = sum_i mu_i|j (P_i + (x_i - x0_j)(x_i - x0_j)^T)
//!           mode j: EKF prediction of (x0_j, P0_j) with Q_j;  mu_j <- c_j
//! update:   mode j: EKF update, innovation nu_j, covariance S_j
//!           Lambda_j = N(nu_j; 0, S_j),  mu_j <- mu_j Lambda_j / sum_k mu_k Lambda_k
//! output:   x = sum_j mu_j x_j,  P = sum_j mu_j (P_j + (x_j - x)(x_j - x)^T)
//! ```
//!
//! The likelihoods are computed in logarithms (`-(nu^T S^-1 nu + ln det S) / 2`, the
//! common `2 pi` dropped) and normalised against the largest, so a mode whose likelihood
//! underflows gets probability 0 and is fed again by the mixing of the next cycle
//! (`c_j >= min pi_ij > 0`). A step without measurement only mixes and predicts (the mode
//! probabilities follow the Markov chain). The reported innovation is the
//! probability-weighted mean `nu = sum_j mu_j- nu_j` of the modes' innovations (prior
//! mode probabilities) and its NIS is taken with the mixture's innovation covariance
//! `S = sum_j mu_j- (S_j + (nu_j - nu)(nu_j - nu)^T)`.
//!
//! Everything is fixed-size (at most [`MAX_MODES`] filters inside the struct); an update or
//! prediction works on a copy of the modes on the stack and commits only on success, so a
//! failed step changes nothing.

use super::{finite, Ekf, Estimator, FilterError, SensorUpdate, UpdateInfo};
use crate::dynamics::{DiscreteModel, Dynamics, RelativeDynamics};
#[cfg(not(feature = "std"))]
use crate::math::Float;
use crate::numerics::state::{refuse, Persist, Reader, StateError, Writer};
use crate::numerics::symmetrize;
use crate::sensors::{MeasurementModel, Sensor};
use crate::types::{Mat3, Mat6, State, Vec3};
use nalgebra::{SMatrix, SVector};

/// Largest number of modes.
pub const MAX_MODES: usize = 3;

/// Settings of the IMM.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImmParams {
    /// Number of modes `r`, 2 or 3.
    pub modes: usize,
    /// White-acceleration density of each mode on top of the nominal process noise
    /// [m^2/s^3], `>= 0` (mode 1, the quiet model: 0).
    pub accel_psd: [f64; MAX_MODES],
    /// Probability of staying in each mode over one second, in (0, 1).
    pub p_stay: [f64; MAX_MODES],
}

impl Default for ImmParams {
    /// Three modes: quiet (the nominal `Q`), a small manoeuvre or model error
    /// (1e-6 m^2/s^3: about 1 mm/s of unmodelled velocity change per second) and a burn
    /// (1e-3 m^2/s^3: about 3 cm/s per second, 3 N on 100 kg). The quiet mode lasts
    /// 10^6 s on average (an unannounced manoeuvre every twelve days), the manoeuvring
    /// ones 10 s, so the manoeuvring modes sit at a stationary probability of about 5e-6
    /// each. Why this sticky: the mixing feeds the burn mode's covariance into the quiet
    /// mode at that weight, which acts as added process noise; with a day's switching it
    /// was of the order of an honest quiet density (1e-10 m^2/s^3) and, most after a
    /// measurement dropout (where the burn mode's covariance grows), cost the quiet mode
    /// its velocity knowledge (`docs/filters.md`, "IMM"). The likelihood ratio of a burn
    /// still lifts mode 3 within seconds.
    fn default() -> Self {
        Self {
            modes: 3,
            accel_psd: [0.0, 1e-6, 1e-3],
            p_stay: [0.999999, 0.9, 0.9],
        }
    }
}

impl ImmParams {
    /// Check the settings; the message names the offending one (with the FMU's names).
    pub fn validate(&self) -> Result<(), crate::message::Message> {
        if !(2..=MAX_MODES).contains(&self.modes) {
            return Err(crate::msg!("imm_modes must be 2 or 3 (got {})", self.modes));
        }
        for j in 0..self.modes {
            let q = self.accel_psd[j];
            if !(q.is_finite() && q >= 0.0) {
                return Err(crate::msg!(
                    "imm_accel_psd_{} must be finite and >= 0 (got {})",
                    j + 1,
                    crate::numerics::num(q)
                ));
            }
            let p = self.p_stay[j];
            if !(p > 0.0 && p < 1.0) {
                return Err(crate::msg!(
                    "imm_p_stay_{} must lie in (0, 1) (got {}): the probability of staying \
                     in mode {} over one second",
                    j + 1,
                    crate::numerics::num(p),
                    j + 1
                ));
            }
        }
        Ok(())
    }

    /// The stationary distribution of the mode chain, `mu_j ~ 1 / (1 - p_j)` (with the
    /// leaving probability split evenly over the other modes every mode carries the same
    /// probability flow `mu_j (1 - p_j)`): the initial mode probabilities.
    pub fn stationary(&self) -> [f64; MAX_MODES] {
        let r = self.modes.clamp(2, MAX_MODES);
        let mut mu = [0.0; MAX_MODES];
        let mut sum = 0.0;
        for (m, p) in mu.iter_mut().zip(self.p_stay).take(r) {
            *m = 1.0 / (1.0 - p);
            sum += *m;
        }
        for m in mu.iter_mut().take(r) {
            *m /= sum;
        }
        mu
    }

    /// Transition probabilities `pi[i][j]` (from mode `i` to mode `j`) over `h` seconds.
    pub fn transition(&self, h: f64) -> [[f64; MAX_MODES]; MAX_MODES] {
        let r = self.modes.clamp(2, MAX_MODES);
        let mut pi = [[0.0; MAX_MODES]; MAX_MODES];
        for (i, row) in pi.iter_mut().enumerate().take(r) {
            let stay = self.p_stay[i].powf(h);
            for (j, p) in row.iter_mut().enumerate().take(r) {
                *p = if i == j {
                    stay
                } else {
                    (1.0 - stay) / (r - 1) as f64
                };
            }
        }
        pi
    }
}

/// The IMM filter (filter code 10) on any relative dynamics.
#[derive(Debug, Clone, PartialEq)]
pub struct Imm {
    params: ImmParams,
    modes: [Ekf; MAX_MODES],
    mu: [f64; MAX_MODES],
    x: State,
    p: Mat6,
    dynamics: Dynamics,
    basis_dt: f64,
    basis: Mat6,
}

impl Imm {
    /// All modes at `(x0, p0)` (canonical), mode probabilities at the stationary
    /// distribution ([`ImmParams::stationary`]); `params` validated by the caller; the
    /// modes' extra noise is the Van Loan noise of `dynamics`.
    pub fn new(x0: State, p0: Mat6, params: ImmParams, dynamics: impl Into<Dynamics>) -> Self {
        Self {
            params,
            modes: core::array::from_fn(|_| Ekf::new(x0, p0)),
            mu: params.stationary(),
            x: x0,
            p: p0,
            dynamics: dynamics.into(),
            basis_dt: f64::NAN,
            basis: Mat6::zeros(),
        }
    }

    /// The settings.
    pub fn params(&self) -> &ImmParams {
        &self.params
    }

    /// Current mode probabilities (entries past `modes` are 0).
    pub fn mode_probabilities(&self) -> [f64; MAX_MODES] {
        self.mu
    }

    /// The mode-conditioned estimate of mode `j` (0-based), if it exists.
    pub fn mode(&self, j: usize) -> Option<&Ekf> {
        self.modes.get(j).filter(|_| j < self.r())
    }

    /// Back to `(x, p)` in every mode with the initial mode probabilities.
    pub fn reset(&mut self, x: State, p: Mat6) {
        self.set_estimate(x, p);
        self.mu = self.params.stationary();
    }

    fn r(&self) -> usize {
        self.params.modes.clamp(2, MAX_MODES)
    }

    fn refresh_basis(&mut self, t: f64, dt: f64) {
        if self.basis_dt != dt || !self.dynamics.time_invariant() {
            self.basis = self.dynamics.step_noise(t, dt, &Mat3::identity());
            self.basis_dt = dt;
        }
    }

    /// `x = sum mu_j x_j`, `P = sum mu_j (P_j + (x_j - x)(x_j - x)^T)`.
    fn combine(&mut self) -> Result<(), FilterError> {
        let r = self.r();
        let mut x = State::zeros();
        for j in 0..r {
            x += self.modes[j].state() * self.mu[j];
        }
        let mut p = Mat6::zeros();
        for j in 0..r {
            let d = self.modes[j].state() - x;
            p += (self.modes[j].covariance() + d * d.transpose()) * self.mu[j];
        }
        let p = symmetrize(&p);
        finite(&x, "combined state")?;
        finite(&p, "combined covariance")?;
        self.x = x;
        self.p = p;
        Ok(())
    }
}

impl Imm {
    /// The measurement update of every mode by `update` (its innovation, NIS and innovation
    /// covariance `S`), the mode probabilities by the Gaussian likelihoods `N(nu_j; 0, S_j)`,
    /// the combined estimate; returns the mixture's innovation and NIS (prior mode
    /// probabilities). The filter is unchanged on error.
    fn update_modes<const D: usize>(
        &mut self,
        mut update: impl FnMut(
            &mut Ekf,
        )
            -> Result<(SVector<f64, D>, f64, SMatrix<f64, D, D>), FilterError>,
    ) -> Result<(SVector<f64, D>, f64), FilterError> {
        let r = self.r();
        let mut next = self.modes.clone();
        let mut ll = [f64::NEG_INFINITY; MAX_MODES];
        let mut nus = [SVector::<f64, D>::zeros(); MAX_MODES];
        let mut ss = [SMatrix::<f64, D, D>::zeros(); MAX_MODES];
        for j in 0..r {
            let (innovation, nis, s) = update(&mut next[j])?;
            let chol = s
                .cholesky()
                .ok_or(FilterError::NotPositiveDefinite("innovation covariance S"))?;
            let ln_det: f64 = chol.l_dirty().diagonal().iter().map(|d| 2.0 * d.ln()).sum();
            ll[j] = -0.5 * (nis + ln_det);
            nus[j] = innovation;
            ss[j] = s;
        }
        let top = ll.iter().take(r).copied().fold(f64::NEG_INFINITY, f64::max);
        if !top.is_finite() {
            return Err(FilterError::NonFinite("mode likelihood"));
        }
        let mut mu = [0.0; MAX_MODES];
        let mut sum = 0.0;
        for j in 0..r {
            mu[j] = self.mu[j] * (ll[j] - top).exp();
            sum += mu[j];
        }
        if !(sum > 0.0 && sum.is_finite()) {
            return Err(FilterError::NonFinite("mode probabilities"));
        }
        for m in mu.iter_mut() {
            *m /= sum;
        }
        // diagnostics of the mixture (prior mode probabilities)
        let mut nu = SVector::<f64, D>::zeros();
        for (n, m) in nus.iter().zip(self.mu).take(r) {
            nu += n * m;
        }
        let mut s = SMatrix::<f64, D, D>::zeros();
        for ((n, sj), m) in nus.iter().zip(ss).zip(self.mu).take(r) {
            let d = n - nu;
            s += (sj + d * d.transpose()) * m;
        }
        let nis = s.cholesky().map_or(f64::NAN, |c| nu.dot(&c.solve(&nu)));
        let saved = (self.modes.clone(), self.mu);
        self.modes = next;
        self.mu = mu;
        if let Err(e) = self.combine() {
            (self.modes, self.mu) = saved;
            return Err(e);
        }
        Ok((nu, nis))
    }
}

impl Estimator for Imm {
    fn predict(&mut self, model: &DiscreteModel, accel: &Vec3) -> Result<(), FilterError> {
        self.refresh_basis(model.t, model.dt);
        let r = self.r();
        let pi = self.params.transition(model.dt);
        let mut c = [0.0; MAX_MODES];
        for (j, cj) in c.iter_mut().enumerate().take(r) {
            *cj = pi
                .iter()
                .zip(self.mu)
                .take(r)
                .map(|(row, m)| row[j] * m)
                .sum();
        }
        let mut next = self.modes.clone();
        for j in 0..r {
            if !(c[j] > 0.0) {
                return Err(FilterError::NonFinite("predicted mode probability"));
            }
            let w: [f64; MAX_MODES] = core::array::from_fn(|i| pi[i][j] * self.mu[i] / c[j]);
            let mut x0 = State::zeros();
            for (f, wi) in self.modes.iter().zip(w).take(r) {
                x0 += f.state() * wi;
            }
            let mut p0 = Mat6::zeros();
            for (f, wi) in self.modes.iter().zip(w).take(r) {
                let d = f.state() - x0;
                p0 += (f.covariance() + d * d.transpose()) * wi;
            }
            next[j].set_estimate(x0, symmetrize(&p0));
            let mut m = *model;
            m.q += self.basis * self.params.accel_psd[j];
            next[j].predict(&m, accel)?;
        }
        let sum: f64 = c.iter().sum();
        let saved = (self.modes.clone(), self.mu);
        self.modes = next;
        for cj in c.iter_mut() {
            *cj /= sum;
        }
        self.mu = c;
        if let Err(e) = self.combine() {
            (self.modes, self.mu) = saved;
            return Err(e);
        }
        Ok(())
    }

    fn update<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
    ) -> Result<UpdateInfo, FilterError> {
        let mut azimuth_used = true;
        let (innovation, nis) = self.update_modes(|mode| {
            let (info, s) = mode.update_with_s(sensor, z)?;
            azimuth_used &= info.azimuth_used;
            Ok((info.innovation, info.nis, s))
        })?;
        Ok(UpdateInfo {
            innovation,
            nis,
            azimuth_used,
        })
    }

    fn update_sensor<const D: usize, S: Sensor<D> + ?Sized>(
        &mut self,
        sensor: &S,
        z: &SVector<f64, D>,
    ) -> Result<SensorUpdate<D>, FilterError> {
        let mut dof = D;
        let (innovation, nis) = self.update_modes(|mode| {
            let (info, s) = mode.update_sensor_with_s(sensor, z)?;
            dof = dof.min(info.dof);
            Ok((info.innovation, info.nis, s))
        })?;
        Ok(SensorUpdate {
            innovation,
            nis,
            dof,
        })
    }

    fn state(&self) -> &State {
        &self.x
    }

    fn covariance(&self) -> &Mat6 {
        &self.p
    }

    /// Every mode to `(x, p)`; the mode probabilities are kept.
    fn set_estimate(&mut self, x: State, p: Mat6) {
        for m in self.modes.iter_mut() {
            m.set_estimate(x, p);
        }
        self.x = x;
        self.p = p;
    }
}

/// Saved state: the number of modes `r`, each mode's EKF (`x`, `P`), the `r` mode
/// probabilities, and the combined estimate (`x`, `P`); see `docs/state-format.md`. The
/// CW model and the settings are configuration; the Van Loan basis is a cache recomputed
/// from them for the next step size (bit-identical: same inputs).
impl Persist for Imm {
    fn save_state(&self, w: &mut Writer<'_>) {
        let Self {
            params,
            modes,
            mu,
            x,
            p,
            dynamics: _,
            basis_dt: _,
            basis: _,
        } = self;
        let r = params.modes.clamp(2, MAX_MODES);
        w.usize(r);
        for m in modes.iter().take(r) {
            m.save_state(w);
        }
        for m in mu.iter().take(r) {
            w.f64(*m);
        }
        w.matrix(x);
        w.matrix(p);
    }

    fn load_state(&mut self, r: &mut Reader<'_>) -> Result<(), StateError> {
        let Self {
            params,
            modes,
            mu,
            x,
            p,
            dynamics: _,
            basis_dt: _,
            basis: _,
        } = self;
        let n = params.modes.clamp(2, MAX_MODES);
        r.count("IMM modes", n)?;
        for m in modes.iter_mut().take(n) {
            m.load_state(r)?;
        }
        let mut sum = 0.0;
        for m in mu.iter_mut().take(n) {
            let v = r.finite("IMM mode probability")?;
            if !(0.0..=1.0).contains(&v) {
                return Err(refuse(crate::msg!(
                    "IMM mode probability {v} outside [0, 1]"
                )));
            }
            *m = v;
            sum += v;
        }
        if (sum - 1.0).abs() > 1e-9 {
            return Err(refuse(crate::msg!(
                "IMM mode probabilities sum to {sum}, not 1"
            )));
        }
        *x = r.finite_matrix("IMM state")?;
        *p = r.finite_matrix("IMM covariance")?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::CwModel;
    use crate::frames::Frame;
    use crate::sensors::RadioSensor;

    fn model(dt: f64, q: f64) -> DiscreteModel {
        CwModel::new(1e-3).discretize(
            dt,
            &(Mat3::identity() * q),
            crate::dynamics::Discretization::Exact,
        )
    }

    /// With equal modes the IMM is the EKF: every mode sees the same mixed estimate, the
    /// likelihoods are equal and the probabilities stay where the chain puts them.
    #[test]
    fn identical_modes_reduce_to_the_ekf() {
        let x0 = State::from_row_slice(&[500.0, 400.0, -200.0, 0.1, -0.8, 0.05]);
        let p0 = Mat6::identity() * 4.0;
        let params = ImmParams {
            modes: 3,
            accel_psd: [0.0; 3],
            p_stay: [0.99, 0.9, 0.8],
        };
        let mut imm = Imm::new(x0, p0, params, CwModel::new(1e-3));
        let mut ekf = Ekf::new(x0, p0);
        let sensor = RadioSensor::new(Frame::RadialAlongNormal, 0.5, 1e-4);
        let m = model(1.0, 1e-8);
        for k in 0..50 {
            let z = Vec3::new(700.0 + 0.01 * k as f64, 0.67, -0.29);
            let a = imm.update(&sensor, &z).unwrap();
            let b = ekf.update(&sensor, &z).unwrap();
            assert!((a.nis - b.nis).abs() <= 1e-9 * b.nis.max(1.0));
            imm.predict(&m, &Vec3::zeros()).unwrap();
            ekf.predict(&m, &Vec3::zeros()).unwrap();
            assert!((imm.state() - ekf.state()).norm() <= 1e-9 * ekf.state().norm());
            assert!((imm.covariance() - ekf.covariance()).norm() <= 1e-9);
        }
        let mu = imm.mode_probabilities();
        let st = params.stationary();
        for j in 0..3 {
            assert!((mu[j] - st[j]).abs() < 1e-9, "{mu:?} vs {st:?}");
        }
    }

    /// The stationary distribution is invariant under the transition matrix, and each
    /// row of the transition matrix sums to one.
    #[test]
    fn stationary_distribution_is_invariant() {
        for modes in [2, 3] {
            let p = ImmParams {
                modes,
                ..Default::default()
            };
            let st = p.stationary();
            for h in [0.1, 1.0, 7.0] {
                let pi = p.transition(h);
                for row in pi.iter().take(modes) {
                    assert!((row.iter().sum::<f64>() - 1.0).abs() < 1e-14);
                }
                if (h - 1.0).abs() < 1e-12 {
                    for j in 0..modes {
                        let next: f64 = (0..modes).map(|i| pi[i][j] * st[i]).sum();
                        assert!((next - st[j]).abs() < 1e-14, "{modes} {j}");
                    }
                }
            }
        }
    }

    /// A failed update changes nothing (zero range in every mode).
    #[test]
    fn failed_update_changes_nothing() {
        let x0 = State::zeros();
        let mut imm = Imm::new(
            x0,
            Mat6::identity() * 1e-30,
            ImmParams::default(),
            CwModel::new(1e-3),
        );
        let before = imm.clone();
        let sensor = RadioSensor::new(Frame::RadialAlongNormal, 0.5, 1e-4);
        assert!(imm.update(&sensor, &Vec3::new(1.0, 0.0, 0.0)).is_err());
        assert_eq!(imm.state(), before.state());
        assert_eq!(imm.covariance(), before.covariance());
        assert_eq!(imm.mode_probabilities(), before.mode_probabilities());
        for j in 0..3 {
            assert_eq!(imm.mode(j), before.mode(j));
        }
    }
}
