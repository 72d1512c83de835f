//! The population the genetic operators work on ([`Pop`]: the filter's buffers, borrowed
//! apart) and the operators in blocks: the random pairing, the selection with the cloud
//! model's adaptive probabilities, the crossover of eight pairs and the mutation of sixteen
//! particles at a time in structure-of-arrays form ([`Block`]), each candidate accepted by
//! the Metropolis–Hastings test on the move target ([`Target`]).

use super::target::Target;
use super::B;
use crate::estimators::pf::likelihood::ParticleLikelihood;
use crate::estimators::pf::rng::PfRng;
use crate::numerics::vexp::exp_nonpos;
use crate::numerics::ziggurat::{Lanes, Ziggurat, LANES};
use crate::types::State;
use rand::RngCore;

/// Fitness `exp(d)` of a log-likelihood `d = l - best` relative to the generation's best:
/// [`exp_nonpos`] (within 2 ulp of `exp`, vectorisable) for `d <= 0`, `exp` above (a
/// candidate better than the generation's best has fitness above 1).
#[inline(always)]
pub(super) fn fitness(d: f64) -> f64 {
    if d <= 0.0 {
        exp_nonpos(d)
    } else {
        d.exp()
    }
}

/// A uniform integer in `0..n` (`n > 0`) by Lemire's multiply-and-reject ("Fast random
/// integer generation in an interval", ACM TOMACS 29(1), 2019): exact; the rejection
/// (and its one division) only when the low word falls below `n`, probability `n / 2^64`.
#[inline(always)]
fn below(rng: &mut PfRng, n: u64) -> u64 {
    let mut m = u128::from(rng.next_u64()) * u128::from(n);
    if (m as u64) < n {
        let t = n.wrapping_neg() % n;
        while (m as u64) < t {
            m = u128::from(rng.next_u64()) * u128::from(n);
        }
    }
    (m >> 64) as u64
}

/// A uniform in `[0, 1)` from a word's top 53 bits (rand's `random::<f64>()`).
#[inline(always)]
fn unit(w: u64) -> f64 {
    (w >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// Metropolis–Hastings acceptance of a log ratio `la` with the uniform `v` in the linear
/// domain: `v < e^la` (the same event as `ln v < la`, no logarithm); `la >= 0` (`+inf`
/// included) always, NaN and `-inf` never.
///
/// A squeeze decides most tests without the exponential: with `y = -la > 0`, Taylor's
/// theorem bounds `e^-y` by `1 - y + y^2/2 - y^3/6 <= e^-y <= 1 / (1 + y + y^2/2 + y^3/6)`
/// (the remainders `e^-xi y^4 / 24` and `e^xi y^4 / 24` are non-negative); `v` below the
/// lower bound accepts, at or above the upper rejects, and only between them is
/// [`exp_nonpos`] formed. The bounds are widened by `2^-40` relative (far above their
/// rounding and `exp_nonpos`' 2 ulp), so the decision is the exponential's, bit for bit.
#[inline(always)]
pub(super) fn accept_linear(v: f64, la: f64) -> bool {
    const WIDEN: f64 = 1.0 / (1u64 << 40) as f64;
    if la >= 0.0 {
        return true;
    }
    if !(la > f64::NEG_INFINITY) {
        return false;
    }
    let y = -la;
    let (y2, y3) = (y * y, y * y * y);
    let lo = 1.0 - y + 0.5 * y2 - y3 * (1.0 / 6.0);
    if v < lo * (1.0 - WIDEN) {
        return true;
    }
    // `v * den` is NaN only for `v = 0` with `den = inf`: falls through to the exponential
    let den = 1.0 + y + 0.5 * y2 + y3 * (1.0 / 6.0);
    if v * den >= 1.0 + WIDEN {
        return false;
    }
    v < exp_nonpos(la)
}

/// Adaptive probabilities from cloud drops for a block of fitnesses `f` with the drops'
/// standard normals `g`: `k exp(-(f - f_avg)^2 / (2 En'^2))`, `En' = En + He g`, for
/// `f >= f_avg` (`En = (f_max - f_avg) / c1`, `He = En / c2`), `k` below the average or when
/// `f_max <= f_avg`, 0 when `En' = 0` (paper 003; Dai, Zhu & Chen 2007). Branch-free over the
/// lanes.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn cloud_probabilities(
    f: &[f64; B],
    g: &[f64; B],
    f_avg: f64,
    f_max: f64,
    c1: f64,
    c2: f64,
    k: f64,
    out: &mut [f64; B],
) {
    let en = (f_max - f_avg) / c1;
    let he = en / c2;
    let flat = f_max <= f_avg;
    for ((o, &fi), &gi) in out.iter_mut().zip(f).zip(g) {
        let en1 = en + he * gi;
        let d = fi - f_avg;
        let p = k * exp_nonpos(-(d * d) / (2.0 * en1 * en1));
        let p = if en1 == 0.0 { 0.0 } else { p };
        *o = if fi < f_avg || flat { k } else { p };
    }
}

/// The population the operators work on (the filter's buffers, borrowed apart).
pub(super) struct Pop<'p> {
    pub(super) x: &'p mut [State],
    pub(super) loglik: &'p mut [f64],
    /// fitness of each particle, kept current within a generation (CGA-PF only)
    pub(super) fit: &'p mut [f64],
    /// indices selected for an operator
    pub(super) sel: &'p mut [usize],
    pub(super) perm: &'p mut [usize],
    pub(super) rng: &'p mut PfRng,
    /// four xoshiro256++ lanes seeded from `rng` for the call ([`Lanes::seed_from`]): the
    /// operators' uniforms, words and normals (transient, as the transition's)
    pub(super) lanes: Lanes,
    pub(super) tried: u64,
    pub(super) accepted: u64,
}

