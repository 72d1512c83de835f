//! LMI designs of the robust H-infinity filter as semidefinite programs in Clarabel's PSD
//! cone (cargo feature `hinf`): the paper's gamma-optimal filter, the gamma-optimal
//! observer (by default through the Riccati route of [`crate::hinf::riccati`], the SDP as
//! reference and fallback) and the mixed H2/H-infinity observer.
//!
//! # Paper design (Theorem 1 / Corollary 1 of paper 002)
//!
//! Variables `R = R^T, S = S^T` (6x6), `Abar_F` (6x6), `Bbar_F` (6x3), `Cbar_F` (6x6),
//! `lambda`, `g2 = gamma^2`; minimise `g2` subject to (blocks of sizes n, n, n, n, p, q, l, h)
//!
//! ```text
//! [ -R  -S  R A + Bb C   Ab   R B   Bb D   0     R Ha ]
//! [  *  -S  S A + Bb C   Ab   S B   Bb D   0     S Ha ]
//! [  *   *  -R + l Ea'Ea -S   0     0      L'    0    ]
//! [  *   *   *          -S    0     0     -Cb'   0    ]   <  0          (paper eq. 20)
//! [  *   *   *           *   -g2 I  0      0     0    ]
//! [  *   *   *           *    *    -g2 I   0     0    ]
//! [  *   *   *           *    *     *     -I     0    ]
//! [  *   *   *           *    *     *      *    -l I  ]
//! ```
//!
//! and `A_F = S^-1 Abar_F`, `B_F = S^-1 Bbar_F`, `C_F = Cbar_F` (eq. 21).
//!
//! # Elimination of the filter matrices (issue 15)
//!
//! Eq. 20 is affine in the filter variables and each of them is unstructured, so the
//! projection (elimination) lemma of Gahinet & Apkarian (1994) applies: for symmetric
//! `Psi` and an unstructured `Theta`,
//!
//! ```text
//! exists Theta:  Psi + U^T Theta V + V^T Theta^T U < 0
//!    <=>  N_U^T Psi N_U < 0  and  N_V^T Psi N_V < 0      (N_X: basis of ker X)
//! ```
//!
//! *Step 1, `Theta = [Abar_F  Bbar_F]`.* Both enter the `R` row and the `S` row alike:
//! `U = E_0 + E_1`, `V = [E_xf; C E_x + D E_v]` (`E_k` selects block `k` of eq. 20; blocks
//! `0, 1` the `R`, `S` rows, then `x, x_f, w, v, z, d`). `Cbar_F` (the `(x_f, z)` block)
//! stays in `Psi`; it is unstructured too and eliminated in step 2.
//!
//! - `ker V` (`xi_xf = 0`, `C xi_x + D xi_v = 0`): the `x_f` block and `Cbar_F` drop out;
//!   rows `R` and `S` with the congruence `xi_1 -> xi_1 - xi_0` become `diag(-W, -S)`,
//!   `W = R - S`, beside `[W; S] [A B Ha]`, and the Schur complement of that pair is the one
//!   of a single row `-R` beside `R [A B Ha]` (`W W^-1 W + S S^-1 S = R`). With `D`
//!   invertible, `ker [C D] = {(x, -D^-1 C x)}`, so (c) is, in the blocks `(R row, x, v,
//!   w, d)` and restricted by the congruence `N = diag(I, [I; -D^-1 C], I)`:
//!
//!   ```text
//!   (c)  N^T [ -R   R A                   0      R B    R Ha ]
//!            [  *  -R + l Ea'Ea + L'L      0      0      0    ]
//!            [  *   *                     -g2 I   0      0    ]  N  <  0
//!            [  *   *                      *     -g2 I   0    ]
//!            [  *   *                      *      *     -l I  ]
//!   ```
//!
//!   (the `z` block `-I` beside `L'` is replaced by its Schur complement `+ L'L`; exact).
//! - `ker U` (`xi_1 = -xi_0`): the `R` row minus the `S` row is free of the filter: the
//!   condition (i) is eq. 20 without the `S` row, in the blocks `(W row, x, x_f, w, v, z, d)`
//!   with the `W` row `[-W, W A, 0, W B, 0, 0, W Ha]`.
//!
//! *Step 2, `Cbar_F` in (i)*: `U = E_z`, `V = E_xf`. `ker V` (`xi_xf = 0`): (i) without
//! `x_f`, which is
//!
//! ```text
//! (b)  [ -W   W A                   W B    W Ha ]
//!      [  *  -R + l Ea'Ea + L'L      0      0    ]  <  0
//!      [  *   *                     -g2 I   0    ]
//!      [  *   *                      *     -l I  ]
//! ```
//!
//! and `ker U` (`xi_z = 0`): (i) without `z`, whose `(x, x_f)` part `[-R + l Ea'Ea, -S;
//! -S, -S]` is, by the Schur complement of `-S` (`S > 0` is imposed anyway), `-W + l
//! Ea'Ea`:
//!
//! ```text
//! (a)  (b) with the x block -W + l Ea'Ea  (no L'L),   and S > 0.
//! ```
//!
//! (The `v` blocks of (a), (b) are decoupled `-g2 I`.) So a filter exists iff `R, S, l, g2`
//! satisfy (a), (b), (c) and `S > 0`: 44 scalars instead of 134, LMIs of sizes 21, 21, 21
//! (with the thin factors below) instead of one of 45. The eliminated SDP has the same
//! infimum as eq. 20 for the same bound `R <= rho I`; the margins `-eps I` now sit on (a),
//! (b), (c), which is less conservative than `-eps I` on the 45 x 45 matrix: measured gamma
//! 0.358760 against 0.358787 (7.6e-5 relative, docs/evaluation.md).
//!
//! *Thin factors.* `B` and `Ha` enter only beside `-g2 I` and `-l I`, i.e. through `W B B'
//! W / g2` and `W Ha Ha' W / l`: any `F` with `F F' = B B'` gives the same LMI (congruence
//! with an orthogonal matrix, the remaining columns decouple). `Ha` has rank 3 (rows 3-5),
//! so its `d` block shrinks from 6 to 3. Numerical rank: eigenvalues of `M M'` above `1e-24`
//! of the largest.
//!
//! *Why `D` invertible.* It is the noise input of the position measurement; a singular `D`
//! (a noise-free axis) makes `ker [C D]` another subspace; [`design_paper`] then runs the
//! literal SDP ([`design_paper_full`]).
//!
//! ## Reconstruction
//!
//! When `Theta` enters one block row `j` only (`Psi + E_j' Theta V + ...`, `V` zero in the
//! columns of `j`), with `Q = -Psi_rr > 0` (the rest of the rows) and `Psi < 0` on `ker V`,
//!
//! ```text
//! Theta = -Psi_jr Q^-1 V_r' (V_r Q^-1 V_r')^-1
//! ```
//!
//! is a solution: it makes `Psi_jr + Theta V_r = Psi_jr Pi`, with `Pi` the `Q`-orthogonal
//! projector onto `ker V_r`; by the Schur complement of `Psi_jj < 0` the LMI is `X'
//! (-Psi_jj)^-1 X < Q` for `X = Psi_jr + Theta V_r`, and splitting `xi = Pi xi + (I - Pi)
//! xi` (`Q`-orthogonal) gives `xi' (Q - Pi' G Pi) xi = k' (Q - G) k + m' Q m > 0`, `k = Pi xi
//! in ker V_r`, `G = Psi_rj (-Psi_jj)^-1 Psi_jr` — positive by the condition on `ker V`
//! and by `Q > 0`. Applied twice: `Cbar_F` from (i) (row `z`, `Psi_zz = -I`, `Q` = -(a)
//! with the `x_f` block), then `[Abar_F Bbar_F]` from eq. 20 after the congruence
//! `xi_1 -> xi_1 - xi_0`, where they enter the `S` row only (`Psi_jj = -S`, `Q` = -(i)).
//! Eq. 20 is then assembled at the reconstructed filter and checked with nalgebra like
//! before ([`crate::hinf::verify::lmi_paper`]); it is not the filter of [`design_paper_full`]
//! (the optimal filter is not unique), its H2 norm differs (docs/evaluation.md).
//!
//! *Observer form.* `Y = P G` enters the `P` row only, beside `-(C E_e + D E_v)`: `ker
//! U` gives `P > L'L`, `ker V` the 21 x 21 LMI in `(P row, e, w, d)` on `ker [C D]`
//! (the `Y` terms vanish there; `z` by its Schur complement); `Y` by the formula above
//! (`Psi_jj = -P`). 22 scalars instead of 40.
//!
//! # Observer (error-dynamics) design, for the open-loop plant
//!
//! Filter `xh(k+1) = A xh + Gamma a + G (y - C xh)`, estimate `xh`. With `e = x - xh`:
//!
//! ```text
//! e(k+1) = (A - G C) e + B w - G D v + Ha d,    d := F Ea x,    z_e = L e
//! ```
//!
//! The known thrust cancels (feed-forward), and the error no longer depends on the plant
//! state except through the uncertainty term, which enters as an exogenous input of the
//! robustness channel: `Ha F Ea x = (|Ea| Ha) d'` with `d' = F Ea x / |Ea|`, `|d'| <= |x|`
//! (Frobenius `|Ea|`, ~`2 w0 delta_bar`), weighted like the unit-intensity noises `w, v`. The
//! discrete bounded-real lemma for `(A - G C, [B, -G D, Ha], L)`, congruence with
//! `diag(P, I, I, I)` and `Y = P G` give the LMI in `P = P^T, Y, g2`:
//!
//! ```text
//! [ -P   P A - Y C   P B    -Y D  |Ea| P Ha 0  ]
//! [  *     -P        0       0       0      L' ]
//! [  *      *      -g2 I     0       0      0  ]   <  0,     G = P^-1 Y
//! [  *      *        *     -g2 I     0      0  ]
//! [  *      *        *       *     -g2 I    0  ]
//! [  *      *        *       *       *     -I  ]
//! ```
//!
//! It does not contain the plant state, so the plant need not be stable: the open-loop CW
//! model (eigenvalues on the unit circle) is fine as long as `(A, C)` is detectable.
//! *Relation to the paper's result*: the paper's augmented state `(x, x_f)` becomes `(x,
//! e)` for the observer structure `A_F = A - B_F C`, `C_F = L`, and there the `x`-rows
//! couple into `e` only through `dA x`; without uncertainty (`delta_bar = 0`, so `d = 0`)
//! and with `u = K x` inside `A`, the H-infinity filtering optimum is attained by an
//! observer-form filter (the central filter), so both designs give the same optimal
//! `gamma` — `tests/hinf.rs` checks this numerically on the paper's closed loop. With
//! uncertainty the observer form bounds the error gain from `(w, v, d)` jointly instead
//! of using the S-procedure on `x`, which the open-loop plant would make unbounded.
//!
//! *Riccati route (issue 15).* For a fixed `g2` the LMI is, by duality and completing the
//! square in `G`, equivalent to a Riccati inequality of the a-priori H-infinity filter, so
//! [`design_observer`] does not solve it as an SDP: it bisects on `gamma` with the
//! stabilising solution of the Riccati equation deciding each trial (structure-preserving
//! doubling), builds the central gain in closed form and checks this LMI at `P = g2 X^-1`
//! with nalgebra ([`crate::hinf::riccati`], with the derivation and references). The SDP
//! ([`design_observer_sdp`], [`design_observer_full`]) stays as the reference and as the
//! fallback, taken automatically and recorded in [`HinfDesign::route`] and
//! [`HinfDesign::riccati_failure`]. The Riccati route is not bounded by `P <= rho I`, so
//! it reaches the infimum where the SDP's bound binds (the quiet-truth noise:
//! docs/evaluation.md).
//!
//! # Mixed H2/H-infinity observer design (issue 12)
//!
//! The gamma-optimal observer is the best filter against the worst noise; against the
//! noise that usually comes (white, with the covariances the user knows) it is far from
//! the best, because the H-infinity criterion weighs every frequency alike. The mixed
//! design keeps a certified H-infinity bound and, within it, minimises the H2 norm of the
//! error system from the unit white noises `(w, v)` to `z_e = L e` — with `B`, `D` square
//! roots of the true covariances, `|T|_2^2 = trace X`, `X = A_e X A_e^T + B B^T + G D D^T
//! G^T` the steady-state error covariance, i.e. the mean-square error (a Kalman filter
//! minimises exactly this). One Lyapunov matrix for both criteria (Khargonekar & Rotea
//! 1991) makes the H2 bound as conservative as the H-infinity certificate; the extended
//! characterisations of de Oliveira, Geromel & Bernussou (2002, "Extended H2 and H-infinity
//! norm characterizations and controller parametrizations for discrete-time systems")
//! decouple them through a common slack `X` (any square matrix) and `Y = X G`:
//!
//! ```text
//! H-infinity (gamma fixed):              H2 (trace Z minimised):
//! [ P - X - X'  X A - Y C  X B  -Y D  X |Ea| Ha  0  ]    [ P2 - X - X'  X A - Y C  0  ]
//! [     *         -P        0    0       0       L' ]    [     *          -P2     L' ]  < 0
//! [     *          *      -g2 I  0       0       0  ]    [     *           *     -I  ]
//! [     *          *        *  -g2 I     0       0  ] < 0
//! [     *          *        *    *     -g2 I     0  ]    [ P2 - X - X'  [X B, -Y D] ]
//! [     *          *        *    *       *      -I  ]    [     *            -Z      ]  < 0
//! ```
//!
//! with `G = X^-1 Y`. Why they hold: `P - X - X' <= -X P^-1 X'` (from `(X - P) P^-1 (X -
//! P)' >= 0`), so each LMI implies the same matrix with `-X P^-1 X'` in the corner, and the
//! congruence `diag(X^-1, I, ...)` turns that into the standard bounded-real (left) and H2
//! (right: `A_e' P2 A_e - P2 + L' L < 0`, so `P2` bounds the observability Gramian, and
//! `B_e' P2 B_e < Z`, so `|T|_2^2 < trace Z`) conditions with separate Lyapunov matrices
//! `P`, `P2`. With `X = P` the left LMI is the gamma-optimal design's, so the gamma-optimal
//! observer is feasible for any bound above its gamma: `g2 = (f gamma_opt)^2` with the
//! factor `f > 1` ([`design_open_loop_mixed`], filter 9's `hinf_gamma_factor`, default
//! 1.5). The returned gain is re-checked like the others: the three LMIs assembled with
//! nalgebra at the recovered `X, G, P, P2, Z` ([`crate::hinf::verify::lmi_mixed`]), and the
//! reported H2 norm is not the solver's bound `sqrt(trace Z)` but the one computed from `G`
//! by a direct Lyapunov solve ([`crate::hinf::verify::observer_h2_norm`]).
//!
//! *Scaling.* With a quiet truth (white acceleration of 1e-10 m^2/s^3, metre-level
//! measurement noise) the error's velocity part is ~1e-4 m/s against ~0.05 m of position,
//! and `P2` spans ~12 orders of magnitude: posed in metres and m/s, Clarabel stops at an H2
//! norm 60 % above the Kalman filter's (0.0696 vs 0.0437 m with the H-infinity constraint
//! dropped; paper 000's orbit and geometry, 1 s period), where the same problem in paper
//! 002's units reaches it. So the LMIs are posed in `e' = diag(I, tau I) e` (an exact change
//! of coordinates: every transfer is unchanged), `tau = sqrt(trace X_pp / trace X_vv)` of
//! the steady-state error covariance of a start gain, and solved once more with the `tau`
//! of the result when that differs by more than a factor 2. With the gamma-optimal
//! observer as start gain: in the quiet case `tau` = 63 s (the result's own: 106 s, one
//! solve; H2 norm 0.072 m at `f = 1.5` against 0.092 m unscaled; without the H-infinity
//! constraint, at `tau` = 100 s, the Kalman bound is reached to 0.02 %); in paper 002's
//! case 0.31 s, then 3.5 s (two solves). The Riccati route's gamma-optimal observer (the
//! central filter) has `tau` = 316 s in the quiet case, which made that case take two
//! solves too; [`design_open_loop_mixed`] therefore starts from the Kalman predictor's
//! gain ([`crate::hinf::riccati::kalman_gain`]; the mixed design minimises the same H2
//! criterion under a bound), one solve in both cases (21 and 42 iterations). The
//! strict inequalities carry the same margin `eps` as the other designs.
//!
//! # Conditioning and the unattained minimum (why the problem is not posed literally)
//!
//! 1. **Scale of the uncertainty.** `T Ha` has entries ~0.2, `Ea` ~`w0 delta_bar` ~4e-6;
//!    `dA = (T Ha / s) F (s Ea)` for any `s > 0`, and `s = sqrt(|T Ha| / |Ea|)` makes both
//!    factors the same size (~1e-3). For the paper design this only rescales `lambda`
//!    (the LMI is equivalent); for the observer design it sets the weight of the
//!    robustness channel, so there the scaling is fixed at `s = 1` and left to `Ea`.
//! 2. **The minimum is not attained**: as `g2` tends to its infimum some of `R, S, Abar_F,
//!    ...` grow without bound (the optimal filter has a singular Lyapunov certificate), and
//!    an interior-point solver never converges. We bound the certificate, `R <= rho I`
//!    (paper) or `P <= rho I` (observer), with `rho` = [`DesignOptions::bound`]
//!    (default 1e4). Observed: with `rho = 1e12` Clarabel ends `AlmostSolved` at a point
//!    whose assembled LMI has a positive eigenvalue (1.5e-4), i.e. no certificate. The
//!    bounded problem has an attained minimum; its
//!    `gamma` exceeds the infimum by a margin that shrinks as `rho` grows (reported, not
//!    hidden: `gamma` is what the returned filter certifies).
//! 3. **Strict inequalities** `LMI < 0` are posed as `LMI <= -eps I` with `eps` =
//!    [`DesignOptions::margin`] (default 1e-5; with 1e-7 the
//!    solver's answer, accurate to its feasibility tolerance, can violate the strict LMI by
//!    ~1e-6 and is then rejected by the check below), plus `lambda >= eps` and `S >= eps I`
//!    (`R > S > 0` is implied by the leading blocks of the LMI). The returned matrices are then re-checked with nalgebra
//!    ([`crate::hinf::verify`]); a solution whose assembled LMI is not negative definite is
//!    reported as infeasible, never returned.

