//! Genetic move steps after resampling: the GA-PF and the cloud-genetic resampling of
//! paper 003 (CGA-PF).
//!
//! Both run on the resampled, equally weighted population and leave the weights at
//! `1/N`. The **fitness** of a particle is its measurement likelihood `f_i = p(z | x_i)`
//! (normalised by the best, so `f_i` lies in (0, 1]). Every candidate that an operator
//! produces is accepted by a **Metropolis–Hastings** test on the filtering posterior
//! `pi(x) = p(z | x) N(x; m-, P-)`, the predictive density approximated by the Gaussian
//! of the predicted particles (before the prior's first update: the Gaussian prior itself):
//! accepted with probability `min(1, pi(x') / pi(x_i))`. Without the moves
//! ([`super::PfParams::moves`] false, the papers' filters as written) the target is the
//! likelihood alone, paper 003's test on the likelihood ratio.
//!
//! Why not the exact resample-move target `p(z | x) p(x | ancestor)`: conditional on its
//! ancestor a particle's velocity is pinned to the process noise (paper 000: 1e-3 m/s
//! per step), so every useful move is rejected and the population keeps the velocity
//! draws it started with — the impoverishment the moves are there to cure (with that
//! target the GA-PF ends tens of metres off on paper 000). The Gaussian predictive is the
//! same kind of approximation as the RPF's kernel density. Paper 003's test on the likelihood
//! ratio alone is this test with a flat predictive: it would pull the population onto the
//! likelihood's peak against the dynamics.
//! Every move is an exact Metropolis–Hastings move for `pi`: the GA-PF mutation is a
//! symmetric random walk; the crossover is made reversible (a pair move with its Jacobian,
//! see `crossover`); the cloud mutation, whose step length depends on the current
//! particle's fitness, carries the Hastings correction for the reverse step. (The heuristic
//! acceptance of the GA-PF literature — the arithmetic crossover `l a + (1 - l) b`,
//! `l ~ U(0, 1)`, accepted on the target ratio alone — contracts the population: on paper
//! 003 the filter becomes grossly overconfident and less accurate than the SIR.) The
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
//! **Implementation.** Within a generation the operators act on disjoint pairs (crossover)
//! and on distinct particles (mutation), with the population statistics fixed, so they run
//! in blocks without changing the algorithm: the selection draws (sixteen uniforms, then the
//! cloud drops' normals from a pool of batched normals, only where they can matter) and the
//! adaptive probabilities for sixteen items at once; the selected pairs' candidates (eight
//! pairs, sixteen lanes) and the selected particles' mutations (sixteen lanes, six batches
//! of normals, component-major) in structure-of-arrays form; their likelihood through
//! `ParticleLikelihood::log_soa` (the radio's vectorised residuals) and the predictive
//! density by forward substitution across the lanes; all inside [`simd::dispatch`] (the same bits on the AVX2 and the
//! baseline path, tested). The uniforms, the words and the mutations' normals come from
//! four xoshiro256++ lanes ([`Lanes`], seeded from the filter's generator at the start of
//! each call, transient like the transition's, so the saved state holds only the
//! generator), the normals by [`Ziggurat::fill_batch_lanes`]; the pairing draws `n / 2`
//! exact bounded integers (Lemire's; see `Pop::shuffle`). The random stream is the blocks'
//! order (documented at `ParticleFilter::genetic_moves` and `ParticleFilter::cloud_moves`).
//! The crossover forms the pair's predictive factor from the whitened half-difference alone
//! (one forward substitution per pair; see `Pop::crossover_block`), so no pass over the
//! population forms every particle's target first: a particle's predictive density
//! `ln N(x; m-, P-)` is formed only in a mutation block (beside its candidate's), and the
//! log ratios are `(ll' - ll) + (lq' - lq)`. The Metropolis–Hastings test compares the
//! uniform in the linear domain, `v < e^la` (the same event as `ln v < la`), decided by a
//! Taylor squeeze where it can be and by [`exp_nonpos`] otherwise (`accept_linear`), and
//! the cloud mutation's Hastings ratio is formed without a logarithm per component (see
//! `hastings_cloud`). Fitness `exp(l - best)` is [`exp_nonpos`] (within 2 ulp of `exp`).
//! The literal GA-PF summarises the moved population itself (mean and covariance in one
//! unweighted pass, instead of the filter's weighted mean pass and the next prediction's
//! weighted moments pass).

pub use super::params::{CloudParams, GeneticParams};

mod population;
mod target;
#[cfg(test)]
mod tests;

use super::likelihood::ParticleLikelihood;
use super::params::{bandwidth, Kernel};
use super::ParticleFilter;
use crate::numerics::eigen::psd_sqrt;
use crate::numerics::moments::{unit_moments, unit_moments_soa};
use crate::numerics::simd;
use crate::numerics::soa::{transpose_into, BLOCK};
use crate::numerics::vexp::exp_nonpos;
use crate::numerics::ziggurat::Lanes;
use crate::types::Mat6;
use population::{accept_linear, fitness, Block, CloudDrop, Pop};
use std::cell::OnceCell;
use target::Target;

// named by the docs only
#[cfg(doc)]
use crate::numerics::ziggurat::Ziggurat;

/// Lanes of a candidate block (one [`Ziggurat::fill_batch_lanes`] per component).
const B: usize = BLOCK;

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

    /// The operators' target: the likelihood times the Gaussian predictive with the moves,
    /// the likelihood alone without them (paper 003 as written).
    fn target<'l, const D: usize, L: ParticleLikelihood<D>>(&self, lik: &'l L) -> Target<'l, L, D> {
        if self.params.moves {
            Target::new(lik, &self.pred_mean, &self.pred_l)
        } else {
            Target::likelihood_only(lik)
        }
    }

    /// GA-PF move step after resampling (see the module documentation). The random
    /// stream: four words of the filter's generator seed the lanes
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
    pub(super) fn genetic_moves<const D: usize, L: ParticleLikelihood<D>>(
        &mut self,
        lik: &L,
        cov_before: &Mat6,
    ) -> bool {
        let g = self.params.genetic;
        let n = self.x.len();
        let t = self.target(lik);
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
                let d: [[f64; 6]; 6] =
                    core::array::from_fn(|i| core::array::from_fn(|j| d[(i, j)]));
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
    /// The random stream: four words of the filter's generator seed
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
    pub(super) fn cloud_moves<const D: usize, L: ParticleLikelihood<D>>(&mut self, lik: &L) {
        let c = self.params.cloud;
        let n = self.x.len();
        let t = self.target(lik);
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
                    let en: [f64; 6] = core::array::from_fn(|k| (hi[k] - lo[k]) / cut);
                    let he: [f64; 6] = core::array::from_fn(|k| en[k] / c.c4);
                    // components with a step density (`He > 0`); the others add nothing
                    // to the Hastings ratio
                    let live: [bool; 6] = core::array::from_fn(|k| he[k] > 0.0);
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
