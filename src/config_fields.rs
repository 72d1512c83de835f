//! Generated from relnav-core's parameter table (`relnav_core::nav::PARAMS`) by
//! `RELNAV_BLESS_CODEGEN=1 cargo test --test c_config`: do not edit. The code lists'
//! enums, the `relnav_config` struct (one field per parameter, in the table's order)
//! and the access to its fields by parameter and element that `config.rs` converts with.

use relnav_core::params::Value;

/// Filter codes (`relnav_config` holds them as plain integers, so that an unknown
/// value is reported, not undefined behaviour).
#[repr(i32)]
#[derive(Debug, Clone, Copy)]
pub enum relnav_filter {
    /// Extended Kalman filter (Joseph form).
    RELNAV_FILTER_EKF = 1,
    /// Unscented Kalman filter (scaled sigma points).
    RELNAV_FILTER_UKF = 2,
    /// Sliding-window adaptive UKF (paper 001: adaptive velocity process noise, see window and q_vv_*).
    RELNAV_FILTER_AQUKF = 3,
    /// SIR particle filter (paper 000); see pf_prior (the default: a Gaussian per particle) and, for point particles, pf_move.
    RELNAV_FILTER_PF = 4,
    /// Regularised particle filter (kernel jitter after resampling).
    RELNAV_FILTER_RPF = 5,
    /// Unscented particle filter (per-particle UKF proposal).
    RELNAV_FILTER_UPF = 6,
    /// Genetic-algorithm particle filter (crossover and mutation after resampling).
    RELNAV_FILTER_GAPF = 7,
    /// Cloud-genetic particle filter (paper 003: UKF proposal, cloud-model genetic moves).
    RELNAV_FILTER_CGAPF = 8,
    /// Robust H-infinity filter (paper 002; observer form designed by an LMI at initialisation for hinf_period; sigma_* are NaN).
    RELNAV_FILTER_HINF = 9,
    /// Interacting multiple-model filter: imm_modes EKFs with the process noise plus imm_accel_psd_*, Markov switching (imm_p_stay_*); mode probabilities in imm_mu_*.
    RELNAV_FILTER_IMM = 10,
    /// Robust EKF: the radio's update uses the density of noise_model (mixture: the Gaussian-sum update collapsed to its moments; Student-t: a variational update) instead of the Gaussian of its variance; the EKF's otherwise.
    RELNAV_FILTER_REKF = 11,
}

/// Frame codes (`relnav_config` holds them as plain integers, so that an unknown
/// value is reported, not undefined behaviour).
#[repr(i32)]
#[derive(Debug, Clone, Copy)]
pub enum relnav_frame {
    /// x radial outward, y along-track, z orbit normal (canonical; paper 002).
    RELNAV_FRAME_RADIAL_ALONG_NORMAL = 1,
    /// x along-track, y radial outward, z minus orbit normal (paper 000).
    RELNAV_FRAME_ALONG_RADIAL_ANTINORMAL = 2,
    /// x along-track, y minus orbit normal, z nadir (paper 003).
    RELNAV_FRAME_ALONG_ANTINORMAL_NADIR = 3,
}

/// Discretization codes (`relnav_config` holds them as plain integers, so that an unknown
/// value is reported, not undefined behaviour).
#[repr(i32)]
#[derive(Debug, Clone, Copy)]
pub enum relnav_discretization {
    /// Exact CW transition, exact zero-order hold, Van Loan process noise.
    RELNAV_DISCRETIZATION_EXACT = 1,
    /// First-order Euler I + T A (literal paper 000).
    RELNAV_DISCRETIZATION_EULER = 2,
}

/// Resampler codes (`relnav_config` holds them as plain integers, so that an unknown
/// value is reported, not undefined behaviour).
#[repr(i32)]
#[derive(Debug, Clone, Copy)]
pub enum relnav_resampler {
    /// N independent draws from the weights (paper 000's SIR).
    RELNAV_RESAMPLER_MULTINOMIAL = 1,
    /// One uniform, N evenly spaced points (Kitagawa 1996).
    RELNAV_RESAMPLER_SYSTEMATIC = 2,
    /// One uniform per stratum (Kitagawa 1996).
    RELNAV_RESAMPLER_STRATIFIED = 3,
    /// floor(N w) deterministic copies, the rest multinomial (Liu and Chen 1998).
    RELNAV_RESAMPLER_RESIDUAL = 4,
    /// Multinomial with pf_move = false (paper 000's SIR as written), systematic with the moves.
    RELNAV_RESAMPLER_AUTO = 5,
}

