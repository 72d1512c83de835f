//! relnav.fmu's model: the navigation estimator behind the C ABI. It builds a C-ABI
//! configuration from the parameters, steps the estimator, publishes the estimate — and
//! talks to the estimator only through the C ABI ([`relnav`]), so the FMU is thin
//! plumbing over what C and C++ users call.

use crate::description::MODEL_DESCRIPTION;
use crate::model::{DefaultExperiment, Model, ModelInfo};
use crate::variables::{vr, VarDef, N_VARS, VARIABLES};
use relnav::{self as ffi, relnav_config, relnav_estimator, relnav_status};
use std::ffi::CStr;
use std::sync::OnceLock;

/// relnav.fmu's static description.
pub static INFO: ModelInfo = ModelInfo {
    model_identifier: crate::description::MODEL_IDENTIFIER,
    description: MODEL_DESCRIPTION,
    variables: VARIABLES,
    default_experiment: DefaultExperiment {
        start: 0.0,
        stop: 600.0,
        step: 1.0,
    },
    fmi_status: vr::FMI_STATUS,
    state_code: Some(vr::FILTER),
    state_name: "estimator",
    generated: OnceLock::new(),
};

/// The estimator of one instance: a C-ABI handle, null until
/// `fmi2ExitInitializationMode`.
#[derive(Debug)]
pub struct RelnavFmu {
    estimator: *mut relnav_estimator,
    /// The diagnostics the estimator's filter can change ([`diagnostics_of`] its `filter`
    /// parameter), set with `estimator`: read per step without looking at the code again.
    diagnostics: Diagnostics,
}

impl Drop for RelnavFmu {
    fn drop(&mut self) {
        self.free_estimator();
    }
}

/// Parameters whose valid values depend on another parameter, with that partner set to
/// its most permissive value for [`RelnavFmu::check_alone`]:
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

/// The C ABI's last error message if `s` is not `RELNAV_OK`.
pub(super) fn status_of(s: relnav_status) -> Result<(), String> {
    if s == relnav_status::RELNAV_OK {
        Ok(())
    } else {
        // SAFETY: relnav_last_error returns a valid NUL-terminated string.
        let p = ffi::relnav_last_error();
        Err(unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned())
    }
}

/// The C-ABI configuration from the values of relnav's variable table (indexed by value
/// reference; parameters are read, other variables ignored): the one mapping from FMU
/// parameters to a `relnav_config`, shared with the front ends that take parameters by
/// their FMU names (the Python package). Fields that are not FMU parameters keep
/// [`ffi::relnav_config_default`]'s values; codes and Integers are the integers their
/// `f64` holds.
pub fn config_of(values: &[f64]) -> relnav_config {
    let v = |r: u32| values.get(r as usize).copied().unwrap_or(f64::NAN);
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

/// Whether the `filter` parameter selects a particle filter (codes 4-8).
fn particle_filter_selected(values: &[f64]) -> bool {
    (4.0..=8.0).contains(&values[vr::FILTER as usize])
}

/// Which diagnostic outputs a filter can change after it is built: the C ABI's getters
/// give `None` (published as NaN, `hinf_certified` 0) for every other kind, always.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Diagnostics {
    /// `ess`: the particle filters (codes 4-8).
    ess: bool,
    /// `q_vv_*`: the AQUKF (3).
    q_vv: bool,
    /// `hinf_gamma`, `hinf_h2_norm`, `hinf_certified`: the H-infinity filter (9).
    hinf: bool,
    /// `imm_mu_*`: the IMM (10).
    modes: bool,
}

impl Diagnostics {
    const ALL: Self = Self {
        ess: true,
        q_vv: true,
        hinf: true,
        modes: true,
    };
}

