//! The gamma-optimal observer without a generic SDP (much faster than the interior-point
//! solve, and not limited by its bound on `P`): a bisection on
//! `gamma` in which each trial is decided by the discrete-time H-infinity filtering
//! Riccati equation, solved by a structure-preserving doubling algorithm; the gain in
//! closed form. [`crate::hinf::design::design_observer`] certifies the result on the
//! literal observer LMI and falls back to the SDP when this route fails.
//!
//! # From the observer LMI to a Riccati equation
//!
//! The observer LMI ([`crate::hinf::design`] module docs, "Observer (error-dynamics)
//! design") is the discrete bounded-real lemma for the error system
//!
//! ```text
//! e(k+1) = Ae e + Be wt,   z_e = L e,   Ae = A - G C,   Be = [B, -G D, Hae],
//! wt = (w, v, d),          Hae = |Ea| Ha,
//! ```
//!
//! which, after the Schur complements of its `-I` and `-P` blocks, reads
//!
//! ```text
//! (primal)   [Ae Be]^T P [Ae Be] - diag(P - L^T L, g2 I)  <  0,   P > 0.
//! ```
//!
//! *Duality.* Both it and the bounded-real lemma of the transposed system `(Ae^T, L^T,
//! Be^T)` (same H-infinity norm, same stability) are Schur complements of one matrix,
//!
//! ```text
//! [ -Ps^-1  Ae      Be      0     ]
//! [  *     -Ps      0       L^T   ]   <  0
//! [  *      *      -g I     0     ]
//! [  *      *       *      -g I   ]
//! ```
//!
//! taken over the blocks `(1, 4)` for the primal (with `P = g Ps`) and over `(2, 3)` for
//!
//! ```text
//! (dual)     [ Ae X Ae^T - X + Be Be^T    Ae X L^T       ]
//!            [ L X Ae^T                   L X L^T - g2 I ]  <  0,      X = g Ps^-1,
//! ```
//!
//! so a strict dual certificate `X` gives the strict primal certificate `P = g2 X^-1`
//! (and back): the two LMIs are equivalent, with no margin lost.
//!
//! *The gain drops out.* With `g2 I - L X L^T > 0`, the Schur complement of the dual's
//! `(2, 2)` block and the matrix inversion lemma give
//!
//! ```text
//! Ae Xt Ae^T + G R G^T + Q - X < 0,    Xt = X + X L^T (g2 I - L X L^T)^-1 L X
//!                                         = (X^-1 - g^-2 L^T L)^-1,
//! Q = B B^T + Hae Hae^T,   R = D D^T,
//! ```
//!
//! and completing the square in `G` (with `R > 0`, i.e. `D` invertible),
//!
//! ```text
//! (A - G C) Xt (A - G C)^T + G R G^T = A (Xt^-1 + C^T R^-1 C)^-1 A^T
//!                                      + (G - G*) (R + C Xt C^T) (G - G*)^T,
//! G* = A Xt C^T (R + C Xt C^T)^-1.
//! ```
//!
//! So a gain exists for `g` iff some `X > 0` with `g2 I - L X L^T > 0` satisfies the
//! Riccati inequality
//!
//! ```text
//! X > A (X^-1 + C^T R^-1 C - g^-2 L^T L)^-1 A^T + Q,
//! ```
//!
//! and `G*` is then a gain (the central one). This is the Riccati recursion of the
//! a-priori (one-step predictor) H-infinity filter with no feedthrough — the observer's
//! estimate `xh(k)` uses `y` up to `k - 1` — whose existence condition is `X^-1 - g^-2
//! L^T L > 0` (Hassibi, Sayed & Kailath, "Linear estimation in Krein spaces — Part II",
//! IEEE TAC 41(1), 1996, and their book "Indefinite-Quadratic Estimation and Control",
//! SIAM 1999; Shaked & Theodor, "H-infinity-optimal estimation: a tutorial", CDC 1992;
//! Nagpal & Khargonekar, "Filtering and smoothing in an H-infinity setting", IEEE TAC
//! 36(2), 1991). Transposed it is the static state-feedback problem, for which de Souza &
//! Xie ("On the discrete-time bounded real lemma with application in the characterization
//! of static state feedback H-infinity controllers", Systems & Control Letters 18, 1992)
//! show that the strict Riccati inequality is solvable iff the equation
//!
//! ```text
//! X = A (X^-1 + Gm)^-1 A^T + Q = A X (I + Gm X)^-1 A^T + Q,   Gm = C^T R^-1 C - g^-2 L^T L
//! ```
//!
//! has a stabilising solution (`A (I + X Gm)^-1` stable) with `X >= 0` and
//! `g2 I - L X L^T > 0`. Paper 002 (sec. 3, Theorem 1) designs the filter from the LMI (eq. 20) only; the
//! observer form and this reduction are ours (the design module's docs relate them).
//!
//! # Strictness and the certificate
//!
//! At the equation's solution the Riccati inequality holds with equality, so the dual LMI
//! is only semidefinite. The route therefore solves the equation with `Q` replaced by `Qe =
//! Q + eps_q diag(X_K)` (`Q_PERTURBATION`; `X_K` is the Kalman predictor's covariance,
//! `g = infinity`, which sets a scale per coordinate and keeps `Qe` invariant under the
//! diagonal changes of units that matter here, metres against m/s). At the gain `G*` from
//! that solution the residual is exactly `-eps_q diag(X_K) < 0`: `X` is a strict dual
//! certificate for the true `Q`, and `P = g2 X^-1` a strict primal one. The design module
//! assembles the literal 33 x 33 observer LMI at `(P, G*, g2)` with nalgebra and accepts
//! the filter only when its largest eigenvalue is negative (the same test as for the
//! SDP's answer). The perturbation raises the optimum by about `eps_q` relative at most,
//! far inside the 1e-4 to which the result must equal the SDP's.
//!
//! # The bisection
//!
//! Feasibility is monotone in `g` (a certificate at `g` is one at every larger `g`). The
//! solution grows as `g` falls (`Gm` decreases; comparison theorem), so `X_K` bounds it
//! from below and `g2 I - L X L^T > 0` needs `g > g_lo = sqrt(lambda_max(L X_K L^T))`: the
//! lower end. The upper end doubles from there until a trial succeeds; then the bracket
//! is halved in `log g` until `g_hi / g_lo - 1 <= ` `GAMMA_TOLERANCE`. A trial succeeds
//! when the doubling algorithm converges to a finite `X` with `X > 0` and `g2 I - L X L^T >
//! 0` (Cholesky) and `A (I + X Gm)^-1` has spectral radius below 1 (the stabilising
//! solution); anything else — `I + G_k H_k` singular, divergence, no convergence in
//! `MAX_DOUBLINGS`, a failed test — is infeasible. The doubling iterate `H_k` is the
//! Riccati recursion's value at horizon `2^k` (started from `X = 0`, the estimator's known
//! initial state), i.e. the finite-horizon a-priori filter's; its existence condition
//! `g2 I - L H_k L^T > 0` (Hassibi, Sayed & Kailath) is necessary for the infinite horizon
//! (the stationary filter restricted to `2^k` steps is a finite-horizon one at the same
//! level), so a trial stops as soon as an iterate violates it instead of doubling on. The returned gamma is the upper end:
//! feasible, and within the tolerance of the infimum of the perturbed problem.
//!
//! # The doubling algorithm
//!
//! The structure-preserving doubling algorithm (SDA) of Chu, Fan & Lin ("A
//! structure-preserving doubling algorithm for discrete-time algebraic Riccati equations",
//! Linear Algebra Appl. 396, 2005; convergence: Lin & Xu, SIAM J. Matrix Anal. Appl.
//! 28(1), 2006) for `X = F^T X (I + Gm X)^-1 F + H` (here `F = A^T`, `H = Qe`):
//!
//! ```text
//! W_k = I + G_k H_k
//! F_k+1 = F_k W_k^-1 F_k,   G_k+1 = G_k + F_k W_k^-1 G_k F_k^T,
//! H_k+1 = H_k + F_k^T H_k W_k^-1 F_k,        F_0 = A^T, G_0 = Gm, H_0 = Qe
//! ```
//!
//! `H_k -> X` quadratically, the error after `k` steps ~ `rho(S)^(2^k)` with `S` the
//! closed loop — 10 to 20 steps even for the slow filters of the quiet-truth case, where
//! a fixed-point iteration of the Riccati recursion would need thousands. The indefinite
//! `Gm` of the H-infinity case is allowed. Everything is 6 x 6 on the stack: no heap
//! allocation in a trial.

