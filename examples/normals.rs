//! The particle filters' two batch normal generators side by side (issue 15): the ziggurat
//! ([`Ziggurat::fill_batch_lanes`]) and Box–Muller ([`boxmuller::fill_batch_lanes`]), each
//! on fresh [`Lanes`] inside one [`simd::dispatch`] (as the filters call them).
//!
//! ```sh
//! cargo build --profile profiling --example normals
//! # instructions per normal: the difference of two runs, e.g. 1000 and 0 batches
//! valgrind --tool=callgrind target/profiling/examples/normals zig 1000
//! valgrind --tool=callgrind target/profiling/examples/normals bm 1000
//! # wall clock, the two interleaved (rounds of `batches` each, ns per normal)
//! target/profiling/examples/normals time 100000 21
//! ```
//!
//! Arguments: `zig`, `bm` or `time`; batches of 16 values per run or round (default
//! 100000); rounds for `time` (default 11).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)] // example code

use rand::SeedableRng;
use relnav::numerics::boxmuller;
use relnav::numerics::simd;
use relnav::numerics::ziggurat::{Lanes, Ziggurat};
use std::hint::black_box;

/// `batches` batches from the ziggurat; returns a checksum.
fn zig(batches: usize, seed: u64) -> f64 {
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
    simd::dispatch(
        #[inline(always)]
        || {
            let z = Ziggurat::get();
            let mut lanes = Lanes::seed_from(&mut rng);
            let mut out = [0.0; 16];
            let mut sum = 0.0;
            for _ in 0..batches {
                z.fill_batch_lanes(&mut lanes, &mut rng, &mut out);
                black_box(&mut out);
                sum += out[3];
            }
            sum
        },
    )
}

/// `batches` batches by Box–Muller; returns a checksum.
fn bm(batches: usize, seed: u64) -> f64 {
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
    simd::dispatch(
        #[inline(always)]
        || {
            let mut lanes = Lanes::seed_from(&mut rng);
            let mut out = [0.0; 16];
            let mut sum = 0.0;
            for _ in 0..batches {
                boxmuller::fill_batch_lanes(&mut lanes, &mut out);
                black_box(&mut out);
                sum += out[3];
            }
            sum
        },
    )
}

fn main() {
    let mode = std::env::args().nth(1).unwrap_or_else(|| "time".into());
    let arg = |i: usize, d: usize| -> usize {
        std::env::args()
            .nth(i)
            .map_or(d, |s| s.parse().expect("a non-negative integer"))
    };
    let batches = arg(2, 100_000);
    match mode.as_str() {
        "zig" => println!("zig {}", zig(batches, 1)),
        "bm" => println!("bm {}", bm(batches, 1)),
        "time" => {
            let rounds = arg(3, 11);
            let (mut tz, mut tb) = (Vec::new(), Vec::new());
            let per = |t: std::time::Duration| t.as_secs_f64() * 1e9 / (16 * batches) as f64;
            for k in 0..rounds as u64 {
                let t = std::time::Instant::now();
                black_box(zig(batches, k));
                tz.push(per(t.elapsed()));
                let t = std::time::Instant::now();
                black_box(bm(batches, k));
                tb.push(per(t.elapsed()));
            }
            let median = |v: &mut Vec<f64>| {
                v.sort_by(f64::total_cmp);
                v[v.len() / 2]
            };
            println!(
                "{}: ns per normal, median of {rounds}: ziggurat {:.3}, Box-Muller {:.3}",
                simd::level(),
                median(&mut tz),
                median(&mut tb)
            );
        }
        m => panic!("unknown mode {m}"),
    }
}
