//! Scenarios as data: one TOML file describes the orbit, the truth, the thrust, the
//! sensor and its noise, the campaign and the filters to compare. Parsing is strict
//! (`deny_unknown_fields`): a misspelt key is an error that names it and lists the keys
//! expected there. See `scenarios/*.toml` for the papers' examples and
//! `docs/scenarios.md` for the full key reference.

use relnav_core::estimators::pf::{Kernel, PfInit};
use relnav_core::frames::Frame;
use relnav_core::nav::{FilterKind, FilterOptions, HinfDesignKind, NavConfig, NoiseKind, PARAMS};
use relnav_core::noise::NoiseModel;
use relnav_core::params::{Kind, Value};
use relnav_core::types::{Mat6, State};
use serde::{Deserialize, Serialize};

/// Standard gravitational parameter of the Earth [m^3/s^2] (EGM-96), used with
/// `orbit.altitude`.
pub const MU_EARTH: f64 = 3.986_004_418e14;
/// Equatorial radius of the Earth [m], used with `orbit.altitude`.
pub const R_EARTH: f64 = 6_378_137.0;

/// A whole scenario file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Short name (used for the output folder).
    pub name: String,
    /// Title for tables and plots.
    pub title: String,
    /// Free notes: which paper, which errata were applied and why.
    #[serde(default)]
    pub notes: String,
    /// Frame of every vector in this file and of the reported errors.
    pub frame: FrameName,
    /// The target's circular orbit.
    pub orbit: Orbit,
    /// The true relative motion.
    pub truth: Truth,
    /// The chaser's thrust.
    #[serde(default)]
    pub thrust: Thrust,
    /// The scenario's first sensor (radio, lidar or Cartesian position): the one the
    /// papers use, scored by the NIS and used in the H-infinity design.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sensor: Option<Sensor>,
    /// Further sensors of any kind (`[[sensors]]`), each at its own rate, applied after
    /// `sensor` in file order at every time they measure.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sensors: Vec<Sensor>,
    /// Campaign settings.
    pub simulation: Simulation,
    /// Filters to compare, in table order.
    #[serde(rename = "filter")]
    pub filters: Vec<FilterSpec>,
    /// The paper's published figures: filter label -> text, shown beside ours.
    #[serde(default)]
    pub published: Vec<Published>,
}

/// Frame names as written in scenario files.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FrameName {
    /// Code 1.
    RadialAlongNormal,
    /// Code 2 (paper 000).
    AlongRadialAntinormal,
    /// Code 3 (paper 003).
    AlongAntinormalNadir,
}

impl From<FrameName> for Frame {
    fn from(f: FrameName) -> Frame {
        match f {
            FrameName::RadialAlongNormal => Frame::RadialAlongNormal,
            FrameName::AlongRadialAntinormal => Frame::AlongRadialAntinormal,
            FrameName::AlongAntinormalNadir => Frame::AlongAntinormalNadir,
        }
    }
}

/// The target's orbit: exactly one of the three size keys, and its eccentricity and true
/// anomaly at time 0 (default 0: a circular orbit).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Orbit {
    /// Mean motion [rad/s].
    pub mean_motion: Option<f64>,
    /// Orbital period [s].
    pub period: Option<f64>,
    /// Altitude above the Earth's equatorial radius [m] (two-body, `MU_EARTH`; the
    /// semi-major axis' altitude when eccentric).
    pub altitude: Option<f64>,
    /// Eccentricity (0 <= e <= 0.99): the truth's orbit and, unless a filter sets its own
    /// `eccentricity`, every filter's model.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub eccentricity: f64,
    /// True anomaly of the target at time 0 [rad].
    #[serde(default, skip_serializing_if = "is_zero")]
    pub true_anomaly0: f64,
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

impl Orbit {
    /// The mean motion, or which keys are wrong.
    pub fn mean_motion(&self) -> Result<f64, String> {
        match (self.mean_motion, self.period, self.altitude) {
            (Some(n), None, None) => Ok(n),
            (None, Some(p), None) => Ok(2.0 * std::f64::consts::PI / p),
            (None, None, Some(h)) => Ok((MU_EARTH / (R_EARTH + h).powi(3)).sqrt()),
            _ => Err("orbit: give exactly one of mean_motion, period, altitude".into()),
        }
    }
}

/// The true relative motion.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Truth {
    /// Initial relative state (x, y, z [m], vx, vy, vz [m/s]).
    pub initial_state: [f64; 6],
    /// 1-sigma per component of a random initial offset drawn per run (default 0: the
    /// truth starts exactly at `initial_state`).
    #[serde(default)]
    pub initial_sigma: [f64; 6],
    /// Chaser mass [kg].
    pub chaser_mass: f64,
    /// Continuous white-acceleration spectral density acting on the truth [m^2/s^3].
    #[serde(default)]
    pub accel_psd: f64,
    /// Discrete process-noise variances added per `simulation.step` (x .. vz, I/O frame),
    /// as papers 000 and 003 state their `Q`.
    #[serde(default)]
    pub process_noise: [f64; 6],
    /// Relative error `delta` of the true orbit rate, `w = w0 (1 + delta)` (paper 002).
    #[serde(default)]
    pub orbit_rate_error: OrbitRateError,
    /// The truth's dynamics: the CW model (default) or both spacecraft around the Earth.
    #[serde(default)]
    pub dynamics: TruthDynamics,
}

