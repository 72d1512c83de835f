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

    /// Send one message. The logger's message is a `printf` format (FMI 2.0 sec. 2.1.5),
    /// so the text itself is passed as the format with `%` escaped as `%%` and no
    /// arguments: a master that formats shows the text, and one that prints the format
    /// as it is still shows it (with `%%`). `#` is FMI's escape character (`#r12#` names a
    /// variable) and is doubled. Messages are cut at [`MAX_LOG_CHARS`] characters (fmpy
    /// formats into 2048 bytes), with ` ...` appended.
    pub fn log(&self, instance: &CStr, status: fmi2Status, category: &str, msg: &str) {
        let Some(cb) = self.callback else { return };
        let Ok(cat) = CString::new(category) else {
            return;
        };
        let Ok(text) = CString::new(escape_log_message(msg)) else {
            return;
        };
        // SAFETY: the master gave us this callback for the lifetime of the instance; all
        // strings are NUL-terminated and live across the call; the format contains no
        // conversion (every `%` is doubled), so no variadic argument is read.
        unsafe {
            cb(
                self.env,
                instance.as_ptr(),
                status as c_int,
                cat.as_ptr(),
                text.as_ptr(),
            )
        };
    }
}

/// Longest message sent to the logger, in characters before escaping.
pub const MAX_LOG_CHARS: usize = 1500;

