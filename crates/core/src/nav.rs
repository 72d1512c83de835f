//! The navigator: one estimator plus everything around it that a user sets — I/O frame,
//! chaser mass, process-noise model, discretisation, initial estimate — behind an API in
//! the user's frame and SI units. The C ABI (the `relnav` crate) is a thin shell around it.
//!
//! **Step semantics** (also those of the C ABI and the FMU): [`Navigator::step`]`(thrust,
//! measurement, h)` at time `t` first applies the measurement taken at `t` (if any), then
//! predicts over `[t, t + h)` with the thrust held constant; afterwards the estimate is the
//! prior at `t + h`.
//!
//! **Process noise** of a step of length `h` (canonical frame):
//! `Q = Qd_VanLoan(accel_psd I3, h) + T6^T diag(q_pos h, q_vel h) T6`, where `accel_psd`
//! [m^2/s^3] is a continuous white-acceleration spectral density (physical; exact
//! discretisation) and `q_pos` [m^2/s], `q_vel` [m^2/s^3] are per-axis variance rates in
//! the I/O frame that reproduce a paper's diagonal discrete `Q` (paper 000: its `Q` per 1 s
//! step, so `q_pos = (0.3^2, 0.025^2, 0.05^2)`, `q_vel = 0.001^2` each).
//! For the **AQUKF** (code 3) the velocity part is adaptive: `q_vel` is the initial
//! adaptive density `q_vv`, and each step adds `Qd_VanLoan(diag(q_vv_k), h)` (canonical)
//! instead of `q_vel h`; `window`, `q_vv_floor`, `q_vv_ceiling` set the adaptation
//! ([`crate::estimators::aqukf`]), [`Navigator::q_vv`] reports it. `aq_law` chooses how:
//! paper 001's window at every update, or (the default) only while the windowed NIS
//! exceeds its chi-square bound (`aq_gate_window`, `aq_gate_quantile`).
//! The **IMM** (code 10) runs 2 or 3 EKFs on the CW model whose process noise is this `Q`
//! plus `Qd_VanLoan(imm_accel_psd[j] I3, h)` (mode `j`), switching as a Markov chain with
//! per-second staying probabilities `imm_p_stay` ([`crate::estimators::imm`]);
//! [`Navigator::mode_probabilities`] reports the mode probabilities.
//!
//! **Measurement noise.** `sigma_range` and `sigma_angle` are the scales of the noise
//! density [`NavConfig::noise_model`] (Gaussian by default; a contaminated Gaussian or a
//! Student-t for heavy tails, see [`crate::noise`]). The particle filters (codes 4-8) weigh
//! with that density itself; the Kalman filters (codes 1, 2) assume the Gaussian of the
//! same variance, i.e. `sigma^2 * variance_factor` (`1 - zeta + zeta scale^2` for the
//! mixture, `dof / (dof - 2)` for the Student-t), so every filter sees the same noise
//! statistics.

use crate::dynamics::{CwModel, DiscreteModel, Discretization};
use crate::estimators::aqukf::AqukfSnapshot;
use crate::estimators::pf::resample::Resampler;
use crate::estimators::pf::{ParticleFilter, PfKind, PfParams, MAX_PARTICLES, MAX_THREADS};
use crate::estimators::{
    AdaptationLaw, AqParams, Aqukf, Ekf, Estimator, FilterError, Imm, ImmParams, Ukf, UkfParams,
    UpdateInfo, MAX_MODES,
};
use crate::frames::Frame;
use crate::hinf::HinfEstimator;
use crate::noise::NoiseModel;
use crate::numerics::num;
use crate::numerics::state::{
    self, crc32, refuse, Persist, Reader, StateError, Writer, ESTIMATOR_MAGIC, KINDS,
};
use crate::sensors::{MeasurementModel, RadioSensor};
use crate::types::{Mat3, Mat6, State, Vec3};

/// Accepted mean motions [rad/s]: from a 200-year orbit to a 1-minute one. Outside, the
/// CW model has no physical meaning and `1 / n^2` terms of the discretisation overflow.
pub const MEAN_MOTION_RANGE: (f64, f64) = (1e-9, 0.1);

/// Longest accepted step, in orbital periods `2 pi / n` of the target: a prediction over
/// more than 1000 orbits (for a 90-minute orbit, two months; geostationary, three years) is
/// far outside the linearised CW model and is almost certainly a units or time-base error
/// (a step of 1e45 s was seen from a co-simulation master). [`Navigator::predict`] and
/// [`Navigator::step`] refuse it with a message naming the limit; below it every step
/// returns a value or an error in bounded time (the discretisation is closed-form).
pub const MAX_STEP_PERIODS: f64 = 1000.0;

/// Bound on `|x0_i| + 100 sigma_i` of the initial estimate [m, m/s]: a numerical limit,
/// not a physical one. Covariances are squares of state differences, and a particle
/// filter's weighted mean is only as exact as the ulp of the state (`1e-16 |x|`): beyond
/// ~1e154 those squares overflow. 1e150 keeps the initial distribution and the first
/// steps' arithmetic inside double precision.
pub const MAX_INITIAL_MAGNITUDE: f64 = 1e150;

/// Filter codes, shared by the C ABI and the FMU (`filter` parameter).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(i32)]
pub enum FilterKind {
    /// Extended Kalman filter.
    Ekf = 1,
    /// Unscented Kalman filter.
    Ukf = 2,
    /// Sliding-window adaptive UKF (paper 001, [`crate::estimators::aqukf`]).
    Aqukf = 3,
    /// SIR (bootstrap) particle filter (paper 000).
    Pf = 4,
    /// Regularised particle filter (kernel jitter after resampling).
    Rpf = 5,
    /// Unscented particle filter (per-particle UKF proposal).
    Upf = 6,
    /// Genetic-algorithm particle filter (crossover and mutation after resampling).
    Gapf = 7,
    /// Cloud-genetic particle filter (paper 003).
    Cgapf = 8,
    /// Robust H-infinity filter (paper 002), observer form designed at construction for
    /// the open-loop CW plant (needs the `hinf` cargo feature; see [`crate::hinf`]).
    Hinf = 9,
    /// Interacting multiple-model filter over CW models with a quiet and one or two
    /// manoeuvring process noises ([`crate::estimators::imm`]).
    Imm = 10,
}

impl FilterKind {
    /// All codes, in order.
    pub const ALL: [FilterKind; 10] = [
        FilterKind::Ekf,
        FilterKind::Ukf,
        FilterKind::Aqukf,
        FilterKind::Pf,
        FilterKind::Rpf,
        FilterKind::Upf,
        FilterKind::Gapf,
        FilterKind::Cgapf,
        FilterKind::Hinf,
        FilterKind::Imm,
    ];

    /// From the stable code 1..=10.
    pub fn from_code(code: i32) -> Option<Self> {
        Self::ALL.into_iter().find(|k| *k as i32 == code)
    }

    /// Short name (`ekf`, `ukf`, ...).
    pub fn name(self) -> &'static str {
        match self {
            FilterKind::Ekf => "ekf",
            FilterKind::Ukf => "ukf",
            FilterKind::Aqukf => "aqukf",
            FilterKind::Pf => "pf",
            FilterKind::Rpf => "rpf",
            FilterKind::Upf => "upf",
            FilterKind::Gapf => "gapf",
            FilterKind::Cgapf => "cgapf",
            FilterKind::Hinf => "hinf",
            FilterKind::Imm => "imm",
        }
    }

    /// Whether this build implements the filter.
    pub fn is_implemented(self) -> bool {
        match self {
            FilterKind::Hinf => cfg!(feature = "hinf"),
            _ => true,
        }
    }

    /// The particle-filter variant of codes 4-8 (`None` for the other filters).
    pub fn pf_kind(self) -> Option<PfKind> {
        match self {
            FilterKind::Pf => Some(PfKind::Sir),
            FilterKind::Rpf => Some(PfKind::Rpf),
            FilterKind::Upf => Some(PfKind::Upf),
            FilterKind::Gapf => Some(PfKind::Gapf),
            FilterKind::Cgapf => Some(PfKind::Cgapf),
            _ => None,
        }
    }
}

/// Measurement-noise density codes, shared by the C ABI (`relnav_noise_model`) and the FMU
/// (`noise_model` parameter). The parameters live beside it in [`NavConfig`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(i32)]
pub enum NoiseKind {
    /// `N(0, sigma^2)`.
    Gaussian = 1,
    /// Contaminated Gaussian `(1 - zeta) N(0, sigma^2) + zeta N(0, (scale sigma)^2)`
    /// (paper 003's heavy-tailed lidar noise).
    Mixture = 2,
    /// `sigma t_dof`, Student-t with `dof` degrees of freedom.
    StudentT = 3,
}

impl NoiseKind {
    /// All codes, in order.
    pub const ALL: [NoiseKind; 3] = [NoiseKind::Gaussian, NoiseKind::Mixture, NoiseKind::StudentT];

    /// From the stable code 1..=3.
    pub fn from_code(code: i32) -> Option<Self> {
        Self::ALL.into_iter().find(|k| *k as i32 == code)
    }

    /// Short name (`gaussian`, `mixture`, `student_t`).
    pub fn name(self) -> &'static str {
        match self {
            NoiseKind::Gaussian => "gaussian",
            NoiseKind::Mixture => "mixture",
            NoiseKind::StudentT => "student_t",
        }
    }
}

