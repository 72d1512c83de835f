//! Robust H-infinity filter of paper 002 (Sun, Deng, Liu, Zhong, J. Astronautics 32(7),
//! 2011): the plant with norm-bounded orbit-rate uncertainty, the LMI design (Clarabel SDP,
//! [`design`], cargo feature `hinf`), a verifier independent of the solver ([`verify`]) and
//! the runtime filter ([`HinfFilter`], no solver, no allocation).
//!
//! **Plant** (paper 002, sec. 2, eq. 9; canonical frame = the paper's frame):
//!
//! ```text
//! x(k+1) = (A + dA(k)) x(k) + B w(k),   dA = Ha F(k) Ea,  F^T F <= I
//! y(k)   = C x(k) + D v(k),             C = [I3 0]
//! z(k)   = L x(k)
//! ```
//!
//! Two uses of it are built here:
//!
//! * [`HinfPlant::paper_closed_loop`] — the paper's case: known closed-loop orbit control
//!   `u = K x`, `A = I + T (A1 + G0 K)` (Euler, literally as the paper, sec. 1.1 eq. 6),
//!   `dA = T dA1`, and the paper's `Ha`, `F`, `Ea` (sec. 4). The design is then
//!   [`design::design_paper`] (Theorem 1 / Corollary 1: the full-order filter
//!   `x_f(k+1) = A_F x_f + B_F y`, `z_f = C_F x_f`).
//! * [`HinfPlant::open_loop`] — the FMU's case: thrust is a known input, the plant is the
//!   open-loop CW model, exactly discretised (`A = Phi(T)`), which is *not* asymptotically
//!   stable (secular along-track drift, eigenvalues on the unit circle): the paper's
//!   augmented LMI, which contains the plant state, is infeasible there. The design is then
//!   [`design::design_observer`] (error-dynamics form, see there).
//!
//! **Erratum (uncertainty structure).** The paper prints `dA = T dA1` and `dA1 = Ha F Ea`
//! with `F = diag(f1, 0, f1, f2, f2, 0)`, `f1 = (2 delta + delta^2) / (2 db + db^2)`,
//! `f2 = delta / db`, `Ea = diag(w0 (2 db + db^2), 0, w0 (2 db + db^2), w0 db, w0 db, 0)`,
//! `Ha` rows 4-6 = `(3 w0, 0, 0, 0, 2, 0)`, `(0, 0, 0, -2, 0, 0)`, `(0, 0, -w0, 0, 0, 0)`.
//! Multiplying out gives `dA1` exactly (e.g. entry (4,1): `3 w0 f1 w0 (2 db + db^2) =
//! 3 w0^2 (2 delta + delta^2)`), so the structure is right as printed; the discrete
//! uncertainty is `dA = (T Ha) F Ea`, i.e. the LMI uses `T Ha` (the digest's LMI omits the
//! `T`). Tested in `tests/hinf.rs`.

use crate::dynamics::CwModel;
#[cfg(not(feature = "std"))]
use crate::math::Float;
use crate::numerics::state::{refuse, Persist, Reader, StateError, Writer};
use crate::numerics::Owned;
use crate::types::{Mat3, Mat36, Mat6, Mat63, State, Vec3};

#[cfg(feature = "hinf")]
pub mod design;
pub mod riccati;
#[cfg(feature = "std")]
pub mod verify;

/// Which computation designed a filter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DesignRoute {
    /// Bisection on the H-infinity filtering Riccati equation ([`crate::hinf::riccati`];
    /// gamma-optimal observer only). `iterations` is 0 (no interior-point solver).
    Riccati,
    /// The SDP with the filter matrices eliminated (`design::design_paper`,
    /// `design::design_observer_sdp`, the mixed design).
    Sdp,
    /// The SDP posed literally (`design::design_paper_full`, `design::design_observer_full`).
    SdpLiteral,
}

/// How an H-infinity filter's matrices were designed: the record
/// [`HinfEstimator::design_info`] keeps from the design (`design::HinfDesign`), for
/// reports and logs. It describes the construction, not the running filter: it is not part
/// of the saved state (a restored estimator was built from the same configuration, and the
/// design is deterministic).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HinfDesignInfo {
    /// The route that designed the filter that runs.
    pub route: DesignRoute,
    /// The route of the gamma-optimal observer: the same as `route` for the gamma-optimal
    /// design; for the mixed design, that of its first stage (the bound's reference).
    pub observer_route: DesignRoute,
    /// Why the gamma-optimal observer's Riccati route was not taken (its SDP fallback ran);
    /// `None` when it was taken.
    pub riccati_failure: Option<riccati::RiccatiFailure>,
    /// Trials of the Riccati bisection (0 when the route was not taken).
    pub riccati_steps: u32,
    /// Interior-point (Clarabel) iterations, both stages of the mixed design together.
    pub iterations: u32,
    /// Wall time of the design [s], both stages together.
    pub solve_time: f64,
}

/// Dimensions: state `n = 6`, measurement `m = 3`, process noise `p = 6`, measurement
/// noise `q = 3`, estimated signal `l = 6`, uncertainty channel `h = 6`.
pub const N: usize = 6;

/// The paper's closed-loop gain `K` (3x6, N per m and per m/s; paper 002, sec. 4, taken
/// there from its ref. 11).
pub const PAPER_K: [[f64; 6]; 3] = [
    [-2.2541, -0.0071, -0.0072, -22.3975, 2.3256, 1.9369],
    [-0.0104, -2.2493, -0.0055, 2.3259, -23.7456, 1.4544],
    [-0.0072, -0.0055, -2.2471, 1.9357, 1.4552, -24.2818],
];

/// Paper 002's example: 24 h orbit, `w0 = 7.2722e-5` rad/s.
pub const PAPER_W0: f64 = 7.2722e-5;
/// Paper 002's chaser mass [kg].
pub const PAPER_MASS: f64 = 1000.0;
/// Paper 002's uncertainty bound `delta_bar`.
pub const PAPER_DELTA_BAR: f64 = 0.05;
/// The sampling period implied by the published `A_F` (0.1 in its position/velocity
/// coupling) [s]; the paper does not state it.
pub const PAPER_PERIOD: f64 = 0.1;

/// Paper 002's published filter (sec. 4, "using MATLAB's LMI tools to solve Corollary 1"),
/// `A_F` row by row.
pub const PAPER_A_F: [[f64; 6]; 6] = [
    [-0.6126, -0.0053, -0.0046, 0.1, -1.7e-6, -1.0e-6],
    [-0.0052, -0.6083, -0.0035, -1.5e-6, 0.1, -1.4e-6],
    [-0.0046, -0.0035, -0.6066, -1.5e-6, -5.6e-7, 0.1],
    [-6.1302, -0.0390, -0.0337, 0.9980, 1.1e-4, 8.2e-5],
    [-0.0385, -6.0991, -0.0259, 8.0e-5, 0.9979, 6.3e-5],
    [-0.0337, -0.0259, -6.0864, 8.3e-5, 6.4e-5, 0.9979],
];
/// Paper 002's published `B_F` (6x3).
pub const PAPER_B_F: [[f64; 3]; 6] = [
    [-1.6126, -0.0053, -0.0046],
    [-0.0052, -1.6083, -0.0035],
    [-0.0046, -0.0035, -1.6066],
    [-6.1300, -0.0390, -0.0337],
    [-0.0385, -6.0989, -0.0259],
    [-0.0337, -0.0259, -6.0862],
];
/// Paper 002's published `C_F` (6x6, printed as `1e-6 x [...]`).
pub const PAPER_C_F: [[f64; 6]; 6] = [
    [
        -1.0, 0.0489e-6, 0.0247e-6, 6.3345e-6, -5.4934e-6, -4.3894e-6,
    ],
    [
        0.0386e-6, -1.0, 0.0418e-6, -5.3662e-6, 10.3349e-6, -2.9326e-6,
    ],
    [
        0.0420e-6, 0.0148e-6, -1.0, -4.5742e-6, -2.9659e-6, 11.3677e-6,
    ],
    [
        -0.3164e-6, 0.3131e-6, 0.1588e-6, -0.999960, -33.635e-6, -28.487e-6,
    ],
    [
        0.2469e-6, -0.5593e-6, 0.2630e-6, -33.612e-6, -0.999935, -19.564e-6,
    ],
    [
        0.2712e-6, 0.0939e-6, -0.5821e-6, -28.520e-6, -19.572e-6, -0.999927,
    ],
];