/// NoiseModel codes (`relnav_config` holds them as plain integers, so that an unknown
/// value is reported, not undefined behaviour).
#[repr(i32)]
#[derive(Debug, Clone, Copy)]
pub enum relnav_noise_model {
    /// Gaussian N(0, sigma^2).
    RELNAV_NOISE_GAUSSIAN = 1,
    /// Contaminated Gaussian (1 - zeta) N(0, sigma^2) + zeta N(0, (scale sigma)^2) (paper 003).
    RELNAV_NOISE_MIXTURE = 2,
    /// Student-t sigma t_dof.
    RELNAV_NOISE_STUDENT_T = 3,
}

/// AdaptationLaw codes (`relnav_config` holds them as plain integers, so that an unknown
/// value is reported, not undefined behaviour).
#[repr(i32)]
#[derive(Debug, Clone, Copy)]
pub enum relnav_adaptation {
    /// Paper 001 literally: the sliding-window estimate of q_vv at every update.
    RELNAV_ADAPTATION_WINDOW = 1,
    /// q_vv stays at q_vel while the windowed NIS is below its chi-square quantile; the sliding window adapts it (never below q_vel) while it is above.
    RELNAV_ADAPTATION_GATED = 2,
}

/// PfPrior codes (`relnav_config` holds them as plain integers, so that an unknown
/// value is reported, not undefined behaviour).
#[repr(i32)]
#[derive(Debug, Clone, Copy)]
pub enum relnav_pf_prior {
    /// Point particles; with pf_move, moves toward the Gaussian of the predictive moments (the Gaussian particle filter).
    RELNAV_PF_PRIOR_GAUSSIAN = 1,
    /// A Gaussian per particle: a Gaussian sum whose terms are updated by their own EKF or UKF step, weighted by their predictive likelihood, resampled and kernel-smoothed; the prior of every update is the set's own predictive mixture.
    RELNAV_PF_PRIOR_PARTICLE = 2,
}

