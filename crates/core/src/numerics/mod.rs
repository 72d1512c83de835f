//! Numerical helpers shared by the layers above (estimators, H-infinity design, navigator,
//! C ABI): number formatting for error messages, the iteration-capped eigen and singular
//! value decompositions every caller uses instead of nalgebra's uncapped ones ([`eigen`]),
//! the thread setting of the BLAS linked for the H-infinity design, and [`state`] (the
//! explicit bytes of saved state) and [`vexp`] (a branch-free `e^x` for `x <= 0` that
//! vectorises, for the particle weights) and [`ziggurat`] (exact standard normals in batches,
//! for the particle filters), [`simd`] (run-time dispatch of hot loops to AVX2, same bits),
//! [`lanes`] (fixed-length array arithmetic: [`lane_sum`], sums in sixteen lanes, for the
//! particle weights), `cholesky` (small Cholesky factors on the stack), `soa` (particles
//! transposed to structure-of-arrays blocks and back), `moments` (weighted first and
//! second moments of 6-vectors, in lanes) and `symmetrize`. Lives below its users;
//! imports nothing from them.

#[cfg(feature = "hinf")]
#[allow(unsafe_code)]
pub mod blas;
pub(crate) mod cholesky;
pub mod eigen;
pub mod lanes;
#[cfg(feature = "std")]
pub(crate) mod moments;
pub mod simd;
#[cfg(feature = "std")]
pub(crate) mod soa;
pub mod state;
#[cfg(feature = "std")]
pub mod vexp;
#[cfg(feature = "std")]
pub mod vlog;
#[cfg(feature = "std")]
pub mod ziggurat;

pub use lanes::{lane_sum, lane_sum_sq};

use crate::types::Mat6;

/// Whether every value is finite (neither NaN nor infinite). Branch-free: the per-value
/// tests are and-ed without short-circuit, so the loop vectorises (a 6x6 covariance in a
/// few vector instructions instead of 36 compare-and-branch rounds). The filters check
/// their estimate and covariance after every step, so a short-circuiting
/// `iter().all(is_finite)` would be a noticeable part of a Kalman step.
#[inline]
pub fn all_finite(v: &[f64]) -> bool {
    v.iter().fold(true, |ok, x| ok & x.is_finite())
}

/// `v` clamped to `[lo, hi]`, as `f64::clamp` computes it, but without its panic (an
/// assertion with formatted floats) for bounds the compiler cannot see ordered: with
/// `lo > hi` this gives `hi` where `v > hi`, else `lo` where `v < lo`; NaN stays NaN.
#[inline]
pub fn clamp(v: f64, lo: f64, hi: f64) -> f64 {
    let mut x = v;
    if x < lo {
        x = lo;
    }
    if x > hi {
        x = hi;
    }
    x
}

/// The inverse of a small square matrix by Gauss-Jordan elimination with partial
/// pivoting; `None` when a pivot is zero or the result is not finite. nalgebra's
/// `try_inverse` (an LU for sizes above 4) keeps index assertions the optimiser cannot
/// remove, panic paths the flight library must not have; here every index comes from a
/// loop bounded by `N`.
pub fn try_inverse<const N: usize>(
    m: &nalgebra::SMatrix<f64, N, N>,
) -> Option<nalgebra::SMatrix<f64, N, N>> {
    let mut a = [[0.0; N]; N];
    let mut inv = [[0.0; N]; N];
    for i in 0..N {
        for j in 0..N {
            a[i][j] = m[(i, j)];
        }
        inv[i][i] = 1.0;
    }
    for k in 0..N {
        // bring the largest remaining entry of column k to row k (swapping in every larger
        // one met keeps each index loop-bounded)
        for i in k + 1..N {
            if a[i][k].abs() > a[k][k].abs() {
                for j in 0..N {
                    let t = a[k][j];
                    a[k][j] = a[i][j];
                    a[i][j] = t;
                    let t = inv[k][j];
                    inv[k][j] = inv[i][j];
                    inv[i][j] = t;
                }
            }
        }
        let pivot = a[k][k];
        if pivot == 0.0 || !pivot.is_finite() {
            return None;
        }
        for j in 0..N {
            a[k][j] /= pivot;
            inv[k][j] /= pivot;
        }
        for i in 0..N {
            if i != k {
                let f = a[i][k];
                for j in 0..N {
                    a[i][j] -= f * a[k][j];
                    inv[i][j] -= f * inv[k][j];
                }
            }
        }
    }
    let out = nalgebra::SMatrix::<f64, N, N>::from_fn(|i, j| inv[i][j]);
    all_finite(out.as_slice()).then_some(out)
}

