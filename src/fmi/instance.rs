//! One FMU instance: the values of the variable table, the call-order state machine, and
//! the model logic (build a C-ABI configuration from the parameters, step the estimator,
//! publish the outputs). It talks to the estimator only through the C ABI ([`crate::ffi`]),
//! like the Reference-FMUs keep `model.c` apart from `fmi2Functions.c`.

use super::description::LOG_CATEGORIES;
use super::types::*;
use super::variables::{lookup, vr, Causality, VarDef, VarType, N_VARS, VARIABLES};
use crate::ffi::{self, relnav_config, relnav_estimator, relnav_status};
use std::ffi::{c_int, CStr, CString};

/// States of the FMI 2.0 co-simulation state machine (bit flags for "allowed in" masks).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u32)]
pub enum ModelState {
    /// After `fmi2Instantiate` or `fmi2Reset`.
    Instantiated = 1,
    /// Between enter and exit initialisation mode.
    InitializationMode = 2,
    /// Ready for `fmi2DoStep`.
    StepComplete = 4,
    /// After `fmi2Terminate`.
    Terminated = 8,
    /// After a call returned `fmi2Error`.
    Error = 16,
}

/// Mask of every state.
pub const ANY_STATE: u32 = 31;

/// A failure inside an FMI call: status plus the message for the log.
#[derive(Debug)]
pub struct FmiFailure {
    /// Status returned to the master.
    pub status: fmi2Status,
    /// Reason, logged under `logStatusError` (or `logStatusWarning`).
    pub message: String,
}

/// Shorthand for an `fmi2Error` failure.
pub fn error(message: String) -> FmiFailure {
    FmiFailure {
        status: fmi2Status::fmi2Error,
        message,
    }
}

/// The logger callback and its environment, copied at instantiation.
#[derive(Clone, Copy)]
pub struct Logger {
    callback: fmi2CallbackLogger,
    env: fmi2ComponentEnvironment,
}

impl Logger {
    /// Wrap the master's callback (which may be absent).
    pub fn new(callback: fmi2CallbackLogger, env: fmi2ComponentEnvironment) -> Self {
        Self { callback, env }
    }

    /// Send one message. The text goes through `"%s"` so `%` is never interpreted;
    /// `#` is FMI's escape character and is doubled.
    pub fn log(&self, instance: &CStr, status: fmi2Status, category: &str, msg: &str) {
        let Some(cb) = self.callback else { return };
        let escaped: String = msg
            .replace('#', "##")
            .chars()
            .filter(|c| *c != '\0')
            .take(1500)
            .collect();
        let (Ok(text), Ok(cat)) = (CString::new(escaped), CString::new(category)) else {
            return;
        };
        // SAFETY: the master gave us this callback for the lifetime of the instance; all
        // strings are NUL-terminated and live across the call; the format "%s" consumes
        // exactly one `const char*` argument.
        unsafe {
            cb(
                self.env,
                instance.as_ptr(),
                status as c_int,
                cat.as_ptr(),
                c"%s".as_ptr(),
                text.as_ptr(),
            )
        };
    }
}

/// All data of one instance.
pub struct Instance {
    /// Instance name given by the master.
    pub name: CString,
    logger: Logger,
    logging_on: bool,
    categories: [bool; LOG_CATEGORIES.len()],
    /// Current state of the state machine.
    pub state: ModelState,
    values: [f64; N_VARS],
    estimator: *mut relnav_estimator,
    time: f64,
    start_time: f64,
    stop_time: Option<f64>,
}

impl Drop for Instance {
    fn drop(&mut self) {
        self.free_estimator();
    }
}

/// Where `fmi2Set*` may write a variable, per state (FMI 2.0 sec. 4.2.4, CS state table).
fn settable(def: &VarDef, state: ModelState) -> bool {
    match state {
        ModelState::Instantiated | ModelState::InitializationMode => {
            def.causality != Causality::Output
        }
        ModelState::StepComplete => def.causality == Causality::Input,
        ModelState::Terminated | ModelState::Error => false,
    }
}

