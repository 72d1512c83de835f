//! One step of the particle transition `x <- Phi x + Gamma a + w`, `w ~ N(0, Q)`: the
//! particle loop's hot path, in blocks of [`BLOCK`] particles transposed to
//! structure-of-arrays arrays on the stack, with the CW transition's block structure
//! ([`CwBlocks`]: 16 + 4 products instead of 36).

use super::rng::PfRng;
use super::N;
use crate::numerics::simd;
use crate::numerics::soa::{block_to_rows, gather_to_block, rows_to_block, BLOCK};
use crate::numerics::ziggurat::{Lanes, Ziggurat};
use crate::types::{Mat6, State};

/// A transition matrix with the CW structure in the canonical frame: the in-plane states
/// `(x, y, vx, vy)` (indices 0, 1, 3, 4) and the out-of-plane `(z, vz)` (2, 5) do not
/// couple, so `Phi x` takes 16 + 4 products instead of 36 (the particle loop's hot path).
pub(super) struct CwBlocks {
    inp: [[f64; 4]; 4],
    out: [[f64; 2]; 2],
}

impl CwBlocks {
    const IN: [usize; 4] = [0, 1, 3, 4];
    const OUT: [usize; 2] = [2, 5];

    /// `Some` when every coupling entry of `phi` is exactly zero.
    pub(super) fn of(phi: &Mat6) -> Option<Self> {
        let decoupled = Self::IN.iter().all(|&i| {
            Self::OUT
                .iter()
                .all(|&o| phi[(i, o)] == 0.0 && phi[(o, i)] == 0.0)
        });
        decoupled.then(|| Self {
            inp: Self::IN.map(|r| Self::IN.map(|c| phi[(r, c)])),
            out: Self::OUT.map(|r| Self::OUT.map(|c| phi[(r, c)])),
        })
    }

    #[inline(always)]
    pub(super) fn apply(&self, x: &State) -> State {
        let a = [x[0], x[1], x[3], x[4]];
        let b = [x[2], x[5]];
        let dot4 = |row: &[f64; 4]| row[0] * a[0] + row[1] * a[1] + row[2] * a[2] + row[3] * a[3];
        let dot2 = |row: &[f64; 2]| row[0] * b[0] + row[1] * b[1];
        let [p0, p1, p3, p4] = self.inp.each_ref().map(dot4);
        let [p2, p5] = self.out.each_ref().map(dot2);
        State::new(p0, p1, p2, p3, p4, p5)
    }
}

/// One step of the transition `x <- Phi x + Gamma a + w`, `w ~ N(0, Q)`.
pub(super) struct Transition {
    pub(super) blocks: Option<CwBlocks>,
    pub(super) phi: Mat6,
    pub(super) u: State,
    /// the standard deviations of a diagonal `Q` (6 products instead of 36)
    pub(super) diag: Option<State>,
    /// a square root of `Q`
    pub(super) l: Mat6,
}

// the transition draws a block's normals of one component in one batch
const _: () = assert!(BLOCK == Ziggurat::BATCH);

/// A block's states, transition means and new states, transposed (reused block to block).
type SoaBlocks = ([[f64; BLOCK]; N], [[f64; BLOCK]; N], [[f64; BLOCK]; N]);

