//! The measurement likelihood the particle filters weigh with: a particle's
//! `ln p(z | x)` under the sensor's noise density ([`Likelihood::log`]), and the same for
//! blocks of particles in structure-of-arrays form through the sensor's vectorised
//! residuals ([`Likelihood::log_many`], [`Likelihood::weigh_many`]: the same bits).

use super::N;
use crate::noise::NoiseModel;
use crate::numerics::simd;
use crate::numerics::soa::BLOCK;
use crate::sensors::{AngleTrig, MeasurementModel, Sensor, SensorNoise};
use crate::types::{State, Vec3};
use nalgebra::{SMatrix, SVector};

/// What the particle filters' moves need of a measurement's likelihood (`D` its
/// components): `ln p(z | x)` of one particle, of a run of particles and of a block of
/// candidates in structure-of-arrays form, and the linearisation and local noise variances
/// of the Gaussian proposal of the rejuvenation. [`Likelihood`] is the radio's (its
/// vectorised residuals), [`SensorLikelihood`] any [`Sensor`]'s.
pub(super) trait ParticleLikelihood<const D: usize>: Sync {
    /// `ln p(z | x)` up to a constant, `-inf` where the measurement is undefined.
    fn log(&self, x: &State) -> f64;
    /// [`ParticleLikelihood::log`] of every particle of `x` into `out` (same length).
    fn log_many(&self, x: &[State], out: &mut [f64]);
    /// `ln p(z | c)` of the first `n` candidates of a block in structure-of-arrays form
    /// (`c[k][lane]`) into `ll` (the other lanes unspecified).
    fn log_soa(&self, c: &[[f64; BLOCK]; 6], n: usize, ll: &mut [f64; BLOCK]);
    /// The measurement linearised at `m0`: `H` and the innovation `z - h(m0)` (components
    /// not used: zero row and zero residual); `None` where it cannot be.
    fn linear(&self, m0: &State) -> Option<(SMatrix<f64, D, 6>, SVector<f64, D>)>;
    /// The variance of the Gaussian that stands in for component `k`'s noise at the
    /// innovation `nu` with predicted variance `pred_var` ([`NoiseModel::local_variance`]).
    fn local_variance(&self, k: usize, nu: f64, pred_var: f64) -> f64;
    /// The weighting pass of the transition-proposal kinds over a run of particles: the
    /// log-likelihoods into `ll`, the new log-weights `logw + ll` into `logw_new`, and
    /// their maximum (NaN ignored, `-inf` if there is none). `soa`: the particles
    /// transposed by blocks (the filter's `soa`), for a likelihood that reads them there.
    /// Default: [`ParticleLikelihood::log`] particle by particle.
    fn weigh_many(
        &self,
        x: &[State],
        soa: Option<&[[[f64; BLOCK]; N]]>,
        logw: &[f64],
        logw_new: &mut [f64],
        ll: &mut [f64],
    ) -> f64 {
        let _ = soa;
        let mut max = f64::NEG_INFINITY;
        for ((xi, lli), (lw, lwn)) in x.iter().zip(ll).zip(logw.iter().zip(logw_new)) {
            *lli = self.log(xi);
            *lwn = lw + *lli;
            // `if l > m` keeps `m` for a NaN `l`
            max = if *lwn > max { *lwn } else { max };
        }
        max
    }
}

/// The likelihood of any [`Sensor`]'s measurement `z` ([`Sensor::log_likelihood`]: its own
/// noise density unless the sensor says otherwise); `noise` for the rejuvenation's local
/// variances.
pub(super) struct SensorLikelihood<'a, S: ?Sized, const D: usize> {
    pub(super) sensor: &'a S,
    pub(super) z: SVector<f64, D>,
    pub(super) noise: SensorNoise<D>,
}