/// A log message as the logger's `printf` format: NULs dropped, cut at
/// [`MAX_LOG_CHARS`] characters (` ...` appended), then `%` -> `%%` and `#` -> `##`.
pub fn escape_log_message(msg: &str) -> String {
    let mut out = String::with_capacity(msg.len() + 8);
    for (i, c) in msg.chars().filter(|c| *c != '\0').enumerate() {
        if i == MAX_LOG_CHARS {
            out.push_str(" ...");
            break;
        }
        match c {
            '%' => out.push_str("%%"),
            '#' => out.push_str("##"),
            c => out.push(c),
        }
    }
    out
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
    /// The FMU states handed out by `fmi2GetFMUstate` / `fmi2DeSerializeFMUstate`.
    pub states: super::state::StateRegistry,
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

/// Parameters whose valid values depend on another parameter, with that partner set to
/// its most permissive value for [`check_alone`]:
/// * `hinf_period` must satisfy `mean_motion * hinf_period <= 0.5`, and the smallest
///   `mean_motion` the library accepts is 1e-9 rad/s (`nav::MEAN_MOTION_RANGE`, checked by
///   a test), so only periods that no orbit admits are refused before
///   fmi2ExitInitializationMode;
/// * `hinf_b_pos` and `hinf_b_vel` are set together (both > 0) or derived together (both
///   0): the partner takes the value's kind (1 for a positive value, else 0).
fn permissive_partner(vr_: u32, value: f64) -> Option<(u32, f64)> {
    let same_kind = if value > 0.0 { 1.0 } else { 0.0 };
    match vr_ {
        vr::HINF_PERIOD => Some((vr::MEAN_MOTION, 1e-9)),
        vr::HINF_B_POS => Some((vr::HINF_B_VEL, same_kind)),
        vr::HINF_B_VEL => Some((vr::HINF_B_POS, same_kind)),
        _ => None,
    }
}

/// Refuse a parameter value that is invalid whatever the other parameters are, at
/// `fmi2Set*` time: the earliest point, where the error belongs to the call and value
/// that caused it (fmpy raises there; libcosim, which sets initial values during its own
/// initialisation, aborts either way; Ecos ignores both). The check is
/// the library's own (`relnav_config_validate`) on the start values with this one value
/// changed: every start value is valid and, apart from [`permissive_partner`], no check
/// couples a parameter to one whose start value could make a valid value fail, so
/// nothing valid is refused early. Combinations are checked at
/// fmi2ExitInitializationMode.
fn check_alone(def: &VarDef, value: f64) -> Result<(), FmiFailure> {
    let mut values = [0.0; N_VARS];
    for v in VARIABLES {
        values[v.vr as usize] = v.start;
    }
    values[def.vr as usize] = value;
    if let Some((partner, loose)) = permissive_partner(def.vr, value) {
        values[partner as usize] = loose;
    }
    let cfg = config_of(&values);
    // SAFETY: a valid local configuration.
    status_of(unsafe { ffi::relnav_config_validate(&cfg) })
}

/// A value as the master gave it: an integer for Integer and code variables.
fn show(def: &VarDef, value: f64) -> String {
    match def.ty {
        VarType::Real(_) => format!("{value}"),
        VarType::Boolean => format!("{}", value != 0.0),
        VarType::Integer | VarType::Code(_) => format!("{}", value as i64),
    }
}

pub(super) fn status_of(s: relnav_status) -> Result<(), FmiFailure> {
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
            states: Default::default(),
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

    /// Record a failed call's status in the `fmi_status` output (the worst so far).
    pub fn note_status(&mut self, status: fmi2Status) {
        let v = &mut self.values[vr::FMI_STATUS as usize];
        *v = v.max(f64::from(status as i32));
    }

    /// Whether `logCalls` messages would be sent (to avoid formatting them otherwise).
    pub fn logs_calls(&self) -> bool {
        self.logging_on && self.categories[3]
    }

    /// Log a call under `logCalls`, formatting the message only when it is sent.
    pub fn log_call(&self, msg: impl FnOnce() -> String) {
        if self.logs_calls() {
            self.log(fmi2Status::fmi2OK, "logCalls", &msg());
        }
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
        config_of(&self.values)
    }
}

/// The C-ABI configuration from the values of the variable table (indexed by value
/// reference; parameters are read, other variables ignored): the one mapping from FMU
/// parameters to a `relnav_config`, shared with the front ends that take parameters by
/// their FMU names (the Python package). Fields that are not FMU parameters keep
/// [`ffi::relnav_config_default`]'s values; codes and Integers are the integers their
/// `f64` holds.
pub fn config_of(values: &[f64; N_VARS]) -> relnav_config {
    {
        let v = |r: u32| values[r as usize];
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
        c.hinf_design = v(vr::HINF_DESIGN) as i32;
        c.hinf_gamma_factor = v(vr::HINF_GAMMA_FACTOR);
        c.hinf_acquisition = i32::from(v(vr::HINF_ACQUISITION) != 0.0);
        c.aq_law = v(vr::AQ_LAW) as i32;
        c.aq_gate_window = v(vr::AQ_GATE_WINDOW) as i32;
        c.aq_gate_quantile = v(vr::AQ_GATE_QUANTILE);
        c.imm_modes = v(vr::IMM_MODES) as i32;
        c.imm_accel_psd = [
            vr::IMM_ACCEL_PSD_1,
            vr::IMM_ACCEL_PSD_2,
            vr::IMM_ACCEL_PSD_3,
        ]
        .map(v);
        c.imm_p_stay = [vr::IMM_P_STAY_1, vr::IMM_P_STAY_2, vr::IMM_P_STAY_3].map(v);
        c.pf_move = i32::from(v(vr::PF_MOVE) != 0.0);
        c.pf_threads = v(vr::PF_THREADS) as i32;
        c
    }
}

impl Instance {
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
        self.values[vr::HINF_H2_NORM as usize] = f64::NAN;
        self.values[vr::HINF_CERTIFIED as usize] = 0.0;
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
        // the IMM starts at the stationary distribution of its mode chain, mu_j ~ 1 / (1 - p_j)
        let imm = v[vr::FILTER as usize] == 10.0;
        let modes = v[vr::IMM_MODES as usize];
        let stay = [vr::IMM_P_STAY_1, vr::IMM_P_STAY_2, vr::IMM_P_STAY_3].map(|r| v[r as usize]);
        let used = |j: usize| (j as f64) < modes;
        let total: f64 = (0..3)
            .filter(|j| used(*j))
            .map(|j| 1.0 / (1.0 - stay[j]))
            .sum();
        for (j, out) in [vr::IMM_MU_1, vr::IMM_MU_2, vr::IMM_MU_3]
            .iter()
            .enumerate()
        {
            self.values[*out as usize] = if imm && used(j) {
                1.0 / (1.0 - stay[j]) / total
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
        let mut h2 = f64::NAN;
        // SAFETY: as above; `h2` is a writable local.
        status_of(unsafe { ffi::relnav_estimator_get_hinf_h2_norm(self.estimator, &mut h2) })?;
        let mut certified = -1;
        // SAFETY: as above; `certified` is a writable local.
        status_of(unsafe {
            ffi::relnav_estimator_get_hinf_certified(self.estimator, &mut certified)
        })?;
        let mut mu = [f64::NAN; 3];
        // SAFETY: as above; `mu` holds 3 doubles.
        status_of(unsafe {
            ffi::relnav_estimator_get_mode_probabilities(self.estimator, mu.as_mut_ptr())
        })?;
        self.values[vr::IMM_MU_1 as usize] = mu[0];
        self.values[vr::IMM_MU_2 as usize] = mu[1];
        self.values[vr::IMM_MU_3 as usize] = mu[2];
        self.write_outputs(&x, &s);
        self.values[vr::ESS as usize] = ess;
        self.values[vr::Q_VV_X as usize] = q[0];
        self.values[vr::Q_VV_Y as usize] = q[1];
        self.values[vr::Q_VV_Z as usize] = q[2];
        self.values[vr::HINF_GAMMA as usize] = gamma;
        self.values[vr::HINF_H2_NORM as usize] = h2;
        self.values[vr::HINF_CERTIFIED as usize] = f64::from(u8::from(certified == 1));
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
                let noise = |v: f64| {
                    if v == 0.0 {
                        "derived".to_string()
                    } else {
                        v.to_string()
                    }
                };
                format!(
                    ", hinf: {} observer design (gamma_factor {}) for hinf_period {} s, delta_bar {}, b_pos {}, b_vel {}, d {}: gamma = {}, H2 norm = {}, acquisition {}",
                    if cfg.hinf_design == 1 { "gamma-optimal" } else { "mixed H2/H-infinity" },
                    cfg.hinf_gamma_factor,
                    cfg.hinf_period,
                    cfg.hinf_delta_bar,
                    noise(cfg.hinf_b_pos),
                    noise(cfg.hinf_b_vel),
                    noise(cfg.hinf_d),
                    self.values[vr::HINF_GAMMA as usize],
                    self.values[vr::HINF_H2_NORM as usize],
                    if cfg.hinf_acquisition != 0 { "on" } else { "off" }
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

    /// `name (vr N)` of a value reference, for call logs (`vr N (unknown)` if it is none).
    pub fn var_label(r: fmi2ValueReference) -> String {
        match lookup(r) {
            Some(d) => format!("{} (vr {r})", d.name),
            None => format!("vr {r} (unknown)"),
        }
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
        if let VarType::Code(t) = d.ty {
            if t.item(value).is_none() {
                return Err(error(format!(
                    "{func}: {} = {value} is not a {} code (allowed: {})",
                    d.name,
                    t.name,
                    t.codes()
                )));
            }
        }
        if d.causality == Causality::Parameter {
            check_alone(d, value).map_err(|e| {
                error(format!(
                    "{func}: {} = {} refused: {}",
                    d.name,
                    show(d, value),
                    e.message
                ))
            })?;
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

/// What the FMU state ([`super::state`]) reads and restores.
impl Instance {
    /// Every variable's value, by value reference.
    pub(super) fn values(&self) -> &[f64; N_VARS] {
        &self.values
    }

    /// `(time, start time, stop time)`.
    pub(super) fn times(&self) -> (f64, f64, Option<f64>) {
        (self.time, self.start_time, self.stop_time)
    }

    /// The estimator handle (null before `fmi2ExitInitializationMode`).
    pub(super) fn estimator_ptr(&self) -> *mut relnav_estimator {
        self.estimator
    }

    /// Take `e` (null or a live handle) as the estimator, freeing the previous one.
    pub(super) fn replace_estimator(&mut self, e: *mut relnav_estimator) {
        if e != self.estimator {
            self.free_estimator();
            self.estimator = e;
        }
    }

    /// Everything but the estimator, as a restored state has it.
    pub(super) fn set_restored(
        &mut self,
        mode: ModelState,
        values: [f64; N_VARS],
        time: f64,
        start_time: f64,
        stop_time: Option<f64>,
    ) {
        self.state = mode;
        self.values = values;
        self.time = time;
        self.start_time = start_time;
        self.stop_time = stop_time;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_messages_are_printf_formats() {
        assert_eq!(escape_log_message("50% #r3# ok"), "50%% ##r3## ok");
        assert_eq!(escape_log_message("a\0b"), "ab");
        let long = "%".repeat(MAX_LOG_CHARS + 10);
        let e = escape_log_message(&long);
        assert_eq!(e, format!("{} ...", "%%".repeat(MAX_LOG_CHARS)));
    }

    /// The permissive partner of `hinf_period` is the smallest mean motion the library
    /// accepts, so the early check refuses only periods no orbit admits.
    #[test]
    fn permissive_partner_is_the_library_bound() {
        assert_eq!(
            permissive_partner(vr::HINF_PERIOD, 1.0),
            Some((vr::MEAN_MOTION, crate::nav::MEAN_MOTION_RANGE.0))
        );
        for (a, b) in [(vr::HINF_B_POS, 0.05), (vr::HINF_B_VEL, 0.001)] {
            assert_eq!(lookup(a).map(|d| check_alone(d, b).is_ok()), Some(true));
            assert_eq!(lookup(a).map(|d| check_alone(d, 0.0).is_ok()), Some(true));
            assert_eq!(lookup(a).map(|d| check_alone(d, -1.0).is_err()), Some(true));
        }
        let hinf = lookup(vr::HINF_PERIOD).map(|d| check_alone(d, 5e8).is_ok());
        assert_eq!(hinf, Some(true));
        let hinf = lookup(vr::HINF_PERIOD).map(|d| check_alone(d, 5.1e8).is_err());
        assert_eq!(hinf, Some(true));
    }

    /// Every start value passes the early check (nothing valid is refused early).
    #[test]
    fn start_values_pass_the_early_check() {
        for v in VARIABLES
            .iter()
            .filter(|v| v.causality == Causality::Parameter)
        {
            assert!(check_alone(v, v.start).is_ok(), "{}", v.name);
        }
    }
}
