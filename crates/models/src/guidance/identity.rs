//! `relnav_guidance.fmu`'s identity: model identifier, description, default experiment,
//! and its variable table (value reference = index): the parameters' rows from
//! relnav-core's declarations ([`relnav_core::guidance::GUIDANCE_PARAMS`]), the inputs' and
//! outputs' here.

use relnav_fmi::model::{ArrayDef, DefaultExperiment, Generated, ModelInfo};
use relnav_fmi::variables::VarDef;
use std::sync::LazyLock;

/// The inputs and outputs (the parameters come from relnav-core's declarations).
mod io {
    use relnav_fmi::variables::VarType::*;

    relnav_fmi::variables! {
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
}

/// Value references by name: the inputs' and outputs' from their rows, the parameters'
/// from relnav-core's declarations.
pub mod vr {
    pub use super::io::vr::*;

    crate::param_vrs! {
        relnav_core::guidance::GUIDANCE_PARAMS;
        FRAME = "frame",
        MEAN_MOTION = "mean_motion",
        CHASER_MASS = "chaser_mass",
        HOLD_X = "hold_x",
        HOLD_Y = "hold_y",
        HOLD_Z = "hold_z",
        BANDWIDTH = "bandwidth",
        DAMPING = "damping",
        THRUST_MAX = "thrust_max",
        MIN_IMPULSE_BIT = "min_impulse_bit",
        ENGAGE_TIME = "engage_time",
        ECCENTRICITY = "eccentricity",
        TRUE_ANOMALY0 = "true_anomaly0",
    }
}

/// The inputs' and outputs' rows alone.
pub fn io_variables() -> &'static [VarDef] {
    io::VARIABLES
}

/// Number of variables.
pub const N_VARS: usize = 24;

/// Every variable; the value reference is the index.
pub static VARIABLES: LazyLock<Vec<VarDef>> = LazyLock::new(|| {
    crate::params::table(
        relnav_core::guidance::GUIDANCE_PARAMS,
        io::VARIABLES,
        N_VARS,
    )
});

/// The vectors relnav_guidance3.fmu publishes as arrays (FMI 3.0; relnav_guidance.fmu keeps
/// the scalars): relnav3.fmu's output names in, the plant's input name out.
static ARRAYS: &[ArrayDef] = &[
    ArrayDef {
        name: "position",
        elements: &[io::vr::X, io::vr::Y, io::vr::Z],
        description: "Estimated relative position at the step's start (relnav's position)",
    },
    ArrayDef {
        name: "velocity",
        elements: &[io::vr::VX, io::vr::VY, io::vr::VZ],
        description: "Estimated relative velocity at the step's start (relnav's velocity)",
    },
    ArrayDef {
        name: "thrust",
        elements: &[io::vr::THRUST_X, io::vr::THRUST_Y, io::vr::THRUST_Z],
        description: "Thrust commanded for the next step (x, y, z)",
    },
];

/// relnav_guidance.fmu's static description.
pub static INFO: LazyLock<ModelInfo> = LazyLock::new(|| ModelInfo {
    model_identifier: "relnav_guidance",
    description: "Hold-point guidance of relnav's system kit: turns the relative-navigation \
estimate into thrust with a Clohessy-Wiltshire-compensated PD law in the Hill frame (one step \
of delay compensated by prediction), a per-axis thrust limit and a minimum impulse bit",
    variables: VARIABLES.as_slice(),
    default_experiment: DefaultExperiment {
        start: 0.0,
        stop: 600.0,
        step: 1.0,
    },
    fmi_status: vr::FMI_STATUS,
    state_code: None,
    state_name: "guidance",
    arrays: ARRAYS,
    has_event_mode: false,
    computed: &[],
    generated: Generated::new(),
});
