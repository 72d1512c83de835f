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
//! # Elimination of the filter matrices
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
//! (b), (c), which is less conservative than `-eps I` on the 45 x 45 matrix: the gamma it
//! reaches is slightly lower than the literal SDP's.
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
//! (the optimal filter is not unique), and its H2 norm differs.
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
//! *Riccati route.* For a fixed `g2` the LMI is, by duality and completing the
//! square in `G`, equivalent to a Riccati inequality of the a-priori H-infinity filter, so
//! [`design_observer`] does not solve it as an SDP: it bisects on `gamma` with the
//! stabilising solution of the Riccati equation deciding each trial (structure-preserving
//! doubling), builds the central gain in closed form and checks this LMI at `P = g2 X^-1`
//! with nalgebra ([`crate::hinf::riccati`], with the derivation and references). The SDP
//! ([`design_observer_sdp`], [`design_observer_full`]) stays as the reference and as the
//! fallback, taken automatically and recorded in [`HinfDesign::route`] and
//! [`HinfDesign::riccati_failure`]. The Riccati route is not bounded by `P <= rho I`, so
//! it reaches the infimum where the SDP's bound binds (as on the quiet-truth noise, whose
//! error covariance spans many orders of magnitude).
//!
//! # Mixed H2/H-infinity observer design
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
//!
//! # Where
//!
//! The paper design in `paper.rs`, the gamma-optimal observer in `observer.rs`, the mixed
//! observer in `mixed.rs`; the assembly of the LMIs into Clarabel's SDP, the solve and the
//! linear algebra of the elimination in `sdp.rs`.

mod mixed;
mod observer;
mod paper;
mod sdp;

pub use super::DesignRoute;
pub use mixed::{
    design_mixed, design_open_loop_mixed, design_plant_mixed, scaled_plant, MixedDesign,
};
pub use observer::{
    design_observer, design_observer_full, design_observer_riccati, design_observer_sdp,
    design_open_loop,
};
pub use paper::{design_paper, design_paper_full, design_paper_spec};

use super::riccati::RiccatiFailure;
use super::{HinfDesignInfo, HinfError, HinfMatrices, HinfPlant};
use crate::types::Mat6;

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

fn check_opts(o: &DesignOptions) -> Result<(), HinfError> {
    if !(o.bound.is_finite() && o.bound > 0.0 && o.margin.is_finite() && o.margin > 0.0) {
        return Err(HinfError::invalid(format!(
            "design options: bound and margin must be finite and > 0 (got {}, {})",
            o.bound, o.margin
        )));
    }
    Ok(())
}

fn check_plant<const M: usize>(p: &HinfPlant<M>) -> Result<(), HinfError> {
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
