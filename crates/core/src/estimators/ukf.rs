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
//! [`DiscreteModel`] computes that form directly, saving the sigma points' propagation;
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

use super::covariance::{moments_update, time_update, time_update_into};
use super::{finite, Estimator, FilterError, SensorUpdate, UpdateInfo};
use crate::dynamics::DiscreteModel;
#[cfg(not(feature = "std"))]
use crate::math::Float;
use crate::numerics::cholesky::{self, chol3_lane, dot3, forward_lane, lower6, outer6};
use crate::numerics::state::{Persist, Reader, StateError, Writer};
use crate::numerics::symmetrize;
use crate::numerics::Owned;
use crate::sensors::{AngleTrig, GeometryError, MeasurementModel, Sensor, SevenBlock, Support};
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
    pub fn validate(&self) -> Result<(), crate::message::Message> {
        if !(self.alpha.is_finite() && self.beta.is_finite() && self.kappa.is_finite()) {
            return Err("UKF parameters alpha, beta and kappa must be finite".into());
        }
        if !(self.alpha > 0.0) {
            return Err(crate::msg!(
                "ukf_alpha must be > 0 (got {})",
                crate::numerics::num(self.alpha)
            ));
        }
        if !(N as f64 + self.lambda() > 0.0) {
            return Err(crate::msg!(
                "ukf_alpha^2 (6 + ukf_kappa) must be > 0 (got alpha {}, kappa {})",
                self.alpha,
                self.kappa
            ));
        }
        Ok(())
    }
}

