//! Estimators behind one trait.
//!
//! Every filter works on the canonical-frame state `(r, v)` (see [`crate::frames`]), takes
//! its dynamics as a [`DiscreteModel`] for the current step and a measurement either from a
//! [`MeasurementModel`] (the radio's range/azimuth/elevation or a Cartesian position, with
//! the vectorised specialisations: [`Estimator::update`]) or from any [`Sensor`] (one
//! generic path: [`Estimator::update_sensor`]). Frames, units of thrust and the choice of
//! step are the caller's
//! ([`crate::nav::Navigator`]). All types are fixed-size nalgebra matrices: a step performs
//! no heap allocation (checked by `tests/no_alloc.rs`). A step that fails leaves the
//! estimate unchanged.

use crate::dynamics::DiscreteModel;
use crate::sensors::{Geometry, GeometryError, Linearization, MeasurementModel, Sensor};
use crate::types::{Mat6, State, Vec3};
use nalgebra::SVector;

pub mod aqukf;
#[cfg(feature = "std")]
pub mod bank;
mod covariance;
pub mod ekf;
#[cfg(feature = "std")]
pub mod gaussian_sum;
pub mod imm;
pub mod pf;
pub mod rekf;
pub mod ukf;

pub use aqukf::{
    AdaptationLaw, AdaptiveQ, AdaptiveUkf, AqParams, Aqukf, MAX_GATE_WINDOW, MAX_WINDOW,
};
#[cfg(feature = "std")]
pub use bank::Bank;
pub use ekf::Ekf;
#[cfg(feature = "std")]
pub use gaussian_sum::GaussianSumPf;
pub use imm::{Imm, ImmParams, MAX_MODES};
pub use ukf::{Ukf, UkfParams};

/// What a range-parameterised bank ([`bank`]) needs of its members beyond [`Estimator`]: a small snapshot to undo a step,
/// and a reset to a new prior (the members' own reset: the AQUKF's adaptation and the IMM's
/// mode probabilities start again).
pub trait Member: Estimator + Clone + core::fmt::Debug {
    /// What [`Member::save`] keeps.
    type Saved: Clone + core::fmt::Debug;
    /// The member as it is now.
    fn save(&self) -> Self::Saved;
    /// Back to `s` (from [`Member::save`] of this member).
    fn restore(&mut self, s: &Self::Saved);
    /// Back to the start at `(x, p)`.
    fn reset(&mut self, x: State, p: Mat6);
    /// [`Estimator::update`] given `g`, the sensor's linearisation at the member's position,
    /// which the bank computed for the member's weight: a member that linearises there takes
    /// it instead of computing it again (the same bits); the others update as they do.
    fn update_at<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
        g: &Geometry,
    ) -> Result<UpdateInfo, FilterError> {
        let _ = g;
        self.update(sensor, z)
    }
    /// [`Estimator::update_sensor`] given the sensor's linearisation and innovation at the
    /// member's state ([`Sensor::innovation`]), as [`Member::update_at`].
    fn update_sensor_at<const D: usize, S: Sensor<D> + ?Sized>(
        &mut self,
        sensor: &S,
        z: &SVector<f64, D>,
        lin: &Linearization<D>,
        nu: &SVector<f64, D>,
    ) -> Result<SensorUpdate<D>, FilterError> {
        let _ = (lin, nu);
        self.update_sensor(sensor, z)
    }
}

