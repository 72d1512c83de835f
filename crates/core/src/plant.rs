//! The truth plant of the system kit (`relnav_plant.fmu`): the chaser's true motion relative
//! to the target, driven by its thrust, and the radio (or lidar) sensor that measures it —
//! the half of a GNC system a user of relnav.fmu would otherwise have to write.
//!
//! **Truth** (canonical Hill frame inside, I/O frame at the interface, SI units):
//! * [`TruthModel::Cw`]: the exact linearised relative motion,
//!   `X(t + h) = Phi X(t) + Gamma F / m` with the thrust `F` held over the step: at
//!   `eccentricity` 0 the closed-form transition and exact zero-order-hold input matrix of
//!   [`crate::dynamics::CwModel`] (papers 000 and 002, sec. 2), otherwise those of the
//!   elliptic model [`crate::dynamics::EllipticModel`] (Yamanaka–Ankersen);
//! * [`TruthModel::TwoBodyJ2`]: target and chaser around the Earth, point mass + J2
//!   ([`crate::orbit::TwoBodyJ2`], the evaluation engine's nonlinear truth), the target
//!   started on the orbit of `mean_motion` and `eccentricity` at `inclination` (perigee at
//!   the ascending node, true anomaly `true_anomaly0`), the relative state read in the
//!   target's Hill frame; [`TruthModel::TwoBody`] the same without J2.
//!
//! **Sensor** ([`crate::sensors::RadioSensor::measure_with`], paper 000 sec. 2): range,
//! azimuth `atan2(y, x)` in `[0, 2 pi)` and elevation `asin(z / range)` of the I/O-frame
//! position, plus noise from [`crate::noise::NoiseModel`] (Gaussian, contaminated Gaussian
//! or Student-t) scaled by `sigma_range` and `sigma_angle`. A measurement is due every
//! `measurement_period` from the start time, taken at the first communication point at or
//! after the due time; it is lost (`valid = false`) inside the dropout window
//! `[dropout_start, dropout_stop)`, with probability `dropout_probability`, and while the
//! true range is outside `[radio_min_range, radio_max_range)`.
//!
//! **Camera and relative GNSS** (relnav's declared sensors beside the radio): each on its
//! own schedule (`camera_period`, `gnss_period`, from the start time, taken as the radio's).
//! The camera gives the line of sight ([`CameraSensor::measure_with`]: azimuth and
//! elevation with the radio's conventions, noise of the `camera_noise_*` density scaled by
//! `sigma_camera`), valid while the true range is in `[camera_min_range,
//! camera_max_range)`; GNSS the relative position and velocity in the I/O frame with noise
//! of the `gnss_noise_*` density scaled by `sigma_gnss` and `sigma_gnss_velocity`, lost
//! inside `[gnss_outage_start, gnss_outage_stop)`.
//!
//! **Random draws** (ChaCha8, seeded by `seed`): the radio on stream 0, per due measurement
//! one uniform for the dropout, then the three noise samples (range, azimuth, elevation) —
//! always, whether the measurement is then dropped or not, so the noise sequence does not
//! depend on the dropout settings; the camera on stream 1 (two samples per reading) and
//! GNSS on stream 2 (six, position first), likewise always, so no sensor's settings move
//! another's noise.