/// An error of the H-infinity design or filter, with a readable reason.
#[derive(Debug, Clone, PartialEq)]
pub struct HinfError {
    /// What went wrong.
    pub kind: HinfErrorKind,
    /// Human-readable reason.
    pub message: crate::message::Message,
}

/// Category of a [`HinfError`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HinfErrorKind {
    /// An input is out of its domain.
    InvalidArgument,
    /// No filter meets the LMI (the SDP is primal infeasible, or its optimum violates the
    /// strict inequality when checked independently).
    Infeasible,
    /// The solver stopped without a usable answer (iteration limit, numerical trouble).
    SolverFailed,
}

impl core::fmt::Display for HinfError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(&self.message)
    }
}

impl HinfError {
    pub(crate) fn invalid(message: impl Into<crate::message::Message>) -> Self {
        Self {
            kind: HinfErrorKind::InvalidArgument,
            message: message.into(),
        }
    }
}

/// Design inputs shared by every design: the orbit, the uncertainty bound, the period and
/// the noise inputs — `B = diag(b_pos I3, b_vel I3)` or a full [`HinfSpec::b_matrix`],
/// `D = d I3` or a full [`HinfSpec::d_matrix`] — and `L = I6`.
///
/// With `B`, `D` square roots of the true process and measurement covariances per step
/// (see [`noise_inputs`]), `w` and `v` are unit white noises and the H2 norm of a design is
/// its steady-state root-mean-square error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HinfSpec {
    /// Nominal mean motion `w0` [rad/s].
    pub w0: f64,
    /// Bound of the relative rate uncertainty, `w = w0 (1 + delta)`, `|delta| <= delta_bar`.
    pub delta_bar: f64,
    /// Sampling period `T` [s]; the discrete filter holds for this period only.
    pub period: f64,
    /// Process-noise scaling on the positions (paper: 0.05).
    pub b_pos: f64,
    /// Process-noise scaling on the velocities (paper: 0.001).
    pub b_vel: f64,
    /// Measurement-noise scaling on the indirect position measurement [m] (paper: 0.1).
    pub d: f64,
    /// Full process-noise input `B` (6x6, canonical); when set, `b_pos` and `b_vel` are
    /// not used.
    pub b_matrix: Option<Mat6>,
    /// Full measurement-noise input `D` (3x3, canonical); when set, `d` is not used.
    pub d_matrix: Option<Mat3>,
}

impl HinfSpec {
    /// Paper 002's example (sec. 4).
    pub fn paper() -> Self {
        Self {
            w0: PAPER_W0,
            delta_bar: PAPER_DELTA_BAR,
            period: PAPER_PERIOD,
            b_pos: 0.05,
            b_vel: 0.001,
            d: 0.1,
            b_matrix: None,
            d_matrix: None,
        }
    }

    /// `B`: [`HinfSpec::b_matrix`], else `diag(b_pos I3, b_vel I3)`.
    pub fn b(&self) -> Mat6 {
        let (bp, bv) = (self.b_pos, self.b_vel);
        self.b_matrix.unwrap_or_else(|| {
            Mat6::from_diagonal(&State::from_row_slice(&[bp, bp, bp, bv, bv, bv]))
        })
    }

    /// `D`: [`HinfSpec::d_matrix`], else `d I3`.
    pub fn d(&self) -> Mat3 {
        self.d_matrix.unwrap_or_else(|| Mat3::identity() * self.d)
    }

    /// Check the domain of every field.
    pub fn validate(&self) -> Result<(), HinfError> {
        let pos = |name: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(HinfError::invalid(crate::msg!(
                    "{name} must be finite and > 0 (got {v})"
                )))
            }
        };
        pos("w0 (mean motion)", self.w0)?;
        pos("period", self.period)?;
        match &self.b_matrix {
            None => {
                pos("b_pos", self.b_pos)?;
                pos("b_vel", self.b_vel)?;
            }
            Some(b) if !b.iter().all(|v| v.is_finite()) => {
                return Err(HinfError::invalid(
                    "the process-noise input B must be finite",
                ))
            }
            Some(_) => {}
        }
        match &self.d_matrix {
            None => pos("d", self.d)?,
            Some(d) if !(d.iter().all(|v| v.is_finite()) && d.determinant() != 0.0) => {
                return Err(HinfError::invalid(
                    "the measurement-noise input D must be finite and invertible",
                ))
            }
            Some(_) => {}
        }
        if !(self.delta_bar.is_finite() && self.delta_bar >= 0.0) {
            return Err(HinfError::invalid(crate::msg!(
                "delta_bar must be finite and >= 0 (got {})",
                self.delta_bar
            )));
        }
        if self.w0 * self.period > 0.5 {
            return Err(HinfError::invalid(crate::msg!(
                "w0 * period = {} > 0.5: the sampling period is not small against the orbit",
                self.w0 * self.period
            )));
        }
        Ok(())
    }
}

#[cfg(feature = "std")]
/// Symmetric square root of a positive semidefinite matrix (eigen-decomposition; rounding
/// below zero clipped). A matrix that is not finite, or whose decomposition does not
/// converge within the cap of [`crate::numerics::eigen`], gives an all-NaN result, which
/// [`HinfSpec::validate`] refuses.
pub fn psd_sqrt<const N: usize>(m: &nalgebra::SMatrix<f64, N, N>) -> nalgebra::SMatrix<f64, N, N> {
    let sym = nalgebra::DMatrix::from_fn(N, N, |i, j| 0.5 * (m[(i, j)] + m[(j, i)]));
    let Some(e) = crate::numerics::eigen::symmetric_eigen(sym) else {
        return nalgebra::SMatrix::<f64, N, N>::from_element(f64::NAN);
    };
    let d = e.eigenvalues.map(|v| v.max(0.0).sqrt());
    let r = &e.eigenvectors * nalgebra::DMatrix::from_diagonal(&d) * e.eigenvectors.transpose();
    nalgebra::SMatrix::<f64, N, N>::from_fn(|i, j| r[(i, j)])
}

#[cfg(feature = "std")]
/// Noise inputs `(B, D)` from covariances: `B = Qd^(1/2)` for the process-noise
/// covariance `Qd` of one design period and `D = R^(1/2)` for the covariance `R` of the
/// indirect position measurement (both canonical, symmetric square roots), so that `B w`
/// and `D v` with unit white `w`, `v` have exactly these covariances.
pub fn noise_inputs(qd: &Mat6, r: &Mat3) -> (Mat6, Mat3) {
    (psd_sqrt(qd), psd_sqrt(r))
}

/// The uncertain discrete plant of paper 002 eq. (9), with the discrete uncertainty
/// structure `dA = ha F ea` (`ha` already includes the period `T`). `M` is the dimension of
/// the measurement: 3, the position (`C = [I3 0]`, the paper's), or 6, the position then the
/// velocity (`C = I6`, [`HinfPlant::measuring_velocity`]); the observer designs and
/// [`HinfMatrices::observer`] take the measurement in that order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HinfPlant<const M: usize = 3> {
    /// Nominal transition `A`.
    pub a: Mat6,
    /// Process-noise input `B` (n x p).
    pub b: Mat6,
    /// Measurement matrix `C` (`[I3 0]`, or `I6` with the velocity).
    pub c: nalgebra::SMatrix<f64, M, 6>,
    /// Measurement-noise input `D`.
    pub d: nalgebra::SMatrix<f64, M, M>,
    /// Estimated signal `z = L x`.
    pub l: Mat6,
    /// Uncertainty input `T Ha`.
    pub ha: Mat6,
    /// Uncertainty output `Ea`.
    pub ea: Mat6,
    /// Known-input matrix (open loop: exact ZOH `Gamma(T)` for an acceleration; closed
    /// loop: zero, the control is inside `A`).
    pub g: Mat63,
}

/// Continuous CW `A1(w)` in the paper's frame (= canonical).
pub fn cw_a(w: f64) -> Mat6 {
    CwModel::new(w).continuous_a()
}

