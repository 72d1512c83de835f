//! Weighted first and second moments of 6-vectors (particles), accumulated in one pass
//! about a reference point ([`Moments`]), and the accumulators that form them: in 16-lane
//! structure-of-arrays blocks ([`moments`], [`MomentLanes`]), particle by particle in
//! register chains ([`PointSums`]), from particles already transposed, four lanes per sum
//! ([`LaneSums`]), with weight one each ([`unit_moments`], [`unit_moments_soa`]); and the
//! weighted sum ([`weighted_sum`]). The order of each sum's additions is fixed by the
//! particle count, so every result is reproducible and the same bits on the dispatched
//! (AVX2) and the baseline path; the forms differ from one another at rounding level.

use super::lanes::{add4, mul4, L4};
use super::simd;
use super::soa::BLOCK;
use crate::types::{Mat6, State};

/// Components per particle.
const N: usize = 6;

/// Weighted first and second moments accumulated in one pass about a reference point
/// `c` near the cloud: `m = c + s1 / W`, `P = s2 / W - (m - c)(m - c)^T` with
/// `s1 = sum w_i d_i`, `s2 = sum w_i d_i d_i^T`, `d_i = x_i - c`, `W = sum w_i`. Shifting
/// to a point inside the cloud avoids the cancellation of the textbook one-pass formula.
/// Partial sums about the same reference [`Moments::merge`] exactly (the parallel path).
/// A variance that still rounds below zero is set to zero.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Moments {
    reference: State,
    pub(crate) s1: State,
    /// upper triangle of `s2`, column by column
    pub(crate) s2: [f64; 21],
    pub(crate) wsum: f64,
}

impl Moments {
    pub(crate) fn new(reference: State) -> Self {
        Self {
            reference,
            s1: State::zeros(),
            s2: [0.0; 21],
            wsum: 0.0,
        }
    }

    /// Add the sums of `other` (same reference).
    pub(crate) fn merge(&mut self, other: &Moments) {
        self.s1 += other.s1;
        self.wsum += other.wsum;
        for (a, b) in self.s2.iter_mut().zip(&other.s2) {
            *a += b;
        }
    }

    /// [`Moments::finish`] when the weights' sum is positive and every moment finite
    /// (else `None`: overflowing offsets, no weight).
    pub(crate) fn mean_cov(&self) -> Option<(State, Mat6)> {
        if !(self.wsum > 0.0) {
            return None;
        }
        let (m, p) = self.finish();
        let finite = crate::numerics::all_finite;
        (finite(m.as_slice()) && finite(p.as_slice())).then_some((m, p))
    }

    /// `(mean, covariance)`.
    pub(crate) fn finish(&self) -> (State, Mat6) {
        let md = self.s1 / self.wsum;
        let mut p = Mat6::zeros();
        let mut k = 0;
        for c in 0..N {
            for r in 0..=c {
                let mut v = self.s2.get(k).copied().unwrap_or(f64::NAN) / self.wsum - md[r] * md[c];
                if r == c && v < 0.0 {
                    // `s2/W >= md^2` in exact arithmetic (Cauchy-Schwarz); a collapsed cloud
                    // can round it to -1e-20, which would read as a failed filter (NaN
                    // sigma). NaN stays NaN.
                    v = 0.0;
                }
                p[(r, c)] = v;
                p[(c, r)] = v;
                k += 1;
            }
        }
        (self.reference + md, p)
    }
}

/// `(sum w_i x_i, sum w_i)`.
pub(crate) fn weighted_sum(x: &[State], w: &[f64]) -> (State, f64) {
    crate::numerics::simd::dispatch(
        #[inline(always)]
        || weighted_sum_inline(x, w),
    )
}

/// [`weighted_sum`]'s body, inlined into its [`crate::numerics::simd::dispatch`].
#[inline(always)]
fn weighted_sum_inline(x: &[State], w: &[f64]) -> (State, f64) {
    let mut m = State::zeros();
    let mut s = 0.0;
    for (xi, wi) in x.iter().zip(w) {
        m += xi * *wi;
        s += *wi;
    }
    (m, s)
}

