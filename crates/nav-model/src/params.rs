//! relnav.fmu's parameters as a navigator configuration: the one mapping from the values
//! of the variable table to a [`NavConfig`], shared with the front ends that take the
//! parameters by their FMU names (the Python package).

use crate::identity::vr;
use relnav::relnav_config;
use relnav_core::nav::{NavConfig, NavError};

/// The checked navigator configuration of relnav.fmu's parameter values (indexed by value
/// reference; other variables are ignored). Fields that are not FMU parameters keep
/// [`NavConfig::default`]'s values; codes and Integers are the integers their `f64` holds.
///
/// The values become the C ABI's `relnav_config` and go through its conversion
/// (`NavConfig::try_from`, which checks the codes and the integer ranges before
/// [`NavConfig::validate`]), so the FMU, the Python package and C users refuse a bad
/// parameter with the same message. This is safe Rust: the struct is plain data.
pub fn config_of(values: &[f64]) -> Result<NavConfig, NavError> {
    NavConfig::try_from(&c_config_of(values))
}

/// The C ABI's configuration of the values (see [`config_of`]).
fn c_config_of(values: &[f64]) -> relnav_config {
    let v = |r: u32| values.get(r as usize).copied().unwrap_or(f64::NAN);
    let mut c = relnav_config::from(&NavConfig::default());
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::identity::VARIABLES;
    use relnav_fmi::variables::start_values;

    /// The start values are the library's default configuration, and every field the
    /// table does not set keeps its default.
    #[test]
    fn start_values_give_the_default_configuration() {
        let values = start_values(VARIABLES);
        assert_eq!(config_of(&values), Ok(NavConfig::default()));
    }

    /// A bad value is refused with the C ABI's message: its conversion checks the integer
    /// ranges first (a negative count never reaches `NavConfig::validate`).
    #[test]
    fn refusals_are_the_c_abis() {
        use relnav_core::estimators::pf::MAX_THREADS;
        let mut values = start_values(VARIABLES);
        values[vr::PF_THREADS as usize] = -1.0;
        let e = config_of(&values).map(|_| ()).map_err(|e| e.message);
        assert_eq!(
            e,
            Err(format!("pf_threads must lie in 0..={MAX_THREADS} (got -1)"))
        );
        values[vr::PF_THREADS as usize] = 0.0;
        values[vr::FILTER as usize] = 11.0;
        let e = config_of(&values).map(|_| ()).map_err(|e| e.message);
        assert!(e.is_err_and(|m| m.starts_with("unknown filter code 11 (allowed: 1 ekf")));
    }
}