/// The paper's `Ha` (continuous, before the factor `T`).
pub fn paper_ha(w0: f64) -> Mat6 {
    let mut h = Mat6::zeros();
    h[(3, 0)] = 3.0 * w0;
    h[(3, 4)] = 2.0;
    h[(4, 3)] = -2.0;
    h[(5, 2)] = -w0;
    h
}

/// The paper's `Ea`.
pub fn paper_ea(w0: f64, db: f64) -> Mat6 {
    let e1 = w0 * (2.0 * db + db * db);
    let e2 = w0 * db;
    Mat6::from_diagonal(&State::from_row_slice(&[e1, 0.0, e1, e2, e2, 0.0]))
}

/// The paper's `F(delta)` (`F^T F <= I` for `|delta| <= delta_bar`).
pub fn paper_f(delta: f64, db: f64) -> Mat6 {
    let f1 = (2.0 * delta + delta * delta) / (2.0 * db + db * db);
    let f2 = delta / db;
    Mat6::from_diagonal(&State::from_row_slice(&[f1, 0.0, f1, f2, f2, 0.0]))
}

fn c_pos() -> Mat36 {
    let mut c = Mat36::zeros();
    c.fixed_view_mut::<3, 3>(0, 0).copy_from(&Mat3::identity());
    c
}

fn c_vel() -> Mat36 {
    let mut c = Mat36::zeros();
    c.fixed_view_mut::<3, 3>(0, 3).copy_from(&Mat3::identity());
    c
}

fn k_matrix(k: &[[f64; 6]; 3]) -> SMatrixK {
    SMatrixK::from_fn(|i, j| k[i][j])
}
type SMatrixK = nalgebra::SMatrix<f64, 3, 6>;

impl HinfPlant {
    fn noise(spec: &HinfSpec) -> (Mat6, Mat3) {
        (spec.b(), spec.d())
    }

    /// The paper's closed loop (sec. 1.1 eq. 6): `A = I + T (A1(w0) + G0 K)` with
    /// `G0 = [0; I3 / m]`, Euler as printed; `dA = T Ha F Ea`.
    pub fn paper_closed_loop(spec: &HinfSpec, k: &[[f64; 6]; 3], mass: f64) -> Self {
        let (b, d) = Self::noise(spec);
        let a = Mat6::identity() + (cw_a(spec.w0) + g0(mass) * k_matrix(k)) * spec.period;
        Self {
            a,
            b,
            c: c_pos(),
            d,
            l: Mat6::identity(),
            ha: paper_ha(spec.w0) * spec.period,
            ea: paper_ea(spec.w0, spec.delta_bar),
            g: Mat63::zeros(),
        }
    }

    /// As [`HinfPlant::paper_closed_loop`] with an acceleration gain `a = K_acc x`
    /// (canonical; `K_acc = K / m`).
    pub fn closed_loop_accel(spec: &HinfSpec, k_acc: &nalgebra::SMatrix<f64, 3, 6>) -> Self {
        let (b, d) = Self::noise(spec);
        let a = Mat6::identity() + (cw_a(spec.w0) + g0(1.0) * k_acc) * spec.period;
        Self {
            a,
            b,
            c: c_pos(),
            d,
            l: Mat6::identity(),
            ha: paper_ha(spec.w0) * spec.period,
            ea: paper_ea(spec.w0, spec.delta_bar),
            g: Mat63::zeros(),
        }
    }

    /// The true closed-loop transition at `w = w0 (1 + delta)` (Euler, as the paper).
    pub fn paper_closed_loop_at(spec: &HinfSpec, k: &[[f64; 6]; 3], mass: f64, delta: f64) -> Mat6 {
        Mat6::identity() + (cw_a(spec.w0 * (1.0 + delta)) + g0(mass) * k_matrix(k)) * spec.period
    }

    /// The open-loop plant of the FMU's case: `A = Phi(T)` (closed-form CW), `g =
    /// Gamma(T)` (exact ZOH for an acceleration), and the paper's uncertainty structure to
    /// first order in `T`: `Phi_w(T) - Phi_w0(T) = T dA1 + O(T^2 w0 dA1)`, so `ha = T Ha`.
    pub fn open_loop(spec: &HinfSpec) -> Self {
        let (b, d) = Self::noise(spec);
        let m = CwModel::new(spec.w0);
        Self {
            a: m.phi(spec.period),
            b,
            c: c_pos(),
            d,
            l: Mat6::identity(),
            ha: paper_ha(spec.w0) * spec.period,
            ea: paper_ea(spec.w0, spec.delta_bar),
            g: m.gamma(spec.period),
        }
    }

    /// The true open-loop transition at `w = w0 (1 + delta)`.
    pub fn open_loop_at(spec: &HinfSpec, delta: f64) -> Mat6 {
        CwModel::new(spec.w0 * (1.0 + delta)).phi(spec.period)
    }

    /// This plant measuring the velocity as well: `C = I6` (position, then velocity) and
    /// the noise input `D = diag(self.d, d_vel)`.
    pub fn measuring_velocity(&self, d_vel: &Mat3) -> HinfPlant<6> {
        let mut d = Mat6::zeros();
        d.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.d);
        d.fixed_view_mut::<3, 3>(3, 3).copy_from(d_vel);
        HinfPlant {
            a: self.a,
            b: self.b,
            c: Mat6::identity(),
            d,
            l: self.l,
            ha: self.ha,
            ea: self.ea,
            g: self.g,
        }
    }
}

/// An observer gain for a measurement of dimension `M` (6 x M).
pub type Gain<const M: usize> = nalgebra::SMatrix<f64, 6, M>;

/// `G0 = [0; I3 / m]` (paper 002 eq. 2).
pub fn g0(mass: f64) -> Mat63 {
    let mut g = Mat63::zeros();
    g.fixed_view_mut::<3, 3>(3, 0)
        .copy_from(&(Mat3::identity() / mass));
    g
}

/// The matrices of a designed filter, in the form both designs share:
///
/// ```text
/// x_f(k+1) = A_F x_f(k) + B_F y(k) + E_F a(k),    z_f(k) = C_F x_f(k)
/// ```
///
/// Paper design: `E_F = 0` (the control is inside `A`). Observer design: `A_F = A - G C`,
/// `B_F = G`, `C_F = I`, `E_F = Gamma(T)` (known thrust acceleration as feed-forward). A
/// design that measures the velocity as well (`C = I6`) has `B_F y + B_V y_v`: `G = [B_F
/// B_V]`; the others have `B_V = 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HinfMatrices {
    /// `A_F` (6x6).
    pub a_f: Mat6,
    /// `B_F` (6x3).
    pub b_f: Mat63,
    /// `C_F` (6x6).
    pub c_f: Mat6,
    /// `E_F` (6x3), feed-forward of the known acceleration [m/s^2].
    pub e_f: Mat63,
    /// `B_V` (6x3), the gain on the measured velocity (zero when the design measures the
    /// position alone).
    pub b_v: Mat63,
    /// The sampling period the matrices hold for [s].
    pub period: f64,
}

impl HinfMatrices {
    /// The paper's published filter (sec. 4), period 0.1 s.
    pub fn paper_published() -> Self {
        Self {
            a_f: Mat6::from_fn(|i, j| PAPER_A_F[i][j]),
            b_f: Mat63::from_fn(|i, j| PAPER_B_F[i][j]),
            c_f: Mat6::from_fn(|i, j| PAPER_C_F[i][j]),
            e_f: Mat63::zeros(),
            b_v: Mat63::zeros(),
            period: PAPER_PERIOD,
        }
    }

    /// The observer with gain `g` for `plant`: `A_F = A - G C`, `B_F` and `B_V` the gain's
    /// position and velocity columns, `C_F = I`, `E_F = Gamma`.
    pub fn observer<const M: usize>(plant: &HinfPlant<M>, g: &Gain<M>, period: f64) -> Self {
        const { assert!(M == 3 || M == 6, "a measurement of the position or of both") };
        let mut b_f = Mat63::zeros();
        let mut b_v = Mat63::zeros();
        for j in 0..M {
            let col = g.column(j);
            if j < 3 {
                b_f.set_column(j, &col);
            } else {
                b_v.set_column(j - 3, &col);
            }
        }
        Self {
            a_f: plant.a - g * plant.c,
            b_f,
            c_f: Mat6::identity(),
            e_f: plant.g,
            b_v,
            period,
        }
    }

