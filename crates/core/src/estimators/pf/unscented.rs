//! The unscented proposal of the UPF and the CGA-PF: each particle drawn from the UKF
//! update of a Gaussian around its transition mean ([`Unscented::draw`]); with one
//! covariance for every particle, the shared-factor algebra of [`SharedPrior`] in
//! whitened coordinates, 16 particles at a time ([`Unscented::run_shared_block`]).

use super::likelihood::Likelihood;
use super::params::{bandwidth, Kernel};
use super::rng::{gauss6, PfRng};
use super::N;
use crate::estimators::ukf::{SharedPrior, Ukf, WhitenedBlock};
use crate::numerics::cholesky::{chol, chol_loaded, half_logdet, log_gauss_with, lower6};
use crate::numerics::simd;
use crate::numerics::soa::BLOCK;
use crate::numerics::symmetrize;
use crate::numerics::vlog::{is_normal_pos, ln_normal, ln_pos};
use crate::sensors::{AngleTrig, MeasurementModel};
use crate::types::{Mat3, Mat6, State, Vec3};

/// The Gaussian around particle `i`'s transition mean that the unscented proposal updates
/// with the measurement: component `i` of the shrinkage kernel (see the [module
/// docs](super)).
pub(super) struct ShrinkKernel {
    pub(super) a: f64,
    /// `(1 - a) m-`
    pub(super) offset: State,
    pub(super) cov: Mat6,
    pub(super) l: Mat6,
    /// the Cholesky factor of `cov` the UKF's sigma points use (computed once for every
    /// particle; `None`: every particle's UKF step fails, as it would on its own)
    pub(super) ukf_l: Option<Mat6>,
}

impl ShrinkKernel {
    /// The kernel of the predictive `N(m-, P-)` with process noise `q` and `n` particles:
    /// `a = sqrt(1 - h^2)`, covariance `(1 - h^2) Q + h^2 P-`.
    pub(super) fn new(pred_mean: &State, pred_cov: &Mat6, q: &Mat6, n: usize) -> Option<Self> {
        let h2 = bandwidth(Kernel::Gaussian, n).powi(2);
        let a = (1.0 - h2).sqrt();
        let cov = symmetrize(&(q * (1.0 - h2) + pred_cov * h2));
        chol_loaded(&cov).map(|l| Self {
            a,
            offset: pred_mean * (1.0 - a),
            cov,
            l,
            ukf_l: cov.cholesky().map(|c| c.unpack()),
        })
    }
}

/// Everything the per-particle unscented proposal reads.
pub(super) struct Unscented<'a, M> {
    /// a copy of the filter's sigma-point machinery (no heap: fixed-size)
    pub(super) ukf: Ukf,
    pub(super) lik: &'a Likelihood<'a, M>,
    pub(super) sensor: &'a M,
    pub(super) r: Mat3,
    pub(super) z: Vec3,
    pub(super) kernel: Option<ShrinkKernel>,
    /// square root of `Q` (the literal proposal's transition density)
    pub(super) q_sqrt: Mat6,
    /// `half_logdet` of the factor the weights' `ln N(x; mu_i, .)` uses (the kernel's or
    /// `q_sqrt`: one for every particle)
    pub(super) prior_half_logdet: f64,
    pub(super) carry: bool,
    /// the shared-factor form of the UKF step, where every particle's UKF covariance is
    /// the one matrix (`None`: the per-particle UKF of [`Ukf::measurement_update`])
    pub(super) shared: Option<SharedDraw>,
    /// the angles of `z`
    pub(super) trig: AngleTrig,
}

