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

use super::covariance::{
    joseph_block, position_innovation, position_update, time_update, time_update_into,
};
use super::{finite, Estimator, FilterError, SensorUpdate, UpdateInfo};
use crate::dynamics::DiscreteModel;
use crate::numerics::cholesky::chol_small;
use crate::numerics::state::{Persist, Reader, StateError, Writer};
use crate::numerics::symmetrize;
use crate::numerics::Owned;
use crate::sensors::{Geometry, Linearization, MeasurementModel, Sensor, Support};
use crate::types::{Mat3, Mat6, State, Vec3};
use nalgebra::{SMatrix, SVector};

/// The linearised (EKF) measurement update of `(x, P)` with any sensor, not committed:
/// the updated state and covariance (Joseph form, full `H`: the generic path), the
/// update's diagnostics and the innovation covariance `S`. Components the sensor marks
/// unused are dropped ([`Sensor::innovation`]). Inlined into its callers: its results
/// would otherwise be copied out through each call's return.
#[inline(always)]
pub(crate) fn linearised_update<const D: usize, S: Sensor<D> + ?Sized>(
    x: &State,
    p: &Mat6,
    sensor: &S,
    z: &SVector<f64, D>,
) -> Result<(State, Mat6, SensorUpdate<D>, SMatrix<f64, D, D>), FilterError> {
    let (lin, nu) = sensor.innovation(x, z)?;
    linearised_update_given(x, p, sensor, &lin, &nu)
}

