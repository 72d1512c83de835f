//! The gamma-optimal observer (error-dynamics) design for the open-loop plant: by the
//! Riccati route ([`design_observer_riccati`]) with the SDP as its reference and fallback
//! ([`design_observer_sdp`], [`design_observer_full`]); see the [design docs](super).

use super::sdp::{dm, kernel_basis, max_eig, one_row_solution, status_name, thin_factor};
use super::sdp::{upper_bound, Lmi, Sdp, SdpSolution, Vars};
use super::{check_opts, check_plant, DesignOptions, DesignRoute, HinfDesign};
use crate::hinf::riccati::RiccatiFailure;
use crate::hinf::verify::lmi_observer;
use crate::hinf::Gain;
use crate::hinf::{HinfError, HinfErrorKind, HinfMatrices, HinfPlant, HinfSpec};
use nalgebra::DMatrix;
use std::time::Instant;

/// The gamma-optimal observer (error-dynamics) design for `plant` (any `A`, e.g.
/// [`HinfPlant::open_loop`]): minimise `gamma` over the observer LMI in the [design
/// docs](super). First the Riccati route ([`design_observer_riccati`]: bisection on the H-infinity
/// filtering Riccati equation, the gain in closed form, certified on the literal LMI);
/// when it fails (singular `D`, no stabilising solution, failed certificate) the SDP
/// ([`design_observer_sdp`]) designs the filter and [`HinfDesign::route`] /
/// [`HinfDesign::riccati_failure`] say so. Returns `A_F = A - G C`, `B_F = G`, `C_F = I`,
/// `E_F = plant.g`.
pub fn design_observer<const M: usize>(
    plant: &HinfPlant<M>,
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
/// observer LMI ([design docs](super)) is then assembled with nalgebra at
/// `P = gamma^2 X^-1`, `G`, `gamma^2` and must be negative definite (the same check as the SDP's answer), or the
/// route reports [`RiccatiFailure::CertificationFailed`]. No interior-point solver:
/// `iterations` is 0, `riccati_steps` the bisection's trials, `status` `"Riccati"`.
pub fn design_observer_riccati<const M: usize>(
    plant: &HinfPlant<M>,
    period: f64,
) -> Result<HinfDesign, RiccatiFailure> {
    let t0 = Instant::now();
    let r = crate::hinf::riccati::observer(plant)?;
    let gamma2 = r.gamma * r.gamma;
    let p =
        r.x.try_inverse()
            .map(|xi| crate::hinf::riccati::symmetric(&(xi * gamma2)))
            .ok_or(RiccatiFailure::CertificationFailed)?;
    let lmi = lmi_observer(plant, &dm(&p), &r.gain, gamma2);
    let max_eig = max_eig(&lmi);
    if !(max_eig < 0.0) {
        return Err(RiccatiFailure::CertificationFailed);
    }
    Ok(HinfDesign {
        matrices: HinfMatrices::observer(plant, &r.gain, period),
        gamma: r.gamma,
        lmi_max_eig: max_eig,
        h2_norm: crate::hinf::verify::observer_h2_norm(plant, &r.gain),
        h2_bound: f64::NAN,
        status: "Riccati",
        iterations: 0,
        solve_time: t0.elapsed().as_secs_f64(),
        route: DesignRoute::Riccati,
        riccati_failure: None,
        riccati_steps: r.steps,
    })
}

/// The gamma-optimal observer as an SDP with the gain variable `Y` eliminated ([design
/// docs](super), "Elimination of the filter matrices"): an SDP in `P, g2` (22 scalars, LMIs of
/// sizes 21 and 6), then `Y` in closed form and the observer LMI checked at `G = P^-1 Y`
/// with nalgebra. [`design_observer_full`] when `D` is singular. The reference of the
/// Riccati route and the fallback of [`design_observer`].
pub fn design_observer_sdp<const M: usize>(
    plant: &HinfPlant<M>,
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
    // no rescaling of the robustness channel (design docs, conditioning 1)
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
    let mut m = Lmi::new(&[n, n, M, pb, ph], nvar);
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
    m.add(Some(g2), 2, 2, &(-eye(M)));
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
    // Y enters the P row only: blocks P-row 0, e 6, w 12, v 18, d 18 + M, z 24 + M
    let psi = lmi_observer(plant, &pv, &Gain::<M>::zeros(), gamma2);
    let mut v = DMatrix::zeros(M, 30 + M);
    for i in 0..M {
        for j in 0..6 {
            v[(i, 6 + j)] = -plant.c[(i, j)];
        }
        for j in 0..M {
            v[(i, 18 + j)] = -plant.d[(i, j)];
        }
    }
    let yv = one_row_solution(&psi, 0..6, &v).ok_or_else(|| HinfError {
        kind: HinfErrorKind::Infeasible,
        message: format!(
            "the solver's P violates the eliminated LMIs (Clarabel {:?}): no observer gain can \
             be reconstructed",
            sol.status
        )
        .into(),
    })?;
    finish_observer(plant, period, &sol, &pv, &yv, gamma2, t0, DesignRoute::Sdp)
}

/// The observer design posed literally, in `P, Y, g2` (40 scalars, one 33 x 33 LMI): the
/// reference for [`design_observer`] (`tests/hinf.rs` compares the two) and its fallback
/// when `D` is singular.
pub fn design_observer_full<const M: usize>(
    plant: &HinfPlant<M>,
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
    // it would change the channel's weight (design docs, conditioning 1)
    let hae = dm(&(plant.ha * plant.ea.norm()));
    let n = 6;
    let mut vars = Vars { n: 0 };
    let p = vars.sym(n);
    let y = vars.full(n, M);
    let g2 = vars.scalar();
    let nvar = vars.n;
    let eye = |k: usize| DMatrix::<f64>::identity(k, k);
    let mut m = Lmi::new(&[n, n, 6, M, 6, 6], nvar);
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
    m.add(Some(g2), 3, 3, &(-eye(M)));
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
fn finish_observer<const M: usize>(
    plant: &HinfPlant<M>,
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
        message: "the solver's P is singular: no observer gain can be recovered"
            .to_string()
            .into(),
    })?;
    let gain = &p_inv * yv;
    let g = Gain::<M>::from_fn(|i, j| gain[(i, j)]);
    let lmi = lmi_observer(plant, pv, &g, gamma2);
    let max_eig = max_eig(&lmi);
    if !(max_eig < 0.0) {
        return Err(HinfError {
            kind: HinfErrorKind::Infeasible,
            message: format!(
                "the solver's answer violates the strict LMI (largest eigenvalue {max_eig:e} \
                 >= 0): no observer with a certified gamma was found"
            )
            .into(),
        });
    }
    Ok(HinfDesign {
        matrices: HinfMatrices::observer(plant, &g, period),
        gamma: gamma2.sqrt(),
        lmi_max_eig: max_eig,
        h2_norm: crate::hinf::verify::observer_h2_norm(plant, &g),
        h2_bound: f64::NAN,
        status: status_name(sol.status),
        iterations: sol.iterations,
        solve_time: t0.elapsed().as_secs_f64(),
        route,
        riccati_failure: None,
        riccati_steps: 0,
    })
}

/// Observer design from a spec on the open-loop CW plant ([`HinfPlant::open_loop`]).
pub fn design_open_loop(spec: &HinfSpec, opts: &DesignOptions) -> Result<HinfDesign, HinfError> {
    spec.validate()?;
    let plant = HinfPlant::open_loop(spec);
    design_observer(&plant, spec.period, opts)
}