/// [`Diagnostics`] of the `filter` parameter's code (the C ABI's `relnav_filter`; an
/// unknown code: all of them).
fn diagnostics_of(code: f64) -> Diagnostics {
    use ffi::relnav_filter as F;
    let is = |f: F| code == f64::from(f as i32);
    let particle = [
        F::RELNAV_FILTER_PF,
        F::RELNAV_FILTER_RPF,
        F::RELNAV_FILTER_UPF,
    ]
    .into_iter()
    .chain([F::RELNAV_FILTER_GAPF, F::RELNAV_FILTER_CGAPF])
    .any(is);
    let known = (1.0..=10.0).contains(&code) && code.fract() == 0.0;
    if !known {
        return Diagnostics::ALL;
    }
    Diagnostics {
        ess: particle,
        q_vv: is(F::RELNAV_FILTER_AQUKF),
        hinf: is(F::RELNAV_FILTER_HINF),
        modes: is(F::RELNAV_FILTER_IMM),
    }
}

/// The value references of the estimate outputs `x .. vz, sigma_x .. sigma_vz`: one
/// contiguous range in the order of `relnav_estimator_get_estimate`'s 12 doubles
/// (checked at compile time).
const ESTIMATE_OUTPUTS: std::ops::Range<usize> = vr::X as usize..vr::X as usize + 12;
const _: () = {
    let order = [
        vr::X,
        vr::Y,
        vr::Z,
        vr::VX,
        vr::VY,
        vr::VZ,
        vr::SIGMA_X,
        vr::SIGMA_Y,
        vr::SIGMA_Z,
        vr::SIGMA_VX,
        vr::SIGMA_VY,
        vr::SIGMA_VZ,
    ];
    let mut i = 0;
    while i < 12 {
        assert!(order[i] == vr::X + i as u32);
        i += 1;
    }
};

/// The estimate outputs (`ESTIMATE_OUTPUTS`: the state, then its 1-sigma) from `x` and
/// `sigma` (the initial outputs; each step writes them through the C ABI getter).
fn write_outputs(values: &mut [f64], x: &[f64; 6], sigma: &[f64; 6]) {
    if let Some((xs, ss)) = values
        .get_mut(ESTIMATE_OUTPUTS)
        .map(|out| out.split_at_mut(6))
    {
        xs.copy_from_slice(x);
        ss.copy_from_slice(sigma);
    }
}

impl RelnavFmu {
    fn free_estimator(&mut self) {
        if !self.estimator.is_null() {
            // SAFETY: the handle came from relnav_estimator_new and is freed once.
            unsafe { ffi::relnav_estimator_free(self.estimator) };
            self.estimator = std::ptr::null_mut();
        }
    }

    /// Write the estimate outputs. With `all`, every diagnostic too; else only those the
    /// filter `code` can change (see [`diagnostics_of`]): the others stay what the last
    /// full publication wrote (NaN, `hinf_certified` 0), which saves six C ABI calls per
    /// step for a Kalman filter (issue 15 item 3).
    fn publish_estimate(&self, values: &mut [f64], all: bool) -> Result<(), String> {
        // the 12 estimate outputs are contiguous in the table, in the C ABI's order
        // (`ESTIMATE_OUTPUTS`): one call writes them in place
        let out = values
            .get_mut(ESTIMATE_OUTPUTS)
            .ok_or_else(|| "the variable table lacks the estimate outputs".to_string())?;
        // SAFETY: `estimator` is live (created at exit-init); `out` holds 12 doubles.
        status_of(unsafe { ffi::relnav_estimator_get_estimate(self.estimator, out.as_mut_ptr()) })?;
        let d = if all {
            Diagnostics::ALL
        } else {
            self.diagnostics
        };
        if d.ess {
            let mut ess = f64::NAN;
            // SAFETY: as above; `ess` is a writable local.
            status_of(unsafe { ffi::relnav_estimator_get_ess(self.estimator, &mut ess) })?;
            values[vr::ESS as usize] = ess;
        }
        if d.q_vv {
            let mut q = [f64::NAN; 3];
            // SAFETY: as above; `q` holds 3 doubles.
            status_of(unsafe { ffi::relnav_estimator_get_q_vv(self.estimator, q.as_mut_ptr()) })?;
            values[vr::Q_VV_X as usize] = q[0];
            values[vr::Q_VV_Y as usize] = q[1];
            values[vr::Q_VV_Z as usize] = q[2];
        }
        if d.hinf {
            self.publish_hinf(values)?;
        }
        if d.modes {
            let mut mu = [f64::NAN; 3];
            // SAFETY: as above; `mu` holds 3 doubles.
            status_of(unsafe {
                ffi::relnav_estimator_get_mode_probabilities(self.estimator, mu.as_mut_ptr())
            })?;
            values[vr::IMM_MU_1 as usize] = mu[0];
            values[vr::IMM_MU_2 as usize] = mu[1];
            values[vr::IMM_MU_3 as usize] = mu[2];
        }
        Ok(())
    }

