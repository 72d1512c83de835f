//! One Monte Carlo run: truth, measurements and every filter of a scenario, scored at
//! each time step. Everything derived from the scenario once lives in [`Prepared`].
//!
//! Timeline of a run with step `h` and `K = duration / h` steps, `t_k = k h`:
//! * truth: `x_(k+1) = Phi_true x_k + Gamma_true a_k + w_k`, `w_k ~ N(0, Q_true)` with
//!   `a_k` the thrust acceleration held over `[t_k, t_(k+1))` (burns, or the feedback
//!   `K x_k / m` on the true state — a sampled-data controller);
//! * each sensor (`[sensor]`, then the `[[sensors]]` in file order) measures at `t_k` when
//!   `t_k` is a multiple of its period, not in one of its dropout windows and the true
//!   range is within its limits, drawn from its noise model;
//! * each filter, at `t_k`, applies the measurements (if any) in that order, is **scored**
//!   there (the a posteriori estimate; the prediction when there was no measurement), then
//!   predicts to `t_(k+1)` with the thrust it is told about.

use crate::scenario::{Scenario, Sensor as SensorSpec, SensorKind, Thrust, TruthDynamics};
use nalgebra::SMatrix;
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use relnav_core::dynamics::{CwModel, DiscreteModel, Discretization, Dynamics, RelativeDynamics};
use relnav_core::estimators::Estimator;
use relnav_core::nav::{
    build_filter_with, AnyFilter, FilterKind, FilterOptions, Named, NavConfig, NavSensor,
};
use relnav_core::noise::NoiseModel;
use relnav_core::sensors::{
    add_noise, AngleTrig, CameraSensor, CartesianSensor, Geometry, MeasurementModel, Modelled,
    RadioSensor, Sensor, SensorNoise, VelocitySensor,
};
use relnav_core::types::{Mat3, Mat6, State, Vec3};
use std::sync::Arc;

/// A sensor of either kind.
#[derive(Debug, Clone, Copy)]
pub enum AnySensor {
    /// Range/azimuth/elevation.
    Radio(RadioSensor),
    /// Cartesian position.
    Cartesian(CartesianSensor),
}

impl MeasurementModel for AnySensor {
    fn predict(&self, r: &Vec3) -> Option<Vec3> {
        match self {
            AnySensor::Radio(s) => s.h(r),
            AnySensor::Cartesian(s) => s.predict(r),
        }
    }
    fn linearize(&self, r: &Vec3) -> Result<Geometry, relnav_core::sensors::GeometryError> {
        match self {
            AnySensor::Radio(s) => s.geometry(r),
            AnySensor::Cartesian(s) => s.linearize(r),
        }
    }
    fn diff(&self, z: &Vec3, z_hat: &Vec3) -> Vec3 {
        match self {
            AnySensor::Radio(_) => RadioSensor::residual(z, z_hat),
            AnySensor::Cartesian(s) => s.diff(z, z_hat),
        }
    }
    fn residuals_at<const B: usize>(
        &self,
        z: &Vec3,
        trig: &relnav_core::sensors::AngleTrig,
        r: &[[f64; B]; 3],
        n: usize,
        d: &mut [[f64; B]; 3],
        ok: &mut [bool; B],
    ) {
        match self {
            AnySensor::Radio(s) => s.residuals_at(z, trig, r, n, d, ok),
            AnySensor::Cartesian(s) => s.residuals_at(z, trig, r, n, d, ok),
        }
    }
    fn weighted_mean(&self, w: &[f64], zs: &[Vec3]) -> Vec3 {
        match self {
            AnySensor::Radio(s) => s.weighted_mean(w, zs),
            AnySensor::Cartesian(s) => s.weighted_mean(w, zs),
        }
    }
    fn noise_cov(&self) -> Mat3 {
        match self {
            AnySensor::Radio(s) => s.noise_cov(),
            AnySensor::Cartesian(s) => s.noise_cov(),
        }
    }
    fn invert(&self, z: &Vec3) -> Option<Vec3> {
        match self {
            AnySensor::Radio(s) => s.invert(z),
            AnySensor::Cartesian(s) => s.invert(z),
        }
    }
    fn residual_at(&self, z: &Vec3, trig: &AngleTrig, r: &Vec3) -> Option<Vec3> {
        match self {
            AnySensor::Radio(s) => s.residual_at(z, trig, r),
            AnySensor::Cartesian(s) => s.residual_at(z, trig, r),
        }
    }
    fn unscented(&self, r: &[Vec3], wm: &[f64], dz: &mut [Vec3]) -> Option<Vec3> {
        match self {
            AnySensor::Radio(s) => s.unscented(r, wm, dz),
            AnySensor::Cartesian(s) => s.unscented(r, wm, dz),
        }
    }
    fn azimuth_usable(&self, r: &Vec3) -> Result<bool, relnav_core::sensors::GeometryError> {
        match self {
            AnySensor::Radio(s) => s.azimuth_usable(r),
            AnySensor::Cartesian(s) => s.azimuth_usable(r),
        }
    }
    fn unscented_seven(
        &self,
        z: &Vec3,
        trig: &AngleTrig,
        c: &Vec3,
        o: &[Vec3; 3],
        wm: (f64, f64),
        dz: &mut [Vec3; 7],
    ) -> Option<(Vec3, bool)> {
        match self {
            AnySensor::Radio(s) => s.unscented_seven(z, trig, c, o, wm, dz),
            AnySensor::Cartesian(s) => s.unscented_seven(z, trig, c, o, wm, dz),
        }
    }
}

