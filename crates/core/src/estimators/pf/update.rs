//! The particle filter's measurement update: the weighting (the transition-proposal kinds'
//! fused likelihood pass, or the unscented proposals), the normalisation with the literal
//! filters' moments, the resampling and the kind's moves, and the first-measurement
//! initialisation.

use super::likelihood::{Likelihood, ParticleLikelihood};
use super::moments::{exp_moments, exp_moments_soa};
use super::par::CHUNK;
use super::params::PfKind;
use super::resample::{self, effective_sample_size, normalize_log_weights_with_max, resample};
use super::rng::{gauss6, PfRng};
use super::unscented::{SharedDraw, ShrinkKernel, Unscented};
use super::{ParticleFilter, N};
use crate::estimators::{FilterError, UpdateInfo};
use crate::noise::NoiseModel;
use crate::numerics::cholesky::{chol, chol_loaded, half_logdet, log_gauss};
use crate::numerics::eigen::psd_sqrt;
use crate::numerics::moments::Moments;
use crate::numerics::soa::{transpose_into, BLOCK};
use crate::numerics::vexp::exp_nonpos;
use crate::numerics::{lane_sum, lane_sum_sq};
use crate::sensors::{AngleTrig, MeasurementModel};
use crate::types::{Mat3, Mat6, State, Vec3};
use nalgebra::SVector;
use std::cell::OnceCell;

/// `z` less a draw of the noise `model` with `scales`, component by component (the
/// first-measurement initialisation's draw of a noise-free measurement).
pub(super) fn less_noise<const D: usize>(
    z: &SVector<f64, D>,
    model: &NoiseModel,
    scales: &[f64; D],
    rng: &mut PfRng,
) -> SVector<f64, D> {
    let mut zi = *z;
    let mut st = 0.0;
    for k in 0..D {
        zi[k] -= model.sample(scales[k], &mut st, rng);
    }
    zi
}

