//! The robust EKF's measurement update (filter code 11, `rekf`): the EKF's linearisation,
//! with the update of the sensor's noise density instead of the Gaussian of its variance.
//!
//! The radio's three components carry independent noise of the configured density, scaled
//! per component: the nominal variances are the Kalman filters' `R` (the density's
//! variance) over [`NoiseModel::variance_factor`].
//!
//! * **Contaminated Gaussian** (`(1 - zeta) N(0, s^2) + zeta N(0, (c s)^2)` per component):
//!   the exact Gaussian-sum update of the linearised model. Each of the `2^3` combinations
//!   of narrow and wide components is a Kalman update with its own `R_j`, weighted by its
//!   prior weight times its innovation likelihood `N(nu; 0, H P H^T + R_j)`; the posterior
//!   mixture is collapsed to its mean and covariance (`sum w_j (P_j + (x_j - x)(x_j - x)^T)`).
//!   Eight Kalman updates; with the azimuth unusable (on the polar axis) its component is
//!   not split.
//! * **Student-t** (`dof` degrees of freedom): the variational update of the Gaussian scale
//!   mixture (`v | lambda ~ N(0, s^2 / lambda)`, `lambda ~ Gamma(dof / 2, dof / 2)`; as
//!   Agamennoni, Nieto and Nebot 2012, Särkkä and Nummenmaa 2009): start from the
//!   predictive expectation of each `lambda_k` ([`NoiseModel::local_variance`]), then
//!   [`VB_ITERATIONS`] times a Kalman update with `R = diag(s_k^2 / E[lambda_k])` and
//!   `E[lambda_k] = (dof + 1) / (dof + (e_k^2 + (H P+ H^T)_kk) / s_k^2)`, `e = nu - H (x+ -
//!   x-)`: a fixed number of Kalman updates.
//! * Any other density (Gaussian, uniform, Laplace, AR(1)): the EKF's update with the
//!   variance.

use super::covariance::{moments_update, position_innovation, position_update};
use super::FilterError;
#[cfg(not(feature = "std"))]
use crate::math::Float;
use crate::noise::NoiseModel;
use crate::numerics::cholesky::chol3;
use crate::types::{Mat3, Mat36, Mat6, Mat63, State, Vec3};

/// Variational iterations of the Student-t update after its predictive start (each one
/// Kalman update).
pub const VB_ITERATIONS: usize = 4;

/// Whether `noise` has a robust update here (otherwise the EKF's is used).
pub fn has_robust_update(noise: &NoiseModel) -> bool {
    matches!(
        noise,
        NoiseModel::Mixture { zeta, .. } if *zeta > 0.0
    ) || matches!(noise, NoiseModel::StudentT { .. })
}

/// What the robust update asks of a filter's linearisation of the radio at the prior:
/// the EKF's Jacobian ([`Jacobian`]) or the UKF's sigma-point moments ([`Moments`]).
trait Linearised {
    /// One Kalman update with noise `r`: the updated state and covariance and the log-
    /// determinant and `nu^T S^-1 nu` of `S = Pzz + R`.
    fn kalman(&self, r: &Mat3) -> Result<(State, Mat6, f64, f64), FilterError>;
    /// `diag(H P H^T)` at the prior.
    fn predicted(&self) -> Vec3;
    /// For the variational step: `e = nu - H (x+ - x-)` and `diag(H P+ H^T)`.
    fn residual(&self, xn: &State, pn: &Mat6) -> (Vec3, Vec3);
}

/// The EKF's linearisation, `H = [h_r 0]`.
struct Jacobian<'a> {
    x: &'a State,
    p: &'a Mat6,
    h_r: &'a Mat3,
    nu: &'a Vec3,
}

impl Linearised for Jacobian<'_> {
    fn kalman(&self, r: &Mat3) -> Result<(State, Mat6, f64, f64), FilterError> {
        let (ph, _, chol) = position_innovation(self.p, self.h_r, r)?;
        let log_det = chol.log_det();
        let maha = chol.forward(self.nu).norm_squared();
        let (xn, pn) = position_update(self.x, self.p, self.h_r, self.nu, r, &ph, &chol);
        Ok((xn, pn, log_det, maha))
    }

    fn predicted(&self) -> Vec3 {
        (self.h_r * self.p.fixed_view::<3, 3>(0, 0) * self.h_r.transpose()).diagonal()
    }

    fn residual(&self, xn: &State, pn: &Mat6) -> (Vec3, Vec3) {
        let e = self.nu - self.h_r * (xn - self.x).fixed_rows::<3>(0);
        let hpnh = self.h_r * pn.fixed_view::<3, 3>(0, 0) * self.h_r.transpose();
        (e, hpnh.diagonal())
    }
}

