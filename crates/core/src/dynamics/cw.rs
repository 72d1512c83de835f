//! Clohessy–Wiltshire (Hill) relative dynamics in the canonical frame.
//!
//! Continuous model (canonical frame: x radial, y along-track, z orbit normal; target on a
//! circular orbit of mean motion `n`; `a = F / m` the chaser's thrust acceleration):
//!
//! ```text
//! x'' = 3 n^2 x + 2 n y' + a_x
//! y'' =        - 2 n x' + a_y
//! z'' =   -n^2 z        + a_z
//! ```
//!
//! i.e. `X' = A X + B a` with `B = [0; I3]`. This is the model of papers 000 and 002 (their
//! frames differ, see [`crate::frames`]). The discrete model over a step `T` is
//! `X(k+1) = Phi(T) X(k) + Gamma(T) a(k) + w(k)` with
//!
//! * `Phi(T) = exp(A T)` in closed form ([`CwModel::phi`]),
//! * `Gamma(T) = integral_0^T Phi(s) ds B` — the exact zero-order-hold input matrix for an
//!   acceleration held constant over the step ([`CwModel::gamma`]),
//! * `Qd(T) = integral_0^T Phi(s) B Qc B^T Phi(s)^T ds` for a continuous white acceleration of
//!   spectral density `Qc = diag(psd)` [m^2/s^3], in closed form ([`CwModel::process_noise`];
//!   Van Loan's matrix exponential gives the same matrix and is the test's reference).
//!
//! Every function here does a fixed amount of work whatever the numbers (no iteration,
//! no matrix exponential): a huge step gives large or non-finite entries, which the
//! filters refuse, never a hang or a panic.
//!
//! Paper 000 discretises with Euler, `Phi = I + T A`; [`Discretization::Euler`] keeps that
//! only so the paper can be reproduced literally.

use super::{DiscreteModel, Discretization, RelativeDynamics};
#[cfg(not(feature = "std"))]
use crate::math::Float;
use crate::types::{Mat3, Mat6, Mat63, State, Vec3};

/// The CW model for one mean motion `n` [rad/s].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CwModel {
    /// Mean motion of the target's circular orbit [rad/s].
    pub n: f64,
}

/// Below this `|n t|` the process noise is summed as a series ([`CwModel::process_noise`]).
const NOISE_SERIES_THETA: f64 = 1.0;
/// Terms of that series: `(2 theta)^k / k!` is below 1e-17 of the first for `k >= 27`.
const NOISE_SERIES_TERMS: usize = 30;

/// `(theta - sin theta)`, accurate also for small `theta` (no cancellation).
fn theta_minus_sin(theta: f64) -> f64 {
    if theta.abs() < 0.05 {
        // theta^3/3! - theta^5/5! + theta^7/7! - theta^9/9!: truncation < theta^11/11! < 2e-22
        let t2 = theta * theta;
        theta * t2 / 6.0 * (1.0 - t2 / 20.0 * (1.0 - t2 / 42.0 * (1.0 - t2 / 72.0)))
    } else {
        theta - theta.sin()
    }
}

impl CwModel {
    /// Model for mean motion `n` [rad/s] (`n > 0`; callers validate).
    pub fn new(n: f64) -> Self {
        Self { n }
    }

    /// Mean motion of a circular orbit of period `period` [s]: `n = 2 pi / period`.
    pub fn from_period(period: f64) -> Self {
        Self::new(2.0 * core::f64::consts::PI / period)
    }

    /// The continuous system matrix `A` (canonical frame).
    pub fn continuous_a(&self) -> Mat6 {
        let n = self.n;
        let mut a = Mat6::zeros();
        a[(0, 3)] = 1.0;
        a[(1, 4)] = 1.0;
        a[(2, 5)] = 1.0;
        a[(3, 0)] = 3.0 * n * n;
        a[(3, 4)] = 2.0 * n;
        a[(4, 3)] = -2.0 * n;
        a[(5, 2)] = -n * n;
        a
    }

    /// The continuous input matrix `B = [0; I3]`.
    pub fn continuous_b() -> Mat63 {
        let mut b = Mat63::zeros();
        b.fixed_view_mut::<3, 3>(3, 0).copy_from(&Mat3::identity());
        b
    }

