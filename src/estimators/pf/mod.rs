//! Particle filters of papers 000 and 003: SIR, regularised (RPF), unscented (UPF),
//! genetic (GA-PF) and cloud-genetic (CGA-PF), on one particle set.
//!
//! | kind | proposal | after resampling |
//! |---|---|---|
//! | [`PfKind::Sir`] (paper 000, sec. 3) | transition density | nothing |
//! | [`PfKind::Rpf`] | transition density | kernel jitter |
//! | [`PfKind::Upf`] | per-particle UKF step with the current measurement | nothing |
//! | [`PfKind::Gapf`] | transition density | crossover + mutation, MH-accepted ([`genetic`]) |
//! | [`PfKind::Cgapf`] (paper 003) | per-particle UKF step | cloud crossover + cloud mutation, MH-accepted |
//!
//! **SIR** (Gordon, Salmond & Smith 1993): `x_i <- Phi x_i + Gamma a + w_i`,
//! `w_i ~ N(0, Q)`; the log-weights grow by the measurement log-likelihood and are
//! normalised with the max-subtraction trick; `N_eff = 1 / sum w_i^2`; when
//! `N_eff < threshold N` (paper 000: 2/3) the particles are resampled ([`resample`]) and
//! the weights reset to `1/N`. The outputs are the weighted mean and covariance. The
//! likelihood is the sensor's true noise density (Gaussian, contaminated Gaussian,
//! Student-t, ... see [`crate::noise`]): the particle filters are where heavy tails are
//! modelled (paper 003), the Kalman filters keep the Gaussian of the same variance.
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
//! **Unscented PF** (van der Merwe, Doucet, de Freitas & Wan 2000; paper 003's proposal):
//! every particle carries a mean and a covariance `(x_i, P_i)`. The time update is
//! `xbar_i = Phi x_i + Gamma a`, `P_i <- Phi P_i Phi^T + Q` (the unscented transform of
//! the linear CW map is exact, so it is done in closed form; paper 003's augmented
//! sigma-point dimension `n_x + n_v + n_u` reduces to this for additive noise). The
//! measurement update runs the UKF of [`crate::estimators::ukf`] on `(xbar_i, P_i)` with
//! the current `z` and the Gaussian of the noise model's variance, giving `N(m_i, P_i+)`;
//! the new particle is drawn from it and weighted by
//! `p(z | x) N(x; xbar_i, Q) / N(x; m_i, P_i+)`. A particle whose UKF step fails (zero
//! range) falls back to the transition proposal.
//! What `P_i` is after the draw is the one choice: van der Merwe keep `P_i <- P_i+` (a
//! bank of UKFs; [`PfParams::carry_covariance`]); by default we restart it at zero, so
//! the next step's proposal is the UKF update of `N(xbar_i, Q)` — the unscented
//! approximation of the optimal proposal `p(x_k | x_(k-1)^i, z_k)`. The particle already
//! *is* a draw from `P_i+`: carrying `P_i+` counts that uncertainty twice, the proposal
//! becomes much wider than the transition density in the velocity directions
//! (accumulated UKF variance against `Q`'s 0.1 (m/s)^2 on paper 003, 1e-6 on paper 000)
//! and the weights degenerate (paper 003, 10 runs: NEES 558 and 3 failed runs of 10 before
//! this choice was made explicit).
//!
//! **Prior of the first update.** Until the first weighting update the prior is the
//! Gaussian `N(x0, P0)` propagated exactly (`xbar_0`, `P_prior`). With
//! [`PfInit::Prior`] the first update's target is `p(z | x) N(x; xbar_0, P_prior)`: the
//! SIR samples the prior (the literal filter of paper 000); the UPF draws every particle
//! from the one UKF posterior of `(xbar_0, P_prior)` and weighs with
//! `p(z | x) N(x; xbar_0, P_prior) / q(x)` — exact importance sampling of the first
//! posterior, which is why the unscented filters need no special initialisation.
//!
//! **The collapse of the literal SIR on paper 000** (issue 4's "known trap"): its prior is
//! 50 m / 1 m/s wide while one measurement pins the position to a 0.5 m x 0.12 m x 0.12 m
//! box, about 1e-7 of the prior's volume: with thousands of particles none lands in the
//! likelihood's support, one particle takes all the weight and the filter ends hundreds of
//! metres off. [`PfInit::Prior`] keeps that literal behaviour. [`PfInit::FirstMeasurement`]
//! is the first half of the fix and the default of the transition-proposal filters: the
//! positions are drawn from the first measurement's likelihood (the noisy measurement
//! inverted to a position, noise drawn from the sensor's noise model) and the velocities
//! from the prior. This is the posterior after the first measurement up to the prior's
//! density over a box of a few decimetres, which a 50 m prior makes flat to 1e-4; the
//! first measurement is consumed by it.
//! The second half is **regularisation or move steps** (RPF, GA-PF): the velocities are
//! the prior's N draws, and with 2000 of them over a 1 m/s-wide prior none lies closer
//! than ~0.1 m/s to the truth; paper 000's velocity process noise (1e-3 m/s per step)
//! cannot refine them, so a plain SIR keeps the best draw and drifts metres off within
//! 100 s (`tests/pf.rs`). The kernel jitter after each resampling moves the velocities by
//! a fraction of their current spread and the population contracts onto the truth:
//! decimetres, as the EKF. The unscented proposals (UPF, CGA-PF) do the same by moving
//! every particle with a UKF step.
//!
//! No heap allocation happens in a step: every buffer is sized at construction
//! (`tests/no_alloc.rs`).

