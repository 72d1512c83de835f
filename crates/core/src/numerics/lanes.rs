//! Fixed-length arithmetic on plain `f64` arrays that the compiler keeps in vector
//! registers: sums in sixteen interleaved lanes ([`lane_sum`], [`lane_sum_sq`]: the
//! particle filters' weight sums), four-lane vectors (`L4`, one AVX2 vector: the moment
//! sums) and the 4- and 6-vector axpys of the covariance products. Every lane is a scalar
//! chain in a fixed order without fused multiply-adds, so the results are the same bits on
//! every instruction set.

/// The number of partial sums of [`lane_sum`] and [`lane_sum_sq`]: four AVX2 vectors (eight
/// SSE2 ones), enough independent chains to cover the latency of a floating-point add
/// (3-4 cycles) at one or two adds per cycle.
const SUM_LANES: usize = 16;

/// `sum v_i` in sixteen interleaved partial sums (`v_i` goes to lane `i mod 16`; the
/// tail of fewer than 16 values to lanes `0..`), the lanes then added pairwise in a fixed
/// order (lane `j` plus lane `j + 8`, then `j + 4`, `j + 2`, `j + 1`). The particle
/// filters' weight sums and sums of squares: one chain in index order is `N`
/// dependent adds for `N` particles, bound by the add's latency; sixteen chains run at the
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

/// Four `f64` lanes (one AVX2 vector).
pub(crate) type L4 = [f64; 4];

/// `a + b` lane by lane.
#[inline(always)]
pub(crate) fn add4(a: L4, b: L4) -> L4 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3]]
}

/// `a b` lane by lane.
#[inline(always)]
pub(crate) fn mul4(a: L4, b: L4) -> L4 {
    [a[0] * b[0], a[1] * b[1], a[2] * b[2], a[3] * b[3]]
}

/// `y += a x` on 4-vectors (two 2-wide SSE2 multiply-adds).
#[inline(always)]
pub(crate) fn axpy4(y: &mut [f64; 4], x: &[f64; 4], a: f64) {
    for (yi, xi) in y.iter_mut().zip(x.iter()) {
        *yi += xi * a;
    }
}

/// `y += a x` on 6-vectors (vectorised by the compiler: three 2-wide multiply-adds with
/// SSE2; no FMA, the same rounding on every x86-64).
#[inline(always)]
pub(crate) fn axpy6(y: &mut [f64; 6], x: &[f64; 6], a: f64) {
    for (yi, xi) in y.iter_mut().zip(x.iter()) {
        *yi += xi * a;
    }
}

#[cfg(test)]
mod tests {
    use super::{lane_sum, lane_sum_sq, SUM_LANES};

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
}
