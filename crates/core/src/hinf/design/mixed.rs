//! The mixed H2/H-infinity observer design: the H2 norm minimised under a certified
//! H-infinity bound, posed in balanced coordinates ([`scaled_plant`]); see the [design
//! docs](super).

use super::observer::design_observer;
use super::sdp::{dm, max_eig, status_name, Lmi, Sdp, Vars};
use super::{check_opts, check_plant, DesignOptions, DesignRoute, HinfDesign};
use crate::hinf::verify::lmi_mixed;
use crate::hinf::Gain;
use crate::hinf::{HinfDesignInfo, HinfError, HinfErrorKind, HinfMatrices, HinfPlant, HinfSpec};
use crate::types::Mat6;
use nalgebra::DMatrix;
use std::time::Instant;

/// Both observer designs of a mixed request: the gamma-optimal one, whose `gamma` sets the
/// bound, and the mixed one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MixedDesign {
    /// The gamma-optimal observer ([`design_observer`]).
    pub pure: HinfDesign,
    /// The mixed design with `gamma <= gamma_factor * pure.gamma`.
    pub mixed: HinfDesign,
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

/// The mixed H2/H-infinity observer design for `plant` ([design docs](super), "Mixed
/// H2/H-infinity observer design"): minimise the bound `trace Z` on the squared H2 norm from `(w, v)` to
/// the error subject to the certified H-infinity bound `gamma_bound` on the gain from `(w,
/// v, d)` (the robustness channel included, as in [`design_observer`]). `start_gain` is a
/// stabilising observer gain (the Kalman predictor's or the gamma-optimal one) that sets
/// the first coordinate scaling. Returns `A_F = A - G C`, `B_F = G`, `C_F = I`, `E_F = plant.g` with `gamma =
/// gamma_bound`; the H2 norm is computed again without the solver
/// ([`crate::hinf::verify::observer_h2_norm`]). `iterations` and `solve_time` cover every
/// solve (one or two, see the [design docs](super)).
pub fn design_mixed<const M: usize>(
    plant: &HinfPlant<M>,
    period: f64,
    gamma_bound: f64,
    start_gain: &Gain<M>,
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
    if let Some(tau1) = error_time_scale(plant, &d.matrices.gain::<M>()) {
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
fn error_time_scale<const M: usize>(plant: &HinfPlant<M>, g: &Gain<M>) -> Option<f64> {
    let x = crate::hinf::verify::observer_error_covariance(plant, g)?;
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
pub fn scaled_plant<const M: usize>(plant: &HinfPlant<M>, tau: f64) -> (HinfPlant<M>, Mat6) {
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
fn solve_mixed<const M: usize>(
    plant: &HinfPlant<M>,
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
    let y = vars.full(n, M);
    let p_inf = vars.sym(n);
    let p2 = vars.sym(n);
    let z = vars.sym(6 + M);
    let nvar = vars.n;
    let eye = |k: usize| DMatrix::<f64>::identity(k, k);
    // H-infinity (extended form): blocks n, n, p, q, h, l
    let mut hinf = Lmi::new(&[n, n, 6, M, 6, 6], nvar);
    // H2, Lyapunov part: blocks n, n, l
    let mut lyap = Lmi::new(&[n, n, 6], nvar);
    // H2, input part: blocks n, p + q
    let mut input = Lmi::new(&[n, 6 + M], nvar);
    let pad = |m: DMatrix<f64>, col: usize| {
        let mut o = DMatrix::zeros(n, 6 + M);
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
    hinf.add(None, 3, 3, &(-eye(M) * g2));
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
        message: "the solver's slack X is singular: no observer gain can be recovered"
            .to_string()
            .into(),
    })?;
    let gain = &x_inv * &yval;
    let g_scaled = Gain::<M>::from_fn(|i, j| gain[(i, j)]);
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
            )
            .into(),
        });
    }
    // back to the plant's coordinates: e = S^-1 e', so G = S^-1 G'
    let g = s_inv * g_scaled;
    Ok(HinfDesign {
        matrices: HinfMatrices::observer(plant, &g, period),
        gamma: gamma_bound,
        lmi_max_eig: max_eig,
        h2_norm: crate::hinf::verify::observer_h2_norm(plant, &g),
        h2_bound: zval.trace().max(0.0).sqrt(),
        status: status_name(sol.status),
        iterations: sol.iterations,
        solve_time: 0.0,
        route: DesignRoute::Sdp,
        riccati_failure: None,
        riccati_steps: 0,
    })
}

/// The mixed design on the open-loop CW plant ([`HinfPlant::open_loop`]): first the
/// gamma-optimal observer, then [`design_mixed`] with `gamma_bound = gamma_factor *
/// gamma_opt` (`gamma_factor > 1`: at 1 the bound is the optimum itself and only the
/// optimal filter, if any, meets it), started from the Kalman predictor's gain ([design
/// docs](super), "Scaling").
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
    design_plant_mixed(&HinfPlant::open_loop(spec), spec.period, gamma_factor, opts)
}

/// [`design_open_loop_mixed`] for any observer plant (e.g. one that measures the velocity
/// as well, [`HinfPlant::measuring_velocity`]): the gamma-optimal observer, then
/// [`design_mixed`] with `gamma_bound = gamma_factor * gamma_opt` from the Kalman
/// predictor's gain.
pub fn design_plant_mixed<const M: usize>(
    plant: &HinfPlant<M>,
    period: f64,
    gamma_factor: f64,
    opts: &DesignOptions,
) -> Result<MixedDesign, HinfError> {
    if !(gamma_factor.is_finite() && gamma_factor > 1.0) {
        return Err(HinfError::invalid(format!(
            "gamma_factor must be finite and > 1 (got {gamma_factor})"
        )));
    }
    let pure = design_observer(plant, period, opts)?;
    // the first coordinate scaling from the Kalman predictor, whose error covariance is
    // closer to the mixed design's than the gamma-optimal observer's (design docs,
    // "Scaling"); the gamma-optimal gain when there is no Kalman gain (singular D)
    let start = crate::hinf::riccati::kalman_gain(plant).unwrap_or(pure.matrices.gain::<M>());
    let mixed = design_mixed(plant, period, gamma_factor * pure.gamma, &start, opts)?;
    Ok(MixedDesign { pure, mixed })
}