/// The 21 `(row, column)` pairs of the upper triangle of a 6 x 6 matrix, column by
/// column (the order of [`Moments::s2`]).
const TRIANGLE: [(usize, usize); 21] = {
    let mut t = [(0, 0); 21];
    let (mut c, mut k) = (0, 0);
    while c < N {
        let mut r = 0;
        while r <= c {
            t[k] = (r, c);
            r += 1;
            k += 1;
        }
        c += 1;
    }
    t
};

/// [`Moments`] of `x` with weights `w` about `reference`, in structure-of-arrays blocks:
/// each block of [`BLOCK`] particles is transposed to `d[k][i] = x_i[k] - c[k]` on the
/// stack and every sum is accumulated in partial sums that vectorise (the weights and
/// first moments lane by lane, particle `i` of every block in lane `i`; each of the 21
/// second-moment entries in four interleaved register sums per block, particle `i` in
/// sum `i mod 4`), the lanes added in order at the end. Run through
/// [`crate::numerics::simd::dispatch`] (AVX2 where present, the same bits). A short
/// last block is padded with zero weight and zero offset, which add exact zeros. The order of the additions is fixed by the particle count, so
/// the result is reproducible; it differs from the one-particle-at-a-time sums
/// at rounding level.
#[allow(clippy::needless_range_loop)] // index loops over fixed lanes: they vectorise
pub(crate) fn moments(reference: &State, x: &[State], w: &[f64]) -> Moments {
    crate::numerics::simd::dispatch(
        #[inline(always)]
        || moments_inline(reference, x, w),
    )
}

/// [`moments`]' body, inlined into its [`crate::numerics::simd::dispatch`].
#[inline(always)]
#[allow(clippy::needless_range_loop)]
fn moments_inline(reference: &State, x: &[State], w: &[f64]) -> Moments {
    let mut lanes = MomentLanes::new();
    for (xs, wsl) in x.chunks(BLOCK).zip(w.chunks(BLOCK)) {
        lanes.add_block(reference, xs, wsl);
    }
    lanes.finish(reference)
}

/// The lane sums of [`moments`] (particle `i` of every block in lane `i`; see there),
/// accumulated block by block: for loops that meet the particles in blocks anyway (the
/// rejuvenation), inlined into their [`crate::numerics::simd::dispatch`].
pub(crate) struct MomentLanes {
    s1: [[f64; BLOCK]; N],
    /// each second-moment entry in four interleaved partial sums (particle `4 m + j` of
    /// every block in sum `j`; one AVX2 vector)
    s2: [[f64; 4]; 21],
    ws: [f64; BLOCK],
    /// a block's offsets, weighted offsets and weights (scratch, reused block to block)
    d: [[f64; BLOCK]; N],
    wd: [[f64; BLOCK]; N],
    wb: [f64; BLOCK],
}

impl MomentLanes {
    pub(crate) fn new() -> Self {
        Self {
            s1: [[0.0; BLOCK]; N],
            s2: [[0.0; 4]; 21],
            ws: [0.0; BLOCK],
            d: [[0.0; BLOCK]; N],
            wd: [[0.0; BLOCK]; N],
            wb: [0.0; BLOCK],
        }
    }

    /// Add a block of at most [`BLOCK`] particles `xs` with weights `wsl` (a short block is
    /// padded with zero weight and zero offset, which add exact zeros).
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // index loops over fixed lanes: they vectorise
    pub(crate) fn add_block(&mut self, reference: &State, xs: &[State], wsl: &[f64]) {
        let Self {
            s1,
            s2,
            ws,
            d,
            wd,
            wb,
        } = self;
        for i in 0..BLOCK {
            let (di, wi) = match (xs.get(i), wsl.get(i)) {
                (Some(xi), Some(wi)) => (xi - reference, *wi),
                _ => (State::zeros(), 0.0),
            };
            wb[i] = wi;
            for k in 0..N {
                d[k][i] = di[k];
            }
        }
        Self::accumulate(s1, s2, ws, wd, d, wb);
    }

