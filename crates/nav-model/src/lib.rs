//! relnav.fmu's model over the generic FMI layer (`relnav-fmi`): the navigation estimator,
//! a [`relnav_core::nav::Navigator`] built from the FMU's parameters at the end of
//! initialisation and called through its safe Rust methods, the way the system kit's models
//! (`relnav-models`) call their plant and guidance law.
//!
//! * [`identity`] — identifier, description, default experiment, the variable table
//!   ([`VARIABLES`], value references [`vr`]) and relnav's code lists;
//! * [`params`] — [`config_of`]: the parameter values as a checked
//!   [`relnav_core::nav::NavConfig`] (also the Python package's mapping);
//! * [`model`] — [`RelnavFmu`], the [`relnav_fmi::model::Model`].
//!
//! The parameters' rows and their mapping come from relnav-core's parameter declarations
//! (`relnav_core::nav::PARAMS`), as the C ABI's struct and the scenario keys do; this crate
//! does not link the C ABI.
#![forbid(unsafe_code)]

pub mod identity;
pub mod model;
pub mod params;

pub use identity::{vr, INFO, N_VARS, VARIABLES};
pub use model::RelnavFmu;
pub use params::config_of;
