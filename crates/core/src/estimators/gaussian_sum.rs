//! The particle filters' particle prior (`pf_prior = particle`): [`GaussianSumPf`], a
//! range-parameterised bank's machinery ([`super::bank`]) with the resampling of
//! [`super::pf::gaussian_sum`] (the method and why it is there).

use super::pf::PfParams;
use crate::dynamics::DiscreteModel;
use crate::estimators::{Bank, Ekf, Estimator, FilterError, SensorUpdate, Ukf, UpdateInfo};
use crate::noise::NoiseModel;
use crate::numerics::state::{Persist, Reader, StateError, Writer};
use crate::sensors::{MeasurementModel, Sensor};
use crate::types::{Mat6, State, Vec3};
use nalgebra::SVector;

/// A Gaussian-sum particle filter ([`super::pf::gaussian_sum`]): EKF terms for the SIR, RPF and
/// GA-PF, UKF terms for the UPF and CGA-PF.
#[derive(Debug, Clone)]
pub enum GaussianSumPf {
    /// EKF terms.
    Ekf(Bank<Ekf>),
    /// UKF terms (the unscented proposal).
    Ukf(Bank<Ukf>),
}

macro_rules! each {
    ($self:expr, $b:ident => $e:expr) => {
        match $self {
            GaussianSumPf::Ekf($b) => $e,
            GaussianSumPf::Ukf($b) => $e,
        }
    };
}

impl GaussianSumPf {
    /// `params.particles` terms drawn from `(x0, p0)`; the kind's term filter, an EKF or
    /// the UKF of `params.ukf`, whose radio update is that of the density `noise` when
    /// given (the robust update, [`super::rekf`]) or of the Gaussian of its variance.
    pub fn new(x0: State, p0: Mat6, params: &PfParams, noise: Option<NoiseModel>) -> Self {
        if params.kind.unscented() {
            let ukf = Ukf::new(x0, p0, params.ukf).robust(noise);
            GaussianSumPf::Ukf(Bank::gaussian_sum(ukf, x0, p0, params))
        } else {
            let ekf = match noise {
                Some(noise) => Ekf::new(x0, p0).robust(noise),
                None => Ekf::new(x0, p0),
            };
            GaussianSumPf::Ekf(Bank::gaussian_sum(ekf, x0, p0, params))
        }
    }

    /// Effective sample size after the last update and the resampling count.
    pub fn stats(&self) -> (f64, u64) {
        each!(self, b => b.particle_stats().unwrap_or((f64::NAN, 0)))
    }

    /// The live terms: weight (summing to one), mean and covariance (canonical frame). A
    /// diagnostic: it allocates.
    pub fn terms(&self) -> Vec<(f64, State, Mat6)> {
        each!(self, b => b
            .weighted()
            .map(|(w, m)| (w, *m.state(), *m.covariance()))
            .collect())
    }

    /// Number of terms.
    pub fn len(&self) -> usize {
        each!(self, b => b.len())
    }

    /// Never empty (at least one term).
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Keep the filter as it is, for [`GaussianSumPf::rollback`].
    pub fn checkpoint(&mut self) {
        each!(self, b => b.checkpoint())
    }

    /// Back to the last [`GaussianSumPf::checkpoint`].
    pub fn rollback(&mut self) {
        each!(self, b => b.rollback())
    }

    /// As new from `(x, p)`: the generator reseeded and the terms drawn from it, so a
    /// reset filter reproduces a new one.
    pub fn reset(&mut self, x: State, p: Mat6) {
        each!(self, b => b.restart(x, p))
    }
}

impl Estimator for GaussianSumPf {
    fn predict(&mut self, model: &DiscreteModel, accel: &Vec3) -> Result<(), FilterError> {
        each!(self, b => b.predict(model, accel))
    }

    fn update<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
    ) -> Result<UpdateInfo, FilterError> {
        each!(self, b => b.update(sensor, z))
    }

    fn update_sensor<const D: usize, S: Sensor<D> + ?Sized>(
        &mut self,
        sensor: &S,
        z: &SVector<f64, D>,
    ) -> Result<SensorUpdate<D>, FilterError> {
        each!(self, b => b.update_sensor(sensor, z))
    }

    fn state(&self) -> &State {
        each!(self, b => b.state())
    }

    fn covariance(&self) -> &Mat6 {
        each!(self, b => b.covariance())
    }

    /// New terms drawn from `(x, p)`, the generator going on where it is.
    fn set_estimate(&mut self, x: State, p: Mat6) {
        each!(self, b => b.reset(x, p))
    }
}

/// Saved state: the bank's ([`Bank`]'s: the terms with their weights, the sum's `x`, `P`),
/// then the generator's words, the resampling count and the last `N_eff`.
impl Persist for GaussianSumPf {
    fn save_state(&self, w: &mut Writer<'_>) {
        each!(self, b => b.save_state(w))
    }

    fn load_state(&mut self, r: &mut Reader<'_>) -> Result<(), StateError> {
        each!(self, b => b.load_state(r))
    }
}
