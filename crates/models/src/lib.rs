//! FMU models over relnav-core, behind the generic FMI layer (`relnav-fmi`): each is a
//! [`relnav_fmi::model::Model`] holding a relnav-core object, built from its parameters
//! by a `config_of` function at the end of initialisation and called through its safe
//! Rust methods, with its identity (identifier, description, default experiment, variable
//! table) in its own module (`identity.rs`) beside it.
//!
//! * [`plant`] — `relnav_plant.fmu`, the system kit's truth plant
//!   ([`relnav_core::plant::Plant`]);
//! * [`guidance`] — `relnav_guidance.fmu`, the kit's hold-point guidance law
//!   ([`relnav_core::guidance::Guidance`]);
//! * [`params`] — parameter rows and `config_of` from relnav-core's declarations (every
//!   model's, relnav.fmu's included).
//!
//! relnav.fmu's own model, the navigation estimator over
//! [`relnav_core::nav::Navigator`], is built the same way in `relnav-nav-model`, a crate
//! of its own because it links the H-infinity design, which the kit's FMU binaries do
//! without.

#![forbid(unsafe_code)]

pub mod guidance;
pub mod params;
pub mod plant;
