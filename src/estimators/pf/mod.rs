//! Particle filters (paper 000's SIR filter and its regularised variant; the unscented,
//! genetic and cloud-genetic variants of paper 003 build on the same particle set).
//!
//! **SIR** (paper 000, sec. 3; Gordon, Salmond & Smith 1993): the transition density is
//! the proposal, `x_i <- Phi x_i + Gamma a + w_i`, `w_i ~ N(0, Q)`; the weights are
//! multiplied by the measurement likelihood, kept as log-weights, normalised with the
//! max-subtraction trick; `N_eff = 1 / sum w_i^2`; when `N_eff < threshold N` (paper 000:
//! 2/3) the particles are resampled ([`resample`]) and the weights reset to `1/N`. The
//! outputs are the weighted mean and covariance.
//!
//! **Regularised PF** (Musso, Oudjane & Le Gland 2001): after each resampling every
//! particle is moved by `h D eps`, `D D^T` the weighted empirical covariance before
//! resampling, `eps` drawn from the kernel, with the bandwidth that is optimal for a
//! Gaussian target in `n = 6` dimensions:
//! * Gaussian kernel: `h = (4 / (N (n + 2)))^(1 / (n + 4))`;
//! * Epanechnikov kernel `K(x) ∝ 1 - |x|^2` on the unit ball:
//!   `h = A N^(-1/(n+4))`, `A = (8 (n + 4) (2 sqrt(pi))^n / c_n)^(1/(n+4))`, `c_n` the unit
//!   ball's volume; `eps = r u` with `u` uniform on the sphere and `r^2 ~ Beta(n/2, 2)`.
//!
//! **The collapse of the literal SIR on paper 000** (issue 4's "known trap"): its prior is
//! 50 m / 1 m/s wide while one measurement pins the position to a 0.5 m x 0.12 m x 0.12 m
//! box, about 1e-7 of the prior's volume: with thousands of particles none lands in the
//! likelihood's support, one particle takes all the weight and the filter ends hundreds of
//! metres off. [`PfInit::Prior`] keeps that literal behaviour. [`PfInit::FirstMeasurement`]
//! is the first half of the fix and the default: the positions are drawn from the first
//! measurement's likelihood (the noisy measurement inverted to a position, noise drawn
//! from the sensor's noise model) and the velocities from the prior. This is the posterior
//! after the first measurement up to the prior's density over a box of a few decimetres,
//! which a 50 m prior makes flat to 1e-4; the first measurement is consumed by it.
//! The second half is **regularisation** (the RPF, [`Kernel`]): the velocities are then
//! the prior's N draws, and with 2000 of them over a 1 m/s-wide prior none lies closer
//! than ~0.1 m/s to the truth; paper 000's velocity process noise (1e-3 m/s per step)
//! cannot refine them, so a plain SIR keeps the best draw and drifts metres off within
//! 100 s (`tests/pf.rs`). The kernel jitter after each resampling moves the velocities by
//! a fraction of their current spread and the population contracts onto the truth:
//! decimetres, as the EKF. The unscented proposals (UPF, CGA-PF) do the same by moving
//! every particle with a UKF step.
//!
//! No heap allocation happens in a step: every buffer is sized at construction.

pub mod resample;

use super::{symmetrize, Estimator, FilterError, UpdateInfo};
use crate::dynamics::DiscreteModel;
use crate::noise::NoiseModel;
use crate::sensors::MeasurementModel;
use crate::types::{Mat6, State, Vec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Beta, Distribution, StandardNormal};
use resample::{effective_sample_size, normalize_log_weights, resample, Resampler};

/// How the particles start.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PfInit {
    /// From the prior `N(x0, P0)` (paper 000 literally; collapses on its example).
    Prior,
    /// Positions from the first measurement's likelihood, velocities from the prior.
    #[default]
    FirstMeasurement,
}