/// Estimator configuration. Get the defaults (paper 000's example) from
/// `relnav_config_default`, then change what you need. Codes and flags are plain
/// integers, so that an unknown value is reported, not undefined behaviour.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct relnav_config {
    /// Estimator (codes 1-11: 1-3 Kalman (EKF, UKF, AQUKF), 4-8 particle filters, 9 robust H-infinity, 10 IMM, 11 robust EKF).
    /// A `relnav_filter` code: 1 ekf, 2 ukf, 3 aqukf, 4 pf, 5 rpf, 6 upf, 7 gapf, 8 cgapf, 9 hinf, 10 imm, 11 rekf.
    /// Default: 1 (ekf).
    pub filter: i32,
    /// Hill-frame convention of every input and output vector and angle.
    /// A `relnav_frame` code: 1 radial_along_normal, 2 along_radial_antinormal, 3 along_antinormal_nadir.
    /// Default: 2 (along_radial_antinormal).
    pub frame: i32,
    /// Discretisation of the CW model.
    /// A `relnav_discretization` code: 1 exact, 2 euler.
    /// Default: 1 (exact).
    pub discretization: i32,
    /// Mean motion of the target's orbit, 2 pi / period (> 0).
    /// Unit: rad/s.
    /// Allowed: > 0.
    /// Default: 0.0008726646259971648.
    pub mean_motion: f64,
    /// Chaser mass: thrust / mass = acceleration (> 0).
    /// Unit: kg.
    /// Allowed: > 0.
    /// Default: 1000.
    pub chaser_mass: f64,
    /// Range measurement noise, 1 sigma of the Gaussian (nominal sigma of the other noise models; > 0).
    /// Unit: m.
    /// Allowed: > 0.
    /// Default: 0.5.
    pub sigma_range: f64,
    /// Azimuth and elevation measurement noise, 1 sigma of the Gaussian (nominal sigma of the other noise models; > 0).
    /// Unit: rad.
    /// Allowed: > 0.
    /// Default: 0.00017453292519943296.
    pub sigma_angle: f64,
    /// Initial estimate (x, y, z [m], vx, vy, vz [m/s]) in the I/O frame; |x0_i| + 100 sigma (of its group: the larger of sigma_pos0 and sigma_range0, or sigma_vel0) must not exceed 1e150.
    /// `[0]` x0 [m]
    /// `[1]` y0 [m]
    /// `[2]` z0 [m]
    /// `[3]` vx0 [m/s]
    /// `[4]` vy0 [m/s]
    /// `[5]` vz0 [m/s]
    /// Default: 405, 505, 205, 0.1, 0.1, 0.1.
    pub x0: [f64; 6],
    /// Initial position uncertainty per axis, 1 sigma (> 0).
    /// Unit: m.
    /// Allowed: > 0.
    /// Default: 50.
    pub sigma_pos0: f64,
    /// Initial velocity uncertainty per axis, 1 sigma (> 0).
    /// Unit: m/s.
    /// Allowed: > 0.
    /// Default: 1.
    pub sigma_vel0: f64,
    /// Process noise: spectral density of a continuous white acceleration per axis (Van Loan discretisation; >= 0).
    /// Unit: m2/s3.
    /// Allowed: >= 0.
    /// Default: 0.
    pub accel_psd: f64,
    /// Process noise: position variance rate per I/O axis (discrete Q = q_pos h; >= 0); paper 000's Q per 1 s step by default.
    /// `[0]` q_pos_x [m2/s]
    /// `[1]` q_pos_y [m2/s]
    /// `[2]` q_pos_z [m2/s]
    /// Allowed: >= 0.
    /// Default: 0.09, 0.000625, 0.0025.
    pub q_pos: [f64; 3],
    /// Process noise: velocity variance rate per I/O axis (discrete Q = q_vel h; >= 0); for the AQUKF the initial adaptive density q_vv.
    /// `[0]` q_vel_x [m2/s3]
    /// `[1]` q_vel_y [m2/s3]
    /// `[2]` q_vel_z [m2/s3]
    /// Allowed: >= 0.
    /// Default: 1e-6, 1e-6, 1e-6.
    pub q_vel: [f64; 3],
    /// UKF sigma-point spread alpha (> 0); also the unscented proposal of upf and cgapf.
    /// Default: 1.
    pub ukf_alpha: f64,
    /// UKF beta (2 for Gaussian priors).
    /// Default: 2.
    pub ukf_beta: f64,
    /// UKF kappa.
    /// Default: 0.
    pub ukf_kappa: f64,
    /// Seed of the filters that draw random numbers (identical seeds give identical outputs).
    /// Default: 0.
    pub seed: u64,
    /// Number of particles of the particle filters (codes 4-8; 1..2000000).
    /// Allowed: 1..=2000000.
    /// Default: 1500.
    pub particles: i32,
    /// Resampling scheme of the particle filters (auto: multinomial with pf_move = false, systematic with the moves).
    /// A `relnav_resampler` code: 1 multinomial, 2 systematic, 3 stratified, 4 residual, 5 auto.
    /// Default: 5 (auto).
    pub resampler: i32,
    /// The particle filters resample when the effective sample size drops below resample_threshold * particles (in (0, 1]; paper 000: 2/3).
    /// Allowed: in (0, 1].
    /// Default: 0.6666666666666666.
    pub resample_threshold: f64,
    /// Measurement-noise density scaled by sigma_range and sigma_angle: the particle filters weigh with it, the Kalman filters assume the Gaussian of its variance.
    /// A `relnav_noise_model` code: 1 gaussian, 2 mixture, 3 student_t.
    /// Default: 1 (gaussian).
    pub noise_model: i32,
    /// Mixture noise: weight of the wide component (in [0, 1)).
    /// Allowed: in [0, 1).
    /// Default: 0.2.
    pub noise_zeta: f64,
    /// Mixture noise: sigma of the wide component over the nominal sigma (>= 1).
    /// Allowed: >= 1.
    /// Default: 10.
    pub noise_scale: f64,
    /// Student-t noise: degrees of freedom (> 2).
    /// Allowed: > 2.
    /// Default: 4.
    pub noise_dof: f64,
    /// AQUKF (filter 3): sliding-window width N of the adaptive process noise (1..512; paper 001: 10). For the AQUKF, q_vel_* is the initial adaptive density.
    /// Allowed: 1..=512.
    /// Default: 10.
    pub window: i32,
    /// AQUKF: lower bound of each adaptive q_vv entry (>= 0).
    /// Unit: m2/s3.
    /// Allowed: >= 0.
    /// Default: 0.
    pub q_vv_floor: f64,
    /// AQUKF: upper bound of each adaptive q_vv entry (finite, > 0 and >= q_vv_floor).
    /// Unit: m2/s3.
    /// Default: 1.
    pub q_vv_ceiling: f64,
    /// H-infinity filter (code 9): sampling period of its discrete design; fmi2DoStep with another step size is refused (set it to the communication step).
    /// Unit: s.
    /// Default: 1.
    pub hinf_period: f64,
    /// H-infinity filter: bound of the orbit-rate uncertainty, w = w0 (1 + delta), |delta| <= hinf_delta_bar (paper 002: 0.05).
    /// Default: 0.05.
    pub hinf_delta_bar: f64,
    /// H-infinity filter: process-noise scaling on positions (paper 002 B: 0.05); 0 with hinf_b_vel = 0 (default): derived from accel_psd, q_pos_*, q_vel_* (the noise every other filter uses).
    /// Unit: m.
    /// Allowed: >= 0.
    /// Default: 0.
    pub hinf_b_pos: f64,
    /// H-infinity filter: process-noise scaling on velocities (paper 002 B: 0.001); 0 with hinf_b_pos = 0 (default): derived.
    /// Unit: m/s.
    /// Allowed: >= 0.
    /// Default: 0.
    pub hinf_b_vel: f64,
    /// H-infinity filter: scaling of the indirect position measurement noise (paper 002 D: 0.1); 0 (default): derived from sigma_range, sigma_angle and the noise model at the initial estimate's position.
    /// Unit: m.
    /// Allowed: >= 0.
    /// Default: 0.
    pub hinf_d: f64,
    /// H-infinity filter: the LMI design (mixed H2/H-infinity by default; gamma_optimal is the pure worst-case design).
    /// A `relnav_hinf_form` code: 1 gamma_optimal, 3 mixed.
    /// Default: 3 (mixed).
    pub hinf_design: i32,
    /// H-infinity filter, mixed design: bound on the certified gamma (hinf_gamma) as a multiple of the gamma-optimal design's (> 1).
    /// Allowed: > 1.
    /// Default: 1.5.
    pub hinf_gamma_factor: f64,
    /// H-infinity filter: start with the Kalman gain of the design's noise model and hand over to the designed gain once that is no worse (track initiation); false: the designed gain from the first step.
    /// 0 or 1.
    /// Default: 1.
    pub hinf_acquisition: i32,
    /// AQUKF (filter 3): adaptation law of the velocity process noise (1 window: paper 001 at every update; 2 gated: only while the windowed NIS exceeds its chi-square bound).
    /// A `relnav_adaptation` code: 1 window, 2 gated.
    /// Default: 2 (gated).
    pub aq_law: i32,
    /// AQUKF, gated law: number of measurement updates in the windowed NIS (1..128).
    /// Allowed: 1..=128.
    /// Default: 10.
    pub aq_gate_window: i32,
    /// AQUKF, gated law: the gate opens when the windowed NIS exceeds its chi-square quantile at this probability (in (0, 1)).
    /// Default: 0.999.
    pub aq_gate_quantile: f64,
    /// IMM (filter 10): number of modes (2 or 3).
    /// Allowed: 2 or 3.
    /// Default: 3.
    pub imm_modes: i32,
    /// IMM: white-acceleration density added to the process noise in each mode (>= 0; the third is unused with 2 modes).
    /// `[0]` imm_accel_psd_1 [m2/s3]
    /// `[1]` imm_accel_psd_2 [m2/s3]
    /// `[2]` imm_accel_psd_3 [m2/s3]
    /// Allowed: >= 0.
    /// Default: 0, 1e-6, 0.001.
    pub imm_accel_psd: [f64; 3],
    /// IMM: probability of staying in each mode over one second (in (0, 1)).
    /// `[0]` imm_p_stay_1
    /// `[1]` imm_p_stay_2
    /// `[2]` imm_p_stay_3
    /// Allowed: in (0, 1).
    /// Default: 0.999999, 0.9, 0.9.
    pub imm_p_stay: [f64; 3],
    /// Particle filters (codes 4-8) with pf_prior = 1 (points; false needs it): after every update, Metropolis-Hastings moves whose target is the likelihood times the Gaussian of the predictive moments (Gaussian-prior moves, not invariant for the exact posterior; as accurate as the EKF on Gaussian noise, also with small process noise); false: the papers' filters as written (particles drawn from the prior N(x0, P0), multinomial resampling with resampler = auto, paper 000's SIR, the plain RPF, van der Merwe's UPF, and the GA-PF's and CGA-PF's operators accepted on the likelihood ratio as paper 003 writes), which degenerate with small process noise.
    /// 0 or 1.
    /// Default: 1.
    pub pf_move: i32,
    /// Particle filters with pf_prior = 1 (points): worker threads of the particle loops from 32768 particles on (0: one per core; 1: the calling thread; <= 1024); results do not depend on it.
    /// Allowed: 0..=1024.
    /// Default: 0.
    pub pf_threads: i32,
    /// Eccentricity of the target's orbit (0 <= e <= 0.99): 0 the Clohessy-Wiltshire model, > 0 the linearised elliptic model of Yamanaka and Ankersen; mean_motion stays 2 pi / period.
    /// Allowed: in [0, 0.99].
    /// Default: 0.
    pub eccentricity: f64,
    /// True anomaly of the target at the start time (unused at eccentricity 0).
    /// Unit: rad.
    /// Default: 0.
    pub true_anomaly0: f64,
    /// Camera (angles-only) azimuth and elevation noise, 1 sigma of the Gaussian (nominal sigma of the other noise models; > 0): the readings camera_azimuth, camera_elevation.
    /// Unit: rad.
    /// Allowed: > 0.
    /// Default: 0.001.
    pub sigma_camera: f64,
    /// Relative GNSS position noise per axis, 1 sigma of the Gaussian (nominal sigma of the other noise models; > 0): the readings gnss_x, gnss_y, gnss_z.
    /// Unit: m.
    /// Allowed: > 0.
    /// Default: 0.05.
    pub sigma_gnss: f64,
    /// Relative GNSS velocity noise per axis, 1 sigma of the Gaussian (nominal sigma of the other noise models; > 0): the readings gnss_vx, gnss_vy, gnss_vz.
    /// Unit: m/s.
    /// Allowed: > 0.
    /// Default: 0.0005.
    pub sigma_gnss_velocity: f64,
    /// Kalman-type filters (codes 1-3, 10): number of members of a range-parameterised bank (1: the filter alone; 2..9: the prior split along its line of sight into a Gaussian sum, one filter per term, weighted by its measurements; for angles-only acquisition, where one filter's range collapses early).
    /// Allowed: 1..=9.
    /// Default: 1.
    pub range_bank: i32,
    /// Initial position uncertainty along the line of sight of x0 (the range), 1 sigma (>= 0; 0: sigma_pos0, the same on every axis); sigma_pos0 is then the uncertainty across it.
    /// Unit: m.
    /// Allowed: >= 0.
    /// Default: 0.
    pub sigma_range0: f64,
    /// Camera: density of the angle noise scaled by sigma_camera (the particle filters weigh with it, the Kalman filters assume the Gaussian of its variance).
    /// A `relnav_noise_model` code: 1 gaussian, 2 mixture, 3 student_t.
    /// Default: 1 (gaussian).
    pub camera_noise_model: i32,
    /// Camera, mixture noise: weight of the wide component (in [0, 1)).
    /// Allowed: in [0, 1).
    /// Default: 0.2.
    pub camera_noise_zeta: f64,
    /// Camera, mixture noise: sigma of the wide component over sigma_camera (>= 1).
    /// Allowed: >= 1.
    /// Default: 10.
    pub camera_noise_scale: f64,
    /// Camera, Student-t noise: degrees of freedom (> 2).
    /// Allowed: > 2.
    /// Default: 4.
    pub camera_noise_dof: f64,
    /// Relative GNSS: density of the position and velocity noise scaled by sigma_gnss and sigma_gnss_velocity (the particle filters weigh with it, the Kalman filters assume the Gaussian of its variance).
    /// A `relnav_noise_model` code: 1 gaussian, 2 mixture, 3 student_t.
    /// Default: 1 (gaussian).
    pub gnss_noise_model: i32,
    /// Relative GNSS, mixture noise: weight of the wide component (in [0, 1)).
    /// Allowed: in [0, 1).
    /// Default: 0.2.
    pub gnss_noise_zeta: f64,
    /// Relative GNSS, mixture noise: sigma of the wide component over the nominal sigma (>= 1).
    /// Allowed: >= 1.
    /// Default: 10.
    pub gnss_noise_scale: f64,
    /// Relative GNSS, Student-t noise: degrees of freedom (> 2).
    /// Allowed: > 2.
    /// Default: 4.
    pub gnss_noise_dof: f64,
    /// H-infinity filter: the measurement set its design is for, the sum of 1 radio, 2 camera, 4 relative GNSS position, 8 relative GNSS velocity (it must hold the radio or the GNSS position: a camera or a velocity alone leaves the position unobservable to a linear observer); the design's noise is each sensor's at the initial estimate.
    /// Allowed: 1..=15.
    /// Default: 1.
    pub hinf_sensors: i32,
    /// Particle filters (codes 4-8): what a particle carries (2 particle, the default: a Gaussian, updated by its own EKF step, by its UKF step for the UPF and CGA-PF, with the noise density's robust update under heavy tails, the set a Gaussian sum resampled and, except for the SIR, its duplicates separated by the kind's step; pf_move and pf_threads do not apply: the terms run on the calling thread; <= 100000 particles. 1 gaussian: a point, moved as pf_move says).
    /// A `relnav_pf_prior` code: 1 gaussian, 2 particle.
    /// Default: 2 (particle).
    pub pf_prior: i32,
}

