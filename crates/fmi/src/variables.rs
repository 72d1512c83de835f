//! The one table of relnav.fmu's variables. It generates `modelDescription.xml`
//! ([`crate::description`]) and drives the get/set dispatch ([`crate::instance`]): value
//! reference = index in [`VARIABLES`] (checked by a test), start values come from here and
//! nowhere else. The types and the `variables!` macro that writes a table are shared with
//! the kit's FMUs, whose own tables live beside their models ([`crate::plant`],
//! [`crate::guidance`]).

use std::f64::consts::PI;

/// FMI causality.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Causality {
    /// Fixed before initialisation.
    Parameter,
    /// Set by the master before each step.
    Input,
    /// Computed by the FMU.
    Output,
}

/// FMI variability.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Variability {
    /// Constant after initialisation.
    Fixed,
    /// Changes only at communication points (held in between).
    Discrete,
    /// A continuous quantity sampled at communication points.
    Continuous,
}

/// A list of named integer codes (the C ABI's enums: filter, frame, ...).
///
/// Declared in `modelDescription.xml` as an FMI **Integer** with `min`/`max` and the
/// codes with their names in the description, not as an FMI Enumeration: libcosim
/// ignores Enumeration variables and Ecos drops them (`../shared/docs/fmi-masters.md`),
/// so an Enumeration could be set from fmpy only. A code outside the list is refused at
/// `fmi2SetInteger`.
#[derive(Debug)]
pub struct EnumType {
    /// Name of the list (the README's code table and error messages).
    pub name: &'static str,
    /// Items: (name, code, description).
    pub items: &'static [(&'static str, i32, &'static str)],
}

impl EnumType {
    /// Smallest and largest code (the Integer's `min` and `max`).
    pub fn range(&self) -> (i32, i32) {
        let codes = self.items.iter().map(|it| it.1);
        (codes.clone().min().unwrap_or(0), codes.max().unwrap_or(0))
    }

    /// The item whose code equals `value`, if any.
    pub fn item(&self, value: f64) -> Option<&'static (&'static str, i32, &'static str)> {
        self.items.iter().find(|it| f64::from(it.1) == value)
    }

    /// `1 ekf, 2 ukf, ...`: the codes with their names.
    pub fn codes(&self) -> String {
        let parts: Vec<String> = self
            .items
            .iter()
            .map(|(n, v, _)| format!("{v} {n}"))
            .collect();
        parts.join(", ")
    }
}

/// FMI base type of a variable.
#[derive(Debug, Clone, Copy)]
pub enum VarType {
    /// Real with a unit (empty string: dimensionless, no unit attribute).
    Real(&'static str),
    /// Integer.
    Integer,
    /// Boolean.
    Boolean,
    /// Integer restricted to the codes of a list (FMI Integer with `min`/`max`).
    Code(&'static EnumType),
}

/// One FMU variable.
#[derive(Debug)]
pub struct VarDef {
    /// Value reference (= index in [`VARIABLES`]).
    pub vr: u32,
    /// Name.
    pub name: &'static str,
    /// Causality.
    pub causality: Causality,
    /// Variability.
    pub variability: Variability,
    /// Type.
    pub ty: VarType,
    /// Start value (Integer/code/Boolean stored exactly as f64); unused for outputs.
    pub start: f64,
    /// Description.
    pub description: &'static str,
}

/// The FMI base type class a `fmi2Get*` / `fmi2Set*` function reads or writes: Real,
/// Integer (Integer variables and codes), Boolean.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum TypeClass {
    /// `fmi2GetReal` / `fmi2SetReal`.
    Real = 1,
    /// `fmi2GetInteger` / `fmi2SetInteger` (Integer and code variables).
    Integer = 2,
    /// `fmi2GetBoolean` / `fmi2SetBoolean`.
    Boolean = 3,
}

impl TypeClass {
    /// The class of a variable type.
    pub const fn of(ty: &VarType) -> Self {
        match ty {
            VarType::Real(_) => Self::Real,
            VarType::Integer | VarType::Code(_) => Self::Integer,
            VarType::Boolean => Self::Boolean,
        }
    }
}

/// What the get/set dispatch needs of one variable, derived from its [`VarDef`] (so the
/// table stays the one source; [`VarDef::access`]): its [`TypeClass`] and the
/// instance states (bit mask of `instance::ModelState`) in which `fmi2Set*` may write it
/// **directly**, with no other check and no other effect. That is an input after
/// initialisation (`StepComplete` = 4): parameters are checked by the model and a set
/// before initialisation refreshes the initial outputs, which the full path does
/// (the same rules and messages either way, only faster for the master's inputs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct VarAccess {
    /// Base type class.
    pub class: TypeClass,
    /// States in which a set is a plain store.
    pub direct_set: u8,
}