/// Regularisation kernel of the RPF.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kernel {
    /// Gaussian.
    Gaussian,
    /// Epanechnikov (optimal in mean integrated squared error).
    Epanechnikov,
}

/// Particle-filter settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PfParams {
    /// Number of particles (>= 1).
    pub particles: usize,
    /// Resampling scheme.
    pub resampler: Resampler,
    /// Resample when `N_eff < threshold N`; in (0, 1] (paper 000: 2/3).
    pub threshold: f64,
    /// Regularisation after resampling (`None`: plain SIR).
    pub kernel: Option<Kernel>,
    /// Initialisation.
    pub init: PfInit,
    /// Seed of the filter's own random numbers.
    pub seed: u64,
}

impl Default for PfParams {
    fn default() -> Self {
        Self {
            particles: 1500,
            resampler: Resampler::Systematic,
            threshold: 2.0 / 3.0,
            kernel: None,
            init: PfInit::FirstMeasurement,
            seed: 0,
        }
    }
}

impl PfParams {
    /// Check the settings; the message names the bad one.
    pub fn validate(&self) -> Result<(), String> {
        if self.particles == 0 {
            return Err("particles must be >= 1 (got 0)".into());
        }
        if !(self.threshold > 0.0 && self.threshold <= 1.0) {
            return Err(format!(
                "resample threshold must lie in (0, 1] (got {})",
                self.threshold
            ));
        }
        Ok(())
    }
}

const N: usize = 6;

/// Volume of the unit ball in 6 dimensions, `pi^3 / 6`.
const UNIT_BALL_6: f64 = std::f64::consts::PI * std::f64::consts::PI * std::f64::consts::PI / 6.0;

/// Optimal RPF bandwidth for `n = 6` and `particles` particles.
pub fn bandwidth(kernel: Kernel, particles: usize) -> f64 {
    let n = N as f64;
    let np = particles as f64;
    match kernel {
        Kernel::Gaussian => (4.0 / (np * (n + 2.0))).powf(1.0 / (n + 4.0)),
        Kernel::Epanechnikov => {
            let a = (8.0 * (n + 4.0) * (2.0 * std::f64::consts::PI.sqrt()).powf(n) / UNIT_BALL_6)
                .powf(1.0 / (n + 4.0));
            a * np.powf(-1.0 / (n + 4.0))
        }
    }
}

/// A particle filter over the canonical 6-state.
#[derive(Debug, Clone)]
pub struct ParticleFilter {
    params: PfParams,
    x0: State,
    p0: Mat6,
    x: Vec<State>,
    x_tmp: Vec<State>,
    logw: Vec<f64>,
    w: Vec<f64>,
    idx: Vec<usize>,
    scratch: Vec<f64>,
    mean: State,
    cov: Mat6,
    ess: f64,
    initialised: bool,
    rng: ChaCha8Rng,
    q_key: Mat6,
    q_sqrt: Mat6,
    resamples: u64,
}

fn gauss6<R: Rng + ?Sized>(rng: &mut R) -> State {
    State::from_fn(|_, _| rng.sample::<f64, _>(StandardNormal))
}

/// Symmetric square root of a PSD matrix (negative rounding eigenvalues clipped).
fn psd_sqrt(q: &Mat6) -> Mat6 {
    let e = nalgebra::SymmetricEigen::new(symmetrize(q));
    let d = e.eigenvalues.map(|v| v.max(0.0).sqrt());
    e.eigenvectors * Mat6::from_diagonal(&d) * e.eigenvectors.transpose()
}

impl ParticleFilter {
    /// A filter with prior `N(x0, p0)` (canonical frame); `params` validated by the caller.
    pub fn new(x0: State, p0: Mat6, params: PfParams) -> Self {
        let n = params.particles.max(1);
        let mut f = Self {
            params,
            x0,
            p0,
            x: vec![State::zeros(); n],
            x_tmp: vec![State::zeros(); n],
            logw: vec![0.0; n],
            w: vec![1.0 / n as f64; n],
            idx: vec![0; n],
            scratch: vec![0.0; n],
            mean: x0,
            cov: p0,
            ess: n as f64,
            initialised: false,
            rng: ChaCha8Rng::seed_from_u64(params.seed),
            q_key: Mat6::from_element(f64::NAN),
            q_sqrt: Mat6::zeros(),
            resamples: 0,
        };
        f.draw_prior();
        f
    }