/// The UKF's sigma-point moments: `Pxz` and `Pzz` without the noise. The variational step
/// takes the statistical linearisation `H = Pxz^T P^-1` (the regression of the sigma
/// points' measurements on their states), formed once per update when it is needed.
struct Moments<'a> {
    x: &'a State,
    p: &'a Mat6,
    pxz: &'a Mat63,
    pzz: &'a Mat3,
    nu: &'a Vec3,
    h: Option<Mat36>,
}

impl Linearised for Moments<'_> {
    fn kalman(&self, r: &Mat3) -> Result<(State, Mat6, f64, f64), FilterError> {
        let s = self.pzz + r;
        let chol = chol3(&s).ok_or(FilterError::NotPositiveDefinite(
            "innovation covariance Pzz",
        ))?;
        let (xn, pn) = moments_update(self.x, self.p, self.pxz, &s, &chol, self.nu);
        Ok((xn, pn, chol.log_det(), chol.forward(self.nu).norm_squared()))
    }

    fn predicted(&self) -> Vec3 {
        self.pzz.diagonal()
    }

    fn residual(&self, xn: &State, pn: &Mat6) -> (Vec3, Vec3) {
        // a prior without a factor has already failed the sigma points
        let Some(h) = &self.h else {
            return (*self.nu, self.pzz.diagonal());
        };
        let e = self.nu - h * (xn - self.x);
        (e, (h * pn * h.transpose()).diagonal())
    }
}

/// The robust update of `(x, P)` (module docs) for the linearisation `h_r`, innovation
/// `nu` and the Kalman filters' noise covariance `r_var` (diagonal: the density's
/// variance per component). `azimuth_usable = false`: the azimuth row of `h_r` and its
/// innovation are zero, and its component is not split. `None` when `noise` has no robust
/// update ([`has_robust_update`]).
pub fn robust_update(
    x: &State,
    p: &Mat6,
    h_r: &Mat3,
    nu: &Vec3,
    r_var: &Mat3,
    noise: &NoiseModel,
    azimuth_usable: bool,
) -> Option<Result<(State, Mat6), FilterError>> {
    let lin = Jacobian { x, p, h_r, nu };
    robust(&lin, nu, r_var, noise, azimuth_usable)
}

/// The same robust update for an unscented filter: its sigma points' cross covariance
/// `pxz` and measurement covariance `pzz` (without the noise) in place of the Jacobian.
#[allow(clippy::too_many_arguments)]
pub fn robust_update_unscented(
    x: &State,
    p: &Mat6,
    pxz: &Mat63,
    pzz: &Mat3,
    nu: &Vec3,
    r_var: &Mat3,
    noise: &NoiseModel,
    azimuth_usable: bool,
) -> Option<Result<(State, Mat6), FilterError>> {
    // H^T = P^-1 Pxz, for the Student-t's variational step alone
    let h = matches!(noise, NoiseModel::StudentT { .. })
        .then(|| p.cholesky().map(|c| c.solve(pxz).transpose()))
        .flatten();
    let lin = Moments {
        x,
        p,
        pxz,
        pzz,
        nu,
        h,
    };
    robust(&lin, nu, r_var, noise, azimuth_usable)
}

fn robust(
    lin: &impl Linearised,
    nu: &Vec3,
    r_var: &Mat3,
    noise: &NoiseModel,
    azimuth_usable: bool,
) -> Option<Result<(State, Mat6), FilterError>> {
    let vf = noise.variance_factor();
    let nominal = Vec3::new(r_var[(0, 0)], r_var[(1, 1)], r_var[(2, 2)]) / vf;
    match *noise {
        NoiseModel::Mixture { zeta, scale } if zeta > 0.0 => {
            Some(mixture_update(lin, &nominal, zeta, scale, azimuth_usable))
        }
        NoiseModel::StudentT { dof } => Some(student_update(lin, nu, &nominal, dof)),
        _ => None,
    }
}

