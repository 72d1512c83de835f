//! relnav.fmu's identity: model identifier, description, default experiment, and the one
//! table of its variables. The parameters' rows are relnav-core's parameter declarations
//! ([`relnav_core::nav::PARAMS`]: name, value reference, unit, default, description, code
//! list), the inputs' and outputs' rows are declared here; together they generate
//! `modelDescription.xml` and drive the get/set dispatch (value reference = index in
//! [`VARIABLES`], checked by a test). The Python package takes its keyword arguments from
//! the same table.

use relnav_core::nav::PARAMS;
use relnav_fmi::model::{ArrayDef, ComputedDef, DefaultExperiment, Generated, ModelInfo};
use relnav_fmi::variables::VarDef;
use std::sync::LazyLock;

/// relnav.fmu's model identifier (and binary name).
pub const MODEL_IDENTIFIER: &str = "relnav";

/// relnav.fmu's `description` attribute.
pub const MODEL_DESCRIPTION: &str =
    "Spacecraft relative navigation near a target on a circular orbit \
(Clohessy-Wiltshire): estimate of the chaser's relative position and velocity, with 1-sigma \
uncertainty, from its thrust and range/azimuth/elevation measurements, by a Kalman filter \
(EKF, UKF, or the sliding-window adaptive AQUKF), a particle filter (SIR, regularised, \
unscented, genetic or cloud-genetic) or the robust H-infinity filter designed by an LMI";

/// The estimate outputs in table order: the state `x .. vz`, then its 1-sigma
/// `sigma_x .. sigma_vz`.
pub const ESTIMATE: [u32; 12] = [
    vr::X,
    vr::Y,
    vr::Z,
    vr::VX,
    vr::VY,
    vr::VZ,
    vr::SIGMA_X,
    vr::SIGMA_Y,
    vr::SIGMA_Z,
    vr::SIGMA_VX,
    vr::SIGMA_VY,
    vr::SIGMA_VZ,
];

/// The vectors relnav3.fmu publishes as arrays (FMI 3.0; relnav.fmu keeps the scalars).
static ARRAYS: &[ArrayDef] = &[
    ArrayDef {
        name: "thrust",
        elements: &[vr::THRUST_X, vr::THRUST_Y, vr::THRUST_Z],
        description: "Thrust on the chaser (x, y, z), held over the step",
    },
    ArrayDef {
        name: "measurement",
        elements: &[vr::RANGE, vr::AZIMUTH, vr::ELEVATION],
        description: "Measured range, azimuth atan2(y, x) in [0, 2 pi) and elevation asin(z / range), taken at the step's start time",
    },
    ArrayDef {
        name: "camera",
        elements: &[vr::CAMERA_AZIMUTH, vr::CAMERA_ELEVATION],
        description: "Camera line of sight: azimuth and elevation (the radio's convention), taken at the step's start time",
    },
    ArrayDef {
        name: "gnss_position",
        elements: &[vr::GNSS_X, vr::GNSS_Y, vr::GNSS_Z],
        description: "Relative GNSS: relative position in the I/O frame, taken at the step's start time",
    },
    ArrayDef {
        name: "gnss_velocity",
        elements: &[vr::GNSS_VX, vr::GNSS_VY, vr::GNSS_VZ],
        description: "Relative GNSS: relative velocity in the I/O frame, taken at the step's start time",
    },
    ArrayDef {
        name: "position",
        elements: ESTIMATE.split_at(3).0,
        description: "Estimated relative position (x, y, z)",
    },
    ArrayDef {
        name: "velocity",
        elements: ESTIMATE.split_at(6).0.split_at(3).1,
        description: "Estimated relative velocity (vx, vy, vz)",
    },
    ArrayDef {
        name: "sigma",
        elements: ESTIMATE.split_at(6).1,
        description: "1-sigma uncertainties of x, y, z, vx, vy, vz (from the covariance)",
    },
];

/// The outputs relnav3.fmu computes beyond the table (FMI 3.0 only).
static COMPUTED: &[ComputedDef] = &[ComputedDef {
    name: "covariance",
    dims: &[6, 6],
    unit: "",
    description: "Covariance of the estimate (x, y, z, vx, vy, vz) in the I/O frame, row-major (m2, m2/s, m2/s2): its diagonal is sigma squared; NaN for the H-infinity filter, which has none",
}];