fn status_of(s: relnav_status) -> Result<(), FmiFailure> {
    if s == relnav_status::RELNAV_OK {
        Ok(())
    } else {
        let msg = {
            // SAFETY: relnav_last_error returns a valid NUL-terminated string.
            let p = ffi::relnav_last_error();
            unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
        };
        Err(error(msg))
    }
}

impl Instance {
    /// A freshly instantiated FMU with every variable at its start value.
    pub fn new(name: CString, logger: Logger, logging_on: bool) -> Self {
        let mut inst = Self {
            name,
            logger,
            logging_on,
            categories: [true; LOG_CATEGORIES.len()],
            state: ModelState::Instantiated,
            values: [0.0; N_VARS],
            estimator: std::ptr::null_mut(),
            time: 0.0,
            start_time: 0.0,
            stop_time: None,
        };
        inst.set_start_values();
        inst
    }

    fn set_start_values(&mut self) {
        for v in VARIABLES {
            self.values[v.vr as usize] = v.start;
        }
        self.publish_initial_outputs();
    }

    fn free_estimator(&mut self) {
        if !self.estimator.is_null() {
            // SAFETY: the handle came from relnav_estimator_new and is freed once.
            unsafe { ffi::relnav_estimator_free(self.estimator) };
            self.estimator = std::ptr::null_mut();
        }
    }

    /// Log a message in `category` (errors are always sent; other categories only when
    /// logging is on and the category is enabled).
    pub fn log(&self, status: fmi2Status, category: &str, msg: &str) {
        let idx = LOG_CATEGORIES.iter().position(|(n, _)| *n == category);
        let enabled = match idx {
            Some(0) => true,
            Some(i) => self.logging_on && self.categories[i],
            None => self.logging_on,
        };
        if enabled {
            self.logger.log(&self.name, status, category, msg);
        }
    }

    /// Whether `logCalls` messages would be sent (to avoid formatting them otherwise).
    pub fn logs_calls(&self) -> bool {
        self.logging_on && self.categories[3]
    }

    /// `fmi2SetDebugLogging`.
    pub fn set_debug_logging(&mut self, on: bool, names: &[&str]) -> Result<(), FmiFailure> {
        if names.is_empty() {
            self.logging_on = on;
            self.categories = [on; LOG_CATEGORIES.len()];
            return Ok(());
        }
        for n in names {
            let i = LOG_CATEGORIES
                .iter()
                .position(|(c, _)| c == n)
                .ok_or_else(|| {
                    error(format!("fmi2SetDebugLogging: unknown log category \"{n}\""))
                })?;
            self.categories[i] = on;
        }
        if on {
            self.logging_on = true;
        }
        Ok(())
    }

    /// Check the call is allowed in the current state.
    pub fn require(&self, func: &str, allowed: u32) -> Result<(), FmiFailure> {
        if self.state as u32 & allowed != 0 {
            Ok(())
        } else {
            Err(error(format!(
                "{func}: illegal call sequence (not allowed in state {:?})",
                self.state
            )))
        }
    }

    /// `fmi2SetupExperiment`.
    pub fn setup_experiment(&mut self, start: f64, stop: Option<f64>) -> Result<(), FmiFailure> {
        if !start.is_finite() {
            return Err(error(format!(
                "fmi2SetupExperiment: startTime {start} is not finite"
            )));
        }
        if let Some(s) = stop {
            if !(s >= start) {
                return Err(error(format!(
                    "fmi2SetupExperiment: stopTime {s} is before startTime {start}"
                )));
            }
        }
        self.start_time = start;
        self.time = start;
        self.stop_time = stop;
        Ok(())
    }

    /// `fmi2EnterInitializationMode`.
    pub fn enter_initialization(&mut self) {
        self.state = ModelState::InitializationMode;
        self.publish_initial_outputs();
    }