use super::{Gain, HinfPlant};
#[cfg(not(feature = "std"))]
use crate::math::Float;
use crate::types::Mat6;
use core::fmt;
use nalgebra::SMatrix;

/// Relative width `g_hi / g_lo - 1` at which the bisection stops (100 times finer than
/// the 1e-4 to which the result must equal the SDP's).
pub(crate) const GAMMA_TOLERANCE: f64 = 1e-6;
/// `eps_q` of the perturbation `Qe = Q + eps_q diag(X_K)` that makes the certificate
/// strict (module docs, "Strictness and the certificate").
pub(crate) const Q_PERTURBATION: f64 = 1e-6;
/// Doubling steps per trial before it counts as not converged.
pub(crate) const MAX_DOUBLINGS: u32 = 64;
/// Doublings of the upper end of the bracket before the route gives up.
pub(crate) const MAX_EXPANSIONS: u32 = 40;
/// Bisection steps before the route gives up (20 are needed from a factor-2 bracket).
pub(crate) const MAX_BISECTIONS: u32 = 64;
/// Scaled change `|dH_ij| / sqrt(H_ii H_jj)` at which a doubling run has converged.
const SDA_TOLERANCE: f64 = 1e-13;

/// Why the Riccati route did not design the observer (the design then runs the SDP).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RiccatiFailure {
    /// `D D^T` is not positive definite (a noise-free measurement axis): the filter Riccati
    /// needs `R^-1`.
    SingularMeasurementNoise,
    /// The Kalman Riccati (`g = infinity`) has no stabilising solution (e.g. `(A, C)` not
    /// detectable), so there is no lower end for the bisection.
    NoKalmanSolution,
    /// No trial up to `2^MAX_EXPANSIONS g_lo` succeeded.
    NoFeasibleGamma,
    /// The constructed observer failed the literal LMI check
    /// ([`crate::hinf::design::design_observer`]).
    CertificationFailed,
}

