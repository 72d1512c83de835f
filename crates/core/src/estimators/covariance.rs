//! The Kalman covariance products the estimators share, specialised to the structure of
//! relnav's models: the time update `P- = Phi P Phi^T + Q` with the transitions' block
//! structure ([`propagate_covariance`], the dense product for any other transition) and the
//! Joseph-form measurement update for a Jacobian `H = [H_r 0]` that measures the position
//! ([`joseph_update`]; with the innovation's factor, [`position_innovation`] and
//! [`position_update`], the EKF's and the robust EKF's update). Estimator algebra rather
//! than general numerics: each relies on the structure of a model. Their 4- and 6-vector
//! axpys are [`crate::numerics::lanes`]'.

use super::{finite, FilterError};
use crate::dynamics::DiscreteModel;
use crate::numerics::cholesky::{chol3, Chol3};
use crate::numerics::lanes::{axpy4, axpy6};
use crate::numerics::symmetrize;
use crate::types::{Mat3, Mat6, Mat63, State, Vec3};

/// In-plane components of the canonical state `(x, y, vx, vy)` and out-of-plane `(z, vz)`:
/// no relnav transition couples the two groups ([`crate::dynamics::CwModel::phi`], the elliptic model).
const IN_PLANE: [usize; 4] = [0, 1, 3, 4];
const OUT_OF_PLANE: [usize; 2] = [2, 5];

/// The structure of a transition that [`propagate_covariance`] exploits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Structure {
    /// none: the dense product
    Dense,
    /// block diagonal in (in-plane) x (out-of-plane) (16 zeros): every relnav model's
    /// transition (the elliptic model's)
    Blocks,
    /// and an along-track column `e_y` (nothing depends on the along-track position `y`:
    /// `phi[(i, 1)] = 0` for `i != 1`, `phi[(1, 1)] = 1`): the exact and the Euler CW
    /// transitions
    Cw,
}

/// The [`Structure`] of `phi`. Branch-free tests: the bits of the entries that must be
/// (signed) zero are or-ed, so each costs a few instructions.
#[inline]
fn structure(phi: &Mat6) -> Structure {
    // `<< 1` drops the sign bit: -0.0 counts as zero, as `== 0.0` would
    let bits = |entries: &[(usize, usize)]| {
        entries
            .iter()
            .fold(0u64, |acc, &(r, c)| acc | (phi[(r, c)].to_bits() << 1))
    };
    let coupling = [
        (0, 2),
        (1, 2),
        (3, 2),
        (4, 2),
        (0, 5),
        (1, 5),
        (3, 5),
        (4, 5),
        (2, 0),
        (2, 1),
        (2, 3),
        (2, 4),
        (5, 0),
        (5, 1),
        (5, 3),
        (5, 4),
    ];
    if bits(&coupling) != 0 {
        Structure::Dense
    } else if bits(&[(0, 1), (3, 1), (4, 1)]) == 0 && phi[(1, 1)] == 1.0 {
        Structure::Cw
    } else {
        Structure::Blocks
    }
}

/// The Kalman time update through the linear discrete model of `(x, p)` in place:
/// `x- = Phi x + Gamma a`, `P- = Phi P Phi^T + Q` ([`propagate_covariance`]), written only
/// when both are finite (the EKF's and the UKF's `predict`). [`time_update_into`]'s body
/// again rather than that function on a copy of `(x, p)`: the release build keeps the copy.
#[inline(always)]
pub(crate) fn time_update(
    model: &DiscreteModel,
    x: &mut State,
    p: &mut Mat6,
    accel: &Vec3,
) -> Result<(), FilterError> {
    let xn = model.apply(x, accel);
    let pn = propagate_covariance(&model.phi, p, &model.q);
    finite(&xn, "predicted state")?;
    finite(&pn, "predicted covariance")?;
    *x = xn;
    *p = pn;
    Ok(())
}

