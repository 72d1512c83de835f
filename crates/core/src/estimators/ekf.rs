//! Extended Kalman filter (the Kalman baseline of papers 000 and 002).
//!
//! Time update (linear CW model, exact): `x- = Phi x + Gamma a`, `P- = Phi P Phi^T + Q`.
//! Measurement update with the sensor's analytic Jacobian `H` (for the radio,
//! [`crate::sensors::RadioSensor::geometry`]):
//!
//! ```text
//! nu = z - h(x-)              (azimuth wrapped to (-pi, pi])
//! S  = H P- H^T + R
//! K  = P- H^T S^-1            (Cholesky solve, no explicit inverse)
//! x+ = x- + K nu
//! P+ = (I - K H) P- (I - K H)^T + K R K^T      (Joseph form: symmetric PSD by construction)
//! ```
//!
//! Both covariance products use the CW structure, which skips the products with zero
//! blocks: `Phi` is block diagonal in
//! the in-plane and out-of-plane components and `H = [H_r 0]` has zero velocity columns
//! (`propagate_covariance`, `joseph_update` in the module `estimators::covariance`).

use super::covariance::{joseph_update, propagate_covariance, time_update};
use super::{finite, Estimator, FilterError, SensorUpdate, UpdateInfo};
use crate::dynamics::DiscreteModel;
use crate::numerics::cholesky::chol3;
use crate::numerics::state::{Persist, Reader, StateError, Writer};
use crate::numerics::symmetrize;
use crate::sensors::{MeasurementModel, Sensor};
use crate::types::{Mat3, Mat6, Mat63, State, Vec3};
use nalgebra::{SMatrix, SVector};

/// The linearised (EKF) measurement update of `(x, P)` with any sensor, not committed:
/// the updated state and covariance (Joseph form, full `H`: the generic path), the
/// update's diagnostics and the innovation covariance `S`. Components the sensor marks
/// unused are dropped ([`Sensor::innovation`]).
pub(crate) fn linearised_update<const D: usize, S: Sensor<D> + ?Sized>(
    x: &State,
    p: &Mat6,
    sensor: &S,
    z: &SVector<f64, D>,
) -> Result<(State, Mat6, SensorUpdate<D>, SMatrix<f64, D, D>), FilterError> {
    let (lin, nu) = sensor.innovation(x, z)?;
    let h = lin.h;
    let r = sensor.noise().cov();
    let ph = p * h.transpose();
    let s = h * ph + r;
    let chol = s
        .cholesky()
        .ok_or(FilterError::NotPositiveDefinite("innovation covariance S"))?;
    // K^T = S^-1 (H P)
    let k = chol.solve(&ph.transpose()).transpose();
    let xn = x + k * nu;
    // Joseph's form (I - K H) P (I - K H)^T + K R K^T, factored as the radio's update
    // (`joseph_update`) is: A = P - K (H P), then A - (A H^T - K R) K^T; products of a D-wide
    // factor only, not of two 6 x 6 matrices
    let a = p - k * ph.transpose();
    let pn = symmetrize(&(a - (a * h.transpose() - k * r) * k.transpose()));
    finite(&xn, "updated state")?;
    finite(&pn, "updated covariance")?;
    let nis = nu.dot(&chol.solve(&nu));
    let dof = lin.used.iter().filter(|u| **u).count();
    Ok((
        xn,
        pn,
        SensorUpdate {
            innovation: nu,
            nis,
            dof,
        },
        s,
    ))
}

/// Extended Kalman filter with a Joseph-form update.
#[derive(Debug, Clone, PartialEq)]
pub struct Ekf {
    x: State,
    p: Mat6,
}

impl Ekf {
    /// A filter starting from estimate `x0` with covariance `p0` (canonical frame).
    pub fn new(x0: State, p0: Mat6) -> Self {
        Self { x: x0, p: p0 }
    }