impl VarDef {
    /// This variable's [`VarAccess`].
    pub const fn access(&self) -> VarAccess {
        VarAccess {
            class: TypeClass::of(&self.ty),
            direct_set: match self.causality {
                // ModelState::StepComplete
                Causality::Input => 4,
                Causality::Parameter | Causality::Output => 0,
            },
        }
    }
}

/// Units used by the table, as (name, exponents of kg, m, s, rad).
pub const UNITS: &[(&str, [i32; 4])] = &[
    ("N", [1, 1, -2, 0]),
    ("kg", [1, 0, 0, 0]),
    ("m", [0, 1, 0, 0]),
    ("m/s", [0, 1, -1, 0]),
    ("rad", [0, 0, 0, 1]),
    ("rad/s", [0, 0, -1, 1]),
    ("m2/s", [0, 2, -1, 0]),
    ("m2/s3", [0, 2, -3, 0]),
    ("s", [0, 0, 1, 0]),
    // appended for the kit's FMUs (a model declares the units its table uses)
    ("N.s", [1, 1, -1, 0]),
];

/// `filter` parameter values (same codes as the C ABI's `relnav_filter`).
pub static FILTER_TYPE: EnumType = EnumType {
    name: "Filter",
    items: &[
        ("ekf", 1, "Extended Kalman filter (Joseph form)"),
        ("ukf", 2, "Unscented Kalman filter (scaled sigma points)"),
        (
            "aqukf",
            3,
            "Sliding-window adaptive UKF (paper 001: adaptive velocity process noise, see window and q_vv_*)",
        ),
        (
            "pf",
            4,
            "SIR particle filter (paper 000), with the posterior-invariant moves of pf_move (without them its velocities stay impoverished, metres off on paper 000)",
        ),
        (
            "rpf",
            5,
            "Regularised particle filter (kernel jitter after resampling)",
        ),
        (
            "upf",
            6,
            "Unscented particle filter (per-particle UKF proposal)",
        ),
        (
            "gapf",
            7,
            "Genetic-algorithm particle filter (crossover and mutation after resampling)",
        ),
        (
            "cgapf",
            8,
            "Cloud-genetic particle filter (paper 003: UKF proposal, cloud-model genetic moves)",
        ),
        (
            "hinf",
            9,
            "Robust H-infinity filter (paper 002; observer form designed by an LMI at initialisation for hinf_period; sigma_* are NaN)",
        ),
        (
            "imm",
            10,
            "Interacting multiple-model filter: imm_modes EKFs with the process noise plus imm_accel_psd_*, Markov switching (imm_p_stay_*); mode probabilities in imm_mu_*",
        ),
    ],
};

/// `frame` parameter values.
pub static FRAME_TYPE: EnumType = EnumType {
    name: "Frame",
    items: &[
        (
            "radial_along_normal",
            1,
            "x radial outward, y along-track, z orbit normal (canonical; paper 002)",
        ),
        (
            "along_radial_antinormal",
            2,
            "x along-track, y radial outward, z minus orbit normal (paper 000)",
        ),
        (
            "along_antinormal_nadir",
            3,
            "x along-track, y minus orbit normal, z nadir (paper 003)",
        ),
    ],
};

/// `discretization` parameter values.
pub static DISCRETIZATION_TYPE: EnumType = EnumType {
    name: "Discretization",
    items: &[
        (
            "exact",
            1,
            "Exact CW transition, exact zero-order hold, Van Loan process noise",
        ),
        ("euler", 2, "First-order Euler I + T A (literal paper 000)"),
    ],
};

/// `resampler` parameter values (same codes as the C ABI's `relnav_resampler`).
pub static RESAMPLER_TYPE: EnumType = EnumType {
    name: "Resampler",
    items: &[
        (
            "multinomial",
            1,
            "N independent draws from the weights (paper 000's SIR)",
        ),
        (
            "systematic",
            2,
            "One uniform, N evenly spaced points (Kitagawa 1996)",
        ),
        ("stratified", 3, "One uniform per stratum (Kitagawa 1996)"),
        (
            "residual",
            4,
            "floor(N w) deterministic copies, the rest multinomial (Liu and Chen 1998)",
        ),
    ],
};

