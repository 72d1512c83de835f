//! Moves: Gaussian-prior Metropolis–Hastings steps after the measurement update (their
//! target is defined below; it is not the exact filtering posterior), and the RPF's kernel
//! jitter.
//!
//! **Why the particle filters need them.** A particle set represents the filtering
//! posterior only as long as it stays diverse. Resampling duplicates the particles with
//! large weights; the transition then separates the copies by the process noise. With an
//! honest small process noise (a white acceleration of 1e-10 m^2/s^3, i.e. 1e-5 m/s per
//! step) the copies stay on top of each other: the set degenerates onto a handful of
//! points, the weighted moments understate the posterior, the next measurements fall
//! outside the cloud and the filter diverges (the SIR ends hundreds of times the EKF's
//! error). With paper 000's large position noise the set stays diverse in position but
//! not in velocity, whose noise is 1e-3 m/s per step: the velocity spread shrinks at every
//! resampling like the variance of a Wright–Fisher population (by about `1 / N_eff` per
//! generation), which the small velocity noise cannot replenish, and the Monte Carlo error
//! of the mean, `P / N` per step at best, accumulates over the velocity's long memory
//! (on paper 000, with `N = 1500`, to more than the EKF's whole velocity error). Both are
//! cured by moving the particles with a Markov kernel toward a posterior target (below) and
//! by estimating the posterior's moments with a variance-reduced estimator — not by
//! widening the set.
//!
//! **The target.** The exact filtering posterior at step `k`,
//! `p(x | z_1:k) ∝ p(z_k | x) ∫ p(x | x') p(x' | z_1:k-1) dx'`, cannot be evaluated
//! pointwise (the integral is over the previous particles: `O(N^2)`), and the resample-move
//! target on the extended space, `p(z_k | x) p(x | x'_ancestor)`, pins each particle to its
//! ancestor within the process noise — with small noise no move is ever accepted (the
//! GA-PF ends tens of metres off on paper 000 with it). The standard practical answer, used
//! here by every move, is the posterior with the predictive density replaced by its Gaussian
//! of the same mean and covariance (the predictive moments are exact for the particle
//! approximation, see the module docs):
//!
//! ```text
//! pi(x) ∝ p(z | x) N(x; m-, P-)
//! ```
//!
//! with the sensor's true noise density in `p(z | x)` (heavy tails included). On the
//! linear-Gaussian CW dynamics the predictive density is Gaussian whenever the previous
//! posterior was; the approximation only forgets non-Gaussian shape carried over from
//! earlier steps — of the same kind as the RPF's kernel density estimate, and the
//! Gaussian-prior resample-move of the literature (e.g. the Gaussian particle filter of
//! Kotecha & Djurić 2003 draws from exactly this Gaussian update).
//!
//! **Rejuvenation** ([`ParticleFilter::rejuvenate`], every kind, after every update when
//! [`super::PfParams::moves`] is on; after the resampling and the kind's own moves when
//! there are any). One independence Metropolis–Hastings step per particle (Tierney 1994)
//! with the Gaussian proposal `q = N(m+, P+)`, the Kalman update of `N(m-, P-)` with the
//! measurement linearised at `m-`, `g(z | x) = N(nu - H (x - m-); 0, R)` (`nu` the
//! innovation of `m-`, `H` the sensor's Jacobian, `R` diagonal: for Gaussian noise its
//! variance, for a Gaussian scale mixture the inverse of the noise precision expected given
//! the innovation, `1 / E[1/s^2 | nu]` ([`crate::noise::NoiseModel::local_variance`]):
//! about the narrow variance for an inlier, the wide one for an outlier; with the
//! mixture's overall variance the proposal would be too wide after an inlier and most of
//! its draws would be rejected). Since
//! `N(x; m-, P-) g(z | x) ∝ q(x)` exactly, the importance ratio needs no matrix solve:
//!
//! ```text
//! pi(x) / q(x) ∝ p(z | x) / g(z | x),    accept y for x with prob. min(1, [p/g](y) / [p/g](x)).
//! ```
//!
//! On Gaussian noise `p / g` varies only through the measurement's curvature over the
//! cloud (decimetres at hundreds of metres' range), nearly every proposal is accepted and
//! the set becomes an almost independent sample of `pi`; with heavy-tailed noise the
//! proposals where the Gaussian is wrong (the measurement is an outlier, or the posterior
//! is narrower than the Gaussian of the mixture's variance suggests) are rejected and the
//! particles stay. Proposals come in antithetic pairs `m+ ± L+ eps` (each marginally `q`;
//! Hammersley & Morton 1956).
//!
//! **The moments, with a control variate.** The filter's mean and covariance after the
//! move are the particles' weighted moments corrected with the proposals as a control
//! variate of known expectation (`E_q[y] = m+`, `E_q[(y - m+)(y - m+)^T] = P+`):
//!
//! ```text
//! E_pi[f] ≈ sum_i w_i f(x_i) - beta (sum_i w_i f(y_i) - E_q[f]),   f = x and (x - m+)(x - m+)^T,
//! ```
//!
//! `y_i` the proposal made to particle `i` and `beta = sum_i w_i [y_i accepted]`, the
//! regression coefficient of `f(x_i)` on `f(y_i)` (an accepted particle *is* its proposal;
//! a rejected one is independent of it). Both sums estimate the same expectation, so the
//! estimate stays unbiased for the moved set; the correction removes the sampling noise
//! of the accepted proposals: with every proposal accepted it returns `(m+, P+)` exactly,
//! with none it is the particles' own moments. (If the corrected covariance is not
//! positive definite, the particles' own moments are used.) This is what makes the
//! particle filters as accurate as the EKF on Gaussian noise: the sampling noise of a
//! 1500-particle set, `P / N` in the mean and `sqrt(2 / N)` relative in the covariance at
//! every step, otherwise accumulates into the velocity (with the move but without the
//! correction, the velocity error stays well above the EKF's; with it, the EKF's).
//!
//! **RPF with moves** ([`ParticleFilter::regularise_mh`]): after resampling, each particle
//! is jittered by the kernel `h D eps` of the module docs and the jittered particle is
//! accepted with probability `min(1, pi(x') / pi(x))` (a symmetric random-walk
//! Metropolis step: the MCMC-regularised filter of Musso, Oudjane & Le Gland 2001). The
//! bandwidth is derived from the cloud (`D D^T` its weighted covariance before resampling,
//! `h` the optimal bandwidth for `N` particles in 6 dimensions). Without moves
//! ([`ParticleFilter::regularise`]) every jitter is kept and the set widens by `h^2 P` at
//! every resampling.
//!
//! The GA-PF's and the CGA-PF's operators are Metropolis–Hastings moves for the same
//! `pi` ([`super::genetic`]).