impl fmt::Display for RiccatiFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::SingularMeasurementNoise => "D D^T is singular (a noise-free measurement axis)",
            Self::NoKalmanSolution => "the Kalman Riccati equation has no stabilising solution",
            Self::NoFeasibleGamma => "no gamma in the bracket admits a stabilising solution",
            Self::CertificationFailed => "the constructed observer failed the literal LMI check",
        })
    }
}

/// Result of the Riccati route, before certification.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RiccatiObserver<const M: usize = 3> {
    /// The central gain `G*` at `gamma`.
    pub gain: Gain<M>,
    /// The upper end of the final bracket: the bound the gain is designed for.
    pub gamma: f64,
    /// The lower end (the last infeasible trial, or `g_lo`).
    pub gamma_lower: f64,
    /// The stabilising solution `X` at `gamma` (dual certificate; `P = gamma^2 X^-1`).
    pub x: Mat6,
    /// Trials (Riccati solves) after the two Kalman ones: expansion plus bisection steps.
    pub steps: u32,
    /// Doubling steps over all solves, the Kalman ones included.
    pub doublings: u32,
}

/// The data of the Riccati route for one plant.
struct Problem<const M: usize> {
    a: Mat6,
    c: SMatrix<f64, M, 6>,
    l: Mat6,
    /// `C^T R^-1 C`
    cri: Mat6,
    /// `L^T L`
    ltl: Mat6,
    r: SMatrix<f64, M, M>,
    /// `Qe`
    q: Mat6,
}

