//! `ln x` for positive normal `x` without a library call or a branch, so that a loop over
//! many values (the unscented particle filter's posterior log-determinants,
//! `ln(M_00 M_11 M_22)`, one per particle) vectorises.
//!
//! fdlibm's `__ieee754_log` (Sun Microsystems 1993, the algorithm of `e_log.c`) without its
//! special cases: `x = 2^k (1 + f)` with `sqrt(2)/2 <= 1 + f < sqrt(2)` (the exponent bits,
//! the mantissa moved into that range by fdlibm's integer test on its high bits), then
//!
//! ```text
//! s = f / (2 + f),   R(z) = Lg1 z + ... + Lg7 z^7 ~ (ln(1+f) - 2s) / s,   z = s^2,
//! ln x = k ln2_hi - ((f^2/2 - (s (f^2/2 + R) + k ln2_lo)) - f)
//! ```
//!
//! with fdlibm's minimax coefficients (`|R - (ln(1+f) - 2s)/s| < 2^-58.45` on the range)
//! and `ln 2` split so that `k ln2_hi` is exact. The exponent `k` becomes a float through the
//! `2^52` bit trick (no integer conversion, which does not vectorise on x86-64 without
//! AVX-512). Accuracy: within 1 ulp of the correctly rounded value for every positive
//! normal `x` (fdlibm's bound; tested against `libm`'s `ln`). Zero, subnormal, negative,
//! infinite and NaN arguments are outside the domain ([`ln_pos`] sends them to `libm`).

/// `2^52`: the low 52 mantissa bits of `k + TWO52` are the integer `k`, `0 <= k < 2^52`.
const TWO52: f64 = 4_503_599_627_370_496.0;
/// `ln 2` to 32 significant bits (fdlibm's `ln2_hi`, bits 0x3fe62e42fee00000).
const LN2_HI: f64 = 0.693_147_180_369_123_8;
/// `ln 2 - LN2_HI` (fdlibm's `ln2_lo`, bits 0x3dea39ef35793c76).
const LN2_LO: f64 = 1.908_214_929_270_587_7e-10;
/// fdlibm's `Lg1` .. `Lg7` (the shortest decimals of its bit patterns; tested).
const LG: [f64; 7] = [
    0.666_666_666_666_673_5,
    0.399_999_999_994_094_2,
    0.285_714_287_436_623_9,
    0.222_221_984_321_497_84,
    0.181_835_721_616_180_5,
    0.153_138_376_992_093_73,
    0.147_981_986_051_165_86,
];

/// `ln x` for a positive normal finite `x` (see the module documentation), no branch;
/// unspecified outside that domain.
#[inline(always)]
pub fn ln_normal(x: f64) -> f64 {
    let b = x.to_bits();
    let hx = (b >> 32) & 0x000f_ffff;
    // 0x100000 where the mantissa exceeds sqrt(2) (fdlibm's test): then halve it
    let i = (hx + 0x95f64) & 0x0010_0000;
    let m = f64::from_bits((b & 0x000f_ffff_ffff_ffff) | ((i ^ 0x3ff0_0000) << 32));
    // k + 1023 as the low bits of 2^52 + k + 1023
    let kb = (b >> 52) + (i >> 20);
    let dk = f64::from_bits(kb | 0x4330_0000_0000_0000) - (TWO52 + 1023.0);
    let f = m - 1.0;
    let s = f / (2.0 + f);
    let z = s * s;
    let w = z * z;
    let t1 = w * (LG[1] + w * (LG[3] + w * LG[5]));
    let t2 = z * (LG[0] + w * (LG[2] + w * (LG[4] + w * LG[6])));
    let r = t2 + t1;
    let hfsq = 0.5 * f * f;
    dk * LN2_HI - ((hfsq - (s * (hfsq + r) + dk * LN2_LO)) - f)
}

/// `ln x` for any `x`: [`ln_normal`] for positive normal finite `x`, `libm`'s `ln`
/// otherwise (zero, subnormal, negative, infinite, NaN).
#[inline]
pub fn ln_pos(x: f64) -> f64 {
    if is_normal_pos(x) {
        ln_normal(x)
    } else {
        x.ln()
    }
}

/// Whether `x` is in [`ln_normal`]'s domain: positive, normal and finite.
#[inline(always)]
pub fn is_normal_pos(x: f64) -> bool {
    (f64::MIN_POSITIVE..=f64::MAX).contains(&x)
}

#[cfg(test)]
mod tests {
    use super::{ln_normal, ln_pos, LG, LN2_HI, LN2_LO};
    use rand::{Rng, SeedableRng};

    fn ulps(a: f64, b: f64) -> f64 {
        let u = if b == 0.0 {
            f64::MIN_POSITIVE
        } else {
            f64::from_bits(b.abs().to_bits() + 1) - b.abs()
        };
        (a - b).abs() / u
    }

    /// The constants are fdlibm's, bit for bit.
    #[test]
    fn constants_are_fdlibms() {
        let bits = [
            0x3fe5_5555_5555_5593_u64,
            0x3fd9_9999_9997_fa04,
            0x3fd2_4924_9422_9359,
            0x3fcc_71c5_1d8e_78af,
            0x3fc7_4664_96cb_03de,
            0x3fc3_9a09_d078_c69f,
            0x3fc2_f112_df3e_5244,
        ];
        for (c, b) in LG.iter().zip(bits) {
            assert_eq!(c.to_bits(), b, "{c:e}");
        }
        assert_eq!(LN2_HI.to_bits(), 0x3fe6_2e42_fee0_0000);
        assert_eq!(LN2_LO.to_bits(), 0x3dea_39ef_3579_3c76);
    }

    /// Within 1 ulp of `libm`'s `ln` (itself correctly rounded in nearly every case) over
    /// the whole normal range, densely around 1 and over (0, 1] (the filter's range).
    #[test]
    fn matches_libm_within_one_ulp() {
        let mut g = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let mut worst: f64 = 0.0;
        for k in 0..400_000 {
            let x = match k % 4 {
                0 => {
                    f64::from_bits(g.random_range(f64::MIN_POSITIVE.to_bits()..=f64::MAX.to_bits()))
                }
                1 => 1.0 + g.random_range(-1e-3..1e-3),
                2 => g.random_range(f64::MIN_POSITIVE..1.0),
                _ => g.random_range(0.5..2.0),
            };
            let (a, b) = (ln_normal(x), x.ln());
            worst = worst.max(ulps(a, b));
            assert!(ulps(a, b) <= 1.0, "{x:e}: {a:e} {b:e}");
        }
        assert!(worst > 0.0);
        for x in [
            1.0,
            2.0,
            0.5,
            4.0,
            f64::MIN_POSITIVE,
            f64::MAX,
            core::f64::consts::E,
        ] {
            assert!(ulps(ln_normal(x), x.ln()) <= 1.0, "{x:e}");
        }
        assert_eq!(ln_normal(1.0), 0.0);
        assert_eq!(ln_normal(2.0), core::f64::consts::LN_2);
    }

    #[test]
    fn outside_the_domain_is_libms() {
        for x in [0.0, -0.0, 1e-310, -1.0, f64::INFINITY, f64::NAN] {
            let (a, b) = (ln_pos(x), x.ln());
            assert!(
                a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
                "{x:e}"
            );
        }
    }
}
