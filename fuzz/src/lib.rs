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

/// Header length of an estimator state (`RELNAVES`, docs/state-format.md).
pub const ESTIMATOR_HEADER: usize = 32;
/// Header length of an FMU state (`RELNAVFM`).
pub const FMU_HEADER: usize = 70;

/// How a saved state is damaged before it is restored or deserialised.
#[derive(Arbitrary, Debug, Clone)]
pub enum Damage {
    /// Intact (must restore).
    None,
    /// Cut to `n mod len` bytes.
    Truncate(u16),
    /// One byte changed (the checksum refuses it).
    Flip { at: u16, xor: u8 },
    /// Bytes overwritten in place (clipped to the blob), then the payload length and
    /// CRC-32 fixed, so the field checks behind the checksum are reached; `inner`: in the
    /// estimator state an FMU state embeds (both envelopes resealed).
    Resealed {
        at: u16,
        bytes: Vec<u8>,
        inner: bool,
    },
    /// A double written at `at`, resealed (`inner` as above).
    Number { at: u16, value: Num, inner: bool },
    /// The header kept, the payload replaced by arbitrary bytes, length and CRC fixed.
    Payload(Vec<u8>),
    /// Arbitrary bytes.
    Raw(Vec<u8>),
}

impl Damage {
    /// Whether the blob stays intact.
    pub fn is_none(&self) -> bool {
        matches!(self, Damage::None)
    }
}

/// Fix the payload length and the CRC-32 of the envelope `b` (header length `hl`), as
/// relnav's `numerics::state::seal` writes them (recomputed here from the documented
/// layout, not by relnav's writer).
pub fn reseal(b: &mut [u8], hl: usize) {
    if b.len() < hl {
        return;
    }
    let n = (b.len() - hl) as u64;
    b[hl - 12..hl - 4].copy_from_slice(&n.to_le_bytes());
    let mut all = b[..hl - 4].to_vec();
    all.extend_from_slice(&b[hl..]);
    let c = relnav_core::numerics::state::crc32(&all);
    b[hl - 4..hl].copy_from_slice(&c.to_le_bytes());
}

fn u64_at(b: &[u8], at: usize) -> Option<u64> {
    Some(u64::from_le_bytes(b.get(at..at + 8)?.try_into().ok()?))
}

/// Where the estimator state embedded in an FMU state lies (`start..end`), if any: after
/// the tag, mode, time, start time, stop flag and time, the variable count and values and
/// the estimator flag and length (docs/state-format.md).
pub fn embedded_estimator(b: &[u8]) -> Option<(usize, usize)> {
    let count_at = FMU_HEADER + 4 + 4 + 8 + 8 + 1 + 8;
    let n = usize::try_from(u64_at(b, count_at)?).ok()?;
    let flag = count_at.checked_add(8)?.checked_add(n.checked_mul(8)?)?;
    if *b.get(flag)? != 1 {
        return None;
    }
    let len = usize::try_from(u64_at(b, flag + 1)?).ok()?;
    let start = flag + 9;
    let end = start.checked_add(len)?;
    (end <= b.len()).then_some((start, end))
}

/// `blob` (an estimator state when `hl` is [`ESTIMATOR_HEADER`], an FMU state when
/// [`FMU_HEADER`]) after `d`.
pub fn damage(blob: &[u8], d: &Damage, hl: usize) -> Vec<u8> {
    let mut b = blob.to_vec();
    let overwrite = |b: &mut Vec<u8>, at: u16, bytes: &[u8], inner: bool| {
        let inner_range = if inner && hl == FMU_HEADER {
            embedded_estimator(b)
        } else {
            None
        };
        let (s, e) = inner_range.unwrap_or((0, b.len()));
        if e > s {
            let at = s + usize::from(at) % (e - s);
            let n = bytes.len().min(e - at);
            b[at..at + n].copy_from_slice(&bytes[..n]);
            if inner_range.is_some() {
                reseal(&mut b[s..e], ESTIMATOR_HEADER);
            }
        }
        reseal(b, hl);
    };
    match d {
        Damage::None => {}
        Damage::Truncate(n) => {
            if !b.is_empty() {
                b.truncate(usize::from(*n) % b.len());
            }
        }
        Damage::Flip { at, xor } => {
            if !b.is_empty() {
                let i = usize::from(*at) % b.len();
                b[i] ^= (*xor).max(1);
            }
        }
        Damage::Resealed { at, bytes, inner } => overwrite(&mut b, *at, bytes, *inner),
        Damage::Number { at, value, inner } => {
            overwrite(&mut b, *at, &value.value(1.0).to_le_bytes(), *inner)
        }
        Damage::Payload(p) => {
            b.truncate(hl);
            b.extend_from_slice(p);
            reseal(&mut b, hl);
        }
        Damage::Raw(r) => b = r.clone(),
    }
    b
}

/// The text of an FMU log message, checked: the FMU passes the message itself as the
/// logger's `printf` format with no arguments, so every `%` must be doubled (`%%`: no
/// conversion that would read a variadic argument) and every `#` doubled (FMI's escape
/// character). Panics otherwise.
pub fn log_text(format: &[u8]) -> String {
    let mut out = Vec::with_capacity(format.len());
    let mut i = 0;
    while i < format.len() {
        let b = format[i];
        if b == b'%' || b == b'#' {
            assert_eq!(
                format.get(i + 1),
                Some(&b),
                "unescaped {:?} in log format {:?}",
                b as char,
                String::from_utf8_lossy(format)
            );
            i += 1;
        }
        out.push(b);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}
