//! `relnav_plant.fmu`: the system kit's truth plant ([`relnav_core::plant`]) behind the generic
//! FMI layer — its own variable table (written by the same `variables!` macro as relnav's),
//! its own model identifier and GUID.
//!
//! Step semantics as relnav.fmu's: the thrust set before `fmi2DoStep(t, h)` is held over
//! `[t, t + h)`; afterwards `true_*` is the true state at `t + h` and, when a measurement
//! was due at `t + h`, `range`/`azimuth`/`elevation` hold it and `measurement_valid` says
//! whether it reached the navigation (they keep the last measurement otherwise, with
//! `measurement_valid` false). At initialisation the outputs describe the start time (a
//! measurement is due there). No output depends on the inputs of the same communication
//! point (no direct feedthrough).

use crate::model::{DefaultExperiment, Model, ModelInfo};
use crate::variables::{variables, EnumType, VarDef, VarType, FRAME_TYPE, NOISE_MODEL_TYPE};
use relnav_core::frames::Frame;
use relnav_core::noise::NoiseModel;
use relnav_core::numerics::state::{Reader, Writer};
use relnav_core::plant::{Plant, PlantConfig, TruthModel};
use relnav_core::types::Vec3;
use std::f64::consts::PI;
use std::sync::OnceLock;

/// `truth_model` parameter values (the codes of [`TruthModel`]).
pub static TRUTH_MODEL_TYPE: EnumType = EnumType {
    name: "TruthModel",
    items: &[
        (
            "cw",
            1,
            "Exact Clohessy-Wiltshire (closed-form transition, exact zero-order hold of the thrust)",
        ),
        (
            "two_body_j2",
            2,
            "Target and chaser around the Earth, point mass + J2 (10th-order Gragg-Bulirsch-Stoer substeps); relative state in the target's Hill frame",
        ),
    ],
};

use VarType::{Boolean, Code, Integer, Real};

variables! {
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
    generated: OnceLock::new(),
};

/// The noise density of a `noise_model` code and its parameters, every parameter checked
/// whatever the code (as relnav checks them).
fn noise_of(code: f64, zeta: f64, scale: f64, dof: f64) -> Result<NoiseModel, String> {
    let fix = |e: String| e.replace("noise.", "noise_");
    NoiseModel::Mixture { zeta, scale }
        .validate()
        .map_err(fix)?;
    NoiseModel::StudentT { dof }.validate().map_err(fix)?;
    match code as i32 {
        1 => Ok(NoiseModel::Gaussian),
        2 => Ok(NoiseModel::Mixture { zeta, scale }),
        3 => Ok(NoiseModel::StudentT { dof }),
        other => Err(format!(
            "noise_model {other} is not a code (allowed: {})",
            NOISE_MODEL_TYPE.codes()
        )),
    }
}

/// The plant configuration the parameter values describe (checked).
pub fn config_of(values: &[f64]) -> Result<PlantConfig, String> {
    let v = |r: u32| values.get(r as usize).copied().unwrap_or(f64::NAN);
    let frame = Frame::from_code(v(vr::FRAME) as i32)
        .ok_or_else(|| format!("frame {} is not a code", v(vr::FRAME)))?;
    let truth_model = TruthModel::from_code(v(vr::TRUTH_MODEL) as i32)
        .ok_or_else(|| format!("truth_model {} is not a code", v(vr::TRUTH_MODEL)))?;
    let cfg = PlantConfig {
        frame,
        truth_model,
        mean_motion: v(vr::MEAN_MOTION),
        chaser_mass: v(vr::CHASER_MASS),
        x0: [
            vr::TRUE_X0,
            vr::TRUE_Y0,
            vr::TRUE_Z0,
            vr::TRUE_VX0,
            vr::TRUE_VY0,
            vr::TRUE_VZ0,
        ]
        .map(v),
        inclination: v(vr::INCLINATION),
        j2_substep: v(vr::J2_SUBSTEP),
        measurement_period: v(vr::MEASUREMENT_PERIOD),
        sigma_range: v(vr::SIGMA_RANGE),
        sigma_angle: v(vr::SIGMA_ANGLE),
        noise: noise_of(
            v(vr::NOISE_MODEL),
            v(vr::NOISE_ZETA),
            v(vr::NOISE_SCALE),
            v(vr::NOISE_DOF),
        )?,
        dropout_probability: v(vr::DROPOUT_PROBABILITY),
        dropout_start: v(vr::DROPOUT_START),
        dropout_stop: v(vr::DROPOUT_STOP),
        // FMI Integers are 32-bit; the seed's bit pattern is kept
        seed: u64::from(v(vr::SEED) as i32 as u32),
    };
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
}

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
        let mut values = crate::instance::start_values(VARIABLES);
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
                for r in [vr::RANGE, vr::AZIMUTH, vr::ELEVATION] {
                    values[r as usize] = f64::NAN;
                }
                values[vr::MEASUREMENT_VALID as usize] = 0.0;
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
            cfg.noise,
            cfg.dropout_probability,
            cfg.dropout_start,
            cfg.dropout_stop,
            cfg.seed
        ))
    }

    fn do_step(&mut self, values: &mut [f64], tc: f64, h: f64) -> Result<(), String> {
        let Some(plant) = self.plant.as_mut() else {
            return Err(format!(
                "fmi2DoStep at t = {tc}: the plant is not initialised"
            ));
        };
        let thrust = Vec3::new(
            values[vr::THRUST_X as usize],
            values[vr::THRUST_Y as usize],
            values[vr::THRUST_Z as usize],
        );
        plant
            .propagate(&thrust, tc, h)
            .map_err(|e| format!("fmi2DoStep at t = {tc}: {e}"))?;
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
    use crate::variables::check_table;

    #[test]
    fn table_is_dense_and_the_defaults_are_the_plants() {
        check_table(VARIABLES);
        let values = crate::instance::start_values(VARIABLES);
        assert_eq!(config_of(&values), Ok(PlantConfig::default()));
        let names: Vec<_> = TRUTH_MODEL_TYPE.items.iter().map(|i| (i.1, i.0)).collect();
        let lib: Vec<_> = TruthModel::ALL
            .iter()
            .map(|k| (*k as i32, k.name()))
            .collect();
        assert_eq!(names, lib);
    }

    /// Every start value passes the early check, and a bad value alone is refused.
    #[test]
    fn early_checks() {
        use crate::variables::Causality;
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
