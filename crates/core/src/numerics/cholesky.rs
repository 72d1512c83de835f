//! Square-root factors of small symmetric matrices, on the stack: the lower Cholesky
//! factors of 6 x 6 and 3 x 3 matrices written out ([`chol6`] with nalgebra's bits,
//! [`chol3`] in closed form with the reciprocals of its diagonal), the 3 x 3 factor on one
//! lane of a structure-of-arrays block without a branch ([`chol3_lane`], so that a loop
//! over lanes vectorises) and the packed lower triangles it reads ([`lower6`]), the factor
//! of a symmetrised covariance ([`chol`], with a diagonal load for one that lost a dimension
//! to rounding: [`chol_loaded`]), and the Gaussian log-density through a factor
//! ([`log_gauss`]).

use super::symmetrize;
#[cfg(not(feature = "std"))]
use crate::math::Float;
use crate::types::{Mat3, Mat6, State, Vec3};

/// The state dimension.
const N: usize = 6;

/// Lower Cholesky factor `L` (`P = L L^T`) of a symmetric 6 x 6 matrix from its lower
/// triangle, the upper triangle zero: nalgebra's column algorithm (`Cholesky::new` then
/// `unpack`) operation for operation, so the same bits (tested), and `None` for the same
/// matrices (a zero, negative or NaN pivot). Written out so that it inlines into the
/// navigator's UKF step: nalgebra's generic factorisation stays an out-of-line call there,
/// with copies of the matrix in and out.
#[inline(always)]
pub(crate) fn chol6(p: &Mat6) -> Option<Mat6> {
    let mut m = *p;
    for j in 0..6 {
        for k in 0..j {
            // column j from row j down, less L[j][k] times column k (nalgebra's `axpy`:
            // `a x + y` with `a = -L[j][k]`)
            let f = -m[(j, k)];
            for r in j..6 {
                m[(r, j)] += f * m[(r, k)];
            }
        }
        let d = m[(j, j)];
        if !(d > 0.0) {
            return None;
        }
        let root = d.sqrt();
        m[(j, j)] = root;
        for r in j + 1..6 {
            m[(r, j)] /= root;
        }
    }
    for c in 1..6 {
        for r in 0..c {
            m[(r, c)] = 0.0;
        }
    }
    Some(m)
}

/// Cholesky factor `L` (lower, `S = L L^T`) of a symmetric 3 x 3 matrix from its lower
/// triangle, in closed form on the stack, with the reciprocals of its diagonal; `None`
/// when a pivot is not positive (nalgebra's `cholesky` refuses the same: zero, negative or
/// NaN pivots).
#[inline]
pub(crate) fn chol3(s: &Mat3) -> Option<Chol3> {
    let d0 = s[(0, 0)];
    if !(d0 > 0.0) {
        return None;
    }
    let l00 = d0.sqrt();
    let i0 = 1.0 / l00;
    let l10 = s[(1, 0)] * i0;
    let l20 = s[(2, 0)] * i0;
    let d1 = s[(1, 1)] - l10 * l10;
    if !(d1 > 0.0) {
        return None;
    }
    let l11 = d1.sqrt();
    let i1 = 1.0 / l11;
    let l21 = (s[(2, 1)] - l20 * l10) * i1;
    let d2 = s[(2, 2)] - l20 * l20 - l21 * l21;
    if !(d2 > 0.0) {
        return None;
    }
    let l22 = d2.sqrt();
    let i2 = 1.0 / l22;
    Some(Chol3 {
        l10,
        l20,
        l21,
        diag: [l00, l11, l22],
        inv: [i0, i1, i2],
    })
}

