//! The literal filters' weighted moments before resampling, formed in the normalisation's
//! pass over the particles: the exponentials `w_i = exp(l_i - max)` with the weighted
//! moments about a reference point, particle by particle ([`exp_moments`]) or from the
//! particles' transposed copy in lanes ([`exp_moments_soa`]).

use super::N;
use crate::numerics::lane_sum;
use crate::numerics::moments::{LaneSums, Moments, PointSums};
use crate::numerics::simd;
use crate::numerics::soa::BLOCK;
use crate::numerics::vexp::exp_nonpos;
use crate::types::State;

/// The normalisation's exponentials `w_i = exp(l_i - max)` (0 for a NaN `l_i`), vectorised
/// across particles ([`exp_nonpos`]); inlined into its caller's [`simd::dispatch`].
#[inline(always)]
fn exp_weights(w: &mut [f64], logw: &[f64], max: f64) {
    for (e, &l) in w.iter_mut().zip(logw) {
        *e = if l.is_nan() { 0.0 } else { exp_nonpos(l - max) };
    }
}

/// The normalisation's exponentials and the weighted moments in one pass over a run of
/// particles: `w_i = exp(l_i - max)` (0 for a NaN `l_i`: the bits of
/// [`super::resample::normalize_log_weights`] before its division), their sum in sixteen lanes
/// ([`lane_sum`]: its bits too) and the [`Moments`] about `reference` with the weights `w_i`
/// ([`PointSums`]: each sum, the moments' weight sum included, one chain in particle order,
/// at rounding level from the lanes'). The exponentials
/// run a block of [`BLOCK`] at a time (vectorised across particles), the moments particle by
/// particle. `max` is the largest `l_i` (finite). Run through [`simd::dispatch`].
pub(super) fn exp_moments(
    reference: &State,
    x: &[State],
    logw: &[f64],
    max: f64,
    w: &mut [f64],
) -> (f64, Moments) {
    simd::dispatch(
        #[inline(always)]
        || exp_moments_inline(reference, x, logw, max, w),
    )
}

/// [`exp_moments`]' body, inlined into its [`simd::dispatch`].
#[inline(always)]
fn exp_moments_inline(
    reference: &State,
    x: &[State],
    logw: &[f64],
    max: f64,
    w: &mut [f64],
) -> (f64, Moments) {
    exp_weights(w, logw, max);
    let rc: [f64; N] = core::array::from_fn(|k| reference[k]);
    let mut acc = PointSums::new();
    for (xi, &wi) in x.iter().zip(w.iter()) {
        acc.add(xi, &rc, wi);
    }
    (lane_sum(w), acc.finish(reference))
}

/// [`exp_moments`] with the particles read from their transposed copy `soa` (one block per
/// [`BLOCK`] particles, at least `w.len()` particles; the filter's `soa` when current):
/// the same weights and weight sum, bit for bit; the moments from [`LaneSums`] (four lanes
/// per sum instead of one chain: at rounding level from [`exp_moments`]'). A short last
/// block is copied with its padding set to `reference` (offset zero) and weight zero.
pub(super) fn exp_moments_soa(
    reference: &State,
    soa: &[[[f64; BLOCK]; N]],
    logw: &[f64],
    max: f64,
    w: &mut [f64],
) -> (f64, Moments) {
    simd::dispatch(
        #[inline(always)]
        || exp_moments_soa_inline(reference, soa, logw, max, w),
    )
}

/// [`exp_moments_soa`]'s body, inlined into its [`simd::dispatch`].
#[inline(always)]
fn exp_moments_soa_inline(
    reference: &State,
    soa: &[[[f64; BLOCK]; N]],
    logw: &[f64],
    max: f64,
    w: &mut [f64],
) -> (f64, Moments) {
    exp_weights(w, logw, max);
    // in lanes: the bits of the normalisation's sum
    let sum = lane_sum(w);
    let acc = LaneSums::of_soa::<true>(reference, soa, w.len(), w);
    (sum, acc.finish(reference, sum))
}