use super::riccati::RiccatiFailure;
use super::verify::{lmi_mixed, lmi_observer, lmi_paper};
pub use super::DesignRoute;
use super::{HinfDesignInfo, HinfError, HinfErrorKind, HinfMatrices, HinfPlant, HinfSpec};
use crate::types::{Mat6, Mat63};
use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};
use nalgebra::DMatrix;
use std::time::Instant;

/// Options of the SDP.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DesignOptions {
    /// Bound `rho` on the Lyapunov certificate (`R <= rho I` or `P <= rho I`).
    pub bound: f64,
    /// Margin `eps` of the strict inequalities.
    pub margin: f64,
    /// Clarabel iteration limit.
    pub max_iter: u32,
}

impl Default for DesignOptions {
    fn default() -> Self {
        Self {
            bound: 1e4,
            margin: 1e-5,
            max_iter: 200,
        }
    }
}

/// Outcome of a design.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HinfDesign {
    /// The filter.
    pub matrices: HinfMatrices,
    /// `gamma = sqrt(g2)` of the solution: the certified bound on the worst-case gain
    /// from the (scaled) noises to the estimation error.
    pub gamma: f64,
    /// Largest eigenvalue of the assembled LMI at the returned variables (nalgebra; < 0).
    pub lmi_max_eig: f64,
    /// H2 norm of the designed filter's nominal error system from the unit white noises
    /// `(w, v)` to the error, computed independently of the solver
    /// ([`crate::hinf::verify::observer_h2_norm`], [`crate::hinf::verify::filter_h2_norm`]):
    /// with `B`, `D` the square roots of the true noise covariances, its square is the
    /// steady-state mean-square error.
    pub h2_norm: f64,
    /// The solver's certified bound on the H2 norm (`sqrt(trace Z)`, mixed design only;
    /// NaN for the gamma-optimal designs).
    pub h2_bound: f64,
    /// Clarabel's status (`Solved` or `AlmostSolved`).
    pub status: &'static str,
    /// Interior-point iterations.
    pub iterations: u32,
    /// Wall time of assembly and solve [s].
    pub solve_time: f64,
    /// The route that designed the filter.
    pub route: DesignRoute,
    /// Why the Riccati route was not taken, when the gamma-optimal observer fell back to
    /// the SDP ([`design_observer`]); `None` otherwise.
    pub riccati_failure: Option<RiccatiFailure>,
    /// Riccati trials of the bisection (Riccati route only; 0 otherwise).
    pub riccati_steps: u32,
}

