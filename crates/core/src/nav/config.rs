//! The navigator's configuration, declared once as a parameter table ([`PARAMS`], written by
//! [`crate::config!`]; see [`crate::params`]): every front end takes its parameters from
//! this table — the C ABI's `relnav_config`, relnav.fmu's parameter variables, the Python
//! keyword arguments and the scenario files' `[[filter]]` keys.
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
//! ([`crate::estimators::aqukf`]). `aq_law` chooses how: paper 001's window at every
//! update, or (the default) only while the windowed NIS exceeds its chi-square bound
//! (`aq_gate_window`, `aq_gate_quantile`).
//! The **IMM** (code 10) runs 2 or 3 EKFs on the CW model whose process noise is this `Q`
//! plus `Qd_VanLoan(imm_accel_psd[j] I3, h)` (mode `j`), switching as a Markov chain with
//! per-second staying probabilities `imm_p_stay` ([`crate::estimators::imm`]).
//!
//! **Measurement noise.** `sigma_range` and `sigma_angle` are the scales of the noise
//! density [`NavConfig::noise_model`] (Gaussian by default; a contaminated Gaussian or a
//! Student-t for heavy tails, see [`crate::noise`]). The particle filters (codes 4-8) weigh
//! with that density itself; the Kalman filters assume the Gaussian of the same variance,
//! i.e. `sigma^2 * variance_factor` (`1 - zeta + zeta scale^2` for the mixture,
//! `dof / (dof - 2)` for the Student-t), so every filter sees the same noise statistics.

use super::error::{NavError, NavErrorKind};
use crate::dynamics::{CwModel, Discretization, MAX_ECCENTRICITY};
use crate::estimators::pf::{
    PfInit, PfKind, PfParams, PfPrior, Resampler, MAX_PARTICLES, MAX_THREADS,
};
use crate::estimators::{
    AdaptationLaw, AqParams, ImmParams, UkfParams, MAX_BANK, MAX_GATE_WINDOW, MAX_MODES, MAX_WINDOW,
};
use crate::frames::Frame;
#[cfg(not(feature = "std"))]
use crate::math::Float;
use crate::noise::NoiseModel;
use crate::numerics::num;
use crate::numerics::state::Writer;
use crate::numerics::Owned;
use crate::params::{closed, open, CodeItem, CodeList, Field, Kind, Param, Rule, Value};

/// `hinf_sensors` bit of the radio (or lidar).
pub const HINF_RADIO: usize = 1;
/// `hinf_sensors` bit of the camera.
pub const HINF_CAMERA: usize = 2;
/// `hinf_sensors` bit of relative GNSS's position.
pub const HINF_GNSS_POSITION: usize = 4;
/// `hinf_sensors` bit of relative GNSS's velocity.
pub const HINF_GNSS_VELOCITY: usize = 8;
use crate::sensors::RadioSensor;
use crate::types::{Mat3, Mat6, State, Vec3};

/// Accepted mean motions [rad/s]: from a 200-year orbit to a 1-minute one. Outside, the
/// CW model has no physical meaning and `1 / n^2` terms of the discretisation overflow.
pub const MEAN_MOTION_RANGE: (f64, f64) = (1e-9, 0.1);

/// Bound on `|x0_i| + 100 sigma_i` of the initial estimate [m, m/s]: a numerical limit,
/// not a physical one. Covariances are squares of state differences, and a particle
/// filter's weighted mean is only as exact as the ulp of the state (`1e-16 |x|`): beyond
/// ~1e154 those squares overflow. 1e150 keeps the initial distribution and the first
/// steps' arithmetic inside double precision.
pub const MAX_INITIAL_MAGNITUDE: f64 = 1e150;

crate::codes! {
    /// Filter codes (`filter` parameter), the same in every front end.
    pub enum FilterKind: FILTER_CODES = "Filter", "relnav_filter", "RELNAV_FILTER_", true {
        /// Extended Kalman filter.
        Ekf = 1, "ekf", "Extended Kalman filter (Joseph form)";
        /// Unscented Kalman filter.
        Ukf = 2, "ukf", "Unscented Kalman filter (scaled sigma points)";
        /// Sliding-window adaptive UKF (paper 001, [`crate::estimators::aqukf`]).
        Aqukf = 3, "aqukf", "Sliding-window adaptive UKF (paper 001: adaptive velocity process noise, see window and q_vv_*)";
        /// SIR (bootstrap) particle filter (paper 000).
        Pf = 4, "pf", "SIR particle filter (paper 000); see pf_prior (the default: a Gaussian per particle) and, for point particles, pf_move";
        /// Regularised particle filter (kernel jitter after resampling).
        Rpf = 5, "rpf", "Regularised particle filter (kernel jitter after resampling)";
        /// Unscented particle filter (per-particle UKF proposal).
        Upf = 6, "upf", "Unscented particle filter (per-particle UKF proposal)";
        /// Genetic-algorithm particle filter (crossover and mutation after resampling).
        Gapf = 7, "gapf", "Genetic-algorithm particle filter (crossover and mutation after resampling)";
        /// Cloud-genetic particle filter (paper 003).
        Cgapf = 8, "cgapf", "Cloud-genetic particle filter (paper 003: UKF proposal, cloud-model genetic moves)";
        /// Robust H-infinity filter (paper 002), observer form designed at construction for
        /// the open-loop CW plant (needs the `hinf` cargo feature; see [`crate::hinf`]).
        Hinf = 9, "hinf", "Robust H-infinity filter (paper 002; observer form designed by an LMI at initialisation for hinf_period; sigma_* are NaN)";
        /// Interacting multiple-model filter over CW models with a quiet and one or two
        /// manoeuvring process noises ([`crate::estimators::imm`]).
        Imm = 10, "imm", "Interacting multiple-model filter: imm_modes EKFs with the process noise plus imm_accel_psd_*, Markov switching (imm_p_stay_*); mode probabilities in imm_mu_*";
        /// Robust EKF: the radio's update with the noise density of `noise_model`
        /// ([`crate::estimators::rekf`]).
        Rekf = 11, "rekf", "Robust EKF: the radio's update uses the density of noise_model (mixture: the Gaussian-sum update collapsed to its moments; Student-t: a variational update) instead of the Gaussian of its variance; the EKF's otherwise";
    }
}