/// `(M + M^T) / 2`.
pub fn symmetric(m: &Mat6) -> Mat6 {
    (m + m.transpose()) * 0.5
}

/// Stabilising solution of `X = F^T X (I + G X)^-1 F + H` by the SDA (module docs),
/// `None` when `I + G_k H_k` is singular, a number is not finite or the scaled change has
/// not fallen below the tolerance in `MAX_DOUBLINGS` steps. Returns `X` and the steps.
pub fn sda(f: &Mat6, g: &Mat6, h: &Mat6) -> Option<(Mat6, u32)> {
    sda_while(f, g, h, |_| true).0
}

/// [`sda`] that also stops (with `None`) as soon as an iterate `H_k` fails
/// `admissible`; returns the doubling steps taken in either case.
fn sda_while(
    f: &Mat6,
    g: &Mat6,
    h: &Mat6,
    admissible: impl Fn(&Mat6) -> bool,
) -> (Option<(Mat6, u32)>, u32) {
    let (mut fk, mut gk, mut hk) = (*f, *g, *h);
    for it in 1..=MAX_DOUBLINGS {
        if !admissible(&hk) {
            return (None, it);
        }
        let Some((f_next, g_next, h_next)) = doubling(&fk, &gk, &hk) else {
            return (None, it);
        };
        let mut change = 0.0_f64;
        for i in 0..6 {
            for j in 0..6 {
                let scale = (h_next[(i, i)] * h_next[(j, j)]).abs().sqrt();
                let d = (h_next[(i, j)] - hk[(i, j)]).abs();
                change = change.max(if scale > 0.0 { d / scale } else { d });
            }
        }
        fk = f_next;
        gk = g_next;
        hk = h_next;
        if change <= SDA_TOLERANCE {
            return (Some((hk, it)), it);
        }
    }
    (None, MAX_DOUBLINGS)
}

/// One doubling step `(F_k, G_k, H_k) -> (F_k+1, G_k+1, H_k+1)` (module docs); `None` when
/// `I + G_k H_k` is singular or a number is not finite.
fn doubling(fk: &Mat6, gk: &Mat6, hk: &Mat6) -> Option<(Mat6, Mat6, Mat6)> {
    let lu = (Mat6::identity() + gk * hk).lu();
    let wf = lu.solve(fk)?;
    let wg = lu.solve(gk)?;
    let f_next = fk * wf;
    let g_next = symmetric(&(gk + fk * wg * fk.transpose()));
    let h_next = symmetric(&(hk + fk.transpose() * hk * wf));
    let finite = (f_next.iter().chain(g_next.iter()).chain(h_next.iter())).all(|v| v.is_finite());
    finite.then_some((f_next, g_next, h_next))
}

/// Spectral radius of a 6 x 6 matrix through its real Schur form (stack only), `None`
/// when not finite or not converged within [`crate::numerics::eigen::MAX_SWEEPS_PER_DIM`]
/// sweeps per dimension.
fn spectral_radius(m: &Mat6) -> Option<f64> {
    if !m.iter().all(|v| v.is_finite()) {
        return None;
    }
    let schur = nalgebra::Schur::try_new(
        *m,
        f64::EPSILON,
        crate::numerics::eigen::MAX_SWEEPS_PER_DIM * 6,
    )?;
    let ev = schur.complex_eigenvalues();
    let rho = ev.iter().fold(0.0_f64, |r, z| r.max(z.re.hypot(z.im)));
    rho.is_finite().then_some(rho)
}

