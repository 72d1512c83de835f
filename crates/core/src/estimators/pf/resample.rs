//! Resampling of weighted particles, log-weight normalisation and the effective sample size.
//!
//! [`resample`] draws `M = out.len()` parent indices from `N = w.len()` normalised weights:
//! new particle `k` copies particle `out[k]`. Every scheme is unbiased, i.e. the expected
//! number of copies of particle `i` is `M w_i`; they differ in the variance of the copy
//! counts (Douc, Cappé & Moulines 2005, "Comparison of resampling schemes for particle
//! filtering", ISPA 2005, compare all four and prove the ordering used in the tests).
//!
//! The schemes map `M` points `u_k` of `[0, 1)` through the inverse of the cumulative
//! weights `C_i = w_0 + ... + w_i` (particle `i` is chosen when `C_{i-1} <= u_k < C_i`):
//!
//! - [`Resampler::Multinomial`]: `M` iid uniforms, i.e. `M` iid draws from the categorical
//!   distribution `w` (the classic SIR / bootstrap filter of paper 000). The uniforms are
//!   generated already sorted by the exponential-spacings method (`u_k = S_k / S_{M+1}` with
//!   `S_k` the partial sums of `M + 1` iid standard exponentials), so no sort is needed and
//!   the output is ascending.
//! - [`Resampler::Stratified`]: one uniform in each stratum, `u_k = (k + U_k) / M` with iid
//!   `U_k` (Kitagawa 1996, "Monte Carlo filter and smoother for non-Gaussian nonlinear state
//!   space models", JCGS 5(1)).
//! - [`Resampler::Systematic`]: one uniform `U` for all strata, `u_k = (k + U) / M`
//!   (Kitagawa 1996; also Carpenter, Clifford & Fearnhead 1999). The default: cheapest and,
//!   in practice, lowest variance; each particle gets `floor(M w_i)` or `ceil(M w_i)` copies.
//! - [`Resampler::Residual`]: `floor(M w_i)` deterministic copies of each particle, then the
//!   remaining `R = M - sum_i floor(M w_i)` draws multinomially from the residual weights
//!   `(M w_i - floor(M w_i)) / R` (Liu & Chen 1998, "Sequential Monte Carlo methods for
//!   dynamic systems", JASA 93(443)).
//!
//! Every scheme returns its indices in ascending order (copies of a particle are
//! contiguous), runs in `O(N + M)` time and allocates nothing: `scratch` holds the sorted
//! uniforms of the multinomial stages. If `scratch` is too short for them the uniforms are
//! generated in the same order by the (slower, one `exp` per draw) product method
//! `u_(k) = u_(k+1) V_k^(1/k)` instead, so any `scratch` length is correct.
//!
//! Robustness: the cumulative sums are compared against `u_k` times the computed total of
//! the weights, and the search never moves past the last particle of positive weight, so
//! round-off can neither produce an index `>= N` nor select a zero-weight particle. Negative
//! and NaN weights count as zero; if no weight is positive (or the total is not finite) the
//! weights are taken as uniform.

use crate::numerics::vexp::exp_nonpos;
use crate::numerics::{lane_sum, lane_sum_sq};
use rand::Rng;
use rand_distr::{Distribution, Exp1};

pub use super::params::Resampler;