    /// Closed-form CW transition matrix `Phi(t) = exp(A t)` (Clohessy & Wiltshire 1960;
    /// e.g. Vallado, *Fundamentals of Astrodynamics*, sec. 6.8), written with
    /// `theta = n t`, `s = sin theta`, `c = cos theta`:
    ///
    /// ```text
    /// x  = (4 - 3c) x0 + s/n vx0 + 2(1 - c)/n vy0
    /// y  = 6(s - theta) x0 + y0 - 2(1 - c)/n vx0 + (4 s - 3 theta)/n vy0
    /// z  = c z0 + s/n vz0
    /// vx = 3 n s x0 + c vx0 + 2 s vy0
    /// vy = -6 n (1 - c) x0 - 2 s vx0 + (4 c - 3) vy0
    /// vz = -n s z0 + c vz0
    /// ```
    ///
    /// `1 - c` is evaluated as `2 sin^2(theta/2)` and `theta - s` by a series for small
    /// `theta`, so the matrix stays accurate for `n t` down to 1e-12 (paper 002: 7e-6).
    pub fn phi(&self, t: f64) -> Mat6 {
        let n = self.n;
        let th = n * t;
        let (s, c) = th.sin_cos();
        let omc = 2.0 * (0.5 * th).sin().powi(2); // 1 - cos
        let tms = theta_minus_sin(th); // theta - sin
        let mut p = Mat6::zeros();
        p[(0, 0)] = 1.0 + 3.0 * omc; // 4 - 3c
        p[(0, 3)] = s / n;
        p[(0, 4)] = 2.0 * omc / n;
        p[(1, 0)] = -6.0 * tms;
        p[(1, 1)] = 1.0;
        p[(1, 3)] = -2.0 * omc / n;
        p[(1, 4)] = (4.0 * s - 3.0 * th) / n;
        p[(2, 2)] = c;
        p[(2, 5)] = s / n;
        p[(3, 0)] = 3.0 * n * s;
        p[(3, 3)] = c;
        p[(3, 4)] = 2.0 * s;
        p[(4, 0)] = -6.0 * n * omc;
        p[(4, 3)] = -2.0 * s;
        p[(4, 4)] = 4.0 * c - 3.0;
        p[(5, 2)] = -n * s;
        p[(5, 5)] = c;
        p
    }

    /// Exact zero-order-hold input matrix `Gamma(t) = integral_0^t Phi(s) ds B` for an
    /// acceleration held constant over `[0, t)`. Integrating the velocity columns of
    /// [`CwModel::phi`] term by term:
    ///
    /// ```text
    /// a_x column: ( (1-c)/n^2, -2(theta - s)/n^2, 0, s/n, -2(1-c)/n, 0 )
    /// a_y column: ( 2(theta - s)/n^2, 4(1-c)/n^2 - 3 t^2/2, 0, 2(1-c)/n, (4 s - 3 theta)/n, 0 )
    /// a_z column: ( 0, 0, (1-c)/n^2, 0, 0, s/n )
    /// ```
    pub fn gamma(&self, t: f64) -> Mat63 {
        let n = self.n;
        let th = n * t;
        let s = th.sin();
        let omc = 2.0 * (0.5 * th).sin().powi(2);
        let tms = theta_minus_sin(th);
        let n2 = n * n;
        let mut g = Mat63::zeros();
        g[(0, 0)] = omc / n2;
        g[(1, 0)] = -2.0 * tms / n2;
        g[(3, 0)] = s / n;
        g[(4, 0)] = -2.0 * omc / n;
        g[(0, 1)] = 2.0 * tms / n2;
        g[(1, 1)] = 4.0 * omc / n2 - 1.5 * t * t;
        g[(3, 1)] = 2.0 * omc / n;
        g[(4, 1)] = (4.0 * s - 3.0 * th) / n;
        g[(2, 2)] = omc / n2;
        g[(5, 2)] = s / n;
        g
    }