impl HinfDesign {
    /// The record of this design for [`super::HinfEstimator::with_design_info`] (a
    /// gamma-optimal design: it is its own observer stage).
    pub fn info(&self) -> HinfDesignInfo {
        HinfDesignInfo {
            route: self.route,
            observer_route: self.route,
            riccati_failure: self.riccati_failure,
            riccati_steps: self.riccati_steps,
            iterations: self.iterations,
            solve_time: self.solve_time,
        }
    }
}

impl MixedDesign {
    /// The record of the mixed design: the route of the filter that runs (the mixed
    /// SDP), its gamma-optimal stage's route and Riccati record, both stages' iterations
    /// and time.
    pub fn info(&self) -> HinfDesignInfo {
        HinfDesignInfo {
            route: self.mixed.route,
            observer_route: self.pure.route,
            riccati_failure: self.pure.riccati_failure,
            riccati_steps: self.pure.riccati_steps,
            iterations: self.pure.iterations + self.mixed.iterations,
            solve_time: self.pure.solve_time + self.mixed.solve_time,
        }
    }
}

/// A symmetric affine matrix function `M(x) = M0 + sum x_i M_i` on a block structure.
struct Lmi {
    dim: usize,
    offsets: Vec<usize>,
    /// `mats[0]` = constant, `mats[i + 1]` = coefficient of variable `i`
    mats: Vec<DMatrix<f64>>,
}

impl Lmi {
    fn new(blocks: &[usize], nvar: usize) -> Self {
        let mut offsets = Vec::with_capacity(blocks.len());
        let mut o = 0;
        for b in blocks {
            offsets.push(o);
            o += b;
        }
        Self {
            dim: o,
            offsets,
            mats: vec![DMatrix::zeros(o, o); nvar + 1],
        }
    }

    /// `N^T M(x) N` for every coefficient: the LMI restricted to the range of `N` (one
    /// block of size `N.ncols()` afterwards).
    fn congruence(&self, n: &DMatrix<f64>) -> Self {
        Self {
            dim: n.ncols(),
            offsets: vec![0],
            mats: self.mats.iter().map(|m| n.transpose() * m * n).collect(),
        }
    }

    /// Add `m` at block `(r, c)` (and `m^T` at `(c, r)`) to the coefficient of `var`
    /// (`None`: the constant).
    fn add(&mut self, var: Option<usize>, r: usize, c: usize, m: &DMatrix<f64>) {
        let k = var.map_or(0, |v| v + 1);
        let (r0, c0) = (self.offsets[r], self.offsets[c]);
        let t = &mut self.mats[k];
        for i in 0..m.nrows() {
            for j in 0..m.ncols() {
                let v = m[(i, j)];
                if v != 0.0 {
                    t[(r0 + i, c0 + j)] += v;
                    if r != c {
                        t[(c0 + j, r0 + i)] += v;
                    }
                }
            }
        }
    }
}

/// The bound `X <= rho I` on a symmetric certificate `X` (n x n), as the LMI
/// `X - rho I <= 0` (why the certificate is bounded: see the module docs).
fn upper_bound(x: &VarMat, n: usize, nvar: usize, rho: f64) -> Lmi {
    let mut lmi = Lmi::new(&[n], nvar);
    for (k, e) in x.basis() {
        lmi.add(Some(k), 0, 0, &e);
    }
    lmi.add(None, 0, 0, &(-DMatrix::<f64>::identity(n, n) * rho));
    lmi
}

/// A group of scalar variables forming a matrix: symmetric (upper triangle) or full.
#[derive(Clone)]
struct VarMat {
    first: usize,
    rows: usize,
    cols: usize,
    sym: bool,
}

impl VarMat {
    fn count(&self) -> usize {
        if self.sym {
            self.rows * (self.rows + 1) / 2
        } else {
            self.rows * self.cols
        }
    }
    /// `(variable index, basis matrix)` for every scalar of the group.
    fn basis(&self) -> Vec<(usize, DMatrix<f64>)> {
        let mut out = Vec::with_capacity(self.count());
        let mut k = self.first;
        if self.sym {
            for j in 0..self.rows {
                for i in 0..=j {
                    let mut e = DMatrix::zeros(self.rows, self.rows);
                    e[(i, j)] = 1.0;
                    e[(j, i)] = 1.0;
                    out.push((k, e));
                    k += 1;
                }
            }
        } else {
            for j in 0..self.cols {
                for i in 0..self.rows {
                    let mut e = DMatrix::zeros(self.rows, self.cols);
                    e[(i, j)] = 1.0;
                    out.push((k, e));
                    k += 1;
                }
            }
        }
        out
    }
    fn value(&self, x: &[f64]) -> DMatrix<f64> {
        let mut m = DMatrix::zeros(self.rows, self.cols);
        for (k, e) in self.basis() {
            m += e * x[k];
        }
        m
    }
}

struct Vars {
    n: usize,
}
impl Vars {
    fn sym(&mut self, n: usize) -> VarMat {
        let v = VarMat {
            first: self.n,
            rows: n,
            cols: n,
            sym: true,
        };
        self.n += v.count();
        v
    }
    fn full(&mut self, r: usize, c: usize) -> VarMat {
        let v = VarMat {
            first: self.n,
            rows: r,
            cols: c,
            sym: false,
        };
        self.n += v.count();
        v
    }
    fn scalar(&mut self) -> usize {
        self.n += 1;
        self.n - 1
    }
}

fn dm<const R: usize, const C: usize>(m: &nalgebra::SMatrix<f64, R, C>) -> DMatrix<f64> {
    DMatrix::from_fn(R, C, |i, j| m[(i, j)])
}

/// svec of a symmetric matrix in Clarabel's convention: upper triangle by columns,
/// off-diagonal entries times sqrt(2).
fn svec(m: &DMatrix<f64>, out: &mut Vec<f64>) {
    let s2 = std::f64::consts::SQRT_2;
    for j in 0..m.ncols() {
        for i in 0..=j {
            out.push(if i == j { m[(i, j)] } else { s2 * m[(i, j)] });
        }
    }
}

/// The SDP: minimise `c^T x` subject to `-M_k(x) - eps_k I` PSD for every `M_k`, and
/// `x_i >= lo_i` for the listed scalars.
struct Sdp {
    nvar: usize,
    cost: Vec<f64>,
    lmis: Vec<(Lmi, f64)>,
    lower: Vec<(usize, f64)>,
    /// Let Clarabel equilibrate (Ruiz-scale) the data. Off for the paper design, which is
    /// posed balanced already (module docs, conditioning 1): there Clarabel's scaling of
    /// the 45 x 45 LMI's rows only costs iterations (measured: 30 -> 22, same gamma to
    /// 1e-6). On for the observer designs, whose quiet-truth cases span many orders of
    /// magnitude and need it (without it the quiet case's gamma-optimal observer ends 1e-3
    /// relative away in gamma).
    equilibrate: bool,
}

struct SdpSolution {
    x: Vec<f64>,
    status: SolverStatus,
    iterations: u32,
}

