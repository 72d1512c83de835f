//! Standard normal draws in batches by the Box–Muller transform, as pure vector arithmetic
//! on the four xoshiro256++ lanes of [`Lanes`]: no table look-up, no per-value branch, no
//! rejection. Built for the particle filters' draws (issue 15) as an alternative to
//! [`crate::numerics::ziggurat::Ziggurat::fill_batch_lanes`] and measured against it
//! (docs/evaluation.md, "Seventh pass"): more instructions (24.1 against 19.8 per normal),
//! faster on its own in wall clock, but slower in the SIR transition (13 % more instructions
//! per step, about 6 % more time), so no filter uses it; `examples/normals.rs` compares the
//! two.
//!
//! Box & Muller, "A Note on the Generation of Random Normal Deviates", Ann. Math. Statist.
//! 29(2), 610–611, 1958: for independent `U1` uniform on `(0, 1]` and `U2` uniform on
//! `[0, 1)`,
//!
//! ```text
//! R = sqrt(-2 ln U1),   Z0 = R cos(2 pi U2),   Z1 = R sin(2 pi U2)
//! ```
//!
//! are independent standard normals (`R^2 / 2` is a unit exponential, the angle uniform).
//! One pair takes two 64-bit words (one per normal, as the ziggurat's fast path):
//! - `U1 = (k + 1) 2^-53` with `k` the word's top 53 bits (the 2^-53 grid on `(0, 1]`),
//!   formed without an integer-to-float conversion (none vectorises on x86-64 below
//!   AVX-512): the top 52 bits as the mantissa of a number `v` in `[1, 2)`, less `1 -
//!   2^-53` or `1 - 2^-52` by the 53rd bit (an exact difference);
//!   `ln U1` by [`ln_normal`] (fdlibm's `__ieee754_log`, within 1 ulp), the square
//!   root IEEE-exact;
//! - the angle reduced exactly in the uniform's own domain: `2 pi U2 = (o + f) pi / 4` with
//!   the octant `o` the second word's top 3 bits and the fraction `f` its next 52 bits (the
//!   mantissa trick again, on the 2^-52 grid), so `U2 = (o + f) / 8` is the word's top 55
//!   bits times 2^-55; in the octant, `x = t pi / 4` with `t = f` (even `o`) or `t = 1 - f`
//!   (odd `o`, the reflection about the octant's upper edge; exact on the grid), so
//!   `0 <= x <= pi / 4`; then `sin x` and `cos x` by fdlibm's kernels on `[-pi/4, pi/4]`
//!   (`__kernel_sin`, `__kernel_cos` in the FreeBSD/musl form, Sun Microsystems 1993 and
//!   Bruce Evans 2008: minimax polynomials of degree 13 and 14, without the argument's tail,
//!   within 1 ulp), and the octant's swap of sine and cosine (`o` = 1, 2, 5, 6) and its
//!   signs (cosine negative for `o` = 2..5, sine for `o` = 4..7) applied by bit selects,
//!   not branches.
//!
//! **The law.** Exact Box–Muller up to the uniforms' grids (`U1` on 2^-53, `U2` on 2^-55)
//! and the floating-point rounding of `ln` (1 ulp), `sqrt` (exact), the product `t pi / 4`
//! (half an ulp, `pi / 4` rounded) and the kernels (1 ulp): relative errors of order
//! 1e-16 in each value, no bias beyond that. The grid truncates the tail: `|Z| <= sqrt(-2
//! ln 2^-53) = sqrt(106 ln 2) = 8.57`, whose true probability is about 1e-17. Two values of a
//! pair are independent (exactly so for the continuous transform; the grid's discreteness
//! aside). The batch draws no further words: its cost and its word count are fixed (16
//! words for 16 values), unlike the ziggurat's rare slow paths.
//!
//! Everything is IEEE arithmetic without fused multiply-adds and bit operations, in the
//! same order per lane, so the AVX2 path of [`crate::numerics::simd::dispatch`] and the
//! baseline path give the same bits (tested).

