//! The particle filter's core: construction and the prior's draw, the accessors, the
//! summaries of the weighted particles (mean, and the covariance when first asked for) and
//! the application of a resampling's indices to every per-particle array.

use super::par::{self, Pool, CHUNK};
use super::params::{PfInit, PfParams, MAX_PARTICLES};
use super::rng::{gauss6, PfRng};
use super::{ParticleFilter, N};
use crate::estimators::ukf::Ukf;
use crate::numerics::eigen::psd_sqrt_or_diagonal;
use crate::numerics::moments::{moments, weighted_sum, Moments};
use crate::numerics::soa::BLOCK;
use crate::types::{Mat6, State};
use rand::SeedableRng;
use std::cell::OnceCell;

impl ParticleFilter {
    /// A filter with prior `N(x0, p0)` (canonical frame); `params` validated by the caller
    /// with [`PfParams::validate`] (an invalid count is clamped to `1..=MAX_PARTICLES`).
    pub fn new(x0: State, p0: Mat6, params: PfParams) -> Self {
        let n = params.particles.clamp(1, MAX_PARTICLES);
        let unscented = params.kind.unscented();
        let m = if unscented { n } else { 0 };
        let rng = PfRng::seed_from_u64(params.seed);
        let chunk_rng = par::chunk_generators(&rng, n);
        let pool = if chunk_rng.is_empty() {
            Pool::Serial
        } else {
            Pool::new(params.threads)
        };
        let mut f = Self {
            params,
            x0,
            p0,
            x: vec![State::zeros(); n],
            xbar: vec![State::zeros(); m],
            pc: vec![Mat6::zeros(); m],
            x_tmp: vec![State::zeros(); n],
            xbar_tmp: vec![State::zeros(); m],
            pc_tmp: vec![Mat6::zeros(); m],
            logw: vec![0.0; n],
            logw_tmp: vec![0.0; n],
            w: vec![1.0 / n as f64; n],
            loglik: vec![0.0; n],
            loglik_tmp: vec![0.0; n],
            idx: vec![0; n],
            pending: false,
            perm: (0..n).collect(),
            soa: vec![[[0.0; BLOCK]; N]; n.div_ceil(BLOCK)],
            soa_fresh: false,
            scratch: vec![0.0; n],
            mean: x0,
            cov: OnceCell::from(p0),
            ess: n as f64,
            awaiting_first: false,
            awaiting_velocity: false,
            prior_mode: true,
            prior_mean: x0,
            prior_cov: p0,
            prior_l: Mat6::identity(),
            pred_mean: x0,
            pred_cov: p0,
            pred_l: Mat6::identity(),
            chunk_rng_saved: chunk_rng.clone(),
            chunk_rng,
            rng,
            pool,
            q_key: Mat6::from_element(f64::NAN),
            q_sqrt: Mat6::zeros(),
            q_pd: false,
            ukf: Ukf::new(x0, p0, params.ukf),
            resamples: 0,
            moves_tried: 0,
            moves_accepted: 0,
        };
        f.draw_prior();
        f
    }

    pub(super) fn draw_prior(&mut self) {
        self.pending = false;
        self.soa_fresh = false;
        // the prior is validated (diagonal, finite); a matrix set through `set_estimate`
        // that has no square root falls back to the square roots of its diagonal
        let l = psd_sqrt_or_diagonal(&self.p0);
        for xi in self.x.iter_mut() {
            *xi = self.x0 + l * gauss6(&mut self.rng);
        }
        self.xbar.iter_mut().for_each(|xb| *xb = self.x0);
        self.pc.iter_mut().for_each(|p| *p = self.p0);
        let n = self.x.len() as f64;
        self.logw.iter_mut().for_each(|v| *v = 0.0);
        self.w.iter_mut().for_each(|v| *v = 1.0 / n);
        self.awaiting_first = self.params.init == PfInit::FirstMeasurement;
        self.awaiting_velocity = self.awaiting_first;
        self.prior_mode = true;
        self.prior_mean = self.x0;
        self.prior_cov = self.p0;
        self.ess = n;
        // the prior itself, not the sample moments of its draws
        self.mean = self.x0;
        self.cov = OnceCell::from(self.p0);
    }

    /// Effective sample size `1 / sum w_i^2` after the last update (before resampling).
    pub fn ess(&self) -> f64 {
        self.ess
    }

    /// How many times the particles were resampled.
    pub fn resample_count(&self) -> u64 {
        self.resamples
    }

    /// Fraction of the Metropolis–Hastings moves (rejuvenation, RPF jitter, genetic
    /// crossover and mutation) accepted so far (NaN before the first move).
    pub fn move_acceptance(&self) -> f64 {
        self.moves_accepted as f64 / self.moves_tried as f64
    }