/// An owned copy of a fixed-size matrix or view, element by element: nalgebra's
/// `into_owned` of a view copies through an iterator whose length it asserts at run time,
/// a panic path the optimiser keeps (the flight library has none).
pub trait Owned<const R: usize, const C: usize> {
    /// The copy.
    fn owned(&self) -> nalgebra::SMatrix<f64, R, C>;
}

impl<const R: usize, const C: usize, S> Owned<R, C>
    for nalgebra::Matrix<f64, nalgebra::Const<R>, nalgebra::Const<C>, S>
where
    S: nalgebra::RawStorage<f64, nalgebra::Const<R>, nalgebra::Const<C>>,
{
    #[inline]
    fn owned(&self) -> nalgebra::SMatrix<f64, R, C> {
        nalgebra::SMatrix::from_fn(|i, j| self[(i, j)])
    }
}

/// Symmetrise a covariance: `(P + P^T) / 2`.
pub(crate) fn symmetrize(p: &Mat6) -> Mat6 {
    (p + p.transpose()) * 0.5
}

/// A number for an error message: plain when readable, scientific when tiny or huge.
#[cfg(feature = "std")]
pub fn num(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 || !v.is_finite() || (1e-4..1e7).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// A number for an error message: without `std` (no float formatting) `"?"`.
#[cfg(not(feature = "std"))]
pub fn num(_: f64) -> &'static str {
    "?"
}

#[cfg(test)]
mod tests {
    use super::{all_finite, num, try_inverse};
    use crate::types::Mat6;

    #[test]
    fn all_finite_finds_every_non_finite_value() {
        assert!(all_finite(&[]));
        assert!(all_finite(&[
            0.0,
            -0.0,
            f64::MAX,
            f64::MIN_POSITIVE,
            -1e-300
        ]));
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            for at in 0..37 {
                let mut v = [1.0; 37];
                v[at] = bad;
                assert!(!all_finite(&v), "{bad} at {at}");
            }
        }
    }

    #[test]
    fn formats_readable_and_extreme_numbers() {
        assert_eq!(num(0.5), "0.5");
        assert_eq!(num(0.0), "0");
        assert_eq!(num(1e-9), "1e-9");
        assert_eq!(num(2.5e12), "2.5e12");
        assert_eq!(num(f64::NAN), "NaN");
    }

    #[test]
    fn inverse_matches_nalgebra_and_refuses_singular_matrices() {
        // deterministic, well-conditioned matrices with zeros on the diagonal (pivoting needed)
        let mut seed = 12345u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for _ in 0..200 {
            let mut m = Mat6::from_fn(|_, _| next());
            m.fill_diagonal(0.0);
            let ours = try_inverse(&m).unwrap();
            let theirs = m.try_inverse().unwrap();
            let scale = theirs.amax().max(1.0);
            assert!(
                (ours - theirs).amax() <= 1e-10 * scale,
                "{ours} vs {theirs}"
            );
            assert!((m * ours - Mat6::identity()).amax() < 1e-10);
        }
        let mut singular = Mat6::from_fn(|i, j| (i + j) as f64);
        assert!(try_inverse(&singular).is_none());
        singular = Mat6::identity();
        singular[(3, 3)] = 0.0;
        assert!(try_inverse(&singular).is_none());
        assert!(try_inverse(&(Mat6::identity() * f64::NAN)).is_none());
        assert!(try_inverse(&(Mat6::identity() * 1e-310)).is_none());
    }
}
