//! The navigator: one estimator plus everything around it that a user sets — I/O frame,
//! chaser mass, process-noise model, discretisation, initial estimate — behind an API in
//! the user's frame and SI units. The C ABI (the `relnav` crate), the FMU and the Python
//! package are thin shells around it.
//!
//! **Step semantics** (also those of the C ABI and the FMU): [`Navigator::step`]`(thrust,
//! measurement, h)` at time `t` first applies the measurement taken at `t` (if any), then
//! predicts over `[t, t + h)` with the thrust held constant; afterwards the estimate is the
//! prior at `t + h`.
//!
//! * [`config`]: [`NavConfig`], declared once as a parameter table from which every front
//!   end takes its parameters; the process and measurement noise models in its docs;
//! * [`factory`]: [`AnyFilter`] and [`build_filter`], the one place a filter code becomes
//!   an estimator;
//! * `persist`: the navigator's saved state;
//! * [`error`]: the navigator's errors, [`NavError`].
//!
//! [`Navigator::q_vv`] reports the AQUKF's adaptive density, [`Navigator::mode_probabilities`]
//! the IMM's mode probabilities.

#[cfg(test)]
mod bank_tests;
pub mod config;
#[cfg(test)]
mod elliptic_tests;
pub mod error;
pub mod factory;
mod persist;
#[cfg(test)]
mod sensor_tests;
pub mod sensors;

#[cfg(not(feature = "std"))]
use crate::math::Float;
use crate::numerics::Owned;
pub use config::{
    FilterKind, HinfDesignKind, NavConfig, NoiseKind, ResamplerSetting, Setting,
    MAX_INITIAL_MAGNITUDE, MEAN_MOTION_RANGE, PARAMS,
};
pub use error::{NavError, NavErrorKind};
pub use factory::{build_filter, build_filter_with, AnyFilter, FilterOptions};
pub use persist::STATE_FORMAT_VERSION;
pub use sensors::{Named, NavSensor, SensorReport};

use crate::dynamics::{DiscreteModel, Dynamics, KeplerMemo, RelativeDynamics};
use crate::estimators::{Estimator, Member, UpdateInfo, MAX_MODES};
use crate::noise::NoiseModel;
use crate::numerics::num;
use crate::sensors::RadioSensor;
use crate::types::{Mat3, Mat6, State, Vec3};
use config::positive;
use factory::Snapshot;
#[cfg(feature = "std")]
use std::sync::Arc;

/// Longest accepted step, in orbital periods `2 pi / n` of the target: a prediction over
/// more than 1000 orbits (for a 90-minute orbit, two months; geostationary, three years) is
/// far outside the linearised CW model and is almost certainly a units or time-base error
/// (a co-simulation master can send a step of 1e45 s). [`Navigator::predict`] and
/// [`Navigator::step`] refuse it with a message naming the limit; below it every step
/// returns a value or an error in bounded time (the discretisation is closed-form).
pub const MAX_STEP_PERIODS: f64 = 1000.0;

/// The thrust `thrust` [N, I/O frame] as the canonical acceleration `F / m` [m/s^2].
#[inline]
fn canonical_accel(cfg: &NavConfig, thrust: &[f64; 3]) -> Vec3 {
    cfg.frame.vec_to_canonical(&Vec3::from(*thrust)) / cfg.chaser_mass
}

#[inline]
fn finite3(name: &str, v: &[f64; 3]) -> Result<(), NavError> {
    if crate::numerics::all_finite(v) {
        Ok(())
    } else {
        Err(NavError::invalid(crate::msg!(
            "{name} must be finite (got {v:?})"
        )))
    }
}

/// A configured estimator working in the user's frame and units.
///
/// **Failures.** Inputs are checked before anything changes. A Kalman filter that fails
/// numerically inside a step (zero range, loss of positive definiteness) is restored to
/// its state before the step. A particle filter's update and prediction are each
/// transactional (new particles go to spare buffers and are swapped in on success; see
/// [`ParticleFilter::update_with`]): a failed `update` or `predict` changes nothing, and
/// so does a `step` whose update fails (every likelihood zero, a measurement that cannot
/// be inverted at the first update). Copying the particle set to undo a *successful*
/// update would cost as much as the step itself, so in the one remaining case — the
/// update succeeded and the prediction after it failed (a non-finite particle mean, i.e.
/// overflow) — the particle filter is marked failed and every later `update`, `predict`
/// or `step` is refused with [`NavErrorKind::Numerical`] until [`Navigator::reset`].
#[derive(Debug, Clone)]
pub struct Navigator {
    cfg: NavConfig,
    dynamics: Dynamics,
    /// start time of the next step [s since construction or reset]: a time-varying
    /// model's (the elliptic one's) steps depend on it; in the saved state
    t: f64,
    /// the sensor with the noise model's scales (particle filters' likelihood)
    sensor: RadioSensor,
    /// the sensor with the noise model's variance (Kalman filters)
    kalman_sensor: RadioSensor,
    noise: NoiseModel,
    scales: [f64; 3],
    filter: AnyFilter,
    step_cache: DiscreteModel,
    /// the elliptic model's Kepler anchor between steps (a cache: no result depends on it)
    kepler: KeplerMemo,
    /// the diagonal of [`NavConfig::process_noise_rates`] (a diagonal matrix: the frame
    /// conversion permutes its entries), added to every step's noise
    q_rates: State,
    last_update: Option<UpdateInfo>,
    /// the sensors beside the radio ([`Navigator::add_sensor`]), in the order they are
    /// applied, and each one's last report
    sensors: SensorList,
    reports: ReportList,
    /// a step's new reports, committed when the step succeeds (allocated with the sensors)
    pending: ReportList,
    /// the declared sensors beside the radio, from the configuration: camera, relative
    /// GNSS position, relative GNSS velocity ([`Readings`])
    declared: Declared,
    /// the last step's NIS per declared sensor (radio, camera, GNSS position, GNSS
    /// velocity), NaN where it gave no reading ([`Navigator::step_nis`])
    step_nis: [f64; 4],
    /// the fraction of a particle filter's moves accepted in the last update or step (NaN
    /// where it made none; [`Navigator::step_acceptance`])
    step_acceptance: f64,
    /// a particle filter's prediction failed after its update in one step: refuse to go
    /// on until reset
    failed: bool,
}

