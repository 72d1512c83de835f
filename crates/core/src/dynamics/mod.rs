//! Relative dynamics of the chaser about the target, in the canonical frame (x radial,
//! y along-track, z orbit normal): a linear model `X' = A(t) X + B (a + w)` with
//! `B = [0; I3]`, `a = F / m` the thrust acceleration and `w` a white acceleration, and its
//! exact discrete step `X(t + dt) = Phi X(t) + Gamma a + w_d`, `cov(w_d) = Q`
//! ([`DiscreteModel`]).
//!
//! [`RelativeDynamics`] is what the navigator, the filters that rebuild process noise
//! (AQUKF, IMM), the plant and the guidance law ask of a model; [`Dynamics`] is the closed
//! set of models the library builds (one variant per model, no allocation, `Copy`), chosen
//! by [`crate::nav::NavConfig::dynamics`]. Today's one model is the circular-orbit
//! Clohessy–Wiltshire model, [`CwModel`] (papers 000 and 002). A new model — the
//! linearised elliptic (Yamanaka–Ankersen) model, for instance — is a new file here, a new
//! variant of [`Dynamics`] and its parameters in the declarations; the filters take its
//! [`DiscreteModel`]s as they take CW's.

mod cw;
mod elliptic;

pub use cw::CwModel;
pub use elliptic::{
    eccentric_anomaly, kepler_iterations, EllipticModel, KeplerMemo, CUBIC_BOUND, CUBIC_SPAN,
    KEPLER_ITERATIONS, QUADRATURE_BOUND, SHORT_BOUND,
};

use crate::types::{Mat3, Mat6, Mat63, State, Vec3};

/// How the continuous model is turned into a discrete one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[repr(i32)]
pub enum Discretization {
    /// Exact: closed-form `Phi`, exact ZOH `Gamma`, closed-form (Van Loan) `Qd` (default).
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

/// One discrete step of the model: `X+ = phi X + gamma a + w`, `cov(w) = q`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DiscreteModel {
    /// Start time of the step [s from the dynamics' epoch] (a time-varying model's steps
    /// differ by it; the CW model's do not).
    pub t: f64,
    /// Step length [s].
    pub dt: f64,
    /// State transition matrix.
    pub phi: Mat6,
    /// Input matrix for a thrust acceleration held over the step [m/s^2 -> state].
    pub gamma: Mat63,
    /// Process-noise covariance added over the step.
    pub q: Mat6,
}

impl DiscreteModel {
    /// `X+ = phi X + gamma a` (mean propagation).
    pub fn apply(&self, x: &State, accel: &Vec3) -> State {
        self.phi * x + self.gamma * accel
    }
}

/// What a relative-dynamics model provides. Times are seconds from the model's epoch
/// (the start of the simulation or the estimator); a time-invariant model ignores them.
pub trait RelativeDynamics {
    /// The discrete step from `t` over `dt` with a continuous white acceleration of
    /// spectral density `qc` (3x3, canonical frame, [m^2/s^3]).
    fn step(&self, t: f64, dt: f64, qc: &Mat3, method: Discretization) -> DiscreteModel;
    /// The step's process-noise covariance alone, `integral Phi B qc B^T Phi^T` over
    /// `[t, t + dt]` (what the AQUKF and the IMM rebuild from their own densities).
    fn step_noise(&self, t: f64, dt: f64, qc: &Mat3) -> Mat6;
    /// The continuous system matrix `A(t)`.
    fn system_matrix(&self, t: f64) -> Mat6;
    /// Whether [`RelativeDynamics::step`] depends on `dt` alone, so that a caller may keep
    /// one step per step length.
    fn time_invariant(&self) -> bool;
}

/// The relative-dynamics models of the library.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Dynamics {
    /// Clohessy–Wiltshire: target on a circular orbit.
    Cw(CwModel),
    /// Yamanaka–Ankersen: target on an elliptic orbit.
    Elliptic(EllipticModel),
}

/// The largest eccentricity the library takes: [`eccentric_anomaly`]'s fixed iterations
/// are verified to double precision up to it.
pub const MAX_ECCENTRICITY: f64 = 0.99;