/// A filter ready to be instantiated for each run.
#[derive(Debug, Clone)]
pub struct PreparedFilter {
    /// Label.
    pub label: String,
    /// Kind name (the filter code's).
    pub kind: String,
    /// Initial estimate (canonical).
    pub x0: State,
    /// Initial covariance.
    pub p0: Mat6,
    /// The filter's discrete model of the first step (closed loop when it knows the
    /// controller); every step's for a time-invariant model ([`PreparedFilter::model_at`]).
    pub model: DiscreteModel,
    /// The filter's relative dynamics (the elliptic model's steps differ along the orbit).
    pub dynamics: Dynamics,
    /// The per-step process noise added to the dynamics' (the table's `process_noise`).
    pub extra_q: Mat6,
    /// The feedback gain the filter models in closed loop, if it knows the controller.
    pub control: Option<SMatrix<f64, 3, 6>>,
    /// Whether it is told the burns' thrust.
    pub told_thrust: bool,
    /// Its measurement model of `[sensor]` (variance-matched Gaussian), if the scenario
    /// has one.
    pub sensor: Option<AnySensor>,
    /// Its configuration (the filter factory's input; the seed is each run's).
    pub config: NavConfig,
    /// What the configuration does not hold: the particle filters' research settings and,
    /// for `kind = "hinf"`, the filter designed once per scenario.
    pub options: FilterOptions,
    /// H-infinity observer under feedback thrust: the applied thrust `K x` is known and fed
    /// forward (the FMU's case); the Kalman filters instead model the closed loop.
    pub feedforward_feedback: bool,
}

impl PreparedFilter {
    /// The filter's discrete model of the step from `t` over `dt` (the prepared one for a
    /// time-invariant model).
    pub fn model_at(&self, t: f64, dt: f64) -> DiscreteModel {
        if self.dynamics.time_invariant() {
            return self.model;
        }
        let mut m = self.dynamics.step(
            t,
            dt,
            &(Mat3::identity() * self.config.accel_psd),
            self.config.discretization,
        );
        m.q += self.extra_q;
        if let Some(k) = &self.control {
            m.phi += m.gamma * k;
        }
        m
    }

    /// A fresh estimator at the initial estimate, from the one filter factory
    /// ([`relnav_core::nav::build_filter_with`]); `seed` seeds a particle filter.
    pub fn instantiate(&self, seed: u64) -> Result<AnyFilter, String> {
        let cfg = NavConfig {
            seed,
            ..self.config
        };
        build_filter_with(&cfg, &self.options).map_err(|e| e.message.into())
    }
}

/// Everything a run needs, derived once from a scenario.
#[derive(Debug, Clone)]
pub struct Prepared {
    /// The scenario.
    pub scenario: Scenario,
    /// Nominal mean motion [rad/s].
    pub n0: f64,
    /// Step [s].
    pub dt: f64,
    /// Number of steps (times are `0..=steps`).
    pub steps: usize,
    /// Whether `[sensor]` is scheduled to measure at each time (its period and dropouts;
    /// all false without one).
    pub measured: Vec<bool>,
    /// Burn acceleration (canonical) held over `[t_k, t_(k+1))`.
    pub burn_accel: Vec<Vec3>,
    /// Feedback acceleration gain (canonical), if any.
    pub feedback: Option<SMatrix<f64, 3, 6>>,
    /// Square root of the truth's process-noise covariance (canonical) for the nominal
    /// rate (recomputed per run when the rate is random).
    pub truth_q_sqrt: Mat6,
    /// Truth's process noise covariance for the nominal rate.
    pub truth_q: Mat6,
    /// The truth's measurement noise model of `[sensor]`.
    pub noise: NoiseModel,
    /// Noise scales per measurement component of `[sensor]`.
    pub noise_sigma: [f64; 3],
    /// The noise-free geometry of `[sensor]` in the truth, if the scenario has one.
    pub truth_sensor: Option<AnySensor>,
    /// The `[[sensors]]`, in file order.
    pub sensors: Vec<PreparedSensor>,
    /// Filters.
    pub filters: Vec<PreparedFilter>,
}