/// Draw `out.len()` parent indices from the normalised weights `w` (sum 1, all >= 0,
/// `w.len() >= 1`): new particle i copies particle out[i]. `scratch` has w.len() slots
/// (cumulative sums / residuals) so the call performs no heap allocation. Output indices
/// are sorted ascending for multinomial too (ordered uniforms by exponential spacings,
/// `O(N)`, no sort), so copies are contiguous.
///
/// With `M = out.len()` different from `N = w.len()` the expected number of copies of
/// particle `i` is `M w_i`. Weights that do not sum to exactly 1 are used relative to their
/// sum. Every index is `< N` and belongs to a particle of positive weight (if there is one;
/// otherwise the weights are treated as uniform). An empty `w` leaves `out` unchanged.
pub fn resample<R: Rng + ?Sized>(
    kind: Resampler,
    w: &[f64],
    out: &mut [usize],
    scratch: &mut [f64],
    rng: &mut R,
) {
    let n = w.len();
    if n == 0 || out.is_empty() {
        return;
    }
    let mut total = 0.0;
    let mut last = None;
    // the walking schemes keep the cumulative sums of this pass in `scratch` (when it is
    // long enough) and walk over them: the same sums, bit for bit, as the walk's own
    // running sum, which then needs neither the weights nor their cleaning again
    let walking = matches!(kind, Resampler::Systematic | Resampler::Stratified);
    match scratch.get_mut(..n).filter(|_| walking) {
        Some(cum) => {
            for (i, (&x, c)) in w.iter().zip(cum.iter_mut()).enumerate() {
                let x = clean(x);
                total += x;
                *c = total;
                if x > 0.0 {
                    last = Some(i);
                }
            }
            if let Some(last) = last.filter(|_| total.is_finite()) {
                let m = out.len();
                let step = total / m as f64;
                match kind {
                    Resampler::Systematic => {
                        let u: f64 = rng.random();
                        walk_systematic(cum, last, out, u, step);
                    }
                    _ => walk_cumulative(
                        cum,
                        last,
                        out,
                        (0..m).map(|k| (k as f64 + rng.random::<f64>()) * step),
                    ),
                }
                return;
            }
        }
        None => {
            for (i, &x) in w.iter().enumerate() {
                let x = clean(x);
                total += x;
                if x > 0.0 {
                    last = Some(i);
                }
            }
        }
    }
    match last {
        Some(last) if total.is_finite() => {
            let weights = Weights {
                wt: |i: usize| w.get(i).copied().map_or(0.0, clean),
                n,
                total,
                last,
            };
            resample_with(kind, &weights, out, scratch, rng);
        }
        _ => {
            // No usable weight: uniform weights (exact sums: 1 + 1 + ... = n).
            let weights = Weights {
                wt: |_: usize| 1.0,
                n,
                total: n as f64,
                last: n - 1,
            };
            resample_with(kind, &weights, out, scratch, rng);
        }
    }
}

/// Effective sample size `1 / sum w_i^2` of normalised weights (`N` for uniform weights,
/// 1 for a single particle carrying all the weight). Returns 0 if the sum of squares is zero
/// or not finite (including an empty slice). The squares are summed in sixteen lanes
/// ([`lane_sum_sq`]), not in one chain of dependent adds.
pub fn effective_sample_size(w: &[f64]) -> f64 {
    let s = lane_sum_sq(w);
    if s > 0.0 && s.is_finite() {
        1.0 / s
    } else {
        0.0
    }
}

/// Normalise log-weights in place into weights (max-subtracted exp, then divide by the sum);
/// returns the log of the mean likelihood increment log(sum exp(lw - max)) + max - ln N, or
/// None if every log-weight is -inf or NaN (total degeneracy; weights left uniform).
///
/// `N` is `min(logw.len(), w.len())` (the two should be equal; entries of `w` beyond
/// `logw.len()` are left untouched). NaN log-weights get weight 0. If some log-weights are
/// `+inf` they share the weight equally and the result is `Some(+inf)`. An empty input
/// returns `None`.
pub fn normalize_log_weights(logw: &[f64], w: &mut [f64]) -> Option<f64> {
    let n = logw.len().min(w.len());
    normalize_log_weights_with_max(logw, w, max_ignoring_nan(&logw[..n]))
}

/// [`normalize_log_weights`] with the largest log-weight known: `max` must be
/// [`max_ignoring_nan`] of `logw[..N]` (found by a pass that produced the log-weights).
pub fn normalize_log_weights_with_max(logw: &[f64], w: &mut [f64], max: f64) -> Option<f64> {
    let n = logw.len().min(w.len());
    if n == 0 {
        return None;
    }
    let pairs = || logw.iter().take(n);
    if max == f64::NEG_INFINITY {
        w.iter_mut().take(n).for_each(|x| *x = 1.0 / n as f64);
        return None;
    }
    if max == f64::INFINITY {
        let count = pairs().filter(|&&l| l == f64::INFINITY).count();
        for (x, &l) in w.iter_mut().zip(logw) {
            *x = if l == f64::INFINITY {
                1.0 / count as f64
            } else {
                0.0
            };
        }
        return Some(f64::INFINITY);
    }
    // exp(l - max) is in [0, 1]; the maximum contributes exactly 1, so sum >= 1 (in any
    // order of the adds: rounding is monotone). The branch-free exponential (within 2 ulp
    // of libm's) lets the loop vectorise; the sum runs in sixteen lanes ([`lane_sum`]).
    let sum = crate::numerics::simd::dispatch(
        #[inline(always)]
        || {
            w.iter_mut()
                .zip(logw)
                .for_each(|(x, &l)| *x = if l.is_nan() { 0.0 } else { exp_nonpos(l - max) });
            lane_sum(&w[..n])
        },
    );
    let inv = 1.0 / sum;
    w.iter_mut().take(n).for_each(|x| *x *= inv);
    Some(sum.ln() + max - (n as f64).ln())
}

