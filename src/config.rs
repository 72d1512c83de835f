//! `relnav_config` and its conversion to and from the core's [`NavConfig`]. The struct
//! and the code lists' enums are generated from relnav-core's parameter table
//! (`config_fields.rs`, checked in; `tests/c_config.rs` regenerates it): a parameter is
//! declared once, in `relnav_core::nav::config`, and becomes a field here.

pub use crate::config_fields::*;
use crate::error::{null, relnav_status};
use crate::panic::boundary;
use relnav_core::nav::{NavConfig, NavError, PARAMS};

impl From<&NavConfig> for relnav_config {
    fn from(c: &NavConfig) -> Self {
        let mut out = relnav_config::ZERO;
        for (k, p) in PARAMS.iter().enumerate() {
            for i in 0..p.elements.len() {
                out.set_element(k, i, (p.get)(c, i));
            }
        }
        out
    }
}

impl TryFrom<&relnav_config> for NavConfig {
    type Error = NavError;
    /// Every field as the core's parameter table reads it (an unknown code, a flag other
    /// than 0 or 1, a count outside its range are refused naming the field), then the
    /// whole configuration validated.
    fn try_from(c: &relnav_config) -> Result<Self, NavError> {
        let mut cfg = NavConfig::default();
        for (k, p) in PARAMS.iter().enumerate() {
            for i in 0..p.elements.len() {
                if let Some(v) = c.element(k, i) {
                    cfg.assign(p, i, v)?;
                }
            }
        }
        cfg.validate()?;
        Ok(cfg)
    }
}

/// The default configuration: paper 000's numerical example (frame 2, 7200 s orbit, EKF,
/// 0.5 m / 0.01 deg Gaussian noise, initial estimate (405, 505, 205, 0.1, 0.1, 0.1),
/// 50 m / 1 m/s initial sigma, the paper's diagonal process noise per 1 s step; for the
/// particle filters 1500 particles, systematic resampling below N_eff = 2/3 N, seed 0,
/// moves on, threads one per core). Cannot fail, so returns the configuration itself.
#[no_mangle]
pub extern "C" fn relnav_config_default() -> relnav_config {
    relnav_config::from(&NavConfig::default())
}

/// Check a configuration without creating an estimator.
///
/// # Safety
/// `config` is null or points to a `relnav_config`.
#[no_mangle]
pub unsafe extern "C" fn relnav_config_validate(config: *const relnav_config) -> relnav_status {
    boundary("relnav_config_validate", || {
        // SAFETY: caller guarantees a valid or null pointer.
        let c =
            unsafe { config.as_ref() }.ok_or_else(|| null("config", "relnav_config_validate"))?;
        NavConfig::try_from(c)?;
        Ok(())
    })
}
