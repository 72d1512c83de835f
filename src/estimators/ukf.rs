//! Unscented Kalman filter with scaled sigma points (Julier 2002; Wan & van der Merwe 2000;
//! the UKF of paper 001, sec. 1, and the proposal of paper 003).
//!
//! With `n = 6`, `lambda = alpha^2 (n + kappa) - n`, `L L^T = P` (Cholesky):
//!
//! ```text
//! chi_0 = x,  chi_i = x + sqrt(n + lambda) L_i,  chi_{n+i} = x - sqrt(n + lambda) L_i
//! Wm_0 = lambda / (n + lambda),  Wc_0 = Wm_0 + 1 - alpha^2 + beta,  W_i = 1 / (2 (n + lambda))
//! ```
//!
//! Time update: every sigma point goes through the process function, `x- = sum Wm chi_i`,
//! `P- = sum Wc (chi_i - x-)(chi_i - x-)^T + Q` (additive noise; [`Ukf::predict_with`],
//! used for nonlinear models). For the linear CW model this equals the Kalman time update
//! — the unscented transform is exact for linear maps — so [`Estimator::predict`] with a
//! [`DiscreteModel`] computes that form directly (issue 15: a quarter of the step's instructions);
//! the tests check that both agree to rounding.
//!
//! Measurement update: sigma points are redrawn from `(x-, P-)`, passed through `h`, and
//! * the predicted range and elevation are weighted means; the predicted **azimuth is a
//!   circular mean** `atan2(sum Wm sin a_i, sum Wm cos a_i)`, so sigma points on both sides
//!   of the 0/2 pi cut average correctly;
//! * every deviation `Z_i - z_hat` and the innovation have their azimuth wrapped to
//!   `(-pi, pi]`;
//! * `Pzz = sum Wc dZ dZ^T + R`, `Pxz = sum Wc dX dZ^T`, `K = Pxz Pzz^-1`,
//!   `x+ = x- + K nu`, `P+ = P- - K Pzz K^T` (symmetrised).
//!
//! Defaults `alpha = 1, beta = 2, kappa = 0` put all twelve outer points at `sqrt(6)` sigma
//! with positive weights (`Wm_0 = 0`), so `P-` is a positive combination of outer products
//! plus `Q` and stays positive definite; small `alpha` (1e-3, common in textbooks) gives
//! `Wc_0 ~ -1e6` and loses about twelve digits of the covariance for this problem.

use super::{finite, propagate_covariance, symmetrize, Estimator, FilterError, UpdateInfo};
use crate::dynamics::DiscreteModel;
use crate::numerics::state::{Persist, Reader, StateError, Writer};
use crate::sensors::{GeometryError, MeasurementModel};
use crate::types::{Mat3, Mat6, Mat63, State, Vec3};
use nalgebra::{SMatrix, SVector};

const N: usize = 6;
const NS: usize = 2 * N + 1;

/// Sigma-point parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UkfParams {
    /// Spread of the sigma points (0 < alpha <= 1 typical).
    pub alpha: f64,
    /// Prior-distribution parameter (2 is optimal for Gaussians).
    pub beta: f64,
    /// Secondary scaling (0, or 3 - n as in paper 001).
    pub kappa: f64,
}

impl Default for UkfParams {
    fn default() -> Self {
        Self {
            alpha: 1.0,
            beta: 2.0,
            kappa: 0.0,
        }
    }
}

impl UkfParams {
    /// `lambda = alpha^2 (n + kappa) - n`.
    pub fn lambda(&self) -> f64 {
        self.alpha * self.alpha * (N as f64 + self.kappa) - N as f64
    }

    /// Check that the parameters give a usable set of sigma points (`n + lambda > 0`).
    pub fn validate(&self) -> Result<(), String> {
        if !(self.alpha.is_finite() && self.beta.is_finite() && self.kappa.is_finite()) {
            return Err("UKF parameters alpha, beta and kappa must be finite".into());
        }
        if !(self.alpha > 0.0) {
            return Err(format!(
                "ukf_alpha must be > 0 (got {})",
                crate::numerics::num(self.alpha)
            ));
        }
        if !(N as f64 + self.lambda() > 0.0) {
            return Err(format!(
                "ukf_alpha^2 (6 + ukf_kappa) must be > 0 (got alpha {}, kappa {})",
                self.alpha, self.kappa
            ));
        }
        Ok(())
    }
}

/// Unscented Kalman filter for the 6-state CW problem.
#[derive(Debug, Clone, PartialEq)]
pub struct Ukf {
    x: State,
    p: Mat6,
    gamma: f64,
    wm: [f64; NS],
    wc: [f64; NS],
}

type Sigma = SMatrix<f64, N, NS>;

