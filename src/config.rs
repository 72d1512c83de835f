//! `relnav_config`, its C-facing enums and the conversion to and from [`NavConfig`].

use crate::error::{null, relnav_status};
use crate::panic::boundary;
use relnav_core::dynamics::Discretization;
use relnav_core::estimators::pf::resample::Resampler;
use relnav_core::estimators::{AdaptationLaw, UkfParams};
use relnav_core::frames::Frame;
use relnav_core::nav::{FilterKind, HinfDesignKind, NavConfig, NavError, NavErrorKind, NoiseKind};

/// Filter codes for `relnav_config.filter` (same as the FMU's `filter` parameter).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub enum relnav_filter {
    /// Extended Kalman filter (Joseph-form update).
    RELNAV_FILTER_EKF = 1,
    /// Unscented Kalman filter (scaled sigma points).
    RELNAV_FILTER_UKF = 2,
    /// Sliding-window adaptive UKF (paper 001): adaptive velocity process noise, `window`,
    /// `q_vv_floor`, `q_vv_ceiling`; `relnav_estimator_get_q_vv` reports it.
    RELNAV_FILTER_AQUKF = 3,
    /// SIR (bootstrap) particle filter (paper 000), with the posterior-invariant moves of
    /// `pf_move` (the literal SIR without them keeps impoverished velocities: metres off
    /// on paper 000's example after 100 s).
    RELNAV_FILTER_PF = 4,
    /// Regularised particle filter (kernel jitter after resampling).
    RELNAV_FILTER_RPF = 5,
    /// Unscented particle filter (per-particle UKF proposal).
    RELNAV_FILTER_UPF = 6,
    /// Genetic-algorithm particle filter (crossover and mutation after resampling).
    RELNAV_FILTER_GAPF = 7,
    /// Cloud-genetic particle filter (paper 003): UKF proposal, cloud-model genetic moves.
    RELNAV_FILTER_CGAPF = 8,
    /// Robust H-infinity filter (paper 002): observer form designed by an LMI (Clarabel)
    /// when the estimator is created, for the open-loop CW plant and `hinf_period`; its
    /// covariance and sigma are NaN (no Gaussian covariance exists).
    RELNAV_FILTER_HINF = 9,
    /// Interacting multiple-model filter (Blom & Bar-Shalom 1988): `imm_modes` EKFs on the
    /// CW model, mode `j` with the configured process noise plus a white acceleration of
    /// density `imm_accel_psd[j]`, Markov switching with per-second staying probabilities
    /// `imm_p_stay`; `relnav_estimator_get_mode_probabilities` reports the modes.
    RELNAV_FILTER_IMM = 10,
}

/// Adaptation laws of the AQUKF for `relnav_config.aq_law` (same codes as the FMU's
/// `aq_law` parameter).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub enum relnav_adaptation {
    /// Paper 001 literally: the sliding-window estimate of `q_vv` at every update.
    RELNAV_ADAPTATION_WINDOW = 1,
    /// The default: `q_vv` stays at `q_vel` while the windowed normalised innovation
    /// squared (`aq_gate_window` updates) is below its chi-square quantile
    /// `aq_gate_quantile`, and follows the sliding window (never below `q_vel`) while it
    /// is above.
    RELNAV_ADAPTATION_GATED = 2,
}

/// Frame codes for `relnav_config.frame` (see ARCHITECTURE.md, "Frames").
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub enum relnav_frame {
    /// Canonical Hill frame: x radial outward, y along-track, z orbit normal (paper 002).
    RELNAV_FRAME_RADIAL_ALONG_NORMAL = 1,
    /// Paper 000: x along-track, y radial outward, z minus orbit normal.
    RELNAV_FRAME_ALONG_RADIAL_ANTINORMAL = 2,
    /// Paper 003: x along-track, y minus orbit normal, z nadir.
    RELNAV_FRAME_ALONG_ANTINORMAL_NADIR = 3,
}

/// Discretisation codes for `relnav_config.discretization`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub enum relnav_discretization {
    /// Exact CW transition, exact zero-order-hold input, Van Loan process noise.
    RELNAV_DISCRETIZATION_EXACT = 1,
    /// First-order Euler `I + T A` (only to reproduce paper 000 literally).
    RELNAV_DISCRETIZATION_EULER = 2,
}

