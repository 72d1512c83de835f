//! The RPF's kernel jitter after resampling: every particle moved by `h D eps`, `D` a
//! square root of the cloud's covariance before resampling, in blocks of [`BLOCK`]
//! particles in structure-of-arrays form ([`Jitter`]). With moves each jittered particle is
//! accepted by the Metropolis–Hastings test on the move target
//! ([`ParticleFilter::regularise_mh`]; [`super::moves`] has the target and why); without,
//! every jitter is kept ([`ParticleFilter::regularise`]).

use super::likelihood::ParticleLikelihood;
use super::par::CHUNK;
use super::params::{bandwidth, Kernel};
use super::{ParticleFilter, N};
use crate::numerics::cholesky::chol;
use crate::numerics::eigen::psd_sqrt;
use crate::numerics::moments::{unit_moments, LaneSums, Moments};
use crate::numerics::soa::{block_to_rows, gather_to_block_in, BLOCK};
use crate::numerics::vexp::exp_nonpos;
use crate::numerics::ziggurat::{Lanes, Ziggurat, LANES};
use crate::types::{Mat6, State};
use std::cell::OnceCell;

impl ParticleFilter {
    /// RPF with moves: kernel jitter `h D eps` after resampling, each jittered particle
    /// accepted by the Metropolis–Hastings test on `pi` (see the module documentation).
    pub(super) fn regularise_mh<const D: usize, L: ParticleLikelihood<D>>(
        &mut self,
        lik: &L,
        cov_before: &Mat6,
    ) {
        // a non-finite particle covariance (particles near overflow) has no kernel: no jitter
        let Some(jitter) = Jitter::new(self.params.kernel, cov_before, self.x.len()) else {
            return;
        };
        let (pm, pl) = (self.pred_mean, self.pred_l);
        let log_pi = |x: &State, ll: f64| match pl.solve_lower_triangular(&(x - pm)) {
            Some(u) => ll - 0.5 * u.norm_squared(),
            None => f64::NEG_INFINITY,
        };
        // block by block: the block's kernel steps ([`Jitter::block`]) and uniforms from
        // lanes derived from the chunk's generator, the candidates, their likelihoods
        // together, then the accept step
        // (called from one place, inside the dispatch below: inlined there)
        // (the attribute makes it so: without it LLVM kept the closure a function of its
        // own, compiled for the baseline, and the dispatch had no effect on the loop;
        // `identity` only because an attribute on a closure needs argument position)
        let run_inline = core::convert::identity(
            #[inline(always)]
            |x: &mut [State], loglik: &mut [f64], rng: &mut super::PfRng| {
                let mut counts = (0u64, 0u64);
                let mut cands = [State::zeros(); BLOCK];
                let mut us = [0.0f64; BLOCK];
                let mut lls = [0.0; BLOCK];
                let mut lanes = Lanes::seed_from(rng);
                let mut e = [[0.0; BLOCK]; N];
                let mut step = [[0.0; BLOCK]; N];
                for (xb, llb) in x.chunks_mut(BLOCK).zip(loglik.chunks_mut(BLOCK)) {
                    let n = xb.len();
                    jitter.block::<false>(&mut lanes, rng, &mut e, &mut step);
                    lanes.uniforms(&mut us);
                    for (i, (c, xi)) in cands.iter_mut().zip(xb.iter()).enumerate() {
                        *c = *xi + State::from_fn(|k, _| step[k][i]);
                    }
                    lik.log_many(&cands[..n], &mut lls[..n]);
                    for (i, (xi, lli)) in xb.iter_mut().zip(llb.iter_mut()).enumerate() {
                        let (cand, ll, u) = (cands[i], lls[i], us[i]);
                        let lp = log_pi(&cand, ll);
                        counts.0 += 1;
                        // `u < min(1, e^d)` (`ln u < d` without the logarithm; NaN rejects)
                        let d = lp - log_pi(xi, *lli);
                        if lp.is_finite() && (d >= 0.0 || u < exp_nonpos(d)) {
                            *xi = cand;
                            *lli = ll;
                            counts.1 += 1;
                        }
                    }
                }
                counts
            },
        );
        // AVX2 where present (the same bits)
        let run = |x: &mut [State], loglik: &mut [f64], rng: &mut super::PfRng| {
            crate::numerics::simd::dispatch(
                #[inline(always)]
                || run_inline(x, loglik, rng),
            )
        };
        let (tried, accepted) = if self.chunked() {
            let jobs: Vec<_> = self
                .x
                .chunks_mut(CHUNK)
                .zip(self.loglik.chunks_mut(CHUNK))
                .zip(self.chunk_rng.iter_mut())
                .collect();
            self.pool
                .map(jobs, |((x, ll), rng)| run(x, ll, rng))
                .into_iter()
                .fold((0, 0), |a, b| (a.0 + b.0, a.1 + b.1))
        } else {
            run(&mut self.x, &mut self.loglik, &mut self.rng)
        };
        self.moves_tried += tried;
        self.moves_accepted += accepted;
    }

