//! Angles: wrapping to `(-pi, pi]` and `[0, 2 pi)`, the sines and cosines of a
//! measurement's angles formed once ([`AngleTrig`]), and `asin` of small residual sines by
//! its series ([`asin_small`], [`asin_series`]).

#[cfg(not(feature = "std"))]
use crate::math::Float;
use crate::types::Vec3;
use core::f64::consts::{PI, TAU};

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

/// The sines and cosines of a measurement's azimuth (component 1) and elevation
/// (component 2), formed once per measurement for
/// [`MeasurementModel::residual_at`](super::MeasurementModel::residual_at).
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

/// `asin(s)` for `|s| <= 1`, by its Maclaurin series where `|s| <= 2^-5`:
///
/// ```text
/// asin s = s + s^3/6 + 3 s^5/40 + 5 s^7/112 + 35 s^9/1152 + O(s^11)
/// ```
///
/// whose first neglected term, `63 s^11 / 2816`, is below `2.3e-2 * 2^-50 |s| < 2^-55 |s|`
/// (under a quarter of an ulp) there; `libm`'s `asin` elsewhere. A particle's angle
/// residuals are milliradians, where the series is much cheaper than `asin`.
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensors::RadioSensor;

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
}
