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

/// The sines and cosines of a measurement's azimuth (component 1) and elevation
/// (component 2), formed once per measurement for [`MeasurementModel::residual_at`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AngleTrig {
    /// `(sin z_1, cos z_1)`
    pub az: (f64, f64),
    /// `(sin z_2, cos z_2)`
    pub el: (f64, f64),
}

impl AngleTrig {
    /// The angles of `z`.
    pub fn of(z: &Vec3) -> Self {
        Self {
            az: z.y.sin_cos(),
            el: z.z.sin_cos(),
        }
    }
}

/// The measurement side of the shared-prior unscented update for a block of `B` centres in
/// structure-of-arrays form ([`MeasurementModel::unscented_seven_block`]): lane `i` holds
/// the deviations `dz[p][k][i]` (point `p` in [`MeasurementModel::unscented_seven`]'s order,
/// component `k`) and the innovation `nu[k][i]` where `fast[i]`. Reused block after block
/// (so that no block zeroes its arrays).
#[derive(Debug, Clone, Copy)]
pub struct SevenBlock<const B: usize> {
    /// deviations `diff(h(p), z_hat)` per point and component
    pub dz: [[[f64; B]; 3]; 7],
    /// innovations `diff(z, z_hat)`
    pub nu: [[f64; B]; 3],
    /// lanes whose `dz` and `nu` are `unscented_seven`'s bit for bit (azimuth usable)
    pub fast: [bool; B],
}

impl<const B: usize> Default for SevenBlock<B> {
    fn default() -> Self {
        Self {
            dz: [[[0.0; B]; 3]; 7],
            nu: [[0.0; B]; 3],
            fast: [false; B],
        }
    }
}

/// `asin(s)` for `|s| <= 1`, by its Maclaurin series where `|s| <= 2^-5`:
///
/// ```text
/// asin s = s + s^3/6 + 3 s^5/40 + 5 s^7/112 + 35 s^9/1152 + O(s^11)
/// ```
///
/// whose first neglected term, `63 s^11 / 2816`, is below `2.3e-2 * 2^-50 |s| < 2^-55 |s|`
/// (under a quarter of an ulp) there; `libm`'s `asin` elsewhere. A particle's angle
/// residuals are milliradians: the series replaces about 80 instructions by 10.
#[inline]
pub fn asin_small(s: f64) -> f64 {
    if s.abs() <= ASIN_SERIES_MAX {
        asin_series(s)
    } else {
        s.asin()
    }
}

/// Where [`asin_series`] is `asin` to a quarter of an ulp: `|s| <= 2^-5`.
pub(crate) const ASIN_SERIES_MAX: f64 = 0.031_25;