/// [`time_update`] of an uncommitted `(x, p)` into `out`, written only when both results
/// are finite: a transactional step (`update_predict`: an update not yet committed, then
/// this) commits both at once. Out-parameters rather than a returned pair: returning the
/// pair costs a copy of it on every step.
#[inline(always)]
pub(crate) fn time_update_into(
    model: &DiscreteModel,
    x: &State,
    p: &Mat6,
    accel: &Vec3,
    out: (&mut State, &mut Mat6),
) -> Result<(), FilterError> {
    let xn = model.apply(x, accel);
    let pn = propagate_covariance(&model.phi, p, &model.q);
    finite(&xn, "predicted state")?;
    finite(&pn, "predicted covariance")?;
    *out.0 = xn;
    *out.1 = pn;
    Ok(())
}

/// The Kalman time update of the covariance, `P- = sym(Phi P Phi^T + Q)` for a symmetric
/// `P` (`sym` as in [`symmetrize`]).
///
/// Block structure: every relnav transition (CW, exact and Euler, and the elliptic model)
/// is block diagonal in (in-plane `x, y, vx, vy`) x (out-of-plane `z, vz`), and CW's
/// along-track column is `e_y` ([`structure`], checked on the matrix itself at every call:
/// the model's fields are public and callers change `q` after discretising, so a flag
/// cached at construction could go stale). Then `Phi P Phi^T` splits into `F P_ii F^T`
/// (4 x 4), `F P_io G^T` (4 x 2) and `G P_oo G^T` (2 x 2) with `F`, `G` the in-plane and
/// out-of-plane blocks. `T = F P_i.` (the in-plane rows of `P`, all six columns) and then
/// `T_i F^T`, `T_o G^T` are computed column by column as 4-vector axpys (vectorised by the
/// compiler), skipping the `y` column of `F` when it is `e_y`; of the symmetric result only
/// the lower triangle is kept and mirrored: 150 multiplications with CW's `e_y` column, 190
/// without it, instead of 432 (dense). `Q` enters as `sym(Q)` (the same bits as `Q` when
/// `Q` is symmetric). Any other transition takes the dense product; the three agree to
/// rounding (unit test). Run through [`crate::numerics::simd::dispatch`]: the axpys in AVX2
/// registers when the CPU has them, the same bits (no fused multiply-add on either path).
pub(crate) fn propagate_covariance(phi: &Mat6, p: &Mat6, q: &Mat6) -> Mat6 {
    crate::numerics::simd::dispatch(
        #[inline(always)]
        || propagate_covariance_inline(phi, p, q),
    )
}

/// [`propagate_covariance`]'s body, inlined into its [`crate::numerics::simd::dispatch`].
#[inline(always)]
fn propagate_covariance_inline(phi: &Mat6, p: &Mat6, q: &Mat6) -> Mat6 {
    match structure(phi) {
        Structure::Dense => symmetrize(&(phi * p * phi.transpose() + q)),
        Structure::Blocks => propagate_blocks::<false>(phi, p, q),
        Structure::Cw => propagate_blocks::<true>(phi, p, q),
    }
}

