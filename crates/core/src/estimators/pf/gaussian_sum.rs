//! The particle prior (`pf_prior = particle`): a Gaussian per particle.
//!
//! **Why.** With a 1 mrad camera five of the six directions of the state are pinned to a
//! few metres while the range stays hundreds of metres wide until the chaser manoeuvres.
//! A point particle has to hit both scales at once: which particles survive in the pinned
//! directions is random with respect to the range, so the set's range marginal drifts by
//! chance at every resampling, and a kernel wide enough to refill it smears the pinned
//! directions. Carrying
//! the pinned directions analytically removes that: each particle is a Gaussian
//! `N(m_i, P_i)` updated by its own Kalman step, and the particles only have to cover
//! what the Kalman steps cannot, the range's non-Gaussian spread.
//!
//! **The filter** is the Gaussian-sum filter with resampling (Alspach and Sorenson 1972
//! for the sum; the resampled, kernel-smoothed form is Kotecha and Djuric's Gaussian sum
//! particle filter, 2003, with the Kalman update of each term in place of its sampled
//! one), run by the range-parameterised bank's machinery ([`crate::estimators::bank`]):
//!
//! * **prior:** the terms' means are drawn from `N(x0, a^2 P0)` and each term has the
//!   covariance `h^2 P0`, `a^2 + h^2 = 1`, `h` the Gaussian kernel's optimal bandwidth for
//!   the particle count ([`super::bandwidth`]): the sum is a kernel density estimate of
//!   the prior with its mean and covariance;
//! * **prediction:** every term by its filter's time update (exact for the linear
//!   dynamics: the sum's predictive is the particle set's own predictive, no Gaussian
//!   stand-in);
//! * **update:** every term's weight times its predictive density
//!   `N(z - h(m_i-); 0, H_i P_i- H_i^T + R)` (linearised at the term's own prior), then the
//!   term's Kalman update: the EKF's for the SIR, RPF and GA-PF, the UKF's (the unscented
//!   proposal) for the UPF and CGA-PF; under a heavy-tailed radio noise both take the robust
//!   update of that density ([`crate::estimators::rekf`], on the UKF's sigma-point moments
//!   for its terms);
//! * **resampling** when `N_eff < threshold N`, by the configured scheme: terms are
//!   copied whole (mean and covariance);
//! * **after resampling** (every kind but the SIR): every copy of a term but its first is
//!   moved, `m`, `L L^T = B` the weighted mean and covariance of the means before
//!   resampling, by the kind's step:
//!   * the RPF and UPF: Liu and West's shrinkage kernel, `m_i <- a m_i + (1 - a) m + h L
//!     eps`: the moved copies, a sample of the resampled set, keep its mean and covariance
//!     in expectation (`a^2 B + h^2 B = B`);
//!   * the GA-PF: the arithmetic crossover with a survivor `m_j` drawn at random and a
//!     mutation, `m_i <- a m_i + (1 - a) m_j + sqrt(2 a (1 - a)) L eps`: the same two
//!     moments (`(a^2 + (1 - a)^2 + 2 a (1 - a)) B = B`), each copy pulled toward another
//!     member of the set rather than toward its mean, so a copy in a mode of the set is
//!     pulled toward that mode as often as the mode holds survivors;
//!   * the CGA-PF: the shrinkage with paper 003's cloud step lengths: the parent's fitness
//!     (its weight before resampling) mapped linearly to a certainty `mu` in `[mu_min,
//!     mu_max]`, a cloud drop's entropy `En' ~ N(1, 1 / c4^2)`, the step `|En'| sqrt(-2 ln
//!     mu)` normalised to a mean square of one over the duplicates: the fittest terms step
//!     short, the poorest long, and the covariance is kept on average over the duplicates.
//!
//!   This is regularisation: it keeps the first two moments of the sum, not the sum itself
//!   (no Metropolis-Hastings correction), so it Gaussianises the spread of the means a
//!   little at each resampling; the first copies are left where they are for that reason,
//!   and with the terms' own covariances doing most of the work the resamplings are rare.
//!
//! The output is the sum's mean and covariance (within plus between the terms). What is
//! left of each paper's filter: the SIR resamples only (copies stay copies); the RPF
//! smooths after resampling with the Gaussian kernel; the UPF's unscented proposal is the
//! UKF update of each term; the GA-PF's crossover and mutation and the CGA-PF's cloud
//! steps are their separation of the duplicates. The point filters' Metropolis-Hastings
//! acceptance of each operator (and the adaptive crossover and mutation probabilities) is
//! not carried over: its target is a density of points, and here every duplicate is moved.