/// Unscented Kalman filter for the 6-state CW problem.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ukf {
    x: State,
    p: Mat6,
    gamma: f64,
    wm: [f64; NS],
    wc: [f64; NS],
    /// the radio update's noise density when it is not the Gaussian of its variance (the
    /// particle prior's unscented terms; [`super::rekf`]). Configuration.
    robust: Option<crate::noise::NoiseModel>,
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
            robust: None,
        }
    }

    /// The radio's update with the noise density `noise` ([`super::rekf`]'s robust update
    /// on the sigma points' moments; the sensor's `R` is its variance). `None`: the
    /// Gaussian of the variance.
    pub fn robust(mut self, noise: Option<crate::noise::NoiseModel>) -> Self {
        self.robust = noise;
        self
    }

    /// The unscented measurement update of `(x, p)` with measurement `z` and noise
    /// covariance `r` (in place of the sensor's own `noise_cov()`): returns `(x+, P+)` and
    /// the diagnostics without touching the filter. The unscented particle filters move
    /// every particle with it (their proposal, paper 003).
    #[inline(always)]
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
    #[inline(always)]
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
        let pos: [Vec3; NS] = core::array::from_fn(|i| s.fixed_view::<3, 1>(0, i).owned());
        let mut dzs = [Vec3::zeros(); NS];
        let z_hat = sensor
            .unscented(&pos, &self.wm, &mut dzs)
            .ok_or(FilterError::Geometry(GeometryError::ZeroRange))?;
        // near the poles the azimuth carries no information (see sensors docs)
        let azimuth_used = sensor.azimuth_usable(&x.fixed_rows::<3>(0).owned())?;
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
        let mut nu = sensor.diff(z, &z_hat);
        if !azimuth_used {
            nu.y = 0.0;
        }
        // the closed-form 3 x 3 factor, inlined (nalgebra's generic factor and solves are
        // out-of-line calls from the navigator's step, whose argument copies are a large
        // part of the UKF's FMU cycle overhead)
        let chol = cholesky::chol3(&pzz).ok_or(FilterError::NotPositiveDefinite(
            "innovation covariance Pzz",
        ))?;
        let robust = self.robust.as_ref().and_then(|noise| {
            super::rekf::robust_update_unscented(
                x,
                p,
                &pxz,
                &(pzz - r),
                &nu,
                r,
                noise,
                azimuth_used,
            )
        });
        let (xn, pn) = match robust {
            Some(updated) => updated?,
            None => moments_update(x, p, &pxz, &pzz, &chol, &nu),
        };
        finite(&xn, "updated state")?;
        finite(&pn, "updated covariance")?;
        // `nu^T Pzz^-1 nu = |L^-1 nu|^2` (a robust update's too: against the variance's)
        let nis = chol.forward(&nu).norm_squared();
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

    /// The parts of the measurement update that depend only on the covariance `P = L L^T`
    /// (`l` its lower Cholesky factor), formed once for many states that share `P` (the
    /// particle filters' unscented proposal). `None` unless the twelve outer sigma points
    /// have one weight (they do for every [`UkfParams`]).
    pub fn shared_prior(&self, l: &Mat6) -> Option<SharedPrior> {
        let (wm, wc) = (self.wm[1], self.wc[1]);
        if !(self.wm[1..].iter().all(|&v| v == wm) && self.wc[1..].iter().all(|&v| v == wc)) {
            return None;
        }
        Some(SharedPrior {
            l: *l,
            o: core::array::from_fn(|j| l.fixed_view::<3, 1>(0, j) * self.gamma),
            gamma: self.gamma,
            // the velocity columns' six points sit at the centre's position
            wm: (self.wm[0] + 6.0 * wm, wm),
            wc: (self.wc[0] + 6.0 * wc, wc),
        })
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
            let c = f(&s.column(i).owned())?;
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
        let plain = Measurement {
            h,
            mean: |wm: &[f64], zs: &[SVector<f64, M>]| {
                let mut z_hat = SVector::<f64, M>::zeros();
                for (zi, w) in zs.iter().zip(wm) {
                    z_hat += *zi * *w;
                }
                z_hat
            },
            residual: |a: &SVector<f64, M>, b: &SVector<f64, M>| a - b,
            r: *r,
            used: [true; M],
        };
        let (x, p, _, nis) = self.unscented_update(&self.x, &self.p, &plain, z)?;
        self.x = x;
        self.p = p;
        Ok(nis)
    }

    /// The unscented measurement update of `(x, P)` with any sensor (the generic path,
    /// [`Estimator::update_sensor`]), not committed: the 13 sigma points' measurements,
    /// their mean and deviations by the sensor's own `mean` and `residual` (circular for
    /// angles), `Pzz = sum Wc dz dz^T + R` with the noise's Gaussian `R`, `Pxz`, the gain
    /// by a Cholesky solve. Components the sensor marks unused at `x` are dropped (zero
    /// deviations and residual).
    ///
    /// Two sensors need less ([`Sensor::support`], [`Sensor::linear`]): the unscented
    /// transform of a linear measurement is exact (`z_hat = H x`, `Pzz = H P H^T + R`,
    /// `Pxz = P H^T` for these weights, `2 W gamma^2 = 1`), so its update is the Kalman
    /// update, computed in closed form ([`super::ekf`]'s, in Joseph's form); a measurement of
    /// the position alone takes the seven distinct positions of the sigma points
    /// ([`Ukf::position_update`]).
    pub fn sensor_update<const D: usize, S: Sensor<D> + ?Sized>(
        &self,
        x: &State,
        p: &Mat6,
        sensor: &S,
        z: &SVector<f64, D>,
    ) -> Result<(State, Mat6, SensorUpdate<D>), FilterError> {
        if sensor.linear() {
            let (xn, pn, info, _) = super::ekf::linearised_update(x, p, sensor, z)?;
            return Ok((xn, pn, info));
        }
        let used = sensor.used(x)?;
        let (xn, pn, nu, nis) = if sensor.support() == Support::Position {
            self.position_update(x, p, sensor, used, z)?
        } else {
            let m = Measurement {
                h: |x: &State| sensor.measure(x),
                mean: |wm: &[f64], zs: &[SVector<f64, D>]| sensor.mean(wm, zs),
                residual: |a: &SVector<f64, D>, b: &SVector<f64, D>| sensor.residual(a, b),
                r: sensor.noise().cov(),
                used,
            };
            self.unscented_update(x, p, &m, z)?
        };
        let info = SensorUpdate {
            innovation: nu,
            nis,
            dof: used.iter().filter(|u| **u).count(),
        };
        Ok((xn, pn, info))
    }

    /// [`Ukf::sensor_update`] for a sensor of the position alone: `L` is lower triangular,
    /// so the six sigma points of its velocity columns share the centre's position and
    /// measurement. Seven measurements, the centre's with the weights of all seven centre
    /// points; those six points' state deviations cancel in pairs in `Pxz`, so
    /// `Pxz = sum_(j<3) W gamma L_j (dZ_(+j) - dZ_(-j))^T`. The same update as the
    /// thirteen-point form, to rounding (unit test).
    fn position_update<const D: usize, S: Sensor<D> + ?Sized>(
        &self,
        x: &State,
        p: &Mat6,
        sensor: &S,
        used: [bool; D],
        z: &SVector<f64, D>,
    ) -> Result<(State, Mat6, SVector<f64, D>, f64), FilterError> {
        let l = cholesky::chol6(p).ok_or(FilterError::NotPositiveDefinite("state covariance P"))?;
        // the outer points share one weight (`Ukf::new`)
        let (wm, wc) = (self.wm[1], self.wc[1]);
        let wm7 = [self.wm[0] + 6.0 * wm, wm, wm, wm, wm, wm, wm];
        let d: [State; 3] = core::array::from_fn(|j| l.column(j) * self.gamma);
        let [d0, d1, d2] = d;
        let points = [*x, x + d0, x + d1, x + d2, x - d0, x - d1, x - d2];
        let mut zs = [SVector::<f64, D>::zeros(); 7];
        for (zi, xi) in zs.iter_mut().zip(&points) {
            *zi = sensor
                .measure(xi)
                .ok_or(FilterError::Geometry(GeometryError::ZeroRange))?;
        }
        let z_hat = sensor.mean(&wm7, &zs);
        let drop = |mut v: SVector<f64, D>| {
            for (k, u) in used.iter().enumerate() {
                if !u {
                    v[k] = 0.0;
                }
            }
            v
        };
        let dz: [SVector<f64, D>; 7] =
            core::array::from_fn(|i| drop(sensor.residual(&zs[i], &z_hat)));
        let mut pzz = sensor.noise().cov() + dz[0] * dz[0].transpose() * (self.wc[0] + 6.0 * wc);
        let mut pxz = SMatrix::<f64, N, D>::zeros();
        for j in 0..3 {
            let (a, b) = (dz[1 + j], dz[4 + j]);
            pzz += (a * a.transpose() + b * b.transpose()) * wc;
            pxz += d[j] * ((a - b) * wc).transpose();
        }
        let chol = pzz.cholesky().ok_or(FilterError::NotPositiveDefinite(
            "innovation covariance Pzz",
        ))?;
        let k = chol.solve(&pxz.transpose()).transpose();
        let nu = drop(sensor.residual(z, &z_hat));
        let xn = x + k * nu;
        let pn = symmetrize(&(p - k * pzz * k.transpose()));
        finite(&xn, "updated state")?;
        finite(&pn, "updated covariance")?;
        let nis = nu.dot(&chol.solve(&nu));
        Ok((xn, pn, nu, nis))
    }

    /// The unscented measurement update of `(x, P)` with measurement `m`, not committed:
    /// the updated state and covariance, the innovation and the NIS.
    fn unscented_update<const D: usize, H, A, R>(
        &self,
        x: &State,
        p: &Mat6,
        m: &Measurement<H, A, R, D>,
        z: &SVector<f64, D>,
    ) -> Result<(State, Mat6, SVector<f64, D>, f64), FilterError>
    where
        H: Fn(&State) -> Option<SVector<f64, D>>,
        A: Fn(&[f64], &[SVector<f64, D>]) -> SVector<f64, D>,
        R: Fn(&SVector<f64, D>, &SVector<f64, D>) -> SVector<f64, D>,
    {
        let s = self.sigma_points(x, p)?;
        let mut zs = [SVector::<f64, D>::zeros(); NS];
        for (i, zi) in zs.iter_mut().enumerate() {
            *zi = (m.h)(&s.column(i).owned())
                .ok_or(FilterError::Geometry(GeometryError::ZeroRange))?;
        }
        let z_hat = (m.mean)(&self.wm, &zs);
        let drop = |mut v: SVector<f64, D>| {
            for (k, u) in m.used.iter().enumerate() {
                if !u {
                    v[k] = 0.0;
                }
            }
            v
        };
        let mut pzz = m.r;
        let mut pxz = SMatrix::<f64, N, D>::zeros();
        for (i, zi) in zs.iter().enumerate() {
            let dz = drop((m.residual)(zi, &z_hat));
            let dx = s.column(i) - x;
            pzz += dz * dz.transpose() * self.wc[i];
            pxz += dx * dz.transpose() * self.wc[i];
        }
        let chol = pzz.cholesky().ok_or(FilterError::NotPositiveDefinite(
            "innovation covariance Pzz",
        ))?;
        let k = chol.solve(&pxz.transpose()).transpose();
        let nu = drop((m.residual)(z, &z_hat));
        let xn = x + k * nu;
        let pn = symmetrize(&(p - k * pzz * k.transpose()));
        finite(&xn, "updated state")?;
        finite(&pn, "updated covariance")?;
        let nis = nu.dot(&chol.solve(&nu));
        Ok((xn, pn, nu, nis))
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

/// A measurement as the unscented update takes it: the function, the weighted mean and the
/// residual of its values, the noise covariance and the components used.
struct Measurement<H, A, R, const D: usize> {
    h: H,
    mean: A,
    residual: R,
    r: SMatrix<f64, D, D>,
    used: [bool; D],
}

/// What the unscented measurement update of any state `x` with the covariance
/// `P = L L^T` shares with every other such state ([`Ukf::shared_prior`]). The sigma points
/// are `x` and `x ± gamma L_j`; `L` is lower triangular, so its velocity columns
/// `j = 3, 4, 5` have no position part, and as the measurement depends on the position
/// alone those six points are measured at the centre: seven distinct positions
/// ([`MeasurementModel::unscented_seven`]). With `dZ_i` the measurement deviations and
/// `W_c`, `W` the centre's (all seven centre points) and every other point's covariance
/// weight (`x_i - x = ± gamma L_j`, the centre's term vanishes):
///
/// ```text
/// Pzz = R + W_c dZ_0 dZ_0^T + W sum_(i>0) dZ_i dZ_i^T
/// Pxz = gamma L E,   E = [d_0 d_1 d_2 0 0 0]^T,   d_j = W (dZ_(+j) - dZ_(-j))
/// ```
///
/// In the prior's whitened coordinates (`x = x- + L u`) with `Pzz = C C^T` (3 x 3
/// Cholesky) and `V = gamma E C^-T` (its last three rows zero), the gain's step and the
/// posterior are
///
/// ```text
/// L^-1 (x+ - x-) = V C^-1 nu,     L^-1 P+ L^-T = I - V V^T = blockdiag(M M^T, I_3)
/// ```
///
/// so `P+`'s Cholesky factor is `L blockdiag(M, I_3)` (a product of lower triangular
/// factors), `M` the 3 x 3 Cholesky factor of `I_3 - V_3 V_3^T`, and
/// `ln det P+ = ln det P + 2 ln(M_00 M_11 M_22)`. Per state: seven measurements, `Pzz`
/// (six entries), two 3 x 3 Cholesky factors and a few 3-vector solves, instead of
/// thirteen measurements, thirteen outer products of `Pzz` and `Pxz`, the 6 x 6 gain, the
/// posterior covariance and its 6 x 6 factor. The same update as
/// [`Ukf::measurement_update`] to rounding (tested in every frame, poles and outliers
/// included).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SharedPrior {
    l: Mat6,
    /// the position parts of `gamma L_j`, `j = 0, 1, 2`
    o: [Vec3; 3],
    gamma: f64,
    /// mean weights `(W_c, W)`
    wm: (f64, f64),
    /// covariance weights `(W_c, W)`
    wc: (f64, f64),
}

