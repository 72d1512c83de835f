//! `relnav._relnav`, the extension module of the Python package `relnav` (PyO3): the
//! library's navigator as `relnav.Estimator` (parameters by their FMU names, driven by
//! the variable table), the evaluation engine's campaigns in chunks that run anywhere
//! (`relnav.campaign`, on threads or on Dask), and the parameter table itself. The
//! pure-Python part (`python/relnav/`) holds the exceptions and the campaign scheduler.
//!
//! This crate sits beside the C ABI, above `relnav_core::nav` and `relnav::eval`: it calls the
//! Rust API directly (no `unsafe`), and takes the FMU's parameter-to-configuration
//! mapping from `relnav::fmi` so that both front ends read parameters the same way.

mod campaign;
mod errors;
mod estimator;
mod params;

use pyo3::prelude::*;

/// Spacecraft relative navigation (Rust extension of the ``relnav`` package).
#[pymodule]
fn _relnav(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", relnav_core::VERSION)?;
    m.add_class::<estimator::Estimator>()?;
    m.add_class::<campaign::PyCampaign>()?;
    m.add_class::<campaign::PyReducer>()?;
    m.add_class::<campaign::CampaignResult>()?;
    m.add_function(wrap_pyfunction!(params::parameters_table, m)?)?;
    m.add_function(wrap_pyfunction!(campaign::scenario_toml, m)?)?;
    m.add_function(wrap_pyfunction!(campaign::builtin_scenario, m)?)?;
    m.add_function(wrap_pyfunction!(campaign::builtin_scenarios, m)?)?;
    Ok(())
}