/// The truth's equations of motion.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum TruthDynamics {
    /// The CW model (exact transition), with the truth's process noise.
    #[default]
    Cw,
    /// Target and chaser propagated in Earth-centred inertial coordinates, point mass plus
    /// J2 (or point mass alone, `j2 = false`), by a 10th-order Gragg–Bulirsch–Stoer step of
    /// `substep` seconds; the target starts on the orbit of `orbit` at inclination
    /// `inclination_deg` (perigee at the ascending node, at `orbit.true_anomaly0`; a
    /// circular orbit at its ascending node); the relative state is taken in the target's
    /// local-vertical frame. The truth's `process_noise` is not used; its `accel_psd` is a
    /// random acceleration on the chaser, drawn per step (variance `accel_psd / step` per
    /// Hill axis, held over the step like the thrust).
    TwoBodyJ2 {
        /// Inclination of the target's orbit [deg].
        inclination_deg: f64,
        /// Integration step [s] (a divisor of `simulation.step`).
        substep: f64,
        /// Whether the Earth's J2 acts on both spacecraft (default true).
        #[serde(default = "yes")]
        j2: bool,
    },
}

/// How the true orbit rate differs from the nominal one.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum OrbitRateError {
    /// No error.
    #[default]
    None,
    /// The same `delta` in every run.
    Fixed {
        /// Relative error.
        delta: f64,
    },
    /// `delta` drawn uniformly in `[-bound, bound]` per run.
    Uniform {
        /// Bound `delta_bar`.
        bound: f64,
    },
}

/// The chaser's thrust.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Thrust {
    /// No thrust.
    #[default]
    None,
    /// Burns: constant forces over time windows.
    Burns {
        /// The burns.
        burns: Vec<Burn>,
        /// Whether the filters are told the thrust (false: unreported manoeuvres).
        #[serde(default = "yes")]
        reported: bool,
    },
    /// Known linear state feedback `F = K x` (force [N] from the I/O-frame state).
    Feedback {
        /// Gain `K` (3 rows of 6) [N/m, N/(m/s)].
        gain: [[f64; 6]; 3],
    },
}

fn yes() -> bool {
    true
}

/// One burn.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Burn {
    /// Start time [s] (inclusive).
    pub start: f64,
    /// Stop time [s] (exclusive).
    pub stop: f64,
    /// Force (I/O frame) [N].
    pub force: [f64; 3],
}

/// A sensor.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sensor {
    /// Measurement type.
    pub kind: SensorKind,
    /// Name in messages and tables (default: the kind's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Range noise scale [m] (radio, lidar).
    #[serde(default)]
    pub sigma_range: f64,
    /// Angle noise scale [deg] (radio, lidar; degrees in the file, radians inside).
    #[serde(default)]
    pub sigma_angle_deg: f64,
    /// Position noise scale per axis [m] (cartesian, gnss).
    #[serde(default)]
    pub sigma_position: f64,
    /// Velocity noise scale per axis [m/s] (gnss_velocity).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub sigma_velocity: f64,
    /// Sample period [s] (a multiple of `simulation.step`).
    pub period: f64,
    /// Windows without measurements.
    #[serde(default)]
    pub dropouts: Vec<Window>,
    /// The sensor measures only while the true range is at least this [m].
    #[serde(default, skip_serializing_if = "is_zero")]
    pub min_range: f64,
    /// The sensor measures only while the true range is below this [m] (default: no
    /// limit).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_range: Option<f64>,
    /// Noise density of the truth's measurements (the Kalman filters assume a Gaussian
    /// of the same variance).
    #[serde(default)]
    pub noise: NoiseModel,
}

/// Measurement types.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SensorKind {
    /// Radio range/azimuth/elevation (paper 000).
    Radio,
    /// Lidar range/azimuth/elevation (paper 003) — the same geometry.
    Lidar,
    /// Indirect Cartesian position (paper 002).
    Cartesian,
    /// Camera: the line of sight alone (azimuth and elevation as the radio's).
    Camera,
    /// Relative GNSS position (Cartesian, `sigma_position`).
    Gnss,
    /// Relative GNSS velocity (`sigma_velocity`).
    GnssVelocity,
}

impl SensorKind {
    /// The name in scenario files.
    pub fn name(self) -> &'static str {
        match self {
            SensorKind::Radio => "radio",
            SensorKind::Lidar => "lidar",
            SensorKind::Cartesian => "cartesian",
            SensorKind::Camera => "camera",
            SensorKind::Gnss => "gnss",
            SensorKind::GnssVelocity => "gnss_velocity",
        }
    }
}