/// One state's update with a [`SharedPrior`], in the prior's whitened coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WhitenedUpdate {
    /// `L^-1 (x+ - x-)` (its last three components are zero)
    pub step: Vec3,
    /// `M`: `P+ = L blockdiag(M M^T, I_3) L^T`, lower triangular
    pub m: Mat3,
    /// Innovation, NIS and the pole test, as [`Ukf::measurement_update`] reports them.
    pub info: UpdateInfo,
}

impl SharedPrior {
    /// The prior covariance's lower Cholesky factor `L`.
    pub fn factor(&self) -> &Mat6 {
        &self.l
    }

    /// The update of the state `x` with measurement `z` (angles `trig`, [`AngleTrig::of`])
    /// and noise covariance `r` (see the type's documentation). Fails where
    /// [`Ukf::measurement_update`] does (zero range, a covariance that is not positive
    /// definite, non-finite results).
    pub fn update<M: MeasurementModel>(
        &self,
        x: &State,
        sensor: &M,
        r: &Mat3,
        z: &Vec3,
        trig: &AngleTrig,
    ) -> Result<WhitenedUpdate, FilterError> {
        let c = Vec3::new(x[0], x[1], x[2]);
        let mut dz = [Vec3::zeros(); 7];
        let (mut nu, azimuth_used) = sensor
            .unscented_seven(z, trig, &c, &self.o, self.wm, &mut dz)
            .ok_or(FilterError::Geometry(GeometryError::ZeroRange))?;
        // near the poles the azimuth carries no information (see sensors docs)
        if !azimuth_used {
            nu.y = 0.0;
            dz.iter_mut().for_each(|d| d.y = 0.0);
        }
        // Pzz's six entries
        let (w0, w) = self.wc;
        let mut s = [0.0; 6];
        for d in &dz[1..] {
            let o = outer6(&[d.x, d.y, d.z]);
            for k in 0..6 {
                s[k] += o[k];
            }
        }
        let o0 = outer6(&[dz[0].x, dz[0].y, dz[0].z]);
        let p: [f64; 6] = core::array::from_fn(|k| w0 * o0[k] + w * s[k]);
        let pzz_err = FilterError::NotPositiveDefinite("innovation covariance Pzz");
        let cz = chol3(&[
            r[(0, 0)] + p[0],
            r[(1, 0)] + p[1],
            r[(2, 0)] + p[2],
            r[(1, 1)] + p[3],
            r[(2, 1)] + p[4],
            r[(2, 2)] + p[5],
        ])
        .ok_or(pzz_err)?;
        // V's rows v_j = C^-1 (gamma d_j)
        let gw = self.gamma * w;
        let v: [Vec3; 3] = core::array::from_fn(|j| cz.forward(&((dz[1 + j] - dz[4 + j]) * gw)));
        let y = cz.forward(&nu);
        let step = Vec3::new(v[0].dot(&y), v[1].dot(&y), v[2].dot(&y));
        let m = chol3(&[
            1.0 - v[0].dot(&v[0]),
            -v[1].dot(&v[0]),
            -v[2].dot(&v[0]),
            1.0 - v[1].dot(&v[1]),
            -v[2].dot(&v[1]),
            1.0 - v[2].dot(&v[2]),
        ])
        .ok_or(FilterError::NotPositiveDefinite("updated covariance"))?
        .factor();
        if !crate::numerics::all_finite(step.as_slice()) {
            return Err(FilterError::NonFinite("updated state"));
        }
        Ok(WhitenedUpdate {
            step,
            m,
            info: UpdateInfo {
                innovation: nu,
                nis: y.norm_squared(),
                azimuth_used,
            },
        })
    }
}