/// The series of [`asin_small`] alone (no test, no branch: the caller checks
/// `|s| <= 2^-5`, where it is `asin` to a quarter of an ulp), for loops that vectorise over many residuals.
#[inline(always)]
pub fn asin_series(s: f64) -> f64 {
    const C3: f64 = 1.0 / 6.0;
    const C5: f64 = 3.0 / 40.0;
    const C7: f64 = 5.0 / 112.0;
    const C9: f64 = 35.0 / 1152.0;
    let s2 = s * s;
    s + s * s2 * (C3 + s2 * (C5 + s2 * (C7 + s2 * C9)))
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
    /// `trig` holds the sines and cosines of `z`'s angles, computed once per measurement by
    /// a caller that evaluates many positions (a particle filter); models without angles
    /// ignore it.
    fn residual_at(&self, z: &Vec3, trig: &AngleTrig, r: &Vec3) -> Option<Vec3> {
        let _ = trig;
        self.predict(r).map(|zh| self.diff(z, &zh))
    }
    /// [`MeasurementModel::residual_at`] for `n <= B` positions in structure-of-arrays form
    /// (`r[k][i]` component `k` of position `i`): writes the residuals `d[k][i]` and
    /// `ok[i]` (false where the measurement is undefined, `d` then unspecified); lanes from
    /// `n` on are left unspecified. Default: `residual_at` lane by lane. The radio sensor
    /// overrides it with a loop the compiler vectorises across positions (a particle
    /// filter's likelihood).
    fn residuals_at<const B: usize>(
        &self,
        z: &Vec3,
        trig: &AngleTrig,
        r: &[[f64; B]; 3],
        n: usize,
        d: &mut [[f64; B]; 3],
        ok: &mut [bool; B],
    ) {
        for i in 0..n.min(B) {
            let ri = Vec3::new(r[0][i], r[1][i], r[2][i]);
            let v = self.residual_at(z, trig, &ri);
            ok[i] = v.is_some();
            let v = v.unwrap_or_default();
            (d[0][i], d[1][i], d[2][i]) = (v.x, v.y, v.z);
        }
    }
    /// The unscented transform of the measurement over sigma-point positions `r` with mean
    /// weights `wm` (same lengths as `dz`): returns `z_hat`, the weighted mean of the
    /// measurements `h(r_i)` as [`MeasurementModel::weighted_mean`] forms it, and writes the
    /// deviations `diff(h(r_i), z_hat)` into `dz`; `None` where a measurement is undefined
    /// (`dz` is then unspecified). Default: `predict`, `weighted_mean` and `diff`.
    fn unscented(&self, r: &[Vec3], wm: &[f64], dz: &mut [Vec3]) -> Option<Vec3> {
        for (ri, di) in r.iter().zip(dz.iter_mut()) {
            *di = self.predict(ri)?;
        }
        let z_hat = self.weighted_mean(wm, dz);
        for di in dz.iter_mut() {
            *di = self.diff(di, &z_hat);
        }
        Some(z_hat)
    }
    /// [`Geometry::azimuth_usable`] at `r` without the Jacobian (default: from
    /// [`MeasurementModel::linearize`]).
    fn azimuth_usable(&self, r: &Vec3) -> Result<bool, GeometryError> {
        self.linearize(r).map(|g| g.azimuth_usable)
    }
    /// The unscented update's measurement side when the sigma points sit at seven distinct
    /// positions: the centre `c` and `c ± o_j`, `j = 0, 1, 2` (sigma points from a lower
    /// triangular factor `L` of a 6-state covariance: `L`'s velocity columns have no
    /// position part, so those six points share the centre's position). `wm = (w_c, w)`:
    /// the mean weight of the centre (all points at it together) and of each other point.
    /// Writes the deviations `diff(h(p_i), z_hat)` into `dz` (order `c`, `c + o_0..2`,
    /// `c - o_0..2`) and returns the innovation `diff(z, z_hat)` with
    /// [`MeasurementModel::azimuth_usable`] at `c`; `None` where a measurement is
    /// undefined. `trig`: the angles of `z` ([`AngleTrig`]). Default
    /// ([`unscented_seven_generic`]): [`MeasurementModel::unscented`] over the seven
    /// points, `diff` and `azimuth_usable`.
    fn unscented_seven(
        &self,
        z: &Vec3,
        trig: &AngleTrig,
        c: &Vec3,
        o: &[Vec3; 3],
        wm: (f64, f64),
        dz: &mut [Vec3; 7],
    ) -> Option<(Vec3, bool)> {
        unscented_seven_generic(self, z, trig, c, o, wm, dz)
    }
    /// [`MeasurementModel::unscented_seven`] for a block of `B` centres in
    /// structure-of-arrays form (`c[k][i]` component `k` of centre `i`; the same offsets
    /// `o` and weights `wm` for every lane), for a particle filter whose particles share
    /// one prior covariance. Writes `out.dz[p][k][i]` (point `p` in `unscented_seven`'s
    /// order), the innovation `out.nu[k][i]` and `out.fast[i]`: where `fast[i]` is true the
    /// lane's `dz` and `nu` are, bit for bit, what `unscented_seven` returns for that centre,
    /// and its azimuth is usable; where false the lane is unspecified and the caller calls
    /// `unscented_seven` itself. Default: every lane false (the caller's per-lane path). The
    /// radio sensor overrides it with branch-free loops the compiler vectorises across
    /// centres (its series path; see [`RadioSensor`]'s `unscented_seven`).
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
        let _ = (z, trig, c, o, wm);
        out.fast.fill(false);
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

/// The default of [`MeasurementModel::unscented_seven`] (also the radio sensor's fallback):
/// the seven positions through [`MeasurementModel::unscented`], the innovation by
/// [`MeasurementModel::diff`], the pole test by [`MeasurementModel::azimuth_usable`].
pub fn unscented_seven_generic<M: MeasurementModel + ?Sized>(
    m: &M,
    z: &Vec3,
    trig: &AngleTrig,
    c: &Vec3,
    o: &[Vec3; 3],
    wm: (f64, f64),
    dz: &mut [Vec3; 7],
) -> Option<(Vec3, bool)> {
    let _ = trig;
    let r = [
        *c,
        c + o[0],
        c + o[1],
        c + o[2],
        c - o[0],
        c - o[1],
        c - o[2],
    ];
    let (w0, w) = wm;
    let z_hat = m.unscented(&r, &[w0, w, w, w, w, w, w], dz)?;
    let usable = m.azimuth_usable(c).ok()?;
    Some((m.diff(z, &z_hat), usable))
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
    /// values as the default to rounding (tested), about half the unscented update's
    /// instructions (issue 15).
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
        let to: [Vec3; 3] = std::array::from_fn(|j| t * o[j]);
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
        let to: [Vec3; 3] = std::array::from_fn(|j| t * o[j]);
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
                std::array::from_fn(|r| t[(r, 0)] * c0 + t[(r, 1)] * c1 + t[(r, 2)] * c2);
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

    /// The particle filters' residual (asin of the angle residuals' sines where they are
    /// small) equals `diff(z, predict(r))` everywhere: every frame, azimuths across 0 / 2 pi,
    /// residuals beyond 60 degrees (the atan2 fallback), near the poles.
    /// The block form equals `residual_at` lane by lane, bit for bit, near the
    /// measurement (the vectorised series), off it by up to 0.09 rad (sines beyond the
    /// series': `asin_small` afterwards) and far from it, on the pole and at zero range
    /// (the lanes redone by `residual_at`), in every frame; the last block is short.
    #[test]
    #[allow(clippy::needless_range_loop)]
    fn residuals_at_equal_residual_at_bitwise() {
        use rand::Rng;
        const B: usize = 16;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(4);
        for frame in [
            Frame::RadialAlongNormal,
            Frame::AlongRadialAntinormal,
            Frame::AlongAntinormalNadir,
        ] {
            let s = RadioSensor::new(frame, 0.5, 1e-4);
            let centre = Vec3::new(400.0, -500.0, 200.0);
            let z = s.predict(&centre).unwrap() + Vec3::new(0.3, 1e-4, -2e-4);
            let trig = AngleTrig::of(&z);
            for k in 0..400 {
                let n = if k % 7 == 6 { 5 } else { B };
                let mut r = [[0.0; B]; 3];
                for i in 0..B {
                    let p = match (k + i) % 9 {
                        0 => Vec3::from_fn(|_, _| rng.random_range(-1000.0..1000.0)),
                        1 => Vec3::zeros(),
                        2 => frame.vec_to_canonical(&Vec3::new(0.0, 0.0, 300.0)),
                        3 => centre * rng.random_range(0.5..1.5),
                        // off the measurement by up to 0.09 rad (sines beyond the series')
                        4 => {
                            let across = centre.cross(&Vec3::new(0.2, 0.3, 1.0)).normalize();
                            centre + across * rng.random_range(-60.0..60.0)
                        }
                        _ => centre + Vec3::from_fn(|_, _| rng.random_range(-2.0..2.0)),
                    };
                    (r[0][i], r[1][i], r[2][i]) = (p.x, p.y, p.z);
                }
                let mut d = [[f64::NAN; B]; 3];
                let mut ok = [false; B];
                s.residuals_at(&z, &trig, &r, n, &mut d, &mut ok);
                for i in 0..n {
                    let ri = Vec3::new(r[0][i], r[1][i], r[2][i]);
                    match s.residual_at(&z, &trig, &ri) {
                        Some(v) => {
                            assert!(ok[i], "{ri:?}");
                            for c in 0..3 {
                                assert_eq!(d[c][i].to_bits(), v[c].to_bits(), "{ri:?} {c}");
                            }
                        }
                        None => assert!(!ok[i], "{ri:?}"),
                    }
                }
            }
        }
    }

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
                let got = s.residual_at(&z, &AngleTrig::of(&z), &r).unwrap();
                assert!(
                    (got - want).abs().max() < 1e-9,
                    "{frame:?} r {r:?} z {z:?}: {got:?} vs {want:?}"
                );
            }
            assert!(s
                .residual_at(
                    &Vec3::new(1.0, 0.0, 0.0),
                    &AngleTrig::of(&Vec3::new(1.0, 0.0, 0.0)),
                    &Vec3::zeros()
                )
                .is_none());
        }
    }

    /// The series agrees with `libm` to an ulp or two where it is used, and is `libm`'s
    /// `asin` elsewhere (a bound derived from the first neglected term, not tuned).
    #[test]
    fn asin_small_is_asin() {
        let mut worst: f64 = 0.0;
        for k in -100_000..=100_000 {
            let s = f64::from(k) * (0.031_25 / 100_000.0);
            let (a, b) = (asin_small(s), s.asin());
            if s != 0.0 {
                worst = worst.max(((a - b) / b).abs());
            } else {
                assert_eq!(a, 0.0);
            }
        }
        assert!(worst < 4.5e-16, "worst relative error {worst:e}");
        for s in [0.031_250_001, 0.1, -0.5, 0.9, 1.0, -1.0] {
            assert_eq!(asin_small(s), s.asin());
        }
        assert!(asin_small(f64::NAN).is_nan());
    }

    /// The radio sensor's unscented transform (no `atan2` per point) equals the default
    /// one (`predict`, circular `weighted_mean`, wrapped `diff`) to rounding: clouds of 13
    /// points near and far, across the azimuth's 0 / 2 pi cut, spreads beyond 60 degrees
    /// (the `atan2` path), a point on the pole, with the UKF's default weights and with a
    /// negative centre weight; and whether the azimuth is usable, as `geometry` says.
    /// `unscented_seven_block` equals `unscented_seven` bit for bit on every lane it marks
    /// fast, on the dispatched and the baseline path, and marks fast every lane whose
    /// centre and points are well inside the series' domain, innovation angles beyond it
    /// included (measurements off the cloud by up to 0.1 rad); far-off lanes, the pole and
    /// zero range are left to the caller.
    #[test]
    #[allow(clippy::needless_range_loop)]
    fn seven_block_equals_unscented_seven_bitwise() {
        use crate::numerics::simd::{dispatch, with_baseline};
        use rand::Rng;
        const B: usize = 16;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(8);
        let (mut fast_lanes, mut lanes, mut wide_lanes) = (0, 0, 0);
        for frame in Frame::ALL {
            let s = RadioSensor::new(frame, 0.5, 1e-3);
            let truth = frame.vec_to_canonical(&Vec3::new(400.0, 500.0, -200.0));
            for k in 0..200 {
                let spread = [0.3, 3.0, 30.0][k % 3];
                let o: [Vec3; 3] = std::array::from_fn(|_| {
                    Vec3::from_fn(|_, _| rng.random_range(-spread..spread))
                });
                let wm = [(0.0, 1.0 / 6.0), (-2.0, 0.5)][k % 2];
                // every fourth measurement off the cloud by up to 0.1 rad (innovation
                // angles beyond the series' 2^-5: `libm`'s `asin` in both forms)
                let da = if k % 4 == 3 { 0.1 } else { 3e-3 };
                let z = s.predict(&truth).unwrap()
                    + Vec3::new(
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-da..da),
                        rng.random_range(-da..da),
                    );
                let trig = AngleTrig::of(&z);
                let c: [[f64; B]; 3] = {
                    let mut c = [[0.0; B]; 3];
                    for i in 0..B {
                        let p = match (k + i) % 23 {
                            0 => Vec3::zeros(),
                            1 => frame.vec_to_canonical(&Vec3::new(0.0, 0.0, 300.0)),
                            2 => truth * 1.5,
                            _ => truth + Vec3::from_fn(|_, _| rng.random_range(-5.0..5.0)),
                        };
                        (c[0][i], c[1][i], c[2][i]) = (p.x, p.y, p.z);
                    }
                    c
                };
                let run = || {
                    let mut out = SevenBlock::<B>::default();
                    dispatch(
                        #[inline(always)]
                        || s.unscented_seven_block(&z, &trig, &c, &o, wm, &mut out),
                    );
                    out
                };
                let (a, b) = (run(), with_baseline(run));
                for i in 0..B {
                    assert_eq!(a.fast[i], b.fast[i]);
                    lanes += 1;
                    if !a.fast[i] {
                        continue;
                    }
                    fast_lanes += 1;
                    let ci = Vec3::new(c[0][i], c[1][i], c[2][i]);
                    let mut dz = [Vec3::zeros(); 7];
                    let (nu, usable) = s.unscented_seven(&z, &trig, &ci, &o, wm, &mut dz).unwrap();
                    assert!(usable);
                    if nu.y.abs().max(nu.z.abs()) > 0.04 {
                        wide_lanes += 1;
                    }
                    for out in [&a, &b] {
                        for kk in 0..3 {
                            assert_eq!(
                                out.nu[kk][i].to_bits(),
                                nu[kk].to_bits(),
                                "{frame:?} {k} {i}"
                            );
                            for (p, d) in dz.iter().enumerate() {
                                assert_eq!(
                                    out.dz[p][kk][i].to_bits(),
                                    d[kk].to_bits(),
                                    "{frame:?} {k} {i} {p}"
                                );
                            }
                        }
                    }
                }
            }
        }
        // the pole, zero range and the far-off lanes (3 in 23) and the widest spreads fall back
        assert!(
            fast_lanes > lanes / 2 && fast_lanes < lanes,
            "{fast_lanes} of {lanes}"
        );
        // and innovation angles beyond the series' domain do not (about half the lanes of
        // the measurements off by up to 0.1 rad)
        assert!(wide_lanes > fast_lanes / 10, "{wide_lanes} of {fast_lanes}");
    }

    #[test]
    fn unscented_transform_equals_the_default() {
        use rand::Rng;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let weights = [
            [1.0 / 12.0; 13],
            std::array::from_fn(|i| if i == 0 { -2.0 } else { 0.25 }),
        ];
        for frame in [
            Frame::RadialAlongNormal,
            Frame::AlongRadialAntinormal,
            Frame::AlongAntinormalNadir,
        ] {
            let s = RadioSensor::new(frame, 0.5, 1e-4);
            for k in 0..4000 {
                let wm = &weights[k % 2];
                let c = match k % 4 {
                    // on the azimuth cut (sensor x axis) and near it
                    0 => frame.vec_to_canonical(&Vec3::new(500.0, 0.0, 100.0)),
                    _ => Vec3::from_fn(|_, _| rng.random_range(-1000.0..1000.0)),
                };
                let spread = [1.0, 50.0, 2000.0][k % 3];
                let mut r: [Vec3; 13] = std::array::from_fn(|_| {
                    c + Vec3::from_fn(|_, _| rng.random_range(-spread..spread))
                });
                if k % 97 == 0 {
                    r[3] = frame.vec_to_canonical(&Vec3::new(0.0, 0.0, 300.0));
                }
                let zs: Vec<Vec3> = r.iter().map(|ri| s.predict(ri).unwrap()).collect();
                let want_hat = s.weighted_mean(wm, &zs);
                let mut got = [Vec3::zeros(); 13];
                let got_hat = s.unscented(&r, wm, &mut got).unwrap();
                let scale = 1.0 + want_hat.x.abs();
                assert!((got_hat.x - want_hat.x).abs() < 1e-12 * scale);
                assert!(wrap_pi(got_hat.y - want_hat.y).abs() < 1e-9);
                assert!((got_hat.z - want_hat.z).abs() < 1e-12);
                for (zi, gi) in zs.iter().zip(&got) {
                    let want = s.diff(zi, &want_hat);
                    assert!(
                        (gi.x - want.x).abs() < 1e-12 * scale
                            && wrap_pi(gi.y - want.y).abs() < 1e-9
                            && (gi.z - want.z).abs() < 1e-12,
                        "{frame:?} {k}: {gi:?} vs {want:?}"
                    );
                }
                assert_eq!(
                    s.azimuth_usable(&c).unwrap(),
                    s.geometry(&c).unwrap().azimuth_usable
                );
            }
            let mut dz = [Vec3::zeros(); 2];
            assert!(s
                .unscented(&[Vec3::x(), Vec3::zeros()], &[0.5, 0.5], &mut dz)
                .is_none());
            assert!(s.azimuth_usable(&Vec3::zeros()).is_err());
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