use crate::dynamics::{Discretization, Dynamics, RelativeDynamics};
use crate::frames::Frame;
use crate::nav::config::ECCENTRICITY_RULE;
use crate::nav::config::{NoiseKind, NOISE_DOF_RULE, NOISE_SCALE_RULE, NOISE_ZETA_RULE};
use crate::noise::NoiseModel;
use crate::numerics::state::{refuse, Reader, StateError, Writer};
use crate::orbit::{TwoBodyJ2, R_EARTH};
use crate::params::{closed, Rule};
use crate::sensors::{add_noise, CameraSensor, RadioSensor};
use crate::types::{Mat3, Mat6, Mat63, State, Vec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

crate::codes! {
    /// Which truth propagates the relative motion (codes of the plant's `truth_model`).
    #[derive(Default)]
    pub enum TruthModel: TRUTH_MODEL_CODES = "TruthModel", "relnav_truth_model", "RELNAV_TRUTH_", false {
        /// Exact CW (closed-form transition, exact zero-order hold).
        #[default]
        Cw = 1, "cw", "Exact linearised relative motion: Clohessy-Wiltshire at eccentricity 0, the elliptic model of Yamanaka and Ankersen otherwise (closed-form transition, zero-order hold of the thrust)";
        /// Two-body + J2 propagation of target and chaser (10th-order GBS substeps).
        TwoBodyJ2 = 2, "two_body_j2", "Target and chaser around the Earth, point mass + J2 (10th-order Gragg-Bulirsch-Stoer substeps); relative state in the target's Hill frame";
        /// Two-body propagation (point mass, no J2) of target and chaser.
        TwoBody = 3, "two_body", "Target and chaser around the Earth, point mass alone (10th-order Gragg-Bulirsch-Stoer substeps); relative state in the target's Hill frame";
    }
}

crate::config! {
    /// Everything that defines a plant: relnav_plant.fmu's parameters (value references in
    /// the declarations). [`Default`] is paper 000's example: frame 2, a 7200 s orbit, the
    /// chaser at rest at (400, 500, 200) m, 1000 kg, a measurement every second with
    /// 0.5 m / 0.01 deg Gaussian noise.
    pub struct PlantConfig, PLANT_PARAMS;
    frame: Frame {
        elements: [("frame", 0, "", 2, "")],
        rule: Rule::Any, c: false, scenario: None, slot: None,
        description: "Hill-frame convention of the thrust, the true state and the measurement angles (as relnav's frame)",
    },
    truth_model: TruthModel {
        elements: [("truth_model", 1, "", 1, "")],
        rule: Rule::Any, c: false, scenario: None, slot: None,
        description: "Truth of the relative motion",
    },
    mean_motion: f64 {
        elements: [("mean_motion", 2, "rad/s", 2.0 * core::f64::consts::PI / 7200.0, "")],
        rule: Rule::Interval { lo: closed(1e-9), hi: closed(0.1), why: " rad/s" },
        c: false, scenario: None, slot: None,
        description: "Mean motion of the target's orbit, 2 pi / period (1e-9..0.1)",
    },
    chaser_mass: f64 {
        elements: [("chaser_mass", 3, "kg", 1000.0, "")],
        rule: Rule::Positive, c: false, scenario: None, slot: None,
        description: "Chaser mass: thrust / mass = acceleration (> 0)",
    },
    x0: [f64; 6] {
        elements: [
            ("true_x0", 4, "m", 400.0, "True initial relative position x"),
            ("true_y0", 5, "m", 500.0, "True initial relative position y"),
            ("true_z0", 6, "m", 200.0, "True initial relative position z"),
            ("true_vx0", 7, "m/s", 0.0, "True initial relative velocity vx"),
            ("true_vy0", 8, "m/s", 0.0, "True initial relative velocity vy"),
            ("true_vz0", 9, "m/s", 0.0, "True initial relative velocity vz"),
        ],
        rule: Rule::Finite, c: false, scenario: None, slot: None,
        description: "True initial relative state (x, y, z, vx, vy, vz) in the I/O frame",
    },
    inclination: f64 {
        elements: [("inclination", 10, "rad", 51.6 * core::f64::consts::PI / 180.0, "")],
        rule: Rule::Interval { lo: closed(0.0), hi: closed(core::f64::consts::PI), why: " rad" },
        c: false, scenario: None, slot: None,
        description: "truth_model two_body_j2 and two_body: inclination of the target's orbit (in [0, pi]; perigee at the ascending node)",
    },
    j2_substep: f64 {
        elements: [("j2_substep", 11, "s", 1.0, "")],
        rule: Rule::Positive, c: false, scenario: None, slot: None,
        description: "truth_model two_body_j2 and two_body: longest integration substep (a step h takes round(h / j2_substep), at least 1, equal substeps; > 0)",
    },
    measurement_period: f64 {
        elements: [("measurement_period", 12, "s", 1.0, "")],
        rule: Rule::Positive, c: false, scenario: None, slot: None,
        description: "Time between measurements from the start time; a measurement is taken at the first communication point at or after its due time (> 0)",
    },
    sigma_range: f64 {
        elements: [("sigma_range", 13, "m", 0.5, "")],
        rule: Rule::Positive, c: false, scenario: None, slot: None,
        description: "Range measurement noise, 1 sigma of the Gaussian (nominal sigma of the other noise models; > 0)",
    },
    sigma_angle: f64 {
        elements: [("sigma_angle", 14, "rad", 0.01 * core::f64::consts::PI / 180.0, "")],
        rule: Rule::Positive, c: false, scenario: None, slot: None,
        description: "Azimuth and elevation measurement noise, 1 sigma of the Gaussian (nominal sigma of the other noise models; > 0)",
    },
    noise_model: NoiseKind {
        elements: [("noise_model", 15, "", 1, "")],
        rule: Rule::Any, c: false, scenario: None, slot: None,
        description: "Measurement-noise density scaled by sigma_range and sigma_angle (as relnav's noise_model)",
    },
    noise_zeta: f64 {
        elements: [("noise_zeta", 16, "", 0.2, "")],
        rule: NOISE_ZETA_RULE,
        c: false, scenario: None, slot: None,
        description: "Mixture noise: weight of the wide component (in [0, 1))",
    },
    noise_scale: f64 {
        elements: [("noise_scale", 17, "", 10.0, "")],
        rule: NOISE_SCALE_RULE,
        c: false, scenario: None, slot: None,
        description: "Mixture noise: sigma of the wide component over the nominal sigma (>= 1)",
    },
    noise_dof: f64 {
        elements: [("noise_dof", 18, "", 4.0, "")],
        rule: NOISE_DOF_RULE,
        c: false, scenario: None, slot: None,
        description: "Student-t noise: degrees of freedom (> 2)",
    },
    dropout_probability: f64 {
        elements: [("dropout_probability", 19, "", 0.0, "")],
        rule: Rule::Interval { lo: closed(0.0), hi: closed(1.0), why: "" },
        c: false, scenario: None, slot: None,
        description: "Probability that a due measurement is lost (in [0, 1]; one uniform draw per due measurement)",
    },
    dropout_start: f64 {
        elements: [("dropout_start", 20, "s", 0.0, "")],
        rule: Rule::Finite, c: false, scenario: None, slot: None,
        description: "Start of a window in which every measurement is lost (none when dropout_stop <= dropout_start)",
    },
    dropout_stop: f64 {
        elements: [("dropout_stop", 21, "s", 0.0, "")],
        rule: Rule::Finite, c: false, scenario: None, slot: None,
        description: "End of the dropout window (excluded)",
    },
    seed: u64 {
        elements: [("seed", 22, "", 0, "")],
        rule: Rule::Any, c: false, scenario: None, slot: None,
        description: "Seed of the measurement noise and dropout draws (identical seeds give identical outputs)",
    },
    eccentricity: f64 {
        elements: [("eccentricity", 37, "", 0.0, "")],
        rule: ECCENTRICITY_RULE,
        c: false, scenario: None, slot: None,
        description: "Eccentricity of the target's orbit (0 <= e <= 0.99): truth_model cw propagates the linearised elliptic model (Yamanaka-Ankersen) when > 0, two_body_j2 starts the target on this Keplerian orbit (perigee at the ascending node); mean_motion stays 2 pi / period",
    },
    true_anomaly0: f64 {
        elements: [("true_anomaly0", 38, "rad", 0.0, "")],
        rule: Rule::Finite, c: false, scenario: None, slot: None,
        description: "True anomaly of the target at the start time (unused at eccentricity 0)",
    },
    radio_min_range: f64 {
        elements: [("radio_min_range", 39, "m", 0.0, "")],
        rule: Rule::NonNegative, c: false, scenario: None, slot: None,
        description: "The radio or lidar measures while the true range is at least this (>= 0)",
    },
    radio_max_range: f64 {
        elements: [("radio_max_range", 40, "m", 1e9, "")],
        rule: Rule::Positive, c: false, scenario: None, slot: None,
        description: "... and below this (> radio_min_range; the default 1e9 m is no limit)",
    },
    camera_period: f64 {
        elements: [("camera_period", 41, "s", 1.0, "")],
        rule: Rule::Positive, c: false, scenario: None, slot: None,
        description: "Time between camera readings from the start time, each taken at the first communication point at or after its due time (> 0)",
    },
    sigma_camera: f64 {
        elements: [("sigma_camera", 42, "rad", 1e-3, "")],
        rule: Rule::Positive, c: false, scenario: None, slot: None,
        description: "Camera azimuth and elevation noise, 1 sigma of the Gaussian (nominal sigma of the other noise models; > 0)",
    },
    camera_min_range: f64 {
        elements: [("camera_min_range", 43, "m", 0.0, "")],
        rule: Rule::NonNegative, c: false, scenario: None, slot: None,
        description: "The camera measures while the true range is at least this (>= 0)",
    },
    camera_max_range: f64 {
        elements: [("camera_max_range", 44, "m", 1e9, "")],
        rule: Rule::Positive, c: false, scenario: None, slot: None,
        description: "... and below this (> camera_min_range; the default 1e9 m is no limit)",
    },
    gnss_period: f64 {
        elements: [("gnss_period", 45, "s", 1.0, "")],
        rule: Rule::Positive, c: false, scenario: None, slot: None,
        description: "Time between relative GNSS readings (position and velocity together) from the start time, each taken at the first communication point at or after its due time (> 0)",
    },
    sigma_gnss: f64 {
        elements: [("sigma_gnss", 46, "m", 0.05, "")],
        rule: Rule::Positive, c: false, scenario: None, slot: None,
        description: "Relative GNSS position noise per axis, 1 sigma of the Gaussian (nominal sigma of the other noise models; > 0)",
    },
    sigma_gnss_velocity: f64 {
        elements: [("sigma_gnss_velocity", 47, "m/s", 5e-4, "")],
        rule: Rule::Positive, c: false, scenario: None, slot: None,
        description: "Relative GNSS velocity noise per axis, 1 sigma of the Gaussian (nominal sigma of the other noise models; > 0)",
    },
    gnss_outage_start: f64 {
        elements: [("gnss_outage_start", 48, "s", 0.0, "")],
        rule: Rule::Finite, c: false, scenario: None, slot: None,
        description: "Start of a window in which every GNSS reading is lost (none when gnss_outage_stop <= gnss_outage_start)",
    },
    gnss_outage_stop: f64 {
        elements: [("gnss_outage_stop", 49, "s", 0.0, "")],
        rule: Rule::Finite, c: false, scenario: None, slot: None,
        description: "End of the GNSS outage window (excluded)",
    },    camera_noise_model: NoiseKind {
        elements: [("camera_noise_model", 61, "", 1, "")],
        rule: Rule::Any, c: false, scenario: None, slot: None,
        description: "Camera: density of the reading's noise scaled by sigma_camera (as relnav's camera_noise_model)",
    },
    camera_noise_zeta: f64 {
        elements: [("camera_noise_zeta", 62, "", 0.2, "")],
        rule: NOISE_ZETA_RULE,
        c: false, scenario: None, slot: None,
        description: "Camera, mixture noise: weight of the wide component (in [0, 1))",
    },
    camera_noise_scale: f64 {
        elements: [("camera_noise_scale", 63, "", 10.0, "")],
        rule: NOISE_SCALE_RULE,
        c: false, scenario: None, slot: None,
        description: "Camera, mixture noise: sigma of the wide component over the nominal sigma (>= 1)",
    },
    camera_noise_dof: f64 {
        elements: [("camera_noise_dof", 64, "", 4.0, "")],
        rule: NOISE_DOF_RULE,
        c: false, scenario: None, slot: None,
        description: "Camera, Student-t noise: degrees of freedom (> 2)",
    },
    gnss_noise_model: NoiseKind {
        elements: [("gnss_noise_model", 65, "", 1, "")],
        rule: Rule::Any, c: false, scenario: None, slot: None,
        description: "Relative GNSS: density of the reading's noise scaled by sigma_gnss and sigma_gnss_velocity (as relnav's gnss_noise_model)",
    },
    gnss_noise_zeta: f64 {
        elements: [("gnss_noise_zeta", 66, "", 0.2, "")],
        rule: NOISE_ZETA_RULE,
        c: false, scenario: None, slot: None,
        description: "Relative GNSS, mixture noise: weight of the wide component (in [0, 1))",
    },
    gnss_noise_scale: f64 {
        elements: [("gnss_noise_scale", 67, "", 10.0, "")],
        rule: NOISE_SCALE_RULE,
        c: false, scenario: None, slot: None,
        description: "Relative GNSS, mixture noise: sigma of the wide component over the nominal sigma (>= 1)",
    },
    gnss_noise_dof: f64 {
        elements: [("gnss_noise_dof", 68, "", 4.0, "")],
        rule: NOISE_DOF_RULE,
        c: false, scenario: None, slot: None,
        description: "Relative GNSS, Student-t noise: degrees of freedom (> 2)",
    },
}

impl PlantConfig {
    /// Check every setting; the message names the first bad one.
    pub fn validate(&self) -> Result<(), String> {
        for p in PLANT_PARAMS {
            p.check(self)?;
        }
        for (name, lo, hi) in [
            ("radio", self.radio_min_range, self.radio_max_range),
            ("camera", self.camera_min_range, self.camera_max_range),
        ] {
            if !(hi > lo) {
                return Err(format!(
                    "{name}_max_range ({hi} m) must exceed {name}_min_range ({lo} m)"
                ));
            }
        }
        if matches!(
            self.truth_model,
            TruthModel::TwoBodyJ2 | TruthModel::TwoBody
        ) {
            let a = (crate::orbit::MU_EARTH / (self.mean_motion * self.mean_motion)).cbrt();
            let rp = a * (1.0 - self.eccentricity);
            if rp <= R_EARTH {
                return Err(format!(
                    "truth_model {}: mean_motion {} rad/s and eccentricity {} give a \
                     perigee radius of {rp:.0} m, inside the Earth (radius {R_EARTH} m)",
                    self.truth_model.name(),
                    self.mean_motion,
                    self.eccentricity
                ));
            }
        }
        Ok(())
    }

    /// The measurement-noise density (scales `sigma_range`, `sigma_angle`).
    pub fn noise(&self) -> NoiseModel {
        self.noise_model
            .model(self.noise_zeta, self.noise_scale, self.noise_dof)
    }

    /// The camera's angle-noise density (scale `sigma_camera`).
    pub fn camera_noise(&self) -> NoiseModel {
        self.camera_noise_model.model(
            self.camera_noise_zeta,
            self.camera_noise_scale,
            self.camera_noise_dof,
        )
    }

    /// Relative GNSS's noise density (scales `sigma_gnss`, `sigma_gnss_velocity`).
    pub fn gnss_noise(&self) -> NoiseModel {
        self.gnss_noise_model.model(
            self.gnss_noise_zeta,
            self.gnss_noise_scale,
            self.gnss_noise_dof,
        )
    }

    fn sensor(&self) -> RadioSensor {
        RadioSensor::new(self.frame, self.sigma_range, self.sigma_angle)
    }
}

/// The true relative motion.
#[derive(Debug, Clone, Copy)]
enum Truth {
    /// The linear relative dynamics (CW): the canonical state and the transition of the
    /// last step length (kept for a time-invariant model).
    Linear {
        x: State,
        model: Dynamics,
        cache: Option<(f64, Mat6, Mat63)>,
    },
    /// Two-body + J2 of both spacecraft.
    TwoBodyJ2(TwoBodyJ2),
}

/// One measurement due at a communication point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// `(range, azimuth, elevation)` [m, rad, rad] with noise; `None` at zero range.
    pub z: Option<Vec3>,
    /// Whether it reached the navigation (not dropped, not at zero range).
    pub valid: bool,
}

