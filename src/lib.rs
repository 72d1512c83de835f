//! relnav — spacecraft relative navigation near a target on a circular orbit.
//!
//! Data flows one way: [`dynamics`] (CW truth and discrete models) → [`sensors`]
//! (range/azimuth/elevation) → [`estimators`] (EKF, UKF behind one trait) → [`nav`] (frames,
//! units, step semantics) → [`ffi`] (the C ABI, `include/relnav.h`) → [`fmi`] (the FMI 2.0
//! Co-Simulation layer). Beside it, [`eval`] runs Monte Carlo campaigns of scenario files
//! against the posterior Cramér–Rao bound (the `relnav` CLI), with the measurement-noise
//! densities of [`noise`]. The system kit's truth plant ([`plant`], over [`orbit`] for
//! two-body + J2) and guidance law ([`guidance`]) sit beside the chain as models of their
//! own FMUs. See `ARCHITECTURE.md` for the map and the invariants.
#![deny(unsafe_code)]

pub mod dynamics;
pub mod estimators;
/// cbindgen:ignore
#[cfg(feature = "eval")]
pub mod eval;
pub mod frames;
/// cbindgen:ignore
pub mod guidance;
pub mod hinf;
pub mod nav;
pub mod noise;
pub mod numerics;
/// cbindgen:ignore
pub mod orbit;
/// cbindgen:ignore
pub mod plant;
pub mod sensors;
pub mod types;

#[allow(unsafe_code)]
pub mod ffi;
/// cbindgen:ignore
#[allow(unsafe_code)]
pub mod fmi;

/// Library version (`CARGO_PKG_VERSION`).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