    /// The C-ABI configuration assembled from the parameter values.
    pub fn config(&self) -> relnav_config {
        let v = |r: u32| self.values[r as usize];
        let mut c = ffi::relnav_config_default();
        c.filter = v(vr::FILTER) as i32;
        c.frame = v(vr::FRAME) as i32;
        c.discretization = v(vr::DISCRETIZATION) as i32;
        c.mean_motion = v(vr::MEAN_MOTION);
        c.chaser_mass = v(vr::CHASER_MASS);
        c.sigma_range = v(vr::SIGMA_RANGE);
        c.sigma_angle = v(vr::SIGMA_ANGLE);
        c.x0 = [vr::X0, vr::Y0, vr::Z0, vr::VX0, vr::VY0, vr::VZ0].map(v);
        c.sigma_pos0 = v(vr::SIGMA_POS0);
        c.sigma_vel0 = v(vr::SIGMA_VEL0);
        c.accel_psd = v(vr::ACCEL_PSD);
        c.q_pos = [vr::Q_POS_X, vr::Q_POS_Y, vr::Q_POS_Z].map(v);
        c.q_vel = [vr::Q_VEL_X, vr::Q_VEL_Y, vr::Q_VEL_Z].map(v);
        c.ukf_alpha = v(vr::UKF_ALPHA);
        c.ukf_beta = v(vr::UKF_BETA);
        c.ukf_kappa = v(vr::UKF_KAPPA);
        // FMI Integers are 32-bit; the seed's bit pattern is kept
        c.seed = u64::from(v(vr::SEED) as i32 as u32);
        c.particles = v(vr::PARTICLES) as i32;
        c.resampler = v(vr::RESAMPLER) as i32;
        c.resample_threshold = v(vr::RESAMPLE_THRESHOLD);
        c.noise_model = v(vr::NOISE_MODEL) as i32;
        c.noise_zeta = v(vr::NOISE_ZETA);
        c.noise_scale = v(vr::NOISE_SCALE);
        c.noise_dof = v(vr::NOISE_DOF);
        c.window = v(vr::WINDOW) as i32;
        c.hinf_period = v(vr::HINF_PERIOD);
        c.hinf_delta_bar = v(vr::HINF_DELTA_BAR);
        c.hinf_b_pos = v(vr::HINF_B_POS);
        c.hinf_b_vel = v(vr::HINF_B_VEL);
        c.hinf_d = v(vr::HINF_D);
        c.pf_move = v(vr::PF_MOVE) as i32;
        c.pf_threads = v(vr::PF_THREADS) as i32;
        c
    }

    /// Whether the `filter` parameter selects a particle filter (codes 4-8).
    fn particle_filter_selected(&self) -> bool {
        (4.0..=8.0).contains(&self.values[vr::FILTER as usize])
    }

    /// Outputs before the first step: the initial estimate and its 1-sigma; `ess` is the
    /// particle count for a particle filter (equal weights) and NaN for a Kalman filter.
    fn publish_initial_outputs(&mut self) {
        let v = self.values;
        let x0 = [vr::X0, vr::Y0, vr::Z0, vr::VX0, vr::VY0, vr::VZ0].map(|r| v[r as usize]);
        let (sp, sv) = (v[vr::SIGMA_POS0 as usize], v[vr::SIGMA_VEL0 as usize]);
        if self.values[vr::FILTER as usize] == 9.0 {
            // no Gaussian covariance exists for the H-infinity filter: NaN, as after init
            self.write_outputs(&x0, &[f64::NAN; 6]);
        } else {
            self.write_outputs(&x0, &[sp, sp, sp, sv, sv, sv]);
        }
        self.values[vr::HINF_GAMMA as usize] = f64::NAN;
        self.values[vr::ESS as usize] = if self.particle_filter_selected() {
            v[vr::PARTICLES as usize]
        } else {
            f64::NAN
        };
        // the AQUKF starts from q_vel (clipped into [floor, ceiling] by the library)
        let aqukf = v[vr::FILTER as usize] == 3.0;
        let def = ffi::relnav_config_default();
        for (out, q) in [
            (vr::Q_VV_X, vr::Q_VEL_X),
            (vr::Q_VV_Y, vr::Q_VEL_Y),
            (vr::Q_VV_Z, vr::Q_VEL_Z),
        ] {
            self.values[out as usize] = if aqukf {
                v[q as usize].clamp(def.q_vv_floor, def.q_vv_ceiling.max(def.q_vv_floor))
            } else {
                f64::NAN
            };
        }
    }

