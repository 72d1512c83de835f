//! Verification of an H-infinity filter independent of the solver (nalgebra only):
//! the assembled LMI, stability of the filter-error system for `delta` on a grid over
//! `[-delta_bar, delta_bar]`, and its H-infinity norm by a frequency sweep, worst case over
//! that grid.
//!
//! **Filter-error system** (paper 002 eq. 14) for a filter `(A_F, B_F, C_F)` on the plant
//! with the true transition `A(delta)` (not the `Ha F Ea` over-bound: the actual CW model at
//! `w0 (1 + delta)`):
//!
//! ```text
//! xi = (x, x_f):  xi(k+1) = [A(delta) 0; B_F C A_F] xi + [B 0; 0 B_F D] (w, v)
//!                 e = L x - C_F x_f = [L  -C_F] xi
//! ```
//!
//! Its H-infinity norm is `max over theta in [0, pi]` of the largest singular value of
//! `Cbar (e^{j theta} I - Abar)^-1 Bbar`, evaluated on a logarithmic grid of `theta` (poles
//! of a slowly sampled orbit sit within 1e-5 rad of `theta = 0`) and refined by golden-
//! section search around the largest grid value. For the open-loop plant the augmented
//! system is not stable (the plant itself is not); there the error system of the observer
//! (`e(k+1) = (A(delta) - G C) e + ... + (A(delta) - A) x`) is what matters, and
//! [`observer_error_norm`] reports the norm from `(w, v)` to `e` at `delta = 0` plus the
//! spectral radius of `A(delta) - G C` over the grid.
//!
//! **H2 norm** (the mixed design, see [`crate::hinf::design`]): for a stable `(A, B, C)`,
//! `|T|_2^2 = trace(C X C^T)` with the controllability Gramian `X = A X A^T + B B^T` — the
//! steady-state covariance of the output when the inputs are unit white noise. [`dlyap`]
//! solves the Stein equation directly (Kronecker form, `(I - A (x) A) vec X = vec(B B^T)`,
//! one LU of an `n^2 x n^2` matrix), without iterating and without the solver's variables.

use super::{HinfMatrices, HinfPlant};
use crate::hinf::Gain;
use crate::types::Mat6;
use nalgebra::{Complex, DMatrix};

/// Result of a verification.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Verification {
    /// Largest spectral radius of the error system over the `delta` grid (< 1: stable).
    pub max_spectral_radius: f64,
    /// Worst-case H-infinity norm over the `delta` grid (frequency sweep).
    pub worst_norm: f64,
    /// The `delta` of the worst case.
    pub worst_delta: f64,
}

fn dm<const R: usize, const C: usize>(m: &nalgebra::SMatrix<f64, R, C>) -> DMatrix<f64> {
    DMatrix::from_fn(R, C, |i, j| m[(i, j)])
}

fn put(m: &mut DMatrix<f64>, r0: usize, c0: usize, b: &DMatrix<f64>, sym: bool) {
    for i in 0..b.nrows() {
        for j in 0..b.ncols() {
            m[(r0 + i, c0 + j)] = b[(i, j)];
            if sym {
                m[(c0 + j, r0 + i)] = b[(i, j)];
            }
        }
    }
}