impl Sdp {
    fn solve(&self, opts: &DesignOptions) -> Result<SdpSolution, HinfError> {
        // columns as triplets
        let (mut rows, mut cols, mut vals) = (Vec::new(), Vec::new(), Vec::new());
        let mut b = Vec::new();
        let mut cones = Vec::new();
        let mut row0 = 0;
        let mut buf = Vec::new();
        for (lmi, eps) in &self.lmis {
            let mut m0 = -&lmi.mats[0];
            for i in 0..lmi.dim {
                m0[(i, i)] -= eps;
            }
            svec(&m0, &mut b);
            for (k, mk) in lmi.mats[1..].iter().enumerate() {
                buf.clear();
                svec(mk, &mut buf);
                for (r, v) in buf.iter().enumerate() {
                    if *v != 0.0 {
                        rows.push(row0 + r);
                        cols.push(k);
                        vals.push(*v);
                    }
                }
            }
            row0 += lmi.dim * (lmi.dim + 1) / 2;
            cones.push(SupportedConeT::PSDTriangleConeT(lmi.dim));
        }
        // x_i - lo >= 0  <=>  s = -lo - (-1) x_i
        for (i, lo) in &self.lower {
            rows.push(row0);
            cols.push(*i);
            vals.push(-1.0);
            b.push(-lo);
            row0 += 1;
        }
        if !self.lower.is_empty() {
            cones.push(SupportedConeT::NonnegativeConeT(self.lower.len()));
        }
        let a = CscMatrix::new_from_triplets(row0, self.nvar, rows, cols, vals);
        let p = CscMatrix::zeros((self.nvar, self.nvar));
        let settings = DefaultSettings {
            max_iter: opts.max_iter,
            verbose: false,
            // Clarabel's own choice of LDL per KKT matrix (its `faer-sparse` feature, as in
            // its Python wheel): faer's supernodal factorisation where the KKT system is
            // dense enough (flops / nnz(L) >= 40: the literal paper form's PSD blocks; 4.0 G
            // -> 1.8 G instructions), QDLDL elsewhere (the eliminated paper form, the
            // observer designs). docs/evaluation.md, "H-infinity design speed".
            // one thread: deterministic, and the machine's cores belong to the caller
            max_threads: 1,
            equilibrate_enable: self.equilibrate,
            direct_solve_method: "auto".to_string(),
            ..DefaultSettings::default()
        };
        let mut solver =
            DefaultSolver::new(&p, &self.cost, &a, &b, &cones, settings).map_err(|e| {
                HinfError {
                    kind: HinfErrorKind::SolverFailed,
                    message: format!("Clarabel rejected the problem: {e:?}"),
                }
            })?;
        crate::numerics::blas::single_thread();
        solver.solve();
        let status = solver.solution.status;
        match status {
            SolverStatus::Solved | SolverStatus::AlmostSolved => Ok(SdpSolution {
                x: solver.solution.x.clone(),
                status,
                iterations: solver.solution.iterations,
            }),
            SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
                Err(HinfError {
                    kind: HinfErrorKind::Infeasible,
                    message: format!(
                        "no filter satisfies the LMI (Clarabel: {status:?} after {} \
                         iterations)",
                        solver.solution.iterations
                    ),
                })
            }
            other => Err(HinfError {
                kind: HinfErrorKind::SolverFailed,
                message: format!(
                    "Clarabel stopped with {other:?} after {} iterations",
                    solver.solution.iterations
                ),
            }),
        }
    }
}

fn status_name(s: SolverStatus) -> &'static str {
    match s {
        SolverStatus::Solved => "Solved",
        SolverStatus::AlmostSolved => "AlmostSolved",
        _ => "Other",
    }
}

fn check_opts(o: &DesignOptions) -> Result<(), HinfError> {
    if !(o.bound.is_finite() && o.bound > 0.0 && o.margin.is_finite() && o.margin > 0.0) {
        return Err(HinfError::invalid(format!(
            "design options: bound and margin must be finite and > 0 (got {}, {})",
            o.bound, o.margin
        )));
    }
    Ok(())
}

fn check_plant(p: &HinfPlant) -> Result<(), HinfError> {
    let all =
        p.a.iter()
            .chain(p.b.iter())
            .chain(p.c.iter())
            .chain(p.d.iter())
            .chain(p.l.iter())
            .chain(p.ha.iter())
            .chain(p.ea.iter());
    if all.into_iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(HinfError::invalid(
            "plant matrices must be finite".to_string(),
        ))
    }
}

/// Balance `ha F ea = (ha / s) F (s ea)`: `s = sqrt(|ha| / |ea|)` (1 when either is zero).
pub fn balance(ha: &Mat6, ea: &Mat6) -> f64 {
    let (nh, ne) = (ha.norm(), ea.norm());
    if nh > 0.0 && ne > 0.0 {
        (nh / ne).sqrt()
    } else {
        1.0
    }
}

/// No uncertainty (`delta_bar = 0`, `Ea = 0`): the channel is dropped as well, or `lambda`
/// would have to grow without bound against `R Ha`.
fn paper_plant(plant: &HinfPlant) -> HinfPlant {
    let mut p = *plant;
    if p.ea.norm() == 0.0 {
        p.ha = Mat6::zeros();
    }
    p
}

/// Paper 002, Corollary 1: minimise `gamma^2` subject to eq. 20 for `plant` (built with
/// [`HinfPlant::paper_closed_loop`]), with the filter matrices eliminated (module docs,
/// "Elimination of the filter matrices"): the SDP is solved in `R, S, lambda, g2` only (44
/// scalars, LMIs of sizes 30, 30, 24), then `Cbar_F` and `[Abar_F Bbar_F]` are
/// reconstructed in closed form and eq. 20 is checked at them with nalgebra.
/// `A_F = S^-1 Abar_F`, `B_F = S^-1 Bbar_F`, `C_F = Cbar_F`. When `D` is singular the
/// kernel basis used here does not exist and [`design_paper_full`] runs instead. Errors:
/// [`HinfErrorKind::Infeasible`] when no filter exists (or the solution fails the
/// independent check), [`HinfErrorKind::SolverFailed`] otherwise.
pub fn design_paper(
    plant: &HinfPlant,
    period: f64,
    opts: &DesignOptions,
) -> Result<HinfDesign, HinfError> {
    check_opts(opts)?;
    check_plant(plant)?;
    let t0 = Instant::now();
    let plant = &paper_plant(plant);
    robustly_stable(plant)?;
    // ker [C D] = { (x, -D^-1 C x) }
    let dinv_c = match plant.d.try_inverse() {
        Some(di) if di.iter().all(|v| v.is_finite()) => dm(&(di * plant.c)),
        _ => return design_paper_full(plant, period, opts),
    };
    let s = balance(&plant.ha, &plant.ea);
    let ea = dm(&plant.ea) * s;
    let a = dm(&plant.a);
    // B and Ha enter only through B B^T and Ha Ha^T (module docs): thin factors
    let (b, ha) = (
        thin_factor(&dm(&plant.b)),
        thin_factor(&(dm(&plant.ha) / s)),
    );
    let (pb, ph) = (b.ncols(), ha.ncols());
    let l = dm(&plant.l);
    // x-block constants: lambda Ea^T Ea (variable), L^T L (the Schur complement of z)
    let eae = ea.transpose() * &ea;
    let ltl = l.transpose() * &l;
    let n = 6;
    let mut vars = Vars { n: 0 };
    let r = vars.sym(n);
    let sv = vars.sym(n);
    let lam = vars.scalar();
    let g2 = vars.scalar();
    let nvar = vars.n;
    let eye = |k: usize| DMatrix::<f64>::identity(k, k);
    // (a), (b): blocks W-row, x, w, d ; (c) before the kernel congruence: R-row, x, v, w, d
    // (W = R - S; module docs)
    let mut ma = Lmi::new(&[n, n, pb, ph], nvar);
    let mut mb = Lmi::new(&[n, n, pb, ph], nvar);
    let mut mc = Lmi::new(&[n, n, 3, pb, ph], nvar);
    for (sign, vm) in [(1.0, &r), (-1.0, &sv)] {
        for (k, e) in vm.basis() {
            let w = e * sign;
            for m in [&mut ma, &mut mb] {
                m.add(Some(k), 0, 0, &(-&w));
                m.add(Some(k), 0, 1, &(&w * &a));
                m.add(Some(k), 0, 2, &(&w * &b));
                m.add(Some(k), 0, 3, &(&w * &ha));
            }
            ma.add(Some(k), 1, 1, &(-&w));
        }
    }
    for (k, e) in r.basis() {
        mb.add(Some(k), 1, 1, &(-&e));
        mc.add(Some(k), 0, 0, &(-&e));
        mc.add(Some(k), 0, 1, &(&e * &a));
        mc.add(Some(k), 0, 3, &(&e * &b));
        mc.add(Some(k), 0, 4, &(&e * &ha));
        mc.add(Some(k), 1, 1, &(-&e));
    }
    for m in [&mut ma, &mut mb, &mut mc] {
        m.add(Some(lam), 1, 1, &eae);
    }
    for m in [&mut mb, &mut mc] {
        m.add(None, 1, 1, &ltl);
    }
    ma.add(Some(g2), 2, 2, &(-eye(pb)));
    ma.add(Some(lam), 3, 3, &(-eye(ph)));
    mb.add(Some(g2), 2, 2, &(-eye(pb)));
    mb.add(Some(lam), 3, 3, &(-eye(ph)));
    mc.add(Some(g2), 2, 2, &(-eye(3)));
    mc.add(Some(g2), 3, 3, &(-eye(pb)));
    mc.add(Some(lam), 4, 4, &(-eye(ph)));
    let mc = mc.congruence(&kernel_basis(&dinv_c, pb + ph));
    let bound = upper_bound(&r, n, nvar, opts.bound);
    let mut spos = Lmi::new(&[n], nvar);
    for (k, e) in sv.basis() {
        spos.add(Some(k), 0, 0, &(-e));
    }
    let mut cost = vec![0.0; nvar];
    cost[g2] = 1.0;
    let sdp = Sdp {
        nvar,
        cost,
        lmis: vec![
            (ma, opts.margin),
            (mb, opts.margin),
            (mc, opts.margin),
            (bound, 0.0),
            (spos, opts.margin),
        ],
        lower: vec![(lam, opts.margin), (g2, 0.0)],
        equilibrate: false,
    };
    let sol = sdp.solve(opts)?;
    let x = &sol.x;
    let (rv, svv) = (r.value(x), sv.value(x));
    let (lambda, gamma2) = (x[lam] * s * s, x[g2]);
    let (abv, bbv, cbv) =
        reconstruct_paper_filter(plant, &rv, &svv, lambda, gamma2).ok_or_else(|| HinfError {
            kind: HinfErrorKind::Infeasible,
            message: format!(
                "the solver's R, S violate the eliminated LMIs (Clarabel {:?}): no filter \
                 can be reconstructed",
                sol.status
            ),
        })?;
    finish_paper(
        plant,
        period,
        &sol,
        &rv,
        &svv,
        &abv,
        &bbv,
        &cbv,
        lambda,
        gamma2,
        t0,
        DesignRoute::Sdp,
    )
}

