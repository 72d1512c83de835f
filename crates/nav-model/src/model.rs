//! relnav.fmu's model: the navigation estimator, a [`Navigator`] built from the parameters
//! at the end of initialisation ([`config_of`]), stepped with the inputs and read into the
//! outputs, through the navigator's safe Rust methods (as the kit's models call their
//! plant and guidance law).

use crate::identity::{vr, ESTIMATE, INFO, N_VARS, VARIABLES};
use crate::params::config_of;
use relnav_core::estimators::{AdaptiveQ, AqParams, ImmParams, MAX_MODES};
use relnav_core::hinf::{DesignRoute, HinfDesignInfo};
use relnav_core::nav::{
    FilterKind, HinfDesignKind, NavConfig, NavError, Navigator, Readings, MEAN_MOTION_RANGE,
};
use relnav_core::types::Vec3;
use relnav_fmi::model::{Model, ModelInfo};
use relnav_fmi::variables::VarDef;

/// The estimator of one instance: none until initialisation ends.
#[derive(Debug)]
pub struct RelnavFmu {
    nav: Option<Navigator>,
    /// The diagnostics the navigator's filter can change ([`Diagnostics::of`]), set with
    /// `nav`: read per step without looking at the filter again.
    diagnostics: Diagnostics,
}

/// Parameters whose valid values depend on another parameter, with that partner set to
/// its most permissive value for [`RelnavFmu::check_alone`]:
/// * `hinf_period` must satisfy `mean_motion * hinf_period <= 0.5`; with the smallest
///   `mean_motion` the library accepts (`MEAN_MOTION_RANGE`, 1e-9 rad/s) only periods that
///   no orbit admits are refused before initialisation ends;
/// * `hinf_b_pos` and `hinf_b_vel` are set together (both > 0) or derived together (both
///   0): the partner takes the value's kind (1 for a positive value, else 0).
fn permissive_partner(vr_: u32, value: f64) -> Option<(u32, f64)> {
    let same_kind = if value > 0.0 { 1.0 } else { 0.0 };
    match vr_ {
        vr::HINF_PERIOD => Some((vr::MEAN_MOTION, MEAN_MOTION_RANGE.0)),
        vr::HINF_B_POS => Some((vr::HINF_B_VEL, same_kind)),
        vr::HINF_B_VEL => Some((vr::HINF_B_POS, same_kind)),
        _ => None,
    }
}

/// The filter the `filter` value selects, if it is one of the codes (the code list
/// refuses any other value when it is set).
fn filter_kind(code: f64) -> Option<FilterKind> {
    FilterKind::ALL
        .into_iter()
        .find(|k| f64::from(*k as i32) == code)
}

/// Which diagnostic outputs a filter can change after it is built: the navigator has
/// none of the others (published as NaN, `hinf_certified` 0), ever.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Diagnostics {
    /// `ess`: the particle filters.
    ess: bool,
    /// `q_vv_*`: the AQUKF.
    q_vv: bool,
    /// `hinf_gamma`, `hinf_h2_norm`, `hinf_certified`: the H-infinity filter.
    hinf: bool,
    /// `imm_mu_*`: the IMM.
    modes: bool,
}

impl Diagnostics {
    const ALL: Self = Self {
        ess: true,
        q_vv: true,
        hinf: true,
        modes: true,
    };

    fn of(kind: FilterKind) -> Self {
        Self {
            ess: kind.pf_kind().is_some(),
            q_vv: kind == FilterKind::Aqukf,
            hinf: kind == FilterKind::Hinf,
            modes: kind == FilterKind::Imm,
        }
    }
}

/// The value references of the estimate outputs `x .. vz, sigma_x .. sigma_vz`: one
/// contiguous range, the state then its 1-sigma (checked at compile time).
const ESTIMATE_OUTPUTS: std::ops::Range<usize> = vr::X as usize..vr::X as usize + 12;
const _: () = {
    let order = ESTIMATE;
    let mut i = 0;
    while i < 12 {
        assert!(order[i] == vr::X + i as u32);
        i += 1;
    }
    assert!(ESTIMATE_OUTPUTS.end <= N_VARS);
};

