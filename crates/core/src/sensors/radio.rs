//! The radio (or lidar) sensor: range, azimuth and elevation in a chosen frame (see the
//! [module documentation](super) for the definitions and the singular geometry), with the
//! particle filters' and the unscented updates' hot paths: the residual without `atan2`
//! ([`MeasurementModel::residual_at`]) and its block form for structure-of-arrays positions
//! ([`MeasurementModel::residuals_at`]), the unscented transform relative to the centre
//! ([`MeasurementModel::unscented_seven`]) and its block form
//! ([`MeasurementModel::unscented_seven_block`]) — the radio's own specialisations of the
//! trait's defaults, the same values (bit for bit where stated).

use super::{
    asin_series, asin_small, unscented_seven_generic, wrap_2pi, wrap_pi, AngleTrig, Geometry,
    GeometryError, MeasurementModel, SevenBlock, ASIN_SERIES_MAX, MIN_RANGE, POLE_COS,
};
use crate::frames::Frame;
#[cfg(not(feature = "std"))]
use crate::math::Float;
use crate::noise::NoiseModel;
use crate::types::{Mat3, Mat36, Vec3};
use core::f64::consts::{FRAC_PI_2, PI};
#[cfg(feature = "std")]
use rand::Rng;
#[cfg(feature = "std")]
use rand_distr::StandardNormal;

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
    /// The lanes of [`MeasurementModel::residuals_at`] that its loop flags (`slow`), apart
    /// (cold, not inlined: the loop's code is the same with or without it). A lane in
    /// [`MeasurementModel::residual_at`]'s small-residual branch whose sine is beyond the
    /// series' domain (a particle off the measurement by more than 2^-5 rad) gets the loop's
    /// values again and its angles by [`asin_small`], as `residual_at` forms them (`libm`'s
    /// `asin` there), without `residual_at`'s matrix product and branches; any other lane
    /// (range below [`MIN_RANGE`], a residual cosine below 1/2, NaN) is `residual_at`'s.
    #[cold]
    #[inline(never)]
    #[allow(clippy::too_many_arguments, clippy::needless_range_loop)]
    fn redo_residuals<const B: usize>(
        &self,
        z: &Vec3,
        trig: &AngleTrig,
        r: &[[f64; B]; 3],
        n: usize,
        slow: &[bool; B],
        d: &mut [[f64; B]; 3],
        ok: &mut [bool; B],
    ) {
        let [(j0, s0), (j1, s1), (j2, s2)] = self.frame.axis_map();
        let (r0, r1, r2) = (&r[j0], &r[j1], &r[j2]);
        for i in 0..n.min(B) {
            if !slow[i] {
                continue;
            }
            let p = Vec3::new(s0 * r0[i], s1 * r1[i], s2 * r2[i]);
            let g = LaneGeometry::of(&p, trig);
            if g.near {
                d[1][i] = asin_small(g.s_az.clamp(-1.0, 1.0));
                d[2][i] = asin_small(g.s_el.clamp(-1.0, 1.0));
                continue;
            }
            let ri = Vec3::new(r[0][i], r[1][i], r[2][i]);
            let v = self.residual_at(z, trig, &ri);
            ok[i] = v.is_some();
            let v = v.unwrap_or_default();
            (d[0][i], d[1][i], d[2][i]) = (v.x, v.y, v.z);
        }
    }

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
        // (sin alpha, cos alpha) = (p_y, p_x) / rho_xy; at the pole from `atan2`'s angle
        let (sa, ca) = if rxy > 0.0 {
            (p.y / rxy, p.x / rxy)
        } else {
            az_raw.sin_cos()
        };
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

    #[cfg(feature = "std")]
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

    #[cfg(feature = "std")]
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
    /// The residual without `atan2` and without a full-range `asin` where the angle
    /// residuals `d` are below 60 degrees. With `(s, c)` the sine and cosine of a measured
    /// angle ([`AngleTrig`]), `rho_xy` the horizontal range and `rho` the range:
    ///
    /// ```text
    /// azimuth:    sin d = (s p_x - c p_y) / rho_xy,      cos d = (c p_x + s p_y) / rho_xy
    /// elevation:  sin d = (s rho_xy - c p_z) / rho,      cos d = (c rho_xy + s p_z) / rho
    /// ```
    ///
    /// (the sine and cosine of a difference of angles), so `d = asin(sin d)` exactly while
    /// `cos d > 1/2`, where `asin` is well conditioned; the residuals of a particle near the
    /// measurement are small, and [`asin_small`] evaluates them with a short series.
    /// Otherwise `wrap(z_az - atan2(p_y, p_x))` and `z_el - asin(p_z / rho)` as in
    /// [`RadioSensor::residual`]. Same value as `diff(z, predict(r))` up to rounding, at
    /// about a third of the cost (particle filters evaluate it for every particle).
    fn residual_at(&self, z: &Vec3, trig: &AngleTrig, r: &Vec3) -> Option<Vec3> {
        let p = self.frame.vec_from_canonical(r);
        let rho_xy2 = p.x * p.x + p.y * p.y;
        let rho = (rho_xy2 + p.z * p.z).sqrt();
        if !(rho >= MIN_RANGE) {
            return None;
        }
        let rho_xy = rho_xy2.sqrt();
        let (s, c) = trig.el;
        let d_el = if c * rho_xy + s * p.z > 0.5 * rho {
            asin_small(((s * rho_xy - c * p.z) / rho).clamp(-1.0, 1.0))
        } else {
            z.z - (p.z / rho).clamp(-1.0, 1.0).asin()
        };
        let (s, c) = trig.az;
        let d_az = if rho_xy > 0.0 && c * p.x + s * p.y > 0.5 * rho_xy {
            asin_small(((s * p.x - c * p.y) / rho_xy).clamp(-1.0, 1.0))
        } else {
            wrap_pi(z.y - wrap_2pi(p.y.atan2(p.x)))
        };
        Some(Vec3::new(z.x - rho, d_az, d_el))
    }
    /// [`RadioSensor::residual_at`]'s small-residual branch for a block of positions with
    /// no branch in the loop (so it vectorises): every lane is evaluated by the series, and
    /// a lane outside the series' domain is redone afterwards: a sine beyond `2^-5` (the
    /// series' domain) with both cosines above 1/2 by [`asin_small`], as `residual_at`
    /// forms it; range below [`MIN_RANGE`], a residual cosine below 1/2 or NaN by
    /// `residual_at` itself. The same values as `residual_at` lane by lane, bit for bit (tested).
    /// Inlined (always) so that a caller's [`crate::numerics::simd::dispatch`] compiles
    /// it for AVX2.
    #[inline(always)]
    fn residuals_at<const B: usize>(
        &self,
        z: &Vec3,
        trig: &AngleTrig,
        r: &[[f64; B]; 3],
        n: usize,
        d: &mut [[f64; B]; 3],
        ok: &mut [bool; B],
    ) {
        // `T r` as the signed permutation it is ([`Frame::axis_map`]): three sign products
        // instead of the matrix product's nine products and six sums, the same values for a
        // finite `r` (the product's zero terms add nothing; only the sign of a zero
        // component can differ, and the residuals take it through squares or the
        // odd series of a zero sine: the log-likelihood's bits are the same)
        let [(j0, s0), (j1, s1), (j2, s2)] = self.frame.axis_map();
        let (r0, r1, r2) = (&r[j0], &r[j1], &r[j2]);
        let mut slow = [false; B];
        for i in 0..B {
            let p = Vec3::new(s0 * r0[i], s1 * r1[i], s2 * r2[i]);
            let g = LaneGeometry::of(&p, trig);
            let fast =
                g.near & (g.s_el.abs() <= ASIN_SERIES_MAX) & (g.s_az.abs() <= ASIN_SERIES_MAX);
            d[0][i] = z.x - g.rho;
            d[1][i] = asin_series(g.s_az);
            d[2][i] = asin_series(g.s_el);
            slow[i] = !fast;
        }
        *ok = [true; B];
        // the lanes to redo, if any: one vector test per block in the common case
        if slow.iter().take(n).fold(false, |a, &s| a | s) {
            self.redo_residuals(z, trig, r, n, &slow, d, ok);
        }
    }
    /// The unscented transform without an `atan2` or `sin_cos` per sigma point. Each point's
    /// azimuth enters the circular mean through `(sin a_i, cos a_i) = (p_y, p_x) / rho_xy`
    /// (sensor frame), which is what `atan2` followed by `sin_cos` returns, and its
    /// deviation from the mean `a` (with `(sin a, cos a)` formed once) is
    ///
    /// ```text
    /// d_i = atan2(sin a_i cos a - cos a_i sin a,  cos a_i cos a + sin a_i sin a)
    /// ```
    ///
    /// the wrapped difference `wrap(a_i - a)` itself, evaluated as [`asin_small`] of the
    /// sine where the cosine exceeds 1/2 (the sigma points of a filter that is not lost lie
    /// within degrees of their mean). Range and elevation as [`RadioSensor::h`]; at
    /// `rho_xy = 0` (a point on the pole) the azimuth is `atan2`'s, as in `h`. The same
    /// values as the default to rounding (tested), and much cheaper: the per-point
    /// trigonometric calls are a large part of the unscented update's cost.
    fn unscented(&self, r: &[Vec3], wm: &[f64], dz: &mut [Vec3]) -> Option<Vec3> {
        // the azimuth's (sin, cos) of one point, sensor frame
        let trig = |p: &Vec3| {
            let rho_xy = (p.x * p.x + p.y * p.y).sqrt();
            if rho_xy > 0.0 {
                (p.y / rho_xy, p.x / rho_xy)
            } else {
                p.y.atan2(p.x).sin_cos()
            }
        };
        let (mut rho_m, mut el_m, mut sn, mut cs) = (0.0, 0.0, 0.0, 0.0);
        for ((ri, di), wi) in r.iter().zip(dz.iter_mut()).zip(wm) {
            let p = self.frame.vec_from_canonical(ri);
            let rho = p.norm();
            if !(rho >= MIN_RANGE) {
                return None;
            }
            let el = (p.z / rho).clamp(-1.0, 1.0).asin();
            let (sa, ca) = trig(&p);
            rho_m += wi * rho;
            el_m += wi * el;
            sn += wi * sa;
            cs += wi * ca;
            *di = Vec3::new(rho, 0.0, el);
        }
        let az_m = wrap_2pi(sn.atan2(cs));
        let (sm, cm) = az_m.sin_cos();
        for (ri, di) in r.iter().zip(dz.iter_mut()) {
            let (sa, ca) = trig(&self.frame.vec_from_canonical(ri));
            let (sd, cd) = (sa * cm - ca * sm, ca * cm + sa * sm);
            let d_az = if cd > 0.5 {
                asin_small(sd.clamp(-1.0, 1.0))
            } else {
                sd.atan2(cd)
            };
            *di = Vec3::new(di.x - rho_m, d_az, di.z - el_m);
        }
        Some(Vec3::new(rho_m, az_m, el_m))
    }
    /// The seven-position unscented transform relative to the centre, without `atan2`,
    /// `sin_cos` or `libm`'s `asin` per point. With `a_c, e_c` the centre's azimuth and
    /// elevation (their sines and cosines `p_y / rho_xy`, `p_x / rho_xy`, `p_z / rho`,
    /// `rho_xy / rho`), each point's angles enter as their differences from the centre's,
    ///
    /// ```text
    /// sin(a_i - a_c) = (p_y cos a_c - p_x sin a_c) / rho_xy,  cos(a_i - a_c) = (p_x cos a_c + p_y sin a_c) / rho_xy
    /// sin(e_i - e_c) = (p_z cos e_c - rho_xy sin e_c) / rho,  cos(e_i - e_c) = (rho_xy cos e_c + p_z sin e_c) / rho
    /// ```
    ///
    /// each difference the [`asin_series`] of its sine. The circular mean of the azimuths is
    /// `a_c + atan2(sum w sin(a_i - a_c), sum w cos(a_i - a_c))` (the same `atan2` as
    /// [`MeasurementModel::weighted_mean`]'s, rotated by `a_c`), the elevations' mean
    /// `e_c + sum w (e_i - e_c)` (the weights sum to one); the deviations and the
    /// innovation are differences of these small angles, the innovation's from
    /// `z - (a_c, e_c)` by the same identities with `trig`. Where a point is outside the
    /// series' domain (a difference whose cosine is below 1/2 or whose sine exceeds
    /// `2^-5`, a point on the pole or at zero range, an innovation angle beyond 60 degrees
    /// or an elevation measurement outside `[-pi, pi]`) the whole transform is
    /// [`unscented_seven_generic`]'s. The same values as that to rounding (tested).
    fn unscented_seven(
        &self,
        z: &Vec3,
        trig: &AngleTrig,
        c: &Vec3,
        o: &[Vec3; 3],
        wm: (f64, f64),
        dz: &mut [Vec3; 7],
    ) -> Option<(Vec3, bool)> {
        let t = self.frame.rotation();
        let pc = t * c;
        let rxy2 = pc.x * pc.x + pc.y * pc.y;
        let rho_c = (rxy2 + pc.z * pc.z).sqrt();
        let rxy_c = rxy2.sqrt();
        // the centre's azimuth and elevation (sin, cos); NaN on the pole or at zero range
        let (sa, ca) = (pc.y / rxy_c, pc.x / rxy_c);
        let (se, ce) = (pc.z / rho_c, rxy_c / rho_c);
        // the measurement's angles relative to the centre's
        let (sz, cz) = trig.az;
        let (sn_a, cn_a) = (sz * ca - cz * sa, cz * ca + sz * sa);
        let (sz, cz) = trig.el;
        let (sn_e, cn_e) = (sz * ce - cz * se, cz * ce + sz * se);
        let mut fast =
            rho_c >= MIN_RANGE && rxy_c > 0.0 && cn_a > 0.5 && cn_e > 0.5 && z.z.abs() <= PI;
        let (w0, w) = wm;
        let (mut rho_s, mut sa_s, mut ca_s, mut de_s) = (0.0, 0.0, 0.0, 0.0);
        let to: [Vec3; 3] = core::array::from_fn(|j| t * o[j]);
        for k in 0..6 {
            let p = if k < 3 { pc + to[k] } else { pc - to[k - 3] };
            let rxy2 = p.x * p.x + p.y * p.y;
            let rho = (rxy2 + p.z * p.z).sqrt();
            let rxy = rxy2.sqrt();
            let (sd_a, cd_a) = ((p.y * ca - p.x * sa) / rxy, (p.x * ca + p.y * sa) / rxy);
            let (sd_e, cd_e) = ((p.z * ce - rxy * se) / rho, (rxy * ce + p.z * se) / rho);
            fast &= (rho >= MIN_RANGE)
                & (rxy > 0.0)
                & (cd_a > 0.5)
                & (cd_e > 0.5)
                & (sd_a.abs() <= ASIN_SERIES_MAX)
                & (sd_e.abs() <= ASIN_SERIES_MAX);
            let de = asin_series(sd_e);
            rho_s += rho;
            sa_s += sd_a;
            ca_s += cd_a;
            de_s += de;
            dz[1 + k] = Vec3::new(rho, asin_series(sd_a), de);
        }
        if !fast {
            return unscented_seven_generic(self, z, trig, c, o, wm, dz);
        }
        let rho_m = w0 * rho_c + w * rho_s;
        // the circular mean's offset from a_c (the centre's own term is sin 0, cos 1)
        let (s_m, c_m) = (w * sa_s, w0 + w * ca_s);
        let h = (s_m * s_m + c_m * c_m).sqrt();
        let da_m = if c_m > 0.5 * h {
            asin_small((s_m / h).clamp(-1.0, 1.0))
        } else {
            s_m.atan2(c_m)
        };
        let de_m = w * de_s;
        dz[0] = Vec3::new(rho_c - rho_m, -da_m, -de_m);
        for d in dz.iter_mut().skip(1) {
            *d = Vec3::new(d.x - rho_m, d.y - da_m, d.z - de_m);
        }
        let nu = Vec3::new(
            z.x - rho_m,
            wrap_pi(asin_small(sn_a.clamp(-1.0, 1.0)) - da_m),
            asin_small(sn_e.clamp(-1.0, 1.0)) - de_m,
        );
        Some((nu, rxy_c / rho_c >= POLE_COS))
    }
    /// [`RadioSensor`]'s `unscented_seven` on a block of centres without a branch in the
    /// loop: every lane runs the series path (the same operations in the same order as the
    /// per-centre form, so the same bits), and a lane is `fast` exactly where that form
    /// takes its series path (every point inside the series' domain, the circular mean's
    /// offset within `2^-5`, both innovation angles' cosines above 1/2, the azimuth
    /// usable); other lanes are left to the caller's per-centre call. An innovation angle
    /// whose sine exceeds `2^-5` is formed afterwards, lane by lane, as the per-centre form
    /// forms it ([`asin_small`]: `libm`'s `asin` there).
    #[allow(clippy::needless_range_loop)]
    #[inline(always)]
    fn unscented_seven_block<const B: usize>(
        &self,
        z: &Vec3,
        trig: &AngleTrig,
        c: &[[f64; B]; 3],
        o: &[Vec3; 3],
        wm: (f64, f64),
        out: &mut SevenBlock<B>,
    ) {
        let t = self.frame.rotation();
        let to: [Vec3; 3] = core::array::from_fn(|j| t * o[j]);
        let (w0, w) = wm;
        let (sza, cza) = trig.az;
        let (sze, cze) = trig.el;
        let z_ok = z.z.abs() <= PI;
        // every loop below runs over the lanes (innermost, fixed length): the compiler
        // vectorises each across centres
        let SevenBlock { dz, nu, fast } = out;
        let mut pc = [[0.0; B]; 3];
        let (mut rho_c, mut rxy_c) = ([0.0; B], [0.0; B]);
        let (mut sa, mut ca, mut se, mut ce) = ([0.0; B], [0.0; B], [0.0; B], [0.0; B]);
        let (mut sn_a, mut sn_e) = ([0.0; B], [0.0; B]);
        let mut ok = [false; B];
        for i in 0..B {
            // t * c as nalgebra's product forms it: column by column
            let (c0, c1, c2) = (c[0][i], c[1][i], c[2][i]);
            let p: [f64; 3] =
                core::array::from_fn(|r| t[(r, 0)] * c0 + t[(r, 1)] * c1 + t[(r, 2)] * c2);
            let rxy2 = p[0] * p[0] + p[1] * p[1];
            let rho = (rxy2 + p[2] * p[2]).sqrt();
            let rxy = rxy2.sqrt();
            let (s_a, c_a) = (p[1] / rxy, p[0] / rxy);
            let (s_e, c_e) = (p[2] / rho, rxy / rho);
            let (sn, cn) = (sza * c_a - cza * s_a, cza * c_a + sza * s_a);
            let (sne, cne) = (sze * c_e - cze * s_e, cze * c_e + sze * s_e);
            ok[i] = (rho >= MIN_RANGE) & (rxy > 0.0) & (cn > 0.5) & (cne > 0.5) & z_ok;
            (pc[0][i], pc[1][i], pc[2][i]) = (p[0], p[1], p[2]);
            (rho_c[i], rxy_c[i]) = (rho, rxy);
            (sa[i], ca[i], se[i], ce[i]) = (s_a, c_a, s_e, c_e);
            (sn_a[i], sn_e[i]) = (sn, sne);
        }
        let (mut rho_s, mut sa_s, mut ca_s, mut de_s) = ([0.0; B], [0.0; B], [0.0; B], [0.0; B]);
        for k in 0..6 {
            let q = to[k % 3];
            let q = if k < 3 { q } else { -q };
            let dk = &mut dz[1 + k];
            for i in 0..B {
                // `pc - o` as `pc + (-o)`: the same difference
                let p = [pc[0][i] + q.x, pc[1][i] + q.y, pc[2][i] + q.z];
                let rxy2 = p[0] * p[0] + p[1] * p[1];
                let rho = (rxy2 + p[2] * p[2]).sqrt();
                let rxy = rxy2.sqrt();
                let sd_a = (p[1] * ca[i] - p[0] * sa[i]) / rxy;
                let cd_a = (p[0] * ca[i] + p[1] * sa[i]) / rxy;
                let sd_e = (p[2] * ce[i] - rxy * se[i]) / rho;
                let cd_e = (rxy * ce[i] + p[2] * se[i]) / rho;
                ok[i] &= (rho >= MIN_RANGE)
                    & (rxy > 0.0)
                    & (cd_a > 0.5)
                    & (cd_e > 0.5)
                    & (sd_a.abs() <= ASIN_SERIES_MAX)
                    & (sd_e.abs() <= ASIN_SERIES_MAX);
                let de = asin_series(sd_e);
                rho_s[i] += rho;
                sa_s[i] += sd_a;
                ca_s[i] += cd_a;
                de_s[i] += de;
                dk[0][i] = rho;
                dk[1][i] = asin_series(sd_a);
                dk[2][i] = de;
            }
        }
        let (mut rho_m, mut da_m, mut de_m) = ([0.0; B], [0.0; B], [0.0; B]);
        let mut wide = [false; B];
        for i in 0..B {
            let rm = w0 * rho_c[i] + w * rho_s[i];
            let (s_m, c_m) = (w * sa_s[i], w0 + w * ca_s[i]);
            let h = (s_m * s_m + c_m * c_m).sqrt();
            let sh = s_m / h;
            let da = asin_series(sh);
            let de = w * de_s[i];
            ok[i] &=
                (c_m > 0.5 * h) & (sh.abs() <= ASIN_SERIES_MAX) & (rxy_c[i] / rho_c[i] >= POLE_COS);
            // the innovation's angles: the series where the per-centre form takes it (and
            // `wrap_pi` the identity: two angles below 2^-5); a lane with a wider
            // innovation angle (its cosine above 1/2 is in `ok`) is finished below
            wide[i] =
                ok[i] & !((sn_a[i].abs() <= ASIN_SERIES_MAX) & (sn_e[i].abs() <= ASIN_SERIES_MAX));
            dz[0][0][i] = rho_c[i] - rm;
            dz[0][1][i] = -da;
            dz[0][2][i] = -de;
            nu[0][i] = z.x - rm;
            nu[1][i] = asin_series(sn_a[i]) - da;
            nu[2][i] = asin_series(sn_e[i]) - de;
            (rho_m[i], da_m[i], de_m[i]) = (rm, da, de);
        }
        // the lanes whose points are all in the series' domain but whose innovation angle
        // is not (a particle cloud off the measurement by more than 2^-5 rad: 61 % of the
        // literal UPF's proposals over the benchmark's 20 000 steps): the innovation as the
        // per-centre form forms it ([`asin_small`], `libm`'s `asin` beyond 2^-5), the same
        // bits, instead of the whole lane redone by the caller. One vector test per block
        // when there are none.
        if wide.iter().fold(false, |a, &w| a | w) {
            for i in 0..B {
                if wide[i] {
                    nu[1][i] = wrap_pi(asin_small(sn_a[i].clamp(-1.0, 1.0)) - da_m[i]);
                    nu[2][i] = asin_small(sn_e[i].clamp(-1.0, 1.0)) - de_m[i];
                }
            }
        }
        for d in dz.iter_mut().skip(1) {
            for i in 0..B {
                d[0][i] -= rho_m[i];
                d[1][i] -= da_m[i];
                d[2][i] -= de_m[i];
            }
        }
        *fast = ok;
    }
    /// `rho_xy / rho >= POLE_COS`, as [`RadioSensor::geometry`] decides it.
    fn azimuth_usable(&self, r: &Vec3) -> Result<bool, GeometryError> {
        let p = self.frame.vec_from_canonical(r);
        let rho = p.norm();
        if !(rho >= MIN_RANGE) {
            return Err(GeometryError::ZeroRange);
        }
        Ok((p.x * p.x + p.y * p.y).sqrt() / rho >= POLE_COS)
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

/// One lane of [`RadioSensor`]'s block residuals at the sensor-frame position `p`: the
/// range `rho`, the residual sines of elevation and azimuth (see
/// [`MeasurementModel::residual_at`]) and `near`, whether `residual_at`'s small-residual
/// branch applies (range at least [`MIN_RANGE`], off the pole, both residual cosines above
/// 1/2). Shared by the vectorised loop of `residuals_at` and its cold redo of flagged lanes,
/// so that both form the sines by the same expressions (the same bits).
struct LaneGeometry {
    rho: f64,
    s_el: f64,
    s_az: f64,
    near: bool,
}

impl LaneGeometry {
    #[inline(always)]
    fn of(p: &Vec3, trig: &AngleTrig) -> Self {
        let (se, ce) = trig.el;
        let (sa, ca) = trig.az;
        let rho_xy2 = p.x * p.x + p.y * p.y;
        let rho = (rho_xy2 + p.z * p.z).sqrt();
        let rho_xy = rho_xy2.sqrt();
        Self {
            rho,
            s_el: (se * rho_xy - ce * p.z) / rho,
            s_az: (sa * p.x - ca * p.y) / rho_xy,
            near: (rho >= MIN_RANGE)
                & (rho_xy > 0.0)
                & (ce * rho_xy + se * p.z > 0.5 * rho)
                & (ca * p.x + sa * p.y > 0.5 * rho_xy),
        }
    }
}

#[cfg(test)]
mod tests;