/// The largest of `v` ignoring NaN (`-inf` if there is none), in four interleaved
/// partial maxima so that the loop vectorises (the maximum does not depend on the order).
pub fn max_ignoring_nan(v: &[f64]) -> f64 {
    // `if l > m` keeps `m` for a NaN `l`, as f64::max does
    let mut lanes = [f64::NEG_INFINITY; 4];
    let mut blocks = v.chunks_exact(4);
    for b in &mut blocks {
        for (m, &l) in lanes.iter_mut().zip(b) {
            *m = if l > *m { l } else { *m };
        }
    }
    let tail = blocks
        .remainder()
        .iter()
        .fold(f64::NEG_INFINITY, |m, &l| if l > m { l } else { m });
    lanes.iter().fold(tail, |m, &l| if l > m { l } else { m })
}

/// A weight of zero for negative and NaN inputs.
fn clean(x: f64) -> f64 {
    if x > 0.0 {
        x
    } else {
        0.0
    }
}

/// Unnormalised weights `wt(i)`, `i < n`, their sum (accumulated in index order, so the
/// running cumulative sum reaches it bitwise) and the last index with positive weight.
struct Weights<F: Fn(usize) -> f64> {
    wt: F,
    n: usize,
    total: f64,
    last: usize,
}

fn resample_with<F: Fn(usize) -> f64, R: Rng + ?Sized>(
    kind: Resampler,
    w: &Weights<F>,
    out: &mut [usize],
    scratch: &mut [f64],
    rng: &mut R,
) {
    let m = out.len();
    let step = w.total / m as f64;
    match kind {
        Resampler::Systematic => {
            let u: f64 = rng.random();
            walk(w, out, (0..m).map(|k| (k as f64 + u) * step));
        }
        Resampler::Stratified => {
            walk(
                w,
                out,
                (0..m).map(|k| (k as f64 + rng.random::<f64>()) * step),
            );
        }
        Resampler::Multinomial => match scratch.get_mut(..m) {
            Some(s) => {
                let scale = w.total / exponential_spacings(s, rng);
                walk(w, out, s.iter().map(|&x| x * scale));
            }
            None => walk(w, out, descending_product(m, w.total, rng)),
        },
        Resampler::Residual => residual(w, out, scratch, rng),
    }
}

/// Fill `s` with the partial sums `S_1 <= ... <= S_M` of iid standard exponentials and return
/// `S_{M+1}`: then `S_k / S_{M+1}` are the order statistics of `M` iid uniforms.
fn exponential_spacings<R: Rng + ?Sized>(s: &mut [f64], rng: &mut R) -> f64 {
    let mut acc = 0.0;
    for x in s.iter_mut() {
        let e: f64 = Exp1.sample(rng);
        acc += e;
        *x = acc;
    }
    let e: f64 = Exp1.sample(rng);
    acc + e
}

/// `m` ascending order statistics of iid uniforms on `[0, scale)`, without storage: the
/// maximum of `j` uniforms on `[0, a)` is `a V^(1/j)`, so `v_(m) = V^(1/m)`,
/// `v_(j) = v_(j+1) V_j^(1/j)` descends; `1 - v` ascends (the uniform is symmetric).
fn descending_product<R: Rng + ?Sized>(
    m: usize,
    scale: f64,
    rng: &mut R,
) -> impl Iterator<Item = f64> + '_ {
    let mut log_v = 0.0;
    (0..m).map(move |k| {
        let e: f64 = Exp1.sample(rng);
        log_v -= e / (m - k) as f64;
        (1.0 - log_v.exp()) * scale
    })
}

/// Inverse-CDF search for ascending targets `t` in `[0, total]`: particle `i` for
/// `C_{i-1} <= t < C_i`, never past the last positive weight.
fn walk<F: Fn(usize) -> f64>(
    w: &Weights<F>,
    out: &mut [usize],
    targets: impl Iterator<Item = f64>,
) {
    let mut i = 0;
    let mut c = (w.wt)(0);
    for (o, t) in out.iter_mut().zip(targets) {
        while t >= c && i < w.last {
            i += 1;
            c += (w.wt)(i);
        }
        *o = i;
    }
}

/// [`walk`] over the cumulative sums `cum` (`cum[i] = C_i`, accumulated in index order as
/// [`walk`]'s running sum is: the same comparisons, the same indices), never past `last`.
fn walk_cumulative(
    cum: &[f64],
    last: usize,
    out: &mut [usize],
    targets: impl Iterator<Item = f64>,
) {
    let cum = &cum[..=last];
    let mut i = 0;
    for (o, t) in out.iter_mut().zip(targets) {
        while i < last && t >= cum[i] {
            i += 1;
        }
        *o = i;
    }
}