impl<const D: usize, S: Sensor<D> + ?Sized> ParticleLikelihood<D> for SensorLikelihood<'_, S, D> {
    fn log(&self, x: &State) -> f64 {
        self.sensor.log_likelihood(&self.z, x)
    }
    fn log_many(&self, x: &[State], out: &mut [f64]) {
        for (xi, o) in x.iter().zip(out.iter_mut()) {
            *o = self.log(xi);
        }
    }
    fn log_soa(&self, c: &[[f64; BLOCK]; 6], n: usize, ll: &mut [f64; BLOCK]) {
        for (i, l) in ll.iter_mut().enumerate().take(n) {
            *l = self.log(&State::from_fn(|k, _| c[k][i]));
        }
    }
    fn linear(&self, m0: &State) -> Option<(SMatrix<f64, D, 6>, SVector<f64, D>)> {
        let (lin, nu) = self.sensor.innovation(m0, &self.z).ok()?;
        Some((lin.h, nu))
    }
    fn local_variance(&self, k: usize, nu: f64, pred_var: f64) -> f64 {
        self.noise
            .model
            .local_variance(nu, pred_var, self.noise.scales[k])
    }
}

/// The measurement likelihood a particle filter weighs with.
pub(super) struct Likelihood<'a, M> {
    pub(super) sensor: &'a M,
    pub(super) z: Vec3,
    pub(super) noise: &'a NoiseModel,
    pub(super) scales: [f64; 3],
    pub(super) gaussian: bool,
    /// `-0.5 / scale_k^2` (the Gaussian case)
    pub(super) neg_half_inv_var: [f64; 3],
    /// the angles' sines and cosines for [`MeasurementModel::residual_at`]
    pub(super) trig: AngleTrig,
}

impl<'a, M: MeasurementModel> Likelihood<'a, M> {
    pub(super) fn new(sensor: &'a M, z: &Vec3, noise: &'a NoiseModel, scales: &[f64; 3]) -> Self {
        Self {
            sensor,
            z: *z,
            noise,
            scales: *scales,
            gaussian: matches!(noise, NoiseModel::Gaussian),
            neg_half_inv_var: scales.map(|s| -0.5 / (s * s)),
            trig: AngleTrig::of(z),
        }
    }

    /// `ln p(z | x)` up to a constant: `-0.5 sum d_k^2 / sigma_k^2` for Gaussian noise, the
    /// noise model's log-density per component otherwise; `-inf` where `z` is undefined.
    pub(super) fn log(&self, x: &State) -> f64 {
        let r = x.fixed_rows::<3>(0).into_owned();
        let Some(d) = self.sensor.residual_at(&self.z, &self.trig, &r) else {
            return f64::NEG_INFINITY;
        };
        if self.gaussian {
            let c = &self.neg_half_inv_var;
            c[0] * d.x * d.x + c[1] * d.y * d.y + c[2] * d.z * d.z
        } else {
            (0..3)
                .map(|k| self.noise.log_density(d[k], self.scales[k]))
                .sum()
        }
    }
}

impl<M: MeasurementModel> ParticleLikelihood<3> for Likelihood<'_, M> {
    #[inline(always)]
    fn log(&self, x: &State) -> f64 {
        Likelihood::log(self, x)
    }
    fn log_many(&self, x: &[State], out: &mut [f64]) {
        Likelihood::log_many(self, x, out)
    }
    /// Through the sensor's vectorised residuals ([`MeasurementModel::residuals_at`]).
    #[inline(always)]
    fn log_soa(&self, c: &[[f64; BLOCK]; 6], n: usize, ll: &mut [f64; BLOCK]) {
        let r = [c[0], c[1], c[2]];
        let mut d = [[0.0; BLOCK]; 3];
        let mut ok = [false; BLOCK];
        self.log_block_soa(&r, n, &mut d, &mut ok, ll);
    }
    fn linear(&self, m0: &State) -> Option<(SMatrix<f64, 3, 6>, Vec3)> {
        let g = self
            .sensor
            .linearize(&m0.fixed_rows::<3>(0).into_owned())
            .ok()?;
        Some((g.h, self.sensor.linearised_residual(&self.z, &g)))
    }
    fn local_variance(&self, k: usize, nu: f64, pred_var: f64) -> f64 {
        self.noise.local_variance(nu, pred_var, self.scales[k])
    }
    /// Through the vectorised residuals, reading the positions from `soa` when given
    /// ([`Likelihood::weigh_many`]).
    fn weigh_many(
        &self,
        x: &[State],
        soa: Option<&[[[f64; BLOCK]; N]]>,
        logw: &[f64],
        logw_new: &mut [f64],
        ll: &mut [f64],
    ) -> f64 {
        Likelihood::weigh_many(self, x, soa, logw, logw_new, ll)
    }
}