/// `noise_model` parameter values (same codes as the C ABI's `relnav_noise_model`).
pub static NOISE_MODEL_TYPE: EnumType = EnumType {
    name: "NoiseModel",
    items: &[
        ("gaussian", 1, "Gaussian N(0, sigma^2)"),
        (
            "mixture",
            2,
            "Contaminated Gaussian (1 - zeta) N(0, sigma^2) + zeta N(0, (scale sigma)^2) (paper 003)",
        ),
        ("student_t", 3, "Student-t sigma t_dof"),
    ],
};

/// `hinf_design` parameter values (the C ABI's `relnav_hinf_form` codes available to
/// filter 9).
pub static HINF_DESIGN_TYPE: EnumType = EnumType {
    name: "HinfDesign",
    items: &[
        (
            "gamma_optimal",
            1,
            "Observer with the least certified gamma (issue 5's design)",
        ),
        (
            "mixed",
            3,
            "Mixed H2/H-infinity observer: least H2 norm (steady-state error) with gamma <= hinf_gamma_factor times the optimum",
        ),
    ],
};

/// `aq_law` parameter values (same codes as the C ABI's `relnav_adaptation`).
pub static AQ_LAW_TYPE: EnumType = EnumType {
    name: "AdaptationLaw",
    items: &[
        (
            "window",
            1,
            "Paper 001 literally: the sliding-window estimate of q_vv at every update",
        ),
        (
            "gated",
            2,
            "q_vv stays at q_vel while the windowed NIS is below its chi-square quantile; the sliding window adapts it (never below q_vel) while it is above",
        ),
    ],
};

/// All code lists, in declaration order.
pub static ENUM_TYPES: [&EnumType; 7] = [
    &FILTER_TYPE,
    &FRAME_TYPE,
    &DISCRETIZATION_TYPE,
    &RESAMPLER_TYPE,
    &NOISE_MODEL_TYPE,
    &HINF_DESIGN_TYPE,
    &AQ_LAW_TYPE,
];

macro_rules! variables {
    ($( $id:ident = $vr:literal : $name:literal, $caus:ident, $var:ident, $ty:expr, $start:expr, $desc:literal; )*) => {
        /// Value references by name (generated from the table).
        pub mod vr {
            $(
                #[doc = $desc]
                pub const $id: u32 = $vr;
            )*
        }
        /// Every FMU variable; the value reference is the index.
        pub static VARIABLES: &[$crate::variables::VarDef] = &[
            $( $crate::variables::VarDef {
                vr: $vr,
                name: $name,
                causality: $crate::variables::Causality::$caus,
                variability: $crate::variables::Variability::$var,
                ty: $ty,
                start: $start,
                description: $desc,
            }, )*
        ];
    };
}
pub(crate) use variables;

use VarType::{Boolean, Code, Integer, Real};