/// `N = diag(I_6, [I_6; -D^-1 C], I_rest)`: the basis of `{(row, x, v, rest) : C x + D v =
/// 0}` for an LMI with blocks `(row 6, x 6, v 3, rest)`.
fn kernel_basis(dinv_c: &DMatrix<f64>, rest: usize) -> DMatrix<f64> {
    let mut kern = DMatrix::zeros(15 + rest, 12 + rest);
    for i in 0..12 {
        kern[(i, i)] = 1.0;
    }
    for i in 0..3 {
        for j in 0..6 {
            kern[(12 + i, 6 + j)] = -dinv_c[(i, j)];
        }
    }
    for i in 0..rest {
        kern[(15 + i, 12 + i)] = 1.0;
    }
    kern
}

/// A thin factor `F` (n x r) with `F F^T = M M^T` to working precision, `r` the numerical
/// rank of `M` (eigenvalues of `M M^T` above `1e-24` of the largest are kept): an input
/// that enters an LMI only as `X M` beside a block `-c I` can be replaced by `F` (module
/// docs). `M` itself when the eigensolver fails (exact, just not smaller).
fn thin_factor(m: &DMatrix<f64>) -> DMatrix<f64> {
    let Some(eig) = crate::numerics::eigen::symmetric_eigen(m * m.transpose()) else {
        return m.clone();
    };
    let top = eig.eigenvalues.iter().fold(0.0_f64, |a, b| a.max(*b));
    let keep: Vec<usize> = (0..eig.eigenvalues.len())
        .filter(|&i| eig.eigenvalues[i] > top * 1e-24)
        .collect();
    if keep.is_empty() {
        // M = 0: one zero column keeps the block structure
        return DMatrix::zeros(m.nrows(), 1);
    }
    let mut f = DMatrix::zeros(m.nrows(), keep.len());
    for (c, &i) in keep.iter().enumerate() {
        let sd = eig.eigenvalues[i].sqrt();
        for row in 0..m.nrows() {
            f[(row, c)] = eig.eigenvectors[(row, i)] * sd;
        }
    }
    f
}

/// `Theta = -Psi_jr Q^-1 V_r^T (V_r Q^-1 V_r^T)^-1`, `Q = -Psi_rr`: a solution of `Psi +
/// E_j^T Theta V + V^T Theta^T E_j < 0` when the variable enters one block row `j` only
/// (`V` zero in those columns), `Psi_rr < 0` and `Psi` is negative on `ker V` (module
/// docs, "Reconstruction"). `None` when `Q` is not positive definite or `V_r Q^-1 V_r^T`
/// is singular.
fn one_row_solution(
    psi: &DMatrix<f64>,
    rows: std::ops::Range<usize>,
    v: &DMatrix<f64>,
) -> Option<DMatrix<f64>> {
    let rest: Vec<usize> = (0..psi.nrows()).filter(|i| !rows.contains(i)).collect();
    let row: Vec<usize> = rows.collect();
    let q = -psi.select_rows(&rest).select_columns(&rest);
    let chol = q.cholesky()?;
    let vr = v.select_columns(&rest);
    let qi_vt = chol.solve(&vr.transpose());
    let gram = (&vr * &qi_vt).cholesky()?;
    let psi_jr = psi.select_rows(&row).select_columns(&rest);
    Some(-(psi_jr * gram.solve(&qi_vt.transpose()).transpose()))
}

/// `(Abar_F, Bbar_F, Cbar_F)` from the eliminated design's `R, S, lambda, g2` (module docs,
/// "Reconstruction"): `Cbar_F` first from condition (i), then `[Abar_F Bbar_F]` from eq. 20
/// in the coordinates where it enters the `S` row only.
fn reconstruct_paper_filter(
    plant: &HinfPlant,
    r: &DMatrix<f64>,
    s: &DMatrix<f64>,
    lambda: f64,
    gamma2: f64,
) -> Option<(DMatrix<f64>, DMatrix<f64>, DMatrix<f64>)> {
    let (z6, z63) = (DMatrix::zeros(6, 6), DMatrix::zeros(6, 3));
    // congruence T: xi_0 = xi_0', xi_1 = xi_1' - xi_0' (row 0' = row 0 - row 1)
    let mut t = DMatrix::<f64>::identity(45, 45);
    for i in 0..6 {
        t[(6 + i, i)] = -1.0;
    }
    let transformed = |m: DMatrix<f64>| t.transpose() * m * &t;
    let m0 = transformed(lmi_paper(plant, r, s, &z6, &z63, &z6, lambda, gamma2));
    // condition (i): without the S row; blocks W-row 0, x 6, x_f 12, w 18, v 24, z 27, d 33
    let keep: Vec<usize> = (0..6).chain(12..45).collect();
    let cond_i = m0.select_rows(&keep).select_columns(&keep);
    let mut v_c = DMatrix::zeros(6, 39);
    for i in 0..6 {
        v_c[(i, 12 + i)] = 1.0;
    }
    // the (z, x_f) block is -Cbar_F
    let cb = -one_row_solution(&cond_i, 27..33, &v_c)?;
    let m1 = transformed(lmi_paper(plant, r, s, &z6, &z63, &cb, lambda, gamma2));
    // blocks W-row 0, S-row 6, x 12, x_f 18, w 24, v 30, z 33, d 39
    let mut v_ab = DMatrix::zeros(9, 45);
    for i in 0..6 {
        v_ab[(i, 18 + i)] = 1.0;
    }
    for i in 0..3 {
        for j in 0..6 {
            v_ab[(6 + i, 12 + j)] = plant.c[(i, j)];
        }
        for j in 0..3 {
            v_ab[(6 + i, 30 + j)] = plant.d[(i, j)];
        }
    }
    let theta = one_row_solution(&m1, 6..12, &v_ab)?;
    Some((
        theta.columns(0, 6).into_owned(),
        theta.columns(6, 3).into_owned(),
        cb,
    ))
}

/// The filter from `(R, S, Abar_F, Bbar_F, Cbar_F)`, eq. 20 re-checked with nalgebra.
#[allow(clippy::too_many_arguments)]
fn finish_paper(
    plant: &HinfPlant,
    period: f64,
    sol: &SdpSolution,
    rv: &DMatrix<f64>,
    svv: &DMatrix<f64>,
    abv: &DMatrix<f64>,
    bbv: &DMatrix<f64>,
    cbv: &DMatrix<f64>,
    lambda: f64,
    gamma2: f64,
    t0: Instant,
    route: DesignRoute,
) -> Result<HinfDesign, HinfError> {
    let s_inv = svv.clone().try_inverse().ok_or_else(|| HinfError {
        kind: HinfErrorKind::Infeasible,
        message: "the solver's S is singular: no filter can be recovered".to_string(),
    })?;
    let a_f = &s_inv * abv;
    let b_f = &s_inv * bbv;
    let matrices = HinfMatrices {
        a_f: Mat6::from_fn(|i, j| a_f[(i, j)]),
        b_f: Mat63::from_fn(|i, j| b_f[(i, j)]),
        c_f: Mat6::from_fn(|i, j| cbv[(i, j)]),
        e_f: Mat63::zeros(),
        period,
    };
    // independent check: the LMI assembled from the recovered blocks with nalgebra
    let lmi = lmi_paper(plant, rv, svv, abv, bbv, cbv, lambda, gamma2);
    let max_eig = max_eig(&lmi);
    if !(max_eig < 0.0) {
        return Err(HinfError {
            kind: HinfErrorKind::Infeasible,
            message: format!(
                "the solver's answer violates the strict LMI (largest eigenvalue {max_eig:e} \
                 >= 0 at gamma {}, Clarabel {:?}): no filter with a certified gamma was found",
                gamma2.sqrt(),
                sol.status
            ),
        });
    }
    Ok(HinfDesign {
        matrices,
        gamma: gamma2.sqrt(),
        lmi_max_eig: max_eig,
        h2_norm: super::verify::filter_h2_norm(plant, &matrices),
        h2_bound: f64::NAN,
        status: status_name(sol.status),
        iterations: sol.iterations,
        solve_time: t0.elapsed().as_secs_f64(),
        route,
        riccati_failure: None,
        riccati_steps: 0,
    })
}