/// One camera reading due at a communication point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraSample {
    /// `(azimuth, elevation)` [rad] with noise; `None` at zero range.
    pub z: Option<[f64; 2]>,
    /// Whether the camera saw the target (true range in its interval, not at zero range).
    pub valid: bool,
}

/// One relative GNSS reading due at a communication point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GnssSample {
    /// Relative position [m] and velocity [m/s] with noise, I/O frame.
    pub position: [f64; 3],
    /// See `position`.
    pub velocity: [f64; 3],
    /// Whether it reached the navigation (not in the outage window).
    pub valid: bool,
}

/// The schedule of one sensor: readings due every `period` from `t0`, each taken at the
/// first communication point at or after its due time.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Schedule {
    period: f64,
    /// Index `m` of the next due reading, at `t0 + m * period`.
    next: u64,
}

impl Schedule {
    /// Whether a reading is due at `t` (and if so, the next one scheduled after `t`: a long
    /// step may skip several).
    fn due(&mut self, t0: f64, t: f64) -> bool {
        let tol = 1e-9 * self.period.max(t.abs());
        if t < t0 + self.next as f64 * self.period - tol {
            return false;
        }
        self.next = ((t - t0 + tol) / self.period).floor().max(0.0) as u64 + 1;
        true
    }
}