impl Pop<'_> {
    /// A uniformly random pairing of `perm`: pair `j` is `(perm[2j], perm[2j + 1])`,
    /// `j < n / 2`, and for odd `n` the one left out, `perm[n - 1]`, is uniform. From the
    /// end: (odd `n`) the left-out position gets a uniform one of all; then the element
    /// at the top of the unpaired part `perm[..k]` is paired with a uniform one of the
    /// other `k - 1`, `k` down by two: `(n - 1)!!` equally likely pairings from `n / 2`
    /// draws (the Fisher–Yates shuffle's `n - 1` draws ordered the pairs and their
    /// members as well, which the operators do not use: the pairs are disjoint, each has its
    /// own draws, and the crossover is symmetric in its two members).
    #[inline(always)]
    pub(super) fn shuffle(&mut self) {
        let n = self.perm.len();
        let mut k = n;
        if n % 2 == 1 {
            let j = below(self.rng, n as u64) as usize;
            self.perm.swap(n - 1, j);
            k = n - 1;
        }
        while k >= 2 {
            let j = below(self.rng, k as u64 - 1) as usize;
            self.perm.swap(k - 2, j);
            k -= 2;
        }
    }

    /// Fitness statistics `(best, min, mean, max)` of `f_i = exp(loglik_i - best)`, `best`
    /// the largest log-likelihood; fills `fit`.
    #[inline(always)]
    pub(super) fn fitness_stats(&mut self) -> (f64, f64, f64, f64) {
        let mut m = [f64::NEG_INFINITY; 4];
        let mut chunks = self.loglik.chunks_exact(4);
        for c in &mut chunks {
            for (mk, &v) in m.iter_mut().zip(c) {
                *mk = mk.max(v);
            }
        }
        let mut best = m[0].max(m[1]).max(m[2].max(m[3]));
        for &v in chunks.remainder() {
            best = best.max(v);
        }
        for (f, &l) in self.fit.iter_mut().zip(self.loglik.iter()) {
            *f = exp_nonpos(l - best);
        }
        let (mut lo, mut sum) = (f64::INFINITY, 0.0);
        for &f in self.fit.iter() {
            lo = lo.min(f);
            sum += f;
        }
        (best, lo, sum / self.fit.len() as f64, 1.0)
    }

    /// Crossover of the selected pairs `(a, b) = (perm[2j], perm[2j + 1])`, `j` in
    /// `sel[..count]`, as a reversible pair move: with the pair's mean `m` and
    /// half-difference `d`, the children are `a' = m + s d`, `b' = m - s d`, `s = ±exp(u)`,
    /// `u ~ U(-ln 2, ln 2)` (`s` in (0, 1): the arithmetic crossover `l a + (1 - l) b` with
    /// `l = (1 + s) / 2`; `|s| > 1`: its inverse, the pair spreading apart). Accepted
    /// jointly with probability `min(1, pi(a') pi(b') |s|^6 / (pi(a) pi(b)))`, `|s|^6` the
    /// Jacobian (Green 1995): an exact Metropolis–Hastings move that leaves `pi x pi`
    /// invariant.
    ///
    /// Eight pairs (sixteen candidates) per block; per pair one word gives `u` (top 53 bits)
    /// and the sign of `s` (bit 0), a second the acceptance uniform. The pairs are disjoint,
    /// so the blocks equal the pairs one at a time. With `best`, the accepted particles'
    /// fitness `exp(ll - best)` is updated.
    ///
    /// The predictive factor of the ratio needs neither a candidate's nor a parent's
    /// quadratic form: in whitened coordinates (`L-^-1 (x - m-)`, where the move is the same
    /// affine map) the children are `w_m ± s w_d`, so with `D = |L-^-1 d|^2` and
    /// `q = |w|^2 = -2 ln N` (up to the constant), `q(a') + q(b') = q(a) + q(b) +
    /// 2 (s^2 - 1) D` exactly: one forward substitution per pair (of `d`, eight lanes)
    /// instead of one per candidate and per parent. The log ratio is
    /// `(ln p(z | a') + ln p(z | b')) - (ln p(z | a) + ln p(z | b)) - (s^2 - 1) D + 6 u`.
    #[inline(always)]
    pub(super) fn crossover_block<const D: usize, L: ParticleLikelihood<D>>(
        &mut self,
        t: &Target<'_, L, D>,
        count: usize,
        best: Option<f64>,
    ) {
        const P: usize = B / 2;
        let ln2 = core::f64::consts::LN_2;
        let mut c = [[0.0; B]; 6];
        let mut dd = [[0.0; P]; 6];
        let mut scratch = [[0.0; P]; 6];
        let (mut ll, mut dq) = ([0.0; B], [0.0; P]);
        let mut start = 0;
        while start < count {
            let np = P.min(count - start);
            let mut ab = [(0usize, 0usize); P];
            for (p, abp) in ab.iter_mut().enumerate().take(np) {
                let j = self.sel[start + p];
                *abp = (self.perm[2 * j], self.perm[2 * j + 1]);
            }
            // eight words (`u` and the sign) and eight acceptance uniforms from the lanes
            let mut w = [0u64; P];
            for wc in w.chunks_exact_mut(LANES) {
                wc.copy_from_slice(&self.lanes.next_words());
            }
            let mut v2 = [0.0; B];
            self.lanes.uniforms(&mut v2);
            let mut u = [0.0; P];
            let mut neg = [false; P];
            let mut v = [0.0; P];
            for p in 0..P {
                u[p] = -ln2 + 2.0 * ln2 * unit(w[p]);
                neg[p] = w[p] & 1 == 1;
                v[p] = v2[p];
            }
            // s = ±e^u
            let mut s = [0.0; P];
            for p in 0..P {
                let e = exp_nonpos(-u[p].abs());
                let e = if u[p] <= 0.0 { e } else { 1.0 / e };
                s[p] = if neg[p] { -e } else { e };
            }
            // the pairs' members in the two halves, `a` in lane `p`, `b` in lane `P + p`:
            // the mixing runs on contiguous lanes
            let mut ll0 = [0.0; B];
            for (p, &(a, b)) in ab.iter().enumerate().take(np) {
                let (xa, xb) = (&self.x[a], &self.x[b]);
                for k in 0..6 {
                    c[k][p] = xa[k];
                    c[k][P + p] = xb[k];
                }
                (ll0[p], ll0[P + p]) = (self.loglik[a], self.loglik[b]);
            }
            // a short last block: the unused lanes repeat the first pair (defined positions,
            // no slow path in the likelihood; never read)
            for p in np..P {
                for ck in c.iter_mut() {
                    (ck[p], ck[P + p]) = (ck[0], ck[P]);
                }
            }
            for (ck, dk) in c.iter_mut().zip(dd.iter_mut()) {
                for p in 0..P {
                    let (xa, xb) = (ck[p], ck[P + p]);
                    let m = (xa + xb) * 0.5;
                    let d = (xa - xb) * 0.5;
                    dk[p] = d;
                    ck[p] = m + d * s[p];
                    ck[P + p] = m - d * s[p];
                }
            }
            t.log_likelihood(&c, B, &mut ll);
            // -D / 2 per pair
            t.log_predictive::<P, false>(&dd, &mut scratch, &mut dq);
            let mut la = [0.0; P];
            for p in 0..P {
                let e = s[p] * s[p] - 1.0;
                // (s^2 - 1) D / 2
                let h = -(e * dq[p]);
                let dl = (ll[p] + ll[P + p]) - (ll0[p] + ll0[P + p]);
                la[p] = (dl - 2.0 * h) + 6.0 * u[p];
            }
            for (p, &(a, b)) in ab.iter().enumerate().take(np) {
                if accept_linear(v[p], la[p]) {
                    for (lane, i) in [(p, a), (P + p, b)] {
                        self.x[i] = State::from_fn(|k, _| c[k][lane]);
                        self.loglik[i] = ll[lane];
                        if let Some(best) = best {
                            self.fit[i] = fitness(ll[lane] - best);
                        }
                    }
                    self.accepted += 1;
                }
            }
            self.tried += np as u64;
            start += np;
        }
    }

    /// Select items `0..n` for an operator: item `j` is kept when `u_j < p_j`, the uniforms
    /// drawn sixteen at a time in item order. Without `cloud`, `p_j = k`. With it, `p_j` is
    /// the cloud probability of the item's fitness (`fit` fills a block's, from the block's
    /// first item): its drop `En'` is drawn only where it can matter, `u_j < k` (every
    /// cloud probability is at most `k`) and `f_j >= f_avg` (below, `p_j = k`), from a pool
    /// of standard normals refilled sixteen at a time by [`Ziggurat::fill_batch_lanes`] — the same
    /// selection law as a drop for every item. Returns the count, the items in `sel`.
    #[inline(always)]
    pub(super) fn select(
        &mut self,
        n: usize,
        k: f64,
        cloud: Option<CloudDrop>,
        mut fit: impl FnMut(&Self, usize, &mut [f64; B]),
    ) -> usize {
        let z = Ziggurat::get();
        let mut pool = [0.0; B];
        let mut used = B;
        let mut f = [0.0; B];
        let mut g = [0.0; B];
        let mut p = [k; B];
        let mut count = 0;
        let mut start = 0;
        while start < n {
            let m = B.min(n - start);
            let mut u = [0.0; B];
            self.lanes.uniforms(&mut u);
            if let Some(cd) = cloud {
                fit(self, start, &mut f);
                let mut need = [false; B];
                for lane in 0..B {
                    need[lane] = u[lane] < k && f[lane] >= cd.f_avg && cd.f_max > cd.f_avg;
                }
                for lane in 0..m {
                    g[lane] = 0.0;
                    if need[lane] {
                        if used == B {
                            z.fill_batch_lanes(&mut self.lanes, self.rng, &mut pool);
                            used = 0;
                        }
                        g[lane] = pool[used];
                        used += 1;
                    }
                }
                cloud_probabilities(&f, &g, cd.f_avg, cd.f_max, cd.c1, cd.c2, k, &mut p);
            }
            // the kept lanes as a bit mask (one vector compare), then only those written
            let mut keep = 0u32;
            for lane in 0..B {
                keep |= u32::from(u[lane] < p[lane]) << lane;
            }
            keep &= u32::MAX >> (32 - m);
            while keep != 0 {
                self.sel[count] = start + keep.trailing_zeros() as usize;
                count += 1;
                keep &= keep - 1;
            }
            start += m;
        }
        count
    }
}