/// Paper 002's LMI (eq. 20) assembled from given blocks (unscaled `T Ha`, `Ea`; `lambda`
/// for those).
#[allow(clippy::too_many_arguments)]
pub fn lmi_paper(
    plant: &HinfPlant,
    r: &DMatrix<f64>,
    s: &DMatrix<f64>,
    ab: &DMatrix<f64>,
    bb: &DMatrix<f64>,
    cb: &DMatrix<f64>,
    lambda: f64,
    gamma2: f64,
) -> DMatrix<f64> {
    let (a, b, c, d, l, ha, ea) = (
        dm(&plant.a),
        dm(&plant.b),
        dm(&plant.c),
        dm(&plant.d),
        dm(&plant.l),
        dm(&plant.ha),
        dm(&plant.ea),
    );
    let o = [0, 6, 12, 18, 24, 30, 33, 39];
    let mut m = DMatrix::zeros(45, 45);
    let i = |k: usize| DMatrix::<f64>::identity(k, k);
    put(&mut m, o[0], o[0], &(-r), true);
    put(&mut m, o[0], o[1], &(-s), true);
    put(&mut m, o[0], o[2], &(r * &a + bb * &c), true);
    put(&mut m, o[0], o[3], ab, true);
    put(&mut m, o[0], o[4], &(r * &b), true);
    put(&mut m, o[0], o[5], &(bb * &d), true);
    put(&mut m, o[0], o[7], &(r * &ha), true);
    put(&mut m, o[1], o[1], &(-s), true);
    put(&mut m, o[1], o[2], &(s * &a + bb * &c), true);
    put(&mut m, o[1], o[3], ab, true);
    put(&mut m, o[1], o[4], &(s * &b), true);
    put(&mut m, o[1], o[5], &(bb * &d), true);
    put(&mut m, o[1], o[7], &(s * &ha), true);
    put(
        &mut m,
        o[2],
        o[2],
        &(-r + ea.transpose() * &ea * lambda),
        true,
    );
    put(&mut m, o[2], o[3], &(-s), true);
    put(&mut m, o[2], o[6], &l.transpose(), true);
    put(&mut m, o[3], o[3], &(-s), true);
    put(&mut m, o[3], o[6], &(-cb.transpose()), true);
    put(&mut m, o[4], o[4], &(-i(6) * gamma2), true);
    put(&mut m, o[5], o[5], &(-i(3) * gamma2), true);
    put(&mut m, o[6], o[6], &(-i(6)), true);
    put(&mut m, o[7], o[7], &(-i(6) * lambda), true);
    m
}

/// The observer LMI (see [`crate::hinf`]'s design docs) at `P`, gain `G`, `gamma^2`.
pub fn lmi_observer<const M: usize>(
    plant: &HinfPlant<M>,
    p: &DMatrix<f64>,
    g: &Gain<M>,
    gamma2: f64,
) -> DMatrix<f64> {
    let ae = dm(&(plant.a - g * plant.c));
    let gd = dm(&(g * plant.d));
    let hae = dm(&(plant.ha * plant.ea.norm()));
    let (b, l) = (dm(&plant.b), dm(&plant.l));
    let o = [0, 6, 12, 18, 18 + M, 24 + M];
    let i = |k: usize| DMatrix::<f64>::identity(k, k);
    let mut m = DMatrix::zeros(30 + M, 30 + M);
    put(&mut m, o[0], o[0], &(-p), true);
    put(&mut m, o[0], o[1], &(p * &ae), true);
    put(&mut m, o[0], o[2], &(p * &b), true);
    put(&mut m, o[0], o[3], &(-(p * &gd)), true);
    put(&mut m, o[0], o[4], &(p * &hae), true);
    put(&mut m, o[1], o[1], &(-p), true);
    put(&mut m, o[1], o[5], &l.transpose(), true);
    put(&mut m, o[2], o[2], &(-i(6) * gamma2), true);
    put(&mut m, o[3], o[3], &(-i(M) * gamma2), true);
    put(&mut m, o[4], o[4], &(-i(6) * gamma2), true);
    put(&mut m, o[5], o[5], &(-i(6)), true);
    m
}