pub mod genetic;
pub mod resample;

use super::ukf::{Ukf, UkfParams};
use super::{symmetrize, Estimator, FilterError, UpdateInfo};
use crate::dynamics::DiscreteModel;
use crate::noise::NoiseModel;
use crate::numerics::state::{refuse, Persist, Reader, StateError, Writer};
use crate::sensors::MeasurementModel;
use crate::types::{Mat3, Mat6, State, Vec3};
use genetic::{CloudParams, GeneticParams};
use rand::{Rng, SeedableRng};
use rand_distr::{Beta, Distribution, StandardNormal};
use rand_xoshiro::Xoshiro256PlusPlus;
use std::cell::OnceCell;

/// The particle filters' generator: xoshiro256++ (Blackman & Vigna), seeded through
/// SplitMix64 by `seed_from_u64`. Chosen over ChaCha8 for speed (the six normals per
/// particle and step were a quarter of a SIR step); statistical quality is ample for
/// Monte Carlo and the stream is fixed by the crate's documented algorithm, so results
/// are reproducible from the seed.
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
use resample::{effective_sample_size, normalize_log_weights, resample, Resampler};

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
    /// Merwe et al. 2000 literally) instead of restarting it from `Q` at every step (the
    /// default; see the module documentation for why).
    pub carry_covariance: bool,
    /// Genetic operators (GA-PF).
    pub genetic: GeneticParams,
    /// Cloud-genetic operators (CGA-PF).
    pub cloud: CloudParams,
}

impl Default for PfParams {
    fn default() -> Self {
        Self::new(PfKind::Sir)
    }
}