/// The unscented proposal when every particle's UKF starts from one covariance
/// `P = L L^T` (the shrinkage kernel's; the literal proposal's `Q` when the covariances
/// are not carried): the UKF step of [`SharedPrior`] in `P`'s whitened coordinates,
/// `x = mu + L u`, `u = (step + M eps_(0..3), eps_(3..6))` with `eps ~ N(0, I)` (the
/// draw `m + L+ eps` with `L+ = L blockdiag(M, I)`, the same six normals in the same
/// order), and the weights' densities without a triangular solve per particle:
///
/// ```text
/// ln q(x)       = -|eps|^2 / 2 - ln det L - ln(M_00 M_11 M_22)
/// ln N(x; mu, .) = -|A u|^2 / 2 - ln det L_p,     A = L_p^-1 L (formed once; I when L_p = L)
/// ```
///
/// `L_p` the factor of the weights' prior density (the kernel's, or `sqrt Q`).
pub(super) struct SharedDraw {
    pub(super) prior: SharedPrior,
    /// `L_p^-1 L` (`None`: the identity)
    a: Option<Mat6>,
    /// `ln det L`
    half_logdet: f64,
    /// the covariance a particle must have for this path (the literal proposal, checked
    /// per particle; `None`: every particle, the kernel's)
    pc: Option<Mat6>,
}

impl SharedDraw {
    /// The shared form for UKF factor `l` and the weights' prior factor `prior_l`, with
    /// `ukf`'s sigma-point weights; `None` where it does not apply (every particle then
    /// takes the per-particle path).
    pub(super) fn new(ukf: &Ukf, l: &Mat6, prior_l: &Mat6, pc: Option<Mat6>) -> Option<Self> {
        let a = if prior_l == l {
            None
        } else {
            Some(prior_l.solve_lower_triangular(l)?)
        };
        Some(Self {
            prior: ukf.shared_prior(l)?,
            a,
            half_logdet: half_logdet(l),
            pc,
        })
    }
}