use super::params::{bandwidth, Kernel, PfKind, PfParams, Resampler};
use super::resample::{effective_sample_size, resample};
use super::rng::{gauss6, rng_from_state, rng_state, PfRng};
use crate::estimators::Member;
use crate::numerics::eigen::psd_sqrt_or_diagonal;
use crate::numerics::state::{refuse, Reader, StateError, Writer};
use crate::numerics::ziggurat::Ziggurat;
use crate::types::{Mat6, State};
use rand::{Rng, SeedableRng};

/// What changes from step to step besides the terms (kept with a step's undo).
#[derive(Debug, Clone, PartialEq)]
pub struct Live {
    rng: PfRng,
    resamples: u64,
    ess: f64,
}

impl Live {
    /// A new filter's: the generator at the seed's start, no resampling, `N_eff = n`.
    fn new(seed: u64, n: usize) -> Self {
        Self {
            rng: PfRng::seed_from_u64(seed),
            resamples: 0,
            ess: n as f64,
        }
    }
}

/// How a kind separates the duplicates of a resampling (the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Separate {
    /// The SIR: copies stay copies.
    Not,
    /// The RPF and UPF: Liu and West's shrinkage toward the mean.
    Shrink,
    /// The GA-PF: arithmetic crossover with a random survivor.
    Crossover,
    /// The CGA-PF: the shrinkage with cloud-model step lengths from the parent's fitness
    /// (hyper-entropy ratio `he = 1 / c4`, certainties `mu_min..mu_max`).
    Cloud { he: f64, mu_min: f64, mu_max: f64 },
}

/// The resampling of a Gaussian-sum particle filter (see the module docs): settings,
/// generator and buffers, all sized at construction.
#[derive(Debug, Clone)]
pub struct Resampling {
    resampler: Resampler,
    threshold: f64,
    seed: u64,
    separate: Separate,
    /// kernel bandwidth `h` and shrinkage `a = sqrt(1 - h^2)`
    h: f64,
    a: f64,
    live: Live,
    idx: Vec<usize>,
    scratch: Vec<f64>,
    w: Vec<f64>,
    /// the cloud's step length per term
    step: Vec<f64>,
}

impl Resampling {
    /// For `n` terms with `params`' resampler, threshold, kind and seed.
    pub fn new(params: &PfParams, n: usize) -> Self {
        let h = bandwidth(Kernel::Gaussian, n);
        let c = &params.cloud;
        let separate = match params.kind {
            PfKind::Sir => Separate::Not,
            PfKind::Rpf | PfKind::Upf => Separate::Shrink,
            PfKind::Gapf => Separate::Crossover,
            PfKind::Cgapf => Separate::Cloud {
                he: 1.0 / c.c4,
                mu_min: c.mu_min,
                mu_max: c.mu_max,
            },
        };
        Self {
            resampler: params.resampler,
            threshold: params.threshold,
            seed: params.seed,
            separate,
            h,
            a: (1.0 - h * h).sqrt(),
            live: Live::new(params.seed, n),
            idx: vec![0; n],
            scratch: vec![0.0; n],
            w: vec![0.0; n],
            step: if matches!(separate, Separate::Cloud { .. }) {
                vec![0.0; n]
            } else {
                Vec::new()
            },
        }
    }

    /// The generator, the resampling count and the last `N_eff` (a step's undo).
    pub fn live(&self) -> &Live {
        &self.live
    }

    /// The generator back to the seed's start, the count and `N_eff` to a new filter's.
    pub fn reseed(&mut self) {
        self.live = Live::new(self.seed, self.w.len());
    }

    /// Back to `live` (from [`Resampling::live`]).
    pub fn set_live(&mut self, live: &Live) {
        self.live.clone_from(live);
    }

    /// Effective sample size after the last update.
    pub fn ess(&self) -> f64 {
        self.live.ess
    }

