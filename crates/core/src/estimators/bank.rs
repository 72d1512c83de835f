//! Range-parameterised bank: a Gaussian sum over the range along the prior's line of sight,
//! one Kalman-type filter per term (Peach's range-parameterised EKF, 1995, with its members
//! split from a Gaussian prior instead of spread over a range interval).
//!
//! Why: with angles only (a camera) the range is unobservable until the chaser manoeuvres,
//! and one Cartesian filter linearised at a range that is 30 % off takes the burns' angle
//! changes with the wrong sensitivity (`1 / r`): its range collapses too early and it ends
//! far from the bound, claiming more than it knows. Each member of the bank starts with a
//! fraction of the prior's range spread, so its linearisation holds; the measurements pick
//! the members that fit.
//!
//! The prior `N(x, P)` is split along `u`, the unit vector of its mean position (the line of
//! sight from the target). With `rho = u^T r`, `sigma^2 = Var(rho)` and `c = Cov(x, rho)`,
//! `rho`'s Gaussian is written as `sum_k w_k N(mu + sigma d_k, s^2 sigma^2)` with the
//! Gauss-Hermite nodes `d_k / sqrt(1 - s^2)` and weights `w_k` of `n` points, and every
//! member is the conditional Gaussian of its term:
//!
//! ```text
//!     x_k = x + c d_k / sigma,        P_k = P - (1 - s^2) c c^T / sigma^2
//! ```
//!
//! The mixture's moments equal the prior's up to order `2n - 1` along `u` (the rule is exact
//! for polynomials of that degree) and its mean and covariance exactly; `s` =
//! [`MEMBER_SPREAD`].
//!
//! Each update multiplies a member's weight by the Gaussian density of its innovation,
//! `N(z - h(x_k); 0, H_k P_k H_k^T + R)`, linearised at the member's own prior whatever
//! the member's kind (the same likelihood for EKF, UKF, AQUKF and IMM members), then
//! updates the member. Members are not mixed; the output is the mixture's mean and
//! covariance. A member whose weight falls below [`DROP_RATIO`] of the largest, or whose
//! update or prediction fails, is dropped and not stepped again; the bank fails (and is
//! unchanged) only when every remaining member fails. Every member is allocated at
//! construction: a step allocates nothing.
//!
//! The same machinery runs the particle filters' particle prior ([`Bank::gaussian_sum`]):
//! any number of members drawn from the prior's kernel density instead of the split, and
//! after each update the resampling and smoothing of [`super::pf::gaussian_sum`].

use super::pf::gaussian_sum::{Live, Resampling};
use super::pf::{PfParams, MAX_GAUSSIAN_SUM};
pub use super::MAX_BANK;
use super::{finite, Estimator, FilterError, SensorUpdate, UpdateInfo};
use crate::dynamics::DiscreteModel;
use crate::numerics::state::{refuse, Persist, Reader, StateError, Writer};
use crate::numerics::symmetrize;
use crate::sensors::{MeasurementModel, Sensor, Support};
use crate::types::{Mat3, Mat6, State, Vec3};
use nalgebra::{SMatrix, SVector};

/// Each member's standard deviation along the line of sight, as a fraction `s` of the
/// prior's.
pub const MEMBER_SPREAD: f64 = 0.5;

/// A member whose weight falls below this fraction of the largest is dropped.
pub const DROP_RATIO: f64 = 1e-12;

pub use super::Member;

/// The Gauss-Hermite rule of `n` points for the standard normal (nodes ascending, weights
/// summing to one): the eigenvalues of the Jacobi matrix of the probabilists' Hermite
/// polynomials and the squared first components of its eigenvectors (Golub and Welsch).
pub fn gauss_hermite(n: usize) -> Vec<(f64, f64)> {
    let j = nalgebra::DMatrix::<f64>::from_fn(n, n, |a, b| {
        if a + 1 == b || b + 1 == a {
            (a.max(b) as f64).sqrt()
        } else {
            0.0
        }
    });
    let e = j.symmetric_eigen();
    let mut rule: Vec<(f64, f64)> = (0..n)
        .map(|k| (e.eigenvalues[k], e.eigenvectors[(0, k)].powi(2)))
        .collect();
    rule.sort_by(|a, b| a.0.total_cmp(&b.0));
    let sum: f64 = rule.iter().map(|r| r.1).sum();
    for r in rule.iter_mut() {
        r.1 /= sum;
    }
    rule
}