use super::vlog::ln_normal;
use super::ziggurat::{Lanes, LANES};

/// Values per batch of [`fill_batch_lanes`] (the same as the ziggurat's batch).
pub(crate) const BATCH: usize = 16;

/// `pi / 4` rounded to the nearest double.
const PIO4: f64 = std::f64::consts::FRAC_PI_4;

/// fdlibm's `__kernel_sin` coefficients `S1` .. `S6` (k_sin.c; the shortest decimals of its
/// bit patterns, tested).
const S: [f64; 6] = [
    -0.166_666_666_666_666_32,
    0.008_333_333_333_322_49,
    -0.000_198_412_698_298_579_5,
    2.755_731_370_707_006_8e-6,
    -2.505_076_025_340_686_3e-8,
    1.589_690_995_211_55e-10,
];

/// fdlibm's `__kernel_cos` coefficients `C1` .. `C6` (k_cos.c; the shortest decimals of its
/// bit patterns, tested).
const C: [f64; 6] = [
    0.041_666_666_666_666_6,
    -0.001_388_888_888_887_411,
    2.480_158_728_947_673e-5,
    -2.755_731_435_139_066_3e-7,
    2.087_572_321_298_175e-9,
    -1.135_964_755_778_819_5e-11,
];

/// `sin x` for `|x| <= pi / 4` (fdlibm's `__kernel_sin` with a zero tail: `x + x^3 (S1 +
/// x^2 r(x^2))`), within 1 ulp.
#[inline(always)]
pub fn kernel_sin(x: f64) -> f64 {
    let z = x * x;
    let w = z * z;
    let r = S[1] + z * (S[2] + z * S[3]) + z * w * (S[4] + z * S[5]);
    let v = z * x;
    x + v * (S[0] + z * r)
}

/// `cos x` for `|x| <= pi / 4` (fdlibm's `__kernel_cos` with a zero tail, Evans' form:
/// `1 - x^2 / 2` split into a rounded head and its exact error, plus `x^4 r(x^2)`),
/// within 1 ulp.
#[inline(always)]
pub fn kernel_cos(x: f64) -> f64 {
    let z = x * x;
    let w = z * z;
    let r = z * (C[0] + z * (C[1] + z * C[2])) + w * w * (C[3] + z * (C[4] + z * C[5]));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    w + (((1.0 - w) - hz) + z * r)
}

/// The normal pair `(R cos(2 pi U2), R sin(2 pi U2))` of the words `w1` (for `U1`) and `w2`
/// (for `U2`), see the module documentation. Branch-free.
#[inline(always)]
pub fn pair(w1: u64, w2: u64) -> (f64, f64) {
    const ONE: u64 = 0x3ff0_0000_0000_0000;
    // U1 = (top 53 bits + 1) 2^-53 = (1 + m 2^-52) - (1 - 2^-53) (53rd bit 0) or
    // - (1 - 2^-52) (bit 1): an exact difference
    let v = f64::from_bits((w1 >> 12) | ONE);
    let u1 = v - f64::from_bits(0x3fef_ffff_ffff_ffff - ((w1 >> 11) & 1));
    let r = (-2.0 * ln_normal(u1)).sqrt();
    // the octant o and the fraction f in [0, 1) of U2 = (o + f) / 8
    let o = w2 >> 61;
    let f = f64::from_bits(((w2 << 3) >> 12) | ONE) - 1.0;
    // t = f (o even) or 1 - f (o odd) as |odd - f|: exact on the grid
    let odd = f64::from_bits((o & 1) * ONE);
    let t = (odd - f).abs();
    let x = t * PIO4;
    let (s, c) = (kernel_sin(x), kernel_cos(x));
    // swap for o = 1, 2, 5, 6; cosine's sign for o = 2..5, sine's for o = 4..7
    let swap = ((o ^ (o >> 1)) & 1).wrapping_neg();
    let (sb, cb) = (s.to_bits(), c.to_bits());
    let cos_b = ((sb & swap) | (cb & !swap)) ^ (((o + 2) & 4) << 61);
    let sin_b = ((cb & swap) | (sb & !swap)) ^ ((o & 4) << 61);
    (r * f64::from_bits(cos_b), r * f64::from_bits(sin_b))
}