impl relnav_config {
    /// Every field zero.
    pub(crate) const ZERO: Self = Self {
        filter: 0,
        frame: 0,
        discretization: 0,
        mean_motion: 0.0,
        chaser_mass: 0.0,
        sigma_range: 0.0,
        sigma_angle: 0.0,
        x0: [0.0; 6],
        sigma_pos0: 0.0,
        sigma_vel0: 0.0,
        accel_psd: 0.0,
        q_pos: [0.0; 3],
        q_vel: [0.0; 3],
        ukf_alpha: 0.0,
        ukf_beta: 0.0,
        ukf_kappa: 0.0,
        seed: 0,
        particles: 0,
        resampler: 0,
        resample_threshold: 0.0,
        noise_model: 0,
        noise_zeta: 0.0,
        noise_scale: 0.0,
        noise_dof: 0.0,
        window: 0,
        q_vv_floor: 0.0,
        q_vv_ceiling: 0.0,
        hinf_period: 0.0,
        hinf_delta_bar: 0.0,
        hinf_b_pos: 0.0,
        hinf_b_vel: 0.0,
        hinf_d: 0.0,
        hinf_design: 0,
        hinf_gamma_factor: 0.0,
        hinf_acquisition: 0,
        aq_law: 0,
        aq_gate_window: 0,
        aq_gate_quantile: 0.0,
        imm_modes: 0,
        imm_accel_psd: [0.0; 3],
        imm_p_stay: [0.0; 3],
        pf_move: 0,
        pf_threads: 0,
        eccentricity: 0.0,
        true_anomaly0: 0.0,
        sigma_camera: 0.0,
        sigma_gnss: 0.0,
        sigma_gnss_velocity: 0.0,
        range_bank: 0,
        sigma_range0: 0.0,
        camera_noise_model: 0,
        camera_noise_zeta: 0.0,
        camera_noise_scale: 0.0,
        camera_noise_dof: 0.0,
        gnss_noise_model: 0,
        gnss_noise_zeta: 0.0,
        gnss_noise_scale: 0.0,
        gnss_noise_dof: 0.0,
        hinf_sensors: 0,
        pf_prior: 0,
    };

