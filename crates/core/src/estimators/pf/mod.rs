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
//! resampling (the RPF and GA-PF without moves, when they resample: of the moved cloud after it), formed in the
//! normalisation's pass over the particles (`exp_moments`, about the predictive mean):
//! a lower-variance estimate than the moments of the resampled copies, which the
//! covariance was before 2 December 2026 (the mean was already the weighted one). After a prediction: the mean and
//! covariance of the particle predictive density `sum_i w_i N(Phi x_i + Gamma a, Q)`,
//! exactly `Phi m + Gamma a` and `Phi P Phi^T + Q` — the same quantities the sample
//! moments of the drawn particles estimate, without their sampling noise.
//!
//! **Moves** ([`PfParams::moves`], on by default; [`moves`] has the method and its
//! justification). With process noise honest for a quiet truth (a white acceleration of
//! 1e-10 m^2/s^3) the particles cannot explore: resampling duplicates them, the
//! transition hardly separates the copies, the set degenerates onto a few points and the
//! filter diverges. With paper 000's large `Q` the same filters drift in velocity, where
//! `Q` is small. Every kind therefore ends each measurement update with a Metropolis–
//! Hastings move that leaves the filtering posterior invariant (resample-move, Gilks &
//! Berzuini 2001). `moves = false` gives the literal filters of the papers: paper 000's
//! SIR, the plain post-regularised RPF, van der Merwe's UPF.
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
//! Plain jitter widens the set by `h^2 P` at every resampling (3 times the EKF's error
//! with small `Q`, measured); with moves each jittered particle is accepted by the
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
//! **The collapse of the literal SIR on paper 000** (issue 4's "known trap"): its prior is
//! 50 m / 1 m/s wide while one measurement pins the position to a 0.5 m x 0.12 m x 0.12 m
//! box, about 1e-7 of the prior's volume: with thousands of particles none lands in the
//! likelihood's support, one particle takes all the weight and the filter ends hundreds of
//! metres off. [`PfInit::Prior`] with `moves = false` keeps that literal behaviour.
//! [`PfInit::FirstMeasurement`] (the default) draws the positions from the first
//! measurement's likelihood (the noisy measurement inverted to a position, noise drawn
//! from the sensor's noise model) and the velocities from the prior: the posterior after
//! the first measurement up to the prior's density over a box of a few decimetres, which
//! a 50 m prior makes flat to 1e-4; the first measurement is consumed by it. That alone
//! leaves the velocities impoverished (the prior's N draws, none closer than ~0.1 m/s to
//! the truth, which paper 000's 1e-3 m/s velocity noise cannot refine: the SIR without
//! moves drifts metres off within 100 s, `tests/pf.rs`); the moves refine them.
//!
//! **Threads.** From [`PARALLEL_MIN_PARTICLES`] particles on the particle loops run in
//! fixed chunks on worker threads, with results independent of the thread count
//! ([`PfParams::threads`]; see the `par` module). Below, a step allocates nothing:
//! every buffer is sized at construction (`tests/no_alloc.rs`).

pub mod genetic;
mod moves;
mod par;
pub mod resample;

pub use par::{CHUNK, MAX_THREADS, PARALLEL_MIN_PARTICLES};

use super::ukf::{SharedPrior, Ukf, UkfParams, WhitenedBlock};
use super::{Estimator, FilterError, UpdateInfo};
use crate::dynamics::DiscreteModel;
use crate::noise::NoiseModel;
use crate::numerics::cholesky::{
    chol, chol_loaded, half_logdet, log_gauss, log_gauss_with, lower6,
};
use crate::numerics::eigen::psd_sqrt;
use crate::numerics::moments::{
    moments, unit_moments_soa, weighted_sum, LaneSums, MomentLanes, Moments, PointSums,
};
use crate::numerics::simd;
use crate::numerics::soa::{
    block_to_rows, gather_to_block, gather_to_block_in, rows_to_block, transpose_into, BLOCK,
};
use crate::numerics::state::{refuse, Persist, Reader, StateError, Writer};
use crate::numerics::vexp::exp_nonpos;
use crate::numerics::vlog::{is_normal_pos, ln_normal, ln_pos};
use crate::numerics::ziggurat::{Lanes, Ziggurat};
use crate::numerics::{lane_sum, lane_sum_sq, symmetrize};
use crate::sensors::{AngleTrig, MeasurementModel};
use crate::types::{Mat3, Mat6, State, Vec3};
use genetic::{CloudParams, GeneticParams};
use par::Pool;
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use std::cell::OnceCell;

/// The particle filters' generator: xoshiro256++ (Blackman & Vigna), seeded through
/// SplitMix64 by `seed_from_u64`. Chosen over ChaCha8 for speed (the six normals per
/// particle and step were a quarter of a SIR step); statistical quality is ample for
/// Monte Carlo and the stream is fixed by the crate's documented algorithm, so results
/// are reproducible from the seed. Its `jump` (2^128 draws) gives the parallel chunks
/// non-overlapping streams.
pub type PfRng = Xoshiro256PlusPlus;

/// The four 64-bit words of a [`PfRng`]'s state. rand_xoshiro exposes them only through its
/// serde form (a struct of one `[u64; 4]`), read here without naming its field; the result
/// is checked by rebuilding the generator from it. `None` if that ever fails (then the saved
/// state carries zeros, which [`rng_from_state`] refuses, rather than a wrong stream).
pub fn rng_state(rng: &PfRng) -> Option<[u64; 4]> {
    fn words(v: &serde_json::Value, out: &mut Vec<u64>) {
        match v {
            serde_json::Value::Number(n) => out.extend(n.as_u64()),
            serde_json::Value::Array(a) => a.iter().for_each(|x| words(x, out)),
            serde_json::Value::Object(m) => m.values().for_each(|x| words(x, out)),
            _ => {}
        }
    }
    let v = serde_json::to_value(rng).ok()?;
    let mut out = Vec::with_capacity(4);
    words(&v, &mut out);
    let s: [u64; 4] = out.try_into().ok()?;
    (rng_from_state(s).as_ref() == Some(rng)).then_some(s)
}

/// The generator in state `s` (xoshiro256++ state words `s[0..4]`, as the reference
/// implementation names them). `None` for the all-zero state, which xoshiro never reaches.
pub fn rng_from_state(s: [u64; 4]) -> Option<PfRng> {
    if s == [0; 4] {
        return None;
    }
    let mut seed = [0u8; 32];
    for (c, w) in seed.chunks_exact_mut(8).zip(s) {
        c.copy_from_slice(&w.to_le_bytes());
    }
    Some(PfRng::from_seed(seed))
}
use resample::{effective_sample_size, normalize_log_weights_with_max, resample, Resampler};

/// The particle-filter variants (FMU / C ABI filter codes 4-8).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PfKind {
    /// Sampling-importance-resampling (bootstrap) filter of paper 000.
    #[default]
    Sir,
    /// Regularised PF: kernel jitter after resampling.
    Rpf,
    /// Unscented PF: per-particle UKF proposal.
    Upf,
    /// Genetic-algorithm PF: crossover and mutation after resampling.
    Gapf,
    /// Cloud-genetic PF of paper 003: UKF proposal, cloud-model genetic resampling.
    Cgapf,
}

impl PfKind {
    /// Lower-case name as in scenario files (`pf`, `rpf`, `upf`, `gapf`, `cgapf`).
    pub fn name(self) -> &'static str {
        match self {
            PfKind::Sir => "pf",
            PfKind::Rpf => "rpf",
            PfKind::Upf => "upf",
            PfKind::Gapf => "gapf",
            PfKind::Cgapf => "cgapf",
        }
    }

    /// The kind of a scenario-file name.
    pub fn from_name(s: &str) -> Option<Self> {
        [
            PfKind::Sir,
            PfKind::Rpf,
            PfKind::Upf,
            PfKind::Gapf,
            PfKind::Cgapf,
        ]
        .into_iter()
        .find(|k| k.name() == s)
    }

    /// Whether the proposal is the per-particle UKF step.
    pub fn unscented(self) -> bool {
        matches!(self, PfKind::Upf | PfKind::Cgapf)
    }

    /// The default initialisation ([`PfInit::FirstMeasurement`] for every kind: even the
    /// UKF proposal of the Gaussian prior is metres off the first posterior on paper
    /// 000's example, where the posterior is decimetres wide).
    pub fn default_init(self) -> PfInit {
        PfInit::FirstMeasurement
    }
}

/// How the particles start.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PfInit {
    /// From the prior `N(x0, P0)` (paper 000 literally; the SIR collapses on its example).
    Prior,
    /// Positions from the first measurement's likelihood, velocities from the prior.
    #[default]
    FirstMeasurement,
}

/// Regularisation kernel of the RPF.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Kernel {
    /// Gaussian.
    #[default]
    Gaussian,
    /// Epanechnikov (optimal in mean integrated squared error).
    Epanechnikov,
}

/// Particle-filter settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PfParams {
    /// The variant.
    pub kind: PfKind,
    /// Number of particles (>= 1).
    pub particles: usize,
    /// Resampling scheme.
    pub resampler: Resampler,
    /// Resample when `N_eff < threshold N`; in (0, 1] (paper 000: 2/3).
    pub threshold: f64,
    /// Regularisation kernel (RPF only).
    pub kernel: Kernel,
    /// Initialisation.
    pub init: PfInit,
    /// Seed of the filter's own random numbers.
    pub seed: u64,
    /// Sigma-point parameters of the unscented proposal (UPF, CGA-PF).
    pub ukf: UkfParams,
    /// Unscented proposal: carry each particle's UKF covariance from step to step (van der
    /// Merwe et al. 2000 literally) instead of starting it afresh at every step (the
    /// default; see the module documentation for why).
    pub carry_covariance: bool,
    /// Genetic operators (GA-PF).
    pub genetic: GeneticParams,
    /// Cloud-genetic operators (CGA-PF).
    pub cloud: CloudParams,
    /// Move the particles with posterior-invariant Metropolis–Hastings steps (the
    /// rejuvenation of [`moves`] after every update, the MH-accepted RPF jitter, the
    /// shrinkage-kernel unscented proposal); default true. False: the papers' literal
    /// filters (paper 000's SIR, the plain RPF, van der Merwe's UPF), which degenerate
    /// with small process noise.
    pub moves: bool,
    /// Worker threads of the particle loops from [`PARALLEL_MIN_PARTICLES`] particles on:
    /// 0 (default) rayon's global pool (one per core), 1 the calling thread, more a pool of
    /// the filter's own. The results do not depend on it.
    pub threads: usize,
}

impl Default for PfParams {
    fn default() -> Self {
        Self::new(PfKind::Sir)
    }
}

impl PfParams {
    /// Defaults for `kind`: 1500 particles (paper 003), systematic resampling, threshold
    /// 2/3 (paper 000), Gaussian kernel, the kind's [`PfKind::default_init`], seed 0,
    /// moves on, threads from rayon's global pool.
    pub fn new(kind: PfKind) -> Self {
        Self {
            kind,
            particles: 1500,
            resampler: Resampler::Systematic,
            threshold: 2.0 / 3.0,
            kernel: Kernel::Gaussian,
            init: kind.default_init(),
            seed: 0,
            ukf: UkfParams::default(),
            carry_covariance: false,
            genetic: GeneticParams::default(),
            cloud: CloudParams::default(),
            moves: true,
            threads: 0,
        }
    }

