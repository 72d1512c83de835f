//! relnav-core: spacecraft relative navigation near a target on a circular orbit, as safe
//! Rust with no FFI, FMI or evaluation engine in it.
//!
//! Data flows one way: [`dynamics`] (CW truth and discrete models) -> [`sensors`]
//! (range/azimuth/elevation) -> [`estimators`] (EKF, UKF, AQUKF, IMM, particle filters,
//! H-infinity behind one trait) -> [`nav`] (frames, units, step semantics). The front ends
//! sit in their own crates above it: the C ABI (`relnav`, `include/relnav.h`), the FMI
//! layer and the FMUs (`relnav-fmi`), the evaluation engine and its CLI (`relnav-eval`) and
//! the Python package. The system kit's truth plant ([`plant`], over [`orbit`] for two-body
//! and J2) and guidance law ([`guidance`]) sit beside the chain as models of their own FMUs.
//! See `ARCHITECTURE.md` for the map and the invariants.
#![deny(unsafe_code)]

pub mod dynamics;
pub mod estimators;
pub mod frames;
pub mod guidance;
pub mod hinf;
pub mod nav;
pub mod noise;
pub mod numerics;
pub mod orbit;
pub mod params;
pub mod plant;
pub mod sensors;
pub mod types;

/// Library version (`CARGO_PKG_VERSION`).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