/// Resampling schemes for `relnav_config.resampler` (particle filters only).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub enum relnav_resampler {
    /// `N` independent draws from the weights (paper 000's SIR).
    RELNAV_RESAMPLER_MULTINOMIAL = 1,
    /// One uniform, `N` evenly spaced points (Kitagawa 1996); the default.
    RELNAV_RESAMPLER_SYSTEMATIC = 2,
    /// One uniform per stratum (Kitagawa 1996).
    RELNAV_RESAMPLER_STRATIFIED = 3,
    /// `floor(N w_i)` deterministic copies, the rest multinomial (Liu & Chen 1998).
    RELNAV_RESAMPLER_RESIDUAL = 4,
}

/// Measurement-noise densities for `relnav_config.noise_model`, each scaled by
/// `sigma_range` / `sigma_angle`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub enum relnav_noise_model {
    /// Gaussian `N(0, sigma^2)`.
    RELNAV_NOISE_GAUSSIAN = 1,
    /// Contaminated Gaussian `(1 - zeta) N(0, sigma^2) + zeta N(0, (scale sigma)^2)`
    /// (`noise_zeta`, `noise_scale`; paper 003).
    RELNAV_NOISE_MIXTURE = 2,
    /// Student-t `sigma t_dof` (`noise_dof`).
    RELNAV_NOISE_STUDENT_T = 3,
}

