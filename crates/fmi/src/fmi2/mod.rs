//! The FMI 2.0 Co-Simulation bindings over the generic layer: the `fmi2` C types
//! ([`types`]), the master's variadic logger ([`Logger`]), every `fmi2*` function generic
//! over the model ([`functions`]), the [`export_fmi2!`](crate::export_fmi2) macro that
//! exports them unprefixed for one model from a shared library ([`export`]), and the
//! `modelDescription.xml` of FMI 2.0 with the GUID derived from it ([`description`]).
//!
//! The FMI 2.0 co-simulation states are the generic ones
//! ([`crate::machine::ModelState`]): Instantiated, InitializationMode, StepComplete,
//! Terminated, Error.

pub mod description;
pub mod export;
pub mod functions;
mod logger;
pub mod types;

pub use logger::{escape_log_message, Logger, MAX_LOG_CHARS};

/// An instance of the model `M` under the FMI 2.0 bindings (what `fmi2Component` points
/// to).
pub type Instance<M> = crate::instance::FmuInstance<M, Logger>;