variables! {
    FILTER = 0: "filter", Parameter, Fixed, Code(&FILTER_TYPE), 1.0,
        "Estimator (codes 1-10: 1-3 Kalman (EKF, UKF, AQUKF), 4-8 particle filters, 9 robust H-infinity, 10 IMM)";
    FRAME = 1: "frame", Parameter, Fixed, Code(&FRAME_TYPE), 2.0,
        "Hill-frame convention of every input and output vector and angle";
    DISCRETIZATION = 2: "discretization", Parameter, Fixed, Code(&DISCRETIZATION_TYPE), 1.0,
        "Discretisation of the CW model";
    MEAN_MOTION = 3: "mean_motion", Parameter, Fixed, Real("rad/s"), 2.0 * PI / 7200.0,
        "Mean motion of the target's circular orbit (> 0)";
    CHASER_MASS = 4: "chaser_mass", Parameter, Fixed, Real("kg"), 1000.0,
        "Chaser mass: thrust / mass = acceleration (> 0)";
    SIGMA_RANGE = 5: "sigma_range", Parameter, Fixed, Real("m"), 0.5,
        "Range measurement noise, 1 sigma of the Gaussian (nominal sigma of the other noise models; > 0)";
    SIGMA_ANGLE = 6: "sigma_angle", Parameter, Fixed, Real("rad"), 0.01 * PI / 180.0,
        "Azimuth and elevation measurement noise, 1 sigma of the Gaussian (nominal sigma of the other noise models; > 0)";
    X0 = 7: "x0", Parameter, Fixed, Real("m"), 405.0, "Initial estimate of x";
    Y0 = 8: "y0", Parameter, Fixed, Real("m"), 505.0, "Initial estimate of y";
    Z0 = 9: "z0", Parameter, Fixed, Real("m"), 205.0, "Initial estimate of z";
    VX0 = 10: "vx0", Parameter, Fixed, Real("m/s"), 0.1, "Initial estimate of vx";
    VY0 = 11: "vy0", Parameter, Fixed, Real("m/s"), 0.1, "Initial estimate of vy";
    VZ0 = 12: "vz0", Parameter, Fixed, Real("m/s"), 0.1, "Initial estimate of vz";
    SIGMA_POS0 = 13: "sigma_pos0", Parameter, Fixed, Real("m"), 50.0,
        "Initial position uncertainty per axis, 1 sigma (> 0)";
    SIGMA_VEL0 = 14: "sigma_vel0", Parameter, Fixed, Real("m/s"), 1.0,
        "Initial velocity uncertainty per axis, 1 sigma (> 0)";
    ACCEL_PSD = 15: "accel_psd", Parameter, Fixed, Real("m2/s3"), 0.0,
        "Process noise: spectral density of a continuous white acceleration per axis (Van Loan discretisation; >= 0)";
    Q_POS_X = 16: "q_pos_x", Parameter, Fixed, Real("m2/s"), 0.09,
        "Process noise: x position variance added per second (discrete Q = q h; >= 0)";
    Q_POS_Y = 17: "q_pos_y", Parameter, Fixed, Real("m2/s"), 0.000625,
        "Process noise: y position variance added per second (>= 0)";
    Q_POS_Z = 18: "q_pos_z", Parameter, Fixed, Real("m2/s"), 0.0025,
        "Process noise: z position variance added per second (>= 0)";
    Q_VEL_X = 19: "q_vel_x", Parameter, Fixed, Real("m2/s3"), 1e-6,
        "Process noise: vx variance added per second (>= 0)";
    Q_VEL_Y = 20: "q_vel_y", Parameter, Fixed, Real("m2/s3"), 1e-6,
        "Process noise: vy variance added per second (>= 0)";
    Q_VEL_Z = 21: "q_vel_z", Parameter, Fixed, Real("m2/s3"), 1e-6,
        "Process noise: vz variance added per second (>= 0)";
    UKF_ALPHA = 22: "ukf_alpha", Parameter, Fixed, Real(""), 1.0,
        "UKF sigma-point spread alpha (> 0); also the unscented proposal of upf and cgapf";
    UKF_BETA = 23: "ukf_beta", Parameter, Fixed, Real(""), 2.0, "UKF beta (2 for Gaussian priors)";
    UKF_KAPPA = 24: "ukf_kappa", Parameter, Fixed, Real(""), 0.0, "UKF kappa";
    SEED = 25: "seed", Parameter, Fixed, Integer, 0.0,
        "Seed of the filters that draw random numbers (identical seeds give identical outputs)";
    THRUST_X = 26: "thrust_x", Input, Discrete, Real("N"), 0.0, "Thrust on the chaser along x, held over the step";
    THRUST_Y = 27: "thrust_y", Input, Discrete, Real("N"), 0.0, "Thrust on the chaser along y, held over the step";
    THRUST_Z = 28: "thrust_z", Input, Discrete, Real("N"), 0.0, "Thrust on the chaser along z, held over the step";
    RANGE = 29: "range", Input, Discrete, Real("m"), 0.0, "Measured range, taken at the step's start time";
    AZIMUTH = 30: "azimuth", Input, Discrete, Real("rad"), 0.0,
        "Measured azimuth atan2(y, x) in [0, 2 pi), taken at the step's start time";
    ELEVATION = 31: "elevation", Input, Discrete, Real("rad"), 0.0,
        "Measured elevation asin(z / range), taken at the step's start time";
    MEASUREMENT_VALID = 32: "measurement_valid", Input, Discrete, Boolean, 0.0,
        "True when range/azimuth/elevation hold a fresh measurement taken at the step's start time";
    X = 33: "x", Output, Continuous, Real("m"), 0.0, "Estimated relative position x";
    Y = 34: "y", Output, Continuous, Real("m"), 0.0, "Estimated relative position y";
    Z = 35: "z", Output, Continuous, Real("m"), 0.0, "Estimated relative position z";
    VX = 36: "vx", Output, Continuous, Real("m/s"), 0.0, "Estimated relative velocity vx";
    VY = 37: "vy", Output, Continuous, Real("m/s"), 0.0, "Estimated relative velocity vy";
    VZ = 38: "vz", Output, Continuous, Real("m/s"), 0.0, "Estimated relative velocity vz";
    SIGMA_X = 39: "sigma_x", Output, Continuous, Real("m"), 0.0, "1-sigma uncertainty of x (from the covariance)";
    SIGMA_Y = 40: "sigma_y", Output, Continuous, Real("m"), 0.0, "1-sigma uncertainty of y";
    SIGMA_Z = 41: "sigma_z", Output, Continuous, Real("m"), 0.0, "1-sigma uncertainty of z";
    SIGMA_VX = 42: "sigma_vx", Output, Continuous, Real("m/s"), 0.0, "1-sigma uncertainty of vx";
    SIGMA_VY = 43: "sigma_vy", Output, Continuous, Real("m/s"), 0.0, "1-sigma uncertainty of vy";
    SIGMA_VZ = 44: "sigma_vz", Output, Continuous, Real("m/s"), 0.0, "1-sigma uncertainty of vz";
    PARTICLES = 45: "particles", Parameter, Fixed, Integer, 1500.0,
        "Number of particles of the particle filters (codes 4-8; 1..2000000)";
    RESAMPLER = 46: "resampler", Parameter, Fixed, Code(&RESAMPLER_TYPE), 2.0,
        "Resampling scheme of the particle filters";
    RESAMPLE_THRESHOLD = 47: "resample_threshold", Parameter, Fixed, Real(""), 2.0 / 3.0,
        "The particle filters resample when the effective sample size drops below resample_threshold * particles (in (0, 1]; paper 000: 2/3)";
    NOISE_MODEL = 48: "noise_model", Parameter, Fixed, Code(&NOISE_MODEL_TYPE), 1.0,
        "Measurement-noise density scaled by sigma_range and sigma_angle: the particle filters weigh with it, the Kalman filters assume the Gaussian of its variance";
    NOISE_ZETA = 49: "noise_zeta", Parameter, Fixed, Real(""), 0.2,
        "Mixture noise: weight of the wide component (in [0, 1))";
    NOISE_SCALE = 50: "noise_scale", Parameter, Fixed, Real(""), 10.0,
        "Mixture noise: sigma of the wide component over the nominal sigma (>= 1)";
    NOISE_DOF = 51: "noise_dof", Parameter, Fixed, Real(""), 4.0,
        "Student-t noise: degrees of freedom (> 2)";
    ESS = 52: "ess", Output, Continuous, Real(""), 0.0,
        "Effective sample size 1 / sum w^2 of a particle filter after the last measurement update, before resampling (in [1, particles]); NaN for the Kalman filters";
    WINDOW = 53: "window", Parameter, Fixed, Integer, 10.0,
        "AQUKF (filter 3): sliding-window width N of the adaptive process noise (1..512; paper 001: 10). For the AQUKF, q_vel_* is the initial adaptive density";
    Q_VV_X = 54: "q_vv_x", Output, Continuous, Real("m2/s3"), 0.0,
        "AQUKF: current adaptive velocity process-noise density along x (I/O frame; q_vv = diag(Q_vv) / T of paper 001); NaN for the other filters";
    Q_VV_Y = 55: "q_vv_y", Output, Continuous, Real("m2/s3"), 0.0,
        "AQUKF: current adaptive velocity process-noise density along y; NaN for the other filters";
    Q_VV_Z = 56: "q_vv_z", Output, Continuous, Real("m2/s3"), 0.0,
        "AQUKF: current adaptive velocity process-noise density along z; NaN for the other filters";
    HINF_PERIOD = 57: "hinf_period", Parameter, Fixed, Real("s"), 1.0,
        "H-infinity filter (code 9): sampling period of its discrete design; fmi2DoStep with another step size is refused (set it to the communication step)";
    HINF_DELTA_BAR = 58: "hinf_delta_bar", Parameter, Fixed, Real(""), 0.05,
        "H-infinity filter: bound of the orbit-rate uncertainty, w = w0 (1 + delta), |delta| <= hinf_delta_bar (paper 002: 0.05)";
    HINF_B_POS = 59: "hinf_b_pos", Parameter, Fixed, Real("m"), 0.0,
        "H-infinity filter: process-noise scaling on positions (paper 002 B: 0.05); 0 with hinf_b_vel = 0 (default): derived from accel_psd, q_pos_*, q_vel_* (the noise every other filter uses)";
    HINF_B_VEL = 60: "hinf_b_vel", Parameter, Fixed, Real("m/s"), 0.0,
        "H-infinity filter: process-noise scaling on velocities (paper 002 B: 0.001); 0 with hinf_b_pos = 0 (default): derived";
    HINF_D = 61: "hinf_d", Parameter, Fixed, Real("m"), 0.0,
        "H-infinity filter: scaling of the indirect position measurement noise (paper 002 D: 0.1); 0 (default): derived from sigma_range, sigma_angle and the noise model at the initial estimate's position";
    HINF_GAMMA = 62: "hinf_gamma", Output, Continuous, Real(""), 0.0,
        "H-infinity filter: the design's certified bound gamma on the worst-case gain from the scaled noises to the estimation error; NaN for the other filters";
    FMI_STATUS = 63: "fmi_status", Output, Discrete, Integer, 0.0,
        "Worst fmi2Status this instance has returned since fmi2Instantiate or fmi2Reset: 0 fmi2OK, 3 fmi2Error, 4 fmi2Fatal (the reason is logged under logStatusError). For masters that ignore fmi2Error (Ecos): 3 means a call was refused, and the other outputs no longer advance";
    HINF_DESIGN = 64: "hinf_design", Parameter, Fixed, Code(&HINF_DESIGN_TYPE), 3.0,
        "H-infinity filter: the LMI design (mixed H2/H-infinity by default; gamma_optimal is issue 5's filter)";
    HINF_GAMMA_FACTOR = 65: "hinf_gamma_factor", Parameter, Fixed, Real(""), 1.5,
        "H-infinity filter, mixed design: bound on the certified gamma (hinf_gamma) as a multiple of the gamma-optimal design's (> 1)";
    HINF_ACQUISITION = 66: "hinf_acquisition", Parameter, Fixed, Boolean, 1.0,
        "H-infinity filter: start with the Kalman gain of the design's noise model and hand over to the designed gain once that is no worse (track initiation); false: the designed gain from the first step";
    HINF_H2_NORM = 67: "hinf_h2_norm", Output, Continuous, Real(""), 0.0,
        "H-infinity filter: H2 norm of the design (from the unit white noises of its noise model to the error; with the derived noise model, the steady-state RMS error in m, velocity in m/s included); NaN for the other filters";
    HINF_CERTIFIED = 68: "hinf_certified", Output, Discrete, Boolean, 0.0,
        "H-infinity filter: true while the designed, certified gain runs (after the hand-over of hinf_acquisition, or always without it); false while acquiring and for the other filters";
    AQ_LAW = 69: "aq_law", Parameter, Fixed, Code(&AQ_LAW_TYPE), 2.0,
        "AQUKF (filter 3): adaptation law of the velocity process noise (1 window: paper 001 at every update; 2 gated: only while the windowed NIS exceeds its chi-square bound)";
    AQ_GATE_WINDOW = 70: "aq_gate_window", Parameter, Fixed, Integer, 10.0,
        "AQUKF, gated law: number of measurement updates in the windowed NIS (1..128)";
    AQ_GATE_QUANTILE = 71: "aq_gate_quantile", Parameter, Fixed, Real(""), 0.999,
        "AQUKF, gated law: the gate opens when the windowed NIS exceeds its chi-square quantile at this probability (in (0, 1))";
    IMM_MODES = 72: "imm_modes", Parameter, Fixed, Integer, 3.0,
        "IMM (filter 10): number of modes (2 or 3)";
    IMM_ACCEL_PSD_1 = 73: "imm_accel_psd_1", Parameter, Fixed, Real("m2/s3"), 0.0,
        "IMM: white-acceleration density added to the process noise in mode 1 (the quiet mode; >= 0)";
    IMM_ACCEL_PSD_2 = 74: "imm_accel_psd_2", Parameter, Fixed, Real("m2/s3"), 1e-6,
        "IMM: white-acceleration density added to the process noise in mode 2 (>= 0)";
    IMM_ACCEL_PSD_3 = 75: "imm_accel_psd_3", Parameter, Fixed, Real("m2/s3"), 1e-3,
        "IMM: white-acceleration density added to the process noise in mode 3 (>= 0; unused with 2 modes)";
    IMM_P_STAY_1 = 76: "imm_p_stay_1", Parameter, Fixed, Real(""), 0.99999,
        "IMM: probability of staying in mode 1 over one second (in (0, 1))";
    IMM_P_STAY_2 = 77: "imm_p_stay_2", Parameter, Fixed, Real(""), 0.9,
        "IMM: probability of staying in mode 2 over one second (in (0, 1))";
    IMM_P_STAY_3 = 78: "imm_p_stay_3", Parameter, Fixed, Real(""), 0.9,
        "IMM: probability of staying in mode 3 over one second (in (0, 1))";
    IMM_MU_1 = 79: "imm_mu_1", Output, Continuous, Real(""), 0.0,
        "IMM: probability of mode 1 after the last step; NaN for the other filters";
    IMM_MU_2 = 80: "imm_mu_2", Output, Continuous, Real(""), 0.0,
        "IMM: probability of mode 2 after the last step; NaN for the other filters";
    IMM_MU_3 = 81: "imm_mu_3", Output, Continuous, Real(""), 0.0,
        "IMM: probability of mode 3 after the last step; NaN with 2 modes and for the other filters";
    PF_MOVE = 82: "pf_move", Parameter, Fixed, Boolean, 1.0,
        "Particle filters (codes 4-8): move the particles after every update with Metropolis-Hastings steps that leave the posterior invariant (as accurate as the EKF on Gaussian noise, also with small process noise); false: the papers' literal filters (paper 000's SIR, plain RPF, van der Merwe's UPF), which degenerate with small process noise";
    PF_THREADS = 83: "pf_threads", Parameter, Fixed, Integer, 0.0,
        "Particle filters: worker threads of the particle loops from 32768 particles on (0: one per core; 1: the calling thread; <= 1024); results do not depend on it";
}

