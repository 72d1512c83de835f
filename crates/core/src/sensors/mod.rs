//! Radio (or lidar) sensor: range, azimuth and elevation of the chaser relative to the
//! target, expressed in a chosen [`Frame`](crate::frames::Frame) (paper 000, sec. 2
//! "measurement model"; the digest's erratum: use `atan2(y, x)`, not `arctan(y / x)`).
//!
//! With `p = T r` the relative position in the measurement frame (`T` from
//! [`Frame::rotation`](crate::frames::Frame::rotation), `r` canonical):
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
//!
//! Two traits say what a filter needs of a sensor. [`Sensor`] (`sensor.rs`) is the generic
//! one: any number of components, a function of the full state, its own noise density;
//! every filter takes it through one path
//! ([`crate::estimators::Estimator::update_sensor`]). [`MeasurementModel`] (here) is the
//! radio-shaped specialisation: three components of the position, with the hooks the
//! filters' vectorised paths use ([`Modelled`] makes one a [`Sensor`]). The sensors are
//! [`RadioSensor`] (`radio.rs`, with its vectorised residuals and unscented transforms),
//! [`CartesianSensor`] (`cartesian.rs`; with a noise, relative GNSS's position), and the
//! [`Sensor`]s [`CameraSensor`] (the line of sight alone) and [`VelocitySensor`] (relative
//! GNSS's velocity) (`camera.rs`); the angle helpers ([`wrap_pi`], [`AngleTrig`],
//! [`asin_small`]) are in `angles.rs`.

mod angles;
mod camera;
mod cartesian;
mod radio;
mod sensor;

pub(crate) use angles::ASIN_SERIES_MAX;
pub use angles::{asin_series, asin_small, wrap_2pi, wrap_pi, AngleTrig};
#[cfg(feature = "std")]
pub use camera::add_noise;
pub use camera::{CameraSensor, VelocitySensor};
pub use cartesian::CartesianSensor;
pub use radio::RadioSensor;
pub use sensor::{Linearization, Modelled, Sensor, SensorNoise, Support};

use crate::types::{Mat3, Mat36, Vec3};

/// Below this range [m] the measurement directions are undefined.
pub const MIN_RANGE: f64 = 1e-6;
/// Below this ratio `rho_xy / rho` (cosine of the elevation) the azimuth is ignored.
pub const POLE_COS: f64 = 1e-6;

/// Why a measurement cannot be predicted at a state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GeometryError {
    /// The relative position is (numerically) zero: no direction exists.
    ZeroRange,
}

impl GeometryError {
    /// The reason in words (what `Display` writes; without `std`, without numbers).
    pub fn message(&self) -> crate::message::Message {
        match self {
            GeometryError::ZeroRange => crate::msg!(
                "relative range below {MIN_RANGE} m: azimuth and elevation are undefined"
            ),
        }
    }
}

impl core::fmt::Display for GeometryError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(&self.message())
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
    /// `z` less the prediction of `g` ([`MeasurementModel::diff`]), the azimuth's
    /// component zero where `g` marks it unusable (its row of `g.h` is zero too, so its
    /// gain column vanishes): the innovation every linearised update takes.
    fn linearised_residual(&self, z: &Vec3, g: &Geometry) -> Vec3 {
        let mut nu = self.diff(z, &g.z);
        if !g.azimuth_usable {
            nu.y = 0.0;
        }
        nu
    }
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
    /// Whether the model is linear in the position, `z = H r` with a constant `H` (default:
    /// false; the Cartesian position sensor).
    fn linear(&self) -> bool {
        false
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