/// [`linearised_update`] given the linearisation and innovation at `x`
/// ([`Sensor::innovation`]).
#[inline(always)]
pub(crate) fn linearised_update_given<const D: usize, S: Sensor<D> + ?Sized>(
    x: &State,
    p: &Mat6,
    sensor: &S,
    lin: &Linearization<D>,
    nu: &SVector<f64, D>,
) -> Result<(State, Mat6, SensorUpdate<D>, SMatrix<f64, D, D>), FilterError> {
    let nu = *nu;
    let r = sensor.noise().cov();
    let (xn, pn, s, nis) = match sensor.support() {
        Support::Position => block_update::<D, 0>(x, p, &lin.h, &nu, &r)?,
        Support::Velocity => block_update::<D, 3>(x, p, &lin.h, &nu, &r)?,
        Support::Full => full_update(x, p, &lin.h, &nu, &r)?,
    };
    finite(&xn, "updated state")?;
    finite(&pn, "updated covariance")?;
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

/// The updated state and covariance, `S` and the NIS, of [`linearised_update`] with a full
/// Jacobian `h`.
type Updated<const D: usize> = (State, Mat6, SMatrix<f64, D, D>, f64);

/// [`linearised_update`]'s algebra for any `h` (`D x 6`).
#[inline(always)]
fn full_update<const D: usize>(
    x: &State,
    p: &Mat6,
    h: &SMatrix<f64, D, 6>,
    nu: &SVector<f64, D>,
    r: &SMatrix<f64, D, D>,
) -> Result<Updated<D>, FilterError> {
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
    let nis = nu.dot(&chol.solve(nu));
    Ok((xn, pn, s, nis))
}

/// [`full_update`] for a Jacobian whose only nonzero columns are the three from `OFF` (the
/// position, `OFF = 0`, or the velocity, `OFF = 3`; [`Support`]): the same formulas with
/// the `D x 3` block, as the radio's update computes them (`P H^T` from the block's
/// columns of `P`, a closed-form factor of `S` on the stack, the gain row by row,
/// [`joseph_block`]'s column axpys), without the full `H`'s zero products.
#[inline(always)]
fn block_update<const D: usize, const OFF: usize>(
    x: &State,
    p: &Mat6,
    h: &SMatrix<f64, D, 6>,
    nu: &SVector<f64, D>,
    r: &SMatrix<f64, D, D>,
) -> Result<Updated<D>, FilterError> {
    let hb: SMatrix<f64, D, 3> = h.fixed_columns::<3>(OFF).owned();
    let ph: SMatrix<f64, 6, D> = p.fixed_columns::<3>(OFF) * hb.transpose();
    let s = hb * ph.fixed_rows::<3>(OFF) + r;
    let chol = chol_small(&s).ok_or(FilterError::NotPositiveDefinite("innovation covariance S"))?;
    // K = P H^T S^-1  <=>  K^T = S^-1 (H P): one solve per row of P H^T
    let mut k = [[0.0; 6]; D];
    for i in 0..6 {
        let ki = chol.solve(&core::array::from_fn(|c| ph[(i, c)]));
        for (kc, v) in k.iter_mut().zip(ki) {
            kc[i] = v;
        }
    }
    let km = SMatrix::<f64, 6, D>::from_data(nalgebra::ArrayStorage(k));
    let xn = x + km * nu;
    let pn = joseph_block::<D, OFF>(p, &k, &hb.data.0, &r.data.0);
    // nu^T S^-1 nu = |L^-1 nu|^2
    let nis = chol
        .forward(&core::array::from_fn(|c| nu[c]))
        .iter()
        .map(|v| v * v)
        .sum();
    Ok((xn, pn, s, nis))
}

/// Extended Kalman filter with a Joseph-form update.
#[derive(Debug, Clone, PartialEq)]
pub struct Ekf {
    x: State,
    p: Mat6,
    /// the robust EKF's noise density (filter code 11; [`super::rekf`]): its radio update
    /// is that density's, not the Gaussian of its variance. Configuration.
    robust: Option<crate::noise::NoiseModel>,
}

impl Ekf {
    /// A filter starting from estimate `x0` with covariance `p0` (canonical frame).
    pub fn new(x0: State, p0: Mat6) -> Self {
        Self {
            x: x0,
            p: p0,
            robust: None,
        }
    }

    /// The robust EKF (filter code 11): the radio's update uses the noise density `noise`
    /// ([`super::rekf`]; the sensor's `R` is its variance).
    pub fn robust(mut self, noise: crate::noise::NoiseModel) -> Self {
        self.robust = Some(noise);
        self
    }

    /// The noise density of a robust EKF's update (`None` for the EKF).
    pub fn robust_noise(&self) -> Option<&crate::noise::NoiseModel> {
        self.robust.as_ref()
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
    #[inline(always)]
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
        time_update_into(model, &x, &p, accel, (&mut self.x, &mut self.p))?;
        Ok(info)
    }

    /// [`Ekf::update_predict`] with any sensor: the update of [`Estimator::update_sensor`],
    /// then the time update, committed only when both succeed (the same bits as the two in
    /// turn; the navigator's step with one reading needs no snapshot).
    #[inline(always)]
    pub fn update_sensor_predict<const D: usize, S: Sensor<D> + ?Sized>(
        &mut self,
        sensor: &S,
        z: &SVector<f64, D>,
        model: &DiscreteModel,
        accel: &Vec3,
    ) -> Result<SensorUpdate<D>, FilterError> {
        let (x, p, info, _) = linearised_update(&self.x, &self.p, sensor, z)?;
        time_update_into(model, &x, &p, accel, (&mut self.x, &mut self.p))?;
        Ok(info)
    }

    /// [`Estimator::update`] given `g`, the sensor's linearisation at the filter's position
    /// (a bank's member: [`super::Member::update_at`]; the same bits as computing it here).
    pub(crate) fn update_given<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
        g: &Geometry,
    ) -> Result<UpdateInfo, FilterError> {
        let (x, p, info, _) = self.updated_given(sensor, z, g)?;
        self.x = x;
        self.p = p;
        Ok(info)
    }

    /// [`Estimator::update_sensor`] given the linearisation and innovation at the filter's
    /// state ([`Sensor::innovation`]; [`super::Member::update_sensor_at`]).
    pub(crate) fn update_sensor_given<const D: usize, S: Sensor<D> + ?Sized>(
        &mut self,
        sensor: &S,
        lin: &Linearization<D>,
        nu: &SVector<f64, D>,
    ) -> Result<SensorUpdate<D>, FilterError> {
        let (x, p, info, _) = linearised_update_given(&self.x, &self.p, sensor, lin, nu)?;
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
        let g = sensor.linearize(&self.x.fixed_rows::<3>(0).owned())?;
        self.updated_given(sensor, z, &g)
    }

    /// [`Ekf::updated`] given the linearisation `g` at the filter's position.
    #[inline(always)]
    fn updated_given<M: MeasurementModel>(
        &self,
        sensor: &M,
        z: &Vec3,
        g: &Geometry,
    ) -> Result<(State, Mat6, UpdateInfo, Mat3), FilterError> {
        let nu = sensor.linearised_residual(z, g);
        let r = sensor.noise_cov();
        // H = [H_r 0]: the sensors measure the position (`Geometry::h`)
        debug_assert!(g.h.fixed_columns::<3>(3).iter().all(|v| *v == 0.0));
        let h_r: Mat3 = g.h.fixed_columns::<3>(0).owned();
        let (ph, s, chol) = position_innovation(&self.p, &h_r, &r)?;
        let robust = self.robust.as_ref().and_then(|noise| {
            super::rekf::robust_update(&self.x, &self.p, &h_r, &nu, &r, noise, g.azimuth_usable)
        });
        let (x, p) = match robust {
            Some(updated) => updated?,
            None => position_update(&self.x, &self.p, &h_r, &nu, &r, &ph, &chol),
        };
        finite(&x, "updated state")?;
        finite(&p, "updated covariance")?;
        // nu^T S^-1 nu = |L^-1 nu|^2 (the robust EKF's too: against the variance's S)
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
        // `robust`: configuration (from the filter code and the noise parameters)
        let Self { x, p, robust: _ } = self;
        w.matrix(x);
        w.matrix(p);
    }

    fn load_state(&mut self, r: &mut Reader<'_>) -> Result<(), StateError> {
        let Self { x, p, robust: _ } = self;
        *x = r.finite_matrix("EKF state")?;
        *p = r.finite_matrix("EKF covariance")?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The block products of a position or velocity measurement ([`block_update`]) give
    /// the full-Jacobian update ([`full_update`]) to rounding.
    #[test]
    fn block_updates_equal_the_full_update() {
        let p = Mat6::from_fn(|i, j| {
            if i == j {
                10.0 + i as f64
            } else {
                0.3 * (i + j) as f64
            }
        });
        let x = State::from_row_slice(&[500.0, -300.0, 20.0, 0.1, -0.2, 0.05]);
        let h = SMatrix::<f64, 2, 3>::new(1e-3, -2e-3, 5e-4, 3e-4, 1e-3, -1e-3);
        let nu = SVector::<f64, 2>::new(1e-3, -2e-3);
        let r = SMatrix::<f64, 2, 2>::identity() * 1e-6;
        for (off, hf) in [
            (0, h.insert_fixed_columns::<3>(3, 0.0)),
            (3, h.insert_fixed_columns::<3>(0, 0.0)),
        ] {
            let (xa, pa, sa, na) = full_update(&x, &p, &hf, &nu, &r).unwrap();
            let (xb, pb, sb, nb) = if off == 0 {
                block_update::<2, 0>(&x, &p, &hf, &nu, &r).unwrap()
            } else {
                block_update::<2, 3>(&x, &p, &hf, &nu, &r).unwrap()
            };
            assert!((xa - xb).amax() <= 1e-12 * xa.amax());
            assert!((pa - pb).amax() <= 1e-12 * pa.amax());
            assert!((sa - sb).amax() <= 1e-12 * sa.amax());
            assert!((na - nb).abs() <= 1e-12 * na);
        }
    }

    /// `update_predict` is `update` then `predict` bit for bit, and a prediction that fails
    /// after the update leaves the filter as it was.
    #[test]
    fn update_predict_is_update_then_predict_and_transactional() {
        crate::estimators::check_update_predict(Ekf::new, |f, s, z, d, a| {
            f.update_predict(s, z, d, a)
        });
    }
}