/// The `n` weighted members' priors of `N(x, p)` (see the module docs); `None` when the
/// mean position is at the target (no line of sight) or `p` gives it no spread along it.
pub fn split(x: &State, p: &Mat6, n: usize) -> Option<Vec<(f64, State, Mat6)>> {
    let r = Vec3::new(x[0], x[1], x[2]);
    let norm = r.norm();
    if !(norm > 0.0 && norm.is_finite()) {
        return None;
    }
    let u = r / norm;
    let c: State = p.fixed_columns::<3>(0) * u;
    let var = u.dot(&c.fixed_rows::<3>(0));
    if !(var > 0.0 && var.is_finite()) {
        return None;
    }
    let sigma = var.sqrt();
    let shrink = (1.0 - MEMBER_SPREAD * MEMBER_SPREAD).sqrt();
    let pk = symmetrize(&(p - c * c.transpose() * ((1.0 - MEMBER_SPREAD.powi(2)) / var)));
    Some(
        gauss_hermite(n)
            .into_iter()
            .map(|(d, w)| (w, x + c * (d * shrink / sigma), pk))
            .collect(),
    )
}

/// `ln N(nu; 0, S)` without `-D/2 ln 2 pi`, and `S = H P H^T + R`; `None` unless `S` is
/// positive definite.
fn log_density<const D: usize>(
    h: &SMatrix<f64, D, 6>,
    nu: &SVector<f64, D>,
    r: &SMatrix<f64, D, D>,
    p: &Mat6,
) -> Option<(f64, SMatrix<f64, D, D>)> {
    gaussian_log_density(h * p * h.transpose() + r, nu)
}

/// [`log_density`] for a Jacobian whose only nonzero columns are the three from `OFF` (the
/// position, `OFF = 0`, or the velocity, `OFF = 3`; [`Support`]): `S` from that block and
/// `P`'s, without the products with the zero columns, which add nothing to its sums.
fn log_density_block<const D: usize, const OFF: usize>(
    h: &SMatrix<f64, D, 6>,
    nu: &SVector<f64, D>,
    r: &SMatrix<f64, D, D>,
    p: &Mat6,
) -> Option<(f64, SMatrix<f64, D, D>)> {
    let hb: SMatrix<f64, D, 3> = h.fixed_columns::<3>(OFF).into_owned();
    let pb: Mat3 = p.fixed_view::<3, 3>(OFF, OFF).into_owned();
    gaussian_log_density(hb * pb * hb.transpose() + r, nu)
}

/// `ln N(nu; 0, s)` without `-D/2 ln 2 pi`, and `s`; `None` unless `s` is positive
/// definite.
fn gaussian_log_density<const D: usize>(
    s: SMatrix<f64, D, D>,
    nu: &SVector<f64, D>,
) -> Option<(f64, SMatrix<f64, D, D>)> {
    let chol = s.cholesky()?;
    let ln_det: f64 = chol.l_dirty().diagonal().iter().map(|d| 2.0 * d.ln()).sum();
    let ll = -0.5 * (nu.dot(&chol.solve(nu)) + ln_det);
    ll.is_finite().then_some((ll, s))
}

/// A member's linearised innovation and its covariance at its prior, for the weights and
/// the bank's diagnostics.
type Predictive<const D: usize> = (f64, SVector<f64, D>, SMatrix<f64, D, D>);