    /// The sums of one transposed block (`wd`: scratch for the weighted offsets).
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // index loops over fixed lanes: they vectorise
    fn accumulate(
        s1: &mut [[f64; BLOCK]; N],
        s2: &mut [[f64; 4]; 21],
        ws: &mut [f64; BLOCK],
        wd: &mut [[f64; BLOCK]; N],
        d: &[[f64; BLOCK]; N],
        wb: &[f64; BLOCK],
    ) {
        for i in 0..BLOCK {
            ws[i] += wb[i];
        }
        for k in 0..N {
            for i in 0..BLOCK {
                wd[k][i] = d[k][i] * wb[i];
                s1[k][i] += wd[k][i];
            }
        }
        // per entry four partial sums over the block in registers (one AVX2 vector,
        // particles `4 m + j` in sum `j`), added to the entry's lanes 0..4
        for (acc, &(r, c)) in s2.iter_mut().zip(&TRIANGLE) {
            let mut a = [0.0; 4];
            for (dp, wp) in d[r].chunks_exact(4).zip(wd[c].chunks_exact(4)) {
                for j in 0..4 {
                    a[j] += dp[j] * wp[j];
                }
            }
            for j in 0..4 {
                acc[j] += a[j];
            }
        }
    }

    /// The lanes added in order: the [`Moments`] about `reference`.
    #[inline(always)]
    pub(crate) fn finish(&self, reference: &State) -> Moments {
        let mut out = Moments::new(*reference);
        for i in 0..BLOCK {
            out.wsum += self.ws[i];
            for k in 0..N {
                out.s1[k] += self.s1[k][i];
            }
        }
        for (o, s) in out.s2.iter_mut().zip(&self.s2) {
            for v in s {
                *o += v;
            }
        }
        out
    }
}

/// Weighted first and second moments accumulated particle by particle, each sum one chain in
/// particle order (the form that keeps the accumulators in registers: eight 4-wide and 2-wide
/// AVX2 vectors for the second moments, one 4-wide and one 2-wide for the first, a scalar for
/// the weights). With `d = x - c` split as `a = d[0..4]`, `b = d[4..6]` and `wd = w d`:
/// `top[c] += a wd_c` (rows 0..4 of every column: the upper triangle's entries in rows 0..4
/// and seven of the lower's, which are not read) and `bot[c - 4] += b wd_c` for `c = 4, 5`
/// (rows 4 and 5 of columns 4 and 5), `s1 += wd`, `ws += w`: 28 products for the 21 entries,
/// each `d_r (w d_c)` as in [`MomentLanes`]. Inlined into the caller's
/// [`simd::dispatch`]; the dispatched and the baseline path perform the same operations per
/// sum in the same order, so the same bits.
#[derive(Clone, Copy)]
pub(crate) struct PointSums {
    top: [[f64; 4]; N],
    bot: [[f64; 2]; 2],
    s1a: [f64; 4],
    s1b: [f64; 2],
    ws: f64,
}

impl PointSums {
    #[inline(always)]
    pub(crate) fn new() -> Self {
        Self {
            top: [[0.0; 4]; N],
            bot: [[0.0; 2]; 2],
            s1a: [0.0; 4],
            s1b: [0.0; 2],
            ws: 0.0,
        }
    }