/// A generator of the plant's seed on its own stream (0: the radio's; the camera's and the
/// GNSS's draws do not move the radio's noise sequence).
fn stream(seed: u64, stream: u64) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(stream);
    rng
}

/// The plant: truth, sensor schedules, random generators.
#[derive(Debug, Clone)]
pub struct Plant {
    cfg: PlantConfig,
    sensor: RadioSensor,
    truth: Truth,
    rng: ChaCha8Rng,
    t0: f64,
    radio: Schedule,
    camera: Schedule,
    camera_rng: ChaCha8Rng,
    gnss: Schedule,
    gnss_rng: ChaCha8Rng,
}

impl Plant {
    /// A plant at `t0` in its initial state (nothing drawn yet: see [`Plant::sample`]).
    pub fn new(cfg: PlantConfig, t0: f64) -> Result<Self, String> {
        cfg.validate()?;
        if !t0.is_finite() {
            return Err(format!("start time must be finite (got {t0})"));
        }
        let x0 = cfg
            .frame
            .state_to_canonical(&State::from_row_slice(&cfg.x0));
        let truth = match cfg.truth_model {
            TruthModel::Cw => Truth::Linear {
                x: x0,
                model: Dynamics::of_orbit(cfg.mean_motion, cfg.eccentricity, cfg.true_anomaly0),
                cache: None,
            },
            TruthModel::TwoBodyJ2 | TruthModel::TwoBody => {
                let mut tb = TwoBodyJ2::keplerian(
                    cfg.mean_motion,
                    cfg.eccentricity,
                    cfg.true_anomaly0,
                    cfg.inclination,
                    &x0,
                    cfg.j2_substep,
                );
                tb.j2 = cfg.truth_model == TruthModel::TwoBodyJ2;
                Truth::TwoBodyJ2(tb)
            }
        };
        Ok(Self {
            cfg,
            sensor: cfg.sensor(),
            truth,
            rng: ChaCha8Rng::seed_from_u64(cfg.seed),
            t0,
            radio: Schedule {
                period: cfg.measurement_period,
                next: 0,
            },
            camera: Schedule {
                period: cfg.camera_period,
                next: 0,
            },
            camera_rng: stream(cfg.seed, 1),
            gnss: Schedule {
                period: cfg.gnss_period,
                next: 0,
            },
            gnss_rng: stream(cfg.seed, 2),
        })
    }