/// [`SharedPrior::update`]'s results for a block of states in structure-of-arrays form
/// ([`SharedPrior::update_block`]): lane `i` holds `step[k][i]` and `M`'s lower triangle
/// `m[.][i] = (M_00, M_10, M_20, M_11, M_21, M_22)` where `fast[i]`.
#[derive(Debug, Clone, Copy)]
pub struct WhitenedBlock<const B: usize> {
    /// `L^-1 (x+ - x-)`, first three components
    pub step: [[f64; B]; 3],
    /// `M`'s lower triangle `(M_00, M_10, M_20, M_11, M_21, M_22)`
    pub m: [[f64; B]; 6],
    /// lanes whose values are [`SharedPrior::update`]'s bit for bit (the others must be
    /// computed by it)
    pub fast: [bool; B],
    /// scratch (kept here so that a caller reusing the block does not zero it block by
    /// block): the sensor's side
    seven: SevenBlock<B>,
    /// scratch: `Pzz`'s sums over the outer points
    s: [[f64; B]; 6],
}

impl<const B: usize> Default for WhitenedBlock<B> {
    fn default() -> Self {
        Self {
            step: [[0.0; B]; 3],
            m: [[0.0; B]; 6],
            fast: [false; B],
            seven: SevenBlock::default(),
            s: [[0.0; B]; 6],
        }
    }
}