    /// Add particle `x` with weight `w`, offsets about `c` (`rc`: its components).
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // fixed-length component loops: they vectorise
    pub(crate) fn add(&mut self, x: &State, rc: &[f64; N], w: f64) {
        let a = [x[0] - rc[0], x[1] - rc[1], x[2] - rc[2], x[3] - rc[3]];
        let b = [x[4] - rc[4], x[5] - rc[5]];
        let wa = [a[0] * w, a[1] * w, a[2] * w, a[3] * w];
        let wb = [b[0] * w, b[1] * w];
        self.ws += w;
        for k in 0..4 {
            self.s1a[k] += wa[k];
        }
        for k in 0..2 {
            self.s1b[k] += wb[k];
        }
        let wd = [wa[0], wa[1], wa[2], wa[3], wb[0], wb[1]];
        for c in 0..N {
            for k in 0..4 {
                self.top[c][k] += a[k] * wd[c];
            }
        }
        for c in 0..2 {
            for k in 0..2 {
                self.bot[c][k] += b[k] * wb[c];
            }
        }
    }

    /// The [`Moments`] about `reference`.
    #[inline(always)]
    pub(crate) fn finish(&self, reference: &State) -> Moments {
        let mut out = Moments::new(*reference);
        out.wsum = self.ws;
        out.s1 = State::new(
            self.s1a[0],
            self.s1a[1],
            self.s1a[2],
            self.s1a[3],
            self.s1b[0],
            self.s1b[1],
        );
        for (o, &(r, c)) in out.s2.iter_mut().zip(&TRIANGLE) {
            *o = if r < 4 {
                self.top[c][r]
            } else {
                self.bot[c - 4][r - 4]
            };
        }
        out
    }
}

/// All-one weights for [`LaneSums::add`] with `W = false` (never read).
const UNIT: [f64; BLOCK] = [1.0; BLOCK];

/// [`TRIANGLE`]'s index of the upper-triangle entry `(r, c)`, `r <= c`.
const fn tri(r: usize, c: usize) -> usize {
    c * (c + 1) / 2 + r
}

/// Weighted first and second moments of particles held transposed (blocks
/// `[[f64; BLOCK]; N]`, component-major: the filter's `soa`, the RPF jitter's moved block),
/// four particles at a time: particle `4 m + j` of the run in lane `j` of every sum (one
/// AVX2 vector per sum), the lanes added in order at the end ([`LaneSums::finish`]). The 21
/// upper-triangle entries and the six first moments (27 four-wide sums) do not fit in the 16
/// AVX2 registers beside their operands, so they are formed in three groups, each a loop
/// over the blocks whose sums stay in registers ([`LaneSums::pass`]): the triangle of rows
/// and columns 0..3 with the first moments 0..3, the triangle of 3..6 with the first moments
/// 3..6, and the cross block rows 0..3 x columns 3..6. Each entry is `sum d_r (w d_c)` as in
/// [`MomentLanes`]; with `W = false` every weight is one (`wd = d`, no products). Inlined
/// into the caller's [`simd::dispatch`]; both paths perform the same operations in the same
/// order per lane, so the same bits. The order of the additions is fixed by the particle
/// count: reproducible, and at rounding level from [`PointSums`]' one chain per sum.
#[derive(Clone, Copy)]
pub(crate) struct LaneSums {
    s1: [L4; N],
    /// the upper triangle, in [`TRIANGLE`]'s order
    s2: [L4; 21],
}

impl LaneSums {
    #[inline(always)]
    fn new() -> Self {
        Self {
            s1: [[0.0; 4]; N],
            s2: [[0.0; 4]; 21],
        }
    }

    /// The sums of the first `n` particles of `soa` about `reference` (at least `n`
    /// particles), with the weights `w` (`n` of them) when `W`, else weight one each. A
    /// short last block is copied with its padding set to `reference` (offset zero) and
    /// weight zero.
    #[inline(always)]
    pub(crate) fn of_soa<const W: bool>(
        reference: &State,
        soa: &[[[f64; BLOCK]; N]],
        n: usize,
        w: &[f64],
    ) -> Self {
        // `x + nc` with `nc` opaque: LLVM would turn `x + (-c)` back into `x - c`, whose
        // loaded operand `x` cannot be folded into the instruction (one load more per
        // component and four particles)
        let nc: [f64; N] = std::hint::black_box(core::array::from_fn(|k| -reference[k]));
        let full = n / BLOCK;
        let rem = n - full * BLOCK;
        let mut acc = Self::new();
        let wf = w.get(..full * BLOCK).unwrap_or_default();
        acc.add::<W>(soa.get(..full).unwrap_or_default(), wf, &nc);
        if let (true, Some(last)) = (rem > 0, soa.get(full)) {
            let mut tb = *last;
            for (k, c) in tb.iter_mut().enumerate() {
                c[rem..].fill(reference[k]);
            }
            let mut tw = [0.0; BLOCK];
            if let Some(wt) = w.get(full * BLOCK..n) {
                tw[..rem].copy_from_slice(wt);
            }
            acc.add::<W>(std::slice::from_ref(&tb), &tw, &nc);
        }
        acc
    }