impl<const M: usize> Problem<M> {
    fn new(plant: &HinfPlant<M>) -> Result<Self, RiccatiFailure> {
        let r = plant.d * plant.d.transpose();
        let chol = r
            .cholesky()
            .ok_or(RiccatiFailure::SingularMeasurementNoise)?;
        let cri = symmetric(&(plant.c.transpose() * chol.solve(&plant.c)));
        if !cri.iter().all(|v| v.is_finite()) {
            return Err(RiccatiFailure::SingularMeasurementNoise);
        }
        let hae = plant.ha * plant.ea.norm();
        Ok(Self {
            a: plant.a,
            c: plant.c,
            l: plant.l,
            cri,
            ltl: plant.l.transpose() * plant.l,
            r,
            q: symmetric(&(plant.b * plant.b.transpose() + hae * hae.transpose())),
        })
    }

    /// The stabilising solution at `g` (`None`: infeasible) and its doubling steps; `g =
    /// infinity` is the Kalman predictor.
    fn trial(&self, g: f64) -> (Option<Mat6>, u32) {
        let gm = if g.is_finite() {
            self.cri - self.ltl / (g * g)
        } else {
            self.cri
        };
        // H_k is the Riccati recursion's value at horizon 2^k: a finite horizon that
        // already violates g2 I - L H_k L^T > 0 proves the infinite one infeasible
        let g2 = g * g;
        let (solution, steps) = sda_while(&self.a.transpose(), &gm, &self.q, |hk| {
            !g.is_finite()
                || (Mat6::identity() * g2 - self.l * hk * self.l.transpose())
                    .cholesky()
                    .is_some()
        });
        let Some((x, steps)) = solution else {
            return (None, steps);
        };
        let ok = x.cholesky().is_some()
            && (!g.is_finite()
                || (Mat6::identity() * (g * g) - self.l * x * self.l.transpose())
                    .cholesky()
                    .is_some())
            && (Mat6::identity() + x * gm)
                .try_inverse()
                .and_then(|m| spectral_radius(&(self.a * m)))
                .is_some_and(|rho| rho < 1.0);
        (ok.then_some(x), steps)
    }

    /// The central gain `G* = A Xt C^T (R + C Xt C^T)^-1`, `Xt = X + X L^T (g2 I - L X
    /// L^T)^-1 L X`.
    fn gain(&self, g: f64, x: &Mat6) -> Option<Gain<M>> {
        let s = (Mat6::identity() * (g * g) - self.l * x * self.l.transpose()).cholesky()?;
        let lx = self.l * x;
        let xt = symmetric(&(x + lx.transpose() * s.solve(&lx)));
        let cxt = self.c * xt;
        let m = (self.r + cxt * self.c.transpose()).cholesky()?;
        let gain = self.a * m.solve(&cxt).transpose();
        gain.iter().all(|v| v.is_finite()).then_some(gain)
    }
}

/// The Kalman (H2-optimal one-step predictor) gain of `plant` for the unit white noises
/// `(w, v, d)`: the stabilising solution at `g = infinity` and `G = A X C^T (R + C X
/// C^T)^-1`; `None` when `D` is singular or there is no stabilising solution.
pub fn kalman_gain<const M: usize>(plant: &HinfPlant<M>) -> Option<Gain<M>> {
    let p = Problem::new(plant).ok()?;
    let x = p.trial(f64::INFINITY).0?;
    let cx = p.c * x;
    let m = (p.r + cx * p.c.transpose()).cholesky()?;
    let gain = p.a * m.solve(&cx).transpose();
    gain.iter().all(|v| v.is_finite()).then_some(gain)
}

