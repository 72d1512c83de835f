//! The particle filters' settings: the variant ([`PfKind`]), the initialisation
//! ([`PfInit`]), the RPF's kernel ([`Kernel`]) and its optimal bandwidth ([`bandwidth`]),
//! the genetic and cloud-genetic operators' settings ([`GeneticParams`], [`CloudParams`])
//! and [`PfParams`], which holds them all.

use super::N;
use crate::estimators::ukf::UkfParams;
#[cfg(not(feature = "std"))]
use crate::math::Float;

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

    /// Every kind, in filter-code order.
    pub const ALL: [PfKind; 5] = [
        PfKind::Sir,
        PfKind::Rpf,
        PfKind::Upf,
        PfKind::Gapf,
        PfKind::Cgapf,
    ];

    /// The kind of a scenario-file name.
    pub fn from_name(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == s)
    }

    /// Whether the proposal is the per-particle UKF step.
    pub fn unscented(self) -> bool {
        matches!(self, PfKind::Upf | PfKind::Cgapf)
    }

    /// The default initialisation with the moves ([`PfInit::FirstMeasurement`] for every
    /// kind: even the UKF proposal of the Gaussian prior is metres off the first posterior
    /// on paper 000's example, where the posterior is decimetres wide); the navigator's
    /// literal filters (`pf_move = false`) start from the prior as the papers write.
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

/// What the particles carry and what their moves aim at (`pf_prior`; C ABI / FMU codes 1
/// and 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[repr(i32)]
pub enum PfPrior {
    /// Points, moved toward the Gaussian of the predictive moments ([`super::moves`]: the
    /// Gaussian particle filter of Kotecha and Djuric; with `moves = false`, the papers'
    /// filters as written).
    Gaussian = 1,
    /// A Gaussian per particle: the set is a Gaussian sum, each term updated by its own
    /// Kalman step and weighted by its predictive likelihood, resampled and
    /// kernel-smoothed ([`super::gaussian_sum`]): the prior of every update is the
    /// particle set's own predictive mixture. The navigator's default.
    #[default]
    Particle = 2,
}

impl PfPrior {
    /// Both, in code order.
    pub const ALL: [PfPrior; 2] = [PfPrior::Gaussian, PfPrior::Particle];

    /// The prior with C ABI / FMU code `c`, or `None` for an unknown code.
    pub fn from_code(c: i32) -> Option<Self> {
        Self::ALL.into_iter().find(|p| *p as i32 == c)
    }