/// [`propagate_covariance`] for a block-diagonal `phi`, whose along-track column is `e_y`
/// if `EY`.
#[inline(always)]
fn propagate_blocks<const EY: bool>(phi: &Mat6, p: &Mat6, q: &Mat6) -> Mat6 {
    // the columns of F the products take: all four, or without the along-track one
    let ks: &[usize] = if EY { &[0, 2, 3] } else { &[0, 1, 2, 3] };
    let f = |r: usize, c: usize| phi[(IN_PLANE[r], IN_PLANE[c])];
    let g = |r: usize, c: usize| phi[(OUT_OF_PLANE[r], OUT_OF_PLANE[c])];
    // columns of F (in-plane 4 x 4; column 1 is e_1 and is not used) and of P's in-plane
    // and coupling blocks, as 4-vectors
    let fc: [[f64; 4]; 4] = core::array::from_fn(|c| core::array::from_fn(|r| f(r, c)));
    let pin: [[f64; 4]; 6] =
        core::array::from_fn(|j| core::array::from_fn(|r| p[(IN_PLANE[r], j)]));
    // T = F P_i. (in-plane rows of F times P's in-plane rows, all six columns):
    // column j = sum over k in {0, 2, 3} of F_k P[k][j], plus P[y][j] in row 1 (F[1][1] = 1)
    let mut t = [[0.0; 4]; 6];
    for (tj, pj) in t.iter_mut().zip(pin.iter()) {
        for &k in ks {
            axpy4(tj, &fc[k], pj[k]);
        }
        if EY {
            tj[1] += pj[1];
        }
    }
    // in-plane block N = T_i F^T: column c = sum over k in {0, 2, 3} of T_k F[c][k] (+ T_1
    // for c = 1); coupling block T_i G^T... (rows in-plane, columns out-of-plane)
    let ti = [t[0], t[1], t[3], t[4]];
    let mut n = [[0.0; 4]; 4];
    for (c, nc) in n.iter_mut().enumerate() {
        for &k in ks {
            axpy4(nc, &ti[k], f(c, k));
        }
        if EY && c == 1 {
            for (v, w) in nc.iter_mut().zip(ti[1].iter()) {
                *v += w;
            }
        }
    }
    let mut nio = [[0.0; 4]; 2];
    for (c, nc) in nio.iter_mut().enumerate() {
        axpy4(nc, &t[2], g(c, 0));
        axpy4(nc, &t[5], g(c, 1));
    }
    // out-of-plane block G P_oo G^T
    let (p22, p25, p52, p55) = (p[(2, 2)], p[(2, 5)], p[(5, 2)], p[(5, 5)]);
    let v = [
        [g(0, 0) * p22 + g(0, 1) * p52, g(0, 0) * p25 + g(0, 1) * p55],
        [g(1, 0) * p22 + g(1, 1) * p52, g(1, 0) * p25 + g(1, 1) * p55],
    ];
    let noo = |r: usize, c: usize| v[r][0] * g(c, 0) + v[r][1] * g(c, 1);
    // assemble the lower triangle with sym(Q), mirror
    let sq = |i: usize, j: usize| {
        if i == j {
            q[(i, i)]
        } else {
            (q[(i, j)] + q[(j, i)]) * 0.5
        }
    };
    let mut out = Mat6::zeros();
    let mut put = |i: usize, j: usize, w: f64| {
        let w = w + sq(i, j);
        out[(i, j)] = w;
        out[(j, i)] = w;
    };
    for (r, &i) in IN_PLANE.iter().enumerate() {
        for (c, &j) in IN_PLANE.iter().enumerate().take(r + 1) {
            put(i, j, n[c][r]);
        }
        for (c, &j) in OUT_OF_PLANE.iter().enumerate() {
            put(i, j, nio[c][r]);
        }
    }
    put(2, 2, noo(0, 0));
    put(5, 2, noo(1, 0));
    put(5, 5, noo(1, 1));
    out
}

/// The Joseph-form covariance update `P+ = (I - K H) P (I - K H)^T + K R K^T` for a
/// measurement Jacobian `H = [H_r 0]` whose velocity columns are zero (every
/// [`crate::sensors::MeasurementModel`]: they measure the position;
/// [`crate::sensors::Geometry::h`]).
///
/// With `M = K H_r` (6 x 3): `A = P - M P_r` (`P_r` the position rows of `P`), then
/// `B = A - A_c M^T` (`A_c` the position columns of `A`) — 216 multiplications for the
/// congruence instead of 648 with the dense 6 x 6 `I - K H`. Computed column by column as
/// 6-vector axpys on plain arrays (the compiler vectorises them; nalgebra's generic small
/// products did not), and the symmetric result is the lower triangle of
/// `B + K R K^T`, mirrored. Every entry kept is the Joseph form's own
/// sum of products, so the result is PSD for any gain `K` to rounding (a sum of two
/// congruences of PSD matrices; no subtraction of `K H P` from `P` as in the short form
/// `(I - K H) P`, which loses that for a suboptimal or inexact gain). Run through
/// [`crate::numerics::simd::dispatch`]: each 6-vector axpy one 4-wide and one 2-wide
/// operation instead of three 2-wide ones, the same bits.
pub(crate) fn joseph_update(p: &Mat6, k: &Mat63, h_r: &Mat3, r: &Mat3) -> Mat6 {
    crate::numerics::simd::dispatch(
        #[inline(always)]
        || joseph_update_inline(p, k, h_r, r),
    )
}