impl Ukf {
    /// A filter from `x0`, `p0` (canonical) with sigma-point parameters `params`
    /// (validated by the caller with [`UkfParams::validate`]).
    pub fn new(x0: State, p0: Mat6, params: UkfParams) -> Self {
        let lambda = params.lambda();
        let c = N as f64 + lambda;
        let mut wm = [0.5 / c; NS];
        let mut wc = [0.5 / c; NS];
        wm[0] = lambda / c;
        wc[0] = lambda / c + 1.0 - params.alpha * params.alpha + params.beta;
        Self {
            x: x0,
            p: p0,
            gamma: c.sqrt(),
            wm,
            wc,
        }
    }

    /// The unscented measurement update of `(x, p)` with measurement `z` and noise
    /// covariance `r` (in place of the sensor's own `noise_cov()`): returns `(x+, P+)` and
    /// the diagnostics without touching the filter. The unscented particle filters move
    /// every particle with it (their proposal, paper 003).
    pub fn measurement_update<M: MeasurementModel>(
        &self,
        x: &State,
        p: &Mat6,
        sensor: &M,
        r: &Mat3,
        z: &Vec3,
    ) -> Result<(State, Mat6, UpdateInfo), FilterError> {
        let l = p
            .cholesky()
            .ok_or(FilterError::NotPositiveDefinite("state covariance P"))?
            .unpack();
        self.measurement_update_factored(x, p, &l, sensor, r, z)
    }

    /// [`Ukf::measurement_update`] with the lower Cholesky factor `l` of `p` given (the
    /// particle filters' unscented proposal: one covariance shared by every particle,
    /// factored once per update instead of once per particle). Same result, bit for bit,
    /// when `l` is `p`'s Cholesky factor.
    pub fn measurement_update_factored<M: MeasurementModel>(
        &self,
        x: &State,
        p: &Mat6,
        l: &Mat6,
        sensor: &M,
        r: &Mat3,
        z: &Vec3,
    ) -> Result<(State, Mat6, UpdateInfo), FilterError> {
        let s = self.sigma_points_of(x, l);
        let pos: [Vec3; NS] = std::array::from_fn(|i| s.fixed_view::<3, 1>(0, i).into_owned());
        let mut dzs = [Vec3::zeros(); NS];
        let z_hat = sensor
            .unscented(&pos, &self.wm, &mut dzs)
            .ok_or(FilterError::Geometry(GeometryError::ZeroRange))?;
        // near the poles the azimuth carries no information (see sensors docs)
        let azimuth_used = sensor.azimuth_usable(&x.fixed_rows::<3>(0).into_owned())?;
        let mut pzz: Mat3 = *r;
        let mut pxz = Mat63::zeros();
        for (i, dz) in dzs.iter().enumerate() {
            let mut dz = *dz;
            if !azimuth_used {
                dz.y = 0.0;
            }
            let dx = s.column(i) - x;
            pzz += dz * dz.transpose() * self.wc[i];
            pxz += dx * dz.transpose() * self.wc[i];
        }
        let chol = pzz.cholesky().ok_or(FilterError::NotPositiveDefinite(
            "innovation covariance Pzz",
        ))?;
        let k = chol.solve(&pxz.transpose()).transpose();
        let mut nu = sensor.diff(z, &z_hat);
        if !azimuth_used {
            nu.y = 0.0;
        }
        let xn = x + k * nu;
        let pn = symmetrize(&(p - k * pzz * k.transpose()));
        finite(&xn, "updated state")?;
        finite(&pn, "updated covariance")?;
        let nis = nu.dot(&chol.solve(&nu));
        Ok((
            xn,
            pn,
            UpdateInfo {
                innovation: nu,
                nis,
                azimuth_used,
            },
        ))
    }

    /// Generic unscented time update (paper 001, sec. 2.1, steps 2-3): every sigma point of
    /// `(x, P)` goes through the process function `f` (any model: the CW transition, or an
    /// RK4 step of a nonlinear orbit), `x- = sum Wm chi_i`,
    /// `P- = sum Wc (chi_i - x-)(chi_i - x-)^T + q`. The filter is unchanged on error.
    pub fn predict_with<F>(&mut self, q: &Mat6, mut f: F) -> Result<(), FilterError>
    where
        F: FnMut(&State) -> Result<State, FilterError>,
    {
        let s = self.sigma_points(&self.x, &self.p)?;
        let mut prop = Sigma::zeros();
        let mut mean = State::zeros();
        for i in 0..NS {
            let c = f(&s.column(i).into_owned())?;
            mean += c * self.wm[i];
            prop.set_column(i, &c);
        }
        let mut p = *q;
        for i in 0..NS {
            let d = prop.column(i) - mean;
            p += d * d.transpose() * self.wc[i];
        }
        let p = symmetrize(&p);
        finite(&mean, "predicted state")?;
        finite(&p, "predicted covariance")?;
        self.x = mean;
        self.p = p;
        Ok(())
    }