/// [`walk_cumulative`] for the systematic points `t_k = (k + u) step`, `k < M`, without
/// a data-dependent branch: the same indices, bit for bit (tested against the walk).
///
/// The walk's inner loop exits after a random number of steps per point, so its branch
/// mispredicts about once per particle, which makes the walk a noticeable part of the
/// literal SIR's step. Here each particle `i < last` counts the
/// points below its cumulative weight instead, independently of the others (the loop
/// vectorises, and no branch depends on the data):
///
/// ```text
/// n_i = #{k < M : t_k < C_i} = the least k with t_k >= C_i (M if none)
/// ```
///
/// (`t_k` ascends with `k`: `k + u` and the product with `step > 0` are monotone in
/// floating point), estimated as `ceil(C_i / step - u)` clamped to `[0, M]` and verified by
/// the exact comparisons `t_(k-1) < C_i <= t_k` of the points themselves (the walk's
/// expression `(k + u) * step`): should an estimate fail them (`C_i / step - u` within
/// rounding of an integer), the walk runs instead. The walk's index for point
/// `k` is the first `i` with `C_i > t_k`, or `last`: the number of particles `i < last` with
/// `C_i <= t_k`, i.e. with `n_i <= k`: particle `i`'s copies are `out[n_(i-1)..n_i]`
/// (`n_(-1) = 0`), and `last`'s the rest. They are written in ascending `i` as runs of a
/// fixed length [`RUN`] (vector stores, no loop whose length depends on the data) from
/// `n_(i-1)`: each run's excess is overwritten by the later particles' runs, and the rare
/// particle with more than [`RUN`] copies has the rest written by a loop of its own.
fn walk_systematic(cum: &[f64], last: usize, out: &mut [usize], u: f64, step: f64) {
    let m = out.len();
    // the points, as the walk and `count_below` form them
    let t = |k: f64| (k + u) * step;
    let (Some(head), true) = (cum.get(..last), step > 0.0 && step.is_finite()) else {
        return walk_cumulative(cum, last, out, (0..m).map(|k| t(k as f64)));
    };
    const CHUNK: usize = 64;
    let mf = m as f64;
    let inv = 1.0 / step;
    let mut n_i = [0u64; CHUNK];
    let mut start = 0;
    for (b, c) in head.chunks(CHUNK).enumerate() {
        // zeros past the end of the last chunk: counted (0), not scattered
        let mut ci = [0.0; CHUNK];
        ci.iter_mut().zip(c).for_each(|(d, &s)| *d = s);
        let exact = crate::numerics::simd::dispatch(
            #[inline(always)]
            || count_below(&ci, u, step, inv, mf, &mut n_i),
        );
        if !exact {
            return walk_cumulative(cum, last, out, (0..m).map(|k| t(k as f64)));
        }
        let first = b * CHUNK;
        start = crate::numerics::simd::dispatch(
            #[inline(always)]
            || write_runs(out, first, &n_i[..c.len()], start),
        );
    }
    if let Some(rest) = out.get_mut(start..) {
        rest.fill(last);
    }
}

/// The length of the runs [`walk_systematic`] writes per particle: copies beyond it take a
/// loop of their own (systematic resampling gives particle `i` `floor(M w_i)` or
/// `ceil(M w_i)` copies: more than eight only for a weight above `8 / M`).
const RUN: usize = 8;

/// [`walk_systematic`]'s runs for the particles `first + j` with counts `ends[j]`
/// (`n_i`, ascending), the first run starting at `start`; returns where the next particle's
/// copies start (the last count).
#[inline(always)]
fn write_runs(out: &mut [usize], first: usize, ends: &[u64], mut start: usize) -> usize {
    for (j, &end) in ends.iter().enumerate() {
        let i = first + j;
        let end = usize::try_from(end).unwrap_or(out.len());
        match out.get_mut(start..start + RUN) {
            Some(run) => run.copy_from_slice(&[i; RUN]),
            None => out.get_mut(start..).unwrap_or_default().fill(i),
        }
        if end > start + RUN {
            if let Some(more) = out.get_mut(start + RUN..end) {
                more.fill(i);
            }
        }
        start = end;
    }
    start
}