    fn write_outputs(&mut self, x: &[f64; 6], sigma: &[f64; 6]) {
        let outs = [vr::X, vr::Y, vr::Z, vr::VX, vr::VY, vr::VZ];
        let sigs = [
            vr::SIGMA_X,
            vr::SIGMA_Y,
            vr::SIGMA_Z,
            vr::SIGMA_VX,
            vr::SIGMA_VY,
            vr::SIGMA_VZ,
        ];
        for i in 0..6 {
            self.values[outs[i] as usize] = x[i];
            self.values[sigs[i] as usize] = sigma[i];
        }
    }

    fn publish_estimate(&mut self) -> Result<(), FmiFailure> {
        let mut x = [0.0; 6];
        let mut s = [0.0; 6];
        // SAFETY: `estimator` is live (created at exit-init); the arrays hold 6 doubles.
        status_of(unsafe { ffi::relnav_estimator_get_state(self.estimator, x.as_mut_ptr()) })?;
        // SAFETY: as above.
        status_of(unsafe { ffi::relnav_estimator_get_sigma(self.estimator, s.as_mut_ptr()) })?;
        let mut ess = f64::NAN;
        // SAFETY: as above; `ess` is a writable local.
        status_of(unsafe { ffi::relnav_estimator_get_ess(self.estimator, &mut ess) })?;
        let mut q = [f64::NAN; 3];
        // SAFETY: as above; `q` holds 3 doubles.
        status_of(unsafe { ffi::relnav_estimator_get_q_vv(self.estimator, q.as_mut_ptr()) })?;
        let mut gamma = f64::NAN;
        // SAFETY: as above; `gamma` is a writable local.
        status_of(unsafe { ffi::relnav_estimator_get_hinf_gamma(self.estimator, &mut gamma) })?;
        self.write_outputs(&x, &s);
        self.values[vr::ESS as usize] = ess;
        self.values[vr::Q_VV_X as usize] = q[0];
        self.values[vr::Q_VV_Y as usize] = q[1];
        self.values[vr::Q_VV_Z as usize] = q[2];
        self.values[vr::HINF_GAMMA as usize] = gamma;
        Ok(())
    }

    /// `fmi2ExitInitializationMode`: validate the parameters and create the estimator.
    pub fn exit_initialization(&mut self) -> Result<(), FmiFailure> {
        self.free_estimator();
        let cfg = self.config();
        let mut est = std::ptr::null_mut();
        // SAFETY: both pointers are valid locals.
        let st = unsafe { ffi::relnav_estimator_new(&cfg, &mut est) };
        status_of(st).map_err(|e| error(format!("invalid parameters: {}", e.message)))?;
        self.estimator = est;
        self.publish_estimate()?;
        self.state = ModelState::StepComplete;
        if self.logging_on {
            let pf = if self.particle_filter_selected() {
                format!(
                    ", particles {}, resampler {}, resample_threshold {}, seed {}",
                    cfg.particles, cfg.resampler, cfg.resample_threshold, cfg.seed
                )
            } else if cfg.filter == 9 {
                format!(
                    ", hinf: observer design for hinf_period {} s, delta_bar {}, b_pos {}, b_vel {}, d {}: gamma = {}",
                    cfg.hinf_period,
                    cfg.hinf_delta_bar,
                    cfg.hinf_b_pos,
                    cfg.hinf_b_vel,
                    cfg.hinf_d,
                    self.values[vr::HINF_GAMMA as usize]
                )
            } else {
                String::new()
            };
            self.log(
                fmi2Status::fmi2OK,
                "logInfo",
                &format!(
                    "initialised: filter {}, frame {}, mean_motion {} rad/s, chaser_mass {} kg, sigma_range {} m, sigma_angle {} rad, noise_model {}{pf}, t0 = {} s",
                    cfg.filter, cfg.frame, cfg.mean_motion, cfg.chaser_mass, cfg.sigma_range, cfg.sigma_angle, cfg.noise_model, self.time
                ),
            );
        }
        Ok(())
    }