/// The readings the inputs flag as fresh.
fn readings_of(values: &[f64]) -> Readings {
    let v = |r: u32| values[r as usize];
    let flag = |r: u32| v(r) != 0.0;
    Readings {
        radio: flag(vr::MEASUREMENT_VALID).then(|| [vr::RANGE, vr::AZIMUTH, vr::ELEVATION].map(v)),
        camera: flag(vr::CAMERA_VALID).then(|| [vr::CAMERA_AZIMUTH, vr::CAMERA_ELEVATION].map(v)),
        gnss_position: flag(vr::GNSS_VALID).then(|| [vr::GNSS_X, vr::GNSS_Y, vr::GNSS_Z].map(v)),
        gnss_velocity: flag(vr::GNSS_VELOCITY_VALID)
            .then(|| [vr::GNSS_VX, vr::GNSS_VY, vr::GNSS_VZ].map(v)),
    }
}

/// The estimate outputs (`ESTIMATE_OUTPUTS`: the state, then its 1-sigma).
fn write_outputs(values: &mut [f64], x: &[f64; 6], sigma: &[f64; 6]) {
    if let Some((xs, ss)) = values
        .get_mut(ESTIMATE_OUTPUTS)
        .map(|out| out.split_at_mut(6))
    {
        xs.copy_from_slice(x);
        ss.copy_from_slice(sigma);
    }
}

/// The three outputs `vrs` from `q`.
fn write3(values: &mut [f64], vrs: [u32; 3], q: [f64; 3]) {
    for (r, q) in vrs.into_iter().zip(q) {
        values[r as usize] = q;
    }
}

/// Publish the navigator's estimate and, with `d`, its diagnostics (each the C ABI's
/// reading: NaN, or `hinf_certified` 0, where the filter has none).
fn publish(nav: &Navigator, values: &mut [f64], d: Diagnostics) {
    write_outputs(values, &nav.state().into(), &nav.sigma());
    values[vr::RANGE_SIGMA as usize] = nav.range_sigma();
    let nis = nav.step_nis();
    for (r, v) in [
        vr::RADIO_NIS,
        vr::CAMERA_NIS,
        vr::GNSS_NIS,
        vr::GNSS_VELOCITY_NIS,
    ]
    .into_iter()
    .zip(nis)
    {
        values[r as usize] = v;
    }
    if d.ess {
        values[vr::ESS as usize] = nav.ess().unwrap_or(f64::NAN);
        values[vr::PF_ACCEPTANCE as usize] = nav.step_acceptance();
    }
    if d.q_vv {
        let q = nav.q_vv().unwrap_or([f64::NAN; 3]);
        write3(values, [vr::Q_VV_X, vr::Q_VV_Y, vr::Q_VV_Z], q);
    }
    if d.hinf {
        values[vr::HINF_GAMMA as usize] = nav.hinf_gamma().unwrap_or(f64::NAN);
        values[vr::HINF_H2_NORM as usize] = nav.hinf_h2_norm().unwrap_or(f64::NAN);
        values[vr::HINF_CERTIFIED as usize] =
            f64::from(u8::from(nav.hinf_certified() == Some(true)));
    }
    if d.modes {
        let mu = nav.mode_probabilities().unwrap_or([f64::NAN; 3]);
        write3(values, [vr::IMM_MU_1, vr::IMM_MU_2, vr::IMM_MU_3], mu);
    }
}

/// The AQUKF's adaptive density before its first update, per axis of the I/O frame: the
/// initial density `q_vel` clipped into the adaptation's bounds by the core
/// ([`AdaptiveQ::nominal`]; the bounds `q_vv_floor`, `q_vv_ceiling` are not FMU
/// parameters: the defaults). The clip is the same on every axis, so it commutes with the
/// frame rotation (a signed permutation) and is taken in the I/O frame.
fn initial_q_vv(q_vel: [f64; 3]) -> [f64; 3] {
    let params = AqParams {
        q_vv0: Vec3::from(q_vel),
        ..NavConfig::default().aq_params()
    };
    AdaptiveQ::new(params).nominal().into()
}