    /// The configuration.
    pub fn config(&self) -> &PlantConfig {
        &self.cfg
    }

    /// The true relative state in the I/O frame.
    pub fn truth(&self) -> State {
        self.cfg.frame.state_from_canonical(&self.truth_canonical())
    }

    /// The true relative state in the canonical Hill frame.
    pub fn truth_canonical(&self) -> State {
        match &self.truth {
            Truth::Linear { x, .. } => *x,
            Truth::TwoBodyJ2(t) => t.relative(),
        }
    }

    /// Propagate the truth over `[t, t + h)` with `thrust` [N, I/O frame] held.
    pub fn propagate(&mut self, thrust: &Vec3, t: f64, h: f64) -> Result<(), String> {
        if !(h.is_finite() && h > 0.0) {
            return Err(format!("step must be finite and > 0 (got {h})"));
        }
        if let Some(i) = thrust.iter().position(|v| !v.is_finite()) {
            return Err(format!(
                "thrust_{} must be finite (got {})",
                ["x", "y", "z"][i],
                thrust[i]
            ));
        }
        let a = self.cfg.frame.vec_to_canonical(thrust) / self.cfg.chaser_mass;
        match &mut self.truth {
            Truth::Linear { x, model, cache } => {
                let (phi, gamma) = match cache {
                    Some((hc, p, g)) if hc.to_bits() == h.to_bits() => (*p, *g),
                    _ => {
                        let d = model.step(t - self.t0, h, &Mat3::zeros(), Discretization::Exact);
                        if model.time_invariant() {
                            *cache = Some((h, d.phi, d.gamma));
                        }
                        (d.phi, d.gamma)
                    }
                };
                *x = phi * *x + gamma * a;
            }
            Truth::TwoBodyJ2(tb) => tb.step(&a, t, h),
        }
        Ok(())
    }

