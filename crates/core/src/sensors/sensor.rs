//! The generic measurement: any number `D` of components, any function of the full
//! canonical state (position and velocity), with its own noise density. Every filter takes
//! it through one path, [`crate::estimators::Estimator::update_sensor`]; the radio keeps
//! its vectorised specialisations behind [`MeasurementModel`], and [`Modelled`] makes any
//! such model a [`Sensor`] too (so the two paths can be compared on the same measurement).

use super::{GeometryError, MeasurementModel};
use crate::noise::NoiseModel;
use crate::types::{State, Vec3};
use nalgebra::{SMatrix, SVector};

/// A sensor's measurement noise: a density ([`NoiseModel`]) with a scale per component,
/// independent across components. The Kalman filters use the Gaussian of its variance,
/// the particle filters weigh with the density itself.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensorNoise<const D: usize> {
    /// The density of each component (scaled by `scales`).
    pub model: NoiseModel,
    /// Scale (1 sigma for the Gaussian) per component, SI units.
    pub scales: [f64; D],
}

impl<const D: usize> SensorNoise<D> {
    /// Gaussian noise with standard deviations `sigmas`.
    pub fn gaussian(sigmas: [f64; D]) -> Self {
        Self {
            model: NoiseModel::Gaussian,
            scales: sigmas,
        }
    }

    /// The covariance the Kalman filters assume: `diag(scale_k^2)` times the density's
    /// variance factor.
    pub fn cov(&self) -> SMatrix<f64, D, D> {
        let f = self.model.variance_factor();
        SMatrix::from_fn(|i, j| {
            if i == j {
                self.scales[i] * self.scales[i] * f
            } else {
                0.0
            }
        })
    }

    /// `ln p(d)` of a residual `d` up to a constant that does not depend on `d` (the
    /// Gaussian: `-0.5 sum d_k^2 / s_k^2`; other densities their log-density per component).
    pub fn log_density(&self, d: &SVector<f64, D>) -> f64 {
        if matches!(self.model, NoiseModel::Gaussian) {
            (0..D).fold(0.0, |acc, k| {
                let u = d[k] / self.scales[k];
                acc - 0.5 * u * u
            })
        } else {
            (0..D).fold(0.0, |acc, k| {
                acc + self.model.log_density(d[k], self.scales[k])
            })
        }
    }

    /// Check the scales (finite, > 0) and the density's parameters.
    pub fn validate(&self) -> Result<(), crate::message::Message> {
        if let Some(s) = self.scales.iter().find(|s| !(**s > 0.0 && s.is_finite())) {
            return Err(crate::msg!(
                "measurement noise scales must be finite and > 0 (got {s})"
            ));
        }
        self.model.validate()
    }
}

/// The part of the canonical state a measurement depends on. A Kalman update multiplies
/// only the Jacobian's columns of that part (the others are zero), and the unscented
/// update of a position measurement measures only the sigma points whose positions differ
/// from the centre's.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Support {
    /// Position and velocity (no structure assumed).
    Full,
    /// The position alone (`h(x)` depends on `x[0..3]`).
    Position,
    /// The velocity alone (`h(x)` depends on `x[3..6]`).
    Velocity,
}

/// A measurement linearised at a state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Linearization<const D: usize> {
    /// Predicted measurement `h(x)`.
    pub z: SVector<f64, D>,
    /// `dh/dx` (D x 6) with respect to the canonical state.
    pub h: SMatrix<f64, D, 6>,
    /// Components that carry information at `x` (the radio's azimuth at the poles does
    /// not): a filter drops the others (zero row of `h`, zero residual).
    pub used: [bool; D],
}