/// Sixteen independent standard normals from the lanes: value `8 h + j` and `8 h + 4 + j`
/// are the pair ([`pair`]) of lane `j`'s words `2 h` (for `U1`) and `2 h + 1` (for `U2`) of
/// this call (`h` = 0, 1). Sixteen words, no other generator, no branch. Written to be
/// inlined into a [`crate::numerics::simd::dispatch`]ed loop, where it runs four lanes per
/// AVX2 instruction. The same batch shape as
/// [`crate::numerics::ziggurat::Ziggurat::fill_batch_lanes`].
#[inline(always)]
pub fn fill_batch_lanes(lanes: &mut Lanes, out: &mut [f64; BATCH]) {
    let mut words = [0u64; BATCH];
    for w in words.chunks_exact_mut(LANES) {
        w.copy_from_slice(&lanes.next_words());
    }
    for (o, w) in out
        .chunks_exact_mut(2 * LANES)
        .zip(words.chunks_exact(2 * LANES))
    {
        let (c, s) = o.split_at_mut(LANES);
        for j in 0..LANES {
            let (z0, z1) = pair(w[j], w[LANES + j]);
            c[j] = z0;
            s[j] = z1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{fill_batch_lanes, kernel_cos, kernel_sin, pair, BATCH, C, PIO4, S};
    use crate::numerics::simd::{dispatch, with_baseline};
    use crate::numerics::ziggurat::Lanes;
    use rand::{Rng, SeedableRng};
    use rand_xoshiro::Xoshiro256PlusPlus;

    /// Distance in ulps of the reference `b`'s magnitude.
    fn ulps(a: f64, b: f64) -> f64 {
        let u = f64::from_bits(b.abs().to_bits() + 1) - b.abs();
        (a - b).abs() / u
    }

    /// The standard normal CDF from the Taylor series of `erf` (|x| <= 6: absolute error
    /// below 1e-7, enough for a KS statistic of 1e6 draws).
    fn phi(x: f64) -> f64 {
        if x.abs() > 6.0 {
            return if x > 0.0 { 1.0 } else { 0.0 };
        }
        let t = x / std::f64::consts::SQRT_2;
        let (mut term, mut sum) = (t, t);
        for n in 1..400 {
            term *= -t * t / n as f64;
            let add = term / (2 * n + 1) as f64;
            sum += add;
            if add.abs() < 1e-18 {
                break;
            }
        }
        0.5 + sum / std::f64::consts::PI.sqrt()
    }

    /// The coefficients are fdlibm's, bit for bit.
    #[test]
    fn constants_are_fdlibms() {
        let s = [
            0xbfc5_5555_5555_5549_u64,
            0x3f81_1111_1110_f8a6,
            0xbf2a_01a0_19c1_61d5,
            0x3ec7_1de3_57b1_fe7d,
            0xbe5a_e5e6_8a2b_9ceb,
            0x3de5_d93a_5acf_d57c,
        ];
        let c = [
            0x3fa5_5555_5555_554c_u64,
            0xbf56_c16c_16c1_5177,
            0x3efa_01a0_19cb_1590,
            0xbe92_7e4f_809c_52ad,
            0x3e21_ee9e_bdb4_b1c4,
            0xbda8_fae9_be88_38d4,
        ];
        for (v, b) in S.iter().zip(s).chain(C.iter().zip(c)) {
            assert_eq!(v.to_bits(), b, "{v:e}");
        }
    }

    /// The kernels within 1 ulp of `libm`'s `sin` and `cos` on a dense grid of `[0, pi/4]`,
    /// the octant edges and their neighbours, and random arguments.
    #[test]
    fn kernels_match_libm_within_one_ulp() {
        let mut worst: f64 = 0.0;
        let mut check = |x: f64| {
            let (s, c) = (kernel_sin(x), kernel_cos(x));
            let (es, ec) = (ulps(s, x.sin()), ulps(c, x.cos()));
            assert!(es <= 1.0, "sin {x:e}: {s:e} {:e}", x.sin());
            assert!(ec <= 1.0, "cos {x:e}: {c:e} {:e}", x.cos());
            worst = worst.max(es).max(ec);
        };
        let n = 1 << 20;
        for k in 0..=n {
            check(PIO4 * k as f64 / n as f64);
        }
        let mut x = PIO4;
        let mut y = f64::MIN_POSITIVE;
        for _ in 0..2000 {
            check(x);
            check(y);
            check(-y);
            x = f64::from_bits(x.to_bits() - 1);
            y = f64::from_bits(y.to_bits() + 1);
        }
        for k in 1..60 {
            check(2f64.powi(-k));
        }
        check(0.0);
        let mut g = rand_chacha::ChaCha8Rng::seed_from_u64(4);
        for _ in 0..1_000_000 {
            check(g.random_range(-PIO4..=PIO4));
        }
        assert!(worst > 0.0);
        assert_eq!(kernel_cos(0.0), 1.0);
        assert_eq!(kernel_sin(0.0).to_bits(), 0);
    }

    /// The words' top bits to the uniform and the angle: the pair is `r (cos, sin)(2 pi
    /// U2)` within the angle's rounding, every octant and its edges.
    #[test]
    fn pairs_are_the_box_muller_transform() {
        let two53 = (1u64 << 53) as f64;
        let mut g = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let mut words: Vec<(u64, u64)> = (0..200_000).map(|_| (g.random(), g.random())).collect();
        // the octant edges: fraction 0 and its largest value, every octant
        for o in 0..8u64 {
            for tail in [0u64, 1, (1 << 52) - 1, 1 << 51] {
                words.push((g.random(), (o << 61) | (tail << 9) | g.random_range(0..512)));
            }
        }
        words.push((0, 0));
        words.push((u64::MAX, u64::MAX));
        for (w1, w2) in words {
            let (z0, z1) = pair(w1, w2);
            let u1 = ((w1 >> 11) + 1) as f64 / two53;
            let r = (-2.0 * u1.ln()).sqrt();
            let ang = 2.0 * std::f64::consts::PI * (w2 >> 9) as f64 / (1u64 << 55) as f64;
            // the reference angle's own rounding (a few 2^-53 of 2 pi) and the kernels', times r
            let tol = 12.0 * f64::EPSILON * r;
            assert!(
                (z0 - r * ang.cos()).abs() <= tol,
                "{w1:x} {w2:x}: {z0} {}",
                r * ang.cos()
            );
            assert!(
                (z1 - r * ang.sin()).abs() <= tol,
                "{w1:x} {w2:x}: {z1} {}",
                r * ang.sin()
            );
            // the radius: within 2 ulp of libm's
            assert!(ulps(z0.hypot(z1), r) <= 4.0, "{w1:x}: {} {r}", z0.hypot(z1));
        }
        // the axes exactly: U2 = o / 8 for even o gives (r, 0), (0, r), (-r, 0), (0, -r)
        let w1 = 0x1234_5678_9abc_def0;
        let (r, _) = pair(w1, 0);
        for (o, want) in [
            (0u64, (r, 0.0)),
            (2, (0.0, r)),
            (4, (-r, 0.0)),
            (6, (0.0, -r)),
        ] {
            let (a, b) = pair(w1, o << 61);
            assert_eq!((a, b), want, "octant {o}");
        }
        // the extremes of U1: 2^-53 (the largest radius, 8.57) and 1 (radius 0)
        let (a, b) = pair(0, 0);
        assert_eq!(b, 0.0);
        assert!(
            (a - (106.0 * std::f64::consts::LN_2).sqrt()).abs() < 1e-14,
            "{a}"
        );
        let (a, b) = pair(u64::MAX, 0);
        assert_eq!((a, b), (0.0, 0.0));
    }

    fn check(draws: &[f64]) {
        let n = draws.len() as f64;
        let mean = draws.iter().sum::<f64>() / n;
        let var = draws.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1.0);
        // 5 standard errors
        assert!(mean.abs() < 5.0 / n.sqrt(), "mean {mean}");
        assert!((var - 1.0).abs() < 5.0 * (2.0 / n).sqrt(), "variance {var}");
        for (k, p) in [(3.0, 2.0 * (1.0 - phi(3.0))), (4.0, 2.0 * (1.0 - phi(4.0)))] {
            let got = draws.iter().filter(|x| x.abs() > k).count() as f64 / n;
            assert!(
                (got - p).abs() < 5.0 * (p / n).sqrt(),
                "mass beyond {k}: {got} vs {p}"
            );
        }
        // Kolmogorov-Smirnov: sqrt(n) D < 1.95 (p = 0.001)
        let mut s = draws.to_vec();
        s.sort_by(f64::total_cmp);
        let d = s
            .iter()
            .enumerate()
            .map(|(i, &x)| {
                let c = phi(x);
                (c - i as f64 / n).abs().max(((i + 1) as f64 / n - c).abs())
            })
            .fold(0.0, f64::max);
        assert!(n.sqrt() * d < 1.95, "KS sqrt(n) D = {}", n.sqrt() * d);
        assert!(s.iter().all(|x| x.is_finite() && x.abs() < 8.58));
    }

    fn draws(seed: u64, n: usize) -> Vec<f64> {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
        let mut v = vec![0.0; n];
        dispatch(
            #[inline(always)]
            || {
                for c in v.chunks_exact_mut(BATCH * 100) {
                    // fresh lanes every 100 batches, as a filter's step derives them
                    let mut lanes = Lanes::seed_from(&mut rng);
                    for b in c.chunks_exact_mut(BATCH) {
                        if let Ok(b) = <&mut [f64; BATCH]>::try_from(b) {
                            fill_batch_lanes(&mut lanes, b);
                        }
                    }
                }
            },
        );
        v
    }

    #[test]
    fn lane_batches_are_standard_normal() {
        let v = draws(15, 1_000_000);
        check(&v);
        // the pair's two values are uncorrelated, and so are their squares
        let pairs = v
            .chunks_exact(8)
            .flat_map(|c| (0..4).map(move |j| (c[j], c[4 + j])));
        let (mut xy, mut x2y2, mut n) = (0.0, 0.0, 0.0);
        for (a, b) in pairs {
            xy += a * b;
            x2y2 += (a * a - 1.0) * (b * b - 1.0);
            n += 1.0;
        }
        assert!((xy / n).abs() < 5.0 / f64::sqrt(n), "E[xy] {}", xy / n);
        assert!(
            (x2y2 / n).abs() < 5.0 * 2.0 / f64::sqrt(n),
            "cov(x^2, y^2) {}",
            x2y2 / n
        );
    }

    #[test]
    fn dispatched_and_baseline_agree_bit_for_bit() {
        let a = draws(16, 64_000);
        let b = with_baseline(|| draws(16, 64_000));
        assert!(a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()));
        // and both equal the scalar pair of the lanes' words
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(16);
        let mut lanes = Lanes::seed_from(&mut rng);
        let mut want = [0.0; BATCH];
        for h in 0..2 {
            let (w1, w2) = (lanes.next_words(), lanes.next_words());
            for j in 0..4 {
                let (z0, z1) = pair(w1[j], w2[j]);
                want[8 * h + j] = z0;
                want[8 * h + 4 + j] = z1;
            }
        }
        assert!(want.iter().zip(&a).all(|(x, y)| x.to_bits() == y.to_bits()));
    }
}
