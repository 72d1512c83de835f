//! relnav's FMI layer: a generic part that knows no FMI version, and the bindings of each
//! version over it (FMI 2.0 Co-Simulation: [`fmi2`]), as the Modelica Reference-FMUs put
//! `fmi2Functions.c` (and `fmi3Functions.c`) over one model interface. The models
//! themselves live in their own crates (`relnav-models`: the system kit's plant and
//! guidance law; `relnav-nav-model`: relnav.fmu's estimator) and each FMU's shared library
//! (`fmu/*`) is one line: [`export_fmi2!`] of its model.
//!
//! The generic part:
//! * [`model`] — the model interface ([`model::Model`]) and static description
//!   ([`model::ModelInfo`]: identifier, description, variable table, default experiment);
//! * [`variables`] — the types of a variable table and the [`variables!`] macro that
//!   writes one;
//! * [`instance`] — one instance: all its data in one struct, the checks every model
//!   shares, typed get/set by value reference, FMU-state save and restore;
//! * [`machine`] — the life-cycle states the bindings map their state machines onto;
//! * [`status`], [`logging`], [`binding`] — call status, log categories, what an instance
//!   needs of its binding (the master's logger);
//! * [`state`] — the FMU state as explicit, versioned bytes, and the registry of handed-out
//!   state handles.
//!
//! No module of the generic part uses [`fmi2`] or [`fmi3`]; [`fmi2`] uses only the generic
//! part, [`fmi3`] the generic part and [`fmi2`]'s description and argument helpers.

// the generic part is safe Rust; only the bindings touch C pointers
#[deny(unsafe_code)]
pub mod binding;
pub mod fmi2;
pub mod fmi3;
#[deny(unsafe_code)]
pub mod instance;
#[deny(unsafe_code)]
pub mod logging;
#[deny(unsafe_code)]
pub mod machine;
#[deny(unsafe_code)]
pub mod model;
#[deny(unsafe_code)]
pub mod state;
#[deny(unsafe_code)]
pub mod status;
#[deny(unsafe_code)]
pub mod variables;
