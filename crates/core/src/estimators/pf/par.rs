//! The particle loops on several threads, with results that do not depend on the thread
//! count.
//!
//! Below [`PARALLEL_MIN_PARTICLES`] every loop runs on the calling thread over the whole
//! particle set with the filter's one generator, and nothing is allocated (the
//! `tests/no_alloc.rs` invariant). From that many particles on, the set is cut into
//! chunks of [`CHUNK`] consecutive particles, fixed by the particle count alone. Chunk
//! `j` draws its random numbers from its own generator, the filter's seed stream advanced
//! by `j + 1` xoshiro256++ jumps of `2^128` draws (non-overlapping streams; Blackman &
//! Vigna), and every reduction (sums of weights, moments, counts) is formed per chunk and
//! combined in chunk order. So a chunk's work is the same whichever thread does it, and
//! the results are bit-identical for one, two or any number of threads (tested). The
//! chunks run on rayon's global pool (`threads = 0`, one worker per core), on a pool of
//! the filter's own (`threads >= 2`, built at construction) or one after the other on the
//! calling thread (`threads = 1`). The parallel path allocates a few small vectors per
//! loop (the chunk jobs and their partial results) and rayon's job queue may allocate:
//! that is why it is reserved for large sets, where a step takes milliseconds.
//!
//! Sequential on every path: resampling (one `O(N)` walk with the filter's generator)
//! and the genetic operators of the GA-PF and CGA-PF (their pairings span the whole
//! population).

use super::PfRng;
use rayon::prelude::*;
use std::sync::Arc;

/// Particles per chunk of the parallel path (fixed: a chunk's work does not depend on the
/// thread count).
pub const CHUNK: usize = 4096;

/// From this many particles on the particle loops run in chunks on worker threads (below,
/// on the calling thread without allocating).
pub const PARALLEL_MIN_PARTICLES: usize = 32_768;

/// Where the chunks run.
#[derive(Debug, Clone)]
pub(super) enum Pool {
    /// One after the other on the calling thread.
    Serial,
    /// rayon's global pool.
    Global,
    /// A pool of the filter's own.
    Own(Arc<rayon::ThreadPool>),
}

impl Pool {
    /// The pool for `threads` workers (0: rayon's global pool).
    pub(super) fn new(threads: usize) -> Self {
        match threads {
            0 => Pool::Global,
            1 => Pool::Serial,
            t => rayon::ThreadPoolBuilder::new()
                .num_threads(t)
                .build()
                .map(|p| Pool::Own(Arc::new(p)))
                .unwrap_or(Pool::Global),
        }
    }

    /// `f` applied to every job, results in job order.
    pub(super) fn map<J, T, F>(&self, jobs: Vec<J>, f: F) -> Vec<T>
    where
        J: Send,
        T: Send,
        F: Fn(J) -> T + Sync + Send,
    {
        match self {
            Pool::Serial => jobs.into_iter().map(f).collect(),
            Pool::Global => jobs.into_par_iter().map(f).collect(),
            Pool::Own(p) => p.install(|| jobs.into_par_iter().map(f).collect()),
        }
    }
}

/// The generators of the `ceil(n / CHUNK)` chunks of the parallel path (empty below
/// [`PARALLEL_MIN_PARTICLES`]): chunk `j` gets `base` advanced by `j + 1` jumps.
pub(super) fn chunk_generators(base: &PfRng, n: usize) -> Vec<PfRng> {
    if n < PARALLEL_MIN_PARTICLES {
        return Vec::new();
    }
    let mut g = base.clone();
    (0..n.div_ceil(CHUNK))
        .map(|_| {
            g.jump();
            g.clone()
        })
        .collect()
}

/// The chunks of a buffer; an empty buffer (the per-particle arrays a kind does not use)
/// yields empty slices without end, so it can be zipped with the others.
pub(super) fn chunks_mut<T>(s: &mut [T]) -> Box<dyn Iterator<Item = &mut [T]> + '_> {
    if s.is_empty() {
        Box::new(core::iter::repeat_with(<&mut [T]>::default))
    } else {
        Box::new(s.chunks_mut(CHUNK))
    }
}