    /// The measurement due at communication point `t`, if one is (drawn now, from the
    /// current truth); `None` if no measurement is due at `t`.
    pub fn sample(&mut self, t: f64) -> Option<Sample> {
        if !self.radio.due(self.t0, t) {
            return None;
        }
        let u: f64 = self.rng.random();
        let mut ar = [0.0; 3];
        let r = self.truth_canonical().fixed_rows::<3>(0).into_owned();
        let z = self
            .sensor
            .measure_with(&r, &self.cfg.noise(), &mut ar, &mut self.rng);
        let in_window = t >= self.cfg.dropout_start && t < self.cfg.dropout_stop;
        let rho = r.norm();
        let in_range = rho >= self.cfg.radio_min_range && rho < self.cfg.radio_max_range;
        let valid = z.is_some() && !in_window && in_range && u >= self.cfg.dropout_probability;
        Some(Sample { z, valid })
    }

    /// The camera reading due at communication point `t`, if one is: the line of sight
    /// of the current truth ([`CameraSensor::measure_with`], two draws of the
    /// `camera_noise_*` density scaled by `sigma_camera` on its own stream, always, so the
    /// sequence does not depend on the range limits); valid while the true range is in
    /// `[camera_min_range, camera_max_range)`.
    pub fn sample_camera(&mut self, t: f64) -> Option<CameraSample> {
        if !self.camera.due(self.t0, t) {
            return None;
        }
        let x = self.truth_canonical();
        let cam = CameraSensor::gaussian(self.cfg.frame, self.cfg.sigma_camera);
        let s = self.cfg.sigma_camera;
        let z = cam.measure_with(
            &x,
            &self.cfg.camera_noise(),
            &[s, s],
            &mut [0.0; 2],
            &mut self.camera_rng,
        );
        let rho = x.fixed_rows::<3>(0).norm();
        let in_range = rho >= self.cfg.camera_min_range && rho < self.cfg.camera_max_range;
        Some(CameraSample {
            z,
            valid: z.is_some() && in_range,
        })
    }

