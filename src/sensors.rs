//! Radio (or lidar) sensor: range, azimuth and elevation of the chaser relative to the
//! target, expressed in a chosen [`Frame`] (paper 000, sec. 2 "measurement model"; the
//! digest's erratum: use `atan2(y, x)`, not `arctan(y / x)`).
//!
//! With `p = T r` the relative position in the measurement frame (`T` from
//! [`Frame::rotation`], `r` canonical):
//!
//! ```text
//! rho   = |p|
//! alpha = atan2(p_y, p_x)         in [0, 2 pi)     (azimuth, from +x toward +y)
//! delta = asin(p_z / rho)         in [-pi/2, pi/2] (elevation)
//! ```
//!
//! Noise is additive and Gaussian, `z = h(r) + v`, `v ~ N(0, diag(s_r^2, s_a^2, s_a^2))`.
//!
//! **Singular geometry** (documented behaviour, relied on by the filters):
//! * *Zero range*: below [`MIN_RANGE`] the directions are undefined; [`RadioSensor::geometry`]
//!   returns [`GeometryError::ZeroRange`] and the filters refuse the update (the C ABI and
//!   the FMU report it as an error, the estimate is left unchanged).
//! * *Poles* (`|elevation| -> pi/2`): the azimuth is undefined and its Jacobian row grows as
//!   `1 / rho_xy`. When `rho_xy / rho < `[`POLE_COS`] (elevation within 1e-6 rad of ±90°)
//!   the azimuth is treated as carrying no information: its Jacobian row and residual are
//!   zeroed, which makes its Kalman gain column exactly zero. Range and elevation are still
//!   used; the elevation Jacobian is evaluated with the azimuth `atan2` returns there.
//! * Azimuth residuals are wrapped to `(-pi, pi]` ([`wrap_pi`]), so a measurement of 359.99°
//!   against a prediction of 0.01° is a 0.02° residual, not 359.98°.

use crate::frames::Frame;
use crate::noise::NoiseModel;
use crate::types::{Mat3, Mat36, Vec3};
use rand::Rng;
use rand_distr::StandardNormal;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// Below this range [m] the measurement directions are undefined.
pub const MIN_RANGE: f64 = 1e-6;
/// Below this ratio `rho_xy / rho` (cosine of the elevation) the azimuth is ignored.
pub const POLE_COS: f64 = 1e-6;

/// Wrap an angle to `(-pi, pi]`.
pub fn wrap_pi(a: f64) -> f64 {
    // fast path: differences of two angles in [0, 2 pi) lie in (-2 pi, 2 pi)
    if a > -PI && a <= PI {
        return a;
    }
    if (-TAU..=TAU).contains(&a) {
        return if a > 0.0 { a - TAU } else { a + TAU };
    }
    let w = a.rem_euclid(TAU); // [0, 2 pi)
    if w > PI {
        w - TAU
    } else {
        w
    }
}

/// Wrap an angle to `[0, 2 pi)`.
pub fn wrap_2pi(a: f64) -> f64 {
    // fast path: atan2 returns (-pi, pi]
    if (0.0..TAU).contains(&a) {
        return a;
    }
    if (-TAU..0.0).contains(&a) {
        let w = a + TAU;
        return if w >= TAU { 0.0 } else { w };
    }
    let w = a.rem_euclid(TAU);
    // rem_euclid can return TAU itself for tiny negative inputs after rounding
    if w >= TAU {
        0.0
    } else {
        w
    }
}

/// Why a measurement cannot be predicted at a state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GeometryError {
    /// The relative position is (numerically) zero: no direction exists.
    ZeroRange,
}

impl std::fmt::Display for GeometryError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            GeometryError::ZeroRange => write!(
                f,
                "relative range below {MIN_RANGE} m: azimuth and elevation are undefined"
            ),
        }
    }
}

/// Predicted measurement and its Jacobian at one position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geometry {
    /// Predicted measurement (radio: `(rho, alpha, delta)`).
    pub z: Vec3,
    /// `dz / d(state)` with respect to the canonical state (3x6; the velocity columns are
    /// zero). The row of a component that is not informative is zero.
    pub h: Mat36,
    /// False near the poles (see the module docs); always true for other sensors.
    pub azimuth_usable: bool,
}