/// relnav.fmu's static description.
pub static INFO: LazyLock<ModelInfo> = LazyLock::new(|| ModelInfo {
    model_identifier: MODEL_IDENTIFIER,
    description: MODEL_DESCRIPTION,
    variables: VARIABLES.as_slice(),
    default_experiment: DefaultExperiment {
        start: 0.0,
        stop: 600.0,
        step: 1.0,
    },
    fmi_status: vr::FMI_STATUS,
    state_code: Some(vr::FILTER),
    state_name: "estimator",
    arrays: ARRAYS,
    has_event_mode: true,
    computed: COMPUTED,
    generated: Generated::new(),
});

/// The inputs and outputs (the parameters come from relnav-core's declarations).
mod io {
    use relnav_fmi::variables::VarType::{Boolean, Integer, Real};

    relnav_fmi::variables! {
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
        ESS = 52: "ess", Output, Continuous, Real(""), 0.0,
        "Effective sample size 1 / sum w^2 of a particle filter after the last measurement update, before resampling (in [1, particles]); NaN for the Kalman filters";
        Q_VV_X = 54: "q_vv_x", Output, Continuous, Real("m2/s3"), 0.0,
        "AQUKF: current adaptive velocity process-noise density along x (I/O frame; q_vv = diag(Q_vv) / T of paper 001); NaN for the other filters";
        Q_VV_Y = 55: "q_vv_y", Output, Continuous, Real("m2/s3"), 0.0,
        "AQUKF: current adaptive velocity process-noise density along y; NaN for the other filters";
        Q_VV_Z = 56: "q_vv_z", Output, Continuous, Real("m2/s3"), 0.0,
        "AQUKF: current adaptive velocity process-noise density along z; NaN for the other filters";
        HINF_GAMMA = 62: "hinf_gamma", Output, Continuous, Real(""), 0.0,
        "H-infinity filter: the design's certified bound gamma on the worst-case gain from the scaled noises to the estimation error; NaN for the other filters";
        FMI_STATUS = 63: "fmi_status", Output, Discrete, Integer, 0.0,
        "Worst fmi2Status this instance has returned since fmi2Instantiate or fmi2Reset: 0 fmi2OK, 3 fmi2Error, 4 fmi2Fatal (the reason is logged under logStatusError). For masters that ignore fmi2Error (Ecos): 3 means a call was refused, and the other outputs no longer advance";
        HINF_H2_NORM = 67: "hinf_h2_norm", Output, Continuous, Real(""), 0.0,
        "H-infinity filter: H2 norm of the design (from the unit white noises of its noise model to the error; with the derived noise model, the steady-state RMS error in m, velocity in m/s included); NaN for the other filters";
        HINF_CERTIFIED = 68: "hinf_certified", Output, Discrete, Boolean, 0.0,
        "H-infinity filter: true while the designed, certified gain runs (after the hand-over of hinf_acquisition, or always without it); false while acquiring and for the other filters";
        IMM_MU_1 = 79: "imm_mu_1", Output, Continuous, Real(""), 0.0,
        "IMM: probability of mode 1 after the last step; NaN for the other filters";
        IMM_MU_2 = 80: "imm_mu_2", Output, Continuous, Real(""), 0.0,
        "IMM: probability of mode 2 after the last step; NaN for the other filters";
        IMM_MU_3 = 81: "imm_mu_3", Output, Continuous, Real(""), 0.0,
        "IMM: probability of mode 3 after the last step; NaN with 2 modes and for the other filters";
        CAMERA_AZIMUTH = 89: "camera_azimuth", Input, Discrete, Real("rad"), 0.0,
        "Camera line of sight: azimuth atan2(y, x) of the relative position in the I/O frame (the radio's convention), taken at the step's start time";
        CAMERA_ELEVATION = 90: "camera_elevation", Input, Discrete, Real("rad"), 0.0,
        "Camera line of sight: elevation asin(z / range) in [-pi/2, pi/2], taken at the step's start time";
        CAMERA_VALID = 91: "camera_valid", Input, Discrete, Boolean, 0.0,
        "True when camera_azimuth/camera_elevation hold a fresh reading taken at the step's start time (applied after the radio's)";
        GNSS_X = 92: "gnss_x", Input, Discrete, Real("m"), 0.0, "Relative GNSS: relative position x in the I/O frame, taken at the step's start time";
        GNSS_Y = 93: "gnss_y", Input, Discrete, Real("m"), 0.0, "Relative GNSS: relative position y in the I/O frame";
        GNSS_Z = 94: "gnss_z", Input, Discrete, Real("m"), 0.0, "Relative GNSS: relative position z in the I/O frame";
        GNSS_VALID = 95: "gnss_valid", Input, Discrete, Boolean, 0.0,
        "True when gnss_x/y/z hold a fresh reading taken at the step's start time (applied after the camera's)";
        GNSS_VX = 96: "gnss_vx", Input, Discrete, Real("m/s"), 0.0, "Relative GNSS: relative velocity vx in the I/O frame, taken at the step's start time";
        GNSS_VY = 97: "gnss_vy", Input, Discrete, Real("m/s"), 0.0, "Relative GNSS: relative velocity vy in the I/O frame";
        GNSS_VZ = 98: "gnss_vz", Input, Discrete, Real("m/s"), 0.0, "Relative GNSS: relative velocity vz in the I/O frame";
        GNSS_VELOCITY_VALID = 99: "gnss_velocity_valid", Input, Discrete, Boolean, 0.0,
        "True when gnss_vx/vy/vz hold a fresh reading taken at the step's start time (applied last)";
        RANGE_SIGMA = 100: "range_sigma", Output, Continuous, Real("m"), 0.0,
        "1-sigma of the estimated range (the covariance along the estimated line of sight): shows when an angles-only range becomes observable; NaN for the H-infinity filter";
        RADIO_NIS = 101: "radio_nis", Output, Continuous, Real(""), 0.0,
        "Normalised innovation squared of the last step's radio update; NaN when the radio gave no reading in that step, and for point particles (pf_prior = 1) and the H-infinity filter";
        CAMERA_NIS = 102: "camera_nis", Output, Continuous, Real(""), 0.0,
        "Normalised innovation squared of the last step's camera update; NaN when the camera gave no reading in that step, and for point particles (pf_prior = 1) and the H-infinity filter";
        GNSS_NIS = 103: "gnss_nis", Output, Continuous, Real(""), 0.0,
        "Normalised innovation squared of the last step's relative-GNSS position update; NaN when it gave no reading in that step, and for point particles (pf_prior = 1) and the H-infinity filter";
        GNSS_VELOCITY_NIS = 104: "gnss_velocity_nis", Output, Continuous, Real(""), 0.0,
        "Normalised innovation squared of the last step's relative-GNSS velocity update; NaN when it gave no reading in that step, and for point particles (pf_prior = 1) and the H-infinity filter";
        PF_ACCEPTANCE = 116: "pf_acceptance", Output, Continuous, Real(""), 0.0,
        "Particle filters: fraction of the Metropolis-Hastings moves (pf_move rejuvenation, RPF jitter, genetic operators) accepted in the last step, how far the particles moved from their proposal; NaN when that step made no move, and for the other filters";
    }
}