/// Paper 002, Corollary 1, posed literally: minimise `gamma^2` over the LMI (eq. 20) for
/// `plant` (built with [`HinfPlant::paper_closed_loop`]) in all of its variables `R, S,
/// Abar_F, Bbar_F, Cbar_F, lambda, g2` (134 scalars, one 45 x 45 LMI); `A_F = S^-1
/// Abar_F`, `B_F = S^-1 Bbar_F`, `C_F = Cbar_F`. [`design_paper`] solves the same problem
/// with the filter matrices eliminated (module docs, "Elimination of the filter
/// matrices"); this form is kept as its reference (`tests/hinf.rs` compares the two) and
/// as the fallback when `D` is singular. Errors: [`HinfErrorKind::Infeasible`] when no
/// filter exists (or the solution fails the independent check),
/// [`HinfErrorKind::SolverFailed`] otherwise.
pub fn design_paper_full(
    plant: &HinfPlant,
    period: f64,
    opts: &DesignOptions,
) -> Result<HinfDesign, HinfError> {
    check_opts(opts)?;
    check_plant(plant)?;
    let t0 = Instant::now();
    let plant = &paper_plant(plant);
    robustly_stable(plant)?;
    let s = balance(&plant.ha, &plant.ea);
    let (ha, ea) = (dm(&plant.ha) / s, dm(&plant.ea) * s);
    let (a, b, c, d, l) = (
        dm(&plant.a),
        dm(&plant.b),
        dm(&plant.c),
        dm(&plant.d),
        dm(&plant.l),
    );
    let n = 6;
    let mut vars = Vars { n: 0 };
    let r = vars.sym(n);
    let sv = vars.sym(n);
    let ab = vars.full(n, n);
    let bb = vars.full(n, 3);
    let cb = vars.full(6, n);
    let lam = vars.scalar();
    let g2 = vars.scalar();
    let nvar = vars.n;
    let blocks = [n, n, n, n, 6, 3, 6, 6];
    let mut m = Lmi::new(&blocks, nvar);
    let eye = |k: usize| DMatrix::<f64>::identity(k, k);
    for (k, e) in r.basis() {
        m.add(Some(k), 0, 0, &(-&e));
        m.add(Some(k), 0, 2, &(&e * &a));
        m.add(Some(k), 0, 4, &(&e * &b));
        m.add(Some(k), 0, 7, &(&e * &ha));
        m.add(Some(k), 2, 2, &(-&e));
    }
    for (k, e) in sv.basis() {
        m.add(Some(k), 0, 1, &(-&e));
        m.add(Some(k), 1, 1, &(-&e));
        m.add(Some(k), 1, 2, &(&e * &a));
        m.add(Some(k), 1, 4, &(&e * &b));
        m.add(Some(k), 1, 7, &(&e * &ha));
        m.add(Some(k), 2, 3, &(-&e));
        m.add(Some(k), 3, 3, &(-&e));
    }
    for (k, e) in ab.basis() {
        m.add(Some(k), 0, 3, &e);
        m.add(Some(k), 1, 3, &e);
    }
    for (k, e) in bb.basis() {
        m.add(Some(k), 0, 2, &(&e * &c));
        m.add(Some(k), 0, 5, &(&e * &d));
        m.add(Some(k), 1, 2, &(&e * &c));
        m.add(Some(k), 1, 5, &(&e * &d));
    }
    for (k, e) in cb.basis() {
        m.add(Some(k), 3, 6, &(-e.transpose()));
    }
    m.add(Some(lam), 2, 2, &(ea.transpose() * &ea));
    m.add(Some(lam), 7, 7, &(-eye(6)));
    m.add(Some(g2), 4, 4, &(-eye(6)));
    m.add(Some(g2), 5, 5, &(-eye(3)));
    m.add(None, 2, 6, &l.transpose());
    m.add(None, 6, 6, &(-eye(6)));

    // R <= rho I  <=>  R - rho I <= 0 ;  S >= eps I  <=>  -S <= -eps I (margin eps) ;
    // R - S >= eps I is implied by the main LMI's leading 2x2 block
    let bound = upper_bound(&r, n, nvar, opts.bound);
    let mut spos = Lmi::new(&[n], nvar);
    for (k, e) in sv.basis() {
        spos.add(Some(k), 0, 0, &(-e));
    }
    let mut cost = vec![0.0; nvar];
    cost[g2] = 1.0;
    let sdp = Sdp {
        nvar,
        cost,
        lmis: vec![(m, opts.margin), (bound, 0.0), (spos, opts.margin)],
        lower: vec![(lam, opts.margin), (g2, 0.0)],
        equilibrate: false,
    };
    let sol = sdp.solve(opts)?;
    let x = &sol.x;
    let (rv, svv, abv, bbv, cbv) = (
        r.value(x),
        sv.value(x),
        ab.value(x),
        bb.value(x),
        cb.value(x),
    );
    finish_paper(
        plant,
        period,
        &sol,
        &rv,
        &svv,
        &abv,
        &bbv,
        &cbv,
        x[lam] * s * s,
        x[g2],
        t0,
        DesignRoute::SdpLiteral,
    )
}

/// Necessary condition of Theorem 1: the augmented error system contains the plant state,
/// so `A + Ha F Ea` must be stable for every admissible `F`. Checked at the 64 sign
/// vertices `F = diag(+-1)`; a violation means the LMI has no solution (reported as
/// infeasible before the solver runs, which otherwise may stop with a numerical error).
fn robustly_stable(plant: &HinfPlant) -> Result<(), HinfError> {
    for mask in 0u32..64 {
        let f = Mat6::from_fn(|i, j| {
            if i != j {
                0.0
            } else if mask & (1 << i) != 0 {
                1.0
            } else {
                -1.0
            }
        });
        let a = dm(&(plant.a + plant.ha * f * plant.ea));
        let rho = super::verify::spectral_radius(&a);
        if !(rho < 1.0) {
            return Err(HinfError {
                kind: HinfErrorKind::Infeasible,
                message: format!(
                    "infeasible: the plant is not robustly stable (spectral radius {rho} of A + \
                     Ha F Ea at F = diag(+-1) vertex {mask}); Theorem 1's augmented system \
                     contains the plant state, so no filter exists — for an open-loop plant \
                     use the observer design"
                ),
            });
        }
    }
    Ok(())
}

/// Largest eigenvalue of a symmetric matrix (NaN when it is not finite or the capped
/// eigensolver does not converge: every caller's `< 0` test then fails).
pub(crate) fn max_eig(m: &DMatrix<f64>) -> f64 {
    let sym = (m + m.transpose()) * 0.5;
    match crate::numerics::eigen::symmetric_eigenvalues(sym) {
        Some(ev) => ev.iter().fold(f64::NEG_INFINITY, |a, b| a.max(*b)),
        None => f64::NAN,
    }
}

/// The gamma-optimal observer (error-dynamics) design for `plant` (any `A`, e.g.
/// [`HinfPlant::open_loop`]): minimise `gamma` over the observer LMI in the module docs.
/// First the Riccati route ([`design_observer_riccati`]: bisection on the H-infinity
/// filtering Riccati equation, the gain in closed form, certified on the literal LMI);
/// when it fails (singular `D`, no stabilising solution, failed certificate) the SDP
/// ([`design_observer_sdp`]) designs the filter and [`HinfDesign::route`] /
/// [`HinfDesign::riccati_failure`] say so. Returns `A_F = A - G C`, `B_F = G`, `C_F = I`,
/// `E_F = plant.g`.
pub fn design_observer(
    plant: &HinfPlant,
    period: f64,
    opts: &DesignOptions,
) -> Result<HinfDesign, HinfError> {
    check_opts(opts)?;
    check_plant(plant)?;
    let t0 = Instant::now();
    match design_observer_riccati(plant, period) {
        Ok(d) => Ok(d),
        Err(failure) => {
            let mut d = design_observer_sdp(plant, period, opts)?;
            d.riccati_failure = Some(failure);
            d.solve_time = t0.elapsed().as_secs_f64();
            Ok(d)
        }
    }
}

/// The gamma-optimal observer by the Riccati route ([`crate::hinf::riccati`]): the
/// bisection gives `gamma`, the stabilising solution `X` and the central gain `G`; the
/// observer LMI (module docs) is then assembled with nalgebra at `P = gamma^2 X^-1`, `G`,
/// `gamma^2` and must be negative definite (the same check as the SDP's answer), or the
/// route reports [`RiccatiFailure::CertificationFailed`]. No interior-point solver:
/// `iterations` is 0, `riccati_steps` the bisection's trials, `status` `"Riccati"`.
pub fn design_observer_riccati(
    plant: &HinfPlant,
    period: f64,
) -> Result<HinfDesign, RiccatiFailure> {
    let t0 = Instant::now();
    let r = super::riccati::observer(plant)?;
    let gamma2 = r.gamma * r.gamma;
    let p =
        r.x.try_inverse()
            .map(|xi| super::riccati::symmetric(&(xi * gamma2)))
            .ok_or(RiccatiFailure::CertificationFailed)?;
    let lmi = lmi_observer(plant, &dm(&p), &r.gain, gamma2);
    let max_eig = max_eig(&lmi);
    if !(max_eig < 0.0) {
        return Err(RiccatiFailure::CertificationFailed);
    }
    Ok(HinfDesign {
        matrices: HinfMatrices {
            a_f: plant.a - r.gain * plant.c,
            b_f: r.gain,
            c_f: Mat6::identity(),
            e_f: plant.g,
            period,
        },
        gamma: r.gamma,
        lmi_max_eig: max_eig,
        h2_norm: super::verify::observer_h2_norm(plant, &r.gain),
        h2_bound: f64::NAN,
        status: "Riccati",
        iterations: 0,
        solve_time: t0.elapsed().as_secs_f64(),
        route: DesignRoute::Riccati,
        riccati_failure: None,
        riccati_steps: r.steps,
    })
}

