//! Short aliases for the fixed-size nalgebra types used everywhere (stack allocated,
//! dimensions checked by the compiler).

use nalgebra::{SMatrix, SVector};

/// Relative state `(x, y, z, vx, vy, vz)` [m, m/s].
pub type State = SVector<f64, 6>;
/// 6x6 matrix (transition matrix, covariance).
pub type Mat6 = SMatrix<f64, 6, 6>;
/// 3-vector (position, velocity, acceleration, measurement).
pub type Vec3 = SVector<f64, 3>;
/// 3x3 matrix.
pub type Mat3 = SMatrix<f64, 3, 3>;
/// 6x3 matrix (input matrix, Kalman gain).
pub type Mat63 = SMatrix<f64, 6, 3>;
/// 3x6 matrix (measurement Jacobian).
pub type Mat36 = SMatrix<f64, 3, 6>;
