//! Bounded versions of nalgebra's iterative decompositions.
//!
//! nalgebra's convenience calls (`SymmetricEigen::new`, `symmetric_eigenvalues`,
//! `complex_eigenvalues`, `singular_values`) iterate without a cap (`max_niter = 0`) and
//! `unwrap` the result: a NaN or an infinity in the input can make them loop forever or
//! panic (the symmetric solver's 2x2 step unwraps an eigenvalue computation that fails on
//! NaN). Every call in relnav goes through these wrappers instead: the input is checked to
//! be finite first, the iteration count is capped at [`MAX_SWEEPS_PER_DIM`] times the
//! dimension, and a failure is a `None` for the caller to turn into an error.
//!
//! The results are checked too: nalgebra rescales the input by its largest entry, and on a
//! finite matrix of extreme dynamic range (a covariance with a 7.5e159 m^2 variance beside
//! one of 1e-6, found by the `capi` fuzz target) the tridiagonalisation underflows and the
//! decomposition comes back with NaN and infinite eigenvalues and vectors. A result with a
//! non-finite number is a `None` as well, never a silently wrong square root.

#[cfg(not(feature = "std"))]
use crate::math::Float;
use nalgebra::allocator::Allocator;
#[cfg(feature = "std")]
use nalgebra::{Complex, DMatrix, DVector, Schur, SVD};
use nalgebra::{DefaultAllocator, Dim, DimDiff, DimSub, OMatrix, OVector, SymmetricEigen, U1};

use super::symmetrize;
use crate::types::Mat6;

/// Iteration cap per dimension. The implicit QR sweeps converge in two to three sweeps
/// per eigenvalue on finite input; 64 per dimension only ever stops a non-converging case.
pub const MAX_SWEEPS_PER_DIM: usize = 64;

fn cap(dim: usize) -> usize {
    MAX_SWEEPS_PER_DIM * dim.max(1)
}

/// Eigendecomposition of a symmetric matrix (lower triangle read), `None` for a
/// non-finite input or no convergence within the cap.
pub fn symmetric_eigen<D>(m: OMatrix<f64, D, D>) -> Option<SymmetricEigen<f64, D>>
where
    D: Dim + DimSub<U1>,
    DefaultAllocator: Allocator<D, D> + Allocator<D> + Allocator<DimDiff<D, U1>>,
{
    if !m.iter().all(|v| v.is_finite()) {
        return None;
    }
    let n = m.nrows();
    SymmetricEigen::try_new(m, f64::EPSILON, cap(n)).filter(|e| {
        e.eigenvalues.iter().all(|v| v.is_finite()) && e.eigenvectors.iter().all(|v| v.is_finite())
    })
}

/// Eigenvalues of a symmetric matrix (see [`symmetric_eigen`]).
pub fn symmetric_eigenvalues<D>(m: OMatrix<f64, D, D>) -> Option<OVector<f64, D>>
where
    D: Dim + DimSub<U1>,
    DefaultAllocator: Allocator<D, D> + Allocator<D> + Allocator<DimDiff<D, U1>>,
{
    symmetric_eigen(m).map(|e| e.eigenvalues)
}

#[cfg(feature = "std")]
/// Complex eigenvalues of a real square matrix through its real Schur form, `None` for a
/// non-finite input or no convergence within the cap.
pub fn complex_eigenvalues(m: &DMatrix<f64>) -> Option<DVector<Complex<f64>>> {
    if !m.iter().all(|v| v.is_finite()) || !m.is_square() {
        return None;
    }
    Schur::try_new(m.clone(), f64::EPSILON, cap(m.nrows()))
        .map(|s| s.complex_eigenvalues())
        .filter(|ev| ev.iter().all(|z| z.re.is_finite() && z.im.is_finite()))
}

#[cfg(feature = "std")]
/// Singular values of a complex matrix (descending), `None` for a non-finite input or no
/// convergence within the cap.
pub fn singular_values(m: &DMatrix<Complex<f64>>) -> Option<DVector<f64>> {
    if !m.iter().all(|v| v.re.is_finite() && v.im.is_finite()) {
        return None;
    }
    let n = m.nrows().max(m.ncols());
    SVD::try_new(m.clone(), false, false, f64::EPSILON, cap(n))
        .map(|s| s.singular_values)
        .filter(|sv| sv.iter().all(|v| v.is_finite()))
}