/// [`joseph_update`]'s body, inlined into its [`crate::numerics::simd::dispatch`].
#[inline(always)]
fn joseph_update_inline(p: &Mat6, k: &Mat63, h_r: &Mat3, r: &Mat3) -> Mat6 {
    joseph_block_inline::<3, 0>(p, &k.data.0, &h_r.data.0, &r.data.0)
}

/// [`joseph_update`] for a measurement of `D` components whose Jacobian's only nonzero
/// columns are the three from `OFF` (the position, `OFF = 0`, or the velocity, `OFF = 3`):
/// `k` the gain's `D` columns, `h` the `D x 3` block's three columns, `r` the noise's `D`
/// columns. The same algebra (`M = K H_b`, `A = P - M P_b`, `A - A_b M^T + K R K^T`, lower
/// triangle mirrored), the same bits as [`joseph_update`] for `D = 3`, `OFF = 0`.
pub(crate) fn joseph_block<const D: usize, const OFF: usize>(
    p: &Mat6,
    k: &[[f64; 6]; D],
    h: &[[f64; D]; 3],
    r: &[[f64; D]; D],
) -> Mat6 {
    crate::numerics::simd::dispatch(
        #[inline(always)]
        || joseph_block_inline::<D, OFF>(p, k, h, r),
    )
}

/// [`joseph_block`]'s body (and [`joseph_update`]'s), inlined into its
/// [`crate::numerics::simd::dispatch`].
#[inline(always)]
fn joseph_block_inline<const D: usize, const OFF: usize>(
    p: &Mat6,
    kc: &[[f64; 6]; D],
    hc: &[[f64; D]; 3],
    rc: &[[f64; D]; D],
) -> Mat6 {
    // columns, as plain arrays (nalgebra stores column by column): the column operations
    // below are 6-vector axpys the compiler vectorises
    let pc = p.data.0;
    // M = K H_b (three columns) and K R (D columns), column by column
    let mut m = [[0.0; 6]; 3];
    for (mj, hj) in m.iter_mut().zip(hc.iter()) {
        for (kl, hlj) in kc.iter().zip(hj.iter()) {
            axpy6(mj, kl, *hlj);
        }
    }
    let mut kr = [[0.0; 6]; D];
    for (krj, rj) in kr.iter_mut().zip(rc.iter()) {
        for (kl, rlj) in kc.iter().zip(rj.iter()) {
            axpy6(krj, kl, *rlj);
        }
    }
    // A = P - M P_b (P_b the block's rows of P): column j = P_j - sum_l M_l P[OFF + l][j]
    let mut a = pc;
    for (aj, pj) in a.iter_mut().zip(pc.iter()) {
        for (l, ml) in m.iter().enumerate() {
            axpy6(aj, ml, -pj[OFF + l]);
        }
    }
    // B = A - A_b M^T (A_b the block's columns of A), plus K R K^T:
    // column j = A_j - sum_l A_(OFF + l) M[j][l] + sum_l (K R)_l K[j][l]
    let mut out = [[0.0; 6]; 6];
    for (j, oj) in out.iter_mut().enumerate() {
        let mut c = a[j];
        for l in 0..3 {
            axpy6(&mut c, &a[OFF + l], -m[l][j]);
            if l < D {
                axpy6(&mut c, &kr[l], kc[l][j]);
            }
        }
        for l in 3..D {
            axpy6(&mut c, &kr[l], kc[l][j]);
        }
        *oj = c;
    }
    // the symmetric result: the lower triangle, mirrored
    let mut out = Mat6::from_data(nalgebra::ArrayStorage(out));
    out.fill_upper_triangle_with_lower_triangle();
    out
}

