//! `relnav_plant.fmu`'s identity: model identifier, description, default experiment, and
//! its variable table (value reference = index): the parameters' rows from relnav-core's
//! declarations ([`relnav_core::plant::PLANT_PARAMS`]), the inputs' and outputs' here.

use relnav_fmi::model::{ArrayDef, DefaultExperiment, Generated, ModelInfo};
use relnav_fmi::variables::VarDef;
use std::sync::LazyLock;

/// `truth_model` parameter values (the codes of [`relnav_core::plant::TruthModel`]).
pub use relnav_core::plant::TRUTH_MODEL_CODES as TRUTH_MODEL_TYPE;

/// The inputs and outputs (the parameters come from relnav-core's declarations).
mod io {
    use relnav_fmi::variables::VarType::*;

    relnav_fmi::variables! {
        THRUST_X = 23: "thrust_x", Input, Discrete, Real("N"), 0.0, "Thrust on the chaser along x, held over the step";
        THRUST_Y = 24: "thrust_y", Input, Discrete, Real("N"), 0.0, "Thrust on the chaser along y, held over the step";
        THRUST_Z = 25: "thrust_z", Input, Discrete, Real("N"), 0.0, "Thrust on the chaser along z, held over the step";
        RANGE = 26: "range", Output, Discrete, Real("m"), 0.0,
        "Measured range at the last measurement time (with noise)";
        AZIMUTH = 27: "azimuth", Output, Discrete, Real("rad"), 0.0,
        "Measured azimuth atan2(y, x) in [0, 2 pi) at the last measurement time";
        ELEVATION = 28: "elevation", Output, Discrete, Real("rad"), 0.0,
        "Measured elevation asin(z / range) at the last measurement time";
        MEASUREMENT_VALID = 29: "measurement_valid", Output, Discrete, Boolean, 0.0,
        "True when range/azimuth/elevation hold a measurement taken at this communication point that was not lost (connect to relnav's measurement_valid)";
        TRUE_X = 30: "true_x", Output, Continuous, Real("m"), 0.0, "True relative position x";
        TRUE_Y = 31: "true_y", Output, Continuous, Real("m"), 0.0, "True relative position y";
        TRUE_Z = 32: "true_z", Output, Continuous, Real("m"), 0.0, "True relative position z";
        TRUE_VX = 33: "true_vx", Output, Continuous, Real("m/s"), 0.0, "True relative velocity vx";
        TRUE_VY = 34: "true_vy", Output, Continuous, Real("m/s"), 0.0, "True relative velocity vy";
        TRUE_VZ = 35: "true_vz", Output, Continuous, Real("m/s"), 0.0, "True relative velocity vz";
        FMI_STATUS = 36: "fmi_status", Output, Discrete, Integer, 0.0,
        "Worst fmi2Status this instance has returned since fmi2Instantiate or fmi2Reset: 0 fmi2OK, 3 fmi2Error, 4 fmi2Fatal (the reason is logged under logStatusError)";
        CAMERA_AZIMUTH = 50: "camera_azimuth", Output, Discrete, Real("rad"), 0.0,
        "Camera line-of-sight azimuth atan2(y, x) in [0, 2 pi) at the last camera time (with noise; connect to relnav's camera_azimuth)";
        CAMERA_ELEVATION = 51: "camera_elevation", Output, Discrete, Real("rad"), 0.0,
        "Camera line-of-sight elevation in [-pi/2, pi/2] at the last camera time (with noise)";
        CAMERA_VALID = 52: "camera_valid", Output, Discrete, Boolean, 0.0,
        "True when camera_azimuth/camera_elevation hold a reading taken at this communication point with the true range inside [camera_min_range, camera_max_range) (connect to relnav's camera_valid)";
        GNSS_X = 53: "gnss_x", Output, Discrete, Real("m"), 0.0, "Relative GNSS position x at the last GNSS time (with noise)";
        GNSS_Y = 54: "gnss_y", Output, Discrete, Real("m"), 0.0, "Relative GNSS position y at the last GNSS time (with noise)";
        GNSS_Z = 55: "gnss_z", Output, Discrete, Real("m"), 0.0, "Relative GNSS position z at the last GNSS time (with noise)";
        GNSS_VX = 56: "gnss_vx", Output, Discrete, Real("m/s"), 0.0, "Relative GNSS velocity vx at the last GNSS time (with noise)";
        GNSS_VY = 57: "gnss_vy", Output, Discrete, Real("m/s"), 0.0, "Relative GNSS velocity vy at the last GNSS time (with noise)";
        GNSS_VZ = 58: "gnss_vz", Output, Discrete, Real("m/s"), 0.0, "Relative GNSS velocity vz at the last GNSS time (with noise)";
        GNSS_VALID = 59: "gnss_valid", Output, Discrete, Boolean, 0.0,
        "True when gnss_x/y/z hold a reading taken at this communication point outside the GNSS outage (connect to relnav's gnss_valid)";
        GNSS_VELOCITY_VALID = 60: "gnss_velocity_valid", Output, Discrete, Boolean, 0.0,
        "True when gnss_vx/vy/vz hold such a reading (equal to gnss_valid: position and velocity come together; connect to relnav's gnss_velocity_valid)";
    }
}

/// Value references by name: the inputs' and outputs' from their rows, the parameters'
/// from relnav-core's declarations.
pub mod vr {
    pub use super::io::vr::*;

