//! The particle filter as an [`Estimator`]: the time update (the transition draw into the
//! spare buffers, the exact predictive moments `Phi m + Gamma a`, `Phi P Phi^T + Q`); the
//! measurement update is [`ParticleFilter::update_with`]'s.

use super::par::{self, CHUNK};
use super::rng::PfRng;
use super::transition::{CwBlocks, Transition};
use super::ParticleFilter;
use crate::dynamics::DiscreteModel;
use crate::estimators::{Estimator, FilterError, SensorUpdate, UpdateInfo};
use crate::noise::NoiseModel;
use crate::numerics::cholesky::chol;
use crate::numerics::eigen::psd_sqrt;
use crate::numerics::symmetrize;
use crate::sensors::{MeasurementModel, Sensor};
use crate::types::{Mat6, State, Vec3};
use nalgebra::SVector;
use rand::SeedableRng;
use std::cell::OnceCell;

impl Estimator for ParticleFilter {
    /// Transition draw `x_i <- Phi x_i + Gamma a + w_i`; the predicted mean and covariance
    /// are the particle predictive's, `Phi m + Gamma a` and `Phi P Phi^T + Q`. The new
    /// particles go to the spare buffers and are swapped in only when they are finite: a
    /// failed prediction changes nothing (the generators included).
    fn predict(&mut self, model: &DiscreteModel, accel: &Vec3) -> Result<(), FilterError> {
        // the square root of Q is cached per Q; the next update's transition density uses
        // it, so it is committed with the particles
        let (l, lower) = if model.q == self.q_key {
            (self.q_sqrt, self.q_pd)
        } else {
            match chol(&model.q) {
                Some(l) => (l, true),
                None => (
                    psd_sqrt(&model.q).ok_or(FilterError::NonFinite("process noise Q"))?,
                    false,
                ),
            }
        };
        let phi = model.phi;
        let tr = Transition {
            blocks: CwBlocks::of(&phi),
            phi,
            u: model.gamma * accel,
            // a diagonal Q (paper 000's) needs 6 products per particle instead of 36
            diag: (l == Mat6::from_diagonal(&l.diagonal())).then(|| l.diagonal()),
            l,
        };
        let mean = phi * self.mean + tr.u;
        let cov = symmetrize(&(phi * *self.cov() * phi.transpose() + model.q));
        let rng_saved = self.rng.clone();
        self.save_chunk_rngs();
        // `soa` is overwritten: current again only if the step succeeds and wrote it
        let soa_in = core::mem::take(&mut self.soa_fresh);
        let mut fresh = false;
        let check = if self.chunked() {
            let jobs: Vec<_> = self
                .x
                .chunks(CHUNK)
                .zip(self.x_tmp.chunks_mut(CHUNK))
                .zip(par::chunks_mut(&mut self.xbar_tmp))
                .zip(self.chunk_rng.iter_mut())
                .collect();
            self.pool
                .map(jobs, |(((x, xn), xb), rng)| {
                    tr.run(x, None, xn, xb, None, false, rng).0
                })
                .into_iter()
                .sum()
        } else {
            let idx = self.pending.then_some(&self.idx[..]);
            let (check, wrote) = tr.run(
                &self.x,
                idx,
                &mut self.x_tmp,
                &mut self.xbar_tmp,
                // (the unscented kinds' update reads its own proposals, never `soa`)
                (!self.params.kind.unscented()).then_some(&mut self.soa[..]),
                soa_in,
                &mut self.rng,
            );
            fresh = wrote;
            check
        };
        // the Gaussian prior before the first weighting update moves with the particles
        let prior = self.prior_mode.then(|| {
            (
                phi * self.prior_mean + tr.u,
                symmetrize(&(phi * self.prior_cov * phi.transpose() + model.q)),
            )
        });
        let finite = crate::numerics::all_finite;
        let prior_bad = prior.is_some_and(|(m, p)| !finite(m.as_slice()) || !finite(p.as_slice()));
        if !check.is_finite() || !finite(mean.as_slice()) || prior_bad {
            self.rng = rng_saved;
            self.restore_chunk_rngs();
            return Err(FilterError::NonFinite(if prior_bad {
                "predicted prior"
            } else {
                "predicted particles"
            }));
        }
        core::mem::swap(&mut self.x, &mut self.x_tmp);
        core::mem::swap(&mut self.xbar, &mut self.xbar_tmp);
        self.soa_fresh = fresh;
        self.awaiting_velocity = false;
        if self.pending {
            // the particles were gathered: the log-likelihoods follow
            for (o, &i) in self.loglik_tmp.iter_mut().zip(&self.idx) {
                *o = self.loglik[i];
            }
            core::mem::swap(&mut self.loglik, &mut self.loglik_tmp);
            self.pending = false;
        }
        (self.q_key, self.q_sqrt, self.q_pd) = (model.q, l, lower);
        self.mean = mean;
        self.cov = OnceCell::from(cov);
        if self.params.carry_covariance {
            for p in self.pc.iter_mut() {
                *p = symmetrize(&(phi * *p * phi.transpose() + model.q));
            }
        } else {
            // not carried: every covariance is zero after an update (restarted), so each
            // prediction is the one matrix `Phi 0 Phi^T + Q`, formed once
            let p = symmetrize(&(phi * Mat6::zeros() * phi.transpose() + model.q));
            self.pc.iter_mut().for_each(|c| *c = p);
        }
        if let Some((m, p)) = prior {
            (self.prior_mean, self.prior_cov) = (m, p);
        }
        Ok(())
    }

    /// Gaussian likelihood from the sensor's covariance (see [`ParticleFilter::update_with`]
    /// for other noise densities).
    fn update<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
    ) -> Result<UpdateInfo, FilterError> {
        let r = sensor.noise_cov();
        let scales = [r[(0, 0)].sqrt(), r[(1, 1)].sqrt(), r[(2, 2)].sqrt()];
        self.update_with(sensor, z, &NoiseModel::Gaussian, &scales)
    }

    fn update_sensor<const D: usize, S: Sensor<D> + ?Sized>(
        &mut self,
        sensor: &S,
        z: &SVector<f64, D>,
    ) -> Result<SensorUpdate<D>, FilterError> {
        self.update_sensor_with(sensor, z)
    }

    fn state(&self) -> &State {
        &self.mean
    }

    fn covariance(&self) -> &Mat6 {
        self.cov()
    }

    fn set_estimate(&mut self, x: State, p: Mat6) {
        self.x0 = x;
        self.p0 = p;
        self.rng = PfRng::seed_from_u64(self.params.seed);
        self.chunk_rng = par::chunk_generators(&self.rng, self.x.len());
        self.chunk_rng_saved.clone_from(&self.chunk_rng);
        self.resamples = 0;
        self.moves_tried = 0;
        self.moves_accepted = 0;
        self.draw_prior();
    }
}
