//! A fixed amount of particle-filter work for instruction counting:
//! the SIR (moves on, the default) on paper 000's model, `warm` steps into steady state,
//! then `steps` more. Under `valgrind --tool=callgrind` the difference of the instruction
//! counts of two runs that differ only in `steps` is the cost of those steps alone (the
//! run is deterministic: fixed seeds).
//!
//! ```sh
//! cargo build --release --example pf_steps
//! valgrind --tool=callgrind target/release/examples/pf_steps 100000 20 0 1
//! valgrind --tool=callgrind target/release/examples/pf_steps 100000 20 5 1
//! ```
//!
//! Arguments: particles, warm-up steps, measured steps, threads, kind (`pf`, `rpf`, `upf`,
//! `gapf`, `cgapf`), moves (`moves` or `literal`: [`PfParams::moves`]; `particle`: the
//! particle prior, a Gaussian per particle, [`GaussianSumPf`]), the RPF's kernel
//! (`gaussian` or `epanechnikov`: [`PfParams::kernel`]; default
//! 100000 20 1 1 pf moves gaussian).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)] // example code

use rand::SeedableRng;
use relnav_core::dynamics::{CwModel, DiscreteModel, Discretization};
use relnav_core::estimators::pf::{Kernel, ParticleFilter, PfKind, PfParams, PfPrior};
use relnav_core::estimators::{Estimator, GaussianSumPf};
use relnav_core::nav::NavConfig;
use relnav_core::sensors::RadioSensor;
use relnav_core::types::{Mat3, Mat6, State, Vec3};

fn main() {
    let arg = |i: usize, d: usize| -> usize {
        std::env::args()
            .nth(i)
            .map_or(d, |s| s.parse().expect("a non-negative integer"))
    };
    let (particles, warm, steps, threads) = (arg(1, 100_000), arg(2, 20), arg(3, 1), arg(4, 1));
    let kind = std::env::args().nth(5).map_or(PfKind::Sir, |s| {
        PfKind::from_name(&s).expect("a filter kind")
    });
    let mode = std::env::args().nth(6);
    let moves = mode.as_deref() != Some("literal");
    let particle_prior = mode.as_deref() == Some("particle");
    let kernel = match std::env::args().nth(7).as_deref() {
        None | Some("gaussian") => Kernel::Gaussian,
        Some("epanechnikov") => Kernel::Epanechnikov,
        Some(k) => panic!("unknown kernel {k}"),
    };
    let cfg = NavConfig::default();
    let f = cfg.frame;
    let model = CwModel::new(cfg.mean_motion);
    let mut d = model.discretize(1.0, &Mat3::zeros(), Discretization::Exact);
    let q = [cfg.q_pos, cfg.q_vel].concat();
    d.q += f.cov_to_canonical(&Mat6::from_diagonal(&State::from_row_slice(&q)));
    let sensor = RadioSensor::new(f, cfg.sigma_range, cfg.sigma_angle);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
    let x0 = f.state_to_canonical(&State::from_row_slice(&[
        400.0, 500.0, 200.0, 0.0, 0.0, 0.0,
    ]));
    let params = PfParams {
        particles,
        seed: 7,
        threads,
        moves,
        kernel,
        ..PfParams::new(kind)
    };
    let (x0f, p0f) = (cfg.initial_state(), cfg.initial_covariance());
    let zs: Vec<Vec3> = (0..warm + steps)
        .map(|k| {
            let x = model.phi(k as f64) * x0;
            sensor
                .measure(&x.fixed_rows::<3>(0).into_owned(), &mut rng)
                .unwrap()
        })
        .collect();
    let m = if particle_prior {
        let params = PfParams {
            prior: PfPrior::Particle,
            ..params
        };
        drive(
            GaussianSumPf::new(x0f, p0f, &params, None),
            &sensor,
            &zs,
            &d,
        )
    } else {
        drive(ParticleFilter::new(x0f, p0f, params), &sensor, &zs, &d)
    };
    println!(
        "{} particles {particles}, steps {}, threads {threads}: mean {:.6} {:.6} {:.6}",
        kind.name(),
        warm + steps,
        m[0],
        m[1],
        m[2]
    );
}

/// The filter's steps (the update with each measurement, then the prediction) and its
/// final estimate.
fn drive<E: Estimator>(mut f: E, sensor: &RadioSensor, zs: &[Vec3], d: &DiscreteModel) -> State {
    for z in zs {
        f.update(sensor, z).unwrap();
        f.predict(d, &Vec3::zeros()).unwrap();
    }
    *f.state()
}