/// Estimator configuration. Get the defaults (paper 000's example) from
/// [`relnav_config_default`], then change what you need. Enum fields are plain integers so
/// that an unknown value is reported, not undefined behaviour.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct relnav_config {
    /// A `relnav_filter` code (1 EKF, 2 UKF, 3 AQUKF, 4-8 particle filters, 9 H-infinity,
    /// 10 IMM).
    pub filter: i32,
    /// A `relnav_frame` code: the frame of every vector and angle passed in and out.
    pub frame: i32,
    /// A `relnav_discretization` code.
    pub discretization: i32,
    /// Target mean motion [rad/s], > 0.
    pub mean_motion: f64,
    /// Chaser mass [kg], > 0.
    pub chaser_mass: f64,
    /// Range noise scale [m], > 0: the 1 sigma of a Gaussian `noise_model`, the nominal
    /// sigma of the others.
    pub sigma_range: f64,
    /// Azimuth and elevation noise scale [rad], > 0 (as `sigma_range`).
    pub sigma_angle: f64,
    /// Initial estimate (x, y, z [m], vx, vy, vz [m/s]); `|x0_i| + 100 sigma` (sigma of
    /// its group, `sigma_pos0` or `sigma_vel0`) must not exceed 1e150.
    pub x0: [f64; 6],
    /// Initial position 1 sigma per axis [m], > 0.
    pub sigma_pos0: f64,
    /// Initial velocity 1 sigma per axis [m/s], > 0.
    pub sigma_vel0: f64,
    /// Continuous white-acceleration spectral density per axis [m^2/s^3], >= 0.
    pub accel_psd: f64,
    /// Position variance rate per axis [m^2/s], >= 0 (discrete Q = q_pos * h).
    pub q_pos: [f64; 3],
    /// Velocity variance rate per axis [m^2/s^3], >= 0 (discrete Q = q_vel * h).
    pub q_vel: [f64; 3],
    /// UKF sigma-point spread alpha (> 0); also the unscented proposal of UPF and CGA-PF.
    pub ukf_alpha: f64,
    /// UKF beta (2 for Gaussian priors).
    pub ukf_beta: f64,
    /// UKF kappa.
    pub ukf_kappa: f64,
    /// Seed for filters that draw random numbers (the particle filters): identical seeds
    /// give bit-identical outputs, also after `relnav_estimator_reset`.
    pub seed: u64,
    /// Number of particles of the particle filters (codes 4-8), 1..=2000000 (default 1500).
    pub particles: i32,
    /// A `relnav_resampler` code (default 2, systematic).
    pub resampler: i32,
    /// Resample when the effective sample size drops below `resample_threshold * particles`;
    /// in (0, 1] (default 2/3, paper 000).
    pub resample_threshold: f64,
    /// A `relnav_noise_model` code (default 1, Gaussian). The particle filters weigh with
    /// this density; the Kalman filters assume the Gaussian of its variance (`sigma^2` times
    /// `1 - zeta + zeta scale^2` for the mixture, `dof / (dof - 2)` for the Student-t), so
    /// every filter sees the same noise statistics.
    pub noise_model: i32,
    /// Mixture: weight of the wide component, in [0, 1) (default 0.2).
    pub noise_zeta: f64,
    /// Mixture: the wide component's sigma over the nominal one, >= 1 (default 10).
    pub noise_scale: f64,
    /// Student-t: degrees of freedom, > 2 (default 4).
    pub noise_dof: f64,
    /// AQUKF (code 3): sliding-window width N, 1..=512 (default 10, paper 001).
    pub window: i32,
    /// AQUKF: lower bound of each adaptive velocity density `q_vv` [m^2/s^3], >= 0
    /// (default 0). For the AQUKF, `q_vel` is the initial `q_vv`.
    pub q_vv_floor: f64,
    /// AQUKF: upper bound of each `q_vv` [m^2/s^3], finite, > 0, >= `q_vv_floor` (default 1).
    pub q_vv_ceiling: f64,
    /// H-infinity filter (code 9): the sampling period of its discrete design [s], > 0
    /// (default 1). A step of another length is refused with `RELNAV_ERROR_INVALID_ARGUMENT`.
    pub hinf_period: f64,
    /// H-infinity filter: orbit-rate uncertainty bound `delta_bar`, >= 0 (default 0.05).
    pub hinf_delta_bar: f64,
    /// H-infinity filter: process-noise scaling on positions [m], >= 0 (paper 002: 0.05).
    /// Default 0 together with `hinf_b_vel = 0`: the design's process noise is derived
    /// from `accel_psd`, `q_pos`, `q_vel` (what the other filters use); both > 0: `B =
    /// diag(b_pos I3, b_vel I3)`.
    pub hinf_b_pos: f64,
    /// H-infinity filter: process-noise scaling on velocities [m/s], >= 0 (paper 002:
    /// 0.001; default 0 = derived, see `hinf_b_pos`).
    pub hinf_b_vel: f64,
    /// H-infinity filter: indirect-position measurement-noise scaling [m], >= 0 (paper
    /// 002: 0.1). Default 0: derived from `sigma_range`, `sigma_angle` and the noise model
    /// at the initial estimate's position.
    pub hinf_d: f64,
    /// H-infinity filter: the design, a `relnav_hinf_form` code: 3 mixed H2/H-infinity
    /// (default; least H2 norm under `gamma <= hinf_gamma_factor * gamma_opt`) or 1 the
    /// gamma-optimal observer.
    pub hinf_design: i32,
    /// H-infinity filter, mixed design: bound on the certified gamma as a multiple of the
    /// gamma-optimal design's, finite and > 1 (default 1.5).
    pub hinf_gamma_factor: f64,
    /// H-infinity filter: 1 (default) to start with the Kalman gain of the design's noise
    /// model and hand over to the designed gain when that is no worse (track initiation),
    /// 0 to run the designed gain from the first step.
    pub hinf_acquisition: i32,
    /// AQUKF (code 3): a `relnav_adaptation` code (default 2, gated; 1 is paper 001's
    /// window at every update).
    pub aq_law: i32,
    /// AQUKF, gated law: updates in the windowed NIS, 1..=128 (default 10).
    pub aq_gate_window: i32,
    /// AQUKF, gated law: chi-square probability of the NIS gate, in (0, 1) (default 0.999).
    pub aq_gate_quantile: f64,
    /// IMM (code 10): number of modes, 2 or 3 (default 3).
    pub imm_modes: i32,
    /// IMM: white-acceleration density added to the process noise in each mode
    /// [m^2/s^3], >= 0 (default 0, 1e-6, 1e-3; the third is unused with 2 modes).
    pub imm_accel_psd: [f64; 3],
    /// IMM: probability of staying in each mode over one second, in (0, 1)
    /// (default 0.99999, 0.9, 0.9).
    pub imm_p_stay: [f64; 3],
    /// Particle filters (codes 4-8): 1 (default) moves the particles with
    /// posterior-invariant Metropolis–Hastings steps after every update (accurate as the
    /// EKF on Gaussian noise, also with small process noise); 0 runs the papers' literal
    /// filters (paper 000's SIR, plain RPF, van der Merwe's UPF). Other values are refused.
    pub pf_move: i32,
    /// Particle filters: worker threads of the particle loops from 32768 particles on
    /// (0, the default: one per core; 1: the calling thread; at most 1024). The results
    /// do not depend on it.
    pub pf_threads: i32,
}