/// The gamma-optimal observer gain of `plant` by bisection on the H-infinity filtering
/// Riccati equation (module docs), not yet certified.
pub fn observer<const M: usize>(
    plant: &HinfPlant<M>,
) -> Result<RiccatiObserver<M>, RiccatiFailure> {
    let mut p = Problem::new(plant)?;
    // Kalman predictor with the true Q: the scale of the perturbation
    let (xk, mut doublings) = p.trial(f64::INFINITY);
    let xk = xk.ok_or(RiccatiFailure::NoKalmanSolution)?;
    let mut d = Mat6::zeros();
    for i in 0..6 {
        d[(i, i)] = xk[(i, i)] * Q_PERTURBATION;
    }
    p.q += d;
    let (xk, n) = p.trial(f64::INFINITY);
    doublings += n;
    let xk = xk.ok_or(RiccatiFailure::NoKalmanSolution)?;
    let top =
        crate::numerics::eigen::symmetric_eigenvalues(symmetric(&(p.l * xk * p.l.transpose())))
            .map(|ev| ev.iter().fold(0.0_f64, |a, b| a.max(*b)))
            .ok_or(RiccatiFailure::NoKalmanSolution)?;
    let mut lo = top.sqrt();
    if !(lo.is_finite() && lo > 0.0) {
        return Err(RiccatiFailure::NoKalmanSolution);
    }
    let mut steps = 0;
    // upper end
    let mut hi = lo;
    let mut x_hi = None;
    for _ in 0..MAX_EXPANSIONS {
        hi *= 2.0;
        if !hi.is_finite() {
            break;
        }
        let (x, n) = p.trial(hi);
        steps += 1;
        doublings += n;
        if x.is_some() {
            x_hi = x;
            break;
        }
        lo = hi;
    }
    let mut x_hi = x_hi.ok_or(RiccatiFailure::NoFeasibleGamma)?;
    // the log-width halves per step: from a factor 2 to GAMMA_TOLERANCE takes 20 steps;
    // the cap only guards against a non-finite bracket
    let mut bisections = 0;
    while hi / lo - 1.0 > GAMMA_TOLERANCE {
        bisections += 1;
        let g = (lo * hi).sqrt();
        if bisections > MAX_BISECTIONS || !(g.is_finite() && g > lo && g < hi) {
            return Err(RiccatiFailure::NoFeasibleGamma);
        }
        let (x, n) = p.trial(g);
        steps += 1;
        doublings += n;
        match x {
            Some(x) => {
                hi = g;
                x_hi = x;
            }
            None => lo = g,
        }
    }
    let gain = p.gain(hi, &x_hi).ok_or(RiccatiFailure::NoFeasibleGamma)?;
    Ok(RiccatiObserver {
        gain,
        gamma: hi,
        gamma_lower: lo,
        x: x_hi,
        steps,
        doublings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The stabilising root of the scalar equation `x = a^2 x / (1 + g x) + q`, i.e. `g x^2
    /// + (1 - a^2 - g q) x - q = 0`, with `|a / (1 + g x)| < 1`.
    fn scalar_root(a: f64, g: f64, q: f64) -> f64 {
        let (b, c) = (1.0 - a * a - g * q, -q);
        let disc = (b * b - 4.0 * g * c).sqrt();
        let roots = [(-b + disc) / (2.0 * g), (-b - disc) / (2.0 * g)];
        roots
            .into_iter()
            .find(|x| (a / (1.0 + g * x)).abs() < 1.0 && *x > 0.0)
            .unwrap_or(f64::NAN)
    }

    /// Six decoupled scalar equations, with a definite `g` (Kalman), an indefinite one (the
    /// H-infinity case) and an unstable and a marginal `a`: the SDA finds every stabilising
    /// root to 1e-12 relative.
    #[test]
    fn sda_solves_decoupled_equations_in_closed_form() {
        let a = [0.5, 0.9, 1.2, 0.999, 1.0, 0.9];
        let g = [1.0, 4.0, 0.5, 100.0, 0.3, 2.0];
        let q = [1.0, 1e-6, 2.0, 1e-8, 0.01, 3.0];
        let f = Mat6::from_diagonal(&crate::types::State::from_row_slice(&a));
        let gm = Mat6::from_diagonal(&crate::types::State::from_row_slice(&g));
        let h = Mat6::from_diagonal(&crate::types::State::from_row_slice(&q));
        let (x, steps) = sda(&f, &gm, &h).unwrap_or_else(|| panic!("no convergence"));
        assert!(steps <= 30, "{steps} doublings");
        for i in 0..6 {
            let want = scalar_root(a[i], g[i], q[i]);
            assert!(
                (x[(i, i)] - want).abs() <= 1e-12 * want,
                "{i}: {} vs {want}",
                x[(i, i)]
            );
        }
        // negative g (the H-infinity sign) on the two stable channels: x = a^2 x / (1 +
        // g x) + q has the stabilising root with 1 + g x > 0
        let g = [-0.5, -0.1, 0.5, 100.0, 0.3, 2.0];
        let q = [0.1, 0.01, 2.0, 1e-8, 0.01, 3.0];
        let gm = Mat6::from_diagonal(&crate::types::State::from_row_slice(&g));
        let h = Mat6::from_diagonal(&crate::types::State::from_row_slice(&q));
        let (x, _) = sda(&f, &gm, &h).unwrap_or_else(|| panic!("no convergence"));
        for i in 0..6 {
            let want = scalar_root(a[i], g[i], q[i]);
            assert!(
                (x[(i, i)] - want).abs() <= 1e-12 * want,
                "{i}: {} vs {want}",
                x[(i, i)]
            );
        }
    }

    /// A full 6 x 6 case: the open-loop CW plant of paper 002 at gamma 0.6 (above the
    /// optimum 0.50001): the solution satisfies the Riccati equation, is stabilising and
    /// meets the positivity conditions; far below the optimum no trial succeeds.
    #[test]
    fn observer_riccati_residual_and_positivity() {
        let spec = crate::hinf::HinfSpec::paper();
        let plant = HinfPlant::open_loop(&spec);
        let p = Problem::new(&plant).unwrap_or_else(|e| panic!("{e}"));
        let g = 0.6;
        let gm = p.cri - p.ltl / (g * g);
        let (x, _) = p.trial(g);
        let x = x.unwrap_or_else(|| panic!("gamma {g} should be feasible"));
        let rhs = p.a
            * x
            * (Mat6::identity() + gm * x)
                .try_inverse()
                .unwrap_or_else(|| panic!("singular"))
            * p.a.transpose()
            + p.q;
        let res = (rhs - x).abs().max();
        assert!(res <= 1e-12 * x.abs().max(), "residual {res}");
        assert!(p.trial(0.3).0.is_none());
        let r = observer(&plant).unwrap_or_else(|e| panic!("{e}"));
        assert!(r.gamma / r.gamma_lower - 1.0 <= GAMMA_TOLERANCE);
        assert!((0.4999..0.5001).contains(&r.gamma), "gamma {}", r.gamma);
        // the perturbation only raises the optimum: the unperturbed problem is feasible at
        // the perturbed one's gamma
        assert!(p.trial(r.gamma).0.is_some());
    }

    /// `D` singular: the route refuses (the design falls back to the SDP).
    #[test]
    fn singular_measurement_noise_is_refused() {
        let spec = crate::hinf::HinfSpec {
            d_matrix: Some(crate::types::Mat3::from_diagonal(&crate::types::Vec3::new(
                0.1, 0.1, 0.0,
            ))),
            ..crate::hinf::HinfSpec::paper()
        };
        let plant = HinfPlant::open_loop(&spec);
        assert_eq!(
            observer(&plant).err(),
            Some(RiccatiFailure::SingularMeasurementNoise)
        );
    }
}