    /// The plain RPF (without moves): every particle jittered by `h D eps`, kept. The
    /// moments of the jittered set (uniform weights after the resampling: weight one each,
    /// the weight sum the count) are formed after the block loop from the moved blocks'
    /// transposed copy ([`LaneSums`], about the mean before the resampling) and become the
    /// filter's mean and covariance: true when they were set, false when there was no
    /// kernel (nothing moved; the caller summarises).
    /// With `gather` (the serial path, no particle covariances) the resampling is applied
    /// here: the jitter reads each new particle's parent through `idx` and writes the moved
    /// particle into the spare buffer, instead of [`ParticleFilter::apply_resampling`]
    /// copying the parents first (the same particles and stream, one pass less).
    pub(super) fn regularise(&mut self, kernel: Kernel, cov_before: &Mat6, gather: bool) -> bool {
        // a non-finite particle covariance (particles near overflow) has no kernel: no jitter
        let Some(jitter) = Jitter::new(kernel, cov_before, self.x.len()) else {
            if gather {
                self.apply_resampling();
            }
            return false;
        };
        let reference = self.mean;
        let run = |x: &mut [State],
                   parents: Option<(&[State], &[usize])>,
                   soa: Option<&mut [[[f64; BLOCK]; N]]>,
                   rng: &mut super::PfRng| {
            crate::numerics::simd::dispatch_v3(
                #[inline(always)]
                |v3| jitter.run_inline(v3, x, parents, soa, rng, &reference),
            )
        };
        let sums = if self.chunked() {
            let jobs: Vec<_> = self
                .x
                .chunks_mut(CHUNK)
                .zip(self.chunk_rng.iter_mut())
                .collect();
            let parts = self.pool.map(jobs, |(x, rng)| run(x, None, None, rng));
            let mut total = Moments::new(reference);
            parts.iter().for_each(|p| total.merge(p));
            total
        } else {
            // the moved particles also transposed, for the next transition and weighting
            let fits = self.soa.len() * BLOCK >= self.x.len();
            let soa = fits.then_some(&mut self.soa[..]);
            let sums = if gather {
                for (l, &i) in self.loglik_tmp.iter_mut().zip(&self.idx) {
                    *l = self.loglik[i];
                }
                core::mem::swap(&mut self.loglik, &mut self.loglik_tmp);
                let parents = Some((&self.x[..], &self.idx[..]));
                let sums = run(&mut self.x_tmp, parents, soa, &mut self.rng);
                core::mem::swap(&mut self.x, &mut self.x_tmp);
                sums
            } else {
                run(&mut self.x, None, soa, &mut self.rng)
            };
            self.soa_fresh = fits;
            sums
        };
        let (mean, cov) = sums.finish();
        self.mean = mean;
        self.cov = OnceCell::from(cov);
        true
    }
}

