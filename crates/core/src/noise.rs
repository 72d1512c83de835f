//! Measurement-noise models for the truth simulation (and, later, the particle filters'
//! likelihoods). Each is parameterised by a scale `sigma` — the standard deviation of
//! the nominal (Gaussian) part — and is zero-mean:
//!
//! | model | density of `v` | variance / sigma^2 | Fisher information x sigma^2 |
//! |---|---|---|---|
//! | `Gaussian` | `N(0, s^2)` | 1 | 1 |
//! | `Mixture { zeta, scale }` | `(1 - zeta) N(0, s^2) + zeta N(0, (scale s)^2)` | `1 - zeta + zeta scale^2` | numeric (quadrature) |
//! | `StudentT { dof }` | `s t_dof` | `dof / (dof - 2)` | `(dof + 1) / (dof + 3)` |
//! | `Uniform` | `U(-sqrt(3) s, sqrt(3) s)` | 1 | undefined (non-regular density) |
//! | `Laplace` | `Laplace(0, b = s / sqrt 2)` | 1 | 2 |
//! | `Ar1 { phi }` | `v_k = phi v_(k-1) + sqrt(1 - phi^2) s e_k` (coloured) | 1 | undefined here (not white) |
//!
//! The contaminated Gaussian is paper 003's heavy-tailed lidar noise (its formula was
//! lost; `zeta = 0.2` is read as the contamination weight, see the digest). The Fisher
//! information feeds the posterior Cramér–Rao bound (`relnav_eval::pcrlb`): a
//! heavy-tailed density carries *less* information per sample than a Gaussian of the same
//! variance would suggest, but more than `1 / variance` for the mixture and Student-t.

#[cfg(not(feature = "std"))]
use crate::math::Float;
#[cfg(feature = "std")]
use rand::Rng;
#[cfg(feature = "std")]
use rand_distr::{Distribution, StandardNormal, StudentT};

/// A zero-mean noise density (see the module table). In scenario files it is written as
/// `noise = { model = "mixture", zeta = 0.2, scale = 10.0 }` (snake-case model names,
/// unknown keys rejected).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "std", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "std",
    serde(tag = "model", rename_all = "snake_case", deny_unknown_fields)
)]
pub enum NoiseModel {
    /// Gaussian.
    #[default]
    Gaussian,
    /// Contaminated Gaussian: weight `zeta` on a component `scale` times wider.
    Mixture {
        /// Weight of the wide component, in [0, 1).
        zeta: f64,
        /// Standard deviation of the wide component over the nominal one (> 1).
        scale: f64,
    },
    /// Student-t with `dof` degrees of freedom, scaled by sigma.
    StudentT {
        /// Degrees of freedom (> 2 so the variance exists).
        dof: f64,
    },
    /// Uniform with standard deviation sigma.
    Uniform,
    /// Laplace with standard deviation sigma.
    Laplace,
    /// First-order Gauss–Markov (coloured) noise with stationary standard deviation sigma.
    Ar1 {
        /// Correlation between successive samples, in [0, 1).
        phi: f64,
    },
}

impl NoiseModel {
    /// Check the parameters; the message names the bad one.
    pub fn validate(&self) -> Result<(), crate::message::Message> {
        match *self {
            NoiseModel::Mixture { zeta, scale } => {
                if !(0.0..1.0).contains(&zeta) {
                    return Err(crate::msg!("noise.zeta must lie in [0, 1) (got {zeta})"));
                }
                if !(scale.is_finite() && scale >= 1.0) {
                    return Err(crate::msg!(
                        "noise.scale must be finite and >= 1 (got {scale})"
                    ));
                }
            }
            NoiseModel::StudentT { dof } => {
                if !(dof.is_finite() && dof > 2.0) {
                    return Err(crate::msg!("noise.dof must be finite and > 2 (got {dof})"));
                }
            }
            NoiseModel::Ar1 { phi } => {
                if !(0.0..1.0).contains(&phi) {
                    return Err(crate::msg!("noise.phi must lie in [0, 1) (got {phi})"));
                }
            }
            NoiseModel::Gaussian | NoiseModel::Uniform | NoiseModel::Laplace => {}
        }
        Ok(())
    }

