//! relnav.fmu's parameters as a navigator configuration: the one mapping from the values
//! of the variable table to a [`NavConfig`], shared with the front ends that take the
//! parameters by their FMU names (the Python package).

use relnav_core::nav::{NavConfig, NavError, PARAMS};

/// The checked navigator configuration of relnav.fmu's parameter values (indexed by value
/// reference; other variables are ignored). Parameters that are not FMU variables keep
/// [`NavConfig::default`]'s values; codes and Integers are the integers their `f64` holds.
///
/// Each value is stored through its declaration in relnav-core ([`PARAMS`]: an unknown code
/// or a count outside its range is refused naming the parameter), then the whole
/// configuration is validated: the FMU, the Python package and C users (whose
/// `relnav_config` goes through the same declarations) refuse a bad parameter with the
/// same message.
pub fn config_of(values: &[f64]) -> Result<NavConfig, NavError> {
    let cfg: NavConfig =
        relnav_models::params::config_from(PARAMS, values).map_err(NavError::invalid)?;
    cfg.validate()?;
    Ok(cfg)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::identity::{vr, VARIABLES};
    use relnav_fmi::variables::start_values;

    /// The start values are the library's default configuration, and every field the
    /// table does not set keeps its default.
    #[test]
    fn start_values_give_the_default_configuration() {
        let values = start_values(&VARIABLES);
        assert_eq!(config_of(&values), Ok(NavConfig::default()));
    }

    /// A bad value is refused with the declaration's message: a count's range is checked
    /// when it is stored (a negative count never reaches `NavConfig::validate`).
    #[test]
    fn refusals_are_the_c_abis() {
        use relnav_core::estimators::pf::MAX_THREADS;
        let mut values = start_values(&VARIABLES);
        values[vr::PF_THREADS as usize] = -1.0;
        let e = config_of(&values)
            .map(|_| ())
            .map_err(|e| String::from(e.message));
        assert_eq!(
            e,
            Err(format!("pf_threads must lie in 0..={MAX_THREADS} (got -1)"))
        );
        values[vr::PF_THREADS as usize] = 0.0;
        values[vr::FILTER as usize] = 12.0;
        let e = config_of(&values).map(|_| ()).map_err(|e| e.message);
        assert!(e.is_err_and(|m| m.starts_with("unknown filter code 12 (allowed: 1 ekf")));
    }
}