    /// Add `blocks` with the weights `w` (`BLOCK` per block; with `W = false` every
    /// weight is one and `w` is not read), the offsets `d_k = x_k + nc_k`
    /// (`nc = -reference`: the same bits as `x_k - reference_k`). Each group is one loop
    /// over the blocks with its sums in registers. Padding lanes must add zero (zero
    /// offset, or zero weight and a finite offset).
    #[inline(always)]
    fn add<const W: bool>(&mut self, blocks: &[[[f64; BLOCK]; N]], w: &[f64], nc: &[f64; N]) {
        self.pass::<0, 0, W>(blocks, w, nc);
        self.pass::<3, 3, W>(blocks, w, nc);
        self.pass::<0, 3, W>(blocks, w, nc);
    }

    /// One group's pass over `blocks` with its sums in registers, added to the sums at
    /// the end.
    #[inline(always)]
    fn pass<const R: usize, const C: usize, const W: bool>(
        &mut self,
        blocks: &[[[f64; BLOCK]; N]],
        w: &[f64],
        nc: &[f64; N],
    ) {
        let mut a = [[[0.0; 4]; 3]; 3];
        let mut s = [[0.0; 4]; 3];
        if W {
            for (blk, wb) in blocks.iter().zip(w.chunks_exact(BLOCK)) {
                if let Ok(wb) = <&[f64; BLOCK]>::try_from(wb) {
                    Self::quarters::<R, C, true>(&mut a, &mut s, blk, wb, nc);
                }
            }
        } else {
            for blk in blocks {
                Self::quarters::<R, C, false>(&mut a, &mut s, blk, &UNIT, nc);
            }
        }
        let (mut a0, mut s0) = ([[[0.0; 4]; 3]; 3], [[0.0; 4]; 3]);
        self.load(R, C, &mut a0, &mut s0);
        for (x, y) in a0.iter_mut().flatten().zip(a.iter().flatten()) {
            *x = add4(*x, *y);
        }
        for (x, y) in s0.iter_mut().zip(&s) {
            *x = add4(*x, *y);
        }
        self.store(R, C, &a0, &s0);
    }

    /// The group `(r, c)`'s sums from `self` (entries outside the triangle: zero).
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // the group's entries by row and column
    fn load(&self, r0: usize, c0: usize, a: &mut [[L4; 3]; 3], s: &mut [L4; 3]) {
        for r in 0..3 {
            for c in 0..3 {
                if r0 != c0 || r <= c {
                    a[r][c] = self.s2[tri(r0 + r, c0 + c)];
                }
            }
        }
        if let (true, Some(s1)) = (r0 == c0, self.s1.get(c0..c0 + 3)) {
            s.copy_from_slice(s1);
        }
    }

    /// The group `(r, c)`'s sums into `self`.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // the group's entries by row and column
    fn store(&mut self, r0: usize, c0: usize, a: &[[L4; 3]; 3], s: &[L4; 3]) {
        for r in 0..3 {
            for c in 0..3 {
                if r0 != c0 || r <= c {
                    self.s2[tri(r0 + r, c0 + c)] = a[r][c];
                }
            }
        }
        if let (true, Some(s1)) = (r0 == c0, self.s1.get_mut(c0..c0 + 3)) {
            s1.copy_from_slice(s);
        }
    }

