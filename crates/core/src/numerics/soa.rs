//! Particles transposed between rows (`State`, `[f64; 6]`: the storage of a particle set)
//! and structure-of-arrays blocks `[[f64; BLOCK]; 6]` (component `k` of particle `i` in
//! `[k][i]`), the form whose fixed-length component loops the compiler vectorises across
//! particles. Four particles at a time by [`simd::rows_to_lanes`]' and
//! [`simd::lanes_to_rows`]' shuffles with pulp's v3 token, the rest element by element:
//! moves of bits, the same on every path.

use super::simd;
use crate::types::State;

/// Particles per block: the particle filters' loops transpose [`BLOCK`] particles at a
/// time into `[[f64; BLOCK]; 6]` arrays on the stack.
pub(crate) const BLOCK: usize = 16;

/// Components per particle.
const N: usize = 6;

/// [`rows_to_block_in`], on the v3 path in a function of its own ([`simd::v3_apart`]):
/// inlined into the transition's loop, the shuffles cost the normals' lanes their
/// registers.
#[inline(always)]
pub(crate) fn rows_to_block(v3: Option<simd::V3>, xs: &[State], a: &mut [[f64; BLOCK]; N]) {
    match v3 {
        #[cfg(target_arch = "x86_64")]
        Some(s) => simd::v3_apart(s, || rows_to_block_in(v3, xs, a)),
        _ => rows_to_block_in(v3, xs, a),
    }
}

/// [`gather_to_block_in`], on the v3 path in a function of its own, as [`rows_to_block`].
#[inline(always)]
pub(crate) fn gather_to_block(
    v3: Option<simd::V3>,
    xs: &[State],
    ib: &[usize],
    a: &mut [[f64; BLOCK]; N],
) {
    match v3 {
        #[cfg(target_arch = "x86_64")]
        Some(s) => simd::v3_apart(s, || gather_to_block_in(v3, xs, ib, a)),
        _ => gather_to_block_in(v3, xs, ib, a),
    }
}

/// `a[k][i] = row(&keys[i])[k]`: the particles named by `keys` (at most [`BLOCK`]) into a
/// transposed block, four at a time by [`simd::rows_to_lanes`]' shuffles (with the token), the
/// rest element by element. The lanes from `keys.len()` on keep their values.
#[inline(always)]
fn keys_to_block_in<'a, T>(
    v3: Option<simd::V3>,
    keys: &'a [T],
    row: impl Fn(&'a T) -> &'a State,
    a: &mut [[f64; BLOCK]; N],
) {
    let mut quads = keys.chunks_exact(4);
    for (q, c) in (&mut quads).enumerate() {
        if let [k0, k1, k2, k3] = c {
            let rows = [k0, k1, k2, k3].map(|k| &row(k).data.0[0]);
            simd::rows_to_lanes(v3, rows, a, 4 * q);
        }
    }
    let done = keys.len() - quads.remainder().len();
    for (i, key) in quads.remainder().iter().enumerate() {
        let xi = row(key);
        for (k, ak) in a.iter_mut().enumerate() {
            ak[done + i] = xi[k];
        }
    }
}

/// `a[k][i] = xs[i][k]`: the particles `xs` (at most [`BLOCK`]) into a transposed block
/// ([`keys_to_block_in`]).
#[inline(always)]
pub(crate) fn rows_to_block_in(v3: Option<simd::V3>, xs: &[State], a: &mut [[f64; BLOCK]; N]) {
    keys_to_block_in(v3, xs, |p| p, a);
}

/// `a[k][i] = xs[ib[i]][k]`: the particles `ib` (at most [`BLOCK`] indices into `xs`)
/// gathered into a transposed block ([`keys_to_block_in`]).
#[inline(always)]
pub(crate) fn gather_to_block_in(
    v3: Option<simd::V3>,
    xs: &[State],
    ib: &[usize],
    a: &mut [[f64; BLOCK]; N],
) {
    keys_to_block_in(v3, ib, |&j| &xs[j], a);
}

