//! Particle filters of papers 000 and 003: SIR, regularised (RPF), unscented (UPF),
//! genetic (GA-PF) and cloud-genetic (CGA-PF), on one particle set.
//!
//! | kind | proposal | after resampling | then, with [`PfParams::moves`] (default) |
//! |---|---|---|---|
//! | [`PfKind::Sir`] (paper 000, sec. 3) | transition density | nothing | rejuvenation ([`moves`]) |
//! | [`PfKind::Rpf`] | transition density | kernel jitter (MH-accepted with moves) | rejuvenation |
//! | [`PfKind::Upf`] | per-particle UKF step with the current measurement (shrinkage kernel with moves) | nothing | rejuvenation |
//! | [`PfKind::Gapf`] | transition density | crossover + mutation, MH-accepted ([`genetic`]) | rejuvenation |
//! | [`PfKind::Cgapf`] (paper 003) | per-particle UKF step (shrinkage kernel with moves) | cloud crossover + cloud mutation, MH-accepted | rejuvenation |
//!
//! **SIR** (Gordon, Salmond & Smith 1993): `x_i <- Phi x_i + Gamma a + w_i`,
//! `w_i ~ N(0, Q)`; the log-weights grow by the measurement log-likelihood and are
//! normalised with the max-subtraction trick; `N_eff = 1 / sum w_i^2`; when
//! `N_eff < threshold N` (paper 000: 2/3) the particles are resampled ([`resample`]) and
//! the weights reset to `1/N`. The literal SIR (`moves = false`) resamples by index only:
//! the next transition gathers its input through the indices (no copy of the cloud);
//! every other reader (the next update, [`ParticleFilter::particles`], the saved state)
//! sees the resampled cloud. The likelihood is the sensor's true noise density
//! (Gaussian, contaminated Gaussian, Student-t, ... see [`crate::noise`]): the particle
//! filters are where heavy tails are modelled (paper 003), the Kalman filters keep the
//! Gaussian of the same variance.
//!
//! **Outputs.** After an update: the weighted mean and covariance of the particles (with
//! moves: those of the rejuvenated set, see [`moves`]). The literal SIR, RPF and GA-PF
//! (`moves = false`) report the weighted mean and covariance of the cloud *before*
//! resampling (the RPF and GA-PF without moves, when they resample: of the moved cloud
//! after it), formed in the normalisation's pass over the particles (`exp_moments`, about
//! the predictive mean): a lower-variance estimate than the moments of the resampled
//! copies. After a prediction: the mean and covariance of the particle predictive density
//! `sum_i w_i N(Phi x_i + Gamma a, Q)`, exactly `Phi m + Gamma a` and `Phi P Phi^T + Q` —
//! the same quantities the sample moments of the drawn particles estimate, without their
//! sampling noise.
//!
//! **Moves** ([`PfParams::moves`], on by default; [`moves`] has the method and its
//! justification). With process noise honest for a quiet truth (a white acceleration of
//! 1e-10 m^2/s^3) the particles cannot explore: resampling duplicates them, the
//! transition hardly separates the copies, the set degenerates onto a few points and the
//! filter diverges. With paper 000's large `Q` the same filters drift in velocity, where
//! `Q` is small. Every kind therefore ends each measurement update with a Metropolis–
//! Hastings move toward the Gaussian-prior posterior, the likelihood times the Gaussian of
//! the predictive moments ([`moves`]; a resample-move after Gilks & Berzuini 2001, whose
//! target here is that approximation, not the exact filtering posterior). `moves = false`
//! gives the papers' filters as written: particles drawn from the prior `N(x0, P0)`
//! ([`PfInit::Prior`], set by the navigator's configuration), paper 000's SIR (with the
//! configuration's `resampler = auto`: multinomial at `N_eff < 2N/3`), the plain
//! post-regularised RPF, van der Merwe's UPF, and the GA-PF's and CGA-PF's operators
//! accepted on the likelihood ratio alone, as paper 003 writes ([`genetic`]).
//!
//! **Particle prior** ([`PfParams::prior`] = [`PfPrior::Particle`], `pf_prior = 2`): not
//! this struct. The navigator's factory builds
//! [`crate::estimators::GaussianSumPf`] instead, whose particles are Gaussians, each
//! updated by its own EKF or UKF step ([`gaussian_sum`] has the method and why).
//!
//! **Regularised PF** (Musso, Oudjane & Le Gland 2001): after each resampling every
//! particle is moved by `h D eps`, `D D^T` the weighted empirical covariance before
//! resampling, `eps` drawn from the kernel, with the bandwidth that is optimal for a
//! Gaussian target in `n = 6` dimensions:
//! * Gaussian kernel: `h = (4 / (N (n + 2)))^(1 / (n + 4))`;
//! * Epanechnikov kernel `K(x) ∝ 1 - |x|^2` on the unit ball:
//!   `h = A N^(-1/(n+4))`, `A = (8 (n + 4) (2 sqrt(pi))^n / c_n)^(1/(n+4))`, `c_n` the unit
//!   ball's volume; `eps = r u` with `u` uniform on the sphere and `r^2 ~ Beta(n/2, 2)`.
//!
//! Plain jitter widens the set by `h^2 P` at every resampling (with small `Q` the error
//! grows to several times the EKF's); with moves each jittered particle is accepted by the
//! Metropolis–Hastings test of [`moves`] — the MCMC-regularised filter of the same
//! authors — and the set keeps the posterior's spread.
//!
//! **Unscented PF** (van der Merwe, Doucet, de Freitas & Wan 2000; paper 003's proposal):
//! every particle carries a transition mean `xbar_i = Phi x_i + Gamma a`; the
//! measurement update runs the UKF of [`crate::estimators::ukf`] on a Gaussian
//! `N(mu_i, S_i)` around it with the current `z` and the Gaussian of the noise model's
//! variance, giving `N(m_i, P_i+)`; the new particle is drawn from it and weighted by
//! `p(z | x) N(x; mu_i, S_i) / N(x; m_i, P_i+)`. A particle whose UKF step fails (zero
//! range) keeps its transition draw. Which Gaussian:
//! * literally (`moves = false`): `N(xbar_i, Q)`, the transition density itself (the
//!   unscented approximation of the optimal proposal `p(x_k | x_(k-1)^i, z_k)`). With
//!   small `Q` this proposal collapses onto the transition and the UPF degenerates like
//!   the SIR (40-216 times the EKF's error with a 1e-10 m^2/s^3 white acceleration);
//! * with moves: component `i` of the kernel-smoothed predictive density of Liu & West
//!   (2001), `N(a xbar_i + (1 - a) m-, (1 - h^2) Q + h^2 P-)`, `m-, P-` the predictive
//!   mean and covariance, `h` the Gaussian kernel's optimal bandwidth and
//!   `a = sqrt(1 - h^2)`: the mixture of these components has exactly the predictive mean
//!   and covariance, and each component is at least `h^2` of the predictive spread wide
//!   however small `Q` is. The weights are those of importance sampling from this mixture
//!   (component `i` taking the place of particle `i`'s transition density);
//! * [`PfParams::carry_covariance`]: van der Merwe's bank of UKFs, `P_i` carried from step
//!   to step (`P_i <- Phi P_i+ Phi^T + Q`). The particle already *is* a draw from `P_i+`:
//!   carrying it counts that uncertainty twice and the weights degenerate (paper 003, 10
//!   runs: NEES 558 and 3 failed runs of 10).
//!
//! **Prior of the first update.** Until the first weighting update the prior is the
//! Gaussian `N(x0, P0)` propagated exactly (`xbar_0`, `P_prior`). With
//! [`PfInit::Prior`] the first update's target is `p(z | x) N(x; xbar_0, P_prior)`: the
//! SIR samples the prior (the literal filter of paper 000); the UPF draws every particle
//! from the one UKF posterior of `(xbar_0, P_prior)` and weighs with
//! `p(z | x) N(x; xbar_0, P_prior) / q(x)` — exact importance sampling of the first
//! posterior.
//!
//! **The collapse of the literal SIR on paper 000** (a known trap of that set-up): its
//! prior is 50 m / 1 m/s wide while one measurement pins the position to a 0.5 m x 0.12 m
//! x 0.12 m box, about 1e-7 of the prior's volume: with thousands of particles none lands
//! in the likelihood's support, one particle takes all the weight and the filter ends
//! hundreds of metres off. [`PfInit::Prior`] with `moves = false` keeps that literal
//! behaviour. [`PfInit::FirstMeasurement`] (the default with the moves) draws the positions from the first
//! measurement's likelihood (the noisy measurement inverted to a position, noise drawn from
//! the sensor's noise model) and the velocities from the prior: the posterior after the
//! first measurement up to the prior's density over a box of a few decimetres, which a 50 m
//! prior makes flat to 1e-4; the first measurement is consumed by it. That alone leaves the
//! velocities impoverished (the prior's N draws, none closer than ~0.1 m/s to the truth,
//! which paper 000's 1e-3 m/s velocity noise cannot refine: the SIR without moves drifts
//! metres off within 100 s, `tests/pf.rs`); the moves refine them.
//!
//! **Threads.** From [`PARALLEL_MIN_PARTICLES`] particles on the particle loops run in
//! fixed chunks on worker threads, with results independent of the thread count
//! ([`PfParams::threads`]; see the `par` module). Below, a step allocates nothing:
//! every buffer is sized at construction (`tests/no_alloc.rs`).