impl Transition {
    /// Draw the new particles `out[i]` from `x[i]` (and store the transition means in
    /// `xbar` when it is not empty); returns a number that is finite exactly when every
    /// new component is (the sum of `0 * v` over them: NaN once one is not).
    ///
    /// The normals come from four xoshiro256++
    /// lanes ([`Lanes::seed_from`]) derived from `rng` at the start of the call (`rng`
    /// advances by one word per lane, plus the words of the slow paths): the lanes are
    /// transient, so the filter's saved state stays `rng`'s four words and a restored filter
    /// continues identically; the draws are deterministic per seed and, since every
    /// parallel chunk derives its lanes from its own generator, independent of the thread
    /// count.
    ///
    /// Block by block: the block's `6 B` normals are drawn first, component by component
    /// (each component's `B` values in one batch of [`Ziggurat::fill_batch_lanes`]; a short
    /// last block by [`Ziggurat::fill`] from `rng`); then, for
    /// the CW block structure with a diagonal `Q` (paper 000's model), the transition
    /// `x_i <- Phi x_i + Gamma a + sqrt(Q) eps_i` runs on the transposed block, the same
    /// operations in the same order per particle as the scalar form (so the same bits),
    /// four particles per AVX2 instruction through [`crate::numerics::simd::dispatch`].
    ///
    /// With `idx` the input particle `j` is `x[idx[j]]` (`idx` as long as `out`: the
    /// resampling indices not yet applied, gathered by the block transposes instead of a
    /// copy of the cloud); without, `x[j]`.
    ///
    /// With `soa` (one block per [`BLOCK`] particles of `out`) the structure-of-arrays path
    /// (CW blocks, diagonal `Q`) also writes each block's new particles there, transposed
    /// (the lanes past a short last block unspecified), and returns whether it did; with
    /// `soa_in` as well (and no `idx`) it reads its input from `soa` (which then holds `x`,
    /// transposed: the same values) instead of transposing `x`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn run(
        &self,
        x: &[State],
        idx: Option<&[usize]>,
        out: &mut [State],
        xbar: &mut [State],
        soa: Option<&mut [[[f64; BLOCK]; N]]>,
        soa_in: bool,
        rng: &mut PfRng,
    ) -> (f64, bool) {
        simd::dispatch_v3(
            #[inline(always)]
            |v3| self.run_inline(v3, x, idx, out, xbar, soa, soa_in, rng),
        )
    }

    /// [`Transition::run`]'s body, inlined into its [`simd::dispatch_v3`] (`v3`: the token
    /// for the block transposes' shuffles).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn run_inline(
        &self,
        v3: Option<simd::V3>,
        x: &[State],
        idx: Option<&[usize]>,
        out: &mut [State],
        xbar: &mut [State],
        mut soa: Option<&mut [[[f64; BLOCK]; N]]>,
        soa_in: bool,
        rng: &mut PfRng,
    ) -> (f64, bool) {
        let blockwise = self.blocks.is_some() && self.diag.is_some();
        let wrote = blockwise && soa.as_ref().is_some_and(|p| p.len() * BLOCK >= out.len());
        let soa_in = soa_in && wrote && idx.is_none();
        let mut g = rng.clone();
        let zig = Ziggurat::get();
        let mut lanes = Lanes::seed_from(&mut g);
        let mut bad = 0.0;
        let mut eps = [[0.0; BLOCK]; N];
        let mut scratch = ([[0.0; BLOCK]; N], [[0.0; BLOCK]; N], [[0.0; BLOCK]; N]);
        for (b, os) in out.chunks_mut(BLOCK).enumerate() {
            let n = os.len();
            let base = b * BLOCK;
            for e in eps.iter_mut() {
                match e.get_mut(..n) {
                    Some(e) if n < BLOCK => zig.fill(&mut g, e),
                    _ => zig.fill_batch_lanes(&mut lanes, &mut g, e),
                }
            }
            let xb_out = xbar.get_mut(base..(base + n));
            // the block's input: its own particles, or the whole set and its indices
            let (xs, ib) = match idx {
                Some(ix) => (x, Some(&ix[base..base + n])),
                None => (&x[base..base + n], None),
            };
            match (&self.blocks, &self.diag) {
                (Some(cw), Some(d)) => {
                    let sb = soa.as_deref_mut().and_then(|p| p.get_mut(b));
                    let io = sb.map(|sb| (sb, soa_in));
                    bad += self.block_soa(v3, cw, d, xs, ib, os, xb_out, io, &eps, &mut scratch);
                }
                _ => {
                    let mut xb_out = xb_out;
                    for (i, xn) in os.iter_mut().enumerate() {
                        let xi = &xs[ib.map_or(i, |ib| ib[i])];
                        let xb = match &self.blocks {
                            Some(cw) => cw.apply(xi) + self.u,
                            None => self.phi * *xi + self.u,
                        };
                        if let Some(slot) = xb_out.as_mut().and_then(|s| s.get_mut(i)) {
                            *slot = xb;
                        }
                        let e = State::from_fn(|k, _| eps[k][i]);
                        *xn = match &self.diag {
                            Some(d) => xb + e.component_mul(d),
                            None => xb + self.l * e,
                        };
                        bad += xn.iter().fold(0.0, |a, v| a + v * 0.0);
                    }
                }
            }
        }
        *rng = g;
        (bad, wrote)
    }

    /// One block of [`Transition::run`] in structure-of-arrays form (CW blocks, diagonal
    /// `Q`): `xb = Phi x + u` with the 16 + 4 products of [`CwBlocks::apply`] in its order,
    /// `x_new = xb + d * eps`.
    #[inline(always)]
    #[allow(clippy::too_many_arguments, clippy::needless_range_loop)]
    fn block_soa(
        &self,
        v3: Option<simd::V3>,
        cw: &CwBlocks,
        d: &State,
        xs: &[State],
        ib: Option<&[usize]>,
        os: &mut [State],
        xb_out: Option<&mut [State]>,
        soa: Option<(&mut [[f64; BLOCK]; N], bool)>,
        eps: &[[f64; BLOCK]; N],
        scratch: &mut SoaBlocks,
    ) -> f64 {
        let (soa, soa_in) = match soa {
            Some((sb, i)) => (Some(sb), i),
            None => (None, false),
        };
        let (a, xb, xn_tmp) = (&mut scratch.0, &mut scratch.1, &mut scratch.2);
        match ib {
            // the block as the last step left it transposed: read in place below
            None if soa_in && soa.is_some() => {}
            None => rows_to_block(v3, xs, a),
            // gathered through the pending resampling's indices
            Some(ib) => gather_to_block(v3, xs, ib, a),
        }
        // (separate functions over distinct references: no aliasing for the vectoriser)
        match soa.as_deref() {
            Some(sb) if soa_in && ib.is_none() => self.cw_means(cw, sb, xb),
            _ => self.cw_means(cw, a, xb),
        }
        if let Some(xbo) = xb_out {
            block_to_rows(v3, xb, xbo);
        }
        // the new block straight into `soa` when given (its input was read)
        let bad = match soa {
            Some(sb) => Self::add_noise(v3, d, xb, eps, sb, os),
            None => Self::add_noise(v3, d, xb, eps, xn_tmp, os),
        };
        // only the block's own particles count (the padding holds stale values)
        bad.iter().take(os.len()).sum()
    }

    /// The transition means `xb = Phi a + u` of a transposed block `a` with the 16 + 4
    /// products of [`CwBlocks::apply`] in its order.
    #[inline(always)]
    fn cw_means(&self, cw: &CwBlocks, a: &[[f64; BLOCK]; N], xb: &mut [[f64; BLOCK]; N]) {
        let (p, q) = (&cw.inp, &cw.out);
        let u = &self.u;
        // row by row, the row's coefficients held in registers across the block's lanes
        // (lanes inside: each row's five broadcasts once per block instead of once per
        // vector); per particle the same operations in the same order
        let [i0, i1, i3, i4] = CwBlocks::IN;
        for (r, row) in CwBlocks::IN.iter().zip(p) {
            let (c, ur) = (*row, u[*r]);
            for i in 0..BLOCK {
                xb[*r][i] =
                    c[0] * a[i0][i] + c[1] * a[i1][i] + c[2] * a[i3][i] + c[3] * a[i4][i] + ur;
            }
        }
        let [o2, o5] = CwBlocks::OUT;
        for (r, row) in CwBlocks::OUT.iter().zip(q) {
            let (c, ur) = (*row, u[*r]);
            for i in 0..BLOCK {
                xb[*r][i] = c[0] * a[o2][i] + c[1] * a[o5][i] + ur;
            }
        }
    }

    /// `xn = xb + d * eps` lane by lane, also into `os` (one particle per lane); each
    /// lane's `sum_k 0 * xn_k` (NaN once one is not finite).
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // index loops over fixed lanes: they vectorise
    fn add_noise(
        v3: Option<simd::V3>,
        d: &State,
        xb: &[[f64; BLOCK]; N],
        eps: &[[f64; BLOCK]; N],
        xn: &mut [[f64; BLOCK]; N],
        os: &mut [State],
    ) -> [f64; BLOCK] {
        let mut bad = [0.0; BLOCK];
        for k in 0..N {
            for i in 0..BLOCK {
                xn[k][i] = xb[k][i] + eps[k][i] * d[k];
                bad[i] += xn[k][i] * 0.0;
            }
        }
        block_to_rows(v3, xn, os);
        bad
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::{CwModel, Discretization};
    use crate::estimators::pf::tests::test_cloud;
    use crate::numerics::cholesky::chol;
    use crate::types::{Mat3, Vec3};
    use rand::SeedableRng;

    /// The block product equals `Phi x` for the exact CW transition, and a coupled matrix
    /// (Euler's is not coupled either; a rotated one is) falls back to the full product.
    #[test]
    fn cw_blocks_equal_the_full_product() {
        let m = CwModel::new(2.0 * core::f64::consts::PI / 5400.0);
        for dt in [0.1, 1.0, 600.0] {
            for disc in [Discretization::Exact, Discretization::Euler] {
                let phi = m.discretize(dt, &Mat3::zeros(), disc).phi;
                let b = CwBlocks::of(&phi).expect("CW transition is block-structured");
                for k in 0..20 {
                    let x = State::from_fn(|i, _| ((i * 7 + k * 3) as f64).sin() * 300.0);
                    let d = b.apply(&x) - phi * x;
                    assert!(d.abs().max() <= 1e-12 * (phi * x).abs().max(), "{d:?}");
                }
            }
        }
        let mut coupled = Mat6::identity();
        coupled[(0, 2)] = 1e-3;
        assert!(CwBlocks::of(&coupled).is_none());
    }

    /// The transition gathering its input through resampling indices (the literal SIR's
    /// index-only resampling) equals the transition of the resampled cloud bit for bit,
    /// with the same draws, on the dispatched and the baseline path.
    #[test]
    fn gathered_transition_equals_the_resampled_cloud() {
        use crate::numerics::simd::with_baseline;
        let m = CwModel::new(2.0 * core::f64::consts::PI / 5400.0);
        let mut d = m.discretize(1.0, &Mat3::zeros(), Discretization::Exact);
        d.q += Mat6::from_diagonal(&State::new(0.09, 6.25e-4, 2.5e-3, 1e-6, 1e-6, 1e-6));
        let l = chol(&d.q).expect("pd");
        let x = test_cloud(&Vec3::new(400.0, 500.0, -200.0));
        let n = x.len();
        // ascending with repeats, as the resamplers' output
        let idx: Vec<usize> = (0..n).map(|k| (k / 3) * 2 + k % 2).collect();
        let xr: Vec<State> = idx.iter().map(|&i| x[i]).collect();
        for diag in [true, false] {
            let tr = Transition {
                blocks: CwBlocks::of(&d.phi),
                phi: d.phi,
                u: State::new(1e-3, 0.0, -2e-3, 0.0, 1e-6, 0.0),
                diag: diag.then(|| l.diagonal()),
                l,
            };
            let run = |src: &[State], ix: Option<&[usize]>| {
                let mut rng = PfRng::seed_from_u64(3);
                let (mut xn, mut xb) = (vec![State::zeros(); n], vec![State::zeros(); n]);
                let (bad, _) = tr.run(src, ix, &mut xn, &mut xb, None, false, &mut rng);
                (xn, xb, bad.to_bits(), rng)
            };
            let want = run(&xr, None);
            assert!(run(&x, Some(&idx)) == want, "diag {diag}");
            assert!(with_baseline(|| run(&x, Some(&idx))) == want, "diag {diag}");
        }
    }
}