fn mixture_update(
    lin: &impl Linearised,
    nominal: &Vec3,
    zeta: f64,
    scale: f64,
    azimuth_usable: bool,
) -> Result<(State, Mat6), FilterError> {
    const TERMS: usize = 8;
    let mut xs = [State::zeros(); TERMS];
    let mut ps = [Mat6::zeros(); TERMS];
    let mut lw = [f64::NEG_INFINITY; TERMS];
    let (ln_n, ln_w) = ((1.0 - zeta).ln(), zeta.ln());
    for j in 0..TERMS {
        let wide = [j & 1 != 0, j & 2 != 0, j & 4 != 0];
        if wide[1] && !azimuth_usable {
            continue;
        }
        let mut r = Mat3::zeros();
        let mut prior = 0.0;
        for k in 0..3 {
            r[(k, k)] = nominal[k] * if wide[k] { scale * scale } else { 1.0 };
            if k != 1 || azimuth_usable {
                prior += if wide[k] { ln_w } else { ln_n };
            }
        }
        let (xj, pj, log_det, maha) = lin.kalman(&r)?;
        xs[j] = xj;
        ps[j] = pj;
        lw[j] = prior - 0.5 * (maha + log_det);
    }
    let top = lw.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if !top.is_finite() {
        return Err(FilterError::NonFinite("mixture weights"));
    }
    let w = lw.map(|l| (l - top).exp());
    let total: f64 = w.iter().sum();
    let mean = xs
        .iter()
        .zip(&w)
        .fold(State::zeros(), |m, (xj, wj)| m + xj * (wj / total));
    let mut cov = Mat6::zeros();
    for j in 0..TERMS {
        if w[j] > 0.0 {
            let d = xs[j] - mean;
            cov += (ps[j] + d * d.transpose()) * (w[j] / total);
        }
    }
    Ok((mean, (cov + cov.transpose()) * 0.5))
}