/// H-infinity design codes for [`NavConfig::hinf_design`], the same as the C ABI's
/// `relnav_hinf_form` (whose code 2, the paper form, needs the closed loop `u = K x` and is
/// not available to the navigator).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(i32)]
pub enum HinfDesignKind {
    /// The gamma-optimal observer ([`crate::hinf::design::design_observer`]; issue 5).
    GammaOptimal = 1,
    /// The mixed H2/H-infinity observer: least H2 norm with `gamma <= hinf_gamma_factor *
    /// gamma_opt` ([`crate::hinf::design::design_mixed`]).
    Mixed = 3,
}

impl HinfDesignKind {
    /// All codes, in order.
    pub const ALL: [HinfDesignKind; 2] = [HinfDesignKind::GammaOptimal, HinfDesignKind::Mixed];

    /// From the stable code (1 or 3).
    pub fn from_code(code: i32) -> Option<Self> {
        Self::ALL.into_iter().find(|k| *k as i32 == code)
    }

    /// Short name (`gamma_optimal`, `mixed`).
    pub fn name(self) -> &'static str {
        match self {
            HinfDesignKind::GammaOptimal => "gamma_optimal",
            HinfDesignKind::Mixed => "mixed",
        }
    }
}

/// Everything that defines a navigator. [`Default`] is paper 000's numerical example
/// (digest, paper 000 "Example", with its covariance-name erratum applied).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NavConfig {
    /// Which estimator.
    pub filter: FilterKind,
    /// I/O frame of state, thrust, covariance and measurement angles.
    pub frame: Frame,
    /// Target mean motion [rad/s], > 0.
    pub mean_motion: f64,
    /// Chaser mass [kg], > 0 (thrust / mass = acceleration).
    pub chaser_mass: f64,
    /// Range noise scale [m], > 0: the standard deviation of the nominal (Gaussian) part of
    /// [`NavConfig::noise_model`].
    pub sigma_range: f64,
    /// Azimuth/elevation noise scale [rad], > 0 (as `sigma_range`).
    pub sigma_angle: f64,
    /// Initial estimate `(x, y, z, vx, vy, vz)` in the I/O frame [m, m/s].
    pub x0: [f64; 6],
    /// Initial position 1 sigma per axis [m], > 0.
    pub sigma_pos0: f64,
    /// Initial velocity 1 sigma per axis [m/s], > 0.
    pub sigma_vel0: f64,
    /// Continuous white-acceleration spectral density per axis [m^2/s^3], >= 0.
    pub accel_psd: f64,
    /// Position variance rate per I/O axis [m^2/s], >= 0.
    pub q_pos: [f64; 3],
    /// Velocity variance rate per I/O axis [m^2/s^3], >= 0.
    pub q_vel: [f64; 3],
    /// Exact (default) or Euler discretisation.
    pub discretization: Discretization,
    /// UKF sigma-point parameters.
    pub ukf: UkfParams,
    /// Seed for filters that draw random numbers (the particle filters): identical seeds
    /// give bit-identical outputs, also after [`Navigator::reset`].
    pub seed: u64,
    /// Number of particles of the particle filters, `1..=MAX_PARTICLES` (paper 003: 1500).
    pub particles: usize,
    /// Resampling scheme of the particle filters (codes 1 multinomial, 2 systematic,
    /// 3 stratified, 4 residual).
    pub resampler: Resampler,
    /// The particle filters resample when `N_eff < resample_threshold * particles`; in
    /// (0, 1] (paper 000: 2/3).
    pub resample_threshold: f64,
    /// Measurement-noise density with scales `sigma_range`, `sigma_angle`. The particle
    /// filters weigh with it; the Kalman filters use the Gaussian of its variance,
    /// `sigma^2 * NoiseModel::variance_factor()` (see the module documentation).
    pub noise_model: NoiseKind,
    /// Contamination weight of the mixture noise model, in [0, 1).
    pub noise_zeta: f64,
    /// Standard deviation of the mixture's wide component over the nominal one, >= 1.
    pub noise_scale: f64,
    /// Degrees of freedom of the Student-t noise model, > 2 (finite variance).
    pub noise_dof: f64,
    /// AQUKF (code 3): sliding-window width `N`, `1..=MAX_WINDOW` (paper 001: 10).
    pub window: usize,
    /// AQUKF: lower bound of each adaptive `q_vv` entry [m^2/s^3], >= 0.
    pub q_vv_floor: f64,
    /// AQUKF: upper bound of each adaptive `q_vv` entry [m^2/s^3], finite, > 0 and
    /// >= `q_vv_floor`.
    pub q_vv_ceiling: f64,
    /// H-infinity filter (code 9): the sampling period the discrete design holds for [s],
    /// > 0. A step of any other length is refused (no re-design inside a step).
    pub hinf_period: f64,
    /// H-infinity filter: bound of the orbit-rate uncertainty, `w = w0 (1 + delta)`,
    /// `|delta| <= hinf_delta_bar`, >= 0 (paper 002: 0.05).
    pub hinf_delta_bar: f64,
    /// H-infinity filter: process-noise scaling on positions [m] (paper 002 `B`: 0.05), not
    /// negative. With `hinf_b_pos = hinf_b_vel = 0` (the default) `B` is derived from the
    /// navigator's own process noise (`accel_psd`, `q_pos`, `q_vel`; see
    /// [`NavConfig::hinf_spec`]); otherwise both must be positive and `B = diag(b_pos I3,
    /// b_vel I3)`.
    pub hinf_b_pos: f64,
    /// H-infinity filter: process-noise scaling on velocities [m/s] (paper 002 `B`: 0.001),
    /// >= 0 (0 with `hinf_b_pos = 0`: derived).
    pub hinf_b_vel: f64,
    /// H-infinity filter: scaling of the indirect position measurement noise [m]
    /// (paper 002 `D`: 0.1), >= 0; 0 (the default): `D` is derived from `sigma_range`,
    /// `sigma_angle` and the noise model at the initial estimate's position.
    pub hinf_d: f64,
    /// H-infinity filter: which design (default: mixed H2/H-infinity).
    pub hinf_design: HinfDesignKind,
    /// H-infinity filter, mixed design: the bound on the certified gamma as a multiple of
    /// the gamma-optimal design's, finite and > 1 (default 1.5).
    pub hinf_gamma_factor: f64,
    /// H-infinity filter: start with the Kalman gain of the design's noise model and hand
    /// over to the designed gain when it is no worse ([`crate::hinf::HinfAcquisition`];
    /// default true). False: the designed gain from the first step (issue 5's filter).
    pub hinf_acquisition: bool,
    /// AQUKF: adaptation law (default [`AdaptationLaw::Gated`]; `Window` is paper 001
    /// literally).
    pub aq_law: AdaptationLaw,
    /// AQUKF, gated law: number of updates in the windowed NIS,
    /// `1..=MAX_GATE_WINDOW` (default 10).
    pub aq_gate_window: usize,
    /// AQUKF, gated law: chi-square probability of the NIS gate, in (0, 1) (default 0.999).
    pub aq_gate_quantile: f64,
    /// IMM (code 10): number of modes, 2 or 3 (default 3).
    pub imm_modes: usize,
    /// IMM: white-acceleration density added to the nominal process noise in each mode
    /// [m^2/s^3], >= 0 (default 0, 1e-6, 1e-3; the third is unused with 2 modes).
    pub imm_accel_psd: [f64; MAX_MODES],
    /// IMM: probability of staying in each mode over one second, in (0, 1)
    /// (default 0.99999, 0.9, 0.9).
    pub imm_p_stay: [f64; MAX_MODES],
    /// Particle filters (codes 4-8): move the particles with posterior-invariant
    /// Metropolis–Hastings steps ([`crate::estimators::pf`], module `moves`; default
    /// true). False gives the papers' literal filters (paper 000's SIR, the plain RPF,
    /// van der Merwe's UPF), which degenerate with small process noise.
    pub pf_move: bool,
    /// Particle filters: worker threads of the particle loops from
    /// [`crate::estimators::pf::PARALLEL_MIN_PARTICLES`] particles on (0: one per core,
    /// rayon's global pool; 1: the calling thread); `0..=MAX_THREADS`. The results do not
    /// depend on it.
    pub pf_threads: usize,
}

impl Default for NavConfig {
    fn default() -> Self {
        let deg = std::f64::consts::PI / 180.0;
        Self {
            filter: FilterKind::Ekf,
            frame: Frame::AlongRadialAntinormal,
            mean_motion: 2.0 * std::f64::consts::PI / 7200.0,
            chaser_mass: 1000.0,
            sigma_range: 0.5,
            sigma_angle: 0.01 * deg,
            x0: [405.0, 505.0, 205.0, 0.1, 0.1, 0.1],
            sigma_pos0: 50.0,
            sigma_vel0: 1.0,
            accel_psd: 0.0,
            // paper 000 "Q" (its process covariance per 1 s step): 0.3^2, 0.025^2, 0.05^2
            q_pos: [0.09, 0.000625, 0.0025],
            q_vel: [1e-6; 3],
            discretization: Discretization::Exact,
            ukf: UkfParams::default(),
            seed: 0,
            particles: 1500,
            resampler: Resampler::Systematic,
            resample_threshold: 2.0 / 3.0,
            noise_model: NoiseKind::Gaussian,
            noise_zeta: 0.2,
            noise_scale: 10.0,
            noise_dof: 4.0,
            window: 10,
            q_vv_floor: 0.0,
            q_vv_ceiling: 1.0,
            hinf_period: 1.0,
            hinf_delta_bar: 0.05,
            hinf_b_pos: 0.0,
            hinf_b_vel: 0.0,
            hinf_d: 0.0,
            hinf_design: HinfDesignKind::Mixed,
            hinf_gamma_factor: 1.5,
            hinf_acquisition: true,
            aq_law: AdaptationLaw::Gated,
            aq_gate_window: 10,
            aq_gate_quantile: 0.999,
            imm_modes: ImmParams::default().modes,
            imm_accel_psd: ImmParams::default().accel_psd,
            imm_p_stay: ImmParams::default().p_stay,
            pf_move: true,
            pf_threads: 0,
        }
    }
}