    /// Check the settings; the message names the bad one.
    pub fn validate(&self) -> Result<(), String> {
        if self.particles == 0 {
            return Err("particles must be >= 1 (got 0)".into());
        }
        if self.particles > MAX_PARTICLES {
            return Err(format!(
                "particles must be <= {MAX_PARTICLES} (got {})",
                self.particles
            ));
        }
        if !(self.threshold > 0.0 && self.threshold <= 1.0) {
            return Err(format!(
                "resample threshold must lie in (0, 1] (got {})",
                self.threshold
            ));
        }
        if self.threads > MAX_THREADS {
            return Err(format!(
                "particle-filter threads must be <= {MAX_THREADS} (got {})",
                self.threads
            ));
        }
        self.ukf.validate()?;
        self.genetic.validate()?;
        self.cloud.validate()
    }

    /// Whether the unscented proposal is the shrinkage kernel (moves on, covariance not
    /// carried) rather than the transition density.
    fn shrinkage(&self) -> bool {
        self.moves && !self.carry_covariance
    }
}

/// Largest particle count accepted (about 1 GB of particle state for the unscented kinds).
pub const MAX_PARTICLES: usize = 2_000_000;

const N: usize = 6;

/// Volume of the unit ball in 6 dimensions, `pi^3 / 6`.
const UNIT_BALL_6: f64 = std::f64::consts::PI * std::f64::consts::PI * std::f64::consts::PI / 6.0;

/// Optimal RPF bandwidth for `n = 6` and `particles` particles.
pub fn bandwidth(kernel: Kernel, particles: usize) -> f64 {
    let n = N as f64;
    let np = particles as f64;
    match kernel {
        Kernel::Gaussian => (4.0 / (np * (n + 2.0))).powf(1.0 / (n + 4.0)),
        Kernel::Epanechnikov => {
            let a = (8.0 * (n + 4.0) * (2.0 * std::f64::consts::PI.sqrt()).powf(n) / UNIT_BALL_6)
                .powf(1.0 / (n + 4.0));
            a * np.powf(-1.0 / (n + 4.0))
        }
    }
}

/// The measurement likelihood a particle filter weighs with.
struct Likelihood<'a, M> {
    sensor: &'a M,
    z: Vec3,
    noise: &'a NoiseModel,
    scales: [f64; 3],
    gaussian: bool,
    /// `-0.5 / scale_k^2` (the Gaussian case)
    neg_half_inv_var: [f64; 3],
    /// the angles' sines and cosines for [`MeasurementModel::residual_at`]
    trig: AngleTrig,
}

impl<'a, M: MeasurementModel> Likelihood<'a, M> {
    fn new(sensor: &'a M, z: &Vec3, noise: &'a NoiseModel, scales: &[f64; 3]) -> Self {
        Self {
            sensor,
            z: *z,
            noise,
            scales: *scales,
            gaussian: matches!(noise, NoiseModel::Gaussian),
            neg_half_inv_var: scales.map(|s| -0.5 / (s * s)),
            trig: AngleTrig::of(z),
        }
    }

    /// `ln p(z | x)` up to a constant: `-0.5 sum d_k^2 / sigma_k^2` for Gaussian noise, the
    /// noise model's log-density per component otherwise; `-inf` where `z` is undefined.
    fn log(&self, x: &State) -> f64 {
        let r = x.fixed_rows::<3>(0).into_owned();
        let Some(d) = self.sensor.residual_at(&self.z, &self.trig, &r) else {
            return f64::NEG_INFINITY;
        };
        if self.gaussian {
            let c = &self.neg_half_inv_var;
            c[0] * d.x * d.x + c[1] * d.y * d.y + c[2] * d.z * d.z
        } else {
            (0..3)
                .map(|k| self.noise.log_density(d[k], self.scales[k]))
                .sum()
        }
    }
}

impl<M: MeasurementModel> Likelihood<'_, M> {
    /// [`Likelihood::log`] of every particle of `x` into `out` (same length), block by
    /// block in structure-of-arrays form ([`MeasurementModel::residuals_at`]): the same
    /// values as `log` particle by particle, bit for bit.
    fn log_many(&self, x: &[State], out: &mut [f64]) {
        crate::numerics::simd::dispatch(
            #[inline(always)]
            || self.log_many_inline(x, out),
        )
    }

    /// [`Likelihood::log_many`]'s body, inlined into its [`crate::numerics::simd::dispatch`].
    #[inline(always)]
    fn log_many_inline(&self, x: &[State], out: &mut [f64]) {
        let mut r = [[0.0; BLOCK]; 3];
        let mut d = [[0.0; BLOCK]; 3];
        let mut ok = [false; BLOCK];
        let mut ll = [0.0; BLOCK];
        for (xs, os) in x.chunks(BLOCK).zip(out.chunks_mut(BLOCK)) {
            self.log_block(xs, &mut r, &mut d, &mut ok, &mut ll);
            os.copy_from_slice(&ll[..os.len()]);
        }
    }

    /// The log-likelihoods of a block of at most [`BLOCK`] particles `xs` into
    /// `ll[..xs.len()]` (the positions transposed into `r`, the residuals into `d`; the
    /// other lanes of `ll` are not meaningful).
    #[inline(always)]
    fn log_block(
        &self,
        xs: &[State],
        r: &mut [[f64; BLOCK]; 3],
        d: &mut [[f64; BLOCK]; 3],
        ok: &mut [bool; BLOCK],
        ll: &mut [f64; BLOCK],
    ) {
        for (i, xi) in xs.iter().enumerate() {
            (r[0][i], r[1][i], r[2][i]) = (xi[0], xi[1], xi[2]);
        }
        self.log_block_soa(r, xs.len(), d, ok, ll);
    }

    /// [`Likelihood::log_block`] of a block of `n` particles whose positions are already
    /// transposed into `r` (the same values).
    #[inline(always)]
    fn log_block_soa(
        &self,
        r: &[[f64; BLOCK]; 3],
        n: usize,
        d: &mut [[f64; BLOCK]; 3],
        ok: &mut [bool; BLOCK],
        ll: &mut [f64; BLOCK],
    ) {
        self.sensor.residuals_at(&self.z, &self.trig, r, n, d, ok);
        if self.gaussian {
            let c = &self.neg_half_inv_var;
            for (i, l) in ll.iter_mut().enumerate() {
                let v = c[0] * d[0][i] * d[0][i] + c[1] * d[1][i] * d[1][i];
                let v = v + c[2] * d[2][i] * d[2][i];
                *l = if ok[i] { v } else { f64::NEG_INFINITY };
            }
        } else {
            for (i, o) in ll.iter_mut().enumerate().take(n) {
                *o = if ok[i] {
                    (0..3)
                        .map(|k| self.noise.log_density(d[k][i], self.scales[k]))
                        .sum()
                } else {
                    f64::NEG_INFINITY
                };
            }
        }
    }

    /// The update pass of the transition-proposal kinds over a run of particles: the
    /// log-likelihoods `ll_i` ([`Likelihood::log`]'s bits) into `ll`, the new log-weights
    /// `l_i = logw_i + ll_i` into `logw_new`, and their maximum (NaN ignored, `-inf` if
    /// there is none; in four interleaved partial maxima per block). Run through
    /// [`simd::dispatch`]. With `soa` (`x` by blocks of [`BLOCK`], transposed: the
    /// filter's `soa`) the positions are read from it instead of transposed from `x`: the
    /// same values.
    fn weigh_many(
        &self,
        x: &[State],
        soa: Option<&[[[f64; BLOCK]; N]]>,
        logw: &[f64],
        logw_new: &mut [f64],
        ll: &mut [f64],
    ) -> f64 {
        simd::dispatch(
            #[inline(always)]
            || self.weigh_many_inline(x, soa, logw, logw_new, ll),
        )
    }

    /// [`Likelihood::weigh_many`]'s body, inlined into its [`simd::dispatch`].
    #[inline(always)]
    fn weigh_many_inline(
        &self,
        x: &[State],
        soa: Option<&[[[f64; BLOCK]; N]]>,
        logw: &[f64],
        logw_new: &mut [f64],
        ll: &mut [f64],
    ) -> f64 {
        let mut r = [[0.0; BLOCK]; 3];
        let mut d = [[0.0; BLOCK]; 3];
        let mut ok = [false; BLOCK];
        let mut llb = [0.0; BLOCK];
        let mut mx = [f64::NEG_INFINITY; 4];
        let blocks = x
            .chunks(BLOCK)
            .zip(logw.chunks(BLOCK))
            .zip(logw_new.chunks_mut(BLOCK))
            .zip(ll.chunks_mut(BLOCK));
        for (b, (((xs, lw), lwn), lls)) in blocks.enumerate() {
            let n = xs.len();
            let pos = soa
                .and_then(|p| p.get(b))
                .and_then(|sb| <&[[f64; BLOCK]; 3]>::try_from(&sb[..3]).ok());
            match pos {
                Some(rb) => self.log_block_soa(rb, n, &mut d, &mut ok, &mut llb),
                None => self.log_block(xs, &mut r, &mut d, &mut ok, &mut llb),
            }
            let mut l = [f64::NEG_INFINITY; BLOCK];
            for ((li, a), b) in l.iter_mut().zip(lw).zip(&llb) {
                *li = a + b;
            }
            lwn.copy_from_slice(&l[..n]);
            lls.copy_from_slice(&llb[..n]);
            for b in l.chunks_exact(4) {
                for (m, &v) in mx.iter_mut().zip(b) {
                    // `if l > m` keeps `m` for a NaN `l` (as max_ignoring_nan)
                    *m = if v > *m { v } else { *m };
                }
            }
        }
        mx.iter()
            .fold(f64::NEG_INFINITY, |m, &v| if v > m { v } else { m })
    }
}

/// A transition matrix with the CW structure in the canonical frame: the in-plane states
/// `(x, y, vx, vy)` (indices 0, 1, 3, 4) and the out-of-plane `(z, vz)` (2, 5) do not
/// couple, so `Phi x` takes 16 + 4 products instead of 36 (the particle loop's hot path).
struct CwBlocks {
    inp: [[f64; 4]; 4],
    out: [[f64; 2]; 2],
}

impl CwBlocks {
    const IN: [usize; 4] = [0, 1, 3, 4];
    const OUT: [usize; 2] = [2, 5];

    /// `Some` when every coupling entry of `phi` is exactly zero.
    fn of(phi: &Mat6) -> Option<Self> {
        let decoupled = Self::IN.iter().all(|&i| {
            Self::OUT
                .iter()
                .all(|&o| phi[(i, o)] == 0.0 && phi[(o, i)] == 0.0)
        });
        decoupled.then(|| Self {
            inp: Self::IN.map(|r| Self::IN.map(|c| phi[(r, c)])),
            out: Self::OUT.map(|r| Self::OUT.map(|c| phi[(r, c)])),
        })
    }

    #[inline(always)]
    fn apply(&self, x: &State) -> State {
        let a = [x[0], x[1], x[3], x[4]];
        let b = [x[2], x[5]];
        let dot4 = |row: &[f64; 4]| row[0] * a[0] + row[1] * a[1] + row[2] * a[2] + row[3] * a[3];
        let dot2 = |row: &[f64; 2]| row[0] * b[0] + row[1] * b[1];
        let [p0, p1, p3, p4] = self.inp.each_ref().map(dot4);
        let [p2, p5] = self.out.each_ref().map(dot2);
        State::new(p0, p1, p2, p3, p4, p5)
    }
}

