//! No heap allocation per step after construction: a counting global allocator (per
//! thread, so parallel tests do not interfere) around EKF/UKF/AQUKF (both adaptation
//! laws)/IMM and particle-filter steps through the library, the C ABI and the FMU's
//! `fmi2DoStep` / `fmi2SetReal` / `fmi2GetReal`.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)] // test code

use relnav as ffi;
use relnav_core::estimators::AdaptationLaw;
use relnav_core::nav::{FilterKind, NavConfig, Navigator};
use relnav_fmi::fmi2::types::*;
use relnav_nav_model::vr;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

// relnav.fmu's fmi2* functions in this binary, as the FMU's shared library exports them
relnav_fmi::export_fmi2!(relnav_nav_model::RelnavFmu);
relnav_fmi::export_fmi3!(relnav_nav_model::RelnavFmu);

/// relnav.fmu's GUID.
fn guid() -> &'static str {
    relnav_fmi::fmi2::description::guid_of(&relnav_nav_model::INFO)
}

struct Counting;

thread_local! {
    static ALLOCS: Cell<u64> = const { Cell::new(0) };
    /// bytes allocated less bytes freed on this thread
    static LIVE: Cell<i64> = const { Cell::new(0) };
}

// SAFETY: forwards to the system allocator; only counts.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let _ = ALLOCS.try_with(|c| c.set(c.get() + 1));
        let _ = LIVE.try_with(|c| c.set(c.get() + l.size() as i64));
        // SAFETY: same contract as the caller's.
        unsafe { System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        let _ = LIVE.try_with(|c| c.set(c.get() - l.size() as i64));
        // SAFETY: same contract as the caller's.
        unsafe { System.dealloc(p, l) }
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, n: usize) -> *mut u8 {
        let _ = ALLOCS.try_with(|c| c.set(c.get() + 1));
        let _ = LIVE.try_with(|c| c.set(c.get() + n as i64 - l.size() as i64));
        // SAFETY: same contract as the caller's.
        unsafe { System.realloc(p, l, n) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations<F: FnMut()>(mut f: F) -> u64 {
    let before = ALLOCS.with(|c| c.get());
    f();
    ALLOCS.with(|c| c.get()) - before
}

fn measurement(k: usize) -> [f64; 3] {
    let t = k as f64;
    [670.0 + 0.01 * t, 0.896 + 1e-5 * t, 0.30 - 1e-5 * t]
}

#[test]
fn library_and_c_abi_steps_do_not_allocate() {
    // the counter does count
    assert_eq!(
        allocations(|| drop(std::hint::black_box(Box::new(1u64)))),
        1
    );
    // the AQUKF with both laws, the IMM, range-parameterised banks
    for (filter, law, bank) in [
        (FilterKind::Ekf, AdaptationLaw::Gated, 1),
        (FilterKind::Ukf, AdaptationLaw::Gated, 1),
        (FilterKind::Aqukf, AdaptationLaw::Gated, 1),
        (FilterKind::Aqukf, AdaptationLaw::Window, 1),
        (FilterKind::Imm, AdaptationLaw::Gated, 1),
        (FilterKind::Ekf, AdaptationLaw::Gated, 5),
        (FilterKind::Ukf, AdaptationLaw::Gated, 3),
        (FilterKind::Aqukf, AdaptationLaw::Gated, 2),
        (FilterKind::Imm, AdaptationLaw::Gated, 3),
    ] {
        let cfg = NavConfig {
            filter,
            aq_law: law,
            accel_psd: 1e-9,
            range_bank: bank,
            ..Default::default()
        };
        let mut nav = Navigator::new(&cfg).unwrap();
        nav.step(&[0.0; 3], Some(&measurement(0)), 1.0).unwrap(); // warm the step cache
        let n = allocations(|| {
            for k in 1..200 {
                nav.step(&[0.1, 0.0, -0.1], Some(&measurement(k)), 1.0)
                    .unwrap();
            }
            // a new step size re-discretises (Van Loan on the stack): still no heap
            nav.step(&[0.0; 3], None, 0.5).unwrap();
            nav.predict(&[0.0; 3], 2.0).unwrap();
        });
        assert_eq!(
            n, 0,
            "{filter:?} (bank {bank}): {n} allocations in library steps"
        );

        let mut c = ffi::relnav_config_default();
        c.filter = filter as i32;
        c.aq_law = law as i32;
        c.range_bank = bank as _;
        let mut est = std::ptr::null_mut();
        // SAFETY: valid pointers.
        unsafe { ffi::relnav_estimator_new(&c, &mut est) };
        assert!(!est.is_null());
        let thrust = [0.0; 3];
        let mut x = [0.0; 6];
        let mut q = [0.0; 3];
        let mut mu = [0.0; 3];
        let n = allocations(|| {
            for k in 0..200 {
                let z = measurement(k);
                // SAFETY: live handle, arrays of the documented lengths.
                unsafe {
                    assert_eq!(
                        ffi::relnav_estimator_step(est, thrust.as_ptr(), z.as_ptr(), 1.0),
                        ffi::relnav_status::RELNAV_OK
                    );
                    ffi::relnav_estimator_get_state(est, x.as_mut_ptr());
                    ffi::relnav_estimator_get_q_vv(est, q.as_mut_ptr());
                    ffi::relnav_estimator_get_mode_probabilities(est, mu.as_mut_ptr());
                }
            }
        });
        // SAFETY: live handle, freed once.
        unsafe { ffi::relnav_estimator_free(est) };
        assert_eq!(
            n, 0,
            "{filter:?} (bank {bank}): {n} allocations in C-ABI steps"
        );
        if filter == FilterKind::Imm {
            assert!((mu.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{mu:?}");
        }
    }
}

/// The H-infinity filter (code 9): navigator steps (with and without a measurement), C-ABI
/// steps and the standalone runtime filter allocate nothing after the design.
#[cfg(feature = "hinf")]
#[test]
fn hinf_steps_do_not_allocate() {
    let cfg = NavConfig {
        filter: FilterKind::Hinf,
        ..Default::default()
    };
    let mut nav = Navigator::new(&cfg).unwrap();
    let n = allocations(|| {
        for k in 0..200 {
            let z = measurement(k);
            let m = if k % 7 == 3 { None } else { Some(&z) };
            nav.step(&[0.1, 0.0, -0.1], m, 1.0).unwrap();
        }
    });
    assert_eq!(n, 0, "{n} allocations in hinf navigator steps");

    let mut c = ffi::relnav_config_default();
    c.filter = FilterKind::Hinf as i32;
    let mut est = std::ptr::null_mut();
    // SAFETY: valid pointers.
    unsafe { ffi::relnav_estimator_new(&c, &mut est) };
    assert!(!est.is_null());
    let thrust = [0.0; 3];
    let mut x = [0.0; 6];
    let n = allocations(|| {
        for k in 0..200 {
            let z = measurement(k);
            // SAFETY: live handle, arrays of the documented lengths.
            unsafe {
                assert_eq!(
                    ffi::relnav_estimator_step(est, thrust.as_ptr(), z.as_ptr(), 1.0),
                    ffi::relnav_status::RELNAV_OK
                );
                ffi::relnav_estimator_get_state(est, x.as_mut_ptr());
            }
        }
    });
    // SAFETY: live handle, freed once.
    unsafe { ffi::relnav_estimator_free(est) };
    assert_eq!(n, 0, "{n} allocations in hinf C-ABI steps");

    let m = ffi::relnav_hinf_matrices {
        a_f: std::array::from_fn(|i| if i % 7 == 0 { 0.9 } else { 0.0 }),
        b_f: [0.01; 18],
        c_f: std::array::from_fn(|i| if i % 7 == 0 { 1.0 } else { 0.0 }),
        e_f: [0.0; 18],
        period: 1.0,
    };
    let mut f = std::ptr::null_mut();
    // SAFETY: valid pointers.
    unsafe { ffi::relnav_hinf_filter_new(&m, [0.0; 6].as_ptr(), &mut f) };
    assert!(!f.is_null());
    let n = allocations(|| {
        for k in 0..200 {
            let yk = [k as f64, 1.0, 2.0];
            // SAFETY: live handle, arrays of the documented lengths.
            unsafe {
                assert_eq!(
                    ffi::relnav_hinf_filter_step(f, yk.as_ptr(), thrust.as_ptr()),
                    ffi::relnav_status::RELNAV_OK
                );
                ffi::relnav_hinf_filter_get_state(f, x.as_mut_ptr());
            }
        }
    });
    // SAFETY: live handle, freed once.
    unsafe { ffi::relnav_hinf_filter_free(f) };
    assert_eq!(n, 0, "{n} allocations in runtime hinf filter steps");
}

/// `fmi2DoStep` cycles (set inputs, step, get the 12 estimate outputs, `ess`, `q_vv_*`,
/// `hinf_gamma` and `imm_mu_*`) for the EKF, the AQUKF (both laws), two particle filters,
/// the H-infinity filter and the IMM.
#[test]
fn fmu_do_step_does_not_allocate() {
    for (filter, law) in [(1, 2), (3, 2), (3, 1), (5, 2), (8, 2), (9, 2), (10, 2)] {
        fmu_cycles_do_not_allocate(filter, law);
    }
}

/// The same through FMI 3.0 (`relnav3.fmu`): set the `measurement` array and its flag,
/// `fmi3DoStep`, get the `position`, `velocity` and `sigma` arrays and the 6x6
/// `covariance` in one call.
#[test]
fn fmi3_do_step_does_not_allocate() {
    use relnav_fmi::fmi3::description::vr_of;
    use relnav_fmi::fmi3::types::fmi3Status;
    let info = &*relnav_nav_model::INFO;
    for filter in [1, 2, 3, 5, 9, 10] {
        let c =
            relnav_fmi::fmi3::functions::instantiate_plain::<relnav_nav_model::RelnavFmu>(c"alloc");
        assert!(!c.is_null());
        let meas = [vr_of(info, "measurement").unwrap()];
        let outs = ["position", "velocity", "sigma", "covariance"].map(|n| vr_of(info, n).unwrap());
        let mut y = [0.0; 48];
        let (mut event, mut terminate, mut early, mut last) = (false, false, false, 0.0);
        // SAFETY: a live instance, arrays of matching lengths.
        unsafe {
            assert_eq!(
                fmi3SetInt32(
                    c,
                    [vr::FILTER, vr::PARTICLES].as_ptr(),
                    2,
                    [filter, 300].as_ptr(),
                    2
                ),
                fmi3Status::fmi3OK
            );
            assert_eq!(
                fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0),
                fmi3Status::fmi3OK
            );
            assert_eq!(fmi3ExitInitializationMode(c), fmi3Status::fmi3OK);
        }
        let n = allocations(|| {
            for k in 0..200 {
                let z = measurement(k);
                // SAFETY: as above.
                unsafe {
                    assert_eq!(
                        fmi3SetFloat64(c, meas.as_ptr(), 1, z.as_ptr(), 3),
                        fmi3Status::fmi3OK
                    );
                    assert_eq!(
                        fmi3SetBoolean(c, &vr::MEASUREMENT_VALID, 1, &true, 1),
                        fmi3Status::fmi3OK
                    );
                    assert_eq!(
                        fmi3DoStep(
                            c,
                            k as f64,
                            1.0,
                            true,
                            &mut event,
                            &mut terminate,
                            &mut early,
                            &mut last
                        ),
                        fmi3Status::fmi3OK
                    );
                    assert_eq!(
                        fmi3GetFloat64(c, outs.as_ptr(), 4, y.as_mut_ptr(), 48),
                        fmi3Status::fmi3OK
                    );
                }
            }
        });
        // SAFETY: freed once.
        unsafe { fmi3FreeInstance(c) };
        assert_eq!(
            n, 0,
            "filter {filter}: {n} allocations in 200 fmi3DoStep cycles"
        );
    }
}

fn fmu_cycles_do_not_allocate(filter: i32, law: i32) {
    let g = std::ffi::CString::new(guid()).unwrap();
    let cb = fmi2CallbackFunctions {
        logger: None,
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: std::ptr::null_mut(),
    };
    // SAFETY: valid strings and callbacks for the call.
    let c = unsafe {
        fmi2Instantiate(
            c"alloc".as_ptr(),
            fmi2CoSimulation,
            g.as_ptr(),
            std::ptr::null(),
            &cb,
            0,
            0,
        )
    };
    assert!(!c.is_null());
    // SAFETY: live instance, arrays of matching lengths.
    unsafe {
        assert_eq!(
            fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0),
            fmi2Status::fmi2OK
        );
        assert_eq!(
            fmi2SetInteger(
                c,
                [vr::FILTER, vr::PARTICLES, vr::WINDOW, vr::AQ_LAW].as_ptr(),
                4,
                [filter, 300, 5, law].as_ptr()
            ),
            fmi2Status::fmi2OK
        );
        assert_eq!(fmi2EnterInitializationMode(c), fmi2Status::fmi2OK);
        assert_eq!(fmi2ExitInitializationMode(c), fmi2Status::fmi2OK);
    }
    let ins = [vr::RANGE, vr::AZIMUTH, vr::ELEVATION];
    // the estimate, then the filters' diagnostics
    let mut outs = [0u32; 20];
    outs[..12].copy_from_slice(&relnav_nav_model::identity::ESTIMATE);
    outs[12..].copy_from_slice(&[
        vr::ESS,
        vr::Q_VV_X,
        vr::Q_VV_Y,
        vr::Q_VV_Z,
        vr::HINF_GAMMA,
        vr::IMM_MU_1,
        vr::IMM_MU_2,
        vr::IMM_MU_3,
    ]);
    let valid = [vr::MEASUREMENT_VALID];
    let mut y = [0.0; 20];
    let n = allocations(|| {
        for k in 0..200 {
            let z = measurement(k);
            // SAFETY: as above.
            unsafe {
                assert_eq!(
                    fmi2SetReal(c, ins.as_ptr(), 3, z.as_ptr()),
                    fmi2Status::fmi2OK
                );
                assert_eq!(
                    fmi2SetBoolean(c, valid.as_ptr(), 1, [1].as_ptr()),
                    fmi2Status::fmi2OK
                );
                assert_eq!(fmi2DoStep(c, k as f64, 1.0, 1), fmi2Status::fmi2OK);
                assert_eq!(
                    fmi2GetReal(c, outs.as_ptr(), 20, y.as_mut_ptr()),
                    fmi2Status::fmi2OK
                );
            }
        }
    });
    // SAFETY: live instance, freed once.
    unsafe { fmi2FreeInstance(c) };
    assert_eq!(
        n, 0,
        "filter {filter} (aq_law {law}): {n} allocations in 200 fmi2DoStep cycles"
    );
}

/// Every particle-filter kind (codes 4-8), with and without the moves, with every
/// resampler and a heavy-tailed noise model: the first step after construction (the first
/// update initialises the particles from the measurement) and every later step
/// (weighting, resampling, rejuvenation, regularisation or genetic moves, UKF proposals,
/// a new step size, steps without measurement) allocate nothing, through the library and
/// the C ABI (with the ess getter). This holds below `PARALLEL_MIN_PARTICLES` particles;
/// from there on the particle loops run in chunks on worker threads, which allocates a
/// few vectors per loop (ARCHITECTURE.md, invariants).
#[test]
fn particle_filter_steps_do_not_allocate() {
    use relnav_core::estimators::pf::{PfPrior, PARALLEL_MIN_PARTICLES};
    use relnav_core::nav::NoiseKind;
    use relnav_core::nav::ResamplerSetting;
    const PARTICLES: usize = 300;
    const { assert!(PARTICLES < PARALLEL_MIN_PARTICLES) };
    let kinds = [
        FilterKind::Pf,
        FilterKind::Rpf,
        FilterKind::Upf,
        FilterKind::Gapf,
        FilterKind::Cgapf,
    ];
    // the moved and the literal filters, and the particle prior (a Gaussian per particle)
    for (i, (filter, pf_move, pf_prior)) in kinds
        .into_iter()
        .flat_map(|k| {
            [
                (k, true, PfPrior::Gaussian),
                (k, false, PfPrior::Gaussian),
                (k, true, PfPrior::Particle),
            ]
        })
        .enumerate()
    {
        let cfg = NavConfig {
            filter,
            pf_move,
            pf_prior,
            particles: PARTICLES,
            resampler: ResamplerSetting::ALL[i % 5],
            noise_model: if i % 2 == 0 {
                NoiseKind::Gaussian
            } else {
                NoiseKind::Mixture
            },
            seed: 7,
            ..Default::default()
        };
        let mut nav = Navigator::new(&cfg).unwrap();
        let first = allocations(|| {
            nav.step(&[0.0; 3], Some(&measurement(0)), 1.0).unwrap();
        });
        assert_eq!(
            first, 0,
            "{filter:?} (pf_move {pf_move}, {pf_prior:?}): {first} allocations in the first step"
        );
        let mut resampled = 0;
        let n = allocations(|| {
            for k in 1..60 {
                nav.step(&[0.1, 0.0, -0.1], Some(&measurement(k)), 1.0)
                    .unwrap();
                if nav.ess().unwrap_or(0.0) < 200.0 {
                    resampled += 1;
                }
            }
            nav.step(&[0.0; 3], None, 0.5).unwrap();
            nav.predict(&[0.0; 3], 2.0).unwrap();
            nav.step(&[0.0; 3], Some(&measurement(61)), 1.0).unwrap();
        });
        assert_eq!(
            n, 0,
            "{filter:?} (pf_move {pf_move}, {pf_prior:?}): {n} allocations in library steps"
        );
        assert!(
            resampled > 0,
            "{filter:?} (pf_move {pf_move}, {pf_prior:?}): never resampled"
        );

        let mut c = ffi::relnav_config_default();
        c.filter = filter as i32;
        c.pf_move = i32::from(pf_move);
        c.pf_prior = pf_prior as i32;
        c.particles = PARTICLES as i32;
        let mut est = std::ptr::null_mut();
        // SAFETY: valid pointers.
        unsafe { ffi::relnav_estimator_new(&c, &mut est) };
        assert!(!est.is_null());
        let thrust = [0.0; 3];
        let mut x = [0.0; 6];
        let mut ess = 0.0;
        let n = allocations(|| {
            for k in 0..60 {
                let z = measurement(k);
                // SAFETY: live handle, arrays of the documented lengths.
                unsafe {
                    assert_eq!(
                        ffi::relnav_estimator_step(est, thrust.as_ptr(), z.as_ptr(), 1.0),
                        ffi::relnav_status::RELNAV_OK
                    );
                    ffi::relnav_estimator_get_state(est, x.as_mut_ptr());
                    ffi::relnav_estimator_get_ess(est, &mut ess);
                }
            }
        });
        // SAFETY: live handle, freed once.
        unsafe { ffi::relnav_estimator_free(est) };
        assert_eq!(
            n, 0,
            "{filter:?} (pf_move {pf_move}, {pf_prior:?}): {n} allocations in C-ABI steps"
        );
        assert!(
            (1.0..=300.0).contains(&ess),
            "{filter:?} (pf_move {pf_move}, {pf_prior:?}): ess {ess}"
        );
    }
}

/// The configuration of the sensor-step tests: `filter` with 300 particles and a white
/// acceleration that keeps every covariance positive definite.
fn sensor_config(filter: FilterKind) -> NavConfig {
    NavConfig {
        filter,
        particles: 300,
        accel_psd: 1e-9,
        ..Default::default()
    }
}

/// Steps with a sensor added beside the radio (the generic path, `Navigator::step_with`)
/// allocate nothing either, in every filter but the H-infinity one (whose test above
/// covers it with the radio).
#[test]
fn steps_with_added_sensors_do_not_allocate() {
    use relnav_core::nav::Named;
    use relnav_core::sensors::{CartesianSensor, Modelled, SensorNoise};
    use std::sync::Arc;
    for filter in FilterKind::ALL {
        if filter == FilterKind::Hinf {
            continue;
        }
        let cfg = sensor_config(filter);
        let mut nav = Navigator::new(&cfg).unwrap();
        let fix = Modelled {
            model: CartesianSensor {
                frame: cfg.frame,
                sigma: 2.0,
            },
            noise: SensorNoise::gaussian([2.0; 3]),
        };
        nav.add_sensor(Arc::new(Named::new("position", fix)));
        // the radio's reading as a position in the same frame
        let position = |k: usize| {
            let [rho, az, el] = measurement(k);
            [
                rho * el.cos() * az.cos(),
                rho * el.cos() * az.sin(),
                rho * el.sin(),
            ]
        };
        let p0 = position(0);
        nav.step_with(&[0.0; 3], Some(&measurement(0)), &[Some(&p0[..])], 1.0)
            .unwrap();
        let n = allocations(|| {
            for k in 1..60 {
                let p = position(k);
                let reading = [(k % 2 == 0).then_some(&p[..])];
                nav.step_with(&[0.1, 0.0, -0.1], Some(&measurement(k)), &reading, 1.0)
                    .unwrap();
            }
        });
        assert_eq!(
            n, 0,
            "{filter:?}: {n} allocations in steps with an added sensor"
        );
        assert!(nav.sensor_report(0).is_some());
    }
}

/// The declared sensors' steps (`Navigator::step_readings`: the radio, the camera and
/// relative GNSS together) allocate nothing either, an added sensor present or not; the
/// H-infinity filter with a design for all four (`hinf_sensors` = 15) included.
#[test]
fn declared_sensor_steps_do_not_allocate() {
    use relnav_core::nav::{Named, Readings};
    use relnav_core::sensors::VelocitySensor;
    use std::sync::Arc;
    let banks = [FilterKind::Ekf, FilterKind::Ukf, FilterKind::Imm].map(|f| (f, 3));
    let singles = FilterKind::ALL.map(|f| (f, 1));
    for (filter, bank) in singles.into_iter().chain(banks) {
        let cfg = NavConfig {
            range_bank: bank,
            hinf_sensors: 15,
            ..sensor_config(filter)
        };
        let mut nav = Navigator::new(&cfg).unwrap();
        nav.add_sensor(Arc::new(Named::new(
            "velocity",
            VelocitySensor::gaussian(cfg.frame, 1e-3),
        )));
        let readings = |k: usize| {
            let [rho, az, el] = measurement(k);
            Readings {
                radio: Some([rho, az, el]),
                camera: Some([az, el]),
                gnss_position: k.is_multiple_of(2).then(|| {
                    [
                        rho * el.cos() * az.cos(),
                        rho * el.cos() * az.sin(),
                        rho * el.sin(),
                    ]
                }),
                gnss_velocity: None,
            }
        };
        nav.step_readings(&[0.0; 3], &readings(0), 1.0).unwrap();
        let n = allocations(|| {
            for k in 1..60 {
                nav.step_readings(&[0.1, 0.0, -0.1], &readings(k), 1.0)
                    .unwrap();
            }
        });
        assert_eq!(
            n, 0,
            "{filter:?} (bank {bank}): {n} allocations in declared-sensor steps"
        );
    }
}

/// Making a Kalman-type navigator allocates nothing, in the full library too (the declared
/// sensors' names are static texts): an estimator made in the caller's storage is then
/// heap-free from the start, and one whose making fails leaves nothing behind (the caller
/// never ends such a handle; a particle filter's or a bank's heap is given back on that
/// path by `Navigator::new_in`).
#[test]
fn making_a_kalman_navigator_does_not_allocate() {
    for filter in [
        FilterKind::Ekf,
        FilterKind::Ukf,
        FilterKind::Aqukf,
        FilterKind::Imm,
        FilterKind::Rekf,
    ] {
        let cfg = NavConfig {
            filter,
            ..NavConfig::default()
        };
        let mut slot = std::mem::MaybeUninit::<Navigator>::uninit();
        let n = allocations(|| {
            Navigator::new_in(&cfg, &mut slot).unwrap();
        });
        assert_eq!(n, 0, "{filter:?}: {n} allocations");
        let n = allocations(|| drop(Navigator::new(&cfg).unwrap()));
        assert_eq!(n, 0, "{filter:?}: {n} allocations");
    }
}
