//! Genetic move steps after resampling: the GA-PF and the cloud-genetic resampling of
//! paper 003 (CGA-PF).
//!
//! Both run on the resampled, equally weighted population and leave the weights at
//! `1/N`. The **fitness** of a particle is its measurement likelihood `f_i = p(z | x_i)`
//! (normalised by the best, so `f_i` lies in (0, 1]). Every candidate that an operator
//! produces is accepted by a **Metropolis–Hastings** test on the filtering posterior
//! `pi(x) = p(z | x) N(x; m-, P-)`, the predictive density approximated by the Gaussian
//! of the predicted particles (before the prior's first update: the Gaussian prior itself):
//! accepted with probability `min(1, pi(x') / pi(x_i))`.
//!
//! Why not the exact resample-move target `p(z | x) p(x | ancestor)`: conditional on its
//! ancestor a particle's velocity is pinned to the process noise (paper 000: 1e-3 m/s
//! per step), so every useful move is rejected and the population keeps the velocity
//! draws it started with — the impoverishment the moves are there to cure (measured:
//! GA-PF 51 m off on paper 000 with that target). The Gaussian predictive is the same
//! kind of approximation as the RPF's kernel density. Paper 003's test on the likelihood
//! ratio alone is this test with a flat predictive: it would pull the population onto the
//! likelihood's peak against the dynamics.
//! Every move is an exact Metropolis–Hastings move for `pi`: the GA-PF mutation is a
//! symmetric random walk; the crossover is made reversible (a pair move with its Jacobian,
//! see `crossover`); the cloud mutation, whose step length depends on the current
//! particle's fitness, carries the Hastings correction for the reverse step. (The heuristic
//! acceptance of the GA-PF literature — the arithmetic crossover `l a + (1 - l) b`,
//! `l ~ U(0, 1)`, accepted on the target ratio alone — contracts the population: measured
//! on paper 003, NEES 106-178 against 6 and RMSE 20 m against the SIR's 16 m.) The
//! fitness-adaptive crossover and mutation probabilities (and the population statistics
//! they use, fixed within a generation) are the one approximation left.
//!
//! **GA-PF** ([`GeneticParams`]): the particles are paired at random (Fisher–Yates
//! shuffle); with probability `p_c` a pair `(a, b)` is replaced by its crossover
//! (`a' = l a + (1 - l) b`, `b' = l b + (1 - l) a`, generalised to a reversible move, see
//! `crossover`); then each
//! particle mutates with probability `p_m` by `x' = x + s h D eps`, `D D^T` the weighted
//! covariance before resampling, `h` the Gaussian kernel's optimal bandwidth, `s` the
//! `mutation_scale`.
//!
//! **Cloud-genetic resampling** ([`CloudParams`], paper 003). The normal cloud model
//! `(Ex, En, He)` generates a drop by `En' ~ N(En, He^2)`, `x ~ N(Ex, En'^2)`, with
//! certainty `mu = exp(-(x - Ex)^2 / (2 En'^2))`. The paper's formulas for the adaptive
//! probabilities were lost in the text; we take the standard published forms of the
//! cloud-model adaptive GA (Dai, Zhu & Chen 2007, "Adaptive genetic algorithm based on
//! cloud theory", Control Theory & Applications 24(4)):
//! * crossover of a pair whose better fitness is `f'`: if `f' >= f_avg`,
//!   `Ex = f_avg, En = (f_max - f_avg) / c1, He = En / c2`,
//!   `p_c = k_c exp(-(f' - Ex)^2 / (2 En'^2))`; otherwise `p_c = k_c`. Good pairs are
//!   protected, poor ones always recombine;
//! * mutation probability of particle `i`: the same form with `f_i` and `k_m`;
//! * cloud mutation (paper 003): `Ex` = the particle, `En_j = range_j / c3` with `range_j`
//!   the population's extent in component `j`, `He_j = En_j / c4` (`c3` in 3..6, `c4` in
//!   3..5); the certainty is mapped linearly from fitness,
//!   `mu_i = mu_min + (mu_max - mu_min) (f_i - f_min) / (f_max - f_min)`
//!   (`mu_min = 0.2`, `mu_max = 0.95`), and the drop is placed at that certainty,
//!   `x'_j = x_j ± |En'_j| sqrt(-2 ln mu_i)` (the "Y-condition" cloud generator): fit
//!   particles take short steps, poor ones long steps;
//! * "iterate while tightening": `generations` rounds, round `g` using `c3 (g + 1)`.
//!
//! **Implementation (issue 15).** Within a generation the operators act on disjoint pairs
//! (crossover) and on distinct particles (mutation), with the population statistics fixed,
//! so they run in blocks without changing the algorithm: the selection draws (the cloud
//! drops' normals by [`Ziggurat::fill_batch`], sixteen at a time, then sixteen uniforms) and
//! the adaptive probabilities for sixteen items at once; the selected pairs' candidates
//! (eight pairs, sixteen lanes) and the selected particles' mutations (sixteen lanes, six
//! batches of normals, component-major) in structure-of-arrays form; their likelihood by
//! [`MeasurementModel::residuals_at`] and the predictive density by forward substitution
//! across the lanes; all inside [`simd::dispatch`] (the same bits on the AVX2 and the
//! baseline path, tested). The Metropolis–Hastings test compares the uniform in the linear
//! domain, `v < e^la` ([`exp_nonpos`]; the same event as `ln v < la`), and the cloud
//! mutation's Hastings ratio is formed without a logarithm per component (see
//! `hastings_cloud`). Fitness `exp(l - best)` is [`exp_nonpos`] (within 2 ulp of `exp`).
//! The random stream is the blocks' order (documented at `ParticleFilter::genetic_moves`
//! and `ParticleFilter::cloud_moves`); it changed with this batching (the selection
//! uniforms of a block come first, the cloud drops after them from a pool of batched
//! normals and only where they can matter; the acceptance uniforms come with the blocks;
//! the shuffle is Lemire's exact bounded integer, not rand's `random_range`). It changed
//! again (branch `perf-gapf6`): the uniforms, the words and the mutations' normals come from
//! four xoshiro256++ lanes ([`Lanes`], seeded from the filter's generator at the start of
//! each call, transient like the transition's, so the saved state is unchanged), the
//! normals by [`Ziggurat::fill_batch_lanes`]; the GA-PF mutation no longer draws the
//! unused sign word; the pairing draws `n / 2` indices instead of a full shuffle's `n - 1`
//! (see `Pop::shuffle`). The laws are the same. Since `perf-gapf7` the literal GA-PF
//! summarises the moved population itself (mean and covariance in one
//! unweighted pass, instead of the filter's weighted mean pass and the next prediction's
//! weighted moments pass); the random stream is unchanged, the particles move from before
//! only by that summary's rounding (the next step's predictive Gaussian). Since `perf-gapf8`
//! the crossover forms the pair's predictive factor from the whitened half-difference alone
//! (one forward substitution per pair; see `Pop::crossover_block`), so no pass over the
//! population forms every particle's target first: a particle's predictive density
//! `ln N(x; m-, P-)` is formed only in a mutation block (beside its candidate's), and the
//! log ratios are `(ll' - ll) + (lq' - lq)`; the test `v < e^la` is decided by a Taylor
//! squeeze where it can be (`accept_linear`, the same decisions). The random stream is
//! unchanged; the log ratios are summed in another order, so the particles move from before
//! at rounding level.