impl SharedPrior {
    /// [`SharedPrior::update`] of a block of states at once (`c[k][i]` component `k` of
    /// state `i`'s position; the velocities do not enter) in structure-of-arrays form,
    /// with no branch in the loops, so that the compiler vectorises them across states
    /// (run it inside [`crate::numerics::simd::dispatch`]): the sensor's
    /// [`MeasurementModel::unscented_seven_block`], then `Pzz`, its factor `C`,
    /// `V = gamma E C^-T`, the step `V C^-1 nu` and `M` (see the type's documentation),
    /// the same operations in the same order as `update` per lane. A lane is `fast` where
    /// the sensor's block form applies (its azimuth usable) and `update` would succeed;
    /// the other lanes are left to `update` (which then also reports the failure).
    #[allow(clippy::too_many_arguments, clippy::needless_range_loop)]
    #[inline(always)]
    pub fn update_block<M: MeasurementModel, const B: usize>(
        &self,
        c: &[[f64; B]; 3],
        sensor: &M,
        r: &Mat3,
        z: &Vec3,
        trig: &AngleTrig,
        out: &mut WhitenedBlock<B>,
    ) {
        sensor.unscented_seven_block(z, trig, c, &self.o, self.wm, &mut out.seven);
        let (dz, nu, s) = (&out.seven.dz, &out.seven.nu, &mut out.s);
        out.fast = out.seven.fast;
        let (w0, w) = self.wc;
        let gw = self.gamma * w;
        let rl = lower6(r);
        // Pzz's six entries: the sums over the outer points, lanes innermost (vectorised)
        for sk in s.iter_mut() {
            sk.fill(0.0);
        }
        for dp in &dz[1..] {
            for i in 0..B {
                let d = [dp[0][i], dp[1][i], dp[2][i]];
                let o = outer6(&d);
                for k in 0..6 {
                    s[k][i] += o[k];
                }
            }
        }
        // the factor of Pzz, lanes innermost (each loop below vectorises across states;
        // the intermediate values in local arrays)
        let (mut cl, mut ci, mut ok) = ([[0.0; B]; 6], [[0.0; B]; 3], [false; B]);
        for i in 0..B {
            let o0 = outer6(&[dz[0][0][i], dz[0][1][i], dz[0][2][i]]);
            let a: [f64; 6] = core::array::from_fn(|k| rl[k] + (w0 * o0[k] + w * s[k][i]));
            let (l, inv, ok_c) = chol3_lane(a);
            for k in 0..6 {
                cl[k][i] = l[k];
            }
            for k in 0..3 {
                ci[k][i] = inv[k];
            }
            ok[i] = ok_c;
        }
        // V's rows v_j = C^-1 (gamma d_j), y = C^-1 nu, the step and I - V V^T
        let (mut step, mut g) = ([[0.0; B]; 3], [[0.0; B]; 6]);
        for i in 0..B {
            let l = [cl[0][i], cl[1][i], cl[2][i], cl[3][i], cl[4][i], cl[5][i]];
            let inv = [ci[0][i], ci[1][i], ci[2][i]];
            let e = |j: usize| {
                let (p, q) = (&dz[1 + j], &dz[4 + j]);
                [
                    (p[0][i] - q[0][i]) * gw,
                    (p[1][i] - q[1][i]) * gw,
                    (p[2][i] - q[2][i]) * gw,
                ]
            };
            let v = [
                forward_lane(&l, &inv, e(0)),
                forward_lane(&l, &inv, e(1)),
                forward_lane(&l, &inv, e(2)),
            ];
            let y = forward_lane(&l, &inv, [nu[0][i], nu[1][i], nu[2][i]]);
            let st = [dot3(&v[0], &y), dot3(&v[1], &y), dot3(&v[2], &y)];
            let gi = [
                1.0 - dot3(&v[0], &v[0]),
                -dot3(&v[1], &v[0]),
                -dot3(&v[2], &v[0]),
                1.0 - dot3(&v[1], &v[1]),
                -dot3(&v[2], &v[1]),
                1.0 - dot3(&v[2], &v[2]),
            ];
            for k in 0..3 {
                step[k][i] = st[k];
            }
            for k in 0..6 {
                g[k][i] = gi[k];
            }
        }
        // M, the factor of I - V V^T
        let (mut mm, mut ok_m) = ([[0.0; B]; 6], [false; B]);
        for i in 0..B {
            let (ml, _, okm) = chol3_lane(core::array::from_fn(|k| g[k][i]));
            let ok_s = step[0][i].is_finite() & step[1][i].is_finite() & step[2][i].is_finite();
            for k in 0..6 {
                mm[k][i] = ml[k];
            }
            ok_m[i] = okm & ok_s;
        }
        out.step = step;
        out.m = mm;
        for i in 0..B {
            out.fast[i] &= ok[i] & ok_m[i];
        }
    }
}

impl WhitenedUpdate {
    /// The updated state `x + L (step, 0)`.
    pub fn mean(&self, x: &State, prior: &SharedPrior) -> State {
        x + prior.l.fixed_columns::<3>(0) * self.step
    }

    /// The updated covariance's lower Cholesky factor `L blockdiag(M, I_3)`.
    pub fn factor(&self, prior: &SharedPrior) -> Mat6 {
        let mut b = Mat6::identity();
        b.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.m);
        prior.l * b
    }
}

/// The Cholesky factor of the symmetric 3 x 3 matrix with lower triangle `(a00, a10,
/// a20, a11, a21, a22)` ([`cholesky::chol3`]); `None` unless positive definite (NaN included)
/// with a finite factor.
fn chol3(a: &[f64; 6]) -> Option<cholesky::Chol3> {
    cholesky::chol3(&Mat3::new(
        a[0], a[1], a[2], a[1], a[3], a[4], a[2], a[4], a[5],
    ))
    .filter(cholesky::Chol3::is_finite)
}