/// The three LMIs of the mixed H2/H-infinity observer design (see [`crate::hinf::design`]
/// module docs) assembled at the recovered slack `X`, gain `G` (`Y = X G`), certificates
/// `P_inf`, `P_2`, the H2 bound `Z` and the fixed `gamma^2`: `(H-infinity, H2 Lyapunov, H2
/// input)`; each must be negative definite.
pub fn lmi_mixed<const M: usize>(
    plant: &HinfPlant<M>,
    x: &DMatrix<f64>,
    g: &Gain<M>,
    p_inf: &DMatrix<f64>,
    p2: &DMatrix<f64>,
    z: &DMatrix<f64>,
    gamma2: f64,
) -> [DMatrix<f64>; 3] {
    let ae = dm(&(plant.a - g * plant.c));
    let gd = dm(&(g * plant.d));
    let hae = dm(&(plant.ha * plant.ea.norm()));
    let (b, l) = (dm(&plant.b), dm(&plant.l));
    let i = |k: usize| DMatrix::<f64>::identity(k, k);
    let xs = x + x.transpose();
    // H-infinity, extended form: blocks n, n, p, q, h, l
    let o = [0, 6, 12, 18, 18 + M, 24 + M];
    let mut hinf = DMatrix::zeros(30 + M, 30 + M);
    put(&mut hinf, o[0], o[0], &(p_inf - &xs), true);
    put(&mut hinf, o[0], o[1], &(x * &ae), true);
    put(&mut hinf, o[0], o[2], &(x * &b), true);
    put(&mut hinf, o[0], o[3], &(-(x * &gd)), true);
    put(&mut hinf, o[0], o[4], &(x * &hae), true);
    put(&mut hinf, o[1], o[1], &(-p_inf), true);
    put(&mut hinf, o[1], o[5], &l.transpose(), true);
    put(&mut hinf, o[2], o[2], &(-i(6) * gamma2), true);
    put(&mut hinf, o[3], o[3], &(-i(M) * gamma2), true);
    put(&mut hinf, o[4], o[4], &(-i(6) * gamma2), true);
    put(&mut hinf, o[5], o[5], &(-i(6)), true);
    // H2 Lyapunov: blocks n, n, l
    let mut lyap = DMatrix::zeros(18, 18);
    put(&mut lyap, 0, 0, &(p2 - &xs), true);
    put(&mut lyap, 0, 6, &(x * &ae), true);
    put(&mut lyap, 6, 6, &(-p2), true);
    put(&mut lyap, 6, 12, &l.transpose(), true);
    put(&mut lyap, 12, 12, &(-i(6)), true);
    // H2 input: blocks n, p + q
    let mut input = DMatrix::zeros(12 + M, 12 + M);
    put(&mut input, 0, 0, &(p2 - &xs), true);
    put(&mut input, 0, 6, &(x * &b), true);
    put(&mut input, 0, 12, &(-(x * &gd)), true);
    put(&mut input, 6, 6, &(-z), true);
    [hinf, lyap, input]
}

/// Solution `X` of the discrete Lyapunov (Stein) equation `X = A X A^T + Q` for a stable
/// `A` (n x n), from the Kronecker form `(I - A (x) A) vec X = vec Q`; `None` when that
/// system is singular (`A` has a pair of eigenvalues with `l_i l_j = 1`). The result is
/// symmetrised.
pub fn dlyap(a: &DMatrix<f64>, q: &DMatrix<f64>) -> Option<DMatrix<f64>> {
    let n = a.nrows();
    let mut m = DMatrix::<f64>::identity(n * n, n * n);
    // vec (A X A^T) = (A (x) A) vec X, column-major vec
    m -= a.kronecker(a);
    let rhs = DMatrix::from_column_slice(n * n, 1, q.as_slice());
    let v = m.lu().solve(&rhs)?;
    let x = DMatrix::from_column_slice(n, n, v.as_slice());
    Some((&x + x.transpose()) * 0.5)
}

/// H2 norm of the discrete system `(A, B, C)` (no feedthrough): `sqrt(trace(C X C^T))`,
/// `X` = [`dlyap`]`(A, B B^T)`. Infinite when `A` is not stable.
pub fn h2_norm(a: &DMatrix<f64>, b: &DMatrix<f64>, c: &DMatrix<f64>) -> f64 {
    if !(spectral_radius(a) < 1.0) {
        return f64::INFINITY;
    }
    match dlyap(a, &(b * b.transpose())) {
        Some(x) => (c * x * c.transpose()).trace().max(0.0).sqrt(),
        None => f64::INFINITY,
    }
}

/// The observer's nominal error system `e(k+1) = (A - G C) e + [B, -G D] (w, v)`,
/// `z_e = L e` as `(A, B, C)`.
pub fn observer_error_system<const M: usize>(
    plant: &HinfPlant<M>,
    g: &Gain<M>,
) -> (DMatrix<f64>, DMatrix<f64>, DMatrix<f64>) {
    let mut b = DMatrix::zeros(6, 6 + M);
    put(&mut b, 0, 0, &dm(&plant.b), false);
    put(&mut b, 0, 6, &dm(&(-(g * plant.d))), false);
    (dm(&(plant.a - g * plant.c)), b, dm(&plant.l))
}