/// [`Member`] for a filter whose estimate `(x, P)` is all a step changes: the snapshot is
/// the estimate, a reset sets it ([`Estimator::set_estimate`]).
macro_rules! estimate_member {
    ($($t:ty { $($own:tt)* }),*) => {$(
        impl Member for $t {
            type Saved = (State, Mat6);

            fn save(&self) -> (State, Mat6) {
                (*self.state(), *self.covariance())
            }

            fn restore(&mut self, s: &(State, Mat6)) {
                self.set_estimate(s.0, s.1);
            }

            fn reset(&mut self, x: State, p: Mat6) {
                self.set_estimate(x, p);
            }

            $($own)*
        }
    )*};
}
estimate_member!(
    Ekf {
        fn update_at<M: MeasurementModel>(
            &mut self,
            sensor: &M,
            z: &Vec3,
            g: &Geometry,
        ) -> Result<UpdateInfo, FilterError> {
            self.update_given(sensor, z, g)
        }

        fn update_sensor_at<const D: usize, S: Sensor<D> + ?Sized>(
            &mut self,
            sensor: &S,
            _z: &SVector<f64, D>,
            lin: &Linearization<D>,
            nu: &SVector<f64, D>,
        ) -> Result<SensorUpdate<D>, FilterError> {
            self.update_sensor_given(sensor, lin, nu)
        }
    },
    Ukf {}
);

/// The largest number of members of a range-parameterised bank ([`bank`]).
pub const MAX_BANK: usize = 9;

/// Why a filter step failed. The estimate is unchanged after an error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FilterError {
    /// The predicted position is at (numerically) zero range.
    Geometry(GeometryError),
    /// A matrix that must be positive definite (innovation or state covariance) is not.
    NotPositiveDefinite(&'static str),
    /// The result contains NaN or infinity.
    NonFinite(&'static str),
    /// This filter cannot take this measurement (the reason).
    Unsupported(&'static str),
}

impl FilterError {
    /// The reason in words (what `Display` writes; without `std`, without numbers).
    pub fn message(&self) -> crate::message::Message {
        use crate::message::Message;
        match self {
            FilterError::Geometry(g) => g.message(),
            FilterError::NotPositiveDefinite(what) => {
                Message::concat(&[what, " is not positive definite"])
            }
            FilterError::NonFinite(what) => Message::concat(&[what, " is not finite"]),
            FilterError::Unsupported(why) => Message::text(why),
        }
    }
}

impl core::fmt::Display for FilterError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(&self.message())
    }
}

impl From<GeometryError> for FilterError {
    fn from(g: GeometryError) -> Self {
        FilterError::Geometry(g)
    }
}

/// Diagnostics of the last measurement update.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct UpdateInfo {
    /// Innovation `z - z_hat` (azimuth wrapped).
    pub innovation: Vec3,
    /// Normalised innovation squared `nu^T S^-1 nu` (chi-square with 3 dof when consistent;
    /// 2 dof when the azimuth was ignored near a pole).
    pub nis: f64,
    /// False when the azimuth was ignored (elevation within 1e-6 rad of ±90°).
    pub azimuth_used: bool,
}

/// Diagnostics of a measurement update through the generic path
/// ([`Estimator::update_sensor`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensorUpdate<const D: usize> {
    /// Innovation `z - h(x-)` at the prior estimate (angles wrapped; zero for the
    /// components not used).
    pub innovation: SVector<f64, D>,
    /// Normalised innovation squared `nu^T S^-1 nu` (NaN for the filters that form no
    /// innovation covariance: point particles and the H-infinity filter).
    pub nis: f64,
    /// Components used (the chi-square degrees of freedom of `nis`).
    pub dof: usize,
}

