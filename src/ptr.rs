//! Null-checked copies between C arrays and Rust arrays.

use crate::error::{null, Failure};

/// Borrow `N` doubles from a C array; null is an error naming `arg`.
///
/// # Safety
/// `ptr` is null or points to `N` readable, initialised doubles.
pub(crate) unsafe fn read_array<const N: usize>(
    ptr: *const f64,
    arg: &str,
    func: &str,
) -> Result<[f64; N], Failure> {
    if ptr.is_null() {
        return Err(null(arg, func));
    }
    let mut out = [0.0; N];
    // SAFETY: the caller guarantees N readable doubles at a non-null `ptr`.
    let src = unsafe { core::slice::from_raw_parts(ptr, N) };
    out.copy_from_slice(src);
    Ok(out)
}

/// Copy `N` doubles out to a C array; null is an error naming `arg`.
///
/// # Safety
/// `ptr` is null or points to `N` writable doubles.
pub(crate) unsafe fn write_array<const N: usize>(
    ptr: *mut f64,
    v: &[f64; N],
    arg: &str,
    func: &str,
) -> Result<(), Failure> {
    if ptr.is_null() {
        return Err(null(arg, func));
    }
    // SAFETY: the caller guarantees N writable doubles at a non-null `ptr`.
    let dst = unsafe { core::slice::from_raw_parts_mut(ptr, N) };
    dst.copy_from_slice(v);
    Ok(())
}