    /// How many times the terms were resampled.
    pub fn resamples(&self) -> u64 {
        self.live.resamples
    }

    /// The terms' priors drawn from `N(x, p)`: means from `N(x, a^2 p)`, covariance
    /// `h^2 p` each (equal weights), from the generator where it is ([`Resampling::reseed`]
    /// first for a filter as new).
    pub fn draw<F: Member>(&mut self, members: &mut [F], log_w: &mut [f64], x: &State, p: &Mat6) {
        // a covariance without a square root (set through `set_estimate`) falls back to
        // its diagonal's, as the point particles' prior does
        let l = psd_sqrt_or_diagonal(p);
        let pk = p * (self.h * self.h);
        for (m, lw) in members.iter_mut().zip(log_w.iter_mut()) {
            m.reset(x + l * gauss6(&mut self.live.rng) * self.a, pk);
            *lw = 0.0;
        }
        self.live.ess = members.len() as f64;
    }

    /// After an update (`log_w` normalised, the largest 0, dropped terms `-inf`): the
    /// effective sample size, and below the threshold the resampling (whole terms, into
    /// `spare` and back) and the smoothing of the means. True when it resampled.
    pub fn after_update<F: Member>(
        &mut self,
        members: &mut Vec<F>,
        spare: &mut Vec<F>,
        log_w: &mut [f64],
    ) -> bool {
        let n = members.len();
        let mut sum = 0.0;
        for (w, l) in self.w.iter_mut().zip(log_w.iter()) {
            *w = if l.is_finite() { l.exp() } else { 0.0 };
            sum += *w;
        }
        self.w.iter_mut().for_each(|w| *w /= sum);
        self.live.ess = effective_sample_size(&self.w);
        if !(self.live.ess < self.threshold * n as f64) {
            return false;
        }
        // the means' weighted moments before resampling (the smoothing's target)
        let mut mean = State::zeros();
        for (m, w) in members.iter().zip(&self.w) {
            mean += m.state() * *w;
        }
        let mut between = Mat6::zeros();
        for (m, w) in members.iter().zip(&self.w) {
            let d = m.state() - mean;
            between += d * d.transpose() * *w;
        }
        resample(
            self.resampler,
            &self.w,
            &mut self.idx,
            &mut self.scratch,
            &mut self.live.rng,
        );
        for (s, &i) in spare.iter_mut().zip(&self.idx) {
            s.clone_from(&members[i]);
        }
        core::mem::swap(members, spare);
        log_w.iter_mut().for_each(|l| *l = 0.0);
        self.live.resamples += 1;
        if self.separate != Separate::Not {
            self.separate_duplicates(members, spare, &mean, &between);
        }
        true
    }

    /// Every copy of a term but its first moved by the kind's step (the module docs):
    /// `members` the resampled terms, `spare` their parents, `mean` and `between` the
    /// parents' weighted mean and covariance of the means. The first copies are left where
    /// they are: only duplicates need separating, and every move Gaussianises the means a
    /// little (the scratch marks the parents seen).
    fn separate_duplicates<F: Member>(
        &mut self,
        members: &mut [F],
        spare: &[F],
        mean: &State,
        between: &Mat6,
    ) {
        let l = psd_sqrt_or_diagonal(between);
        let n = members.len();
        let (a, h) = (self.a, self.h);
        if let Separate::Cloud { he, mu_min, mu_max } = self.separate {
            self.cloud_steps(he, mu_min, mu_max);
        }
        self.scratch.iter_mut().for_each(|v| *v = 0.0);
        for (k, m) in members.iter_mut().enumerate() {
            let i = self.idx[k];
            if self.scratch[i] == 0.0 {
                self.scratch[i] = 1.0;
                continue;
            }
            let eps = l * gauss6(&mut self.live.rng);
            let x = match self.separate {
                Separate::Not => continue,
                Separate::Shrink => m.state() * a + mean * (1.0 - a) + eps * h,
                // a' = a m + (1 - a) m_j with m_j an independent survivor has covariance
                // (a^2 + (1 - a)^2) B; the mutation adds the 2 a (1 - a) B that keeps B
                Separate::Crossover => {
                    let j = self.idx[self.live.rng.random_range(0..n)];
                    m.state() * a
                        + spare[j].state() * (1.0 - a)
                        + eps * (2.0 * a * (1.0 - a)).sqrt()
                }
                Separate::Cloud { .. } => {
                    m.state() * a + mean * (1.0 - a) + eps * (h * self.step[k])
                }
            };
            let p = *m.covariance();
            m.set_estimate(x, p);
        }
    }