/// Symmetric square root of a PSD matrix (negative rounding eigenvalues clipped); `None`
/// when `q` is not finite or the (iteration-capped) eigensolver does not converge.
pub(crate) fn psd_sqrt(q: &Mat6) -> Option<Mat6> {
    let e = symmetric_eigen(symmetrize(q))?;
    let d = e.eigenvalues.map(|v| v.max(0.0).sqrt());
    Some(e.eigenvectors * Mat6::from_diagonal(&d) * e.eigenvectors.transpose())
}

/// [`psd_sqrt`], or the square roots of the diagonal when it has none (a matrix set from
/// outside, not finite or without convergence).
pub(crate) fn psd_sqrt_or_diagonal(q: &Mat6) -> Mat6 {
    psd_sqrt(q).unwrap_or_else(|| Mat6::from_diagonal(&q.diagonal().map(|v| v.max(0.0).sqrt())))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::types::Mat6;

    #[test]
    fn finite_inputs_decompose_and_bad_ones_are_refused() {
        let m = Mat6::from_fn(|i, j| 1.0 / (1.0 + i as f64 + j as f64)); // Hilbert
        let e = symmetric_eigen(m).expect("Hilbert matrix decomposes");
        let back =
            e.eigenvectors * Mat6::from_diagonal(&e.eigenvalues) * e.eigenvectors.transpose();
        assert!((back - m).norm() < 1e-14);
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let mut b = m;
            b[(2, 1)] = bad;
            b[(1, 2)] = bad;
            assert!(symmetric_eigen(b).is_none());
            let d = DMatrix::from_fn(6, 6, |i, j| b[(i, j)]);
            assert!(complex_eigenvalues(&d).is_none());
            assert!(singular_values(&d.map(|v| Complex::new(v, 0.0))).is_none());
        }
        // a rotation by 0.3 rad: eigenvalues exp(+-0.3 i), singular values 1
        let (s, c) = 0.3f64.sin_cos();
        let r = DMatrix::from_row_slice(2, 2, &[c, -s, s, c]);
        let ev = complex_eigenvalues(&r).expect("rotation");
        assert!(ev
            .iter()
            .all(|z| (z.norm() - 1.0).abs() < 1e-15 && (z.im.abs() - s).abs() < 1e-15));
        let sv = singular_values(&r.map(|v| Complex::new(v, 0.0))).expect("rotation");
        assert!(sv.iter().all(|v| (v - 1.0).abs() < 1e-15));
        // huge but finite entries are fine (nalgebra rescales by the largest entry)
        let big = m * 1e300;
        assert!(symmetric_eigenvalues(big).is_some());
    }

    /// A covariance found by the `capi` fuzz target: finite, but a dynamic range
    /// of 1e166 makes nalgebra's decomposition return NaN and infinities. Refused, not
    /// returned.
    #[test]
    fn extreme_dynamic_range_is_refused_not_returned_as_nan() {
        #[rustfmt::skip]
        let p = Mat6::from_row_slice(&[
            7.525296354261714e159, -1.6614601122210803e-6, 0.0, 1.0056512143614154, -0.0008775427321789831, 0.0,
            -1.6614601122210803e-6, 2535.083890979902, 0.0, 0.0008725573795232369, 0.999938457741548, 0.0,
            0.0, 0.0, 2500.99859901582, 0.0, 0.0, 0.9980347160360834,
            1.0056512143614154, 0.0008725573795232369, 0.0, 1.000003298337343, -2.0047361100378444e-9, 0.0,
            -0.0008775427321789831, 0.999938457741548, 0.0, -2.0047361100378444e-9, 1.000001000940653, 0.0,
            0.0, 0.0, 0.9980347160360834, 0.0, 0.0, 1.0000002409382005,
        ]);
        match symmetric_eigen(p) {
            None => {}
            Some(e) => {
                // should nalgebra ever handle it, the answer must at least be finite
                assert!(e
                    .eigenvalues
                    .iter()
                    .chain(e.eigenvectors.iter())
                    .all(|v| v.is_finite()));
            }
        }
    }
}