/// What a filter needs of a sensor: the measurement function, its linearisation, the
/// residual and mean that respect angles, and the noise covariance. Component 1 is the
/// one that [`Geometry::azimuth_usable`] may switch off.
pub trait MeasurementModel: Sync {
    /// Noise-free measurement of the canonical relative position `r` (`None` where it is
    /// undefined).
    fn predict(&self, r: &Vec3) -> Option<Vec3>;
    /// Predicted measurement and Jacobian at `r`.
    fn linearize(&self, r: &Vec3) -> Result<Geometry, GeometryError>;
    /// `z - z_hat`, angle components wrapped.
    fn diff(&self, z: &Vec3, z_hat: &Vec3) -> Vec3;
    /// Weighted mean of predicted measurements `zs` (circular for angle components).
    fn weighted_mean(&self, w: &[f64], zs: &[Vec3]) -> Vec3;
    /// Measurement noise covariance the filters assume.
    fn noise_cov(&self) -> Mat3;
    /// The canonical position whose noise-free measurement is `z` (`None` if `z` is not
    /// a possible measurement).
    fn invert(&self, z: &Vec3) -> Option<Vec3>;
    /// `diff(z, predict(r))` in one go, `None` where the measurement is undefined.
    /// `az_sin_cos` is `(sin z_1, cos z_1)`, computed once per measurement by a caller that
    /// evaluates many positions (a particle filter); models without an azimuth ignore it.
    fn residual_at(&self, z: &Vec3, az_sin_cos: (f64, f64), r: &Vec3) -> Option<Vec3> {
        let _ = az_sin_cos;
        self.predict(r).map(|zh| self.diff(z, &zh))
    }
    /// Log-likelihood of `z` at canonical position `r`, up to a constant, as a particle
    /// filter weighs it. Default: the Gaussian of [`MeasurementModel::noise_cov`]'s
    /// diagonal, `-0.5 sum_i d_i^2 / R_ii` with `d = diff(z, predict(r))`; `-inf` where
    /// the measurement is undefined.
    fn log_likelihood(&self, z: &Vec3, r: &Vec3) -> f64 {
        match self.predict(r) {
            Some(zh) => {
                let d = self.diff(z, &zh);
                let rr = self.noise_cov();
                -0.5 * (d.x * d.x / rr[(0, 0)] + d.y * d.y / rr[(1, 1)] + d.z * d.z / rr[(2, 2)])
            }
            None => f64::NEG_INFINITY,
        }
    }
}

impl MeasurementModel for RadioSensor {
    fn predict(&self, r: &Vec3) -> Option<Vec3> {
        self.h(r)
    }
    fn linearize(&self, r: &Vec3) -> Result<Geometry, GeometryError> {
        self.geometry(r)
    }
    fn diff(&self, z: &Vec3, z_hat: &Vec3) -> Vec3 {
        Self::residual(z, z_hat)
    }
    /// The residual without the azimuth's `atan2` where the azimuth residual `d` is below
    /// 60 degrees: with `(s, c) = (sin z_az, cos z_az)` and `rho_xy` the horizontal range,
    /// `sin d = (s p_x - c p_y) / rho_xy` and `cos d = (c p_x + s p_y) / rho_xy`, so
    /// `d = asin(sin d)` exactly while `cos d > 1/2` (where `asin` is well conditioned);
    /// otherwise `wrap(z_az - atan2(p_y, p_x))` as in [`RadioSensor::residual`]. Same value
    /// as `diff(z, predict(r))` up to rounding, at about half the cost (particle filters
    /// evaluate it for every particle).
    fn residual_at(&self, z: &Vec3, az_sin_cos: (f64, f64), r: &Vec3) -> Option<Vec3> {
        let p = self.frame.vec_from_canonical(r);
        let rho = p.norm();
        if !(rho >= MIN_RANGE) {
            return None;
        }
        let el = (p.z / rho).clamp(-1.0, 1.0).asin();
        let rho_xy = (p.x * p.x + p.y * p.y).sqrt();
        let (s, c) = az_sin_cos;
        let cos_d = c * p.x + s * p.y;
        let d_az = if rho_xy > 0.0 && cos_d > 0.5 * rho_xy {
            ((s * p.x - c * p.y) / rho_xy).clamp(-1.0, 1.0).asin()
        } else {
            wrap_pi(z.y - wrap_2pi(p.y.atan2(p.x)))
        };
        Some(Vec3::new(z.x - rho, d_az, z.z - el))
    }
    /// Range and elevation: arithmetic means. Azimuth: circular mean
    /// `atan2(sum w sin a, sum w cos a)` in `[0, 2 pi)`.
    fn weighted_mean(&self, w: &[f64], zs: &[Vec3]) -> Vec3 {
        let (mut rho, mut el, mut sn, mut cs) = (0.0, 0.0, 0.0, 0.0);
        for (wi, zi) in w.iter().zip(zs) {
            rho += wi * zi.x;
            el += wi * zi.z;
            let (s, c) = zi.y.sin_cos();
            sn += wi * s;
            cs += wi * c;
        }
        Vec3::new(rho, wrap_2pi(sn.atan2(cs)), el)
    }
    fn noise_cov(&self) -> Mat3 {
        self.r()
    }
    /// `p = rho (cos d cos a, cos d sin a, sin d)` in the sensor frame, then `T^T p`.
    fn invert(&self, z: &Vec3) -> Option<Vec3> {
        if !(z.x >= 0.0 && z.iter().all(|v| v.is_finite())) {
            return None;
        }
        let (sa, ca) = z.y.sin_cos();
        let (se, ce) = z.z.sin_cos();
        let p = Vec3::new(z.x * ce * ca, z.x * ce * sa, z.x * se);
        Some(self.frame.vec_to_canonical(&p))
    }
}

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
    fn invert(&self, z: &Vec3) -> Option<Vec3> {
        Some(self.frame.vec_to_canonical(z))
    }
}