/// `P H^T`, `S = H P H^T + R` and the closed-form Cholesky factor of `S` (on the stack) for
/// a measurement of the position, `H = [h_r 0]`.
#[inline(always)]
pub(crate) fn position_innovation(
    p: &Mat6,
    h_r: &Mat3,
    r: &Mat3,
) -> Result<(Mat63, Mat3, Chol3), FilterError> {
    let ph = p.fixed_columns::<3>(0) * h_r.transpose();
    let s = h_r * ph.fixed_rows::<3>(0) + r;
    let chol = chol3(&s).ok_or(FilterError::NotPositiveDefinite("innovation covariance S"))?;
    Ok((ph, s, chol))
}

/// The Kalman update of `(x, P)` with innovation `nu` from [`position_innovation`]'s `P H^T`
/// and factor: `K = P H^T S^-1` (one solve per row: `S`, `P` symmetric), `x + K nu` and
/// the Joseph form.
#[inline(always)]
pub(crate) fn position_update(
    x: &State,
    p: &Mat6,
    h_r: &Mat3,
    nu: &Vec3,
    r: &Mat3,
    ph: &Mat63,
    chol: &Chol3,
) -> (State, Mat6) {
    let k = chol.gain(ph);
    (x + k * nu, joseph_update(p, &k, h_r, r))
}