impl<M: MeasurementModel> Unscented<'_, M> {
    /// Draw particle `i` from its UKF proposal: `(x, P_i, ln p(x|.) - ln q(x))`, `None`
    /// when the UKF step fails.
    pub(super) fn draw(
        &self,
        xbar: &State,
        pc: &Mat6,
        rng: &mut PfRng,
    ) -> Option<(State, Mat6, f64)> {
        if let Some(sd) = &self.shared {
            // (compared entry by entry without early exit, so that it vectorises: nalgebra's
            // `==` walks an iterator, and a slice `==` branches at every entry)
            if sd.pc.as_ref().is_none_or(|p| same_entries(p, pc)) {
                return self.draw_shared(sd, xbar, rng);
            }
        }
        let (mu, prior_l, update) = match &self.kernel {
            Some(k) => {
                let mu = xbar * k.a + k.offset;
                let u = self.ukf.measurement_update_factored(
                    &mu,
                    &k.cov,
                    k.ukf_l.as_ref()?,
                    self.sensor,
                    &self.r,
                    &self.z,
                );
                (mu, &k.l, u)
            }
            None => (
                *xbar,
                &self.q_sqrt,
                self.ukf
                    .measurement_update(xbar, pc, self.sensor, &self.r, &self.z),
            ),
        };
        let (m, p, _) = update.ok()?;
        let l = chol(&p)?;
        let eps = gauss6(rng);
        let x = m + l * eps;
        let half_logdet: f64 = (0..N).map(|k| l[(k, k)].ln()).sum();
        let log_q = -0.5 * eps.norm_squared() - half_logdet;
        let pc_new = if self.carry { p } else { Mat6::zeros() };
        Some((
            x,
            pc_new,
            log_gauss_with(&x, &mu, prior_l, self.prior_half_logdet) - log_q,
        ))
    }

    /// [`Unscented::draw`] by the shared-factor algebra ([`SharedDraw`]).
    fn draw_shared(
        &self,
        sd: &SharedDraw,
        xbar: &State,
        rng: &mut PfRng,
    ) -> Option<(State, Mat6, f64)> {
        let mu = match &self.kernel {
            Some(k) => xbar * k.a + k.offset,
            None => *xbar,
        };
        let wu = sd
            .prior
            .update(&mu, self.sensor, &self.r, &self.z, &self.trig)
            .ok()?;
        let eps = gauss6(rng);
        let m = &wu.m;
        let u = State::new(
            wu.step.x + m[(0, 0)] * eps[0],
            wu.step.y + m[(1, 0)] * eps[0] + m[(1, 1)] * eps[1],
            wu.step.z + m[(2, 0)] * eps[0] + m[(2, 1)] * eps[1] + m[(2, 2)] * eps[2],
            eps[3],
            eps[4],
            eps[5],
        );
        let x = mu + sd.prior.factor() * u;
        let log_q =
            -0.5 * eps.norm_squared() - sd.half_logdet - ln_pos(m[(0, 0)] * m[(1, 1)] * m[(2, 2)]);
        let up = sd.a.as_ref().map_or(u, |a| a * u);
        let log_p = -0.5 * up.norm_squared() - self.prior_half_logdet;
        let pc_new = if self.carry {
            let f = wu.factor(&sd.prior);
            f * f.transpose()
        } else {
            Mat6::zeros()
        };
        Some((x, pc_new, log_p - log_q))
    }

    /// [`Unscented::run`] on one block of at most [`BLOCK`] particles by the shared-factor
    /// algebra (covariances not carried), in structure-of-arrays form: the particles'
    /// whitened updates at once ([`SharedPrior::update_block`], lanes outside its fast path
    /// redone by [`SharedPrior::update`]), then the normals particle by particle in the
    /// old order (a particle whose update fails draws none, a particle whose covariance
    /// is not the shared one takes [`Unscented::draw`]), then the draws `x = mu + L u`
    /// and both log-densities at once, and the likelihoods by [`Likelihood::log_many`].
    /// The same operations in the same order per particle as [`Unscented::draw_shared`]
    /// and [`Likelihood::log`], so the same bits (tested); the arithmetic loops run in
    /// [`simd::dispatch`].
    #[allow(clippy::too_many_arguments, clippy::needless_range_loop)]
    fn run_shared_block(
        &self,
        sd: &SharedDraw,
        x: &[State],
        xbar: &[State],
        pc: &[Mat6],
        logw: &[f64],
        x_new: &mut [State],
        pc_new: &mut [Mat6],
        logw_new: &mut [f64],
        loglik: &mut [f64],
        rng: &mut PfRng,
        wb: &mut WhitenedBlock<BLOCK>,
    ) {
        let n = x.len();
        debug_assert!(n <= BLOCK);
        // transition means, transposed, and the shrinkage kernel's centres
        let mut mu = [[0.0; BLOCK]; N];
        for (i, xb) in xbar.iter().enumerate() {
            for k in 0..N {
                mu[k][i] = xb[k];
            }
        }
        if let Some(kn) = &self.kernel {
            let (a, off) = (kn.a, kn.offset);
            for k in 0..N {
                for i in 0..BLOCK {
                    mu[k][i] = mu[k][i] * a + off[k];
                }
            }
        }
        let c = [mu[0], mu[1], mu[2]];
        simd::dispatch(
            #[inline(always)]
            || {
                sd.prior
                    .update_block(&c, self.sensor, &self.r, &self.z, &self.trig, wb)
            },
        );
        // lane by lane in order: the per-particle fallbacks and the normals
        let mut eps = [[0.0; BLOCK]; N];
        // 0: failed (no draw), 1: the shared draw, 2: `draw`'s own result (in `x_new`)
        let mut lane = [0u8; BLOCK];
        let mut own_corr = [0.0; BLOCK];
        for i in 0..n {
            let eligible = sd.pc.as_ref().is_none_or(|p| same_entries(p, &pc[i]));
            if !eligible {
                if let Some((xi, _, corr)) = self.draw(&xbar[i], &pc[i], rng) {
                    x_new[i] = xi;
                    own_corr[i] = corr;
                    lane[i] = 2;
                }
                continue;
            }
            if !wb.fast[i] {
                let m = State::from_fn(|k, _| mu[k][i]);
                match sd
                    .prior
                    .update(&m, self.sensor, &self.r, &self.z, &self.trig)
                {
                    Ok(wu) => {
                        for k in 0..3 {
                            wb.step[k][i] = wu.step[k];
                        }
                        let ml = lower6(&wu.m);
                        for k in 0..6 {
                            wb.m[k][i] = ml[k];
                        }
                    }
                    Err(_) => continue,
                }
            }
            let e = gauss6(rng);
            for k in 0..N {
                eps[k][i] = e[k];
            }
            lane[i] = 1;
        }
        // the draws and the densities (without the logarithm), every lane
        let l = sd.prior.factor();
        let mut xs = [[0.0; BLOCK]; N];
        let (mut prod, mut ln_prod) = ([0.0; BLOCK], [0.0; BLOCK]);
        let mut log_p = [0.0; BLOCK];
        let mut half_e2 = [0.0; BLOCK];
        let (hl, phl) = (sd.half_logdet, self.prior_half_logdet);
        simd::dispatch(
            #[inline(always)]
            || {
                for i in 0..BLOCK {
                    let (st, m) = (&wb.step, &wb.m);
                    let e: [f64; N] = core::array::from_fn(|k| eps[k][i]);
                    let u = [
                        st[0][i] + m[0][i] * e[0],
                        st[1][i] + m[1][i] * e[0] + m[3][i] * e[1],
                        st[2][i] + m[2][i] * e[0] + m[4][i] * e[1] + m[5][i] * e[2],
                        e[3],
                        e[4],
                        e[5],
                    ];
                    // `mu + L u`, L lower triangular, in nalgebra's column order
                    for r in 0..N {
                        let mut y = l[(r, 0)] * u[0];
                        for j in 1..=r {
                            y += l[(r, j)] * u[j];
                        }
                        xs[r][i] = mu[r][i] + y;
                    }
                    // `|A u|^2` (A = I: `|u|^2`), summed from zero as nalgebra does
                    let up: [f64; N] = match &sd.a {
                        Some(a) => core::array::from_fn(|r| {
                            let mut y = a[(r, 0)] * u[0];
                            for j in 1..N {
                                y += a[(r, j)] * u[j];
                            }
                            y
                        }),
                        None => u,
                    };
                    let mut s = 0.0;
                    for v in up {
                        s += v * v;
                    }
                    log_p[i] = -0.5 * s - phl;
                    let mut s = 0.0;
                    for v in e {
                        s += v * v;
                    }
                    half_e2[i] = -0.5 * s - hl;
                    prod[i] = m[0][i] * m[3][i] * m[5][i];
                }
                for i in 0..BLOCK {
                    ln_prod[i] = ln_normal(prod[i]);
                }
            },
        );
        // in a dispatch: the AVX2 path zeroes each covariance slot (not carried) inline,
        // nine 32-byte stores, where the baseline calls `memset` per particle
        simd::dispatch(
            #[inline(always)]
            || {
                for i in 0..n {
                    match lane[i] {
                        1 => {
                            x_new[i] = State::from_fn(|k, _| xs[k][i]);
                            // `ln_pos` (as `draw_shared`), its rare libm lanes here
                            let lp = if is_normal_pos(prod[i]) {
                                ln_prod[i]
                            } else {
                                prod[i].ln()
                            };
                            let log_q = half_e2[i] - lp;
                            own_corr[i] = log_p[i] - log_q;
                        }
                        2 => {}
                        _ => {
                            x_new[i] = x[i];
                            own_corr[i] = 0.0;
                        }
                    }
                    pc_new[i] = Mat6::zeros();
                }
            },
        );
        let mut ll = [0.0; BLOCK];
        self.lik.log_many(x_new, &mut ll[..n]);
        for i in 0..n {
            logw_new[i] = logw[i] + ll[i] + own_corr[i];
            loglik[i] = ll[i];
        }
    }

    /// The proposals of a run of particles: new particles, covariances, log-weights and
    /// log-likelihoods into the spare buffers.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn run(
        &self,
        x: &[State],
        xbar: &[State],
        pc: &[Mat6],
        logw: &[f64],
        x_new: &mut [State],
        pc_new: &mut [Mat6],
        logw_new: &mut [f64],
        loglik: &mut [f64],
        rng: &mut PfRng,
    ) {
        if let (Some(sd), false) = (&self.shared, self.carry) {
            let mut wb = WhitenedBlock::<BLOCK>::default();
            for (b, xs) in x.chunks(BLOCK).enumerate() {
                let r = b * BLOCK..b * BLOCK + xs.len();
                self.run_shared_block(
                    sd,
                    xs,
                    &xbar[r.clone()],
                    &pc[r.clone()],
                    &logw[r.clone()],
                    &mut x_new[r.clone()],
                    &mut pc_new[r.clone()],
                    &mut logw_new[r.clone()],
                    &mut loglik[r],
                    rng,
                    &mut wb,
                );
            }
            return;
        }
        for i in 0..x.len() {
            let (xi, pci, corr) = match self.draw(&xbar[i], &pc[i], rng) {
                Some(d) => d,
                // without carrying, every covariance starts afresh at the next prediction
                None => (x[i], if self.carry { pc[i] } else { Mat6::zeros() }, 0.0),
            };
            let ll = self.lik.log(&xi);
            x_new[i] = xi;
            pc_new[i] = pci;
            logw_new[i] = logw[i] + ll + corr;
            loglik[i] = ll;
        }
    }
}

