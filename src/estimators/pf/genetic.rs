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

use super::{bandwidth, gauss6, psd_sqrt, Kernel, Likelihood, ParticleFilter};
use crate::numerics::vexp::exp_nonpos;
use crate::sensors::MeasurementModel;
use crate::types::{Mat6, State};
use rand::Rng;
use rand_distr::StandardNormal;

/// GA-PF operators.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GeneticParams {
    /// Crossover probability of a pair, in [0, 1].
    pub crossover: f64,
    /// Mutation probability of a particle, in [0, 1] (default 0.5: with 0.1 the velocities
    /// stay impoverished on paper 000, 13.9 m off against 0.40 m).
    pub mutation: f64,
    /// Mutation step over the Gaussian kernel's optimal bandwidth (> 0).
    pub mutation_scale: f64,
}

impl Default for GeneticParams {
    fn default() -> Self {
        Self {
            crossover: 0.8,
            mutation: 0.5,
            mutation_scale: 1.0,
        }
    }
}

impl GeneticParams {
    /// Check the settings.
    pub fn validate(&self) -> Result<(), String> {
        prob("genetic crossover probability", self.crossover)?;
        prob("genetic mutation probability", self.mutation)?;
        positive("genetic mutation_scale", self.mutation_scale)
    }
}

/// Cloud-genetic operators of the CGA-PF (paper 003).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CloudParams {
    /// Entropy divisor of the adaptive probabilities, `En = (f_max - f_avg) / c1`.
    pub c1: f64,
    /// Hyper-entropy divisor of the adaptive probabilities, `He = En / c2`.
    pub c2: f64,
    /// Mutation entropy divisor, `En = range / c3` (paper: 3..6).
    pub c3: f64,
    /// Mutation hyper-entropy divisor, `He = En / c4` (paper: 3..5).
    pub c4: f64,
    /// Certainty of the least fit particle (paper: 0.2).
    pub mu_min: f64,
    /// Certainty of the fittest particle (paper: 0.95).
    pub mu_max: f64,
    /// Largest crossover probability `k_c`.
    pub k_crossover: f64,
    /// Largest mutation probability `k_m`.
    pub k_mutation: f64,
    /// Rounds of crossover and mutation per resampling (>= 1).
    pub generations: usize,
}

impl Default for CloudParams {
    fn default() -> Self {
        Self {
            c1: 3.0,
            c2: 10.0,
            c3: 4.0,
            c4: 4.0,
            mu_min: 0.2,
            mu_max: 0.95,
            k_crossover: 0.8,
            k_mutation: 0.2,
            generations: 3,
        }
    }
}

impl CloudParams {
    /// Check the settings.
    pub fn validate(&self) -> Result<(), String> {
        positive("cloud c1", self.c1)?;
        positive("cloud c2", self.c2)?;
        positive("cloud c3", self.c3)?;
        positive("cloud c4", self.c4)?;
        if !(self.mu_min > 0.0 && self.mu_min <= self.mu_max && self.mu_max < 1.0) {
            return Err(format!(
                "cloud certainties need 0 < mu_min <= mu_max < 1 (got {}, {})",
                self.mu_min, self.mu_max
            ));
        }
        prob("cloud k_crossover", self.k_crossover)?;
        prob("cloud k_mutation", self.k_mutation)?;
        if self.generations == 0 || self.generations > 100 {
            return Err(format!(
                "cloud generations must lie in 1..=100 (got {})",
                self.generations
            ));
        }
        Ok(())
    }
}

fn prob(name: &str, v: f64) -> Result<(), String> {
    if (0.0..=1.0).contains(&v) {
        Ok(())
    } else {
        Err(format!("{name} must lie in [0, 1] (got {v})"))
    }
}

fn positive(name: &str, v: f64) -> Result<(), String> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(format!("{name} must be finite and > 0 (got {v})"))
    }
}

/// Adaptive probability from a cloud drop: `k exp(-(f - f_avg)^2 / (2 En'^2))` for
/// `f >= f_avg` with `En = (f_max - f_avg) / c1`, `En' ~ N(En, (En / c2)^2)`; `k` below the
/// average.
fn cloud_probability<R: Rng + ?Sized>(
    f: f64,
    f_avg: f64,
    f_max: f64,
    c1: f64,
    c2: f64,
    k: f64,
    rng: &mut R,
) -> f64 {
    if f < f_avg || f_max <= f_avg {
        return k;
    }
    let en = (f_max - f_avg) / c1;
    let he = en / c2;
    let en1 = en + he * rng.sample::<f64, _>(StandardNormal);
    if en1 == 0.0 {
        return 0.0;
    }
    k * (-(f - f_avg).powi(2) / (2.0 * en1 * en1)).exp()
}