use super::likelihood::ParticleLikelihood;
use super::par::CHUNK;
use super::ParticleFilter;
use crate::numerics::cholesky::chol;
use crate::numerics::moments::{MomentLanes, Moments};
use crate::numerics::soa::BLOCK;
use crate::numerics::symmetrize;
use crate::numerics::vexp::exp_nonpos;
use crate::numerics::ziggurat::{Lanes, Ziggurat};
use crate::types::{Mat6, State};
use nalgebra::{SMatrix, SVector};
use std::cell::OnceCell;

/// The independence sampler of the rejuvenation (see the module documentation).
struct Rejuvenation<'a, L, const D: usize> {
    lik: &'a L,
    /// the linearisation point `m-`
    m0: State,
    h: SMatrix<f64, D, 6>,
    nu: SVector<f64, D>,
    /// `1 / R_kk`
    rinv: SVector<f64, D>,
    /// proposal mean `m+` and Cholesky factor `L+`
    mq: State,
    lq: Mat6,
    /// `H L+` and `nu - H (m+ - m-)`: the linearised residual of `y = m+ + L+ eps` is
    /// `c - H L+ eps`
    hl: SMatrix<f64, D, 6>,
    c: SVector<f64, D>,
}

/// What one run of particles contributes to the moments and the counts.
struct RejuvenationSums {
    /// moments of the moved particles and of the proposals, about `m+`
    x: Moments,
    y: Moments,
    /// summed weight of the accepted proposals
    accepted_w: f64,
    tried: u64,
    accepted: u64,
}