    /// Discrete process noise `Qd(t) = integral_0^t Phi(s) B diag(psd) B^T Phi(s)^T ds` of a
    /// continuous white acceleration with spectral density `psd` [m^2/s^3] per canonical
    /// axis, in closed form (what Van Loan's matrix exponential computes, C. F. Van Loan,
    /// "Computing integrals involving the matrix exponential", IEEE TAC 23(3), 1978, without
    /// the exponential). With `theta = n t`, `s = sin theta`, `c = cos theta`,
    /// `w = 1 - c`, `s2 = sin 2 theta` and `a = theta - s2 / 2`, integrating the products of
    /// the velocity columns of [`CwModel::phi`] gives, per unit density (the matrix is
    /// symmetric; entries not listed are zero):
    ///
    /// ```text
    /// radial   (q_x):  xx    = a / (2 n^3)                 xy    = -w^2 / n^3
    ///                  x vx  = s^2 / (2 n^2)               x vy  = -a / n^2
    ///                  yy    = 2 (3 theta - 4 s + s2/2) / n^3
    ///                  y vx  = (theta - 2 s + s2/2) / n^2  y vy  = 2 w^2 / n^2
    ///                  vx vx = (theta + s2/2) / (2 n)      vx vy = -s^2 / n
    ///                  vy vy = 2 a / n
    /// along    (q_y):  xx    = 2 (3 theta - 4 s + s2/2) / n^3
    ///                  xy    = (-3 theta^2 + 6 theta s + 2 w - 4 s^2) / n^3
    ///                  x vx  = 2 w^2 / n^2                 x vy  = 2 (7 s - 5 theta - s2) / n^2
    ///                  yy    = (3 theta^3 + 24 theta c + 8 theta - 24 s - 4 s2) / n^3
    ///                  y vx  = 2 (3 theta c + 2 theta - 3 s - s2) / n^2
    ///                  y vy  = (3 theta - 4 s)^2 / (2 n^2)
    ///                  vx vx = 2 a / n                     vx vy = 2 (2 s^2 - 3 w) / n
    ///                  vy vy = (17 theta - 24 s + 4 s2) / n
    /// normal   (q_z):  zz    = a / (2 n^3)   z vz = s^2 / (2 n^2)   vz vz = (theta + s2/2) / (2 n)
    /// ```
    ///
    /// As `n -> 0` every axis tends to the double integrator `[[t^3/3, t^2/2], [t^2/2, t]]`.
    /// These expressions cancel catastrophically for small `theta` (the radial `yy` is
    /// `theta^5 / (5 n^3) + ...` from terms of size `theta / n^3`), so below
    /// `|theta| = 1` the same integral is summed as its Taylor series
    /// `Qd = sum_k M_k t^(k+1) / (k+1)!`, `M_0 = B diag(psd) B^T`, `M_(k+1) = A M_k + M_k A^T`
    /// (the derivatives of `Phi(s) M_0 Phi(s)^T` at 0), with a fixed number of terms (30:
    /// the terms fall like `(2 theta)^k / k!`). Both branches are accurate to ~1e-14
    /// relative per entry (tested against the Van Loan exponential, quadrature and the
    /// double integrator in `tests`); the work is bounded whatever `n` and `t` (no
    /// iteration depends on the numbers), and a huge `n t` gives large or infinite entries,
    /// never a hang.
    pub fn process_noise(&self, psd: &Vec3, t: f64) -> Mat6 {
        if (self.n * t).abs() < NOISE_SERIES_THETA {
            let mut m0 = Mat6::zeros();
            for i in 0..3 {
                m0[(3 + i, 3 + i)] = psd[i];
            }
            self.noise_series(m0, t)
        } else {
            let [qx, qy, qz] = self.noise_closed_form(t);
            qx * psd[0] + qy * psd[1] + qz * psd[2]
        }
    }

    /// [`CwModel::process_noise`] of a unit density on each canonical axis (radial,
    /// along-track, normal); `process_noise(psd, t) = sum_i psd_i axes_i` (linear in `psd`).
    pub fn process_noise_axes(&self, t: f64) -> [Mat6; 3] {
        if (self.n * t).abs() < NOISE_SERIES_THETA {
            core::array::from_fn(|i| {
                let mut m0 = Mat6::zeros();
                m0[(3 + i, 3 + i)] = 1.0;
                self.noise_series(m0, t)
            })
        } else {
            self.noise_closed_form(t)
        }
    }

    /// `sum_k M_k t^(k+1) / (k+1)!` (see [`CwModel::process_noise`]); exactly symmetric.
    fn noise_series(&self, m0: Mat6, t: f64) -> Mat6 {
        let mut m = m0;
        let mut q = Mat6::zeros();
        let mut coef = t; // t^(k+1) / (k+1)!
        for k in 0..NOISE_SERIES_TERMS {
            q += m * coef;
            let am = self.a_times(&m);
            m = am + am.transpose();
            coef *= t / (k + 2) as f64;
        }
        q
    }