/// The Kalman update of `(x, P)` from a measurement's cross covariance `pxz` (`P H^T`, or
/// the UKF's sigma-point `Pxz`), its innovation covariance `s` and that one's factor:
/// `K = Pxz S^-1` (one solve per row), `x + K nu` and `P - K S K^T`, symmetrised. The UKF's
/// radio update and the robust update on its moments.
#[inline(always)]
pub(crate) fn moments_update(
    x: &State,
    p: &Mat6,
    pxz: &Mat63,
    s: &Mat3,
    chol: &Chol3,
    nu: &Vec3,
) -> (State, Mat6) {
    let k = chol.gain(pxz);
    (x + k * nu, symmetrize(&(p - k * s * k.transpose())))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::{CwModel, Discretization};

    fn spd() -> Mat6 {
        let a = Mat6::from_fn(|i, j| ((i * 7 + j * 3) % 5) as f64 - 1.7 + 0.1 * i as f64);
        a * a.transpose() + Mat6::identity()
    }

    /// The block-structured products equal the dense formulas to rounding, for CW
    /// transitions (exact, Euler) and for a full matrix (dense path).
    #[test]
    fn structured_covariance_products_equal_the_dense_ones() {
        let p = spd();
        let q = Mat6::from_diagonal(&State::from_row_slice(&[
            1e-3, 2e-3, 3e-3, 1e-6, 2e-6, 3e-6,
        ]));
        let m = CwModel::new(1.1e-3);
        let full = Mat6::from_fn(|i, j| 0.1 * (i as f64 + 1.0) - 0.05 * j as f64);
        for phi in [
            m.discretize(7.0, &Mat3::zeros(), Discretization::Exact).phi,
            m.discretize(7.0, &Mat3::zeros(), Discretization::Euler).phi,
            full,
        ] {
            let dense = symmetrize(&(phi * p * phi.transpose() + q));
            let got = propagate_covariance(&phi, &p, &q);
            assert!((got - dense).norm() <= 1e-14 * dense.norm(), "{phi}");
            assert_eq!(got, got.transpose());
        }
        let mut h = crate::types::Mat36::zeros();
        let h_r = Mat3::from_fn(|i, j| 0.3 * i as f64 - 0.2 * j as f64 + 1.0);
        h.fixed_columns_mut::<3>(0).copy_from(&h_r);
        let r = Mat3::from_diagonal(&Vec3::new(0.25, 4e-8, 4e-8));
        let k = Mat63::from_fn(|i, j| 0.01 * (i as f64 - j as f64) + 0.02);
        let ikh = Mat6::identity() - k * h;
        let dense = symmetrize(&(ikh * p * ikh.transpose() + k * r * k.transpose()));
        let got = joseph_update(&p, &k, &h_r, &r);
        assert!((got - dense).norm() <= 1e-14 * dense.norm());
        assert_eq!(got, got.transpose());
        // the dispatched (AVX2 when present) and the baseline paths: the same bits
        let bits = |m: &Mat6| m.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        let base = crate::numerics::simd::with_baseline(|| joseph_update(&p, &k, &h_r, &r));
        assert_eq!(bits(&got), bits(&base));
        for phi in [
            m.discretize(7.0, &Mat3::zeros(), Discretization::Exact).phi,
            crate::dynamics::EllipticModel::new(1.1e-3, 0.3, 0.5).phi(100.0, 7.0),
            full,
        ] {
            let fast = propagate_covariance(&phi, &p, &q);
            let base = crate::numerics::simd::with_baseline(|| propagate_covariance(&phi, &p, &q));
            assert_eq!(bits(&fast), bits(&base));
        }
    }

    /// The structure test takes the exact and Euler CW transitions as CW, a transition with
    /// anything in the along-track column as blocks and one with anything in the
    /// in-plane/out-of-plane coupling as dense; every path agrees with the dense formula.
    #[test]
    fn structure_is_detected_exactly() {
        let p = spd();
        let q = Mat6::from_diagonal(&State::from_row_slice(&[
            1e-3, 2e-3, 3e-3, 1e-6, 2e-6, 3e-6,
        ]));
        let m = CwModel::new(1.1e-3);
        let phi = m.discretize(7.0, &Mat3::zeros(), Discretization::Exact).phi;
        assert_eq!(structure(&phi), Structure::Cw);
        assert_eq!(
            structure(&m.discretize(7.0, &Mat3::zeros(), Discretization::Euler).phi),
            Structure::Cw
        );
        let mut neg_zero = phi;
        neg_zero[(0, 1)] = -0.0;
        assert_eq!(structure(&neg_zero), Structure::Cw);
        let elliptic = crate::dynamics::EllipticModel::new(1.1e-3, 0.3, 0.5);
        let ell_phi = elliptic.phi(100.0, 7.0);
        assert_eq!(structure(&ell_phi), Structure::Blocks);
        let dense = symmetrize(&(ell_phi * p * ell_phi.transpose() + q));
        let got = propagate_covariance(&ell_phi, &p, &q);
        assert!((got - dense).norm() <= 1e-14 * dense.norm());
        assert_eq!(got, got.transpose());
        for (r, c, v, expected) in [
            (0, 1, 1e-300, Structure::Blocks),
            (3, 1, 0.5, Structure::Blocks),
            (4, 1, -2.0, Structure::Blocks),
            (1, 1, 1.0 + 1e-15, Structure::Blocks),
            (2, 0, 1e-9, Structure::Dense),
            (3, 5, 0.1, Structure::Dense),
            (5, 4, f64::NAN, Structure::Dense),
        ] {
            let mut other = phi;
            other[(r, c)] = v;
            assert_eq!(structure(&other), expected, "({r}, {c}) = {v}");
            if v.is_finite() {
                let dense = symmetrize(&(other * p * other.transpose() + q));
                let got = propagate_covariance(&other, &p, &q);
                assert!((got - dense).norm() <= 1e-14 * dense.norm());
            }
        }
        // an asymmetric Q enters as sym(Q), as in the dense formula
        let mut qa = q;
        qa[(0, 3)] = 1e-4;
        let dense = symmetrize(&(phi * p * phi.transpose() + qa));
        let got = propagate_covariance(&phi, &p, &qa);
        assert!((got - dense).norm() <= 1e-14 * dense.norm());
    }
}
