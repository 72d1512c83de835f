//! Criterion benchmarks: one EKF and one UKF step (update + predict) on paper 000's model,
//! the same through the navigator and the C ABI, and one FMU `fmi2DoStep` through the C
//! entry points. `scripts/bench.sh` runs these together with the filterpy anchor and
//! prints medians and ratios.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, missing_docs)] // bench code

use criterion::{criterion_group, criterion_main, Criterion};
use rand::SeedableRng;
use relnav as ffi;
use relnav_core::dynamics::{CwModel, Discretization};
use relnav_core::estimators::{Aqukf, Ekf, Estimator, Imm, Ukf, UkfParams};
use relnav_core::nav::{FilterKind, NavConfig, Navigator};
use relnav_core::sensors::RadioSensor;
use relnav_core::types::{Mat3, Mat6, State, Vec3};
use relnav_fmi::fmi2::types::*;
use relnav_nav_model::vr;
use std::hint::black_box;

// relnav.fmu's fmi2* functions in this binary, as the FMU's shared library exports them
relnav_fmi::export_fmi2!(relnav_nav_model::RelnavFmu);

/// relnav.fmu's GUID.
fn guid() -> &'static str {
    relnav_fmi::fmi2::description::guid_of(&relnav_nav_model::INFO)
}

const STEPS: usize = 600;

/// Paper 000's measurements (noisy, seeded) along the truth, in frame 2.
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

/// One navigator step (update + predict) over paper 000's measurements, restarting after
/// the last.
fn bench_navigator(c: &mut Criterion, name: &str, cfg: NavConfig) {
    let zs = measurements();
    let mut nav = Navigator::new(&cfg).unwrap();
    let mut k = 0;
    c.bench_function(name, |b| {
        b.iter(|| {
            if k == STEPS {
                k = 0;
                nav.reset();
            }
            nav.step(&[0.0; 3], Some(black_box(&zs[k])), 1.0).unwrap();
            k += 1;
        })
    });
}

fn bare<E: Estimator>(c: &mut Criterion, name: &str, make: impl Fn() -> E) {
    let cfg = NavConfig::default();
    let zs = measurements();
    let model = CwModel::new(cfg.mean_motion);
    let mut d = model.discretize(1.0, &Mat3::zeros(), Discretization::Exact);
    d.q += cfg
        .frame
        .cov_to_canonical(&Mat6::from_diagonal(&State::from_row_slice(&[
            cfg.q_pos[0],
            cfg.q_pos[1],
            cfg.q_pos[2],
            cfg.q_vel[0],
            cfg.q_vel[1],
            cfg.q_vel[2],
        ])));
    let sensor = RadioSensor::new(cfg.frame, cfg.sigma_range, cfg.sigma_angle);
    let mut f = make();
    let mut k = 0;
    let accel = Vec3::zeros();
    c.bench_function(name, |b| {
        b.iter(|| {
            if k == STEPS {
                k = 0;
                f = make();
            }
            let z = Vec3::from_row_slice(&zs[k]);
            f.update(&sensor, black_box(&z)).unwrap();
            f.predict(&d, black_box(&accel)).unwrap();
            k += 1;
        })
    });
}