/// The bank (see the module docs).
#[derive(Debug, Clone)]
pub struct Bank<F: Member> {
    members: Vec<F>,
    /// `ln` of the weights, the largest 0; `-inf` for a dropped member.
    log_w: Vec<f64>,
    /// `exp` of `log_w` where a sum over the members needs it twice (scratch)
    exp_w: Vec<f64>,
    x: State,
    p: Mat6,
    /// one operation's undo (the estimator's contract: unchanged on error)
    undo: Vec<F::Saved>,
    undo_w: Vec<f64>,
    /// a caller's checkpoint over several operations ([`Bank::checkpoint`])
    check: Vec<F::Saved>,
    check_w: Vec<f64>,
    check_xp: (State, Mat6),
    /// the particle prior's resampling ([`super::pf::gaussian_sum`]; `None`: the
    /// range-parameterised bank), with its copies of the members and its undo points
    resampling: Option<Resampling>,
    spare: Vec<F>,
    undo_live: Option<Live>,
    check_live: Option<Live>,
}

impl<F: Member> Bank<F> {
    /// `n` (2..=[`MAX_BANK`]) copies of `member` on the split of `(x0, p0)`; `None` when
    /// the prior cannot be split ([`split`]).
    pub fn new(member: F, x0: State, p0: Mat6, n: usize) -> Option<Self> {
        let mut bank = Self::of_copies(member, x0, p0, n.clamp(2, MAX_BANK), None);
        bank.start(x0, p0).then_some(bank)
    }

    /// The particle prior ([`super::pf::gaussian_sum`]): `params.particles` copies of
    /// `member` drawn from `(x0, p0)`, resampled and smoothed as `params` says.
    pub fn gaussian_sum(member: F, x0: State, p0: Mat6, params: &PfParams) -> Self {
        let n = params.particles.clamp(1, MAX_GAUSSIAN_SUM);
        let resampling = Resampling::new(params, n);
        let mut bank = Self::of_copies(member, x0, p0, n, Some(resampling));
        bank.start(x0, p0);
        bank
    }

    /// `n` copies of `member` and every buffer a step uses (the resampling's too), not yet
    /// started.
    fn of_copies(member: F, x0: State, p0: Mat6, n: usize, resampling: Option<Resampling>) -> Self {
        let saved = member.save();
        let live = resampling.as_ref().map(|r| r.live().clone());
        let spare = if resampling.is_some() {
            vec![member.clone(); n]
        } else {
            Vec::new()
        };
        Self {
            members: vec![member; n],
            log_w: vec![0.0; n],
            exp_w: vec![0.0; n],
            x: x0,
            p: p0,
            undo: vec![saved.clone(); n],
            undo_w: vec![0.0; n],
            check: vec![saved; n],
            check_w: vec![0.0; n],
            check_xp: (x0, p0),
            resampling,
            spare,
            undo_live: live.clone(),
            check_live: live,
        }
    }

    /// The particle prior's effective sample size after the last update and its
    /// resampling count (`None` for a range-parameterised bank).
    pub fn particle_stats(&self) -> Option<(f64, u64)> {
        self.resampling.as_ref().map(|r| (r.ess(), r.resamples()))
    }
}

impl<F: Member> Bank<F> {
    /// Every member reset to its part of the split of `(x, p)`; false (and nothing
    /// changed) when `(x, p)` cannot be split.
    fn start(&mut self, x: State, p: Mat6) -> bool {
        if let Some(r) = &mut self.resampling {
            r.draw(&mut self.members, &mut self.log_w, &x, &p);
            self.x = x;
            self.p = p;
            return true;
        }
        let Some(parts) = split(&x, &p, self.members.len()) else {
            return false;
        };
        for ((m, lw), (w, xk, pk)) in self.members.iter_mut().zip(&mut self.log_w).zip(parts) {
            m.reset(xk, pk);
            *lw = w.ln();
        }
        let top = self.log_w.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        self.log_w.iter_mut().for_each(|l| *l -= top);
        self.x = x;
        self.p = p;
        true
    }