/// The noise-free geometry of a `[[sensors]]` entry (canonical state in, I/O-frame
/// reading out).
#[derive(Debug, Clone, Copy)]
pub enum SensorGeometry {
    /// Range, azimuth, elevation (radio, lidar).
    Radio(RadioSensor),
    /// Azimuth, elevation (camera).
    Camera(CameraSensor),
    /// Position (relative GNSS).
    Position(CartesianSensor),
    /// Velocity (relative GNSS).
    Velocity(VelocitySensor),
}

fn position(x: &State) -> Vec3 {
    x.fixed_rows::<3>(0).into_owned()
}

impl SensorGeometry {
    /// A reading of the true canonical state `x` with noise of density `noise` and scales
    /// `s` (`ar`: the AR(1) model's previous samples); azimuths wrapped to `[0, 2 pi)`,
    /// elevations clamped to `[-pi/2, pi/2]`, ranges to `>= 0`. `None` at zero range.
    fn measure(
        &self,
        x: &State,
        noise: &NoiseModel,
        s: &[f64; 3],
        ar: &mut [f64; 3],
        rng: &mut ChaCha8Rng,
    ) -> Option<[f64; 3]> {
        let s3 = [s[0], s[1], s[2]];
        match self {
            SensorGeometry::Radio(m) => m
                .measure_with(&position(x), noise, ar, rng)
                .map(|z| [z.x, z.y, z.z]),
            SensorGeometry::Camera(m) => {
                let mut ar2 = [ar[0], ar[1]];
                let z = m.measure_with(x, noise, &[s[0], s[1]], &mut ar2, rng);
                (ar[0], ar[1]) = (ar2[0], ar2[1]);
                z.map(|z| [z[0], z[1], 0.0])
            }
            SensorGeometry::Position(m) => m
                .predict(&position(x))
                .map(|z| add_noise(&z, noise, &s3, ar, rng)),
            SensorGeometry::Velocity(m) => m.measure(x).map(|z| add_noise(&z, noise, &s3, ar, rng)),
        }
    }

    /// `H^T diag(f / s_i^2) H` at the true canonical state `x` (zero where the geometry
    /// is singular): the Fisher information of one reading with noise scales `s` and the
    /// density's Fisher factor `f`.
    pub fn information(&self, x: &State, s: &[f64; 3], f: f64) -> Mat6 {
        fn info<const D: usize>(h: &SMatrix<f64, D, 6>, s: &[f64; 3], f: f64) -> Mat6 {
            let iv =
                SMatrix::<f64, D, D>::from_fn(|i, j| if i == j { f / (s[i] * s[i]) } else { 0.0 });
            h.transpose() * iv * h
        }
        let j = match self {
            SensorGeometry::Radio(m) => m.linearize(&position(x)).map(|g| info(&g.h, s, f)),
            SensorGeometry::Camera(m) => m.linearize(x).map(|g| info(&g.h, s, f)),
            SensorGeometry::Position(m) => m.linearize(&position(x)).map(|g| info(&g.h, s, f)),
            SensorGeometry::Velocity(m) => m.linearize(x).map(|g| info(&g.h, s, f)),
        };
        j.unwrap_or_else(|_| Mat6::zeros())
    }
}

/// A `[[sensors]]` entry, prepared: its schedule, its truth and the filters' update.
#[derive(Debug, Clone)]
pub struct PreparedSensor {
    /// The scenario's entry.
    pub spec: SensorSpec,
    /// Whether it is scheduled to measure at each time (period, dropouts; the range
    /// limits are checked on each run's truth).
    pub measured: Vec<bool>,
    /// The truth's noise-free geometry.
    pub geometry: SensorGeometry,
    /// Noise scales per component (SI units, radians).
    pub scales: [f64; 3],
    /// The filters' update with a reading (every filter through the generic sensor path;
    /// the Kalman filters assume the Gaussian of the noise's variance, the particle
    /// filters weigh with the density itself).
    pub nav: Arc<dyn NavSensor>,
}