    /// The observer gain `[B_F B_V]` restricted to a measurement of dimension `M` (3: the
    /// position; 6: position and velocity).
    pub fn gain<const M: usize>(&self) -> Gain<M> {
        const { assert!(M == 3 || M == 6, "a measurement of the position or of both") };
        Gain::<M>::from_fn(|i, j| {
            if j < 3 {
                self.b_f[(i, j)]
            } else {
                self.b_v[(i, j - 3)]
            }
        })
    }

    /// The observer form's transition `A = A_F + B_F C_p (+ B_V C_v` when the design
    /// measures the velocity).
    pub fn observer_transition(&self) -> Mat6 {
        let a = self.a_f + self.b_f * c_pos();
        if self.measures_velocity() {
            a + self.b_v * c_vel()
        } else {
            a
        }
    }

    /// Whether the filter takes a measured velocity (`B_V != 0`).
    pub fn measures_velocity(&self) -> bool {
        self.b_v.iter().any(|v| *v != 0.0)
    }
}

/// The runtime filter: matrices in, one step out, no solver, no allocation.
///
/// `step(y, a)`: `x_f <- A_F x_f + B_F y + E_F a`; the estimate is `C_F x_f` (for both
/// designs `z = L x = x`, so the estimate is the state). A missing measurement is replaced
/// by its prediction `y_hat = C C_F x_f`; for the observer design (`A_F + B_F C = A`,
/// `C_F = I`) that is exactly the open-loop prediction `x <- A x + Gamma a`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HinfFilter {
    m: HinfMatrices,
    /// `C_F^-1` (to start the filter at a given estimate).
    c_f_inv: Mat6,
    x_f: State,
    est: State,
}

impl HinfFilter {
    /// A filter whose estimate `C_F x_f` starts at `x0` (`x_f = C_F^-1 x0`).
    pub fn new(m: HinfMatrices, x0: State) -> Result<Self, HinfError> {
        if !(m.a_f.iter().chain(m.c_f.iter()).all(|v| v.is_finite())
            && m.b_f.iter().chain(m.e_f.iter()).all(|v| v.is_finite()))
        {
            return Err(HinfError::invalid("filter matrices must be finite"));
        }
        let c_f_inv = crate::numerics::try_inverse(&m.c_f).ok_or_else(|| {
            HinfError::invalid("C_F is singular: the estimate cannot be initialised")
        })?;
        let mut f = Self {
            m,
            c_f_inv,
            x_f: State::zeros(),
            est: State::zeros(),
        };
        f.set_estimate(x0);
        Ok(f)
    }

    /// Restart at estimate `x0`.
    pub fn set_estimate(&mut self, x0: State) {
        self.x_f = self.c_f_inv * x0;
        self.est = self.m.c_f * self.x_f;
    }

    /// One step with the indirect position measurement `y` (canonical frame, or `None`)
    /// and the known acceleration `a` [m/s^2] held over the period.
    pub fn step(&mut self, y: Option<&Vec3>, a: &Vec3) {
        self.step_with_velocity(y, None, a)
    }

    /// [`HinfFilter::step`] with a measured velocity `v` as well (used when the design
    /// measures it, `B_V != 0`; a missing one is replaced by its prediction).
    pub fn step_with_velocity(&mut self, y: Option<&Vec3>, v: Option<&Vec3>, a: &Vec3) {
        let yv = match y {
            Some(y) => *y,
            None => self.est.fixed_rows::<3>(0).owned(),
        };
        self.x_f = self.m.a_f * self.x_f + self.m.b_f * yv + self.m.e_f * a;
        if self.m.measures_velocity() {
            let vv = match v {
                Some(v) => *v,
                None => self.est.fixed_rows::<3>(3).owned(),
            };
            self.x_f += self.m.b_v * vv;
        }
        self.est = self.m.c_f * self.x_f;
    }

    /// Current estimate `C_F x_f`.
    pub fn state(&self) -> &State {
        &self.est
    }

    /// The matrices.
    pub fn matrices(&self) -> &HinfMatrices {
        &self.m
    }
}

/// Number of instants, evenly spread in true anomaly over one orbit, of a scheduled design
/// ([`HinfSchedule`]).
pub const SCHEDULE_POINTS: usize = 24;

/// The horizon of a scheduled design's certificate ([`HinfSchedule::certified_gamma`]):
/// this many orbits of steps from the start...
pub const SCHEDULE_CERTIFIED_ORBITS: f64 = 4.0;
/// ... and at most this many steps (the work of the certificate is bounded for every step
/// length).
pub const SCHEDULE_CERTIFIED_STEPS: usize = 40_000;

/// Observer gains designed at [`SCHEDULE_POINTS`] instants of an eccentric orbit, evenly
/// spread in true anomaly (`nu_k = 2 pi k / N`: denser in time near perigee, where the plant
/// changes fastest), each for the frozen plant of the step that starts there
/// (`A = Phi(t_k + T, t_k)`, `Gamma`, the step's process noise, the CW uncertainty
/// structure at the local orbit rate) and certified on its own LMI. At run time the step
/// from `t` uses the gain of the nearest instant in true anomaly, with the step's own
/// transition: `x <- Phi x + Gamma a + G_k (y - C x)`.
///
/// What is guaranteed: the error system as it runs, every step with its own transition,
/// noise and uncertainty structure and the gain its start time picks (switching included),
/// has an l2 gain from the design's inputs to the error of at most `certified_gamma` over
/// the first `certified_steps` steps, for every start within them, from a zero initial
/// error: the time-varying bounded-real Riccati recursion passes at that `gamma`
/// ([`verify::varying_gain_below`], a Cholesky factorisation per step). It is the largest
/// frozen-plant bound when that passes, and the recursion's own bisection value otherwise.
/// When the orbit is a whole number of steps the system is periodic, and `certified_steps
/// = usize::MAX` says the recursion closes a period ([`verify::closes_period`]): the bound
/// holds over every horizon.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HinfSchedule {
    /// The gains `G_k`.
    pub gains: [Mat63; SCHEDULE_POINTS],
    /// The target's orbit.
    pub orbit: crate::dynamics::EllipticModel,
    /// The largest of the instants' frozen-plant bounds.
    pub frozen_gamma: f64,
    /// The bound certified for the time-varying error system (`>= frozen_gamma`).
    pub certified_gamma: f64,
    /// The steps the certificate covers (`usize::MAX`: every horizon).
    pub certified_steps: usize,
}

impl HinfSchedule {
    /// The true anomaly of instant `k`, `2 pi k / N` [rad].
    pub fn anomaly(k: usize) -> f64 {
        core::f64::consts::TAU * k as f64 / SCHEDULE_POINTS as f64
    }

    /// The gain of the instant nearest in true anomaly to time `t`.
    pub fn gain_at(&self, t: f64) -> &Mat63 {
        let x = self.orbit.true_anomaly(t) / core::f64::consts::TAU * SCHEDULE_POINTS as f64;
        // a finite index in 0..N for every input (NaN maps to 0)
        let k = (x.round().rem_euclid(SCHEDULE_POINTS as f64) as usize).min(SCHEDULE_POINTS - 1);
        &self.gains[k]
    }
}

/// Margin of the switch from acquisition to the certified gain ([`HinfAcquisition`]): the
/// fixed gain takes over when the covariance is below `(1 + ACQUISITION_MARGIN) X_G`.
pub const ACQUISITION_MARGIN: f64 = 0.25;