impl Sensor {
    /// Its name (the kind's unless named).
    pub fn label(&self) -> String {
        self.name
            .clone()
            .unwrap_or_else(|| self.kind.name().to_string())
    }

    /// Whether it measures at the true canonical relative position `r` (range limits).
    pub fn in_range(&self, r: f64) -> bool {
        r >= self.min_range && self.max_range.is_none_or(|m| r < m)
    }

    /// The noise scales of its components, SI units (radians for angles), and their number.
    pub fn scales(&self) -> ([f64; 3], usize) {
        let a = self.sigma_angle_deg.to_radians();
        match self.kind {
            SensorKind::Radio | SensorKind::Lidar => ([self.sigma_range, a, a], 3),
            SensorKind::Cartesian | SensorKind::Gnss => ([self.sigma_position; 3], 3),
            SensorKind::Camera => ([a, a, 0.0], 2),
            SensorKind::GnssVelocity => ([self.sigma_velocity; 3], 3),
        }
    }

    /// Check the values that parse but make no sense; `key` prefixes the messages.
    fn validate(&self, key: &str, step: f64) -> Result<(), String> {
        let pos = |k: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(format!("{key}.{k} must be finite and > 0 (got {v})"))
            }
        };
        pos("period", self.period)?;
        let ratio = self.period / step;
        if (ratio - ratio.round()).abs() > 1e-9 || ratio.round() < 1.0 {
            return Err(format!(
                "{key}.period ({}) must be a whole multiple of simulation.step ({step})",
                self.period
            ));
        }
        match self.kind {
            SensorKind::Radio | SensorKind::Lidar => {
                pos("sigma_range", self.sigma_range)?;
                pos("sigma_angle_deg", self.sigma_angle_deg)?;
            }
            SensorKind::Camera => pos("sigma_angle_deg", self.sigma_angle_deg)?,
            SensorKind::Cartesian | SensorKind::Gnss => pos("sigma_position", self.sigma_position)?,
            SensorKind::GnssVelocity => pos("sigma_velocity", self.sigma_velocity)?,
        }
        if !(self.min_range.is_finite() && self.min_range >= 0.0) {
            return Err(format!("{key}.min_range must be finite and >= 0"));
        }
        if let Some(m) = self.max_range {
            if !(m > self.min_range) {
                return Err(format!(
                    "{key}.max_range ({m}) must exceed min_range ({})",
                    self.min_range
                ));
            }
        }
        self.noise.validate().map_err(|e| format!("{key}.{e}"))
    }
}

/// A time window `[start, stop)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Window {
    /// Start [s].
    pub start: f64,
    /// Stop [s].
    pub stop: f64,
}

/// Campaign settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Simulation {
    /// Duration [s].
    pub duration: f64,
    /// Filter and truth step [s].
    pub step: f64,
    /// Monte Carlo runs.
    pub runs: u32,
    /// Base seed; run `i` uses a seed derived from it (see `runner`).
    pub seed: u64,
    /// Errors are averaged from this time on [s].
    pub convergence_time: f64,
    /// Per-axis thresholds (position [m], velocity [m/s]) defining the convergence time.
    pub convergence_threshold: [f64; 2],
}