fn filters(c: &mut Criterion) {
    let cfg = NavConfig::default();
    let x0 = cfg.initial_state();
    let p0 = cfg.initial_covariance();
    bare(c, "ekf_step", || Ekf::new(x0, p0));
    bare(c, "ukf_step", || Ukf::new(x0, p0, UkfParams::default()));
    // the AQUKF with the NIS-gated law (the default) and the three-mode IMM
    bare(c, "aqukf_gated_step", || {
        Aqukf::new(
            x0,
            p0,
            UkfParams::default(),
            cfg.aq_params(),
            cfg.dynamics(),
        )
    });
    bare(c, "imm_step", || {
        Imm::new(x0, p0, cfg.imm_params(), cfg.dynamics())
    });

    // the navigator's EKF on the elliptic model (e = 0.1): Kepler solves, the transition
    // and the quadrature of the input matrix and the noise at every step (summarize.py
    // prints its ratio to `navigator_step_ekf`)
    bench_navigator(
        c,
        "navigator_step_ekf_elliptic",
        NavConfig {
            eccentricity: 0.1,
            ..Default::default()
        },
    );

    for kind in [FilterKind::Ekf, FilterKind::Ukf] {
        let zs = measurements();
        let cfg = NavConfig {
            filter: kind,
            ..Default::default()
        };
        let mut c_cfg = ffi::relnav_config_default();
        c_cfg.filter = kind as i32;
        bench_navigator(c, &format!("navigator_step_{}", kind.name()), cfg);
        let mut est = std::ptr::null_mut();
        // SAFETY: valid pointers; the handle is freed below.
        unsafe { ffi::relnav_estimator_new(&c_cfg, &mut est) };
        let mut k = 0;
        let thrust = [0.0; 3];
        c.bench_function(&format!("capi_step_{}", kind.name()), |b| {
            b.iter(|| {
                // SAFETY: live handle, documented array lengths.
                unsafe {
                    if k == STEPS {
                        k = 0;
                        ffi::relnav_estimator_reset(est);
                    }
                    ffi::relnav_estimator_step(
                        est,
                        thrust.as_ptr(),
                        black_box(zs[k].as_ptr()),
                        1.0,
                    );
                }
                k += 1;
            })
        });
        // SAFETY: freed once.
        unsafe { ffi::relnav_estimator_free(est) };

        // FMU: set the measurement inputs, doStep, read the 12 outputs — one master cycle
        let g = std::ffi::CString::new(guid()).unwrap();
        let cb = fmi2CallbackFunctions {
            logger: None,
            allocateMemory: None,
            freeMemory: None,
            stepFinished: None,
            componentEnvironment: std::ptr::null_mut(),
        };
        // SAFETY: valid arguments; the instance is freed below.
        let comp = unsafe {
            fmi2Instantiate(
                c"bench".as_ptr(),
                fmi2CoSimulation,
                g.as_ptr(),
                std::ptr::null(),
                &cb,
                0,
                0,
            )
        };
        let init = |comp| {
            // SAFETY: live instance.
            unsafe {
                fmi2SetInteger(comp, &vr::FILTER, 1, &(kind as i32));
                fmi2SetupExperiment(comp, 0, 0.0, 0.0, 0, 0.0);
                fmi2EnterInitializationMode(comp);
                fmi2ExitInitializationMode(comp);
            }
        };
        init(comp);
        let ins = [vr::RANGE, vr::AZIMUTH, vr::ELEVATION];
        let outs: Vec<u32> = (vr::X..=vr::SIGMA_VZ).collect();
        let mut y = [0.0; 12];
        let mut k = 0;
        // SAFETY: live instance.
        unsafe { fmi2SetBoolean(comp, &vr::MEASUREMENT_VALID, 1, &1) };
        c.bench_function(&format!("fmu_cycle_{}", kind.name()), |b| {
            b.iter(|| {
                // SAFETY: live instance, matching lengths.
                unsafe {
                    if k == STEPS {
                        k = 0;
                        fmi2Reset(comp);
                        init(comp);
                        fmi2SetBoolean(comp, &vr::MEASUREMENT_VALID, 1, &1);
                    }
                    fmi2SetReal(comp, ins.as_ptr(), 3, zs[k].as_ptr());
                    let st = fmi2DoStep(comp, k as f64, 1.0, 1);
                    debug_assert_eq!(st, fmi2Status::fmi2OK);
                    fmi2GetReal(comp, outs.as_ptr(), 12, y.as_mut_ptr());
                }
                black_box(&y);
                k += 1;
            })
        });
        // SAFETY: freed once.
        unsafe { fmi2FreeInstance(comp) };
    }
}

criterion_group!(benches, filters);
criterion_main!(benches);
