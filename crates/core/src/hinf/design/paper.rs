//! Paper 002's design (Theorem 1 / Corollary 1): the gamma-optimal filter of the closed
//! loop, with the filter matrices eliminated ([`design_paper`]) or posed literally
//! ([`design_paper_full`]); see the [design docs](super).

use super::sdp::{dm, kernel_basis, max_eig, one_row_solution, status_name, thin_factor};
use super::sdp::{upper_bound, Lmi, Sdp, SdpSolution, Vars};
use super::{balance, check_opts, check_plant, DesignOptions, DesignRoute, HinfDesign};
use crate::hinf::verify::lmi_paper;
use crate::hinf::{HinfError, HinfErrorKind, HinfMatrices, HinfPlant, HinfSpec};
use crate::types::{Mat6, Mat63};
use nalgebra::DMatrix;
use std::time::Instant;

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
/// [`HinfPlant::paper_closed_loop`]), with the filter matrices eliminated ([design
/// docs](super), "Elimination of the filter matrices"): the SDP is solved in `R, S, lambda, g2` only (44
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
    // B and Ha enter only through B B^T and Ha Ha^T (design docs): thin factors
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
    // (W = R - S; design docs)
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
            )
            .into(),
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

/// `(Abar_F, Bbar_F, Cbar_F)` from the eliminated design's `R, S, lambda, g2` ([design
/// docs](super), "Reconstruction"): `Cbar_F` first from condition (i), then `[Abar_F Bbar_F]` from eq. 20
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
        message: "the solver's S is singular: no filter can be recovered"
            .to_string()
            .into(),
    })?;
    let a_f = &s_inv * abv;
    let b_f = &s_inv * bbv;
    let matrices = HinfMatrices {
        a_f: Mat6::from_fn(|i, j| a_f[(i, j)]),
        b_f: Mat63::from_fn(|i, j| b_f[(i, j)]),
        c_f: Mat6::from_fn(|i, j| cbv[(i, j)]),
        e_f: Mat63::zeros(),
        b_v: Mat63::zeros(),
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
            )
            .into(),
        });
    }
    Ok(HinfDesign {
        matrices,
        gamma: gamma2.sqrt(),
        lmi_max_eig: max_eig,
        h2_norm: crate::hinf::verify::filter_h2_norm(plant, &matrices),
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
/// with the filter matrices eliminated ([design docs](super), "Elimination of the filter
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
        let rho = crate::hinf::verify::spectral_radius(&a);
        if !(rho < 1.0) {
            return Err(HinfError {
                kind: HinfErrorKind::Infeasible,
                message: format!(
                    "infeasible: the plant is not robustly stable (spectral radius {rho} of A + \
                     Ha F Ea at F = diag(+-1) vertex {mask}); Theorem 1's augmented system \
                     contains the plant state, so no filter exists — for an open-loop plant \
                     use the observer design"
                )
                .into(),
            });
        }
    }
    Ok(())
}

/// Paper design from a spec: [`HinfPlant::paper_closed_loop`] with the paper's `K` and mass.
pub fn design_paper_spec(spec: &HinfSpec, opts: &DesignOptions) -> Result<HinfDesign, HinfError> {
    spec.validate()?;
    let plant = HinfPlant::paper_closed_loop(spec, &crate::hinf::PAPER_K, crate::hinf::PAPER_MASS);
    design_paper(&plant, spec.period, opts)
}