fn student_update(
    lin: &impl Linearised,
    nu: &Vec3,
    nominal: &Vec3,
    dof: f64,
) -> Result<(State, Mat6), FilterError> {
    // the predictive E-step: E[lambda | nu] under N(nu; 0, s^2 / lambda + (H P H^T)_kk)
    let hph = lin.predicted();
    let mut var = Vec3::from_fn(|k, _| {
        NoiseModel::StudentT { dof }.local_variance(nu[k], hph[k], nominal[k].sqrt())
    });
    let mut out = None;
    for it in 0..=VB_ITERATIONS {
        let (xn, pn, _, _) = lin.kalman(&Mat3::from_diagonal(&var))?;
        if it < VB_ITERATIONS {
            let (e, hpnh) = lin.residual(&xn, &pn);
            var = Vec3::from_fn(|k, _| {
                let e_lambda = (dof + 1.0) / (dof + (e[k] * e[k] + hpnh[k]) / nominal[k]);
                nominal[k] / e_lambda
            });
        }
        out = Some((xn, pn));
    }
    out.ok_or(FilterError::NonFinite("variational update"))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A one-dimensional check of the Gaussian-sum update against its closed form: a scalar
    /// state measured directly (the other two components far less informative), the
    /// collapsed mean and variance of `(1 - zeta) N(m_n, v_n) + zeta N(m_w, v_w)` with the
    /// weights of the two predictive Gaussians, written out by hand.
    #[test]
    fn mixture_update_is_the_collapsed_gaussian_sum() {
        let (zeta, scale) = (0.2, 10.0);
        let p = Mat6::identity() * 4.0;
        let x = State::zeros();
        let h_r = Mat3::identity();
        // components 1 and 2 nearly uninformative (huge nominal variance)
        let nominal = Vec3::new(1.0, 1e12, 1e12);
        let vf = 1.0 - zeta + zeta * scale * scale;
        let r_var = Mat3::from_diagonal(&(nominal * vf));
        for z0 in [0.5, 3.0, 8.0, 30.0] {
            let nu = Vec3::new(z0, 0.0, 0.0);
            let (xm, pm) = robust_update(
                &x,
                &p,
                &h_r,
                &nu,
                &r_var,
                &NoiseModel::Mixture { zeta, scale },
                true,
            )
            .unwrap()
            .unwrap();
            let post = |r: f64| {
                let k = 4.0 / (4.0 + r);
                (k * z0, (1.0 - k) * 4.0)
            };
            let like = |r: f64| (-0.5 * z0 * z0 / (4.0 + r)).exp() / (4.0 + r).sqrt();
            let (wn, ww) = ((1.0 - zeta) * like(1.0), zeta * like(scale * scale));
            let (wn, ww) = (wn / (wn + ww), ww / (wn + ww));
            let ((mn, vn), (mw, vw)) = (post(1.0), post(scale * scale));
            let m = wn * mn + ww * mw;
            let v = wn * (vn + (mn - m).powi(2)) + ww * (vw + (mw - m).powi(2));
            assert!(
                (xm[0] - m).abs() < 1e-9 * m.abs().max(1.0),
                "{z0}: {} {m}",
                xm[0]
            );
            assert!(
                (pm[(0, 0)] - v).abs() < 1e-9 * v,
                "{z0}: {} {v}",
                pm[(0, 0)]
            );
        }
    }

    /// The Student-t update down-weights an outlier and keeps an inlier near the narrow
    /// update; the Gaussian density has no robust update.
    #[test]
    fn student_update_downweights_outliers() {
        let p = Mat6::identity() * 4.0;
        let x = State::zeros();
        let h_r = Mat3::identity();
        let dof = 4.0;
        let r_var = Mat3::identity() * (dof / (dof - 2.0));
        let noise = NoiseModel::StudentT { dof };
        let at = |z0: f64| {
            robust_update(&x, &p, &h_r, &Vec3::new(z0, 0.0, 0.0), &r_var, &noise, true)
                .unwrap()
                .unwrap()
                .0[0]
        };
        // the variance's Kalman gain: 4 / (4 + 2)
        let ekf = |z0: f64| z0 * 4.0 / 6.0;
        assert!(
            at(0.5) > ekf(0.5),
            "an inlier gets more than the variance's gain"
        );
        assert!(
            at(40.0) < 0.3 * ekf(40.0),
            "an outlier is down-weighted: {}",
            at(40.0)
        );
        assert!(robust_update(
            &x,
            &p,
            &h_r,
            &Vec3::zeros(),
            &r_var,
            &NoiseModel::Gaussian,
            true
        )
        .is_none());
    }

    /// For a linear measurement the sigma points' moments are `Pxz = P H^T`, `Pzz = H P
    /// H^T`, and the statistical linearisation is `H` itself: the unscented form of both
    /// robust updates is the Jacobian form (to rounding: Joseph's form against `P - K S
    /// K^T`), the azimuth dropped or not.
    #[test]
    fn unscented_form_is_the_jacobian_form_for_a_linear_measurement() {
        let a = Mat6::from_fn(|i, j| {
            ((i * 7 + j * 3) % 5) as f64 * 0.3 + if i == j { 2.0 } else { 0.0 }
        });
        let p = a * a.transpose();
        let x = State::from_fn(|i, _| i as f64 - 2.5);
        let h_r = Mat3::new(1.0, 0.2, -0.1, 0.3, 0.9, 0.05, -0.2, 0.1, 1.1);
        let r_var = Mat3::from_diagonal(&Vec3::new(0.5, 0.2, 0.8));
        for usable in [true, false] {
            let mut h_r = h_r;
            if !usable {
                h_r.row_mut(1).fill(0.0);
            }
            let h = {
                let mut h = Mat36::zeros();
                h.fixed_view_mut::<3, 3>(0, 0).copy_from(&h_r);
                h
            };
            let (pxz, pzz) = (p * h.transpose(), h * p * h.transpose());
            for nu in [Vec3::new(0.3, -0.2, 0.1), Vec3::new(12.0, 0.0, -9.0)] {
                let nu = if usable {
                    nu
                } else {
                    Vec3::new(nu.x, 0.0, nu.z)
                };
                for noise in [
                    NoiseModel::Mixture {
                        zeta: 0.1,
                        scale: 8.0,
                    },
                    NoiseModel::StudentT { dof: 3.0 },
                ] {
                    let (xj, pj) = robust_update(&x, &p, &h_r, &nu, &r_var, &noise, usable)
                        .unwrap()
                        .unwrap();
                    let (xu, pu) =
                        robust_update_unscented(&x, &p, &pxz, &pzz, &nu, &r_var, &noise, usable)
                            .unwrap()
                            .unwrap();
                    assert!((xj - xu).norm() < 1e-10 * (1.0 + xj.norm()), "{noise:?}");
                    assert!((pj - pu).norm() < 1e-10 * pj.norm(), "{noise:?}");
                }
            }
        }
    }
}