/// Track initiation of an observer-form H-infinity filter (as fixed-gain alpha-beta
/// trackers are started with expanding-memory gains): a designed gain `G` is a
/// *steady-state* gain, and from
/// a large initial error it converges at its own, slow, rate (a gain designed for a quiet
/// truth has time constants of minutes). So the filter starts with the time-varying
/// Kalman gain of the design's own noise model and hands over to `G` once that is no
/// worse:
///
/// ```text
/// acquisition:  K = A P C^T (C P C^T + R)^-1,   P <- (A - K C) P (A - K C)^T + Q + K R K^T
/// certified:    K = G,                          P <- (A - G C) P (A - G C)^T + Q + G R G^T
/// no measurement:                               P <- A P A^T + Q
/// ```
///
/// with `Q = B B^T + H H^T`, `R = D D^T` and `P(0)` the initial covariance; the estimate is
/// `x <- A x + Gamma a + K (y - C x)`. `B`, `D` are the design's noise inputs and `H = |Ea|
/// Ha` its robustness input (the orbit-rate uncertainty), taken as one more unit white
/// noise, as the H-infinity criterion weighs it like the others: without it the acquiring
/// Kalman filter trusts the nominal orbit rate as much as an EKF does, and with the orbit
/// rate off by a few per cent its error is several times larger. At each measurement the
/// certified gain is used iff `P <= (1 + m) X_G` (Loewner order; `m` =
/// [`ACQUISITION_MARGIN`]), `X_G` the steady-state error covariance of `G` under the same
/// `Q`, `R` ([`verify::observer_error_covariance`]). Since `P -> (A - G C) P (A - G C)^T + Q
/// + G R G^T` is monotone and maps `(1 + m) X_G` to `(1 + m) X_G - m (Q + G R G^T)`, once
/// the certified gain runs it keeps running while measurements come (no chattering), and
/// `P` stays below `(1 + m) X_G`: under the design's noise model, never more than `1 + m`
/// times the steady-state mean-square error. A dropout grows `P` (prediction only); if it
/// leaves that set, the next measurements re-acquire with the Kalman gain. The Kalman `P`
/// tends to the Riccati solution, which is `<= X_G`, so the hand-over always comes.
///
/// A step of a design for several sensors, or with a velocity ([`HinfStep`]), is taken in
/// information form, with the step's information `J` and information innovation `u`, and
/// the design's equivalent fix `e = N u` ([`step_normaliser`]: `J_D^-1` for the design's
/// readings or a subset of them):
///
/// ```text
/// acquisition:  x <- A x + Gamma a + A (P^-1 + J)^-1 u,   P <- A (P^-1 + J)^-1 A^T + Q
/// certified:    x <- A x + Gamma a + G e,
///               P <- (A - G N J) P (A - G N J)^T + Q + G N J N G^T
/// ```
///
/// (`(P^-1 + J)^-1` computed as `P (I + J P)^-1`): the Kalman update of the step's own
/// measurements, and the designed gain on the equivalent fix (exact: `e = N J (x - xh) + N
/// H^T R^-1 v`); with one position fix and `J = J_D = R^-1` both are the forms above.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HinfAcquisition {
    a: Mat6,
    q: Mat6,
    r: Mat3,
    g: Mat63,
    /// the design's gain on the measured velocity (zero without one)
    g_v: Mat63,
    bound: Mat6,
    p: Mat6,
    certified: bool,
}

impl HinfAcquisition {
    #[cfg(feature = "std")]
    /// For the observer gain `g` of `plant`, starting at covariance `p0`; `None` when `A -
    /// G C` is not stable (no steady state to hand over to).
    pub fn new<const M: usize>(plant: &HinfPlant<M>, g: &Gain<M>, p0: Mat6) -> Option<Self> {
        // the robustness input d of the observer design, weighted like the unit noises
        let hd = plant.ha * plant.ea.norm();
        let q = plant.b * plant.b.transpose() + hd * hd.transpose();
        let mut robust = *plant;
        robust.b = psd_sqrt(&q);
        let x_g = verify::observer_error_covariance(&robust, g)?;
        let r = plant.d * plant.d.transpose();
        let split = HinfMatrices::observer(plant, g, 1.0);
        Some(Self {
            a: plant.a,
            q,
            r: r.fixed_view::<3, 3>(0, 0).owned(),
            g: split.b_f,
            g_v: split.b_v,
            bound: x_g * (1.0 + ACQUISITION_MARGIN),
            p: p0,
            certified: false,
        })
    }

    /// Whether `P <= (1 + m) X_G` (the designed gain may run).
    fn within_bound(&self) -> bool {
        let slack = self.bound - self.p;
        nalgebra::Cholesky::new((slack + slack.transpose()) * 0.5).is_some()
    }

    /// The correction of a step in information form (type docs), `None` when `I + J P` is
    /// singular; updates `P` and the hand-over flag.
    fn correction_info(&mut self, m: &HinfStep, n: &Mat6) -> Option<State> {
        self.certified = self.within_bound();
        let (dx, p) = if self.certified {
            let g = self.gain6() * n;
            let ae = self.a - g * m.j;
            let noise = g * m.j * g.transpose();
            (g * m.u, ae * self.p * ae.transpose() + self.q + noise)
        } else {
            let post = self.p * (Mat6::identity() + m.j * self.p).try_inverse()?;
            let post = (post + post.transpose()) * 0.5;
            (
                self.a * post * m.u,
                self.a * post * self.a.transpose() + self.q,
            )
        };
        self.p = (p + p.transpose()) * 0.5;
        Some(dx)
    }

    /// `[G G_v]` (6 x 6).
    fn gain6(&self) -> Mat6 {
        let mut g = Mat6::zeros();
        g.fixed_view_mut::<6, 3>(0, 0).copy_from(&self.g);
        g.fixed_view_mut::<6, 3>(0, 3).copy_from(&self.g_v);
        g
    }

    /// The gain for this step's measurement (zero without one) and the covariance update.
    fn gain(&mut self, measured: bool) -> Mat63 {
        if !measured {
            self.p = self.a * self.p * self.a.transpose() + self.q;
            return Mat63::zeros();
        }
        self.certified = self.within_bound();
        let c = c_pos();
        let k = if self.certified {
            self.g
        } else {
            let pc = self.p * c.transpose();
            match (c * pc + self.r).try_inverse() {
                Some(s_inv) => self.a * pc * s_inv,
                None => self.g,
            }
        };
        let ae = self.a - k * c;
        let p = ae * self.p * ae.transpose() + self.q + k * self.r * k.transpose();
        self.p = (p + p.transpose()) * 0.5;
        k
    }

    /// Whether the certified gain made the last measurement update.
    pub fn certified(&self) -> bool {
        self.certified
    }

    /// The covariance of the prediction under the design's noise model.
    pub fn covariance(&self) -> &Mat6 {
        &self.p
    }

    /// Restart at covariance `p0`.
    pub fn reset(&mut self, p0: Mat6) {
        self.p = p0;
        self.certified = false;
    }
}

/// Iterations of the 3 x 3 eigen-decomposition of a step's information (bounded work;
/// Jacobi-type sweeps converge in a handful).
const PINV_MAX_ITER: usize = 64;
/// Eigenvalues of a block of information below this fraction of its largest are no
/// information (the pseudo-inverse drops them).
const PINV_RELATIVE_FLOOR: f64 = 1e-12;
/// A step's information within this relative margin of the design's counts as the design's
/// (or a subset of it): its readings' geometry is the design's to rounding.
const SUBSET_TOLERANCE: f64 = 1e-9;

/// The measurements of one step as the H-infinity estimator gathers them before its step:
/// per block (position, velocity) the number of sensors, the information `J` (6 x 6,
/// block diagonal) and the information innovation `u` (relative to the estimate at the
/// step's start: `u = H^T R^-1 (z - h(x))` for a sensor linearised there, `J_s (y - x)` for
/// one that fixes its block, `J_s` from its noise at the fix), and the first position fix.
/// In a design for one sensor, one position fix alone is the design's own measurement and
/// runs as before; anything else runs through the design's equivalent fix `e = N u`
/// ([`step_normaliser`]): the design's observer with the readings of the declared sensors
/// that gave none replaced by their prediction
/// ([`HinfEstimator::with_measurement_information`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HinfStep {
    n_pos: u8,
    n_vel: u8,
    fix: Option<Vec3>,
    j: Mat6,
    u: State,
}

impl Default for HinfStep {
    fn default() -> Self {
        Self {
            n_pos: 0,
            n_vel: 0,
            fix: None,
            j: Mat6::zeros(),
            u: State::zeros(),
        }
    }
}

impl HinfStep {
    /// No measurement this step.
    pub fn is_empty(&self) -> bool {
        self.n_pos == 0 && self.n_vel == 0
    }

    /// The position fix when it is the step's only measurement.
    pub fn single_fix(&self) -> Option<&Vec3> {
        if self.n_pos == 1 && self.n_vel == 0 {
            self.fix.as_ref()
        } else {
            None
        }
    }