impl FilterKind {
    /// Whether this build implements the filter.
    // the arms' values differ with the features (a `matches!` only without them)
    #[allow(clippy::match_like_matches_macro)]
    pub fn is_implemented(self) -> bool {
        match self {
            FilterKind::Hinf => cfg!(feature = "hinf"),
            FilterKind::Pf
            | FilterKind::Rpf
            | FilterKind::Upf
            | FilterKind::Gapf
            | FilterKind::Cgapf => cfg!(feature = "std"),
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

crate::codes! {
    /// Measurement-noise density codes (`noise_model` parameter). The parameters live
    /// beside it in [`NavConfig`].
    pub enum NoiseKind: NOISE_MODEL_CODES = "NoiseModel", "relnav_noise_model", "RELNAV_NOISE_", true {
        /// `N(0, sigma^2)`.
        Gaussian = 1, "gaussian", "Gaussian N(0, sigma^2)";
        /// Contaminated Gaussian `(1 - zeta) N(0, sigma^2) + zeta N(0, (scale sigma)^2)`
        /// (paper 003's heavy-tailed lidar noise).
        Mixture = 2, "mixture", "Contaminated Gaussian (1 - zeta) N(0, sigma^2) + zeta N(0, (scale sigma)^2) (paper 003)";
        /// `sigma t_dof`, Student-t with `dof` degrees of freedom.
        StudentT = 3, "student_t", "Student-t sigma t_dof";
    }
}

impl NoiseKind {
    /// The density of this code with its parameters (the navigator's and the plant's).
    pub fn model(self, zeta: f64, scale: f64, dof: f64) -> NoiseModel {
        match self {
            NoiseKind::Gaussian => NoiseModel::Gaussian,
            NoiseKind::Mixture => NoiseModel::Mixture { zeta, scale },
            NoiseKind::StudentT => NoiseModel::StudentT { dof },
        }
    }
}

/// Domain of `noise_zeta` (every configuration with a noise model declares it with this).
pub const NOISE_ZETA_RULE: Rule = Rule::Interval {
    lo: closed(0.0),
    hi: open(1.0),
    why: ": the weight of the mixture's wide component",
};
/// Domain of `noise_scale`.
pub const NOISE_SCALE_RULE: Rule = Rule::Interval {
    lo: closed(1.0),
    hi: open(f64::INFINITY),
    why: ": the mixture's wide component over the nominal sigma",
};
/// Domain of `noise_dof`.
pub const NOISE_DOF_RULE: Rule = Rule::Interval {
    lo: open(2.0),
    hi: open(f64::INFINITY),
    why: ": the Student-t needs a finite variance",
};

crate::codes! {
    /// H-infinity design codes (`hinf_design` parameter): the C ABI's `relnav_hinf_form`
    /// codes available to the navigator (code 2, the paper form, needs the closed loop
    /// `u = K x` and is for `relnav_hinf_design` only).
    pub enum HinfDesignKind: HINF_DESIGN_CODES = "HinfDesign", "relnav_hinf_form", "RELNAV_HINF_", false {
        /// The gamma-optimal observer ([`crate::hinf::design::design_observer`]).
        GammaOptimal = 1, "gamma_optimal", "Observer with the least certified gamma";
        /// The mixed H2/H-infinity observer: least H2 norm with `gamma <= hinf_gamma_factor *
        /// gamma_opt` ([`crate::hinf::design::design_mixed`]).
        Mixed = 3, "mixed", "Mixed H2/H-infinity observer: least H2 norm (steady-state error) with gamma <= hinf_gamma_factor times the optimum";
    }
}

/// The codes of [`Frame`] (`frame` parameter).
pub const FRAME_CODES: CodeList = CodeList {
    name: "Frame",
    c_type: "relnav_frame",
    c_prefix: "RELNAV_FRAME_",
    c_enum: true,
    items: &[
        CodeItem {
            name: "radial_along_normal",
            code: 1,
            description: "x radial outward, y along-track, z orbit normal (canonical; paper 002)",
        },
        CodeItem {
            name: "along_radial_antinormal",
            code: 2,
            description: "x along-track, y radial outward, z minus orbit normal (paper 000)",
        },
        CodeItem {
            name: "along_antinormal_nadir",
            code: 3,
            description: "x along-track, y minus orbit normal, z nadir (paper 003)",
        },
    ],
};

/// The codes of [`Discretization`] (`discretization` parameter).
pub const DISCRETIZATION_CODES: CodeList = CodeList {
    name: "Discretization",
    c_type: "relnav_discretization",
    c_prefix: "RELNAV_DISCRETIZATION_",
    c_enum: true,
    items: &[
        CodeItem {
            name: "exact",
            code: 1,
            description: "Exact CW transition, exact zero-order hold, Van Loan process noise",
        },
        CodeItem {
            name: "euler",
            code: 2,
            description: "First-order Euler I + T A (literal paper 000)",
        },
    ],
};

/// The codes of [`ResamplerSetting`] (`resampler` parameter): the schemes of [`Resampler`]
/// and `auto`.
pub const RESAMPLER_CODES: CodeList = CodeList {
    name: "Resampler",
    c_type: "relnav_resampler",
    c_prefix: "RELNAV_RESAMPLER_",
    c_enum: true,
    items: &[
        CodeItem {
            name: "multinomial",
            code: 1,
            description: "N independent draws from the weights (paper 000's SIR)",
        },
        CodeItem {
            name: "systematic",
            code: 2,
            description: "One uniform, N evenly spaced points (Kitagawa 1996)",
        },
        CodeItem {
            name: "stratified",
            code: 3,
            description: "One uniform per stratum (Kitagawa 1996)",
        },
        CodeItem {
            name: "residual",
            code: 4,
            description:
                "floor(N w) deterministic copies, the rest multinomial (Liu and Chen 1998)",
        },
        CodeItem {
            name: "auto",
            code: 5,
            description: "Multinomial with pf_move = false (paper 000's SIR as written), systematic with the moves",
        },
    ],
};

/// The `resampler` parameter: a resampling scheme, or [`ResamplerSetting::Auto`], the
/// scheme that goes with `pf_move` ([`ResamplerSetting::resolve`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ResamplerSetting {
    /// This scheme.
    Scheme(Resampler),
    /// Multinomial for the papers' literal filters (`pf_move = false`), systematic (the
    /// lower-variance scheme) with the moves.
    Auto,
}

impl ResamplerSetting {
    /// Every setting, in code order.
    pub const ALL: [ResamplerSetting; 5] = [
        ResamplerSetting::Scheme(Resampler::Multinomial),
        ResamplerSetting::Scheme(Resampler::Systematic),
        ResamplerSetting::Scheme(Resampler::Stratified),
        ResamplerSetting::Scheme(Resampler::Residual),
        ResamplerSetting::Auto,
    ];

    /// The C ABI / FMU code (1-4 the schemes, 5 `auto`).
    pub fn code(self) -> i32 {
        match self {
            ResamplerSetting::Scheme(r) => r as i32,
            ResamplerSetting::Auto => 5,
        }
    }

    /// The setting of code `c`, or `None` for an unknown code.
    pub fn from_code(c: i32) -> Option<Self> {
        match c {
            5 => Some(ResamplerSetting::Auto),
            _ => Resampler::from_code(c).map(ResamplerSetting::Scheme),
        }
    }

    /// Lower-case name (a scheme's, or `"auto"`).
    pub fn name(self) -> &'static str {
        match self {
            ResamplerSetting::Scheme(r) => r.name(),
            ResamplerSetting::Auto => "auto",
        }
    }

    /// The scheme a particle filter uses, with or without the moves.
    pub fn resolve(self, moves: bool) -> Resampler {
        match self {
            ResamplerSetting::Scheme(r) => r,
            ResamplerSetting::Auto if moves => Resampler::Systematic,
            ResamplerSetting::Auto => Resampler::Multinomial,
        }
    }
}

/// The codes of [`AdaptationLaw`] (`aq_law` parameter).
pub const AQ_LAW_CODES: CodeList = CodeList {
    name: "AdaptationLaw",
    c_type: "relnav_adaptation",
    c_prefix: "RELNAV_ADAPTATION_",
    c_enum: true,
    items: &[
        CodeItem {
            name: "window",
            code: 1,
            description: "Paper 001 literally: the sliding-window estimate of q_vv at every update",
        },
        CodeItem {
            name: "gated",
            code: 2,
            description: "q_vv stays at q_vel while the windowed NIS is below its chi-square quantile; the sliding window adapts it (never below q_vel) while it is above",
        },
    ],
};

/// The codes of [`PfPrior`] (`pf_prior` parameter).
pub const PF_PRIOR_CODES: CodeList = CodeList {
    name: "PfPrior",
    c_type: "relnav_pf_prior",
    c_prefix: "RELNAV_PF_PRIOR_",
    c_enum: true,
    items: &[
        CodeItem {
            name: "gaussian",
            code: 1,
            description: "Point particles; with pf_move, moves toward the Gaussian of the predictive moments (the Gaussian particle filter)",
        },
        CodeItem {
            name: "particle",
            code: 2,
            description: "A Gaussian per particle: a Gaussian sum whose terms are updated by their own EKF or UKF step, weighted by their predictive likelihood, resampled and kernel-smoothed; the prior of every update is the set's own predictive mixture",
        },
    ],
};

/// Every code list of the configuration, in declaration order.
pub const CODE_LISTS: [&CodeList; 8] = [
    &FILTER_CODES,
    &FRAME_CODES,
    &DISCRETIZATION_CODES,
    &RESAMPLER_CODES,
    &NOISE_MODEL_CODES,
    &HINF_DESIGN_CODES,
    &AQ_LAW_CODES,
    &PF_PRIOR_CODES,
];

/// [`Field`] for an enum declared elsewhere with a code list here.
macro_rules! code_field {
    ($ty:ty, $list:ident, $zero:expr, $code:expr, $from:expr) => {
        impl Field for $ty {
            const KIND: Kind = Kind::Code(&$list);
            const ZERO: Self = $zero;
            fn get(&self, _: usize) -> Value {
                Value::Int(i64::from($code(*self)))
            }
            fn set(
                &mut self,
                _: usize,
                v: Value,
                name: &str,
            ) -> Result<(), crate::message::Message> {
                let code = v.as_int().and_then(|c| i32::try_from(c).ok());
                *self = code
                    .and_then($from)
                    .ok_or_else(|| crate::params::unknown_code(name, v, &$list))?;
                Ok(())
            }
        }
    };
}

code_field!(
    Frame,
    FRAME_CODES,
    Frame::RadialAlongNormal,
    Frame::code,
    Frame::from_code
);
code_field!(
    Discretization,
    DISCRETIZATION_CODES,
    Discretization::Exact,
    |d: Discretization| d as i32,
    Discretization::from_code
);
code_field!(
    ResamplerSetting,
    RESAMPLER_CODES,
    ResamplerSetting::Auto,
    ResamplerSetting::code,
    ResamplerSetting::from_code
);
code_field!(
    AdaptationLaw,
    AQ_LAW_CODES,
    AdaptationLaw::Gated,
    |a: AdaptationLaw| a as i32,
    AdaptationLaw::from_code
);
code_field!(
    PfPrior,
    PF_PRIOR_CODES,
    PfPrior::Gaussian,
    |p: PfPrior| p as i32,
    PfPrior::from_code
);

/// No scenario key (the parameter comes from elsewhere in a scenario file, or not at all).
const NO_KEY: Option<&str> = None;

/// The domain of `eccentricity` (relnav, the plant and the guidance law).
pub const ECCENTRICITY_RULE: Rule = Rule::Interval {
    lo: closed(0.0),
    hi: closed(MAX_ECCENTRICITY),
    why: ": the eccentricity of the target's orbit (Kepler's equation is solved with a fixed number of iterations verified up to 0.99)",
};

crate::config! {
    /// Everything that defines a navigator. [`Default`] is paper 000's numerical example
    /// (digest, paper 000 "Example", with its covariance-name erratum applied). Field order
    /// is the C struct's and the saved state's; new parameters are appended.
    pub struct NavConfig, PARAMS;
    filter: FilterKind {
        elements: [("filter", 0, "", 1, "")],
        rule: Rule::Any, c: true, scenario: Some("kind"), slot: Some(0),
        description: "Estimator (codes 1-11: 1-3 Kalman (EKF, UKF, AQUKF), 4-8 particle filters, 9 robust H-infinity, 10 IMM, 11 robust EKF)",
    },
    frame: Frame {
        elements: [("frame", 1, "", 2, "")],
        rule: Rule::Any, c: true, scenario: NO_KEY, slot: Some(1),
        description: "Hill-frame convention of every input and output vector and angle",
    },
    discretization: Discretization {
        elements: [("discretization", 2, "", 1, "")],
        rule: Rule::Any, c: true, scenario: Some("discretization"), slot: Some(12),
        description: "Discretisation of the CW model",
    },
    mean_motion: f64 {
        elements: [("mean_motion", 3, "rad/s", 2.0 * core::f64::consts::PI / 7200.0, "")],
        rule: Rule::Positive, c: true, scenario: NO_KEY, slot: Some(2),
        description: "Mean motion of the target's orbit, 2 pi / period (> 0)",
    },
    chaser_mass: f64 {
        elements: [("chaser_mass", 4, "kg", 1000.0, "")],
        rule: Rule::Positive, c: true, scenario: NO_KEY, slot: Some(3),
        description: "Chaser mass: thrust / mass = acceleration (> 0)",
    },
    sigma_range: f64 {
        elements: [("sigma_range", 5, "m", 0.5, "")],
        rule: Rule::Positive, c: true, scenario: NO_KEY, slot: Some(4),
        description: "Range measurement noise, 1 sigma of the Gaussian (nominal sigma of the other noise models; > 0)",
    },
    sigma_angle: f64 {
        elements: [("sigma_angle", 6, "rad", 0.01 * core::f64::consts::PI / 180.0, "")],
        rule: Rule::Positive, c: true, scenario: NO_KEY, slot: Some(5),
        description: "Azimuth and elevation measurement noise, 1 sigma of the Gaussian (nominal sigma of the other noise models; > 0)",
    },
    x0: [f64; 6] {
        elements: [
            ("x0", 7, "m", 405.0, "Initial estimate of x"),
            ("y0", 8, "m", 505.0, "Initial estimate of y"),
            ("z0", 9, "m", 205.0, "Initial estimate of z"),
            ("vx0", 10, "m/s", 0.1, "Initial estimate of vx"),
            ("vy0", 11, "m/s", 0.1, "Initial estimate of vy"),
            ("vz0", 12, "m/s", 0.1, "Initial estimate of vz"),
        ],
        rule: Rule::Finite, c: true, scenario: Some("initial_state"), slot: Some(6),
        description: "Initial estimate (x, y, z [m], vx, vy, vz [m/s]) in the I/O frame; |x0_i| + 100 sigma (of its group: the larger of sigma_pos0 and sigma_range0, or sigma_vel0) must not exceed 1e150",
    },
    sigma_pos0: f64 {
        elements: [("sigma_pos0", 13, "m", 50.0, "")],
        rule: Rule::Positive, c: true, scenario: Some("sigma_pos0"), slot: Some(7),
        description: "Initial position uncertainty per axis, 1 sigma (> 0)",
    },
    sigma_vel0: f64 {
        elements: [("sigma_vel0", 14, "m/s", 1.0, "")],
        rule: Rule::Positive, c: true, scenario: Some("sigma_vel0"), slot: Some(8),
        description: "Initial velocity uncertainty per axis, 1 sigma (> 0)",
    },
    accel_psd: f64 {
        elements: [("accel_psd", 15, "m2/s3", 0.0, "")],
        rule: Rule::NonNegative, c: true, scenario: Some("accel_psd"), slot: Some(9),
        description: "Process noise: spectral density of a continuous white acceleration per axis (Van Loan discretisation; >= 0)",
    },
    q_pos: [f64; 3] {
        elements: [
            ("q_pos_x", 16, "m2/s", 0.09, "Process noise: x position variance added per second (discrete Q = q h; >= 0)"),
            ("q_pos_y", 17, "m2/s", 0.000625, "Process noise: y position variance added per second (>= 0)"),
            ("q_pos_z", 18, "m2/s", 0.0025, "Process noise: z position variance added per second (>= 0)"),
        ],
        rule: Rule::NonNegative, c: true, scenario: NO_KEY, slot: Some(10),
        description: "Process noise: position variance rate per I/O axis (discrete Q = q_pos h; >= 0); paper 000's Q per 1 s step by default",
    },
    q_vel: [f64; 3] {
        elements: [
            ("q_vel_x", 19, "m2/s3", 1e-6, "Process noise: vx variance added per second (>= 0)"),
            ("q_vel_y", 20, "m2/s3", 1e-6, "Process noise: vy variance added per second (>= 0)"),
            ("q_vel_z", 21, "m2/s3", 1e-6, "Process noise: vz variance added per second (>= 0)"),
        ],
        rule: Rule::NonNegative, c: true, scenario: NO_KEY, slot: Some(11),
        description: "Process noise: velocity variance rate per I/O axis (discrete Q = q_vel h; >= 0); for the AQUKF the initial adaptive density q_vv",
    },
    ukf_alpha: f64 {
        elements: [("ukf_alpha", 22, "", 1.0, "")],
        rule: Rule::Any, c: true, scenario: Some("ukf_alpha"), slot: Some(13),
        description: "UKF sigma-point spread alpha (> 0); also the unscented proposal of upf and cgapf",
    },
    ukf_beta: f64 {
        elements: [("ukf_beta", 23, "", 2.0, "")],
        rule: Rule::Any, c: true, scenario: Some("ukf_beta"), slot: Some(14),
        description: "UKF beta (2 for Gaussian priors)",
    },
    ukf_kappa: f64 {
        elements: [("ukf_kappa", 24, "", 0.0, "")],
        rule: Rule::Any, c: true, scenario: Some("ukf_kappa"), slot: Some(15),
        description: "UKF kappa",
    },
    seed: u64 {
        elements: [("seed", 25, "", 0, "")],
        rule: Rule::Any, c: true, scenario: NO_KEY, slot: Some(16),
        description: "Seed of the filters that draw random numbers (identical seeds give identical outputs)",
    },
    particles: usize {
        elements: [("particles", 45, "", 1500, "")],
        rule: Rule::Count { lo: 1, hi: MAX_PARTICLES as i64 }, c: true, scenario: Some("particles"), slot: Some(17),
        description: "Number of particles of the particle filters (codes 4-8; 1..2000000)",
    },
    resampler: ResamplerSetting {
        elements: [("resampler", 46, "", 5, "")],
        rule: Rule::Any, c: true, scenario: Some("resampler"), slot: Some(18),
        description: "Resampling scheme of the particle filters (auto: multinomial with pf_move = false, systematic with the moves)",
    },
    resample_threshold: f64 {
        elements: [("resample_threshold", 47, "", 2.0 / 3.0, "")],
        rule: Rule::Interval {
            lo: open(0.0),
            hi: closed(1.0),
            why: ": the particles are resampled when N_eff < resample_threshold * particles",
        },
        c: true, scenario: Some("threshold"), slot: Some(19),
        description: "The particle filters resample when the effective sample size drops below resample_threshold * particles (in (0, 1]; paper 000: 2/3)",
    },
    noise_model: NoiseKind {
        elements: [("noise_model", 48, "", 1, "")],
        rule: Rule::Any, c: true, scenario: NO_KEY, slot: Some(20),
        description: "Measurement-noise density scaled by sigma_range and sigma_angle: the particle filters weigh with it, the Kalman filters assume the Gaussian of its variance",
    },
    noise_zeta: f64 {
        elements: [("noise_zeta", 49, "", 0.2, "")],
        rule: NOISE_ZETA_RULE,
        c: true, scenario: NO_KEY, slot: Some(21),
        description: "Mixture noise: weight of the wide component (in [0, 1))",
    },
    noise_scale: f64 {
        elements: [("noise_scale", 50, "", 10.0, "")],
        rule: NOISE_SCALE_RULE,
        c: true, scenario: NO_KEY, slot: Some(22),
        description: "Mixture noise: sigma of the wide component over the nominal sigma (>= 1)",
    },
    noise_dof: f64 {
        elements: [("noise_dof", 51, "", 4.0, "")],
        rule: NOISE_DOF_RULE,
        c: true, scenario: NO_KEY, slot: Some(23),
        description: "Student-t noise: degrees of freedom (> 2)",
    },
    window: usize {
        elements: [("window", 53, "", 10, "")],
        rule: Rule::Count { lo: 1, hi: MAX_WINDOW as i64 }, c: true, scenario: Some("window"), slot: Some(24),
        description: "AQUKF (filter 3): sliding-window width N of the adaptive process noise (1..512; paper 001: 10). For the AQUKF, q_vel_* is the initial adaptive density",
    },
    q_vv_floor: f64 {
        elements: [("q_vv_floor", -, "m2/s3", 0.0, "")],
        rule: Rule::NonNegative, c: true, scenario: Some("q_vv_floor"), slot: Some(25),
        description: "AQUKF: lower bound of each adaptive q_vv entry (>= 0)",
    },
    q_vv_ceiling: f64 {
        elements: [("q_vv_ceiling", -, "m2/s3", 1.0, "")],
        rule: Rule::Any, c: true, scenario: Some("q_vv_ceiling"), slot: Some(26),
        description: "AQUKF: upper bound of each adaptive q_vv entry (finite, > 0 and >= q_vv_floor)",
    },
    hinf_period: f64 {
        elements: [("hinf_period", 57, "s", 1.0, "")],
        rule: Rule::Any, c: true, scenario: NO_KEY, slot: Some(27),
        description: "H-infinity filter (code 9): sampling period of its discrete design; fmi2DoStep with another step size is refused (set it to the communication step)",
    },
    hinf_delta_bar: f64 {
        elements: [("hinf_delta_bar", 58, "", 0.05, "")],
        rule: Rule::Any, c: true, scenario: NO_KEY, slot: Some(28),
        description: "H-infinity filter: bound of the orbit-rate uncertainty, w = w0 (1 + delta), |delta| <= hinf_delta_bar (paper 002: 0.05)",
    },
    hinf_b_pos: f64 {
        elements: [("hinf_b_pos", 59, "m", 0.0, "")],
        rule: Rule::NonNegative, c: true, scenario: NO_KEY, slot: Some(29),
        description: "H-infinity filter: process-noise scaling on positions (paper 002 B: 0.05); 0 with hinf_b_vel = 0 (default): derived from accel_psd, q_pos_*, q_vel_* (the noise every other filter uses)",
    },
    hinf_b_vel: f64 {
        elements: [("hinf_b_vel", 60, "m/s", 0.0, "")],
        rule: Rule::NonNegative, c: true, scenario: NO_KEY, slot: Some(30),
        description: "H-infinity filter: process-noise scaling on velocities (paper 002 B: 0.001); 0 with hinf_b_pos = 0 (default): derived",
    },
    hinf_d: f64 {
        elements: [("hinf_d", 61, "m", 0.0, "")],
        rule: Rule::NonNegative, c: true, scenario: NO_KEY, slot: Some(31),
        description: "H-infinity filter: scaling of the indirect position measurement noise (paper 002 D: 0.1); 0 (default): derived from sigma_range, sigma_angle and the noise model at the initial estimate's position",
    },
    hinf_design: HinfDesignKind {
        elements: [("hinf_design", 64, "", 3, "")],
        rule: Rule::Any, c: true, scenario: NO_KEY, slot: Some(32),
        description: "H-infinity filter: the LMI design (mixed H2/H-infinity by default; gamma_optimal is the pure worst-case design)",
    },
    hinf_gamma_factor: f64 {
        elements: [("hinf_gamma_factor", 65, "", 1.5, "")],
        rule: Rule::Interval {
            lo: open(1.0),
            hi: open(f64::INFINITY),
            why: ": the mixed design's bound on gamma as a multiple of the gamma-optimal design's",
        },
        c: true, scenario: NO_KEY, slot: Some(33),
        description: "H-infinity filter, mixed design: bound on the certified gamma (hinf_gamma) as a multiple of the gamma-optimal design's (> 1)",
    },
    hinf_acquisition: bool {
        elements: [("hinf_acquisition", 66, "", 1, "")],
        rule: Rule::Any, c: true, scenario: NO_KEY, slot: Some(34),
        description: "H-infinity filter: start with the Kalman gain of the design's noise model and hand over to the designed gain once that is no worse (track initiation); false: the designed gain from the first step",
    },
    aq_law: AdaptationLaw {
        elements: [("aq_law", 69, "", 2, "")],
        rule: Rule::Any, c: true, scenario: Some("adaptation"), slot: Some(35),
        description: "AQUKF (filter 3): adaptation law of the velocity process noise (1 window: paper 001 at every update; 2 gated: only while the windowed NIS exceeds its chi-square bound)",
    },
    aq_gate_window: usize {
        elements: [("aq_gate_window", 70, "", 10, "")],
        rule: Rule::Count { lo: 1, hi: MAX_GATE_WINDOW as i64 }, c: true, scenario: Some("gate_window"), slot: Some(36),
        description: "AQUKF, gated law: number of measurement updates in the windowed NIS (1..128)",
    },
    aq_gate_quantile: f64 {
        elements: [("aq_gate_quantile", 71, "", 0.999, "")],
        rule: Rule::Any, c: true, scenario: Some("gate_quantile"), slot: Some(37),
        description: "AQUKF, gated law: the gate opens when the windowed NIS exceeds its chi-square quantile at this probability (in (0, 1))",
    },
    imm_modes: usize {
        elements: [("imm_modes", 72, "", 3, "")],
        rule: Rule::Count { lo: 2, hi: MAX_MODES as i64 }, c: true, scenario: Some("imm_modes"), slot: Some(38),
        description: "IMM (filter 10): number of modes (2 or 3)",
    },
    imm_accel_psd: [f64; MAX_MODES] {
        elements: [
            ("imm_accel_psd_1", 73, "m2/s3", 0.0, "IMM: white-acceleration density added to the process noise in mode 1 (the quiet mode; >= 0)"),
            ("imm_accel_psd_2", 74, "m2/s3", 1e-6, "IMM: white-acceleration density added to the process noise in mode 2 (>= 0)"),
            ("imm_accel_psd_3", 75, "m2/s3", 1e-3, "IMM: white-acceleration density added to the process noise in mode 3 (>= 0; unused with 2 modes)"),
        ],
        rule: Rule::NonNegative, c: true, scenario: Some("imm_accel_psd"), slot: Some(39),
        description: "IMM: white-acceleration density added to the process noise in each mode (>= 0; the third is unused with 2 modes)",
    },
    imm_p_stay: [f64; MAX_MODES] {
        elements: [
            ("imm_p_stay_1", 76, "", 0.999999, "IMM: probability of staying in mode 1 over one second (in (0, 1))"),
            ("imm_p_stay_2", 77, "", 0.9, "IMM: probability of staying in mode 2 over one second (in (0, 1))"),
            ("imm_p_stay_3", 78, "", 0.9, "IMM: probability of staying in mode 3 over one second (in (0, 1))"),
        ],
        rule: Rule::Interval {
            lo: open(0.0),
            hi: open(1.0),
            why: ": the probability of staying in the mode over one second",
        },
        c: true, scenario: Some("imm_p_stay"), slot: Some(40),
        description: "IMM: probability of staying in each mode over one second (in (0, 1))",
    },
    pf_move: bool {
        elements: [("pf_move", 82, "", 1, "")],
        rule: Rule::Any, c: true, scenario: Some("move"), slot: Some(41),
        description: "Particle filters (codes 4-8) with pf_prior = 1 (points; false needs it): after every update, Metropolis-Hastings moves whose target is the likelihood times the Gaussian of the predictive moments (Gaussian-prior moves, not invariant for the exact posterior; as accurate as the EKF on Gaussian noise, also with small process noise); false: the papers' filters as written (particles drawn from the prior N(x0, P0), multinomial resampling with resampler = auto, paper 000's SIR, the plain RPF, van der Merwe's UPF, and the GA-PF's and CGA-PF's operators accepted on the likelihood ratio as paper 003 writes), which degenerate with small process noise",
    },
    pf_threads: usize {
        elements: [("pf_threads", 83, "", 0, "")],
        rule: Rule::Count { lo: 0, hi: MAX_THREADS as i64 }, c: true, scenario: NO_KEY, slot: None,
        description: "Particle filters with pf_prior = 1 (points): worker threads of the particle loops from 32768 particles on (0: one per core; 1: the calling thread; <= 1024); results do not depend on it",
    },
    eccentricity: f64 {
        elements: [("eccentricity", 84, "", 0.0, "")],
        rule: ECCENTRICITY_RULE,
        c: true, scenario: Some("eccentricity"), slot: Some(42),
        description: "Eccentricity of the target's orbit (0 <= e <= 0.99): 0 the Clohessy-Wiltshire model, > 0 the linearised elliptic model of Yamanaka and Ankersen; mean_motion stays 2 pi / period",
    },
    true_anomaly0: f64 {
        elements: [("true_anomaly0", 85, "rad", 0.0, "")],
        rule: Rule::Finite, c: true, scenario: Some("true_anomaly0"), slot: Some(43),
        description: "True anomaly of the target at the start time (unused at eccentricity 0)",
    },
    sigma_camera: f64 {
        elements: [("sigma_camera", 86, "rad", 1e-3, "")],
        rule: Rule::Positive, c: true, scenario: NO_KEY, slot: Some(44),
        description: "Camera (angles-only) azimuth and elevation noise, 1 sigma of the Gaussian (nominal sigma of the other noise models; > 0): the readings camera_azimuth, camera_elevation",
    },
    sigma_gnss: f64 {
        elements: [("sigma_gnss", 87, "m", 0.05, "")],
        rule: Rule::Positive, c: true, scenario: NO_KEY, slot: Some(45),
        description: "Relative GNSS position noise per axis, 1 sigma of the Gaussian (nominal sigma of the other noise models; > 0): the readings gnss_x, gnss_y, gnss_z",
    },
    sigma_gnss_velocity: f64 {
        elements: [("sigma_gnss_velocity", 88, "m/s", 5e-4, "")],
        rule: Rule::Positive, c: true, scenario: NO_KEY, slot: Some(46),
        description: "Relative GNSS velocity noise per axis, 1 sigma of the Gaussian (nominal sigma of the other noise models; > 0): the readings gnss_vx, gnss_vy, gnss_vz",
    },
    range_bank: usize {
        elements: [("range_bank", 105, "", 1, "")],
        rule: Rule::Count { lo: 1, hi: MAX_BANK as i64 }, c: true, scenario: Some("range_bank"), slot: Some(47),
        description: "Kalman-type filters (codes 1-3, 10): number of members of a range-parameterised bank (1: the filter alone; 2..9: the prior split along its line of sight into a Gaussian sum, one filter per term, weighted by its measurements; for angles-only acquisition, where one filter's range collapses early)",
    },
    sigma_range0: f64 {
        elements: [("sigma_range0", 106, "m", 0.0, "")],
        rule: Rule::NonNegative, c: true, scenario: Some("sigma_range0"), slot: Some(48),
        description: "Initial position uncertainty along the line of sight of x0 (the range), 1 sigma (>= 0; 0: sigma_pos0, the same on every axis); sigma_pos0 is then the uncertainty across it",
    },
    camera_noise_model: NoiseKind {
        elements: [("camera_noise_model", 107, "", 1, "")],
        rule: Rule::Any, c: true, scenario: NO_KEY, slot: Some(49),
        description: "Camera: density of the angle noise scaled by sigma_camera (the particle filters weigh with it, the Kalman filters assume the Gaussian of its variance)",
    },
    camera_noise_zeta: f64 {
        elements: [("camera_noise_zeta", 108, "", 0.2, "")],
        rule: NOISE_ZETA_RULE,
        c: true, scenario: NO_KEY, slot: Some(50),
        description: "Camera, mixture noise: weight of the wide component (in [0, 1))",
    },
    camera_noise_scale: f64 {
        elements: [("camera_noise_scale", 109, "", 10.0, "")],
        rule: NOISE_SCALE_RULE,
        c: true, scenario: NO_KEY, slot: Some(51),
        description: "Camera, mixture noise: sigma of the wide component over sigma_camera (>= 1)",
    },
    camera_noise_dof: f64 {
        elements: [("camera_noise_dof", 110, "", 4.0, "")],
        rule: NOISE_DOF_RULE,
        c: true, scenario: NO_KEY, slot: Some(52),
        description: "Camera, Student-t noise: degrees of freedom (> 2)",
    },
    gnss_noise_model: NoiseKind {
        elements: [("gnss_noise_model", 111, "", 1, "")],
        rule: Rule::Any, c: true, scenario: NO_KEY, slot: Some(53),
        description: "Relative GNSS: density of the position and velocity noise scaled by sigma_gnss and sigma_gnss_velocity (the particle filters weigh with it, the Kalman filters assume the Gaussian of its variance)",
    },
    gnss_noise_zeta: f64 {
        elements: [("gnss_noise_zeta", 112, "", 0.2, "")],
        rule: NOISE_ZETA_RULE,
        c: true, scenario: NO_KEY, slot: Some(54),
        description: "Relative GNSS, mixture noise: weight of the wide component (in [0, 1))",
    },
    gnss_noise_scale: f64 {
        elements: [("gnss_noise_scale", 113, "", 10.0, "")],
        rule: NOISE_SCALE_RULE,
        c: true, scenario: NO_KEY, slot: Some(55),
        description: "Relative GNSS, mixture noise: sigma of the wide component over the nominal sigma (>= 1)",
    },
    gnss_noise_dof: f64 {
        elements: [("gnss_noise_dof", 114, "", 4.0, "")],
        rule: NOISE_DOF_RULE,
        c: true, scenario: NO_KEY, slot: Some(56),
        description: "Relative GNSS, Student-t noise: degrees of freedom (> 2)",
    },
    hinf_sensors: usize {
        elements: [("hinf_sensors", 115, "", 1, "")],
        rule: Rule::Count { lo: 1, hi: 15 }, c: true, scenario: Some("hinf_sensors"), slot: Some(57),
        description: "H-infinity filter: the measurement set its design is for, the sum of 1 radio, 2 camera, 4 relative GNSS position, 8 relative GNSS velocity (it must hold the radio or the GNSS position: a camera or a velocity alone leaves the position unobservable to a linear observer); the design's noise is each sensor's at the initial estimate",
    },
    pf_prior: PfPrior {
        elements: [("pf_prior", 117, "", 2, "")],
        rule: Rule::Any, c: true, scenario: Some("prior"), slot: Some(58),
        description: "Particle filters (codes 4-8): what a particle carries (2 particle, the default: a Gaussian, updated by its own EKF step, by its UKF step for the UPF and CGA-PF, with the noise density's robust update under heavy tails, the set a Gaussian sum resampled and, except for the SIR, its duplicates separated by the kind's step; pf_move and pf_threads do not apply: the terms run on the calling thread; <= 100000 particles. 1 gaussian: a point, moved as pf_move says)",
    },
}

/// One setting of a [`NavConfig`] as a saved state records it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Setting {
    /// A code, count, flag or seed (the seed's `u64` bits as `i64`).
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
    pub(super) fn with_bits(self, b: u64) -> Self {
        match self {
            Setting::Int(_) => Setting::Int(b as i64),
            Setting::Real(_) => Setting::Real(f64::from_bits(b)),
        }
    }
}

