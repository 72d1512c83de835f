//! `relnav_guidance.fmu`'s identity: model identifier, description, default experiment,
//! and its variable table (value reference = index).

use crate::codes::FRAME_TYPE;
use relnav_fmi::model::{DefaultExperiment, Generated, ModelInfo};
use relnav_fmi::variables::VarType;
use std::f64::consts::PI;

use VarType::{Code, Integer, Real};

relnav_fmi::variables! {
    FRAME = 0: "frame", Parameter, Fixed, Code(&FRAME_TYPE), 2.0,
        "Hill-frame convention of the estimate, the hold point and the thrust (as relnav's frame)";
    MEAN_MOTION = 1: "mean_motion", Parameter, Fixed, Real("rad/s"), 2.0 * PI / 7200.0,
        "Mean motion of the target's circular orbit (1e-9..0.1)";
    CHASER_MASS = 2: "chaser_mass", Parameter, Fixed, Real("kg"), 1000.0,
        "Chaser mass: thrust = mass * commanded acceleration (> 0)";
    HOLD_X = 3: "hold_x", Parameter, Fixed, Real("m"), 300.0, "Hold point x (at rest in the Hill frame)";
    HOLD_Y = 4: "hold_y", Parameter, Fixed, Real("m"), 0.0, "Hold point y";
    HOLD_Z = 5: "hold_z", Parameter, Fixed, Real("m"), 0.0, "Hold point z";
    BANDWIDTH = 6: "bandwidth", Parameter, Fixed, Real("rad/s"), 0.01,
        "Natural frequency w of the closed loop e'' + 2 zeta w e' + w^2 e = 0 (> 0; w * step <= 0.5)";
    DAMPING = 7: "damping", Parameter, Fixed, Real(""), 0.9, "Damping ratio zeta of the closed loop (> 0)";
    THRUST_MAX = 8: "thrust_max", Parameter, Fixed, Real("N"), 10.0, "Largest thrust per axis (> 0)";
    MIN_IMPULSE_BIT = 9: "min_impulse_bit", Parameter, Fixed, Real("N.s"), 0.0,
        "Smallest impulse a thruster delivers: the commanded impulse is accumulated per axis and fired once it reaches this bit (0: none)";
    ENGAGE_TIME = 10: "engage_time", Parameter, Fixed, Real("s"), 0.0,
        "Time from which thrust is commanded (zero thrust before)";
    X = 11: "x", Input, Discrete, Real("m"), 0.0, "Estimated relative position x at the step's start (relnav's x)";
    Y = 12: "y", Input, Discrete, Real("m"), 0.0, "Estimated relative position y";
    Z = 13: "z", Input, Discrete, Real("m"), 0.0, "Estimated relative position z";
    VX = 14: "vx", Input, Discrete, Real("m/s"), 0.0, "Estimated relative velocity vx";
    VY = 15: "vy", Input, Discrete, Real("m/s"), 0.0, "Estimated relative velocity vy";
    VZ = 16: "vz", Input, Discrete, Real("m/s"), 0.0, "Estimated relative velocity vz";
    THRUST_X = 17: "thrust_x", Output, Discrete, Real("N"), 0.0,
        "Thrust along x commanded for the next step (after the per-axis limit and the minimum impulse bit)";
    THRUST_Y = 18: "thrust_y", Output, Discrete, Real("N"), 0.0, "Thrust along y commanded for the next step";
    THRUST_Z = 19: "thrust_z", Output, Discrete, Real("N"), 0.0, "Thrust along z commanded for the next step";
    DELTA_V = 20: "delta_v", Output, Discrete, Real("m/s"), 0.0,
        "Velocity increment delivered so far, sum of |thrust_x| + |thrust_y| + |thrust_z| times step over mass (what three axis thrusters burn)";
    FMI_STATUS = 21: "fmi_status", Output, Discrete, Integer, 0.0,
        "Worst fmi2Status this instance has returned since fmi2Instantiate or fmi2Reset: 0 fmi2OK, 3 fmi2Error, 4 fmi2Fatal (the reason is logged under logStatusError)";
}

/// relnav_guidance.fmu's static description.
pub static INFO: ModelInfo = ModelInfo {
    model_identifier: "relnav_guidance",
    description: "Hold-point guidance of relnav's system kit: turns the relative-navigation \
estimate into thrust with a Clohessy-Wiltshire-compensated PD law in the Hill frame (one step \
of delay compensated by prediction), a per-axis thrust limit and a minimum impulse bit",
    variables: VARIABLES,
    default_experiment: DefaultExperiment {
        start: 0.0,
        stop: 600.0,
        step: 1.0,
    },
    fmi_status: vr::FMI_STATUS,
    state_code: None,
    state_name: "guidance",
    generated: Generated::new(),
};
