//! Run-time selection of the instruction set for the hot loops (the particle filters' blocks,
//! the covariance time update, the elliptic model's short step).
//!
//! The library is built for the x86-64 baseline (SSE2: two `f64` per vector instruction, no
//! gathers), so that one binary (and one FMU) runs on every x86-64 machine. [`dispatch`] runs a
//! closure compiled a second time with the x86-64-v3 features (AVX2, FMA, BMI1/2) when the CPU
//! has them, through [`pulp`]'s `Arch::dispatch` (the dispatch layer of faer, already in the
//! dependency tree through Clarabel): the `#[target_feature]` call and its `unsafe` live in
//! pulp, none in this crate. For the features to reach the loop, the loop must be inlined into
//! the closure (write it in the closure, or call `#[inline(always)]` functions from it).
//!
//! **The same bits either way.** Rust never contracts `a * b + c` into a fused multiply-add and
//! LLVM never reassociates floating-point arithmetic, so the v3 code performs the same IEEE
//! operations in the same order as the baseline code, lane by lane, and rounds identically;
//! library calls (`exp`, `ln`, `sin_cos`) are the same functions on both paths. Loops in
//! [`dispatch`] must keep it so: no `f64::mul_add` (it is a libm call on the baseline and one
//! instruction on v3 — the same result, but keep the paths visibly equal) and no
//! order-dependent shortcuts. Tests compare the two paths bit for bit ([`with_baseline`]).
//!
//! **Explicit shuffles.** [`dispatch_v3`] is the second entry point: it runs its closure like
//! [`dispatch`] and hands it pulp's [`V3`] token on the v3 path (`None` on the baseline path),
//! whose intrinsics (`simd.avx._mm256_unpacklo_pd` and the like) are safe methods of the
//! token. The crate uses it only for moves of bits that LLVM leaves scalar: the transposes,
//! four particles at a time, between particles stored as `[f64; 6]` rows and 16-lane
//! structure-of-arrays blocks ([`rows_to_lanes`], [`lanes_to_rows`]; loads and stores through
//! [`pulp::cast`] of `[f64; 2]` and `[f64; 4]` arrays, no gathers: pulp's gathers take raw
//! pointers and are `unsafe`). A shuffle moves values
//! without arithmetic, so both paths give the same bits by construction (tested against the
//! baseline element copies). [`v3_apart`] runs such a loop compiled for v3 in a function of
//! its own, where inlined into a large loop it would cost that loop its registers.
//!
//! **Valgrind.** valgrind 3.19 (Debian 12's, which the benches' instruction counts and the
//! C++ harness's memory checks run under) does not decode the register form of the VEX
//! `vmovq` (`66 0F D6`), which LLVM emits in v3 code to put a number beside a known zero in
//! one vector (an array literal mixing computed values with `0.0`). Dispatched code keeps
//! such zeros out: it writes only the nonzero entries of sparse results, whose zeros the
//! caller sets outside. A slip shows as SIGILL under valgrind (the benches fail).
//!
//! `RELNAV_SIMD=baseline` in the environment (read once per process) keeps every dispatch on
//! the baseline path: for comparing machines, or a CPU whose AVX2 is suspect.

#[cfg(feature = "std")]
use std::cell::Cell;
#[cfg(feature = "std")]
use std::sync::OnceLock;

#[cfg(feature = "std")]
thread_local! {
    /// Set by [`with_baseline`] on this thread.
    static FORCE_BASELINE: Cell<bool> = const { Cell::new(false) };
}

#[cfg(feature = "std")]
/// The instruction set [`dispatch`] uses in this process (CPU detection and
/// `RELNAV_SIMD`, once).
fn arch() -> Option<pulp::Arch> {
    static ARCH: OnceLock<Option<pulp::Arch>> = OnceLock::new();
    *ARCH.get_or_init(|| match std::env::var("RELNAV_SIMD") {
        Ok(v) if v.eq_ignore_ascii_case("baseline") => None,
        _ => Some(pulp::Arch::new()),
    })
}