    /// `variance / sigma^2`.
    pub fn variance_factor(&self) -> f64 {
        match *self {
            NoiseModel::Mixture { zeta, scale } => 1.0 - zeta + zeta * scale * scale,
            NoiseModel::StudentT { dof } => dof / (dof - 2.0),
            _ => 1.0,
        }
    }

    /// The variance of a Gaussian that stands in for this density at the innovation `nu`
    /// of an uncertain prediction (predicted-measurement variance `pred_var`), scale
    /// `sigma`. For the Gaussian scale mixtures it is the inverse of the noise precision
    /// expected given `nu`, `1 / E[1/s^2 | nu]` — the E-step of the EM / variational
    /// treatment of heavy-tailed noise (e.g. Agamennoni, Nieto & Nebot 2012): contaminated
    /// Gaussian, `r = P(wide | nu)` from the two predictive Gaussians
    /// `N(nu; 0, s_i^2 + pred_var)`, giving `1 / ((1 - r) / s1^2 + r / s2^2)`; Student-t,
    /// `E[lambda | nu] = (dof + 1) / (dof + nu^2 / (sigma^2 + pred_var))`, giving
    /// `sigma^2 / E[lambda | nu]`. Other densities: the variance. An inlier thus gets the
    /// narrow variance, an outlier the wide one (the particle filters' Gaussian proposal,
    /// [`crate::estimators::pf`]).
    pub fn local_variance(&self, nu: f64, pred_var: f64, sigma: f64) -> f64 {
        let s2 = sigma * sigma;
        match *self {
            NoiseModel::Mixture { zeta, scale } if zeta > 0.0 => {
                let (v1, v2) = (s2, s2 * scale * scale);
                // log N(nu; 0, v) up to the common constant
                let ln_n = |v: f64| -0.5 * (nu * nu / v + v.ln());
                let (a, b) = (
                    (1.0 - zeta).ln() + ln_n(v1 + pred_var),
                    zeta.ln() + ln_n(v2 + pred_var),
                );
                let r = 1.0 / (1.0 + (a - b).exp());
                let r = if r.is_finite() { r } else { 0.0 };
                1.0 / ((1.0 - r) / v1 + r / v2)
            }
            NoiseModel::StudentT { dof } => {
                let e_lambda = (dof + 1.0) / (dof + nu * nu / (s2 + pred_var));
                s2 / e_lambda
            }
            _ => s2 * self.variance_factor(),
        }
    }

    /// Whether successive samples are independent.
    pub fn is_white(&self) -> bool {
        !matches!(self, NoiseModel::Ar1 { .. })
    }

    /// Fisher information of the location of the density times `sigma^2`, `None` where it
    /// is undefined (uniform: non-regular; AR(1): not white).
    pub fn fisher_factor(&self) -> Option<f64> {
        match *self {
            NoiseModel::Gaussian => Some(1.0),
            NoiseModel::StudentT { dof } => Some((dof + 1.0) / (dof + 3.0)),
            NoiseModel::Laplace => Some(2.0),
            NoiseModel::Mixture { zeta, scale } => Some(mixture_fisher(zeta, scale)),
            NoiseModel::Uniform | NoiseModel::Ar1 { .. } => None,
        }
    }

    /// Log of the density at `v` for scale `sigma` (the AR(1) model gives its stationary
    /// marginal).
    pub fn log_density(&self, v: f64, sigma: f64) -> f64 {
        let ln2pi = (2.0 * core::f64::consts::PI).ln();
        match *self {
            NoiseModel::Gaussian | NoiseModel::Ar1 { .. } => {
                let u = v / sigma;
                -0.5 * (u * u + ln2pi) - sigma.ln()
            }
            NoiseModel::Mixture { zeta, scale } => {
                let g = |s: f64| {
                    let u = v / s;
                    (-0.5 * u * u).exp() / (s * (2.0 * core::f64::consts::PI).sqrt())
                };
                ((1.0 - zeta) * g(sigma) + zeta * g(scale * sigma)).ln()
            }
            NoiseModel::StudentT { dof } => {
                let u = v / sigma;
                ln_gamma((dof + 1.0) / 2.0)
                    - ln_gamma(dof / 2.0)
                    - 0.5 * (dof * core::f64::consts::PI).ln()
                    - sigma.ln()
                    - (dof + 1.0) / 2.0 * (1.0 + u * u / dof).ln()
            }
            NoiseModel::Uniform => {
                let a = 3f64.sqrt() * sigma;
                if v.abs() <= a {
                    -(2.0 * a).ln()
                } else {
                    f64::NEG_INFINITY
                }
            }
            NoiseModel::Laplace => {
                let b = sigma / core::f64::consts::SQRT_2;
                -(2.0 * b).ln() - v.abs() / b
            }
        }
    }