    /// The relative GNSS reading due at communication point `t`, if one is: the true
    /// position and velocity in the I/O frame plus noise of the `gnss_noise_*` density
    /// scaled by `sigma_gnss` and `sigma_gnss_velocity` (six draws on its own stream,
    /// position first); lost inside
    /// `[gnss_outage_start, gnss_outage_stop)`.
    pub fn sample_gnss(&mut self, t: f64) -> Option<GnssSample> {
        if !self.gnss.due(self.t0, t) {
            return None;
        }
        let x = self.truth();
        let (sp, sv) = (self.cfg.sigma_gnss, self.cfg.sigma_gnss_velocity);
        let g = self.cfg.gnss_noise();
        let position = add_noise(
            &x.fixed_rows::<3>(0).into_owned(),
            &g,
            &[sp; 3],
            &mut [0.0; 3],
            &mut self.gnss_rng,
        );
        let velocity = add_noise(
            &x.fixed_rows::<3>(3).into_owned(),
            &g,
            &[sv; 3],
            &mut [0.0; 3],
            &mut self.gnss_rng,
        );
        let outage = t >= self.cfg.gnss_outage_start && t < self.cfg.gnss_outage_stop;
        Some(GnssSample {
            position,
            velocity,
            valid: !outage,
        })
    }

    /// Bytes of the plant's dynamic state (truth, generator, schedule); the configuration
    /// is the caller's (the FMU's parameters).
    pub fn save(&self, w: &mut Writer<'_>) {
        w.tag(b"PLNT");
        match &self.truth {
            Truth::Linear { x, .. } => {
                w.u8(TruthModel::Cw as u8);
                w.matrix(x);
            }
            Truth::TwoBodyJ2(t) => {
                w.u8(TruthModel::TwoBodyJ2 as u8);
                w.matrix(&t.target);
                w.matrix(&t.chaser);
            }
        }
        w.bytes(&self.rng.get_seed());
        w.u64(self.rng.get_stream());
        let pos = self.rng.get_word_pos();
        w.u64(pos as u64);
        w.u64((pos >> 64) as u64);
        w.f64(self.t0);
        w.u64(self.radio.next);
        for (sched, rng) in [
            (&self.camera, &self.camera_rng),
            (&self.gnss, &self.gnss_rng),
        ] {
            w.u64(sched.next);
            let pos = rng.get_word_pos();
            w.u64(pos as u64);
            w.u64((pos >> 64) as u64);
        }
    }

