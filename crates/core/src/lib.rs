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
#![cfg_attr(not(feature = "std"), no_std)]
// Without `std`: the helpers the particle filters share with the rest stay unused, a
// message's arguments are left out of its text, and a message is a fixed buffer
// (`message`), so results that carry one are large.
#![cfg_attr(
    not(feature = "std"),
    allow(dead_code, unused_imports, unused_variables, clippy::result_large_err)
)]

pub mod dynamics;
pub mod estimators;
pub mod frames;
#[cfg(feature = "std")]
pub mod guidance;
pub mod hinf;
pub mod math;
pub mod message;
pub mod nav;
pub mod noise;
pub mod numerics;
#[cfg(feature = "std")]
pub mod orbit;
pub mod params;
#[cfg(feature = "std")]
pub mod plant;
pub mod sensors;
pub mod types;

/// Library version (`CARGO_PKG_VERSION`).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