/// The gamma-optimal observer as an SDP with the gain variable `Y` eliminated (module
/// docs, "Elimination of the filter matrices"): an SDP in `P, g2` (22 scalars, LMIs of
/// sizes 21 and 6), then `Y` in closed form and the observer LMI checked at `G = P^-1 Y`
/// with nalgebra. [`design_observer_full`] when `D` is singular. The reference of the
/// Riccati route and the fallback of [`design_observer`].
pub fn design_observer_sdp(
    plant: &HinfPlant,
    period: f64,
    opts: &DesignOptions,
) -> Result<HinfDesign, HinfError> {
    check_opts(opts)?;
    check_plant(plant)?;
    let t0 = Instant::now();
    let dinv_c = match plant.d.try_inverse() {
        Some(di) if di.iter().all(|v| v.is_finite()) => dm(&(di * plant.c)),
        _ => return design_observer_full(plant, period, opts),
    };
    let a = dm(&plant.a);
    let b = thin_factor(&dm(&plant.b));
    // no rescaling of the robustness channel (module docs, conditioning 1)
    let hae = thin_factor(&dm(&(plant.ha * plant.ea.norm())));
    let l = dm(&plant.l);
    let ltl = l.transpose() * &l;
    let (pb, ph) = (b.ncols(), hae.ncols());
    let n = 6;
    let mut vars = Vars { n: 0 };
    let p = vars.sym(n);
    let g2 = vars.scalar();
    let nvar = vars.n;
    let eye = |k: usize| DMatrix::<f64>::identity(k, k);
    // on ker [C D]: blocks P-row, e, v, w, d (z by its Schur complement L^T L)
    let mut m = Lmi::new(&[n, n, 3, pb, ph], nvar);
    // outside it: P - L^T L > 0
    let mut out = Lmi::new(&[n], nvar);
    for (k, e) in p.basis() {
        m.add(Some(k), 0, 0, &(-&e));
        m.add(Some(k), 0, 1, &(&e * &a));
        m.add(Some(k), 0, 3, &(&e * &b));
        m.add(Some(k), 0, 4, &(&e * &hae));
        m.add(Some(k), 1, 1, &(-&e));
        out.add(Some(k), 0, 0, &(-&e));
    }
    m.add(None, 1, 1, &ltl);
    out.add(None, 0, 0, &ltl);
    m.add(Some(g2), 2, 2, &(-eye(3)));
    m.add(Some(g2), 3, 3, &(-eye(pb)));
    m.add(Some(g2), 4, 4, &(-eye(ph)));
    let m = m.congruence(&kernel_basis(&dinv_c, pb + ph));
    let bound = upper_bound(&p, n, nvar, opts.bound);
    let mut cost = vec![0.0; nvar];
    cost[g2] = 1.0;
    let sdp = Sdp {
        nvar,
        cost,
        lmis: vec![(m, opts.margin), (out, opts.margin), (bound, 0.0)],
        lower: vec![(g2, 0.0)],
        equilibrate: true,
    };
    let sol = sdp.solve(opts)?;
    let x = &sol.x;
    let pv = p.value(x);
    let gamma2 = x[g2];
    // Y enters the P row only: blocks P-row 0, e 6, w 12, v 18, d 21, z 27
    let psi = lmi_observer(plant, &pv, &Mat63::zeros(), gamma2);
    let mut v = DMatrix::zeros(3, 33);
    for i in 0..3 {
        for j in 0..6 {
            v[(i, 6 + j)] = -plant.c[(i, j)];
        }
        for j in 0..3 {
            v[(i, 18 + j)] = -plant.d[(i, j)];
        }
    }
    let yv = one_row_solution(&psi, 0..6, &v).ok_or_else(|| HinfError {
        kind: HinfErrorKind::Infeasible,
        message: format!(
            "the solver's P violates the eliminated LMIs (Clarabel {:?}): no observer gain can \
             be reconstructed",
            sol.status
        ),
    })?;
    finish_observer(plant, period, &sol, &pv, &yv, gamma2, t0, DesignRoute::Sdp)
}

/// The observer design posed literally, in `P, Y, g2` (40 scalars, one 33 x 33 LMI): the
/// reference for [`design_observer`] (`tests/hinf.rs` compares the two) and its fallback
/// when `D` is singular.
pub fn design_observer_full(
    plant: &HinfPlant,
    period: f64,
    opts: &DesignOptions,
) -> Result<HinfDesign, HinfError> {
    check_opts(opts)?;
    check_plant(plant)?;
    let t0 = Instant::now();
    let (a, b, c, d, l) = (
        dm(&plant.a),
        dm(&plant.b),
        dm(&plant.c),
        dm(&plant.d),
        dm(&plant.l),
    );
    // the robustness channel d = F Ea x enters with Ha; |d| <= |Ea x|: no rescaling here,
    // it would change the channel's weight (module docs, conditioning 1)
    let hae = dm(&(plant.ha * plant.ea.norm()));
    let n = 6;
    let mut vars = Vars { n: 0 };
    let p = vars.sym(n);
    let y = vars.full(n, 3);
    let g2 = vars.scalar();
    let nvar = vars.n;
    let eye = |k: usize| DMatrix::<f64>::identity(k, k);
    let mut m = Lmi::new(&[n, n, 6, 3, 6, 6], nvar);
    for (k, e) in p.basis() {
        m.add(Some(k), 0, 0, &(-&e));
        m.add(Some(k), 0, 1, &(&e * &a));
        m.add(Some(k), 0, 2, &(&e * &b));
        m.add(Some(k), 0, 4, &(&e * &hae));
        m.add(Some(k), 1, 1, &(-&e));
    }
    for (k, e) in y.basis() {
        m.add(Some(k), 0, 1, &(-(&e * &c)));
        m.add(Some(k), 0, 3, &(-(&e * &d)));
    }
    m.add(Some(g2), 2, 2, &(-eye(6)));
    m.add(Some(g2), 3, 3, &(-eye(3)));
    m.add(Some(g2), 4, 4, &(-eye(6)));
    m.add(None, 1, 5, &l.transpose());
    m.add(None, 5, 5, &(-eye(6)));
    let bound = upper_bound(&p, n, nvar, opts.bound);
    let mut cost = vec![0.0; nvar];
    cost[g2] = 1.0;
    let sdp = Sdp {
        nvar,
        cost,
        lmis: vec![(m, opts.margin), (bound, 0.0)],
        lower: vec![(g2, 0.0)],
        equilibrate: true,
    };
    let sol = sdp.solve(opts)?;
    let x = &sol.x;
    let (pv, yv) = (p.value(x), y.value(x));
    finish_observer(
        plant,
        period,
        &sol,
        &pv,
        &yv,
        x[g2],
        t0,
        DesignRoute::SdpLiteral,
    )
}

/// The observer from `(P, Y)`: `G = P^-1 Y`, the observer LMI re-checked with nalgebra.
#[allow(clippy::too_many_arguments)]
fn finish_observer(
    plant: &HinfPlant,
    period: f64,
    sol: &SdpSolution,
    pv: &DMatrix<f64>,
    yv: &DMatrix<f64>,
    gamma2: f64,
    t0: Instant,
    route: DesignRoute,
) -> Result<HinfDesign, HinfError> {
    let p_inv = pv.clone().try_inverse().ok_or_else(|| HinfError {
        kind: HinfErrorKind::Infeasible,
        message: "the solver's P is singular: no observer gain can be recovered".to_string(),
    })?;
    let gain = &p_inv * yv;
    let g = Mat63::from_fn(|i, j| gain[(i, j)]);
    let lmi = lmi_observer(plant, pv, &g, gamma2);
    let max_eig = max_eig(&lmi);
    if !(max_eig < 0.0) {
        return Err(HinfError {
            kind: HinfErrorKind::Infeasible,
            message: format!(
                "the solver's answer violates the strict LMI (largest eigenvalue {max_eig:e} \
                 >= 0): no observer with a certified gamma was found"
            ),
        });
    }
    Ok(HinfDesign {
        matrices: HinfMatrices {
            a_f: plant.a - g * plant.c,
            b_f: g,
            c_f: Mat6::identity(),
            e_f: plant.g,
            period,
        },
        gamma: gamma2.sqrt(),
        lmi_max_eig: max_eig,
        h2_norm: super::verify::observer_h2_norm(plant, &g),
        h2_bound: f64::NAN,
        status: status_name(sol.status),
        iterations: sol.iterations,
        solve_time: t0.elapsed().as_secs_f64(),
        route,
        riccati_failure: None,
        riccati_steps: 0,
    })
}

/// Paper design from a spec: [`HinfPlant::paper_closed_loop`] with the paper's `K` and mass.
pub fn design_paper_spec(spec: &HinfSpec, opts: &DesignOptions) -> Result<HinfDesign, HinfError> {
    spec.validate()?;
    let plant = HinfPlant::paper_closed_loop(spec, &super::PAPER_K, super::PAPER_MASS);
    design_paper(&plant, spec.period, opts)
}

/// Observer design from a spec on the open-loop CW plant ([`HinfPlant::open_loop`]).
pub fn design_open_loop(spec: &HinfSpec, opts: &DesignOptions) -> Result<HinfDesign, HinfError> {
    spec.validate()?;
    let plant = HinfPlant::open_loop(spec);
    design_observer(&plant, spec.period, opts)
}

/// The mixed H2/H-infinity observer design for `plant` (module docs, "Mixed H2/H-infinity
/// observer design"): minimise the bound `trace Z` on the squared H2 norm from `(w, v)` to
/// the error subject to the certified H-infinity bound `gamma_bound` on the gain from `(w,
/// v, d)` (the robustness channel included, as in [`design_observer`]). `start_gain` is a
/// stabilising observer gain (the Kalman predictor's or the gamma-optimal one) that sets
/// the first coordinate scaling. Returns `A_F = A - G C`, `B_F = G`, `C_F = I`, `E_F = plant.g` with `gamma =
/// gamma_bound`; the H2 norm is computed again without the solver
/// ([`crate::hinf::verify::observer_h2_norm`]). `iterations` and `solve_time` cover every
/// solve (one or two, see the module docs).
pub fn design_mixed(
    plant: &HinfPlant,
    period: f64,
    gamma_bound: f64,
    start_gain: &Mat63,
    opts: &DesignOptions,
) -> Result<HinfDesign, HinfError> {
    check_opts(opts)?;
    check_plant(plant)?;
    if !(gamma_bound.is_finite() && gamma_bound > 0.0) {
        return Err(HinfError::invalid(format!(
            "the H-infinity bound of the mixed design must be finite and > 0 (got {gamma_bound})"
        )));
    }
    let t0 = Instant::now();
    let tau0 = error_time_scale(plant, start_gain).ok_or_else(|| {
        HinfError::invalid("the start gain of the mixed design is not stabilising".to_string())
    })?;
    let mut d = solve_mixed(plant, period, gamma_bound, tau0, opts)?;
    if let Some(tau1) = error_time_scale(plant, &d.matrices.b_f) {
        if !(tau1 / tau0 > 0.5 && tau1 / tau0 < 2.0) {
            let first = d;
            d = solve_mixed(plant, period, gamma_bound, tau1, opts)?;
            d.iterations += first.iterations;
        }
    }
    d.solve_time = t0.elapsed().as_secs_f64();
    Ok(d)
}