    /// Read what [`Plant::save`] wrote into this plant (same configuration); on error
    /// nothing changes.
    pub fn load(&mut self, r: &mut Reader<'_>) -> Result<(), StateError> {
        r.tag(b"PLNT")?;
        let kind = r.u8("truth model")?;
        let mut truth = self.truth;
        match (&mut truth, kind) {
            (Truth::Linear { x, .. }, 1) => *x = r.finite_matrix("true state")?,
            (Truth::TwoBodyJ2(t), 2) => {
                t.target = r.finite_matrix("target state")?;
                t.chaser = r.finite_matrix("chaser state")?;
            }
            _ => {
                return Err(refuse(format!(
                    "truth model {kind} in the state, {} in this plant",
                    self.cfg.truth_model as i32
                )))
            }
        }
        let mut seed = [0u8; 32];
        seed.copy_from_slice(r.take(32, "generator seed")?);
        let stream = r.u64("generator stream")?;
        let lo = r.u64("generator position (low)")?;
        let hi = r.u64("generator position (high)")?;
        let t0 = r.finite("start time")?;
        let next = r.u64("next measurement index")?;
        let mut rng = ChaCha8Rng::from_seed(seed);
        rng.set_stream(stream);
        rng.set_word_pos(u128::from(lo) | (u128::from(hi) << 64));
        // the camera's and GNSS's schedules and generator positions (their seed and stream
        // are the configuration's)
        let mut others = [
            (self.camera, self.camera_rng.clone()),
            (self.gnss, self.gnss_rng.clone()),
        ];
        for (sched, g) in others.iter_mut() {
            sched.next = r.u64("next reading index")?;
            let lo = r.u64("generator position (low)")?;
            let hi = r.u64("generator position (high)")?;
            g.set_word_pos(u128::from(lo) | (u128::from(hi) << 64));
        }
        let [(camera, camera_rng), (gnss, gnss_rng)] = others;
        self.truth = truth;
        self.rng = rng;
        self.t0 = t0;
        self.radio.next = next;
        self.camera = camera;
        self.camera_rng = camera_rng;
        self.gnss = gnss;
        self.gnss_rng = gnss_rng;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::CwModel;

    /// The CW truth with a burn equals `Phi`/`Gamma` chained by hand, and the schedule
    /// takes a measurement every period with the configured draws.
    #[test]
    fn cw_truth_and_schedule() {
        let cfg = PlantConfig {
            measurement_period: 2.0,
            ..PlantConfig::default()
        };
        let mut p = Plant::new(cfg, 0.0).unwrap_or_else(|e| panic!("{e}"));
        assert!(p.sample(0.0).is_some_and(|s| s.valid));
        let f = Vec3::new(1.0, -2.0, 0.5);
        let m = CwModel::new(cfg.mean_motion);
        let mut x = cfg
            .frame
            .state_to_canonical(&State::from_row_slice(&cfg.x0));
        let mut count = 0;
        for k in 0..10 {
            p.propagate(&f, k as f64, 1.0)
                .unwrap_or_else(|e| panic!("{e}"));
            x = m.phi(1.0) * x + m.gamma(1.0) * (cfg.frame.vec_to_canonical(&f) / 1000.0);
            count += usize::from(p.sample(k as f64 + 1.0).is_some());
        }
        assert_eq!(count, 5);
        assert_eq!(p.truth_canonical(), x);
    }

    /// Saved and loaded state continues bit for bit (truth, generator, schedule).
    #[test]
    fn save_and_load_continue_bit_for_bit() {
        let cfg = PlantConfig {
            noise_model: NoiseKind::StudentT,
            dropout_probability: 0.3,
            truth_model: TruthModel::TwoBodyJ2,
            ..PlantConfig::default()
        };
        let mut a = Plant::new(cfg, 0.0).unwrap_or_else(|e| panic!("{e}"));
        let run = |p: &mut Plant, k0: usize| -> Vec<Option<Sample>> {
            (k0..k0 + 5)
                .map(|k| {
                    let _ = p.propagate(&Vec3::new(0.1, 0.0, 0.0), k as f64, 1.0);
                    p.sample(k as f64 + 1.0)
                })
                .collect()
        };
        let _ = run(&mut a, 0);
        let mut bytes = Vec::new();
        a.save(&mut Writer::new(&mut bytes));
        let after_a = run(&mut a, 5);
        let mut b = Plant::new(cfg, 0.0).unwrap_or_else(|e| panic!("{e}"));
        b.load(&mut Reader::new(&bytes))
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(run(&mut b, 5), after_a);
        assert_eq!(a.truth(), b.truth());
    }

    #[test]
    fn invalid_settings_are_named() {
        let bad = PlantConfig {
            sigma_range: 0.0,
            ..PlantConfig::default()
        };
        assert!(bad.validate().is_err_and(|e| e.contains("sigma_range")));
        let bad = PlantConfig {
            truth_model: TruthModel::TwoBodyJ2,
            mean_motion: 0.01,
            ..PlantConfig::default()
        };
        assert!(bad
            .validate()
            .is_err_and(|e| e.contains("inside the Earth")));
    }
}