    /// The Metropolis–Hastings moves tried and accepted so far (the counts behind
    /// [`ParticleFilter::move_acceptance`]).
    pub fn move_counts(&self) -> (u64, u64) {
        (self.moves_tried, self.moves_accepted)
    }

    /// The settings.
    pub fn params(&self) -> &PfParams {
        &self.params
    }

    /// The particles (canonical frame) and their normalised weights (`&mut`: a literal SIR's
    /// index-only resampling is applied first).
    pub fn particles(&mut self) -> (&[State], &[f64]) {
        self.materialise();
        (&self.x, &self.w)
    }

    /// Apply a pending index-only resampling ([`ParticleFilter::apply_resampling`]).
    pub(super) fn materialise(&mut self) {
        if self.pending {
            self.apply_resampling();
            self.pending = false;
        }
    }

    /// Whether the particle loops run in chunks (the parallel path).
    pub(super) fn chunked(&self) -> bool {
        !self.chunk_rng.is_empty()
    }

    /// Remember the chunk generators before a step that may fail.
    pub(super) fn save_chunk_rngs(&mut self) {
        self.chunk_rng_saved.clone_from_slice(&self.chunk_rng);
    }

    pub(super) fn restore_chunk_rngs(&mut self) {
        self.chunk_rng.clone_from_slice(&self.chunk_rng_saved);
    }

    /// Weighted mean of the particles; the covariance is computed when first asked for
    /// ([`ParticleFilter::cov`]).
    pub(super) fn summarise(&mut self) {
        let (m, wsum) = if self.chunked() {
            let jobs: Vec<_> = self.x.chunks(CHUNK).zip(self.w.chunks(CHUNK)).collect();
            self.pool
                .map(jobs, |(x, w)| weighted_sum(x, w))
                .into_iter()
                .fold((State::zeros(), 0.0), |(m, s), (mj, sj)| (m + mj, s + sj))
        } else {
            weighted_sum(&self.x, &self.w)
        };
        self.mean = m / wsum;
        self.cov = OnceCell::new();
    }

    /// Weighted covariance of the particles ([`Moments`] about the weighted mean), unless
    /// it is known.
    pub(super) fn cov(&self) -> &Mat6 {
        self.cov.get_or_init(|| {
            if self.chunked() {
                let jobs: Vec<_> = self.x.chunks(CHUNK).zip(self.w.chunks(CHUNK)).collect();
                let mean = self.mean;
                let parts = self.pool.map(jobs, |(x, w)| moments(&mean, x, w));
                let mut acc = Moments::new(mean);
                parts.iter().for_each(|p| acc.merge(p));
                acc.finish().1
            } else {
                moments(&self.mean, &self.x, &self.w).finish().1
            }
        })
    }

    /// Reorder every per-particle array by `self.idx` (after resampling).
    pub(super) fn apply_resampling(&mut self) {
        if self.chunked() {
            let (x, ll, idx) = (&self.x, &self.loglik, &self.idx);
            let jobs: Vec<_> = self
                .x_tmp
                .chunks_mut(CHUNK)
                .zip(self.loglik_tmp.chunks_mut(CHUNK))
                .zip(idx.chunks(CHUNK))
                .collect();
            self.pool.map(jobs, |((xo, lo), ix)| {
                for ((xk, lk), &i) in xo.iter_mut().zip(lo.iter_mut()).zip(ix) {
                    *xk = x[i];
                    *lk = ll[i];
                }
            });
        } else {
            let (x, ll) = (&self.x, &self.loglik);
            let (xo, lo) = (&mut self.x_tmp, &mut self.loglik_tmp);
            // AVX2 where present: a particle is one 32-byte and one 16-byte move
            crate::numerics::simd::dispatch(
                #[inline(always)]
                || {
                    for ((xk, lk), &i) in xo.iter_mut().zip(lo.iter_mut()).zip(&self.idx) {
                        *xk = x[i];
                        *lk = ll[i];
                    }
                },
            );
        }
        core::mem::swap(&mut self.x, &mut self.x_tmp);
        core::mem::swap(&mut self.loglik, &mut self.loglik_tmp);
        if !self.pc.is_empty() {
            for (k, &i) in self.idx.iter().enumerate() {
                self.xbar_tmp[k] = self.xbar[i];
            }
            core::mem::swap(&mut self.xbar, &mut self.xbar_tmp);
            // not carried, the covariances are all equal (zero after an update): nothing
            // to reorder
            if self.params.carry_covariance {
                for (k, &i) in self.idx.iter().enumerate() {
                    self.pc_tmp[k] = self.pc[i];
                }
                core::mem::swap(&mut self.pc, &mut self.pc_tmp);
            }
        }
    }
}