    /// Add a sensor's information `j` and information innovation `u` to block `at` (0:
    /// position, 3: velocity); `fix` is a position fix.
    fn add(&mut self, at: usize, j: &Mat3, u: &Vec3, fix: Option<Vec3>) {
        if at == 0 {
            self.n_pos = self.n_pos.saturating_add(1);
            if self.fix.is_none() {
                self.fix = fix;
            }
        } else {
            self.n_vel = self.n_vel.saturating_add(1);
        }
        let mut jb = self.j.fixed_view_mut::<3, 3>(at, at);
        jb += j;
        let mut ub = self.u.fixed_rows_mut::<3>(at);
        ub += u;
    }
}

/// `f(M)` of a symmetric 3 x 3 block through its eigen-decomposition, `f` applied to each
/// eigenvalue with the largest one's magnitude (`None`: not converged or not finite).
fn spectral_map(m: &Mat3, f: impl Fn(f64, f64) -> f64) -> Option<Mat3> {
    if !m.iter().all(|v| v.is_finite()) {
        return None;
    }
    let e = nalgebra::SymmetricEigen::try_new(*m, f64::EPSILON, PINV_MAX_ITER)?;
    let top = e.eigenvalues.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    let mut out = Mat3::zeros();
    for k in 0..3 {
        let v = e.eigenvectors.column(k);
        out += v * v.transpose() * f(e.eigenvalues[k], top);
    }
    Some(out)
}

/// A sensor's information `H^T R^-1 H` on the 3-column block `h` of its Jacobian and its
/// information innovation `H^T R^-1 nu`, through a Cholesky factor of the noise covariance
/// `r` (`None` when `r` is not positive definite).
pub fn information<const D: usize>(
    h: &nalgebra::SMatrix<f64, D, 3>,
    r: &nalgebra::SMatrix<f64, D, D>,
    nu: &nalgebra::SVector<f64, D>,
) -> Option<(Mat3, Vec3)> {
    let chol = r.cholesky()?;
    Some((
        h.transpose() * chol.solve(h),
        h.transpose() * chol.solve(nu),
    ))
}

/// Pseudo-inverse of a symmetric positive semidefinite block (eigenvalues below
/// [`PINV_RELATIVE_FLOOR`] of the largest dropped).
fn pinv_psd(m: &Mat3) -> Option<Mat3> {
    spectral_map(m, |l, top| {
        if l > top * PINV_RELATIVE_FLOOR && l > 0.0 {
            1.0 / l
        } else {
            0.0
        }
    })
}

/// The normaliser `N` of a step's information innovation, block by block (position,
/// velocity): `N = (J_D + (J - J_D)_+)^+`, `J_D` the design's information, `J` the step's,
/// `(.)_+` the positive part. For readings of declared sensors at the design's geometry or
/// a subset of them (`J <= J_D`) it is `J_D^-1`: the design's observer with the missing
/// readings replaced by their prediction. Information beyond the design's (a sensor closer
/// or more precise than designed for, or not declared) enters with its own weight, so that
/// `N J` never exceeds the identity: a fix is never over-corrected. `n_d` is `J_D^+` (block
/// pseudo-inverse), taken as it is when `J <= J_D (1 + 1e-9)` (a Cholesky test, no
/// eigen-decomposition). `None` when a decomposition does not converge.
pub fn step_normaliser(j_d: &Mat6, n_d: &Mat6, j: &Mat6) -> Option<Mat6> {
    let mut out = Mat6::zeros();
    for at in [0, 3] {
        let d = j_d.fixed_view::<3, 3>(at, at).owned();
        let s = j.fixed_view::<3, 3>(at, at).owned();
        if s.iter().all(|v| *v == 0.0) {
            continue;
        }
        let slack = d * (1.0 + SUBSET_TOLERANCE) - s;
        if (slack + slack.transpose()).cholesky().is_some() {
            out.fixed_view_mut::<3, 3>(at, at)
                .copy_from(&n_d.fixed_view::<3, 3>(at, at));
            continue;
        }
        let excess = spectral_map(&((s - d + (s - d).transpose()) * 0.5), |l, _| l.max(0.0))?;
        let n = pinv_psd(&(d + excess))?;
        out.fixed_view_mut::<3, 3>(at, at).copy_from(&n);
    }
    Some(out)
}

/// The runtime filter behind the [`crate::estimators::Estimator`] trait, as the navigator
/// (filter code 9) runs it: [`Estimator::update`](crate::estimators::Estimator::update)
/// turns the radio measurement into the indirect Cartesian position of paper 002 (sec. 1.2
/// eq. 7: `rho (cos el cos az, cos el sin az, sin el)` in the measurement frame, rotated to
/// the canonical frame) and holds it; the following
/// [`Estimator::predict`](crate::estimators::Estimator::predict) makes the one filter step
/// `x_f <- A_F x_f + B_F y + E_F a` with it (or with the prediction when no measurement
/// came), or, with an [`HinfAcquisition`] (observer form only), the acquisition step.
/// A step with other measurements than one position fix (several sensors, a camera's line
/// of sight, a velocity: [`HinfStep`]) makes the observer step on their equivalent fix,
/// `x <- A x + Gamma a + [B_F B_V] J^+ u` (observer form, without a schedule).
/// There is no Gaussian covariance: [`HinfEstimator::covariance`] is NaN.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HinfEstimator {
    filter: HinfFilter,
    pending: HinfStep,
    gamma: f64,
    h2_norm: f64,
    acquisition: Option<HinfAcquisition>,
    nan: Mat6,
    design: Option<HinfDesignInfo>,
    schedule: Option<HinfSchedule>,
    /// the design's measurement set: its information `J_D`, `J_D^+` and its sensor count
    set: Option<(Mat6, Mat6, u32)>,
}

impl HinfEstimator {
    /// Wrap designed matrices with their certified `gamma`; the estimate starts at `x0`.
    pub fn new(m: HinfMatrices, gamma: f64, x0: State) -> Result<Self, HinfError> {
        Ok(Self {
            filter: HinfFilter::new(m, x0)?,
            pending: HinfStep::default(),
            gamma,
            h2_norm: f64::NAN,
            acquisition: None,
            nan: Mat6::from_element(f64::NAN),
            design: None,
            schedule: None,
            set: None,
        })
    }
    /// Record the design's measurement set: its information `J_D` (block diagonal:
    /// position, velocity; `C^T (D D^T)^-1 C` of the design's plant) and how many sensors
    /// it declares. With it a step's measurements other than the design's one position fix
    /// ([`HinfStep`]) make the observer step on the design's equivalent fix `N u`
    /// ([`step_normaliser`]); without it such a step is refused.
    pub fn with_measurement_information(
        mut self,
        j_d: &Mat6,
        sensors: u32,
    ) -> Result<Self, HinfError> {
        let mut n_d = Mat6::zeros();
        for at in [0, 3] {
            let b = j_d.fixed_view::<3, 3>(at, at).owned();
            let n = pinv_psd(&b).ok_or_else(|| {
                HinfError::invalid("the design's measurement information is not finite")
            })?;
            n_d.fixed_view_mut::<3, 3>(at, at).copy_from(&n);
        }
        self.set = Some((*j_d, n_d, sensors));
        Ok(self)
    }
    /// Run the scheduled gains of an eccentric orbit ([`HinfSchedule`]; observer form, no
    /// track initiation): each step uses the step's own transition and the gain of its
    /// instant.
    pub fn with_schedule(mut self, schedule: HinfSchedule) -> Result<Self, HinfError> {
        if self.acquisition.is_some() {
            return Err(HinfError::invalid(
                "a scheduled design runs without track initiation",
            ));
        }
        self.schedule = Some(schedule);
        Ok(self)
    }
    /// The scheduled gains, if any.
    pub fn schedule(&self) -> Option<&HinfSchedule> {
        self.schedule.as_ref()
    }
    /// Record the design's H2 norm (reported by [`HinfEstimator::h2_norm`]).
    pub fn with_h2_norm(mut self, h2_norm: f64) -> Self {
        self.h2_norm = h2_norm;
        self
    }
    #[cfg(feature = "std")]
    /// Start with track initiation ([`HinfAcquisition`]) from covariance `p0`. The
    /// matrices must be an observer design for `plant` (`C_F = I`, `A_F = A - B_F C`,
    /// `E_F = Gamma`).
    pub fn with_acquisition<const M: usize>(
        mut self,
        plant: &HinfPlant<M>,
        p0: Mat6,
    ) -> Result<Self, HinfError> {
        let m = self.filter.matrices();
        let tol = 1e-9 * (1.0 + plant.a.abs().max());
        if (m.c_f - Mat6::identity()).abs().max() > 0.0
            || (m.a_f + m.gain::<M>() * plant.c - plant.a).abs().max() > tol
            || (m.e_f - plant.g).abs().max() > tol
        {
            return Err(HinfError::invalid(
                "track initiation needs an observer-form filter of the same plant",
            ));
        }
        self.acquisition = Some(
            HinfAcquisition::new(plant, &m.gain::<M>(), p0)
                .ok_or_else(|| HinfError::invalid("the observer gain is not stabilising"))?,
        );
        Ok(self)
    }
    /// Record how the matrices were designed (reported by [`HinfEstimator::design_info`]).
    pub fn with_design_info(mut self, info: HinfDesignInfo) -> Self {
        self.design = Some(info);
        self
    }
    /// How the matrices were designed, when recorded ([`HinfEstimator::with_design_info`]).
    pub fn design_info(&self) -> Option<&HinfDesignInfo> {
        self.design.as_ref()
    }
    /// The design's `gamma`.
    pub fn gamma(&self) -> f64 {
        self.gamma
    }
    /// The design's H2 norm (NaN when not recorded).
    pub fn h2_norm(&self) -> f64 {
        self.h2_norm
    }
    /// Track initiation, if any.
    pub fn acquisition(&self) -> Option<&HinfAcquisition> {
        self.acquisition.as_ref()
    }
    /// Whether the designed (certified) gain runs: always without track initiation, after
    /// the hand-over with it.
    pub fn certified(&self) -> bool {
        self.acquisition.as_ref().is_none_or(|a| a.certified())
    }
    /// The period the matrices hold for [s].
    pub fn period(&self) -> f64 {
        self.filter.matrices().period
    }
    /// The runtime filter.
    pub fn filter(&self) -> &HinfFilter {
        &self.filter
    }
}