    /// The cloud's step length of every duplicate, normalised to a mean square of one over
    /// the duplicates (so the shrinkage keeps the means' covariance on average): the
    /// parent's fitness `f` (its weight before resampling) mapped linearly to a certainty
    /// `mu` in `[mu_min, mu_max]` (the fittest parent `mu_max`), a cloud drop's entropy
    /// `En' ~ N(1, he^2)`, and the step `|En'| sqrt(-2 ln mu)`: fit terms step short, poor
    /// ones long.
    fn cloud_steps(&mut self, he: f64, mu_min: f64, mu_max: f64) {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for &i in &self.idx {
            lo = lo.min(self.w[i]);
            hi = hi.max(self.w[i]);
        }
        self.scratch.iter_mut().for_each(|v| *v = 0.0);
        let (mut sum, mut count) = (0.0, 0usize);
        for (k, &i) in self.idx.iter().enumerate() {
            self.step[k] = 0.0;
            if self.scratch[i] == 0.0 {
                self.scratch[i] = 1.0;
                continue;
            }
            let f = if hi > lo {
                (self.w[i] - lo) / (hi - lo)
            } else {
                1.0
            };
            let mu = mu_min + (mu_max - mu_min) * f;
            let mut e = [0.0; 1];
            Ziggurat::get().fill(&mut self.live.rng, &mut e);
            let step = (1.0 + he * e[0]).abs() * (-2.0 * mu.ln()).sqrt();
            self.step[k] = step;
            sum += step * step;
            count += 1;
        }
        if count > 0 && sum > 0.0 {
            let rms = (sum / count as f64).sqrt();
            self.step.iter_mut().for_each(|s| *s /= rms);
        } else {
            self.step.iter_mut().for_each(|s| *s = 1.0);
        }
    }

    /// Saved state: the generator's four words, the resampling count, the last `N_eff`.
    pub fn save_state(&self, w: &mut Writer<'_>) {
        for word in rng_state(&self.live.rng).unwrap_or([0; 4]) {
            w.u64(word);
        }
        w.u64(self.live.resamples);
        w.f64(self.live.ess);
    }