#[cfg(feature = "std")]
mod filter;
#[cfg(feature = "std")]
pub mod gaussian_sum;
#[cfg(feature = "std")]
pub mod genetic;
#[cfg(feature = "std")]
mod likelihood;
#[cfg(feature = "std")]
mod moments;
#[cfg(feature = "std")]
mod moves;
#[cfg(feature = "std")]
mod par;
mod params;
#[cfg(feature = "std")]
mod persist;
#[cfg(feature = "std")]
mod predict;
#[cfg(feature = "std")]
mod regularise;
#[cfg(feature = "std")]
pub mod resample;
#[cfg(feature = "std")]
mod rng;
#[cfg(feature = "std")]
mod sensor_update;
#[cfg(test)]
mod tests;
#[cfg(feature = "std")]
mod transition;
#[cfg(feature = "std")]
mod unscented;
#[cfg(feature = "std")]
mod update;

#[cfg(feature = "std")]
pub use par::{CHUNK, PARALLEL_MIN_PARTICLES};
pub use params::{
    bandwidth, Kernel, PfInit, PfKind, PfParams, PfPrior, Resampler, MAX_GAUSSIAN_SUM,
    MAX_PARTICLES, MAX_THREADS,
};
#[cfg(feature = "std")]
pub use rng::{rng_from_state, rng_state, PfRng};