#[cfg(feature = "std")]
/// The name of the instruction set [`dispatch`] uses on this thread now: `"x86-64-v3"` (AVX2)
/// or `"baseline"` (for logs and the benches' headers).
pub fn level() -> &'static str {
    #[cfg(target_arch = "x86_64")]
    if !FORCE_BASELINE.with(Cell::get) {
        if let Some(pulp::Arch::V3(_)) = arch() {
            return "x86-64-v3";
        }
    }
    "baseline"
}

#[cfg(feature = "std")]
/// Runs `f` compiled for the best instruction set of this CPU (see the module documentation);
/// the result is the same bits as `f()` on the baseline path.
#[inline(always)]
pub fn dispatch<R>(f: impl FnOnce() -> R) -> R {
    match arch() {
        Some(a) if !FORCE_BASELINE.with(Cell::get) => a.dispatch(f),
        _ => f(),
    }
}

/// pulp's x86-64-v3 token: AVX2, FMA, BMI1/2 present ([`dispatch_v3`] hands it out only then).
#[cfg(all(feature = "std", target_arch = "x86_64"))]
pub use pulp::x86::V3;

/// Stands for pulp's x86-64-v3 token off x86-64: never constructed ([`dispatch_v3`] hands
/// out `None`).
#[cfg(not(all(feature = "std", target_arch = "x86_64")))]
#[derive(Clone, Copy, Debug)]
pub enum V3 {}

#[cfg(feature = "std")]
/// Runs `f` like [`dispatch`] (compiled for x86-64-v3 when the CPU has it, unless
/// [`with_baseline`] or `RELNAV_SIMD=baseline` keep the baseline), handing it pulp's [`V3`]
/// token on the v3 path and `None` on the baseline path, for explicit shuffles. Within `f`,
/// `Some(simd)` and `None` must give the same bits (the module documentation).
#[inline(always)]
pub fn dispatch_v3<R>(f: impl FnOnce(Option<V3>) -> R) -> R {
    match arch() {
        #[cfg(target_arch = "x86_64")]
        Some(pulp::Arch::V3(simd)) if !FORCE_BASELINE.with(Cell::get) => simd.vectorize(
            #[inline(always)]
            move || f(Some(simd)),
        ),
        _ => f(None),
    }
}

/// Runs `f` compiled for x86-64-v3 in a function of its own (never inlined into the caller):
/// for a short shuffle loop called from inside a large [`dispatch_v3`]ed loop, whose
/// register allocation it would otherwise disturb. One call (and pulp's inner call) per use.
#[cfg(all(feature = "std", target_arch = "x86_64"))]
#[inline(never)]
pub fn v3_apart<R>(simd: V3, f: impl FnOnce() -> R) -> R {
    simd.vectorize(f)
}

#[cfg(feature = "std")]
/// `lanes[k][at + j] = rows[j][k]` for the four rows `j` and the six components `k`: four
/// particles into lanes `at..at + 4` of a transposed block. With the token, per pair of
/// components `(k, k + 1)` two 128-bit loads and two 128-bit inserts give
/// `(p0_k p0_k+1 p2_k p2_k+1)` and `(p1_k p1_k+1 p3_k p3_k+1)`, whose interleaves
/// (`unpacklo`, `unpackhi`) are components `k` and `k + 1` of the four particles (six
/// instructions and two stores per pair); without, element copies. The same values either
/// way. (A 4 x 4 transpose of components 0..4 from 256-bit row loads is as many
/// instructions on paper, but LLVM rewrites its cross-lane shuffles into broadcasts and
/// blends of the loaded elements: more.)
#[inline(always)]
pub fn rows_to_lanes<const B: usize>(
    simd: Option<V3>,
    rows: [&[f64; 6]; 4],
    lanes: &mut [[f64; B]; 6],
    at: usize,
) {
    #[cfg(target_arch = "x86_64")]
    if let Some(s) = simd {
        use core::arch::x86_64::{__m128d, __m256d};
        let a = s.avx;
        let [p0, p1, p2, p3] = rows;
        let pair = |p: &[f64; 6], k: usize| -> __m128d { pulp::cast([p[k], p[k + 1]]) };
        for (k, ls) in lanes.chunks_exact_mut(2).enumerate() {
            let k = 2 * k;
            // (p0_k p0_k+1 p2_k p2_k+1), (p1_k p1_k+1 p3_k p3_k+1)
            let u02 = a._mm256_set_m128d(pair(p2, k), pair(p0, k));
            let u13 = a._mm256_set_m128d(pair(p3, k), pair(p1, k));
            let c: [__m256d; 2] = [
                a._mm256_unpacklo_pd(u02, u13),
                a._mm256_unpackhi_pd(u02, u13),
            ];
            for (l, ck) in ls.iter_mut().zip(c) {
                let v: [f64; 4] = pulp::cast(ck);
                l[at..at + 4].copy_from_slice(&v);
            }
        }
        return;
    }
    let _ = simd;
    for (k, l) in lanes.iter_mut().enumerate() {
        for (j, r) in rows.iter().enumerate() {
            l[at + j] = r[k];
        }
    }
}