    /// Lower-case name (`"gaussian"`, `"particle"`).
    pub fn name(self) -> &'static str {
        match self {
            PfPrior::Gaussian => "gaussian",
            PfPrior::Particle => "particle",
        }
    }
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
    /// default; see the [module documentation](super) for why).
    pub carry_covariance: bool,
    /// Genetic operators (GA-PF).
    pub genetic: GeneticParams,
    /// Cloud-genetic operators (CGA-PF).
    pub cloud: CloudParams,
    /// Move the particles with Gaussian-prior Metropolis–Hastings steps (the
    /// rejuvenation of [`super::moves`] after every update, the MH-accepted RPF jitter, the
    /// shrinkage-kernel unscented proposal); default true. False: the papers' literal
    /// filters (paper 000's SIR, the plain RPF, van der Merwe's UPF), which degenerate
    /// with small process noise.
    pub moves: bool,
    /// What the particles carry ([`PfPrior`]); `moves` applies to [`PfPrior::Gaussian`].
    pub prior: PfPrior,
    /// Worker threads of the particle loops from [`super::PARALLEL_MIN_PARTICLES`] particles on:
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
            prior: PfPrior::Gaussian,
            threads: 0,
        }
    }

    /// Check the settings; the message names the bad one.
    pub fn validate(&self) -> Result<(), crate::message::Message> {
        if self.particles == 0 {
            return Err("particles must be >= 1 (got 0)".into());
        }
        if self.particles > MAX_PARTICLES {
            return Err(crate::msg!(
                "particles must be <= {MAX_PARTICLES} (got {})",
                self.particles
            ));
        }
        if self.prior == PfPrior::Particle && self.particles > MAX_GAUSSIAN_SUM {
            return Err(crate::msg!(
                "particles must be <= {MAX_GAUSSIAN_SUM} with pf_prior = particle (got {})",
                self.particles
            ));
        }
        if !(self.threshold > 0.0 && self.threshold <= 1.0) {
            return Err(crate::msg!(
                "resample threshold must lie in (0, 1] (got {})",
                self.threshold
            ));
        }
        if self.threads > MAX_THREADS {
            return Err(crate::msg!(
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
    pub(super) fn shrinkage(&self) -> bool {
        self.moves && !self.carry_covariance
    }
}

/// Largest particle count accepted (about 1 GB of particle state for the unscented kinds).
pub const MAX_PARTICLES: usize = 2_000_000;

/// Largest particle count of the particle prior (a Gaussian per particle: about 2 KB each
/// with the copies a step keeps to undo itself).
pub const MAX_GAUSSIAN_SUM: usize = 100_000;

/// Volume of the unit ball in 6 dimensions, `pi^3 / 6`.
const UNIT_BALL_6: f64 =
    core::f64::consts::PI * core::f64::consts::PI * core::f64::consts::PI / 6.0;

/// Optimal RPF bandwidth for `n = 6` and `particles` particles.
pub fn bandwidth(kernel: Kernel, particles: usize) -> f64 {
    let n = N as f64;
    let np = particles as f64;
    match kernel {
        Kernel::Gaussian => (4.0 / (np * (n + 2.0))).powf(1.0 / (n + 4.0)),
        Kernel::Epanechnikov => {
            let a = (8.0 * (n + 4.0) * (2.0 * core::f64::consts::PI.sqrt()).powf(n) / UNIT_BALL_6)
                .powf(1.0 / (n + 4.0));
            a * np.powf(-1.0 / (n + 4.0))
        }
    }
}

/// GA-PF operators.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GeneticParams {
    /// Crossover probability of a pair, in [0, 1].
    pub crossover: f64,
    /// Mutation probability of a particle, in [0, 1] (default 0.5: with 0.1 the velocities
    /// stay impoverished on paper 000, 13.9 m off against 0.40 m).
    pub mutation: f64,
    /// Mutation step over the Gaussian kernel's optimal bandwidth (> 0).
    pub mutation_scale: f64,
}

impl Default for GeneticParams {
    fn default() -> Self {
        Self {
            crossover: 0.8,
            mutation: 0.5,
            mutation_scale: 1.0,
        }
    }
}

impl GeneticParams {
    /// Check the settings.
    pub fn validate(&self) -> Result<(), crate::message::Message> {
        prob("genetic crossover probability", self.crossover)?;
        prob("genetic mutation probability", self.mutation)?;
        positive("genetic mutation_scale", self.mutation_scale)
    }
}

/// Cloud-genetic operators of the CGA-PF (paper 003).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CloudParams {
    /// Entropy divisor of the adaptive probabilities, `En = (f_max - f_avg) / c1`.
    pub c1: f64,
    /// Hyper-entropy divisor of the adaptive probabilities, `He = En / c2`.
    pub c2: f64,
    /// Mutation entropy divisor, `En = range / c3` (paper: 3..6).
    pub c3: f64,
    /// Mutation hyper-entropy divisor, `He = En / c4` (paper: 3..5).
    pub c4: f64,
    /// Certainty of the least fit particle (paper: 0.2).
    pub mu_min: f64,
    /// Certainty of the fittest particle (paper: 0.95).
    pub mu_max: f64,
    /// Largest crossover probability `k_c`.
    pub k_crossover: f64,
    /// Largest mutation probability `k_m`.
    pub k_mutation: f64,
    /// Rounds of crossover and mutation per resampling (>= 1).
    pub generations: usize,
}

impl Default for CloudParams {
    fn default() -> Self {
        Self {
            c1: 3.0,
            c2: 10.0,
            c3: 4.0,
            c4: 4.0,
            mu_min: 0.2,
            mu_max: 0.95,
            k_crossover: 0.8,
            k_mutation: 0.2,
            generations: 3,
        }
    }
}

impl CloudParams {
    /// Check the settings.
    pub fn validate(&self) -> Result<(), crate::message::Message> {
        positive("cloud c1", self.c1)?;
        positive("cloud c2", self.c2)?;
        positive("cloud c3", self.c3)?;
        positive("cloud c4", self.c4)?;
        if !(self.mu_min > 0.0 && self.mu_min <= self.mu_max && self.mu_max < 1.0) {
            return Err(crate::msg!(
                "cloud certainties need 0 < mu_min <= mu_max < 1 (got {}, {})",
                self.mu_min,
                self.mu_max
            ));
        }
        prob("cloud k_crossover", self.k_crossover)?;
        prob("cloud k_mutation", self.k_mutation)?;
        if self.generations == 0 || self.generations > 100 {
            return Err(crate::msg!(
                "cloud generations must lie in 1..=100 (got {})",
                self.generations
            ));
        }
        Ok(())
    }
}

fn prob(name: &str, v: f64) -> Result<(), crate::message::Message> {
    if (0.0..=1.0).contains(&v) {
        Ok(())
    } else {
        Err(crate::msg!("{name} must lie in [0, 1] (got {v})"))
    }
}

fn positive(name: &str, v: f64) -> Result<(), crate::message::Message> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(crate::msg!("{name} must be finite and > 0 (got {v})"))
    }
}

/// Resampling schemes (codes for the C ABI / FMU: 1 multinomial, 2 systematic, 3 stratified,
/// 4 residual). See the [`resample`](super::resample) module for the definitions and references.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[repr(i32)]
pub enum Resampler {
    /// `M` iid draws from the categorical distribution of the weights (paper 000's SIR).
    Multinomial = 1,
    /// One uniform `U`, points `(k + U) / M` (Kitagawa 1996).
    #[default]
    Systematic = 2,
    /// One uniform per stratum, points `(k + U_k) / M` (Kitagawa 1996).
    Stratified = 3,
    /// `floor(M w_i)` deterministic copies, the rest multinomial (Liu & Chen 1998).
    Residual = 4,
}

impl Resampler {
    /// Every scheme, in code order.
    pub const ALL: [Resampler; 4] = [
        Resampler::Multinomial,
        Resampler::Systematic,
        Resampler::Stratified,
        Resampler::Residual,
    ];

    /// The scheme with C ABI / FMU code `c` (1-4), or `None` for an unknown code.
    pub fn from_code(c: i32) -> Option<Self> {
        match c {
            1 => Some(Resampler::Multinomial),
            2 => Some(Resampler::Systematic),
            3 => Some(Resampler::Stratified),
            4 => Some(Resampler::Residual),
            _ => None,
        }
    }

    /// Lower-case name (`"multinomial"`, `"systematic"`, `"stratified"`, `"residual"`).
    pub fn name(self) -> &'static str {
        match self {
            Resampler::Multinomial => "multinomial",
            Resampler::Systematic => "systematic",
            Resampler::Stratified => "stratified",
            Resampler::Residual => "residual",
        }
    }
}

/// Largest accepted worker-thread count of a particle filter's own pool.
pub const MAX_THREADS: usize = 1024;