/// A recursive estimator of the canonical relative state.
pub trait Estimator {
    /// Time update over one step: `x+ = Phi x + Gamma a`, covariance through the model,
    /// plus the step's process noise `model.q`. `accel` is the known thrust acceleration
    /// [m/s^2], canonical frame, held over the step.
    fn predict(&mut self, model: &DiscreteModel, accel: &Vec3) -> Result<(), FilterError>;
    /// Measurement update with `z` from `sensor` (radio: `(range, azimuth, elevation)`).
    fn update<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
    ) -> Result<UpdateInfo, FilterError>;
    /// Measurement update with `z` from any `sensor` of any dimension: the generic path
    /// every filter has (the Kalman filters' update with the sensor's linearisation or
    /// sigma points and its noise's Gaussian, the particle filters' weighting with its
    /// noise density; see each filter). [`Estimator::update`] is the radio's specialised
    /// path. The estimate is unchanged on error.
    fn update_sensor<const D: usize, S: Sensor<D> + ?Sized>(
        &mut self,
        sensor: &S,
        z: &SVector<f64, D>,
    ) -> Result<SensorUpdate<D>, FilterError>;
    /// Current state estimate (canonical frame).
    fn state(&self) -> &State;
    /// Current error covariance (canonical frame).
    fn covariance(&self) -> &Mat6;
    /// Overwrite the estimate (used by reset and re-initialisation).
    fn set_estimate(&mut self, x: State, p: Mat6);
}

/// Check that a matrix has only finite entries ([`crate::numerics::all_finite`]).
pub(crate) fn finite<const R: usize, const C: usize>(
    m: &nalgebra::SMatrix<f64, R, C>,
    what: &'static str,
) -> Result<(), FilterError> {
    if crate::numerics::all_finite(m.as_slice()) {
        Ok(())
    } else {
        Err(FilterError::NonFinite(what))
    }
}

/// The Kalman filters' `update_predict` test (EKF and UKF): on one step case (a state and
/// covariance, a radio sensor in frame 2, paper 000's orbit over 1 s with a small process
/// noise, a thrust, a noisy measurement of a nearby truth), `update_predict` is `update`
/// then `predict` bit for bit for three steps, and a prediction that fails after the update
/// leaves the filter as it was (the navigator relies on it instead of a snapshot).
#[cfg(test)]
#[allow(clippy::unwrap_used)]
pub(crate) fn check_update_predict<F: Estimator + Clone + PartialEq + core::fmt::Debug>(
    make: impl Fn(State, Mat6) -> F,
    update_predict: impl Fn(
        &mut F,
        &crate::sensors::RadioSensor,
        &Vec3,
        &crate::dynamics::DiscreteModel,
        &Vec3,
    ) -> Result<UpdateInfo, FilterError>,
) {
    use crate::dynamics::{CwModel, Discretization};
    use crate::types::Mat3;
    let sensor =
        crate::sensors::RadioSensor::new(crate::frames::Frame::AlongRadialAntinormal, 0.5, 1.7e-4);
    let model = CwModel::new(core::f64::consts::TAU / 7200.0);
    let d = model.discretize(1.0, &(Mat3::identity() * 1e-8), Discretization::Exact);
    let accel = Vec3::new(1e-3, -2e-3, 5e-4);
    let truth = Vec3::new(505.0, 395.0, -198.0);
    let z = sensor.h(&truth).unwrap() + Vec3::new(0.3, 1e-4, -2e-4);
    let x0 = State::from_row_slice(&[500.0, 400.0, -200.0, 0.1, -0.2, 0.05]);
    let p0 = Mat6::from_diagonal(&State::from_row_slice(&[
        2500.0, 2500.0, 2500.0, 1.0, 1.0, 1.0,
    ]));
    let bits = |f: &F| -> Vec<u64> {
        f.state()
            .iter()
            .chain(f.covariance().iter())
            .map(|v| v.to_bits())
            .collect()
    };
    let mut a = make(x0, p0);
    let mut b = a.clone();
    for _ in 0..3 {
        let ia = a.update(&sensor, &z).unwrap();
        a.predict(&d, &accel).unwrap();
        let ib = update_predict(&mut b, &sensor, &z, &d, &accel).unwrap();
        assert_eq!(ia, ib);
        assert_eq!(bits(&a), bits(&b));
    }
    let mut bad = d;
    bad.q[(0, 0)] = f64::INFINITY;
    let before = b.clone();
    assert!(update_predict(&mut b, &sensor, &z, &bad, &accel).is_err());
    assert_eq!(b, before);
    assert_eq!(bits(&b), bits(&before));
}
