//! Sensors of the camera and relative GNSS, the navigator's declared sensors beside the radio:
//! [`CameraSensor`], the line of sight alone (azimuth and elevation with the radio's
//! conventions, in the chosen frame), and [`VelocitySensor`], the relative velocity in the
//! chosen frame. Relative GNSS's position is the Cartesian position sensor,
//! `Modelled<CartesianSensor>` ([`super::CartesianSensor`] with a [`SensorNoise`]), which
//! fixes the position.

use super::{
    wrap_2pi, wrap_pi, GeometryError, Linearization, MeasurementModel, RadioSensor, Sensor,
    SensorNoise, Support,
};
use crate::frames::Frame;
#[cfg(not(feature = "std"))]
use crate::math::Float;
use crate::noise::NoiseModel;
use crate::types::{State, Vec3};
use core::f64::consts::FRAC_PI_2;
use nalgebra::{SMatrix, SVector};

/// An angles-only sensor (a camera's line of sight): `z = (alpha, delta)`, the azimuth in
/// `[0, 2 pi)` from `+x` toward `+y` and the elevation in `[-pi/2, pi/2]` of the relative
/// position in `frame` — the radio's angles ([`RadioSensor`], whose geometry it uses: the
/// same zero-range refusal, the azimuth dropped within 1e-6 rad of the poles), without the
/// range. It does not fix the position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraSensor {
    /// Frame of the angles.
    pub frame: Frame,
    /// Noise of the azimuth and of the elevation [rad].
    pub noise: SensorNoise<2>,
}

impl CameraSensor {
    /// Gaussian angle noise of `sigma` [rad] on both angles.
    pub fn gaussian(frame: Frame, sigma: f64) -> Self {
        Self {
            frame,
            noise: SensorNoise::gaussian([sigma; 2]),
        }
    }

    #[cfg(feature = "std")]
    /// A reading of the canonical state `x` with additive noise from the density `noise`,
    /// scaled by `sigma[i]` (azimuth, then elevation, drawn in that order; `ar` the AR(1)
    /// model's previous samples), the azimuth wrapped to `[0, 2 pi)` and the elevation
    /// clamped to `[-pi/2, pi/2]` as the radio's ([`RadioSensor::measure_with`]). `None` at
    /// zero range (nothing drawn). The truth of the evaluation engine and of the plant FMU.
    pub fn measure_with<R: rand::Rng + ?Sized>(
        &self,
        x: &State,
        noise: &NoiseModel,
        sigma: &[f64; 2],
        ar: &mut [f64; 2],
        rng: &mut R,
    ) -> Option<[f64; 2]> {
        let z = self.measure(x)?;
        let az = z[0] + noise.sample(sigma[0], &mut ar[0], rng);
        let el = z[1] + noise.sample(sigma[1], &mut ar[1], rng);
        Some([wrap_2pi(az), el.clamp(-FRAC_PI_2, FRAC_PI_2)])
    }

    /// The radio whose angles these are (its range noise is not used).
    fn radio(&self) -> RadioSensor {
        RadioSensor::new(self.frame, 1.0, 1.0)
    }
}

fn position(x: &State) -> Vec3 {
    Vec3::new(x[0], x[1], x[2])
}

impl Sensor<2> for CameraSensor {
    fn measure(&self, x: &State) -> Option<SVector<f64, 2>> {
        self.radio()
            .h(&position(x))
            .map(|z| SVector::<f64, 2>::new(z.y, z.z))
    }
    fn linearize(&self, x: &State) -> Result<Linearization<2>, GeometryError> {
        let g = self.radio().geometry(&position(x))?;
        let mut h = SMatrix::<f64, 2, 6>::zeros();
        h.row_mut(0).copy_from(&g.h.row(1));
        h.row_mut(1).copy_from(&g.h.row(2));
        if !g.azimuth_usable {
            h.row_mut(0).fill(0.0);
        }
        Ok(Linearization {
            z: SVector::<f64, 2>::new(g.z.y, g.z.z),
            h,
            used: [g.azimuth_usable, true],
        })
    }
    fn residual(&self, z: &SVector<f64, 2>, z_hat: &SVector<f64, 2>) -> SVector<f64, 2> {
        SVector::<f64, 2>::new(wrap_pi(z[0] - z_hat[0]), z[1] - z_hat[1])
    }
    fn mean(&self, w: &[f64], zs: &[SVector<f64, 2>]) -> SVector<f64, 2> {
        let (mut el, mut sn, mut cs) = (0.0, 0.0, 0.0);
        for (wi, zi) in w.iter().zip(zs) {
            el += wi * zi[1];
            let (s, c) = zi[0].sin_cos();
            sn += wi * s;
            cs += wi * c;
        }
        SVector::<f64, 2>::new(wrap_2pi(sn.atan2(cs)), el)
    }
    fn noise(&self) -> SensorNoise<2> {
        self.noise
    }
    fn support(&self) -> Support {
        Support::Position
    }
    fn used(&self, x: &State) -> Result<[bool; 2], GeometryError> {
        Ok([self.radio().azimuth_usable(&position(x))?, true])
    }
    fn check(&self, z: &SVector<f64, 2>) -> Result<(), crate::message::Message> {
        if !(z[0].is_finite() && z[1].is_finite()) {
            return Err(crate::msg!(
                "camera azimuth and elevation must be finite (got {}, {})",
                z[0],
                z[1]
            ));
        }
        if z[1].abs() > FRAC_PI_2 {
            return Err(crate::msg!(
                "camera elevation must lie in [-pi/2, pi/2] rad (got {})",
                z[1]
            ));
        }
        Ok(())
    }
}

