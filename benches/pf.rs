//! Criterion benchmarks of the particle filters: one step (update with the measurement,
//! resampling when due, predict) on paper 000's model, in steady state. The literal SIR
//! (no moves, the algorithm of the numpy anchor) at N = 1500, single-threaded; with the
//! moves (the default) at N = 1500 and N = 100 000 (ns per particle), RPF, UPF, GA-PF and
//! CGA-PF at N = 1500 each literal (no moves: comparable with figures taken without the
//! moves) and with the moves (the targets are in `benches/summarize.py`); the SIR, RPF
//! and UPF with the particle prior (`pf_prior = particle`) at N = 1500; the thread
//! scaling of the chunked path at N = 10^5 and 10^6 on 1 and 2 threads (`pf_scaling`, 10
//! samples each; `cargo bench --bench pf -- threads`). `scripts/bench.sh` runs these
//! with the vectorised numpy SIR anchor (`benches/anchor_numpy_sir.py`) and prints medians
//! and ratios.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)] // bench code

use criterion::{criterion_group, criterion_main, Criterion};
use rand::SeedableRng;
use relnav_core::dynamics::{CwModel, DiscreteModel, Discretization};
use relnav_core::estimators::pf::{ParticleFilter, PfKind, PfParams, PfPrior};
use relnav_core::estimators::Estimator;
use relnav_core::estimators::GaussianSumPf;
use relnav_core::nav::NavConfig;
use relnav_core::sensors::RadioSensor;
use relnav_core::types::{Mat3, Mat6, State, Vec3};
use std::hint::black_box;

/// Paper 000's model, sensor and a long run of noisy measurements (frame 2).
fn setup(steps: usize) -> (DiscreteModel, RadioSensor, Vec<Vec3>) {
    let cfg = NavConfig::default();
    let f = cfg.frame;
    let model = CwModel::new(cfg.mean_motion);
    let mut d = model.discretize(1.0, &Mat3::zeros(), Discretization::Exact);
    d.q += f.cov_to_canonical(&Mat6::from_diagonal(&State::from_row_slice(&[
        cfg.q_pos[0],
        cfg.q_pos[1],
        cfg.q_pos[2],
        cfg.q_vel[0],
        cfg.q_vel[1],
        cfg.q_vel[2],
    ])));
    let sensor = RadioSensor::new(f, cfg.sigma_range, cfg.sigma_angle);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
    let x0 = f.state_to_canonical(&State::from_row_slice(&[
        400.0, 500.0, 200.0, 0.0, 0.0, 0.0,
    ]));
    let zs = (0..steps)
        .map(|k| {
            let x = model.phi(k as f64) * x0;
            sensor
                .measure(&x.fixed_rows::<3>(0).into_owned(), &mut rng)
                .unwrap()
        })
        .collect();
    (d, sensor, zs)
}

fn bench_pf(c: &mut Criterion, name: &str, kind: PfKind, particles: usize) {
    bench_pf_threads(c, name, kind, particles, 0, true);
}

/// As [`bench_pf`] with `threads` worker threads for the chunked particle loops (from
/// 32768 particles on; 0: one per core; the results do not depend on it) and the moves on
/// or off ([`PfParams::moves`]).
fn bench_pf_threads(
    c: &mut Criterion,
    name: &str,
    kind: PfKind,
    particles: usize,
    threads: usize,
    moves: bool,
) {
    let cfg = NavConfig::default();
    let (d, sensor, zs) = setup(20_000);
    let params = PfParams {
        particles,
        seed: 7,
        threads,
        moves,
        ..PfParams::new(kind)
    };
    let make = || ParticleFilter::new(cfg.initial_state(), cfg.initial_covariance(), params);
    bench_steps(c, name, make, &d, &sensor, &zs);
}