    /// Read what [`Resampling::save_state`] wrote.
    pub fn load_state(&mut self, r: &mut Reader<'_>) -> Result<(), StateError> {
        let mut s = [0u64; 4];
        for word in s.iter_mut() {
            *word = r.u64("particle-prior generator")?;
        }
        let rng = rng_from_state(s)
            .ok_or_else(|| refuse("particle-prior generator state is all zeros"))?;
        let resamples = r.u64("particle-prior resampling count")?;
        let ess = r.finite("particle-prior effective sample size")?;
        if !(ess >= 0.0 && ess <= self.w.len() as f64 * (1.0 + 1e-12)) {
            return Err(refuse(crate::msg!(
                "particle-prior effective sample size {ess} is not in [0, {}]",
                self.w.len()
            )));
        }
        self.live = Live {
            rng,
            resamples,
            ess,
        };
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::estimators::{Ekf, Estimator};

    /// A set of terms whose means spread mostly along one axis in two unequal modes (a
    /// skewed range posterior), with weights that force a resampling.
    fn set(n: usize) -> (Vec<Ekf>, Vec<f64>) {
        let mut rng = PfRng::seed_from_u64(5);
        let p = Mat6::identity() * 0.01;
        let members = (0..n)
            .map(|k| {
                let g = gauss6(&mut rng);
                let mode = if k % 4 == 0 { 300.0 } else { 0.0 };
                let x = State::from_fn(|i, _| if i == 0 { mode + 40.0 * g[0] } else { g[i] });
                Ekf::new(x, p)
            })
            .collect();
        let log_w = (0..n).map(|k| -((k % 7) as f64) * 0.3).collect();
        (members, log_w)
    }

    fn moments(ms: &[Ekf], w: Option<&[f64]>) -> (State, Mat6) {
        let n = ms.len() as f64;
        let wt = |k: usize| w.map_or(1.0 / n, |w| w[k]);
        let mean = ms
            .iter()
            .enumerate()
            .fold(State::zeros(), |a, (k, m)| a + m.state() * wt(k));
        let cov = ms.iter().enumerate().fold(Mat6::zeros(), |a, (k, m)| {
            let d = m.state() - mean;
            a + d * d.transpose() * wt(k)
        });
        (mean, cov)
    }

    /// Averaged over many resamplings, the means after each kind's separation have the
    /// parents' weighted mean and covariance (Liu and West's shrinkage, the crossover with
    /// its mutation, the cloud's normalised steps), and the SIR's copies stay copies.
    #[test]
    fn every_kind_keeps_the_means_moments_in_expectation() {
        let n = 400;
        let (parents, log_w) = set(n);
        let w: Vec<f64> = {
            let e: Vec<f64> = log_w.iter().map(|l| l.exp()).collect();
            let s: f64 = e.iter().sum();
            e.iter().map(|v| v / s).collect()
        };
        let (m0, b0) = moments(&parents, Some(&w));
        for kind in PfKind::ALL {
            let reps = 200;
            let (mut mean, mut cov) = (State::zeros(), Mat6::zeros());
            let mut distinct = 0usize;
            for seed in 0..reps {
                let params = PfParams {
                    threshold: 1.0,
                    seed,
                    ..PfParams::new(kind)
                };
                let mut r = Resampling::new(&params, n);
                let (mut members, mut lw) = (parents.clone(), log_w.clone());
                let mut spare = parents.clone();
                assert!(r.after_update(&mut members, &mut spare, &mut lw));
                let (m, c) = moments(&members, None);
                mean += m / reps as f64;
                cov += c / reps as f64;
                let mut xs: Vec<f64> = members.iter().map(|m| m.state()[0]).collect();
                xs.sort_by(f64::total_cmp);
                xs.dedup();
                distinct += xs.len();
            }
            let distinct = distinct as f64 / reps as f64;
            if kind == PfKind::Sir {
                assert!(distinct < 0.8 * n as f64, "{kind:?}: {distinct}");
                continue;
            }
            assert_eq!(distinct, n as f64, "{kind:?}: every duplicate moved");
            for i in 0..6 {
                let sd = b0[(i, i)].sqrt();
                assert!((mean[i] - m0[i]).abs() < 0.02 * sd, "{kind:?} mean {i}");
                // the equally weighted sample covariance of n draws is (n - 1) / n of B
                let c = cov[(i, i)] * n as f64 / (n - 1) as f64;
                assert!(
                    (c / b0[(i, i)] - 1.0).abs() < 0.03,
                    "{kind:?} var {i}: {c} {}",
                    b0[(i, i)]
                );
            }
        }
    }

    /// The cloud's steps: a duplicate of a fitter parent steps shorter on average.
    #[test]
    fn the_cloud_steps_short_from_fit_parents() {
        let n = 2000;
        let (parents, log_w) = set(n);
        let params = PfParams {
            threshold: 1.0,
            ..PfParams::new(PfKind::Cgapf)
        };
        let mut r = Resampling::new(&params, n);
        let (mut members, mut lw) = (parents.clone(), log_w.clone());
        let mut spare = parents.clone();
        assert!(r.after_update(&mut members, &mut spare, &mut lw));
        let (mut fit, mut poor) = ((0.0, 0), (0.0, 0));
        for (k, &i) in r.idx.iter().enumerate() {
            if r.step[k] == 0.0 {
                continue;
            }
            // parents 0 (mod 7) carry the largest weight; 2 (mod 7), half as large, is the
            // least fit class with duplicates in numbers
            match i % 7 {
                0 => fit = (fit.0 + r.step[k], fit.1 + 1),
                2 => poor = (poor.0 + r.step[k], poor.1 + 1),
                _ => {}
            }
        }
        let (fit, poor) = (fit.0 / fit.1 as f64, poor.0 / poor.1 as f64);
        assert!(fit < 0.6 * poor, "{fit} {poor}");
    }
}
