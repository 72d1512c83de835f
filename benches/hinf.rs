//! H-infinity filter (paper 002): the LMI design solves (assembly included) — paper form,
//! gamma-optimal observer (the Riccati route; its SDP as `hinf_design_observer_sdp`; also
//! on the quiet-truth noise), mixed H2/H-infinity observer (both of its solves: the
//! gamma-optimal observer it is bounded by, then the mixed SDP) on paper 002's noise and on
//! the noise model filter 9 derives for a quiet truth — and one runtime filter step.
//! Targets: design <= 0.5 s, step <= 200 ns.
#![allow(missing_docs, clippy::unwrap_used)]

use criterion::{criterion_group, criterion_main, Criterion};
use relnav_core::hinf::design::{
    design_observer_sdp, design_open_loop, design_open_loop_mixed, design_paper_spec, DesignOptions,
};
use relnav_core::hinf::{HinfFilter, HinfSpec};
use relnav_core::types::{State, Vec3};
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
    // the SDP route of the gamma-optimal observer (the eliminated SDP), its reference and
    // fallback: both routes timed in one binary
    let open = relnav_core::hinf::HinfPlant::open_loop(&spec);
    g.bench_function("hinf_design_observer_sdp", |b| {
        b.iter(|| design_observer_sdp(black_box(&open), spec.period, &opts).unwrap())
    });
    g.bench_function("hinf_design_mixed", |b| {
        b.iter(|| design_open_loop_mixed(black_box(&spec), 1.5, &opts).unwrap())
    });
    // filter 9's default on paper 000's example with a quiet truth (derived B, D)
    let quiet = relnav_core::nav::NavConfig {
        filter: relnav_core::nav::FilterKind::Hinf,
        accel_psd: 1e-10,
        q_pos: [0.0; 3],
        q_vel: [0.0; 3],
        ..Default::default()
    }
    .hinf_spec()
    .unwrap();
    g.bench_function("hinf_design_observer_quiet", |b| {
        b.iter(|| design_open_loop(black_box(&quiet), &opts).unwrap())
    });
    g.bench_function("hinf_design_mixed_quiet", |b| {
        b.iter(|| design_open_loop_mixed(black_box(&quiet), 1.5, &opts).unwrap())
    });
    g.finish();
    for (name, sp) in [("paper", &spec), ("quiet", &quiet)] {
        let m = design_open_loop_mixed(sp, 1.5, &opts).unwrap();
        eprintln!(
            "{name}: gamma-optimal observer gamma {:.5}, H2 {:.5}, {} iterations; mixed gamma \
             {:.5}, H2 {:.5}, {} iterations",
            m.pure.gamma,
            m.pure.h2_norm,
            m.pure.iterations,
            m.mixed.gamma,
            m.mixed.h2_norm,
            m.mixed.iterations
        );
    }
    let p = design_paper_spec(&spec, &opts).unwrap();
    eprintln!(
        "paper form: gamma {:.5}, H2 {:.5}, {} iterations",
        p.gamma, p.h2_norm, p.iterations
    );
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
