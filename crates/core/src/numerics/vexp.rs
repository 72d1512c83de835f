//! `e^x` for `x <= 0` without a library call or a branch, so that a loop over many values
//! (a particle filter's weights, `exp(l_i - max_j l_j)`) vectorises.
//!
//! The classic reduction (Cody & Waite 1980; Tang 1989): `x = n ln 2 + r` with
//! `n = round(x / ln 2)` and `|r| <= ln 2 / 2`, `r` formed with `ln 2` split into a head of
//! 32 significant bits (so `n ln2_hi` is exact for `|n| < 2^20`) and a tail;
//! `e^r` by its Taylor polynomial to degree 13, whose first neglected term
//! `|r|^14 / 14! < 3.6e-18` is below `2^-58` of `e^r >= 0.7`, evaluated as
//! `1 + (r + r^2 U(r))` with `U(r) = sum_(k=2)^13 r^(k-2) / k!` by Estrin's scheme (pairs
//! `c_k + c_(k+1) r`, combined with `r^2`, then `r^4`): as many operations as Horner's rule
//! but a third of its dependent depth, which bounds a vectorised loop over many values by
//! latency (the `1 +` last, so that its one rounding
//! dominates as in Horner's form); then `e^x = e^r 2^n`, the
//! power of two applied as two normal factors `2^n1 2^n2` (`n1 + n2 = n`, both
//! `>= -538`), so a result in the subnormal range is rounded once, as it should be.
//! `n` and the exponent bits are formed with the round-to-nearest constant `1.5 2^52`
//! instead of `round` and integer conversions (neither vectorises on the x86-64 baseline).
//!
//! Accuracy: within 2 ulp of the correctly rounded value on `[-745.2, 0]` (tested
//! against `libm`'s `exp` over the whole range); `exp_nonpos(0) = 1` exactly (the
//! largest particle weight stays exactly 1 after the max subtraction); below
//! `-745.2` (where `e^x` rounds to zero) the result is 0; NaN gives NaN.

/// `1.5 * 2^52`: `(y + ROUND) - ROUND` is `y` rounded to the nearest integer for
/// `|y| < 2^51`, and the low mantissa bits of `y + ROUND` hold that integer.
const ROUND: f64 = 6_755_399_441_055_744.0;
/// `2^52`: the low 52 mantissa bits of `k + TWO52` are the integer `k`, `0 <= k < 2^52`.
const TWO52: f64 = 4_503_599_627_370_496.0;
const LOG2E: f64 = core::f64::consts::LOG2_E;
/// `ln 2` to 32 significant bits (fdlibm's `ln2_hi`, bits 0x3fe62e42fee00000: trailing mantissa
/// bits zero).
const LN2_HI: f64 = 0.693_147_180_369_123_8;
/// `ln 2 - LN2_HI` (fdlibm's `ln2_lo`, bits 0x3dea39ef35793c76).
const LN2_LO: f64 = 1.908_214_929_270_587_7e-10;

/// `2^k` for an integer-valued `k` in `[-1022, 1023]`, from the exponent bits.
#[inline(always)]
fn pow2(k: f64) -> f64 {
    f64::from_bits((k + (1023.0 + TWO52)).to_bits() << 52)
}

/// `e^x` for `x <= 0` (see the module documentation); positive `x` are taken as 0
/// (result 1).
#[inline(always)]
pub fn exp_nonpos(x: f64) -> f64 {
    // NaN stays NaN through the arithmetic; the clamps keep it (comparisons are false)
    let xc = if x < -745.2 { -745.2 } else { x };
    let xc = if xc > 0.0 { 0.0 } else { xc };
    let n = (xc * LOG2E + ROUND) - ROUND;
    let r = (xc - n * LN2_HI) - n * LN2_LO;
    // U's coefficients 1/k!, k = 2..=13
    const C: [f64; 12] = [
        0.5,
        1.0 / 6.0,
        1.0 / 24.0,
        1.0 / 120.0,
        1.0 / 720.0,
        1.0 / 5_040.0,
        1.0 / 40_320.0,
        1.0 / 362_880.0,
        1.0 / 3_628_800.0,
        1.0 / 39_916_800.0,
        1.0 / 479_001_600.0,
        1.0 / 6_227_020_800.0,
    ];
    let r2 = r * r;
    let r4 = r2 * r2;
    let b0 = (C[0] + C[1] * r) + (C[2] + C[3] * r) * r2;
    let b1 = (C[4] + C[5] * r) + (C[6] + C[7] * r) * r2;
    let b2 = (C[8] + C[9] * r) + (C[10] + C[11] * r) * r2;
    let u = b0 + (b1 + b2 * r4) * r4;
    let p = 1.0 + (r + r2 * u);
    let n1 = (n * 0.5 + ROUND) - ROUND;
    let n2 = n - n1;
    let y = p * pow2(n1) * pow2(n2);
    // e^x rounds to 0 below about -745.13
    if x < -745.2 {
        0.0
    } else {
        y
    }
}

#[cfg(test)]
mod tests {
    use super::exp_nonpos;

    /// Distance in units in the last place (of the reference's magnitude; subnormals in
    /// units of the smallest subnormal).
    fn ulps(a: f64, b: f64) -> f64 {
        (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs() as f64
    }

    #[test]
    fn matches_libm_within_two_ulp() {
        let mut worst: f64 = 0.0;
        let mut x = 0.0f64;
        // a dense sweep of [-746, 0], steps not commensurate with ln 2
        while x > -746.0 {
            let (a, b) = (exp_nonpos(x), x.exp());
            worst = worst.max(ulps(a, b));
            x -= 0.000_737_1;
        }
        // values near zero and near the rounding boundaries of n
        for k in 0..2000 {
            for x in [
                -(k as f64) * 1e-9,
                -(k as f64) * core::f64::consts::LN_2 * 0.5,
                -(k as f64) * core::f64::consts::LN_2 * 0.5 - 1e-12,
            ] {
                if x > -746.0 {
                    worst = worst.max(ulps(exp_nonpos(x), x.exp()));
                }
            }
        }
        assert!(worst <= 2.0, "worst error {worst} ulp");
    }

    #[test]
    fn constants_are_fdlibms() {
        assert_eq!(super::LN2_HI.to_bits(), 0x3fe6_2e42_fee0_0000);
        assert_eq!(super::LN2_LO.to_bits(), 0x3dea_39ef_3579_3c76);
        assert_eq!(super::LN2_HI.to_bits() & 0x1f_ffff, 0);
    }

    #[test]
    fn edges() {
        assert_eq!(exp_nonpos(0.0), 1.0);
        assert_eq!(exp_nonpos(-0.0), 1.0);
        assert_eq!(exp_nonpos(1.0), 1.0);
        assert_eq!(exp_nonpos(-800.0), 0.0);
        assert_eq!(exp_nonpos(f64::NEG_INFINITY), 0.0);
        assert!(exp_nonpos(f64::NAN).is_nan());
        assert!(exp_nonpos(-745.0) > 0.0);
    }
}