impl From<&NavConfig> for relnav_config {
    fn from(c: &NavConfig) -> Self {
        relnav_config {
            filter: c.filter as i32,
            frame: c.frame.code(),
            discretization: c.discretization as i32,
            mean_motion: c.mean_motion,
            chaser_mass: c.chaser_mass,
            sigma_range: c.sigma_range,
            sigma_angle: c.sigma_angle,
            x0: c.x0,
            sigma_pos0: c.sigma_pos0,
            sigma_vel0: c.sigma_vel0,
            accel_psd: c.accel_psd,
            q_pos: c.q_pos,
            q_vel: c.q_vel,
            ukf_alpha: c.ukf.alpha,
            ukf_beta: c.ukf.beta,
            ukf_kappa: c.ukf.kappa,
            seed: c.seed,
            particles: i32::try_from(c.particles).unwrap_or(i32::MAX),
            resampler: c.resampler as i32,
            resample_threshold: c.resample_threshold,
            noise_model: c.noise_model as i32,
            noise_zeta: c.noise_zeta,
            noise_scale: c.noise_scale,
            noise_dof: c.noise_dof,
            window: i32::try_from(c.window).unwrap_or(i32::MAX),
            q_vv_floor: c.q_vv_floor,
            q_vv_ceiling: c.q_vv_ceiling,
            hinf_period: c.hinf_period,
            hinf_delta_bar: c.hinf_delta_bar,
            hinf_b_pos: c.hinf_b_pos,
            hinf_b_vel: c.hinf_b_vel,
            hinf_d: c.hinf_d,
            hinf_design: c.hinf_design as i32,
            hinf_gamma_factor: c.hinf_gamma_factor,
            hinf_acquisition: i32::from(c.hinf_acquisition),
            aq_law: c.aq_law as i32,
            aq_gate_window: i32::try_from(c.aq_gate_window).unwrap_or(i32::MAX),
            aq_gate_quantile: c.aq_gate_quantile,
            imm_modes: i32::try_from(c.imm_modes).unwrap_or(i32::MAX),
            imm_accel_psd: c.imm_accel_psd,
            imm_p_stay: c.imm_p_stay,
            pf_move: i32::from(c.pf_move),
            pf_threads: i32::try_from(c.pf_threads).unwrap_or(i32::MAX),
        }
    }
}