/// [`walk_systematic`]'s counts for one chunk: `n[i]` the number of points
/// `t_k = (k + u) step`, `k < m` (`mf = m < 2^52`), below `c[i]`, estimated as
/// `ceil(c[i] inv - u)` clamped to `[0, m]` (`inv` about `1 / step`) and checked by the
/// points' own comparisons `t_(k-1) < c[i] <= t_k`; `false` if an estimate failed them (then
/// the walk runs: the estimate is off only where `c[i] / step - u` lies within rounding of
/// an integer). Branch-free, so that it vectorises; the count, an integer in `[0, 2^52)`,
/// becomes one as the low bits of `k + 2^52` (exact, and cheaper than the saturating
/// conversion `as usize`).
#[inline(always)]
#[allow(clippy::needless_range_loop)] // index loops over fixed lanes: they vectorise
fn count_below<const C: usize>(
    c: &[f64; C],
    u: f64,
    step: f64,
    inv: f64,
    mf: f64,
    n: &mut [u64; C],
) -> bool {
    const TWO52: f64 = 4_503_599_627_370_496.0;
    let mut off = [0u64; C];
    for i in 0..C {
        let ci = c[i];
        let k = (ci * inv - u).ceil().max(0.0).min(mf);
        let below = ((k - 1.0) + u) * step;
        let at = (k + u) * step;
        let exact = ((k <= 0.0) | (below < ci)) & ((k >= mf) | (at >= ci));
        off[i] = u64::from(!exact);
        n[i] = (k + TWO52).to_bits() - TWO52.to_bits();
    }
    // integer flags: their `|` reassociates (vectorised), a sum of floats would not
    let mut bad = 0;
    for i in 0..C {
        bad |= off[i];
    }
    bad == 0
}

fn residual<F: Fn(usize) -> f64, R: Rng + ?Sized>(
    w: &Weights<F>,
    out: &mut [usize],
    scratch: &mut [f64],
    rng: &mut R,
) {
    let m = out.len();
    let mf = m as f64;
    // Expected copies x_i = M w_i / total, split into floor and fractional residual. The same
    // expression is evaluated in both passes, so the residual sums agree bitwise.
    let split = |i: usize| {
        let x = (w.wt)(i) / w.total * mf;
        let f = x.floor();
        (f, x - f)
    };
    let mut deterministic = 0usize;
    let mut residual_total = 0.0;
    let mut last_residual = None;
    for i in 0..w.n {
        let (f, r) = split(i);
        // `as` saturates; x <= M up to round-off.
        deterministic = deterministic.saturating_add(f as usize);
        residual_total += r;
        if r > 0.0 {
            last_residual = Some(i);
        }
    }
    let draws = match last_residual {
        Some(_) => m.saturating_sub(deterministic),
        None => 0,
    };
    match scratch.get_mut(..draws) {
        Some(s) => {
            let scale = residual_total / exponential_spacings(s, rng);
            merge(w, &split, last_residual, out, s.iter().map(|&x| x * scale));
        }
        None => {
            let targets = descending_product(draws, residual_total, rng);
            merge(w, &split, last_residual, out, targets);
        }
    }
}

