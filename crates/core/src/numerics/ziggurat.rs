//! Standard normal draws in batches by the ziggurat method (Marsaglia & Tsang, "The
//! Ziggurat Method for Generating Random Variables", J. Stat. Softw. 5(8), 2000, with
//! Doornik's ZIGNOR variant, "An Improved Ziggurat Method to Generate Normal Random
//! Samples", 2005: one 64-bit word per attempt, the layer index from the low bits and a
//! symmetric uniform from the top 52, so index and value never share bits), with 1024 layers
//! (index: the low 10 bits) instead of their 128 or 256: the fraction of values that leave
//! the fast path falls from 1.49 % (256 layers) to 0.43 %, for a table of 8 KiB on the fast
//! path (`X_i`; the slow path's `f(X_i)` another 8 KiB). More layers would leave the fast
//! path still less often, but the larger table costs more time than it saves.
//!
//! Why not `rand_distr::StandardNormal`: it is the same algorithm, but it draws one value
//! at a time behind a per-value branch, and rand_distr exposes neither a batch interface
//! nor its tables. The particle filters need 6 N normals per step, so
//! [`Ziggurat::fill_batch`] splits the work on a batch of 16 values into three loops:
//! 1. the batch's 64-bit words from the generator (one word per value, in order);
//! 2. the fast path on every word without a branch: `x = u X_i` and the flag
//!    `|x| >= X_{i+1}` (the point is outside the layer's rectangle that lies wholly under
//!    the density) or-ed into one flag for the batch;
//! 3. when flagged, the failed values (about 0.43 % with 1024 layers) redone by the exact
//!    scalar slow path ([`Ziggurat::slow`]: the wedge test with one more uniform, Marsaglia's tail
//!    algorithm for the base layer, and a fresh scalar attempt on rejection), drawing
//!    further words from the same generator, in the order of the values.
//!
//! Every value is an exact standard normal draw (up to the 2^-52 grid of the uniform and
//! the tables' rounding, as for every ziggurat), independent of the others: a value's first
//! attempt uses its own word, every further attempt fresh words. The stream of values
//! differs from rand_distr's (other word-to-value mapping), and from one value at a time
//! ([`Ziggurat::sample`]) once a slow path draws words (they come after the batch's).
//!
//! Tables: with `f(x) = exp(-x^2 / 2)`, the base layer's right edge `R`
//! (`Ziggurat::R`) and the common area `V = R f(R) + int_R^inf f` (`Ziggurat::V`) of
//! the 1024 layers, `X_1 = R`, `X_0 = V / f(R)`, `X_{i+1} = f^-1(V / X_i + f(X_i))`,
//! `X_1024 = 0`; computed once at first use (`OnceLock`, no heap).

use rand::{RngCore, SeedableRng};
use rand_xoshiro::SplitMix64;
use std::sync::OnceLock;

/// Layer count (the index is the low 10 bits of a word).
const LAYERS: usize = 1024;

/// The ziggurat's tables: layer edges `x[i] = X_i` and `f[i] = f(X_i)` (`i = 0..=LAYERS`).
#[derive(Debug)]
pub struct Ziggurat {
    x: [f64; LAYERS + 1],
    f: [f64; LAYERS + 1],
}

/// `exp(-x^2 / 2)`, the unnormalised density.
#[inline]
fn pdf(x: f64) -> f64 {
    (-0.5 * x * x).exp()
}

