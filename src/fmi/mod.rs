//! The FMI 2.0 Co-Simulation layer (`fmi2*` exports), thin plumbing over the C ABI.
//!
//! * [`variables`] — the one table of variables (name, value reference, causality,
//!   variability, unit, start, description);
//! * [`description`] — `modelDescription.xml` and the GUID, generated from that table;
//! * [`instance`] — the state machine and the model logic, calling only `relnav_*`;
//! * [`functions`] — every FMI 2.0 common and co-simulation function, exported unprefixed;
//! * [`state`] — FMU state get/set/serialisation as explicit, versioned bytes.
//!
//! Packaging: `cargo run --release --bin relnav-fmu` writes `target/fmu/relnav.fmu`.

pub mod description;
pub mod functions;
pub mod instance;
pub mod state;
pub mod types;
pub mod variables;