    /// Element `i` of parameter `k` (its index in the table).
    pub(crate) fn element(&self, k: usize, i: usize) -> Option<Value> {
        Some(match k {
            0 => Value::Int(i64::from(self.filter)),
            1 => Value::Int(i64::from(self.frame)),
            2 => Value::Int(i64::from(self.discretization)),
            3 => Value::Real(self.mean_motion),
            4 => Value::Real(self.chaser_mass),
            5 => Value::Real(self.sigma_range),
            6 => Value::Real(self.sigma_angle),
            7 => Value::Real(*self.x0.get(i)?),
            8 => Value::Real(self.sigma_pos0),
            9 => Value::Real(self.sigma_vel0),
            10 => Value::Real(self.accel_psd),
            11 => Value::Real(*self.q_pos.get(i)?),
            12 => Value::Real(*self.q_vel.get(i)?),
            13 => Value::Real(self.ukf_alpha),
            14 => Value::Real(self.ukf_beta),
            15 => Value::Real(self.ukf_kappa),
            16 => Value::Int(self.seed as i64),
            17 => Value::Int(i64::from(self.particles)),
            18 => Value::Int(i64::from(self.resampler)),
            19 => Value::Real(self.resample_threshold),
            20 => Value::Int(i64::from(self.noise_model)),
            21 => Value::Real(self.noise_zeta),
            22 => Value::Real(self.noise_scale),
            23 => Value::Real(self.noise_dof),
            24 => Value::Int(i64::from(self.window)),
            25 => Value::Real(self.q_vv_floor),
            26 => Value::Real(self.q_vv_ceiling),
            27 => Value::Real(self.hinf_period),
            28 => Value::Real(self.hinf_delta_bar),
            29 => Value::Real(self.hinf_b_pos),
            30 => Value::Real(self.hinf_b_vel),
            31 => Value::Real(self.hinf_d),
            32 => Value::Int(i64::from(self.hinf_design)),
            33 => Value::Real(self.hinf_gamma_factor),
            34 => Value::Int(i64::from(self.hinf_acquisition)),
            35 => Value::Int(i64::from(self.aq_law)),
            36 => Value::Int(i64::from(self.aq_gate_window)),
            37 => Value::Real(self.aq_gate_quantile),
            38 => Value::Int(i64::from(self.imm_modes)),
            39 => Value::Real(*self.imm_accel_psd.get(i)?),
            40 => Value::Real(*self.imm_p_stay.get(i)?),
            41 => Value::Int(i64::from(self.pf_move)),
            42 => Value::Int(i64::from(self.pf_threads)),
            43 => Value::Real(self.eccentricity),
            44 => Value::Real(self.true_anomaly0),
            45 => Value::Real(self.sigma_camera),
            46 => Value::Real(self.sigma_gnss),
            47 => Value::Real(self.sigma_gnss_velocity),
            48 => Value::Int(i64::from(self.range_bank)),
            49 => Value::Real(self.sigma_range0),
            50 => Value::Int(i64::from(self.camera_noise_model)),
            51 => Value::Real(self.camera_noise_zeta),
            52 => Value::Real(self.camera_noise_scale),
            53 => Value::Real(self.camera_noise_dof),
            54 => Value::Int(i64::from(self.gnss_noise_model)),
            55 => Value::Real(self.gnss_noise_zeta),
            56 => Value::Real(self.gnss_noise_scale),
            57 => Value::Real(self.gnss_noise_dof),
            58 => Value::Int(i64::from(self.hinf_sensors)),
            59 => Value::Int(i64::from(self.pf_prior)),
            _ => return None,
        })
    }

