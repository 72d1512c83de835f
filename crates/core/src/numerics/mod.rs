//! Numerical helpers shared by the layers above (estimators, H-infinity design, navigator,
//! C ABI): number formatting for error messages, the iteration-capped eigen and singular
//! value decompositions every caller uses instead of nalgebra's uncapped ones ([`eigen`]),
//! the thread setting of the BLAS linked for the H-infinity design, and [`state`] (the
//! explicit bytes of saved state) and [`vexp`] (a branch-free `e^x` for `x <= 0` that
//! vectorises, for the particle weights) and [`ziggurat`] (exact standard normals in batches,
//! for the particle filters), [`simd`] (run-time dispatch of hot loops to AVX2, same bits),
//! and [`lane_sum`] (sums in sixteen lanes, for the particle weights). Lives below its
//! users; imports nothing from them.

#[cfg(feature = "hinf")]
#[allow(unsafe_code)]
pub mod blas;
pub mod eigen;
pub mod simd;
pub mod state;
pub mod vexp;
pub mod vlog;
pub mod ziggurat;

/// Whether every value is finite (neither NaN nor infinite). Branch-free: the per-value
/// tests are and-ed without short-circuit, so the loop vectorises (a 6x6 covariance in a
/// few vector instructions instead of 36 compare-and-branch rounds). The filters check
/// their estimate and covariance after every step (issue 15: a tenth of the EKF's step
/// went to the short-circuiting `iter().all(is_finite)`).
#[inline]
pub fn all_finite(v: &[f64]) -> bool {
    v.iter().fold(true, |ok, x| ok & x.is_finite())
}

/// The number of partial sums of [`lane_sum`] and [`lane_sum_sq`]: four AVX2 vectors (eight
/// SSE2 ones), enough independent chains to cover the latency of a floating-point add
/// (3-4 cycles) at one or two adds per cycle.
const SUM_LANES: usize = 16;

/// `sum v_i` in sixteen interleaved partial sums (`v_i` goes to lane `i mod 16`; the
/// tail of fewer than 16 values to lanes `0..`), the lanes then added pairwise in a fixed
/// order (lane `j` plus lane `j + 8`, then `j + 4`, `j + 2`, `j + 1`). The particle
/// filters' weight sums and sums of squares (issue 15): one chain in index order is 1 500
/// dependent adds for 1 500 particles, bound by the add's latency; sixteen chains run at the
/// adds' throughput. Every lane is a scalar chain whatever the vector width, so the result
/// is the same bits on every instruction set, and fixed by the length: reproducible. It
/// differs from the in-order sum at rounding level (both are within `(n - 1) eps sum|v_i|`).
/// For non-negative `v_i` the result is at least every `v_i` (rounding is monotone).
#[inline(always)]
pub fn lane_sum(v: &[f64]) -> f64 {
    lane_sum_of(v, |x| x)
}

/// `sum v_i^2` in the lanes and order of [`lane_sum`] (the product rounded, then added: no
/// fused multiply-add, so the same bits on every instruction set).
#[inline(always)]
pub fn lane_sum_sq(v: &[f64]) -> f64 {
    lane_sum_of(v, |x| x * x)
}

/// [`lane_sum`] of `f(v_i)`.
#[inline(always)]
fn lane_sum_of(v: &[f64], f: impl Fn(f64) -> f64) -> f64 {
    let mut acc = [0.0; SUM_LANES];
    let mut blocks = v.chunks_exact(SUM_LANES);
    for b in &mut blocks {
        for (a, &x) in acc.iter_mut().zip(b) {
            *a += f(x);
        }
    }
    for (a, &x) in acc.iter_mut().zip(blocks.remainder()) {
        *a += f(x);
    }
    let mut half = SUM_LANES / 2;
    while half > 0 {
        let (lo, hi) = acc.split_at_mut(half);
        for (a, &b) in lo.iter_mut().zip(hi.iter()) {
            *a += b;
        }
        half /= 2;
    }
    acc[0]
}

/// A number for an error message: plain when readable, scientific when tiny or huge.
pub fn num(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 || !v.is_finite() || (1e-4..1e7).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::{all_finite, lane_sum, lane_sum_sq, num, SUM_LANES};

    /// The lanes' order, written out: lane `j` takes `v_j, v_{j+16}, ...`, the tail goes to
    /// the first lanes, and the lanes are added pairwise (8, 4, 2, 1 apart). Checked with
    /// values whose sums round differently in another order.
    #[test]
    fn lane_sums_follow_their_documented_order() {
        for n in [0usize, 1, 5, 15, 16, 17, 40, 1500, 1501] {
            let v: Vec<f64> = (0..n)
                .map(|i| (1.0 + (i as f64) * 0.37).powi(3) * if i % 3 == 0 { 1e-9 } else { 1.0 })
                .collect();
            let reference = |f: fn(f64) -> f64| {
                let mut l = [0.0f64; SUM_LANES];
                let full = n / SUM_LANES * SUM_LANES;
                for (i, &x) in v[..full].iter().enumerate() {
                    l[i % SUM_LANES] += f(x);
                }
                for (i, &x) in v[full..].iter().enumerate() {
                    l[i] += f(x);
                }
                for half in [8, 4, 2, 1] {
                    for j in 0..half {
                        l[j] += l[j + half];
                    }
                }
                l[0]
            };
            assert_eq!(
                lane_sum(&v).to_bits(),
                reference(|x| x).to_bits(),
                "n = {n}"
            );
            assert_eq!(
                lane_sum_sq(&v).to_bits(),
                reference(|x| x * x).to_bits(),
                "n = {n}"
            );
            // and at rounding level from the in-order sum
            let plain: f64 = v.iter().sum();
            assert!((lane_sum(&v) - plain).abs() <= 1e-15 * n as f64 * plain.abs().max(1.0));
        }
        // the dispatched (AVX2) form is the same bits as the baseline's
        let v: Vec<f64> = (0..1503)
            .map(|i| ((i * 7919) % 1000) as f64 * 1e-3)
            .collect();
        let fast = crate::numerics::simd::dispatch(
            #[inline(always)]
            || (lane_sum(&v), lane_sum_sq(&v)),
        );
        assert_eq!(fast.0.to_bits(), lane_sum(&v).to_bits());
        assert_eq!(fast.1.to_bits(), lane_sum_sq(&v).to_bits());
    }

    #[test]
    fn all_finite_finds_every_non_finite_value() {
        assert!(all_finite(&[]));
        assert!(all_finite(&[
            0.0,
            -0.0,
            f64::MAX,
            f64::MIN_POSITIVE,
            -1e-300
        ]));
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            for at in 0..37 {
                let mut v = [1.0; 37];
                v[at] = bad;
                assert!(!all_finite(&v), "{bad} at {at}");
            }
        }
    }

    #[test]
    fn formats_readable_and_extreme_numbers() {
        assert_eq!(num(0.5), "0.5");
        assert_eq!(num(0.0), "0");
        assert_eq!(num(1e-9), "1e-9");
        assert_eq!(num(2.5e12), "2.5e12");
        assert_eq!(num(f64::NAN), "NaN");
    }
}