/// One filter to run: the navigator's parameters a `[[filter]]` table sets (keys of
/// relnav-core's parameter table, [`ScenarioParams`]: `kind`, `initial_state`,
/// `sigma_pos0`, `particles`, `threshold`, ...), and what only the evaluation engine knows
/// about a filter (its label, its per-step process noise, a model error, the particle
/// filters' research settings, the H-infinity designs of paper 002's reproduction).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FilterSpec {
    /// Row label.
    pub label: String,
    /// The navigator's parameters this filter sets; the others keep their defaults
    /// (`relnav_core::nav::PARAMS`).
    #[serde(flatten)]
    pub params: ScenarioParams,
    /// Discrete process-noise variances per step assumed (x .. vz, I/O frame), as papers
    /// 000 and 003 state their `Q`. For the AQUKF the velocity part divided by the step is
    /// the initial adaptive density.
    #[serde(default)]
    pub process_noise: [f64; 6],
    /// Relative error of the filter's orbit rate (a filter that does not know the model).
    #[serde(default)]
    pub orbit_rate_error: f64,
    /// With feedback thrust: whether the filter models the closed loop `Phi + Gamma K / m`
    /// (true) or ignores the thrust (false: it does not know the controller).
    #[serde(default = "yes")]
    pub knows_control: bool,
    /// Particle filters: `first_measurement` (the default with the moves, for every kind:
    /// [`relnav_core::estimators::pf::PfKind::default_init`]) or `prior` (paper 000
    /// literally; the default with `move = false`).
    #[serde(default)]
    pub init: Option<InitName>,
    /// Regularised PF: `gaussian` (default) or `epanechnikov`.
    #[serde(default)]
    pub kernel: Option<KernelName>,
    /// Unscented PF / CGA-PF: carry each particle's UKF covariance (van der Merwe
    /// literally) instead of restarting it from `Q` each step (default false).
    #[serde(default)]
    pub carry_covariance: bool,
    /// H-infinity (`kind = "hinf"`): `paper` (Theorem 1 / Corollary 1 on the closed loop
    /// `u = K x`, Euler as the paper; needs `thrust.kind = "feedback"`), `published` (the
    /// paper's printed `A_F, B_F, C_F`, T = 0.1 s), `observer` (open-loop observer form,
    /// the known thrust as feed-forward, gamma-optimal) or `mixed` (the same observer form,
    /// least H2 norm under `gamma <= hinf_gamma_factor * gamma_opt`; filter code 9's
    /// default). Default `paper`.
    #[serde(default)]
    pub hinf_design: Option<String>,
    /// H-infinity: uncertainty bound `delta_bar` of the design (default 0.05).
    #[serde(default)]
    pub hinf_delta_bar: Option<f64>,
    /// H-infinity: noise scalings `(b_pos, b_vel, d)` of the design (default the paper's
    /// 0.05, 0.001, 0.1). Zeros are derived as filter code 9 derives them: `b_pos = b_vel
    /// = 0` gives `B = Qd^(1/2)` of this filter's `accel_psd` and `process_noise`, `d = 0`
    /// gives `D = R^(1/2)` of the sensor noise this filter assumes (radio: the indirect
    /// position's covariance at its initial estimate).
    #[serde(default)]
    pub hinf_scalings: Option<[f64; 3]>,
    /// H-infinity, `mixed`: bound on gamma as a multiple of the gamma-optimal observer's
    /// (default 1.5).
    #[serde(default)]
    pub hinf_gamma_factor: Option<f64>,
    /// H-infinity, `observer` and `mixed`: start with the Kalman gain of the design's noise
    /// model and hand over to the designed gain ([`relnav_core::hinf::HinfAcquisition`]).
    /// Default false here (the gamma-optimal rows of paper 002's reproduction); filter
    /// code 9's default is true.
    #[serde(default)]
    pub hinf_acquisition: bool,
}

/// The `[[filter]]` keys the evaluation engine reads itself (besides [`ScenarioParams`]'s).
pub const FILTER_OWN_KEYS: [&str; 11] = [
    "label",
    "process_noise",
    "orbit_rate_error",
    "knows_control",
    "init",
    "kernel",
    "carry_covariance",
    "hinf_design",
    "hinf_delta_bar",
    "hinf_scalings",
    "hinf_gamma_factor",
];

/// The keys of relnav-core's parameter table a `[[filter]]` table must set: which filter,
/// and its initial estimate and uncertainty.
pub const FILTER_REQUIRED_KEYS: [&str; 4] = ["kind", "initial_state", "sigma_pos0", "sigma_vel0"];

/// The navigator's parameters a `[[filter]]` table sets, by their scenario keys
/// ([`relnav_core::params::Fronts::scenario`]): a code by its name (`kind = "ukf"`,
/// `resampler = "multinomial"`), an array parameter as an array, a flag as a boolean. A key
/// that is neither one of these nor one of the engine's own ([`FILTER_OWN_KEYS`]) is an
/// error naming it and the keys expected.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ScenarioParams {
    /// (index in `PARAMS`, the elements' values), in the order the file gave them.
    set: Vec<(usize, Vec<Value>)>,
}