impl crate::estimators::Estimator for HinfEstimator {
    fn predict(
        &mut self,
        model: &crate::dynamics::DiscreteModel,
        accel: &Vec3,
    ) -> Result<(), crate::estimators::FilterError> {
        use crate::estimators::FilterError;
        let (saved, saved_acq) = (self.filter, self.acquisition);
        let step = core::mem::take(&mut self.pending);
        let fused = self.set.is_some_and(|(_, _, k)| k > 1);
        let fix = if fused {
            None
        } else {
            step.single_fix().copied()
        };
        if fix.is_none() && !step.is_empty() {
            // several sensors, a line of sight or a velocity: the design's equivalent fix
            let m = *self.filter.matrices();
            let observer = self.schedule.is_none() && m.c_f == Mat6::identity();
            let Some((j_d, n_d, _)) = self.set.filter(|_| observer) else {
                return Err(FilterError::Unsupported(
                    "the H-infinity filter takes one position fix per step when its design is \
                     scheduled along an eccentric orbit, is not of observer form, or does not \
                     record its measurement set",
                ));
            };
            let n = step_normaliser(&j_d, &n_d, &step.j)
                .ok_or(FilterError::NonFinite("H-infinity step information"))?;
            let x = *self.filter.state();
            // observer form: the estimate is the state, A = A_F + B_F C_p + B_V C_v
            let a = m.observer_transition();
            let dx = match &mut self.acquisition {
                Some(acq) => acq.correction_info(&step, &n),
                None => Some(m.gain::<6>() * (n * step.u)),
            };
            let next = dx.map(|dx| a * x + m.e_f * accel + dx);
            match next {
                Some(next) => self.filter.set_estimate(next),
                None => {
                    self.acquisition = saved_acq;
                    return Err(FilterError::NonFinite("H-infinity step information"));
                }
            }
        } else {
            match &mut self.acquisition {
                None if self.schedule.is_some() => {
                    let x = *self.filter.state();
                    let mut next = model.phi * x + model.gamma * accel;
                    if let (Some(y), Some(s)) = (&fix, &self.schedule) {
                        next += s.gain_at(model.t) * (y - x.fixed_rows::<3>(0));
                    }
                    self.filter.set_estimate(next);
                }
                None => self.filter.step(fix.as_ref(), accel),
                Some(acq) => {
                    // observer form: the estimate is the state, A = A_F + B_F C, Gamma = E_F
                    let x = *self.filter.state();
                    let k = acq.gain(fix.is_some());
                    let m = self.filter.matrices();
                    let a = m.observer_transition();
                    let mut next = a * x + m.e_f * accel;
                    if let Some(y) = &fix {
                        next += k * (y - x.fixed_rows::<3>(0));
                    }
                    self.filter.set_estimate(next);
                }
            }
        }
        if !self.filter.state().iter().all(|v| v.is_finite()) {
            self.filter = saved;
            self.acquisition = saved_acq;
            return Err(crate::estimators::FilterError::NonFinite(
                "H-infinity estimate",
            ));
        }
        Ok(())
    }
    fn update<M: crate::sensors::MeasurementModel>(
        &mut self,
        sensor: &M,
        z: &Vec3,
    ) -> Result<crate::estimators::UpdateInfo, crate::estimators::FilterError> {
        let y = sensor
            .invert(z)
            .ok_or(crate::estimators::FilterError::NonFinite(
                "indirect position",
            ))?;
        let r = self.filter.state().fixed_rows::<3>(0).owned();
        let innovation = match sensor.predict(&r) {
            Some(zh) => sensor.diff(z, &zh),
            None => Vec3::from_element(f64::NAN),
        };
        // the fix's information from its noise at the fix (NaN where that has no
        // geometry: used only when the step fuses it with other measurements)
        let j = sensor
            .linearize(&y)
            .ok()
            .and_then(|g| {
                let h = g.h.fixed_view::<3, 3>(0, 0).owned();
                information(&h, &sensor.noise_cov(), &Vec3::zeros())
            })
            .map_or(Mat3::from_element(f64::NAN), |(j, _)| j);
        self.pending.add(0, &j, &(j * (y - r)), Some(y));
        Ok(crate::estimators::UpdateInfo {
            innovation,
            nis: f64::NAN,
            azimuth_used: true,
        })
    }
    /// A sensor of the position alone or of the velocity alone
    /// ([`crate::sensors::Sensor::support`]) is gathered into the step's [`HinfStep`]: a
    /// position fix ([`crate::sensors::Sensor::position_fix`]: the radio, a Cartesian
    /// position) or a velocity reading as the fix with its information, any other (a
    /// camera's line of sight) linearised at the estimate. Refused: a sensor of position and
    /// velocity together, and a velocity when the design measures none (`hinf_sensors`).
    fn update_sensor<const D: usize, S: crate::sensors::Sensor<D> + ?Sized>(
        &mut self,
        sensor: &S,
        z: &nalgebra::SVector<f64, D>,
    ) -> Result<crate::estimators::SensorUpdate<D>, crate::estimators::FilterError> {
        use crate::estimators::FilterError;
        use crate::sensors::Support;
        let at = match sensor.support() {
            Support::Position => 0,
            Support::Velocity if self.filter.matrices().measures_velocity() => 3,
            Support::Velocity => {
                return Err(FilterError::Unsupported(
                    "the H-infinity design measures no velocity: declare relative GNSS \
                     velocity (8) in hinf_sensors",
                ))
            }
            Support::Full => {
                return Err(FilterError::Unsupported(
                    "the H-infinity filter takes sensors of the position alone or of the \
                     velocity alone: this one measures both",
                ))
            }
        };
        let x = *self.filter.state();
        let fix = if at == 0 {
            sensor.position_fix(z)
        } else {
            sensor.velocity_fix(z)
        };
        if fix.is_some_and(|f| !f.iter().all(|v| v.is_finite())) {
            return Err(FilterError::NonFinite("indirect position or velocity"));
        }
        // a fix's information from its noise at the fix, another's at the estimate
        let mut at_x = x;
        if let Some(f) = &fix {
            at_x.fixed_rows_mut::<3>(at).copy_from(f);
        }
        let lin = sensor.linearize(&at_x).ok();
        let info = lin.as_ref().and_then(|lin| {
            let mut h: nalgebra::SMatrix<f64, D, 3> = lin.h.fixed_view::<D, 3>(0, at).into();
            let mut nu = sensor.residual(z, &lin.z);
            for k in 0..D {
                if !lin.used[k] {
                    h.row_mut(k).fill(0.0);
                    nu[k] = 0.0;
                }
            }
            information(&h, &sensor.noise().cov(), &nu)
        });
        let (j, u) = match (info, &fix) {
            (Some((j, _)), Some(f)) => (j, j * (f - x.fixed_rows::<3>(at))),
            (Some(ju), None) => ju,
            // a fix whose noise has no geometry there: usable alone, as the design's
            (None, Some(_)) => (Mat3::from_element(f64::NAN), Vec3::from_element(f64::NAN)),
            (None, None) => return Err(FilterError::NonFinite("line of sight at the estimate")),
        };
        // linearised at the estimate itself (no fix), the prediction is already there
        let predicted = match (&lin, &fix) {
            (Some(lin), None) => Some(lin.z),
            _ => sensor.measure(&x),
        };
        let innovation = match predicted {
            Some(zh) => sensor.residual(z, &zh),
            None => nalgebra::SVector::from_element(f64::NAN),
        };
        self.pending.add(at, &j, &u, fix.filter(|_| at == 0));
        Ok(crate::estimators::SensorUpdate {
            innovation,
            nis: f64::NAN,
            dof: D,
        })
    }
    fn state(&self) -> &State {
        self.filter.state()
    }
    fn covariance(&self) -> &Mat6 {
        &self.nan
    }
    fn set_estimate(&mut self, x: State, p: Mat6) {
        self.filter.set_estimate(x);
        self.pending = HinfStep::default();
        if let Some(acq) = &mut self.acquisition {
            acq.reset(p);
        }
    }
}