/// One step of the filter `make` builds (update with the next measurement, predict), in
/// steady state: past 20 steps (the first-measurement initialisation), a new filter when
/// the measurements run out.
fn bench_steps<F: Estimator>(
    c: &mut Criterion,
    name: &str,
    make: impl Fn() -> F,
    d: &DiscreteModel,
    sensor: &RadioSensor,
    zs: &[Vec3],
) {
    let warm = || {
        let mut f = make();
        for z in zs.iter().take(20) {
            f.update(sensor, z).unwrap();
            f.predict(d, &Vec3::zeros()).unwrap();
        }
        f
    };
    let mut f = warm();
    let mut k = 20;
    c.bench_function(name, |b| {
        b.iter(|| {
            if k == zs.len() {
                f = warm();
                k = 20;
            }
            f.update(sensor, black_box(&zs[k])).unwrap();
            f.predict(d, black_box(&Vec3::zeros())).unwrap();
            k += 1;
        })
    });
    black_box(f.state());
}

/// The particle prior ([`GaussianSumPf`], a Gaussian per particle) of `kind` at
/// `particles` on the same measurements as [`bench_pf`]: the rows `benches/summarize.py`
/// divides by the Gaussian-prior rows of the same kind and count.
fn bench_particle_prior(c: &mut Criterion, name: &str, kind: PfKind, particles: usize) {
    let cfg = NavConfig::default();
    let (d, sensor, zs) = setup(20_000);
    let params = PfParams {
        particles,
        seed: 7,
        prior: PfPrior::Particle,
        ..PfParams::new(kind)
    };
    let (x0, p0) = (cfg.initial_state(), cfg.initial_covariance());
    let make = || GaussianSumPf::new(x0, p0, &params, None);
    bench_steps(c, name, make, &d, &sensor, &zs);
}

fn benches(c: &mut Criterion) {
    // the literal SIR of paper 000 (no moves): the same algorithm as the numpy anchor
    bench_pf_threads(c, "sir_literal_step_n1500", PfKind::Sir, 1500, 0, false);
    bench_pf(c, "sir_step_n1500", PfKind::Sir, 1500);
    // the literal filters are the rows comparable with figures taken without the moves;
    // the default (moves) rows add the rejuvenation
    bench_pf_threads(c, "rpf_literal_step_n1500", PfKind::Rpf, 1500, 0, false);
    bench_pf(c, "rpf_step_n1500", PfKind::Rpf, 1500);
    bench_pf_threads(c, "gapf_literal_step_n1500", PfKind::Gapf, 1500, 0, false);
    bench_pf(c, "gapf_step_n1500", PfKind::Gapf, 1500);
    bench_pf_threads(c, "upf_literal_step_n1500", PfKind::Upf, 1500, 0, false);
    bench_pf(c, "upf_step_n1500", PfKind::Upf, 1500);
    bench_pf_threads(c, "cgapf_literal_step_n1500", PfKind::Cgapf, 1500, 0, false);
    bench_pf(c, "cgapf_step_n1500", PfKind::Cgapf, 1500);
    bench_pf(c, "sir_step_n100000", PfKind::Sir, 100_000);
    // the particle prior: EKF terms (SIR, RPF), UKF terms (UPF)
    bench_particle_prior(c, "sir_particle_prior_step_n1500", PfKind::Sir, 1500);
    bench_particle_prior(c, "rpf_particle_prior_step_n1500", PfKind::Rpf, 1500);
    bench_particle_prior(c, "upf_particle_prior_step_n1500", PfKind::Upf, 1500);
}

/// The thread scaling of the chunked path: the SIR (with its moves) at N = 10^5 and 10^6 on
/// 1 and 2 threads.
fn scaling(c: &mut Criterion) {
    for n in [100_000, 1_000_000] {
        for t in [1, 2] {
            bench_pf_threads(
                c,
                &format!("sir_step_n{n}_threads{t}"),
                PfKind::Sir,
                n,
                t,
                true,
            );
        }
    }
}

criterion_group!(pf, benches);
criterion_group! {
    name = pf_scaling;
    config = Criterion::default().sample_size(10);
    targets = scaling
}
criterion_main!(pf, pf_scaling);
