//! Wall-clock companion of `kalman_profile` for the FMU cycle overhead (issue 15 item 3):
//! the bare UKF step (`update` + `predict`), the navigator's step and one FMU master cycle
//! (set the 3 measurement inputs, `fmi2DoStep`, get the 12 estimate outputs), 600 steps of
//! paper 000's measurements each, **interleaved** batch by batch so that a busy machine
//! slows all three alike; prints the minimum, 10th percentile and median ns per step of
//! each and the cycle's overhead over the bare step. The minimum of many short batches is
//! the uncontended figure on a shared machine; criterion (`benches/filters.rs`) stays the
//! reference for the README.
//!
//! ```sh
//! cargo run --release --example cycle_time -- 300   # batches
//! ```
#![allow(clippy::unwrap_used, clippy::expect_used)] // example code

use rand::SeedableRng;
use relnav::dynamics::{CwModel, Discretization};
use relnav::estimators::{Estimator, Ukf, UkfParams};
use relnav::fmi::description::guid;
use relnav::fmi::functions::*;
use relnav::fmi::types::*;
use relnav::fmi::variables::vr;
use relnav::nav::{FilterKind, NavConfig, Navigator};
use relnav::sensors::RadioSensor;
use relnav::types::{Mat3, Mat6, State, Vec3};
use std::hint::black_box;
use std::time::Instant;

const STEPS: usize = 600;

/// Paper 000's seeded measurements along the truth (frame 2, 1 s apart), as in
/// `benches/filters.rs`.
fn measurements() -> Vec<[f64; 3]> {
    let cfg = NavConfig::default();
    let f = cfg.frame;
    let model = CwModel::new(cfg.mean_motion);
    let sensor = RadioSensor::new(f, cfg.sigma_range, cfg.sigma_angle);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
    let x0 = f.state_to_canonical(&State::from_row_slice(&[
        400.0, 500.0, 200.0, 0.0, 0.0, 0.0,
    ]));
    (0..STEPS)
        .map(|k| {
            let x = model.phi(k as f64) * x0;
            let z = sensor
                .measure(&x.fixed_rows::<3>(0).into_owned(), &mut rng)
                .unwrap();
            [z.x, z.y, z.z]
        })
        .collect()
}

/// Nanoseconds per step of `steps` steps of `f`.
fn per_step(mut f: impl FnMut()) -> f64 {
    let s = Instant::now();
    f();
    s.elapsed().as_nanos() as f64 / STEPS as f64
}

fn main() {
    let batches: usize = std::env::args()
        .nth(1)
        .map_or(300, |s| s.parse().expect("a batch count"));
    let kind = FilterKind::Ukf;
    let cfg = NavConfig {
        filter: kind,
        ..Default::default()
    };
    let zs = measurements();
    let model = CwModel::new(cfg.mean_motion);
    let mut d = model.discretize(1.0, &Mat3::zeros(), Discretization::Exact);
    let q = [cfg.q_pos, cfg.q_vel].concat();
    d.q += cfg
        .frame
        .cov_to_canonical(&Mat6::from_diagonal(&State::from_row_slice(&q)));
    let sensor = RadioSensor::new(cfg.frame, cfg.sigma_range, cfg.sigma_angle);
    let (x0, p0) = (cfg.initial_state(), cfg.initial_covariance());
    let accel = Vec3::zeros();
    let mut nav = Navigator::new(&cfg).unwrap();

    let g = std::ffi::CString::new(guid()).unwrap();
    let cb = fmi2CallbackFunctions {
        logger: None,
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: std::ptr::null_mut(),
    };
    // SAFETY: valid arguments; the instance is freed at the end.
    let comp = unsafe {
        fmi2Instantiate(
            c"cycle_time".as_ptr(),
            fmi2CoSimulation,
            g.as_ptr(),
            std::ptr::null(),
            &cb,
            0,
            0,
        )
    };
    assert!(!comp.is_null());
    let init = |comp| {
        // SAFETY: live instance, one value each.
        unsafe {
            fmi2SetInteger(comp, &vr::FILTER, 1, &(kind as i32));
            fmi2SetupExperiment(comp, 0, 0.0, 0.0, 0, 0.0);
            fmi2EnterInitializationMode(comp);
            fmi2ExitInitializationMode(comp);
            fmi2SetBoolean(comp, &vr::MEASUREMENT_VALID, 1, &1);
        }
    };
    let ins = [vr::RANGE, vr::AZIMUTH, vr::ELEVATION];
    let outs: Vec<u32> = (vr::X..=vr::SIGMA_VZ).collect();
    let mut y = [0.0; 12];

    let mut t = [Vec::new(), Vec::new(), Vec::new()];
    for _ in 0..batches {
        let mut f = Ukf::new(x0, p0, UkfParams::default());
        t[0].push(per_step(|| {
            for z in &zs {
                let z = Vec3::from_row_slice(z);
                f.update(&sensor, black_box(&z)).unwrap();
                f.predict(&d, black_box(&accel)).unwrap();
            }
        }));
        nav.reset();
        t[1].push(per_step(|| {
            for z in &zs {
                nav.step(&[0.0; 3], Some(black_box(z)), 1.0).unwrap();
            }
        }));
        // SAFETY: live instance.
        unsafe { fmi2Reset(comp) };
        init(comp);
        t[2].push(per_step(|| {
            for (k, z) in zs.iter().enumerate() {
                // SAFETY: live instance, matching lengths.
                unsafe {
                    fmi2SetReal(comp, ins.as_ptr(), 3, black_box(z.as_ptr()));
                    assert_eq!(fmi2DoStep(comp, k as f64, 1.0, 1), fmi2Status::fmi2OK);
                    fmi2GetReal(comp, outs.as_ptr(), 12, y.as_mut_ptr());
                }
                black_box(&y);
            }
        }));
    }
    for v in t.iter_mut() {
        v.sort_by(f64::total_cmp);
    }
    let q = |v: &[f64], p: f64| v[((v.len() - 1) as f64 * p) as usize];
    for (name, v) in ["ukf_step", "navigator_step_ukf", "fmu_cycle_ukf"]
        .iter()
        .zip(&t)
    {
        println!(
            "{name:20} min {:7.1}  p10 {:7.1}  median {:7.1} ns",
            q(v, 0.0),
            q(v, 0.1),
            q(v, 0.5)
        );
    }
    println!(
        "{:20} min {:7.1}  p10 {:7.1} ns",
        "fmu - bare",
        q(&t[2], 0.0) - q(&t[0], 0.0),
        q(&t[2], 0.1) - q(&t[0], 0.1)
    );
    // SAFETY: freed once.
    unsafe { fmi2FreeInstance(comp) };
}