/// Range/azimuth/elevation sensor in a chosen I/O frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RadioSensor {
    /// Frame in which azimuth and elevation are defined.
    pub frame: Frame,
    /// Range noise, 1 sigma [m].
    pub sigma_range: f64,
    /// Azimuth and elevation noise, 1 sigma [rad].
    pub sigma_angle: f64,
}

impl RadioSensor {
    /// A sensor with the given frame and noise levels.
    pub fn new(frame: Frame, sigma_range: f64, sigma_angle: f64) -> Self {
        Self {
            frame,
            sigma_range,
            sigma_angle,
        }
    }

    /// Measurement covariance `R = diag(s_r^2, s_a^2, s_a^2)`.
    pub fn r(&self) -> Mat3 {
        let a2 = self.sigma_angle * self.sigma_angle;
        Mat3::from_diagonal(&Vec3::new(self.sigma_range * self.sigma_range, a2, a2))
    }

    /// Noise-free measurement of the canonical relative position `r`; `None` at zero range.
    pub fn h(&self, r: &Vec3) -> Option<Vec3> {
        let p = self.frame.vec_from_canonical(r);
        let rho = p.norm();
        if !(rho >= MIN_RANGE) {
            return None;
        }
        let az = wrap_2pi(p.y.atan2(p.x));
        let el = (p.z / rho).clamp(-1.0, 1.0).asin();
        Some(Vec3::new(rho, az, el))
    }

    /// Predicted measurement and analytic Jacobian at canonical position `r`:
    ///
    /// ```text
    /// d rho   / dp = p^T / rho
    /// d alpha / dp = (-p_y, p_x, 0) / rho_xy^2
    /// d delta / dp = (-p_x p_z / rho_xy, -p_y p_z / rho_xy, rho_xy) / rho^2
    /// ```
    ///
    /// then `H = [dz/dp T, 0]` (chain rule through `p = T r`).
    pub fn geometry(&self, r: &Vec3) -> Result<Geometry, GeometryError> {
        let t = self.frame.rotation();
        let p = t * r;
        let rho2 = p.norm_squared();
        let rho = rho2.sqrt();
        if !(rho >= MIN_RANGE) {
            return Err(GeometryError::ZeroRange);
        }
        let rxy2 = p.x * p.x + p.y * p.y;
        let rxy = rxy2.sqrt();
        let az_raw = p.y.atan2(p.x);
        let el = (p.z / rho).clamp(-1.0, 1.0).asin();
        let azimuth_usable = rxy / rho >= POLE_COS;
        let mut dp = Mat3::zeros();
        dp[(0, 0)] = p.x / rho;
        dp[(0, 1)] = p.y / rho;
        dp[(0, 2)] = p.z / rho;
        if azimuth_usable {
            dp[(1, 0)] = -p.y / rxy2;
            dp[(1, 1)] = p.x / rxy2;
        }
        // (p_x / rho_xy, p_y / rho_xy) = (cos alpha, sin alpha), well defined at the pole too
        let (sa, ca) = az_raw.sin_cos();
        dp[(2, 0)] = -ca * p.z / rho2;
        dp[(2, 1)] = -sa * p.z / rho2;
        dp[(2, 2)] = rxy / rho2;
        let mut h = Mat36::zeros();
        h.fixed_view_mut::<3, 3>(0, 0).copy_from(&(dp * t));
        Ok(Geometry {
            z: Vec3::new(rho, wrap_2pi(az_raw), el),
            h,
            azimuth_usable,
        })
    }