impl PreparedSensor {
    fn new(spec: &SensorSpec, frame: relnav_core::frames::Frame, measured: Vec<bool>) -> Self {
        let (scales, _) = spec.scales();
        let name = spec.label();
        let noise = spec.noise;
        let n3 = SensorNoise {
            model: noise,
            scales,
        };
        let (geometry, nav): (SensorGeometry, Arc<dyn NavSensor>) = match spec.kind {
            SensorKind::Radio | SensorKind::Lidar => {
                let m = RadioSensor::new(frame, scales[0], scales[1]);
                (
                    SensorGeometry::Radio(m),
                    Arc::new(Named::<_, 3>::new(
                        name,
                        Modelled {
                            model: m,
                            noise: n3,
                        },
                    )),
                )
            }
            SensorKind::Camera => {
                let m = CameraSensor {
                    frame,
                    noise: SensorNoise {
                        model: noise,
                        scales: [scales[0], scales[1]],
                    },
                };
                (
                    SensorGeometry::Camera(m),
                    Arc::new(Named::<_, 2>::new(name, m)),
                )
            }
            SensorKind::Cartesian | SensorKind::Gnss => {
                let m = CartesianSensor {
                    frame,
                    sigma: scales[0],
                };
                (
                    SensorGeometry::Position(m),
                    Arc::new(Named::<_, 3>::new(
                        name,
                        Modelled {
                            model: m,
                            noise: n3,
                        },
                    )),
                )
            }
            SensorKind::GnssVelocity => {
                let m = VelocitySensor { frame, noise: n3 };
                (
                    SensorGeometry::Velocity(m),
                    Arc::new(Named::<_, 3>::new(name, m)),
                )
            }
        };
        Self {
            spec: spec.clone(),
            measured,
            geometry,
            scales,
            nav,
        }
    }
}

/// One run's truth: the states and every sensor's readings (I/O frame, SI units).
#[derive(Debug, Clone, Default)]
pub struct RunTruth {
    /// True canonical states at `t_k`.
    pub states: Vec<State>,
    /// `[sensor]`'s readings (`None` where it did not measure).
    pub meas: Vec<Option<Vec3>>,
    /// Each `[[sensors]]` entry's readings, `[sensor][k]` (components beyond the sensor's
    /// dimension are 0).
    pub extra: Vec<Vec<Option<[f64; 3]>>>,
}

/// The H-infinity filter of a scenario's `[[filter]]` with `kind = "hinf"` (designed once
/// per scenario; see [`crate::scenario::FilterSpec::hinf_design`]). `qd` is the filter's
/// own process-noise covariance per step and `sensor` its measurement model (for derived
/// noise inputs, zero `hinf_scalings`). Returns the filter and whether the feedback thrust
/// is fed forward.
#[allow(clippy::too_many_arguments)]
fn prepare_hinf(
    f: &crate::scenario::FilterSpec,
    n0: f64,
    dt: f64,
    feedback: Option<&SMatrix<f64, 3, 6>>,
    x0: State,
    p0: Mat6,
    qd: &Mat6,
    sensor: Option<&AnySensor>,
) -> Result<(relnav_core::hinf::HinfEstimator, bool), String> {
    let sensor = sensor.ok_or(
        "the H-infinity filter needs a [sensor] (radio, lidar or cartesian): its design and \
         its runtime take that measurement",
    )?;
    use relnav_core::hinf::{psd_sqrt, HinfEstimator, HinfMatrices, HinfSpec};
    let sc = f.hinf_scalings.unwrap_or([0.05, 0.001, 0.1]);
    let d_matrix = if sc[2] == 0.0 {
        let r = match sensor {
            AnySensor::Radio(s) => s
                .position_covariance(&x0.fixed_rows::<3>(0).into_owned())
                .ok_or("hinf_scalings: d = 0 needs an initial estimate off zero range")?,
            AnySensor::Cartesian(s) => Mat3::identity() * (s.sigma * s.sigma),
        };
        Some(psd_sqrt(&r))
    } else {
        None
    };
    let spec = HinfSpec {
        w0: n0,
        delta_bar: f.hinf_delta_bar.unwrap_or(0.05),
        period: dt,
        b_pos: sc[0],
        b_vel: sc[1],
        d: sc[2],
        b_matrix: (sc[0] == 0.0 && sc[1] == 0.0).then(|| psd_sqrt(qd)),
        d_matrix,
    };
    let design = f.hinf_design.as_deref().unwrap_or("paper");
    if f.hinf_acquisition && !matches!(design, "observer" | "mixed") {
        return Err(format!(
            "hinf_acquisition needs an observer-form design (observer, mixed), not \"{design}\""
        ));
    }
    if design == "published" {
        if (dt - relnav_core::hinf::PAPER_PERIOD).abs() > 1e-12 {
            return Err(format!(
                "the published H-infinity filter holds for T = 0.1 s only (simulation.step = {dt})"
            ));
        }
        let m = HinfMatrices::paper_published();
        return HinfEstimator::new(m, f64::NAN, x0)
            .map(|h| (h, false))
            .map_err(|e| e.to_string());
    }
    #[cfg(feature = "hinf")]
    {
        use relnav_core::hinf::design::{
            design_observer, design_open_loop_mixed, design_paper, DesignOptions,
        };
        use relnav_core::hinf::HinfPlant;
        let opts = DesignOptions::default();
        let (d, ff) = match design {
            "paper" => {
                let k = feedback.ok_or(
                    "hinf_design = \"paper\" needs thrust.kind = \"feedback\" (the closed loop \
                     u = K x)",
                )?;
                let plant = HinfPlant::closed_loop_accel(&spec, k);
                (design_paper(&plant, dt, &opts), false)
            }
            "observer" => {
                spec.validate().map_err(|e| e.to_string())?;
                (
                    design_observer(&HinfPlant::open_loop(&spec), dt, &opts),
                    feedback.is_some(),
                )
            }
            "mixed" => (
                design_open_loop_mixed(&spec, f.hinf_gamma_factor.unwrap_or(1.5), &opts)
                    .map(|m| m.mixed),
                feedback.is_some(),
            ),
            other => {
                return Err(format!(
                    "unknown hinf_design \"{other}\" (paper, published, observer, mixed)"
                ))
            }
        };
        let d = d.map_err(|e| format!("H-infinity design: {e}"))?;
        let mut h = HinfEstimator::new(d.matrices, d.gamma, x0)
            .map_err(|e| e.to_string())?
            .with_h2_norm(d.h2_norm);
        if f.hinf_acquisition {
            h = h
                .with_acquisition(&HinfPlant::open_loop(&spec), p0)
                .map_err(|e| e.to_string())?;
        }
        Ok((h, ff))
    }
    #[cfg(not(feature = "hinf"))]
    {
        let _ = (feedback, spec, p0);
        Err(format!(
            "hinf_design = \"{design}\" needs the `hinf` cargo feature (the LMI solver)"
        ))
    }
}