/// `tau = sqrt(trace X_pp / trace X_vv)` [s] of the steady-state error covariance `X` of
/// the observer with gain `g` ([`crate::hinf::verify::observer_error_covariance`]): the
/// time over which a velocity error makes a position error of its size.
fn error_time_scale(plant: &HinfPlant, g: &Mat63) -> Option<f64> {
    let x = super::verify::observer_error_covariance(plant, g)?;
    let pp = x[(0, 0)] + x[(1, 1)] + x[(2, 2)];
    let vv = x[(3, 3)] + x[(4, 4)] + x[(5, 5)];
    let tau = (pp / vv).sqrt();
    (tau.is_finite() && tau > 0.0).then_some(tau)
}

/// The plant in the coordinates `e' = S e`, `S = diag(I3, tau I3)`: `S A S^-1`, `S B`,
/// `C S^-1`, `L S^-1`, `S Ha`, `S Gamma` (`Ea` acts on the plant state, not on `e`, and is
/// kept). Every transfer from `(w, v, d)` to `z_e` is unchanged, so is the optimal gamma.
/// Returns the plant and `S^-1`. (Also used by the tests and `examples/hinf_profile.rs` to
/// pose the observer SDP in balanced units.)
pub fn scaled_plant(plant: &HinfPlant, tau: f64) -> (HinfPlant, Mat6) {
    let s = Mat6::from_diagonal(&crate::types::State::from_row_slice(&[
        1.0, 1.0, 1.0, tau, tau, tau,
    ]));
    let si = Mat6::from_diagonal(&crate::types::State::from_row_slice(&[
        1.0,
        1.0,
        1.0,
        1.0 / tau,
        1.0 / tau,
        1.0 / tau,
    ]));
    (
        HinfPlant {
            a: s * plant.a * si,
            b: s * plant.b,
            c: plant.c * si,
            d: plant.d,
            l: plant.l * si,
            ha: s * plant.ha,
            ea: plant.ea,
            g: s * plant.g,
        },
        si,
    )
}

/// One solve of the mixed SDP in the coordinates scaled by `tau`.
fn solve_mixed(
    plant: &HinfPlant,
    period: f64,
    gamma_bound: f64,
    tau: f64,
    opts: &DesignOptions,
) -> Result<HinfDesign, HinfError> {
    let (sp, s_inv) = scaled_plant(plant, tau);
    let (a, b, c, d, l) = (dm(&sp.a), dm(&sp.b), dm(&sp.c), dm(&sp.d), dm(&sp.l));
    let hae = dm(&(sp.ha * sp.ea.norm()));
    let g2 = gamma_bound * gamma_bound;
    let n = 6;
    let mut vars = Vars { n: 0 };
    let xv = vars.full(n, n);
    let y = vars.full(n, 3);
    let p_inf = vars.sym(n);
    let p2 = vars.sym(n);
    let z = vars.sym(9);
    let nvar = vars.n;
    let eye = |k: usize| DMatrix::<f64>::identity(k, k);
    // H-infinity (extended form): blocks n, n, p, q, h, l
    let mut hinf = Lmi::new(&[n, n, 6, 3, 6, 6], nvar);
    // H2, Lyapunov part: blocks n, n, l
    let mut lyap = Lmi::new(&[n, n, 6], nvar);
    // H2, input part: blocks n, p + q
    let mut input = Lmi::new(&[n, 9], nvar);
    let pad = |m: DMatrix<f64>, col: usize| {
        let mut o = DMatrix::zeros(n, 9);
        o.view_mut((0, col), (n, m.ncols())).copy_from(&m);
        o
    };
    for (k, e) in xv.basis() {
        let sym = -(&e + e.transpose());
        for lmi in [&mut hinf, &mut lyap, &mut input] {
            lmi.add(Some(k), 0, 0, &sym);
        }
        hinf.add(Some(k), 0, 1, &(&e * &a));
        hinf.add(Some(k), 0, 2, &(&e * &b));
        hinf.add(Some(k), 0, 4, &(&e * &hae));
        lyap.add(Some(k), 0, 1, &(&e * &a));
        input.add(Some(k), 0, 1, &pad(&e * &b, 0));
    }
    for (k, e) in y.basis() {
        hinf.add(Some(k), 0, 1, &(-(&e * &c)));
        hinf.add(Some(k), 0, 3, &(-(&e * &d)));
        lyap.add(Some(k), 0, 1, &(-(&e * &c)));
        input.add(Some(k), 0, 1, &pad(-(&e * &d), 6));
    }
    for (k, e) in p_inf.basis() {
        hinf.add(Some(k), 0, 0, &e);
        hinf.add(Some(k), 1, 1, &(-&e));
    }
    for (k, e) in p2.basis() {
        lyap.add(Some(k), 0, 0, &e);
        lyap.add(Some(k), 1, 1, &(-&e));
        input.add(Some(k), 0, 0, &e);
    }
    // minimise trace Z
    let mut cost = vec![0.0; nvar];
    for (k, e) in z.basis() {
        input.add(Some(k), 1, 1, &(-&e));
        cost[k] = e.trace();
    }
    hinf.add(None, 1, 5, &l.transpose());
    hinf.add(None, 2, 2, &(-eye(6) * g2));
    hinf.add(None, 3, 3, &(-eye(3) * g2));
    hinf.add(None, 4, 4, &(-eye(6) * g2));
    hinf.add(None, 5, 5, &(-eye(6)));
    lyap.add(None, 1, 2, &l.transpose());
    lyap.add(None, 2, 2, &(-eye(6)));
    let sdp = Sdp {
        nvar,
        cost,
        lmis: vec![
            (hinf, opts.margin),
            (lyap, opts.margin),
            (input, opts.margin),
        ],
        lower: vec![],
        equilibrate: true,
    };
    let sol = sdp.solve(opts)?;
    let xs = &sol.x;
    let (xval, yval) = (xv.value(xs), y.value(xs));
    let x_inv = xval.clone().try_inverse().ok_or_else(|| HinfError {
        kind: HinfErrorKind::Infeasible,
        message: "the solver's slack X is singular: no observer gain can be recovered".to_string(),
    })?;
    let gain = &x_inv * &yval;
    let g_scaled = Mat63::from_fn(|i, j| gain[(i, j)]);
    let zval = z.value(xs);
    // independent check, in the solver's coordinates
    let lmis = lmi_mixed(
        &sp,
        &xval,
        &g_scaled,
        &p_inf.value(xs),
        &p2.value(xs),
        &zval,
        g2,
    );
    let max_eig = lmis.iter().map(max_eig).fold(f64::NEG_INFINITY, f64::max);
    if !(max_eig < 0.0) {
        return Err(HinfError {
            kind: HinfErrorKind::Infeasible,
            message: format!(
                "the solver's answer violates the strict mixed LMIs (largest eigenvalue \
                 {max_eig:e} >= 0 at gamma {gamma_bound}, Clarabel {:?}): no observer with a \
                 certified bound was found",
                sol.status
            ),
        });
    }
    // back to the plant's coordinates: e = S^-1 e', so G = S^-1 G'
    let g = s_inv * g_scaled;
    Ok(HinfDesign {
        matrices: HinfMatrices {
            a_f: plant.a - g * plant.c,
            b_f: g,
            c_f: Mat6::identity(),
            e_f: plant.g,
            period,
        },
        gamma: gamma_bound,
        lmi_max_eig: max_eig,
        h2_norm: super::verify::observer_h2_norm(plant, &g),
        h2_bound: zval.trace().max(0.0).sqrt(),
        status: status_name(sol.status),
        iterations: sol.iterations,
        solve_time: 0.0,
        route: DesignRoute::Sdp,
        riccati_failure: None,
        riccati_steps: 0,
    })
}

/// Both observer designs of a mixed request: the gamma-optimal one, whose `gamma` sets the
/// bound, and the mixed one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MixedDesign {
    /// The gamma-optimal observer ([`design_observer`]).
    pub pure: HinfDesign,
    /// The mixed design with `gamma <= gamma_factor * pure.gamma`.
    pub mixed: HinfDesign,
}

/// The mixed design on the open-loop CW plant ([`HinfPlant::open_loop`]): first the
/// gamma-optimal observer, then [`design_mixed`] with `gamma_bound = gamma_factor *
/// gamma_opt` (`gamma_factor > 1`: at 1 the bound is the optimum itself and only the
/// optimal filter, if any, meets it), started from the Kalman predictor's gain (module
/// docs, "Scaling").
pub fn design_open_loop_mixed(
    spec: &HinfSpec,
    gamma_factor: f64,
    opts: &DesignOptions,
) -> Result<MixedDesign, HinfError> {
    spec.validate()?;
    if !(gamma_factor.is_finite() && gamma_factor > 1.0) {
        return Err(HinfError::invalid(format!(
            "gamma_factor must be finite and > 1 (got {gamma_factor})"
        )));
    }
    let plant = HinfPlant::open_loop(spec);
    let pure = design_observer(&plant, spec.period, opts)?;
    // the first coordinate scaling from the Kalman predictor, whose error covariance is
    // closer to the mixed design's than the gamma-optimal observer's (module docs,
    // "Scaling"); the gamma-optimal gain when there is no Kalman gain (singular D)
    let start = super::riccati::kalman_gain(&plant).unwrap_or(pure.matrices.b_f);
    let mixed = design_mixed(&plant, spec.period, gamma_factor * pure.gamma, &start, opts)?;
    Ok(MixedDesign { pure, mixed })
}
