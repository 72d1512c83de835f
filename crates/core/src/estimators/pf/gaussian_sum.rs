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
//!   moved by Liu and West's shrinkage kernel, `m_i <- a m_i + (1 - a) m + h L eps`, `m`,
//!   `L L^T = B` the weighted mean and covariance of the means before resampling: the
//!   moved copies, a sample of the resampled set, keep its mean and covariance in
//!   expectation (`a^2 B + h^2 B = B`), and duplicated terms separate. This is
//!   regularisation: it keeps the first two moments of the sum, not the sum itself (no
//!   Metropolis-Hastings correction), so it Gaussianises the spread of the means a little
//!   at each resampling; the first copies are left where they are for that reason, and
//!   with the terms' own covariances doing most of the work the resamplings are rare.
//!
//! The output is the sum's mean and covariance (within plus between the terms). What is
//! left of each paper's filter: the SIR resamples only (copies stay copies); the RPF
//! smooths after resampling with the Gaussian kernel; the UPF's unscented proposal is the
//! UKF update of each term; the GA-PF's and CGA-PF's genetic operators act on points and
//! are not carried over (the GA-PF is the RPF, the CGA-PF the UPF with smoothing).

use super::params::{bandwidth, Kernel, PfKind, PfParams, Resampler};
use super::resample::{effective_sample_size, resample};
use super::rng::{gauss6, rng_from_state, rng_state, PfRng};
use crate::estimators::Member;
use crate::numerics::eigen::psd_sqrt_or_diagonal;
use crate::numerics::state::{refuse, Reader, StateError, Writer};
use crate::types::{Mat6, State};
use rand::SeedableRng;

/// What changes from step to step besides the terms (kept with a step's undo).
#[derive(Debug, Clone, PartialEq)]
pub struct Live {
    rng: PfRng,
    resamples: u64,
    ess: f64,
}

/// The resampling of a Gaussian-sum particle filter (see the module docs): settings,
/// generator and buffers, all sized at construction.
#[derive(Debug, Clone)]
pub struct Resampling {
    resampler: Resampler,
    threshold: f64,
    /// smooth the means after resampling (every kind but the SIR)
    smooth: bool,
    /// kernel bandwidth `h` and shrinkage `a = sqrt(1 - h^2)`
    h: f64,
    a: f64,
    live: Live,
    idx: Vec<usize>,
    scratch: Vec<f64>,
    w: Vec<f64>,
}

impl Resampling {
    /// For `n` terms with `params`' resampler, threshold, kind and seed.
    pub fn new(params: &PfParams, n: usize) -> Self {
        let h = bandwidth(Kernel::Gaussian, n);
        Self {
            resampler: params.resampler,
            threshold: params.threshold,
            smooth: params.kind != PfKind::Sir,
            h,
            a: (1.0 - h * h).sqrt(),
            live: Live {
                rng: PfRng::seed_from_u64(params.seed),
                resamples: 0,
                ess: n as f64,
            },
            idx: vec![0; n],
            scratch: vec![0.0; n],
            w: vec![0.0; n],
        }
    }

    /// The generator, the resampling count and the last `N_eff` (a step's undo).
    pub fn live(&self) -> &Live {
        &self.live
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
    /// `h^2 p` each (equal weights). The generator restarts from the seed's stream where
    /// it is: a reset draws new terms.
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
        if self.smooth {
            let l = psd_sqrt_or_diagonal(&between);
            // the first copy of each parent keeps its mean: only duplicates need separating,
            // and every move Gaussianises the means a little (the scratch marks parents seen)
            self.scratch.iter_mut().for_each(|v| *v = 0.0);
            for (m, &i) in members.iter_mut().zip(&self.idx) {
                if self.scratch[i] == 0.0 {
                    self.scratch[i] = 1.0;
                    continue;
                }
                let x = m.state() * self.a
                    + mean * (1.0 - self.a)
                    + l * gauss6(&mut self.live.rng) * self.h;
                let p = *m.covariance();
                m.set_estimate(x, p);
            }
        }
        true
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