#[cfg(feature = "std")]
/// `rows[j][k] = lanes[k][at + j]`: lanes `at..at + 4` of a transposed block out into four
/// particles, the inverse of [`rows_to_lanes`] (per pair of components two loads, the two
/// interleaves, four 128-bit stores). The same values with and without the token.
#[inline(always)]
pub fn lanes_to_rows<const B: usize>(
    simd: Option<V3>,
    lanes: &[[f64; B]; 6],
    at: usize,
    rows: [&mut [f64; 6]; 4],
) {
    #[cfg(target_arch = "x86_64")]
    if let Some(s) = simd {
        use core::arch::x86_64::{__m128d, __m256d};
        let a = s.avx;
        let [p0, p1, p2, p3] = rows;
        // one 32-byte copy: a single load (built from four elements, LLVM would rebuild the
        // vector from broadcasts and blends)
        let ld = |l: &[f64; B]| -> __m256d {
            let mut v = [0.0; 4];
            v.copy_from_slice(&l[at..at + 4]);
            pulp::cast(v)
        };
        let st = |p: &mut [f64; 6], k: usize, v: __m128d| {
            let v: [f64; 2] = pulp::cast(v);
            p[k..k + 2].copy_from_slice(&v);
        };
        for (k, ls) in lanes.chunks_exact(2).enumerate() {
            let k = 2 * k;
            if let [l0, l1] = ls {
                let (c0, c1) = (ld(l0), ld(l1));
                // (p0_k p0_k+1 p2_k p2_k+1), (p1_k p1_k+1 p3_k p3_k+1)
                let u02 = a._mm256_unpacklo_pd(c0, c1);
                let u13 = a._mm256_unpackhi_pd(c0, c1);
                st(p0, k, a._mm256_castpd256_pd128(u02));
                st(p1, k, a._mm256_castpd256_pd128(u13));
                st(p2, k, a._mm256_extractf128_pd::<1>(u02));
                st(p3, k, a._mm256_extractf128_pd::<1>(u13));
            }
        }
        return;
    }
    let _ = simd;
    for (j, r) in rows.into_iter().enumerate() {
        for (k, v) in r.iter_mut().enumerate() {
            *v = lanes[k][at + j];
        }
    }
}

#[cfg(feature = "std")]
/// Runs `f` with every [`dispatch`] and [`dispatch_v3`] on this thread kept on the baseline
/// path (for tests that compare the two paths bit for bit; threads `f` starts are not
/// affected).
pub fn with_baseline<R>(f: impl FnOnce() -> R) -> R {
    struct Restore(bool);
    impl Drop for Restore {
        fn drop(&mut self) {
            FORCE_BASELINE.with(|c| c.set(self.0));
        }
    }
    let _restore = Restore(FORCE_BASELINE.with(|c| c.replace(true)));
    f()
}

/// Without `std` (no CPU detection): `"baseline"`.
#[cfg(not(feature = "std"))]
pub fn level() -> &'static str {
    "baseline"
}