    /// One block's four quarters into the group sums `a` (rows `R..R + 3` by columns
    /// `C..C + 3`; `R == C`: the upper triangle, and the columns' first moments into `s`);
    /// weights `wb` when `W` (else one), offsets `x + nc`.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // fixed-length lane loops: they vectorise
    fn quarters<const R: usize, const C: usize, const W: bool>(
        a: &mut [[L4; 3]; 3],
        s: &mut [L4; 3],
        blk: &[[f64; BLOCK]; N],
        wb: &[f64; BLOCK],
        nc: &[f64; N],
    ) {
        let diag = R == C;
        for t in 0..BLOCK / 4 {
            let o = 4 * t;
            let quarter = |k: usize| -> L4 {
                let v: L4 = core::array::from_fn(|j| blk[k][o + j]);
                add4(v, [nc[k]; 4])
            };
            let wq: L4 = core::array::from_fn(|j| wb[o + j]);
            let dr: [L4; 3] = [quarter(R), quarter(R + 1), quarter(R + 2)];
            for c in 0..3 {
                let dc = if diag { dr[c] } else { quarter(C + c) };
                let wd = if W { mul4(wq, dc) } else { dc };
                if diag {
                    s[c] = add4(s[c], wd);
                }
                for r in 0..3 {
                    if !diag || r <= c {
                        a[r][c] = add4(a[r][c], mul4(dr[r], wd));
                    }
                }
            }
        }
    }

    /// The lanes added in order: the [`Moments`] about `reference` with the weights' sum
    /// `wsum`.
    #[inline(always)]
    pub(crate) fn finish(&self, reference: &State, wsum: f64) -> Moments {
        // the sums through memory: else LLVM sees the lane additions below as the sums'
        // uses and its SLP vectoriser packs the loops across entries instead of lanes
        // (scalar arithmetic with shuffles, far slower)
        let sums = std::hint::black_box(self);
        let lanes = |v: &L4| v[0] + v[1] + v[2] + v[3];
        let mut out = Moments::new(*reference);
        out.wsum = wsum;
        for (o, v) in out.s1.iter_mut().zip(&sums.s1) {
            *o = lanes(v);
        }
        for (o, v) in out.s2.iter_mut().zip(&sums.s2) {
            *o = lanes(v);
        }
        out
    }
}

/// [`Moments`] of equally weighted particles (weight 1 each) about `r` in one pass,
/// particle by particle: the offsets `d = x_i - r`, their sum and the full outer products
/// `d d^T` (six columns of six, the form that vectorises within a particle: the sums stay
/// in registers, no transposition), the upper triangle kept. The literal GA-PF's summary of
/// the moved population on the parallel path (the serial filter transposes the population
/// into `soa` and sums its lanes: [`unit_moments_soa`]): its mean and covariance in
/// one pass, without the weight products of the weighted [`moments`] and without
/// its separate mean pass. Run through
/// [`simd::dispatch`] (AVX2 where present; each sum is one chain in particle order on either
/// path, so the same bits); it differs from the weighted pass at rounding level.
// index loops over fixed rows and columns: they vectorise
#[allow(clippy::needless_range_loop)]
pub(crate) fn unit_moments(x: &[State], r: &State) -> Moments {
    simd::dispatch(
        #[inline(always)]
        || {
            let rr: [f64; 6] = core::array::from_fn(|k| r[k]);
            let mut s1 = [0.0; 6];
            let mut s2 = [[0.0; 6]; 6];
            for xi in x {
                let d: [f64; 6] = core::array::from_fn(|k| xi[k] - rr[k]);
                for k in 0..6 {
                    s1[k] += d[k];
                }
                for c in 0..6 {
                    for k in 0..6 {
                        s2[c][k] += d[k] * d[c];
                    }
                }
            }
            let mut out = Moments::new(*r);
            out.wsum = x.len() as f64;
            out.s1 = State::from_fn(|k, _| s1[k]);
            for (o, &(r, c)) in out.s2.iter_mut().zip(&TRIANGLE) {
                *o = s2[c][r];
            }
            out
        },
    )
}