/// Largest entry of a restored `C_F` or `C_F^-1`. A reset computes `C_F (C_F^-1 x0)` for any
/// accepted initial state (up to about 1e150 m): with both factors below 1e50 the
/// intermediate stays below 1e201 and the result finite. Designed filters have entries of
/// order 1e-3 to 1e3.
const MAX_OUTPUT_MAP_ENTRY: f64 = 1e50;

/// A restored output map `C_F` and its saved inverse must be an inverse pair of moderate
/// size: otherwise a crafted state behind a valid checksum with a finite but huge
/// `C_F^-1` (as the `capi` fuzz target found) is accepted because its estimate is finite,
/// and the next reset (which cannot fail) turns the estimate into infinities.
fn check_output_map(c_f: &Mat6, c_f_inv: &Mat6) -> Result<(), StateError> {
    let big = c_f
        .iter()
        .chain(c_f_inv.iter())
        .any(|v| v.abs() > MAX_OUTPUT_MAP_ENTRY);
    let off = (c_f * c_f_inv - Mat6::identity()).amax();
    if big || !(off <= 1e-6) {
        return Err(refuse(crate::msg!(
            "H-infinity C_F and C_F^-1 are not an inverse pair of moderate size \
             (largest entry above {MAX_OUTPUT_MAP_ENTRY:e}: {big}; |C_F C_F^-1 - I| = {off:e})"
        )));
    }
    Ok(())
}

/// Saved state: the matrices `A_F` (36), `B_F` (18), `C_F` (36), `E_F` (18), `B_V` (18),
/// column by column, and their period (8) — saved rather than re-designed, so a restore continues
/// with exactly these numbers whatever the solver gives on another machine — then
/// `C_F^-1` (36), the filter state `x_f` (6) and the estimate `C_F x_f` (6).
impl Persist for HinfFilter {
    fn save_state(&self, w: &mut Writer<'_>) {
        let Self {
            m,
            c_f_inv,
            x_f,
            est,
        } = self;
        let HinfMatrices {
            a_f,
            b_f,
            c_f,
            e_f,
            b_v,
            period,
        } = m;
        w.matrix(a_f);
        w.matrix(b_f);
        w.matrix(c_f);
        w.matrix(e_f);
        w.matrix(b_v);
        w.f64(*period);
        w.matrix(c_f_inv);
        w.matrix(x_f);
        w.matrix(est);
    }

    fn load_state(&mut self, r: &mut Reader<'_>) -> Result<(), StateError> {
        let Self {
            m,
            c_f_inv,
            x_f,
            est,
        } = self;
        let HinfMatrices {
            a_f,
            b_f,
            c_f,
            e_f,
            b_v,
            period,
        } = m;
        *a_f = r.finite_matrix("H-infinity A_F")?;
        *b_f = r.finite_matrix("H-infinity B_F")?;
        *c_f = r.finite_matrix("H-infinity C_F")?;
        *e_f = r.finite_matrix("H-infinity E_F")?;
        *b_v = r.finite_matrix("H-infinity B_V")?;
        *period = r.finite("H-infinity period")?;
        if !(*period > 0.0) {
            return Err(refuse(crate::msg!(
                "H-infinity period must be > 0 (got {period})"
            )));
        }
        *c_f_inv = r.finite_matrix("H-infinity C_F^-1")?;
        check_output_map(c_f, c_f_inv)?;
        *x_f = r.finite_matrix("H-infinity filter state")?;
        *est = r.finite_matrix("H-infinity estimate")?;
        Ok(())
    }
}

/// Saved state of a step's gathered measurements: the sensor counts of the two blocks (1
/// byte each), the first position fix (flag, then 3), the information `J` (36) and the
/// information innovation `u` (6). Between steps it is empty.
impl Persist for HinfStep {
    fn save_state(&self, w: &mut Writer<'_>) {
        let Self {
            n_pos,
            n_vel,
            fix,
            j,
            u,
        } = self;
        w.u8(*n_pos);
        w.u8(*n_vel);
        w.opt_matrix(fix.as_ref());
        w.matrix(j);
        w.matrix(u);
    }

    fn load_state(&mut self, r: &mut Reader<'_>) -> Result<(), StateError> {
        self.n_pos = r.u8("H-infinity step: position sensors")?;
        self.n_vel = r.u8("H-infinity step: velocity sensors")?;
        self.fix = r.opt_matrix("H-infinity step: position fix")?;
        self.j = r.matrix("H-infinity step: information")?;
        self.u = r.matrix("H-infinity step: information innovation")?;
        Ok(())
    }
}

/// Saved state: the runtime filter's, the measurements gathered for a step not yet made
/// ([`HinfStep`]), the design's `gamma` and H2 norm (8 each), and the
/// track initiation (flag; when present its covariance (36) and hand-over flag).
impl Persist for HinfEstimator {
    fn save_state(&self, w: &mut Writer<'_>) {
        let Self {
            filter,
            pending,
            gamma,
            h2_norm,
            acquisition,
            nan: _,
            design: _,
            // configuration: designed again, the same, by the restoring estimator
            schedule: _,
            set: _,
        } = self;
        filter.save_state(w);
        pending.save_state(w);
        w.f64(*gamma);
        w.f64(*h2_norm);
        // track initiation: its model (a, q, r, g, bound) follows from the design; the
        // covariance and the hand-over flag are state
        w.bool(acquisition.is_some());
        if let Some(a) = acquisition {
            w.matrix(&a.p);
            w.bool(a.certified);
        }
    }

    fn load_state(&mut self, r: &mut Reader<'_>) -> Result<(), StateError> {
        let Self {
            filter,
            pending,
            gamma,
            h2_norm,
            acquisition,
            nan: _,
            design: _,
            schedule: _,
            set: _,
        } = self;
        filter.load_state(r)?;
        pending.load_state(r)?;
        *gamma = r.f64("H-infinity gamma")?;
        *h2_norm = r.f64("H-infinity H2 norm")?;
        let acquiring = r.bool("H-infinity track initiation flag")?;
        match acquisition {
            Some(a) if acquiring => {
                a.p = r.finite_matrix("H-infinity track-initiation covariance")?;
                a.certified = r.bool("H-infinity hand-over flag")?;
            }
            None if !acquiring => {}
            _ => {
                return Err(refuse(
                    "H-infinity track initiation (hinf_acquisition) differs between the state \
                     and this estimator",
                ))
            }
        }
        Ok(())
    }
}