/// One step of the transition `x <- Phi x + Gamma a + w`, `w ~ N(0, Q)`.
struct Transition {
    blocks: Option<CwBlocks>,
    phi: Mat6,
    u: State,
    /// the standard deviations of a diagonal `Q` (6 products instead of 36)
    diag: Option<State>,
    /// a square root of `Q`
    l: Mat6,
}

// the transition draws a block's normals of one component in one batch
const _: () = assert!(BLOCK == Ziggurat::BATCH);

/// A block's states, transition means and new states, transposed (reused block to block).
type SoaBlocks = ([[f64; BLOCK]; N], [[f64; BLOCK]; N], [[f64; BLOCK]; N]);

impl Transition {
    /// Draw the new particles `out[i]` from `x[i]` (and store the transition means in
    /// `xbar` when it is not empty); returns a number that is finite exactly when every
    /// new component is (the sum of `0 * v` over them: NaN once one is not).
    ///
    /// The normals come from four xoshiro256++
    /// lanes ([`Lanes::seed_from`]) derived from `rng` at the start of the call (`rng`
    /// advances by one word per lane, plus the words of the slow paths): the lanes are
    /// transient, so the filter's saved state stays `rng`'s four words and a restored filter
    /// continues identically; the draws are deterministic per seed and, since every
    /// parallel chunk derives its lanes from its own generator, independent of the thread
    /// count.
    ///
    /// Block by block: the block's `6 B` normals are drawn first, component by component
    /// (each component's `B` values in one batch of [`Ziggurat::fill_batch_lanes`]; a short
    /// last block by [`Ziggurat::fill`] from `rng`); then, for
    /// the CW block structure with a diagonal `Q` (paper 000's model), the transition
    /// `x_i <- Phi x_i + Gamma a + sqrt(Q) eps_i` runs on the transposed block, the same
    /// operations in the same order per particle as the scalar form (so the same bits),
    /// four particles per AVX2 instruction through [`crate::numerics::simd::dispatch`].
    ///
    /// With `idx` the input particle `j` is `x[idx[j]]` (`idx` as long as `out`: the
    /// resampling indices not yet applied, gathered by the block transposes instead of a
    /// copy of the cloud); without, `x[j]`.
    ///
    /// With `soa` (one block per [`BLOCK`] particles of `out`) the structure-of-arrays path
    /// (CW blocks, diagonal `Q`) also writes each block's new particles there, transposed
    /// (the lanes past a short last block unspecified), and returns whether it did; with
    /// `soa_in` as well (and no `idx`) it reads its input from `soa` (which then holds `x`,
    /// transposed: the same values) instead of transposing `x`.
    #[allow(clippy::too_many_arguments)]
    fn run(
        &self,
        x: &[State],
        idx: Option<&[usize]>,
        out: &mut [State],
        xbar: &mut [State],
        soa: Option<&mut [[[f64; BLOCK]; N]]>,
        soa_in: bool,
        rng: &mut PfRng,
    ) -> (f64, bool) {
        simd::dispatch_v3(
            #[inline(always)]
            |v3| self.run_inline(v3, x, idx, out, xbar, soa, soa_in, rng),
        )
    }

    /// [`Transition::run`]'s body, inlined into its [`simd::dispatch_v3`] (`v3`: the token
    /// for the block transposes' shuffles).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn run_inline(
        &self,
        v3: Option<simd::V3>,
        x: &[State],
        idx: Option<&[usize]>,
        out: &mut [State],
        xbar: &mut [State],
        mut soa: Option<&mut [[[f64; BLOCK]; N]]>,
        soa_in: bool,
        rng: &mut PfRng,
    ) -> (f64, bool) {
        let blockwise = self.blocks.is_some() && self.diag.is_some();
        let wrote = blockwise && soa.as_ref().is_some_and(|p| p.len() * BLOCK >= out.len());
        let soa_in = soa_in && wrote && idx.is_none();
        let mut g = rng.clone();
        let zig = Ziggurat::get();
        let mut lanes = Lanes::seed_from(&mut g);
        let mut bad = 0.0;
        let mut eps = [[0.0; BLOCK]; N];
        let mut scratch = ([[0.0; BLOCK]; N], [[0.0; BLOCK]; N], [[0.0; BLOCK]; N]);
        for (b, os) in out.chunks_mut(BLOCK).enumerate() {
            let n = os.len();
            let base = b * BLOCK;
            for e in eps.iter_mut() {
                match e.get_mut(..n) {
                    Some(e) if n < BLOCK => zig.fill(&mut g, e),
                    _ => zig.fill_batch_lanes(&mut lanes, &mut g, e),
                }
            }
            let xb_out = xbar.get_mut(base..(base + n));
            // the block's input: its own particles, or the whole set and its indices
            let (xs, ib) = match idx {
                Some(ix) => (x, Some(&ix[base..base + n])),
                None => (&x[base..base + n], None),
            };
            match (&self.blocks, &self.diag) {
                (Some(cw), Some(d)) => {
                    let sb = soa.as_deref_mut().and_then(|p| p.get_mut(b));
                    let io = sb.map(|sb| (sb, soa_in));
                    bad += self.block_soa(v3, cw, d, xs, ib, os, xb_out, io, &eps, &mut scratch);
                }
                _ => {
                    let mut xb_out = xb_out;
                    for (i, xn) in os.iter_mut().enumerate() {
                        let xi = &xs[ib.map_or(i, |ib| ib[i])];
                        let xb = match &self.blocks {
                            Some(cw) => cw.apply(xi) + self.u,
                            None => self.phi * *xi + self.u,
                        };
                        if let Some(slot) = xb_out.as_mut().and_then(|s| s.get_mut(i)) {
                            *slot = xb;
                        }
                        let e = State::from_fn(|k, _| eps[k][i]);
                        *xn = match &self.diag {
                            Some(d) => xb + e.component_mul(d),
                            None => xb + self.l * e,
                        };
                        bad += xn.iter().fold(0.0, |a, v| a + v * 0.0);
                    }
                }
            }
        }
        *rng = g;
        (bad, wrote)
    }

    /// One block of [`Transition::run`] in structure-of-arrays form (CW blocks, diagonal
    /// `Q`): `xb = Phi x + u` with the 16 + 4 products of [`CwBlocks::apply`] in its order,
    /// `x_new = xb + d * eps`.
    #[inline(always)]
    #[allow(clippy::too_many_arguments, clippy::needless_range_loop)]
    fn block_soa(
        &self,
        v3: Option<simd::V3>,
        cw: &CwBlocks,
        d: &State,
        xs: &[State],
        ib: Option<&[usize]>,
        os: &mut [State],
        xb_out: Option<&mut [State]>,
        soa: Option<(&mut [[f64; BLOCK]; N], bool)>,
        eps: &[[f64; BLOCK]; N],
        scratch: &mut SoaBlocks,
    ) -> f64 {
        let (soa, soa_in) = match soa {
            Some((sb, i)) => (Some(sb), i),
            None => (None, false),
        };
        let (a, xb, xn_tmp) = (&mut scratch.0, &mut scratch.1, &mut scratch.2);
        match ib {
            // the block as the last step left it transposed: read in place below
            None if soa_in && soa.is_some() => {}
            None => rows_to_block(v3, xs, a),
            // gathered through the pending resampling's indices
            Some(ib) => gather_to_block(v3, xs, ib, a),
        }
        // (separate functions over distinct references: no aliasing for the vectoriser)
        match soa.as_deref() {
            Some(sb) if soa_in && ib.is_none() => self.cw_means(cw, sb, xb),
            _ => self.cw_means(cw, a, xb),
        }
        if let Some(xbo) = xb_out {
            block_to_rows(v3, xb, xbo);
        }
        // the new block straight into `soa` when given (its input was read)
        let bad = match soa {
            Some(sb) => Self::add_noise(v3, d, xb, eps, sb, os),
            None => Self::add_noise(v3, d, xb, eps, xn_tmp, os),
        };
        // only the block's own particles count (the padding holds stale values)
        bad.iter().take(os.len()).sum()
    }

    /// The transition means `xb = Phi a + u` of a transposed block `a` with the 16 + 4
    /// products of [`CwBlocks::apply`] in its order.
    #[inline(always)]
    fn cw_means(&self, cw: &CwBlocks, a: &[[f64; BLOCK]; N], xb: &mut [[f64; BLOCK]; N]) {
        let (p, q) = (&cw.inp, &cw.out);
        let u = &self.u;
        // row by row, the row's coefficients held in registers across the block's lanes
        // (lanes inside: each row's five broadcasts once per block instead of once per
        // vector); per particle the same operations in the same order
        let [i0, i1, i3, i4] = CwBlocks::IN;
        for (r, row) in CwBlocks::IN.iter().zip(p) {
            let (c, ur) = (*row, u[*r]);
            for i in 0..BLOCK {
                xb[*r][i] =
                    c[0] * a[i0][i] + c[1] * a[i1][i] + c[2] * a[i3][i] + c[3] * a[i4][i] + ur;
            }
        }
        let [o2, o5] = CwBlocks::OUT;
        for (r, row) in CwBlocks::OUT.iter().zip(q) {
            let (c, ur) = (*row, u[*r]);
            for i in 0..BLOCK {
                xb[*r][i] = c[0] * a[o2][i] + c[1] * a[o5][i] + ur;
            }
        }
    }

    /// `xn = xb + d * eps` lane by lane, also into `os` (one particle per lane); each
    /// lane's `sum_k 0 * xn_k` (NaN once one is not finite).
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // index loops over fixed lanes: they vectorise
    fn add_noise(
        v3: Option<simd::V3>,
        d: &State,
        xb: &[[f64; BLOCK]; N],
        eps: &[[f64; BLOCK]; N],
        xn: &mut [[f64; BLOCK]; N],
        os: &mut [State],
    ) -> [f64; BLOCK] {
        let mut bad = [0.0; BLOCK];
        for k in 0..N {
            for i in 0..BLOCK {
                xn[k][i] = xb[k][i] + eps[k][i] * d[k];
                bad[i] += xn[k][i] * 0.0;
            }
        }
        block_to_rows(v3, xn, os);
        bad
    }
}

/// The Gaussian around particle `i`'s transition mean that the unscented proposal updates
/// with the measurement: component `i` of the shrinkage kernel (see the module docs).
struct ShrinkKernel {
    a: f64,
    /// `(1 - a) m-`
    offset: State,
    cov: Mat6,
    l: Mat6,
    /// the Cholesky factor of `cov` the UKF's sigma points use (computed once for every
    /// particle; `None`: every particle's UKF step fails, as it would on its own)
    ukf_l: Option<Mat6>,
}

impl ShrinkKernel {
    /// The kernel of the predictive `N(m-, P-)` with process noise `q` and `n` particles:
    /// `a = sqrt(1 - h^2)`, covariance `(1 - h^2) Q + h^2 P-`.
    fn new(pred_mean: &State, pred_cov: &Mat6, q: &Mat6, n: usize) -> Option<Self> {
        let h2 = bandwidth(Kernel::Gaussian, n).powi(2);
        let a = (1.0 - h2).sqrt();
        let cov = symmetrize(&(q * (1.0 - h2) + pred_cov * h2));
        chol_loaded(&cov).map(|l| Self {
            a,
            offset: pred_mean * (1.0 - a),
            cov,
            l,
            ukf_l: cov.cholesky().map(|c| c.unpack()),
        })
    }
}