/// A uniform in `[0, 1)` on the 2^-53 grid from a word's top 53 bits.
#[inline]
fn unit(w: u64) -> f64 {
    (w >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// A uniform in `(0, 1]` (for logarithms).
#[inline]
fn unit_open0(w: u64) -> f64 {
    ((w >> 11) + 1) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// The layer index and the symmetric uniform `u` in `[-1, 1)` of a word: the low 10 bits
/// and the top 52 bits as the mantissa of a number in `[2, 4)`, less 3.
#[inline(always)]
fn split(w: u64) -> (usize, f64) {
    let i = (w & (LAYERS as u64 - 1)) as usize;
    let u = f64::from_bits((w >> 12) | 0x4000_0000_0000_0000) - 3.0;
    (i, u)
}

impl Ziggurat {
    /// The right edge of the base layer for 1024 layers (the root of the recursion's closure
    /// `X_1024 = 0`, by bisection in double precision; 3.654 152 885 361 009 for 256 layers).
    pub(crate) const R: f64 = 4.038_849_846_109_504;
    /// The area of each layer (base layer: rectangle up to `R` plus the tail),
    /// `R f(R) + sqrt(pi / 2) erfc(R / sqrt 2)`.
    pub(crate) const V: f64 = 0.001_226_324_646_353_089_3;

    /// The shared tables (computed on first use).
    pub fn get() -> &'static Ziggurat {
        static T: OnceLock<Ziggurat> = OnceLock::new();
        T.get_or_init(Self::build)
    }

    fn build() -> Self {
        let mut x = [0.0; LAYERS + 1];
        let mut f = [0.0; LAYERS + 1];
        x[1] = Self::R;
        f[1] = pdf(Self::R);
        x[0] = Self::V / f[1];
        f[0] = 0.0;
        for i in 1..LAYERS - 1 {
            let next = Self::V / x[i] + f[i];
            x[i + 1] = (-2.0 * next.ln()).sqrt();
            f[i + 1] = next;
        }
        x[LAYERS] = 0.0;
        f[LAYERS] = 1.0;
        Self { x, f }
    }

    /// One standard normal draw (scalar, one word per attempt).
    pub fn sample<R: RngCore + ?Sized>(&self, rng: &mut R) -> f64 {
        let w = rng.next_u64();
        let (i, u) = split(w);
        let x = u * self.x[i];
        if x.abs() < self.x[i + 1] {
            x
        } else {
            self.slow(w, rng)
        }
    }

    /// Values per batch of [`Ziggurat::fill_batch`].
    pub(crate) const BATCH: usize = 16;

    /// Fill `out` with independent standard normal draws: whole batches of
    /// [`Ziggurat::BATCH`] by [`Ziggurat::fill_batch`], the remainder one at a time
    /// ([`Ziggurat::sample`]).
    pub fn fill<R: RngCore + ?Sized>(&self, rng: &mut R, out: &mut [f64]) {
        let mut it = out.chunks_exact_mut(Self::BATCH);
        for o in &mut it {
            if let Ok(o) = <&mut [f64; Self::BATCH]>::try_from(o) {
                self.fill_batch(rng, o);
            }
        }
        for v in it.into_remainder() {
            *v = self.sample(rng);
        }
    }

    /// One batch of independent standard normal draws: the batch's words first (in order),
    /// then the fast path on every word without a branch (an or-ed flag, not a branch per
    /// value), then, only when a value failed the fast test (about 6.6 % of the batches),
    /// the slow paths of the failed values in order (see the module docs).
    #[inline(always)]
    pub fn fill_batch<R: RngCore + ?Sized>(&self, rng: &mut R, out: &mut [f64; Self::BATCH]) {
        let words: [u64; Self::BATCH] = core::array::from_fn(|_| rng.next_u64());
        let mut redo = false;
        for (v, &w) in out.iter_mut().zip(&words) {
            let (i, u) = split(w);
            let x = u * self.x[i];
            *v = x;
            redo |= x.abs() >= self.x[i + 1];
        }
        if redo {
            self.redo(rng, &words, out);
        }
    }

    /// One batch of independent standard normal draws with the words from the lane
    /// generator `lanes` ([`Lanes`], four xoshiro256++ streams advanced together: value
    /// `4 t + j` of the batch takes the `t`-th word of lane `j`), the fast path on every
    /// value without a branch with a bit per value, and the flagged values (about 0.43 %)
    /// redone in order by the exact slow path with further words from the scalar generator
    /// `rng`. Written to be inlined into a [`crate::numerics::simd::dispatch`]ed loop, where
    /// the lanes and the fast path run in AVX2 registers.
    #[inline(always)]
    pub fn fill_batch_lanes<R: RngCore + ?Sized>(
        &self,
        lanes: &mut Lanes,
        rng: &mut R,
        out: &mut [f64; Self::BATCH],
    ) {
        self.fill_batch_lanes_with::<false, R>(lanes, rng, out);
    }

    /// [`Ziggurat::fill_batch_lanes`]' body with the words from [`Lanes::step`]`::<SHIFTED>`
    /// (the same values either way; `SHIFTED` for the RPF's jitter, see [`Lanes`]).
    #[inline(always)]
    pub(crate) fn fill_batch_lanes_with<const SHIFTED: bool, R: RngCore + ?Sized>(
        &self,
        lanes: &mut Lanes,
        rng: &mut R,
        out: &mut [f64; Self::BATCH],
    ) {
        let mut words = [0u64; Self::BATCH];
        for w in words.chunks_exact_mut(LANES) {
            w.copy_from_slice(&lanes.step::<SHIFTED>());
        }
        let mut flags = 0u32;
        for (k, (v, &w)) in out.iter_mut().zip(&words).enumerate() {
            let (i, u) = split(w);
            let x = u * self.x[i];
            *v = x;
            flags |= u32::from(x.abs() >= self.x[i + 1]) << k;
        }
        if flags != 0 {
            self.redo_flagged(rng, &words, flags, out);
        }
    }

    /// The slow paths of the flagged values of a batch (bit `k` of `flags` for value `k`), in
    /// order: one step per flagged value (lowest set bit), not a test per value.
    #[cold]
    #[inline(never)]
    fn redo_flagged<R: RngCore + ?Sized>(
        &self,
        rng: &mut R,
        words: &[u64; Self::BATCH],
        mut flags: u32,
        out: &mut [f64; Self::BATCH],
    ) {
        while flags != 0 {
            let k = flags.trailing_zeros() as usize % Self::BATCH;
            flags &= flags - 1;
            out[k] = self.slow(words[k], rng);
        }
    }

    /// The slow paths of a batch's values that failed the fast test, in order.
    #[cold]
    #[inline(never)]
    fn redo<R: RngCore + ?Sized>(
        &self,
        rng: &mut R,
        words: &[u64; Self::BATCH],
        out: &mut [f64; Self::BATCH],
    ) {
        for (v, &w) in out.iter_mut().zip(words) {
            let (i, u) = split(w);
            if (u * self.x[i]).abs() >= self.x[i + 1] {
                *v = self.slow(w, rng);
            }
        }
    }

    /// The exact continuation of an attempt with word `w` that failed the fast test:
    /// the tail beyond `R` for the base layer (Marsaglia 1964: `x = -ln(U1) / R`,
    /// `y = -ln(U2)`, accept when `2 y >= x^2`, return `R + x`), the wedge test
    /// `f(X_i) + (f(X_{i+1}) - f(X_i)) U < f(x)` otherwise, and fresh attempts (fast
    /// test included) with new words while rejected.
    #[cold]
    fn slow<R: RngCore + ?Sized>(&self, mut w: u64, rng: &mut R) -> f64 {
        loop {
            // the attempt with `w` failed the fast test (`|x| >= X_{i+1}`)
            let (i, u) = split(w);
            let x = u * self.x[i];
            if i == 0 {
                loop {
                    let a = -unit_open0(rng.next_u64()).ln() / Self::R;
                    let b = -unit_open0(rng.next_u64()).ln();
                    if 2.0 * b >= a * a {
                        return if u < 0.0 { -(Self::R + a) } else { Self::R + a };
                    }
                }
            }
            let y = self.f[i] + (self.f[i + 1] - self.f[i]) * unit(rng.next_u64());
            if y < pdf(x) {
                return x;
            }
            // a fresh attempt, fast test first
            w = rng.next_u64();
            let (i, u) = split(w);
            let x = u * self.x[i];
            if x.abs() < self.x[i + 1] {
                return x;
            }
        }
    }
}

/// Lanes of [`Lanes`] (not exported to C: `pub(crate)`).
pub(crate) const LANES: usize = 4;

/// Four (`LANES`) xoshiro256++ generators (Blackman & Vigna 2021) advanced together, state word
/// `k` of lane `j` in `s[k][j]` (structure of arrays), so that one step of all lanes is a
/// few vector instructions (AVX2: 64-bit adds, shifts and xors four wide; the rotations
/// as two shifts and an or) instead of about 15 scalar instructions per word.
///
/// Transient by design: a particle filter derives the lanes from its own (saved)
/// generator at the start of each transition ([`Lanes::seed_from`]), so its saved state is
/// still that generator's four words and a restored filter continues identically.
///
/// The output's rotation `rotl(s0 + s3, 23)` is written as a left and a right shift by
/// amounts held in the struct (`rot`, set through [`std::hint::black_box`] when the lanes
/// are made), because LLVM folds every constant-amount form of a rotation (`rotate_left`,
/// `(x << k) | (x >> (64 - k))`, with `^` or `+`) into a funnel-shift intrinsic that its SLP
/// vectoriser then keeps scalar (`rorx` per lane, with extracts and inserts around it); with
/// amounts it cannot see, the output is two AVX2 shifts by a broadcast count and an or per
/// four words. The state's rotation `rotl(s3, 45)` stays a constant rotation: in the
/// particle steps' simple loops that mix vectorises the whole step, and where the SLP
/// vectoriser does not take the step it falls back to one `rorx` (not three scalar shifts).
/// One loop is the exception: the RPF's jitter, where
/// the SLP vectoriser splits the step into 128-bit halves with a `rorx` and two extracts and
/// inserts per word; it draws its words by `Lanes::step::<true>`, with the state's
/// rotation by opaque amounts as well, which keeps that step in AVX2 registers. The
/// bits are the same either way (tested against the reference generator).
#[derive(Debug, Clone)]
pub struct Lanes {
    s: [[u64; LANES]; 4],
    /// `[23, 41, 45, 19]`: the left and right shifts of `rotl(x, 23)` and of `rotl(x, 45)`.
    rot: [u32; 4],
}

impl Lanes {
    /// Lane `j`'s state from the `j`-th of `LANES` words of `rng`, expanded by SplitMix64
    /// into its four state words (as `seed_from_u64` seeds xoshiro256++; the four outputs
    /// come from distinct counter values of a bijection, so they are never all zero).
    /// Draws exactly `LANES` words from `rng`. The lanes' streams start at independent
    /// random points of xoshiro256++'s period of 2^256 - 1: an overlap of the few thousand
    /// words a step draws has probability of order 2^-200.
    #[inline(always)]
    pub fn seed_from<R: RngCore + ?Sized>(rng: &mut R) -> Self {
        let mut s = [[0u64; LANES]; 4];
        for j in 0..LANES {
            let mut x = SplitMix64::seed_from_u64(rng.next_u64());
            for sk in s.iter_mut() {
                sk[j] = x.next_u64();
            }
        }
        Self {
            s,
            rot: std::hint::black_box([23, 41, 45, 19]),
        }
    }

    /// Sixteen uniforms in `[0, 1)` on the 2^-52 grid, value `4 t + j` from the `t`-th
    /// word of lane `j` (its top 52 bits as the mantissa of a number in `[1, 2)`, less 1:
    /// no integer-to-float conversion, so the loop vectorises).
    #[inline(always)]
    pub fn uniforms(&mut self, out: &mut [f64; 16]) {
        for o in out.chunks_exact_mut(LANES) {
            let w = self.next_words();
            for (v, w) in o.iter_mut().zip(w) {
                *v = f64::from_bits((w >> 12) | 0x3ff0_0000_0000_0000) - 1.0;
            }
        }
    }

    /// The next word of every lane (xoshiro256++: `rotl(s0 + s3, 23) + s0`, then the
    /// state transition), lane by lane in one loop that vectorises (the output's rotation
    /// by the opaque shifts `rot`, see the type's docs).
    #[inline(always)]
    pub fn next_words(&mut self) -> [u64; LANES] {
        self.step::<false>()
    }

    /// One step of the lanes: [`Lanes::next_words`]; with `SHIFTED` the same words with the
    /// state's rotation `rotl(s3, 45)` by opaque shifts too (see the type's docs: for a loop
    /// where the SLP vectoriser would split the step around a `rorx`).
    #[inline(always)]
    pub(crate) fn step<const SHIFTED: bool>(&mut self) -> [u64; LANES] {
        let [l23, r41, l45, r19] = self.rot;
        let [s0, s1, s2, s3] = &mut self.s;
        let mut r = [0u64; LANES];
        for j in 0..LANES {
            let a = s0[j].wrapping_add(s3[j]);
            r[j] = (a.wrapping_shl(l23) | a.wrapping_shr(r41)).wrapping_add(s0[j]);
            let t = s1[j] << 17;
            s2[j] ^= s0[j];
            s3[j] ^= s1[j];
            s1[j] ^= s2[j];
            s0[j] ^= s3[j];
            s2[j] ^= t;
            s3[j] = if SHIFTED {
                s3[j].wrapping_shl(l45) | s3[j].wrapping_shr(r19)
            } else {
                s3[j].rotate_left(45)
            };
        }
        r
    }
}

#[cfg(test)]
mod tests {
    use super::{pdf, Lanes, Ziggurat, LANES, LAYERS};
    use rand::SeedableRng;
    use rand_xoshiro::Xoshiro256PlusPlus;

    /// `int_a^b exp(-x^2/2) dx` by composite Simpson (smooth integrand: 1e-14 relative).
    fn integral(a: f64, b: f64) -> f64 {
        let n = 20_000;
        let h = (b - a) / n as f64;
        let mut s = pdf(a) + pdf(b);
        for k in 1..n {
            s += pdf(a + k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 };
        }
        s * h / 3.0
    }

    /// The standard normal CDF from the Taylor series of `erf` (|x| <= 6: absolute error
    /// below 1e-7, enough for a KS statistic of 1e6 draws).
    fn phi(x: f64) -> f64 {
        if x.abs() > 6.0 {
            return if x > 0.0 { 1.0 } else { 0.0 };
        }
        let t = x / core::f64::consts::SQRT_2;
        let (mut term, mut sum) = (t, t);
        for n in 1..400 {
            term *= -t * t / n as f64;
            let add = term / (2 * n + 1) as f64;
            sum += add;
            if add.abs() < 1e-18 {
                break;
            }
        }
        0.5 + sum / core::f64::consts::PI.sqrt()
    }

    #[test]
    fn every_layer_has_the_same_area() {
        let z = Ziggurat::get();
        // base layer: rectangle up to R plus the tail
        let tail = integral(Ziggurat::R, Ziggurat::R + 30.0);
        let base = Ziggurat::R * pdf(Ziggurat::R) + tail;
        assert!((base / Ziggurat::V - 1.0).abs() < 1e-9, "base {base}");
        assert!((z.x[0] * z.f[1] / Ziggurat::V - 1.0).abs() < 1e-14);
        for i in 1..LAYERS {
            let a = z.x[i] * (z.f[i + 1] - z.f[i]);
            assert!((a / Ziggurat::V - 1.0).abs() < 1e-8, "layer {i}: {a}");
            assert!(
                z.x[i + 1] < z.x[i] && z.f[i + 1] > z.f[i],
                "layer {i} order"
            );
            assert!((z.f[i] - pdf(z.x[i])).abs() < 1e-12, "layer {i} f");
        }
        // the recursion closes: the top layer ends at the mode
        let top = Ziggurat::V / z.x[LAYERS - 1] + z.f[LAYERS - 1];
        assert!((top - 1.0).abs() < 1e-9, "top {top}");
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
        assert!(s.iter().all(|x| x.is_finite()));
    }

    #[test]
    fn batches_are_standard_normal() {
        let z = Ziggurat::get();
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(11);
        let mut v = vec![0.0; 1_000_000];
        // uneven batch lengths: every path of `fill` (full words, short tails)
        let mut at = 0;
        for len in [1usize, 16, 64, 65, 96, 3].iter().cycle() {
            let end = (at + len).min(v.len());
            z.fill(&mut rng, &mut v[at..end]);
            at = end;
            if at == v.len() {
                break;
            }
        }
        check(&v);
    }

    #[test]
    fn single_draws_are_standard_normal() {
        let z = Ziggurat::get();
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(12);
        let v: Vec<f64> = (0..1_000_000).map(|_| z.sample(&mut rng)).collect();
        check(&v);
    }

    #[test]
    fn the_tail_and_wedges_are_exact() {
        // conditional on |x| > R the draws follow the normal tail: P(|X| > R + 0.5 | |X| > R)
        let z = Ziggurat::get();
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(13);
        let (mut beyond_r, mut beyond_r5) = (0u64, 0u64);
        let mut buf = [0.0; 64];
        for _ in 0..200_000 {
            z.fill(&mut rng, &mut buf);
            for x in buf {
                beyond_r += u64::from(x.abs() > Ziggurat::R);
                beyond_r5 += u64::from(x.abs() > Ziggurat::R + 0.5);
            }
        }
        let p = (1.0 - phi(Ziggurat::R + 0.5)) / (1.0 - phi(Ziggurat::R));
        let got = beyond_r5 as f64 / beyond_r as f64;
        let se = (p * (1.0 - p) / beyond_r as f64).sqrt();
        assert!((got - p).abs() < 5.0 * se, "tail ratio {got} vs {p}");
        let p_r = 2.0 * (1.0 - phi(Ziggurat::R));
        let n = 200_000.0 * 64.0;
        assert!(((beyond_r as f64 / n) - p_r).abs() < 5.0 * (p_r / n).sqrt());
        // a fine histogram over one wedge region (between X_2 and X_1 = R) against the density
        let (lo, hi) = (z.x[3], z.x[1]);
        let bins = 8;
        let mut h = [0u64; 8];
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(14);
        let total = 4_000_000usize;
        for _ in 0..total / 64 {
            z.fill(&mut rng, &mut buf);
            for x in buf {
                let a = x.abs();
                if a >= lo && a < hi {
                    let b = (((a - lo) / (hi - lo)) * bins as f64) as usize;
                    h[b.min(bins - 1)] += 1;
                }
            }
        }
        for (b, &c) in h.iter().enumerate() {
            let a0 = lo + (hi - lo) * b as f64 / bins as f64;
            let a1 = lo + (hi - lo) * (b + 1) as f64 / bins as f64;
            let p = 2.0 * (phi(a1) - phi(a0));
            let e = p * total as f64;
            assert!((c as f64 - e).abs() < 5.0 * e.sqrt(), "bin {b}: {c} vs {e}");
        }
    }

    /// Each lane is the reference xoshiro256++ stream of its SplitMix64-expanded seed.
    #[test]
    fn lanes_are_xoshiro_streams() {
        use rand::RngCore;
        let mut src = Xoshiro256PlusPlus::seed_from_u64(21);
        let mut probe = Xoshiro256PlusPlus::seed_from_u64(21);
        let words: Vec<u64> = (0..LANES).map(|_| probe.next_u64()).collect();
        let mut lanes = Lanes::seed_from(&mut src);
        assert_eq!(src, probe, "draws exactly LANES words");
        // rand_xoshiro's seed_from_u64 is the same SplitMix64 expansion
        let mut refs: Vec<Xoshiro256PlusPlus> = words
            .iter()
            .map(|&w| Xoshiro256PlusPlus::seed_from_u64(w))
            .collect();
        for t in 0..1000 {
            // both forms of the step, interleaved: the same state transition and words
            let got = if t % 3 == 0 {
                lanes.step::<true>()
            } else {
                lanes.next_words()
            };
            for (j, r) in refs.iter_mut().enumerate() {
                assert_eq!(got[j], r.next_u64());
            }
        }
    }

    /// The shifted batches are the plain batches, slow paths included (bit for bit).
    #[test]
    fn shifted_lane_batches_equal_the_plain_ones() {
        let z = Ziggurat::get();
        let (mut ra, mut rb) = (
            Xoshiro256PlusPlus::seed_from_u64(33),
            Xoshiro256PlusPlus::seed_from_u64(33),
        );
        let (mut la, mut lb) = (Lanes::seed_from(&mut ra), Lanes::seed_from(&mut rb));
        let (mut a, mut b) = ([0.0; Ziggurat::BATCH], [0.0; Ziggurat::BATCH]);
        for _ in 0..20_000 {
            z.fill_batch_lanes(&mut la, &mut ra, &mut a);
            z.fill_batch_lanes_with::<true, _>(&mut lb, &mut rb, &mut b);
            assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits));
        }
        assert_eq!(ra, rb, "the same slow-path words");
    }

    #[test]
    fn lane_batches_are_standard_normal() {
        let z = Ziggurat::get();
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(15);
        let mut v = vec![0.0; 1_000_000];
        for c in v.chunks_exact_mut(Ziggurat::BATCH * 100) {
            // fresh lanes every 100 batches, as a filter's step derives them
            let mut lanes = Lanes::seed_from(&mut rng);
            for b in c.chunks_exact_mut(Ziggurat::BATCH) {
                let b: &mut [f64; Ziggurat::BATCH] = b.try_into().expect("a batch");
                z.fill_batch_lanes(&mut lanes, &mut rng, b);
            }
        }
        check(&v);
        let p_r = 2.0 * (1.0 - phi(Ziggurat::R));
        let beyond = v.iter().filter(|x| x.abs() > Ziggurat::R).count() as f64 / v.len() as f64;
        assert!((beyond - p_r).abs() < 5.0 * (p_r / v.len() as f64).sqrt());
    }

    #[test]
    fn fill_is_deterministic_for_a_seed() {
        let z = Ziggurat::get();
        let mut a = [0.0; 96];
        let mut b = [0.0; 96];
        z.fill(&mut Xoshiro256PlusPlus::seed_from_u64(5), &mut a);
        z.fill(&mut Xoshiro256PlusPlus::seed_from_u64(5), &mut b);
        assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits));
    }
}
