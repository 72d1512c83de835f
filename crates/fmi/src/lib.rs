//! The FMI 2.0 Co-Simulation layer (`fmi2*` exports): a generic layer over a small
//! per-model interface ([`model`], after the Modelica Reference-FMUs' `model.h`), and the
//! three models built on it.
//!
//! * [`model`] — the per-model interface ([`model::Model`]) and static description
//!   ([`model::ModelInfo`]);
//! * [`variables`] — the types of a variable table, the `variables!` macro that writes one,
//!   and relnav.fmu's table (name, value reference, causality, variability, unit, start,
//!   description);
//! * [`description`] — `modelDescription.xml` and the GUID, generated from a model's table;
//! * [`instance`] — one instance: the state machine, values, time, logging;
//! * [`entry`] — every FMI 2.0 common and co-simulation function, generic over the model;
//! * [`functions`] — the unprefixed `fmi2*` exports ([`crate::export_fmi2`]; relnav's own
//!   behind the default feature `fmi-exports`);
//! * [`state`] — FMU state get/set/serialisation as explicit, versioned bytes;
//! * [`relnav`] — relnav.fmu's model, calling only `relnav_*` of the C ABI;
//! * [`plant`], [`guidance`] — the system kit's truth plant and guidance law
//!   (`relnav_plant.fmu`, `relnav_guidance.fmu`), over [`relnav_core::plant`] and
//!   [`relnav_core::guidance`].
//!
//! Packaging: `fmu/build.sh` builds and packs all three FMUs and `relnav_system.ssp`;
//! `cargo run --release --bin relnav-fmu` packs `target/fmu/relnav.fmu` alone.

pub mod description;
pub mod entry;
pub mod functions;
pub mod guidance;
pub mod instance;
pub mod model;
pub mod plant;
pub mod relnav;
pub mod state;
pub mod types;
pub mod variables;