    /// Generic unscented measurement update (paper 001, sec. 2.1, steps 4-6) for a
    /// measurement of any dimension `M` with additive noise covariance `r`, arithmetic means
    /// and plain differences (no angle wrapping: for measurements that stay away from a
    /// cut, such as the star-to-body angles of paper 001 in `[0, pi]`). `h` returns `None`
    /// where the measurement is undefined. Returns the NIS `nu^T Pzz^-1 nu`; the filter is
    /// unchanged on error.
    pub fn update_generic<const M: usize, H>(
        &mut self,
        h: H,
        z: &SVector<f64, M>,
        r: &SMatrix<f64, M, M>,
    ) -> Result<f64, FilterError>
    where
        H: Fn(&State) -> Option<SVector<f64, M>>,
    {
        let s = self.sigma_points(&self.x, &self.p)?;
        let mut zs = [SVector::<f64, M>::zeros(); NS];
        let mut z_hat = SVector::<f64, M>::zeros();
        for (i, zi) in zs.iter_mut().enumerate() {
            *zi = h(&s.column(i).into_owned())
                .ok_or(FilterError::Geometry(GeometryError::ZeroRange))?;
            z_hat += *zi * self.wm[i];
        }
        let mut pzz = *r;
        let mut pxz = SMatrix::<f64, N, M>::zeros();
        for (i, zi) in zs.iter().enumerate() {
            let dz = zi - z_hat;
            let dx = s.column(i) - self.x;
            pzz += dz * dz.transpose() * self.wc[i];
            pxz += dx * dz.transpose() * self.wc[i];
        }
        let chol = pzz.cholesky().ok_or(FilterError::NotPositiveDefinite(
            "innovation covariance Pzz",
        ))?;
        let k = chol.solve(&pxz.transpose()).transpose();
        let nu = z - z_hat;
        let xn = self.x + k * nu;
        let pn = symmetrize(&(self.p - k * pzz * k.transpose()));
        finite(&xn, "updated state")?;
        finite(&pn, "updated covariance")?;
        let nis = nu.dot(&chol.solve(&nu));
        self.x = xn;
        self.p = pn;
        Ok(nis)
    }

    fn sigma_points(&self, x: &State, p: &Mat6) -> Result<Sigma, FilterError> {
        let l = p
            .cholesky()
            .ok_or(FilterError::NotPositiveDefinite("state covariance P"))?
            .unpack();
        Ok(self.sigma_points_of(x, &l))
    }

    /// The sigma points of `(x, L L^T)`.
    fn sigma_points_of(&self, x: &State, l: &Mat6) -> Sigma {
        let mut s = Sigma::zeros();
        s.set_column(0, x);
        for i in 0..N {
            let d = l.column(i) * self.gamma;
            s.set_column(1 + i, &(x + d));
            s.set_column(1 + N + i, &(x - d));
        }
        s
    }
}

impl Estimator for Ukf {
    /// The time update through the linear discrete model. The unscented transform of a
    /// linear map is exact, `sum Wc (Phi chi_i - Phi x)(...)^T = Phi P Phi^T`, so this is
    /// the Kalman form `x- = Phi x + Gamma a`, `P- = Phi P Phi^T + Q` (CW block structure,
    /// as the EKF's): the same result as [`Ukf::predict_with`] with `model.apply` to
    /// rounding (tested) without the Cholesky factor and the 13 propagated sigma points.
    fn predict(&mut self, model: &DiscreteModel, accel: &Vec3) -> Result<(), FilterError> {
        let x = model.apply(&self.x, accel);
        let p = propagate_covariance(&model.phi, &self.p, &model.q);
        finite(&x, "predicted state")?;
        finite(&p, "predicted covariance")?;
        self.x = x;
        self.p = p;
        Ok(())
    }

    fn update<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
    ) -> Result<UpdateInfo, FilterError> {
        let (x, p, info) =
            self.measurement_update(&self.x, &self.p, sensor, &sensor.noise_cov(), z)?;
        self.x = x;
        self.p = p;
        Ok(info)
    }

    fn state(&self) -> &State {
        &self.x
    }

    fn covariance(&self) -> &Mat6 {
        &self.p
    }

    fn set_estimate(&mut self, x: State, p: Mat6) {
        self.x = x;
        self.p = p;
    }
}

/// Saved state: `x` (6), `P` (36, column by column). The sigma-point scale and weights are
/// configuration (`UkfParams`), rebuilt by the restoring filter.
impl Persist for Ukf {
    fn save_state(&self, w: &mut Writer<'_>) {
        let Self {
            x,
            p,
            gamma: _,
            wm: _,
            wc: _,
        } = self;
        w.matrix(x);
        w.matrix(p);
    }

    fn load_state(&mut self, r: &mut Reader<'_>) -> Result<(), StateError> {
        let Self {
            x,
            p,
            gamma: _,
            wm: _,
            wc: _,
        } = self;
        *x = r.finite_matrix("UKF state")?;
        *p = r.finite_matrix("UKF covariance")?;
        Ok(())
    }
}