/// Without `std` (no CPU detection): `f()` on the baseline path, the same bits as the
/// dispatched path computes.
#[cfg(not(feature = "std"))]
#[inline(always)]
pub fn dispatch<R>(f: impl FnOnce() -> R) -> R {
    f()
}

/// Without `std` (no CPU detection): `f(None)`, the baseline path.
#[cfg(not(feature = "std"))]
#[inline(always)]
pub fn dispatch_v3<R>(f: impl FnOnce(Option<V3>) -> R) -> R {
    f(None)
}

#[cfg(test)]
mod tests {
    use super::{dispatch, dispatch_v3, lanes_to_rows, level, rows_to_lanes, with_baseline};

    /// A loop the v3 path vectorises with 4-wide AVX2 operations: the same bits as baseline.
    fn kernel(x: &[f64; 64]) -> [f64; 64] {
        dispatch(
            #[inline(always)]
            || {
                let mut y = [0.0; 64];
                for (yi, xi) in y.iter_mut().zip(x) {
                    *yi = (xi * 1.1 + 0.3) * xi - (xi / 3.0).sqrt();
                }
                y
            },
        )
    }

    /// The four-particle transposes with the v3 token (shuffles) and without (element
    /// copies) move the same bits, and they are the transposes.
    #[test]
    fn v3_and_baseline_transposes_agree() {
        let rows: [[f64; 6]; 4] = core::array::from_fn(|j| {
            core::array::from_fn(|k| match (j + k) % 5 {
                0 => -0.0,
                1 => f64::from_bits(0xfff8_0000_0000_0abc),
                _ => (10 * j + k) as f64 + 0.125,
            })
        });
        let token = dispatch_v3(|t| t);
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2")
            && std::is_x86_feature_detected!("fma")
            && std::env::var_os("RELNAV_SIMD").is_none()
        {
            assert!(token.is_some());
        }
        assert!(with_baseline(|| dispatch_v3(|t| t)).is_none());
        let bits = |a: &[[f64; 8]; 6]| a.map(|r| r.map(f64::to_bits));
        for at in [0, 4] {
            let (mut a, mut b) = ([[7.0; 8]; 6], [[7.0; 8]; 6]);
            rows_to_lanes(token, [&rows[0], &rows[1], &rows[2], &rows[3]], &mut a, at);
            rows_to_lanes(None, [&rows[0], &rows[1], &rows[2], &rows[3]], &mut b, at);
            assert_eq!(bits(&a), bits(&b));
            for (k, l) in a.iter().enumerate() {
                for (j, r) in rows.iter().enumerate() {
                    assert_eq!(l[at + j].to_bits(), r[k].to_bits());
                }
                assert!(l[4 - at..8 - at].iter().all(|v| *v == 7.0));
            }
            let (mut p, mut q) = ([[0.0; 6]; 4], [[0.0; 6]; 4]);
            let [p0, p1, p2, p3] = &mut p;
            lanes_to_rows(token, &a, at, [p0, p1, p2, p3]);
            let [q0, q1, q2, q3] = &mut q;
            lanes_to_rows(None, &a, at, [q0, q1, q2, q3]);
            assert_eq!(
                p.map(|r| r.map(f64::to_bits)),
                rows.map(|r| r.map(f64::to_bits))
            );
            assert_eq!(
                q.map(|r| r.map(f64::to_bits)),
                rows.map(|r| r.map(f64::to_bits))
            );
        }
    }

    #[test]
    fn dispatched_and_baseline_paths_agree_bit_for_bit() {
        let x: [f64; 64] = core::array::from_fn(|i| 0.37 * i as f64 + 1e-3);
        let fast = kernel(&x);
        let base = with_baseline(|| {
            assert_eq!(level(), "baseline");
            kernel(&x)
        });
        assert!(fast
            .iter()
            .zip(&base)
            .all(|(a, b)| a.to_bits() == b.to_bits()));
        // the override is undone on return
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2")
            && std::is_x86_feature_detected!("fma")
            && std::env::var_os("RELNAV_SIMD").is_none()
        {
            assert_eq!(level(), "x86-64-v3");
        }
    }
}