/// The population statistics and divisors of the adaptive probabilities' cloud drops.
#[derive(Debug, Clone, Copy)]
pub(super) struct CloudDrop {
    pub(super) f_avg: f64,
    pub(super) f_max: f64,
    pub(super) c1: f64,
    pub(super) c2: f64,
}

/// The lanes of a mutation block (see [`Pop::mutate_blocks`]).
pub(super) struct Block {
    /// lanes in use
    pub(super) n: usize,
    pub(super) idx: [usize; B],
    /// the particles, their fitness, log-likelihoods and log predictive densities (formed in
    /// the block)
    pub(super) x: [[f64; B]; 6],
    pub(super) f: [f64; B],
    pub(super) ll0: [f64; B],
    pub(super) lq0: [f64; B],
    /// six standard normals per lane (component-major)
    pub(super) eps: [[f64; B]; 6],
    /// a word per lane (the cloud mutation's signs) and the acceptance uniform
    pub(super) w: [u64; B],
    pub(super) v: [f64; B],
    /// the candidates, their log-likelihoods, log predictive and log target densities,
    /// and the log target ratio `la = (ll - ll0) + (lq - lq0)`
    pub(super) c: [[f64; B]; 6],
    pub(super) ll: [f64; B],
    pub(super) lq: [f64; B],
    pub(super) lp: [f64; B],
    pub(super) la: [f64; B],
    pub(super) acc: [bool; B],
    /// per-operator lane values (the cloud mutation's `ln mu` and reach)
    pub(super) aux: [f64; B],
    pub(super) reach: [f64; B],
}