    /// The particle prior as new: its generator reseeded and the terms drawn from `(x, p)`
    /// (a range-parameterised bank: [`Bank::reset`]).
    pub fn restart(&mut self, x: State, p: Mat6) {
        if let Some(r) = &mut self.resampling {
            r.reseed();
        }
        self.reset(x, p);
    }

    /// Back to the start at `(x, p)`: the members re-split from it (kept as they are if it
    /// cannot be split; the factory refuses such a prior).
    pub fn reset(&mut self, x: State, p: Mat6) {
        if !self.start(x, p) {
            self.x = x;
            self.p = p;
        }
    }

    /// Number of members (dropped ones included).
    pub fn len(&self) -> usize {
        self.members.len()
    }

    /// Whether the bank has no member (never: at least two).
    pub fn is_empty(&self) -> bool {
        self.members.is_empty()
    }

    /// The members still stepped, with their weights (summing to one).
    pub fn weighted(&self) -> impl Iterator<Item = (f64, &F)> + '_ {
        let sum: f64 = self.log_w.iter().map(|l| l.exp()).sum();
        self.members
            .iter()
            .zip(&self.log_w)
            .filter(|(_, l)| l.is_finite())
            .map(move |(m, l)| (l.exp() / sum, m))
    }

    /// Keep the bank as it is, for [`Bank::rollback`] (a navigator's step of several
    /// operations). No allocation.
    pub fn checkpoint(&mut self) {
        for (c, m) in self.check.iter_mut().zip(&self.members) {
            *c = m.save();
        }
        self.check_w.copy_from_slice(&self.log_w);
        self.check_xp = (self.x, self.p);
        if let (Some(c), Some(r)) = (&mut self.check_live, &self.resampling) {
            c.clone_from(r.live());
        }
    }

    /// Back to the last [`Bank::checkpoint`].
    pub fn rollback(&mut self) {
        for (m, c) in self.members.iter_mut().zip(&self.check) {
            m.restore(c);
        }
        self.log_w.copy_from_slice(&self.check_w);
        (self.x, self.p) = self.check_xp;
        if let (Some(c), Some(r)) = (&self.check_live, &mut self.resampling) {
            r.set_live(c);
        }
    }

    fn save_undo(&mut self) {
        for (u, m) in self.undo.iter_mut().zip(&self.members) {
            *u = m.save();
        }
        self.undo_w.copy_from_slice(&self.log_w);
        if let (Some(u), Some(r)) = (&mut self.undo_live, &self.resampling) {
            u.clone_from(r.live());
        }
    }

    fn undo(&mut self) {
        for (m, u) in self.members.iter_mut().zip(&self.undo) {
            m.restore(u);
        }
        self.log_w.copy_from_slice(&self.undo_w);
        if let (Some(u), Some(r)) = (&self.undo_live, &mut self.resampling) {
            r.set_live(u);
        }
    }

    /// The mixture's mean and covariance from the members and weights; on error the bank
    /// is taken back to its undo point.
    fn combine(&mut self) -> Result<(), FilterError> {
        let sum = self.exponentiate();
        let mut x = State::zeros();
        for ((m, l), e) in self.members.iter().zip(&self.log_w).zip(&self.exp_w) {
            if l.is_finite() {
                x += m.state() * (e / sum);
            }
        }
        let mut p = Mat6::zeros();
        for ((m, l), e) in self.members.iter().zip(&self.log_w).zip(&self.exp_w) {
            if l.is_finite() {
                let d = m.state() - x;
                p += (m.covariance() + d * d.transpose()) * (e / sum);
            }
        }
        let p = symmetrize(&p);
        let ok = finite(&x, "bank state").and_then(|()| finite(&p, "bank covariance"));
        if let Err(e) = ok {
            self.undo();
            return Err(e);
        }
        self.x = x;
        self.p = p;
        Ok(())
    }

    /// `exp_w` = `exp(log_w)`; returns their sum.
    fn exponentiate(&mut self) -> f64 {
        for (e, l) in self.exp_w.iter_mut().zip(&self.log_w) {
            *e = l.exp();
        }
        self.exp_w.iter().sum()
    }

    /// One measurement through every live member: `predictive` gives a member's
    /// linearised innovation and its covariance at its prior, and the linearisation it
    /// made, which `update` passes on to update the member (its own diagnostics: `dof` or
    /// the azimuth flag, folded by `fold`). Returns the mixture's innovation and NIS (prior
    /// weights) and the folded diagnostics.
    fn update_members<const D: usize, C, T: Copy>(
        &mut self,
        mut predictive: impl FnMut(&F) -> Option<(SVector<f64, D>, SMatrix<f64, D, D>, f64, C)>,
        mut update: impl FnMut(&mut F, &C) -> Result<T, FilterError>,
        mut fold: impl FnMut(T, T) -> T,
    ) -> Result<(SVector<f64, D>, f64, T), FilterError> {
        self.save_undo();
        let prior_sum = self.exponentiate();
        let mut first_error = None;
        let mut folded: Option<T> = None;
        let mut nu = SVector::<f64, D>::zeros();
        let mut parts = [None::<Predictive<D>>; MAX_BANK];
        // beyond MAX_BANK members: sum w (S + nu nu^T), the mixture's second moment
        let mut second = SMatrix::<f64, D, D>::zeros();
        let few = self.members.len() <= MAX_BANK;
        for (k, m) in self.members.iter_mut().enumerate() {
            if !self.log_w[k].is_finite() {
                continue;
            }
            let wk = self.exp_w[k] / prior_sum;
            let step = predictive(m)
                .ok_or(FilterError::NotPositiveDefinite(
                    "a bank member's innovation covariance",
                ))
                .and_then(|(n, s, ll, c)| update(m, &c).map(|t| (n, s, ll, t)));
            match step {
                Ok((n, s, ll, t)) => {
                    self.log_w[k] += ll;
                    nu += n * wk;
                    if few {
                        parts[k] = Some((wk, n, s));
                    } else {
                        second += (s + n * n.transpose()) * wk;
                    }
                    folded = Some(folded.map_or(t, |f| fold(f, t)));
                }
                Err(e) => {
                    self.log_w[k] = f64::NEG_INFINITY;
                    first_error.get_or_insert(e);
                }
            }
        }
        let Some(folded) = folded else {
            self.undo();
            return Err(first_error.unwrap_or(FilterError::NonFinite("bank weights")));
        };
        self.normalise();
        let s = if few {
            let mut s = SMatrix::<f64, D, D>::zeros();
            for (wk, n, sk) in parts.iter().flatten() {
                let d = n - nu;
                s += (sk + d * d.transpose()) * *wk;
            }
            s
        } else {
            second - nu * nu.transpose()
        };
        if let Some(r) = &mut self.resampling {
            r.after_update(&mut self.members, &mut self.spare, &mut self.log_w);
        }
        let nis = s.cholesky().map_or(f64::NAN, |c| nu.dot(&c.solve(&nu)));
        self.combine()?;
        Ok((nu, nis, folded))
    }

    /// The largest weight to 1 (`ln` 0); members below [`DROP_RATIO`] of it dropped.
    fn normalise(&mut self) {
        let top = self.log_w.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let floor = DROP_RATIO.ln();
        for l in self.log_w.iter_mut() {
            *l -= top;
            if !(*l >= floor) {
                *l = f64::NEG_INFINITY;
            }
        }
    }
}