/// `a == b` entry by entry (IEEE `==`: a NaN differs from everything, `0 == -0`), all 36
/// comparisons and-ed without an early exit so that they vectorise: the UPF's test whether
/// a particle's covariance is the shared one, once per particle.
#[inline(always)]
fn same_entries(a: &Mat6, b: &Mat6) -> bool {
    a.as_slice()
        .iter()
        .zip(b.as_slice())
        .fold(true, |all, (x, y)| all & (x == y))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::estimators::ukf::UkfParams;
    use crate::noise::NoiseModel;
    use crate::numerics::eigen::psd_sqrt;
    use rand::{Rng, SeedableRng};

    /// The unscented proposal's shared-factor blocks ([`Unscented::run_shared_block`])
    /// equal the particle-by-particle path ([`Unscented::draw`] and [`Likelihood::log`])
    /// bit for bit, with the same normals drawn in the same order, on the dispatched and the
    /// baseline path: the shrinkage kernel and the literal proposal (some particles with
    /// another covariance: `draw`'s per-particle UKF), particles in the series domain,
    /// far off (the per-particle fallback), on the pole and at zero range (failures), a
    /// short last block, in every frame.
    #[test]
    fn shared_blocks_equal_the_per_particle_proposal() {
        use crate::numerics::simd::with_baseline;
        use crate::sensors::RadioSensor;
        let mut g = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let q = Mat6::from_diagonal(&State::new(0.09, 6.25e-4, 2.5e-3, 1e-6, 1e-6, 1e-6));
        let (mut fast_lanes, mut wide_lanes) = (0, 0);
        for frame in crate::frames::Frame::ALL {
            let s = RadioSensor::new(frame, 0.5, 1e-3);
            let c = frame.vec_to_canonical(&Vec3::new(400.0, 500.0, -200.0));
            let z = s.predict(&c).expect("defined") + Vec3::new(0.2, -1e-3, 3e-3);
            let noise = NoiseModel::Gaussian;
            let lik = Likelihood::new(&s, &z, &noise, &[0.5, 1e-3, 1e-3]);
            let n = 403;
            let x: Vec<State> = (0..n)
                .map(|k| {
                    let mut v = State::from_fn(|i, _| {
                        g.random_range(-1.0..1.0) * if i < 3 { 3.0 } else { 0.01 }
                    });
                    let pole = frame.vec_to_canonical(&Vec3::new(0.0, 0.0, 300.0));
                    let base = match k % 37 {
                        0 => {
                            v.fill(0.0);
                            Vec3::zeros()
                        }
                        1 => {
                            v.fixed_rows_mut::<3>(0).fill(0.0);
                            pole
                        }
                        2 => c * 1.5,
                        3 => Vec3::zeros(),
                        // off the measurement by about 0.06 rad across and along the
                        // horizon (innovation angles beyond the series' 2^-5)
                        4 => c + c.cross(&Vec3::x()).normalize() * 40.0,
                        5 => c + c.cross(&Vec3::z()).normalize() * 40.0,
                        _ => c,
                    };
                    for i in 0..3 {
                        v[i] += base[i];
                    }
                    v
                })
                .collect();
            let mean = x.iter().sum::<State>() / n as f64;
            let pred_cov = Mat6::from_diagonal(&State::new(4.0, 4.0, 4.0, 1e-4, 1e-4, 1e-4));
            let ukf = Ukf::new(State::zeros(), Mat6::identity(), UkfParams::default());
            let q_sqrt = psd_sqrt(&q).expect("PSD");
            let pq = q.cholesky().expect("PD").unpack();
            for literal in [false, true] {
                let kernel = if literal {
                    None
                } else {
                    Some(ShrinkKernel::new(&mean, &pred_cov, &q, n).expect("PD"))
                };
                let shared = match &kernel {
                    Some(k) => SharedDraw::new(&ukf, &k.ukf_l.expect("PD"), &k.l, None),
                    None => SharedDraw::new(&ukf, &pq, &q_sqrt, Some(q)),
                };
                let u = Unscented {
                    ukf,
                    lik: &lik,
                    sensor: &s,
                    r: s.noise_cov(),
                    z,
                    prior_half_logdet: half_logdet(kernel.as_ref().map_or(&q_sqrt, |k| &k.l)),
                    kernel,
                    q_sqrt,
                    carry: false,
                    shared,
                    trig: AngleTrig::of(&z),
                };
                let sd = u.shared.as_ref().expect("the shared form applies");
                // the literal proposal: every fifth particle with another covariance
                let pc: Vec<Mat6> = (0..n)
                    .map(|k| if literal && k % 5 == 0 { q * 2.0 } else { q })
                    .collect();
                let logw: Vec<f64> = (0..n).map(|k| -(k as f64) * 1e-3).collect();
                let rng0 = PfRng::seed_from_u64(9);
                // the per-particle reference
                let mut rng = rng0.clone();
                let mut want = Vec::new();
                for i in 0..n {
                    let (xi, corr) = match u.draw(&x[i], &pc[i], &mut rng) {
                        Some((xi, _, corr)) => (xi, corr),
                        None => (x[i], 0.0),
                    };
                    let ll = lik.log(&xi);
                    want.push((xi, logw[i] + ll + corr, ll));
                }
                let after = rng.random::<u64>();
                let run = || {
                    let mut rng = rng0.clone();
                    let mut xn = vec![State::zeros(); n];
                    let mut pcn = vec![Mat6::identity(); n];
                    let (mut lwn, mut ll) = (vec![0.0; n], vec![0.0; n]);
                    u.run(
                        &x, &x, &pc, &logw, &mut xn, &mut pcn, &mut lwn, &mut ll, &mut rng,
                    );
                    assert!(pcn.iter().all(|p| *p == Mat6::zeros()));
                    (xn, lwn, ll, rng.random::<u64>())
                };
                for (xn, lwn, ll, next) in [run(), with_baseline(run)] {
                    assert_eq!(next, after, "the same normals are drawn");
                    for i in 0..n {
                        let (wx, wlw, wll) = &want[i];
                        let same = xn[i]
                            .iter()
                            .zip(wx.iter())
                            .all(|(a, b)| a.to_bits() == b.to_bits());
                        assert!(same, "{frame:?} {literal} {i}: {} {}", xn[i], wx);
                        assert_eq!(lwn[i].to_bits(), wlw.to_bits(), "{frame:?} {literal} {i}");
                        assert_eq!(ll[i].to_bits(), wll.to_bits(), "{frame:?} {literal} {i}");
                    }
                }
                // most particles take the block's fast path
                let mut wb = WhitenedBlock::<BLOCK>::default();
                for (b, xs) in x.chunks(BLOCK).enumerate() {
                    let mut cb = [[0.0; BLOCK]; 3];
                    for (i, xi) in xs.iter().enumerate() {
                        let m = u.kernel.as_ref().map_or(*xi, |k| xi * k.a + k.offset);
                        (cb[0][i], cb[1][i], cb[2][i]) = (m[0], m[1], m[2]);
                    }
                    sd.prior.update_block(&cb, &s, &u.r, &z, &u.trig, &mut wb);
                    fast_lanes += wb.fast[..xs.len()].iter().filter(|f| **f).count();
                    // the particles off the measurement by 0.06 rad stay in the block
                    for (i, f) in wb.fast[..xs.len()].iter().enumerate() {
                        if matches!((b * BLOCK + i) % 37, 4 | 5) {
                            assert!(*f, "{frame:?} {literal} {i}");
                            wide_lanes += 1;
                        }
                    }
                }
            }
        }
        assert!(fast_lanes > 3 * 2 * 403 * 8 / 10, "{fast_lanes}");
        assert!(wide_lanes >= 3 * 2 * 2 * 10, "{wide_lanes}");
    }
}