/// An invalid argument, with a readable reason.
#[derive(Debug, Clone, PartialEq)]
pub struct NavError {
    /// What went wrong.
    pub kind: NavErrorKind,
    /// Human-readable reason, naming the offending parameter or input.
    pub message: String,
}

/// Category of a [`NavError`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NavErrorKind {
    /// A parameter or input is out of its domain.
    InvalidArgument,
    /// The requested filter is not implemented in this build.
    NotImplemented,
    /// The filter could not complete the step (geometry, loss of positive definiteness).
    Numerical,
    /// A saved state was refused ([`Navigator::restore_state`]): truncated, corrupted,
    /// another format version, or saved for another configuration.
    InvalidState,
}

impl std::fmt::Display for NavError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl NavError {
    fn invalid(message: String) -> Self {
        Self {
            kind: NavErrorKind::InvalidArgument,
            message,
        }
    }
}

impl From<FilterError> for NavError {
    fn from(e: FilterError) -> Self {
        Self {
            kind: NavErrorKind::Numerical,
            message: format!("filter step failed: {e}"),
        }
    }
}

/// One setting of a [`NavConfig`] as a saved state records it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Setting {
    /// A code, count or seed (the seed's `u64` bits as `i64`).
    Int(i64),
    /// A real number.
    Real(f64),
}

impl Setting {
    /// The 8 bytes a state stores: the two's complement of an `Int`, the IEEE-754 bits of
    /// a `Real` (so `-0.0` and `0.0` differ: a restore must continue bit for bit).
    pub fn bits(self) -> u64 {
        match self {
            Setting::Int(v) => v as u64,
            Setting::Real(v) => v.to_bits(),
        }
    }

    /// The same kind of setting with the stored bits `b`.
    fn with_bits(self, b: u64) -> Self {
        match self {
            Setting::Int(_) => Setting::Int(b as i64),
            Setting::Real(_) => Setting::Real(f64::from_bits(b)),
        }
    }
}

impl std::fmt::Display for Setting {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Setting::Int(v) => write!(f, "{v}"),
            Setting::Real(v) => f.write_str(&num(*v)),
        }
    }
}

impl From<StateError> for NavError {
    fn from(e: StateError) -> Self {
        Self {
            kind: NavErrorKind::InvalidState,
            message: format!("state refused: {e}"),
        }
    }
}

fn positive(name: &str, v: f64) -> Result<(), NavError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(NavError::invalid(format!(
            "{name} must be finite and > 0 (got {})",
            num(v)
        )))
    }
}

fn non_negative(name: &str, v: f64) -> Result<(), NavError> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(NavError::invalid(format!(
            "{name} must be finite and >= 0 (got {})",
            num(v)
        )))
    }
}

/// The thrust `thrust` [N, I/O frame] as the canonical acceleration `F / m` [m/s^2].
#[inline]
fn canonical_accel(cfg: &NavConfig, thrust: &[f64; 3]) -> Vec3 {
    cfg.frame.vec_to_canonical(&Vec3::from_row_slice(thrust)) / cfg.chaser_mass
}

#[inline]
fn finite3(name: &str, v: &[f64; 3]) -> Result<(), NavError> {
    if crate::numerics::all_finite(v) {
        Ok(())
    } else {
        Err(NavError::invalid(format!(
            "{name} must be finite (got {v:?})"
        )))
    }
}

impl NavConfig {
    /// Check every field; the error names the first offending one.
    pub fn validate(&self) -> Result<(), NavError> {
        if !self.filter.is_implemented() {
            let available: Vec<String> = FilterKind::ALL
                .iter()
                .filter(|k| k.is_implemented())
                .map(|k| format!("{} {}", *k as i32, k.name()))
                .collect();
            return Err(NavError {
                kind: NavErrorKind::NotImplemented,
                message: format!(
                    "filter {} ({}) is not implemented in relnav {}; available: {}",
                    self.filter as i32,
                    self.filter.name(),
                    crate::VERSION,
                    available.join(", ")
                ),
            });
        }
        positive("mean_motion", self.mean_motion)?;
        if !(MEAN_MOTION_RANGE.0..=MEAN_MOTION_RANGE.1).contains(&self.mean_motion) {
            return Err(NavError::invalid(format!(
                "mean_motion must lie in [{:e}, {}] rad/s (got {}): a circular orbit's rate \
                 (low Earth orbit ~1.1e-3, geostationary ~7.3e-5)",
                MEAN_MOTION_RANGE.0,
                MEAN_MOTION_RANGE.1,
                num(self.mean_motion)
            )));
        }
        positive("chaser_mass", self.chaser_mass)?;
        positive("sigma_range", self.sigma_range)?;
        positive("sigma_angle", self.sigma_angle)?;
        positive("sigma_pos0", self.sigma_pos0)?;
        positive("sigma_vel0", self.sigma_vel0)?;
        for (name, v) in [
            ("sigma_pos0", self.sigma_pos0),
            ("sigma_vel0", self.sigma_vel0),
        ] {
            if !(v * v).is_finite() || v * v == 0.0 {
                return Err(NavError::invalid(format!(
                    "{name} = {} has no finite, non-zero variance",
                    num(v)
                )));
            }
        }
        for (name, v) in [
            ("sigma_range", self.sigma_range),
            ("sigma_angle", self.sigma_angle),
        ] {
            if !(v * v).is_finite() || v * v == 0.0 {
                return Err(NavError::invalid(format!(
                    "{name} = {} has no finite, non-zero variance",
                    num(v)
                )));
            }
        }
        non_negative("accel_psd", self.accel_psd)?;
        for (i, n) in ["x0", "y0", "z0", "vx0", "vy0", "vz0"].iter().enumerate() {
            if !self.x0[i].is_finite() {
                return Err(NavError::invalid(format!(
                    "{n} must be finite (got {})",
                    self.x0[i]
                )));
            }
            // headroom in double precision for the initial distribution (a particle
            // filter draws x0 + sigma eps) and the first steps' arithmetic
            let sigma = if i < 3 {
                self.sigma_pos0
            } else {
                self.sigma_vel0
            };
            if !(self.x0[i].abs() + 100.0 * sigma <= MAX_INITIAL_MAGNITUDE) {
                return Err(NavError::invalid(format!(
                    "|{n}| + 100 sigma must not exceed {MAX_INITIAL_MAGNITUDE:e} (got {n} = {}, \
                     sigma {}): the initial estimate would overflow double precision",
                    num(self.x0[i]),
                    num(sigma)
                )));
            }
        }
        for (i, axis) in ["x", "y", "z"].iter().enumerate() {
            non_negative(&format!("q_pos_{axis}"), self.q_pos[i])?;
            non_negative(&format!("q_vel_{axis}"), self.q_vel[i])?;
        }
        // checked whatever the filter, so a bad value never hides until the filter changes
        self.ukf.validate().map_err(NavError::invalid)?;
        if !(1..=MAX_PARTICLES).contains(&self.particles) {
            return Err(NavError::invalid(format!(
                "particles must lie in 1..={MAX_PARTICLES} (got {})",
                self.particles
            )));
        }
        if !(self.resample_threshold > 0.0 && self.resample_threshold <= 1.0) {
            return Err(NavError::invalid(format!(
                "resample_threshold must lie in (0, 1] (got {}): the particles are resampled \
                 when N_eff < resample_threshold * particles",
                num(self.resample_threshold)
            )));
        }
        if !(0.0..1.0).contains(&self.noise_zeta) {
            return Err(NavError::invalid(format!(
                "noise_zeta must lie in [0, 1) (got {}): the weight of the mixture's wide component",
                num(self.noise_zeta)
            )));
        }
        if !(self.noise_scale.is_finite() && self.noise_scale >= 1.0) {
            return Err(NavError::invalid(format!(
                "noise_scale must be finite and >= 1 (got {}): the mixture's wide component over \
                 the nominal sigma",
                num(self.noise_scale)
            )));
        }
        if !(self.noise_dof.is_finite() && self.noise_dof > 2.0) {
            return Err(NavError::invalid(format!(
                "noise_dof must be finite and > 2 (got {}): the Student-t needs a finite variance",
                num(self.noise_dof)
            )));
        }
        for (name, v) in [
            ("sigma_range", self.sigma_range),
            ("sigma_angle", self.sigma_angle),
        ] {
            let var = v * v * self.noise().variance_factor();
            if !var.is_finite() {
                return Err(NavError::invalid(format!(
                    "{name} = {} with noise model {} has no finite variance",
                    num(v),
                    self.noise_model.name()
                )));
            }
        }
        if self.filter.pf_kind().is_some_and(PfKind::unscented)
            && !self.pf_move
            && !(self.accel_psd > 0.0 || self.q_pos.iter().chain(&self.q_vel).all(|q| *q > 0.0))
        {
            return Err(NavError::invalid(format!(
                "filter {} with pf_move = false needs a positive-definite process noise \
                 (accel_psd > 0, or every q_pos_* and q_vel_* > 0): its literal proposal is \
                 built on the transition density",
                self.filter.name()
            )));
        }
        if self.pf_threads > MAX_THREADS {
            return Err(NavError::invalid(format!(
                "pf_threads must lie in 0..={MAX_THREADS} (got {}); 0 = one per core",
                self.pf_threads
            )));
        }
        if let Some(p) = self.pf_params() {
            p.validate().map_err(NavError::invalid)?;
        }
        self.aq_params().validate().map_err(NavError::invalid)?;
        self.validate_hinf()?;
        self.imm_params().validate().map_err(NavError::invalid)?;
        Ok(())
    }