    /// The measurement update of [`Estimator::update`], returning also the innovation
    /// covariance `S = H P- H^T + R` it used (the interacting multiple-model filter weighs
    /// its modes with the Gaussian likelihood `N(nu; 0, S)`). The filter is unchanged on
    /// error.
    pub fn update_with_s<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
    ) -> Result<(UpdateInfo, Mat3), FilterError> {
        let (x, p, info, s) = self.updated(sensor, z)?;
        self.x = x;
        self.p = p;
        Ok((info, s))
    }

    /// [`Estimator::update_sensor`], returning also the innovation covariance `S` (the
    /// interacting multiple-model filter's mode likelihood).
    pub fn update_sensor_with_s<const D: usize, S: Sensor<D> + ?Sized>(
        &mut self,
        sensor: &S,
        z: &SVector<f64, D>,
    ) -> Result<(SensorUpdate<D>, SMatrix<f64, D, D>), FilterError> {
        let (x, p, info, s) = linearised_update(&self.x, &self.p, sensor, z)?;
        self.x = x;
        self.p = p;
        Ok((info, s))
    }

    /// One step, transactional: the measurement update with `z`, then the time update
    /// with `model` and `accel`, committed only when both succeed (the same arithmetic as
    /// [`Estimator::update`] then [`Estimator::predict`], so the same bits; the navigator
    /// needs no snapshot to undo the update when the prediction fails).
    pub fn update_predict<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
        model: &DiscreteModel,
        accel: &Vec3,
    ) -> Result<UpdateInfo, FilterError> {
        let (x, p, info, _) = self.updated(sensor, z)?;
        // the time update of `Estimator::predict`, from the uncommitted update
        // written out rather than through `time_update`: its in-place form costs an extra
        // copy of the state and covariance here
        let x = model.apply(&x, accel);
        let p = propagate_covariance(&model.phi, &p, &model.q);
        finite(&x, "predicted state")?;
        finite(&p, "predicted covariance")?;
        self.x = x;
        self.p = p;
        Ok(info)
    }

    /// The measurement update, checked, not committed: the updated state and covariance,
    /// the update's diagnostics and `S`.
    #[inline(always)]
    fn updated<M: MeasurementModel>(
        &self,
        sensor: &M,
        z: &Vec3,
    ) -> Result<(State, Mat6, UpdateInfo, Mat3), FilterError> {
        let g = sensor.linearize(&self.x.fixed_rows::<3>(0).into_owned())?;
        let mut nu = sensor.diff(z, &g.z);
        if !g.azimuth_usable {
            nu.y = 0.0; // H row is zero too: the gain column vanishes (see sensors docs)
        }
        let r = sensor.noise_cov();
        // H = [H_r 0]: the sensors measure the position (`Geometry::h`)
        debug_assert!(g.h.fixed_columns::<3>(3).iter().all(|v| *v == 0.0));
        let h_r: Mat3 = g.h.fixed_columns::<3>(0).into_owned();
        let ph = self.p.fixed_columns::<3>(0) * h_r.transpose();
        let s = h_r * ph.fixed_rows::<3>(0) + r;
        // closed-form Cholesky of S (lower triangle), on the stack
        let chol = chol3(&s).ok_or(FilterError::NotPositiveDefinite("innovation covariance S"))?;
        // K = P H^T S^-1  <=>  K^T = S^-1 (H P)   (S, P symmetric): one solve per row of P H^T
        let mut k = Mat63::zeros();
        for i in 0..6 {
            let row = Vec3::new(ph[(i, 0)], ph[(i, 1)], ph[(i, 2)]);
            let ki = chol.solve(&row);
            k[(i, 0)] = ki.x;
            k[(i, 1)] = ki.y;
            k[(i, 2)] = ki.z;
        }
        let x = self.x + k * nu;
        let p = joseph_update(&self.p, &k, &h_r, &r);
        finite(&x, "updated state")?;
        finite(&p, "updated covariance")?;
        // nu^T S^-1 nu = |L^-1 nu|^2
        let nis = chol.forward(&nu).norm_squared();
        Ok((
            x,
            p,
            UpdateInfo {
                innovation: nu,
                nis,
                azimuth_used: g.azimuth_usable,
            },
            s,
        ))
    }
}

impl Estimator for Ekf {
    fn predict(&mut self, model: &DiscreteModel, accel: &Vec3) -> Result<(), FilterError> {
        time_update(model, &mut self.x, &mut self.p, accel)?;
        Ok(())
    }

    fn update<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
    ) -> Result<UpdateInfo, FilterError> {
        self.update_with_s(sensor, z).map(|(info, _)| info)
    }

    fn update_sensor<const D: usize, S: Sensor<D> + ?Sized>(
        &mut self,
        sensor: &S,
        z: &SVector<f64, D>,
    ) -> Result<SensorUpdate<D>, FilterError> {
        self.update_sensor_with_s(sensor, z).map(|(info, _)| info)
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

/// Saved state: `x` (6), `P` (36, column by column); see `docs/state-format.md`.
impl Persist for Ekf {
    fn save_state(&self, w: &mut Writer<'_>) {
        let Self { x, p } = self;
        w.matrix(x);
        w.matrix(p);
    }

    fn load_state(&mut self, r: &mut Reader<'_>) -> Result<(), StateError> {
        let Self { x, p } = self;
        *x = r.finite_matrix("EKF state")?;
        *p = r.finite_matrix("EKF covariance")?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `update_predict` is `update` then `predict` bit for bit, and a prediction that fails
    /// after the update leaves the filter as it was.
    #[test]
    fn update_predict_is_update_then_predict_and_transactional() {
        crate::estimators::check_update_predict(Ekf::new, |f, s, z, d, a| {
            f.update_predict(s, z, d, a)
        });
    }
}
