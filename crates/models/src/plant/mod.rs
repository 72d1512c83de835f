//! `relnav_plant.fmu`: the system kit's truth plant ([`relnav_core::plant::Plant`]) behind
//! the generic FMI layer; its identity and variable table are in [`identity`].
//!
//! Step semantics as relnav.fmu's: the thrust set before the step from `t` over `h` is held
//! over `[t, t + h)`; afterwards `true_*` is the true state at `t + h` and, when a measurement
//! was due at `t + h`, `range`/`azimuth`/`elevation` hold it and `measurement_valid` says
//! whether it reached the navigation (they keep the last measurement otherwise, with
//! `measurement_valid` false); the camera's (`camera_*`) and the GNSS's (`gnss_*`) readings
//! the same way on their own schedules. At initialisation the outputs describe the start time (a
//! measurement is due there). No output depends on the inputs of the same communication
//! point (no direct feedthrough).

pub mod identity;

pub use identity::{vr, INFO, TRUTH_MODEL_TYPE, VARIABLES};

use relnav_core::numerics::state::{Reader, Writer};
use relnav_core::plant::{Plant, PlantConfig, PLANT_PARAMS};
use relnav_core::types::Vec3;
use relnav_fmi::model::{Model, ModelInfo};
use relnav_fmi::variables::{start_values, VarDef};

/// The plant configuration the parameter values describe (each stored through its
/// declaration in [`relnav_core::plant::PLANT_PARAMS`], then the whole checked).
pub fn config_of(values: &[f64]) -> Result<PlantConfig, String> {
    let cfg: PlantConfig = crate::params::config_from(PLANT_PARAMS, values)?;
    cfg.validate()?;
    Ok(cfg)
}

/// The plant of one instance (built at `fmi2ExitInitializationMode`).
#[derive(Debug)]
pub struct PlantFmu {
    plant: Option<Plant>,
}

const TRUE_OUT: [u32; 6] = [
    vr::TRUE_X,
    vr::TRUE_Y,
    vr::TRUE_Z,
    vr::TRUE_VX,
    vr::TRUE_VY,
    vr::TRUE_VZ,
];

/// Publish the true state and, if one is due at `t`, the measurement.
fn publish(plant: &mut Plant, values: &mut [f64], t: f64) {
    let x = plant.truth();
    for (r, xi) in TRUE_OUT.iter().zip(x.iter()) {
        values[*r as usize] = *xi;
    }
    let valid = match plant.sample(t) {
        Some(s) => {
            if let Some(z) = s.z {
                values[vr::RANGE as usize] = z.x;
                values[vr::AZIMUTH as usize] = z.y;
                values[vr::ELEVATION as usize] = z.z;
            }
            s.valid
        }
        None => false,
    };
    values[vr::MEASUREMENT_VALID as usize] = f64::from(u8::from(valid));
    let valid = match plant.sample_camera(t) {
        Some(s) => {
            if let Some(z) = s.z {
                values[vr::CAMERA_AZIMUTH as usize] = z[0];
                values[vr::CAMERA_ELEVATION as usize] = z[1];
            }
            s.valid
        }
        None => false,
    };
    values[vr::CAMERA_VALID as usize] = f64::from(u8::from(valid));
    let valid = match plant.sample_gnss(t) {
        Some(s) => {
            for (r, v) in GNSS_OUT.iter().zip(s.position.iter().chain(&s.velocity)) {
                values[*r as usize] = *v;
            }
            s.valid
        }
        None => false,
    };
    values[vr::GNSS_VALID as usize] = f64::from(u8::from(valid));
    values[vr::GNSS_VELOCITY_VALID as usize] = f64::from(u8::from(valid));
}

const GNSS_OUT: [u32; 6] = [
    vr::GNSS_X,
    vr::GNSS_Y,
    vr::GNSS_Z,
    vr::GNSS_VX,
    vr::GNSS_VY,
    vr::GNSS_VZ,
];

/// The readings' outputs (NaN while the parameters are invalid) and their flags.
const READINGS: [u32; 11] = [
    vr::RANGE,
    vr::AZIMUTH,
    vr::ELEVATION,
    vr::CAMERA_AZIMUTH,
    vr::CAMERA_ELEVATION,
    vr::GNSS_X,
    vr::GNSS_Y,
    vr::GNSS_Z,
    vr::GNSS_VX,
    vr::GNSS_VY,
    vr::GNSS_VZ,
];