/// H2 norm of the observer's nominal error system from the unit white noises `(w, v)` to
/// `z_e = L e`: with `B`, `D` the square roots of the process and measurement covariances
/// and `L = I`, its square is the steady-state mean-square error of the one-step
/// prediction (position [m^2] plus velocity [m^2/s^2]).
pub fn observer_h2_norm<const M: usize>(plant: &HinfPlant<M>, g: &Gain<M>) -> f64 {
    let (a, b, c) = observer_error_system(plant, g);
    h2_norm(&a, &b, &c)
}

/// Steady-state error covariance `X = (A - G C) X (A - G C)^T + B B^T + G D D^T G^T` of
/// the observer (the H2 Gramian; `None` if `A - G C` is not stable).
pub fn observer_error_covariance<const M: usize>(
    plant: &HinfPlant<M>,
    g: &Gain<M>,
) -> Option<crate::types::Mat6> {
    let (a, b, _) = observer_error_system(plant, g);
    if !(spectral_radius(&a) < 1.0) {
        return None;
    }
    let x = dlyap(&a, &(&b * b.transpose()))?;
    Some(crate::types::Mat6::from_fn(|i, j| x[(i, j)]))
}

/// H-infinity norm (frequency sweep) of the channel the observer design certifies: from
/// `(w, v, d)` to `z_e` at the nominal plant, with the robustness input `|Ea| Ha`
/// ([`crate::hinf::design`] module docs). The design's `gamma` must bound it.
pub fn observer_certified_norm<const M: usize>(plant: &HinfPlant<M>, g: &Gain<M>) -> f64 {
    let (a, b, c) = observer_error_system(plant, g);
    let mut bf = DMatrix::zeros(6, 12 + M);
    put(&mut bf, 0, 0, &b, false);
    put(&mut bf, 0, 6 + M, &dm(&(plant.ha * plant.ea.norm())), false);
    hinf_norm(&a, &bf, &c)
}

/// H2 norm of the paper's filter-error system (eq. 14) at the nominal transition
/// `plant.a`, from the unit white noises `(w, v)` to `e = L x - C_F x_f`.
pub fn filter_h2_norm(plant: &HinfPlant, f: &HinfMatrices) -> f64 {
    let (a, b, c) = error_system(plant, f, &plant.a);
    h2_norm(&a, &b, &c)
}

/// Spectral radius of a real square matrix (NaN when it is not finite or its Schur form
/// does not converge within the cap of [`crate::numerics::eigen`]: every caller's `< 1`
/// test then fails).
pub fn spectral_radius(a: &DMatrix<f64>) -> f64 {
    match crate::numerics::eigen::complex_eigenvalues(a) {
        Some(ev) => ev.iter().fold(0.0, |m, z| m.max(z.norm())),
        None => f64::NAN,
    }
}

/// Largest singular value of `C (e^{j theta} I - A)^-1 B` (infinite when singular or not
/// finite).
pub fn gain_at(a: &DMatrix<f64>, b: &DMatrix<f64>, c: &DMatrix<f64>, theta: f64) -> f64 {
    let n = a.nrows();
    let z = Complex::new(theta.cos(), theta.sin());
    let mut m: DMatrix<Complex<f64>> = a.map(|v| Complex::new(-v, 0.0));
    for i in 0..n {
        m[(i, i)] += z;
    }
    let bc = b.map(|v| Complex::new(v, 0.0));
    let Some(x) = m.lu().solve(&bc) else {
        return f64::INFINITY;
    };
    let g = c.map(|v| Complex::new(v, 0.0)) * x;
    match crate::numerics::eigen::singular_values(&g) {
        Some(sv) => sv.iter().fold(0.0, |m, v| m.max(*v)),
        None => f64::INFINITY,
    }
}

