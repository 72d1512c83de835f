//! The indirect Cartesian position measurement of paper 002.

use super::{Geometry, GeometryError, MeasurementModel};
use crate::frames::Frame;
use crate::types::{Mat3, Mat36, Vec3};

/// Indirect Cartesian position measurement (paper 002, sec. 1: the position computed from
/// range and two line-of-sight angles), `z = T r + v`, `v ~ N(0, sigma^2 I3)`, in the
/// chosen frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CartesianSensor {
    /// Frame of the measured position.
    pub frame: Frame,
    /// Noise per axis, 1 sigma [m].
    pub sigma: f64,
}

impl MeasurementModel for CartesianSensor {
    fn predict(&self, r: &Vec3) -> Option<Vec3> {
        Some(self.frame.vec_from_canonical(r))
    }
    fn linearize(&self, r: &Vec3) -> Result<Geometry, GeometryError> {
        let mut h = Mat36::zeros();
        h.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&self.frame.rotation());
        Ok(Geometry {
            z: self.frame.vec_from_canonical(r),
            h,
            azimuth_usable: true,
        })
    }
    fn diff(&self, z: &Vec3, z_hat: &Vec3) -> Vec3 {
        z - z_hat
    }
    fn weighted_mean(&self, w: &[f64], zs: &[Vec3]) -> Vec3 {
        w.iter()
            .zip(zs)
            .fold(Vec3::zeros(), |acc, (wi, zi)| acc + zi * *wi)
    }
    fn noise_cov(&self) -> Mat3 {
        Mat3::identity() * (self.sigma * self.sigma)
    }
    fn linear(&self) -> bool {
        true
    }
    fn invert(&self, z: &Vec3) -> Option<Vec3> {
        Some(self.frame.vec_to_canonical(z))
    }
}