    /// `A M` with [`CwModel::continuous_a`]'s seven non-zero entries alone: the same sums
    /// as the dense product less its terms with a zero factor. The series takes one
    /// product per term, and dense products were most of the work of a step whose length
    /// changed (docs/c-abi.md, "Work per step").
    fn a_times(&self, m: &Mat6) -> Mat6 {
        let n = self.n;
        let (k3, k2, w) = (3.0 * n * n, -n * n, 2.0 * n);
        Mat6::from_fn(|i, j| match i {
            0..=2 => m[(i + 3, j)],
            3 => k3 * m[(0, j)] + w * m[(4, j)],
            4 => -w * m[(3, j)],
            _ => k2 * m[(2, j)],
        })
    }

    /// The closed-form entries of [`CwModel::process_noise`] per unit-density axis.
    fn noise_closed_form(&self, t: f64) -> [Mat6; 3] {
        let n = self.n;
        let th = n * t;
        let (s, c) = th.sin_cos();
        let w = 2.0 * (0.5 * th).sin().powi(2); // 1 - cos
        let s2 = (2.0 * th).sin();
        let a = 0.5 * theta_minus_sin(2.0 * th); // theta - sin(2 theta) / 2
        let (n2, n3) = (n * n, n * n * n);
        let sym = |entries: &[(usize, usize, f64)]| {
            let mut m = Mat6::zeros();
            for &(i, j, v) in entries {
                m[(i, j)] = v;
                m[(j, i)] = v;
            }
            m
        };
        let yy_x = 2.0 * (3.0 * th - 4.0 * s + 0.5 * s2) / n3;
        let radial = sym(&[
            (0, 0, a / (2.0 * n3)),
            (0, 1, -w * w / n3),
            (0, 3, s * s / (2.0 * n2)),
            (0, 4, -a / n2),
            (1, 1, yy_x),
            (1, 3, (th - 2.0 * s + 0.5 * s2) / n2),
            (1, 4, 2.0 * w * w / n2),
            (3, 3, (th + 0.5 * s2) / (2.0 * n)),
            (3, 4, -s * s / n),
            (4, 4, 2.0 * a / n),
        ]);
        let along = sym(&[
            (0, 0, yy_x),
            (
                0,
                1,
                (-3.0 * th * th + 6.0 * th * s + 2.0 * w - 4.0 * s * s) / n3,
            ),
            (0, 3, 2.0 * w * w / n2),
            (0, 4, 2.0 * (7.0 * s - 5.0 * th - s2) / n2),
            (
                1,
                1,
                (3.0 * th * th * th + 24.0 * th * c + 8.0 * th - 24.0 * s - 4.0 * s2) / n3,
            ),
            (1, 3, 2.0 * (3.0 * th * c + 2.0 * th - 3.0 * s - s2) / n2),
            (1, 4, (3.0 * th - 4.0 * s).powi(2) / (2.0 * n2)),
            (3, 3, 2.0 * a / n),
            (3, 4, 2.0 * (2.0 * s * s - 3.0 * w) / n),
            (4, 4, (17.0 * th - 24.0 * s + 4.0 * s2) / n),
        ]);
        let normal = sym(&[
            (2, 2, a / (2.0 * n3)),
            (2, 5, s * s / (2.0 * n2)),
            (5, 5, (th + 0.5 * s2) / (2.0 * n)),
        ]);
        [radial, along, normal]
    }

    /// Discrete process noise for a continuous white acceleration of spectral density `qc`
    /// (3x3, symmetric, canonical frame, [m^2/s^3]): the Van Loan integral
    /// `Qd(t) = integral_0^t Phi(s) B qc B^T Phi(s)^T ds` (C. F. Van Loan, IEEE TAC 23(3),
    /// 1978) without the matrix exponential. A diagonal `qc` (every caller in relnav) is
    /// [`CwModel::process_noise`] of its diagonal (closed form, or the series below
    /// `|n t| = 1`). Otherwise the series is summed over `t / 2^k` with the least `k` that
    /// brings `|n t| / 2^k` below 1, and doubled `k` times by
    /// `Qd(2 s) = Qd(s) + Phi(s) Qd(s) Phi(s)^T` (`k <= 1025` for any finite `n t`: bounded
    /// work). A non-finite `n t` gives an all-NaN matrix, which the filters refuse.
    pub fn van_loan_q(&self, qc: &Mat3, t: f64) -> Mat6 {
        let qc = (qc + qc.transpose()) * 0.5;
        if (0..3).all(|i| (0..3).all(|j| i == j || qc[(i, j)] == 0.0)) {
            return self.process_noise(&qc.diagonal(), t);
        }
        let theta = (self.n * t).abs();
        if !theta.is_finite() {
            return Mat6::from_element(f64::NAN);
        }
        let b = Self::continuous_b();
        let m0 = b * qc * b.transpose();
        let mut k = 0i32;
        while theta * 0.5f64.powi(k) >= NOISE_SERIES_THETA {
            k += 1;
        }
        let mut s = t * 0.5f64.powi(k);
        let mut q = self.noise_series(m0, s);
        for _ in 0..k {
            let phi = self.phi(s);
            q += phi * q * phi.transpose();
            q = (q + q.transpose()) * 0.5;
            s *= 2.0;
        }
        q
    }