impl Ukf {
    /// One step, transactional: the measurement update with `z`, then the time update with
    /// `model` and `accel`, committed only when both succeed (the same arithmetic as
    /// [`Estimator::update`] then [`Estimator::predict`], so the same bits; the navigator
    /// needs no snapshot to undo the update when the prediction fails), as the EKF's
    /// `update_predict`.
    pub fn update_predict<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
        model: &DiscreteModel,
        accel: &Vec3,
    ) -> Result<UpdateInfo, FilterError> {
        // `measurement_update` with the factor written out (`chol6`, the same bits): inlined
        // into the navigator's step, nalgebra's factorisation stays an out-of-line call with
        // copies in and out
        let l = cholesky::chol6(&self.p)
            .ok_or(FilterError::NotPositiveDefinite("state covariance P"))?;
        let (x, p, info) =
            self.measurement_update_factored(&self.x, &self.p, &l, sensor, &sensor.noise_cov(), z)?;
        time_update_into(model, &x, &p, accel, (&mut self.x, &mut self.p))?;
        Ok(info)
    }

    /// [`Ukf::update_predict`] with any sensor ([`Ukf::sensor_update`], then the time
    /// update), committed only when both succeed.
    #[inline(always)]
    pub fn update_sensor_predict<const D: usize, S: Sensor<D> + ?Sized>(
        &mut self,
        sensor: &S,
        z: &SVector<f64, D>,
        model: &DiscreteModel,
        accel: &Vec3,
    ) -> Result<SensorUpdate<D>, FilterError> {
        let (x, p, info) = self.sensor_update(&self.x, &self.p, sensor, z)?;
        time_update_into(model, &x, &p, accel, (&mut self.x, &mut self.p))?;
        Ok(info)
    }
}