    /// The H-infinity design's outputs (`hinf_gamma`, `hinf_h2_norm`, `hinf_certified`).
    fn publish_hinf(&self, values: &mut [f64]) -> Result<(), String> {
        let mut gamma = f64::NAN;
        // SAFETY: `estimator` is live (created at exit-init); `gamma` is a writable local.
        status_of(unsafe { ffi::relnav_estimator_get_hinf_gamma(self.estimator, &mut gamma) })?;
        let mut h2 = f64::NAN;
        // SAFETY: as above; `h2` is a writable local.
        status_of(unsafe { ffi::relnav_estimator_get_hinf_h2_norm(self.estimator, &mut h2) })?;
        let mut certified = -1;
        // SAFETY: as above; `certified` is a writable local.
        status_of(unsafe {
            ffi::relnav_estimator_get_hinf_certified(self.estimator, &mut certified)
        })?;
        values[vr::HINF_GAMMA as usize] = gamma;
        values[vr::HINF_H2_NORM as usize] = h2;
        values[vr::HINF_CERTIFIED as usize] = f64::from(u8::from(certified == 1));
        Ok(())
    }

    /// How the H-infinity filter was designed, in words for the initialisation log (the
    /// route of the filter that runs, the gamma-optimal stage's for the mixed design, and
    /// why the Riccati route fell back to the SDP when it did).
    fn hinf_design_words(&self) -> Result<String, String> {
        let mut info = ffi::relnav_hinf_design_info {
            route: 0,
            observer_route: 0,
            riccati_failure: 0,
            riccati_steps: 0,
            iterations: 0,
            solve_time: f64::NAN,
        };
        // SAFETY: `estimator` is live (created at exit-init); `info` is a writable local.
        status_of(unsafe { ffi::relnav_estimator_get_hinf_design(self.estimator, &mut info) })?;
        Ok(hinf_design_words(&info))
    }

    /// The C ABI's saved state of the estimator, if it exists.
    fn estimator_state(&self) -> Result<Option<Vec<u8>>, String> {
        let est = self.estimator;
        if est.is_null() {
            return Ok(None);
        }
        let mut need = 0usize;
        // SAFETY: `est` is the instance's live handle; a null buffer is a size query.
        let st = unsafe { ffi::relnav_estimator_save(est, std::ptr::null_mut(), 0, &mut need) };
        status_of(st)?;
        let mut b = vec![0u8; need];
        // SAFETY: as above; `b` holds `need` writable bytes.
        let st = unsafe { ffi::relnav_estimator_save(est, b.as_mut_ptr(), b.len(), &mut need) };
        status_of(st)?;
        b.truncate(need);
        Ok(Some(b))
    }
}

