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
use crate::types::{Mat3, Mat6, Mat63, State, Vec3};
use nalgebra::{Matrix2, Matrix4, Matrix4x2};

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

/// In-plane components of the canonical state `(x, y, vx, vy)` and out-of-plane `(z, vz)`:
/// the CW transition never couples the two groups ([`crate::dynamics::CwModel::phi`]).
const IN_PLANE: [usize; 4] = [0, 1, 3, 4];
const OUT_OF_PLANE: [usize; 2] = [2, 5];

/// The Kalman time update of the covariance, `P- = sym(Phi P Phi^T + Q)` for a symmetric
/// `P` (`sym` as in [`symmetrize`]).
///
/// CW structure (issue 15): the exact and the Euler CW transitions are block diagonal in
/// (in-plane `x, y, vx, vy`) x (out-of-plane `z, vz`), so `Phi P Phi^T` splits into
/// `Phi_i P_ii Phi_i^T` (4 x 4), `Phi_i P_io Phi_o^T` (4 x 2) and `Phi_o P_oo Phi_o^T`
/// (2 x 2): 192 multiplications instead of 432. Checked on the matrix itself (16 exact
/// zeros), so any other transition takes the dense product; the two agree to rounding.
pub(crate) fn propagate_covariance(phi: &Mat6, p: &Mat6, q: &Mat6) -> Mat6 {
    let decoupled = IN_PLANE.iter().all(|&i| {
        OUT_OF_PLANE
            .iter()
            .all(|&o| phi[(i, o)] == 0.0 && phi[(o, i)] == 0.0)
    });
    let m = if decoupled {
        let fi = Matrix4::from_fn(|r, c| phi[(IN_PLANE[r], IN_PLANE[c])]);
        let fo = Matrix2::from_fn(|r, c| phi[(OUT_OF_PLANE[r], OUT_OF_PLANE[c])]);
        let pii = Matrix4::from_fn(|r, c| p[(IN_PLANE[r], IN_PLANE[c])]);
        let pio = Matrix4x2::from_fn(|r, c| p[(IN_PLANE[r], OUT_OF_PLANE[c])]);
        let poo = Matrix2::from_fn(|r, c| p[(OUT_OF_PLANE[r], OUT_OF_PLANE[c])]);
        let nii = fi * pii * fi.transpose();
        let nio = fi * pio * fo.transpose();
        let noo = fo * poo * fo.transpose();
        let mut m = *q;
        for (r, &i) in IN_PLANE.iter().enumerate() {
            for (c, &j) in IN_PLANE.iter().enumerate() {
                m[(i, j)] += nii[(r, c)];
            }
            for (c, &o) in OUT_OF_PLANE.iter().enumerate() {
                m[(i, o)] += nio[(r, c)];
                m[(o, i)] += nio[(r, c)];
            }
        }
        for (r, &i) in OUT_OF_PLANE.iter().enumerate() {
            for (c, &j) in OUT_OF_PLANE.iter().enumerate() {
                m[(i, j)] += noo[(r, c)];
            }
        }
        m
    } else {
        phi * p * phi.transpose() + q
    };
    symmetrize(&m)
}

/// The Joseph-form covariance update `P+ = sym((I - K H) P (I - K H)^T + K R K^T)` for a
/// measurement Jacobian `H = [H_r 0]` whose velocity columns are zero (every
/// [`MeasurementModel`]: they measure the position; [`crate::sensors::Geometry::h`]). With
/// `M = K H_r` (6 x 3): `A = P - M P_r` (`P_r` the position rows of `P`), then
/// `A - A_r M^T` (`A_r` the position columns of `A`) — 216 multiplications for the
/// congruence instead of 648 with the dense 6 x 6 `I - K H`.
pub(crate) fn joseph_update(p: &Mat6, k: &Mat63, h_r: &Mat3, r: &Mat3) -> Mat6 {
    let m = k * h_r;
    let a = p - m * p.fixed_rows::<3>(0);
    let b = a - a.fixed_columns::<3>(0) * m.transpose();
    symmetrize(&(b + k * r * k.transpose()))
}

/// Check that a matrix has only finite entries ([`crate::numerics::all_finite`]).
pub(crate) fn finite<const R: usize, const C: usize>(
    m: &nalgebra::SMatrix<f64, R, C>,
    what: &'static str,
) -> Result<(), FilterError> {
    if crate::numerics::all_finite(m.as_slice()) {
        Ok(())
    } else {
        Err(FilterError::NonFinite(what))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::{CwModel, Discretization};

    fn spd() -> Mat6 {
        let a = Mat6::from_fn(|i, j| ((i * 7 + j * 3) % 5) as f64 - 1.7 + 0.1 * i as f64);
        a * a.transpose() + Mat6::identity()
    }

    /// The block-structured products equal the dense formulas to rounding, for CW
    /// transitions (exact, Euler) and for a full matrix (dense path).
    #[test]
    fn structured_covariance_products_equal_the_dense_ones() {
        let p = spd();
        let q = Mat6::from_diagonal(&State::from_row_slice(&[
            1e-3, 2e-3, 3e-3, 1e-6, 2e-6, 3e-6,
        ]));
        let m = CwModel::new(1.1e-3);
        let full = Mat6::from_fn(|i, j| 0.1 * (i as f64 + 1.0) - 0.05 * j as f64);
        for phi in [
            m.discretize(7.0, &Mat3::zeros(), Discretization::Exact).phi,
            m.discretize(7.0, &Mat3::zeros(), Discretization::Euler).phi,
            full,
        ] {
            let dense = symmetrize(&(phi * p * phi.transpose() + q));
            let got = propagate_covariance(&phi, &p, &q);
            assert!((got - dense).norm() <= 1e-14 * dense.norm(), "{phi}");
            assert_eq!(got, got.transpose());
        }
        let mut h = crate::types::Mat36::zeros();
        let h_r = Mat3::from_fn(|i, j| 0.3 * i as f64 - 0.2 * j as f64 + 1.0);
        h.fixed_columns_mut::<3>(0).copy_from(&h_r);
        let r = Mat3::from_diagonal(&Vec3::new(0.25, 4e-8, 4e-8));
        let k = Mat63::from_fn(|i, j| 0.01 * (i as f64 - j as f64) + 0.02);
        let ikh = Mat6::identity() - k * h;
        let dense = symmetrize(&(ikh * p * ikh.transpose() + k * r * k.transpose()));
        let got = joseph_update(&p, &k, &h_r, &r);
        assert!((got - dense).norm() <= 1e-14 * dense.norm());
        assert_eq!(got, got.transpose());
    }
}
