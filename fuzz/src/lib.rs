//! Shared pieces of relnav's fuzz targets: how a fuzzer's bytes become numbers.
//!
//! A number is drawn as a [`Num`]: mostly the field's meaningful default, scaled by a power
//! of ten or nudged, sometimes a special value (0, -0, NaN, +-inf, the largest and smallest
//! doubles, 1e45, 1e300, ...), sometimes any bit pattern. Defaults keep most inputs valid
//! enough to reach the filters' inner code; the rest covers every double.

use arbitrary::Arbitrary;

/// Special values every numeric input is tried with.
pub const SPECIAL: [f64; 28] = [
    0.0,
    -0.0,
    1.0,
    -1.0,
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    f64::MAX,
    -f64::MAX,
    f64::MIN_POSITIVE,
    5e-324,
    f64::EPSILON,
    1e45,
    1e300,
    -1e300,
    1e-300,
    0.5,
    2.0,
    1e9,
    -1e9,
    std::f64::consts::PI,
    std::f64::consts::TAU,
    std::f64::consts::FRAC_PI_2,
    -std::f64::consts::FRAC_PI_2,
    7200.0,
    1e-9,
    0.1,
    1e6,
];

/// One fuzzed number, relative to a default.
#[derive(Arbitrary, Debug, Clone, Copy)]
pub enum Num {
    /// The default.
    Default,
    /// `default * 10^(e mod 641 - 320)`.
    Scaled(i16),
    /// `default * (1 + f / 2^15)`.
    Nudge(i16),
    /// `default + f / 2^8` (reaches values near a zero default).
    Offset(i16),
    /// One of [`SPECIAL`].
    Special(u8),
    /// Any bit pattern.
    Raw(f64),
}

impl Num {
    /// The number this draw stands for, given the field's default.
    pub fn value(self, default: f64) -> f64 {
        match self {
            Num::Default => default,
            Num::Scaled(e) => default * 10f64.powi(i32::from(e).rem_euclid(641) - 320),
            Num::Nudge(f) => default * (1.0 + f64::from(f) / 32768.0),
            Num::Offset(f) => default + f64::from(f) / 256.0,
            Num::Special(i) => SPECIAL[usize::from(i) % SPECIAL.len()],
            Num::Raw(v) => v,
        }
    }
}

/// Three numbers with their defaults.
pub fn values3(n: &[Num; 3], default: [f64; 3]) -> [f64; 3] {
    [
        n[0].value(default[0]),
        n[1].value(default[1]),
        n[2].value(default[2]),
    ]
}

/// `(range, azimuth in [0, 2 pi), elevation)` of a position, as the sensor defines them
/// (written here, independently of relnav's sensor model).
pub fn measure(p: &[f64]) -> [f64; 3] {
    let (x, y, z) = (p[0], p[1], p[2]);
    let r = (x * x + y * y + z * z).sqrt();
    let mut az = y.atan2(x);
    if az < 0.0 {
        az += std::f64::consts::TAU;
    }
    let el = if r > 0.0 {
        (z / r).clamp(-1.0, 1.0).asin()
    } else {
        0.0
    };
    [r, az, el]
}

/// Bitwise equality of two slices of doubles (NaN equal to the same NaN).
pub fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}