/// Value references by name: the inputs' and outputs' from their rows, the parameters'
/// from relnav-core's declarations (a name that is not declared fails to compile).
pub mod vr {
    pub use super::io::vr::*;

    relnav_models::param_vrs! {
        relnav_core::nav::PARAMS;
        FILTER = "filter",
        FRAME = "frame",
        DISCRETIZATION = "discretization",
        MEAN_MOTION = "mean_motion",
        CHASER_MASS = "chaser_mass",
        SIGMA_RANGE = "sigma_range",
        SIGMA_ANGLE = "sigma_angle",
        X0 = "x0",
        Y0 = "y0",
        Z0 = "z0",
        VX0 = "vx0",
        VY0 = "vy0",
        VZ0 = "vz0",
        SIGMA_POS0 = "sigma_pos0",
        SIGMA_VEL0 = "sigma_vel0",
        ACCEL_PSD = "accel_psd",
        Q_POS_X = "q_pos_x",
        Q_POS_Y = "q_pos_y",
        Q_POS_Z = "q_pos_z",
        Q_VEL_X = "q_vel_x",
        Q_VEL_Y = "q_vel_y",
        Q_VEL_Z = "q_vel_z",
        UKF_ALPHA = "ukf_alpha",
        UKF_BETA = "ukf_beta",
        UKF_KAPPA = "ukf_kappa",
        SEED = "seed",
        PARTICLES = "particles",
        RESAMPLER = "resampler",
        RESAMPLE_THRESHOLD = "resample_threshold",
        NOISE_MODEL = "noise_model",
        NOISE_ZETA = "noise_zeta",
        NOISE_SCALE = "noise_scale",
        NOISE_DOF = "noise_dof",
        WINDOW = "window",
        HINF_PERIOD = "hinf_period",
        HINF_DELTA_BAR = "hinf_delta_bar",
        HINF_B_POS = "hinf_b_pos",
        HINF_B_VEL = "hinf_b_vel",
        HINF_D = "hinf_d",
        HINF_DESIGN = "hinf_design",
        HINF_GAMMA_FACTOR = "hinf_gamma_factor",
        HINF_ACQUISITION = "hinf_acquisition",
        AQ_LAW = "aq_law",
        AQ_GATE_WINDOW = "aq_gate_window",
        AQ_GATE_QUANTILE = "aq_gate_quantile",
        IMM_MODES = "imm_modes",
        IMM_ACCEL_PSD_1 = "imm_accel_psd_1",
        IMM_ACCEL_PSD_2 = "imm_accel_psd_2",
        IMM_ACCEL_PSD_3 = "imm_accel_psd_3",
        IMM_P_STAY_1 = "imm_p_stay_1",
        IMM_P_STAY_2 = "imm_p_stay_2",
        IMM_P_STAY_3 = "imm_p_stay_3",
        PF_MOVE = "pf_move",
        PF_THREADS = "pf_threads",
        ECCENTRICITY = "eccentricity",
        TRUE_ANOMALY0 = "true_anomaly0",
        RANGE_BANK = "range_bank",
        SIGMA_RANGE0 = "sigma_range0",
        PF_PRIOR = "pf_prior",
    }
}

