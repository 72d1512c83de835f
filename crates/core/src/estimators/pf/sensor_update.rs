//! The particle filters' generic measurement update ([`Estimator::update_sensor`]): any
//! [`Sensor`], weighed with its own noise density.
//!
//! Every kind weighs its transition-drawn particles with the sensor's likelihood
//! (`w_i <- w_i p(z | x_i)`: successive sensors in one step multiply their likelihoods),
//! then normalises, resamples and moves as on the radio's path (the RPF's kernel, the
//! GA-PF's and CGA-PF's operators and the Gaussian-prior rejuvenation through
//! `ParticleLikelihood`). The unscented kinds' per-particle proposals are formed for the
//! radio only: on this path the UPF and CGA-PF weigh with the transition as proposal. At
//! the first update a particle filter started from the first measurement draws its
//! positions from the measurement when the sensor fixes the position
//! ([`Sensor::position_fix`]), and otherwise keeps the particles drawn from the prior; a
//! reading of the velocity in that same first step ([`Sensor::velocity_fix`]) then draws
//! the velocities from it.
//!
//! [`Estimator::update_sensor`]: crate::estimators::Estimator::update_sensor

use super::likelihood::SensorLikelihood;
use super::update::less_noise;
use super::ParticleFilter;
use crate::estimators::{FilterError, SensorUpdate};
use crate::sensors::Sensor;
use nalgebra::SVector;

impl ParticleFilter {
    /// The generic measurement update (see the module documentation); transactional as
    /// [`ParticleFilter::update_with`].
    pub fn update_sensor_with<const D: usize, S: Sensor<D> + ?Sized>(
        &mut self,
        sensor: &S,
        z: &SVector<f64, D>,
    ) -> Result<SensorUpdate<D>, FilterError> {
        let rng = self.rng.clone();
        self.save_chunk_rngs();
        let r = self.try_update_sensor(sensor, z);
        if r.is_err() {
            self.rng = rng;
            self.restore_chunk_rngs();
        }
        r
    }

    fn try_update_sensor<const D: usize, S: Sensor<D> + ?Sized>(
        &mut self,
        sensor: &S,
        z: &SVector<f64, D>,
    ) -> Result<SensorUpdate<D>, FilterError> {
        let fresh = core::mem::take(&mut self.soa_fresh);
        self.materialise();
        let noise = sensor.noise();
        // the first step's velocity reading, after its position fix: the velocities from
        // it (a 1 m/s prior cloud weighed by a sub-mm/s density would keep one particle)
        if self.awaiting_velocity && !self.awaiting_first && sensor.velocity_fix(z).is_some() {
            self.init_velocities(|rng| {
                sensor.velocity_fix(&less_noise(z, &noise.model, &noise.scales, rng))
            })?;
            self.first_update_done();
            self.awaiting_velocity = false;
            return Ok(SensorUpdate {
                innovation: SVector::zeros(),
                nis: f64::NAN,
                dof: D,
            });
        }
        if self.awaiting_first {
            if sensor.position_fix(z).is_some() {
                self.init_from_fix(sensor, z)?;
                self.first_update_done();
                return Ok(SensorUpdate {
                    innovation: SVector::zeros(),
                    nis: f64::NAN,
                    dof: D,
                });
            }
            // no position to draw from: the particles drawn from the prior are weighed
            self.awaiting_first = false;
        }
        let lik = SensorLikelihood {
            sensor,
            z: *z,
            noise,
        };
        self.set_predictive()?;
        let max = self.weigh(&lik, fresh);
        self.finish_update(&lik, Some(max), fresh, false)?;
        // an extreme but finite reading can carry the estimate past double precision: a
        // failed update, as the radio's first update refuses non-finite particles
        if !crate::numerics::all_finite(self.mean.as_slice()) {
            return Err(FilterError::NonFinite("estimate after the sensor update"));
        }
        let innovation = sensor
            .measure(&self.mean)
            .map_or_else(SVector::zeros, |zh| sensor.residual(z, &zh));
        Ok(SensorUpdate {
            innovation,
            nis: f64::NAN,
            dof: D,
        })
    }

    /// Positions from the sensor's position fix of the measurement less a noise draw,
    /// velocities from the prior (the radio path's first-measurement initialisation for
    /// any position-fixing sensor).
    fn init_from_fix<const D: usize, S: Sensor<D> + ?Sized>(
        &mut self,
        sensor: &S,
        z: &SVector<f64, D>,
    ) -> Result<(), FilterError> {
        let noise = sensor.noise();
        self.init_positions(|rng| {
            sensor.position_fix(&less_noise(z, &noise.model, &noise.scales, rng))
        })
    }
}