impl Dynamics {
    /// The model of a target orbit: CW at `e = 0` (closed-form noise and input matrices),
    /// the linearised elliptic model otherwise.
    pub fn of_orbit(n: f64, e: f64, nu0: f64) -> Self {
        if e == 0.0 {
            Dynamics::Cw(CwModel::new(n))
        } else {
            Dynamics::Elliptic(EllipticModel::new(n, e, nu0))
        }
    }

    /// Propagate a state exactly from `t` over `dt` with a constant acceleration `accel`.
    pub fn propagate(&self, x: &State, accel: &Vec3, t: f64, dt: f64) -> State {
        match self {
            Dynamics::Cw(m) => m.propagate(x, accel, dt),
            Dynamics::Elliptic(m) => m.propagate(x, accel, t, dt),
        }
    }

    /// [`RelativeDynamics::step`] for a caller stepping forward, which keeps `memo` between
    /// its steps (the elliptic model's Kepler anchor; the same result, bit for bit).
    pub fn step_into(
        &self,
        memo: &mut KeplerMemo,
        t: f64,
        dt: f64,
        qc: &Mat3,
        method: Discretization,
        out: &mut DiscreteModel,
    ) {
        match self {
            Dynamics::Cw(m) => *out = m.step(t, dt, qc, method),
            Dynamics::Elliptic(m) => m.step_into(memo, t, dt, qc, method, out),
        }
    }

    /// The zero-order-hold input matrix of the step from `t` over `dt`.
    pub fn input_matrix(&self, t: f64, dt: f64) -> Mat63 {
        match self {
            Dynamics::Cw(m) => m.gamma(dt),
            Dynamics::Elliptic(m) => m.gamma(t, dt),
        }
    }
}

impl From<EllipticModel> for Dynamics {
    fn from(m: EllipticModel) -> Self {
        Dynamics::Elliptic(m)
    }
}

impl From<CwModel> for Dynamics {
    fn from(m: CwModel) -> Self {
        Dynamics::Cw(m)
    }
}

impl RelativeDynamics for Dynamics {
    fn step(&self, t: f64, dt: f64, qc: &Mat3, method: Discretization) -> DiscreteModel {
        match self {
            Dynamics::Cw(m) => m.step(t, dt, qc, method),
            Dynamics::Elliptic(m) => m.step(t, dt, qc, method),
        }
    }
    fn step_noise(&self, t: f64, dt: f64, qc: &Mat3) -> Mat6 {
        match self {
            Dynamics::Cw(m) => m.step_noise(t, dt, qc),
            Dynamics::Elliptic(m) => m.step_noise(t, dt, qc),
        }
    }
    fn system_matrix(&self, t: f64) -> Mat6 {
        match self {
            Dynamics::Cw(m) => m.system_matrix(t),
            Dynamics::Elliptic(m) => m.system_matrix(t),
        }
    }
    fn time_invariant(&self) -> bool {
        match self {
            Dynamics::Cw(m) => m.time_invariant(),
            Dynamics::Elliptic(m) => m.time_invariant(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The CW model's step does not depend on its start time, and the enum gives what the
    /// model gives.
    #[test]
    fn cw_steps_do_not_depend_on_their_start_time() {
        let cw = CwModel::new(core::f64::consts::TAU / 5400.0);
        let m = Dynamics::from(cw);
        let qc = Mat3::identity() * 1e-6;
        let a = m.step(0.0, 10.0, &qc, Discretization::Exact);
        let b = m.step(1234.5, 10.0, &qc, Discretization::Exact);
        assert_eq!((a.phi, a.gamma, a.q), (b.phi, b.gamma, b.q));
        assert_eq!((a.t, b.t), (0.0, 1234.5));
        assert_eq!(
            a,
            DiscreteModel {
                t: 0.0,
                ..cw.discretize(10.0, &qc, Discretization::Exact)
            }
        );
        assert_eq!(m.step_noise(7.0, 10.0, &qc), a.q);
        assert_eq!(m.system_matrix(3.0), cw.continuous_a());
        assert!(m.time_invariant());
        let (x, acc) = (State::from_element(1.0), Vec3::new(1e-3, 0.0, -1e-3));
        assert_eq!(m.propagate(&x, &acc, 50.0, 10.0), a.apply(&x, &acc));
        assert_eq!(m.input_matrix(50.0, 10.0), a.gamma);
    }
}