/// The inputs' and outputs' rows alone.
pub fn io_variables() -> &'static [VarDef] {
    io::VARIABLES
}

/// Number of variables.
pub const N_VARS: usize = 118;

/// Every variable of relnav.fmu; the value reference is the index.
pub static VARIABLES: LazyLock<Vec<VarDef>> =
    LazyLock::new(|| relnav_models::params::table(PARAMS, io::VARIABLES, N_VARS));

#[cfg(test)]
mod tests {
    use super::*;
    use relnav_fmi::variables::check_table;

    /// The table is dense and checked; the inputs and outputs take no parameter's value
    /// reference; every declared parameter with a value reference is in it.
    #[test]
    fn table_is_dense_and_holds_every_declared_parameter() {
        assert_eq!(check_table(&VARIABLES), Ok(()));
        assert_eq!(relnav_fmi::fmi3::description::check_arrays(&INFO), Ok(()));
        assert_eq!(VARIABLES.len(), N_VARS);
        assert_eq!(
            relnav_models::params::check_declared(PARAMS, io_variables(), &VARIABLES),
            Ok(())
        );
        assert_eq!(vr::FILTER, 0);
        assert_eq!(vr::PF_THREADS, 83);
    }

    /// relnav.fmu's FMI 2.0 description declares every variable at its value reference and
    /// carries the GUID derived from it.
    #[test]
    fn xml_contains_every_variable_and_the_guid() {
        use relnav_fmi::fmi2::description::{guid_of, model_description_of, GENERATION_DATE};
        let (xml, guid) = (model_description_of(&INFO), guid_of(&INFO));
        assert!(xml.contains(&format!(r#"guid="{guid}""#)));
        for v in VARIABLES.iter() {
            assert!(xml.contains(&format!(r#"name="{}" valueReference="{}""#, v.name, v.vr)));
        }
        assert!(xml.contains(r#"modelIdentifier="relnav""#));
        assert!(xml.contains("canRunAsynchronuously"));
        assert_eq!(guid.len(), 38);
        assert!(xml.contains(&format!(r#"generationDateAndTime="{GENERATION_DATE}""#)));
    }
}
