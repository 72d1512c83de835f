//! Run-time selection of the instruction set for the hot loops (the particle filters' blocks).
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
//! `RELNAV_SIMD=baseline` in the environment (read once per process) keeps every dispatch on
//! the baseline path: for comparing machines, or a CPU whose AVX2 is suspect.

use std::cell::Cell;
use std::sync::OnceLock;

thread_local! {
    /// Set by [`with_baseline`] on this thread.
    static FORCE_BASELINE: Cell<bool> = const { Cell::new(false) };
}

/// The instruction set [`dispatch`] uses in this process (CPU detection and
/// `RELNAV_SIMD`, once).
fn arch() -> Option<pulp::Arch> {
    static ARCH: OnceLock<Option<pulp::Arch>> = OnceLock::new();
    *ARCH.get_or_init(|| match std::env::var("RELNAV_SIMD") {
        Ok(v) if v.eq_ignore_ascii_case("baseline") => None,
        _ => Some(pulp::Arch::new()),
    })
}

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

/// Runs `f` compiled for the best instruction set of this CPU (see the module documentation);
/// the result is the same bits as `f()` on the baseline path.
#[inline(always)]
pub fn dispatch<R>(f: impl FnOnce() -> R) -> R {
    match arch() {
        Some(a) if !FORCE_BASELINE.with(Cell::get) => a.dispatch(f),
        _ => f(),
    }
}

/// Runs `f` with every [`dispatch`] on this thread kept on the baseline path (for tests that
/// compare the two paths bit for bit; threads `f` starts are not affected).
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

#[cfg(test)]
mod tests {
    use super::{dispatch, level, with_baseline};

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

    #[test]
    fn dispatched_and_baseline_paths_agree_bit_for_bit() {
        let x: [f64; 64] = std::array::from_fn(|i| 0.37 * i as f64 + 1e-3);
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
