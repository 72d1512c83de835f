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
//! * [`codes`] — the code lists these tables share with relnav.fmu's.
//!
//! relnav.fmu's own model, the navigation estimator over
//! [`relnav_core::nav::Navigator`], is built the same way in `relnav-nav-model`: its
//! parameters become a configuration through the C ABI crate's conversion (the messages C
//! users get), which this crate does not link, so the kit's FMU binaries export nothing but
//! their `fmi2*` functions.

#![forbid(unsafe_code)]

pub mod codes;
pub mod guidance;
pub mod plant;