    /// Every setting by name, in the order of a saved state's configuration section
    /// (`docs/state-format.md`). The destructuring names every field: a new field of
    /// `NavConfig` does not compile until it is added here (and so to the fingerprint) —
    /// or is named as not state-relevant (`pf_threads`: the results do not depend on it).
    pub fn settings(&self) -> Vec<(&'static str, Setting)> {
        use Setting::{Int, Real};
        let NavConfig {
            filter,
            frame,
            mean_motion,
            chaser_mass,
            sigma_range,
            sigma_angle,
            x0,
            sigma_pos0,
            sigma_vel0,
            accel_psd,
            q_pos,
            q_vel,
            discretization,
            ukf,
            seed,
            particles,
            resampler,
            resample_threshold,
            noise_model,
            noise_zeta,
            noise_scale,
            noise_dof,
            window,
            q_vv_floor,
            q_vv_ceiling,
            hinf_period,
            hinf_delta_bar,
            hinf_b_pos,
            hinf_b_vel,
            hinf_d,
            hinf_design,
            hinf_gamma_factor,
            hinf_acquisition,
            aq_law,
            aq_gate_window,
            aq_gate_quantile,
            imm_modes,
            imm_accel_psd,
            imm_p_stay,
            pf_move,
            // the results (and so a saved state) do not depend on the thread count: a state
            // moves between instances that run the particle loops on different threads
            pf_threads: _,
        } = *self;
        let UkfParams { alpha, beta, kappa } = ukf;
        vec![
            ("filter", Int(filter as i64)),
            ("frame", Int(frame.code() as i64)),
            ("mean_motion", Real(mean_motion)),
            ("chaser_mass", Real(chaser_mass)),
            ("sigma_range", Real(sigma_range)),
            ("sigma_angle", Real(sigma_angle)),
            ("x0[0]", Real(x0[0])),
            ("x0[1]", Real(x0[1])),
            ("x0[2]", Real(x0[2])),
            ("x0[3]", Real(x0[3])),
            ("x0[4]", Real(x0[4])),
            ("x0[5]", Real(x0[5])),
            ("sigma_pos0", Real(sigma_pos0)),
            ("sigma_vel0", Real(sigma_vel0)),
            ("accel_psd", Real(accel_psd)),
            ("q_pos[0]", Real(q_pos[0])),
            ("q_pos[1]", Real(q_pos[1])),
            ("q_pos[2]", Real(q_pos[2])),
            ("q_vel[0]", Real(q_vel[0])),
            ("q_vel[1]", Real(q_vel[1])),
            ("q_vel[2]", Real(q_vel[2])),
            ("discretization", Int(discretization as i64)),
            ("ukf_alpha", Real(alpha)),
            ("ukf_beta", Real(beta)),
            ("ukf_kappa", Real(kappa)),
            ("seed", Int(seed as i64)),
            ("particles", Int(particles as i64)),
            ("resampler", Int(resampler as i64)),
            ("resample_threshold", Real(resample_threshold)),
            ("noise_model", Int(noise_model as i64)),
            ("noise_zeta", Real(noise_zeta)),
            ("noise_scale", Real(noise_scale)),
            ("noise_dof", Real(noise_dof)),
            ("window", Int(window as i64)),
            ("q_vv_floor", Real(q_vv_floor)),
            ("q_vv_ceiling", Real(q_vv_ceiling)),
            ("hinf_period", Real(hinf_period)),
            ("hinf_delta_bar", Real(hinf_delta_bar)),
            ("hinf_b_pos", Real(hinf_b_pos)),
            ("hinf_b_vel", Real(hinf_b_vel)),
            ("hinf_d", Real(hinf_d)),
            ("hinf_design", Int(hinf_design as i64)),
            ("hinf_gamma_factor", Real(hinf_gamma_factor)),
            ("hinf_acquisition", Int(i64::from(hinf_acquisition))),
            ("aq_law", Int(aq_law as i64)),
            ("aq_gate_window", Int(aq_gate_window as i64)),
            ("aq_gate_quantile", Real(aq_gate_quantile)),
            ("imm_modes", Int(imm_modes as i64)),
            ("imm_accel_psd[0]", Real(imm_accel_psd[0])),
            ("imm_accel_psd[1]", Real(imm_accel_psd[1])),
            ("imm_accel_psd[2]", Real(imm_accel_psd[2])),
            ("imm_p_stay[0]", Real(imm_p_stay[0])),
            ("imm_p_stay[1]", Real(imm_p_stay[1])),
            ("imm_p_stay[2]", Real(imm_p_stay[2])),
            ("pf_move", Int(i64::from(pf_move))),
        ]
    }

    /// The configuration section of a saved state: the number of settings (u32) and each
    /// setting's 8 bytes ([`Setting::bits`]), in [`NavConfig::settings`] order.
    fn write_settings(&self, w: &mut Writer<'_>) {
        let s = self.settings();
        w.u32(s.len() as u32);
        for (_, v) in s {
            w.u64(v.bits());
        }
    }

    /// The configuration fingerprint of a saved state's header: the CRC-32 of the
    /// configuration section ([`NavConfig::settings`]).
    pub fn fingerprint(&self) -> u32 {
        let mut b = Vec::new();
        self.write_settings(&mut Writer::new(&mut b));
        crc32(&b)
    }

    /// The H-infinity parameters: their domains whatever the filter; the derived noise
    /// model (which needs a usable initial position) only for filter 9.
    fn validate_hinf(&self) -> Result<(), NavError> {
        non_negative("hinf_b_pos", self.hinf_b_pos)?;
        non_negative("hinf_b_vel", self.hinf_b_vel)?;
        non_negative("hinf_d", self.hinf_d)?;
        if (self.hinf_b_pos == 0.0) != (self.hinf_b_vel == 0.0) {
            return Err(NavError::invalid(format!(
                "hinf_b_pos and hinf_b_vel are set together (both > 0) or derived together \
                 (both 0) (got {} and {})",
                num(self.hinf_b_pos),
                num(self.hinf_b_vel)
            )));
        }
        if !(self.hinf_gamma_factor.is_finite() && self.hinf_gamma_factor > 1.0) {
            return Err(NavError::invalid(format!(
                "hinf_gamma_factor must be finite and > 1 (got {}): the mixed design's bound on \
                 gamma as a multiple of the gamma-optimal design's",
                num(self.hinf_gamma_factor)
            )));
        }
        let hinf = |e: crate::hinf::HinfError| NavError::invalid(format!("hinf_*: {}", e.message));
        let mut spec = self.hinf_spec_scalars();
        // scalars 0 mean "derived": the placeholders only let the shared checks run
        spec.b_pos = if spec.b_pos > 0.0 { spec.b_pos } else { 1.0 };
        spec.b_vel = if spec.b_vel > 0.0 { spec.b_vel } else { 1.0 };
        spec.d = if spec.d > 0.0 { spec.d } else { 1.0 };
        spec.validate().map_err(hinf)?;
        if self.filter == FilterKind::Hinf {
            self.hinf_spec()?.validate().map_err(hinf)?;
        }
        Ok(())
    }

    fn hinf_spec_scalars(&self) -> crate::hinf::HinfSpec {
        crate::hinf::HinfSpec {
            w0: self.mean_motion,
            delta_bar: self.hinf_delta_bar,
            period: self.hinf_period,
            b_pos: self.hinf_b_pos,
            b_vel: self.hinf_b_vel,
            d: self.hinf_d,
            b_matrix: None,
            d_matrix: None,
        }
    }