impl Block {
    /// A block with `n` lanes in use, unit fitness and `aux`, `reach` in every lane (the
    /// rest zero).
    #[inline(always)]
    pub(super) fn new(n: usize, aux: f64, reach: f64) -> Self {
        Block {
            n,
            idx: [0; B],
            x: [[0.0; B]; 6],
            f: [1.0; B],
            ll0: [0.0; B],
            lq0: [0.0; B],
            eps: [[0.0; B]; 6],
            w: [0; B],
            v: [0.0; B],
            c: [[0.0; B]; 6],
            ll: [0.0; B],
            lq: [0.0; B],
            lp: [0.0; B],
            la: [0.0; B],
            acc: [false; B],
            aux: [aux; B],
            reach: [reach; B],
        }
    }
}

impl Pop<'_> {
    /// Mutation of the selected particles `sel[..count]`, sixteen per block: gathers the
    /// particles, draws from the lanes six batches of normals (component-major), sixteen
    /// words when `words` (the cloud mutation's signs) and sixteen acceptance uniforms,
    /// `make` forms the candidates `c`, the candidates' likelihood and the predictive
    /// density of the candidates and of the particles are evaluated (the log ratio
    /// `la = (ll - ll0) + (lq - lq0)`), `decide` sets `acc`, and the accepted candidates
    /// replace their particles.
    /// Particles are distinct, so the blocks equal the particles one at a time.
    #[inline(always)]
    pub(super) fn mutate_blocks<const D: usize, L: ParticleLikelihood<D>>(
        &mut self,
        t: &Target<'_, L, D>,
        count: usize,
        words: bool,
        mut make: impl FnMut(&mut Block),
        mut decide: impl FnMut(&mut Block),
    ) {
        let z = Ziggurat::get();
        let mut l = Block::new(0, -1.0, 1.0);
        let mut scratch = [[0.0; B]; 6];
        let mut start = 0;
        while start < count {
            let m = B.min(count - start);
            l.n = m;
            for lane in 0..m {
                let i = self.sel[start + lane];
                l.idx[lane] = i;
                for k in 0..6 {
                    l.x[k][lane] = self.x[i][k];
                }
                // the fitness only for the cloud mutation (the GA-PF's `fit` is unused)
                if words {
                    l.f[lane] = self.fit[i];
                }
                l.ll0[lane] = self.loglik[i];
            }
            for e in l.eps.iter_mut() {
                z.fill_batch_lanes(&mut self.lanes, self.rng, e);
            }
            if words {
                for wc in l.w.chunks_exact_mut(LANES) {
                    wc.copy_from_slice(&self.lanes.next_words());
                }
            }
            self.lanes.uniforms(&mut l.v);
            make(&mut l);
            t.log_likelihood(&l.c, m, &mut l.ll);
            t.log_predictive::<B, true>(&l.x, &mut scratch, &mut l.lq0);
            t.log_predictive::<B, true>(&l.c, &mut scratch, &mut l.lq);
            for lane in 0..B {
                l.lp[lane] = l.ll[lane] + l.lq[lane];
                l.la[lane] = (l.ll[lane] - l.ll0[lane]) + (l.lq[lane] - l.lq0[lane]);
            }
            decide(&mut l);
            for lane in 0..m {
                if l.acc[lane] {
                    let i = l.idx[lane];
                    self.x[i] = State::from_fn(|k, _| l.c[k][lane]);
                    self.loglik[i] = l.ll[lane];
                    self.accepted += 1;
                }
            }
            self.tried += m as u64;
            start += m;
        }
    }
}