/// [`Moments`] of the first `n` particles of `soa` (transposed, at least `n`) with weight one
/// each (the weight sum the count) about `reference`, from the lanes ([`LaneSums`]). Run
/// through [`simd::dispatch`].
pub(crate) fn unit_moments_soa(reference: &State, soa: &[[[f64; BLOCK]; N]], n: usize) -> Moments {
    simd::dispatch(
        #[inline(always)]
        || LaneSums::of_soa::<false>(reference, soa, n, &[]).finish(reference, n as f64),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::numerics::soa::transpose_into;
    use rand::SeedableRng;

    /// Merged partial moments equal the one-pass moments of the whole set.
    #[test]
    fn merged_moments_equal_one_pass() {
        let x: Vec<State> = (0..1000)
            .map(|k| State::from_fn(|i, _| ((i * 13 + k * 7) as f64).sin() * (i + 1) as f64))
            .collect();
        let w: Vec<f64> = (0..1000).map(|k| 1.0 + (k as f64).cos()).collect();
        let c = State::from_element(0.1);
        let (m1, p1) = moments(&c, &x, &w).finish();
        let mut acc = Moments::new(c);
        for (xs, ws) in x.chunks(64).zip(w.chunks(64)) {
            acc.merge(&moments(&c, xs, ws));
        }
        let (m2, p2) = acc.finish();
        assert!((m1 - m2).abs().max() < 1e-12 && (p1 - p2).abs().max() < 1e-12);
    }

    /// `unit_moments` gives the same bits on the dispatched and the baseline path, and the
    /// weighted pass's mean and covariance (weights `1/n`) to rounding level, for a short
    /// last block and a cloud far from the reference.
    #[test]
    fn unit_moments_agree_with_the_weighted_pass() {
        use rand::Rng;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        for n in [1, 7, 16, 1500] {
            let x: Vec<State> = (0..n)
                .map(|_| {
                    State::from_fn(|k, _| 1e3 * (k as f64 + 1.0) + rng.random_range(-50.0..50.0))
                })
                .collect();
            let r = State::from_element(900.0);
            let fast = unit_moments(&x, &r).finish();
            let base = simd::with_baseline(|| unit_moments(&x, &r)).finish();
            assert!(fast
                .0
                .iter()
                .zip(base.0.iter())
                .all(|(a, b)| a.to_bits() == b.to_bits()));
            assert!(fast
                .1
                .iter()
                .zip(base.1.iter())
                .all(|(a, b)| a.to_bits() == b.to_bits()));
            let w = vec![1.0 / n as f64; n];
            let (m, p) = moments(&r, &x, &w).finish();
            assert!((fast.0 - m).amax() <= 1e-9 * m.amax(), "{n}: mean");
            assert!(
                (fast.1 - p).amax() <= 1e-9 * (1.0 + p.amax()),
                "{n}: covariance"
            );
            // the lane sums from the transposed copy (the serial filter's form; the short
            // last block's padding holds garbage): the same bits on both paths, the same
            // moments to rounding level
            let mut soa = vec![[[f64::NAN; BLOCK]; 6]; n.div_ceil(BLOCK)];
            transpose_into(&x, &mut soa);
            let lanes = unit_moments_soa(&r, &soa, n).finish();
            let lanes_base = simd::with_baseline(|| unit_moments_soa(&r, &soa, n)).finish();
            assert!(
                lanes.0 == lanes_base.0 && lanes.1 == lanes_base.1,
                "{n}: bits"
            );
            assert!((lanes.0 - m).amax() <= 1e-9 * m.amax(), "{n}: lane mean");
            assert!(
                (lanes.1 - p).amax() <= 1e-9 * (1.0 + p.amax()),
                "{n}: lane covariance"
            );
        }
    }
}
