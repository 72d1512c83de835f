//! `relnav_guidance.fmu`: the system kit's hold-point guidance law ([`relnav_core::guidance`])
//! behind the generic FMI layer — its own variable table, model identifier and GUID.
//!
//! Step semantics: the estimate set before `fmi2DoStep(t, h)` holds at `t` (connect
//! relnav's outputs `x` ... `vz`); the thrust published at `t + h` is the command for
//! `[t + h, t + 2 h)` (connect it to the plant's and relnav's `thrust_*`). The thrust at
//! initialisation is zero. No output depends on the inputs of the same communication point
//! (no direct feedthrough), so a loop through relnav, whose outputs have none either, is
//! not algebraic.

use crate::model::{DefaultExperiment, Model, ModelInfo};
use crate::variables::{variables, VarDef, VarType, FRAME_TYPE};
use relnav_core::frames::Frame;
use relnav_core::guidance::{Guidance, GuidanceConfig};
use relnav_core::numerics::state::{Reader, Writer};
use relnav_core::types::State;
use std::f64::consts::PI;
use std::sync::OnceLock;

use VarType::{Code, Integer, Real};

variables! {
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
    generated: OnceLock::new(),
};

/// The guidance configuration the parameter values describe (checked).
pub fn config_of(values: &[f64]) -> Result<GuidanceConfig, String> {
    let v = |r: u32| values.get(r as usize).copied().unwrap_or(f64::NAN);
    let frame = Frame::from_code(v(vr::FRAME) as i32)
        .ok_or_else(|| format!("frame {} is not a code", v(vr::FRAME)))?;
    let cfg = GuidanceConfig {
        frame,
        mean_motion: v(vr::MEAN_MOTION),
        chaser_mass: v(vr::CHASER_MASS),
        hold: [vr::HOLD_X, vr::HOLD_Y, vr::HOLD_Z].map(v),
        bandwidth: v(vr::BANDWIDTH),
        damping: v(vr::DAMPING),
        thrust_max: v(vr::THRUST_MAX),
        min_impulse_bit: v(vr::MIN_IMPULSE_BIT),
        engage_time: v(vr::ENGAGE_TIME),
    };
    cfg.validate()?;
    Ok(cfg)
}

/// The guidance law of one instance (built at `fmi2ExitInitializationMode`).
#[derive(Debug)]
pub struct GuidanceFmu {
    law: Option<Guidance>,
}

fn publish(law: &Guidance, values: &mut [f64]) {
    let f = law.thrust();
    values[vr::THRUST_X as usize] = f.x;
    values[vr::THRUST_Y as usize] = f.y;
    values[vr::THRUST_Z as usize] = f.z;
    values[vr::DELTA_V as usize] = law.delta_v();
}

impl Model for GuidanceFmu {
    fn info() -> &'static ModelInfo {
        &INFO
    }

    fn new() -> Self {
        Self { law: None }
    }

    fn check_alone(def: &VarDef, value: f64) -> Result<(), String> {
        let mut values = crate::instance::start_values(VARIABLES);
        values[def.vr as usize] = value;
        config_of(&values).map(|_| ())
    }

    /// Zero thrust and velocity increment until the first step.
    fn initial_outputs(values: &mut [f64], _time: f64) {
        for r in [vr::THRUST_X, vr::THRUST_Y, vr::THRUST_Z, vr::DELTA_V] {
            values[r as usize] = 0.0;
        }
    }

    fn initialize(&mut self, values: &mut [f64], time: f64) -> Result<String, String> {
        let cfg = config_of(values).map_err(|e| format!("invalid parameters: {e}"))?;
        let law = Guidance::new(cfg).map_err(|e| format!("invalid parameters: {e}"))?;
        publish(&law, values);
        self.law = Some(law);
        Ok(format!(
            "initialised: frame {}, mean_motion {} rad/s, chaser_mass {} kg, hold point {:?} m, \
             bandwidth {} rad/s, damping {}, thrust_max {} N, min_impulse_bit {} N s, \
             engage_time {} s, t0 = {time} s",
            cfg.frame.code(),
            cfg.mean_motion,
            cfg.chaser_mass,
            cfg.hold,
            cfg.bandwidth,
            cfg.damping,
            cfg.thrust_max,
            cfg.min_impulse_bit,
            cfg.engage_time
        ))
    }

    fn do_step(&mut self, values: &mut [f64], tc: f64, h: f64) -> Result<(), String> {
        let Some(law) = self.law.as_mut() else {
            return Err(format!(
                "fmi2DoStep at t = {tc}: the guidance is not initialised"
            ));
        };
        let est = State::from_fn(|i, _| values[(vr::X + i as u32) as usize]);
        law.step(&est, tc, h)
            .map_err(|e| format!("fmi2DoStep at t = {tc}: {e}"))?;
        publish(law, values);
        Ok(())
    }

    fn reset(&mut self) {
        self.law = None;
    }

    fn is_built(&self) -> bool {
        self.law.is_some()
    }

    fn save(&self) -> Result<Option<Vec<u8>>, String> {
        Ok(self.law.as_ref().map(|g| {
            let mut b = Vec::new();
            g.save(&mut Writer::new(&mut b));
            b
        }))
    }

    fn restore(&mut self, values: &[f64], bytes: &[u8]) -> Result<(), String> {
        let mut law = match &self.law {
            Some(g) => *g,
            None => config_of(values)
                .and_then(Guidance::new)
                .map_err(|e| format!("its parameters do not make a guidance law: {e}"))?,
        };
        let mut r = Reader::new(bytes);
        law.load(&mut r).map_err(|e| e.to_string())?;
        r.finish().map_err(|e| e.to_string())?;
        self.law = Some(law);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::variables::check_table;

    #[test]
    fn table_is_dense_and_the_defaults_are_the_laws() {
        check_table(VARIABLES);
        let values = crate::instance::start_values(VARIABLES);
        assert_eq!(config_of(&values), Ok(GuidanceConfig::default()));
        // the inputs x..vz are contiguous (read as one state)
        let names: Vec<_> = (vr::X..=vr::VZ)
            .map(|r| VARIABLES[r as usize].name)
            .collect();
        assert_eq!(names, ["x", "y", "z", "vx", "vy", "vz"]);
    }
}