/// Everything the per-particle unscented proposal reads.
struct Unscented<'a, M> {
    /// a copy of the filter's sigma-point machinery (no heap: fixed-size)
    ukf: Ukf,
    lik: &'a Likelihood<'a, M>,
    sensor: &'a M,
    r: Mat3,
    z: Vec3,
    kernel: Option<ShrinkKernel>,
    /// square root of `Q` (the literal proposal's transition density)
    q_sqrt: Mat6,
    /// `half_logdet` of the factor the weights' `ln N(x; mu_i, .)` uses (the kernel's or
    /// `q_sqrt`: one for every particle)
    prior_half_logdet: f64,
    carry: bool,
    /// the shared-factor form of the UKF step, where every particle's UKF covariance is
    /// the one matrix (`None`: the per-particle UKF of [`Ukf::measurement_update`])
    shared: Option<SharedDraw>,
    /// the angles of `z`
    trig: AngleTrig,
}

/// The unscented proposal when every particle's UKF starts from one covariance
/// `P = L L^T` (the shrinkage kernel's; the literal proposal's `Q` when the covariances
/// are not carried): the UKF step of [`SharedPrior`] in `P`'s whitened coordinates,
/// `x = mu + L u`, `u = (step + M eps_(0..3), eps_(3..6))` with `eps ~ N(0, I)` (the
/// draw `m + L+ eps` with `L+ = L blockdiag(M, I)`, the same six normals in the same
/// order), and the weights' densities without a triangular solve per particle:
///
/// ```text
/// ln q(x)       = -|eps|^2 / 2 - ln det L - ln(M_00 M_11 M_22)
/// ln N(x; mu, .) = -|A u|^2 / 2 - ln det L_p,     A = L_p^-1 L (formed once; I when L_p = L)
/// ```
///
/// `L_p` the factor of the weights' prior density (the kernel's, or `sqrt Q`).
struct SharedDraw {
    prior: SharedPrior,
    /// `L_p^-1 L` (`None`: the identity)
    a: Option<Mat6>,
    /// `ln det L`
    half_logdet: f64,
    /// the covariance a particle must have for this path (the literal proposal, checked
    /// per particle; `None`: every particle, the kernel's)
    pc: Option<Mat6>,
}

impl SharedDraw {
    /// The shared form for UKF factor `l` and the weights' prior factor `prior_l`, with
    /// `ukf`'s sigma-point weights; `None` where it does not apply (every particle then
    /// takes the per-particle path).
    fn new(ukf: &Ukf, l: &Mat6, prior_l: &Mat6, pc: Option<Mat6>) -> Option<Self> {
        let a = if prior_l == l {
            None
        } else {
            Some(prior_l.solve_lower_triangular(l)?)
        };
        Some(Self {
            prior: ukf.shared_prior(l)?,
            a,
            half_logdet: half_logdet(l),
            pc,
        })
    }
}

impl<M: MeasurementModel> Unscented<'_, M> {
    /// Draw particle `i` from its UKF proposal: `(x, P_i, ln p(x|.) - ln q(x))`, `None`
    /// when the UKF step fails.
    fn draw(&self, xbar: &State, pc: &Mat6, rng: &mut PfRng) -> Option<(State, Mat6, f64)> {
        if let Some(sd) = &self.shared {
            // (compared entry by entry without early exit: nalgebra's `==` walks an
            // iterator, about 800 instructions; a slice `==` exits at the first difference,
            // about 140)
            if sd.pc.as_ref().is_none_or(|p| same_entries(p, pc)) {
                return self.draw_shared(sd, xbar, rng);
            }
        }
        let (mu, prior_l, update) = match &self.kernel {
            Some(k) => {
                let mu = xbar * k.a + k.offset;
                let u = self.ukf.measurement_update_factored(
                    &mu,
                    &k.cov,
                    k.ukf_l.as_ref()?,
                    self.sensor,
                    &self.r,
                    &self.z,
                );
                (mu, &k.l, u)
            }
            None => (
                *xbar,
                &self.q_sqrt,
                self.ukf
                    .measurement_update(xbar, pc, self.sensor, &self.r, &self.z),
            ),
        };
        let (m, p, _) = update.ok()?;
        let l = chol(&p)?;
        let eps = gauss6(rng);
        let x = m + l * eps;
        let half_logdet: f64 = (0..N).map(|k| l[(k, k)].ln()).sum();
        let log_q = -0.5 * eps.norm_squared() - half_logdet;
        let pc_new = if self.carry { p } else { Mat6::zeros() };
        Some((
            x,
            pc_new,
            log_gauss_with(&x, &mu, prior_l, self.prior_half_logdet) - log_q,
        ))
    }

    /// [`Unscented::draw`] by the shared-factor algebra ([`SharedDraw`]).
    fn draw_shared(
        &self,
        sd: &SharedDraw,
        xbar: &State,
        rng: &mut PfRng,
    ) -> Option<(State, Mat6, f64)> {
        let mu = match &self.kernel {
            Some(k) => xbar * k.a + k.offset,
            None => *xbar,
        };
        let wu = sd
            .prior
            .update(&mu, self.sensor, &self.r, &self.z, &self.trig)
            .ok()?;
        let eps = gauss6(rng);
        let m = &wu.m;
        let u = State::new(
            wu.step.x + m[(0, 0)] * eps[0],
            wu.step.y + m[(1, 0)] * eps[0] + m[(1, 1)] * eps[1],
            wu.step.z + m[(2, 0)] * eps[0] + m[(2, 1)] * eps[1] + m[(2, 2)] * eps[2],
            eps[3],
            eps[4],
            eps[5],
        );
        let x = mu + sd.prior.factor() * u;
        let log_q =
            -0.5 * eps.norm_squared() - sd.half_logdet - ln_pos(m[(0, 0)] * m[(1, 1)] * m[(2, 2)]);
        let up = sd.a.as_ref().map_or(u, |a| a * u);
        let log_p = -0.5 * up.norm_squared() - self.prior_half_logdet;
        let pc_new = if self.carry {
            let f = wu.factor(&sd.prior);
            f * f.transpose()
        } else {
            Mat6::zeros()
        };
        Some((x, pc_new, log_p - log_q))
    }

    /// [`Unscented::run`] on one block of at most [`BLOCK`] particles by the shared-factor
    /// algebra (covariances not carried), in structure-of-arrays form: the particles'
    /// whitened updates at once ([`SharedPrior::update_block`], lanes outside its fast path
    /// redone by [`SharedPrior::update`]), then the normals particle by particle in the
    /// old order (a particle whose update fails draws none, a particle whose covariance
    /// is not the shared one takes [`Unscented::draw`]), then the draws `x = mu + L u`
    /// and both log-densities at once, and the likelihoods by [`Likelihood::log_many`].
    /// The same operations in the same order per particle as [`Unscented::draw_shared`]
    /// and [`Likelihood::log`], so the same bits (tested); the arithmetic loops run in
    /// [`simd::dispatch`].
    #[allow(clippy::too_many_arguments, clippy::needless_range_loop)]
    fn run_shared_block(
        &self,
        sd: &SharedDraw,
        x: &[State],
        xbar: &[State],
        pc: &[Mat6],
        logw: &[f64],
        x_new: &mut [State],
        pc_new: &mut [Mat6],
        logw_new: &mut [f64],
        loglik: &mut [f64],
        rng: &mut PfRng,
        wb: &mut WhitenedBlock<BLOCK>,
    ) {
        let n = x.len();
        debug_assert!(n <= BLOCK);
        // transition means, transposed, and the shrinkage kernel's centres
        let mut mu = [[0.0; BLOCK]; N];
        for (i, xb) in xbar.iter().enumerate() {
            for k in 0..N {
                mu[k][i] = xb[k];
            }
        }
        if let Some(kn) = &self.kernel {
            let (a, off) = (kn.a, kn.offset);
            for k in 0..N {
                for i in 0..BLOCK {
                    mu[k][i] = mu[k][i] * a + off[k];
                }
            }
        }
        let c = [mu[0], mu[1], mu[2]];
        simd::dispatch(
            #[inline(always)]
            || {
                sd.prior
                    .update_block(&c, self.sensor, &self.r, &self.z, &self.trig, wb)
            },
        );
        // lane by lane in order: the per-particle fallbacks and the normals
        let mut eps = [[0.0; BLOCK]; N];
        // 0: failed (no draw), 1: the shared draw, 2: `draw`'s own result (in `x_new`)
        let mut lane = [0u8; BLOCK];
        let mut own_corr = [0.0; BLOCK];
        for i in 0..n {
            let eligible = sd.pc.as_ref().is_none_or(|p| same_entries(p, &pc[i]));
            if !eligible {
                if let Some((xi, _, corr)) = self.draw(&xbar[i], &pc[i], rng) {
                    x_new[i] = xi;
                    own_corr[i] = corr;
                    lane[i] = 2;
                }
                continue;
            }
            if !wb.fast[i] {
                let m = State::from_fn(|k, _| mu[k][i]);
                match sd
                    .prior
                    .update(&m, self.sensor, &self.r, &self.z, &self.trig)
                {
                    Ok(wu) => {
                        for k in 0..3 {
                            wb.step[k][i] = wu.step[k];
                        }
                        let ml = lower6(&wu.m);
                        for k in 0..6 {
                            wb.m[k][i] = ml[k];
                        }
                    }
                    Err(_) => continue,
                }
            }
            let e = gauss6(rng);
            for k in 0..N {
                eps[k][i] = e[k];
            }
            lane[i] = 1;
        }
        // the draws and the densities (without the logarithm), every lane
        let l = sd.prior.factor();
        let mut xs = [[0.0; BLOCK]; N];
        let (mut prod, mut ln_prod) = ([0.0; BLOCK], [0.0; BLOCK]);
        let mut log_p = [0.0; BLOCK];
        let mut half_e2 = [0.0; BLOCK];
        let (hl, phl) = (sd.half_logdet, self.prior_half_logdet);
        simd::dispatch(
            #[inline(always)]
            || {
                for i in 0..BLOCK {
                    let (st, m) = (&wb.step, &wb.m);
                    let e: [f64; N] = std::array::from_fn(|k| eps[k][i]);
                    let u = [
                        st[0][i] + m[0][i] * e[0],
                        st[1][i] + m[1][i] * e[0] + m[3][i] * e[1],
                        st[2][i] + m[2][i] * e[0] + m[4][i] * e[1] + m[5][i] * e[2],
                        e[3],
                        e[4],
                        e[5],
                    ];
                    // `mu + L u`, L lower triangular, in nalgebra's column order
                    for r in 0..N {
                        let mut y = l[(r, 0)] * u[0];
                        for j in 1..=r {
                            y += l[(r, j)] * u[j];
                        }
                        xs[r][i] = mu[r][i] + y;
                    }
                    // `|A u|^2` (A = I: `|u|^2`), summed from zero as nalgebra does
                    let up: [f64; N] = match &sd.a {
                        Some(a) => std::array::from_fn(|r| {
                            let mut y = a[(r, 0)] * u[0];
                            for j in 1..N {
                                y += a[(r, j)] * u[j];
                            }
                            y
                        }),
                        None => u,
                    };
                    let mut s = 0.0;
                    for v in up {
                        s += v * v;
                    }
                    log_p[i] = -0.5 * s - phl;
                    let mut s = 0.0;
                    for v in e {
                        s += v * v;
                    }
                    half_e2[i] = -0.5 * s - hl;
                    prod[i] = m[0][i] * m[3][i] * m[5][i];
                }
                for i in 0..BLOCK {
                    ln_prod[i] = ln_normal(prod[i]);
                }
            },
        );
        // in a dispatch: the AVX2 path zeroes each covariance slot (not carried) inline,
        // nine 32-byte stores, where the baseline calls `memset` per particle
        simd::dispatch(
            #[inline(always)]
            || {
                for i in 0..n {
                    match lane[i] {
                        1 => {
                            x_new[i] = State::from_fn(|k, _| xs[k][i]);
                            // `ln_pos` (as `draw_shared`), its rare libm lanes here
                            let lp = if is_normal_pos(prod[i]) {
                                ln_prod[i]
                            } else {
                                prod[i].ln()
                            };
                            let log_q = half_e2[i] - lp;
                            own_corr[i] = log_p[i] - log_q;
                        }
                        2 => {}
                        _ => {
                            x_new[i] = x[i];
                            own_corr[i] = 0.0;
                        }
                    }
                    pc_new[i] = Mat6::zeros();
                }
            },
        );
        let mut ll = [0.0; BLOCK];
        self.lik.log_many(x_new, &mut ll[..n]);
        for i in 0..n {
            logw_new[i] = logw[i] + ll[i] + own_corr[i];
            loglik[i] = ll[i];
        }
    }

    /// The proposals of a run of particles: new particles, covariances, log-weights and
    /// log-likelihoods into the spare buffers.
    #[allow(clippy::too_many_arguments)]
    fn run(
        &self,
        x: &[State],
        xbar: &[State],
        pc: &[Mat6],
        logw: &[f64],
        x_new: &mut [State],
        pc_new: &mut [Mat6],
        logw_new: &mut [f64],
        loglik: &mut [f64],
        rng: &mut PfRng,
    ) {
        if let (Some(sd), false) = (&self.shared, self.carry) {
            let mut wb = WhitenedBlock::<BLOCK>::default();
            for (b, xs) in x.chunks(BLOCK).enumerate() {
                let r = b * BLOCK..b * BLOCK + xs.len();
                self.run_shared_block(
                    sd,
                    xs,
                    &xbar[r.clone()],
                    &pc[r.clone()],
                    &logw[r.clone()],
                    &mut x_new[r.clone()],
                    &mut pc_new[r.clone()],
                    &mut logw_new[r.clone()],
                    &mut loglik[r],
                    rng,
                    &mut wb,
                );
            }
            return;
        }
        for i in 0..x.len() {
            let (xi, pci, corr) = match self.draw(&xbar[i], &pc[i], rng) {
                Some(d) => d,
                // without carrying, every covariance starts afresh at the next prediction
                None => (x[i], if self.carry { pc[i] } else { Mat6::zeros() }, 0.0),
            };
            let ll = self.lik.log(&xi);
            x_new[i] = xi;
            pc_new[i] = pci;
            logw_new[i] = logw[i] + ll + corr;
            loglik[i] = ll;
        }
    }
}