impl Estimator for Ukf {
    /// The time update through the linear discrete model. The unscented transform of a
    /// linear map is exact, `sum Wc (Phi chi_i - Phi x)(...)^T = Phi P Phi^T`, so this is
    /// the Kalman form `x- = Phi x + Gamma a`, `P- = Phi P Phi^T + Q` (CW block structure,
    /// as the EKF's): the same result as [`Ukf::predict_with`] with `model.apply` to
    /// rounding (tested) without the Cholesky factor and the 13 propagated sigma points.
    fn predict(&mut self, model: &DiscreteModel, accel: &Vec3) -> Result<(), FilterError> {
        time_update(model, &mut self.x, &mut self.p, accel)?;
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

    fn update_sensor<const D: usize, S: Sensor<D> + ?Sized>(
        &mut self,
        sensor: &S,
        z: &SVector<f64, D>,
    ) -> Result<SensorUpdate<D>, FilterError> {
        let (x, p, info) = self.sensor_update(&self.x, &self.p, sensor, z)?;
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

/// Saved state: `x` (6), `P` (36, column by column). The sigma-point scale and weights and
/// the noise density are configuration (`UkfParams`, `noise_model`), rebuilt by the
/// restoring filter.
impl Persist for Ukf {
    fn save_state(&self, w: &mut Writer<'_>) {
        let Self {
            x,
            p,
            gamma: _,
            wm: _,
            wc: _,
            robust: _,
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
            robust: _,
        } = self;
        *x = r.finite_matrix("UKF state")?;
        *p = r.finite_matrix("UKF covariance")?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frames::Frame;
    use crate::sensors::RadioSensor;
    use rand::{Rng, SeedableRng};

    /// `update_predict` is `update` then `predict` bit for bit, and a prediction that fails
    /// after the update leaves the filter as it was (the navigator relies on it instead of a
    /// snapshot).
    #[test]
    fn update_predict_is_update_then_predict_and_transactional() {
        crate::estimators::check_update_predict(
            |x, p| Ukf::new(x, p, UkfParams::default()),
            |f, s, z, d, a| f.update_predict(s, z, d, a),
        );
    }

    /// `max |a - b| / max |b|` over the entries.
    fn rel<const R: usize, const C: usize>(a: &SMatrix<f64, R, C>, b: &SMatrix<f64, R, C>) -> f64 {
        (a - b).amax() / b.amax().max(f64::MIN_POSITIVE)
    }

    /// The seven-point update of a position measurement ([`Ukf::position_update`]) and the
    /// closed-form update of a linear one equal the thirteen-point unscented update to
    /// rounding (of the prior's covariance and spread): the camera (both angles, and at a
    /// pole where its azimuth is dropped), the GNSS position and velocity, in every frame,
    /// from random priors.
    #[test]
    fn reduced_sensor_updates_equal_the_thirteen_point_update() {
        use crate::sensors::{
            CameraSensor, CartesianSensor, Modelled, SensorNoise, VelocitySensor,
        };
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let f = Ukf::new(State::zeros(), Mat6::identity(), UkfParams::default());
        fn full<const D: usize, S: Sensor<D>>(
            f: &Ukf,
            x: &State,
            p: &Mat6,
            s: &S,
            z: &SVector<f64, D>,
        ) -> (State, Mat6, f64) {
            let used = s.used(x).unwrap();
            let m = Measurement {
                h: |x: &State| s.measure(x),
                mean: |wm: &[f64], zs: &[SVector<f64, D>]| s.mean(wm, zs),
                residual: |a: &SVector<f64, D>, b: &SVector<f64, D>| s.residual(a, b),
                r: s.noise().cov(),
                used,
            };
            let (x, p, _, nis) = f.unscented_update(x, p, &m, z).unwrap();
            (x, p, nis)
        }
        // rounding of the covariance is relative to the prior's (the 13-point form subtracts
        // `K Pzz K^T` from it), of the state to the prior's spread
        let close = |a: (&State, &Mat6), b: (&State, &Mat6), p: &Mat6| {
            let (dx, dp) = ((a.0 - b.0).amax(), (a.1 - b.1).amax());
            dx <= 1e-9 * p.amax().sqrt() && dp <= 1e-12 * p.amax()
        };
        let mut checked = 0;
        for frame in Frame::ALL {
            for k in 0..20 {
                let mut x = State::from_fn(|i, _| {
                    if i < 3 {
                        rng.random_range(-2000.0..2000.0)
                    } else {
                        rng.random_range(-1.0..1.0)
                    }
                });
                if k == 0 {
                    // on the sensor frame's pole: the camera's azimuth is dropped
                    let up = frame.vec_to_canonical(&Vec3::new(0.0, 0.0, 800.0));
                    x.fixed_rows_mut::<3>(0).copy_from(&up);
                }
                let a = Mat6::from_fn(|_, _| rng.random_range(-1.0..1.0));
                let scale = State::from_row_slice(&[30.0, 30.0, 30.0, 0.05, 0.05, 0.05]);
                let p = Mat6::from_diagonal(&scale)
                    * (a * a.transpose() + Mat6::identity())
                    * Mat6::from_diagonal(&scale);
                let cam = CameraSensor::gaussian(frame, 1e-3);
                let z = cam.measure(&x).unwrap() + SVector::<f64, 2>::new(2e-3, -1e-3);
                let (xr, pr, info) = f.sensor_update(&x, &p, &cam, &z).unwrap();
                let (xf, pf, nis) = full(&f, &x, &p, &cam, &z);
                assert!(close((&xr, &pr), (&xf, &pf), &p), "camera {frame:?}");
                assert!((info.nis - nis).abs() <= 1e-9 * nis.max(1.0));
                assert_eq!(info.dof, if k == 0 { 1 } else { 2 });
                let gnss = Modelled {
                    model: CartesianSensor { frame, sigma: 0.05 },
                    noise: SensorNoise::gaussian([0.05; 3]),
                };
                let z = gnss.measure(&x).unwrap() + Vec3::new(0.1, -0.03, 0.02);
                let (xr, pr, _) = f.sensor_update(&x, &p, &gnss, &z).unwrap();
                let (xf, pf, _) = full(&f, &x, &p, &gnss, &z);
                assert!(close((&xr, &pr), (&xf, &pf), &p), "GNSS {frame:?}");
                let vel = VelocitySensor::gaussian(frame, 5e-4);
                let z = vel.measure(&x).unwrap() + Vec3::new(1e-3, 0.0, -5e-4);
                let (xr, pr, _) = f.sensor_update(&x, &p, &vel, &z).unwrap();
                let (xf, pf, _) = full(&f, &x, &p, &vel, &z);
                assert!(close((&xr, &pr), (&xf, &pf), &p), "velocity {frame:?}");
                checked += 1;
            }
        }
        assert_eq!(checked, 20 * Frame::ALL.len());
    }

    /// The shared-factor update ([`SharedPrior`]) equals [`Ukf::measurement_update_factored`]
    /// on random states, covariances and measurements in every frame: small and large
    /// spreads (the radio model's series path and its fallback), outlier measurements,
    /// points on and near the poles (azimuth ignored) and at zero range (both fail).
    #[test]
    fn shared_prior_update_equals_the_generic_update() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let mut checked = 0;
        for params in [
            UkfParams::default(),
            UkfParams {
                alpha: 0.5,
                beta: 2.0,
                kappa: 0.0,
            },
        ] {
            for frame in Frame::ALL {
                let s = RadioSensor::new(frame, 0.5, 1e-3);
                let ukf = Ukf::new(State::zeros(), Mat6::identity(), params);
                for k in 0..3000 {
                    let spread = [1e-2, 1.0, 30.0, 400.0][k % 4];
                    let a = Mat6::from_fn(|_, _| rng.random_range(-1.0..1.0));
                    let p = (a * a.transpose() + Mat6::identity() * 0.05) * (spread * spread);
                    let Some(l) = p.cholesky().map(|c| c.unpack()) else {
                        continue;
                    };
                    let pos = match k % 11 {
                        // on the pole and within 1e-7 of it (sensor frame)
                        0 => Vec3::new(0.0, 0.0, 300.0),
                        1 => Vec3::new(1e-5, -1e-5, -100.0),
                        // zero range
                        2 if k % 3 == 0 => Vec3::zeros(),
                        // on the azimuth cut
                        3 => Vec3::new(500.0, 0.0, 100.0),
                        _ => Vec3::from_fn(|_, _| rng.random_range(-1000.0..1000.0)),
                    };
                    let (l, p) = if k % 11 == 1 {
                        // near the pole: the series path with the azimuth ignored
                        let l = l * 1e-9;
                        (l, l * l.transpose())
                    } else {
                        (l, p)
                    };
                    let mut x = State::from_fn(|_, _| rng.random_range(-1.0..1.0));
                    x.fixed_rows_mut::<3>(0)
                        .copy_from(&frame.vec_to_canonical(&pos));
                    let truth = x.fixed_rows::<3>(0)
                        + Vec3::from_fn(|_, _| rng.random_range(-2.0..2.0) * spread);
                    let mut z = s.h(&truth).unwrap_or_default()
                        + Vec3::new(
                            rng.random_range(-1.0..1.0),
                            rng.random_range(-1e-3..1e-3),
                            rng.random_range(-1e-3..1e-3),
                        );
                    if k % 7 == 0 {
                        // an outlier: any direction
                        z.y = rng.random_range(0.0..core::f64::consts::TAU);
                        z.z = rng.random_range(-1.5..1.5);
                    }
                    let r = s.noise_cov() * [1.0, 10.0][k % 2];
                    let want = ukf.measurement_update_factored(&x, &p, &l, &s, &r, &z);
                    let sp = ukf.shared_prior(&l).expect("equal outer weights");
                    let got = sp.update(&x, &s, &r, &z, &AngleTrig::of(&z));
                    let (Ok((m, pn, info)), Ok(g)) = (&want, &got) else {
                        assert_eq!(want.is_ok(), got.is_ok(), "{k}: {want:?} {got:?}");
                        continue;
                    };
                    let f = g.factor(&sp);
                    let dm = m - x;
                    let gm = g.mean(&x, &sp) - x;
                    // the step relative to itself or to the prior's spread, whichever is
                    // larger, plus the rounding of `m` itself (a few ulp of `x`)
                    let step_scale = dm.amax().max(1e-6 * p.diagonal().amax().sqrt());
                    // within 1e-6 of the pole (azimuth ignored) the generic update's
                    // elevations `asin(p_z / rho)` are conditioned as `1 / cos(el)` > 1e6:
                    // good to about 1e-9 rad, as large as the sigma points' elevation
                    // differences there (1e-9 m spreads), so its step and `P+` are no
                    // reference; innovation, NIS and the pole test still are
                    let near_pole = k % 11 == 1;
                    assert!(
                        near_pole
                            || (gm - dm).amax()
                                <= 1e-10 * step_scale + 4.0 * f64::EPSILON * x.amax(),
                        "{k}: step {gm} {dm}"
                    );
                    assert!(
                        near_pole || rel(&(f * f.transpose()), pn) <= 1e-10,
                        "{k}: P+ {pn}"
                    );
                    // the generic elevation `asin(p_z / rho)` is conditioned as
                    // `1 / cos(el)`: within 1e-7 of the pole it is good to 1e-9 only
                    let q = frame.vec_from_canonical(&x.fixed_rows::<3>(0).into_owned());
                    let el_tol = 8.0 * f64::EPSILON * q.norm() / q.xy().norm();
                    let (mut gi, mut wi) = (g.info.innovation, info.innovation);
                    assert!((gi.z - wi.z).abs() <= 1e-10 * wi.amax() + el_tol, "{k}: el");
                    (gi.z, wi.z) = (0.0, 0.0);
                    // (the range innovation `z - rho_m` cancels: plus a few ulp of `z`)
                    assert!(
                        (gi - wi).amax() <= 1e-10 * wi.amax() + 8.0 * f64::EPSILON * z.x.abs(),
                        "{k}: nu {} {} P {}",
                        g.info.innovation,
                        info.innovation,
                        p.diagonal()
                    );
                    // (the elevation's rounding enters through `Pzz^-1/2 nu`, `Pzz >= R`)
                    let nis_tol = 1e-10 * info.nis.max(1e-12)
                        + 2.0 * info.nis.sqrt() * el_tol / r.diagonal().min().sqrt();
                    assert!((g.info.nis - info.nis).abs() <= nis_tol, "{k}: nis");
                    assert_eq!(g.info.azimuth_used, info.azimuth_used);
                    checked += 1;
                }
            }
        }
        assert!(checked > 15_000, "{checked}");
    }

    /// With a prior small against the range the radio is linear over the sigma points:
    /// the UKF's robust update (on its sigma-point moments) is the robust EKF's, for both
    /// heavy-tailed densities, an inlier and an outlier; a Gaussian density leaves the
    /// UKF's own update.
    #[test]
    fn robust_update_is_the_robust_ekfs_for_a_linear_geometry() {
        use crate::estimators::Ekf;
        use crate::noise::NoiseModel;
        let frame = Frame::ALL[1];
        let x = State::from_row_slice(&[400.0, -900.0, 250.0, 0.1, -0.2, 0.05]);
        let p = Mat6::from_diagonal(&State::from_row_slice(&[
            1e-4, 2e-4, 1.5e-4, 1e-8, 1e-8, 1e-8,
        ]));
        for noise in [
            NoiseModel::Mixture {
                zeta: 0.2,
                scale: 10.0,
            },
            NoiseModel::StudentT { dof: 4.0 },
        ] {
            let f = noise.variance_factor().sqrt();
            let s = RadioSensor::new(frame, 0.01 * f, 1e-5 * f);
            let z0 = s.h(&x.fixed_rows::<3>(0).owned()).unwrap();
            for dz in [Vec3::new(0.01, 1e-5, -1e-5), Vec3::new(0.5, -3e-4, 2e-4)] {
                let z = z0 + dz;
                let mut ekf = Ekf::new(x, p).robust(noise);
                let mut ukf = Ukf::new(x, p, UkfParams::default()).robust(Some(noise));
                ekf.update(&s, &z).unwrap();
                ukf.update(&s, &z).unwrap();
                let dx = (ekf.state() - ukf.state()).amax();
                assert!(dx < 1e-5 * p.amax().sqrt(), "{noise:?} {dz:?}: {dx}");
                let dp = (ekf.covariance() - ukf.covariance()).amax();
                assert!(dp < 1e-4 * p.amax(), "{noise:?} {dz:?}: {dp}");
                let mut plain = Ukf::new(x, p, UkfParams::default());
                plain.update(&s, &z).unwrap();
                assert!((plain.state() - ukf.state()).amax() > 1e-3 * p.amax().sqrt());
            }
        }
        let mut a = Ukf::new(x, p, UkfParams::default()).robust(Some(NoiseModel::Gaussian));
        let mut b = Ukf::new(x, p, UkfParams::default());
        let s = RadioSensor::new(frame, 0.01, 1e-5);
        let z = s.h(&x.fixed_rows::<3>(0).owned()).unwrap() + Vec3::new(0.02, 1e-5, 0.0);
        a.update(&s, &z).unwrap();
        b.update(&s, &z).unwrap();
        assert_eq!((a.state(), a.covariance()), (b.state(), b.covariance()));
    }
}