impl PfParams {
    /// Defaults for `kind`: 1500 particles (paper 003), systematic resampling, threshold
    /// 2/3 (paper 000), Gaussian kernel, the kind's [`PfKind::default_init`], seed 0.
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
        self.ukf.validate()?;
        self.genetic.validate()?;
        self.cloud.validate()
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
    /// `(sin z_1, cos z_1)` for [`MeasurementModel::residual_at`]
    az_sin_cos: (f64, f64),
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
            az_sin_cos: z.y.sin_cos(),
        }
    }

    /// `ln p(z | x)` up to a constant: `-0.5 sum d_k^2 / sigma_k^2` for Gaussian noise, the
    /// noise model's log-density per component otherwise; `-inf` where `z` is undefined.
    fn log(&self, x: &State) -> f64 {
        let r = x.fixed_rows::<3>(0).into_owned();
        let Some(d) = self.sensor.residual_at(&self.z, self.az_sin_cos, &r) else {
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

/// `ln N(x; m, L L^T)` up to the constant `-3 ln 2 pi`, `L` lower triangular.
fn log_gauss(x: &State, m: &State, l: &Mat6) -> f64 {
    let d = x - m;
    let half_logdet: f64 = (0..N).map(|i| l[(i, i)].ln()).sum();
    match l.solve_lower_triangular(&d) {
        Some(u) => -0.5 * u.norm_squared() - half_logdet,
        None => f64::NEG_INFINITY,
    }
}

/// Weighted first and second moments accumulated in one pass about a reference point
/// `c` near the cloud: `m = c + s1 / W`, `P = s2 / W - (m - c)(m - c)^T` with
/// `s1 = sum w_i d_i`, `s2 = sum w_i d_i d_i^T`, `d_i = x_i - c`, `W = sum w_i`. Shifting
/// to a point inside the cloud avoids the cancellation of the textbook one-pass formula;
/// a variance that still rounds below zero is set to zero.
struct Moments {
    reference: State,
    s1: State,
    /// upper triangle of `s2`, column by column
    s2: [f64; 21],
    wsum: f64,
}

impl Moments {
    fn new(reference: State) -> Self {
        Self {
            reference,
            s1: State::zeros(),
            s2: [0.0; 21],
            wsum: 0.0,
        }
    }

    #[inline(always)]
    fn add(&mut self, x: &State, w: f64) {
        let d = x - self.reference;
        let wd = d * w;
        self.s1 += wd;
        self.wsum += w;
        // the 21 products of the triangle on plain arrays (constant indices once unrolled)
        let (d, wd) = (d.data.0[0], wd.data.0[0]);
        let mut k = 0;
        for (c, wdc) in wd.iter().enumerate() {
            for dr in d.iter().take(c + 1) {
                if let Some(s) = self.s2.get_mut(k) {
                    *s += dr * wdc;
                }
                k += 1;
            }
        }
    }

    fn finish(self) -> (State, Mat6) {
        let md = self.s1 / self.wsum;
        let mut p = Mat6::zeros();
        let mut k = 0;
        for c in 0..N {
            for r in 0..=c {
                let mut v = self.s2.get(k).copied().unwrap_or(f64::NAN) / self.wsum - md[r] * md[c];
                if r == c && v < 0.0 {
                    // `s2/W >= md^2` in exact arithmetic (Cauchy-Schwarz); a collapsed cloud
                    // can round it to -1e-20, which would read as a failed filter (NaN
                    // sigma). NaN stays NaN.
                    v = 0.0;
                }
                p[(r, c)] = v;
                p[(c, r)] = v;
                k += 1;
            }
        }
        (self.reference + md, p)
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

/// Lower Cholesky factor, `None` unless positive definite.
fn chol(p: &Mat6) -> Option<Mat6> {
    symmetrize(p).cholesky().map(|c| c.unpack())
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
    /// log target density `ln p(z|x) + ln p(x|ancestor)` during the move steps
    logpi: Vec<f64>,
    idx: Vec<usize>,
    perm: Vec<usize>,
    scratch: Vec<f64>,
    mean: State,
    /// weighted covariance, computed when first asked for after an update (a SIR step
    /// inside `Navigator::step` never needs the posterior one: the prediction follows)
    cov: OnceCell<Mat6>,
    ess: f64,
    /// the first-measurement initialisation is still to come
    awaiting_first: bool,
    /// no weighting update yet: the prior is the Gaussian (prior_mean, prior_cov)
    prior_mode: bool,
    prior_mean: State,
    prior_cov: Mat6,
    prior_l: Mat6,
    /// Cholesky factor of the predicted particles' covariance (target of the move steps)
    pred_mean: State,
    pred_l: Mat6,
    rng: PfRng,
    q_key: Mat6,
    /// square root of Q used to sample (Cholesky factor when Q is positive definite)
    q_sqrt: Mat6,
    q_pd: bool,
    ukf: Ukf,
    resamples: u64,
    moves_tried: u64,
    moves_accepted: u64,
}

#[inline(always)]
fn gauss6<R: Rng + ?Sized>(rng: &mut R) -> State {
    let mut e = [0.0; N];
    for v in &mut e {
        *v = StandardNormal.sample(rng);
    }
    State::from(e)
}

/// Symmetric square root of a PSD matrix (negative rounding eigenvalues clipped); `None`
/// when `q` is not finite or the (iteration-capped) eigensolver does not converge.
fn psd_sqrt(q: &Mat6) -> Option<Mat6> {
    let e = crate::numerics::eigen::symmetric_eigen(symmetrize(q))?;
    let d = e.eigenvalues.map(|v| v.max(0.0).sqrt());
    Some(e.eigenvectors * Mat6::from_diagonal(&d) * e.eigenvectors.transpose())
}

impl ParticleFilter {
    /// A filter with prior `N(x0, p0)` (canonical frame); `params` validated by the caller
    /// with [`PfParams::validate`] (an invalid count is clamped to `1..=MAX_PARTICLES`).
    pub fn new(x0: State, p0: Mat6, params: PfParams) -> Self {
        let n = params.particles.clamp(1, MAX_PARTICLES);
        let unscented = params.kind.unscented();
        let m = if unscented { n } else { 0 };
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
            logpi: vec![0.0; n],
            idx: vec![0; n],
            perm: (0..n).collect(),
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
            pred_l: Mat6::identity(),
            rng: PfRng::seed_from_u64(params.seed),
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
        self.summarise();
    }

    /// Effective sample size `1 / sum w_i^2` after the last update (before resampling).
    pub fn ess(&self) -> f64 {
        self.ess
    }

    /// How many times the particles were resampled.
    pub fn resample_count(&self) -> u64 {
        self.resamples
    }

    /// Fraction of the genetic moves (crossover, mutation) accepted by the
    /// Metropolis–Hastings test so far (NaN before the first move).
    pub fn move_acceptance(&self) -> f64 {
        self.moves_accepted as f64 / self.moves_tried as f64
    }

    /// The settings.
    pub fn params(&self) -> &PfParams {
        &self.params
    }

    /// The particles (canonical frame) and their normalised weights.
    pub fn particles(&self) -> (&[State], &[f64]) {
        (&self.x, &self.w)
    }

    /// Weighted mean of the particles; the covariance is computed when first asked for
    /// ([`ParticleFilter::cov`]).
    fn summarise(&mut self) {
        let mut m = State::zeros();
        let mut wsum = 0.0;
        for (xi, wi) in self.x.iter().zip(&self.w) {
            m += xi * *wi;
            wsum += *wi;
        }
        self.mean = m / wsum;
        self.cov = OnceCell::new();
    }

    /// Weighted covariance of the particles ([`Moments`] about the weighted mean).
    fn cov(&self) -> &Mat6 {
        self.cov.get_or_init(|| {
            let mut acc = Moments::new(self.mean);
            for (xi, wi) in self.x.iter().zip(&self.w) {
                acc.add(xi, *wi);
            }
            acc.finish().1
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
        // commit only when every particle was drawn
        std::mem::swap(&mut self.x, &mut self.x_tmp);
        std::mem::swap(&mut self.xbar, &mut self.xbar_tmp);
        Ok(())
    }

    fn regularise(&mut self, kernel: Kernel, cov_before: &Mat6) {
        let h = bandwidth(kernel, self.x.len());
        // a non-finite particle covariance (particles near overflow) has no kernel: no jitter
        let Some(sqrt) = psd_sqrt(cov_before) else {
            return;
        };
        let d = sqrt * h;
        let beta = Beta::new(N as f64 / 2.0, 2.0).ok();
        for xi in self.x.iter_mut() {
            let eps = match kernel {
                Kernel::Gaussian => gauss6(&mut self.rng),
                Kernel::Epanechnikov => {
                    let u = gauss6(&mut self.rng);
                    let un = u.norm();
                    let r2: f64 = beta.map(|b| b.sample(&mut self.rng)).unwrap_or(0.0);
                    if un > 0.0 {
                        u * (r2.sqrt() / un)
                    } else {
                        State::zeros()
                    }
                }
            };
            *xi += d * eps;
        }
    }

    /// `ln N(x; m-, P-)`, the Gaussian of the predicted particles: the predictive density
    /// in the target of the move steps.
    fn log_predictive(&self, x: &State) -> f64 {
        log_gauss(x, &self.pred_mean, &self.pred_l)
    }

    /// Reorder every per-particle array by `self.idx` (after resampling).
    fn apply_resampling(&mut self) {
        for (k, &i) in self.idx.iter().enumerate() {
            self.x_tmp[k] = self.x[i];
            self.loglik_tmp[k] = self.loglik[i];
        }
        std::mem::swap(&mut self.x, &mut self.x_tmp);
        std::mem::swap(&mut self.loglik, &mut self.loglik_tmp);
        if !self.pc.is_empty() {
            for (k, &i) in self.idx.iter().enumerate() {
                self.xbar_tmp[k] = self.xbar[i];
                self.pc_tmp[k] = self.pc[i];
            }
            std::mem::swap(&mut self.xbar, &mut self.xbar_tmp);
            std::mem::swap(&mut self.pc, &mut self.pc_tmp);
        }
    }

    /// Draw particle `i` from its UKF proposal into `x_tmp[i]`, `pc_tmp[i]` and return
    /// `ln p(x|anc) - ln q(x)`. `None` when the UKF step fails (the caller keeps the
    /// transition draw).
    fn unscented_move<M: MeasurementModel>(
        &mut self,
        i: usize,
        sensor: &M,
        r: &Mat3,
        z: &Vec3,
    ) -> Option<f64> {
        let (m, p, _) = self
            .ukf
            .measurement_update(&self.xbar[i], &self.pc[i], sensor, r, z)
            .ok()?;
        let l = chol(&p)?;
        let eps = gauss6(&mut self.rng);
        let x = m + l * eps;
        let half_logdet: f64 = (0..N).map(|k| l[(k, k)].ln()).sum();
        let log_q = -0.5 * eps.norm_squared() - half_logdet;
        self.x_tmp[i] = x;
        self.pc_tmp[i] = if self.params.carry_covariance {
            p
        } else {
            Mat6::zeros()
        };
        Some(log_gauss(&x, &self.xbar[i], &self.q_sqrt) - log_q)
    }

    /// Measurement update with the sensor's likelihood under `noise` (per-component
    /// scales `scales`): the particle filters weigh with the true noise density, heavy
    /// tails included; the unscented proposal uses the Gaussian of the same variance.
    ///
    /// A failed update changes nothing (the generator included): new particles, weights
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
        let r = self.try_update(sensor, z, noise, scales);
        if r.is_err() {
            self.rng = rng;
        }
        r
    }

    fn try_update<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
        noise: &NoiseModel,
        scales: &[f64; 3],
    ) -> Result<UpdateInfo, FilterError> {
        let n = self.x.len();
        if self.awaiting_first {
            self.init_from_measurement(sensor, z, noise, scales)?;
            self.w.iter_mut().for_each(|v| *v = 1.0 / n as f64);
            self.logw.iter_mut().for_each(|v| *v = 0.0);
            self.awaiting_first = false;
            self.prior_mode = false;
            if !self.pc.is_empty() {
                // the particle's own uncertainty: the spread of the drawn positions and the
                // prior's velocity block (or nothing: restarted from Q at the next step)
                let p = if self.params.carry_covariance {
                    self.summarise();
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
            self.summarise();
            return Ok(UpdateInfo {
                innovation: Vec3::zeros(),
                nis: f64::NAN,
                azimuth_used: true,
            });
        }
        let lik = Likelihood::new(sensor, z, noise, scales);
        if self.params.kind.unscented() {
            if self.prior_mode {
                self.prior_l = chol(&self.prior_cov)
                    .ok_or(FilterError::NotPositiveDefinite("prior covariance"))?;
            } else if !self.q_pd {
                return Err(FilterError::NotPositiveDefinite(
                    "process noise Q (the UPF and CGA-PF need a transition density)",
                ));
            }
        }
        if matches!(self.params.kind, PfKind::Gapf | PfKind::Cgapf) {
            // the predicted particles (the state after predict) as a Gaussian
            let cov = *self.cov();
            self.pred_l = chol(&cov)
                .or_else(|| {
                    let eps = 1e-12 * cov.trace().max(f64::MIN_POSITIVE);
                    chol(&(cov + Mat6::identity() * eps))
                })
                .ok_or(FilterError::NotPositiveDefinite(
                    "predicted particle covariance",
                ))?;
            self.pred_mean = self.mean;
        }
        if self.params.kind.unscented() {
            let vf = noise.variance_factor();
            let r = Mat3::from_diagonal(&Vec3::from_fn(|k, _| scales[k] * scales[k] * vf));
            if self.prior_mode {
                // one UKF posterior of the Gaussian prior, every particle drawn from it
                let (m, p, _) = self.ukf.measurement_update(
                    &self.prior_mean,
                    &self.prior_cov,
                    sensor,
                    &r,
                    z,
                )?;
                let l = chol(&p).ok_or(FilterError::NotPositiveDefinite("UKF proposal"))?;
                let half_logdet: f64 = (0..N).map(|k| l[(k, k)].ln()).sum();
                for i in 0..n {
                    let eps = gauss6(&mut self.rng);
                    let x = m + l * eps;
                    let log_q = -0.5 * eps.norm_squared() - half_logdet;
                    let ll = lik.log(&x);
                    self.logw_tmp[i] =
                        self.logw[i] + ll + log_gauss(&x, &self.prior_mean, &self.prior_l) - log_q;
                    self.loglik[i] = ll;
                    self.x_tmp[i] = x;
                    self.pc_tmp[i] = if self.params.carry_covariance {
                        p
                    } else {
                        Mat6::zeros()
                    };
                }
            } else {
                for i in 0..n {
                    let corr = match self.unscented_move(i, sensor, &r, z) {
                        Some(c) => c,
                        None => {
                            self.x_tmp[i] = self.x[i];
                            self.pc_tmp[i] = self.pc[i];
                            0.0
                        }
                    };
                    let ll = lik.log(&self.x_tmp[i]);
                    self.logw_tmp[i] = self.logw[i] + ll + corr;
                    self.loglik[i] = ll;
                }
            }
        } else {
            for (((xi, lw), lw_new), ll) in self
                .x
                .iter()
                .zip(&self.logw)
                .zip(self.logw_tmp.iter_mut())
                .zip(self.loglik.iter_mut())
            {
                *ll = lik.log(xi);
                *lw_new = *lw + *ll;
            }
        }
        // normalise into the spare buffer; nothing is committed if every weight is zero
        let log_mean = normalize_log_weights(&self.logw_tmp, &mut self.scratch).ok_or(
            FilterError::NonFinite("particle weights (every likelihood is zero)"),
        )?;
        // commit: from here on nothing can fail
        std::mem::swap(&mut self.w, &mut self.scratch);
        std::mem::swap(&mut self.logw, &mut self.logw_tmp);
        if self.params.kind.unscented() {
            std::mem::swap(&mut self.x, &mut self.x_tmp);
            std::mem::swap(&mut self.pc, &mut self.pc_tmp);
        }
        // keep log-weights bounded: store the normalised ones, ln w_i = l_i - ln sum_j e^l_j
        let log_sum = log_mean + (n as f64).ln();
        if log_sum.is_finite() {
            self.logw.iter_mut().for_each(|lw| *lw -= log_sum);
        } else {
            for (lw, w) in self.logw.iter_mut().zip(&self.w) {
                *lw = w.ln();
            }
        }
        self.ess = effective_sample_size(&self.w);
        self.summarise();
        let innovation = sensor
            .predict(&self.mean.fixed_rows::<3>(0).into_owned())
            .map(|zh| sensor.diff(z, &zh))
            .unwrap_or_default();
        if self.ess < self.params.threshold * n as f64 {
            let cov_before = match self.params.kind {
                PfKind::Rpf | PfKind::Gapf => *self.cov(),
                _ => Mat6::zeros(),
            };
            resample(
                self.params.resampler,
                &self.w,
                &mut self.idx,
                &mut self.scratch,
                &mut self.rng,
            );
            self.apply_resampling();
            self.w.iter_mut().for_each(|v| *v = 1.0 / n as f64);
            self.logw.iter_mut().for_each(|v| *v = 0.0);
            self.resamples += 1;
            // the weighted mean and covariance before a plain resampling are kept (lower
            // variance than the resampled set's); moved particles are summarised again
            match self.params.kind {
                PfKind::Rpf => self.regularise(self.params.kernel, &cov_before),
                PfKind::Gapf => self.genetic_moves(&lik, &cov_before),
                PfKind::Cgapf => self.cloud_moves(&lik),
                PfKind::Sir | PfKind::Upf => {}
            }
            if !matches!(self.params.kind, PfKind::Sir | PfKind::Upf) {
                self.summarise();
            }
        }
        self.prior_mode = false;
        Ok(UpdateInfo {
            innovation,
            nis: f64::NAN,
            azimuth_used: true,
        })
    }
}

impl Estimator for ParticleFilter {
    /// Transition draw `x_i <- Phi x_i + Gamma a + w_i` fused with the weighted moments.
    /// The new particles go to the spare buffers and are swapped in only when their mean
    /// and covariance (and the Gaussian prior, before the first update) are finite: a failed
    /// prediction changes nothing (the generator included).
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
        // a diagonal Q (paper 000's) needs 6 products per particle instead of 36
        let diag = (l == Mat6::from_diagonal(&l.diagonal())).then(|| l.diagonal());
        let u = model.gamma * accel;
        let phi = model.phi;
        let blocks = CwBlocks::of(&phi);
        // moments about a reference point near the mean (no cancellation)
        let reference = phi * self.mean + u;
        let rng_saved = self.rng.clone();
        let mut acc = Moments::new(reference);
        for (i, ((xi, xn), wi)) in self
            .x
            .iter()
            .zip(self.x_tmp.iter_mut())
            .zip(&self.w)
            .enumerate()
        {
            let xb = match &blocks {
                Some(b) => b.apply(xi) + u,
                None => phi * *xi + u,
            };
            if let Some(slot) = self.xbar_tmp.get_mut(i) {
                *slot = xb;
            }
            let e = gauss6(&mut self.rng);
            *xn = match &diag {
                Some(d) => xb + e.component_mul(d),
                None => xb + l * e,
            };
            acc.add(xn, *wi);
        }
        let (mean, cov) = acc.finish();
        // the Gaussian prior before the first weighting update moves with the particles
        let prior = self.prior_mode.then(|| {
            (
                phi * self.prior_mean + u,
                symmetrize(&(phi * self.prior_cov * phi.transpose() + model.q)),
            )
        });
        let finite = |m: &[f64]| m.iter().all(|v| v.is_finite());
        let bad = if !finite(mean.as_slice()) {
            Some("particle mean")
        } else if !finite(cov.as_slice()) {
            Some("particle covariance")
        } else if prior.is_some_and(|(m, p)| !finite(m.as_slice()) || !finite(p.as_slice())) {
            Some("predicted prior")
        } else {
            None
        };
        if let Some(what) = bad {
            self.rng = rng_saved;
            return Err(FilterError::NonFinite(what));
        }
        std::mem::swap(&mut self.x, &mut self.x_tmp);
        std::mem::swap(&mut self.xbar, &mut self.xbar_tmp);
        (self.q_key, self.q_sqrt, self.q_pd) = (model.q, l, lower);
        self.mean = mean;
        self.cov = OnceCell::from(cov);
        for p in self.pc.iter_mut() {
            *p = symmetrize(&(phi * *p * phi.transpose() + model.q));
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
/// move steps' predictive Gaussian, the generator's four state words, the cached `Q`, its
/// square root and definiteness, and the counters. The settings and the unscented
/// proposal's weights are configuration; the `*_tmp`, `logpi`, `idx` and `scratch`
/// buffers are overwritten by every step before they are read.
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
            logpi: _,
            idx: _,
            perm,
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
            pred_l,
            rng,
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
        x.iter().for_each(|v| w.matrix(v));
        xbar.iter().for_each(|v| w.matrix(v));
        pc.iter().for_each(|v| w.matrix(v));
        logw.iter().for_each(|v| w.f64(*v));
        weights.iter().for_each(|v| w.f64(*v));
        loglik.iter().for_each(|v| w.f64(*v));
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
        w.matrix(pred_l);
        for word in rng_state(rng).unwrap_or([0; 4]) {
            w.u64(word);
        }
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
            logpi: _,
            idx: _,
            perm,
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
            pred_l,
            rng,
            q_key,
            q_sqrt,
            q_pd,
            ukf: _,
            resamples,
            moves_tried,
            moves_accepted,
        } = self;
        let n = x.len();
        r.count("particle count", n)?;
        r.count("per-particle proposal count", pc.len())?;
        *x0 = r.matrix("prior mean x0")?;
        *p0 = r.matrix("prior covariance P0")?;
        for v in x.iter_mut() {
            *v = r.finite_matrix("particle")?;
        }
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
        *pred_l = r.matrix("predictive covariance factor")?;
        let mut s = [0u64; 4];
        for word in s.iter_mut() {
            *word = r.u64("generator state")?;
        }
        *rng = rng_from_state(s).ok_or_else(|| {
            refuse("the particle filter's generator state is all zero (not a xoshiro256++ state)")
        })?;
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