    #[cfg(feature = "std")]
    /// Draw one sample with scale `sigma`. `state` carries the previous sample of the
    /// AR(1) model (start it at a stationary draw, see [`NoiseModel::initial_state`]).
    pub fn sample<R: Rng + ?Sized>(&self, sigma: f64, state: &mut f64, rng: &mut R) -> f64 {
        let n: f64 = rng.sample(StandardNormal);
        match *self {
            NoiseModel::Gaussian => sigma * n,
            NoiseModel::Mixture { zeta, scale } => {
                let u: f64 = rng.random();
                if u < zeta {
                    scale * sigma * n
                } else {
                    sigma * n
                }
            }
            NoiseModel::StudentT { dof } => match StudentT::new(dof) {
                Ok(t) => sigma * t.sample(rng),
                Err(_) => f64::NAN,
            },
            NoiseModel::Uniform => {
                let u: f64 = rng.random();
                3f64.sqrt() * sigma * (2.0 * u - 1.0)
            }
            NoiseModel::Laplace => {
                let u: f64 = rng.random::<f64>() - 0.5;
                let b = sigma / core::f64::consts::SQRT_2;
                -b * u.signum() * (1.0 - 2.0 * u.abs()).max(f64::MIN_POSITIVE).ln()
            }
            NoiseModel::Ar1 { phi } => {
                *state = phi * *state + (1.0 - phi * phi).sqrt() * sigma * n;
                *state
            }
        }
    }

    #[cfg(feature = "std")]
    /// A stationary starting state for [`NoiseModel::sample`] (0 for white models).
    pub fn initial_state<R: Rng + ?Sized>(&self, sigma: f64, rng: &mut R) -> f64 {
        match self {
            NoiseModel::Ar1 { .. } => sigma * rng.sample::<f64, _>(StandardNormal),
            _ => 0.0,
        }
    }
}