/// The readings of the declared sensors at one step, in the I/O frame, SI units and
/// radians, each applied when given, in this order: the radio's `(range, azimuth,
/// elevation)`, the camera's `(azimuth, elevation)` (the radio's angle conventions),
/// relative GNSS's position `(x, y, z)` and velocity `(vx, vy, vz)`
/// ([`Navigator::step_readings`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Readings {
    /// Range [m], azimuth, elevation [rad] (the radio or lidar).
    pub radio: Option<[f64; 3]>,
    /// Azimuth, elevation [rad] of the line of sight (the camera).
    pub camera: Option<[f64; 2]>,
    /// Relative position [m] (relative GNSS).
    pub gnss_position: Option<[f64; 3]>,
    /// Relative velocity [m/s] (relative GNSS).
    pub gnss_velocity: Option<[f64; 3]>,
}

/// The sensors added at run time ([`Navigator::add_sensor`]); without `std` there are
/// none (an empty array: no heap).
#[cfg(feature = "std")]
type SensorList = Vec<Arc<dyn NavSensor>>;
#[cfg(not(feature = "std"))]
#[derive(Debug, Clone, Default)]
struct SensorList;

#[cfg(not(feature = "std"))]
impl SensorList {
    fn iter(&self) -> core::iter::Empty<&&'static dyn NavSensor> {
        core::iter::empty()
    }
    fn len(&self) -> usize {
        0
    }
    fn get(&self, _: usize) -> Option<&&'static dyn NavSensor> {
        None
    }
}
/// One report per added sensor.
#[cfg(feature = "std")]
type ReportList = Vec<Option<SensorReport>>;
#[cfg(not(feature = "std"))]
type ReportList = [Option<SensorReport>; 0];

/// The declared sensors beside the radio, from the configuration (noise densities
/// `camera_noise_*` and `gnss_noise_*` scaled by `sigma_camera`, `sigma_gnss`,
/// `sigma_gnss_velocity`; in the I/O frame), held by value.
#[derive(Debug, Clone)]
struct Declared {
    camera: Named<crate::sensors::CameraSensor, 2>,
    gnss_position: Named<crate::sensors::Modelled<crate::sensors::CartesianSensor>, 3>,
    gnss_velocity: Named<crate::sensors::VelocitySensor, 3>,
}

impl Declared {
    fn new(cfg: &NavConfig) -> Self {
        Self {
            camera: Named::new("camera", cfg.camera_sensor()),
            gnss_position: Named::new("GNSS position", cfg.gnss_position_sensor()),
            gnss_velocity: Named::new("GNSS velocity", cfg.gnss_velocity_sensor()),
        }
    }

    /// The sensors in [`Readings`] order: camera, GNSS position, GNSS velocity.
    fn all(&self) -> [&dyn NavSensor; 3] {
        [&self.camera, &self.gnss_position, &self.gnss_velocity]
    }
}

impl Navigator {
    /// Build a navigator; fails with a message naming the bad parameter.
    pub fn new(cfg: &NavConfig) -> Result<Self, NavError> {
        cfg.validate()?;
        let mut nav = Self::unfiltered(cfg);
        nav.configure()?;
        Ok(nav)
    }