pub use super::params::{CloudParams, GeneticParams};

use super::likelihood::Likelihood;
use super::params::{bandwidth, Kernel};
use super::rng::PfRng;
use super::ParticleFilter;
use crate::numerics::eigen::psd_sqrt;
use crate::numerics::moments::unit_moments;
use crate::numerics::moments::unit_moments_soa;
use crate::numerics::simd;
use crate::numerics::soa::{transpose_into, BLOCK};
use crate::numerics::vexp::exp_nonpos;
use crate::numerics::ziggurat::{Lanes, Ziggurat, LANES};
use crate::sensors::MeasurementModel;
use crate::types::{Mat6, State};
use rand::RngCore;
use std::cell::OnceCell;

/// Lanes of a candidate block (one [`Ziggurat::fill_batch_lanes`] per component).
const B: usize = BLOCK;

/// Fitness `exp(d)` of a log-likelihood `d = l - best` relative to the generation's best:
/// [`exp_nonpos`] (within 2 ulp of `exp`, vectorisable) for `d <= 0`, `exp` above (a
/// candidate better than the generation's best has fitness above 1).
#[inline(always)]
fn fitness(d: f64) -> f64 {
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
fn accept_linear(v: f64, la: f64) -> bool {
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

/// The move steps' target `ln pi(x) = ln p(z | x) + ln N(x; m-, P-)` on blocks of
/// candidates in structure-of-arrays form (`c[k][lane]`): the likelihood through
/// [`MeasurementModel::residuals_at`], the predictive's quadratic form by forward
/// substitution with `L-`'s reciprocal diagonal.
struct Target<'a, 'b, M> {
    lik: &'a Likelihood<'b, M>,
    m: [f64; 6],
    l: [[f64; 6]; 6],
    inv_diag: [f64; 6],
}

impl<'a, 'b, M: MeasurementModel> Target<'a, 'b, M> {
    fn new(lik: &'a Likelihood<'b, M>, m: &State, l: &Mat6) -> Self {
        Self {
            lik,
            m: std::array::from_fn(|k| m[k]),
            l: std::array::from_fn(|i| std::array::from_fn(|j| l[(i, j)])),
            inv_diag: std::array::from_fn(|k| 1.0 / l[(k, k)]),
        }
    }

    /// `ln N(c; m-, P-)` up to a constant, `-|L-^-1 (c - m-)|^2 / 2`, for every lane
    /// (`CENTRE`; without it `-|L-^-1 c|^2 / 2`, the form of a difference of two states).
    // lane-indexed loops over several arrays: the form that vectorises across lanes
    #[allow(clippy::needless_range_loop)]
    #[inline(always)]
    /// `u` is scratch (the whitened offsets; the caller's, so that a block does not zero
    /// it).
    fn log_predictive<const L: usize, const CENTRE: bool>(
        &self,
        c: &[[f64; L]; 6],
        u: &mut [[f64; L]; 6],
        out: &mut [f64; L],
    ) {
        for i in 0..6 {
            let mut s = [0.0; L];
            for lane in 0..L {
                s[lane] = if CENTRE {
                    c[i][lane] - self.m[i]
                } else {
                    c[i][lane]
                };
            }
            for j in 0..i {
                let lij = self.l[i][j];
                for lane in 0..L {
                    s[lane] -= lij * u[j][lane];
                }
            }
            for lane in 0..L {
                u[i][lane] = s[lane] * self.inv_diag[i];
            }
        }
        let mut q = [0.0; L];
        for ui in u.iter() {
            for lane in 0..L {
                q[lane] += ui[lane] * ui[lane];
            }
        }
        for (o, &qi) in out.iter_mut().zip(&q) {
            *o = -0.5 * qi;
        }
    }

    /// `ln p(z | c)` into `ll` for the first `n` lanes (the others unspecified): `-inf`
    /// where the measurement is undefined.
    #[inline(always)]
    fn log_likelihood(&self, c: &[[f64; B]; 6], n: usize, ll: &mut [f64; B]) {
        let r = [c[0], c[1], c[2]];
        let mut d = [[0.0; B]; 3];
        let mut ok = [false; B];
        let lik = self.lik;
        lik.sensor
            .residuals_at(&lik.z, &lik.trig, &r, n, &mut d, &mut ok);
        if lik.gaussian {
            let w = &lik.neg_half_inv_var;
            for (i, l) in ll.iter_mut().enumerate() {
                let v = w[0] * d[0][i] * d[0][i] + w[1] * d[1][i] * d[1][i];
                let v = v + w[2] * d[2][i] * d[2][i];
                *l = if ok[i] { v } else { f64::NEG_INFINITY };
            }
        } else {
            for (i, l) in ll.iter_mut().enumerate().take(n) {
                *l = if ok[i] {
                    (0..3)
                        .map(|k| lik.noise.log_density(d[k][i], lik.scales[k]))
                        .sum()
                } else {
                    f64::NEG_INFINITY
                };
            }
        }
    }
}

/// The population the operators work on (the filter's buffers, borrowed apart).
struct Pop<'p> {
    x: &'p mut [State],
    loglik: &'p mut [f64],
    /// fitness of each particle, kept current within a generation (CGA-PF only)
    fit: &'p mut [f64],
    /// indices selected for an operator
    sel: &'p mut [usize],
    perm: &'p mut [usize],
    rng: &'p mut PfRng,
    /// four xoshiro256++ lanes seeded from `rng` for the call ([`Lanes::seed_from`]): the
    /// operators' uniforms, words and normals (transient, as the transition's)
    lanes: Lanes,
    tried: u64,
    accepted: u64,
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
    fn shuffle(&mut self) {
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
    fn fitness_stats(&mut self) -> (f64, f64, f64, f64) {
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
    fn crossover_block<M: MeasurementModel>(
        &mut self,
        t: &Target<'_, '_, M>,
        count: usize,
        best: Option<f64>,
    ) {
        const P: usize = B / 2;
        let ln2 = std::f64::consts::LN_2;
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
    fn select(
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
struct CloudDrop {
    f_avg: f64,
    f_max: f64,
    c1: f64,
    c2: f64,
}

impl ParticleFilter {
    /// The population view and the target of the move steps.
    fn pop(&mut self) -> Pop<'_> {
        Pop {
            x: &mut self.x,
            loglik: &mut self.loglik,
            fit: &mut self.scratch,
            sel: &mut self.idx,
            perm: &mut self.perm,
            lanes: Lanes::seed_from(&mut self.rng),
            rng: &mut self.rng,
            tried: 0,
            accepted: 0,
        }
    }

    /// GA-PF move step after resampling (see the module documentation). The random
    /// stream (since `perf-gapf6`): four words of the filter's generator seed the lanes
    /// ([`Lanes::seed_from`]); the pairing's `n / 2` indices from the generator
    /// (`Pop::shuffle`); from the lanes: the pairs' crossover uniforms (sixteen per block);
    /// per block of eight selected pairs eight words (`u` and the sign), then sixteen
    /// uniforms (the first eight the acceptance uniforms); the mutation uniforms; per block
    /// of sixteen mutated particles six batches of normals (component-major;
    /// [`Ziggurat::fill_batch_lanes`], the rare slow paths from the generator), then sixteen
    /// acceptance uniforms.
    // lane-indexed loops over several arrays: the form that vectorises across lanes
    #[allow(clippy::needless_range_loop)]
    ///
    /// The literal GA-PF (`moves` off) sets the filter's mean and covariance from the moved
    /// population in one pass and returns true (the summary is set); with `moves`, false
    /// (the rejuvenation sets it). Serially the population is transposed into `soa` (marked
    /// current: the next transition reads it there) and summed in lanes
    /// ([`unit_moments_soa`]); in chunks particle by particle (`unit_moments`).
    pub(super) fn genetic_moves<M: MeasurementModel>(
        &mut self,
        lik: &Likelihood<'_, M>,
        cov_before: &Mat6,
    ) -> bool {
        let g = self.params.genetic;
        let n = self.x.len();
        let t = Target::new(lik, &self.pred_mean, &self.pred_l);
        // `D` any square root of the covariance (the step's law is N(0, h^2 s^2 D D^T)):
        // the Cholesky factor (lower triangular, 21 products per step instead of 36, no
        // eigendecomposition), the symmetric root when the covariance is only
        // semi-definite; a non-finite particle covariance (particles near overflow): no
        // mutation step
        let root = if cov_before.iter().all(|v| v.is_finite()) {
            cov_before.cholesky().map(|c| c.unpack())
        } else {
            None
        };
        let d = root
            .or_else(|| psd_sqrt(cov_before))
            .map(|s| s * (bandwidth(Kernel::Gaussian, n) * g.mutation_scale));
        let mut pop = self.pop();
        simd::dispatch(
            #[inline(always)]
            || {
                pop.shuffle();
                let count = pop.select(n / 2, g.crossover, None, |_, _, _| {});
                pop.crossover_block(&t, count, None);
                let Some(d) = d else {
                    return;
                };
                let d: [[f64; 6]; 6] = std::array::from_fn(|i| std::array::from_fn(|j| d[(i, j)]));
                let lower = (0..6).all(|i| (i + 1..6).all(|j| d[i][j] == 0.0));
                let count = pop.select(n, g.mutation, None, |_, _, _| {});
                pop.mutate_blocks(
                    &t,
                    count,
                    false,
                    #[inline(always)]
                    |l| {
                        for i in 0..6 {
                            let mut s = [0.0; B];
                            // the symmetric root is full: every column
                            let last = if lower { i } else { 5 };
                            for j in 0..=last {
                                let dij = d[i][j];
                                for lane in 0..B {
                                    s[lane] += dij * l.eps[j][lane];
                                }
                            }
                            for lane in 0..B {
                                l.c[i][lane] = l.x[i][lane] + s[lane];
                            }
                        }
                    },
                    #[inline(always)]
                    |l| {
                        for lane in 0..B {
                            l.acc[lane] =
                                l.lp[lane].is_finite() && accept_linear(l.v[lane], l.la[lane]);
                        }
                    },
                );
            },
        );
        let (tried, accepted) = (pop.tried, pop.accepted);
        self.moves_tried += tried;
        self.moves_accepted += accepted;
        if self.params.moves {
            return false;
        }
        let n = self.x.len();
        let mom = if !self.chunked() && self.soa.len() * BLOCK >= n {
            // the moved population transposed: its moments from the lanes, and the next
            // transition's input (no transposition there)
            transpose_into(&self.x, &mut self.soa);
            self.soa_fresh = true;
            unit_moments_soa(&self.mean, &self.soa, n)
        } else {
            unit_moments(&self.x, &self.mean)
        };
        let (mean, cov) = mom.finish();
        (self.mean, self.cov) = (mean, OnceCell::from(cov));
        true
    }

    /// The CGA-PF's cloud-genetic resampling of paper 003 (see the module documentation).
    /// The random stream (since `perf-gapf6`): four words of the filter's generator seed
    /// the lanes ([`Lanes::seed_from`]); then per generation: the pairing's `n / 2` indices
    /// from the generator (`Pop::shuffle`); from the lanes per block of sixteen pairs
    /// sixteen uniforms, then the cloud drops of the pairs that need one (`Pop::select`:
    /// from a pool of normals refilled sixteen at a time by [`Ziggurat::fill_batch_lanes`],
    /// the pool restarted for each selection); per block of eight
    /// selected pairs eight words (`u` and the sign) and sixteen uniforms from the lanes
    /// (the first eight the acceptance uniforms); the mutation selection likewise per block
    /// of sixteen particles; per block of sixteen mutated particles six batches of sixteen
    /// normals from the lanes (component-major: the drops `En'_k`;
    /// [`Ziggurat::fill_batch_lanes`]), then sixteen words (the six signs, bits 0..6) and
    /// sixteen acceptance uniforms.
    // lane-indexed loops over several arrays: the form that vectorises across lanes
    #[allow(clippy::needless_range_loop)]
    pub(super) fn cloud_moves<M: MeasurementModel>(&mut self, lik: &Likelihood<'_, M>) {
        let c = self.params.cloud;
        let n = self.x.len();
        let t = Target::new(lik, &self.pred_mean, &self.pred_l);
        let mut pop = self.pop();
        simd::dispatch(
            #[inline(always)]
            || {
                for gen in 0..c.generations {
                    let (best, f_min, f_avg, f_max) = pop.fitness_stats();
                    if !best.is_finite() {
                        return;
                    }
                    // crossover
                    pop.shuffle();
                    let cd = Some(CloudDrop {
                        f_avg,
                        f_max,
                        c1: c.c1,
                        c2: c.c2,
                    });
                    let count = pop.select(
                        n / 2,
                        c.k_crossover,
                        cd,
                        #[inline(always)]
                        |pop, start, f| {
                            let m = B.min(n / 2 - start);
                            for (lane, fl) in f.iter_mut().enumerate().take(m) {
                                let j = start + lane;
                                let (a, b) = (pop.perm[2 * j], pop.perm[2 * j + 1]);
                                *fl = pop.fit[a].max(pop.fit[b]);
                            }
                        },
                    );
                    pop.crossover_block(&t, count, Some(best));
                    // cloud mutation
                    let mut lo = [f64::INFINITY; 6];
                    let mut hi = [f64::NEG_INFINITY; 6];
                    for xi in pop.x.iter() {
                        for k in 0..6 {
                            lo[k] = lo[k].min(xi[k]);
                            hi[k] = hi[k].max(xi[k]);
                        }
                    }
                    let cut = c.c3 * (gen + 1) as f64;
                    let en: [f64; 6] = std::array::from_fn(|k| (hi[k] - lo[k]) / cut);
                    let he: [f64; 6] = std::array::from_fn(|k| en[k] / c.c4);
                    // components with a step density (`He > 0`); the others add nothing
                    // to the Hastings ratio
                    let live: [bool; 6] = std::array::from_fn(|k| he[k] > 0.0);
                    let count = pop.select(
                        n,
                        c.k_mutation,
                        cd,
                        #[inline(always)]
                        |pop, start, f| {
                            let m = B.min(n - start);
                            f[..m].copy_from_slice(&pop.fit[start..start + m]);
                        },
                    );
                    // certainty mapped linearly from fitness, the drop placed at that
                    // certainty: ln mu
                    let ln_mu = |f: f64| ln_certainty(f, f_min, f_max, &c);
                    pop.mutate_blocks(
                        &t,
                        count,
                        true,
                        #[inline(always)]
                        |l| {
                            for lane in 0..l.n {
                                l.aux[lane] = ln_mu(l.f[lane]);
                            }
                            for lane in 0..B {
                                l.reach[lane] = (-2.0 * l.aux[lane]).sqrt();
                            }
                            for k in 0..6 {
                                for lane in 0..B {
                                    let en1 = en[k] + he[k] * l.eps[k][lane];
                                    let sign = if (l.w[lane] >> k) & 1 == 1 { 1.0 } else { -1.0 };
                                    l.c[k][lane] = l.x[k][lane] + sign * en1.abs() * l.reach[lane];
                                }
                            }
                        },
                        #[inline(always)]
                        |l| {
                            // Hastings correction: the reverse step is drawn with the
                            // candidate's reach (see `hastings_cloud`)
                            let mut ln_mu_back = [-1.0; B];
                            for lane in 0..l.n {
                                ln_mu_back[lane] = ln_mu(fitness(l.ll[lane] - best));
                            }
                            let (q, r) = hastings_cloud(l, &ln_mu_back, &en, &he, &live);
                            for lane in 0..B {
                                let la = l.la[lane] + q[lane];
                                // v < r e^la without a logarithm: e^-|la| is <= 1
                                let e = exp_nonpos(-la.abs());
                                let v = l.v[lane];
                                let ok = if la <= 0.0 {
                                    v < r[lane] * e
                                } else {
                                    v * e < r[lane]
                                };
                                l.acc[lane] = l.lp[lane].is_finite() && ok;
                            }
                        },
                    );
                }
            },
        );
        let (tried, accepted) = (pop.tried, pop.accepted);
        self.moves_tried += tried;
        self.moves_accepted += accepted;
    }
}

/// The lanes of a mutation block (see [`Pop::mutate_blocks`]).
struct Block {
    /// lanes in use
    n: usize,
    idx: [usize; B],
    /// the particles, their fitness, log-likelihoods and log predictive densities (formed in
    /// the block)
    x: [[f64; B]; 6],
    f: [f64; B],
    ll0: [f64; B],
    lq0: [f64; B],
    /// six standard normals per lane (component-major)
    eps: [[f64; B]; 6],
    /// a word per lane (the cloud mutation's signs) and the acceptance uniform
    w: [u64; B],
    v: [f64; B],
    /// the candidates, their log-likelihoods, log predictive and log target densities,
    /// and the log target ratio `la = (ll - ll0) + (lq - lq0)`
    c: [[f64; B]; 6],
    ll: [f64; B],
    lq: [f64; B],
    lp: [f64; B],
    la: [f64; B],
    acc: [bool; B],
    /// per-operator lane values (the cloud mutation's `ln mu` and reach)
    aux: [f64; B],
    reach: [f64; B],
}

impl Block {
    /// A block with `n` lanes in use, unit fitness and `aux`, `reach` in every lane (the
    /// rest zero).
    #[inline(always)]
    fn new(n: usize, aux: f64, reach: f64) -> Self {
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
    fn mutate_blocks<M: MeasurementModel>(
        &mut self,
        t: &Target<'_, '_, M>,
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

/// `ln mu` of the cloud mutation's certainty, mapped linearly from fitness `f`:
/// `mu = mu_min + (mu_max - mu_min) (f - f_min) / (f_max - f_min)` (clamped to the
/// interval; `mu_max` when every fitness is equal); the drop is placed at that certainty.
#[inline(always)]
fn ln_certainty(f: f64, f_min: f64, f_max: f64, c: &CloudParams) -> f64 {
    let mu = if f_max > f_min {
        c.mu_min + (c.mu_max - c.mu_min) * ((f - f_min) / (f_max - f_min)).clamp(0.0, 1.0)
    } else {
        c.mu_max
    };
    mu.ln()
}

/// The cloud mutation's Hastings term for a block: returns `(q, r)` per lane with
/// `ln q(x | c) - ln q(c | x) = q + ln r`. A step of size `s` in component `k` has the
/// density (up to a constant) `phi(s / reach) / reach`,
/// `phi(y) = e^(-a^2/2) + e^(-b^2/2)`, `a = (y - En_k) / He_k`, `b = (y + En_k) / He_k` (the
/// folded normal of `|En'_k|`); since `b^2 - a^2 = 4 y En_k / He_k^2`,
/// `ln phi(y) = -a^2 / 2 + ln(1 + e^(-t))`, `t = 2 y En_k / He_k^2 >= 0`. Summed over the
/// components with `He_k > 0` (the others have no density: they add nothing), forward
/// (`reach = sqrt(-2 ln mu)`) and backward (`reach_back`, from `ln_mu_back`):
/// `q = sum_k (a_f^2 - a_b^2) / 2` and
/// `r = prod_k (1 + e^(-t_b)) / (1 + e^(-t_f)) * reach / reach_back`; each factor lies in
/// `[1/2, 2]` times the reach ratio, so no logarithm is needed.
#[inline(always)]
fn hastings_cloud(
    l: &Block,
    ln_mu_back: &[f64; B],
    en: &[f64; 6],
    he: &[f64; 6],
    live: &[bool; 6],
) -> ([f64; B], [f64; B]) {
    let mut reach_back = [0.0; B];
    let mut ratio = [0.0; B];
    for lane in 0..B {
        reach_back[lane] = (-2.0 * ln_mu_back[lane]).sqrt();
        ratio[lane] = l.reach[lane] / reach_back[lane];
    }
    let (mut q, mut r) = ([0.0; B], [1.0; B]);
    for k in 0..6 {
        if !live[k] {
            continue;
        }
        let s = 2.0 * en[k] / (he[k] * he[k]);
        for lane in 0..B {
            let step = (l.c[k][lane] - l.x[k][lane]).abs();
            let (yf, yb) = (step / l.reach[lane], step / reach_back[lane]);
            let (af, ab) = ((yf - en[k]) / he[k], (yb - en[k]) / he[k]);
            let pf = 1.0 + exp_nonpos(-(yf * s));
            let pb = 1.0 + exp_nonpos(-(yb * s));
            q[lane] += 0.5 * (af * af) - 0.5 * (ab * ab);
            r[lane] *= (pb / pf) * ratio[lane];
        }
    }
    (q, r)
}

#[cfg(test)]
mod tests {
    use super::super::{ParticleFilter, PfKind, PfParams};
    use crate::dynamics::{CwModel, Discretization};
    use crate::estimators::Estimator;
    use crate::numerics::simd;
    use crate::sensors::RadioSensor;
    use crate::types::{Mat3, Mat6, State, Vec3};
    use rand::SeedableRng;

    /// The particles' bits (and the move counts) after a few steps on a paper-000-like
    /// model, with the moves' blocks on whichever path [`simd::dispatch`] takes.
    fn run(kind: PfKind, moves: bool) -> (Vec<u64>, f64) {
        let model = CwModel::new(0.001_1);
        let mut d = model.discretize(1.0, &Mat3::zeros(), Discretization::Exact);
        d.q += Mat6::from_diagonal(&State::new(0.09, 6.25e-4, 2.5e-3, 1e-6, 1e-6, 1e-6));
        let f = crate::frames::Frame::AlongRadialAntinormal;
        let sensor = RadioSensor::new(f, 0.5, 1e-3);
        let x0 = State::new(400.0, 500.0, 200.0, 0.0, 0.0, 0.0);
        let params = PfParams {
            particles: 700,
            seed: 3,
            threads: 1,
            moves,
            ..PfParams::new(kind)
        };
        let p0 = Mat6::from_diagonal(&State::new(400.0, 400.0, 400.0, 1e-2, 1e-2, 1e-2));
        let mut pf = ParticleFilter::new(x0 + State::from_element(5.0), p0, params);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        for k in 0..8 {
            let x = model.phi(k as f64) * x0;
            let z = sensor
                .measure(&x.fixed_rows::<3>(0).into_owned(), &mut rng)
                .expect("defined");
            pf.update(&sensor, &z).expect("update");
            pf.predict(&d, &Vec3::zeros()).expect("predict");
        }
        let (x, w) = pf.particles();
        let bits = x
            .iter()
            .flat_map(|xi| xi.iter().map(|v| v.to_bits()).collect::<Vec<_>>())
            .chain(w.iter().map(|v| v.to_bits()))
            .collect();
        (bits, pf.move_acceptance())
    }

    /// The cloud mutation's Hastings term `q + ln r` of `hastings_cloud` equals the sum of
    /// the folded-normal step log-densities it replaces,
    /// `sum_k [ln phi_k(s_k / reach_back) - ln reach_back - ln phi_k(s_k / reach) + ln reach]`
    /// over the components with `He_k > 0`, for steps drawn as the mutation draws them.
    #[test]
    #[allow(clippy::needless_range_loop)]
    fn hastings_ratio_equals_the_step_densities() {
        use super::{hastings_cloud, Block, B};
        use rand::Rng;
        fn log_step_density(step: f64, reach: f64, en: f64, he: f64) -> f64 {
            let y = step / reach;
            let a = (y - en) / he;
            let b = (y + en) / he;
            ((-0.5 * a * a).exp() + (-0.5 * b * b).exp()).ln() - reach.ln()
        }
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
        for case in 0..400 {
            let en: [f64; 6] =
                std::array::from_fn(|k| 10f64.powf(rng.random_range(-3.0..2.0)) * (k + 1) as f64);
            let he: [f64; 6] = std::array::from_fn(|k| {
                if case % 7 == 0 && k == 2 {
                    0.0
                } else {
                    en[k] / rng.random_range(3.0..5.0)
                }
            });
            let live: [bool; 6] = std::array::from_fn(|k| he[k] > 0.0);
            let mut l = Block::new(B, 0.0, 0.0);
            let mut ln_mu_back = [0.0; B];
            for lane in 0..B {
                let mu: f64 = rng.random_range(0.2..0.95);
                let mu_back: f64 = rng.random_range(0.2..0.95);
                l.aux[lane] = mu.ln();
                l.reach[lane] = (-2.0 * mu.ln()).sqrt();
                ln_mu_back[lane] = mu_back.ln();
                for k in 0..6 {
                    let x = rng.random_range(-500.0..500.0);
                    let g: f64 = rng.sample(rand_distr::StandardNormal);
                    let sign = if rng.random::<bool>() { 1.0 } else { -1.0 };
                    l.x[k][lane] = x;
                    l.c[k][lane] = x + sign * (en[k] + he[k] * g).abs() * l.reach[lane];
                }
            }
            let (q, r) = hastings_cloud(&l, &ln_mu_back, &en, &he, &live);
            for lane in 0..B {
                let reach_back = (-2.0 * ln_mu_back[lane]).sqrt();
                let mut want = 0.0;
                for k in (0..6).filter(|&k| live[k]) {
                    let step = (l.c[k][lane] - l.x[k][lane]).abs();
                    want += log_step_density(step, reach_back, en[k], he[k])
                        - log_step_density(step, l.reach[lane], en[k], he[k]);
                }
                let got = q[lane] + r[lane].ln();
                if want.is_finite() {
                    assert!(
                        (got - want).abs() <= 1e-9 * (1.0 + want.abs()),
                        "{got} {want}"
                    );
                } else {
                    // the reverse step's density underflows in the old form: the ratio is 0
                    assert!(want == f64::NEG_INFINITY && got < -700.0, "{got} {want}");
                }
            }
        }
    }

    /// The genetic operators' blocks give the same bits on the dispatched (AVX2) and the
    /// baseline path, and they run (some moves tried and accepted).
    #[test]
    fn dispatched_and_baseline_operators_agree_bit_for_bit() {
        for kind in [PfKind::Gapf, PfKind::Cgapf] {
            for moves in [false, true] {
                let (fast, acc) = run(kind, moves);
                let (base, acc_base) = simd::with_baseline(|| run(kind, moves));
                assert!(acc > 0.0 && acc < 1.0, "{kind:?} {moves}: acceptance {acc}");
                assert_eq!(acc.to_bits(), acc_base.to_bits());
                assert!(fast == base, "{kind:?} moves {moves}: paths differ");
            }
        }
    }
}