/// H-infinity norm of the discrete system `(A, B, C)` (no feedthrough) by a frequency
/// sweep: 600 log-spaced `theta` in `[1e-8, pi]` plus `0`, then golden-section refinement
/// around the largest value. Infinite when `A` has a pole on or outside the unit circle.
pub fn hinf_norm(a: &DMatrix<f64>, b: &DMatrix<f64>, c: &DMatrix<f64>) -> f64 {
    if !(spectral_radius(a) < 1.0) {
        return f64::INFINITY;
    }
    let npts = 600;
    let (lo, hi) = (1e-8f64.ln(), core::f64::consts::PI.ln());
    let thetas: Vec<f64> = core::iter::once(0.0)
        .chain((0..npts).map(|k| (lo + (hi - lo) * k as f64 / (npts - 1) as f64).exp()))
        .collect();
    let vals: Vec<f64> = thetas.iter().map(|t| gain_at(a, b, c, *t)).collect();
    let (mut kbest, mut best) = (0, f64::NEG_INFINITY);
    for (k, v) in vals.iter().enumerate() {
        if *v > best {
            best = *v;
            kbest = k;
        }
    }
    // golden-section search on [theta_{k-1}, theta_{k+1}]
    let mut x0 = thetas[kbest.saturating_sub(1)];
    let mut x3 = thetas[(kbest + 1).min(thetas.len() - 1)];
    let r = 0.618_033_988_749_895;
    for _ in 0..60 {
        let x1 = x3 - r * (x3 - x0);
        let x2 = x0 + r * (x3 - x0);
        let (f1, f2) = (gain_at(a, b, c, x1), gain_at(a, b, c, x2));
        best = best.max(f1).max(f2);
        if f1 > f2 {
            x3 = x2;
        } else {
            x0 = x1;
        }
    }
    best
}

/// The filter-error system of paper 002 eq. (14) at the true transition `a_true`.
pub fn error_system(
    plant: &HinfPlant,
    f: &HinfMatrices,
    a_true: &Mat6,
) -> (DMatrix<f64>, DMatrix<f64>, DMatrix<f64>) {
    let mut a = DMatrix::zeros(12, 12);
    put(&mut a, 0, 0, &dm(a_true), false);
    put(&mut a, 6, 0, &dm(&(f.b_f * plant.c)), false);
    put(&mut a, 6, 6, &dm(&f.a_f), false);
    let mut b = DMatrix::zeros(12, 9);
    put(&mut b, 0, 0, &dm(&plant.b), false);
    put(&mut b, 6, 6, &dm(&(f.b_f * plant.d)), false);
    let mut c = DMatrix::zeros(6, 12);
    put(&mut c, 0, 0, &dm(&plant.l), false);
    put(&mut c, 0, 6, &dm(&(-f.c_f)), false);
    (a, b, c)
}

/// `n` points evenly spaced over `[-delta_bar, delta_bar]` (`n >= 2`; `0` included when `n`
/// is odd).
pub fn delta_grid(delta_bar: f64, n: usize) -> Vec<f64> {
    let n = n.max(2);
    (0..n)
        .map(|k| -delta_bar + 2.0 * delta_bar * k as f64 / (n - 1) as f64)
        .collect()
}

/// Largest spectral radius and worst H-infinity norm of the error systems
/// `system(delta) = (A, B, C)` over `deltas` (shared by both verifiers).
fn worst_case<F: FnMut(f64) -> (DMatrix<f64>, DMatrix<f64>, DMatrix<f64>)>(
    deltas: &[f64],
    mut system: F,
) -> Verification {
    let mut v = Verification {
        max_spectral_radius: 0.0,
        worst_norm: 0.0,
        worst_delta: f64::NAN,
    };
    for &d in deltas {
        let (a, b, c) = system(d);
        v.max_spectral_radius = v.max_spectral_radius.max(spectral_radius(&a));
        let nrm = hinf_norm(&a, &b, &c);
        if !(nrm <= v.worst_norm) {
            v.worst_norm = nrm;
            v.worst_delta = d;
        }
    }
    v
}

/// Worst case over `deltas` of the paper's filter-error system: `a_of(delta)` is the
/// true plant transition.
pub fn verify_filter<F: Fn(f64) -> Mat6>(
    plant: &HinfPlant,
    f: &HinfMatrices,
    deltas: &[f64],
    a_of: F,
) -> Verification {
    worst_case(deltas, |d| error_system(plant, f, &a_of(d)))
}