impl<F: Member> Estimator for Bank<F> {
    fn predict(&mut self, model: &DiscreteModel, accel: &Vec3) -> Result<(), FilterError> {
        self.save_undo();
        let mut first_error = None;
        let mut any = false;
        for (m, l) in self.members.iter_mut().zip(self.log_w.iter_mut()) {
            if !l.is_finite() {
                continue;
            }
            match m.predict(model, accel) {
                Ok(()) => any = true,
                Err(e) => {
                    *l = f64::NEG_INFINITY;
                    first_error.get_or_insert(e);
                }
            }
        }
        if !any {
            self.undo();
            return Err(first_error.unwrap_or(FilterError::NonFinite("bank weights")));
        }
        self.normalise();
        self.combine()
    }

    fn update<M: MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
    ) -> Result<UpdateInfo, FilterError> {
        let r = sensor.noise_cov();
        let (innovation, nis, azimuth_used) = self.update_members(
            |m| {
                let x = m.state();
                let g = sensor.linearize(&Vec3::new(x[0], x[1], x[2])).ok()?;
                let nu = sensor.linearised_residual(z, &g);
                let mut h = g.h;
                if !g.azimuth_usable {
                    h.row_mut(1).fill(0.0);
                }
                // the radio measures the position: H = [H_r 0]
                let (ll, s) = log_density_block::<3, 0>(&h, &nu, &r, m.covariance())?;
                Some((nu, s, ll, g))
            },
            |m, g| m.update_at(sensor, z, g).map(|info| info.azimuth_used),
            |a, b| a && b,
        )?;
        Ok(UpdateInfo {
            innovation,
            nis,
            azimuth_used,
        })
    }

    fn update_sensor<const D: usize, S: Sensor<D> + ?Sized>(
        &mut self,
        sensor: &S,
        z: &SVector<f64, D>,
    ) -> Result<SensorUpdate<D>, FilterError> {
        let r = sensor.noise().cov();
        let (innovation, nis, dof) = self.update_members(
            |m| {
                let (lin, nu) = sensor.innovation(m.state(), z).ok()?;
                let p = m.covariance();
                let (ll, s) = match sensor.support() {
                    Support::Position => log_density_block::<D, 0>(&lin.h, &nu, &r, p),
                    Support::Velocity => log_density_block::<D, 3>(&lin.h, &nu, &r, p),
                    Support::Full => log_density(&lin.h, &nu, &r, p),
                }?;
                Some((nu, s, ll, (lin, nu)))
            },
            |m, (lin, nu)| m.update_sensor_at(sensor, z, lin, nu).map(|info| info.dof),
            usize::min,
        )?;
        Ok(SensorUpdate {
            innovation,
            nis,
            dof,
        })
    }

    fn state(&self) -> &State {
        &self.x
    }

    fn covariance(&self) -> &Mat6 {
        &self.p
    }

    /// The members re-split from `(x, p)` (as [`Bank::reset`]).
    fn set_estimate(&mut self, x: State, p: Mat6) {
        self.reset(x, p);
    }
}