    /// The H-infinity design inputs of this configuration (`w0` = `mean_motion`, canonical
    /// frame). Set scalings are used as given; zero ones are derived from the noise every
    /// other filter uses (issue 12):
    ///
    /// * `B = Qd^(1/2)` ([`crate::hinf::noise_inputs`]) with `Qd` the process-noise
    ///   covariance of one step `T = hinf_period`, exactly as the navigator builds it:
    ///   `Qd_VanLoan(accel_psd I3, T) + T6^T diag(q_pos T, q_vel T) T6` (the `q_*` are per
    ///   I/O axis, rotated to the canonical frame);
    /// * `D = R^(1/2)` with `R` the covariance of the indirect Cartesian position
    ///   ([`RadioSensor::position_covariance`]) at the initial estimate's position, of the
    ///   radio noise the Kalman filters assume (`sigma^2` times the noise model's variance
    ///   factor): `sigma_range` along the line of sight, `range * sigma_angle` across it.
    ///
    /// Errors: a zero initial range when `D` is derived; a derived `B` of zero (no process
    /// noise at all) for the mixed design, whose H2 criterion needs one.
    pub fn hinf_spec(&self) -> Result<crate::hinf::HinfSpec, NavError> {
        let mut spec = self.hinf_spec_scalars();
        let t = self.hinf_period;
        if self.hinf_b_pos == 0.0 && self.hinf_b_vel == 0.0 {
            positive("hinf_period", t)?;
            let qc = Mat3::identity() * self.accel_psd;
            let mut qd = CwModel::new(self.mean_motion).van_loan_q(&qc, t);
            let qio = State::from_row_slice(&[
                self.q_pos[0],
                self.q_pos[1],
                self.q_pos[2],
                self.q_vel[0],
                self.q_vel[1],
                self.q_vel[2],
            ]) * t;
            qd += self.frame.cov_to_canonical(&Mat6::from_diagonal(&qio));
            if self.hinf_design == HinfDesignKind::Mixed && qd.abs().max() == 0.0 {
                return Err(NavError::invalid(
                    "hinf: the mixed design's process noise is derived from accel_psd, q_pos_* \
                     and q_vel_*, which are all 0: set one of them (or hinf_b_pos and \
                     hinf_b_vel)"
                        .to_string(),
                ));
            }
            spec.b_matrix = Some(crate::hinf::psd_sqrt(&qd));
        }
        if self.hinf_d == 0.0 {
            let inflate = self.noise().variance_factor().sqrt();
            let sensor = RadioSensor::new(
                self.frame,
                self.sigma_range * inflate,
                self.sigma_angle * inflate,
            );
            let r0 = self.initial_state().fixed_rows::<3>(0).into_owned();
            let r = sensor.position_covariance(&r0).ok_or_else(|| {
                NavError::invalid(
                    "hinf: the measurement noise is derived at the initial estimate's \
                     position, which is at zero range: set x0, y0, z0 (or hinf_d)"
                        .to_string(),
                )
            })?;
            spec.d_matrix = Some(crate::hinf::psd_sqrt(&r));
        }
        Ok(spec)
    }

    /// The measurement-noise density (scales `sigma_range`, `sigma_angle`).
    pub fn noise(&self) -> NoiseModel {
        match self.noise_model {
            NoiseKind::Gaussian => NoiseModel::Gaussian,
            NoiseKind::Mixture => NoiseModel::Mixture {
                zeta: self.noise_zeta,
                scale: self.noise_scale,
            },
            NoiseKind::StudentT => NoiseModel::StudentT {
                dof: self.noise_dof,
            },
        }
    }

    /// The particle-filter settings for filter codes 4-8 (`None` for the other filters):
    /// `PfParams::new(kind)` with `particles`, `resampler`, `resample_threshold`, `seed`,
    /// the UKF parameters (the unscented proposal of `upf` and `cgapf`), `pf_move` and
    /// `pf_threads` of this configuration.
    pub fn pf_params(&self) -> Option<PfParams> {
        let kind = self.filter.pf_kind()?;
        Some(PfParams {
            moves: self.pf_move,
            threads: self.pf_threads,
            particles: self.particles,
            resampler: self.resampler,
            threshold: self.resample_threshold,
            seed: self.seed,
            ukf: self.ukf,
            ..PfParams::new(kind)
        })
    }

    /// The AQUKF's adaptive settings: `window`, `q_vv_floor`, `q_vv_ceiling`, and the
    /// initial `q_vv` = `q_vel` rotated to the canonical frame (for the AQUKF, `q_vel_*`
    /// is the initial adaptive density rather than a fixed part of `Q`; see
    /// [`Navigator`]). MAX: [`crate::estimators::MAX_WINDOW`] bounds `window`.
    pub fn aq_params(&self) -> AqParams {
        let qv = self
            .frame
            .cov_to_canonical(&Mat6::from_diagonal(&State::from_row_slice(&[
                0.0,
                0.0,
                0.0,
                self.q_vel[0],
                self.q_vel[1],
                self.q_vel[2],
            ])));
        AqParams {
            window: self.window,
            q_vv0: Vec3::new(qv[(3, 3)], qv[(4, 4)], qv[(5, 5)]),
            floor: self.q_vv_floor,
            ceiling: self.q_vv_ceiling,
            law: self.aq_law,
            gate_window: self.aq_gate_window,
            gate_quantile: self.aq_gate_quantile,
        }
    }

    /// The IMM's settings: `imm_modes`, `imm_accel_psd`, `imm_p_stay` (the densities are
    /// isotropic, so frame-independent).
    pub fn imm_params(&self) -> ImmParams {
        ImmParams {
            modes: self.imm_modes,
            accel_psd: self.imm_accel_psd,
            p_stay: self.imm_p_stay,
        }
    }

    /// Initial estimate in the canonical frame.
    pub fn initial_state(&self) -> State {
        self.frame
            .state_to_canonical(&State::from_row_slice(&self.x0))
    }

    /// Initial covariance `diag(sigma_pos0^2 I3, sigma_vel0^2 I3)` (frame-independent).
    pub fn initial_covariance(&self) -> Mat6 {
        let (p, v) = (self.sigma_pos0.powi(2), self.sigma_vel0.powi(2));
        Mat6::from_diagonal(&State::from_row_slice(&[p, p, p, v, v, v]))
    }
}

/// The estimators a navigator can run (enum dispatch: no boxing, no allocation per step).
#[derive(Debug, Clone)]
pub enum AnyFilter {
    /// Extended Kalman filter.
    Ekf(Ekf),
    /// Unscented Kalman filter.
    Ukf(Ukf),
    /// Sliding-window adaptive UKF (paper 001).
    Aqukf(Aqukf),
    /// Particle filter (codes 4-8: SIR, regularised, unscented, genetic, cloud-genetic).
    Pf(ParticleFilter),
    /// Robust H-infinity filter (code 9).
    Hinf(HinfEstimator),
    /// Interacting multiple-model filter (code 10).
    Imm(Imm),
}

/// What a step of a Kalman-type filter can change, to restore after a failed step. Small
/// on purpose: `AnyFilter` itself is as large as its largest variant (the AQUKF's window),
/// and copying that on every step cost a quarter of an EKF step.
#[derive(Debug, Clone)]
enum Snapshot {
    Ekf(Ekf),
    Ukf(Ukf),
    Aqukf(AqukfSnapshot),
    Hinf(HinfEstimator),
    Imm(Imm),
    /// particle filters are transactional themselves (see [`Navigator`])
    None,
}

impl AnyFilter {
    fn snapshot(&self) -> Snapshot {
        match self {
            AnyFilter::Ekf(f) => Snapshot::Ekf(f.clone()),
            AnyFilter::Ukf(f) => Snapshot::Ukf(f.clone()),
            AnyFilter::Aqukf(f) => Snapshot::Aqukf(f.snapshot()),
            AnyFilter::Hinf(f) => Snapshot::Hinf(*f),
            AnyFilter::Imm(f) => Snapshot::Imm(f.clone()),
            AnyFilter::Pf(_) => Snapshot::None,
        }
    }

    /// Undo the step since `s` was taken (`s` from [`AnyFilter::snapshot`] of this filter).
    fn restore(&mut self, s: &Snapshot) {
        match (self, s) {
            (AnyFilter::Ekf(f), Snapshot::Ekf(g)) => f.clone_from(g),
            (AnyFilter::Ukf(f), Snapshot::Ukf(g)) => f.clone_from(g),
            (AnyFilter::Aqukf(f), Snapshot::Aqukf(g)) => f.restore(g),
            (AnyFilter::Hinf(f), Snapshot::Hinf(g)) => *f = *g,
            (AnyFilter::Imm(f), Snapshot::Imm(g)) => f.clone_from(g),
            _ => {}
        }
    }
}

impl AnyFilter {
    /// The 4-byte tag of this filter's section in a saved state.
    fn state_tag(&self) -> &'static [u8; 4] {
        match self {
            AnyFilter::Ekf(_) => b"EKF ",
            AnyFilter::Ukf(_) => b"UKF ",
            AnyFilter::Aqukf(_) => b"AQUK",
            AnyFilter::Pf(_) => b"PART",
            AnyFilter::Hinf(_) => b"HINF",
            AnyFilter::Imm(_) => b"IMM ",
        }
    }
}

/// The filter's section: its tag, then the filter's own [`Persist`] fields (each defined
/// beside the filter).
impl Persist for AnyFilter {
    fn save_state(&self, w: &mut Writer<'_>) {
        w.tag(self.state_tag());
        match self {
            AnyFilter::Ekf(f) => f.save_state(w),
            AnyFilter::Ukf(f) => f.save_state(w),
            AnyFilter::Aqukf(f) => f.save_state(w),
            AnyFilter::Pf(f) => f.save_state(w),
            AnyFilter::Hinf(f) => f.save_state(w),
            AnyFilter::Imm(f) => f.save_state(w),
        }
    }

    fn load_state(&mut self, r: &mut Reader<'_>) -> Result<(), StateError> {
        r.tag(self.state_tag())?;
        match self {
            AnyFilter::Ekf(f) => f.load_state(r),
            AnyFilter::Ukf(f) => f.load_state(r),
            AnyFilter::Aqukf(f) => f.load_state(r),
            AnyFilter::Pf(f) => f.load_state(r),
            AnyFilter::Hinf(f) => f.load_state(r),
            AnyFilter::Imm(f) => f.load_state(r),
        }
    }
}