    /// Store element `i` of parameter `k`: a real as it is, an integer saturated to
    /// the field's type (a count beyond `i32` becomes `i32::MAX`).
    pub(crate) fn set_element(&mut self, k: usize, i: usize, v: Value) {
        match k {
            0 => self.filter = v.as_int().map_or(i32::MAX, |x| i32::try_from(x).unwrap_or(i32::MAX)),
            1 => self.frame = v.as_int().map_or(i32::MAX, |x| i32::try_from(x).unwrap_or(i32::MAX)),
            2 => self.discretization = v.as_int().map_or(i32::MAX, |x| i32::try_from(x).unwrap_or(i32::MAX)),
            3 => self.mean_motion = v.as_f64(),
            4 => self.chaser_mass = v.as_f64(),
            5 => self.sigma_range = v.as_f64(),
            6 => self.sigma_angle = v.as_f64(),
            7 if i < 6 => self.x0[i] = v.as_f64(),
            8 => self.sigma_pos0 = v.as_f64(),
            9 => self.sigma_vel0 = v.as_f64(),
            10 => self.accel_psd = v.as_f64(),
            11 if i < 3 => self.q_pos[i] = v.as_f64(),
            12 if i < 3 => self.q_vel[i] = v.as_f64(),
            13 => self.ukf_alpha = v.as_f64(),
            14 => self.ukf_beta = v.as_f64(),
            15 => self.ukf_kappa = v.as_f64(),
            16 => self.seed = v.as_int().unwrap_or(0) as u64,
            17 => self.particles = v.as_int().map_or(i32::MAX, |x| i32::try_from(x).unwrap_or(i32::MAX)),
            18 => self.resampler = v.as_int().map_or(i32::MAX, |x| i32::try_from(x).unwrap_or(i32::MAX)),
            19 => self.resample_threshold = v.as_f64(),
            20 => self.noise_model = v.as_int().map_or(i32::MAX, |x| i32::try_from(x).unwrap_or(i32::MAX)),
            21 => self.noise_zeta = v.as_f64(),
            22 => self.noise_scale = v.as_f64(),
            23 => self.noise_dof = v.as_f64(),
            24 => self.window = v.as_int().map_or(i32::MAX, |x| i32::try_from(x).unwrap_or(i32::MAX)),
            25 => self.q_vv_floor = v.as_f64(),
            26 => self.q_vv_ceiling = v.as_f64(),
            27 => self.hinf_period = v.as_f64(),
            28 => self.hinf_delta_bar = v.as_f64(),
            29 => self.hinf_b_pos = v.as_f64(),
            30 => self.hinf_b_vel = v.as_f64(),
            31 => self.hinf_d = v.as_f64(),
            32 => self.hinf_design = v.as_int().map_or(i32::MAX, |x| i32::try_from(x).unwrap_or(i32::MAX)),
            33 => self.hinf_gamma_factor = v.as_f64(),
            34 => self.hinf_acquisition = v.as_int().map_or(i32::MAX, |x| i32::try_from(x).unwrap_or(i32::MAX)),
            35 => self.aq_law = v.as_int().map_or(i32::MAX, |x| i32::try_from(x).unwrap_or(i32::MAX)),
            36 => self.aq_gate_window = v.as_int().map_or(i32::MAX, |x| i32::try_from(x).unwrap_or(i32::MAX)),
            37 => self.aq_gate_quantile = v.as_f64(),
            38 => self.imm_modes = v.as_int().map_or(i32::MAX, |x| i32::try_from(x).unwrap_or(i32::MAX)),
            39 if i < 3 => self.imm_accel_psd[i] = v.as_f64(),
            40 if i < 3 => self.imm_p_stay[i] = v.as_f64(),
            41 => self.pf_move = v.as_int().map_or(i32::MAX, |x| i32::try_from(x).unwrap_or(i32::MAX)),
            42 => self.pf_threads = v.as_int().map_or(i32::MAX, |x| i32::try_from(x).unwrap_or(i32::MAX)),
            43 => self.eccentricity = v.as_f64(),
            44 => self.true_anomaly0 = v.as_f64(),
            45 => self.sigma_camera = v.as_f64(),
            46 => self.sigma_gnss = v.as_f64(),
            47 => self.sigma_gnss_velocity = v.as_f64(),
            48 => self.range_bank = v.as_int().map_or(i32::MAX, |x| i32::try_from(x).unwrap_or(i32::MAX)),
            49 => self.sigma_range0 = v.as_f64(),
            50 => self.camera_noise_model = v.as_int().map_or(i32::MAX, |x| i32::try_from(x).unwrap_or(i32::MAX)),
            51 => self.camera_noise_zeta = v.as_f64(),
            52 => self.camera_noise_scale = v.as_f64(),
            53 => self.camera_noise_dof = v.as_f64(),
            54 => self.gnss_noise_model = v.as_int().map_or(i32::MAX, |x| i32::try_from(x).unwrap_or(i32::MAX)),
            55 => self.gnss_noise_zeta = v.as_f64(),
            56 => self.gnss_noise_scale = v.as_f64(),
            57 => self.gnss_noise_dof = v.as_f64(),
            58 => self.hinf_sensors = v.as_int().map_or(i32::MAX, |x| i32::try_from(x).unwrap_or(i32::MAX)),
            59 => self.pf_prior = v.as_int().map_or(i32::MAX, |x| i32::try_from(x).unwrap_or(i32::MAX)),
            _ => {}
        }
    }
}