impl<const D: usize, L: ParticleLikelihood<D>> Rejuvenation<'_, L, D> {
    /// `ln g(z | x)` from the linearised residual `res`.
    #[inline(always)]
    fn log_g(&self, res: &SVector<f64, D>) -> f64 {
        // every term is >= 0, so starting from +0 adds nothing
        let q = (0..D).fold(0.0, |acc, k| acc + res[k] * res[k] * self.rinv[k]);
        -0.5 * q
    }

    /// One independence MH step for each particle of a run, block by block: the block's
    /// proposals and uniforms are drawn first (the normals of its 8 antithetic pairs in
    /// three batches of [`Ziggurat::fill_batch_lanes`], then 16 uniforms, all from
    /// [`Lanes`] derived from `rng` at the start of the run), their likelihoods evaluated
    /// together ([`Likelihood::log_many`]), then the particles accepted or kept.
    fn run(
        &self,
        x: &mut [State],
        loglik: &mut [f64],
        w: &[f64],
        rng: &mut super::PfRng,
    ) -> RejuvenationSums {
        crate::numerics::simd::dispatch(
            #[inline(always)]
            || self.run_inline(x, loglik, w, rng),
        )
    }

    /// [`Rejuvenation::run`]'s body, inlined into its [`crate::numerics::simd::dispatch`]
    /// (AVX2 where present, the same bits).
    #[inline(always)]
    fn run_inline(
        &self,
        x: &mut [State],
        loglik: &mut [f64],
        w: &[f64],
        rng: &mut super::PfRng,
    ) -> RejuvenationSums {
        let mut s = RejuvenationSums {
            x: Moments::new(self.mq),
            y: Moments::new(self.mq),
            accepted_w: 0.0,
            tried: 0,
            accepted: 0,
        };
        let zig = Ziggurat::get();
        let mut lanes = Lanes::seed_from(rng);
        let mut normals = [0.0; 3 * Ziggurat::BATCH];
        let mut ys = [State::zeros(); BLOCK];
        let mut es = [State::zeros(); BLOCK];
        let mut us = [0.0f64; BLOCK];
        let mut lly = [0.0; BLOCK];
        let (mut mx, mut my) = (MomentLanes::new(), MomentLanes::new());
        for ((xb, llb), wb) in x
            .chunks_mut(BLOCK)
            .zip(loglik.chunks_mut(BLOCK))
            .zip(w.chunks(BLOCK))
        {
            let n = xb.len();
            // the block's 8 pairs' normals (6 each) and 16 uniforms from the lanes
            for c in normals.chunks_exact_mut(Ziggurat::BATCH) {
                if let Ok(c) = <&mut [f64; Ziggurat::BATCH]>::try_from(c) {
                    zig.fill_batch_lanes(&mut lanes, rng, c);
                }
            }
            lanes.uniforms(&mut us);
            for (i, (y, e)) in ys.iter_mut().zip(es.iter_mut()).enumerate().take(n) {
                // antithetic pairs: a fresh draw, then its mirror image
                let p = &normals[6 * (i / 2)..6 * (i / 2) + 6];
                let f = State::from_fn(|k, _| p[k]);
                *e = if i % 2 == 0 { f } else { -f };
                *y = self.mq + self.lq * *e;
            }
            self.lik.log_many(&ys[..n], &mut lly[..n]);
            my.add_block(&self.mq, &ys[..n], wb);
            for (i, ((xi, lli), &wi)) in xb.iter_mut().zip(llb.iter_mut()).zip(wb).enumerate() {
                let (y, eps, ll, u) = (ys[i], es[i], lly[i], us[i]);
                let lw_y = ll - self.log_g(&(self.c - self.hl * eps));
                let lw_x = *lli - self.log_g(&(self.nu - self.h * (*xi - self.m0)));
                s.tried += 1;
                // `u < min(1, e^d)` (`ln u < d` without the logarithm; NaN rejects)
                let d = lw_y - lw_x;
                if lw_y.is_finite() && (d >= 0.0 || u < exp_nonpos(d)) {
                    *xi = y;
                    *lli = ll;
                    s.accepted += 1;
                    s.accepted_w += wi;
                }
            }
            mx.add_block(&self.mq, xb, wb);
        }
        s.x = mx.finish(&self.mq);
        s.y = my.finish(&self.mq);
        s
    }
}