    fn draw_prior(&mut self) {
        let l = psd_sqrt(&self.p0);
        for xi in self.x.iter_mut() {
            *xi = self.x0 + l * gauss6(&mut self.rng);
        }
        let n = self.x.len() as f64;
        self.logw.iter_mut().for_each(|v| *v = 0.0);
        self.w.iter_mut().for_each(|v| *v = 1.0 / n);
        self.initialised = self.params.init == PfInit::Prior;
        self.ess = n;
        self.summarise();
    }

    /// Effective sample size after the last update.
    pub fn ess(&self) -> f64 {
        self.ess
    }

    /// How many times the particles were resampled.
    pub fn resample_count(&self) -> u64 {
        self.resamples
    }

    /// The settings.
    pub fn params(&self) -> &PfParams {
        &self.params
    }

    fn summarise(&mut self) {
        let mut m = State::zeros();
        for (xi, wi) in self.x.iter().zip(&self.w) {
            m += xi * *wi;
        }
        let mut c = Mat6::zeros();
        for (xi, wi) in self.x.iter().zip(&self.w) {
            let d = xi - m;
            c += d * d.transpose() * *wi;
        }
        self.mean = m;
        self.cov = symmetrize(&c);
    }

    /// Positions from the measurement's likelihood, velocities from the prior.
    fn init_from_measurement<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
        noise: &NoiseModel,
        scales: &[f64; 3],
    ) -> Result<(), FilterError> {
        // the velocity rows of a square root of P0 draw from the prior's velocity marginal
        let l = psd_sqrt(&self.p0);
        for i in 0..self.x.len() {
            let mut zi = *z;
            let mut st = 0.0;
            for k in 0..3 {
                zi[k] -= noise.sample(scales[k], &mut st, &mut self.rng);
            }
            let r = sensor
                .invert(&zi)
                .ok_or(FilterError::NonFinite("measurement inversion"))?;
            let v = self.x0.fixed_rows::<3>(3) + (l * gauss6(&mut self.rng)).fixed_rows::<3>(3);
            self.x[i] = State::from_row_slice(&[r.x, r.y, r.z, v.x, v.y, v.z]);
        }
        self.initialised = true;
        Ok(())
    }

    fn regularise(&mut self, kernel: Kernel, cov_before: &Mat6) {
        let h = bandwidth(kernel, self.x.len());
        let d = psd_sqrt(cov_before) * h;
        let beta = Beta::new(N as f64 / 2.0, 2.0).ok();
        for xi in self.x.iter_mut() {
            let eps = match kernel {
                Kernel::Gaussian => gauss6(&mut self.rng),
                Kernel::Epanechnikov => {
                    let u = gauss6(&mut self.rng);
                    let un = u.norm();
                    let r2: f64 = beta.map(|b| b.sample(&mut self.rng)).unwrap_or(0.0);
                    if un > 0.0 {
                        u * (r2.sqrt() / un)
                    } else {
                        State::zeros()
                    }
                }
            };
            *xi += d * eps;
        }
    }
}