/// Lower Cholesky factor of a symmetric `D x D` matrix (`D` small: a sensor's innovation
/// covariance) from its lower triangle, with the reciprocals of its diagonal, on the stack;
/// `None` for a zero, negative or NaN pivot (as [`chol3`]). The loops have constant bounds
/// and unroll.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // triangular loops, written as the formulas
pub(crate) fn chol_small<const D: usize>(s: &nalgebra::SMatrix<f64, D, D>) -> Option<CholSmall<D>> {
    let mut l = [[0.0; D]; D];
    let mut inv = [0.0; D];
    for j in 0..D {
        let mut d = s[(j, j)];
        for k in 0..j {
            d -= l[j][k] * l[j][k];
        }
        if !(d > 0.0) {
            return None;
        }
        let root = d.sqrt();
        l[j][j] = root;
        inv[j] = 1.0 / root;
        for i in j + 1..D {
            let mut v = s[(i, j)];
            for k in 0..j {
                v -= l[i][k] * l[j][k];
            }
            l[i][j] = v * inv[j];
        }
    }
    Some(CholSmall { l, inv })
}

/// A factor from [`chol_small`]: `l[i][j]` row `i`, column `j` (lower), and the reciprocals
/// of the diagonal.
#[derive(Debug, Clone, Copy)]
pub(crate) struct CholSmall<const D: usize> {
    l: [[f64; D]; D],
    inv: [f64; D],
}

#[allow(clippy::needless_range_loop)] // triangular loops, written as the formulas
impl<const D: usize> CholSmall<D> {
    /// `y = L^-1 b` (forward substitution).
    #[inline(always)]
    pub(crate) fn forward(&self, b: &[f64; D]) -> [f64; D] {
        let mut y = [0.0; D];
        for i in 0..D {
            let mut v = b[i];
            for k in 0..i {
                v -= self.l[i][k] * y[k];
            }
            y[i] = v * self.inv[i];
        }
        y
    }

    /// `S^-1 b`: forward, then back substitution (`x = L^-T y`).
    #[inline(always)]
    pub(crate) fn solve(&self, b: &[f64; D]) -> [f64; D] {
        let mut x = self.forward(b);
        for i in (0..D).rev() {
            let mut v = x[i];
            for k in i + 1..D {
                v -= self.l[k][i] * x[k];
            }
            x[i] = v * self.inv[i];
        }
        x
    }
}

/// A 3 x 3 Cholesky factor from [`chol3`]: the strictly lower entries and the reciprocals
/// of the diagonal.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Chol3 {
    l10: f64,
    l20: f64,
    l21: f64,
    diag: [f64; 3],
    inv: [f64; 3],
}

impl Chol3 {
    /// Whether every entry of the factor is finite.
    pub(crate) fn is_finite(&self) -> bool {
        crate::numerics::all_finite(&[
            self.diag[0],
            self.diag[1],
            self.diag[2],
            self.l10,
            self.l20,
            self.l21,
        ])
    }

    /// `ln det S = 2 sum ln L_ii`.
    pub(crate) fn log_det(&self) -> f64 {
        2.0 * (self.diag[0].ln() + self.diag[1].ln() + self.diag[2].ln())
    }

    /// The factor `L` as a matrix.
    pub(crate) fn factor(&self) -> Mat3 {
        let [l00, l11, l22] = self.diag;
        Mat3::new(l00, 0.0, 0.0, self.l10, l11, 0.0, self.l20, self.l21, l22)
    }

    /// `y = L^-1 b` (forward substitution).
    #[inline]
    pub(crate) fn forward(&self, b: &Vec3) -> Vec3 {
        let y0 = b.x * self.inv[0];
        let y1 = (b.y - self.l10 * y0) * self.inv[1];
        let y2 = (b.z - self.l20 * y0 - self.l21 * y1) * self.inv[2];
        Vec3::new(y0, y1, y2)
    }

    /// `x = L^-T y` (back substitution).
    #[inline]
    pub(crate) fn backward(&self, y: &Vec3) -> Vec3 {
        let x2 = y.z * self.inv[2];
        let x1 = (y.y - self.l21 * x2) * self.inv[1];
        let x0 = (y.x - self.l10 * x1 - self.l20 * x2) * self.inv[0];
        Vec3::new(x0, x1, x2)
    }