/// Lanczos approximation of `ln Gamma(x)` for `x > 0` (g = 7, n = 9; relative error
/// below 1e-13 on the range used here).
fn ln_gamma(x: f64) -> f64 {
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        let pi = core::f64::consts::PI;
        return (pi / (pi * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = C[0];
    let t = x + 7.5;
    for (i, c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    0.5 * (2.0 * core::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// Fisher information (times sigma^2) of the unit contaminated Gaussian,
/// `integral p'(v)^2 / p(v) dv`, by composite Simpson quadrature over +-12 wide sigmas.
fn mixture_fisher(zeta: f64, scale: f64) -> f64 {
    if zeta == 0.0 || scale == 1.0 {
        return 1.0;
    }
    let c = 1.0 / (2.0 * core::f64::consts::PI).sqrt();
    let f = |v: f64| {
        let g1 = c * (-0.5 * v * v).exp();
        let u = v / scale;
        let g2 = c / scale * (-0.5 * u * u).exp();
        let p = (1.0 - zeta) * g1 + zeta * g2;
        let dp = -(1.0 - zeta) * v * g1 - zeta * v / (scale * scale) * g2;
        if p > 0.0 {
            dp * dp / p
        } else {
            0.0
        }
    };
    let l = 12.0 * scale;
    let n = 20_000;
    let h = 2.0 * l / n as f64;
    let mut s = f(-l) + f(l);
    for i in 1..n {
        let w = if i % 2 == 1 { 4.0 } else { 2.0 };
        s += w * f(-l + i as f64 * h);
    }
    s * h / 3.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    const MODELS: [NoiseModel; 6] = [
        NoiseModel::Gaussian,
        NoiseModel::Mixture {
            zeta: 0.2,
            scale: 10.0,
        },
        NoiseModel::StudentT { dof: 4.0 },
        NoiseModel::Uniform,
        NoiseModel::Laplace,
        NoiseModel::Ar1 { phi: 0.9 },
    ];

    #[test]
    fn samples_have_the_stated_variance() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        for m in MODELS {
            let sigma = 0.7;
            let mut st = m.initial_state(sigma, &mut rng);
            let k = 400_000;
            let (mut s1, mut s2) = (0.0, 0.0);
            for _ in 0..k {
                let v = m.sample(sigma, &mut st, &mut rng);
                s1 += v;
                s2 += v * v;
            }
            let var = s2 / k as f64 - (s1 / k as f64).powi(2);
            let want = sigma * sigma * m.variance_factor();
            // heavy tails (t with 4 dof has no 4th moment) and AR(1) correlation widen
            // the sampling error; 5 % is > 4 standard errors for all of these here
            assert!((var / want - 1.0).abs() < 0.05, "{m:?}: {var} vs {want}");
        }
    }

    #[test]
    fn densities_integrate_to_one_and_fisher_matches_quadrature() {
        for m in MODELS {
            let sigma = 1.3;
            let l = 60.0 * sigma;
            let n = 200_000;
            let h = 2.0 * l / n as f64;
            let (mut mass, mut fisher) = (0.0, 0.0);
            for i in 0..n {
                let v = -l + (i as f64 + 0.5) * h;
                let p = m.log_density(v, sigma).exp();
                mass += p * h;
                let d = (m.log_density(v + 1e-5, sigma) - m.log_density(v - 1e-5, sigma)) / 2e-5;
                if p > 0.0 && d.is_finite() {
                    fisher += d * d * p * h;
                }
            }
            // the uniform density is discontinuous: the midpoint rule is only O(h) there
            let tol = if m == NoiseModel::Uniform {
                4.0 * h
            } else {
                1e-6
            };
            assert!((mass - 1.0).abs() < tol, "{m:?}: mass {mass}");
            if let Some(f) = m.fisher_factor() {
                if m.is_white() {
                    assert!(
                        (fisher * sigma * sigma / f - 1.0).abs() < 1e-4,
                        "{m:?}: {fisher} vs {f}"
                    );
                }
            }
        }
    }

    #[test]
    fn lanczos_gamma() {
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-12);
        assert!((ln_gamma(0.5) - core::f64::consts::PI.sqrt().ln()).abs() < 1e-12);
    }

    #[test]
    fn validation_names_the_parameter() {
        assert!(NoiseModel::Mixture {
            zeta: 1.0,
            scale: 3.0
        }
        .validate()
        .unwrap_err()
        .contains("zeta"));
        assert!(NoiseModel::StudentT { dof: 2.0 }
            .validate()
            .unwrap_err()
            .contains("dof"));
        assert!(NoiseModel::Ar1 { phi: -0.1 }
            .validate()
            .unwrap_err()
            .contains("phi"));
    }

    #[test]
    fn local_variance_is_the_narrow_or_the_wide_one() {
        let (sigma, pv) = (0.5, 0.01);
        assert_eq!(NoiseModel::Gaussian.local_variance(3.0, pv, sigma), 0.25);
        let mix = NoiseModel::Mixture {
            zeta: 0.2,
            scale: 10.0,
        };
        // an inlier: nearly the narrow variance; a 20-sigma outlier: nearly the wide one
        let inlier = mix.local_variance(0.3 * sigma, pv, sigma);
        let outlier = mix.local_variance(20.0 * sigma, pv, sigma);
        assert!((inlier / 0.25 - 1.0).abs() < 0.05, "{inlier}");
        assert!((outlier / 25.0 - 1.0).abs() < 0.01, "{outlier}");
        // monotone in |nu| between the two
        let mut last = 0.0;
        for k in 0..40 {
            let v = mix.local_variance(0.5 * k as f64 * sigma, pv, sigma);
            assert!(v >= last && (0.25..=25.0).contains(&v), "{k}: {v}");
            last = v;
        }
        // Student-t: sigma^2 (dof + nu^2 / (sigma^2 + pv)) / (dof + 1)
        let t = NoiseModel::StudentT { dof: 4.0 };
        let nu = 1.5;
        let want = 0.25 * (4.0 + nu * nu / (0.25 + pv)) / 5.0;
        assert!((t.local_variance(nu, pv, sigma) - want).abs() < 1e-15);
    }
}