impl ParticleFilter {
    /// Fill `logpi` with each particle's log target density.
    fn target_densities(&mut self) {
        for i in 0..self.x.len() {
            self.logpi[i] = self.loglik[i] + self.log_predictive(&self.x[i]);
        }
    }

    /// Metropolis–Hastings: replace particle `i` by `cand` with probability
    /// `min(1, pi_i(cand) / pi_i(x_i))`.
    fn try_move<M: MeasurementModel>(&mut self, i: usize, cand: &State, lik: &Likelihood<'_, M>) {
        let ll = lik.log(cand);
        self.try_move_with(i, cand, ll, 0.0);
    }

    /// Metropolis–Hastings with a precomputed candidate log-likelihood `ll` and the log
    /// ratio `log_q = ln q(x | cand) - ln q(cand | x)` of the proposal densities.
    fn try_move_with(&mut self, i: usize, cand: &State, ll: f64, log_q: f64) {
        self.moves_tried += 1;
        let lp = ll + self.log_predictive(cand);
        if !lp.is_finite() {
            return;
        }
        let u: f64 = self.rng.random();
        // `u < min(1, e^d)` (`ln u < d` without the logarithm; NaN rejects)
        let d = lp - self.logpi[i] + log_q;
        if d >= 0.0 || u < exp_nonpos(d) {
            self.x[i] = *cand;
            self.loglik[i] = ll;
            self.logpi[i] = lp;
            self.moves_accepted += 1;
        }
    }

    fn shuffle(&mut self) {
        for i in (1..self.perm.len()).rev() {
            let j = self.rng.random_range(0..=i);
            self.perm.swap(i, j);
        }
    }

    /// Crossover of particles `a` and `b` as a reversible pair move: with the pair's mean
    /// `m` and half-difference `d`, the children are `a' = m + s d`, `b' = m - s d`,
    /// `s = ±exp(u)`, `u ~ U(-ln 2, ln 2)` (`s` in (0, 1): the arithmetic crossover
    /// `l a + (1 - l) b` with `l = (1 + s) / 2`; `|s| > 1`: its inverse, the pair spreading
    /// apart). Accepted jointly with probability
    /// `min(1, pi(a') pi(b') |s|^6 / (pi(a) pi(b)))`, `|s|^6` the Jacobian (Green 1995):
    /// an exact Metropolis–Hastings move that leaves `pi x pi` invariant.
    fn crossover<M: MeasurementModel>(&mut self, a: usize, b: usize, lik: &Likelihood<'_, M>) {
        self.moves_tried += 1;
        let u: f64 = self
            .rng
            .random_range(-std::f64::consts::LN_2..std::f64::consts::LN_2);
        let s = if self.rng.random::<bool>() {
            u.exp()
        } else {
            -u.exp()
        };
        let m = (self.x[a] + self.x[b]) * 0.5;
        let d = (self.x[a] - self.x[b]) * 0.5;
        let (ca, cb) = (m + d * s, m - d * s);
        let (la, lb) = (lik.log(&ca), lik.log(&cb));
        let (pa, pb) = (la + self.log_predictive(&ca), lb + self.log_predictive(&cb));
        let log_alpha = pa + pb - self.logpi[a] - self.logpi[b] + 6.0 * u;
        if !log_alpha.is_finite() && log_alpha != f64::INFINITY {
            return;
        }
        let v: f64 = self.rng.random();
        if log_alpha >= 0.0 || v < exp_nonpos(log_alpha) {
            self.x[a] = ca;
            self.x[b] = cb;
            self.loglik[a] = la;
            self.loglik[b] = lb;
            self.logpi[a] = pa;
            self.logpi[b] = pb;
            self.moves_accepted += 1;
        }
    }

    /// GA-PF move step after resampling (see the module documentation), through
    /// [`crate::numerics::simd::dispatch`] (AVX2 where present, the same bits).
    pub(super) fn genetic_moves<M: MeasurementModel>(
        &mut self,
        lik: &Likelihood<'_, M>,
        cov_before: &Mat6,
    ) {
        crate::numerics::simd::dispatch(
            #[inline(always)]
            || self.genetic_moves_inline(lik, cov_before),
        )
    }

    /// [`ParticleFilter::genetic_moves`]' body.
    #[inline(always)]
    fn genetic_moves_inline<M: MeasurementModel>(
        &mut self,
        lik: &Likelihood<'_, M>,
        cov_before: &Mat6,
    ) {
        let g = self.params.genetic;
        self.target_densities();
        self.shuffle();
        let n = self.x.len();
        for j in 0..n / 2 {
            if self.rng.random::<f64>() < g.crossover {
                let (a, b) = (self.perm[2 * j], self.perm[2 * j + 1]);
                self.crossover(a, b, lik);
            }
        }
        // a non-finite particle covariance (particles near overflow): no mutation step
        let Some(sqrt) = psd_sqrt(cov_before) else {
            return;
        };
        let d = sqrt * (bandwidth(Kernel::Gaussian, n) * g.mutation_scale);
        for i in 0..n {
            if self.rng.random::<f64>() < g.mutation {
                let cand = self.x[i] + d * gauss6(&mut self.rng);
                self.try_move(i, &cand, lik);
            }
        }
    }