/// Saved state: the number of members `n`; each member's `ln` weight (`-inf` for a dropped
/// one) and its own section (tag and fields, [`Persist`] of the member); the mixture's
/// `x`, `P`. See `docs/state-format.md`.
impl<F: Member + Persist> Persist for Bank<F> {
    fn save_state(&self, w: &mut Writer<'_>) {
        w.usize(self.members.len());
        for (m, l) in self.members.iter().zip(&self.log_w) {
            w.f64(*l);
            m.save_state(w);
        }
        w.matrix(&self.x);
        w.matrix(&self.p);
        if let Some(r) = &self.resampling {
            r.save_state(w);
        }
    }

    fn load_state(&mut self, r: &mut Reader<'_>) -> Result<(), StateError> {
        r.count("bank members", self.members.len())?;
        let mut top = f64::NEG_INFINITY;
        for (m, l) in self.members.iter_mut().zip(self.log_w.iter_mut()) {
            let v = r.f64("bank member log-weight")?;
            if v.is_nan() || v > 0.0 {
                return Err(refuse(format!(
                    "bank member log-weight {v} is not in [-inf, 0]"
                )));
            }
            *l = v;
            top = top.max(v);
            m.load_state(r)?;
        }
        if top != 0.0 {
            return Err(refuse(format!(
                "the largest bank member log-weight is {top}, not 0"
            )));
        }
        self.x = r.finite_matrix("bank state")?;
        self.p = r.finite_matrix("bank covariance")?;
        match &mut self.resampling {
            Some(res) => res.load_state(r),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    /// `E[d^k]` of the standard normal: `(k - 1)!!` for even `k`, 0 for odd.
    fn normal_moment(k: u32) -> f64 {
        if k % 2 == 1 {
            0.0
        } else {
            (1..k).step_by(2).map(f64::from).product()
        }
    }

    #[test]
    fn gauss_hermite_integrates_polynomials_to_degree_2n_minus_1() {
        for n in 1..=MAX_BANK {
            let rule = gauss_hermite(n);
            for k in 0..(2 * n as u32) {
                let q: f64 = rule.iter().map(|(d, w)| w * d.powi(k as i32)).sum();
                let scale: f64 = rule.iter().map(|(d, w)| w * d.abs().powi(k as i32)).sum();
                let exact = normal_moment(k);
                assert!(
                    (q - exact).abs() <= 1e-12 * scale.max(1.0),
                    "n = {n}, k = {k}: {q} vs {exact}"
                );
            }
        }
    }

    /// The block form's `S` and log-density are the full form's, bit for bit, for a
    /// Jacobian with zeros outside its block (position and velocity; two and three rows).
    #[test]
    fn the_block_log_density_is_the_full_ones() {
        fn check<const D: usize, const OFF: usize>() {
            let a = Mat6::from_fn(|i, j| ((i * 7 + j * 3) % 11) as f64 * 0.37 - 1.3);
            let p = a * a.transpose() + Mat6::identity() * 0.5;
            let mut h = SMatrix::<f64, D, 6>::zeros();
            for i in 0..D {
                for j in 0..3 {
                    h[(i, OFF + j)] = ((i * 5 + j * 2) % 7) as f64 * 0.11 - 0.29;
                }
            }
            let nu = SVector::<f64, D>::from_fn(|i, _| 0.3 - 0.17 * i as f64);
            let r = SMatrix::<f64, D, D>::identity() * 0.04;
            let full = log_density(&h, &nu, &r, &p).unwrap();
            let block = log_density_block::<D, OFF>(&h, &nu, &r, &p).unwrap();
            assert_eq!(full.0.to_bits(), block.0.to_bits(), "D = {D}, OFF = {OFF}");
            assert_eq!(full.1, block.1, "D = {D}, OFF = {OFF}");
        }
        check::<3, 0>();
        check::<2, 0>();
        check::<3, 3>();
    }

    #[test]
    fn the_split_keeps_the_prior_moments() {
        let x = State::from_row_slice(&[300.0, -1800.0, 50.0, 0.1, 0.0, -0.05]);
        let mut p = Mat6::from_diagonal(&State::from_row_slice(&[
            400.0, 360_000.0, 900.0, 1e-4, 4e-4, 1e-4,
        ]));
        p[(1, 4)] = 2.0;
        p[(4, 1)] = 2.0;
        p[(0, 1)] = 1000.0;
        p[(1, 0)] = 1000.0;
        for n in 2..=MAX_BANK {
            let parts = split(&x, &p, n).unwrap();
            let w: f64 = parts.iter().map(|q| q.0).sum();
            assert!((w - 1.0).abs() < 1e-14);
            let mean: State = parts.iter().map(|(w, xk, _)| xk * *w).sum();
            let cov: Mat6 = parts
                .iter()
                .map(|(w, xk, pk)| (pk + (xk - mean) * (xk - mean).transpose()) * *w)
                .sum();
            assert!((mean - x).norm() < 1e-9, "n = {n}");
            assert!((cov - p).norm() < 1e-8 * p.norm(), "n = {n}");
            // every member is positive definite, with s^2 of the prior's variance along u
            let u = Vec3::new(x[0], x[1], x[2]).normalize();
            let var = |m: &Mat6| u.dot(&(m.fixed_view::<3, 3>(0, 0) * u));
            for (_, _, pk) in &parts {
                assert!(pk.cholesky().is_some());
                assert!((var(pk) / var(&p) - MEMBER_SPREAD.powi(2)).abs() < 1e-12);
            }
        }
        assert!(split(&State::zeros(), &p, 3).is_none());
    }
}