    /// Covariance of the indirect Cartesian position `p(z) = rho (cos el cos az, cos el sin
    /// az, sin el)` (paper 002 sec. 1.2 eq. 7; [`MeasurementModel::invert`]) of a
    /// measurement of the canonical position `r`, to first order: `J R J^T` with the
    /// Jacobian of `p(z)` in the sensor frame,
    ///
    /// ```text
    /// J = [ u,  rho cos el (-sin az, cos az, 0),  rho (-sin el cos az, -sin el sin az, cos el) ]
    /// ```
    ///
    /// (`u` the line of sight), rotated to the canonical frame (`T^T J R J^T T`): `sigma_range^2`
    /// along the line of sight and `(rho sigma_angle)^2` across it in elevation, `(rho cos el
    /// sigma_angle)^2` in azimuth. `None` below [`MIN_RANGE`].
    pub fn position_covariance(&self, r: &Vec3) -> Option<Mat3> {
        let z = self.h(r)?;
        let (rho, (sa, ca), (se, ce)) = (z.x, z.y.sin_cos(), z.z.sin_cos());
        let j = Mat3::from_columns(&[
            Vec3::new(ce * ca, ce * sa, se),
            Vec3::new(-rho * ce * sa, rho * ce * ca, 0.0),
            Vec3::new(-rho * se * ca, -rho * se * sa, rho * ce),
        ]);
        let t = self.frame.rotation();
        Some(t.transpose() * j * self.r() * j.transpose() * t)
    }

    /// Residual `z - z_hat` with the azimuth difference wrapped to `(-pi, pi]`.
    pub fn residual(z: &Vec3, z_hat: &Vec3) -> Vec3 {
        Vec3::new(z.x - z_hat.x, wrap_pi(z.y - z_hat.y), z.z - z_hat.z)
    }

    /// A noisy measurement of the canonical position `r` drawn from `rng`; the azimuth is
    /// wrapped to `[0, 2 pi)`, the elevation clamped to `[-pi/2, pi/2]` and the range to
    /// `>= 0` (a sensor never reports outside these domains, and the filters reject such
    /// values; the clamps act only within a few sigma of the poles or of zero range).
    /// `None` at zero range.
    pub fn measure<R: Rng + ?Sized>(&self, r: &Vec3, rng: &mut R) -> Option<Vec3> {
        let z = self.h(r)?;
        let n0: f64 = rng.sample(StandardNormal);
        let n1: f64 = rng.sample(StandardNormal);
        let n2: f64 = rng.sample(StandardNormal);
        Some(Vec3::new(
            (z.x + self.sigma_range * n0).max(0.0),
            wrap_2pi(z.y + self.sigma_angle * n1),
            (z.z + self.sigma_angle * n2).clamp(-FRAC_PI_2, FRAC_PI_2),
        ))
    }