/// Symmetric square root of a PSD matrix (eigen-decomposition; negative rounding
/// eigenvalues clipped to 0); `None` when `q` is not finite or the capped eigensolver
/// ([`relnav_core::numerics::eigen`]) does not converge.
pub fn psd_sqrt(q: &Mat6) -> Option<Mat6> {
    let e = relnav_core::numerics::eigen::symmetric_eigen((q + q.transpose()) * 0.5)?;
    let d = e.eigenvalues.map(|v| v.max(0.0).sqrt());
    Some(e.eigenvectors * Mat6::from_diagonal(&d) * e.eigenvectors.transpose())
}

impl Prepared {
    /// Derive everything from a (validated) scenario.
    pub fn new(scenario: &Scenario) -> Result<Prepared, String> {
        scenario.validate()?;
        let s = scenario;
        let frame = s.io_frame();
        let n0 = s.orbit.mean_motion()?;
        let dt = s.simulation.step;
        let steps = (s.simulation.duration / dt).round() as usize;
        let times: Vec<f64> = (0..=steps).map(|k| k as f64 * dt).collect();
        let schedule = |p: &SensorSpec| -> Vec<bool> {
            let every = (p.period / dt).round() as usize;
            times
                .iter()
                .enumerate()
                .map(|(k, t)| {
                    k % every.max(1) == 0
                        && !p.dropouts.iter().any(|w| *t >= w.start && *t < w.stop)
                })
                .collect()
        };
        let measured = match &s.sensor {
            Some(p) => schedule(p),
            None => vec![false; steps + 1],
        };
        let sensors = s
            .sensors
            .iter()
            .map(|p| PreparedSensor::new(p, frame, schedule(p)))
            .collect();
        let burn_accel = times
            .iter()
            .map(|t| match &s.thrust {
                Thrust::Burns { burns, .. } => {
                    let mut f = Vec3::zeros();
                    for b in burns {
                        if *t >= b.start - 1e-9 && *t < b.stop - 1e-9 {
                            f += Vec3::from_row_slice(&b.force);
                        }
                    }
                    frame.vec_to_canonical(&f) / s.truth.chaser_mass
                }
                _ => Vec3::zeros(),
            })
            .collect();
        let feedback = s.feedback_accel_gain();
        let qc = Mat3::identity() * s.truth.accel_psd;
        let truth_q = s.truth_q(
            CwModel::new(n0)
                .discretize(dt, &qc, Discretization::Exact)
                .q,
        );
        let noise = s.sensor.as_ref().map_or(NoiseModel::Gaussian, |p| p.noise);
        let r = s.filter_r_diag();
        let (noise_sigma, truth_sensor, filter_sensor) = match &s.sensor {
            Some(p) => {
                let (sc, _) = p.scales();
                match p.kind {
                    SensorKind::Cartesian => (
                        sc,
                        Some(AnySensor::Cartesian(CartesianSensor {
                            frame,
                            sigma: sc[0],
                        })),
                        Some(AnySensor::Cartesian(CartesianSensor {
                            frame,
                            sigma: r[0].sqrt(),
                        })),
                    ),
                    _ => (
                        sc,
                        Some(AnySensor::Radio(RadioSensor::new(frame, sc[0], sc[1]))),
                        Some(AnySensor::Radio(RadioSensor::new(
                            frame,
                            r[0].sqrt(),
                            r[1].sqrt(),
                        ))),
                    ),
                }
            }
            None => ([1.0; 3], None, None),
        };
        let told_thrust = match &s.thrust {
            Thrust::Burns { reported, .. } => *reported,
            _ => false,
        };
        let mut filters = Vec::new();
        for f in &s.filters {
            let nf = n0 * (1.0 + f.orbit_rate_error);
            let config = f
                .nav_config(s, nf)
                .map_err(|e| format!("filter \"{}\": {e}", f.label))?;
            let dynamics = config.dynamics();
            let mut model = dynamics.step(
                0.0,
                dt,
                &(Mat3::identity() * config.accel_psd),
                config.discretization,
            );
            // the AQUKF adapts the velocity part (its initial q_vv comes from it)
            let mut pn = f.process_noise;
            if config.filter == FilterKind::Aqukf {
                pn[3..].fill(0.0);
            }
            let extra_q = frame.cov_to_canonical(&Mat6::from_diagonal(&State::from_row_slice(&pn)));
            model.q += extra_q;
            let control = if f.knows_control { feedback } else { None };
            if let Some(k) = &control {
                model.phi += model.gamma * k;
            }
            let x0 = config.initial_state();
            let p0 = config.initial_covariance();
            let mut options = f.filter_options();
            // an eccentric orbit's H-infinity filter is the factory's scheduled design, and
            // that of a scenario with [[sensors]] the factory's design for hinf_sensors
            let feedforward_feedback = if config.filter == FilterKind::Hinf
                && config.eccentricity == 0.0
                && s.sensor.is_some()
            {
                let (h, ff) = prepare_hinf(
                    f,
                    n0,
                    dt,
                    feedback.as_ref(),
                    x0,
                    p0,
                    &model.q,
                    filter_sensor.as_ref(),
                )
                .map_err(|e| format!("filter \"{}\": {e}", f.label))?;
                options.hinf = Some(h);
                ff
            } else {
                if config.filter == FilterKind::Hinf {
                    if let Some(d) = f
                        .hinf_design
                        .as_deref()
                        .filter(|d| !["observer", "mixed"].contains(d))
                    {
                        return Err(format!(
                            "filter \"{}\": hinf_design = \"{d}\" needs a [sensor]; with \
                             [[sensors]] or an eccentric orbit the design is filter code 9's \
                             (observer or mixed)",
                            f.label
                        ));
                    }
                    // designed once per scenario (one design per instant of an eccentric
                    // orbit)
                    match relnav_core::nav::build_filter(&config)
                        .map_err(|e| format!("filter \"{}\": {}", f.label, e.message))?
                    {
                        AnyFilter::Hinf(h) => options.hinf = Some(h),
                        _ => {
                            return Err(format!("filter \"{}\": not an H-infinity filter", f.label))
                        }
                    }
                }
                false
            };
            filters.push(PreparedFilter {
                label: f.label.clone(),
                kind: config.filter.name().to_string(),
                x0,
                p0,
                model,
                dynamics,
                extra_q,
                control,
                told_thrust,
                sensor: filter_sensor,
                config,
                options,
                feedforward_feedback,
            });
        }
        Ok(Prepared {
            scenario: s.clone(),
            n0,
            dt,
            steps,
            measured,
            burn_accel,
            feedback,
            truth_q_sqrt: psd_sqrt(&truth_q)
                .ok_or("the truth's process noise has no square root (not finite)")?,
            truth_q,
            noise,
            noise_sigma,
            truth_sensor,
            sensors,
            filters,
        })
    }

