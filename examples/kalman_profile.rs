//! Runs `steps` Kalman filter steps (update + predict, the `ekf_step` / `ukf_step` of
//! `benches/filters.rs`: paper 000's model and seeded measurements) and prints the final
//! estimate's bits: the workload for `valgrind --tool=callgrind` instruction counts per step
//! (`(I(n2) - I(n1)) / (n2 - n1)` cancels the setup) and a check that a change left the
//! arithmetic bit for bit as it was (or by how much it moved).
//! `none` generates the measurements only (their count is subtracted from the filters').
//! `cargo run --release --example kalman_profile -- ekf 600`.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use rand::SeedableRng;
use relnav::dynamics::{CwModel, Discretization};
use relnav::estimators::{Ekf, Estimator, Ukf, UkfParams};
use relnav::nav::NavConfig;
use relnav::sensors::RadioSensor;
use relnav::types::{Mat3, Mat6, State, Vec3};

fn run<E: Estimator>(f: Option<E>, steps: usize) -> (State, Mat6) {
    let cfg = NavConfig::default();
    let fr = cfg.frame;
    let model = CwModel::new(cfg.mean_motion);
    let sensor = RadioSensor::new(fr, cfg.sigma_range, cfg.sigma_angle);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
    let x0 = fr.state_to_canonical(&State::from_row_slice(&[
        400.0, 500.0, 200.0, 0.0, 0.0, 0.0,
    ]));
    let zs: Vec<Vec3> = (0..steps)
        .map(|k| {
            let x = model.phi(k as f64) * x0;
            sensor
                .measure(&x.fixed_rows::<3>(0).into_owned(), &mut rng)
                .unwrap()
        })
        .collect();
    let mut d = model.discretize(1.0, &Mat3::zeros(), Discretization::Exact);
    d.q += fr.cov_to_canonical(&Mat6::from_diagonal(&State::from_row_slice(&[
        cfg.q_pos[0],
        cfg.q_pos[1],
        cfg.q_pos[2],
        cfg.q_vel[0],
        cfg.q_vel[1],
        cfg.q_vel[2],
    ])));
    let accel = Vec3::zeros();
    let Some(mut f) = f else {
        // the measurements alone: subtracted from the filters' counts
        return (std::hint::black_box(State::zeros()), d.q);
    };
    for z in &zs {
        f.update(&sensor, std::hint::black_box(z)).unwrap();
        f.predict(&d, std::hint::black_box(&accel)).unwrap();
    }
    (*f.state(), *f.covariance())
}

fn main() {
    let which = std::env::args().nth(1).unwrap_or_else(|| "ekf".to_string());
    let steps: usize = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(600);
    let cfg = NavConfig::default();
    let (x0, p0) = (cfg.initial_state(), cfg.initial_covariance());
    let (x, p) = match which.as_str() {
        "ekf" => run(Some(Ekf::new(x0, p0)), steps),
        "ukf" => run(Some(Ukf::new(x0, p0, UkfParams::default())), steps),
        "none" => run(None::<Ekf>, steps),
        other => panic!("unknown filter {other}"),
    };
    let h = x
        .iter()
        .chain(p.iter())
        .fold(0u64, |h, v| h.rotate_left(7) ^ v.to_bits());
    println!(
        "{which} {steps} steps: x {:?} P00 {:e} P55 {:e} bits-hash {h:016x}",
        x.as_slice(),
        p[(0, 0)],
        p[(5, 5)]
    );
}