/// The observer's error system `e(k+1) = (A(delta) - G C) e + B w - G D v`, `z_e = L e`,
/// worst case over `deltas` (the term `(A(delta) - A) x` is the robustness channel and is
/// not part of this transfer).
pub fn observer_error_norm<const M: usize, F: Fn(f64) -> Mat6>(
    plant: &HinfPlant<M>,
    g: &Gain<M>,
    deltas: &[f64],
    a_of: F,
) -> Verification {
    let mut b = DMatrix::zeros(6, 6 + M);
    put(&mut b, 0, 0, &dm(&plant.b), false);
    put(&mut b, 0, 6, &dm(&(-(g * plant.d))), false);
    let c = dm(&plant.l);
    worst_case(deltas, |d| {
        (dm(&(a_of(d) - g * plant.c)), b.clone(), c.clone())
    })
}

/// One step of a time-varying error system `e(k+1) = A_k e(k) + Bbar_k d(k)`, `z(k) = L
/// e(k)`: `A_k` and `W_k = Bbar_k Bbar_k^T` (all the gain test needs of the input).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VaryingStep {
    /// The step's error transition `A_k`.
    pub a: Mat6,
    /// `Bbar_k Bbar_k^T`.
    pub w: Mat6,
}

/// The forward bounded-real Riccati recursion of a time-varying system from `y0`: `Y(k+1)
/// = A_k (Y + Y L^T S^-1 L Y) A_k^T + W_k` (`= A_k (Y^-1 - gamma^-2 L^T L)^-1 A_k^T + W_k`)
/// while `S = gamma^2 I - L Y(k) L^T` is positive definite (a Cholesky factorisation at
/// every `k` through the last): the last `Y`, or `None` where it is not.
pub fn varying_riccati(steps: &[VaryingStep], l: &Mat6, gamma: f64, y0: &Mat6) -> Option<Mat6> {
    let g2 = Mat6::identity() * (gamma * gamma);
    let mut y = *y0;
    for s in steps {
        let ly = l * y;
        let ch = (g2 - ly * l.transpose()).cholesky()?;
        let inner = y + ly.transpose() * ch.solve(&ly);
        let next = s.a * inner * s.a.transpose() + s.w;
        y = (next + next.transpose()) * 0.5;
        if !y.iter().all(|v| v.is_finite()) {
            return None;
        }
    }
    (g2 - l * y * l.transpose()).cholesky().map(|_| y)
}

/// Whether the l2 gain from `d` to `z = L e` over `steps` from a zero initial error is
/// below `gamma`: the bounded-real lemma of a time-varying system in its forward (filter)
/// form, [`varying_riccati`] from `Y(0) = 0` passes. Necessary and sufficient over the
/// horizon; for a time-invariant system it tends, as the horizon grows, to the H-infinity
/// norm (tested against the frequency sweep).
pub fn varying_gain_below(steps: &[VaryingStep], l: &Mat6, gamma: f64) -> bool {
    varying_riccati(steps, l, gamma, &Mat6::zeros()).is_some()
}

/// For a periodic system whose one period is `period` (its steps repeat): whether `y_bar`
/// closes a period at `gamma`, `varying_riccati(period, y_bar) <= y_bar` (Loewner order, a
/// Cholesky factorisation of the difference). The recursion is monotone in `Y`, so then
/// every period from `y_bar` stays below `y_bar`'s first, and a run from `Y(0) <= y_bar`
/// never fails: the gain is below `gamma` over every horizon.
pub fn closes_period(period: &[VaryingStep], l: &Mat6, gamma: f64, y_bar: &Mat6) -> bool {
    varying_riccati(period, l, gamma, y_bar).is_some_and(|y| (y_bar - y).cholesky().is_some())
}

/// The l2 gain of [`varying_gain_below`]'s system over `steps` (zero initial error), by
/// bisection on `gamma` to a relative `tol`: the smallest `gamma` found to pass (an upper
/// bound within `tol` of the gain); infinite if none below `1e150` does.
pub fn varying_l2_gain(steps: &[VaryingStep], l: &Mat6, tol: f64) -> f64 {
    let passes = |g: f64| varying_gain_below(steps, l, g);
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    while !passes(hi) {
        lo = hi;
        hi *= 2.0;
        if hi > 1e150 {
            return f64::INFINITY;
        }
    }
    if lo == 0.0 {
        lo = hi;
        while lo > 1e-150 && passes(lo * 0.5) {
            lo *= 0.5;
        }
        hi = lo;
        lo *= 0.5;
    }
    while hi > lo * (1.0 + tol) {
        let mid = (lo * hi).sqrt();
        if passes(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}
