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

/// Write `T`'s size and alignment to `size` and `align` (the `*_storage` queries).
///
/// # Safety
/// `size` and `align` are null or writable.
pub(crate) unsafe fn storage_of<T>(
    size: *mut usize,
    align: *mut usize,
    func: &str,
) -> Result<(), Failure> {
    // SAFETY: the caller's contract, checked for null.
    let s = unsafe { size.as_mut() }.ok_or_else(|| null("size", func))?;
    // SAFETY: as above.
    let a = unsafe { align.as_mut() }.ok_or_else(|| null("align", func))?;
    *s = core::mem::size_of::<T>();
    *a = core::mem::align_of::<T>();
    Ok(())
}

/// The caller's `storage` (`size` bytes) as a place for one `T`: refused when null, smaller
/// than `T` or misaligned (`query` names the call that tells the need).
pub(crate) fn place_for<T>(
    storage: *mut core::ffi::c_void,
    size: usize,
    func: &str,
    query: &str,
) -> Result<*mut T, Failure> {
    if storage.is_null() {
        return Err(null("storage", func));
    }
    let place = storage.cast::<T>();
    if size < core::mem::size_of::<T>() || !place.is_aligned() {
        return Err(Failure(
            crate::error::relnav_status::RELNAV_ERROR_INVALID_ARGUMENT,
            relnav_core::message::Message::concat(&[
                func,
                ": the storage is smaller or less aligned than ",
                query,
                " says",
            ]),
        ));
    }
    Ok(place)
}

/// End a value made in the caller's storage by a `*_init` call (null: nothing to do).
///
/// # Safety
/// `handle` is null or points to a `T` written by its `*_init` call and not yet ended.
pub(crate) unsafe fn drop_placed<T>(handle: *mut T) {
    if !handle.is_null() {
        // SAFETY: a live `T` in the caller's storage, ended once by the caller's contract.
        unsafe { core::ptr::drop_in_place(handle) };
    }
}
