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
//!   spectral density `Qc` [m^2/s^3], computed by Van Loan's method ([`CwModel::van_loan_q`]).
//!
//! Paper 000 discretises with Euler, `Phi = I + T A`; [`Discretization::Euler`] keeps that
//! only so the paper can be reproduced literally.

use crate::types::{Mat3, Mat6, Mat63, State, Vec3};
use nalgebra::SMatrix;

/// How the continuous model is turned into a discrete one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[repr(i32)]
pub enum Discretization {
    /// Exact: closed-form `Phi`, exact ZOH `Gamma`, Van Loan `Qd` (default).
    #[default]
    Exact = 1,
    /// First order, `Phi = I + T A`, `Gamma = T B`, `Qd = T B Qc B^T` (paper 000 literally).
    Euler = 2,
}

impl Discretization {
    /// From the stable code (1 exact, 2 Euler).
    pub fn from_code(code: i32) -> Option<Self> {
        match code {
            1 => Some(Self::Exact),
            2 => Some(Self::Euler),
            _ => None,
        }
    }
}

/// The CW model for one mean motion `n` [rad/s].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CwModel {
    /// Mean motion of the target's circular orbit [rad/s].
    pub n: f64,
}

/// One discrete step of the model: `X+ = phi X + gamma a + w`, `cov(w) = q`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiscreteModel {
    /// Step length [s].
    pub dt: f64,
    /// State transition matrix.
    pub phi: Mat6,
    /// Input matrix for a thrust acceleration held over the step [m/s^2 -> state].
    pub gamma: Mat63,
    /// Process-noise covariance added over the step.
    pub q: Mat6,
}

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
        Self::new(2.0 * std::f64::consts::PI / period)
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

    /// Discrete process noise for a continuous white acceleration with spectral density
    /// `qc` (3x3, canonical frame, [m^2/s^3]) by Van Loan's method (C. F. Van Loan, "Computing
    /// integrals involving the matrix exponential", IEEE TAC 23(3), 1978):
    ///
    /// ```text
    /// M = [ -A  B Qc B^T ] t,   exp(M) = [ .  F12 ],   Qd = F22^T F12,  F22 = Phi(t)^T
    ///     [  0  A^T      ]               [ 0  F22 ]
    /// ```
    ///
    /// The 12x12 exponential is nalgebra's Padé approximant with scaling and squaring, on
    /// stack-allocated matrices. The result is symmetrised.
    pub fn van_loan_q(&self, qc: &Mat3, t: f64) -> Mat6 {
        let a = self.continuous_a();
        let b = Self::continuous_b();
        let mut m = SMatrix::<f64, 12, 12>::zeros();
        m.fixed_view_mut::<6, 6>(0, 0).copy_from(&(-a * t));
        m.fixed_view_mut::<6, 6>(0, 6)
            .copy_from(&(b * qc * b.transpose() * t));
        m.fixed_view_mut::<6, 6>(6, 6)
            .copy_from(&(a.transpose() * t));
        let e = m.exp();
        let f12: Mat6 = e.fixed_view::<6, 6>(0, 6).into_owned();
        let f22: Mat6 = e.fixed_view::<6, 6>(6, 6).into_owned();
        let q = f22.transpose() * f12;
        (q + q.transpose()) * 0.5
    }

    /// The discrete model over a step `dt` with continuous acceleration noise `qc`.
    pub fn discretize(&self, dt: f64, qc: &Mat3, method: Discretization) -> DiscreteModel {
        match method {
            Discretization::Exact => DiscreteModel {
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

impl DiscreteModel {
    /// `X+ = phi X + gamma a` (mean propagation).
    pub fn apply(&self, x: &State, accel: &Vec3) -> State {
        self.phi * x + self.gamma * accel
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    const N: f64 = 2.0 * std::f64::consts::PI / 7200.0;

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

    #[test]
    fn van_loan_matches_quadrature_and_double_integrator() {
        let m = CwModel::new(N);
        let qc = Mat3::from_diagonal(&Vec3::new(1e-6, 2e-6, 5e-7));
        let t = 30.0;
        // composite Simpson quadrature of Phi(s) B Qc B^T Phi(s)^T
        let b = CwModel::continuous_b();
        let k = 2000;
        let h = t / k as f64;
        let mut q = Mat6::zeros();
        for i in 0..=k {
            let w = if i == 0 || i == k {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            let p = m.phi(i as f64 * h);
            q += p * b * qc * b.transpose() * p.transpose() * w;
        }
        q *= h / 3.0;
        let vl = m.van_loan_q(&qc, t);
        assert!((vl - q).norm() < 1e-10 * q.norm(), "{}", vl - q);
        // n -> 0: double integrator, Qd = q [[t^3/3, t^2/2], [t^2/2, t]] per axis
        let m0 = CwModel::new(1e-12);
        let vl0 = m0.van_loan_q(&Mat3::identity(), t);
        assert_relative_eq!(vl0[(0, 0)], t * t * t / 3.0, max_relative = 1e-9);
        assert_relative_eq!(vl0[(0, 3)], t * t / 2.0, max_relative = 1e-9);
        assert_relative_eq!(vl0[(3, 3)], t, max_relative = 1e-9);
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