impl ScenarioParams {
    /// Every key this struct takes, in table order.
    pub fn keys() -> impl Iterator<Item = &'static str> {
        PARAMS.iter().filter_map(|p| p.fronts.scenario)
    }

    /// The values set for the parameter named `name` (its field name), if any.
    pub fn get(&self, name: &str) -> Option<&[Value]> {
        self.set
            .iter()
            .find(|(k, _)| PARAMS.get(*k).is_some_and(|p| p.name == name))
            .map(|(_, v)| v.as_slice())
    }

    /// Whether the file set the scenario key `key`.
    pub fn has(&self, key: &str) -> bool {
        self.set
            .iter()
            .any(|(k, _)| PARAMS.get(*k).and_then(|p| p.fronts.scenario) == Some(key))
    }

    /// The defaults with these values applied (values a configuration cannot hold are
    /// left at their defaults; [`Scenario::validate`] names them).
    pub fn resolved(&self) -> NavConfig {
        let mut c = NavConfig::default();
        for (k, vals) in &self.set {
            let Some(p) = PARAMS.get(*k) else { continue };
            for (i, v) in vals.iter().enumerate() {
                let _ = c.assign(p, i, *v);
            }
        }
        c
    }

    /// Set the parameter named `name` (its field name) to `values` (one per element),
    /// replacing what the file gave.
    pub fn set(&mut self, name: &str, values: &[Value]) -> Result<(), String> {
        let (k, p) = PARAMS
            .iter()
            .enumerate()
            .find(|(_, p)| p.name == name)
            .ok_or_else(|| format!("no parameter named {name}"))?;
        if values.len() != p.elements.len() {
            return Err(format!("{name} has {} elements", p.elements.len()));
        }
        self.set.retain(|(j, _)| *j != k);
        self.set.push((k, values.to_vec()));
        Ok(())
    }

    /// Apply the values to `c`; the message names the key.
    pub fn apply(&self, c: &mut NavConfig) -> Result<(), String> {
        for (k, vals) in &self.set {
            let Some(p) = PARAMS.get(*k) else { continue };
            for (i, v) in vals.iter().enumerate() {
                c.assign(p, i, *v).map_err(|e| e.message)?;
            }
        }
        Ok(())
    }

    /// The filter code (`kind`; the default filter when absent).
    pub fn kind(&self) -> FilterKind {
        self.resolved().filter
    }

    fn parse(key: &str, v: &toml::Value) -> Result<(usize, Vec<Value>), String> {
        let (k, p) = PARAMS
            .iter()
            .enumerate()
            .find(|(_, p)| p.fronts.scenario == Some(key))
            .ok_or_else(|| {
                let expected: Vec<String> = FILTER_OWN_KEYS
                    .iter()
                    .copied()
                    .chain(Self::keys())
                    .map(|k| format!("`{k}`"))
                    .collect();
                format!(
                    "unknown field `{key}`, expected one of {}",
                    expected.join(", ")
                )
            })?;
        let scalar = |x: &toml::Value| -> Result<Value, String> {
            match (p.kind, x) {
                (Kind::Real, toml::Value::Float(f)) => Ok(Value::Real(*f)),
                (Kind::Real, toml::Value::Integer(i)) => Ok(Value::Real(*i as f64)),
                (Kind::Count | Kind::Seed, toml::Value::Integer(i)) => Ok(Value::Int(*i)),
                (Kind::Bool, toml::Value::Boolean(b)) => Ok(Value::Int(i64::from(*b))),
                (Kind::Code(list), toml::Value::String(name)) => list
                    .by_name(name)
                    .map(|it| Value::Int(i64::from(it.code)))
                    .ok_or_else(|| {
                        format!(
                            "{key} = \"{name}\" is not available (implemented: {})",
                            list.names()
                        )
                    }),
                (kind, other) => Err(format!(
                    "{key} must be {} (got {other})",
                    match kind {
                        Kind::Real => "a number",
                        Kind::Count | Kind::Seed => "an integer",
                        Kind::Bool => "true or false",
                        Kind::Code(_) => "a name",
                    }
                )),
            }
        };
        let values = if p.elements.len() == 1 {
            vec![scalar(v)?]
        } else {
            match v {
                toml::Value::Array(a) if a.len() == p.elements.len() => {
                    a.iter().map(scalar).collect::<Result<Vec<_>, _>>()?
                }
                other => {
                    return Err(format!(
                        "{key} must be an array of {} (got {other})",
                        p.elements.len()
                    ))
                }
            }
        };
        Ok((k, values))
    }
}

impl<'de> Deserialize<'de> for ScenarioParams {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let table = toml::Table::deserialize(d)?;
        let mut set = Vec::new();
        for (key, v) in &table {
            set.push(Self::parse(key, v).map_err(serde::de::Error::custom)?);
        }
        Ok(Self { set })
    }
}

impl Serialize for ScenarioParams {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(Some(self.set.len()))?;
        for (k, vals) in &self.set {
            let Some(p) = PARAMS.get(*k) else { continue };
            let Some(key) = p.fronts.scenario else {
                continue;
            };
            let one = |v: &Value| -> toml::Value {
                match (p.kind, v) {
                    (Kind::Code(list), Value::Int(c)) => {
                        list.item(*c).map_or(toml::Value::Integer(*c), |it| {
                            toml::Value::String(it.name.to_string())
                        })
                    }
                    (Kind::Bool, Value::Int(b)) => toml::Value::Boolean(*b != 0),
                    (_, Value::Int(i)) => toml::Value::Integer(*i),
                    (_, Value::Real(x)) => toml::Value::Float(*x),
                }
            };
            if p.elements.len() == 1 {
                if let Some(v) = vals.first() {
                    m.serialize_entry(key, &one(v))?;
                }
            } else {
                let a: Vec<toml::Value> = vals.iter().map(one).collect();
                m.serialize_entry(key, &a)?;
            }
        }
        m.end()
    }
}

/// Particle initialisation names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum InitName {
    /// From the first measurement.
    FirstMeasurement,
    /// From the prior.
    Prior,
}

/// Kernel names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum KernelName {
    /// Gaussian.
    Gaussian,
    /// Epanechnikov.
    Epanechnikov,
}

impl FilterSpec {
    /// The filter code of `kind`.
    pub fn kind(&self) -> FilterKind {
        self.params.kind()
    }