/// Write, for each particle in turn, its deterministic copies and then the residual draws
/// whose targets fall in its residual interval (all remaining ones at the last particle with
/// a positive residual), so the output is ascending.
fn merge<F: Fn(usize) -> f64, S: Fn(usize) -> (f64, f64)>(
    w: &Weights<F>,
    split: &S,
    last_residual: Option<usize>,
    out: &mut [usize],
    mut targets: impl Iterator<Item = f64>,
) {
    let m = out.len();
    let mut pos = 0usize;
    let mut c = 0.0;
    let mut next = targets.next();
    for i in 0..w.n {
        let (f, r) = split(i);
        c += r;
        let end = pos.saturating_add(f as usize).min(m);
        if let Some(slots) = out.get_mut(pos..end) {
            slots.fill(i);
        }
        pos = end;
        let at_last = last_residual == Some(i);
        while let Some(t) = next {
            if t >= c && !at_last {
                break;
            }
            if let Some(o) = out.get_mut(pos) {
                *o = i;
                pos += 1;
            }
            next = targets.next();
        }
    }
    // Only reached through round-off in the floors: complete with the last positive-weight
    // particle (the largest index written so far, so the output stays ascending).
    if let Some(rest) = out.get_mut(pos..) {
        rest.fill(w.last);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    /// N = 50 weights proportional to exp of a parabola (near-zero tails, about 1e-8 at the
    /// left end) plus one dominant particle.
    fn test_weights() -> Vec<f64> {
        let n = 50;
        let mut lw: Vec<f64> = (0..n)
            .map(|i| -0.5 * ((i as f64 - 30.0) / 5.0).powi(2))
            .collect();
        lw[12] = 2.5;
        let mut w = vec![0.0; n];
        assert!(normalize_log_weights(&lw, &mut w).is_some());
        w
    }

    /// Per-particle mean and sample variance of the copy counts over `reps` calls.
    fn copy_stats(
        kind: Resampler,
        w: &[f64],
        m: usize,
        scratch_len: usize,
        reps: usize,
        seed: u64,
    ) -> (Vec<f64>, Vec<f64>) {
        let n = w.len();
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut out = vec![0; m];
        let mut scratch = vec![0.0; scratch_len];
        let mut counts = vec![0usize; n];
        let mut sum = vec![0.0; n];
        let mut sum_sq = vec![0.0; n];
        for _ in 0..reps {
            resample(kind, w, &mut out, &mut scratch, &mut rng);
            counts.iter_mut().for_each(|c| *c = 0);
            for &o in &out {
                counts[o] += 1;
            }
            for i in 0..n {
                let c = counts[i] as f64;
                sum[i] += c;
                sum_sq[i] += c * c;
            }
        }
        let r = reps as f64;
        let mean: Vec<f64> = sum.iter().map(|s| s / r).collect();
        let var = (0..n)
            .map(|i| ((sum_sq[i] - r * mean[i] * mean[i]) / (r - 1.0)).max(0.0))
            .collect();
        (mean, var)
    }

    const REPS: usize = 20_000;

    fn check_unbiased(kind: Resampler, w: &[f64], m: usize, scratch_len: usize, seed: u64) {
        let (mean, var) = copy_stats(kind, w, m, scratch_len, REPS, seed);
        for (i, (&mu, &v)) in mean.iter().zip(&var).enumerate() {
            let expected = m as f64 * w[i];
            // An integer-valued count with mean x has variance >= frac(x) (1 - frac(x)):
            // this floors the estimated variance where the sample shows none (systematic,
            // residual, or a near-zero weight never drawn).
            let f = expected - expected.floor();
            let se = (v.max(f * (1.0 - f)) / REPS as f64).sqrt();
            assert!(
                (mu - expected).abs() <= 4.0 * se + 1e-9,
                "{} M={m} scratch={scratch_len}: particle {i} mean copies {mu} vs M w_i \
                 {expected} (se {se})",
                kind.name()
            );
        }
    }

    /// The branch-free systematic walk gives the walk's indices, bit for bit: weights with
    /// zeros (leading, trailing, runs), ties, one dominant particle, sizes `M` below, equal
    /// to and above `N`, and the points' offset `u` at both ends of `[0, 1)` and between.
    #[test]
    fn systematic_counts_equal_the_walk() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let mut cases: Vec<Vec<f64>> = vec![
            test_weights(),
            vec![1.0],
            vec![0.0, 0.0, 1.0, 0.0],
            vec![0.25; 4],
            vec![1e-300, 1.0, 1e-300],
        ];
        for n in [2, 7, 63, 64, 65, 130, 1500] {
            for zeros in [0.0, 0.3, 0.9] {
                cases.push(
                    (0..n)
                        .map(|_| {
                            if rng.random::<f64>() < zeros {
                                0.0
                            } else {
                                // heavy spread: exp of a normal-ish log-weight
                                (8.0 * (rng.random::<f64>() - 0.5)).exp()
                            }
                        })
                        .collect(),
                );
            }
        }
        let offsets = [0.0, 0.5, 1.0 - f64::EPSILON / 2.0, 0.123_456_789];
        for w in &cases {
            let n = w.len();
            let mut cum = vec![0.0; n];
            let mut total = 0.0;
            let mut last = None;
            for (i, (&x, c)) in w.iter().zip(cum.iter_mut()).enumerate() {
                total += x;
                *c = total;
                if x > 0.0 {
                    last = Some(i);
                }
            }
            let Some(last) = last else { continue };
            for m in [1, n / 2 + 1, n, 2 * n + 3] {
                let step = total / m as f64;
                let draws = (0..20).map(|_| rng.random::<f64>());
                for u in offsets.into_iter().chain(draws) {
                    let mut a = vec![usize::MAX; m];
                    let mut b = vec![usize::MAX; m];
                    walk_cumulative(&cum, last, &mut a, (0..m).map(|k| (k as f64 + u) * step));
                    walk_systematic(&cum, last, &mut b, u, step);
                    assert_eq!(a, b, "n {n} m {m} u {u}");
                }
            }
        }
    }

    /// The counts' check refuses an estimate that is off (here by a reciprocal 1 % too
    /// large: the walk would then run) and accepts the exact one.
    #[test]
    fn counts_check_refuses_a_wrong_estimate() {
        let (m, u) = (100usize, 0.37);
        let step = 1.0 / m as f64;
        let c: [f64; 8] = core::array::from_fn(|i| (i as f64 + 0.5) * 0.13);
        let mut n = [0u64; 8];
        assert!(count_below(&c, u, step, 1.0 / step, m as f64, &mut n));
        for (ci, &ni) in c.iter().zip(&n) {
            let want = (0..m).filter(|&k| (k as f64 + u) * step < *ci).count();
            assert_eq!(ni as usize, want);
        }
        assert!(!count_below(&c, u, step, 1.01 / step, m as f64, &mut n));
    }

    #[test]
    fn codes_and_names_round_trip() {
        for (k, r) in Resampler::ALL.iter().enumerate() {
            assert_eq!(*r as i32, k as i32 + 1);
            assert_eq!(Resampler::from_code(*r as i32), Some(*r));
        }
        assert_eq!(Resampler::from_code(0), None);
        assert_eq!(Resampler::from_code(5), None);
        assert_eq!(Resampler::default(), Resampler::Systematic);
        let names: Vec<_> = Resampler::ALL.iter().map(|r| r.name()).collect();
        assert_eq!(
            names,
            ["multinomial", "systematic", "stratified", "residual"]
        );
    }

    #[test]
    fn all_schemes_unbiased() {
        let w = test_weights();
        let n = w.len();
        for (s, kind) in Resampler::ALL.into_iter().enumerate() {
            check_unbiased(kind, &w, n, n, 100 + s as u64);
        }
    }

    #[test]
    fn all_schemes_unbiased_with_other_output_sizes() {
        let w = test_weights();
        let n = w.len();
        for (s, kind) in Resampler::ALL.into_iter().enumerate() {
            check_unbiased(kind, &w, 2 * n, n, 200 + s as u64);
            check_unbiased(kind, &w, 37, n, 300 + s as u64);
        }
    }

    #[test]
    fn all_schemes_unbiased_without_scratch() {
        // Too short a scratch: the ordered uniforms come from the product method instead.
        let w = test_weights();
        let n = w.len();
        for (s, kind) in Resampler::ALL.into_iter().enumerate() {
            check_unbiased(kind, &w, n, 0, 400 + s as u64);
            check_unbiased(kind, &w, 2 * n, n, 500 + s as u64);
        }
    }

    #[test]
    fn variance_below_multinomial() {
        let w = test_weights();
        let n = w.len();
        let total_var = |kind: Resampler| -> f64 {
            let (_, var) = copy_stats(kind, &w, n, n, REPS, 7);
            var.iter().sum()
        };
        let multinomial = total_var(Resampler::Multinomial);
        // Theory: N (1 - sum w_i^2).
        let theory = n as f64 * (1.0 - w.iter().map(|x| x * x).sum::<f64>());
        assert!(
            (multinomial - theory).abs() < 0.05 * theory,
            "multinomial summed variance {multinomial} vs N(1 - sum w^2) = {theory}"
        );
        for kind in [
            Resampler::Systematic,
            Resampler::Stratified,
            Resampler::Residual,
        ] {
            let v = total_var(kind);
            eprintln!(
                "summed copy-count variance: {} {v:.3}, multinomial {multinomial:.3}",
                kind.name()
            );
            assert!(
                v < multinomial,
                "{} summed variance {v} not below multinomial {multinomial}",
                kind.name()
            );
        }
    }

    #[test]
    fn indices_in_range_and_ascending() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        for &n in &[1usize, 2, 7, 50, 1500] {
            let lw: Vec<f64> = (0..n).map(|_| -20.0 * rng.random::<f64>()).collect();
            let mut w = vec![0.0; n];
            normalize_log_weights(&lw, &mut w).unwrap();
            for &m in &[1usize, n, 2 * n, n / 2 + 1] {
                for kind in Resampler::ALL {
                    for scratch_len in [n, 0] {
                        let mut out = vec![usize::MAX; m];
                        let mut scratch = vec![0.0; scratch_len];
                        for _ in 0..20 {
                            resample(kind, &w, &mut out, &mut scratch, &mut rng);
                            assert!(out.iter().all(|&o| o < n), "{} n={n} m={m}", kind.name());
                            assert!(
                                out.windows(2).all(|p| p[0] <= p[1]),
                                "{} n={n} m={m}: not ascending",
                                kind.name()
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn degenerate_weights_give_all_copies() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let n = 20;
        for j in [0, 9, n - 1] {
            let mut w = vec![0.0; n];
            w[j] = 1.0;
            for kind in Resampler::ALL {
                for m in [n, 2 * n, 3] {
                    for scratch_len in [n, 0] {
                        let mut out = vec![usize::MAX; m];
                        let mut scratch = vec![0.0; scratch_len];
                        for _ in 0..50 {
                            resample(kind, &w, &mut out, &mut scratch, &mut rng);
                            assert!(out.iter().all(|&o| o == j), "{} j={j}", kind.name());
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn zero_weights_never_selected() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        // Zeros at both ends and in between, weights not summing exactly to 1.
        let w = [0.0, 0.0, 0.3, 0.0, 0.1 + 0.2, 0.0, 0.4 + 1e-12, 0.0, 0.0];
        let mut out = vec![0; 1000];
        let mut scratch = vec![0.0; w.len()];
        for kind in Resampler::ALL {
            for _ in 0..100 {
                resample(kind, &w, &mut out, &mut scratch, &mut rng);
                assert!(out.iter().all(|&o| w[o] > 0.0), "{}", kind.name());
            }
        }
    }

    #[test]
    fn unusable_weights_are_taken_as_uniform() {
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let n = 8;
        for w in [vec![0.0; n], vec![f64::NAN; n], vec![-1.0; n]] {
            for kind in [Resampler::Systematic, Resampler::Residual] {
                let mut out = vec![usize::MAX; n];
                let mut scratch = vec![0.0; n];
                resample(kind, &w, &mut out, &mut scratch, &mut rng);
                assert_eq!(out, (0..n).collect::<Vec<_>>(), "{}", kind.name());
            }
        }
        // Empty weights: nothing to draw from, output untouched.
        let mut out = vec![7usize; 3];
        resample(Resampler::Multinomial, &[], &mut out, &mut [], &mut rng);
        assert_eq!(out, [7, 7, 7]);
    }

    #[test]
    fn normalize_handles_huge_negative_log_weights() {
        let lw = [-1e4, -1e4 - 1.0, -1e4 - 2.0, f64::NEG_INFINITY, f64::NAN];
        let mut w = [0.0; 5];
        let ll = normalize_log_weights(&lw, &mut w).unwrap();
        let z = 1.0 + (-1.0f64).exp() + (-2.0f64).exp();
        assert!((w[0] - 1.0 / z).abs() < 1e-15);
        assert!((w[1] - (-1.0f64).exp() / z).abs() < 1e-15);
        assert!((w[2] - (-2.0f64).exp() / z).abs() < 1e-15);
        assert_eq!(w[3], 0.0);
        assert_eq!(w[4], 0.0);
        assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        // log mean likelihood = log(z) - 1e4 - ln 5.
        let expected = z.ln() - 1e4 - 5.0f64.ln();
        assert!((ll - expected).abs() < 1e-9, "{ll} vs {expected}");
    }

    #[test]
    fn normalize_uniform_log_weights() {
        let n = 1500;
        let lw = vec![-3.0; n];
        let mut w = vec![0.0; n];
        let ll = normalize_log_weights(&lw, &mut w).unwrap();
        assert!((ll + 3.0).abs() < 1e-12);
        assert!(w.iter().all(|&x| (x - 1.0 / n as f64).abs() < 1e-18));
        assert!((effective_sample_size(&w) - n as f64).abs() < 1e-9);
    }

    #[test]
    fn normalize_degenerate_returns_none_and_uniform() {
        let mut w = [0.5, 0.0, 0.25, 0.25];
        let lw = [
            f64::NEG_INFINITY,
            f64::NAN,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ];
        assert_eq!(normalize_log_weights(&lw, &mut w), None);
        assert_eq!(w, [0.25; 4]);
        assert_eq!(normalize_log_weights(&[], &mut []), None);
        // +inf log-weights share the weight.
        let lw = [0.0, f64::INFINITY, 1.0, f64::INFINITY];
        assert_eq!(normalize_log_weights(&lw, &mut w), Some(f64::INFINITY));
        assert_eq!(w, [0.0, 0.5, 0.0, 0.5]);
    }

    #[test]
    fn effective_sample_size_limits() {
        assert_eq!(effective_sample_size(&[0.25; 4]), 4.0);
        assert_eq!(effective_sample_size(&[0.0, 1.0, 0.0]), 1.0);
        assert_eq!(effective_sample_size(&[]), 0.0);
        assert_eq!(effective_sample_size(&[0.0; 3]), 0.0);
        let w = test_weights();
        let ess = effective_sample_size(&w);
        assert!(ess > 1.0 && ess < w.len() as f64, "{ess}");
    }
}