impl Estimator for AnyFilter {
    fn predict(&mut self, model: &DiscreteModel, accel: &Vec3) -> Result<(), FilterError> {
        match self {
            AnyFilter::Ekf(f) => f.predict(model, accel),
            AnyFilter::Ukf(f) => f.predict(model, accel),
            AnyFilter::Aqukf(f) => f.predict(model, accel),
            AnyFilter::Pf(f) => f.predict(model, accel),
            AnyFilter::Hinf(f) => f.predict(model, accel),
            AnyFilter::Imm(f) => f.predict(model, accel),
        }
    }
    fn update<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
    ) -> Result<UpdateInfo, FilterError> {
        match self {
            AnyFilter::Ekf(f) => f.update(sensor, z),
            AnyFilter::Ukf(f) => f.update(sensor, z),
            AnyFilter::Aqukf(f) => f.update(sensor, z),
            AnyFilter::Pf(f) => f.update(sensor, z),
            AnyFilter::Hinf(f) => f.update(sensor, z),
            AnyFilter::Imm(f) => f.update(sensor, z),
        }
    }
    fn state(&self) -> &State {
        match self {
            AnyFilter::Ekf(f) => f.state(),
            AnyFilter::Ukf(f) => f.state(),
            AnyFilter::Aqukf(f) => f.state(),
            AnyFilter::Pf(f) => f.state(),
            AnyFilter::Hinf(f) => f.state(),
            AnyFilter::Imm(f) => f.state(),
        }
    }
    fn covariance(&self) -> &Mat6 {
        match self {
            AnyFilter::Ekf(f) => f.covariance(),
            AnyFilter::Ukf(f) => f.covariance(),
            AnyFilter::Aqukf(f) => f.covariance(),
            AnyFilter::Pf(f) => f.covariance(),
            AnyFilter::Hinf(f) => f.covariance(),
            AnyFilter::Imm(f) => f.covariance(),
        }
    }
    fn set_estimate(&mut self, x: State, p: Mat6) {
        match self {
            AnyFilter::Ekf(f) => f.set_estimate(x, p),
            AnyFilter::Ukf(f) => f.set_estimate(x, p),
            AnyFilter::Aqukf(f) => f.set_estimate(x, p),
            AnyFilter::Pf(f) => f.set_estimate(x, p),
            AnyFilter::Hinf(f) => f.set_estimate(x, p),
            AnyFilter::Imm(f) => f.set_estimate(x, p),
        }
    }
}

/// A configured estimator working in the user's frame and units.
///
/// **Failures.** Inputs are checked before anything changes. A Kalman filter that fails
/// numerically inside a step (zero range, loss of positive definiteness) is restored to
/// its state before the step. A particle filter's update and prediction are each
/// transactional (new particles go to spare buffers and are swapped in on success; see
/// [`ParticleFilter::update_with`]): a failed `update` or `predict` changes nothing, and
/// so does a `step` whose update fails (every likelihood zero, a measurement that cannot
/// be inverted at the first update). Copying the particle set to undo a *successful*
/// update would cost as much as the step itself, so in the one remaining case — the
/// update succeeded and the prediction after it failed (a non-finite particle mean, i.e.
/// overflow) — the particle filter is marked failed and every later `update`, `predict`
/// or `step` is refused with [`NavErrorKind::Numerical`] until [`Navigator::reset`].
#[derive(Debug, Clone)]
pub struct Navigator {
    cfg: NavConfig,
    model: CwModel,
    /// the sensor with the noise model's scales (particle filters' likelihood)
    sensor: RadioSensor,
    /// the sensor with the noise model's variance (Kalman filters)
    kalman_sensor: RadioSensor,
    noise: NoiseModel,
    scales: [f64; 3],
    filter: AnyFilter,
    step_cache: DiscreteModel,
    last_update: Option<UpdateInfo>,
    /// a particle filter's prediction failed after its update in one step: refuse to go
    /// on until reset
    failed: bool,
}

fn build_filter(cfg: &NavConfig) -> Result<AnyFilter, NavError> {
    let x0 = cfg.initial_state();
    let p0 = cfg.initial_covariance();
    if let Some(params) = cfg.pf_params() {
        return Ok(AnyFilter::Pf(ParticleFilter::new(x0, p0, params)));
    }
    match cfg.filter {
        FilterKind::Ekf => Ok(AnyFilter::Ekf(Ekf::new(x0, p0))),
        FilterKind::Ukf => Ok(AnyFilter::Ukf(Ukf::new(x0, p0, cfg.ukf))),
        FilterKind::Aqukf => Ok(AnyFilter::Aqukf(Aqukf::new(
            x0,
            p0,
            cfg.ukf,
            cfg.aq_params(),
            cfg.mean_motion,
        ))),
        FilterKind::Imm => Ok(AnyFilter::Imm(Imm::new(
            x0,
            p0,
            cfg.imm_params(),
            cfg.mean_motion,
        ))),
        #[cfg(feature = "hinf")]
        FilterKind::Hinf => {
            use crate::hinf::design::{design_open_loop, design_open_loop_mixed, DesignOptions};
            let spec = cfg.hinf_spec()?;
            let opts = DesignOptions::default();
            let (d, info) = match cfg.hinf_design {
                HinfDesignKind::GammaOptimal => design_open_loop(&spec, &opts).map(|d| {
                    let info = d.info();
                    (d, info)
                }),
                HinfDesignKind::Mixed => {
                    design_open_loop_mixed(&spec, cfg.hinf_gamma_factor, &opts).map(|m| {
                        let info = m.info();
                        (m.mixed, info)
                    })
                }
            }
            .map_err(|e| NavError {
                kind: NavErrorKind::InvalidArgument,
                message: format!("hinf design ({}) failed: {e}", cfg.hinf_design.name()),
            })?;
            let invalid = |e: crate::hinf::HinfError| NavError::invalid(format!("hinf: {e}"));
            let mut f = HinfEstimator::new(d.matrices, d.gamma, x0)
                .map_err(invalid)?
                .with_h2_norm(d.h2_norm)
                .with_design_info(info);
            if cfg.hinf_acquisition {
                let plant = crate::hinf::HinfPlant::open_loop(&spec);
                f = f.with_acquisition(&plant, p0).map_err(invalid)?;
            }
            Ok(AnyFilter::Hinf(f))
        }
        other => Err(NavError {
            kind: NavErrorKind::NotImplemented,
            message: format!("filter {} is not implemented", other.name()),
        }),
    }
}

impl Navigator {
    /// Build a navigator; fails with a message naming the bad parameter.
    pub fn new(cfg: &NavConfig) -> Result<Self, NavError> {
        cfg.validate()?;
        let filter = build_filter(cfg)?;
        let model = CwModel::new(cfg.mean_motion);
        let noise = cfg.noise();
        let inflate = noise.variance_factor().sqrt();
        let mut nav = Self {
            cfg: *cfg,
            model,
            sensor: RadioSensor::new(cfg.frame, cfg.sigma_range, cfg.sigma_angle),
            kalman_sensor: RadioSensor::new(
                cfg.frame,
                cfg.sigma_range * inflate,
                cfg.sigma_angle * inflate,
            ),
            noise,
            scales: [cfg.sigma_range, cfg.sigma_angle, cfg.sigma_angle],
            filter,
            step_cache: DiscreteModel {
                dt: f64::NAN,
                phi: Mat6::identity(),
                gamma: Default::default(),
                q: Mat6::zeros(),
            },
            last_update: None,
            failed: false,
        };
        nav.discrete(1.0);
        // every field is finite, but x0 near the largest double with its uncertainty can
        // still overflow (a particle filter's initial draw x0 + L eps): refuse it here rather
        // than hand out an estimator whose estimate is not a number
        let cov_ok = matches!(nav.filter, AnyFilter::Hinf(_))
            || nav.filter.covariance().iter().all(|v| v.is_finite());
        if !(nav.filter.state().iter().all(|v| v.is_finite()) && cov_ok) {
            return Err(NavError::invalid(format!(
                "the initial estimate x0 = {:?} with sigma_pos0 = {}, sigma_vel0 = {} overflows \
                 double precision in the {} filter's initial state",
                cfg.x0,
                num(cfg.sigma_pos0),
                num(cfg.sigma_vel0),
                cfg.filter.name()
            )));
        }
        Ok(nav)
    }

    /// The configuration this navigator was built from.
    pub fn config(&self) -> &NavConfig {
        &self.cfg
    }

    /// Make `step_cache` the discrete model for step `dt` (recomputed only when `dt`
    /// changes).
    fn discrete(&mut self, dt: f64) {
        if self.step_cache.dt != dt {
            let qc = Mat3::identity() * self.cfg.accel_psd;
            let mut d = self.model.discretize(dt, &qc, self.cfg.discretization);
            // the AQUKF adapts the velocity part itself (q_vel is its initial q_vv)
            let qv = if self.cfg.filter == FilterKind::Aqukf {
                [0.0; 3]
            } else {
                self.cfg.q_vel
            };
            let qio = State::from_row_slice(&[
                self.cfg.q_pos[0],
                self.cfg.q_pos[1],
                self.cfg.q_pos[2],
                qv[0],
                qv[1],
                qv[2],
            ]) * dt;
            d.q += self.cfg.frame.cov_to_canonical(&Mat6::from_diagonal(&qio));
            self.step_cache = d;
        }
    }