impl Model for RelnavFmu {
    fn info() -> &'static ModelInfo {
        &INFO
    }

    fn new() -> Self {
        Self {
            estimator: std::ptr::null_mut(),
            diagnostics: Diagnostics::ALL,
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
    fn check_alone(def: &VarDef, value: f64) -> Result<(), String> {
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

    /// Outputs before the first step: the initial estimate and its 1-sigma; `ess` is the
    /// particle count for a particle filter (equal weights) and NaN for a Kalman filter.
    fn initial_outputs(values: &mut [f64], _time: f64) {
        let v = |r: u32| values[r as usize];
        let x0 = [vr::X0, vr::Y0, vr::Z0, vr::VX0, vr::VY0, vr::VZ0].map(v);
        let (sp, sv) = (v(vr::SIGMA_POS0), v(vr::SIGMA_VEL0));
        let filter = v(vr::FILTER);
        let particles = v(vr::PARTICLES);
        let q_vel = [vr::Q_VEL_X, vr::Q_VEL_Y, vr::Q_VEL_Z].map(v);
        if filter == 9.0 {
            // no Gaussian covariance exists for the H-infinity filter: NaN, as after init
            write_outputs(values, &x0, &[f64::NAN; 6]);
        } else {
            write_outputs(values, &x0, &[sp, sp, sp, sv, sv, sv]);
        }
        values[vr::HINF_GAMMA as usize] = f64::NAN;
        values[vr::HINF_H2_NORM as usize] = f64::NAN;
        values[vr::HINF_CERTIFIED as usize] = 0.0;
        values[vr::ESS as usize] = if particle_filter_selected(values) {
            particles
        } else {
            f64::NAN
        };
        // the AQUKF starts from q_vel (clipped into [floor, ceiling] by the library)
        let aqukf = filter == 3.0;
        let def = ffi::relnav_config_default();
        for (out, q) in [vr::Q_VV_X, vr::Q_VV_Y, vr::Q_VV_Z].into_iter().zip(q_vel) {
            values[out as usize] = if aqukf {
                q.clamp(def.q_vv_floor, def.q_vv_ceiling.max(def.q_vv_floor))
            } else {
                f64::NAN
            };
        }
        // the IMM starts at the stationary distribution of its mode chain, mu_j ~ 1 / (1 - p_j)
        let imm = filter == 10.0;
        let modes = values[vr::IMM_MODES as usize];
        let stay =
            [vr::IMM_P_STAY_1, vr::IMM_P_STAY_2, vr::IMM_P_STAY_3].map(|r| values[r as usize]);
        let used = |j: usize| (j as f64) < modes;
        let total: f64 = (0..3)
            .filter(|j| used(*j))
            .map(|j| 1.0 / (1.0 - stay[j]))
            .sum();
        for (j, out) in [vr::IMM_MU_1, vr::IMM_MU_2, vr::IMM_MU_3]
            .iter()
            .enumerate()
        {
            values[*out as usize] = if imm && used(j) {
                1.0 / (1.0 - stay[j]) / total
            } else {
                f64::NAN
            };
        }
    }

    /// Validate the parameters and create the estimator.
    fn initialize(&mut self, values: &mut [f64], time: f64) -> Result<String, String> {
        self.free_estimator();
        let cfg = config_of(values);
        let mut est = std::ptr::null_mut();
        // SAFETY: both pointers are valid locals.
        let st = unsafe { ffi::relnav_estimator_new(&cfg, &mut est) };
        status_of(st).map_err(|e| format!("invalid parameters: {e}"))?;
        self.estimator = est;
        self.diagnostics = diagnostics_of(values[vr::FILTER as usize]);
        self.publish_estimate(values, true)?;
        let pf = if particle_filter_selected(values) {
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
                values[vr::HINF_GAMMA as usize],
                values[vr::HINF_H2_NORM as usize],
                if cfg.hinf_acquisition != 0 { "on" } else { "off" }
            ) + &self.hinf_design_words()?
        } else {
            String::new()
        };
        Ok(format!(
            "initialised: filter {}, frame {}, mean_motion {} rad/s, chaser_mass {} kg, sigma_range {} m, sigma_angle {} rad, noise_model {}{pf}, t0 = {} s",
            cfg.filter, cfg.frame, cfg.mean_motion, cfg.chaser_mass, cfg.sigma_range, cfg.sigma_angle, cfg.noise_model, time
        ))
    }

    /// Measurement at `tc` (if valid), then prediction to `tc + h`.
    fn do_step(&mut self, values: &mut [f64], tc: f64, h: f64) -> Result<(), String> {
        let v = |r: u32| values[r as usize];
        let thrust = [vr::THRUST_X, vr::THRUST_Y, vr::THRUST_Z].map(v);
        let z = [vr::RANGE, vr::AZIMUTH, vr::ELEVATION].map(v);
        let valid = v(vr::MEASUREMENT_VALID) != 0.0;
        let zp = if valid { z.as_ptr() } else { std::ptr::null() };
        // SAFETY: `estimator` is live in StepComplete; arrays hold 3 doubles.
        let st = unsafe { ffi::relnav_estimator_step(self.estimator, thrust.as_ptr(), zp, h) };
        status_of(st).map_err(|e| format!("fmi2DoStep at t = {tc}: {e}"))?;
        self.publish_estimate(values, false)
    }

    fn reset(&mut self) {
        self.free_estimator();
    }

    fn is_built(&self) -> bool {
        !self.estimator.is_null()
    }

    fn save(&self) -> Result<Option<Vec<u8>>, String> {
        self.estimator_state()
    }

    /// The estimator is restored into the existing one (same parameters), or into a new
    /// one built from the state's parameters; the C ABI's restore is transactional.
    fn restore(&mut self, values: &[f64], bytes: &[u8]) -> Result<(), String> {
        let current = self.estimator;
        let mut created = std::ptr::null_mut();
        let target = if current.is_null() {
            let cfg = config_of(values);
            // SAFETY: both pointers are valid locals.
            let st = unsafe { ffi::relnav_estimator_new(&cfg, &mut created) };
            status_of(st).map_err(|e| format!("its parameters do not make an estimator: {e}"))?;
            created
        } else {
            current
        };
        // SAFETY: `target` is a live handle; `bytes` is a readable byte slice.
        let st = unsafe { ffi::relnav_estimator_restore(target, bytes.as_ptr(), bytes.len()) };
        if let Err(e) = status_of(st) {
            // SAFETY: `created` is null or the handle made above, freed once.
            unsafe { ffi::relnav_estimator_free(created) };
            return Err(e);
        }
        if current.is_null() {
            self.estimator = created;
            self.diagnostics = diagnostics_of(values[vr::FILTER as usize]);
        }
        Ok(())
    }
}

/// `relnav_hinf_design_info` in words: ", designed by <route> (...)" for the log.
fn hinf_design_words(info: &ffi::relnav_hinf_design_info) -> String {
    use ffi::relnav_hinf_riccati_failure as F;
    use ffi::relnav_hinf_route as R;
    let route = |code: i32| {
        if code == R::RELNAV_HINF_ROUTE_RICCATI as i32 {
            format!("Riccati bisection ({} trials)", info.riccati_steps)
        } else if code == R::RELNAV_HINF_ROUTE_SDP as i32 {
            "SDP (Clarabel)".to_string()
        } else if code == R::RELNAV_HINF_ROUTE_SDP_LITERAL as i32 {
            "literal SDP (Clarabel)".to_string()
        } else {
            format!("route {code}")
        }
    };
    let mut w = if info.route == info.observer_route {
        format!(", designed by {}", route(info.route))
    } else {
        format!(
            ", designed by {} from the gamma-optimal observer by {}",
            route(info.route),
            route(info.observer_route)
        )
    };
    let why = (info.riccati_failure != F::RELNAV_HINF_RICCATI_OK as i32).then(|| {
        // SAFETY: the C ABI returns a static NUL-terminated string for every code.
        unsafe {
            CStr::from_ptr(ffi::relnav_hinf_riccati_failure_string(
                info.riccati_failure,
            ))
        }
        .to_string_lossy()
    });
    if let Some(why) = why {
        w += &format!(" (the Riccati route fell back to the SDP: {why})");
    }
    w += &format!(
        ", {} interior-point iterations, {:.1} ms",
        info.iterations,
        info.solve_time * 1e3
    );
    w
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The diagnostics skipped per step are exactly those the navigator has none of, for
    /// every filter code (they would otherwise go stale in the FMU's outputs).
    #[test]
    fn skipped_diagnostics_are_the_ones_the_filter_does_not_have() {
        use relnav_core::nav::{FilterKind, NavConfig, Navigator};
        for kind in FilterKind::ALL {
            let cfg = NavConfig {
                filter: kind,
                particles: 50,
                ..NavConfig::default()
            };
            let nav = Navigator::new(&cfg).unwrap();
            let d = diagnostics_of(f64::from(kind as i32));
            assert_eq!(d.ess, nav.ess().is_some(), "{kind:?}");
            assert_eq!(d.q_vv, nav.q_vv().is_some(), "{kind:?}");
            assert_eq!(d.hinf, nav.hinf_gamma().is_some(), "{kind:?}");
            assert_eq!(d.hinf, nav.hinf_h2_norm().is_some(), "{kind:?}");
            assert_eq!(d.hinf, nav.hinf_certified().is_some(), "{kind:?}");
            assert_eq!(d.modes, nav.mode_probabilities().is_some(), "{kind:?}");
        }
        assert_eq!(diagnostics_of(0.0), Diagnostics::ALL);
        assert_eq!(diagnostics_of(11.0), Diagnostics::ALL);
        assert_eq!(diagnostics_of(2.5), Diagnostics::ALL);
    }

    /// The permissive partner of `hinf_period` is the smallest mean motion the library
    /// accepts, so the early check refuses only periods no orbit admits.
    #[test]
    fn permissive_partner_is_the_library_bound() {
        assert_eq!(
            permissive_partner(vr::HINF_PERIOD, 1.0),
            Some((vr::MEAN_MOTION, relnav_core::nav::MEAN_MOTION_RANGE.0))
        );
        let lookup = |r: u32| VARIABLES.get(r as usize);
        for (a, b) in [(vr::HINF_B_POS, 0.05), (vr::HINF_B_VEL, 0.001)] {
            assert_eq!(
                lookup(a).map(|d| RelnavFmu::check_alone(d, b).is_ok()),
                Some(true)
            );
            assert_eq!(
                lookup(a).map(|d| RelnavFmu::check_alone(d, 0.0).is_ok()),
                Some(true)
            );
            assert_eq!(
                lookup(a).map(|d| RelnavFmu::check_alone(d, -1.0).is_err()),
                Some(true)
            );
        }
        let hinf = lookup(vr::HINF_PERIOD).map(|d| RelnavFmu::check_alone(d, 5e8).is_ok());
        assert_eq!(hinf, Some(true));
        let hinf = lookup(vr::HINF_PERIOD).map(|d| RelnavFmu::check_alone(d, 5.1e8).is_err());
        assert_eq!(hinf, Some(true));
    }

    /// The initialisation message of filter 9 names the design route (issue 15): the
    /// gamma-optimal design by the Riccati bisection, the mixed design by the SDP from a
    /// Riccati stage.
    #[test]
    fn initialisation_log_names_the_hinf_design_route() {
        use crate::instance::start_values;
        for (design, want) in [
            (1.0, ", designed by Riccati bisection ("),
            (
                3.0,
                ", designed by SDP (Clarabel) from the gamma-optimal observer by Riccati bisection (",
            ),
        ] {
            let mut values = start_values(VARIABLES);
            values[vr::FILTER as usize] = 9.0;
            values[vr::HINF_DESIGN as usize] = design;
            let mut m = RelnavFmu::new();
            let msg = m.initialize(&mut values, 0.0).unwrap_or_else(|e| e);
            assert!(msg.contains(want), "{msg}");
            assert!(!msg.contains("fell back"), "{msg}");
        }
    }

    /// The words for a fallback name the reason.
    #[test]
    fn fallback_reason_in_words() {
        use ffi::relnav_hinf_riccati_failure as F;
        use ffi::relnav_hinf_route as R;
        let w = hinf_design_words(&ffi::relnav_hinf_design_info {
            route: R::RELNAV_HINF_ROUTE_SDP as i32,
            observer_route: R::RELNAV_HINF_ROUTE_SDP as i32,
            riccati_failure: F::RELNAV_HINF_RICCATI_SINGULAR_MEASUREMENT_NOISE as i32,
            riccati_steps: 0,
            iterations: 17,
            solve_time: 0.0123,
        });
        assert_eq!(
            w,
            ", designed by SDP (Clarabel) (the Riccati route fell back to the SDP: D D^T is \
             singular (a noise-free measurement axis)), 17 interior-point iterations, 12.3 ms"
        );
    }

    /// Every start value passes the early check (nothing valid is refused early).
    #[test]
    fn start_values_pass_the_early_check() {
        use crate::variables::Causality;
        for v in VARIABLES
            .iter()
            .filter(|v| v.causality == Causality::Parameter)
        {
            assert!(RelnavFmu::check_alone(v, v.start).is_ok(), "{}", v.name);
        }
    }
}