impl ParticleFilter {
    /// Positions from the measurement's likelihood, velocities from the prior.
    fn init_from_measurement<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
        noise: &NoiseModel,
        scales: &[f64; 3],
    ) -> Result<(), FilterError> {
        self.init_positions(|rng| sensor.invert(&less_noise(z, noise, scales, rng)))
    }

    /// Each particle's position from `fix` (a position drawn from the measurement's
    /// likelihood: the measurement less a noise draw, inverted; `None` where it cannot be
    /// inverted), its velocity from the prior; committed only when every particle was
    /// drawn, and drawn finite.
    pub(super) fn init_positions(
        &mut self,
        mut fix: impl FnMut(&mut PfRng) -> Option<Vec3>,
    ) -> Result<(), FilterError> {
        // the velocity rows of a square root of the prior draw from its velocity marginal
        let l = psd_sqrt(&self.prior_cov).ok_or(FilterError::NonFinite("prior covariance"))?;
        let v0 = self.prior_mean.fixed_rows::<3>(3).into_owned();
        let what = (
            "measurement inversion",
            "particles drawn from the measurement",
        );
        self.redraw(what, |rng, _| {
            let r = fix(rng)?;
            let v = v0 + (l * gauss6(rng)).fixed_rows::<3>(3);
            Some(State::new(r.x, r.y, r.z, v.x, v.y, v.z))
        })
    }

    /// Velocities from a velocity reading's likelihood (`fix` draws one), positions kept:
    /// the first step's velocity reading after the positions' initialisation.
    pub(super) fn init_velocities(
        &mut self,
        mut fix: impl FnMut(&mut PfRng) -> Option<Vec3>,
    ) -> Result<(), FilterError> {
        let what = (
            "velocity inversion",
            "particles drawn from the velocity reading",
        );
        self.redraw(what, |rng, x| {
            let v = fix(rng)?;
            Some(State::new(x[0], x[1], x[2], v.x, v.y, v.z))
        })
    }

    /// Every particle replaced by `draw(rng, particle)`, committed only when every draw
    /// succeeded and is finite; `what` names the failed draw and the non-finite set.
    fn redraw(
        &mut self,
        what: (&'static str, &'static str),
        mut draw: impl FnMut(&mut PfRng, &State) -> Option<State>,
    ) -> Result<(), FilterError> {
        for i in 0..self.x.len() {
            self.x_tmp[i] =
                draw(&mut self.rng, &self.x[i]).ok_or(FilterError::NonFinite(what.0))?;
            if let Some(xb) = self.xbar_tmp.get_mut(i) {
                *xb = self.x_tmp[i];
            }
        }
        if !self.x_tmp.iter().all(|x| x.iter().all(|v| v.is_finite())) {
            return Err(FilterError::NonFinite(what.1));
        }
        core::mem::swap(&mut self.x, &mut self.x_tmp);
        core::mem::swap(&mut self.xbar, &mut self.xbar_tmp);
        Ok(())
    }

    /// The bookkeeping after the first-measurement initialisation drew the particles:
    /// equal weights, the summary, each particle's own covariance, the ESS.
    pub(super) fn first_update_done(&mut self) {
        let n = self.x.len();
        self.w.iter_mut().for_each(|v| *v = 1.0 / n as f64);
        self.logw.iter_mut().for_each(|v| *v = 0.0);
        self.awaiting_first = false;
        self.prior_mode = false;
        self.summarise();
        if !self.pc.is_empty() {
            // the particle's own uncertainty: the spread of the drawn positions and the
            // prior's velocity block (or nothing: started afresh at the next step)
            let p = if self.params.carry_covariance {
                let mut p = self.prior_cov;
                p.fixed_view_mut::<3, 3>(0, 0)
                    .copy_from(&self.cov().fixed_view::<3, 3>(0, 0));
                p.fixed_view_mut::<3, 3>(0, 3).fill(0.0);
                p.fixed_view_mut::<3, 3>(3, 0).fill(0.0);
                p
            } else {
                Mat6::zeros()
            };
            self.pc.iter_mut().for_each(|c| *c = p);
        }
        self.ess = n as f64;
    }

    /// The predictive density as a Gaussian, the prior part of the moves' target
    /// (`pred_mean`, `pred_cov`, and the factor `pred_l` for the kinds whose moves use it).
    pub(super) fn set_predictive(&mut self) -> Result<(), FilterError> {
        let kind = self.params.kind;
        (self.pred_mean, self.pred_cov) = if self.prior_mode {
            (self.prior_mean, self.prior_cov)
        } else {
            (self.mean, *self.cov())
        };
        let needs_pred_l = match kind {
            PfKind::Rpf | PfKind::Gapf | PfKind::Cgapf => self.params.moves,
            PfKind::Sir | PfKind::Upf => false,
        };
        if needs_pred_l {
            self.pred_l = chol_loaded(&self.pred_cov).ok_or(FilterError::NotPositiveDefinite(
                "predictive covariance of the particles",
            ))?;
        }
        Ok(())
    }

    /// Measurement update with the sensor's likelihood under `noise` (per-component
    /// scales `scales`): the particle filters weigh with the true noise density, heavy
    /// tails included; the unscented proposal and the rejuvenation's Gaussian proposal use
    /// the Gaussian of the same variance.
    ///
    /// A failed update changes nothing (the generators included): new particles, weights
    /// and covariances are written to the spare buffers and swapped in once the weights
    /// have normalised; every later step cannot fail.
    pub fn update_with<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
        noise: &NoiseModel,
        scales: &[f64; 3],
    ) -> Result<UpdateInfo, FilterError> {
        let rng = self.rng.clone();
        self.save_chunk_rngs();
        let r = self.try_update(sensor, z, noise, scales);
        if r.is_err() {
            self.rng = rng;
            self.restore_chunk_rngs();
        }
        r
    }

    /// The log-weights `logw_tmp` and log-likelihoods of the transition-proposal kinds, in
    /// one pass ([`ParticleLikelihood::weigh_many`]); their maximum (per chunk on the
    /// parallel path). `fresh`: `soa` holds the particles (transposed, serial path).
    pub(super) fn weigh<const D: usize, L: ParticleLikelihood<D>>(
        &mut self,
        lik: &L,
        fresh: bool,
    ) -> f64 {
        if self.chunked() {
            let jobs: Vec<_> = self
                .x
                .chunks(CHUNK)
                .zip(self.logw.chunks(CHUNK))
                .zip(self.logw_tmp.chunks_mut(CHUNK))
                .zip(self.loglik.chunks_mut(CHUNK))
                .collect();
            self.pool
                .map(jobs, |(((x, lw), lwn), ll)| {
                    lik.weigh_many(x, None, lw, lwn, ll)
                })
                .into_iter()
                .fold(f64::NEG_INFINITY, |m, v| if v > m { v } else { m })
        } else {
            // the positions as the transition left them transposed, when it did
            let soa = fresh.then_some(&self.soa[..]);
            lik.weigh_many(
                &self.x,
                soa,
                &self.logw,
                &mut self.logw_tmp,
                &mut self.loglik,
            )
        }
    }

    /// The unscented proposals of every particle (spare buffers).
    fn propose_unscented<M: MeasurementModel>(&mut self, u: &Unscented<'_, M>) {
        if self.chunked() {
            let jobs: Vec<_> = self
                .x
                .chunks(CHUNK)
                .zip(self.xbar.chunks(CHUNK))
                .zip(self.pc.chunks(CHUNK))
                .zip(self.logw.chunks(CHUNK))
                .zip(self.x_tmp.chunks_mut(CHUNK))
                .zip(self.pc_tmp.chunks_mut(CHUNK))
                .zip(self.logw_tmp.chunks_mut(CHUNK))
                .zip(self.loglik.chunks_mut(CHUNK))
                .zip(self.chunk_rng.iter_mut())
                .collect();
            self.pool.map(
                jobs,
                |((((((((x, xb), pc), lw), xn), pcn), lwn), ll), rng)| {
                    u.run(x, xb, pc, lw, xn, pcn, lwn, ll, rng)
                },
            );
        } else {
            u.run(
                &self.x,
                &self.xbar,
                &self.pc,
                &self.logw,
                &mut self.x_tmp,
                &mut self.pc_tmp,
                &mut self.logw_tmp,
                &mut self.loglik,
                &mut self.rng,
            );
        }
    }

    /// Normalise `logw_tmp`, whose largest entry (NaN ignored) is `max`, into `scratch`;
    /// the log mean likelihood increment, `None` when every weight is zero
    /// ([`normalize_log_weights_with_max`]; chunk sums combined in order on the parallel
    /// path). With a `reference` (and a finite `max`) the same pass over the particles
    /// forms the weighted [`Moments`] about it ([`exp_moments`]; chunk sums merged in
    /// order): the same weights, bit for bit. `fresh`: `soa` holds the particles (serial
    /// path: the moments read them there, [`exp_moments_soa`]).
    fn normalise(
        &mut self,
        max: f64,
        reference: Option<State>,
        fresh: bool,
    ) -> Option<(f64, Option<Moments>)> {
        let n = self.logw_tmp.len();
        if !max.is_finite() || (reference.is_none() && !self.chunked()) {
            // no weight, or infinite ones: the sequential rules (rare, exact either way)
            return normalize_log_weights_with_max(&self.logw_tmp, &mut self.scratch, max)
                .map(|l| (l, None));
        }
        let (sum, mom) = match (reference, self.chunked()) {
            (Some(c), false) => {
                // the particles as the transition left them transposed; else transposed
                // here, so that the moments are the same bits whether or not `soa` was
                // current (it is not marked current: the update may still change `x`)
                let (sum, mom) = if self.soa.len() * BLOCK >= n {
                    if !fresh {
                        transpose_into(&self.x, &mut self.soa);
                    }
                    exp_moments_soa(&c, &self.soa, &self.logw_tmp, max, &mut self.scratch)
                } else {
                    exp_moments(&c, &self.x, &self.logw_tmp, max, &mut self.scratch)
                };
                (sum, Some(mom))
            }
            (Some(c), true) => {
                let jobs: Vec<_> = self
                    .x
                    .chunks(CHUNK)
                    .zip(self.logw_tmp.chunks(CHUNK))
                    .zip(self.scratch.chunks_mut(CHUNK))
                    .collect();
                let parts = self
                    .pool
                    .map(jobs, |((x, lw), w)| exp_moments(&c, x, lw, max, w));
                let mut acc = Moments::new(c);
                let mut sum = 0.0;
                for (s, m) in &parts {
                    sum += s;
                    acc.merge(m);
                }
                (sum, Some(acc))
            }
            (None, _) => {
                let jobs: Vec<_> = self
                    .logw_tmp
                    .chunks(CHUNK)
                    .zip(self.scratch.chunks_mut(CHUNK))
                    .collect();
                let sum: f64 = self
                    .pool
                    .map(jobs, |(lw, w)| {
                        w.iter_mut().zip(lw).for_each(|(x, &l)| {
                            *x = if l.is_nan() { 0.0 } else { exp_nonpos(l - max) }
                        });
                        lane_sum(w)
                    })
                    .into_iter()
                    .sum();
                (sum, None)
            }
        };
        let inv = 1.0 / sum;
        if self.chunked() {
            let jobs: Vec<_> = self.scratch.chunks_mut(CHUNK).collect();
            self.pool
                .map(jobs, |w| w.iter_mut().for_each(|x| *x *= inv));
        } else {
            self.scratch.iter_mut().for_each(|x| *x *= inv);
        }
        Some((sum.ln() + max - (n as f64).ln(), mom))
    }

    fn effective_sample_size(&self) -> f64 {
        if !self.chunked() {
            return effective_sample_size(&self.w);
        }
        let jobs: Vec<_> = self.w.chunks(CHUNK).collect();
        let s: f64 = self.pool.map(jobs, lane_sum_sq).into_iter().sum();
        if s > 0.0 && s.is_finite() {
            1.0 / s
        } else {
            0.0
        }
    }

    fn try_update<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
        noise: &NoiseModel,
        scales: &[f64; 3],
    ) -> Result<UpdateInfo, FilterError> {
        let n = self.x.len();
        // whether `soa` holds the current particles (cleared: the update may change them)
        let fresh = core::mem::take(&mut self.soa_fresh);
        self.materialise();
        if self.awaiting_first {
            self.init_from_measurement(sensor, z, noise, scales)?;
            self.first_update_done();
            return Ok(UpdateInfo {
                innovation: Vec3::zeros(),
                nis: f64::NAN,
                azimuth_used: true,
            });
        }
        let lik = Likelihood::new(sensor, z, noise, scales);
        let kind = self.params.kind;
        self.set_predictive()?;
        let vf = noise.variance_factor();
        let r = Mat3::from_diagonal(&Vec3::from_fn(|k, _| scales[k] * scales[k] * vf));
        let fused = if kind.unscented() {
            if self.prior_mode {
                self.prior_l = chol(&self.prior_cov)
                    .ok_or(FilterError::NotPositiveDefinite("prior covariance"))?;
                self.propose_from_prior(&lik, sensor, &r, z)?;
            } else {
                let kernel = if self.params.shrinkage() {
                    Some(
                        ShrinkKernel::new(&self.pred_mean, &self.pred_cov, &self.q_key, n).ok_or(
                            FilterError::NotPositiveDefinite("shrinkage kernel of the proposal"),
                        )?,
                    )
                } else if self.q_pd {
                    None
                } else {
                    return Err(FilterError::NotPositiveDefinite(
                        "process noise Q (the literal UPF and CGA-PF need a transition density)",
                    ));
                };
                let prior_half_logdet = half_logdet(kernel.as_ref().map_or(&self.q_sqrt, |k| &k.l));
                let shared = match &kernel {
                    Some(k) => k
                        .ukf_l
                        .and_then(|l| SharedDraw::new(&self.ukf, &l, &k.l, None)),
                    // the literal proposal: every covariance is the predicted `Q` unless
                    // carried (checked per particle all the same)
                    None if !self.params.carry_covariance => self.pc.first().and_then(|p| {
                        let l = p.cholesky()?.unpack();
                        SharedDraw::new(&self.ukf, &l, &self.q_sqrt, Some(*p))
                    }),
                    None => None,
                };
                let u = Unscented {
                    ukf: self.ukf,
                    lik: &lik,
                    sensor,
                    r,
                    z: *z,
                    kernel,
                    q_sqrt: self.q_sqrt,
                    prior_half_logdet,
                    carry: self.params.carry_covariance,
                    shared,
                    trig: AngleTrig::of(z),
                };
                self.propose_unscented(&u);
            }
            None
        } else {
            Some(self.weigh(&lik, fresh))
        };
        self.finish_update(&lik, fused, fresh, kind.unscented())?;
        let innovation = sensor
            .predict(&self.mean.fixed_rows::<3>(0).into_owned())
            .map(|zh| sensor.diff(z, &zh))
            .unwrap_or_default();
        Ok(UpdateInfo {
            innovation,
            nis: f64::NAN,
            azimuth_used: true,
        })
    }

    /// The update after the weighting, for any likelihood: the normalisation (`fused`: the
    /// maximum log-weight when the weighting pass formed it), the commit, the resampling
    /// and the kind's moves on resampling, the rejuvenation. `fresh`: `soa` held the
    /// particles before the update.
    pub(super) fn finish_update<const D: usize, L: ParticleLikelihood<D>>(
        &mut self,
        lik: &L,
        fused: Option<f64>,
        fresh: bool,
        proposed: bool,
    ) -> Result<(), FilterError> {
        let n = self.x.len();
        let kind = self.params.kind;
        let max = fused.unwrap_or_else(|| resample::max_ignoring_nan(&self.logw_tmp));
        // the literal transition-proposal filters' moments before resampling are their
        // outputs (and the RPF's and GA-PF's kernels), formed with the weights; with moves
        // the rejuvenation's replace them
        let reference = (fused.is_some() && !self.params.moves).then_some(self.pred_mean);
        // normalise into the spare buffer; nothing is committed if every weight is zero
        let (log_mean, moments) =
            self.normalise(max, reference, fresh)
                .ok_or(FilterError::NonFinite(
                    "particle weights (every likelihood is zero)",
                ))?;
        // commit: from here on nothing can fail
        core::mem::swap(&mut self.w, &mut self.scratch);
        core::mem::swap(&mut self.logw, &mut self.logw_tmp);
        if proposed {
            core::mem::swap(&mut self.x, &mut self.x_tmp);
            core::mem::swap(&mut self.pc, &mut self.pc_tmp);
        }
        self.ess = self.effective_sample_size();
        let resampling = self.ess < self.params.threshold * n as f64;
        // keep log-weights bounded: store the normalised ones, ln w_i = l_i - ln sum_j e^l_j
        // (not when resampling: the reset below overwrites them)
        if !resampling {
            let log_sum = log_mean + (n as f64).ln();
            if log_sum.is_finite() {
                self.logw.iter_mut().for_each(|lw| *lw -= log_sum);
            } else {
                for (lw, w) in self.logw.iter_mut().zip(&self.w) {
                    *lw = w.ln();
                }
            }
        }
        // the weighted mean and covariance before resampling: from the fused pass when it
        // formed them, else the mean now and the covariance when first asked for
        match moments.and_then(|m| m.mean_cov()) {
            Some((m, p)) => {
                self.mean = m;
                self.cov = OnceCell::from(p);
            }
            None => self.summarise(),
        }
        if resampling {
            let cov_before = match kind {
                PfKind::Rpf | PfKind::Gapf => *self.cov(),
                _ => Mat6::zeros(),
            };
            // the plain RPF on the serial path applies the resampling in its jitter
            // (`regularise` with `gather`): one condition for both places below
            let jitter_gathers =
                kind == PfKind::Rpf && !self.params.moves && !self.chunked() && self.pc.is_empty();
            resample(
                self.params.resampler,
                &self.w,
                &mut self.idx,
                &mut self.scratch,
                &mut self.rng,
            );
            // the literal SIR reads the resampled cloud first in the next transition: it
            // gathers through the indices (serial path; the covariance is known, so no lazy
            // moments read the cloud either)
            if kind == PfKind::Sir
                && !self.params.moves
                && !self.chunked()
                && self.cov.get().is_some()
            {
                self.pending = true;
            } else if jitter_gathers {
                // the plain RPF's jitter gathers through the indices itself (it applies
                // the resampling if it cannot jitter)
            } else {
                self.apply_resampling();
            }
            self.w.iter_mut().for_each(|v| *v = 1.0 / n as f64);
            // a zero the compiler cannot see: vector stores instead of a call to memset,
            // whose `rep stosb` callgrind counts as one instruction per byte: it would
            // swamp the step's instruction count (on hardware both take the same time)
            let zero = std::hint::black_box(0.0);
            self.logw.iter_mut().for_each(|v| *v = zero);
            self.resamples += 1;
            // the plain RPF's jitter and the literal GA-PF's operators set the summary of
            // the moved set themselves
            let mut summarised = false;
            match kind {
                PfKind::Rpf if self.params.moves => self.regularise_mh(lik, &cov_before),
                PfKind::Rpf => {
                    summarised = self.regularise(self.params.kernel, &cov_before, jitter_gathers)
                }
                PfKind::Gapf => summarised = self.genetic_moves(lik, &cov_before),
                PfKind::Cgapf => self.cloud_moves(lik),
                PfKind::Sir | PfKind::Upf => {}
            }
            // the weighted moments before a plain resampling are kept (lower variance
            // than the resampled set's); moved particles are summarised again
            if !self.params.moves && !summarised && !matches!(kind, PfKind::Sir | PfKind::Upf) {
                self.summarise();
            }
        }
        if self.params.moves && !self.rejuvenate(lik) {
            self.summarise();
        }
        // particles left as the transition drew them: `soa` still holds them
        if fresh && !resampling && !self.params.moves && !proposed {
            self.soa_fresh = true;
        }
        self.prior_mode = false;
        Ok(())
    }

    /// The unscented kinds' first update from the Gaussian prior ([`super::PfInit::Prior`]):
    /// one UKF posterior of the prior, every particle drawn from it.
    fn propose_from_prior<M: MeasurementModel>(
        &mut self,
        lik: &Likelihood<'_, M>,
        sensor: &M,
        r: &Mat3,
        z: &Vec3,
    ) -> Result<(), FilterError> {
        let (m, p, _) =
            self.ukf
                .measurement_update(&self.prior_mean, &self.prior_cov, sensor, r, z)?;
        let l = chol(&p).ok_or(FilterError::NotPositiveDefinite("UKF proposal"))?;
        let half_logdet: f64 = (0..N).map(|k| l[(k, k)].ln()).sum();
        let pc = if self.params.carry_covariance {
            p
        } else {
            Mat6::zeros()
        };
        for i in 0..self.x.len() {
            let eps = gauss6(&mut self.rng);
            let x = m + l * eps;
            let log_q = -0.5 * eps.norm_squared() - half_logdet;
            let ll = lik.log(&x);
            self.logw_tmp[i] =
                self.logw[i] + ll + log_gauss(&x, &self.prior_mean, &self.prior_l) - log_q;
            self.loglik[i] = ll;
            self.x_tmp[i] = x;
            self.pc_tmp[i] = pc;
        }
        Ok(())
    }
}