impl ParticleFilter {
    /// Measurement update with the sensor's likelihood under `noise` (per-component
    /// scales `scales`): the particle filters weigh with the true noise density, heavy
    /// tails included.
    pub fn update_with<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
        noise: &NoiseModel,
        scales: &[f64; 3],
    ) -> Result<UpdateInfo, FilterError> {
        if !self.initialised {
            self.init_from_measurement(sensor, z, noise, scales)?;
            let n = self.x.len() as f64;
            self.w.iter_mut().for_each(|v| *v = 1.0 / n);
            self.logw.iter_mut().for_each(|v| *v = 0.0);
            self.ess = n;
            self.summarise();
            return Ok(UpdateInfo {
                innovation: Vec3::zeros(),
                nis: f64::NAN,
                azimuth_used: true,
            });
        }
        let gaussian = matches!(noise, NoiseModel::Gaussian);
        for (xi, lw) in self.x.iter().zip(self.logw.iter_mut()) {
            let r = xi.fixed_rows::<3>(0).into_owned();
            *lw += if gaussian {
                sensor.log_likelihood(z, &r)
            } else {
                match sensor.predict(&r) {
                    Some(zh) => {
                        let d = sensor.diff(z, &zh);
                        (0..3).map(|k| noise.log_density(d[k], scales[k])).sum()
                    }
                    None => f64::NEG_INFINITY,
                }
            };
        }
        normalize_log_weights(&self.logw, &mut self.w).ok_or(FilterError::NonFinite(
            "particle weights (every likelihood is zero)",
        ))?;
        // keep log-weights bounded: store the normalised ones
        for (lw, w) in self.logw.iter_mut().zip(&self.w) {
            *lw = w.ln();
        }
        self.ess = effective_sample_size(&self.w);
        self.summarise();
        let innovation = sensor
            .predict(&self.mean.fixed_rows::<3>(0).into_owned())
            .map(|zh| sensor.diff(z, &zh))
            .unwrap_or_default();
        let n = self.x.len();
        if self.ess < self.params.threshold * n as f64 {
            let cov_before = self.cov;
            resample(
                self.params.resampler,
                &self.w,
                &mut self.idx,
                &mut self.scratch,
                &mut self.rng,
            );
            for (t, &i) in self.x_tmp.iter_mut().zip(&self.idx) {
                *t = self.x[i];
            }
            std::mem::swap(&mut self.x, &mut self.x_tmp);
            self.w.iter_mut().for_each(|v| *v = 1.0 / n as f64);
            self.logw.iter_mut().for_each(|v| *v = 0.0);
            self.resamples += 1;
            if let Some(k) = self.params.kernel {
                self.regularise(k, &cov_before);
            }
            self.summarise();
        }
        Ok(UpdateInfo {
            innovation,
            nis: f64::NAN,
            azimuth_used: true,
        })
    }
}

impl Estimator for ParticleFilter {
    fn predict(&mut self, model: &DiscreteModel, accel: &Vec3) -> Result<(), FilterError> {
        if model.q != self.q_key {
            self.q_sqrt = psd_sqrt(&model.q);
            self.q_key = model.q;
        }
        let u = model.gamma * accel;
        for xi in self.x.iter_mut() {
            *xi = model.phi * *xi + u + self.q_sqrt * gauss6(&mut self.rng);
        }
        self.summarise();
        if !self.mean.iter().all(|v| v.is_finite()) {
            return Err(FilterError::NonFinite("particle mean"));
        }
        Ok(())
    }

    /// Gaussian likelihood from the sensor's covariance (see [`ParticleFilter::update_with`]
    /// for other noise densities).
    fn update<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
    ) -> Result<UpdateInfo, FilterError> {
        let r = sensor.noise_cov();
        let scales = [r[(0, 0)].sqrt(), r[(1, 1)].sqrt(), r[(2, 2)].sqrt()];
        self.update_with(sensor, z, &NoiseModel::Gaussian, &scales)
    }

    fn state(&self) -> &State {
        &self.mean
    }

    fn covariance(&self) -> &Mat6 {
        &self.cov
    }

    fn set_estimate(&mut self, x: State, p: Mat6) {
        self.x0 = x;
        self.p0 = p;
        self.rng = ChaCha8Rng::seed_from_u64(self.params.seed);
        self.resamples = 0;
        self.draw_prior();
    }
}