impl From<Value> for Setting {
    fn from(v: Value) -> Self {
        match v {
            Value::Int(i) => Setting::Int(i),
            Value::Real(x) => Setting::Real(x),
        }
    }
}

impl core::fmt::Display for Setting {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Setting::Int(v) => write!(f, "{v}"),
            Setting::Real(v) => f.write_str(num(*v).as_ref()),
        }
    }
}

/// [`Rule::Positive`] of one number, as a [`NavError`].
pub(crate) fn positive(name: &str, v: f64) -> Result<(), NavError> {
    Rule::Positive
        .check(name, Value::Real(v))
        .map_err(NavError::invalid)
}

impl NavConfig {
    /// The parameter table ([`PARAMS`]).
    pub fn params() -> &'static [Param<NavConfig>] {
        PARAMS
    }

    /// Store element `i` of parameter `p` as a front end hands it over
    /// ([`Param::assign`]); the message names the parameter.
    pub fn assign(&mut self, p: &Param<NavConfig>, i: usize, v: Value) -> Result<(), NavError> {
        p.assign(self, i, v).map_err(NavError::invalid)
    }

    /// Check every field; the error names the first offending one: the parameters' own
    /// rules ([`PARAMS`], in declaration order), then the rules between them.
    pub fn validate(&self) -> Result<(), NavError> {
        if !self.filter.is_implemented() {
            #[cfg(feature = "std")]
            let message = {
                let available: Vec<String> = FilterKind::ALL
                    .iter()
                    .filter(|k| k.is_implemented())
                    .map(|k| format!("{} {}", *k as i32, k.name()))
                    .collect();
                crate::msg!(
                    "filter {} ({}) is not implemented in relnav {}; available: {}",
                    self.filter as i32,
                    self.filter.name(),
                    crate::VERSION,
                    available.join(", ")
                )
            };
            #[cfg(not(feature = "std"))]
            let message = crate::message::Message::concat(&[
                "filter ",
                self.filter.name(),
                " is not in this build (the flight library)",
            ]);
            return Err(NavError {
                kind: NavErrorKind::NotImplemented,
                message,
            });
        }
        for p in PARAMS {
            p.check(self).map_err(NavError::invalid)?;
        }
        if !(MEAN_MOTION_RANGE.0..=MEAN_MOTION_RANGE.1).contains(&self.mean_motion) {
            return Err(NavError::invalid(crate::msg!(
                "mean_motion must lie in [{:e}, {}] rad/s (got {}): an orbit's mean rate \
                 (low Earth orbit ~1.1e-3, geostationary ~7.3e-5)",
                MEAN_MOTION_RANGE.0,
                MEAN_MOTION_RANGE.1,
                num(self.mean_motion)
            )));
        }
        for (name, v) in [
            ("sigma_pos0", self.sigma_pos0),
            ("sigma_vel0", self.sigma_vel0),
            ("sigma_range", self.sigma_range),
            ("sigma_angle", self.sigma_angle),
        ] {
            if !(v * v).is_finite() || v * v == 0.0 {
                return Err(NavError::invalid(crate::msg!(
                    "{name} = {} has no finite, non-zero variance",
                    num(v)
                )));
            }
        }
        for (i, n) in ["x0", "y0", "z0", "vx0", "vy0", "vz0"].iter().enumerate() {
            // headroom in double precision for the initial distribution (a particle
            // filter draws x0 + sigma eps) and the first steps' arithmetic
            let sigma = if i < 3 {
                self.sigma_pos0
            } else {
                self.sigma_vel0
            };
            let sigma = if i < 3 {
                sigma.max(self.sigma_range0)
            } else {
                sigma
            };
            if !(self.x0[i].abs() + 100.0 * sigma <= MAX_INITIAL_MAGNITUDE) {
                return Err(NavError::invalid(crate::msg!(
                    "|{n}| + 100 sigma must not exceed {MAX_INITIAL_MAGNITUDE:e} (got {n} = {}, \
                     sigma {}): the initial estimate would overflow double precision",
                    num(self.x0[i]),
                    num(sigma)
                )));
            }
        }
        if self.sigma_range0 > 0.0 && self.x0[..3].iter().all(|v| *v == 0.0) {
            return Err(NavError::invalid(crate::msg!(
                "sigma_range0 = {} is the uncertainty along x0's line of sight: x0, y0, z0 \
                 must not all be 0 (the target)",
                num(self.sigma_range0)
            )));
        }
        if self.range_bank > 1 {
            let kalman = [
                FilterKind::Ekf,
                FilterKind::Ukf,
                FilterKind::Aqukf,
                FilterKind::Imm,
            ];
            if !kalman.contains(&self.filter) {
                return Err(NavError::invalid(crate::msg!(
                    "range_bank = {} needs a Kalman-type filter (1 ekf, 2 ukf, 3 aqukf, 10 imm; \
                     got {} {}): the particle filters carry a non-Gaussian prior themselves \
                     and the H-infinity filter's guarantee is for one estimator",
                    self.range_bank,
                    self.filter as i32,
                    self.filter.name()
                )));
            }
            if self.x0[..3].iter().all(|v| *v == 0.0) {
                return Err(NavError::invalid(crate::msg!(
                    "range_bank = {} splits the prior along its line of sight: x0, y0, z0 \
                     must not all be 0 (the target)",
                    self.range_bank
                )));
            }
        }
        // checked whatever the filter, so a bad value never hides until the filter changes
        self.ukf().validate().map_err(NavError::invalid)?;
        for (name, v) in [
            ("sigma_range", self.sigma_range),
            ("sigma_angle", self.sigma_angle),
        ] {
            let var = v * v * self.noise().variance_factor();
            if !var.is_finite() {
                return Err(NavError::invalid(crate::msg!(
                    "{name} = {} with noise model {} has no finite variance",
                    num(v),
                    self.noise_model.name()
                )));
            }
        }
        if self.filter.pf_kind().is_some() && !self.pf_move && self.pf_prior == PfPrior::Particle {
            return Err(NavError::invalid(crate::msg!(
                "filter {} with pf_move = false (the papers' filters as written) needs \
                 pf_prior = 1 (gaussian: point particles); pf_move does not apply to the \
                 particle prior, the default",
                self.filter.name()
            )));
        }
        if self.filter.pf_kind().is_some_and(PfKind::unscented)
            && !self.pf_move
            && self.pf_prior == PfPrior::Gaussian
            && !(self.accel_psd > 0.0 || self.q_pos.iter().chain(&self.q_vel).all(|q| *q > 0.0))
        {
            return Err(NavError::invalid(crate::msg!(
                "filter {} with pf_move = false needs a positive-definite process noise \
                 (accel_psd > 0, or every q_pos_* and q_vel_* > 0): its literal proposal is \
                 built on the transition density",
                self.filter.name()
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

    #[cfg(feature = "std")]
    /// Every saved setting by name, in slot order: a saved state's configuration section
    /// (`docs/state-format.md`). A parameter without a slot (`pf_threads`: the results do
    /// not depend on it) is left out.
    pub fn settings(&self) -> Vec<(String, Setting)> {
        let mut saved: Vec<(u16, &Param<NavConfig>)> = PARAMS
            .iter()
            .filter_map(|p| p.slot.map(|s| (s, p)))
            .collect();
        saved.sort_by_key(|(s, _)| *s);
        saved
            .into_iter()
            .flat_map(|(_, p)| {
                (0..p.elements.len()).map(move |i| (p.setting_name(i), (p.get)(self, i).into()))
            })
            .collect()
    }

    /// The configuration section of a saved state: the number of settings (u32) and each
    /// setting's 8 bytes ([`Setting::bits`]), in [`NavConfig::settings`] order.
    pub(super) fn write_settings(&self, w: &mut Writer<'_>) {
        w.u32(self.settings_count() as u32);
        self.visit_settings(|_, _, v| w.u64(v.bits()));
    }

    /// The number of saved settings ([`NavConfig::settings`]).
    pub(super) fn settings_count(&self) -> usize {
        PARAMS
            .iter()
            .filter(|p| p.slot.is_some())
            .map(|p| p.elements.len())
            .sum()
    }

    /// Every saved setting in slot order ([`NavConfig::settings`]): its parameter, the
    /// element's index and its value, visited slot by slot without a list (no heap).
    pub(super) fn visit_settings(&self, mut f: impl FnMut(&Param<NavConfig>, usize, Setting)) {
        let mut last: Option<u16> = None;
        while let Some((s, p)) = PARAMS
            .iter()
            .filter_map(|p| p.slot.map(|s| (s, p)))
            .filter(|(s, _)| last.is_none_or(|l| *s > l))
            .min_by_key(|(s, _)| *s)
        {
            for i in 0..p.elements.len() {
                f(p, i, Setting::from((p.get)(self, i)));
            }
            last = Some(s);
        }
    }

    /// The configuration fingerprint of a saved state's header: the CRC-32 of the
    /// configuration section ([`NavConfig::settings`]).
    pub fn fingerprint(&self) -> u32 {
        let mut h = crc32fast::Hasher::new();
        self.write_settings(&mut Writer::into_crc(&mut h));
        h.finalize()
    }

    /// The UKF's sigma-point parameters (`ukf_alpha`, `ukf_beta`, `ukf_kappa`; also the
    /// unscented proposal of the UPF and the CGA-PF).
    pub fn ukf(&self) -> UkfParams {
        UkfParams {
            alpha: self.ukf_alpha,
            beta: self.ukf_beta,
            kappa: self.ukf_kappa,
        }
    }

    /// The H-infinity parameters: the pairing of the process-noise scalings and the
    /// shared checks of the design inputs whatever the filter; the derived noise model
    /// (which needs a usable initial position) only for filter 9.
    fn validate_hinf(&self) -> Result<(), NavError> {
        if (self.hinf_b_pos == 0.0) != (self.hinf_b_vel == 0.0) {
            return Err(NavError::invalid(crate::msg!(
                "hinf_b_pos and hinf_b_vel are set together (both > 0) or derived together \
                 (both 0) (got {} and {})",
                num(self.hinf_b_pos),
                num(self.hinf_b_vel)
            )));
        }
        let hinf =
            |e: crate::hinf::HinfError| NavError::invalid(crate::msg!("hinf_*: {}", e.message));
        let mut spec = self.hinf_spec_scalars();
        // scalars 0 mean "derived": the placeholders only let the shared checks run
        spec.b_pos = if spec.b_pos > 0.0 { spec.b_pos } else { 1.0 };
        spec.b_vel = if spec.b_vel > 0.0 { spec.b_vel } else { 1.0 };
        spec.d = if spec.d > 0.0 { spec.d } else { 1.0 };
        spec.validate().map_err(hinf)?;
        if self.hinf_sensors & (HINF_RADIO | HINF_GNSS_POSITION) == 0 {
            return Err(NavError::invalid(crate::msg!(
                "hinf_sensors = {}: the set must hold the radio (1) or the relative GNSS position \
                 (4); a camera's line of sight leaves the range, a velocity the along-track \
                 position unobservable to a linear observer, so no design exists for them alone",
                self.hinf_sensors
            )));
        }
        if self.filter == FilterKind::Hinf
            && self.eccentricity > 0.0
            && ![HINF_RADIO, HINF_GNSS_POSITION].contains(&self.hinf_sensors)
        {
            return Err(NavError::invalid(crate::msg!(
                "filter 9 (hinf) at eccentricity = {}: the design scheduled over the orbit \
                 measures one position fix; set hinf_sensors to 1 (radio) or 4 (GNSS position) \
                 (got {})",
                num(self.eccentricity),
                self.hinf_sensors
            )));
        }
        if self.filter == FilterKind::Hinf && self.eccentricity > 0.0 && self.hinf_acquisition {
            return Err(NavError::invalid(crate::msg!(
                "filter 9 (hinf) at eccentricity = {}: the design is scheduled over the orbit \
                 and runs without track initiation; set hinf_acquisition = false",
                num(self.eccentricity)
            )));
        }
        #[cfg(feature = "std")]
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

    #[cfg(feature = "std")]
    /// The H-infinity design inputs of this configuration (`w0` = `mean_motion`, canonical
    /// frame). Set scalings are used as given; zero ones are derived from the noise every
    /// other filter uses:
    ///
    /// * `B = Qd^(1/2)` ([`crate::hinf::noise_inputs`]) with `Qd` the process-noise
    ///   covariance of one step `T = hinf_period`, exactly as the navigator builds it:
    ///   `Qd_VanLoan(accel_psd I3, T) + T6^T diag(q_pos T, q_vel T) T6` (the `q_*` are per
    ///   I/O axis, rotated to the canonical frame);
    /// * `D = R^(1/2)` with `R` the covariance of the indirect Cartesian position
    ///   ([`RadioSensor::position_covariance`]) at the initial estimate's position, of the
    ///   radio noise the Kalman filters assume (`sigma^2` times the noise model's variance
    ///   factor): `sigma_range` along the line of sight, `range * sigma_angle` across it;
    ///   for another `hinf_sensors` than the radio alone, `R` is the covariance of the
    ///   declared sensors' fused position fix ([`NavConfig::hinf_position_noise`]).
    ///
    /// Errors: a zero initial range when `D` is derived; a derived `B` of zero (no process
    /// noise at all) for the mixed design, whose H2 criterion needs one.
    pub fn hinf_spec(&self) -> Result<crate::hinf::HinfSpec, NavError> {
        let mut spec = self.hinf_spec_scalars();
        let t = self.hinf_period;
        if self.hinf_b_pos == 0.0 && self.hinf_b_vel == 0.0 {
            positive("hinf_period", t)?;
            let qc = Mat3::identity() * self.accel_psd;
            let qd = self.hinf_process_noise(CwModel::new(self.mean_motion).van_loan_q(&qc, t));
            if self.hinf_design == HinfDesignKind::Mixed && qd.abs().max() == 0.0 {
                return Err(NavError::invalid(
                    "hinf: the mixed design's process noise is derived from accel_psd, q_pos_* \
                     and q_vel_*, which are all 0: set one of them (or hinf_b_pos and \
                     hinf_b_vel)",
                ));
            }
            spec.b_matrix = Some(crate::hinf::psd_sqrt(&qd));
        }
        if self.hinf_sensors != HINF_RADIO {
            spec.d_matrix = Some(crate::hinf::psd_sqrt(&self.hinf_position_noise()?));
        } else if self.hinf_d == 0.0 {
            let inflate = self.noise().variance_factor().sqrt();
            let sensor = RadioSensor::new(
                self.frame,
                self.sigma_range * inflate,
                self.sigma_angle * inflate,
            );
            let r0 = self.initial_state().fixed_rows::<3>(0).owned();
            let r = sensor.position_covariance(&r0).ok_or_else(|| {
                NavError::invalid(
                    "hinf: the measurement noise is derived at the initial estimate's \
                     position, which is at zero range: set x0, y0, z0 (or hinf_d)",
                )
            })?;
            spec.d_matrix = Some(crate::hinf::psd_sqrt(&r));
        }
        Ok(spec)
    }

    /// The covariance of the H-infinity design's position fix for the declared
    /// `hinf_sensors`: the inverse of the sum of each declared sensor's position information
    /// at the initial estimate, `J = sum H^T R^-1 H` (the radio: the inverse of its indirect
    /// position's covariance, or `hinf_d^2 I` when set; the camera: its line of sight's
    /// Jacobian and `sigma_camera`; relative GNSS: `sigma_gnss` per axis; each noise scaled
    /// by its density's variance factor). Error when `J` is singular (no position fix
    /// declared) or the initial estimate is at zero range.
    pub fn hinf_position_noise(&self) -> Result<Mat3, NavError> {
        use crate::sensors::Sensor;
        use nalgebra::SVector;
        let x0 = self.initial_state();
        let r0 = x0.fixed_rows::<3>(0).owned();
        let at_zero = || {
            NavError::invalid(
                "hinf: the design's measurement noise is derived at the initial estimate's \
                 position, which is at zero range: set x0, y0, z0",
            )
        };
        let mut j = Mat3::zeros();
        if self.hinf_sensors & HINF_RADIO != 0 {
            let r = if self.hinf_d > 0.0 {
                Mat3::identity() * (self.hinf_d * self.hinf_d)
            } else {
                let inflate = self.noise().variance_factor().sqrt();
                RadioSensor::new(
                    self.frame,
                    self.sigma_range * inflate,
                    self.sigma_angle * inflate,
                )
                .position_covariance(&r0)
                .ok_or_else(at_zero)?
            };
            j += r.try_inverse().ok_or_else(at_zero)?;
        }
        // a declared sensor's information on the position at the initial estimate
        fn at<const D: usize, S: Sensor<D>>(s: &S, x0: &State) -> Option<Mat3> {
            let lin = s.linearize(x0).ok()?;
            let h = lin.h.fixed_view::<D, 3>(0, 0).owned();
            crate::hinf::information(&h, &s.noise().cov(), &SVector::zeros()).map(|(j, _)| j)
        }
        if self.hinf_sensors & HINF_CAMERA != 0 {
            j += at(&self.camera_sensor(), &x0).ok_or_else(at_zero)?;
        }
        if self.hinf_sensors & HINF_GNSS_POSITION != 0 {
            j += at(&self.gnss_position_sensor(), &x0).ok_or_else(at_zero)?;
        }
        let r = j.try_inverse().filter(|r| r.iter().all(|v| v.is_finite()));
        r.map(|r| (r + r.transpose()) * 0.5).ok_or_else(|| {
            NavError::invalid(crate::msg!(
                "hinf_sensors = {}: the declared sensors do not fix the position at the initial \
                 estimate",
                self.hinf_sensors
            ))
        })
    }

    /// The covariance of the H-infinity design's velocity fix when `hinf_sensors` declares
    /// relative GNSS velocity (`sigma_gnss_velocity^2` per axis times the GNSS density's
    /// variance factor), `None` otherwise.
    pub fn hinf_velocity_noise(&self) -> Option<Mat3> {
        use crate::sensors::Sensor;
        (self.hinf_sensors & HINF_GNSS_VELOCITY != 0)
            .then(|| self.gnss_velocity_sensor().noise().cov())
    }

    /// The declared camera (`sigma_camera`, `camera_noise_*`; I/O frame).
    pub fn camera_sensor(&self) -> crate::sensors::CameraSensor {
        crate::sensors::CameraSensor {
            frame: self.frame,
            noise: crate::sensors::SensorNoise {
                model: self.camera_noise(),
                scales: [self.sigma_camera; 2],
            },
        }
    }

    /// The declared relative GNSS position (`sigma_gnss`, `gnss_noise_*`; I/O frame).
    pub fn gnss_position_sensor(
        &self,
    ) -> crate::sensors::Modelled<crate::sensors::CartesianSensor> {
        crate::sensors::Modelled {
            model: crate::sensors::CartesianSensor {
                frame: self.frame,
                sigma: self.sigma_gnss,
            },
            noise: crate::sensors::SensorNoise {
                model: self.gnss_noise(),
                scales: [self.sigma_gnss; 3],
            },
        }
    }

    /// The declared relative GNSS velocity (`sigma_gnss_velocity`, `gnss_noise_*`; I/O
    /// frame).
    pub fn gnss_velocity_sensor(&self) -> crate::sensors::VelocitySensor {
        crate::sensors::VelocitySensor {
            frame: self.frame,
            noise: crate::sensors::SensorNoise {
                model: self.gnss_noise(),
                scales: [self.sigma_gnss_velocity; 3],
            },
        }
    }

    /// The process-noise covariance of one H-infinity period `T = hinf_period` from the
    /// model's white-acceleration part `model_q`: `model_q + T6^T diag(q_pos T, q_vel T) T6`
    /// (the `q_*` are per I/O axis, rotated to the canonical frame).
    pub fn hinf_process_noise(&self, model_q: Mat6) -> Mat6 {
        model_q + self.process_noise_rates() * self.hinf_period
    }

    /// The per-second process-noise variances `q_pos`, `q_vel` (per I/O axis) as a
    /// canonical-frame covariance rate; the AQUKF's velocity part is zero (`q_vel` is its
    /// initial adaptive density). A signed permutation of a diagonal: scaling it by a step
    /// gives the bits of rotating the scaled diagonal.
    pub fn process_noise_rates(&self) -> Mat6 {
        let qv = if self.filter == FilterKind::Aqukf {
            [0.0; 3]
        } else {
            self.q_vel
        };
        let rates = State::from_row_slice(&[
            self.q_pos[0],
            self.q_pos[1],
            self.q_pos[2],
            qv[0],
            qv[1],
            qv[2],
        ]);
        self.frame.cov_to_canonical(&Mat6::from_diagonal(&rates))
    }

    /// The relative dynamics the configuration describes (the one place that chooses the
    /// model): the Clohessy–Wiltshire model of `mean_motion` at `eccentricity` 0, the
    /// linearised elliptic model otherwise.
    pub fn dynamics(&self) -> crate::dynamics::Dynamics {
        crate::dynamics::Dynamics::of_orbit(self.mean_motion, self.eccentricity, self.true_anomaly0)
    }

    /// Whether the factory builds this filter's radio update on the density of
    /// `noise_model` ([`NavConfig::noise`]) rather than on the Gaussian of its variance:
    /// the robust EKF (11) and the particle prior's terms (EKF or UKF). The point particles
    /// weigh with the density whatever this says.
    pub fn robust_radio(&self) -> bool {
        self.filter == FilterKind::Rekf
            || (self.filter.pf_kind().is_some() && self.pf_prior == PfPrior::Particle)
    }

    /// The measurement-noise density (scales `sigma_range`, `sigma_angle`).
    pub fn noise(&self) -> NoiseModel {
        self.noise_model
            .model(self.noise_zeta, self.noise_scale, self.noise_dof)
    }

    /// The camera's angle-noise density (`camera_noise_*`), scaled by `sigma_camera`.
    pub fn camera_noise(&self) -> NoiseModel {
        self.camera_noise_model.model(
            self.camera_noise_zeta,
            self.camera_noise_scale,
            self.camera_noise_dof,
        )
    }

    /// Relative GNSS's noise density (`gnss_noise_*`), scaled by `sigma_gnss` and
    /// `sigma_gnss_velocity`.
    pub fn gnss_noise(&self) -> NoiseModel {
        self.gnss_noise_model.model(
            self.gnss_noise_zeta,
            self.gnss_noise_scale,
            self.gnss_noise_dof,
        )
    }

    /// The particle-filter settings for filter codes 4-8 (`None` for the other filters):
    /// `PfParams::new(kind)` with `particles`, `resampler` (`auto` resolved by `pf_move`),
    /// `resample_threshold`, `seed`, the UKF parameters (the unscented proposal of `upf`
    /// and `cgapf`), `pf_move` and `pf_threads` of this configuration; without the moves the
    /// particles start from the prior ([`PfInit::Prior`]), as the papers write.
    pub fn pf_params(&self) -> Option<PfParams> {
        let kind = self.filter.pf_kind()?;
        Some(PfParams {
            moves: self.pf_move,
            prior: self.pf_prior,
            threads: self.pf_threads,
            particles: self.particles,
            // the particle prior resamples as the moves do
            resampler: self
                .resampler
                .resolve(self.pf_move || self.pf_prior == PfPrior::Particle),
            init: if self.pf_move {
                kind.default_init()
            } else {
                PfInit::Prior
            },
            threshold: self.resample_threshold,
            seed: self.seed,
            ukf: self.ukf(),
            ..PfParams::new(kind)
        })
    }

    /// The AQUKF's adaptive settings: `window`, `q_vv_floor`, `q_vv_ceiling`, the gated
    /// law's settings, and the initial `q_vv` = `q_vel` rotated to the canonical frame (for
    /// the AQUKF, `q_vel_*` is the initial adaptive density rather than a fixed part of
    /// `Q`; see [`super::Navigator`]).
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

    /// Initial covariance in the canonical frame: `diag(sigma_pos0^2 I3, sigma_vel0^2 I3)`
    /// (frame-independent), and with `sigma_range0 > 0` the position block
    /// `sigma_pos0^2 I3 + (sigma_range0^2 - sigma_pos0^2) u u^T`, `u` the unit vector of
    /// `x0`'s position (its line of sight from the target).
    pub fn initial_covariance(&self) -> Mat6 {
        let (p, v) = (self.sigma_pos0.powi(2), self.sigma_vel0.powi(2));
        let mut c = Mat6::from_diagonal(&State::from_row_slice(&[p, p, p, v, v, v]));
        let x = self.initial_state();
        let r = Vec3::new(x[0], x[1], x[2]);
        if self.sigma_range0 > 0.0 && r.norm() > 0.0 {
            let u = r / r.norm();
            let along = u * u.transpose() * (self.sigma_range0.powi(2) - p);
            let mut block = c.fixed_view_mut::<3, 3>(0, 0);
            block += along;
        }
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Element;

    /// The configuration section, written slot by slot without a list, is the settings
    /// list's count and values in order.
    #[test]
    fn settings_section_is_the_settings_list() {
        let c = NavConfig {
            filter: FilterKind::Imm,
            sigma_range: 2.5,
            ..NavConfig::default()
        };
        let mut b = Vec::new();
        c.write_settings(&mut Writer::new(&mut b));
        let list = c.settings();
        let mut expect = (list.len() as u32).to_le_bytes().to_vec();
        for (_, v) in &list {
            expect.extend_from_slice(&v.bits().to_le_bytes());
        }
        assert_eq!(b, expect);
        assert_eq!(c.settings_count(), list.len());
    }

    /// Every declared default is one its type holds (a setter that failed would leave the
    /// placeholder) and passes validation.
    #[test]
    fn defaults_are_the_declared_ones_and_valid() {
        let c = NavConfig::default();
        for p in PARAMS {
            for (i, e) in p.elements.iter().enumerate() {
                assert_eq!((p.get)(&c, i), e.default, "{}", e.name);
            }
        }
        assert_eq!(c.validate(), Ok(()));
    }

    /// Names, value references and slots are unique; slots are contiguous from 0 and every
    /// element's kind of default matches its parameter's.
    #[test]
    fn table_is_consistent() {
        let elements: Vec<&Element> = PARAMS.iter().flat_map(|p| p.elements.iter()).collect();
        for (k, e) in elements.iter().enumerate() {
            assert!(
                elements[k + 1..].iter().all(|f| f.name != e.name),
                "name {}",
                e.name
            );
            if let Some(id) = e.id {
                assert!(
                    elements[k + 1..].iter().all(|f| f.id != Some(id)),
                    "id {id}"
                );
            }
        }
        let mut slots: Vec<u16> = PARAMS.iter().filter_map(|p| p.slot).collect();
        slots.sort_unstable();
        assert!(slots.iter().enumerate().all(|(i, s)| usize::from(*s) == i));
        for p in PARAMS {
            for e in p.elements {
                assert_eq!(
                    matches!(e.default, Value::Real(_)),
                    p.kind == Kind::Real,
                    "{}",
                    e.name
                );
            }
        }
    }

    /// `pf_move = false` is the papers' filters as written: drawn from the prior and, with
    /// the default `resampler = auto`, resampled multinomially; an explicit scheme is kept,
    /// and with the moves `auto` is systematic from the first measurement.
    #[test]
    fn literal_filters_are_the_papers() {
        use crate::estimators::pf::resample::Resampler;
        for filter in [
            FilterKind::Pf,
            FilterKind::Rpf,
            FilterKind::Upf,
            FilterKind::Gapf,
            FilterKind::Cgapf,
        ] {
            let moved = NavConfig {
                filter,
                pf_prior: PfPrior::Gaussian,
                ..Default::default()
            };
            assert_eq!(moved.resampler, ResamplerSetting::Auto);
            let p = moved.pf_params().unwrap();
            assert!(p.moves);
            assert_eq!(
                (p.init, p.resampler, p.threshold),
                (PfInit::FirstMeasurement, Resampler::Systematic, 2.0 / 3.0)
            );
            let literal = NavConfig {
                pf_move: false,
                ..moved
            };
            let p = literal.pf_params().unwrap();
            assert!(!p.moves);
            assert_eq!(
                (p.init, p.resampler, p.threshold),
                (PfInit::Prior, Resampler::Multinomial, 2.0 / 3.0)
            );
            let chosen = NavConfig {
                resampler: ResamplerSetting::Scheme(Resampler::Residual),
                ..literal
            };
            assert_eq!(chosen.pf_params().unwrap().resampler, Resampler::Residual);
        }
    }

    /// The enums declared elsewhere agree with their code lists here, item by item.
    #[test]
    fn code_lists_match_their_enums() {
        let check = |list: &CodeList, items: Vec<(i32, &str)>| {
            let declared: Vec<(i32, &str)> = list.items.iter().map(|i| (i.code, i.name)).collect();
            assert_eq!(declared, items, "{}", list.name);
        };
        check(
            &FRAME_CODES,
            Frame::ALL.iter().map(|f| (f.code(), f.name())).collect(),
        );
        check(
            &RESAMPLER_CODES,
            ResamplerSetting::ALL
                .iter()
                .map(|r| (r.code(), r.name()))
                .collect(),
        );
        check(
            &AQ_LAW_CODES,
            AdaptationLaw::ALL
                .iter()
                .map(|a| (*a as i32, a.name()))
                .collect(),
        );
        check(
            &DISCRETIZATION_CODES,
            (1..=2)
                .filter_map(Discretization::from_code)
                .map(|d| {
                    (
                        d as i32,
                        if d == Discretization::Exact {
                            "exact"
                        } else {
                            "euler"
                        },
                    )
                })
                .collect(),
        );
        assert!(Discretization::from_code(3).is_none());
    }

    /// The saved state's settings keep their historical order and names
    /// (`docs/state-format.md`): the first ones, and the total.
    #[test]
    fn settings_order_is_the_state_format() {
        let names: Vec<String> = NavConfig::default()
            .settings()
            .into_iter()
            .map(|(n, _)| n)
            .collect();
        assert_eq!(names.len(), 72);
        assert_eq!(
            &names[..8],
            [
                "filter",
                "frame",
                "mean_motion",
                "chaser_mass",
                "sigma_range",
                "sigma_angle",
                "x0[0]",
                "x0[1]"
            ]
        );
        assert_eq!(names[21], "discretization");
        assert_eq!(names[54], "pf_move");
        assert_eq!(&names[55..57], ["eccentricity", "true_anomaly0"]);
        assert_eq!(
            &names[57..],
            [
                "sigma_camera",
                "sigma_gnss",
                "sigma_gnss_velocity",
                "range_bank",
                "sigma_range0",
                "camera_noise_model",
                "camera_noise_zeta",
                "camera_noise_scale",
                "camera_noise_dof",
                "gnss_noise_model",
                "gnss_noise_zeta",
                "gnss_noise_scale",
                "gnss_noise_dof",
                "hinf_sensors",
                "pf_prior",
            ]
        );
    }
}