impl ParticleFilter {
    /// The rejuvenation of the module documentation on the current (weighted) particles;
    /// sets the filter's mean and covariance. False (nothing moved) when the Gaussian
    /// proposal cannot be formed (the sensor's linearisation fails at the predictive mean
    /// or a covariance is not positive definite).
    pub(super) fn rejuvenate<const D: usize, L: ParticleLikelihood<D>>(&mut self, lik: &L) -> bool {
        let (m0, p0) = (self.pred_mean, self.pred_cov);
        let Some((h, nu)) = lik.linear(&m0) else {
            return false;
        };
        let ph = p0 * h.transpose();
        let hph = h * ph;
        // the noise's Gaussian stand-in at this innovation (its variance for Gaussian
        // noise; the narrow or the wide one for an inlier or an outlier of a heavy tail)
        let r = SMatrix::<f64, D, D>::from_diagonal(&SVector::<f64, D>::from_fn(|k, _| {
            lik.local_variance(k, nu[k], hph[(k, k)])
        }));
        let Some(s) = (hph + r).cholesky() else {
            return false;
        };
        let k = s.solve(&ph.transpose()).transpose();
        let mq = m0 + k * nu;
        let ikh = Mat6::identity() - k * h;
        let pq = symmetrize(&(ikh * p0 * ikh.transpose() + k * r * k.transpose()));
        let Some(lq) = chol(&pq) else {
            return false;
        };
        let rj = Rejuvenation {
            lik,
            m0,
            h,
            nu,
            rinv: SVector::<f64, D>::from_fn(|k, _| 1.0 / r[(k, k)]),
            mq,
            lq,
            hl: h * lq,
            c: nu - h * (mq - m0),
        };
        let sums = if self.chunked() {
            let jobs: Vec<_> = self
                .x
                .chunks_mut(CHUNK)
                .zip(self.loglik.chunks_mut(CHUNK))
                .zip(self.w.chunks(CHUNK))
                .zip(self.chunk_rng.iter_mut())
                .collect();
            let parts = self
                .pool
                .map(jobs, |(((x, ll), w), rng)| rj.run(x, ll, w, rng));
            let mut total = RejuvenationSums {
                x: Moments::new(mq),
                y: Moments::new(mq),
                accepted_w: 0.0,
                tried: 0,
                accepted: 0,
            };
            for p in &parts {
                total.x.merge(&p.x);
                total.y.merge(&p.y);
                total.accepted_w += p.accepted_w;
                total.tried += p.tried;
                total.accepted += p.accepted;
            }
            total
        } else {
            rj.run(&mut self.x, &mut self.loglik, &self.w, &mut self.rng)
        };
        self.moves_tried += sums.tried;
        self.moves_accepted += sums.accepted;
        let (mx, px) = sums.x.finish();
        let (my, py) = sums.y.finish();
        let beta = sums.accepted_w / sums.x.wsum;
        // second moments about m+, where E_q is P+
        let raw = |m: &State, p: &Mat6| p + (m - mq) * (m - mq).transpose();
        let m_cv = mx - (my - mq) * beta;
        let s_cv = raw(&mx, &px) - (raw(&my, &py) - pq) * beta;
        let p_cv = symmetrize(&(s_cv - (m_cv - mq) * (m_cv - mq).transpose()));
        let ok = m_cv.iter().all(|v| v.is_finite()) && chol(&p_cv).is_some();
        (self.mean, self.cov) = if ok {
            (m_cv, OnceCell::from(p_cv))
        } else {
            (mx, OnceCell::from(symmetrize(&px)))
        };
        true
    }
}
