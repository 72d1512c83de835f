//! H-infinity filter (paper 002): the LMI design solve (assembly included) and one
//! runtime filter step. Targets: design <= 0.5 s, step <= 200 ns.
#![allow(missing_docs, clippy::unwrap_used)]

use criterion::{criterion_group, criterion_main, Criterion};
use relnav::hinf::design::{design_open_loop, design_paper_spec, DesignOptions};
use relnav::hinf::{HinfFilter, HinfSpec};
use relnav::types::{State, Vec3};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let spec = HinfSpec::paper();
    let opts = DesignOptions::default();
    let mut g = c.benchmark_group("hinf_design");
    g.sample_size(10);
    g.bench_function("hinf_design_paper", |b| {
        b.iter(|| design_paper_spec(black_box(&spec), &opts).unwrap())
    });
    g.bench_function("hinf_design_observer", |b| {
        b.iter(|| design_open_loop(black_box(&spec), &opts).unwrap())
    });
    g.finish();
    let d = design_open_loop(&spec, &opts).unwrap();
    let mut f = HinfFilter::new(
        d.matrices,
        State::from_row_slice(&[630.0, 520.0, 1000.0, 0.0, 0.0, 0.0]),
    )
    .unwrap();
    let y = Vec3::new(600.0, 550.0, 1040.0);
    let a = Vec3::new(1e-3, 0.0, -1e-3);
    c.bench_function("hinf_step", |b| {
        b.iter(|| {
            f.step(Some(black_box(&y)), black_box(&a));
            black_box(f.state()[0])
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