    /// The navigator configuration of this filter in `scenario`: the scenario's frame, the
    /// filter's orbit rate `mean_motion` (with its `orbit_rate_error`), the orbit's
    /// eccentricity and true anomaly (a table's `eccentricity = 0.0` gives a CW-model
    /// filter on an eccentric orbit), the per-step
    /// process noise as rates (`process_noise / step`; for the AQUKF the velocity part is
    /// its initial adaptive density), the H-infinity settings of this table, then every
    /// parameter the table sets. Its sensor settings are the navigator's defaults: the
    /// engine gives each filter its measurement model itself; only an H-infinity filter
    /// of a scenario with `[[sensors]]` takes their noise (`sigma_range`, `sigma_angle` of
    /// the first radio or lidar, `sigma_camera`, `sigma_gnss`, `sigma_gnss_velocity`, each
    /// the Gaussian of its density's variance), from which the factory derives its design's
    /// measurement noise for `hinf_sensors`.
    pub fn nav_config(&self, scenario: &Scenario, mean_motion: f64) -> Result<NavConfig, String> {
        let step = scenario.simulation.step;
        let mut c = NavConfig {
            frame: scenario.io_frame(),
            mean_motion,
            eccentricity: scenario.orbit.eccentricity,
            true_anomaly0: scenario.orbit.true_anomaly0,
            chaser_mass: scenario.truth.chaser_mass,
            hinf_period: step,
            hinf_acquisition: self.hinf_acquisition,
            ..NavConfig::default()
        };
        for i in 0..3 {
            c.q_pos[i] = self.process_noise[i] / step;
            c.q_vel[i] = self.process_noise[i + 3] / step;
        }
        if let Some(d) = self.hinf_delta_bar {
            c.hinf_delta_bar = d;
        }
        if let Some(g) = self.hinf_gamma_factor {
            c.hinf_gamma_factor = g;
        }
        if self.hinf_design.as_deref() == Some("observer") {
            c.hinf_design = HinfDesignKind::GammaOptimal;
        }
        let sc = self.hinf_scalings.unwrap_or([0.05, 0.001, 0.1]);
        (c.hinf_b_pos, c.hinf_b_vel, c.hinf_d) = (sc[0], sc[1], sc[2]);
        self.params.apply(&mut c)?;
        if c.filter == FilterKind::Hinf {
            let mut radio = false;
            for p in &scenario.sensors {
                let (sc, _) = p.scales();
                let f = p.noise.variance_factor().sqrt();
                match p.kind {
                    SensorKind::Radio | SensorKind::Lidar if !radio => {
                        radio = true;
                        (c.sigma_range, c.sigma_angle) = (sc[0] * f, sc[1] * f);
                    }
                    SensorKind::Camera => c.sigma_camera = sc[0] * f,
                    SensorKind::Gnss => c.sigma_gnss = sc[0] * f,
                    SensorKind::GnssVelocity => c.sigma_gnss_velocity = sc[0] * f,
                    _ => {}
                }
            }
        }
        if c.robust_radio() {
            // the robust EKF, and the particle prior's terms, update with the
            // [sensor]'s density (its variance is the filters' R)
            if let Some(p) = &scenario.sensor {
                (c.noise_model, c.noise_zeta, c.noise_scale, c.noise_dof) = match p.noise {
                    NoiseModel::Mixture { zeta, scale } => {
                        (NoiseKind::Mixture, zeta, scale, c.noise_dof)
                    }
                    NoiseModel::StudentT { dof } => {
                        (NoiseKind::StudentT, c.noise_zeta, c.noise_scale, dof)
                    }
                    // no robust update: the EKF's
                    _ => (
                        NoiseKind::Gaussian,
                        c.noise_zeta,
                        c.noise_scale,
                        c.noise_dof,
                    ),
                };
            }
        }
        Ok(c)
    }

    /// The settings of this filter that its navigator configuration does not hold.
    pub fn filter_options(&self) -> FilterOptions {
        FilterOptions {
            pf_init: self.init.map(|i| match i {
                InitName::FirstMeasurement => PfInit::FirstMeasurement,
                InitName::Prior => PfInit::Prior,
            }),
            pf_kernel: match self.kernel {
                Some(KernelName::Epanechnikov) => Kernel::Epanechnikov,
                _ => Kernel::Gaussian,
            },
            pf_carry_covariance: self.carry_covariance,
            hinf: None,
        }
    }
}

/// A published figure.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Published {
    /// Filter label it belongs to (may be a filter not run here yet).
    pub filter: String,
    /// The figure, as text.
    pub figure: String,
}

impl Scenario {
    /// Parse a scenario from TOML text; errors name the key and the line.
    pub fn from_toml(text: &str) -> Result<Scenario, String> {
        let s: Scenario = toml::from_str(text).map_err(|e| e.to_string())?;
        s.validate()?;
        Ok(s)
    }

    /// Serialise back to TOML.
    pub fn to_toml(&self) -> Result<String, String> {
        toml::to_string(self).map_err(|e| e.to_string())
    }