    crate::param_vrs! {
        relnav_core::plant::PLANT_PARAMS;
        FRAME = "frame",
        TRUTH_MODEL = "truth_model",
        MEAN_MOTION = "mean_motion",
        CHASER_MASS = "chaser_mass",
        TRUE_X0 = "true_x0",
        TRUE_Y0 = "true_y0",
        TRUE_Z0 = "true_z0",
        TRUE_VX0 = "true_vx0",
        TRUE_VY0 = "true_vy0",
        TRUE_VZ0 = "true_vz0",
        INCLINATION = "inclination",
        J2_SUBSTEP = "j2_substep",
        MEASUREMENT_PERIOD = "measurement_period",
        SIGMA_RANGE = "sigma_range",
        SIGMA_ANGLE = "sigma_angle",
        NOISE_MODEL = "noise_model",
        NOISE_ZETA = "noise_zeta",
        NOISE_SCALE = "noise_scale",
        NOISE_DOF = "noise_dof",
        DROPOUT_PROBABILITY = "dropout_probability",
        DROPOUT_START = "dropout_start",
        DROPOUT_STOP = "dropout_stop",
        SEED = "seed",
        ECCENTRICITY = "eccentricity",
        TRUE_ANOMALY0 = "true_anomaly0",
        RADIO_MIN_RANGE = "radio_min_range",
        RADIO_MAX_RANGE = "radio_max_range",
        CAMERA_PERIOD = "camera_period",
        SIGMA_CAMERA = "sigma_camera",
        CAMERA_MIN_RANGE = "camera_min_range",
        CAMERA_MAX_RANGE = "camera_max_range",
        GNSS_PERIOD = "gnss_period",
        SIGMA_GNSS = "sigma_gnss",
        SIGMA_GNSS_VELOCITY = "sigma_gnss_velocity",
        GNSS_OUTAGE_START = "gnss_outage_start",
        GNSS_OUTAGE_STOP = "gnss_outage_stop",
    }
}

/// The inputs' and outputs' rows alone.
pub fn io_variables() -> &'static [VarDef] {
    io::VARIABLES
}

/// Number of variables.
pub const N_VARS: usize = 69;

/// Every variable; the value reference is the index.
pub static VARIABLES: LazyLock<Vec<VarDef>> =
    LazyLock::new(|| crate::params::table(relnav_core::plant::PLANT_PARAMS, io::VARIABLES, N_VARS));

/// The vectors relnav_plant3.fmu publishes as arrays (FMI 3.0; relnav_plant.fmu keeps the
/// scalars): the names relnav3.fmu's inputs have, so that a master connects them directly.
static ARRAYS: &[ArrayDef] = &[
    ArrayDef {
        name: "thrust",
        elements: &[io::vr::THRUST_X, io::vr::THRUST_Y, io::vr::THRUST_Z],
        description: "Thrust on the chaser (x, y, z), held over the step",
    },
    ArrayDef {
        name: "measurement",
        elements: &[io::vr::RANGE, io::vr::AZIMUTH, io::vr::ELEVATION],
        description:
            "Measured range, azimuth and elevation at the last measurement time (held between)",
    },
    ArrayDef {
        name: "camera",
        elements: &[io::vr::CAMERA_AZIMUTH, io::vr::CAMERA_ELEVATION],
        description: "Camera line of sight: azimuth and elevation at the last camera time",
    },
    ArrayDef {
        name: "gnss_position",
        elements: &[io::vr::GNSS_X, io::vr::GNSS_Y, io::vr::GNSS_Z],
        description: "Relative GNSS position at the last GNSS time",
    },
    ArrayDef {
        name: "gnss_velocity",
        elements: &[io::vr::GNSS_VX, io::vr::GNSS_VY, io::vr::GNSS_VZ],
        description: "Relative GNSS velocity at the last GNSS time",
    },
    ArrayDef {
        name: "true_position",
        elements: &[io::vr::TRUE_X, io::vr::TRUE_Y, io::vr::TRUE_Z],
        description: "True relative position (x, y, z)",
    },
    ArrayDef {
        name: "true_velocity",
        elements: &[io::vr::TRUE_VX, io::vr::TRUE_VY, io::vr::TRUE_VZ],
        description: "True relative velocity (vx, vy, vz)",
    },
];

/// relnav_plant.fmu's static description.
pub static INFO: LazyLock<ModelInfo> = LazyLock::new(|| ModelInfo {
    model_identifier: "relnav_plant",
    description: "Truth plant of relnav's system kit: the chaser's true motion relative to a \
target on a circular orbit (exact Clohessy-Wiltshire, or two-body + J2 of both spacecraft) \
driven by its thrust, and a radio or lidar sensor measuring range, azimuth and elevation \
every measurement_period with Gaussian, contaminated-Gaussian or Student-t noise and \
dropouts, a camera (line of sight) and relative GNSS (position and velocity) each at its own \
period with Gaussian noise, each sensor available over its range interval or outside its \
outage; outputs the readings for relnav.fmu and the true state",
    variables: VARIABLES.as_slice(),
    default_experiment: DefaultExperiment {
        start: 0.0,
        stop: 600.0,
        step: 1.0,
    },
    fmi_status: vr::FMI_STATUS,
    state_code: Some(vr::TRUTH_MODEL),
    state_name: "plant",
    arrays: ARRAYS,
    has_event_mode: false,
    computed: &[],
    generated: Generated::new(),
});