    /// Fitness statistics `(min, mean, max)` of `exp(loglik - max loglik)`.
    fn fitness_stats(&self) -> (f64, f64, f64, f64) {
        let best = self.loglik.iter().fold(f64::NEG_INFINITY, |m, &v| m.max(v));
        let (mut lo, mut sum) = (f64::INFINITY, 0.0);
        for &l in &self.loglik {
            let f = (l - best).exp();
            lo = lo.min(f);
            sum += f;
        }
        (best, lo, sum / self.loglik.len() as f64, 1.0)
    }

    /// Cloud-genetic resampling of paper 003 (see the module documentation), through
    /// [`crate::numerics::simd::dispatch`] (AVX2 where present, the same bits).
    pub(super) fn cloud_moves<M: MeasurementModel>(&mut self, lik: &Likelihood<'_, M>) {
        crate::numerics::simd::dispatch(
            #[inline(always)]
            || self.cloud_moves_inline(lik),
        )
    }

    /// [`ParticleFilter::cloud_moves`]' body.
    #[inline(always)]
    fn cloud_moves_inline<M: MeasurementModel>(&mut self, lik: &Likelihood<'_, M>) {
        let c = self.params.cloud;
        let n = self.x.len();
        self.target_densities();
        for gen in 0..c.generations {
            let (best, f_min, f_avg, f_max) = self.fitness_stats();
            if !best.is_finite() {
                return;
            }
            let fit = |l: f64| (l - best).exp();
            // certainty mapped linearly from fitness, the drop placed at that certainty
            let reach_of = |f: f64| {
                let mu = if f_max > f_min {
                    c.mu_min
                        + (c.mu_max - c.mu_min) * ((f - f_min) / (f_max - f_min)).clamp(0.0, 1.0)
                } else {
                    c.mu_max
                };
                (-2.0 * mu.ln()).sqrt()
            };
            // crossover
            self.shuffle();
            for j in 0..n / 2 {
                let (a, b) = (self.perm[2 * j], self.perm[2 * j + 1]);
                let fp = fit(self.loglik[a]).max(fit(self.loglik[b]));
                let pc =
                    cloud_probability(fp, f_avg, f_max, c.c1, c.c2, c.k_crossover, &mut self.rng);
                if self.rng.random::<f64>() < pc {
                    self.crossover(a, b, lik);
                }
            }
            // cloud mutation
            let mut lo = State::from_element(f64::INFINITY);
            let mut hi = State::from_element(f64::NEG_INFINITY);
            for xi in &self.x {
                lo = lo.inf(xi);
                hi = hi.sup(xi);
            }
            let en = (hi - lo) / (c.c3 * (gen + 1) as f64);
            let he = en / c.c4;
            for i in 0..n {
                let fi = fit(self.loglik[i]);
                let pm =
                    cloud_probability(fi, f_avg, f_max, c.c1, c.c2, c.k_mutation, &mut self.rng);
                if self.rng.random::<f64>() >= pm {
                    continue;
                }
                let reach = reach_of(fi);
                let mut cand = self.x[i];
                for k in 0..6 {
                    let en1 = en[k] + he[k] * self.rng.sample::<f64, _>(StandardNormal);
                    let sign = if self.rng.random::<bool>() { 1.0 } else { -1.0 };
                    cand[k] += sign * en1.abs() * reach;
                }
                // Hastings correction: the reverse step is drawn with the candidate's reach
                let ll = lik.log(&cand);
                let reach_back = reach_of(fit(ll));
                let mut log_q = 0.0;
                for k in 0..6 {
                    let step = (cand[k] - self.x[i][k]).abs();
                    log_q += log_step_density(step, reach_back, en[k], he[k])
                        - log_step_density(step, reach, en[k], he[k]);
                }
                self.try_move_with(i, &cand, ll, log_q);
            }
        }
    }
}

/// Log density (up to a constant) of a cloud-mutation step of size `step` in one
/// component: `step = |En'| reach`, `En' ~ N(en, he^2)`, so `|En'|` is folded normal.
fn log_step_density(step: f64, reach: f64, en: f64, he: f64) -> f64 {
    if !(reach > 0.0 && he > 0.0) {
        return 0.0;
    }
    let y = step / reach;
    let a = (y - en) / he;
    let b = (y + en) / he;
    ((-0.5 * a * a).exp() + (-0.5 * b * b).exp()).ln() - reach.ln()
}