    /// `S^-1 b`.
    #[inline]
    pub(crate) fn solve(&self, b: &Vec3) -> Vec3 {
        self.backward(&self.forward(b))
    }

    /// The Kalman gain `K = C S^-1` of a cross covariance `C` (`P H^T`, or the UKF's
    /// `Pxz`), row by row: `S` is symmetric, so each row of `K` is `S^-1` times that row of
    /// `C`.
    #[inline(always)]
    pub(crate) fn gain(&self, c: &crate::types::Mat63) -> crate::types::Mat63 {
        let mut k = crate::types::Mat63::zeros();
        for i in 0..6 {
            let ki = self.solve(&Vec3::new(c[(i, 0)], c[(i, 1)], c[(i, 2)]));
            k[(i, 0)] = ki.x;
            k[(i, 1)] = ki.y;
            k[(i, 2)] = ki.z;
        }
        k
    }
}

/// Lower Cholesky factor, `None` unless positive definite.
pub(crate) fn chol(p: &Mat6) -> Option<Mat6> {
    symmetrize(p).cholesky().map(|c| c.unpack())
}

/// Lower Cholesky factor, with a relative `1e-12` diagonal load if the matrix is only
/// semi-definite (a cloud that lost a dimension to rounding).
pub(crate) fn chol_loaded(p: &Mat6) -> Option<Mat6> {
    chol(p).or_else(|| {
        let eps = 1e-12 * p.trace().max(f64::MIN_POSITIVE);
        chol(&(p + Mat6::identity() * eps))
    })
}

/// `ln N(x; m, L L^T)` up to the constant `-3 ln 2 pi`, `L` lower triangular.
pub(crate) fn log_gauss(x: &State, m: &State, l: &Mat6) -> f64 {
    log_gauss_with(x, m, l, half_logdet(l))
}

/// `sum_i ln L_ii = ln det(L L^T) / 2`.
pub(crate) fn half_logdet(l: &Mat6) -> f64 {
    (0..N).map(|i| l[(i, i)].ln()).sum()
}

/// [`log_gauss`] with `half_logdet(l)` given (a factor shared by many particles).
pub(crate) fn log_gauss_with(x: &State, m: &State, l: &Mat6, half_logdet: f64) -> f64 {
    let d = x - m;
    match l.solve_lower_triangular(&d) {
        Some(u) => -0.5 * u.norm_squared() - half_logdet,
        None => f64::NEG_INFINITY,
    }
}

/// The lower triangle of `m`, `(m00, m10, m20, m11, m21, m22)`: the packed form of the
/// shared-prior updates' symmetric 3 x 3 matrices.
#[inline(always)]
pub(crate) fn lower6(m: &Mat3) -> [f64; 6] {
    [
        m[(0, 0)],
        m[(1, 0)],
        m[(2, 0)],
        m[(1, 1)],
        m[(2, 1)],
        m[(2, 2)],
    ]
}

/// The lower triangle of the symmetric `d d^T`, in the order `(00, 10, 20, 11, 21, 22)` of
/// [`lower6`] (the innovation covariance's sums over the sigma points).
#[inline(always)]
pub(crate) fn outer6(d: &[f64; 3]) -> [f64; 6] {
    [
        d[0] * d[0],
        d[0] * d[1],
        d[0] * d[2],
        d[1] * d[1],
        d[1] * d[2],
        d[2] * d[2],
    ]
}