    /// The longest accepted step [s]: [`MAX_STEP_PERIODS`] orbital periods.
    pub fn max_step(&self) -> f64 {
        MAX_STEP_PERIODS * std::f64::consts::TAU / self.cfg.mean_motion
    }

    /// [`Navigator::check_dt_in_full`] without a call in the common case: `0 < dt <=`
    /// [`Navigator::max_step`] (false for NaN; `max_step` is finite) and no filter with a
    /// fixed period.
    #[inline(always)]
    fn check_dt(&self, dt: f64) -> Result<(), NavError> {
        if dt > 0.0 && dt <= self.max_step() && !matches!(self.filter, AnyFilter::Hinf(_)) {
            Ok(())
        } else {
            self.check_dt_in_full(dt)
        }
    }

    #[cold]
    #[inline(never)]
    fn check_dt_in_full(&self, dt: f64) -> Result<(), NavError> {
        positive("step size h", dt)?;
        if dt > self.max_step() {
            return Err(NavError::invalid(format!(
                "step size h = {} s is longer than {MAX_STEP_PERIODS} orbital periods ({} s at \
                 mean_motion {} rad/s), where the linearised CW model means nothing: split \
                 the interval, or check the time unit",
                num(dt),
                num(self.max_step()),
                num(self.cfg.mean_motion)
            )));
        }
        if let AnyFilter::Hinf(f) = &self.filter {
            let t = f.period();
            if (dt - t).abs() > 1e-9 * t {
                return Err(NavError::invalid(format!(
                    "the hinf filter was designed for hinf_period = {} s and holds for that \
                     period only; step h = {} s refused (set hinf_period to the step size)",
                    num(t),
                    num(dt)
                )));
            }
        }
        Ok(())
    }

    /// [`Navigator::check_measurement_in_full`] without a call in the common case (finite,
    /// range `>= 0`, elevation in `[-pi/2, pi/2]`).
    #[inline(always)]
    fn check_measurement(z: &[f64; 3]) -> Result<(), NavError> {
        if crate::numerics::all_finite(z)
            && z[0] >= 0.0
            && z[2].abs() <= std::f64::consts::FRAC_PI_2
        {
            Ok(())
        } else {
            Self::check_measurement_in_full(z)
        }
    }

    #[cold]
    #[inline(never)]
    fn check_measurement_in_full(z: &[f64; 3]) -> Result<(), NavError> {
        finite3("measurement (range, azimuth, elevation)", z)?;
        if z[0] < 0.0 {
            return Err(NavError::invalid(format!(
                "measured range must be >= 0 (got {})",
                num(z[0])
            )));
        }
        if z[2].abs() > std::f64::consts::FRAC_PI_2 {
            return Err(NavError::invalid(format!(
                "measured elevation must lie in [-pi/2, pi/2] (got {})",
                num(z[2])
            )));
        }
        Ok(())
    }

    fn check_not_failed(&self) -> Result<(), NavError> {
        if self.failed {
            Err(NavError {
                kind: NavErrorKind::Numerical,
                message: format!(
                    "the {} particle filter failed in an earlier step (its prediction after \
                     a successful update) and its particles are no longer valid: reset the \
                     estimator",
                    self.cfg.filter.name()
                ),
            })
        } else {
            Ok(())
        }
    }

    /// Time update over `dt` [s] with thrust `thrust` [N] (I/O frame) held constant.
    pub fn predict(&mut self, thrust: &[f64; 3], dt: f64) -> Result<(), NavError> {
        self.check_dt(dt)?;
        finite3("thrust", thrust)?;
        self.check_not_failed()?;
        self.predict_checked(thrust, dt)
    }

    /// [`Navigator::predict`] once its inputs are checked.
    fn predict_checked(&mut self, thrust: &[f64; 3], dt: f64) -> Result<(), NavError> {
        let accel = canonical_accel(&self.cfg, thrust);
        self.discrete(dt);
        // the cached model by reference (no copy of its ~100 numbers per step)
        self.filter
            .predict(&self.step_cache, &accel)
            .map_err(NavError::from)
    }

    /// Measurement update with `(range [m], azimuth [rad], elevation [rad])` in the I/O frame.
    /// The particle filters weigh with the configured noise density, the Kalman filters use
    /// the Gaussian of its variance.
    pub fn update(&mut self, z: &[f64; 3]) -> Result<UpdateInfo, NavError> {
        Self::check_measurement(z)?;
        self.check_not_failed()?;
        self.update_checked(z)
    }

    /// [`Navigator::update`] once its input is checked.
    fn update_checked(&mut self, z: &[f64; 3]) -> Result<UpdateInfo, NavError> {
        let zv = Vec3::from_row_slice(z);
        let r = match &mut self.filter {
            AnyFilter::Pf(pf) => pf.update_with(&self.sensor, &zv, &self.noise, &self.scales),
            other => other.update(&self.kalman_sensor, &zv),
        };
        let info = r?;
        self.last_update = Some(info);
        Ok(info)
    }

    /// One step: update with `measurement` (taken at the step's start, if any), then predict
    /// over `dt` with `thrust` held. All inputs are checked before anything changes; a
    /// failed step leaves the estimate as it was, except a particle filter whose
    /// prediction fails after a successful update, which is marked failed (see the type's
    /// documentation).
    pub fn step(
        &mut self,
        thrust: &[f64; 3],
        measurement: Option<&[f64; 3]>,
        dt: f64,
    ) -> Result<(), NavError> {
        self.check_dt(dt)?;
        finite3("thrust", thrust)?;
        if let Some(z) = measurement {
            Self::check_measurement(z)?;
        }
        self.check_not_failed()?;
        // the EKF's update and prediction commit together (no snapshot to copy); the
        // discrete model is a cache of `dt` alone
        self.discrete(dt);
        if let (AnyFilter::Ekf(f), Some(z)) = (&mut self.filter, measurement) {
            let accel = canonical_accel(&self.cfg, thrust);
            let zv = Vec3::from_row_slice(z);
            let info = f.update_predict(&self.kalman_sensor, &zv, &self.step_cache, &accel)?;
            self.last_update = Some(info);
            return Ok(());
        }
        // the UKF's likewise (issue 15: the snapshot and its copies were ~40 % of its FMU
        // cycle's overhead)
        if let (AnyFilter::Ukf(f), Some(z)) = (&mut self.filter, measurement) {
            let accel = canonical_accel(&self.cfg, thrust);
            let zv = Vec3::from_row_slice(z);
            let info = f.update_predict(&self.kalman_sensor, &zv, &self.step_cache, &accel)?;
            self.last_update = Some(info);
            return Ok(());
        }
        // other Kalman-type filters: a small snapshot on the stack to restore
        let saved = self.filter.snapshot();
        let last = self.last_update;
        let mut updated = false;
        // checked above, once
        let result = match measurement {
            Some(z) => self.update_checked(z).map(|_| updated = true),
            None => Ok(()),
        }
        .and_then(|()| self.predict_checked(thrust, dt));
        if result.is_err() {
            match saved {
                // a particle filter's failed update or prediction changed nothing by
                // itself; a failed prediction after a committed update cannot be undone
                Snapshot::None => self.failed |= updated,
                s => {
                    self.filter.restore(&s);
                    self.last_update = last;
                }
            }
        }
        result
    }

    /// Back to the initial estimate. A particle filter is rebuilt from its settings (new
    /// particles drawn with the configured seed), so a reset navigator reproduces a new one
    /// bit for bit; a failed particle filter works again.
    pub fn reset(&mut self) {
        let (x0, p0) = (self.cfg.initial_state(), self.cfg.initial_covariance());
        match &mut self.filter {
            AnyFilter::Pf(pf) => *pf = ParticleFilter::new(x0, p0, *pf.params()),
            AnyFilter::Aqukf(f) => f.reset(x0, p0),
            AnyFilter::Imm(f) => f.reset(x0, p0),
            other => other.set_estimate(x0, p0),
        }
        self.last_update = None;
        self.failed = false;
    }

    /// State estimate in the I/O frame.
    pub fn state(&self) -> State {
        self.cfg.frame.state_from_canonical(self.filter.state())
    }

    /// Covariance in the I/O frame.
    pub fn covariance(&self) -> Mat6 {
        self.cfg.frame.cov_from_canonical(self.filter.covariance())
    }

    /// 1-sigma per state component in the I/O frame: the square roots of the covariance's
    /// diagonal. A NaN or negative variance (a failed filter; the H-infinity filter, which
    /// has no covariance) gives NaN, never a reassuring 0. The C ABI, the FMU and the
    /// Python package all report this.
    pub fn sigma(&self) -> [f64; 6] {
        let p = self
            .cfg
            .frame
            .variances_from_canonical(self.filter.covariance());
        std::array::from_fn(|i| {
            let v = p[i];
            if v >= 0.0 {
                v.sqrt()
            } else {
                f64::NAN
            }
        })
    }

    /// Diagnostics of the last measurement update, if any since construction or reset.
    /// The particle filters report the innovation of their weighted mean and no NIS (NaN).
    pub fn last_update(&self) -> Option<UpdateInfo> {
        self.last_update
    }

    /// Effective sample size `1 / sum w_i^2` of a particle filter after its last update
    /// (before resampling; the particle count before the first update), in
    /// `[1, particles]` (clamped there against rounding of the normalised weights). `None`
    /// for the Kalman filters, which carry no particles.
    pub fn ess(&self) -> Option<f64> {
        match &self.filter {
            AnyFilter::Pf(pf) => Some(pf.ess().clamp(1.0, pf.params().particles as f64)),
            _ => None,
        }
    }