    /// Times `t_k`.
    pub fn times(&self) -> Vec<f64> {
        (0..=self.steps).map(|k| k as f64 * self.dt).collect()
    }

    /// The true orbit rate error of a run.
    fn delta<R: Rng>(&self, rng: &mut R) -> f64 {
        use crate::scenario::OrbitRateError;
        match self.scenario.truth.orbit_rate_error {
            OrbitRateError::None => 0.0,
            OrbitRateError::Fixed { delta } => delta,
            OrbitRateError::Uniform { bound } => bound * (2.0 * rng.random::<f64>() - 1.0),
        }
    }

    /// Truth states (canonical) and every sensor's readings of one run.
    pub fn simulate_truth(&self, rng: &mut ChaCha8Rng) -> RunTruth {
        let s = &self.scenario;
        let frame = s.io_frame();
        let delta = self.delta(rng);
        let model = CwModel::new(self.n0 * (1.0 + delta));
        let (phi, gamma) = (model.phi(self.dt), model.gamma(self.dt));
        let mut x0 = State::from_row_slice(&s.truth.initial_state);
        for i in 0..6 {
            x0[i] += s.truth.initial_sigma[i] * rng.sample::<f64, _>(StandardNormal);
        }
        let mut x = frame.state_to_canonical(&x0);
        if let TruthDynamics::TwoBodyJ2 {
            inclination_deg,
            substep,
            j2,
        } = s.truth.dynamics
        {
            return self.simulate_two_body(x, inclination_deg.to_radians(), substep, j2, rng);
        }
        let mut run = self.new_run();
        let mut ar = self.initial_noise(rng);
        for k in 0..=self.steps {
            // (coloured noise advances at the measurement rate only)
            self.measure_all(k, &x, &mut ar, &mut run, rng);
            if k < self.steps {
                let mut a = self.burn_accel[k];
                if let Some(kg) = &self.feedback {
                    a += kg * x;
                }
                let w: State =
                    self.truth_q_sqrt * State::from_fn(|_, _| rng.sample::<f64, _>(StandardNormal));
                x = phi * x + gamma * a + w;
            }
        }
        run
    }

