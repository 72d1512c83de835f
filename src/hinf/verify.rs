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

use super::{HinfMatrices, HinfPlant};
use crate::types::{Mat6, Mat63};
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
pub fn lmi_observer(plant: &HinfPlant, p: &DMatrix<f64>, g: &Mat63, gamma2: f64) -> DMatrix<f64> {
    let ae = dm(&(plant.a - g * plant.c));
    let gd = dm(&(g * plant.d));
    let hae = dm(&(plant.ha * plant.ea.norm()));
    let (b, l) = (dm(&plant.b), dm(&plant.l));
    let o = [0, 6, 12, 18, 21, 27];
    let i = |k: usize| DMatrix::<f64>::identity(k, k);
    let mut m = DMatrix::zeros(33, 33);
    put(&mut m, o[0], o[0], &(-p), true);
    put(&mut m, o[0], o[1], &(p * &ae), true);
    put(&mut m, o[0], o[2], &(p * &b), true);
    put(&mut m, o[0], o[3], &(-(p * &gd)), true);
    put(&mut m, o[0], o[4], &(p * &hae), true);
    put(&mut m, o[1], o[1], &(-p), true);
    put(&mut m, o[1], o[5], &l.transpose(), true);
    put(&mut m, o[2], o[2], &(-i(6) * gamma2), true);
    put(&mut m, o[3], o[3], &(-i(3) * gamma2), true);
    put(&mut m, o[4], o[4], &(-i(6) * gamma2), true);
    put(&mut m, o[5], o[5], &(-i(6)), true);
    m
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
    let (lo, hi) = (1e-8f64.ln(), std::f64::consts::PI.ln());
    let thetas: Vec<f64> = std::iter::once(0.0)
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
pub fn observer_error_norm<F: Fn(f64) -> Mat6>(
    plant: &HinfPlant,
    g: &Mat63,
    deltas: &[f64],
    a_of: F,
) -> Verification {
    let mut b = DMatrix::zeros(6, 9);
    put(&mut b, 0, 0, &dm(&plant.b), false);
    put(&mut b, 0, 6, &dm(&(-(g * plant.d))), false);
    let c = dm(&plant.l);
    worst_case(deltas, |d| {
        (dm(&(a_of(d) - g * plant.c)), b.clone(), c.clone())
    })
}