    /// [`Navigator::new`] built in `slot` (the C ABI's caller storage) rather than on the
    /// stack and moved there (the navigator holds the largest filter by value). On error `slot` holds no navigator
    /// the caller may use, and nothing is leaked.
    pub fn new_in<'a>(
        cfg: &NavConfig,
        slot: &'a mut core::mem::MaybeUninit<Self>,
    ) -> Result<&'a mut Self, NavError> {
        cfg.validate()?;
        let nav = slot.write(Self::unfiltered(cfg));
        if let Err(e) = nav.configure() {
            // the filter may hold heap (particles): give it back
            nav.filter = Self::placeholder_filter();
            return Err(e);
        }
        Ok(nav)
    }

    /// A small filter that [`Navigator::configure`] replaces in place.
    #[inline(always)]
    fn placeholder_filter() -> AnyFilter {
        AnyFilter::Ekf(crate::estimators::Ekf::new(
            State::zeros(),
            Mat6::identity(),
        ))
    }

    /// The navigator of a validated `cfg` before its filter and its first discrete model
    /// ([`Navigator::configure`]).
    #[inline(always)]
    fn unfiltered(cfg: &NavConfig) -> Self {
        let noise = cfg.noise();
        let inflate = noise.variance_factor().sqrt();
        Self {
            cfg: *cfg,
            dynamics: cfg.dynamics(),
            t: 0.0,
            sensor: RadioSensor::new(cfg.frame, cfg.sigma_range, cfg.sigma_angle),
            kalman_sensor: RadioSensor::new(
                cfg.frame,
                cfg.sigma_range * inflate,
                cfg.sigma_angle * inflate,
            ),
            noise,
            scales: [cfg.sigma_range, cfg.sigma_angle, cfg.sigma_angle],
            filter: Self::placeholder_filter(),
            step_cache: DiscreteModel {
                t: 0.0,
                dt: f64::NAN,
                phi: Mat6::identity(),
                gamma: Default::default(),
                q: Mat6::zeros(),
            },
            kepler: KeplerMemo::default(),
            q_rates: State::zeros(),
            last_update: None,
            // a unit struct without std, a list with it
            #[allow(clippy::default_constructed_unit_structs)]
            sensors: SensorList::default(),
            reports: ReportList::default(),
            pending: ReportList::default(),
            declared: Declared::new(cfg),
            step_nis: [f64::NAN; 4],
            step_acceptance: f64::NAN,
            failed: false,
        }
    }

    /// Build the filter in place (the factory's `build_filter_into`: a filter as large as
    /// the AQUKF's is not held twice on the stack), the process-noise rates and the
    /// discrete model of a 1 s step, and check that the initial estimate is finite.
    fn configure(&mut self) -> Result<(), NavError> {
        let cfg = self.cfg;
        factory::build_filter_into(&cfg, &FilterOptions::default(), &mut self.filter)?;
        let rates = cfg.process_noise_rates();
        debug_assert_eq!(rates, Mat6::from_diagonal(&rates.diagonal()));
        self.q_rates = rates.diagonal();
        self.discrete(1.0);
        // every field is finite, but x0 near the largest double with its uncertainty can
        // still overflow (a particle filter's initial draw x0 + L eps): refuse it here rather
        // than hand out an estimator whose estimate is not a number
        let cov_ok =
            self.filter.hinf().is_some() || self.filter.covariance().iter().all(|v| v.is_finite());
        if !(self.filter.state().iter().all(|v| v.is_finite()) && cov_ok) {
            return Err(NavError::invalid(crate::msg!(
                "the initial estimate x0 = {:?} with sigma_pos0 = {}, sigma_vel0 = {} overflows \
                 double precision in the {} filter's initial state",
                cfg.x0,
                num(cfg.sigma_pos0),
                num(cfg.sigma_vel0),
                cfg.filter.name()
            )));
        }
        Ok(())
    }

    /// The configuration this navigator was built from.
    pub fn config(&self) -> &NavConfig {
        &self.cfg
    }

    /// Make `step_cache` the discrete model of the step from `self.t` over `dt`
    /// (recomputed only when `dt` changes, or at every step for a time-varying model).
    fn discrete(&mut self, dt: f64) {
        if self.step_cache.dt != dt || !self.dynamics.time_invariant() {
            let qc = Mat3::identity() * self.cfg.accel_psd;
            self.dynamics.step_into(
                &mut self.kepler,
                self.t,
                dt,
                &qc,
                self.cfg.discretization,
                &mut self.step_cache,
            );
            for (i, r) in self.q_rates.iter().enumerate() {
                self.step_cache.q[(i, i)] += r * dt;
            }
        }
        self.step_cache.t = self.t;
    }

    /// The longest accepted step [s]: [`MAX_STEP_PERIODS`] orbital periods.
    pub fn max_step(&self) -> f64 {
        MAX_STEP_PERIODS * core::f64::consts::TAU / self.cfg.mean_motion
    }

    /// [`Navigator::check_dt_in_full`] without a call in the common case: `0 < dt <=`
    /// [`Navigator::max_step`] (false for NaN; `max_step` is finite) and no filter with a
    /// fixed period.
    #[inline(always)]
    fn check_dt(&self, dt: f64) -> Result<(), NavError> {
        if dt > 0.0 && dt <= self.max_step() && self.filter.hinf().is_none() {
            Ok(())
        } else {
            self.check_dt_in_full(dt)
        }
    }

    #[cold]
    #[inline(never)]
    fn check_dt_in_full(&self, dt: f64) -> Result<(), NavError> {
        positive("step size h", dt)?;
        if dt > self.max_step() {
            return Err(NavError::invalid(crate::msg!(
                "step size h = {} s is longer than {MAX_STEP_PERIODS} orbital periods ({} s at \
                 mean_motion {} rad/s), where the linearised relative motion means nothing: \
                 split the interval, or check the time unit",
                num(dt),
                num(self.max_step()),
                num(self.cfg.mean_motion)
            )));
        }
        if let Some(f) = self.filter.hinf() {
            let t = f.period();
            if (dt - t).abs() > 1e-9 * t {
                return Err(NavError::invalid(crate::msg!(
                    "the hinf filter was designed for hinf_period = {} s and holds for that \
                     period only; step h = {} s refused (set hinf_period to the step size)",
                    num(t),
                    num(dt)
                )));
            }
        }
        Ok(())
    }

    /// [`Navigator::check_measurement_in_full`] without a call in the common case (finite,
    /// range `>= 0`, elevation in `[-pi/2, pi/2]`).
    #[inline(always)]
    fn check_measurement(z: &[f64; 3]) -> Result<(), NavError> {
        if crate::numerics::all_finite(z)
            && z[0] >= 0.0
            && z[2].abs() <= core::f64::consts::FRAC_PI_2
        {
            Ok(())
        } else {
            Self::check_measurement_in_full(z)
        }
    }

    #[cold]
    #[inline(never)]
    fn check_measurement_in_full(z: &[f64; 3]) -> Result<(), NavError> {
        finite3("measurement (range, azimuth, elevation)", z)?;
        if z[0] < 0.0 {
            return Err(NavError::invalid(crate::msg!(
                "measured range must be >= 0 (got {})",
                num(z[0])
            )));
        }
        if z[2].abs() > core::f64::consts::FRAC_PI_2 {
            return Err(NavError::invalid(crate::msg!(
                "measured elevation must lie in [-pi/2, pi/2] (got {})",
                num(z[2])
            )));
        }
        Ok(())
    }

    /// The checks of a step's step size, thrust and radio measurement.
    #[inline(always)]
    fn check_step(
        &self,
        thrust: &[f64; 3],
        measurement: Option<&[f64; 3]>,
        dt: f64,
    ) -> Result<(), NavError> {
        self.check_dt(dt)?;
        finite3("thrust", thrust)?;
        if let Some(z) = measurement {
            Self::check_measurement(z)?;
        }
        Ok(())
    }

    fn check_not_failed(&self) -> Result<(), NavError> {
        if self.failed {
            Err(NavError {
                kind: NavErrorKind::Numerical,
                message: crate::msg!(
                    "the {} particle filter failed in an earlier step (its prediction after \
                     a successful update) and its particles are no longer valid: reset the \
                     estimator",
                    self.cfg.filter.name()
                ),
            })
        } else {
            Ok(())
        }
    }

    /// Time update over `dt` [s] with thrust `thrust` [N] (I/O frame) held constant.
    pub fn predict(&mut self, thrust: &[f64; 3], dt: f64) -> Result<(), NavError> {
        self.check_dt(dt)?;
        finite3("thrust", thrust)?;
        self.check_not_failed()?;
        self.predict_checked(thrust, dt)
    }

    /// [`Navigator::predict`] once its inputs are checked.
    fn predict_checked(&mut self, thrust: &[f64; 3], dt: f64) -> Result<(), NavError> {
        let accel = canonical_accel(&self.cfg, thrust);
        self.discrete(dt);
        // the cached model by reference (no copy of its ~100 numbers per step)
        self.filter.predict(&self.step_cache, &accel)?;
        self.t += dt;
        Ok(())
    }

    /// Measurement update with `(range [m], azimuth [rad], elevation [rad])` in the I/O frame.
    /// The particle filters weigh with the configured noise density, the Kalman filters use
    /// the Gaussian of its variance.
    pub fn update(&mut self, z: &[f64; 3]) -> Result<UpdateInfo, NavError> {
        Self::check_measurement(z)?;
        self.check_not_failed()?;
        self.tallied(|nav| nav.update_checked(z))
    }

    /// The moves a particle filter has tried and accepted so far (`None` for the others).
    fn move_counts(&self) -> Option<(u64, u64)> {
        match &self.filter {
            #[cfg(feature = "std")]
            AnyFilter::Pf(pf) => Some(pf.move_counts()),
            _ => None,
        }
    }

    /// Run `f` (an update or a step) and, when it succeeds, record the fraction of the
    /// moves it made that were accepted ([`Navigator::step_acceptance`]).
    #[inline(always)]
    fn tallied<T>(
        &mut self,
        f: impl FnOnce(&mut Self) -> Result<T, NavError>,
    ) -> Result<T, NavError> {
        let before = self.move_counts();
        let r = f(self);
        if r.is_ok() {
            self.step_acceptance = match (before, self.move_counts()) {
                (Some((t0, a0)), Some((t1, a1))) if t1 > t0 => (a1 - a0) as f64 / (t1 - t0) as f64,
                _ => f64::NAN,
            };
        }
        r
    }

    /// [`Navigator::update`] once its input is checked.
    fn update_checked(&mut self, z: &[f64; 3]) -> Result<UpdateInfo, NavError> {
        let zv = Vec3::from(*z);
        let r = match &mut self.filter {
            #[cfg(feature = "std")]
            AnyFilter::Pf(pf) => pf.update_with(&self.sensor, &zv, &self.noise, &self.scales),
            other => other.update(&self.kalman_sensor, &zv),
        };
        let info = r?;
        self.last_update = Some(info);
        Ok(info)
    }

    /// One step: update with `measurement` (taken at the step's start, if any), then predict
    /// over `dt` with `thrust` held. All inputs are checked before anything changes; a
    /// failed step leaves the estimate as it was, except a particle filter whose
    /// prediction fails after a successful update, which is marked failed (see the type's
    /// documentation).
    pub fn step(
        &mut self,
        thrust: &[f64; 3],
        measurement: Option<&[f64; 3]>,
        dt: f64,
    ) -> Result<(), NavError> {
        let r = self.tallied(|nav| nav.step_radio(thrust, measurement, dt));
        if r.is_ok() {
            let nis = measurement
                .and(self.last_update)
                .map_or(f64::NAN, |u| u.nis);
            self.step_nis = [nis, f64::NAN, f64::NAN, f64::NAN];
        }
        r
    }

    /// [`Navigator::step`] but for its diagnostics.
    #[inline(always)]
    fn step_radio(
        &mut self,
        thrust: &[f64; 3],
        measurement: Option<&[f64; 3]>,
        dt: f64,
    ) -> Result<(), NavError> {
        self.check_step(thrust, measurement, dt)?;
        self.check_not_failed()?;
        // the EKF's update and prediction commit together (no snapshot to copy); the
        // discrete model is a cache of `dt` alone
        self.discrete(dt);
        if let (AnyFilter::Ekf(f), Some(z)) = (&mut self.filter, measurement) {
            let accel = canonical_accel(&self.cfg, thrust);
            let zv = Vec3::from(*z);
            let info = f.update_predict(&self.kalman_sensor, &zv, &self.step_cache, &accel)?;
            self.last_update = Some(info);
            self.t += dt;
            return Ok(());
        }
        // the UKF's likewise (a snapshot and its copies would be a large part of its FMU
        // cycle's cost)
        if let (AnyFilter::Ukf(f), Some(z)) = (&mut self.filter, measurement) {
            let accel = canonical_accel(&self.cfg, thrust);
            let zv = Vec3::from(*z);
            let info = f.update_predict(&self.kalman_sensor, &zv, &self.step_cache, &accel)?;
            self.last_update = Some(info);
            self.t += dt;
            return Ok(());
        }
        // other Kalman-type filters: a small snapshot on the stack to restore
        let saved = self.filter.snapshot();
        let last = self.last_update;
        let mut updated = false;
        // checked above, once
        let result = match measurement {
            Some(z) => self.update_checked(z).map(|_| updated = true),
            None => Ok(()),
        }
        .and_then(|()| self.predict_checked(thrust, dt));
        if result.is_err() {
            match saved {
                // a particle filter's failed update or prediction changed nothing by
                // itself; a failed prediction after a committed update cannot be undone
                Snapshot::None => self.failed |= updated,
                s => {
                    self.filter.restore(&s);
                    self.last_update = last;
                }
            }
        }
        result
    }

    #[cfg(feature = "std")]
    /// Add a sensor beside the configured radio (any [`crate::sensors::Sensor`] through
    /// [`Named`]); returns its index among the added sensors, the position of its reading
    /// in [`Navigator::step_with`]. Sensors are configuration: a saved state does not hold
    /// them, and a navigator that restores one must have been given the same sensors.
    pub fn add_sensor(&mut self, sensor: Arc<dyn NavSensor>) -> usize {
        self.sensors.push(sensor);
        self.reports.push(None);
        self.pending.push(None);
        self.sensors.len() - 1
    }

    #[cfg(feature = "std")]
    /// The sensors added by [`Navigator::add_sensor`], in order.
    pub fn sensors(&self) -> &[Arc<dyn NavSensor>] {
        &self.sensors
    }

    /// The last report of added sensor `i` (`None` before its first update or after a
    /// reset).
    pub fn sensor_report(&self, i: usize) -> Option<SensorReport> {
        self.reports.get(i).copied().flatten()
    }

    /// One step with every sensor: the radio's `measurement` (if any), then the reading of
    /// each added sensor that has one (`readings[i]` for sensor `i`, in the order they were
    /// added; `readings` as long as the sensors), all taken at the step's start, then the
    /// prediction over `dt` with `thrust` held. Inputs are checked before anything changes.
    /// A failed step leaves the estimate as it was, except a particle filter that fails
    /// after one of its updates succeeded (its updates are each transactional, not the
    /// step): it is marked failed, as in [`Navigator::step`].
    pub fn step_with(
        &mut self,
        thrust: &[f64; 3],
        measurement: Option<&[f64; 3]>,
        readings: &[Option<&[f64]>],
        dt: f64,
    ) -> Result<(), NavError> {
        if readings.len() != self.sensors.len() {
            return Err(NavError::invalid(crate::msg!(
                "{} readings given for {} added sensors",
                readings.len(),
                self.sensors.len()
            )));
        }
        self.tallied(|nav| nav.step_all(thrust, measurement, [None; 3], readings, dt))
    }

    /// One step with the declared sensors' `readings` ([`Readings`]: the radio, then the
    /// camera, relative GNSS's position and its velocity, each applied when given, all
    /// taken at the step's start), then the prediction over `dt` with `thrust` held. Every
    /// reading is checked before anything changes (a refusal names the sensor); a failed
    /// step leaves the estimate as it was, as [`Navigator::step_with`].
    pub fn step_readings(
        &mut self,
        thrust: &[f64; 3],
        readings: &Readings,
        dt: f64,
    ) -> Result<(), NavError> {
        let declared = [
            readings.camera.as_ref().map(|z| &z[..]),
            readings.gnss_position.as_ref().map(|z| &z[..]),
            readings.gnss_velocity.as_ref().map(|z| &z[..]),
        ];
        // no reading for the added sensors (`step_all` takes the first `readings.len()`)
        self.tallied(|nav| nav.step_all(thrust, readings.radio.as_ref(), declared, &[], dt))
    }

    /// The fraction of the Metropolis–Hastings moves (rejuvenation, RPF jitter, genetic
    /// operators) a particle filter accepted in the last update or step: how far its
    /// particles moved from their proposal. NaN when that step made no move (no reading,
    /// the first update, which draws the particles from the measurement, `pf_move = false`
    /// on a kind without operators), for the other filters, before the first step and
    /// after a restore.
    pub fn step_acceptance(&self) -> f64 {
        self.step_acceptance
    }

    /// The normalised innovation squared of the last step's update by each declared sensor
    /// (radio, camera, GNSS position, GNSS velocity; NaN for a sensor that gave no reading
    /// in that step, for point particles and the H-infinity filter, and after a restore).
    pub fn step_nis(&self) -> [f64; 4] {
        self.step_nis
    }

    /// 1-sigma of the estimated range: `sqrt(u^T P_rr u)` with `u` the estimated line of
    /// sight (NaN at zero range and for the H-infinity filter, which carries no
    /// covariance). Shows when an angles-only range becomes observable.
    pub fn range_sigma(&self) -> f64 {
        let x = self.filter.state();
        let r = Vec3::new(x[0], x[1], x[2]);
        let n = r.norm();
        if !(n > 0.0) {
            return f64::NAN;
        }
        let u = r / n;
        let p = self.filter.covariance().fixed_view::<3, 3>(0, 0).owned();
        let v = u.dot(&(p * u));
        if v >= 0.0 {
            v.sqrt()
        } else {
            f64::NAN
        }
    }

    /// The step of [`Navigator::step_with`] and [`Navigator::step_readings`]: `readings`
    /// for the first `readings.len()` added sensors (none for the others); no heap.
    fn step_all(
        &mut self,
        thrust: &[f64; 3],
        measurement: Option<&[f64; 3]>,
        declared: [Option<&[f64]>; 3],
        readings: &[Option<&[f64]>],
        dt: f64,
    ) -> Result<(), NavError> {
        if readings.iter().chain(&declared).all(Option::is_none) {
            return self.step(thrust, measurement, dt);
        }
        self.check_step(thrust, measurement, dt)?;
        for (s, z) in self.declared.all().into_iter().zip(&declared) {
            if let Some(z) = z {
                s.check(z).map_err(NavError::invalid)?;
            }
        }
        for (s, z) in self.sensors.iter().zip(readings) {
            if let Some(z) = z {
                s.check(z).map_err(NavError::invalid)?;
            }
        }
        self.check_not_failed()?;
        self.discrete(dt);
        // one reading: the EKF's and UKF's update and prediction commit together, as the
        // radio's step does (no snapshot)
        if measurement.is_none() && self.step_one(thrust, &declared, readings, dt)? {
            return Ok(());
        }
        // several updates: the step's small snapshot to restore (not a copy of the whole
        // filter, as large as the AQUKF's window); the particle filters' updates are each
        // transactional
        let saved = self.filter.snapshot();
        let last = self.last_update;
        let mut nis = [f64::NAN; 4];
        let mut updated = false;
        let result = self.apply_updates(measurement, &declared, readings, &mut nis, &mut updated);
        let result = result.and_then(|()| self.predict_checked(thrust, dt));
        match (&result, saved) {
            (Ok(()), _) => {
                for (r, p) in self.reports.iter_mut().zip(&self.pending) {
                    if p.is_some() {
                        *r = *p;
                    }
                }
                self.step_nis = nis;
            }
            (Err(_), Snapshot::None) => self.failed |= updated,
            (Err(_), s) => {
                self.filter.restore(&s);
                self.last_update = last;
            }
        }
        result
    }

    /// The updates of a step or an event, in order (the radio, the declared sensors, the
    /// added ones), each reading checked before: the NIS of each into `nis`, `updated` once
    /// one has changed the filter; the added sensors' reports wait in `pending`. Stops at
    /// the first failure (the caller restores).
    fn apply_updates(
        &mut self,
        measurement: Option<&[f64; 3]>,
        declared: &[Option<&[f64]>; 3],
        readings: &[Option<&[f64]>],
        nis: &mut [f64; 4],
        updated: &mut bool,
    ) -> Result<(), NavError> {
        self.pending.iter_mut().for_each(|r| *r = None);
        if let Some(z) = measurement {
            let u = self.update_checked(z)?;
            nis[0] = u.nis;
            *updated = true;
        }
        for (i, z) in declared.iter().enumerate() {
            if let Some(z) = z {
                let Some(s) = self.declared.all().get(i).copied() else {
                    continue;
                };
                let r = s.apply(&mut self.filter, z)?;
                nis[i + 1] = r.nis;
                *updated = true;
            }
        }
        for (i, z) in readings.iter().enumerate() {
            if let (Some(z), Some(s)) = (z, self.sensors.get(i)) {
                self.pending[i] = Some(s.apply(&mut self.filter, z)?);
                *updated = true;
            }
        }
        Ok(())
    }

    /// The declared sensors' `readings` ([`Readings`]) applied at the current time, with no
    /// prediction (a measurement that arrives inside a step: FMI 3.0's Event Mode): every
    /// reading checked before anything changes; all or none applied.
    pub fn update_readings(&mut self, readings: &Readings) -> Result<(), NavError> {
        let declared = [
            readings.camera.as_ref().map(|z| &z[..]),
            readings.gnss_position.as_ref().map(|z| &z[..]),
            readings.gnss_velocity.as_ref().map(|z| &z[..]),
        ];
        let radio = readings.radio.as_ref();
        if radio.is_none() && declared.iter().all(Option::is_none) {
            return Ok(());
        }
        if let Some(z) = radio {
            Self::check_measurement(z)?;
        }
        for (s, z) in self.declared.all().into_iter().zip(&declared) {
            if let Some(z) = z {
                s.check(z).map_err(NavError::invalid)?;
            }
        }
        self.check_not_failed()?;
        self.tallied(|nav| {
            let saved = nav.filter.snapshot();
            let last = nav.last_update;
            let mut nis = [f64::NAN; 4];
            let mut updated = false;
            let result = nav.apply_updates(radio, &declared, &[], &mut nis, &mut updated);
            match (&result, saved) {
                (Ok(()), _) => nav.step_nis = nis,
                (Err(_), Snapshot::None) => nav.failed |= updated,
                (Err(_), s) => {
                    nav.filter.restore(&s);
                    nav.last_update = last;
                }
            }
            result
        })
    }

    /// [`Navigator::step_all`] with exactly one reading (of a declared or an added sensor)
    /// and a filter with a fused update and prediction: the step done, `Ok(true)`;
    /// otherwise `Ok(false)` and nothing changed. On error nothing changed either.
    #[inline(always)]
    fn step_one(
        &mut self,
        thrust: &[f64; 3],
        declared: &[Option<&[f64]>; 3],
        readings: &[Option<&[f64]>],
        dt: f64,
    ) -> Result<bool, NavError> {
        let mut given = declared
            .iter()
            .enumerate()
            .filter_map(|(i, z)| z.map(|z| (Some(i), None, z)))
            .chain(
                readings
                    .iter()
                    .take(self.sensors.len())
                    .enumerate()
                    .filter_map(|(i, z)| z.map(|z| (None, Some(i), z))),
            );
        let (Some((declared_i, added_i, z)), None) = (given.next(), given.next()) else {
            return Ok(false);
        };
        let declared = self.declared.all();
        let sensor: &dyn NavSensor = match (declared_i, added_i) {
            (Some(i), _) => match declared.get(i) {
                Some(s) => *s,
                None => return Ok(false),
            },
            (_, Some(i)) => match self.sensors.get(i) {
                Some(s) => &**s,
                None => return Ok(false),
            },
            _ => return Ok(false),
        };
        let accel = canonical_accel(&self.cfg, thrust);
        let Some(r) = sensor.apply_predict(&mut self.filter, z, &self.step_cache, &accel) else {
            return Ok(false);
        };
        let report = r?;
        self.t += dt;
        let mut nis = [f64::NAN; 4];
        if let Some(i) = declared_i {
            nis[i + 1] = report.nis;
        }
        if let Some(i) = added_i {
            self.reports[i] = Some(report);
        }
        self.step_nis = nis;
        Ok(true)
    }

    /// Back to the initial estimate. A particle filter is rebuilt from its settings (new
    /// particles drawn with the configured seed), so a reset navigator reproduces a new one
    /// bit for bit; a failed particle filter works again.
    pub fn reset(&mut self) {
        let (x0, p0) = (self.cfg.initial_state(), self.cfg.initial_covariance());
        Member::reset(&mut self.filter, x0, p0);
        self.last_update = None;
        self.reports.iter_mut().for_each(|r| *r = None);
        self.step_nis = [f64::NAN; 4];
        self.step_acceptance = f64::NAN;
        self.failed = false;
        self.t = 0.0;
    }

    /// State estimate in the I/O frame.
    pub fn state(&self) -> State {
        self.cfg.frame.state_from_canonical(self.filter.state())
    }

    /// Covariance in the I/O frame.
    pub fn covariance(&self) -> Mat6 {
        self.cfg.frame.cov_from_canonical(self.filter.covariance())
    }

    /// 1-sigma per state component in the I/O frame: the square roots of the covariance's
    /// diagonal. A NaN or negative variance (a failed filter; the H-infinity filter, which
    /// has no covariance) gives NaN, never a reassuring 0. The C ABI, the FMU and the
    /// Python package all report this.
    pub fn sigma(&self) -> [f64; 6] {
        let p = self
            .cfg
            .frame
            .variances_from_canonical(self.filter.covariance());
        core::array::from_fn(|i| {
            let v = p[i];
            if v >= 0.0 {
                v.sqrt()
            } else {
                f64::NAN
            }
        })
    }

    /// Diagnostics of the last measurement update, if any since construction or reset.
    /// Point particles report the innovation of their weighted mean and no NIS (NaN); the
    /// particle prior's Gaussian sum reports its mixture's innovation and NIS.
    pub fn last_update(&self) -> Option<UpdateInfo> {
        self.last_update
    }

    /// Effective sample size `1 / sum w_i^2` of a particle filter after its last update
    /// (before resampling; the particle count before the first update), in
    /// `[1, particles]` (clamped there against rounding of the normalised weights). `None`
    /// for the Kalman filters, which carry no particles.
    pub fn ess(&self) -> Option<f64> {
        match &self.filter {
            #[cfg(feature = "std")]
            AnyFilter::Pf(pf) => Some(pf.ess().clamp(1.0, pf.params().particles as f64)),
            #[cfg(feature = "std")]
            AnyFilter::GaussianSum(g) => Some(g.stats().0.clamp(1.0, g.len() as f64)),
            _ => None,
        }
    }

    /// The AQUKF's current adaptive velocity density `q_vv` [m^2/s^3] in the I/O frame:
    /// the diagonal of `T blockdiag(0, diag(q_vv)) T^T`. Every frame rotation is a signed
    /// permutation, so the rotated matrix is diagonal again and this is exact (entries
    /// permuted). `None` for the other filters.
    pub fn q_vv(&self) -> Option<[f64; 3]> {
        fn canonical(f: &AnyFilter) -> Option<Vec3> {
            match f {
                AnyFilter::Aqukf(f) => Some(f.q_vv()),
                // the members' weighted mean
                #[cfg(feature = "std")]
                AnyFilter::Bank(b) => b.weighted().map(|(w, m)| canonical(m).map(|q| q * w)).sum(),
                _ => None,
            }
        }
        match canonical(&self.filter) {
            Some(q) => {
                let c = Mat6::from_diagonal(&State::from([0.0, 0.0, 0.0, q[0], q[1], q[2]]));
                let io = self.cfg.frame.cov_from_canonical(&c);
                Some([io[(3, 3)], io[(4, 4)], io[(5, 5)]])
            }
            _ => None,
        }
    }

    /// The IMM's (filter code 10) mode probabilities after the last step, NaN past
    /// `imm_modes`; `None` for the other filters.
    pub fn mode_probabilities(&self) -> Option<[f64; MAX_MODES]> {
        fn canonical(f: &AnyFilter) -> Option<([f64; MAX_MODES], usize)> {
            match f {
                AnyFilter::Imm(f) => Some((f.mode_probabilities(), f.params().modes)),
                // a bank of IMMs: each mode's probability over the members
                #[cfg(feature = "std")]
                AnyFilter::Bank(b) => {
                    b.weighted().try_fold(([0.0; MAX_MODES], 0), |acc, (w, m)| {
                        let (mu, r) = canonical(m)?;
                        Some((core::array::from_fn(|j| acc.0[j] + w * mu[j]), r))
                    })
                }
                _ => None,
            }
        }
        match canonical(&self.filter) {
            Some((mu, r)) => Some(core::array::from_fn(
                |j| {
                    if j < r {
                        mu[j]
                    } else {
                        f64::NAN
                    }
                },
            )),
            _ => None,
        }
    }

    /// The certified `gamma` of the H-infinity design (filter code 9), `None` otherwise.
    pub fn hinf_gamma(&self) -> Option<f64> {
        self.filter.hinf().map(crate::hinf::HinfEstimator::gamma)
    }

    /// How the H-infinity filter was designed (filter code 9; route, Riccati record,
    /// iterations: [`crate::hinf::HinfDesignInfo`]), `None` otherwise.
    pub fn hinf_design_info(&self) -> Option<crate::hinf::HinfDesignInfo> {
        self.filter.hinf().and_then(|f| f.design_info().copied())
    }

    /// The H2 norm of the H-infinity design (filter code 9; see
    /// [`crate::hinf::design::HinfDesign::h2_norm`]), `None` otherwise.
    pub fn hinf_h2_norm(&self) -> Option<f64> {
        self.filter.hinf().map(crate::hinf::HinfEstimator::h2_norm)
    }

    /// Whether the H-infinity filter (code 9) runs its designed, certified gain (true
    /// after the hand-over of track initiation, or always without it); `None` for the
    /// other filters.
    pub fn hinf_certified(&self) -> Option<bool> {
        self.filter
            .hinf()
            .map(crate::hinf::HinfEstimator::certified)
    }

    /// The estimator itself (canonical frame).
    pub fn filter(&self) -> &AnyFilter {
        &self.filter
    }
}