/// `os[i][k] = a[k][i]`: a transposed block out into the particles `os` (at most
/// [`BLOCK`]), four at a time by [`simd::lanes_to_rows`]' shuffles (with the token), the rest
/// element by element. Inlined: the shuffles pay off only inside the caller's loop (behind
/// a call of their own they cost more than they save).
#[inline(always)]
pub(crate) fn block_to_rows(v3: Option<simd::V3>, a: &[[f64; BLOCK]; N], os: &mut [State]) {
    let done = os.len() - os.len() % 4;
    let mut quads = os.chunks_exact_mut(4);
    for (q, c) in (&mut quads).enumerate() {
        if let [p0, p1, p2, p3] = c {
            let rows = [
                &mut p0.data.0[0],
                &mut p1.data.0[0],
                &mut p2.data.0[0],
                &mut p3.data.0[0],
            ];
            simd::lanes_to_rows(v3, a, 4 * q, rows);
        }
    }
    for (i, o) in quads.into_remainder().iter_mut().enumerate() {
        *o = State::from_fn(|k, _| a[k][done + i]);
    }
}

/// `x` transposed into `soa` (one block per [`BLOCK`] particles, component-major; at least
/// `x.len()` particles; the last block's padding lanes are left as they were), block by
/// block by [`rows_to_block_in`] (the transition's shuffles with the v3 token).
pub(crate) fn transpose_into(x: &[State], soa: &mut [[[f64; BLOCK]; N]]) {
    simd::dispatch_v3(
        #[inline(always)]
        |v3| {
            for (xb, sb) in x.chunks(BLOCK).zip(soa.iter_mut()) {
                rows_to_block_in(v3, xb, sb);
            }
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The block transposes with pulp's v3 token (shuffles) and without (element copies)
    /// move the same bits, for full and short blocks, contiguous and through indices; and
    /// they are the transposes: `a[k][i] = x[i][k]`, `os[i][k] = a[k][i]`.
    #[test]
    fn v3_and_baseline_block_transposes_agree() {
        // distinct bit patterns, signed zeros, a NaN with a payload, infinities
        let x: Vec<State> = (0..40)
            .map(|i| {
                State::from_fn(|k, _| match (i + k) % 9 {
                    0 => -0.0,
                    1 => f64::from_bits(0x7ff8_0000_dead_beef),
                    2 => f64::NEG_INFINITY,
                    _ => (i * 6 + k) as f64 * 1.25e-3 - 0.1,
                })
            })
            .collect();
        let idx: Vec<usize> = (0..BLOCK).map(|j| (7 * j + 3) % x.len()).collect();
        let bits = |a: &[[f64; BLOCK]; N]| a.map(|r| r.map(f64::to_bits));
        let tokens = simd::dispatch_v3(|t| t);
        for n in [BLOCK, 13, 12, 4, 3, 1] {
            let fill = f64::from_bits(0x1234_5678);
            let (mut a, mut b) = ([[fill; BLOCK]; N], [[fill; BLOCK]; N]);
            rows_to_block(tokens, &x[5..5 + n], &mut a);
            rows_to_block(None, &x[5..5 + n], &mut b);
            assert_eq!(bits(&a), bits(&b));
            for (i, xi) in x[5..5 + n].iter().enumerate() {
                assert!((0..N).all(|k| a[k][i].to_bits() == xi[k].to_bits()));
            }
            assert!(a
                .iter()
                .all(|r| r[n..].iter().all(|v| v.to_bits() == fill.to_bits())));
            gather_to_block(tokens, &x, &idx[..n], &mut a);
            gather_to_block(None, &x, &idx[..n], &mut b);
            assert_eq!(bits(&a), bits(&b));
            for (i, &j) in idx[..n].iter().enumerate() {
                assert!((0..N).all(|k| a[k][i].to_bits() == x[j][k].to_bits()));
            }
            let (mut o1, mut o2) = (vec![State::zeros(); n], vec![State::zeros(); n]);
            block_to_rows(tokens, &a, &mut o1);
            block_to_rows(None, &a, &mut o2);
            for (i, (p, q)) in o1.iter().zip(&o2).enumerate() {
                assert!((0..N).all(|k| p[k].to_bits() == q[k].to_bits()));
                assert!((0..N).all(|k| p[k].to_bits() == x[idx[i]][k].to_bits()));
            }
        }
    }
}