impl<M: MeasurementModel> Likelihood<'_, M> {
    /// [`Likelihood::log`] of every particle of `x` into `out` (same length), block by
    /// block in structure-of-arrays form ([`MeasurementModel::residuals_at`]): the same
    /// values as `log` particle by particle, bit for bit.
    pub(super) fn log_many(&self, x: &[State], out: &mut [f64]) {
        crate::numerics::simd::dispatch(
            #[inline(always)]
            || self.log_many_inline(x, out),
        )
    }

    /// [`Likelihood::log_many`]'s body, inlined into its [`crate::numerics::simd::dispatch`].
    #[inline(always)]
    fn log_many_inline(&self, x: &[State], out: &mut [f64]) {
        let mut r = [[0.0; BLOCK]; 3];
        let mut d = [[0.0; BLOCK]; 3];
        let mut ok = [false; BLOCK];
        let mut ll = [0.0; BLOCK];
        for (xs, os) in x.chunks(BLOCK).zip(out.chunks_mut(BLOCK)) {
            self.log_block(xs, &mut r, &mut d, &mut ok, &mut ll);
            os.copy_from_slice(&ll[..os.len()]);
        }
    }

    /// The log-likelihoods of a block of at most [`BLOCK`] particles `xs` into
    /// `ll[..xs.len()]` (the positions transposed into `r`, the residuals into `d`; the
    /// other lanes of `ll` are not meaningful).
    #[inline(always)]
    fn log_block(
        &self,
        xs: &[State],
        r: &mut [[f64; BLOCK]; 3],
        d: &mut [[f64; BLOCK]; 3],
        ok: &mut [bool; BLOCK],
        ll: &mut [f64; BLOCK],
    ) {
        for (i, xi) in xs.iter().enumerate() {
            (r[0][i], r[1][i], r[2][i]) = (xi[0], xi[1], xi[2]);
        }
        self.log_block_soa(r, xs.len(), d, ok, ll);
    }

    /// [`Likelihood::log_block`] of a block of `n` particles whose positions are already
    /// transposed into `r` (the same values).
    #[inline(always)]
    fn log_block_soa(
        &self,
        r: &[[f64; BLOCK]; 3],
        n: usize,
        d: &mut [[f64; BLOCK]; 3],
        ok: &mut [bool; BLOCK],
        ll: &mut [f64; BLOCK],
    ) {
        self.sensor.residuals_at(&self.z, &self.trig, r, n, d, ok);
        if self.gaussian {
            let c = &self.neg_half_inv_var;
            for (i, l) in ll.iter_mut().enumerate() {
                let v = c[0] * d[0][i] * d[0][i] + c[1] * d[1][i] * d[1][i];
                let v = v + c[2] * d[2][i] * d[2][i];
                *l = if ok[i] { v } else { f64::NEG_INFINITY };
            }
        } else {
            for (i, o) in ll.iter_mut().enumerate().take(n) {
                *o = if ok[i] {
                    (0..3)
                        .map(|k| self.noise.log_density(d[k][i], self.scales[k]))
                        .sum()
                } else {
                    f64::NEG_INFINITY
                };
            }
        }
    }

    /// The update pass of the transition-proposal kinds over a run of particles: the
    /// log-likelihoods `ll_i` ([`Likelihood::log`]'s bits) into `ll`, the new log-weights
    /// `l_i = logw_i + ll_i` into `logw_new`, and their maximum (NaN ignored, `-inf` if
    /// there is none; in four interleaved partial maxima per block). Run through
    /// [`simd::dispatch`]. With `soa` (`x` by blocks of [`BLOCK`], transposed: the
    /// filter's `soa`) the positions are read from it instead of transposed from `x`: the
    /// same values.
    pub(super) fn weigh_many(
        &self,
        x: &[State],
        soa: Option<&[[[f64; BLOCK]; N]]>,
        logw: &[f64],
        logw_new: &mut [f64],
        ll: &mut [f64],
    ) -> f64 {
        simd::dispatch(
            #[inline(always)]
            || self.weigh_many_inline(x, soa, logw, logw_new, ll),
        )
    }

    /// [`Likelihood::weigh_many`]'s body, inlined into its [`simd::dispatch`].
    #[inline(always)]
    fn weigh_many_inline(
        &self,
        x: &[State],
        soa: Option<&[[[f64; BLOCK]; N]]>,
        logw: &[f64],
        logw_new: &mut [f64],
        ll: &mut [f64],
    ) -> f64 {
        let mut r = [[0.0; BLOCK]; 3];
        let mut d = [[0.0; BLOCK]; 3];
        let mut ok = [false; BLOCK];
        let mut llb = [0.0; BLOCK];
        let mut mx = [f64::NEG_INFINITY; 4];
        let blocks = x
            .chunks(BLOCK)
            .zip(logw.chunks(BLOCK))
            .zip(logw_new.chunks_mut(BLOCK))
            .zip(ll.chunks_mut(BLOCK));
        for (b, (((xs, lw), lwn), lls)) in blocks.enumerate() {
            let n = xs.len();
            let pos = soa
                .and_then(|p| p.get(b))
                .and_then(|sb| <&[[f64; BLOCK]; 3]>::try_from(&sb[..3]).ok());
            match pos {
                Some(rb) => self.log_block_soa(rb, n, &mut d, &mut ok, &mut llb),
                None => self.log_block(xs, &mut r, &mut d, &mut ok, &mut llb),
            }
            let mut l = [f64::NEG_INFINITY; BLOCK];
            for ((li, a), b) in l.iter_mut().zip(lw).zip(&llb) {
                *li = a + b;
            }
            lwn.copy_from_slice(&l[..n]);
            lls.copy_from_slice(&llb[..n]);
            for b in l.chunks_exact(4) {
                for (m, &v) in mx.iter_mut().zip(b) {
                    // `if l > m` keeps `m` for a NaN `l` (as max_ignoring_nan)
                    *m = if v > *m { v } else { *m };
                }
            }
        }
        mx.iter()
            .fold(f64::NEG_INFINITY, |m, &v| if v > m { v } else { m })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::estimators::pf::tests::test_cloud;

    /// The block likelihood equals the particle-by-particle one bit for bit (Gaussian and
    /// heavy-tailed noise, undefined positions, a short last block).
    #[test]
    fn block_likelihood_equals_scalar() {
        use crate::sensors::RadioSensor;
        let s = RadioSensor::new(crate::frames::Frame::AlongRadialAntinormal, 0.5, 1e-4);
        let c = Vec3::new(400.0, 500.0, -200.0);
        let z = s.predict(&c).expect("defined") + Vec3::new(0.2, -1e-4, 3e-4);
        let x = test_cloud(&c);
        for noise in [NoiseModel::Gaussian, NoiseModel::StudentT { dof: 4.0 }] {
            let lik = Likelihood::new(&s, &z, &noise, &[0.5, 1e-4, 1e-4]);
            let mut out = vec![0.0; x.len()];
            lik.log_many(&x, &mut out);
            for (xi, o) in x.iter().zip(&out) {
                assert_eq!(o.to_bits(), lik.log(xi).to_bits(), "{xi:?}");
            }
        }
    }
}