/// The IMM's mode probabilities before its first step: the stationary distribution of its
/// mode chain ([`ImmParams::stationary`]), NaN past `modes`.
fn initial_mode_probabilities(modes: usize, p_stay: [f64; 3]) -> [f64; MAX_MODES] {
    let params = ImmParams {
        modes,
        p_stay,
        ..NavConfig::default().imm_params()
    };
    let mu = params.stationary();
    std::array::from_fn(|j| if j < modes { mu[j] } else { f64::NAN })
}

/// The navigator's refusal of a saved state, as the C ABI's restore words it.
fn refused_state(e: NavError) -> String {
    format!("relnav_estimator_restore: {}", e.message)
}

impl RelnavFmu {
    /// Take `nav` as the instance's estimator.
    fn set(&mut self, nav: Navigator) -> &Navigator {
        self.diagnostics = Diagnostics::of(nav.config().filter);
        self.nav.insert(nav)
    }
}

impl Model for RelnavFmu {
    fn info() -> &'static ModelInfo {
        &INFO
    }

    fn new() -> Self {
        Self {
            nav: None,
            diagnostics: Diagnostics::ALL,
        }
    }

    /// Refuse a parameter value that is invalid whatever the other parameters are, when it
    /// is set: the earliest point, where the error belongs to the call and value that
    /// caused it (fmpy raises there; libcosim, which sets initial values during its own
    /// initialisation, aborts either way; Ecos ignores both). The check is the
    /// configuration's own ([`config_of`]) on the start values with this one value
    /// changed: every start value is valid and, apart from [`permissive_partner`], no check
    /// couples a parameter to one whose start value could make a valid value fail, so
    /// nothing valid is refused early. Combinations are checked when initialisation ends.
    fn check_alone(def: &VarDef, value: f64) -> Result<(), String> {
        let mut values = [0.0; N_VARS];
        for v in VARIABLES.iter() {
            values[v.vr as usize] = v.start;
        }
        values[def.vr as usize] = value;
        if let Some((partner, loose)) = permissive_partner(def.vr, value) {
            values[partner as usize] = loose;
        }
        config_of(&values).map(|_| ()).map_err(|e| e.message.into())
    }

    /// Outputs before the first step: the initial estimate and its 1-sigma; `ess` is the
    /// particle count for a particle filter (equal weights) and NaN for a Kalman filter;
    /// the AQUKF's and the IMM's starting diagnostics as the navigator will have them.
    fn initial_outputs(values: &mut [f64], _time: f64) {
        let v = |r: u32| values[r as usize];
        let x0 = [vr::X0, vr::Y0, vr::Z0, vr::VX0, vr::VY0, vr::VZ0].map(v);
        let (sp, sv) = (v(vr::SIGMA_POS0), v(vr::SIGMA_VEL0));
        let kind = filter_kind(v(vr::FILTER));
        let particles = v(vr::PARTICLES);
        let q_vel = [vr::Q_VEL_X, vr::Q_VEL_Y, vr::Q_VEL_Z].map(v);
        let modes = v(vr::IMM_MODES) as usize;
        let p_stay = [vr::IMM_P_STAY_1, vr::IMM_P_STAY_2, vr::IMM_P_STAY_3].map(v);
        if kind == Some(FilterKind::Hinf) {
            // no Gaussian covariance exists for the H-infinity filter: NaN, as after init
            write_outputs(values, &x0, &[f64::NAN; 6]);
        } else {
            write_outputs(values, &x0, &[sp, sp, sp, sv, sv, sv]);
        }
        values[vr::HINF_GAMMA as usize] = f64::NAN;
        values[vr::HINF_H2_NORM as usize] = f64::NAN;
        values[vr::HINF_CERTIFIED as usize] = 0.0;
        values[vr::ESS as usize] = if kind.and_then(FilterKind::pf_kind).is_some() {
            particles
        } else {
            f64::NAN
        };
        // no step has moved particles yet
        values[vr::PF_ACCEPTANCE as usize] = f64::NAN;
        let q_vv = if kind == Some(FilterKind::Aqukf) {
            initial_q_vv(q_vel)
        } else {
            [f64::NAN; 3]
        };
        write3(values, [vr::Q_VV_X, vr::Q_VV_Y, vr::Q_VV_Z], q_vv);
        let mu = if kind == Some(FilterKind::Imm) {
            initial_mode_probabilities(modes, p_stay)
        } else {
            [f64::NAN; 3]
        };
        write3(values, [vr::IMM_MU_1, vr::IMM_MU_2, vr::IMM_MU_3], mu);
    }

    /// Validate the parameters and build the navigator.
    fn initialize(&mut self, values: &mut [f64], time: f64) -> Result<String, String> {
        self.nav = None;
        let invalid = |e: NavError| format!("invalid parameters: {}", e.message);
        let cfg = config_of(values).map_err(invalid)?;
        let nav = Navigator::new(&cfg).map_err(invalid)?;
        let nav = self.set(nav);
        publish(nav, values, Diagnostics::ALL);
        let pf = if cfg.filter.pf_kind().is_some() {
            format!(
                ", particles {}, resampler {}, resample_threshold {}, seed {}",
                cfg.particles,
                cfg.resampler.code(),
                cfg.resample_threshold,
                cfg.seed
            )
        } else if cfg.filter == FilterKind::Hinf {
            let noise = |v: f64| {
                if v == 0.0 {
                    "derived".to_string()
                } else {
                    v.to_string()
                }
            };
            format!(
                ", hinf: {} observer design (gamma_factor {}) for hinf_period {} s, delta_bar {}, b_pos {}, b_vel {}, d {}: gamma = {}, H2 norm = {}, acquisition {}",
                if cfg.hinf_design == HinfDesignKind::GammaOptimal { "gamma-optimal" } else { "mixed H2/H-infinity" },
                cfg.hinf_gamma_factor,
                cfg.hinf_period,
                cfg.hinf_delta_bar,
                noise(cfg.hinf_b_pos),
                noise(cfg.hinf_b_vel),
                noise(cfg.hinf_d),
                values[vr::HINF_GAMMA as usize],
                values[vr::HINF_H2_NORM as usize],
                if cfg.hinf_acquisition { "on" } else { "off" }
            ) + &nav
                .hinf_design_info()
                .map_or_else(String::new, |i| hinf_design_words(&i))
        } else {
            String::new()
        };
        Ok(format!(
            "initialised: filter {}, frame {}, mean_motion {} rad/s, chaser_mass {} kg, sigma_range {} m, sigma_angle {} rad, noise_model {}{pf}, t0 = {} s",
            cfg.filter as i32,
            cfg.frame.code(),
            cfg.mean_motion,
            cfg.chaser_mass,
            cfg.sigma_range,
            cfg.sigma_angle,
            cfg.noise_model as i32,
            time
        ))
    }

    /// Measurement at `tc` (if valid), then prediction to `tc + h`.
    fn do_step(&mut self, values: &mut [f64], _tc: f64, h: f64) -> Result<(), String> {
        let Some(nav) = self.nav.as_mut() else {
            return Err("the estimator is not initialised".to_string());
        };
        let thrust = [vr::THRUST_X, vr::THRUST_Y, vr::THRUST_Z].map(|r| values[r as usize]);
        let readings = readings_of(values);
        nav.step_readings(&thrust, &readings, h)
            .map_err(|e| e.message)?;
        publish(nav, values, self.diagnostics);
        Ok(())
    }

    fn reset(&mut self) {
        self.nav = None;
    }

    /// The flagged readings applied at `t` (no prediction: `Navigator::update_readings`).
    fn event_update(&mut self, values: &mut [f64], _t: f64) -> Result<(), String> {
        let Some(nav) = self.nav.as_mut() else {
            return Err("the estimator is not initialised".to_string());
        };
        nav.update_readings(&readings_of(values))
            .map_err(|e| e.message)?;
        publish(nav, values, self.diagnostics);
        Ok(())
    }

    /// The covariance (the one computed output): the navigator's in the I/O frame once
    /// built, before that the diagonal of the published initial sigmas squared.
    fn computed(&self, values: &[f64], _index: usize, out: &mut [f64]) {
        let p = match &self.nav {
            Some(nav) => nav.covariance(),
            None => {
                let s = |i: usize| values[ESTIMATE[6 + i] as usize];
                // uncorrelated; all NaN where the sigmas are (the H-infinity filter)
                relnav_core::types::Mat6::from_fn(|i, j| {
                    if i == j {
                        s(i) * s(i)
                    } else {
                        0.0 * s(i) * s(j)
                    }
                })
            }
        };
        for (k, o) in out.iter_mut().enumerate().take(36) {
            *o = p[(k / 6, k % 6)];
        }
    }

    fn is_built(&self) -> bool {
        self.nav.is_some()
    }

    fn save(&self) -> Result<Option<Vec<u8>>, String> {
        Ok(self.nav.as_ref().map(|nav| {
            let mut b = Vec::with_capacity(nav.state_len());
            nav.save_state(&mut b);
            b
        }))
    }

    /// The estimator is restored into the existing one (same parameters), or into a new
    /// one built from the state's parameters; the navigator's restore is transactional.
    fn restore(&mut self, values: &[f64], bytes: &[u8]) -> Result<(), String> {
        match self.nav.as_mut() {
            Some(nav) => nav.restore_state(bytes).map_err(refused_state),
            None => {
                let unbuildable =
                    |e: NavError| format!("its parameters do not make an estimator: {}", e.message);
                let cfg = config_of(values).map_err(unbuildable)?;
                let mut nav = Navigator::new(&cfg).map_err(unbuildable)?;
                nav.restore_state(bytes).map_err(refused_state)?;
                self.set(nav);
                Ok(())
            }
        }
    }
}