/// nalgebra's `Vector3::dot`: `(a0 b0 + a1 b1) + a2 b2`.
#[inline(always)]
pub(crate) fn dot3(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// [`chol3`] on one lane without a branch: `(l00, l10, l20, l11, l21, l22)`, the
/// reciprocals of the diagonal and whether `chol3` would have succeeded (every pivot
/// positive, every entry finite). The same operations in the same order, so the same bits
/// where it succeeds.
#[inline(always)]
pub(crate) fn chol3_lane(a: [f64; 6]) -> ([f64; 6], [f64; 3], bool) {
    let d0 = a[0];
    let l00 = d0.sqrt();
    let i0 = 1.0 / l00;
    let l10 = a[1] * i0;
    let l20 = a[2] * i0;
    let d1 = a[3] - l10 * l10;
    let l11 = d1.sqrt();
    let i1 = 1.0 / l11;
    let l21 = (a[4] - l20 * l10) * i1;
    let d2 = a[5] - l20 * l20 - l21 * l21;
    let l22 = d2.sqrt();
    let i2 = 1.0 / l22;
    let ok = (d0 > 0.0)
        & (d1 > 0.0)
        & (d2 > 0.0)
        & l00.is_finite()
        & l11.is_finite()
        & l22.is_finite()
        & l10.is_finite()
        & l20.is_finite()
        & l21.is_finite();
    ([l00, l10, l20, l11, l21, l22], [i0, i1, i2], ok)
}

/// `Chol3::forward` on one lane: `y = L^-1 b` with `l` and `inv` from [`chol3_lane`].
#[inline(always)]
pub(crate) fn forward_lane(l: &[f64; 6], inv: &[f64; 3], b: [f64; 3]) -> [f64; 3] {
    let y0 = b[0] * inv[0];
    let y1 = (b[1] - l[1] * y0) * inv[1];
    let y2 = (b[2] - l[2] * y0 - l[4] * y1) * inv[2];
    [y0, y1, y2]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The written-out 6 x 6 Cholesky factor is nalgebra's bit for bit, and refuses the same
    /// matrices.
    #[test]
    fn chol6_is_nalgebras_factor_bit_for_bit() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        for _ in 0..500 {
            let a = Mat6::from_fn(|_, _| rng.random_range(-3.0..3.0));
            let scale = 10f64.powi(rng.random_range(-6..6));
            let p = (a * a.transpose() + Mat6::identity() * 1e-9) * scale;
            let ours = chol6(&p).unwrap();
            let theirs = p.cholesky().unwrap().unpack();
            for (x, y) in ours.iter().zip(theirs.iter()) {
                assert_eq!(x.to_bits(), y.to_bits(), "{p}");
            }
        }
        let mut bad = Mat6::identity();
        for v in [0.0, -0.0, -1.0, f64::NAN] {
            bad[(3, 3)] = v;
            assert!(chol6(&bad).is_none() && bad.cholesky().is_none(), "{v}");
        }
        let mut rank1 = Mat6::zeros();
        rank1[(0, 0)] = 1.0;
        assert!(chol6(&rank1).is_none() && rank1.cholesky().is_none());
    }

    /// The closed-form 3 x 3 Cholesky factor solves like nalgebra's and refuses the same
    /// matrices (zero, negative or NaN pivots).
    #[test]
    fn chol3_solves_and_refuses_like_nalgebra() {
        let a = Mat3::new(4.0, 1.0, -0.5, 0.3, 2.0, 0.2, 1.1, -0.7, 3.0);
        let s = a * a.transpose() + Mat3::identity() * 1e-3;
        let c = chol3(&s).unwrap();
        let reference = s.cholesky().unwrap();
        let b = Vec3::new(0.3, -2.0, 7.5);
        let x = c.solve(&b);
        let xr = reference.solve(&b);
        assert!((x - xr).norm() <= 1e-14 * xr.norm());
        assert!((s * x - b).norm() <= 1e-12 * b.norm());
        let nis = c.forward(&b).norm_squared();
        assert!((nis - b.dot(&xr)).abs() <= 1e-14 * nis);
        for bad in [
            Mat3::zeros(),
            Mat3::from_diagonal(&Vec3::new(1.0, -1.0, 1.0)),
            Mat3::from_diagonal(&Vec3::new(1.0, 1.0, f64::NAN)),
            Mat3::new(1.0, 1.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 1.0),
        ] {
            assert!(chol3(&bad).is_none(), "{bad}");
            assert!(bad.cholesky().is_none(), "{bad}");
        }
    }
}