    /// The discrete model over a step `dt` (from `t = 0`; the model is time-invariant) with a continuous white acceleration of
    /// spectral density `qc` (3x3, canonical frame, [m^2/s^3]; noise by
    /// [`CwModel::van_loan_q`]).
    pub fn discretize(&self, dt: f64, qc: &Mat3, method: Discretization) -> DiscreteModel {
        match method {
            Discretization::Exact => DiscreteModel {
                t: 0.0,
                dt,
                phi: self.phi(dt),
                gamma: self.gamma(dt),
                q: if qc.iter().all(|v| *v == 0.0) {
                    Mat6::zeros()
                } else {
                    self.van_loan_q(qc, dt)
                },
            },
            Discretization::Euler => {
                let b = Self::continuous_b();
                DiscreteModel {
                    t: 0.0,
                    dt,
                    phi: Mat6::identity() + self.continuous_a() * dt,
                    gamma: b * dt,
                    q: b * qc * b.transpose() * dt,
                }
            }
        }
    }

    /// Propagate a state exactly over `t` with a constant acceleration `accel`.
    pub fn propagate(&self, x: &State, accel: &Vec3, t: f64) -> State {
        self.phi(t) * x + self.gamma(t) * accel
    }
}

/// CW is time-invariant: every step of the same length is the same.
impl RelativeDynamics for CwModel {
    fn step(&self, t: f64, dt: f64, qc: &Mat3, method: Discretization) -> DiscreteModel {
        DiscreteModel {
            t,
            ..self.discretize(dt, qc, method)
        }
    }
    fn step_noise(&self, _t: f64, dt: f64, qc: &Mat3) -> Mat6 {
        self.van_loan_q(qc, dt)
    }
    fn system_matrix(&self, _t: f64) -> Mat6 {
        self.continuous_a()
    }
    fn time_invariant(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    const N: f64 = 2.0 * core::f64::consts::PI / 7200.0;

    /// Reference: integrate X' = A X + B a with classical RK4 at a tiny step.
    fn rk4(model: &CwModel, x0: &State, a: &Vec3, t: f64, steps: usize) -> State {
        let am = model.continuous_a();
        let b = CwModel::continuous_b();
        let f = |x: &State| am * x + b * a;
        let h = t / steps as f64;
        let mut x = *x0;
        for _ in 0..steps {
            let k1 = f(&x);
            let k2 = f(&(x + k1 * (h / 2.0)));
            let k3 = f(&(x + k2 * (h / 2.0)));
            let k4 = f(&(x + k3 * h));
            x += (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);
        }
        x
    }

    #[test]
    fn phi_matches_the_matrix_exponential() {
        let m = CwModel::new(N);
        for t in [0.1, 1.0, 60.0, 1800.0, 7200.0] {
            let e = (m.continuous_a() * t).exp();
            assert!((m.phi(t) - e).norm() < 1e-9 * e.norm(), "t = {t}");
        }
    }

    #[test]
    fn closed_relative_orbit_returns_after_one_period() {
        // Bounded CW orbit: vy0 = -2 n x0 (canonical), any z motion.
        let m = CwModel::new(N);
        let x0 = State::from_row_slice(&[100.0, 30.0, 50.0, 0.05, -2.0 * N * 100.0, 0.02]);
        let x = m.propagate(&x0, &Vec3::zeros(), 7200.0);
        assert!((x - x0).norm() < 1e-9, "{x} vs {x0}");
        // halfway the radial offset has changed sign
        let xh = m.propagate(&x0, &Vec3::zeros(), 3600.0);
        assert_relative_eq!(xh[0], -100.0, epsilon = 1e-9);
    }

    #[test]
    fn along_track_velocity_offset_drifts() {
        // Closed form: an along-track velocity offset vy0 alone gives, after a full period
        // (theta = 2 pi), y = -3 theta vy0 / n = -3 vy0 T, x = 0 (Vallado eq. 6-66).
        let m = CwModel::new(N);
        let vy0 = 0.01;
        let x0 = State::from_row_slice(&[0.0, 0.0, 0.0, 0.0, vy0, 0.0]);
        let x = m.propagate(&x0, &Vec3::zeros(), 7200.0);
        assert_relative_eq!(x[1], -3.0 * vy0 * 7200.0, max_relative = 1e-12);
        assert!(x[0].abs() < 1e-9 && (x[4] - vy0).abs() < 1e-12);
    }

    #[test]
    fn gamma_is_exact_zoh() {
        let m = CwModel::new(N);
        let a = Vec3::new(1e-3, -2e-3, 5e-4);
        let x0 = State::from_row_slice(&[400.0, 500.0, 200.0, 0.1, 0.0, -0.1]);
        for t in [1.0, 60.0, 600.0] {
            let exact = m.propagate(&x0, &a, t);
            let reference = rk4(&m, &x0, &a, t, 20_000);
            assert!(
                (exact - reference).norm() < 1e-9 * (1.0 + reference.norm()),
                "t = {t}"
            );
        }
    }

    #[test]
    fn tiny_theta_is_accurate() {
        // paper 002: w0 = 7.2722e-5, T = 0.1 s -> theta = 7e-6; compare with a series
        // expansion of exp(A t) to third order, which is exact to ~(n t)^4 here.
        let m = CwModel::new(7.2722e-5);
        let t = 0.1;
        let a = m.continuous_a() * t;
        let series = Mat6::identity() + a + a * a / 2.0 + a * a * a / 6.0 + a * a * a * a / 24.0;
        assert!((m.phi(t) - series).norm() < 1e-15);
        let b = CwModel::continuous_b();
        let gs = (Mat6::identity() * t + a * t / 2.0 + a * a * t / 6.0 + a * a * a * t / 24.0) * b;
        assert!((m.gamma(t) - gs).norm() < 1e-16, "{}", m.gamma(t) - gs);
    }

    /// Van Loan's reference: `exp([[-A, B Qc B^T], [0, A^T]] t)`, `Qd = F22^T F12`
    /// (nalgebra's Pade exponential; fine at moderate `n t`).
    fn van_loan(m: &CwModel, psd: &Vec3, t: f64) -> Mat6 {
        van_loan_full(m, &Mat3::from_diagonal(psd), t)
    }

    /// [`van_loan`] of a full (symmetric) `qc`.
    fn van_loan_full(m: &CwModel, qc: &Mat3, t: f64) -> Mat6 {
        let a = m.continuous_a();
        let b = CwModel::continuous_b();
        let mut big = nalgebra::SMatrix::<f64, 12, 12>::zeros();
        big.fixed_view_mut::<6, 6>(0, 0).copy_from(&(-a * t));
        big.fixed_view_mut::<6, 6>(0, 6)
            .copy_from(&(b * qc * b.transpose() * t));
        big.fixed_view_mut::<6, 6>(6, 6)
            .copy_from(&(a.transpose() * t));
        let e = big.exp();
        let f12: Mat6 = e.fixed_view::<6, 6>(0, 6).into_owned();
        let f22: Mat6 = e.fixed_view::<6, 6>(6, 6).into_owned();
        f22.transpose() * f12
    }

    /// Composite Gauss-Legendre (5 points per panel) of `Phi(s) B diag(psd) B^T Phi(s)^T`
    /// over `[0, t]`, with the closed-form `Phi` (itself checked against `exp(A t)`).
    fn quadrature(m: &CwModel, psd: &Vec3, t: f64, panels: usize) -> Mat6 {
        let x = [
            0.0,
            0.538_469_310_105_683_1,
            -0.538_469_310_105_683_1,
            0.906_179_845_938_664,
            -0.906_179_845_938_664,
        ];
        let w = [
            0.568_888_888_888_888_9,
            0.478_628_670_499_366_5,
            0.478_628_670_499_366_5,
            0.236_926_885_056_189_1,
            0.236_926_885_056_189_1,
        ];
        let b = CwModel::continuous_b();
        let qc = b * Mat3::from_diagonal(psd) * b.transpose();
        let h = t / panels as f64;
        let mut q = Mat6::zeros();
        for k in 0..panels {
            let mid = (k as f64 + 0.5) * h;
            for (xi, wi) in x.iter().zip(w) {
                let p = m.phi(mid + 0.5 * h * xi);
                q += p * qc * p.transpose() * (0.5 * h * wi);
            }
        }
        q
    }

    /// Largest entry error relative to the entry's natural scale `sqrt(Q_ii Q_jj)`.
    fn scaled_error(q: &Mat6, reference: &Mat6) -> f64 {
        let mut e: f64 = 0.0;
        for i in 0..6 {
            for j in 0..6 {
                let scale = (reference[(i, i)] * reference[(j, j)]).sqrt();
                if scale > 0.0 {
                    e = e.max((q[(i, j)] - reference[(i, j)]).abs() / scale);
                } else {
                    assert_eq!(q[(i, j)], 0.0, "({i}, {j})");
                }
            }
        }
        e
    }

    #[test]
    fn process_noise_matches_the_van_loan_exponential() {
        let m = CwModel::new(N);
        let psd = Vec3::new(1e-6, 2e-6, 5e-7);
        // n t from 0.01 to 6 rad, both sides of the series/closed-form switch at 1
        for theta in [0.01, 0.3, 0.999, 1.0, 1.001, 2.0, 6.0] {
            let t = theta / N;
            let e = scaled_error(&m.process_noise(&psd, t), &van_loan(&m, &psd, t));
            eprintln!("n t = {theta}: closed form vs Van Loan exponential {e:.1e}");
            assert!(e < 1e-10, "theta = {theta}: {e:e}");
        }
    }

    #[test]
    fn process_noise_matches_quadrature() {
        let m = CwModel::new(1.1e-3);
        let psd = Vec3::new(3e-8, 1e-8, 2e-8);
        for theta in [1e-6, 1e-3, 0.3, 1.0, 3.0, 30.0, 300.0] {
            let t = theta / m.n;
            let panels = (20.0 * theta).ceil().max(20.0) as usize;
            let q = m.process_noise(&psd, t);
            let e = scaled_error(&q, &quadrature(&m, &psd, t, panels));
            eprintln!("n t = {theta}: closed form vs quadrature {e:.1e}");
            assert!(e < 1e-11, "theta = {theta}: {e:e}");
            // symmetric positive definite
            assert_eq!(q, q.transpose());
            assert!(q.cholesky().is_some(), "theta = {theta}");
        }
    }

    #[test]
    fn process_noise_small_theta_keeps_every_digit() {
        // leading terms of the entries the closed form cancels to (series from SymPy):
        // radial yy = n^2 t^5 / 5 (1 - 5 theta^2 / 42), radial xy = -n t^4 / 4 (1 - theta^2 / 6),
        // along xy = n t^4 / 4 (1 - theta^2 / 2), along yy = t^3 / 3 (1 - 4 theta^2 / 5)
        let m = CwModel::new(1e-3);
        for theta in [1e-9, 1e-6, 1e-4] {
            let t = theta / m.n;
            let [qx, qy, _] = m.process_noise_axes(t);
            let n = m.n;
            let want = [
                (
                    qx[(1, 1)],
                    n * n * t.powi(5) / 5.0 * (1.0 - 5.0 * theta * theta / 42.0),
                ),
                (
                    qx[(0, 1)],
                    -n * t.powi(4) / 4.0 * (1.0 - theta * theta / 6.0),
                ),
                (
                    qy[(0, 1)],
                    n * t.powi(4) / 4.0 * (1.0 - theta * theta / 2.0),
                ),
                (qy[(1, 1)], t.powi(3) / 3.0 * (1.0 - 0.8 * theta * theta)),
            ];
            for (got, want) in want {
                assert_relative_eq!(got, want, max_relative = 1e-13);
            }
        }
    }

    #[test]
    fn process_noise_is_continuous_at_the_branch_switch() {
        let m = CwModel::new(N);
        let psd = Vec3::new(1.0, 2.0, 3.0);
        let t1 = 1.0 / N;
        // both branches at the same steps around the switch agree to rounding
        for t in [0.9 * t1, t1, 1.1 * t1] {
            let [cx, cy, cz] = m.noise_closed_form(t);
            let closed = cx * psd[0] + cy * psd[1] + cz * psd[2];
            let mut m0 = Mat6::zeros();
            for i in 0..3 {
                m0[(3 + i, 3 + i)] = psd[i];
            }
            let e = scaled_error(&m.noise_series(m0, t), &closed);
            assert!(e < 1e-13, "t = {t}: {e:e}");
        }
        // per axis: process_noise is linear in psd
        let [qx, qy, qz] = m.process_noise_axes(t1 * 0.5);
        let sum = qx + qy * 2.0 + qz * 3.0;
        assert!(scaled_error(&sum, &m.process_noise(&psd, t1 * 0.5)) < 1e-15);
    }

    #[test]
    fn process_noise_tends_to_the_double_integrator() {
        // n -> 0: Qd = q [[t^3/3, t^2/2], [t^2/2, t]] per axis
        let t = 30.0;
        let q0 = CwModel::new(1e-12).process_noise(&Vec3::repeat(1.0), t);
        for i in 0..3 {
            assert_relative_eq!(q0[(i, i)], t * t * t / 3.0, max_relative = 1e-9);
            assert_relative_eq!(q0[(i, i + 3)], t * t / 2.0, max_relative = 1e-9);
            assert_relative_eq!(q0[(i + 3, i + 3)], t, max_relative = 1e-9);
        }
        // exactly n = 0 takes the series: the double integrator itself
        let qz = CwModel::new(0.0).process_noise(&Vec3::repeat(1.0), t);
        assert_relative_eq!(qz[(1, 1)], t * t * t / 3.0, max_relative = 1e-15);
    }

    #[test]
    fn huge_steps_give_numbers_not_hangs() {
        // no iteration depends on the numbers (an iterative matrix exponential hangs or
        // panics on steps like these): 1000 orbits still give a positive-definite Q; 1e45 s gives
        // huge finite entries; 1e300 s non-finite ones, which the filters refuse (the
        // navigator refuses such steps before, see nav::MAX_STEP_PERIODS)
        let m = CwModel::new(N);
        let psd = Mat3::identity() * 1e-9;
        let d = m.discretize(7200.0 * 1000.0, &psd, Discretization::Exact);
        assert!(d.q.iter().chain(d.phi.iter()).all(|v| v.is_finite()));
        assert!(d.q.cholesky().is_some());
        let d = m.discretize(1e45, &psd, Discretization::Exact);
        assert!(d.q.iter().all(|v| v.is_finite()) && d.q.max() > 1e100);
        for t in [1e300, f64::MAX] {
            let d = m.discretize(t, &psd, Discretization::Exact);
            assert!(!d.q.iter().chain(d.phi.iter()).all(|v| v.is_finite()));
        }
    }

    #[test]
    fn sparse_product_is_the_dense_product() {
        let m = CwModel::new(N);
        let x = Mat6::from_fn(|i, j| ((i * 7 + j * 3) % 11) as f64 - 4.5 + 0.01 * (i * j) as f64);
        assert_eq!(m.a_times(&x), m.continuous_a() * x);
    }

    #[test]
    fn van_loan_q_of_a_full_density_matches_the_exponential() {
        // correlated axes: the series over t / 2^k doubled k times
        let m = CwModel::new(N);
        let qc = Mat3::new(2e-6, 5e-7, -3e-7, 5e-7, 1e-6, 2e-7, -3e-7, 2e-7, 8e-7);
        for theta in [0.01, 0.5, 1.0, 2.0, 6.0, 20.0] {
            let t = theta / N;
            let q = m.van_loan_q(&qc, t);
            let e = scaled_error(&q, &van_loan_full(&m, &qc, t));
            eprintln!("n t = {theta}: doubled series vs Van Loan exponential {e:.1e}");
            assert!(e < 1e-10, "theta = {theta}: {e:e}");
            assert_eq!(q, q.transpose());
        }
        // a diagonal density takes the closed form, bit for bit
        let psd = Vec3::new(1e-6, 2e-6, 5e-7);
        assert_eq!(
            m.van_loan_q(&Mat3::from_diagonal(&psd), 3.0 / N),
            m.process_noise(&psd, 3.0 / N)
        );
        // bounded work whatever the step: at most ~1025 doublings for a finite n t
        let q = m.van_loan_q(&qc, 1e300);
        assert!(!q.iter().all(|v| v.is_finite()));
        let q = m.van_loan_q(&qc, f64::INFINITY);
        assert!(q.iter().all(|v| v.is_nan()));
    }

    #[test]
    fn euler_is_first_order() {
        let m = CwModel::new(N);
        let d = m.discretize(1.0, &Mat3::zeros(), Discretization::Euler);
        assert_eq!(d.phi, Mat6::identity() + m.continuous_a());
        let e = m.discretize(1.0, &Mat3::zeros(), Discretization::Exact);
        // the difference is the second-order term A^2 T^2 / 2 up to O(T^3)
        let a = m.continuous_a();
        let second = a * a / 2.0;
        assert!(second.norm() > 1e-4);
        assert!((e.phi - d.phi - second).norm() < 1e-3 * second.norm());
    }
}