/// How the H-infinity filter was designed, in words for the initialisation log (the route
/// of the filter that runs, the gamma-optimal stage's for the mixed design, and why the
/// Riccati route fell back to the SDP when it did): ", designed by <route> (...)".
fn hinf_design_words(info: &HinfDesignInfo) -> String {
    let route = |r: DesignRoute| match r {
        DesignRoute::Riccati => format!("Riccati bisection ({} trials)", info.riccati_steps),
        DesignRoute::Sdp => "SDP (Clarabel)".to_string(),
        DesignRoute::SdpLiteral => "literal SDP (Clarabel)".to_string(),
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
    if let Some(why) = info.riccati_failure {
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
    use relnav_fmi::variables::start_values;

    /// The diagnostics skipped per step are exactly those the navigator has none of, for
    /// every filter (they would otherwise go stale in the FMU's outputs); only the codes
    /// select a filter.
    #[test]
    fn skipped_diagnostics_are_the_ones_the_filter_does_not_have() {
        for kind in FilterKind::ALL {
            let cfg = NavConfig {
                filter: kind,
                particles: 50,
                ..NavConfig::default()
            };
            let nav = Navigator::new(&cfg).unwrap();
            let d = Diagnostics::of(kind);
            assert_eq!(d.ess, nav.ess().is_some(), "{kind:?}");
            assert_eq!(d.q_vv, nav.q_vv().is_some(), "{kind:?}");
            assert_eq!(d.hinf, nav.hinf_gamma().is_some(), "{kind:?}");
            assert_eq!(d.hinf, nav.hinf_h2_norm().is_some(), "{kind:?}");
            assert_eq!(d.hinf, nav.hinf_certified().is_some(), "{kind:?}");
            assert_eq!(d.modes, nav.mode_probabilities().is_some(), "{kind:?}");
            assert_eq!(filter_kind(f64::from(kind as i32)), Some(kind));
        }
        assert_eq!(filter_kind(0.0), None);
        assert_eq!(filter_kind(12.0), None);
        assert_eq!(filter_kind(2.5), None);
    }

    /// The outputs before initialisation ends are what initialisation publishes, bit for
    /// bit: the diagnostics for every filter (with a two-mode IMM and clipped AQUKF
    /// starts in other frames), the estimate for the filters whose initial estimate is the
    /// parameters' (not a particle cloud or a mixture of modes).
    #[test]
    fn initial_outputs_are_the_initialised_ones() {
        let mut cases: Vec<Vec<(u32, f64)>> = FilterKind::ALL
            .iter()
            .map(|k| vec![(vr::FILTER, f64::from(*k as i32)), (vr::PARTICLES, 40.0)])
            .collect();
        cases.push(vec![
            (vr::FILTER, 10.0),
            (vr::IMM_MODES, 2.0),
            (vr::IMM_P_STAY_2, 0.7),
        ]);
        cases.push(vec![
            (vr::FILTER, 3.0),
            (vr::Q_VEL_Y, 3.0),
            (vr::FRAME, 3.0),
        ]);
        cases.push(vec![
            (vr::FILTER, 3.0),
            (vr::Q_VEL_X, 0.0),
            (vr::FRAME, 1.0),
        ]);
        for case in cases {
            let mut values = start_values(&VARIABLES);
            for (r, v) in &case {
                values[*r as usize] = *v;
            }
            RelnavFmu::initial_outputs(&mut values, 0.0);
            let before = values.clone();
            RelnavFmu::new().initialize(&mut values, 0.0).unwrap();
            let kind = filter_kind(values[vr::FILTER as usize]).unwrap();
            let mut compared = vec![
                vr::ESS,
                vr::PF_ACCEPTANCE,
                vr::Q_VV_X,
                vr::Q_VV_Y,
                vr::Q_VV_Z,
            ];
            compared.extend([vr::IMM_MU_1, vr::IMM_MU_2, vr::IMM_MU_3]);
            if kind != FilterKind::Hinf {
                // the design's figures exist once it is designed
                compared.extend([vr::HINF_GAMMA, vr::HINF_H2_NORM, vr::HINF_CERTIFIED]);
            }
            if kind.pf_kind().is_none() && kind != FilterKind::Imm {
                compared.extend(ESTIMATE_OUTPUTS.map(|i| i as u32));
            }
            for r in compared {
                let (a, b) = (before[r as usize], values[r as usize]);
                assert_eq!(
                    a.to_bits(),
                    b.to_bits(),
                    "{case:?}: {} {a} != {b}",
                    VARIABLES[r as usize].name
                );
            }
        }
    }

    /// The permissive partner of `hinf_period` is the smallest mean motion the library
    /// accepts, so the early check refuses only periods no orbit admits.
    #[test]
    fn permissive_partner_is_the_library_bound() {
        let lookup = |r: u32| VARIABLES.get(r as usize);
        // the partner of hinf_period is a mean motion the library accepts, and no smaller
        // one is accepted
        let Some((partner, loose)) = permissive_partner(vr::HINF_PERIOD, 1.0) else {
            panic!("hinf_period has a partner")
        };
        assert_eq!(partner, vr::MEAN_MOTION);
        let mean_motion = lookup(partner).unwrap();
        assert!(RelnavFmu::check_alone(mean_motion, loose).is_ok());
        assert!(RelnavFmu::check_alone(mean_motion, loose * 0.99).is_err());
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

    /// The initialisation message of filter 9 names the design route: the gamma-optimal
    /// design by the Riccati bisection, the mixed design by the SDP from a Riccati stage.
    #[test]
    fn initialisation_log_names_the_hinf_design_route() {
        for (design, want) in [
            (1.0, ", designed by Riccati bisection ("),
            (
                3.0,
                ", designed by SDP (Clarabel) from the gamma-optimal observer by Riccati bisection (",
            ),
        ] {
            let mut values = start_values(&VARIABLES);
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
        use relnav_core::hinf::riccati::RiccatiFailure;
        let w = hinf_design_words(&HinfDesignInfo {
            route: DesignRoute::Sdp,
            observer_route: DesignRoute::Sdp,
            riccati_failure: Some(RiccatiFailure::SingularMeasurementNoise),
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
        use relnav_fmi::variables::Causality;
        for v in VARIABLES
            .iter()
            .filter(|v| v.causality == Causality::Parameter)
        {
            assert!(RelnavFmu::check_alone(v, v.start).is_ok(), "{}", v.name);
        }
    }
}