    fn new_run(&self) -> RunTruth {
        let n = self.steps + 1;
        RunTruth {
            states: Vec::with_capacity(n),
            meas: Vec::with_capacity(n),
            extra: vec![Vec::with_capacity(n); self.sensors.len()],
        }
    }

    /// The AR(1) states of every sensor's noise (`[sensor]` first) at the start of a run.
    fn initial_noise(&self, rng: &mut ChaCha8Rng) -> Vec<[f64; 3]> {
        let mut ar = vec![[0.0; 3]; 1 + self.sensors.len()];
        for (i, a) in ar[0].iter_mut().enumerate() {
            *a = self.noise.initial_state(self.noise_sigma[i], rng);
        }
        for (s, a) in self.sensors.iter().zip(&mut ar[1..]) {
            let n = s.spec.scales().1;
            for (ai, si) in a.iter_mut().zip(&s.scales).take(n) {
                *ai = s.spec.noise.initial_state(*si, rng);
            }
        }
        ar
    }

    /// Whether `[sensor]` measures at time `k` with the true canonical state `x`.
    pub fn primary_measures(&self, k: usize, x: &State) -> bool {
        self.measured[k]
            && self
                .scenario
                .sensor
                .as_ref()
                .is_some_and(|p| p.in_range(position(x).norm()))
    }

    /// Record `x` and every sensor's reading of it at time `k`.
    fn measure_all(
        &self,
        k: usize,
        x: &State,
        ar: &mut [[f64; 3]],
        run: &mut RunTruth,
        rng: &mut ChaCha8Rng,
    ) {
        run.states.push(*x);
        run.meas.push(if self.primary_measures(k, x) {
            self.measure(x, &mut ar[0], rng)
        } else {
            None
        });
        let range = position(x).norm();
        for (i, s) in self.sensors.iter().enumerate() {
            let z = if s.measured[k] && s.spec.in_range(range) {
                s.geometry
                    .measure(x, &s.spec.noise, &s.scales, &mut ar[i + 1], rng)
            } else {
                None
            };
            run.extra[i].push(z);
        }
    }
}

impl Prepared {
    /// Components of the NIS scored ([`run_filter`]): `[sensor]`'s, else the first
    /// `[[sensors]]` entry's.
    pub fn nis_dof(&self) -> usize {
        match (&self.truth_sensor, self.sensors.first()) {
            (None, Some(s)) => s.nav.dim(),
            _ => 3,
        }
    }

    /// Noisy measurement of a true canonical state (or `None` at zero range).
    fn measure(&self, x: &State, ar: &mut [f64; 3], rng: &mut ChaCha8Rng) -> Option<Vec3> {
        // the `[[sensors]]`' truth geometry, with `[sensor]`'s noise and scales
        let g = match self.truth_sensor.as_ref()? {
            AnySensor::Radio(s) => SensorGeometry::Radio(*s),
            AnySensor::Cartesian(s) => SensorGeometry::Position(*s),
        };
        g.measure(x, &self.noise, &self.noise_sigma, ar, rng)
            .map(Vec3::from)
    }

