//! The move steps' target `ln pi(x) = ln p(z | x) + ln N(x; m-, P-)` on blocks of
//! candidates in structure-of-arrays form.

use super::B;
use crate::estimators::pf::likelihood::ParticleLikelihood;
use crate::types::{Mat6, State};
use core::marker::PhantomData;

/// The move steps' target `ln pi(x) = ln p(z | x) + ln N(x; m-, P-)` on blocks of
/// candidates in structure-of-arrays form (`c[k][lane]`): the likelihood through
/// [`ParticleLikelihood::log_soa`] (the radio's vectorised residuals), the predictive's quadratic form by forward
/// substitution with `L-`'s reciprocal diagonal.
pub(super) struct Target<'a, L, const D: usize> {
    lik: &'a L,
    dim: PhantomData<[(); D]>,
    m: [f64; 6],
    l: [[f64; 6]; 6],
    inv_diag: [f64; 6],
}

impl<'a, const D: usize, Lk: ParticleLikelihood<D>> Target<'a, Lk, D> {
    pub(super) fn new(lik: &'a Lk, m: &State, l: &Mat6) -> Self {
        Self {
            lik,
            dim: PhantomData,
            m: core::array::from_fn(|k| m[k]),
            l: core::array::from_fn(|i| core::array::from_fn(|j| l[(i, j)])),
            inv_diag: core::array::from_fn(|k| 1.0 / l[(k, k)]),
        }
    }

    /// The likelihood alone, `ln pi(x) = ln p(z | x)` (a flat predictive: its quadratic form
    /// is zero): paper 003's acceptance on the likelihood ratio, the literal filters'.
    pub(super) fn likelihood_only(lik: &'a Lk) -> Self {
        Self {
            lik,
            dim: PhantomData,
            m: [0.0; 6],
            l: [[0.0; 6]; 6],
            inv_diag: [0.0; 6],
        }
    }

    /// `ln N(c; m-, P-)` up to a constant, `-|L-^-1 (c - m-)|^2 / 2`, for every lane
    /// (`CENTRE`; without it `-|L-^-1 c|^2 / 2`, the form of a difference of two states).
    // lane-indexed loops over several arrays: the form that vectorises across lanes
    #[allow(clippy::needless_range_loop)]
    #[inline(always)]
    /// `u` is scratch (the whitened offsets; the caller's, so that a block does not zero
    /// it).
    pub(super) fn log_predictive<const L: usize, const CENTRE: bool>(
        &self,
        c: &[[f64; L]; 6],
        u: &mut [[f64; L]; 6],
        out: &mut [f64; L],
    ) {
        for i in 0..6 {
            let mut s = [0.0; L];
            for lane in 0..L {
                s[lane] = if CENTRE {
                    c[i][lane] - self.m[i]
                } else {
                    c[i][lane]
                };
            }
            for j in 0..i {
                let lij = self.l[i][j];
                for lane in 0..L {
                    s[lane] -= lij * u[j][lane];
                }
            }
            for lane in 0..L {
                u[i][lane] = s[lane] * self.inv_diag[i];
            }
        }
        let mut q = [0.0; L];
        for ui in u.iter() {
            for lane in 0..L {
                q[lane] += ui[lane] * ui[lane];
            }
        }
        for (o, &qi) in out.iter_mut().zip(&q) {
            *o = -0.5 * qi;
        }
    }

    /// `ln p(z | c)` into `ll` for the first `n` lanes (the others unspecified): `-inf`
    /// where the measurement is undefined ([`ParticleLikelihood::log_soa`]).
    #[inline(always)]
    pub(super) fn log_likelihood(&self, c: &[[f64; B]; 6], n: usize, ll: &mut [f64; B]) {
        self.lik.log_soa(c, n, ll);
    }
}
