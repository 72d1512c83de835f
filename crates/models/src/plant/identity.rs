//! `relnav_plant.fmu`'s identity: model identifier, description, default experiment, and
//! its variable table (value reference = index) with its own code list.

use crate::codes::{FRAME_TYPE, NOISE_MODEL_TYPE};
use relnav_fmi::model::{DefaultExperiment, Generated, ModelInfo};
use relnav_fmi::variables::VarType;
use std::f64::consts::PI;

/// `truth_model` parameter values (the codes of [`relnav_core::plant::TruthModel`]).
pub use relnav_core::plant::TRUTH_MODEL_CODES as TRUTH_MODEL_TYPE;

use VarType::{Boolean, Code, Integer, Real};

relnav_fmi::variables! {
    FRAME = 0: "frame", Parameter, Fixed, Code(&FRAME_TYPE), 2.0,
        "Hill-frame convention of the thrust, the true state and the measurement angles (as relnav's frame)";
    TRUTH_MODEL = 1: "truth_model", Parameter, Fixed, Code(&TRUTH_MODEL_TYPE), 1.0,
        "Truth of the relative motion";
    MEAN_MOTION = 2: "mean_motion", Parameter, Fixed, Real("rad/s"), 2.0 * PI / 7200.0,
        "Mean motion of the target's circular orbit (1e-9..0.1)";
    CHASER_MASS = 3: "chaser_mass", Parameter, Fixed, Real("kg"), 1000.0,
        "Chaser mass: thrust / mass = acceleration (> 0)";
    TRUE_X0 = 4: "true_x0", Parameter, Fixed, Real("m"), 400.0, "True initial relative position x";
    TRUE_Y0 = 5: "true_y0", Parameter, Fixed, Real("m"), 500.0, "True initial relative position y";
    TRUE_Z0 = 6: "true_z0", Parameter, Fixed, Real("m"), 200.0, "True initial relative position z";
    TRUE_VX0 = 7: "true_vx0", Parameter, Fixed, Real("m/s"), 0.0, "True initial relative velocity vx";
    TRUE_VY0 = 8: "true_vy0", Parameter, Fixed, Real("m/s"), 0.0, "True initial relative velocity vy";
    TRUE_VZ0 = 9: "true_vz0", Parameter, Fixed, Real("m/s"), 0.0, "True initial relative velocity vz";
    INCLINATION = 10: "inclination", Parameter, Fixed, Real("rad"), 51.6 * PI / 180.0,
        "truth_model two_body_j2: inclination of the target's orbit (in [0, pi]; the target starts at its ascending node)";
    J2_SUBSTEP = 11: "j2_substep", Parameter, Fixed, Real("s"), 1.0,
        "truth_model two_body_j2: longest integration substep (a step h takes round(h / j2_substep), at least 1, equal substeps; > 0)";
    MEASUREMENT_PERIOD = 12: "measurement_period", Parameter, Fixed, Real("s"), 1.0,
        "Time between measurements from the start time; a measurement is taken at the first communication point at or after its due time (> 0)";
    SIGMA_RANGE = 13: "sigma_range", Parameter, Fixed, Real("m"), 0.5,
        "Range measurement noise, 1 sigma of the Gaussian (nominal sigma of the other noise models; > 0)";
    SIGMA_ANGLE = 14: "sigma_angle", Parameter, Fixed, Real("rad"), 0.01 * PI / 180.0,
        "Azimuth and elevation measurement noise, 1 sigma of the Gaussian (nominal sigma of the other noise models; > 0)";
    NOISE_MODEL = 15: "noise_model", Parameter, Fixed, Code(&NOISE_MODEL_TYPE), 1.0,
        "Measurement-noise density scaled by sigma_range and sigma_angle (as relnav's noise_model)";
    NOISE_ZETA = 16: "noise_zeta", Parameter, Fixed, Real(""), 0.2,
        "Mixture noise: weight of the wide component (in [0, 1))";
    NOISE_SCALE = 17: "noise_scale", Parameter, Fixed, Real(""), 10.0,
        "Mixture noise: sigma of the wide component over the nominal sigma (>= 1)";
    NOISE_DOF = 18: "noise_dof", Parameter, Fixed, Real(""), 4.0,
        "Student-t noise: degrees of freedom (> 2)";
    DROPOUT_PROBABILITY = 19: "dropout_probability", Parameter, Fixed, Real(""), 0.0,
        "Probability that a due measurement is lost (in [0, 1]; one uniform draw per due measurement)";
    DROPOUT_START = 20: "dropout_start", Parameter, Fixed, Real("s"), 0.0,
        "Start of a window in which every measurement is lost (none when dropout_stop <= dropout_start)";
    DROPOUT_STOP = 21: "dropout_stop", Parameter, Fixed, Real("s"), 0.0,
        "End of the dropout window (excluded)";
    SEED = 22: "seed", Parameter, Fixed, Integer, 0.0,
        "Seed of the measurement noise and dropout draws (identical seeds give identical outputs)";
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
}

/// relnav_plant.fmu's static description.
pub static INFO: ModelInfo = ModelInfo {
    model_identifier: "relnav_plant",
    description: "Truth plant of relnav's system kit: the chaser's true motion relative to a \
target on a circular orbit (exact Clohessy-Wiltshire, or two-body + J2 of both spacecraft) \
driven by its thrust, and a radio or lidar sensor measuring range, azimuth and elevation \
every measurement_period with Gaussian, contaminated-Gaussian or Student-t noise and \
dropouts; outputs the measurement for relnav.fmu and the true state",
    variables: VARIABLES,
    default_experiment: DefaultExperiment {
        start: 0.0,
        stop: 600.0,
        step: 1.0,
    },
    fmi_status: vr::FMI_STATUS,
    state_code: Some(vr::TRUTH_MODEL),
    state_name: "plant",
    generated: Generated::new(),
};
