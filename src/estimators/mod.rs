//! Estimators behind one trait.
//!
//! Every filter works on the canonical-frame state `(r, v)` (see [`crate::frames`]), takes
//! its dynamics as a [`DiscreteModel`] for the current step and its measurement model as a
//! [`MeasurementModel`] (radio range/azimuth/elevation or Cartesian position). Frames, units of thrust and the choice of step are the caller's
//! ([`crate::nav::Navigator`]). All types are fixed-size nalgebra matrices: a step performs
//! no heap allocation (checked by `tests/no_alloc.rs`). A step that fails leaves the
//! estimate unchanged.

use crate::dynamics::DiscreteModel;
use crate::sensors::{GeometryError, MeasurementModel};
use crate::types::{Mat6, State, Vec3};

pub mod aqukf;
pub mod ekf;
pub mod imm;
/// cbindgen:ignore
pub mod pf;
pub mod ukf;

pub use aqukf::{
    AdaptationLaw, AdaptiveQ, AdaptiveUkf, AqParams, Aqukf, MAX_GATE_WINDOW, MAX_WINDOW,
};
pub use ekf::Ekf;
pub use imm::{Imm, ImmParams, MAX_MODES};
pub use ukf::{Ukf, UkfParams};

/// Why a filter step failed. The estimate is unchanged after an error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FilterError {
    /// The predicted position is at (numerically) zero range.
    Geometry(GeometryError),
    /// A matrix that must be positive definite (innovation or state covariance) is not.
    NotPositiveDefinite(&'static str),
    /// The result contains NaN or infinity.
    NonFinite(&'static str),
}

impl std::fmt::Display for FilterError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FilterError::Geometry(g) => write!(f, "{g}"),
            FilterError::NotPositiveDefinite(what) => {
                write!(f, "{what} is not positive definite")
            }
            FilterError::NonFinite(what) => write!(f, "{what} is not finite"),
        }
    }
}

impl From<GeometryError> for FilterError {
    fn from(g: GeometryError) -> Self {
        FilterError::Geometry(g)
    }
}

/// Diagnostics of the last measurement update.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct UpdateInfo {
    /// Innovation `z - z_hat` (azimuth wrapped).
    pub innovation: Vec3,
    /// Normalised innovation squared `nu^T S^-1 nu` (chi-square with 3 dof when consistent;
    /// 2 dof when the azimuth was ignored near a pole).
    pub nis: f64,
    /// False when the azimuth was ignored (elevation within 1e-6 rad of ±90°).
    pub azimuth_used: bool,
}

/// A recursive estimator of the canonical relative state.
pub trait Estimator {
    /// Time update over one step: `x+ = Phi x + Gamma a`, covariance through the model,
    /// plus the step's process noise `model.q`. `accel` is the known thrust acceleration
    /// [m/s^2], canonical frame, held over the step.
    fn predict(&mut self, model: &DiscreteModel, accel: &Vec3) -> Result<(), FilterError>;
    /// Measurement update with `z` from `sensor` (radio: `(range, azimuth, elevation)`).
    fn update<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
    ) -> Result<UpdateInfo, FilterError>;
    /// Current state estimate (canonical frame).
    fn state(&self) -> &State;
    /// Current error covariance (canonical frame).
    fn covariance(&self) -> &Mat6;
    /// Overwrite the estimate (used by reset and re-initialisation).
    fn set_estimate(&mut self, x: State, p: Mat6);
}

/// Symmetrise a covariance: `(P + P^T) / 2`.
pub(crate) fn symmetrize(p: &Mat6) -> Mat6 {
    (p + p.transpose()) * 0.5
}

/// Check that a matrix has only finite entries.
pub(crate) fn finite<const R: usize, const C: usize>(
    m: &nalgebra::SMatrix<f64, R, C>,
    what: &'static str,
) -> Result<(), FilterError> {
    if m.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(FilterError::NonFinite(what))
    }
}