/// What every filter needs of a sensor: the measurement function of the canonical state,
/// its linearisation, residuals and means that respect angles, and the noise.
/// Measurements are in the sensor's own frame and SI units (the sensor holds its frame).
pub trait Sensor<const D: usize>: Sync {
    /// Noise-free measurement `h(x)` of the canonical state `x` (`None` where undefined).
    fn measure(&self, x: &State) -> Option<SVector<f64, D>>;
    /// `h(x)` and its Jacobian at `x`.
    fn linearize(&self, x: &State) -> Result<Linearization<D>, GeometryError>;
    /// `z - z_hat`, angle components wrapped (default: the plain difference).
    fn residual(&self, z: &SVector<f64, D>, z_hat: &SVector<f64, D>) -> SVector<f64, D> {
        z - z_hat
    }
    /// The weighted mean of measurements `zs` (weights `w`, summing to one; circular for
    /// angle components). Default: the arithmetic mean.
    fn mean(&self, w: &[f64], zs: &[SVector<f64, D>]) -> SVector<f64, D> {
        w.iter()
            .zip(zs)
            .fold(SVector::zeros(), |acc, (wi, zi)| acc + zi * *wi)
    }
    /// The measurement noise.
    fn noise(&self) -> SensorNoise<D>;
    /// The part of the state `h` depends on (default: [`Support::Full`]). A sensor that
    /// declares [`Support::Position`] or [`Support::Velocity`] must have zero Jacobian
    /// columns outside it.
    fn support(&self) -> Support {
        Support::Full
    }
    /// Whether `h` is linear, `h(x) = H x` with a constant `H` (default: false). The
    /// unscented update of a linear measurement is the Kalman update, which the UKF then
    /// computes in closed form.
    fn linear(&self) -> bool {
        false
    }
    /// The components that carry information at `x` ([`Linearization::used`]; default:
    /// through [`Sensor::linearize`]), for the updates that need no Jacobian.
    fn used(&self, x: &State) -> Result<[bool; D], GeometryError> {
        self.linearize(x).map(|l| l.used)
    }
    /// The linearisation at `x` and the innovation `z - h(x)`, with the components not
    /// used dropped (zero row of `H`, zero residual: their gain column vanishes), as every
    /// linearised update takes them.
    fn innovation(
        &self,
        x: &State,
        z: &SVector<f64, D>,
    ) -> Result<(Linearization<D>, SVector<f64, D>), GeometryError> {
        let mut lin = self.linearize(x)?;
        let mut nu = self.residual(z, &lin.z);
        for (k, used) in lin.used.iter().enumerate() {
            if !used {
                nu[k] = 0.0;
                lin.h.row_mut(k).fill(0.0);
            }
        }
        Ok((lin, nu))
    }
    /// `ln p(z | x)` up to a constant, as the particle filters weigh: the noise density of
    /// the residual, `-inf` where the measurement is undefined.
    fn log_likelihood(&self, z: &SVector<f64, D>, x: &State) -> f64 {
        match self.measure(x) {
            Some(zh) => self.noise().log_density(&self.residual(z, &zh)),
            None => f64::NEG_INFINITY,
        }
    }
    /// The canonical position whose noise-free measurement is `z`, for sensors that fix the
    /// position (the radio, a Cartesian position); `None` for the others (angles only, a
    /// velocity). The H-infinity filter takes such fixes, and a particle filter draws its
    /// first particles from them.
    fn position_fix(&self, z: &SVector<f64, D>) -> Option<Vec3> {
        let _ = z;
        None
    }
    /// The canonical velocity whose noise-free measurement is `z`, for sensors of the
    /// velocity alone; `None` for the others. A particle filter started from the first
    /// measurement draws its velocities from such a reading in its first step.
    fn velocity_fix(&self, z: &SVector<f64, D>) -> Option<Vec3> {
        let _ = z;
        None
    }
    /// Whether `z` is a measurement this sensor can produce (finite, in its domain); the
    /// message names the first bad component. Default: finite.
    fn check(&self, z: &SVector<f64, D>) -> Result<(), crate::message::Message> {
        if z.iter().all(|v| v.is_finite()) {
            Ok(())
        } else {
            Err(crate::msg!(
                "measurement must be finite (got {:?})",
                z.as_slice()
            ))
        }
    }
}

/// A position-only [`MeasurementModel`] of three components (the radio, the Cartesian
/// position) with its noise, as a [`Sensor`]: the generic path's view of the specialised
/// models.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Modelled<M> {
    /// The measurement model.
    pub model: M,
    /// Its noise.
    pub noise: SensorNoise<3>,
}

fn position(x: &State) -> Vec3 {
    Vec3::new(x[0], x[1], x[2])
}

impl<M: MeasurementModel> Sensor<3> for Modelled<M> {
    fn measure(&self, x: &State) -> Option<Vec3> {
        self.model.predict(&position(x))
    }
    fn linearize(&self, x: &State) -> Result<Linearization<3>, GeometryError> {
        let g = self.model.linearize(&position(x))?;
        let mut h = g.h;
        if !g.azimuth_usable {
            h.row_mut(1).fill(0.0);
        }
        Ok(Linearization {
            z: g.z,
            h,
            used: [true, g.azimuth_usable, true],
        })
    }
    fn residual(&self, z: &Vec3, z_hat: &Vec3) -> Vec3 {
        self.model.diff(z, z_hat)
    }
    fn mean(&self, w: &[f64], zs: &[Vec3]) -> Vec3 {
        self.model.weighted_mean(w, zs)
    }
    fn noise(&self) -> SensorNoise<3> {
        self.noise
    }
    fn support(&self) -> Support {
        Support::Position
    }
    fn linear(&self) -> bool {
        self.model.linear()
    }
    fn used(&self, x: &State) -> Result<[bool; 3], GeometryError> {
        let usable = self.model.azimuth_usable(&position(x))?;
        Ok([true, usable, true])
    }
    fn position_fix(&self, z: &Vec3) -> Option<Vec3> {
        self.model.invert(z)
    }
}