    /// Check values that parse but make no sense; the message names the key.
    pub fn validate(&self) -> Result<(), String> {
        let pos = |k: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(format!("{k} must be finite and > 0 (got {v})"))
            }
        };
        let n = self.orbit.mean_motion()?;
        pos("orbit (mean motion)", n)?;
        let e = self.orbit.eccentricity;
        if !(0.0..=relnav_core::dynamics::MAX_ECCENTRICITY).contains(&e) {
            return Err(format!(
                "orbit.eccentricity must lie in [0, 0.99] (got {e})"
            ));
        }
        if !self.orbit.true_anomaly0.is_finite() {
            return Err("orbit.true_anomaly0 must be finite".into());
        }
        if e > 0.0 && self.truth.dynamics == TruthDynamics::Cw {
            return Err(
                "orbit.eccentricity > 0 needs truth.dynamics = two_body_j2 (the truth is \
                 integrated as two-body motion, independent of the filters' linear model)"
                    .into(),
            );
        }
        pos("truth.chaser_mass", self.truth.chaser_mass)?;
        pos("simulation.duration", self.simulation.duration)?;
        pos("simulation.step", self.simulation.step)?;
        let step = self.simulation.step;
        if let Some(p) = &self.sensor {
            if !matches!(
                p.kind,
                SensorKind::Radio | SensorKind::Lidar | SensorKind::Cartesian
            ) {
                return Err(format!(
                    "sensor.kind = \"{}\": the first sensor is a radio, lidar or cartesian \
                     one; give others as [[sensors]]",
                    p.kind.name()
                ));
            }
            p.validate("sensor", step)?;
        }
        for (i, x) in self.sensors.iter().enumerate() {
            x.validate(&format!("sensors[{i}]"), step)?;
        }
        if self.sensor.is_none() && self.sensors.is_empty() {
            return Err("give a [sensor] or at least one [[sensors]]".into());
        }
        if self.simulation.runs == 0 {
            return Err("simulation.runs must be >= 1".into());
        }
        if self
            .truth
            .process_noise
            .iter()
            .any(|q| !(q.is_finite() && *q >= 0.0))
        {
            return Err("truth.process_noise entries must be finite and >= 0".into());
        }
        if let TruthDynamics::TwoBodyJ2 { substep, .. } = self.truth.dynamics {
            pos("truth.dynamics.substep", substep)?;
            let r = self.simulation.step / substep;
            if (r - r.round()).abs() > 1e-9 || r.round() < 1.0 {
                return Err(format!(
                    "truth.dynamics.substep ({substep}) must divide simulation.step ({})",
                    self.simulation.step
                ));
            }
            if matches!(self.thrust, Thrust::Feedback { .. }) {
                return Err("truth.dynamics: two_body_j2 does not support feedback thrust".into());
            }
            if !matches!(self.truth.orbit_rate_error, OrbitRateError::None) {
                return Err("truth.dynamics: two_body_j2 takes no orbit_rate_error".into());
            }
        }
        if self.filters.is_empty() {
            return Err("at least one [[filter]] is required".into());
        }
        for f in &self.filters {
            let missing: Vec<&str> = FILTER_REQUIRED_KEYS
                .iter()
                .copied()
                .filter(|k| !f.params.has(k))
                .collect();
            if !missing.is_empty() {
                return Err(format!(
                    "filter \"{}\": missing key(s) {}",
                    f.label,
                    missing.join(", ")
                ));
            }
            let n = self.orbit.mean_motion()? * (1.0 + f.orbit_rate_error);
            f.nav_config(self, n)
                .and_then(|c| c.validate().map_err(|e| String::from(e.message)))
                .map_err(|e| format!("filter \"{}\": {e}", f.label))?;
        }
        Ok(())
    }

    /// The I/O frame.
    pub fn io_frame(&self) -> Frame {
        self.frame.into()
    }

    /// Truth's discrete process noise of one step (canonical frame), `Qd` of the
    /// acceleration density plus the diagonal per-step variances.
    pub fn truth_q(&self, van_loan: Mat6) -> Mat6 {
        van_loan
            + self
                .io_frame()
                .cov_to_canonical(&Mat6::from_diagonal(&State::from_row_slice(
                    &self.truth.process_noise,
                )))
    }

    /// Feedback gain as acceleration per canonical state, `T^T K T6 / m`, if any.
    pub fn feedback_accel_gain(&self) -> Option<nalgebra::SMatrix<f64, 3, 6>> {
        match &self.thrust {
            Thrust::Feedback { gain } => {
                let f = self.io_frame();
                let k = nalgebra::SMatrix::<f64, 3, 6>::from_fn(|i, j| gain[i][j]);
                let kc: nalgebra::SMatrix<f64, 3, 6> =
                    f.rotation().transpose() * k * f.rotation6() / self.truth.chaser_mass;
                Some(kc)
            }
            _ => None,
        }
    }

    /// The filters' assumed measurement covariance diagonal of `[sensor]` (variance-matched
    /// to the truth's noise model); zeros without one.
    pub fn filter_r_diag(&self) -> [f64; 3] {
        match &self.sensor {
            Some(p) => {
                let vf = p.noise.variance_factor();
                p.scales().0.map(|s| s * s * vf)
            }
            None => [0.0; 3],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MINIMAL: &str = r#"
name = "t"
title = "test"
frame = "radial_along_normal"
[orbit]
period = 7200.0
[truth]
initial_state = [1.0, 2.0, 3.0, 0.0, 0.0, 0.0]
chaser_mass = 100.0
[sensor]
kind = "radio"
sigma_range = 0.5
sigma_angle_deg = 0.01
period = 1.0
[simulation]
duration = 10.0
step = 1.0
runs = 2
seed = 1
convergence_time = 5.0
convergence_threshold = [1.0, 0.1]
[[filter]]
label = "EKF"
kind = "ekf"
initial_state = [1.0, 2.0, 3.0, 0.0, 0.0, 0.0]
sigma_pos0 = 1.0
sigma_vel0 = 0.1
"#;

    #[test]
    fn round_trip() {
        let s = Scenario::from_toml(MINIMAL).unwrap();
        let back = Scenario::from_toml(&s.to_toml().unwrap()).unwrap();
        assert_eq!(s, back);
        assert_eq!(s.thrust, Thrust::None);
        assert_eq!(
            s.sensor.as_ref().map(|p| p.noise),
            Some(NoiseModel::Gaussian)
        );
    }

    #[test]
    fn wrong_key_is_named() {
        let bad = MINIMAL.replace("sigma_range", "sigma_rnage");
        let e = Scenario::from_toml(&bad).unwrap_err();
        assert!(e.contains("sigma_rnage"), "{e}");
        let bad = MINIMAL.replace("kind = \"radio\"", "kind = \"sonar\"");
        let e = Scenario::from_toml(&bad).unwrap_err();
        assert!(e.contains("sonar") && e.contains("radio"), "{e}");
        let bad = MINIMAL.replace("period = 7200.0", "period = 7200.0\naltitude = 4e5");
        assert!(Scenario::from_toml(&bad)
            .unwrap_err()
            .contains("exactly one"));
        let bad = MINIMAL.replace("kind = \"ekf\"", "kind = \"kalman\"");
        let e = Scenario::from_toml(&bad).unwrap_err();
        assert!(e.contains("kalman") && e.contains("ekf, ukf"), "{e}");
        let bad = MINIMAL.replace("kind = \"ekf\"", "kind = \"pf\"\nparticles = 0");
        let e = Scenario::from_toml(&bad).unwrap_err();
        assert!(e.contains("particles"), "{e}");
    }

    #[test]
    fn sensor_sets() {
        const CAMERA: &str =
            "[[sensors]]\nkind = \"camera\"\nsigma_angle_deg = 0.05\nperiod = 2.0\n";
        let with = |extra: &str| MINIMAL.replace("[simulation]", &format!("{extra}[simulation]"));
        // further sensors round-trip; a scenario may have them alone
        let s = Scenario::from_toml(&with(CAMERA)).unwrap();
        assert_eq!(s.sensors.len(), 1);
        let (scales, n) = s.sensors[0].scales();
        assert_eq!(
            (scales[0], scales[1], n),
            (0.05f64.to_radians(), 0.05f64.to_radians(), 2)
        );
        assert_eq!(Scenario::from_toml(&s.to_toml().unwrap()).unwrap(), s);
        let radio =
            "[sensor]\nkind = \"radio\"\nsigma_range = 0.5\nsigma_angle_deg = 0.01\nperiod = 1.0\n";
        let alone = with(CAMERA).replace(radio, "");
        assert!(Scenario::from_toml(&alone).unwrap().sensor.is_none());
        let e = Scenario::from_toml(&MINIMAL.replace(radio, "")).unwrap_err();
        assert!(e.contains("[[sensors]]"), "{e}");
        // the first sensor is the papers' kind; values that make no sense are named
        let e = Scenario::from_toml(&MINIMAL.replace("kind = \"radio\"", "kind = \"camera\""))
            .unwrap_err();
        assert!(
            e.contains("sensor.kind") && e.contains("[[sensors]]"),
            "{e}"
        );
        let e = Scenario::from_toml(&with(&CAMERA.replace("sigma_angle_deg = 0.05\n", "")))
            .unwrap_err();
        assert!(e.contains("sensors[0].sigma_angle_deg"), "{e}");
        let e = Scenario::from_toml(&with(&CAMERA.replace("period = 2.0", "period = 2.5")))
            .unwrap_err();
        assert!(e.contains("sensors[0].period"), "{e}");
        let e = Scenario::from_toml(&with(&format!(
            "{CAMERA}min_range = 10.0\nmax_range = 5.0\n"
        )))
        .unwrap_err();
        assert!(e.contains("sensors[0].max_range"), "{e}");
        let gated = Scenario::from_toml(&with(&format!(
            "{CAMERA}min_range = 10.0\nmax_range = 50.0\n"
        )))
        .unwrap();
        let c = &gated.sensors[0];
        assert!(!c.in_range(9.9) && c.in_range(10.0) && c.in_range(49.9) && !c.in_range(50.0));
    }
}
