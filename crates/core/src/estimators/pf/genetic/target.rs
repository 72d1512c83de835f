//! The move steps' target `ln pi(x) = ln p(z | x) + ln N(x; m-, P-)` on blocks of
//! candidates in structure-of-arrays form.

use super::B;
use crate::estimators::pf::likelihood::Likelihood;
use crate::sensors::MeasurementModel;
use crate::types::{Mat6, State};

/// The move steps' target `ln pi(x) = ln p(z | x) + ln N(x; m-, P-)` on blocks of
/// candidates in structure-of-arrays form (`c[k][lane]`): the likelihood through
/// [`MeasurementModel::residuals_at`], the predictive's quadratic form by forward
/// substitution with `L-`'s reciprocal diagonal.
pub(super) struct Target<'a, 'b, M> {
    lik: &'a Likelihood<'b, M>,
    m: [f64; 6],
    l: [[f64; 6]; 6],
    inv_diag: [f64; 6],
}

impl<'a, 'b, M: MeasurementModel> Target<'a, 'b, M> {
    pub(super) fn new(lik: &'a Likelihood<'b, M>, m: &State, l: &Mat6) -> Self {
        Self {
            lik,
            m: std::array::from_fn(|k| m[k]),
            l: std::array::from_fn(|i| std::array::from_fn(|j| l[(i, j)])),
            inv_diag: std::array::from_fn(|k| 1.0 / l[(k, k)]),
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
    /// where the measurement is undefined.
    #[inline(always)]
    pub(super) fn log_likelihood(&self, c: &[[f64; B]; 6], n: usize, ll: &mut [f64; B]) {
        let r = [c[0], c[1], c[2]];
        let mut d = [[0.0; B]; 3];
        let mut ok = [false; B];
        let lik = self.lik;
        lik.sensor
            .residuals_at(&lik.z, &lik.trig, &r, n, &mut d, &mut ok);
        if lik.gaussian {
            let w = &lik.neg_half_inv_var;
            for (i, l) in ll.iter_mut().enumerate() {
                let v = w[0] * d[0][i] * d[0][i] + w[1] * d[1][i] * d[1][i];
                let v = v + w[2] * d[2][i] * d[2][i];
                *l = if ok[i] { v } else { f64::NEG_INFINITY };
            }
        } else {
            for (i, l) in ll.iter_mut().enumerate().take(n) {
                *l = if ok[i] {
                    (0..3)
                        .map(|k| lik.noise.log_density(d[k][i], lik.scales[k]))
                        .sum()
                } else {
                    f64::NEG_INFINITY
                };
            }
        }
    }
}
