//! The FMI 3.0 Co-Simulation bindings over the generic layer, beside [`crate::fmi2`]: the
//! `fmi3` C types ([`types`]), the master's logger ([`Logger`]), the functions generic over
//! the model ([`functions`]), the [`export_fmi3!`](crate::export_fmi3) macro that exports
//! every function of the standard, unprefixed, for one model ([`export`]), and the
//! `modelDescription.xml` of FMI 3.0 with array variables and the instantiation token
//! derived from it ([`description`]).
//!
//! What differs from FMI 2.0 for the same model: vectors of the table are array variables
//! ([`crate::model::ArrayDef`]), the value types are FMI 3.0's (`Float64`, `Int32`,
//! `Boolean`), the start and stop time come with `fmi3EnterInitializationMode`, and
//! `fmi3DoStep` reports that it neither returned early nor needs event handling; a model
//! with Event Mode applies inputs between steps there (`fmi3UpdateDiscreteStates`); outputs
//! beyond the table are computed on request ([`crate::model::ComputedDef`]). Clocks, Model
//! Exchange and Scheduled Execution are not offered; their functions return `fmi3Error`
//! with the reason logged.

pub mod description;
pub mod export;
pub mod functions;
mod logger;
pub mod types;

pub use logger::Logger;

/// An instance of the model `M` under the FMI 3.0 bindings (what `fmi3Instance` points
/// to).
pub type Instance<M> = crate::instance::FmuInstance<M, Logger>;
