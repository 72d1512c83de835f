//! The one foreign call into the statically linked OpenBLAS (the only unsafe code outside
//! `ffi` and `fmi`: it is itself an FFI binding, kept below the H-infinity design that uses it).

#[cfg(relnav_openblas)]
mod openblas {
    extern "C" {
        /// OpenBLAS's thread-count setter (linked statically by build.rs).
        pub(super) fn openblas_set_num_threads(n: std::ffi::c_int);
    }
}

/// Run OpenBLAS single-threaded. The H-infinity design's dense blocks are 45x45: threads
/// only add synchronisation, and on a loaded machine they make a solve several
/// times slower. Called by the design before each solve. OpenBLAS
/// is linked statically and its symbols are not exported, so this changes only relnav's
/// own copy, never a host's BLAS.
pub fn single_thread() {
    #[cfg(relnav_openblas)]
    // SAFETY: OpenBLAS's documented setter; it only stores the thread count for later calls.
    unsafe {
        openblas::openblas_set_num_threads(1)
    };
}