    /// A measurement of the canonical position `r` with additive noise from the density
    /// `noise` (see [`crate::noise`]): `z_i = h_i(r) + v_i`, `v_i` drawn with scale
    /// `sigma_range` for the range and `sigma_angle` for each angle, in that order, `ar`
    /// holding the AR(1) model's previous sample per component. Wrapped and clamped as
    /// [`RadioSensor::measure`]. `None` at zero range (then nothing is drawn). The truth of
    /// the evaluation engine and the plant FMU (`relnav_plant`) both measure through it.
    pub fn measure_with<R: Rng + ?Sized>(
        &self,
        r: &Vec3,
        noise: &NoiseModel,
        ar: &mut [f64; 3],
        rng: &mut R,
    ) -> Option<Vec3> {
        let mut z = self.h(r)?;
        let sigma = [self.sigma_range, self.sigma_angle, self.sigma_angle];
        for i in 0..3 {
            z[i] += noise.sample(sigma[i], &mut ar[i], rng);
        }
        z.x = z.x.max(0.0);
        z.y = wrap_2pi(z.y);
        z.z = z.z.clamp(-FRAC_PI_2, FRAC_PI_2);
        Some(z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn definitions_in_each_frame() {
        // paper 000 frame: (400, 500, 200) m
        let s = RadioSensor::new(Frame::AlongRadialAntinormal, 0.5, 1e-4);
        let r = Frame::AlongRadialAntinormal.vec_to_canonical(&Vec3::new(400.0, 500.0, 200.0));
        let z = s.h(&r).unwrap_or_default();
        let rho = (400.0f64 * 400.0 + 500.0 * 500.0 + 200.0 * 200.0).sqrt();
        assert!((z.x - rho).abs() < 1e-12);
        assert!((z.y - (500.0f64).atan2(400.0)).abs() < 1e-15);
        assert!((z.z - (200.0 / rho).asin()).abs() < 1e-15);
        // azimuth in the third and fourth quadrant is in [pi, 2 pi)
        let s1 = RadioSensor::new(Frame::RadialAlongNormal, 0.5, 1e-4);
        let z = s1.h(&Vec3::new(1.0, -1.0, 0.0)).unwrap_or_default();
        assert!((z.y - 1.75 * PI).abs() < 1e-15);
        let z = s1.h(&Vec3::new(-1.0, -1.0, 0.0)).unwrap_or_default();
        assert!((z.y - 1.25 * PI).abs() < 1e-15);
    }

    #[test]
    fn jacobian_matches_finite_differences() {
        let pts = [
            Vec3::new(400.0, 500.0, 200.0),
            Vec3::new(-30.0, 7.0, -900.0),
            Vec3::new(1.0, -2.0, 0.5),
            Vec3::new(-250.0, -0.3, 10.0), // near the azimuth wrap in some frames
        ];
        for f in Frame::ALL {
            let s = RadioSensor::new(f, 1.0, 1.0);
            for r in pts {
                let g = s.geometry(&r).unwrap_or_else(|_| Geometry {
                    z: Vec3::zeros(),
                    h: Mat36::zeros(),
                    azimuth_usable: false,
                });
                assert!(g.azimuth_usable);
                for j in 0..3 {
                    let eps = 1e-6 * r.norm();
                    let mut rp = r;
                    rp[j] += eps;
                    let mut rm = r;
                    rm[j] -= eps;
                    let zp = s.h(&rp).unwrap_or_default();
                    let zm = s.h(&rm).unwrap_or_default();
                    let fd = RadioSensor::residual(&zp, &zm) / (2.0 * eps);
                    for i in 0..3 {
                        let an = g.h[(i, j)];
                        assert!(
                            (an - fd[i]).abs() < 1e-6 * (1.0 + an.abs()),
                            "{f:?} r={r:?} ({i},{j}): {an} vs {}",
                            fd[i]
                        );
                    }
                    assert_eq!(g.h[(0, j + 3)], 0.0);
                }
            }
        }
    }

    /// The particle filters' residual (asin of the azimuth residual's sine where it is
    /// small) equals `diff(z, predict(r))` everywhere: every frame, azimuths across 0 / 2 pi,
    /// residuals beyond 60 degrees (the atan2 fallback), near the poles.
    #[test]
    fn residual_at_equals_diff_of_predict() {
        use rand::Rng;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        for frame in [
            Frame::RadialAlongNormal,
            Frame::AlongRadialAntinormal,
            Frame::AlongAntinormalNadir,
        ] {
            let s = RadioSensor::new(frame, 0.5, 1e-4);
            for k in 0..20_000 {
                let r = Vec3::from_fn(|_, _| rng.random_range(-1000.0..1000.0));
                let r = if k % 50 == 0 {
                    Vec3::new(1e-9, -1e-9, 700.0)
                } else {
                    r
                };
                let zh = s.predict(&r).unwrap();
                // measurements near the prediction, and anywhere
                let z = if k % 2 == 0 {
                    Vec3::new(
                        zh.x + rng.random_range(-5.0..5.0),
                        wrap_2pi(zh.y + rng.random_range(-0.3..0.3)),
                        (zh.z + rng.random_range(-0.3..0.3)).clamp(-FRAC_PI_2, FRAC_PI_2),
                    )
                } else {
                    Vec3::new(
                        rng.random_range(0.0..2000.0),
                        rng.random_range(0.0..TAU),
                        rng.random_range(-FRAC_PI_2..FRAC_PI_2),
                    )
                };
                let want = s.diff(&z, &zh);
                let got = s.residual_at(&z, z.y.sin_cos(), &r).unwrap();
                assert!(
                    (got - want).abs().max() < 1e-9,
                    "{frame:?} r {r:?} z {z:?}: {got:?} vs {want:?}"
                );
            }
            assert!(s
                .residual_at(&Vec3::new(1.0, 0.0, 0.0), (0.0, 1.0), &Vec3::zeros())
                .is_none());
        }
    }

    #[test]
    fn wrapping() {
        assert!((wrap_pi(TAU - 1e-3) + 1e-3).abs() < 1e-15);
        assert!((wrap_pi(PI + 0.1) - (-PI + 0.1)).abs() < 1e-15);
        // the range is (-pi, pi], on every path
        assert_eq!(wrap_pi(-PI), PI);
        assert_eq!(wrap_pi(PI), PI);
        assert_eq!(wrap_pi(-TAU), 0.0);
        assert_eq!(wrap_pi(TAU), 0.0);
        assert!((wrap_pi(-PI - 0.1) - (PI - 0.1)).abs() < 1e-15);
        assert!((wrap_pi(5.0 * PI + 0.1) - (-PI + 0.1)).abs() < 1e-12);
        assert!(wrap_pi(f64::NAN).is_nan());
        assert_eq!(wrap_2pi(-0.0), 0.0);
        assert!((wrap_2pi(-1e-3) - (TAU - 1e-3)).abs() < 1e-15);
        let r = RadioSensor::residual(&Vec3::new(0.0, 1e-4, 0.0), &Vec3::new(0.0, TAU - 1e-4, 0.0));
        assert!((r.y - 2e-4).abs() < 1e-15);
    }

    #[test]
    fn singular_geometry() {
        let s = RadioSensor::new(Frame::RadialAlongNormal, 1.0, 1.0);
        assert_eq!(s.geometry(&Vec3::zeros()), Err(GeometryError::ZeroRange));
        assert!(s.h(&Vec3::new(f64::NAN, 0.0, 0.0)).is_none());
        let g = s.geometry(&Vec3::new(1e-9, 0.0, 100.0));
        assert!(
            matches!(g, Ok(g) if !g.azimuth_usable && g.h.row(1).norm() == 0.0
            && g.h.row(2).iter().all(|v| v.is_finite()))
        );
    }

    #[test]
    fn noise_is_seeded_and_has_the_stated_spread() {
        let s = RadioSensor::new(Frame::AlongRadialAntinormal, 0.5, 1.745e-4);
        let r = Vec3::new(500.0, 400.0, -200.0);
        let z0 = s.h(&r).unwrap_or_default();
        let mut a = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let mut b = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        assert_eq!(s.measure(&r, &mut a), s.measure(&r, &mut b));
        let k = 20_000;
        let mut sum = Vec3::zeros();
        let mut sq = Vec3::zeros();
        for _ in 0..k {
            let d = RadioSensor::residual(&s.measure(&r, &mut a).unwrap_or_default(), &z0);
            sum += d;
            sq += d.component_mul(&d);
        }
        let sd = (sq / k as f64).map(f64::sqrt);
        // sample sd of a Gaussian: relative standard error 1/sqrt(2k) = 0.5 %; allow 4 sigma
        assert!((sd.x / 0.5 - 1.0).abs() < 0.02);
        assert!((sd.y / 1.745e-4 - 1.0).abs() < 0.02);
        assert!((sd.z / 1.745e-4 - 1.0).abs() < 0.02);
        assert!((sum.x / k as f64).abs() < 4.0 * 0.5 / (k as f64).sqrt());
    }
}