/// The RPF's kernel step `h D eps`, a block of [`BLOCK`] particles at a time in
/// structure-of-arrays form (component `k` of particle `i` in `[k][i]`, four particles per
/// AVX2 instruction inside a [`crate::numerics::simd::dispatch`]).
///
/// **Which square root.** `D` is any matrix with `D D^T = P` (the cloud's covariance):
/// for a spherically symmetric `eps` (both kernels), `D eps` and `D Q eps` have the same
/// law for every orthogonal `Q`, and every square root of `P` is `D_0 Q` for one of them,
/// so the law of the step is that of `N(0, h^2 P)` (Gaussian) or of the Epanechnikov kernel
/// with covariance shape `P`, whichever root is taken. The lower-triangular Cholesky factor
/// takes 21 products per particle instead of the 36 of the symmetric root; a cloud that is
/// only semi-definite (lost a dimension to rounding) keeps the symmetric root of its
/// clipped eigen-decomposition ([`psd_sqrt`]).
///
/// **The Epanechnikov radius.** The kernel `K(x) ∝ 1 - |x|^2` on the unit ball of
/// `R^n` is `eps = r u / |u|` with `u` standard normal (its direction uniform on the
/// sphere) and `r` independent of `u` with density `∝ r^(n-1) (1 - r^2)` on `[0, 1]`,
/// i.e. `s = r^2` with density `∝ s^(n/2-1) (1 - s)`: `s ~ Beta(n/2, 2)`, for `n = 6`
/// `Beta(3, 2)`, density `12 s^2 (1 - s)`. The `k`-th smallest of `m` independent uniforms
/// has density `m! / ((k-1)! (m-k)!) s^(k-1) (1-s)^(m-k)` (order statistics), for `k = 3`,
/// `m = 4` exactly `12 s^2 (1 - s)`: `s` is the second largest of four uniforms
/// `a, b, c, d`, branch-free `max(min(max(a, b), max(c, d)), max(min(a, b), min(c, d)))`
/// (if the largest is in the pair `(a, b)`, the second largest is the larger of `min(a, b)`
/// and `max(c, d)`, and `min(c, d) <= max(c, d)`; symmetrically for `(c, d)`). The four
/// uniforms per particle come from the same lanes as the normals, the two 32-bit halves of
/// a word each (on the `2^-32` grid: [`epanechnikov_s`]), and `r / |u| = sqrt(s / |u|^2)` is one division and one square
/// root per particle, in the block.
struct Jitter {
    /// `h D`, row by row (lower-triangular when `lower`)
    d: [[f64; N]; N],
    lower: bool,
    kernel: Kernel,
}

impl Jitter {
    /// The kernel step for a cloud of covariance `cov` and `particles` particles; `None`
    /// when `cov` is not finite or has no square root.
    fn new(kernel: Kernel, cov: &Mat6, particles: usize) -> Option<Self> {
        if !crate::numerics::all_finite(cov.as_slice()) {
            return None;
        }
        let (root, lower) = match chol(cov) {
            Some(l) => (l, true),
            None => (psd_sqrt(cov)?, false),
        };
        let h = bandwidth(kernel, particles);
        Some(Self {
            d: core::array::from_fn(|r| core::array::from_fn(|c| root[(r, c)] * h)),
            lower,
            kernel,
        })
    }

    /// The kernel steps of one block into `step` (`e`: scratch for the kernel's `eps`):
    /// six batches of normals from `lanes` ([`Ziggurat::fill_batch_lanes`], the rare slow
    /// paths from `rng`), for the Epanechnikov kernel four batches of uniforms for the
    /// radius (see the type's docs), then `step = h D eps` row by row.
    ///
    /// `SHIFTED` goes to [`Ziggurat::fill_batch_lanes_with`] (the same values either way):
    /// true in the plain RPF's loop, where it keeps the generator's step in AVX2 registers,
    /// false in the MH moves' loop, where the shifted form is slower.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // index loops over fixed lanes: they vectorise
    fn block<const SHIFTED: bool>(
        &self,
        lanes: &mut Lanes,
        rng: &mut super::PfRng,
        e: &mut [[f64; BLOCK]; N],
        step: &mut [[f64; BLOCK]; N],
    ) {
        let zig = Ziggurat::get();
        for c in e.iter_mut() {
            zig.fill_batch_lanes_with::<SHIFTED, _>(lanes, rng, c);
        }
        if self.kernel == Kernel::Epanechnikov {
            let s = epanechnikov_s(lanes);
            let mut nn = [0.0; BLOCK];
            for ek in e.iter() {
                for i in 0..BLOCK {
                    nn[i] += ek[i] * ek[i];
                }
            }
            let mut scale = [0.0; BLOCK];
            for i in 0..BLOCK {
                scale[i] = if nn[i] > 0.0 {
                    (s[i] / nn[i]).sqrt()
                } else {
                    0.0
                };
            }
            for ek in e.iter_mut() {
                for i in 0..BLOCK {
                    ek[i] *= scale[i];
                }
            }
        }
        for (r, (sr, dr)) in step.iter_mut().zip(&self.d).enumerate() {
            let cols = if self.lower { r + 1 } else { N };
            let mut acc = [0.0; BLOCK];
            for (ec, &drc) in e.iter().zip(dr).take(cols) {
                for i in 0..BLOCK {
                    acc[i] += drc * ec[i];
                }
            }
            *sr = acc;
        }
    }