    /// The truth of a `two_body_j2` scenario: target and chaser around the Earth (point
    /// mass + J2, or point mass alone, GBS steps of `substep`), the target on the orbit of
    /// `orbit` (eccentric: perigee at the ascending node), burns and the truth's random
    /// acceleration (`accel_psd / step` per axis, drawn per step after the measurement)
    /// acting on the chaser (along the rotating Hill axes),
    /// relative state in the target's Hill frame.
    fn simulate_two_body(
        &self,
        rel0: State,
        incl: f64,
        substep: f64,
        j2: bool,
        rng: &mut ChaCha8Rng,
    ) -> RunTruth {
        let o = &self.scenario.orbit;
        let mut truth = relnav_core::orbit::TwoBodyJ2::keplerian(
            self.n0,
            o.eccentricity,
            o.true_anomaly0,
            incl,
            &rel0,
            substep,
        );
        truth.j2 = j2;
        let sigma_a = (self.scenario.truth.accel_psd / self.dt).sqrt();
        let mut run = self.new_run();
        let mut ar = self.initial_noise(rng);
        for k in 0..=self.steps {
            let x = truth.relative();
            self.measure_all(k, &x, &mut ar, &mut run, rng);
            if k < self.steps {
                let mut a = self.burn_accel[k];
                if sigma_a > 0.0 {
                    a += Vec3::from_fn(|_, _| sigma_a * rng.sample::<f64, _>(StandardNormal));
                }
                truth.step(&a, k as f64 * self.dt, self.dt);
            }
        }
        run
    }
}

/// Per-time score of one filter in one run: squared errors (I/O frame), NEES, NIS (NaN
/// without a measurement), position and velocity error norms, the squared range error
/// (estimated range less the true one) and the range variance the filter reports (its
/// covariance along its estimated line of sight; NaN without a covariance).
pub type Score = [f64; 12];

/// Run one filter over a run's truth and measurements. `Err` when the filter fails
/// numerically (the run is then excluded from its statistics and counted). The NIS scored
/// is that of `[sensor]`, or of the first `[[sensors]]` entry without one
/// ([`Prepared::nis_dof`] components).
pub fn run_filter(
    prep: &Prepared,
    f: &PreparedFilter,
    run: &RunTruth,
    seed: u64,
    out: &mut Vec<Score>,
) -> Result<(u64, u64), String> {
    let (truth, meas) = (&run.states, &run.meas);
    let frame = prep.scenario.io_frame();
    let t6 = frame.rotation6();
    let mut est = f.instantiate(seed)?;
    out.clear();
    for k in 0..=prep.steps {
        let mut nis = f64::NAN;
        if let (Some(z), Some(truth_sensor), Some(sensor)) =
            (&meas[k], &prep.truth_sensor, &f.sensor)
        {
            let info = match &mut est {
                // particle filters weigh with the true noise density (heavy tails included)
                AnyFilter::Pf(pf) => {
                    pf.update_with(truth_sensor, z, &prep.noise, &prep.noise_sigma)
                }
                other => other.update(sensor, z),
            }
            .map_err(|e| format!("t = {}: {e}", k as f64 * prep.dt))?;
            nis = info.nis;
        }
        for (i, s) in prep.sensors.iter().enumerate() {
            if let Some(z) = &run.extra[i][k] {
                let r = s
                    .nav
                    .apply(&mut est, &z[..s.nav.dim()])
                    .map_err(|e| format!("t = {}: {}: {e}", k as f64 * prep.dt, s.nav.name()))?;
                if i == 0 && prep.truth_sensor.is_none() {
                    nis = r.nis;
                }
            }
        }
        let e = est.state() - truth[k];
        let p = est.covariance();
        // a collapsed particle set claims zero uncertainty: its NEES is infinite
        // the H-infinity filter has no covariance (NaN): no NEES either
        let nees = if p[(0, 0)].is_nan() {
            f64::NAN
        } else {
            p.cholesky()
                .map(|c| e.dot(&c.solve(&e)))
                .unwrap_or(f64::INFINITY)
        };
        let eio = t6 * e;
        let (r_est, r_true) = (est.state().fixed_rows::<3>(0), truth[k].fixed_rows::<3>(0));
        let u = r_est / r_est.norm();
        let range_var = (u.transpose() * p.fixed_view::<3, 3>(0, 0) * u)[(0, 0)];
        out.push([
            eio[0] * eio[0],
            eio[1] * eio[1],
            eio[2] * eio[2],
            eio[3] * eio[3],
            eio[4] * eio[4],
            eio[5] * eio[5],
            nees,
            nis,
            eio.fixed_rows::<3>(0).norm(),
            eio.fixed_rows::<3>(3).norm(),
            (r_est.norm() - r_true.norm()).powi(2),
            range_var,
        ]);
        if k < prep.steps {
            let mut a = if f.told_thrust {
                prep.burn_accel[k]
            } else {
                Vec3::zeros()
            };
            if let (true, Some(kg)) = (f.feedforward_feedback, &prep.feedback) {
                a += kg * truth[k];
            }
            let t = k as f64 * prep.dt;
            est.predict(&f.model_at(t, prep.dt), &a)
                .map_err(|e| format!("t = {t}: {e}"))?;
        }
    }
    // a particle filter's Metropolis–Hastings moves over the run: tried, accepted
    Ok(match &est {
        AnyFilter::Pf(pf) => pf.move_counts(),
        _ => (0, 0),
    })
}
