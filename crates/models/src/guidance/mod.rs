//! `relnav_guidance.fmu`: the system kit's hold-point guidance law
//! ([`relnav_core::guidance::Guidance`]) behind the generic FMI layer; its identity and
//! variable table are in [`identity`].
//!
//! Step semantics: the estimate set before the step from `t` over `h` holds at `t` (connect
//! relnav's outputs `x` ... `vz`); the thrust published at `t + h` is the command for
//! `[t + h, t + 2 h)` (connect it to the plant's and relnav's `thrust_*`). The thrust at
//! initialisation is zero. No output depends on the inputs of the same communication point
//! (no direct feedthrough), so a loop through relnav, whose outputs have none either, is
//! not algebraic.

pub mod identity;

pub use identity::{vr, INFO, VARIABLES};

use relnav_core::guidance::{Guidance, GuidanceConfig, GUIDANCE_PARAMS};
use relnav_core::numerics::state::{Reader, Writer};
use relnav_core::types::State;
use relnav_fmi::model::{Model, ModelInfo};
use relnav_fmi::variables::{start_values, VarDef};

/// The guidance configuration the parameter values describe (each stored through its
/// declaration in [`relnav_core::guidance::GUIDANCE_PARAMS`], then the whole checked).
pub fn config_of(values: &[f64]) -> Result<GuidanceConfig, String> {
    let cfg: GuidanceConfig = crate::params::config_from(GUIDANCE_PARAMS, values)?;
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
        let mut values = start_values(&VARIABLES);
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
        let law = Guidance::new(cfg)
            .map_err(|e| format!("invalid parameters: {e}"))?
            .starting_at(time);
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
            return Err("the guidance is not initialised".to_string());
        };
        let est = State::from_fn(|i, _| values[(vr::X + i as u32) as usize]);
        law.step(&est, tc, h)?;
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
    use relnav_fmi::variables::check_table;

    #[test]
    fn table_is_dense_and_the_defaults_are_the_laws() {
        assert_eq!(check_table(&VARIABLES), Ok(()));
        assert_eq!(relnav_fmi::fmi3::description::check_arrays(&INFO), Ok(()));
        assert_eq!(VARIABLES.len(), identity::N_VARS);
        assert_eq!(
            crate::params::check_declared(GUIDANCE_PARAMS, identity::io_variables(), &VARIABLES),
            Ok(())
        );
        let values = start_values(&VARIABLES);
        assert_eq!(config_of(&values), Ok(GuidanceConfig::default()));
        // the inputs x..vz are contiguous (read as one state)
        let names: Vec<_> = (vr::X..=vr::VZ)
            .map(|r| VARIABLES[r as usize].name)
            .collect();
        assert_eq!(names, ["x", "y", "z", "vx", "vy", "vz"]);
    }
}