    /// The plain RPF's loop over a run of particles, block by block: the block's kernel
    /// steps ([`Jitter::block`]), the particles transposed in, moved and transposed out
    /// once (out by [`block_to_rows`]' shuffles with the v3 token `v3`); lanes
    /// derived from `rng`. With `soa` (one block per [`BLOCK`] particles) the moved blocks
    /// are also stored there, transposed, and the moments of the moved set (weight one
    /// each, about `reference`) are formed from them after the loop ([`LaneSums`], each
    /// group's sums in registers for the whole run); without it particle by particle from
    /// `x` ([`unit_moments`], the same sums as the GA-PF's parallel path).
    /// (Accumulated in the block loop, the lane sums break the vectorisation of the block
    /// code.) Inlined into [`ParticleFilter::regularise`]'s
    /// [`crate::numerics::simd::dispatch_v3`].
    ///
    /// With `parents` `(src, idx)` particle `k` of `x` is written as `src[idx[k]]` moved
    /// (the resampling applied on the way: the parents gathered into the block by
    /// [`gather_to_block_in`]' shuffles), else `x` is moved in place.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // index loops over fixed lanes: they vectorise
    fn run_inline(
        &self,
        v3: Option<crate::numerics::simd::V3>,
        x: &mut [State],
        parents: Option<(&[State], &[usize])>,
        mut soa: Option<&mut [[[f64; BLOCK]; N]]>,
        rng: &mut super::PfRng,
        reference: &State,
    ) -> Moments {
        let mut lanes = Lanes::seed_from(rng);
        let mut e = [[0.0; BLOCK]; N];
        let mut step = [[0.0; BLOCK]; N];
        let mut xs = [[0.0; BLOCK]; N];
        for (b, xb) in x.chunks_mut(BLOCK).enumerate() {
            self.block::<true>(&mut lanes, rng, &mut e, &mut step);
            let block = b * BLOCK..b * BLOCK + xb.len();
            match parents.and_then(|(src, idx)| Some((src, idx.get(block)?))) {
                Some((src, ib)) => gather_to_block_in(v3, src, ib, &mut xs),
                None => {
                    // element copies: the shuffles are slower here, inlined or in a
                    // function of their own (whose call spills the loop's vector registers)
                    for (i, xi) in xb.iter().enumerate() {
                        for k in 0..N {
                            xs[k][i] = xi[k];
                        }
                    }
                }
            }
            for k in 0..N {
                for i in 0..BLOCK {
                    xs[k][i] += step[k][i];
                }
            }
            // out by shuffles (with the token)
            block_to_rows(v3, &xs, xb);
            if let Some(sb) = soa.as_deref_mut().and_then(|s| s.get_mut(b)) {
                *sb = xs;
            }
        }
        // the moments of the moved set with weight one each (uniform weights: the sums of
        // the offsets, the weight sum the count), from the transposed copy when it was
        // written, else from `x`
        let n = x.len();
        match soa.as_deref() {
            Some(s) if s.len() * BLOCK >= n => {
                LaneSums::of_soa::<false>(reference, s, n, &[]).finish(reference, n as f64)
            }
            _ => unit_moments(x, reference),
        }
    }
}