impl TryFrom<&relnav_config> for NavConfig {
    type Error = NavError;
    fn try_from(c: &relnav_config) -> Result<Self, NavError> {
        let bad = |what: &str, v: i32, allowed: &str| NavError {
            kind: NavErrorKind::InvalidArgument,
            message: format!("unknown {what} code {v} (allowed: {allowed})"),
        };
        let particles = usize::try_from(c.particles).map_err(|_| NavError {
            kind: NavErrorKind::InvalidArgument,
            message: format!(
                "particles must lie in 1..={} (got {})",
                relnav_core::estimators::pf::MAX_PARTICLES,
                c.particles
            ),
        })?;
        let window = usize::try_from(c.window).map_err(|_| NavError {
            kind: NavErrorKind::InvalidArgument,
            message: format!(
                "window must lie in 1..={} (got {})",
                relnav_core::estimators::MAX_WINDOW,
                c.window
            ),
        })?;
        let aq_gate_window = usize::try_from(c.aq_gate_window).map_err(|_| NavError {
            kind: NavErrorKind::InvalidArgument,
            message: format!(
                "aq_gate_window must lie in 1..={} (got {})",
                relnav_core::estimators::MAX_GATE_WINDOW,
                c.aq_gate_window
            ),
        })?;
        let imm_modes = usize::try_from(c.imm_modes).map_err(|_| NavError {
            kind: NavErrorKind::InvalidArgument,
            message: format!("imm_modes must be 2 or 3 (got {})", c.imm_modes),
        })?;
        let pf_move = match c.pf_move {
            0 => false,
            1 => true,
            v => {
                return Err(NavError {
                    kind: NavErrorKind::InvalidArgument,
                    message: format!("pf_move must be 0 or 1 (got {v})"),
                })
            }
        };
        let pf_threads = usize::try_from(c.pf_threads).map_err(|_| NavError {
            kind: NavErrorKind::InvalidArgument,
            message: format!(
                "pf_threads must lie in 0..={} (got {})",
                relnav_core::estimators::pf::MAX_THREADS,
                c.pf_threads
            ),
        })?;
        let cfg = NavConfig {
            filter: FilterKind::from_code(c.filter).ok_or_else(|| {
                bad(
                    "filter",
                    c.filter,
                    "1 ekf, 2 ukf, 3 aqukf, 4 pf, 5 rpf, 6 upf, 7 gapf, 8 cgapf, 9 hinf, 10 imm",
                )
            })?,
            frame: Frame::from_code(c.frame).ok_or_else(|| {
                bad(
                    "frame",
                    c.frame,
                    "1 radial_along_normal, 2 along_radial_antinormal, 3 along_antinormal_nadir",
                )
            })?,
            discretization: Discretization::from_code(c.discretization)
                .ok_or_else(|| bad("discretization", c.discretization, "1 exact, 2 euler"))?,
            mean_motion: c.mean_motion,
            chaser_mass: c.chaser_mass,
            sigma_range: c.sigma_range,
            sigma_angle: c.sigma_angle,
            x0: c.x0,
            sigma_pos0: c.sigma_pos0,
            sigma_vel0: c.sigma_vel0,
            accel_psd: c.accel_psd,
            q_pos: c.q_pos,
            q_vel: c.q_vel,
            ukf: UkfParams {
                alpha: c.ukf_alpha,
                beta: c.ukf_beta,
                kappa: c.ukf_kappa,
            },
            seed: c.seed,
            particles,
            resampler: Resampler::from_code(c.resampler).ok_or_else(|| {
                bad(
                    "resampler",
                    c.resampler,
                    "1 multinomial, 2 systematic, 3 stratified, 4 residual",
                )
            })?,
            resample_threshold: c.resample_threshold,
            noise_model: NoiseKind::from_code(c.noise_model).ok_or_else(|| {
                bad(
                    "noise_model",
                    c.noise_model,
                    "1 gaussian, 2 mixture, 3 student_t",
                )
            })?,
            noise_zeta: c.noise_zeta,
            noise_scale: c.noise_scale,
            noise_dof: c.noise_dof,
            window,
            q_vv_floor: c.q_vv_floor,
            q_vv_ceiling: c.q_vv_ceiling,
            hinf_period: c.hinf_period,
            hinf_delta_bar: c.hinf_delta_bar,
            hinf_b_pos: c.hinf_b_pos,
            hinf_b_vel: c.hinf_b_vel,
            hinf_d: c.hinf_d,
            hinf_design: HinfDesignKind::from_code(c.hinf_design).ok_or_else(|| {
                bad(
                    "hinf_design",
                    c.hinf_design,
                    "1 gamma_optimal (RELNAV_HINF_OBSERVER), 3 mixed (RELNAV_HINF_MIXED); the \
                     paper form (2) needs the closed loop u = K x and is for \
                     relnav_hinf_design only",
                )
            })?,
            hinf_gamma_factor: c.hinf_gamma_factor,
            hinf_acquisition: match c.hinf_acquisition {
                0 => false,
                1 => true,
                other => return Err(bad("hinf_acquisition", other, "0 off, 1 on")),
            },
            aq_law: AdaptationLaw::from_code(c.aq_law)
                .ok_or_else(|| bad("aq_law", c.aq_law, "1 window, 2 gated"))?,
            aq_gate_window,
            aq_gate_quantile: c.aq_gate_quantile,
            imm_modes,
            imm_accel_psd: c.imm_accel_psd,
            imm_p_stay: c.imm_p_stay,
            pf_move,
            pf_threads,
        };
        cfg.validate()?;
        Ok(cfg)
    }
}

/// The default configuration: paper 000's numerical example (frame 2, 7200 s orbit, EKF,
/// 0.5 m / 0.01 deg Gaussian noise, initial estimate (405, 505, 205, 0.1, 0.1, 0.1),
/// 50 m / 1 m/s initial sigma, the paper's diagonal process noise per 1 s step; for the
/// particle filters 1500 particles, systematic resampling below N_eff = 2/3 N, seed 0,
/// moves on, threads one per core).
#[no_mangle]
pub extern "C" fn relnav_config_default() -> relnav_config {
    relnav_config::from(&NavConfig::default())
}

/// Check a configuration without creating an estimator.
///
/// # Safety
/// `config` is null or points to a `relnav_config`.
#[no_mangle]
pub unsafe extern "C" fn relnav_config_validate(config: *const relnav_config) -> relnav_status {
    boundary("relnav_config_validate", || {
        // SAFETY: caller guarantees a valid or null pointer.
        let c =
            unsafe { config.as_ref() }.ok_or_else(|| null("config", "relnav_config_validate"))?;
        NavConfig::try_from(c)?;
        Ok(())
    })
}