    /// The AQUKF's current adaptive velocity density `q_vv` [m^2/s^3] in the I/O frame:
    /// the diagonal of `T blockdiag(0, diag(q_vv)) T^T`. Every frame rotation is a signed
    /// permutation, so the rotated matrix is diagonal again and this is exact (entries
    /// permuted). `None` for the other filters.
    pub fn q_vv(&self) -> Option<[f64; 3]> {
        match &self.filter {
            AnyFilter::Aqukf(f) => {
                let q = f.q_vv();
                let c =
                    Mat6::from_diagonal(&State::from_row_slice(&[0.0, 0.0, 0.0, q[0], q[1], q[2]]));
                let io = self.cfg.frame.cov_from_canonical(&c);
                Some([io[(3, 3)], io[(4, 4)], io[(5, 5)]])
            }
            _ => None,
        }
    }

    /// The IMM's (filter code 10) mode probabilities after the last step, NaN past
    /// `imm_modes`; `None` for the other filters.
    pub fn mode_probabilities(&self) -> Option<[f64; MAX_MODES]> {
        match &self.filter {
            AnyFilter::Imm(f) => {
                let mu = f.mode_probabilities();
                let r = f.params().modes;
                Some(std::array::from_fn(
                    |j| {
                        if j < r {
                            mu[j]
                        } else {
                            f64::NAN
                        }
                    },
                ))
            }
            _ => None,
        }
    }

    /// The certified `gamma` of the H-infinity design (filter code 9), `None` otherwise.
    pub fn hinf_gamma(&self) -> Option<f64> {
        match &self.filter {
            AnyFilter::Hinf(f) => Some(f.gamma()),
            _ => None,
        }
    }

    /// How the H-infinity filter was designed (filter code 9; route, Riccati record,
    /// iterations: [`crate::hinf::HinfDesignInfo`]), `None` otherwise.
    pub fn hinf_design_info(&self) -> Option<crate::hinf::HinfDesignInfo> {
        match &self.filter {
            AnyFilter::Hinf(f) => f.design_info().copied(),
            _ => None,
        }
    }

    /// The H2 norm of the H-infinity design (filter code 9; see
    /// [`crate::hinf::design::HinfDesign::h2_norm`]), `None` otherwise.
    pub fn hinf_h2_norm(&self) -> Option<f64> {
        match &self.filter {
            AnyFilter::Hinf(f) => Some(f.h2_norm()),
            _ => None,
        }
    }

    /// Whether the H-infinity filter (code 9) runs its designed, certified gain (true
    /// after the hand-over of track initiation, or always without it); `None` for the
    /// other filters.
    pub fn hinf_certified(&self) -> Option<bool> {
        match &self.filter {
            AnyFilter::Hinf(f) => Some(f.certified()),
            _ => None,
        }
    }

    /// The estimator itself (canonical frame).
    pub fn filter(&self) -> &AnyFilter {
        &self.filter
    }

    /// The payload of a saved state: configuration section, navigator section, filter
    /// section (`docs/state-format.md`). The destructuring names every field: a new one
    /// does not compile until it is saved here or marked as configuration or cache.
    fn write_state(&self, w: &mut Writer<'_>) {
        let Self {
            cfg,
            // configuration: rebuilt from `cfg` by the restoring navigator
            model: _,
            sensor: _,
            kalman_sensor: _,
            noise: _,
            scales: _,
            filter,
            // a cache of the discrete model per step size, recomputed from `cfg` (same bits)
            step_cache: _,
            last_update,
            failed,
        } = self;
        w.tag(b"CONF");
        cfg.write_settings(w);
        w.tag(b"NAVG");
        w.bool(*failed);
        // always the same size: zeros in place of an absent last update
        let u = last_update.unwrap_or_default();
        w.bool(last_update.is_some());
        w.matrix(&u.innovation);
        w.f64(u.nis);
        w.bool(u.azimuth_used);
        filter.save_state(w);
    }

    /// The identity block of a saved state's header: filter code (i32 LE), configuration
    /// fingerprint (u32 LE, [`NavConfig::fingerprint`]).
    fn state_ident(&self) -> [u8; 8] {
        let mut id = [0u8; 8];
        id[..4].copy_from_slice(&(self.cfg.filter as i32).to_le_bytes());
        id[4..].copy_from_slice(&self.cfg.fingerprint().to_le_bytes());
        id
    }

    /// Size in bytes of [`Navigator::save_state`]'s output (counted, nothing allocated). It
    /// depends on the configuration only (a particle filter's grows with `particles`), not
    /// on the history: one buffer of this size holds every later state.
    pub fn state_len(&self) -> usize {
        state::sealed_len(STATE_IDENT_LEN, |w| self.write_state(w))
    }

    /// Append the complete state to `out` as explicit, versioned bytes
    /// (`docs/state-format.md`): a header (magic `RELNAVES`, [`STATE_FORMAT_VERSION`],
    /// filter code, configuration fingerprint, payload length, CRC-32) and a payload with
    /// the configuration, the navigator's own state (failure flag, last-update
    /// diagnostics) and the filter's (particles, weights and generator state, the AQUKF
    /// window, the H-infinity matrices, ...). [`Navigator::restore_state`] on a navigator
    /// of the same configuration — this one or another, in this process or another —
    /// continues bit for bit as this one would.
    pub fn save_state(&self, out: &mut Vec<u8>) {
        let ident = self.state_ident();
        state::seal(out, ESTIMATOR_MAGIC, STATE_FORMAT_VERSION, &ident, |w| {
            self.write_state(w)
        });
    }

    /// Restore a state saved by [`Navigator::save_state`]. Refused with
    /// [`NavErrorKind::InvalidState`] and a reason when the bytes are truncated or
    /// corrupted (length, CRC-32), of another format version or kind, or saved for another
    /// configuration (the message names the first setting that differs); a malformed field
    /// (a permutation that is none, an index out of range, a non-finite estimate) is
    /// refused too. Transactional: on error nothing changes.
    pub fn restore_state(&mut self, bytes: &[u8]) -> Result<(), NavError> {
        let o = state::open(
            bytes,
            ESTIMATOR_MAGIC,
            STATE_FORMAT_VERSION,
            STATE_IDENT_LEN,
            "a relnav estimator state",
            &KINDS,
        )?;
        let mut id = Reader::new(o.ident);
        let code = id.i32("filter code")?;
        let fingerprint = id.u32("configuration fingerprint")?;
        if code != self.cfg.filter as i32 {
            let name = FilterKind::from_code(code).map_or("unknown", FilterKind::name);
            return Err(refuse(format!(
                "the state is for filter {code} ({name}), this estimator runs filter {} ({})",
                self.cfg.filter as i32,
                self.cfg.filter.name()
            ))
            .into());
        }
        let mut r = Reader::new(o.payload);
        r.tag(b"CONF")?;
        let conf_at = r.position();
        let mine = self.cfg.settings();
        let n = r.u32("number of settings")? as usize;
        if n != mine.len() {
            return Err(refuse(format!(
                "the state records {n} settings, this build has {}",
                mine.len()
            ))
            .into());
        }
        for (name, v) in &mine {
            let b = r.u64(name)?;
            if b != v.bits() {
                return Err(refuse(format!(
                    "the state was saved for another configuration: {name} = {} in the \
                     state, {v} in this estimator",
                    v.with_bits(b)
                ))
                .into());
            }
        }
        let conf = o.payload.get(conf_at..r.position()).unwrap_or_default();
        if crc32(conf) != fingerprint || fingerprint != self.cfg.fingerprint() {
            return Err(refuse(format!(
                "configuration fingerprint {fingerprint:08x} of the header does not match the \
                 configuration it carries ({:08x})",
                crc32(conf)
            ))
            .into());
        }
        r.tag(b"NAVG")?;
        let failed = r.bool("failure flag")?;
        let present = r.bool("last-update flag")?;
        let u = UpdateInfo {
            innovation: r.matrix("last innovation")?,
            nis: r.f64("last NIS")?,
            azimuth_used: r.bool("last azimuth-used flag")?,
        };
        let last_update = present.then_some(u);
        let mut filter = self.filter.clone();
        filter.load_state(&mut r)?;
        r.finish()?;
        // a crafted state behind a valid checksum can carry fields a filter reads without
        // a finiteness check (a particle filter's weighted mean): the estimate handed out
        // must be numbers (fuzz finding, `tests/robustness.rs`). The covariance is not
        // checked: a reachable state may hold an infinite one (particles spread beyond
        // 1e154 m by absurd thrust), and it must restore.
        if !filter.state().iter().all(|v| v.is_finite()) {
            return Err(refuse(
                "the state's estimate is not finite (a crafted or corrupted state behind a \
                 valid checksum)",
            )
            .into());
        }
        // commit: nothing below can fail
        self.filter = filter;
        self.last_update = last_update;
        self.failed = failed;
        Ok(())
    }
}

/// Format version of [`Navigator::save_state`]'s bytes. Bump it whenever the layout
/// changes (a field added to a filter's `Persist`, a new setting); a state of another
/// version is refused, never misread.
pub const STATE_FORMAT_VERSION: u32 = 1;

/// Length of the identity block of an estimator state's header (filter code, fingerprint).
const STATE_IDENT_LEN: usize = 8;
