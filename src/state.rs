//! Saving and restoring an estimator's complete state as explicit, versioned bytes
//! (`docs/state-format.md`): checkpoints, rollback, branching runs from one estimate.
//!
//! The bytes are the navigator's ([`relnav_core::nav::Navigator::save_state`]): a 32-byte header
//! (magic `RELNAVES`, format version, filter code, configuration fingerprint, payload
//! length, CRC-32) and the payload. They restore into any estimator created with the same
//! configuration — the same one or another, in this process or another — which then
//! continues bit for bit as the saved one would have.

use crate::error::{null, relnav_status, Failure};
use crate::estimator::{estimator_mut, estimator_ref};
use crate::panic::boundary;

/// Save the estimator's state into `buf` (capacity `cap` bytes); `*len` receives the size
/// the state needs, in every case.
///
/// * `buf == NULL`: a size query; returns `RELNAV_OK` with the size in `*len` (`cap` is
///   ignored).
/// * `cap < *len`: returns `RELNAV_ERROR_BUFFER_TOO_SMALL`, nothing written.
/// * otherwise the first `*len` bytes of `buf` hold the state; `RELNAV_OK`.
///
/// The size depends on the configuration only (a particle filter's grows with
/// `particles`), not on the estimator's history: query it once, and a buffer of that size
/// holds every later state of the estimator.
///
/// # Safety
/// `estimator` is a live handle or null; `buf` is null or points to `cap` writable bytes;
/// `len` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_save(
    estimator: *const crate::relnav_estimator,
    buf: *mut u8,
    cap: usize,
    len: *mut usize,
) -> relnav_status {
    const F: &str = "relnav_estimator_save";
    boundary(F, || {
        if len.is_null() {
            return Err(null("len", F));
        }
        // SAFETY: pointer contracts are the caller's, checked for null.
        let nav = unsafe { estimator_ref(estimator, F) }?;
        let need = nav.state_len();
        // SAFETY: `len` is non-null and writable by the caller's contract.
        unsafe { *len = need };
        if buf.is_null() {
            return Ok(());
        }
        if cap < need {
            return Err(Failure(
                relnav_status::RELNAV_ERROR_BUFFER_TOO_SMALL,
                relnav_core::msg!("{F}: the state needs {need} bytes, the buffer holds {cap}"),
            ));
        }
        // SAFETY: `buf` is non-null with `cap >= need` writable bytes by contract.
        let dst = unsafe { core::slice::from_raw_parts_mut(buf, need) };
        let took = nav.save_state_into(dst)?;
        if took != need {
            return Err(Failure(
                relnav_status::RELNAV_ERROR_PANIC,
                relnav_core::msg!(
                    "{F}: internal error: the state took {took} bytes, {need} were counted"
                ),
            ));
        }
        Ok(())
    })
}

/// Restore a state saved by [`relnav_estimator_save`] (`len` bytes at `buf`) into an
/// estimator created with the same configuration. A state that is truncated, corrupted
/// (CRC-32), of another format version, or saved for another configuration is refused
/// with `RELNAV_ERROR_INVALID_STATE` and a reason in `relnav_last_error` (naming, for
/// another configuration, the first setting that differs); the estimator is then
/// unchanged.
///
/// # Safety
/// `estimator` is a live handle or null; `buf` is null or points to `len` readable bytes.
#[no_mangle]
pub unsafe extern "C" fn relnav_estimator_restore(
    estimator: *mut crate::relnav_estimator,
    buf: *const u8,
    len: usize,
) -> relnav_status {
    const F: &str = "relnav_estimator_restore";
    boundary(F, || {
        // SAFETY: pointer contracts are the caller's, checked for null.
        let nav = unsafe { estimator_mut(estimator, F) }?;
        if buf.is_null() {
            return Err(null("buf", F));
        }
        // SAFETY: `buf` is non-null with `len` readable bytes by contract.
        let bytes = unsafe { core::slice::from_raw_parts(buf, len) };
        nav.restore_state(bytes).map_err(|e| {
            let mut f = Failure::from(e);
            f.1 = f.1.prefixed("relnav_estimator_restore: ");
            f
        })
    })
}