    /// `fmi2DoStep(tc, h)`: measurement at `tc` (if valid), then prediction to `tc + h`.
    pub fn do_step(&mut self, tc: f64, h: f64) -> Result<(), FmiFailure> {
        if !(h.is_finite() && h > 0.0) {
            return Err(error(format!(
                "fmi2DoStep: communicationStepSize must be finite and > 0 (got {h})"
            )));
        }
        let tol = 1e-9 * self.time.abs().max(1.0);
        if !tc.is_finite() || (tc - self.time).abs() > tol {
            return Err(error(format!(
                "fmi2DoStep: currentCommunicationPoint {tc} does not match the FMU's time {}",
                self.time
            )));
        }
        if let Some(stop) = self.stop_time {
            if tc + h > stop + 1e-9 * stop.abs().max(1.0) {
                return Err(error(format!(
                    "fmi2DoStep: step to {} goes past stopTime {stop}",
                    tc + h
                )));
            }
        }
        let v = &self.values;
        let thrust = [vr::THRUST_X, vr::THRUST_Y, vr::THRUST_Z].map(|r| v[r as usize]);
        let z = [vr::RANGE, vr::AZIMUTH, vr::ELEVATION].map(|r| v[r as usize]);
        let valid = v[vr::MEASUREMENT_VALID as usize] != 0.0;
        let zp = if valid { z.as_ptr() } else { std::ptr::null() };
        // SAFETY: `estimator` is live in StepComplete; arrays hold 3 doubles.
        let st = unsafe { ffi::relnav_estimator_step(self.estimator, thrust.as_ptr(), zp, h) };
        status_of(st).map_err(|e| error(format!("fmi2DoStep at t = {tc}: {}", e.message)))?;
        self.time = tc + h;
        self.publish_estimate()
    }

    /// `fmi2Reset`: back to the just-instantiated state with start values.
    pub fn reset(&mut self) {
        self.free_estimator();
        self.set_start_values();
        self.time = 0.0;
        self.start_time = 0.0;
        self.stop_time = None;
        self.state = ModelState::Instantiated;
    }

    /// `fmi2Terminate`.
    pub fn terminate(&mut self) {
        self.state = ModelState::Terminated;
    }

    /// Last successful communication time.
    pub fn time(&self) -> f64 {
        self.time
    }

    fn def(&self, r: fmi2ValueReference, func: &str) -> Result<&'static VarDef, FmiFailure> {
        lookup(r).ok_or_else(|| error(format!("{func}: unknown value reference {r}")))
    }

    /// Read a variable of the expected base type (`want` is a predicate on its type).
    pub fn get(
        &self,
        r: fmi2ValueReference,
        func: &str,
        want: fn(&VarType) -> bool,
    ) -> Result<f64, FmiFailure> {
        let d = self.def(r, func)?;
        if !want(&d.ty) {
            return Err(error(format!(
                "{func}: variable {} (vr {r}) has another type",
                d.name
            )));
        }
        Ok(self.values[r as usize])
    }

    /// Write a variable of the expected base type, checking causality, state and domain.
    pub fn set(
        &mut self,
        r: fmi2ValueReference,
        value: f64,
        func: &str,
        want: fn(&VarType) -> bool,
    ) -> Result<(), FmiFailure> {
        let d = self.def(r, func)?;
        if !want(&d.ty) {
            return Err(error(format!(
                "{func}: variable {} (vr {r}) has another type",
                d.name
            )));
        }
        if !settable(d, self.state) {
            return Err(error(format!(
                "{func}: variable {} ({:?}) cannot be set in state {:?}",
                d.name, d.causality, self.state
            )));
        }
        if let VarType::Enumeration(t) = d.ty {
            if !t.items.iter().any(|it| f64::from(it.1) == value) {
                let allowed: Vec<String> = t
                    .items
                    .iter()
                    .map(|it| format!("{} {}", it.1, it.0))
                    .collect();
                return Err(error(format!(
                    "{func}: {} = {value} is not a valid {} (allowed: {})",
                    d.name,
                    t.name,
                    allowed.join(", ")
                )));
            }
        }
        self.values[r as usize] = value;
        if matches!(
            self.state,
            ModelState::Instantiated | ModelState::InitializationMode
        ) {
            self.publish_initial_outputs();
        }
        Ok(())
    }
}