impl Model for PlantFmu {
    fn info() -> &'static ModelInfo {
        &INFO
    }

    fn new() -> Self {
        Self { plant: None }
    }

    /// The configuration of the start values with this one value, checked (codes are
    /// checked by the generic layer; the orbit-inside-the-Earth combination at
    /// initialisation).
    fn check_alone(def: &VarDef, value: f64) -> Result<(), String> {
        let mut values = start_values(&VARIABLES);
        values[def.vr as usize] = value;
        config_of(&values).map(|_| ())
    }

    /// The truth at the start and the measurement due there, as initialisation will draw
    /// it (NaN measurement while the parameters are invalid).
    fn initial_outputs(values: &mut [f64], time: f64) {
        match config_of(values).and_then(|c| Plant::new(c, time)) {
            Ok(mut p) => publish(&mut p, values, time),
            Err(_) => {
                let x0 = [
                    vr::TRUE_X0,
                    vr::TRUE_Y0,
                    vr::TRUE_Z0,
                    vr::TRUE_VX0,
                    vr::TRUE_VY0,
                    vr::TRUE_VZ0,
                ]
                .map(|r| values[r as usize]);
                for (r, xi) in TRUE_OUT.iter().zip(x0) {
                    values[*r as usize] = xi;
                }
                for r in READINGS {
                    values[r as usize] = f64::NAN;
                }
                for r in [
                    vr::MEASUREMENT_VALID,
                    vr::CAMERA_VALID,
                    vr::GNSS_VALID,
                    vr::GNSS_VELOCITY_VALID,
                ] {
                    values[r as usize] = 0.0;
                }
            }
        }
    }

    fn initialize(&mut self, values: &mut [f64], time: f64) -> Result<String, String> {
        let cfg = config_of(values).map_err(|e| format!("invalid parameters: {e}"))?;
        let mut plant = Plant::new(cfg, time).map_err(|e| format!("invalid parameters: {e}"))?;
        publish(&mut plant, values, time);
        self.plant = Some(plant);
        Ok(format!(
            "initialised: truth_model {}, frame {}, mean_motion {} rad/s, chaser_mass {} kg, \
             measurement_period {} s, sigma_range {} m, sigma_angle {} rad, noise {:?}, \
             dropout_probability {}, dropout window [{}, {}) s, seed {}, t0 = {time} s",
            cfg.truth_model.name(),
            cfg.frame.code(),
            cfg.mean_motion,
            cfg.chaser_mass,
            cfg.measurement_period,
            cfg.sigma_range,
            cfg.sigma_angle,
            cfg.noise(),
            cfg.dropout_probability,
            cfg.dropout_start,
            cfg.dropout_stop,
            cfg.seed
        ))
    }

    fn do_step(&mut self, values: &mut [f64], tc: f64, h: f64) -> Result<(), String> {
        let Some(plant) = self.plant.as_mut() else {
            return Err("the plant is not initialised".to_string());
        };
        let thrust = Vec3::new(
            values[vr::THRUST_X as usize],
            values[vr::THRUST_Y as usize],
            values[vr::THRUST_Z as usize],
        );
        plant.propagate(&thrust, tc, h)?;
        publish(plant, values, tc + h);
        Ok(())
    }

    fn reset(&mut self) {
        self.plant = None;
    }

    fn is_built(&self) -> bool {
        self.plant.is_some()
    }

    fn save(&self) -> Result<Option<Vec<u8>>, String> {
        Ok(self.plant.as_ref().map(|p| {
            let mut b = Vec::new();
            p.save(&mut Writer::new(&mut b));
            b
        }))
    }

    fn restore(&mut self, values: &[f64], bytes: &[u8]) -> Result<(), String> {
        let mut plant = match &self.plant {
            Some(p) => p.clone(),
            None => config_of(values)
                .and_then(|c| Plant::new(c, 0.0))
                .map_err(|e| format!("its parameters do not make a plant: {e}"))?,
        };
        let mut r = Reader::new(bytes);
        plant.load(&mut r).map_err(|e| e.to_string())?;
        r.finish().map_err(|e| e.to_string())?;
        self.plant = Some(plant);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use relnav_fmi::variables::check_table;

    #[test]
    fn table_is_dense_and_the_defaults_are_the_plants() {
        assert_eq!(check_table(&VARIABLES), Ok(()));
        assert_eq!(relnav_fmi::fmi3::description::check_arrays(&INFO), Ok(()));
        assert_eq!(VARIABLES.len(), identity::N_VARS);
        assert_eq!(
            crate::params::check_declared(PLANT_PARAMS, identity::io_variables(), &VARIABLES),
            Ok(())
        );
        let values = start_values(&VARIABLES);
        assert_eq!(config_of(&values), Ok(PlantConfig::default()));
    }

    /// Every start value passes the early check, and a bad value alone is refused.
    #[test]
    fn early_checks() {
        use relnav_fmi::variables::Causality;
        for v in VARIABLES
            .iter()
            .filter(|v| v.causality == Causality::Parameter)
        {
            assert!(PlantFmu::check_alone(v, v.start).is_ok(), "{}", v.name);
        }
        let def = &VARIABLES[vr::NOISE_ZETA as usize];
        assert!(PlantFmu::check_alone(def, 1.5).is_err_and(|e| e.contains("noise_zeta")));
    }
}