/// Number of variables.
pub const N_VARS: usize = 84;

/// The definition for a value reference, if it exists.
pub fn lookup(vr: u32) -> Option<&'static VarDef> {
    VARIABLES.get(vr as usize)
}

/// Check a variable table: value reference = index, unique names, declared units, start
/// values of code parameters in their list (used by each model's tests; codes need not be
/// contiguous: `hinf_design` has 1 and 3).
#[cfg(test)]
pub(crate) fn check_table(vars: &[VarDef]) {
    for (i, v) in vars.iter().enumerate() {
        assert_eq!(v.vr as usize, i, "{}", v.name);
        assert!(vars.iter().filter(|w| w.name == v.name).count() == 1);
        if let VarType::Real(u) = v.ty {
            assert!(
                u.is_empty() || UNITS.iter().any(|(n, _)| *n == u),
                "unit {u}"
            );
        }
        if let VarType::Code(t) = v.ty {
            assert!(t.item(v.start).is_some(), "{}", v.name);
        }
        // outputs change only in fmi2DoStep; inputs need a start value
        if v.causality == Causality::Parameter {
            assert_eq!(v.variability, Variability::Fixed, "{}", v.name);
        }
    }
    assert!(
        vars.iter()
            .any(|v| v.name == "fmi_status" && v.causality == Causality::Output),
        "every model publishes fmi_status"
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use relnav_core::nav::NavConfig;

    #[test]
    fn table_is_dense_and_unique() {
        check_table(VARIABLES);
        assert_eq!(VARIABLES.len(), N_VARS);
        for (i, v) in VARIABLES.iter().enumerate() {
            assert_eq!(v.vr as usize, i, "{}", v.name);
            assert!(VARIABLES.iter().filter(|w| w.name == v.name).count() == 1);
            if let VarType::Real(u) = v.ty {
                assert!(
                    u.is_empty() || UNITS.iter().any(|(n, _)| *n == u),
                    "unit {u}"
                );
            }
            if let VarType::Code(t) = v.ty {
                assert!(t.item(v.start).is_some(), "{}", v.name);
                // ascending, distinct codes: min/max in the XML bound them; a gap
                // (hinf_design has no code 2, the paper form) is refused at fmi2Set*
                assert!(t.items.windows(2).all(|w| w[0].1 < w[1].1), "{}", t.name);
            }
        }
    }

    /// The FMU's start values are the library's defaults (paper 000's example).
    #[test]
    fn start_values_match_library_defaults() {
        let c = NavConfig::default();
        let s = |vr: u32| VARIABLES[vr as usize].start;
        assert_eq!(s(vr::FILTER), c.filter as i32 as f64);
        assert_eq!(s(vr::FRAME), c.frame.code() as f64);
        assert_eq!(s(vr::DISCRETIZATION), c.discretization as i32 as f64);
        assert_eq!(s(vr::MEAN_MOTION), c.mean_motion);
        assert_eq!(s(vr::CHASER_MASS), c.chaser_mass);
        assert_eq!(s(vr::SIGMA_RANGE), c.sigma_range);
        assert_eq!(s(vr::SIGMA_ANGLE), c.sigma_angle);
        let x0 = [vr::X0, vr::Y0, vr::Z0, vr::VX0, vr::VY0, vr::VZ0].map(s);
        assert_eq!(x0, c.x0);
        assert_eq!(s(vr::SIGMA_POS0), c.sigma_pos0);
        assert_eq!(s(vr::SIGMA_VEL0), c.sigma_vel0);
        assert_eq!(s(vr::ACCEL_PSD), c.accel_psd);
        assert_eq!([vr::Q_POS_X, vr::Q_POS_Y, vr::Q_POS_Z].map(s), c.q_pos);
        assert_eq!([vr::Q_VEL_X, vr::Q_VEL_Y, vr::Q_VEL_Z].map(s), c.q_vel);
        assert_eq!(
            [vr::UKF_ALPHA, vr::UKF_BETA, vr::UKF_KAPPA].map(s),
            [c.ukf_alpha, c.ukf_beta, c.ukf_kappa]
        );
        assert_eq!(s(vr::SEED), c.seed as f64);
        assert_eq!(s(vr::PARTICLES), c.particles as f64);
        assert_eq!(s(vr::RESAMPLER), c.resampler as i32 as f64);
        assert_eq!(s(vr::RESAMPLE_THRESHOLD), c.resample_threshold);
        assert_eq!(s(vr::NOISE_MODEL), c.noise_model as i32 as f64);
        assert_eq!(s(vr::NOISE_ZETA), c.noise_zeta);
        assert_eq!(s(vr::NOISE_SCALE), c.noise_scale);
        assert_eq!(s(vr::NOISE_DOF), c.noise_dof);
        assert_eq!(s(vr::WINDOW), c.window as f64);
        assert_eq!(s(vr::HINF_PERIOD), c.hinf_period);
        assert_eq!(s(vr::HINF_DELTA_BAR), c.hinf_delta_bar);
        assert_eq!(s(vr::HINF_B_POS), c.hinf_b_pos);
        assert_eq!(s(vr::HINF_B_VEL), c.hinf_b_vel);
        assert_eq!(s(vr::HINF_D), c.hinf_d);
        assert_eq!(s(vr::HINF_DESIGN), c.hinf_design as i32 as f64);
        assert_eq!(s(vr::HINF_GAMMA_FACTOR), c.hinf_gamma_factor);
        assert_eq!(
            s(vr::HINF_ACQUISITION),
            f64::from(u8::from(c.hinf_acquisition))
        );
        assert_eq!(s(vr::AQ_LAW), c.aq_law as i32 as f64);
        assert_eq!(s(vr::AQ_GATE_WINDOW), c.aq_gate_window as f64);
        assert_eq!(s(vr::AQ_GATE_QUANTILE), c.aq_gate_quantile);
        assert_eq!(s(vr::IMM_MODES), c.imm_modes as f64);
        assert_eq!(
            [
                vr::IMM_ACCEL_PSD_1,
                vr::IMM_ACCEL_PSD_2,
                vr::IMM_ACCEL_PSD_3
            ]
            .map(s),
            c.imm_accel_psd
        );
        assert_eq!(
            [vr::IMM_P_STAY_1, vr::IMM_P_STAY_2, vr::IMM_P_STAY_3].map(s),
            c.imm_p_stay
        );
        assert_eq!(s(vr::PF_MOVE), f64::from(u8::from(c.pf_move)));
        assert_eq!(s(vr::PF_THREADS), c.pf_threads as f64);
    }

    /// The code lists carry the library's codes and names.
    #[test]
    fn code_lists_match_library_codes() {
        use relnav_core::estimators::pf::resample::Resampler;
        use relnav_core::nav::{FilterKind, NoiseKind};
        let names = |t: &EnumType| -> Vec<(i32, &str)> {
            t.items.iter().map(|(n, v, _)| (*v, *n)).collect()
        };
        let filters: Vec<(i32, &str)> = FilterKind::ALL
            .iter()
            .map(|k| (*k as i32, k.name()))
            .collect();
        assert_eq!(names(&FILTER_TYPE), filters);
        let resamplers: Vec<(i32, &str)> = Resampler::ALL
            .iter()
            .map(|k| (*k as i32, k.name()))
            .collect();
        assert_eq!(names(&RESAMPLER_TYPE), resamplers);
        let noises: Vec<(i32, &str)> = NoiseKind::ALL
            .iter()
            .map(|k| (*k as i32, k.name()))
            .collect();
        assert_eq!(names(&NOISE_MODEL_TYPE), noises);
        let designs: Vec<(i32, &str)> = relnav_core::nav::HinfDesignKind::ALL
            .iter()
            .map(|k| (*k as i32, k.name()))
            .collect();
        assert_eq!(names(&HINF_DESIGN_TYPE), designs);
        let laws: Vec<(i32, &str)> = relnav_core::estimators::AdaptationLaw::ALL
            .iter()
            .map(|k| (*k as i32, k.name()))
            .collect();
        assert_eq!(names(&AQ_LAW_TYPE), laws);
    }
}