/// `BLOCK` draws of `Beta(3, 2)`, the squared radius of the Epanechnikov kernel in six
/// dimensions: the second largest of four uniforms (see [`Jitter`]). The uniforms are the
/// two 32-bit halves of the lanes' words (each as the top of a mantissa in `[1, 2)`, less 1:
/// on the `2^-32` grid), so a block takes 32 words instead of 64; the law is Beta(3, 2)'s
/// up to that grid (the distribution functions differ by less than `4 * 2^-32`).
#[inline(always)]
#[allow(clippy::needless_range_loop)] // index loops over fixed lanes: they vectorise
fn epanechnikov_s(lanes: &mut Lanes) -> [f64; BLOCK] {
    const ONE: u64 = 0x3ff0_0000_0000_0000;
    let mut u = [[0.0; BLOCK]; 4];
    for pair in u.chunks_exact_mut(2) {
        if let [hi, lo] = pair {
            for t in 0..BLOCK / LANES {
                let w = lanes.next_words();
                for j in 0..LANES {
                    hi[t * LANES + j] = f64::from_bits(((w[j] >> 32) << 20) | ONE) - 1.0;
                    lo[t * LANES + j] = f64::from_bits(((w[j] & 0xffff_ffff) << 20) | ONE) - 1.0;
                }
            }
        }
    }
    let max = |a: f64, b: f64| if a > b { a } else { b };
    let min = |a: f64, b: f64| if a < b { a } else { b };
    let mut s = [0.0; BLOCK];
    for i in 0..BLOCK {
        let (a, b, c, d) = (u[0][i], u[1][i], u[2][i], u[3][i]);
        s[i] = max(min(max(a, b), max(c, d)), max(min(a, b), min(c, d)));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::{epanechnikov_s, Jitter, Moments, BLOCK, N};
    use crate::estimators::pf::{bandwidth, Kernel, PfRng};
    use crate::numerics::cholesky::chol;
    use crate::numerics::moments::{moments, weighted_sum};
    use crate::numerics::simd::{dispatch_v3, with_baseline};
    use crate::numerics::ziggurat::Lanes;
    use crate::types::{Mat6, State};
    use rand::SeedableRng;

    /// A covariance with correlations (positive definite) and one of a cloud collapsed in
    /// the last component (semi-definite, a zero pivot: the symmetric-root fallback).
    fn covariances() -> [Mat6; 2] {
        let a = Mat6::from_fn(|r, c| {
            ((r * 7 + c * 3) % 5) as f64 - 1.5 + if r == c { 3.0 } else { 0.0 }
        });
        let pd = a * a.transpose();
        let mut b = a;
        b.row_mut(5).fill(0.0);
        [pd, b * b.transpose()]
    }

    /// The squared Epanechnikov radius from the lanes is `Beta(3, 2)` (fixed seed, 10^5
    /// draws): mean 3/5 and variance 1/25 within 5 standard errors, and the
    /// Kolmogorov–Smirnov distance to `F(s) = 4 s^3 - 3 s^4` below the 1 % critical value
    /// `1.63 / sqrt(n)`.
    #[test]
    fn epanechnikov_radius_is_beta_3_2() {
        let mut rng = PfRng::seed_from_u64(11);
        let mut lanes = Lanes::seed_from(&mut rng);
        let mut s: Vec<f64> = (0..100_000 / BLOCK)
            .flat_map(|_| epanechnikov_s(&mut lanes))
            .collect();
        let n = s.len() as f64;
        let mean = s.iter().sum::<f64>() / n;
        let var = s.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0);
        // standard errors: 0.2 / sqrt(n) = 6.3e-4 and sqrt((mu4 - var^2) / n) = 1.5e-4
        assert!((mean - 0.6).abs() < 3.2e-3, "mean {mean}");
        assert!((var - 0.04).abs() < 7.5e-4, "variance {var}");
        s.sort_by(f64::total_cmp);
        let ks = s
            .iter()
            .enumerate()
            .map(|(i, &v)| {
                let f = 4.0 * v.powi(3) - 3.0 * v.powi(4);
                (f - i as f64 / n).abs().max(((i + 1) as f64 / n - f).abs())
            })
            .fold(0.0, f64::max);
        assert!(ks < 1.63 / n.sqrt(), "KS distance {ks}");
    }

    /// The kernel step has the kernel's law for the cloud's covariance `P` with either square
    /// root: sample covariance `h^2 P` (Gaussian) or `h^2 P / (n + 4)` (Epanechnikov) within
    /// 0.03 `sqrt(P_rr P_cc)` from 64 000 draws (about five standard errors), and the
    /// Epanechnikov steps inside the ellipsoid `x^T (h^2 P)^-1 x <= 1`.
    #[test]
    #[allow(clippy::needless_range_loop)] // particle `i` of the transposed block
    fn jitter_has_the_kernel_covariance() {
        for (j, p) in covariances().iter().enumerate() {
            for kernel in [Kernel::Gaussian, Kernel::Epanechnikov] {
                let jit = Jitter::new(kernel, p, 1500).expect("a square root");
                assert_eq!(
                    jit.lower,
                    j == 0,
                    "Cholesky for the definite covariance only"
                );
                let h = bandwidth(kernel, 1500);
                let c = match kernel {
                    Kernel::Gaussian => 1.0,
                    Kernel::Epanechnikov => 1.0 / (N as f64 + 4.0),
                };
                let mut rng = PfRng::seed_from_u64(5);
                let mut lanes = Lanes::seed_from(&mut rng);
                let (mut e, mut step) = ([[0.0; BLOCK]; N], [[0.0; BLOCK]; N]);
                let mut s2 = Mat6::zeros();
                let blocks = 4000;
                let l = chol(p).map(|l| l * h);
                for _ in 0..blocks {
                    jit.block::<true>(&mut lanes, &mut rng, &mut e, &mut step);
                    for i in 0..BLOCK {
                        let v = State::from_fn(|k, _| step[k][i]);
                        s2 += v * v.transpose();
                        if let (Kernel::Epanechnikov, Some(l)) = (kernel, l) {
                            let u = l.solve_lower_triangular(&v).expect("pd");
                            assert!(u.norm() <= 1.0 + 1e-12, "outside the kernel: {u}");
                        }
                    }
                }
                let cov = s2 / (blocks * BLOCK) as f64 / (h * h * c);
                for r in 0..N {
                    for k in 0..N {
                        let tol = 0.03 * (p[(r, r)] * p[(k, k)]).sqrt() + 1e-9;
                        assert!(
                            (cov[(r, k)] - p[(r, k)]).abs() < tol,
                            "{kernel:?}, covariance {j}, ({r}, {k}): {} vs {}",
                            cov[(r, k)],
                            p[(r, k)]
                        );
                    }
                }
            }
        }
    }

    /// The plain RPF's block loop gives the same bits dispatched (AVX2 where present) and on
    /// the baseline path: the jittered particles, the moments and the generator, for both
    /// kernels and both square roots, with a short last block, with and without the
    /// transposed copy; with the copy it holds the moved particles, and the moments (from
    /// the copy's lanes, or particle by particle from `x` without it) equal the two-pass
    /// moments of the moved particles (uniform weights, about their mean) to 1e-12.
    #[test]
    #[allow(clippy::needless_range_loop)] // particle `i` of the transposed block
    fn jitter_dispatched_equals_baseline_bitwise() {
        let x0: Vec<State> = (0..1003)
            .map(|i| State::from_fn(|k, _| ((i * 31 + k * 17) % 97) as f64 * 0.1 - 4.0))
            .collect();
        let reference = State::from_element(0.2);
        let blocks = x0.len().div_ceil(BLOCK);
        let run = || {
            let mut out = Vec::new();
            for p in covariances() {
                for kernel in [Kernel::Gaussian, Kernel::Epanechnikov] {
                    let jit = Jitter::new(kernel, &p, x0.len()).expect("a square root");
                    let mut moved = Vec::new();
                    for with_soa in [false, true] {
                        let mut x = x0.clone();
                        let mut soa = vec![[[f64::NAN; BLOCK]; N]; blocks];
                        let mut rng = PfRng::seed_from_u64(9);
                        let s = with_soa.then_some(&mut soa[..]);
                        let m: Moments = dispatch_v3(
                            #[inline(always)]
                            |v3| jit.run_inline(v3, &mut x, None, s, &mut rng, &reference),
                        );
                        if with_soa {
                            for (i, xi) in x.iter().enumerate() {
                                for k in 0..N {
                                    assert_eq!(soa[i / BLOCK][k][i % BLOCK], xi[k]);
                                }
                            }
                        }
                        // the moments are those of the moved particles
                        let w = vec![1.0 / x.len() as f64; x.len()];
                        let (ms, ws) = weighted_sum(&x, &w);
                        let m2 = ms / ws;
                        let (_, p2) = moments(&m2, &x, &w).finish();
                        let (m1, p1) = m.finish();
                        assert!((m1 - m2).abs().max() <= 1e-12 * m2.abs().max(), "{m1} {m2}");
                        let scale = p2.abs().max();
                        assert!((p1 - p2).abs().max() <= 1e-12 * scale, "{p1} {p2}");
                        assert_eq!(m.wsum, x.len() as f64);
                        let mut b: Vec<u64> = x
                            .iter()
                            .flat_map(|s| s.iter().map(|v| v.to_bits()))
                            .collect();
                        b.extend(
                            m.s1.iter()
                                .chain(&m.s2)
                                .chain([&m.wsum])
                                .map(|v| v.to_bits()),
                        );
                        moved.push(x);
                        out.push((b, rng));
                    }
                    // the same particles either way
                    assert!(moved[0] == moved[1]);
                }
            }
            out
        };
        let fast = run();
        let base = with_baseline(run);
        assert!(fast == base);
    }
}