#[cfg(feature = "std")]
use super::ukf::Ukf;
#[cfg(feature = "std")]
use crate::numerics::soa::BLOCK;
#[cfg(feature = "std")]
use crate::types::{Mat6, State};
#[cfg(feature = "std")]
use par::Pool;
#[cfg(feature = "std")]
use std::cell::OnceCell;

/// The state dimension.
const N: usize = 6;

/// A particle filter over the canonical 6-state (see the module documentation).
#[cfg(feature = "std")]
#[derive(Debug, Clone)]
pub struct ParticleFilter {
    params: PfParams,
    x0: State,
    p0: Mat6,
    /// particles
    x: Vec<State>,
    /// each particle's transition mean `Phi x_prev + Gamma a` (unscented kinds, whose
    /// proposal starts there; empty otherwise)
    xbar: Vec<State>,
    /// each particle's covariance (unscented kinds; empty otherwise)
    pc: Vec<Mat6>,
    x_tmp: Vec<State>,
    xbar_tmp: Vec<State>,
    pc_tmp: Vec<Mat6>,
    logw: Vec<f64>,
    /// the update's new log-weights until the update has succeeded
    logw_tmp: Vec<f64>,
    w: Vec<f64>,
    /// log-likelihood of each particle at the last update (fitness of the genetic kinds)
    loglik: Vec<f64>,
    loglik_tmp: Vec<f64>,
    /// resampling indices; after resampling, the genetic operators' selected items
    idx: Vec<usize>,
    /// the literal SIR's resampling is in `idx` only, not yet applied to `x` and `loglik`
    /// (index-only resampling: the next transition gathers its input through `idx`; every
    /// other reader applies it first, the saved state is written through it)
    pending: bool,
    perm: Vec<usize>,
    /// the particles by blocks of [`BLOCK`], transposed (structure of arrays): written
    /// beside `x` by the serial transition, the plain RPF's jitter and the literal GA-PF's
    /// moves, read by the next weighting (the positions), the literal update's moments
    /// ([`moments::exp_moments_soa`], which transposes `x` here first when the copy is not
    /// current)
    /// and the next transition instead of transpositions of `x`
    soa: Vec<[[f64; BLOCK]; N]>,
    /// `soa` holds the current particles (set by the steps that wrote it, cleared by every
    /// other change of the particles)
    soa_fresh: bool,
    /// the spare weight buffer; after resampling, the genetic operators' fitness
    scratch: Vec<f64>,
    mean: State,
    /// covariance: computed from the particles when first asked for (a SIR step without
    /// moves never needs the posterior one), set directly when known (after a prediction
    /// or a rejuvenation)
    cov: OnceCell<Mat6>,
    ess: f64,
    /// the first-measurement initialisation is still to come
    awaiting_first: bool,
    /// the first step's velocity reading may still draw the velocities (cleared by the
    /// first prediction)
    awaiting_velocity: bool,
    /// no weighting update yet: the prior is the Gaussian (prior_mean, prior_cov)
    prior_mode: bool,
    prior_mean: State,
    prior_cov: Mat6,
    prior_l: Mat6,
    /// the predictive mean and covariance at the current update (the Gaussian part of
    /// the move steps' target) and the covariance's Cholesky factor
    pred_mean: State,
    pred_cov: Mat6,
    pred_l: Mat6,
    rng: PfRng,
    /// the chunks' generators of the parallel path (empty below PARALLEL_MIN_PARTICLES)
    chunk_rng: Vec<PfRng>,
    /// their state before the step in progress (a failed step restores it)
    chunk_rng_saved: Vec<PfRng>,
    pool: Pool,
    q_key: Mat6,
    /// square root of Q used to sample (Cholesky factor when Q is positive definite)
    q_sqrt: Mat6,
    q_pd: bool,
    ukf: Ukf,
    resamples: u64,
    moves_tried: u64,
    moves_accepted: u64,
}