/// The relative velocity in `frame` (relative GNSS's velocity): `z = T v`, linear.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VelocitySensor {
    /// Frame of the measured velocity.
    pub frame: Frame,
    /// Noise per axis [m/s].
    pub noise: SensorNoise<3>,
}

impl VelocitySensor {
    /// Gaussian noise of `sigma` [m/s] per axis.
    pub fn gaussian(frame: Frame, sigma: f64) -> Self {
        Self {
            frame,
            noise: SensorNoise::gaussian([sigma; 3]),
        }
    }
}

#[cfg(feature = "std")]
/// `v + n` with `n_i` drawn from the density `noise` scaled by `sigma[i]`, in component
/// order (`ar`: the AR(1) model's previous samples): a noisy reading of a linear sensor
/// (relative GNSS's position and velocity, in the truth of the evaluation engine and of the
/// plant FMU).
pub fn add_noise<R: rand::Rng + ?Sized>(
    v: &Vec3,
    noise: &NoiseModel,
    sigma: &[f64; 3],
    ar: &mut [f64; 3],
    rng: &mut R,
) -> [f64; 3] {
    core::array::from_fn(|i| v[i] + noise.sample(sigma[i], &mut ar[i], rng))
}

impl Sensor<3> for VelocitySensor {
    fn measure(&self, x: &State) -> Option<Vec3> {
        Some(self.frame.vec_from_canonical(&Vec3::new(x[3], x[4], x[5])))
    }
    fn linearize(&self, x: &State) -> Result<Linearization<3>, GeometryError> {
        let mut h = SMatrix::<f64, 3, 6>::zeros();
        h.fixed_view_mut::<3, 3>(0, 3)
            .copy_from(&self.frame.rotation());
        Ok(Linearization {
            z: self.frame.vec_from_canonical(&Vec3::new(x[3], x[4], x[5])),
            h,
            used: [true; 3],
        })
    }
    fn noise(&self) -> SensorNoise<3> {
        self.noise
    }
    fn support(&self) -> Support {
        Support::Velocity
    }
    fn velocity_fix(&self, z: &Vec3) -> Option<Vec3> {
        Some(self.frame.vec_to_canonical(z))
    }
    fn linear(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use core::f64::consts::{PI, TAU};

    const FRAMES: [Frame; 3] = [
        Frame::RadialAlongNormal,
        Frame::AlongRadialAntinormal,
        Frame::AlongAntinormalNadir,
    ];

    /// The frame's axes written out here (the documented conventions), not taken from
    /// `Frame`: x_io, y_io, z_io as canonical components.
    fn axes(f: Frame) -> [[f64; 3]; 3] {
        match f {
            Frame::RadialAlongNormal => [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            // along, radial, anti-normal
            Frame::AlongRadialAntinormal => [[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]],
            // along, anti-normal, nadir
            Frame::AlongAntinormalNadir => [[0.0, 1.0, 0.0], [0.0, 0.0, -1.0], [-1.0, 0.0, 0.0]],
        }
    }

    fn io(f: Frame, v: [f64; 3]) -> [f64; 3] {
        axes(f).map(|a| a[0] * v[0] + a[1] * v[1] + a[2] * v[2])
    }

    fn states() -> Vec<State> {
        let mut out = Vec::new();
        for k in 0..40 {
            let t = k as f64 * 0.61;
            let r = 10f64.powf(-1.0 + 0.15 * k as f64);
            // away from every frame's poles (no axis of the three frames dominates)
            let (az, el) = (t + 0.4, 0.3 * t + 0.2);
            out.push(State::from_row_slice(&[
                r * az.cos() * el.cos(),
                r * az.sin() * el.cos(),
                r * el.sin(),
                0.1 * t.sin(),
                -0.2,
                0.05 * t,
            ]));
        }
        out
    }

    /// Against the angles written here from the frame's axes, and the Jacobian against
    /// central differences of the measurement.
    #[test]
    fn camera_angles_and_jacobian() {
        for f in FRAMES {
            let cam = CameraSensor::gaussian(f, 1e-3);
            for x in states() {
                let p = io(f, [x[0], x[1], x[2]]);
                let rho = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
                let az = p[1].atan2(p[0]).rem_euclid(TAU);
                let el = (p[2] / rho).asin();
                let z = cam.measure(&x).unwrap();
                assert!((z[0] - az).abs() < 1e-12 && (z[1] - el).abs() < 1e-12);
                let lin = cam.linearize(&x).unwrap();
                assert_eq!(lin.z, z);
                assert_eq!(lin.used, [true, true]);
                for j in 0..6 {
                    let h = 1e-6 * rho;
                    let (mut a, mut b) = (x, x);
                    a[j] += h;
                    b[j] -= h;
                    let d = cam.residual(&cam.measure(&a).unwrap(), &cam.measure(&b).unwrap())
                        / (2.0 * h);
                    for i in 0..2 {
                        let scale = 1.0 / rho;
                        assert!(
                            (lin.h[(i, j)] - d[i]).abs() < 1e-6 * scale,
                            "{f:?} ({i}, {j}): {} vs {}",
                            lin.h[(i, j)],
                            d[i]
                        );
                    }
                }
            }
        }
    }

    /// Residuals wrap the azimuth; the circular mean; zero range and the poles; bad readings.
    #[test]
    fn camera_edges() {
        let cam = CameraSensor::gaussian(Frame::RadialAlongNormal, 1e-3);
        let d = cam.residual(
            &SVector::<f64, 2>::new(0.01_f64.to_radians(), 0.0),
            &SVector::<f64, 2>::new(359.99_f64.to_radians(), 0.0),
        );
        assert!((d[0] - 0.02_f64.to_radians()).abs() < 1e-12);
        let m = cam.mean(
            &[0.5, 0.5],
            &[
                SVector::<f64, 2>::new(TAU - 0.1, 0.2),
                SVector::<f64, 2>::new(0.1, 0.4),
            ],
        );
        assert!(m[0].min(TAU - m[0]) < 1e-12 && (m[1] - 0.3).abs() < 1e-15);
        assert!(cam.measure(&State::zeros()).is_none());
        assert_eq!(
            cam.linearize(&State::zeros()),
            Err(GeometryError::ZeroRange)
        );
        let pole = State::from_row_slice(&[1e-9, 0.0, 100.0, 0.0, 0.0, 0.0]);
        let lin = cam.linearize(&pole).unwrap();
        assert_eq!(lin.used, [false, true]);
        assert!(lin.h.row(0).iter().all(|v| *v == 0.0));
        assert!(cam.check(&SVector::<f64, 2>::new(1.0, 0.5)).is_ok());
        for bad in [
            [f64::NAN, 0.0],
            [0.0, f64::INFINITY],
            [0.0, PI / 2.0 + 1e-9],
            [0.0, -2.0],
        ] {
            assert!(cam.check(&SVector::<f64, 2>::from(bad)).is_err(), "{bad:?}");
        }
        assert!(cam
            .position_fix(&SVector::<f64, 2>::new(1.0, 0.5))
            .is_none());
    }

    /// The velocity in each frame, and its Jacobian.
    #[test]
    fn velocity_in_every_frame() {
        for f in FRAMES {
            let s = VelocitySensor::gaussian(f, 5e-4);
            for x in states() {
                let v = io(f, [x[3], x[4], x[5]]);
                let z = s.measure(&x).unwrap();
                assert_eq!([z.x, z.y, z.z], v);
                let lin = s.linearize(&x).unwrap();
                assert_eq!(lin.h * x, z);
                assert!(lin.h.fixed_view::<3, 3>(0, 0).iter().all(|v| *v == 0.0));
            }
            assert_eq!(s.noise().cov(), nalgebra::Matrix3::identity() * 2.5e-7);
        }
    }
}