/// A particle filter over the canonical 6-state (see the module documentation).
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
    /// ([`exp_moments_soa`], which transposes `x` here first when the copy is not current)
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

/// Six independent standard normals (one batch of [`Ziggurat::fill`]).
#[inline(always)]
fn gauss6<R: Rng + ?Sized>(rng: &mut R) -> State {
    let mut e = [0.0; N];
    Ziggurat::get().fill(rng, &mut e);
    State::from(e)
}

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

    fn draw_prior(&mut self) {
        self.pending = false;
        self.soa_fresh = false;
        // the prior is validated (diagonal, finite); a matrix set through `set_estimate`
        // that has no square root falls back to the square roots of its diagonal
        let l = psd_sqrt(&self.p0)
            .unwrap_or_else(|| Mat6::from_diagonal(&self.p0.diagonal().map(|v| v.max(0.0).sqrt())));
        for xi in self.x.iter_mut() {
            *xi = self.x0 + l * gauss6(&mut self.rng);
        }
        self.xbar.iter_mut().for_each(|xb| *xb = self.x0);
        self.pc.iter_mut().for_each(|p| *p = self.p0);
        let n = self.x.len() as f64;
        self.logw.iter_mut().for_each(|v| *v = 0.0);
        self.w.iter_mut().for_each(|v| *v = 1.0 / n);
        self.awaiting_first = self.params.init == PfInit::FirstMeasurement;
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
    fn materialise(&mut self) {
        if self.pending {
            self.apply_resampling();
            self.pending = false;
        }
    }

    /// Whether the particle loops run in chunks (the parallel path).
    fn chunked(&self) -> bool {
        !self.chunk_rng.is_empty()
    }

    /// Remember the chunk generators before a step that may fail.
    fn save_chunk_rngs(&mut self) {
        self.chunk_rng_saved.clone_from_slice(&self.chunk_rng);
    }

    fn restore_chunk_rngs(&mut self) {
        self.chunk_rng.clone_from_slice(&self.chunk_rng_saved);
    }

    /// Weighted mean of the particles; the covariance is computed when first asked for
    /// ([`ParticleFilter::cov`]).
    fn summarise(&mut self) {
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
    fn cov(&self) -> &Mat6 {
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

    /// Positions from the measurement's likelihood, velocities from the prior.
    fn init_from_measurement<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
        noise: &NoiseModel,
        scales: &[f64; 3],
    ) -> Result<(), FilterError> {
        // the velocity rows of a square root of the prior draw from its velocity marginal
        let l = psd_sqrt(&self.prior_cov).ok_or(FilterError::NonFinite("prior covariance"))?;
        for i in 0..self.x.len() {
            let mut zi = *z;
            let mut st = 0.0;
            for k in 0..3 {
                zi[k] -= noise.sample(scales[k], &mut st, &mut self.rng);
            }
            let r = sensor
                .invert(&zi)
                .ok_or(FilterError::NonFinite("measurement inversion"))?;
            let v =
                self.prior_mean.fixed_rows::<3>(3) + (l * gauss6(&mut self.rng)).fixed_rows::<3>(3);
            self.x_tmp[i] = State::new(r.x, r.y, r.z, v.x, v.y, v.z);
            if let Some(xb) = self.xbar_tmp.get_mut(i) {
                *xb = self.x_tmp[i];
            }
        }
        // commit only when every particle was drawn, and drawn finite
        if !self.x_tmp.iter().all(|x| x.iter().all(|v| v.is_finite())) {
            return Err(FilterError::NonFinite(
                "particles drawn from the measurement",
            ));
        }
        std::mem::swap(&mut self.x, &mut self.x_tmp);
        std::mem::swap(&mut self.xbar, &mut self.xbar_tmp);
        Ok(())
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
        std::mem::swap(&mut self.x, &mut self.x_tmp);
        std::mem::swap(&mut self.loglik, &mut self.loglik_tmp);
        if !self.pc.is_empty() {
            for (k, &i) in self.idx.iter().enumerate() {
                self.xbar_tmp[k] = self.xbar[i];
            }
            std::mem::swap(&mut self.xbar, &mut self.xbar_tmp);
            // not carried, the covariances are all equal (zero after an update): nothing
            // to reorder
            if self.params.carry_covariance {
                for (k, &i) in self.idx.iter().enumerate() {
                    self.pc_tmp[k] = self.pc[i];
                }
                std::mem::swap(&mut self.pc, &mut self.pc_tmp);
            }
        }
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
    /// one pass ([`Likelihood::weigh_many`]); their maximum (per chunk on the parallel path).
    /// `fresh`: `soa` holds the particles (transposed, serial path).
    fn weigh<M: MeasurementModel>(&mut self, lik: &Likelihood<'_, M>, fresh: bool) -> f64 {
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
        let fresh = std::mem::take(&mut self.soa_fresh);
        self.materialise();
        if self.awaiting_first {
            self.init_from_measurement(sensor, z, noise, scales)?;
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
            return Ok(UpdateInfo {
                innovation: Vec3::zeros(),
                nis: f64::NAN,
                azimuth_used: true,
            });
        }
        let lik = Likelihood::new(sensor, z, noise, scales);
        let kind = self.params.kind;
        // the predictive density as a Gaussian: the prior part of the moves' target
        (self.pred_mean, self.pred_cov) = if self.prior_mode {
            (self.prior_mean, self.prior_cov)
        } else {
            (self.mean, *self.cov())
        };
        let needs_pred_l = match kind {
            PfKind::Rpf => self.params.moves,
            PfKind::Gapf | PfKind::Cgapf => true,
            PfKind::Sir | PfKind::Upf => false,
        };
        if needs_pred_l {
            self.pred_l = chol_loaded(&self.pred_cov).ok_or(FilterError::NotPositiveDefinite(
                "predictive covariance of the particles",
            ))?;
        }
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
                    ukf: self.ukf.clone(),
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
        std::mem::swap(&mut self.w, &mut self.scratch);
        std::mem::swap(&mut self.logw, &mut self.logw_tmp);
        if kind.unscented() {
            std::mem::swap(&mut self.x, &mut self.x_tmp);
            std::mem::swap(&mut self.pc, &mut self.pc_tmp);
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
            // whose `rep stosb` is one counted instruction per byte (12 000 per step at
            // N = 1500, measured; the same time on hardware)
            let zero = std::hint::black_box(0.0);
            self.logw.iter_mut().for_each(|v| *v = zero);
            self.resamples += 1;
            // the plain RPF's jitter and the literal GA-PF's operators set the summary of
            // the moved set themselves
            let mut summarised = false;
            match kind {
                PfKind::Rpf if self.params.moves => self.regularise_mh(&lik, &cov_before),
                PfKind::Rpf => {
                    summarised = self.regularise(self.params.kernel, &cov_before, jitter_gathers)
                }
                PfKind::Gapf => summarised = self.genetic_moves(&lik, &cov_before),
                PfKind::Cgapf => self.cloud_moves(&lik),
                PfKind::Sir | PfKind::Upf => {}
            }
            // the weighted moments before a plain resampling are kept (lower variance
            // than the resampled set's); moved particles are summarised again
            if !self.params.moves && !summarised && !matches!(kind, PfKind::Sir | PfKind::Upf) {
                self.summarise();
            }
        }
        if self.params.moves && !self.rejuvenate(&lik, sensor, z) {
            self.summarise();
        }
        // particles left as the transition drew them: `soa` still holds them
        if fresh && !resampling && !self.params.moves && !kind.unscented() {
            self.soa_fresh = true;
        }
        self.prior_mode = false;
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

    /// The unscented kinds' first update from the Gaussian prior ([`PfInit::Prior`]):
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

/// `a == b` entry by entry (IEEE `==`: a NaN differs from everything, `0 == -0`), all 36
/// comparisons and-ed without an early exit so that they vectorise: the UPF's test whether
/// a particle's covariance is the shared one, once per particle.
#[inline(always)]
fn same_entries(a: &Mat6, b: &Mat6) -> bool {
    a.as_slice()
        .iter()
        .zip(b.as_slice())
        .fold(true, |all, (x, y)| all & (x == y))
}

/// The normalisation's exponentials `w_i = exp(l_i - max)` (0 for a NaN `l_i`), vectorised
/// across particles ([`exp_nonpos`]); inlined into its caller's [`simd::dispatch`].
#[inline(always)]
fn exp_weights(w: &mut [f64], logw: &[f64], max: f64) {
    for (e, &l) in w.iter_mut().zip(logw) {
        *e = if l.is_nan() { 0.0 } else { exp_nonpos(l - max) };
    }
}

/// The normalisation's exponentials and the weighted moments in one pass over a run of
/// particles: `w_i = exp(l_i - max)` (0 for a NaN `l_i`: the bits of
/// [`resample::normalize_log_weights`] before its division), their sum in sixteen lanes
/// ([`lane_sum`]: its bits too) and the [`Moments`] about `reference` with the weights `w_i`
/// ([`PointSums`]: each sum, the moments' weight sum included, one chain in particle order,
/// at rounding level from the lanes'). The exponentials
/// run a block of [`BLOCK`] at a time (vectorised across particles), the moments particle by
/// particle. `max` is the largest `l_i` (finite). Run through [`simd::dispatch`].
fn exp_moments(
    reference: &State,
    x: &[State],
    logw: &[f64],
    max: f64,
    w: &mut [f64],
) -> (f64, Moments) {
    simd::dispatch(
        #[inline(always)]
        || exp_moments_inline(reference, x, logw, max, w),
    )
}

/// [`exp_moments`]' body, inlined into its [`simd::dispatch`].
#[inline(always)]
fn exp_moments_inline(
    reference: &State,
    x: &[State],
    logw: &[f64],
    max: f64,
    w: &mut [f64],
) -> (f64, Moments) {
    exp_weights(w, logw, max);
    let rc: [f64; N] = std::array::from_fn(|k| reference[k]);
    let mut acc = PointSums::new();
    for (xi, &wi) in x.iter().zip(w.iter()) {
        acc.add(xi, &rc, wi);
    }
    (lane_sum(w), acc.finish(reference))
}

/// [`exp_moments`] with the particles read from their transposed copy `soa` (one block per
/// [`BLOCK`] particles, at least `w.len()` particles; the filter's `soa` when current):
/// the same weights and weight sum, bit for bit; the moments from [`LaneSums`] (four lanes
/// per sum instead of one chain: at rounding level from [`exp_moments`]'). A short last
/// block is copied with its padding set to `reference` (offset zero) and weight zero.
fn exp_moments_soa(
    reference: &State,
    soa: &[[[f64; BLOCK]; N]],
    logw: &[f64],
    max: f64,
    w: &mut [f64],
) -> (f64, Moments) {
    simd::dispatch(
        #[inline(always)]
        || exp_moments_soa_inline(reference, soa, logw, max, w),
    )
}

/// [`exp_moments_soa`]'s body, inlined into its [`simd::dispatch`].
#[inline(always)]
fn exp_moments_soa_inline(
    reference: &State,
    soa: &[[[f64; BLOCK]; N]],
    logw: &[f64],
    max: f64,
    w: &mut [f64],
) -> (f64, Moments) {
    exp_weights(w, logw, max);
    // in lanes: the bits of the normalisation's sum
    let sum = lane_sum(w);
    let acc = LaneSums::of_soa::<true>(reference, soa, w.len(), w);
    (sum, acc.finish(reference, sum))
}

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
        let soa_in = std::mem::take(&mut self.soa_fresh);
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
        std::mem::swap(&mut self.x, &mut self.x_tmp);
        std::mem::swap(&mut self.xbar, &mut self.xbar_tmp);
        self.soa_fresh = fresh;
        if self.pending {
            // the particles were gathered: the log-likelihoods follow
            for (o, &i) in self.loglik_tmp.iter_mut().zip(&self.idx) {
                *o = self.loglik[i];
            }
            std::mem::swap(&mut self.loglik, &mut self.loglik_tmp);
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

/// Saved state (see `docs/state-format.md`): the particle count `n` and the count `m` of
/// per-particle proposal means and covariances (`n` for the unscented kinds, else 0), the
/// prior `x0`, `P0`; per particle the state, proposal mean and covariance, log-weight,
/// weight, log-likelihood and the pairing permutation (u32; the genetic moves shuffle it in
/// place, so its order is state); then the weighted mean, the cached covariance (if
/// computed), the ESS, the initialisation flags, the Gaussian prior and its factor, the
/// move steps' predictive Gaussian (mean, covariance, factor), the generator's four state
/// words and those of every chunk generator of the parallel path (one per 4096 particles
/// from `PARALLEL_MIN_PARTICLES` on, none below), the cached `Q`, its square root and
/// definiteness, and the counters (resamplings, moves tried and accepted). The settings,
/// the worker pool and the unscented proposal's weights are configuration; the `*_tmp`,
/// `idx` and `scratch` buffers and the chunk generators' saved copies are
/// overwritten by every step before they are read, and the transposed copy `soa` is not
/// saved (marked stale by a load).
impl Persist for ParticleFilter {
    fn save_state(&self, w: &mut Writer<'_>) {
        let Self {
            params: _,
            x0,
            p0,
            x,
            xbar,
            pc,
            x_tmp: _,
            xbar_tmp: _,
            pc_tmp: _,
            logw,
            logw_tmp: _,
            w: weights,
            loglik,
            loglik_tmp: _,
            idx,
            pending,
            perm,
            soa: _,
            soa_fresh: _,
            scratch: _,
            mean,
            cov,
            ess,
            awaiting_first,
            prior_mode,
            prior_mean,
            prior_cov,
            prior_l,
            pred_mean,
            pred_cov,
            pred_l,
            rng,
            chunk_rng,
            chunk_rng_saved,
            pool: _,
            q_key,
            q_sqrt,
            q_pd,
            ukf: _,
            resamples,
            moves_tried,
            moves_accepted,
        } = self;
        w.usize(x.len());
        w.usize(pc.len());
        w.matrix(x0);
        w.matrix(p0);
        // a pending index-only resampling is saved applied (the layout is unchanged)
        let order = |k: usize| if *pending { idx[k] } else { k };
        (0..x.len()).for_each(|k| w.matrix(&x[order(k)]));
        xbar.iter().for_each(|v| w.matrix(v));
        pc.iter().for_each(|v| w.matrix(v));
        logw.iter().for_each(|v| w.f64(*v));
        weights.iter().for_each(|v| w.f64(*v));
        (0..loglik.len()).for_each(|k| w.f64(loglik[order(k)]));
        perm.iter().for_each(|v| w.u32(*v as u32));
        w.matrix(mean);
        w.opt_matrix(cov.get());
        w.f64(*ess);
        w.bool(*awaiting_first);
        w.bool(*prior_mode);
        w.matrix(prior_mean);
        w.matrix(prior_cov);
        w.matrix(prior_l);
        w.matrix(pred_mean);
        w.matrix(pred_cov);
        w.matrix(pred_l);
        for g in std::iter::once(rng).chain(chunk_rng.iter()) {
            for word in rng_state(g).unwrap_or([0; 4]) {
                w.u64(word);
            }
        }
        // the saved copies are rewritten at the start of every step before they are read
        let _ = chunk_rng_saved;
        w.matrix(q_key);
        w.matrix(q_sqrt);
        w.bool(*q_pd);
        w.u64(*resamples);
        w.u64(*moves_tried);
        w.u64(*moves_accepted);
    }

    fn load_state(&mut self, r: &mut Reader<'_>) -> Result<(), StateError> {
        let Self {
            params: _,
            x0,
            p0,
            x,
            xbar,
            pc,
            x_tmp: _,
            xbar_tmp: _,
            pc_tmp: _,
            logw,
            logw_tmp: _,
            w: weights,
            loglik,
            loglik_tmp: _,
            idx,
            pending,
            perm,
            soa: _,
            soa_fresh,
            scratch: _,
            mean,
            cov,
            ess,
            awaiting_first,
            prior_mode,
            prior_mean,
            prior_cov,
            prior_l,
            pred_mean,
            pred_cov,
            pred_l,
            rng,
            chunk_rng,
            chunk_rng_saved,
            pool: _,
            q_key,
            q_sqrt,
            q_pd,
            ukf: _,
            resamples,
            moves_tried,
            moves_accepted,
        } = self;
        let n = x.len();
        let _ = idx;
        *soa_fresh = false;
        r.count("particle count", n)?;
        r.count("per-particle proposal count", pc.len())?;
        *x0 = r.matrix("prior mean x0")?;
        *p0 = r.matrix("prior covariance P0")?;
        for v in x.iter_mut() {
            *v = r.finite_matrix("particle")?;
        }
        // the particles were saved with any pending resampling applied
        *pending = false;
        for v in xbar.iter_mut() {
            *v = r.matrix("particle proposal mean")?;
        }
        for v in pc.iter_mut() {
            *v = r.matrix("particle proposal covariance")?;
        }
        for v in logw.iter_mut() {
            *v = r.f64("log-weight")?;
        }
        for v in weights.iter_mut() {
            *v = r.finite("weight")?;
            if *v < 0.0 {
                return Err(refuse(format!("a particle weight is negative ({v})")));
            }
        }
        for v in loglik.iter_mut() {
            *v = r.f64("log-likelihood")?;
        }
        let mut seen = vec![false; n];
        for v in perm.iter_mut() {
            let i = r.u32("pairing permutation")? as usize;
            match seen.get_mut(i) {
                Some(s) if !*s => *s = true,
                _ => {
                    return Err(refuse(format!(
                        "the pairing permutation is not a permutation of 0..{n} (entry {i})"
                    )))
                }
            }
            *v = i;
        }
        *mean = r.matrix("weighted mean")?;
        *cov = match r.opt_matrix("weighted covariance")? {
            Some(c) => OnceCell::from(c),
            None => OnceCell::new(),
        };
        *ess = r.f64("effective sample size")?;
        *awaiting_first = r.bool("awaiting-first-measurement flag")?;
        *prior_mode = r.bool("prior-mode flag")?;
        *prior_mean = r.matrix("prior mean")?;
        *prior_cov = r.matrix("prior covariance")?;
        *prior_l = r.matrix("prior covariance factor")?;
        *pred_mean = r.matrix("predictive mean")?;
        *pred_cov = r.matrix("predictive covariance")?;
        *pred_l = r.matrix("predictive covariance factor")?;
        for g in std::iter::once(rng).chain(chunk_rng.iter_mut()) {
            let mut s = [0u64; 4];
            for word in s.iter_mut() {
                *word = r.u64("generator state")?;
            }
            *g = rng_from_state(s).ok_or_else(|| {
                refuse("a particle filter's generator state is all zero (not a xoshiro256++ state)")
            })?;
        }
        chunk_rng_saved.clone_from(chunk_rng);
        *q_key = r.matrix("cached process noise")?;
        *q_sqrt = r.matrix("cached square root of the process noise")?;
        *q_pd = r.bool("process-noise definiteness flag")?;
        *resamples = r.u64("resampling count")?;
        *moves_tried = r.u64("moves tried")?;
        *moves_accepted = r.u64("moves accepted")?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::resample::normalize_log_weights;
    use super::*;
    use crate::dynamics::{CwModel, Discretization};

    /// The block product equals `Phi x` for the exact CW transition, and a coupled matrix
    /// (Euler's is not coupled either; a rotated one is) falls back to the full product.
    #[test]
    fn cw_blocks_equal_the_full_product() {
        let m = CwModel::new(2.0 * std::f64::consts::PI / 5400.0);
        for dt in [0.1, 1.0, 600.0] {
            for disc in [Discretization::Exact, Discretization::Euler] {
                let phi = m.discretize(dt, &Mat3::zeros(), disc).phi;
                let b = CwBlocks::of(&phi).expect("CW transition is block-structured");
                for k in 0..20 {
                    let x = State::from_fn(|i, _| ((i * 7 + k * 3) as f64).sin() * 300.0);
                    let d = b.apply(&x) - phi * x;
                    assert!(d.abs().max() <= 1e-12 * (phi * x).abs().max(), "{d:?}");
                }
            }
        }
        let mut coupled = Mat6::identity();
        coupled[(0, 2)] = 1e-3;
        assert!(CwBlocks::of(&coupled).is_none());
    }

    /// The unscented proposal's shared-factor blocks ([`Unscented::run_shared_block`])
    /// equal the particle-by-particle path ([`Unscented::draw`] and [`Likelihood::log`])
    /// bit for bit, with the same normals drawn in the same order, on the dispatched and the
    /// baseline path: the shrinkage kernel and the literal proposal (some particles with
    /// another covariance: `draw`'s per-particle UKF), particles in the series domain,
    /// far off (the per-particle fallback), on the pole and at zero range (failures), a
    /// short last block, in every frame.
    #[test]
    fn shared_blocks_equal_the_per_particle_proposal() {
        use crate::numerics::simd::with_baseline;
        use crate::sensors::RadioSensor;
        let mut g = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let q = Mat6::from_diagonal(&State::new(0.09, 6.25e-4, 2.5e-3, 1e-6, 1e-6, 1e-6));
        let (mut fast_lanes, mut wide_lanes) = (0, 0);
        for frame in crate::frames::Frame::ALL {
            let s = RadioSensor::new(frame, 0.5, 1e-3);
            let c = frame.vec_to_canonical(&Vec3::new(400.0, 500.0, -200.0));
            let z = s.predict(&c).expect("defined") + Vec3::new(0.2, -1e-3, 3e-3);
            let noise = NoiseModel::Gaussian;
            let lik = Likelihood::new(&s, &z, &noise, &[0.5, 1e-3, 1e-3]);
            let n = 403;
            let x: Vec<State> = (0..n)
                .map(|k| {
                    let mut v = State::from_fn(|i, _| {
                        g.random_range(-1.0..1.0) * if i < 3 { 3.0 } else { 0.01 }
                    });
                    let pole = frame.vec_to_canonical(&Vec3::new(0.0, 0.0, 300.0));
                    let base = match k % 37 {
                        0 => {
                            v.fill(0.0);
                            Vec3::zeros()
                        }
                        1 => {
                            v.fixed_rows_mut::<3>(0).fill(0.0);
                            pole
                        }
                        2 => c * 1.5,
                        3 => Vec3::zeros(),
                        // off the measurement by about 0.06 rad across and along the
                        // horizon (innovation angles beyond the series' 2^-5)
                        4 => c + c.cross(&Vec3::x()).normalize() * 40.0,
                        5 => c + c.cross(&Vec3::z()).normalize() * 40.0,
                        _ => c,
                    };
                    for i in 0..3 {
                        v[i] += base[i];
                    }
                    v
                })
                .collect();
            let mean = x.iter().sum::<State>() / n as f64;
            let pred_cov = Mat6::from_diagonal(&State::new(4.0, 4.0, 4.0, 1e-4, 1e-4, 1e-4));
            let ukf = Ukf::new(State::zeros(), Mat6::identity(), UkfParams::default());
            let q_sqrt = psd_sqrt(&q).expect("PSD");
            let pq = q.cholesky().expect("PD").unpack();
            for literal in [false, true] {
                let kernel = if literal {
                    None
                } else {
                    Some(ShrinkKernel::new(&mean, &pred_cov, &q, n).expect("PD"))
                };
                let shared = match &kernel {
                    Some(k) => SharedDraw::new(&ukf, &k.ukf_l.expect("PD"), &k.l, None),
                    None => SharedDraw::new(&ukf, &pq, &q_sqrt, Some(q)),
                };
                let u = Unscented {
                    ukf: ukf.clone(),
                    lik: &lik,
                    sensor: &s,
                    r: s.noise_cov(),
                    z,
                    prior_half_logdet: half_logdet(kernel.as_ref().map_or(&q_sqrt, |k| &k.l)),
                    kernel,
                    q_sqrt,
                    carry: false,
                    shared,
                    trig: AngleTrig::of(&z),
                };
                let sd = u.shared.as_ref().expect("the shared form applies");
                // the literal proposal: every fifth particle with another covariance
                let pc: Vec<Mat6> = (0..n)
                    .map(|k| if literal && k % 5 == 0 { q * 2.0 } else { q })
                    .collect();
                let logw: Vec<f64> = (0..n).map(|k| -(k as f64) * 1e-3).collect();
                let rng0 = PfRng::seed_from_u64(9);
                // the per-particle reference
                let mut rng = rng0.clone();
                let mut want = Vec::new();
                for i in 0..n {
                    let (xi, corr) = match u.draw(&x[i], &pc[i], &mut rng) {
                        Some((xi, _, corr)) => (xi, corr),
                        None => (x[i], 0.0),
                    };
                    let ll = lik.log(&xi);
                    want.push((xi, logw[i] + ll + corr, ll));
                }
                let after = rng.random::<u64>();
                let run = || {
                    let mut rng = rng0.clone();
                    let mut xn = vec![State::zeros(); n];
                    let mut pcn = vec![Mat6::identity(); n];
                    let (mut lwn, mut ll) = (vec![0.0; n], vec![0.0; n]);
                    u.run(
                        &x, &x, &pc, &logw, &mut xn, &mut pcn, &mut lwn, &mut ll, &mut rng,
                    );
                    assert!(pcn.iter().all(|p| *p == Mat6::zeros()));
                    (xn, lwn, ll, rng.random::<u64>())
                };
                for (xn, lwn, ll, next) in [run(), with_baseline(run)] {
                    assert_eq!(next, after, "the same normals are drawn");
                    for i in 0..n {
                        let (wx, wlw, wll) = &want[i];
                        let same = xn[i]
                            .iter()
                            .zip(wx.iter())
                            .all(|(a, b)| a.to_bits() == b.to_bits());
                        assert!(same, "{frame:?} {literal} {i}: {} {}", xn[i], wx);
                        assert_eq!(lwn[i].to_bits(), wlw.to_bits(), "{frame:?} {literal} {i}");
                        assert_eq!(ll[i].to_bits(), wll.to_bits(), "{frame:?} {literal} {i}");
                    }
                }
                // most particles take the block's fast path
                let mut wb = WhitenedBlock::<BLOCK>::default();
                for (b, xs) in x.chunks(BLOCK).enumerate() {
                    let mut cb = [[0.0; BLOCK]; 3];
                    for (i, xi) in xs.iter().enumerate() {
                        let m = u.kernel.as_ref().map_or(*xi, |k| xi * k.a + k.offset);
                        (cb[0][i], cb[1][i], cb[2][i]) = (m[0], m[1], m[2]);
                    }
                    sd.prior.update_block(&cb, &s, &u.r, &z, &u.trig, &mut wb);
                    fast_lanes += wb.fast[..xs.len()].iter().filter(|f| **f).count();
                    // the particles off the measurement by 0.06 rad stay in the block
                    for (i, f) in wb.fast[..xs.len()].iter().enumerate() {
                        if matches!((b * BLOCK + i) % 37, 4 | 5) {
                            assert!(*f, "{frame:?} {literal} {i}");
                            wide_lanes += 1;
                        }
                    }
                }
            }
        }
        assert!(fast_lanes > 3 * 2 * 403 * 8 / 10, "{fast_lanes}");
        assert!(wide_lanes >= 3 * 2 * 2 * 10, "{wide_lanes}");
    }

    /// The block likelihood equals the particle-by-particle one bit for bit (Gaussian and
    /// heavy-tailed noise, undefined positions, a short last block).
    /// 1003 states (a short last block) around `c`, with the zero-range and far-off states
    /// the block paths must hand to their scalar fallbacks.
    fn test_cloud(c: &Vec3) -> Vec<State> {
        (0..1003)
            .map(|k| {
                let f = |i: usize| ((i * 7 + k * 13) as f64).sin();
                match k % 11 {
                    0 => State::zeros(),
                    1 => State::new(f(0) * 900.0, f(1) * 900.0, f(2) * 900.0, 0.0, 0.0, 0.0),
                    _ => State::new(c.x + f(0), c.y + f(1), c.z + f(2), f(3), f(4), f(5)),
                }
            })
            .collect()
    }

    #[test]
    fn block_likelihood_equals_scalar() {
        use crate::sensors::RadioSensor;
        let s = RadioSensor::new(crate::frames::Frame::AlongRadialAntinormal, 0.5, 1e-4);
        let c = Vec3::new(400.0, 500.0, -200.0);
        let z = s.predict(&c).expect("defined") + Vec3::new(0.2, -1e-4, 3e-4);
        let x = test_cloud(&c);
        for noise in [NoiseModel::Gaussian, NoiseModel::StudentT { dof: 4.0 }] {
            let lik = Likelihood::new(&s, &z, &noise, &[0.5, 1e-4, 1e-4]);
            let mut out = vec![0.0; x.len()];
            lik.log_many(&x, &mut out);
            for (xi, o) in x.iter().zip(&out) {
                assert_eq!(o.to_bits(), lik.log(xi).to_bits(), "{xi:?}");
            }
        }
    }

    /// The hot loops run through `simd::dispatch` (AVX2 where the CPU has it) give the
    /// same bits as the baseline path: the transition (particles, means, generator), the
    /// block likelihood, the moments, the weighted sum and the normalised weights.
    #[test]
    fn dispatched_loops_equal_baseline_bitwise() {
        use crate::numerics::simd::with_baseline;
        use crate::sensors::RadioSensor;
        let bits = |v: &[State]| -> Vec<u64> {
            v.iter()
                .flat_map(|s| s.iter().map(|x| x.to_bits()))
                .collect()
        };
        let fbits = |v: &[f64]| -> Vec<u64> { v.iter().map(|x| x.to_bits()).collect() };
        let m = CwModel::new(2.0 * std::f64::consts::PI / 5400.0);
        let mut d = m.discretize(1.0, &Mat3::zeros(), Discretization::Exact);
        d.q += Mat6::from_diagonal(&State::new(0.09, 6.25e-4, 2.5e-3, 1e-6, 1e-6, 1e-6));
        let l = chol(&d.q).expect("pd");
        let c = Vec3::new(400.0, 500.0, -200.0);
        // 1003: a short last block
        let x = test_cloud(&c);
        let w: Vec<f64> = (0..x.len()).map(|k| 1.0 + (k as f64).cos()).collect();
        let s = RadioSensor::new(crate::frames::Frame::AlongRadialAntinormal, 0.5, 1e-4);
        let z = s.predict(&c).expect("defined") + Vec3::new(0.2, -1e-4, 3e-4);
        let run = || {
            let mut out = Vec::new();
            for diag in [true, false] {
                let tr = Transition {
                    blocks: CwBlocks::of(&d.phi),
                    phi: d.phi,
                    u: State::new(1e-3, 0.0, -2e-3, 0.0, 1e-6, 0.0),
                    diag: diag.then(|| l.diagonal()),
                    l,
                };
                let mut rng = PfRng::seed_from_u64(3);
                let (mut xn, mut xb) =
                    (vec![State::zeros(); x.len()], vec![State::zeros(); x.len()]);
                let (bad, _) = tr.run(&x, None, &mut xn, &mut xb, None, false, &mut rng);
                out.push((bits(&xn), bits(&xb), bad.to_bits(), rng));
            }
            let lik = Likelihood::new(&s, &z, &NoiseModel::Gaussian, &[0.5, 1e-4, 1e-4]);
            let mut ll = vec![0.0; x.len()];
            lik.log_many(&x, &mut ll);
            let mom = moments(&State::from_element(0.1), &x, &w);
            let (ws, wsum) = weighted_sum(&x, &w);
            let mut wn = vec![0.0; x.len()];
            let lm = normalize_log_weights(&ll, &mut wn);
            // the update pass and the normalisation's exponentials with the moments
            let lw: Vec<f64> = w.iter().map(|v| -v).collect();
            let (mut lwn, mut ll2) = (vec![0.0; x.len()], vec![0.0; x.len()]);
            let max = lik.weigh_many(&x, None, &lw, &mut lwn, &mut ll2);
            let mut ew = vec![0.0; x.len()];
            let (esum, emom) = exp_moments(&State::from_element(0.1), &x, &lwn, max, &mut ew);
            let upd = (fbits(&lwn), fbits(&ll2), max.to_bits(), fbits(&ew));
            let mut soa = vec![[[0.0; BLOCK]; N]; x.len().div_ceil(BLOCK)];
            transpose_into(&x, &mut soa);
            let (ssum, smom) = exp_moments_soa(&State::from_element(0.1), &soa, &lwn, max, &mut ew);
            let em = [esum, emom.wsum, ssum, smom.wsum]
                .into_iter()
                .chain(emom.s1.iter().copied())
                .chain(emom.s2)
                .chain(smom.s1.iter().copied())
                .chain(smom.s2)
                .chain(ew.iter().copied())
                .collect::<Vec<_>>();
            (
                out,
                upd,
                fbits(&em),
                fbits(&ll),
                fbits(mom.s1.as_slice()),
                fbits(&mom.s2),
                mom.wsum.to_bits(),
                fbits(ws.as_slice()),
                wsum.to_bits(),
                fbits(&wn),
                lm.map(f64::to_bits),
            )
        };
        let fast = run();
        let base = with_baseline(run);
        assert!(fast == base);
    }

    /// The update pass and [`exp_moments`] give the weights of [`normalize_log_weights`]
    /// bit for bit (and the same log mean likelihood through
    /// [`ParticleFilter::normalise`]'s formula), and the weighted moments of the two-pass
    /// form (about the weighted mean) to rounding; merged chunk sums equal them too.
    #[test]
    fn one_pass_weights_and_moments_equal_the_two_pass_ones() {
        use crate::sensors::RadioSensor;
        let s = RadioSensor::new(crate::frames::Frame::AlongRadialAntinormal, 0.5, 1e-3);
        let c = Vec3::new(400.0, 500.0, -200.0);
        let z = s.predict(&c).expect("defined") + Vec3::new(0.2, -1e-3, 3e-3);
        let lik = Likelihood::new(&s, &z, &NoiseModel::Gaussian, &[0.5, 1e-3, 1e-3]);
        let x = test_cloud(&c);
        let n = x.len();
        let logw: Vec<f64> = (0..n).map(|k| -((k % 7) as f64) * 0.1).collect();
        let (mut lwn, mut ll) = (vec![0.0; n], vec![0.0; n]);
        let max = lik.weigh_many(&x, None, &logw, &mut lwn, &mut ll);
        assert_eq!(max.to_bits(), resample::max_ignoring_nan(&lwn).to_bits());
        for i in 0..n {
            assert_eq!(ll[i].to_bits(), lik.log(&x[i]).to_bits());
            assert_eq!(lwn[i].to_bits(), (logw[i] + ll[i]).to_bits());
        }
        let mut want = vec![0.0; n];
        let lm = normalize_log_weights(&lwn, &mut want).expect("weights");
        let reference = State::new(c.x + 0.3, c.y - 0.2, c.z + 0.1, 0.0, 0.0, 0.0);
        let mut w = vec![0.0; n];
        let (sum, mom) = exp_moments(&reference, &x, &lwn, max, &mut w);
        let inv = 1.0 / sum;
        w.iter_mut().for_each(|v| *v *= inv);
        assert!(w.iter().zip(&want).all(|(a, b)| a.to_bits() == b.to_bits()));
        assert_eq!((sum.ln() + max - (n as f64).ln()).to_bits(), lm.to_bits());
        // the two-pass moments of the normalised weights about their weighted mean
        let (ms, ws) = weighted_sum(&x, &want);
        let m2 = ms / ws;
        let (_, p2) = moments(&m2, &x, &want).finish();
        let (m1, p1) = mom.mean_cov().expect("finite");
        let scale = p2.abs().max();
        assert!((m1 - m2).abs().max() <= 1e-12 * m2.abs().max(), "{m1} {m2}");
        assert!((p1 - p2).abs().max() <= 1e-12 * scale, "{p1} {p2}");
        // chunk sums merged in order (the parallel path's form)
        let mut acc = Moments::new(reference);
        let mut sum2 = 0.0;
        for ((xs, ls), ws) in x.chunks(100).zip(lwn.chunks(100)).zip(w.chunks_mut(100)) {
            let (s, m) = exp_moments(&reference, xs, ls, max, ws);
            sum2 += s;
            acc.merge(&m);
        }
        let (m3, p3) = acc.mean_cov().expect("finite");
        assert!((sum2 - sum).abs() <= 1e-12 * sum);
        assert!((m3 - m2).abs().max() <= 1e-12 * m2.abs().max());
        assert!((p3 - p2).abs().max() <= 1e-12 * scale);
        // from the transposed copy (lane sums; a short last block whose padding holds
        // garbage): the same weights and sum bit for bit, the moments to rounding
        let mut soa = vec![[[f64::NAN; BLOCK]; N]; n.div_ceil(BLOCK)];
        transpose_into(&x, &mut soa);
        let mut w4 = vec![0.0; n];
        let (sum4, mom4) = exp_moments_soa(&reference, &soa, &lwn, max, &mut w4);
        assert_eq!(sum4.to_bits(), sum.to_bits());
        assert_eq!(mom4.wsum.to_bits(), sum.to_bits());
        w4.iter_mut().for_each(|v| *v *= inv);
        assert!(w4
            .iter()
            .zip(&want)
            .all(|(a, b)| a.to_bits() == b.to_bits()));
        let (m4, p4) = mom4.mean_cov().expect("finite");
        assert!((m4 - m2).abs().max() <= 1e-12 * m2.abs().max(), "{m4} {m2}");
        assert!((p4 - p2).abs().max() <= 1e-12 * scale, "{p4} {p2}");
    }

    /// The transition gathering its input through resampling indices (the literal SIR's
    /// index-only resampling) equals the transition of the resampled cloud bit for bit,
    /// with the same draws, on the dispatched and the baseline path.
    #[test]
    fn gathered_transition_equals_the_resampled_cloud() {
        use crate::numerics::simd::with_baseline;
        let m = CwModel::new(2.0 * std::f64::consts::PI / 5400.0);
        let mut d = m.discretize(1.0, &Mat3::zeros(), Discretization::Exact);
        d.q += Mat6::from_diagonal(&State::new(0.09, 6.25e-4, 2.5e-3, 1e-6, 1e-6, 1e-6));
        let l = chol(&d.q).expect("pd");
        let x = test_cloud(&Vec3::new(400.0, 500.0, -200.0));
        let n = x.len();
        // ascending with repeats, as the resamplers' output
        let idx: Vec<usize> = (0..n).map(|k| (k / 3) * 2 + k % 2).collect();
        let xr: Vec<State> = idx.iter().map(|&i| x[i]).collect();
        for diag in [true, false] {
            let tr = Transition {
                blocks: CwBlocks::of(&d.phi),
                phi: d.phi,
                u: State::new(1e-3, 0.0, -2e-3, 0.0, 1e-6, 0.0),
                diag: diag.then(|| l.diagonal()),
                l,
            };
            let run = |src: &[State], ix: Option<&[usize]>| {
                let mut rng = PfRng::seed_from_u64(3);
                let (mut xn, mut xb) = (vec![State::zeros(); n], vec![State::zeros(); n]);
                let (bad, _) = tr.run(src, ix, &mut xn, &mut xb, None, false, &mut rng);
                (xn, xb, bad.to_bits(), rng)
            };
            let want = run(&xr, None);
            assert!(run(&x, Some(&idx)) == want, "diag {diag}");
            assert!(with_baseline(|| run(&x, Some(&idx))) == want, "diag {diag}");
        }
    }

    /// The particles kept transposed beside `x` (`soa`: read by the next weighting and
    /// transition instead of transposing `x`) change no bit: a filter that never reads them
    /// (its `soa_fresh` cleared before every step) draws the same particles and weights, on
    /// the literal transition kinds and with moves, with a short last block.
    #[test]
    fn transposed_particles_change_no_bit() {
        use crate::sensors::RadioSensor;
        let m = CwModel::new(2.0 * std::f64::consts::PI / 5400.0);
        let mut d = m.discretize(1.0, &Mat3::zeros(), Discretization::Exact);
        d.q += Mat6::from_diagonal(&State::new(0.09, 6.25e-4, 2.5e-3, 1e-6, 1e-6, 1e-6));
        let s = RadioSensor::new(crate::frames::Frame::AlongRadialAntinormal, 0.5, 1e-3);
        let truth = State::new(400.0, 500.0, -200.0, 0.1, -0.05, 0.02);
        let p0 = Mat6::from_diagonal(&State::new(100.0, 100.0, 100.0, 0.01, 0.01, 0.01));
        for (kind, moves) in [
            (PfKind::Sir, false),
            (PfKind::Rpf, false),
            (PfKind::Gapf, false),
            (PfKind::Sir, true),
        ] {
            let params = PfParams {
                particles: 100,
                seed: 11,
                moves,
                ..PfParams::new(kind)
            };
            let mut a = ParticleFilter::new(truth, p0, params);
            let mut b = ParticleFilter::new(truth, p0, params);
            let mut x = truth;
            for _ in 0..12 {
                x = d.phi * x;
                let z = s
                    .predict(&x.fixed_rows::<3>(0).into_owned())
                    .expect("a measurement");
                a.predict(&d, &Vec3::zeros()).expect("predict");
                b.soa_fresh = false;
                b.predict(&d, &Vec3::zeros()).expect("predict");
                a.update(&s, &z).expect("update");
                b.soa_fresh = false;
                b.update(&s, &z).expect("update");
                assert!(a.state() == b.state(), "{kind:?} moves {moves}");
            }
            let (pa, wa) = a.particles();
            let (pa, wa) = (pa.to_vec(), wa.to_vec());
            let (pb, wb) = b.particles();
            assert!(pa == pb && wa == wb, "{kind:?} moves {moves}");
            assert!(a.resample_count() > 0, "{kind:?} moves {moves}");
        }
    }

    /// The generator's state words read through serde rebuild the same stream (and are
    /// the reference implementation's: the first output is `rotl(s0 + s3, 23) + s0`).
    #[test]
    fn generator_state_round_trips() {
        use rand::RngCore;
        let mut rng = PfRng::seed_from_u64(42);
        for _ in 0..1000 {
            rng.next_u64();
        }
        let s = rng_state(&rng).expect("state words");
        let want = s[0].wrapping_add(s[3]).rotate_left(23).wrapping_add(s[0]);
        let mut copy = rng_from_state(s).expect("non-zero");
        assert_eq!(copy, rng);
        assert_eq!(copy.next_u64(), want);
        assert_eq!(rng.next_u64(), want);
        assert!(rng_from_state([0; 4]).is_none());
    }
}
