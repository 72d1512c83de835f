//! Bounded time, no panic, for every input: the inputs that hung or panicked inside
//! nalgebra's matrix exponential (reached from the Van Loan noise via
//! `Navigator::predict`), the FMU steps of 1e45 and 1e300 s, random fmi2 and fmi3 call
//! sequences with such steps, and the crashes the fuzz targets found (fuzz/README.md), each as a
//! readable Rust test.
//!
//! Every call runs under [`bounded`], a generous hang detector (10 s for work that takes
//! microseconds to milliseconds; it is not a speed target, criterion benches are).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)] // test code

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use relnav::*;
use relnav_core::nav::{FilterKind, NavConfig, NavErrorKind, Navigator, MAX_STEP_PERIODS};
use relnav_fmi::fmi2::types::*;
use relnav_nav_model::VARIABLES;
use std::ffi::{CStr, CString};
use std::sync::mpsc;
use std::time::Duration;

// relnav.fmu's fmi2* functions in this binary, as the FMU's shared library exports them
relnav_fmi::export_fmi2!(relnav_nav_model::RelnavFmu);
// and its fmi3* functions (relnav3.fmu: the same library)
relnav_fmi::export_fmi3!(relnav_nav_model::RelnavFmu);

/// relnav.fmu's GUID.
fn guid() -> &'static str {
    relnav_fmi::fmi2::description::guid_of(&relnav_nav_model::INFO)
}

/// Hang detector: run `f` on its own thread and fail when it has not returned within
/// 10 s (a hung thread is left behind; the test fails either way).
fn bounded<T: Send + 'static>(what: &str, f: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    match rx.recv_timeout(Duration::from_secs(10)) {
        Ok(v) => v,
        Err(mpsc::RecvTimeoutError::Timeout) => panic!("{what}: no return within 10 s"),
        Err(mpsc::RecvTimeoutError::Disconnected) => panic!("{what}: panicked"),
    }
}

fn last_error() -> String {
    // SAFETY: relnav_last_error returns a valid NUL-terminated string.
    unsafe { CStr::from_ptr(relnav_last_error()) }
        .to_string_lossy()
        .into_owned()
}

/// Filter codes this build implements, with a particle count that keeps the tests quick.
fn configs() -> Vec<NavConfig> {
    FilterKind::ALL
        .into_iter()
        .filter(|k| k.is_implemented())
        .map(|filter| NavConfig {
            filter,
            particles: 200,
            accel_psd: 1e-9, // the Van Loan path of every discretisation
            ..Default::default()
        })
        .collect()
}

const Z: [f64; 3] = [670.8, 0.8961, 0.3025];

/// The reported hangs' inputs: steps of 1e45 and 1e300 s (and the other extremes) are
/// refused at once, with a message naming the limit, by every filter, through predict and
/// step; the estimate is unchanged.
#[test]
fn absurd_steps_are_refused_with_the_limit_named() {
    for cfg in configs() {
        bounded(cfg.filter.name(), move || {
            let mut nav = Navigator::new(&cfg).unwrap();
            let x = nav.state();
            let limit = nav.max_step();
            assert_eq!(
                limit,
                MAX_STEP_PERIODS * std::f64::consts::TAU / cfg.mean_motion
            );
            for dt in [limit * (1.0 + 1e-12), 1e45, 1e300, f64::MAX] {
                for r in [
                    nav.predict(&[0.0; 3], dt),
                    nav.step(&[0.0; 3], Some(&Z), dt),
                    nav.step(&[1.0, 0.0, 0.0], None, dt),
                ] {
                    let e = r.unwrap_err();
                    assert_eq!(e.kind, NavErrorKind::InvalidArgument, "{}", e.message);
                    assert!(e.message.contains("orbital periods"), "{}", e.message);
                }
                assert_eq!(
                    nav.state(),
                    x,
                    "{:?}: a refused step changed the estimate",
                    cfg.filter
                );
            }
        });
    }
}

/// Legitimate huge-but-finite steps below the limit (down to 1000 orbits at the slowest
/// accepted mean motion, 6e12 s) come back as a value or an error, for every filter.
#[test]
fn huge_legitimate_steps_return_a_value_or_an_error() {
    for mean_motion in [2.0 * std::f64::consts::PI / 7200.0, 1e-9, 0.1] {
        for base in configs() {
            let cfg = NavConfig {
                mean_motion,
                ..base
            };
            bounded(cfg.filter.name(), move || {
                let Ok(mut nav) = Navigator::new(&cfg) else {
                    // the H-infinity design may be infeasible at extreme rates: an error
                    return;
                };
                let limit = nav.max_step();
                for dt in [limit * (1.0 - 1e-12), limit / 3.0, 1e6, 1e-300] {
                    for _ in 0..3 {
                        let _ = nav.step(&[0.0; 3], Some(&Z), dt);
                        let _ = nav.predict(&[0.5, -0.5, 0.1], dt);
                        let _ = nav.update(&Z);
                    }
                    // whatever happened, the estimate is a number or the filter said why
                    let _ = (nav.state(), nav.covariance());
                    nav.reset();
                }
            });
        }
    }
}

/// The reported AQUKF hang: `fmi2DoStep` with a step of 1e45 s (filter 3, every other
/// parameter at its default) must fail at once with a logged reason, and so must 1e300
/// and the largest double; the instance can be reset.
#[test]
fn fmu_step_of_1e45_on_the_aqukf_returns_an_error() {
    bounded("fmi2DoStep(1e45)", || {
        for h in [1e45, 1e300, f64::MAX] {
            let c = instantiate();
            // SAFETY: live instance; one element each.
            unsafe {
                let filter = vr_named("filter");
                assert_eq!(fmi2SetInteger(c, &filter, 1, &3), fmi2Status::fmi2OK);
                assert_eq!(
                    fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0),
                    fmi2Status::fmi2OK
                );
                assert_eq!(fmi2EnterInitializationMode(c), fmi2Status::fmi2OK);
                assert_eq!(fmi2ExitInitializationMode(c), fmi2Status::fmi2OK);
                assert_eq!(fmi2DoStep(c, 0.0, 1.0, 0), fmi2Status::fmi2OK);
                assert_eq!(fmi2DoStep(c, 1.0, h, 0), fmi2Status::fmi2Error);
                assert_eq!(fmi2Reset(c), fmi2Status::fmi2OK);
                fmi2FreeInstance(c);
            }
        }
    });
}

fn instantiate() -> fmi2Component {
    let g = CString::new(guid()).unwrap();
    let cb = fmi2CallbackFunctions {
        logger: None,
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: std::ptr::null_mut(),
    };
    // SAFETY: valid strings and callbacks for the duration of the call.
    let c = unsafe {
        fmi2Instantiate(
            c"robust".as_ptr(),
            fmi2CoSimulation,
            g.as_ptr(),
            std::ptr::null(),
            &cb,
            0,
            0,
        )
    };
    assert!(!c.is_null());
    c
}

fn vr_named(name: &str) -> u32 {
    VARIABLES.iter().find(|v| v.name == name).unwrap().vr
}

/// Random fmi2 call sequences: 300 sequences (seeded) of parameter changes,
/// initialisation, inputs and steps of random sizes including 1e45 and 1e300 s, over the
/// filters 1-8 (the H-infinity design runs in the C-ABI tests). Every sequence returns;
/// no call returns fmi2Fatal (a caught panic).
#[test]
fn random_fmi2_sequences_with_absurd_steps_return() {
    let steps = [1.0, 0.1, 10.0, 1e45, 1e300, 7200.0 * 999.0, 1e-9, f64::MAX];
    for seq in 0..300u64 {
        bounded(&format!("sequence {seq}"), move || {
            let mut rng = ChaCha8Rng::seed_from_u64(seq);
            let c = instantiate();
            let filter: i32 = rng.random_range(1..=8);
            let mut t = 0.0;
            // SAFETY: live instance; one element per call.
            unsafe {
                let vr = vr_named("filter");
                assert_eq!(fmi2SetInteger(c, &vr, 1, &filter), fmi2Status::fmi2OK);
                let vr = vr_named("particles");
                assert_eq!(fmi2SetInteger(c, &vr, 1, &100), fmi2Status::fmi2OK);
                let vr = vr_named("accel_psd");
                let psd = [0.0, 1e-9, 1e-3][rng.random_range(0..3)];
                assert_eq!(fmi2SetReal(c, &vr, 1, &psd), fmi2Status::fmi2OK);
                fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0);
                fmi2EnterInitializationMode(c);
                assert_eq!(fmi2ExitInitializationMode(c), fmi2Status::fmi2OK);
                for _ in 0..40 {
                    let st = match rng.random_range(0..6) {
                        0 => {
                            let valid = i32::from(rng.random::<bool>());
                            let vr = vr_named("measurement_valid");
                            fmi2SetBoolean(c, &vr, 1, &valid)
                        }
                        1 => {
                            let refs = [
                                vr_named("range"),
                                vr_named("azimuth"),
                                vr_named("elevation"),
                            ];
                            let z = [
                                670.0 * rng.random::<f64>(),
                                6.0 * rng.random::<f64>(),
                                rng.random::<f64>() - 0.5,
                            ];
                            fmi2SetReal(c, refs.as_ptr(), 3, z.as_ptr())
                        }
                        2 => {
                            let vr = vr_named("thrust_x");
                            let f = [0.0, 1.0, -50.0, 1e45][rng.random_range(0..4)];
                            fmi2SetReal(c, &vr, 1, &f)
                        }
                        3 => fmi2Reset(c).min(fmi2Status::fmi2OK),
                        _ => {
                            let h = steps[rng.random_range(0..steps.len())];
                            let st = fmi2DoStep(c, t, h, 0);
                            if st == fmi2Status::fmi2OK {
                                t += h;
                            }
                            st
                        }
                    };
                    assert_ne!(st, fmi2Status::fmi2Fatal, "sequence {seq}");
                    if st == fmi2Status::fmi2Error {
                        // the master's way out of the error state
                        assert_eq!(fmi2Reset(c), fmi2Status::fmi2OK);
                        let vr = vr_named("filter");
                        fmi2SetInteger(c, &vr, 1, &filter);
                        fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0);
                        fmi2EnterInitializationMode(c);
                        fmi2ExitInitializationMode(c);
                        t = 0.0;
                    }
                }
                fmi2FreeInstance(c);
            }
        });
    }
}

/// Random fmi3 call sequences: 300 sequences (seeded), with and without Event Mode, of
/// parameter changes, array and scalar sets and gets with right and wrong value counts and
/// unknown value references, Event Mode entries and discrete updates in and out of order,
/// steps of random sizes including 1e45 and 1e300 s, FMU state round trips, over the
/// filters 1-8. Every sequence returns; no call returns fmi3Fatal (a caught panic); after
/// any error the master's way out (`fmi3Reset`) works.
/// A relnav3.fmu instance made with `eventModeUsed` (its initialisation ends in Event Mode).
fn instantiate_event_mode(name: &CStr) -> relnav_fmi::fmi3::types::fmi3Instance {
    let info = &*relnav_nav_model::INFO;
    let token = CString::new(relnav_fmi::fmi3::description::token_of(info)).unwrap();
    // SAFETY: valid strings, null pointers where the standard allows them.
    unsafe {
        fmi3InstantiateCoSimulation(
            name.as_ptr(),
            token.as_ptr(),
            std::ptr::null(),
            false,
            false,
            true,
            false,
            std::ptr::null(),
            0,
            std::ptr::null_mut(),
            None,
            None,
        )
    }
}

#[test]
fn random_fmi3_sequences_return() {
    use relnav_fmi::fmi3::description::{vr_of, TIME_VR};
    use relnav_fmi::fmi3::functions::instantiate_plain;
    use relnav_fmi::fmi3::types::fmi3Status;
    let steps = [
        1.0,
        0.1,
        10.0,
        1e45,
        1e300,
        7200.0 * 999.0,
        1e-9,
        f64::MAX,
        -1.0,
        f64::NAN,
    ];
    let info = &*relnav_nav_model::INFO;
    let arrays = [
        "measurement",
        "thrust",
        "position",
        "sigma",
        "covariance",
        "camera",
    ]
    .map(|n| vr_of(info, n).unwrap());
    for seq in 0..300u64 {
        bounded(&format!("fmi3 sequence {seq}"), move || {
            let mut rng = ChaCha8Rng::seed_from_u64(seq);
            let event = rng.random::<bool>();
            let c = if event {
                instantiate_event_mode(c"robust3")
            } else {
                instantiate_plain::<relnav_nav_model::RelnavFmu>(c"robust3")
            };
            assert!(!c.is_null());
            let filter: i32 = rng.random_range(1..=8);
            let mut t = 0.0;
            let init = |c, filter: i32| {
                // SAFETY: live instance; one element per call.
                unsafe {
                    let vr = vr_named("filter");
                    fmi3SetInt32(c, &vr, 1, &filter, 1);
                    let vr = vr_named("particles");
                    fmi3SetInt32(c, &vr, 1, &100, 1);
                    fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0);
                    fmi3ExitInitializationMode(c)
                }
            };
            assert_eq!(init(c, filter), fmi3Status::fmi3OK);
            let mut buf = [0.0f64; 64];
            for _ in 0..40 {
                let a = arrays[rng.random_range(0..arrays.len())];
                let n = rng.random_range(0..40usize);
                let (mut e, mut ts, mut er, mut last) = (false, false, false, 0.0);
                let mut flags = [false; 5];
                let mut next = 0.0;
                // SAFETY: live instance; `buf` holds at least `n` values and `flags` five.
                let st = unsafe {
                    match rng.random_range(0..10) {
                        0 => {
                            for v in buf.iter_mut().take(n) {
                                *v = [1.0, -1e300, f64::NAN, 670.0][rng.random_range(0..4)];
                            }
                            fmi3SetFloat64(c, &a, 1, buf.as_ptr(), n)
                        }
                        1 => fmi3GetFloat64(c, &a, 1, buf.as_mut_ptr(), n),
                        2 => {
                            let r = [a, TIME_VR, 12_345, 20_001][rng.random_range(0..4)];
                            fmi3GetFloat64(c, &r, 1, buf.as_mut_ptr(), n)
                        }
                        3 => {
                            let vr = vr_named("measurement_valid");
                            fmi3SetBoolean(c, &vr, 1, &rng.random::<bool>(), 1)
                        }
                        4 => fmi3EnterEventMode(c),
                        5 => fmi3EnterStepMode(c),
                        6 => fmi3UpdateDiscreteStates(
                            c,
                            &mut flags[0],
                            &mut flags[1],
                            &mut flags[2],
                            &mut flags[3],
                            &mut flags[4],
                            &mut next,
                        ),
                        7 => {
                            let mut s = std::ptr::null_mut();
                            let got = fmi3GetFMUState(c, &mut s);
                            let set = fmi3SetFMUState(c, s);
                            fmi3FreeFMUState(c, &mut s);
                            got.max(set)
                        }
                        _ => {
                            let h = steps[rng.random_range(0..steps.len())];
                            let st = fmi3DoStep(c, t, h, true, &mut e, &mut ts, &mut er, &mut last);
                            if st == fmi3Status::fmi3OK {
                                t += h;
                            }
                            st
                        }
                    }
                };
                assert_ne!(st, fmi3Status::fmi3Fatal, "fmi3 sequence {seq}");
                if st == fmi3Status::fmi3Error {
                    // SAFETY: live instance.
                    assert_eq!(unsafe { fmi3Reset(c) }, fmi3Status::fmi3OK);
                    init(c, filter);
                    t = 0.0;
                }
            }
            // SAFETY: freed once.
            unsafe { fmi3FreeInstance(c) };
        });
    }
}

/// A particle filter's Gaussian prior (before its first measurement) with the widest
/// accepted velocity uncertainty (1e147 m/s: `|v0| + 100 sigma` stays below
/// `MAX_INITIAL_MAGNITUDE` and its variance is finite), predicted over
/// the longest accepted steps at the slowest mean motion, overflows to infinity; the first
/// measurement then took the square root of an infinite matrix (nalgebra's eigensolver:
/// an endless loop or a panic). The prediction now refuses to produce non-finite particle
/// moments or prior, and the estimate stays usable.
#[test]
fn particle_prior_never_overflows_into_the_eigensolver() {
    for filter in [FilterKind::Pf, FilterKind::Upf, FilterKind::Cgapf] {
        bounded(filter.name(), move || {
            let cfg = NavConfig {
                filter,
                mean_motion: 1e-9,
                sigma_vel0: 1e147,
                particles: 100,
                ..Default::default()
            };
            let mut nav = Navigator::new(&cfg).unwrap();
            let dt = nav.max_step() * 0.99;
            let mut refused = false;
            for _ in 0..40 {
                match nav.predict(&[0.0; 3], dt) {
                    Ok(()) => assert!(nav.state().iter().all(|v| v.is_finite())),
                    Err(e) => {
                        assert_eq!(e.kind, NavErrorKind::Numerical, "{}", e.message);
                        refused = true;
                        break;
                    }
                }
            }
            assert!(
                refused,
                "{filter:?}: 40 predictions of 6e12 s from 1e147 m/s stayed finite?"
            );
            let _ = nav.update(&Z);
            nav.reset();
            nav.step(&[0.0; 3], Some(&Z), 1.0).unwrap();
        });
    }
}

/// Through the C ABI: the same absurd steps give `RELNAV_ERROR_INVALID_ARGUMENT` and a
/// message, never `RELNAV_ERROR_PANIC`.
#[test]
fn c_abi_absurd_steps_give_an_error_status_and_message() {
    bounded("C ABI", || {
        for f in [1, 2, 3, 4, 6] {
            let mut c = relnav_config_default();
            c.filter = f;
            c.particles = 100;
            c.accel_psd = 1e-6;
            let mut e = std::ptr::null_mut();
            // SAFETY: valid pointers; live handle afterwards; 3-element arrays.
            unsafe {
                assert_eq!(relnav_estimator_new(&c, &mut e), relnav_status::RELNAV_OK);
                for dt in [1e45, 1e300, f64::MAX] {
                    let st = relnav_estimator_predict(e, [0.0; 3].as_ptr(), dt);
                    assert_eq!(st, relnav_status::RELNAV_ERROR_INVALID_ARGUMENT);
                    assert!(last_error().contains("orbital periods"), "{}", last_error());
                    let st = relnav_estimator_step(e, [0.0; 3].as_ptr(), Z.as_ptr(), dt);
                    assert_eq!(st, relnav_status::RELNAV_ERROR_INVALID_ARGUMENT);
                }
                relnav_estimator_free(e);
            }
        }
    });
}

/// The H-infinity design at the edges of its validated domain (tiny and huge scalings,
/// the longest period its check allows, a huge uncertainty bound) returns a design or an
/// error: every eigen and singular value computation in the design and its verification
/// is iteration-capped, and Clarabel's iterations are capped.
#[cfg(feature = "hinf")]
#[test]
fn hinf_design_at_the_edges_returns() {
    use relnav_core::hinf::design::{design_open_loop, DesignOptions};
    use relnav_core::hinf::HinfSpec;
    let base = HinfSpec {
        w0: 2.0 * std::f64::consts::PI / 7200.0,
        ..HinfSpec::paper()
    };
    let specs = [
        HinfSpec {
            b_pos: 1e-300,
            b_vel: 1e-300,
            d: 1e-300,
            ..base
        },
        HinfSpec {
            b_pos: 1e300,
            ..base
        },
        HinfSpec { d: 1e300, ..base },
        HinfSpec {
            delta_bar: 1e300,
            ..base
        },
        HinfSpec {
            period: 0.5 / base.w0,
            ..base
        },
        HinfSpec {
            period: 1e-300,
            ..base
        },
        HinfSpec {
            w0: 1e-9,
            period: 1.0,
            ..base
        },
    ];
    for (k, spec) in specs.into_iter().enumerate() {
        bounded(&format!("hinf design {k}"), move || {
            let _ = design_open_loop(&spec, &DesignOptions::default());
        });
    }
}

/// Fuzz finding (capi): a GA-PF configured with `z0 = f64::MAX` (finite, so accepted) drew
/// its initial particles `x0 + sigma eps` into infinity: the estimator was created, and its
/// state and every reset were NaN. The configuration is now refused (`|x0_i| + 100 sigma`
/// must stay below 1e150: covariances are squares), the C ABI's validate and new agree, and the largest accepted
/// initial estimate gives a finite state in every filter.
#[test]
fn fuzz_initial_estimate_near_the_largest_double() {
    for base in configs() {
        bounded(base.filter.name(), move || {
            // the whole configuration moved in (a closure capturing only `base.filter`
            // next to `..base` crashes rustc 1.95: broken MIR on the IMM array lengths)
            let base = base;
            let mut x0 = base.x0;
            x0[2] = f64::MAX;
            let bad = NavConfig { x0, ..base };
            let e = bad.validate().unwrap_err();
            assert!(e.message.contains("z0"), "{}", e.message);
            assert!(Navigator::new(&bad).is_err());
            let mut c = relnav_config::from(&bad);
            c.x0[2] = f64::MAX;
            let mut est = std::ptr::null_mut();
            // SAFETY: valid pointers.
            unsafe {
                assert_eq!(
                    relnav_config_validate(&c),
                    relnav_status::RELNAV_ERROR_INVALID_ARGUMENT
                );
                assert_eq!(
                    relnav_estimator_new(&c, &mut est),
                    relnav_status::RELNAV_ERROR_INVALID_ARGUMENT
                );
            }
            assert!(est.is_null());
            // the largest accepted: a finite estimate, before and after reset and a step
            // (the mixed H-infinity design derives its measurement noise at the initial
            // range, here 1e150 m: its solver may refuse that, with an error)
            x0[2] = 1e150 - 100.0 * base.sigma_pos0;
            let ok = NavConfig { x0, ..base };
            let mut nav = match Navigator::new(&ok) {
                Ok(nav) => nav,
                Err(e) if base.filter == FilterKind::Hinf => {
                    assert_eq!(e.kind, NavErrorKind::InvalidArgument, "{}", e.message);
                    return;
                }
                Err(e) => panic!("{}: {}", base.filter.name(), e.message),
            };
            assert!(nav.state().iter().all(|v| v.is_finite()));
            let _ = nav.step(&[0.0; 3], None, 1.0);
            nav.reset();
            assert!(nav.state().iter().all(|v| v.is_finite()));
        });
    }
}

/// Fix the CRC-32 of an estimator state (32-byte header; docs/state-format.md) after an
/// edit, as a crafted state would carry it.
fn reseal_estimator_state(b: &mut [u8]) {
    let mut h = crc32fast::Hasher::new();
    h.update(&b[..28]);
    h.update(&b[32..]);
    let c = h.finalize();
    b[28..32].copy_from_slice(&c.to_le_bytes());
}

/// Restore `b` into `nav`: refused with `InvalidState` and the estimate bit for bit
/// unchanged, or accepted with a finite estimate.
fn restore_contract(nav: &mut Navigator, b: &[u8], what: &str) {
    let (x, p) = (nav.state(), nav.covariance());
    match nav.restore_state(b) {
        Ok(()) => {
            assert!(
                nav.state().iter().all(|v| v.is_finite()),
                "{what}: accepted with estimate {:?}",
                nav.state()
            );
            // a reset cannot fail: an accepted state must not make it non-finite (the
            // `capi` fuzz target's H-infinity state with a huge C_F^-1)
            nav.reset();
            assert!(
                nav.state().iter().all(|v| v.is_finite()),
                "{what}: accepted, then reset to {:?}",
                nav.state()
            );
        }
        Err(e) => {
            assert_eq!(e.kind, NavErrorKind::InvalidState, "{what}: {}", e.message);
            let same =
                |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(u, v)| u.to_bits() == v.to_bits());
            assert!(
                same(x.as_slice(), nav.state().as_slice())
                    && same(p.as_slice(), nav.covariance().as_slice()),
                "{what}: refused but changed"
            );
        }
    }
}

/// Fuzz finding (target `state`): a CGA-PF state (2 particles) with three bytes of the
/// weighted mean overwritten by 0xff and the checksum fixed was accepted, and the
/// estimator's state became NaN. The reader took the weighted mean without a finiteness
/// check; a restored state whose estimate is not finite is now refused. The artifact's
/// bytes (offset 65535 modulo the state length), then every filter with NaN and 0xff
/// bytes written at every offset of its payload behind a valid checksum: refused
/// unchanged, or a finite estimate. The particle filters' state has grown since the
/// finding, so the artifact's offset no longer lands in the weighted mean: the same three
/// 0xff bytes are written at every offset of the CGA-PF state, and at least one (the
/// weighted mean) must be refused for its non-finite estimate. Two more patches, the finite
/// but huge 1e300 and `f64::MAX`, and a reset after every accepted state, come from a
/// finding of the `capi` target: an H-infinity state with a huge `C_F^-1` was accepted (its
/// estimate was finite) and the next reset, which cannot fail, gave infinities; a restored
/// `C_F` / `C_F^-1` must be an inverse pair of moderate size.
#[test]
fn crafted_states_behind_a_valid_checksum_never_give_a_nan_estimate() {
    // the artifact's filter: point particles
    let cfg = NavConfig {
        filter: FilterKind::Cgapf,
        particles: 2,
        pf_prior: relnav_core::estimators::pf::PfPrior::Gaussian,
        ..Default::default()
    };
    let mut nav = Navigator::new(&cfg).unwrap();
    let mut b = Vec::new();
    nav.save_state(&mut b);
    let good = b.clone();
    let at = 65535 % b.len();
    let n = 3.min(b.len() - at);
    b[at..at + n].fill(0xff);
    reseal_estimator_state(&mut b);
    restore_contract(&mut nav, &b, "fuzz artifact");
    nav.restore_state(&good).unwrap();
    // the artifact's kind of corruption (three 0xff bytes) where it now lands in the
    // weighted mean: refused for the estimate, whatever the layout
    let refused_for_the_estimate = (0..good.len() - 3).any(|at| {
        let mut c = good.clone();
        c[at..at + 3].fill(0xff);
        reseal_estimator_state(&mut c);
        match nav.restore_state(&c) {
            Err(e) => e.message.contains("estimate is not finite"),
            Ok(()) => {
                nav.restore_state(&good).unwrap();
                false
            }
        }
    });
    assert!(
        refused_for_the_estimate,
        "0xff bytes in the weighted mean must be refused"
    );
    for base in configs() {
        bounded(base.filter.name(), move || {
            // the whole configuration moved in (a closure capturing only `base.filter`
            // next to `..base` crashes rustc 1.95: broken MIR on the IMM array lengths)
            let base = base;
            let cfg = NavConfig {
                particles: 3,
                ..base
            };
            let mut nav = Navigator::new(&cfg).unwrap();
            nav.step(&[0.0; 3], Some(&Z), 1.0).unwrap();
            let mut good = Vec::new();
            nav.save_state(&mut good);
            for at in 32..good.len() {
                let (huge, max) = (1e300f64.to_le_bytes(), f64::MAX.to_le_bytes());
                let patches = [&f64::NAN.to_le_bytes()[..], &[0xff; 3], &huge, &max];
                for patch in patches {
                    let mut b = good.clone();
                    let n = patch.len().min(b.len() - at);
                    b[at..at + n].copy_from_slice(&patch[..n]);
                    reseal_estimator_state(&mut b);
                    restore_contract(&mut nav, &b, &format!("{} at {at}", cfg.filter.name()));
                    nav.restore_state(&good).unwrap();
                }
            }
        });
    }
}

/// A crash found by the `capi` fuzz target: an RPF with 2 particles, a position process
/// noise of 7.5e159 m^2 on one axis and a 4e-149 rad angle noise. Its first update draws
/// the particles from the measurement and the velocities from the prior, whose covariance
/// (variances from 1e-6 to 7.5e159) nalgebra's eigensolver returned as NaN: the update
/// succeeded with a NaN estimate. The decomposition must be refused (`numerics::eigen`
/// checks its results) and the update fail with the estimate untouched. Every particle
/// kind, the same inputs.
#[test]
fn particle_update_with_an_extreme_prior_fails_cleanly_or_stays_finite() {
    bounded("particle filters, extreme prior", || {
        for filter in 4..=8 {
            let mut c = relnav_config_default();
            c.filter = filter;
            c.frame = 3;
            c.discretization = 1;
            c.resampler = 3;
            c.noise_model = 3;
            c.particles = 2;
            c.seed = 81_382_552_153_096_225;
            c.sigma_angle = 4.186_217_997_340_713e-149;
            c.accel_psd = 1e-9;
            c.q_pos[0] += 8703.0 / 256.0;
            c.q_pos[2] = 7.525_755_689_936_148e159;
            let mut e = std::ptr::null_mut();
            // SAFETY: valid pointers; live handle until freed; arrays of 3 and 6 doubles.
            unsafe {
                assert_eq!(relnav_estimator_new(&c, &mut e), relnav_status::RELNAV_OK);
                let st = relnav_estimator_predict(e, [0.0; 3].as_ptr(), 1.0 - 2.0 / 32768.0);
                assert_eq!(st, relnav_status::RELNAV_OK, "{}", last_error());
                let mut x = [0.0; 6];
                relnav_estimator_get_state(e, x.as_mut_ptr());
                // the measurement of the estimate itself (the fuzz target's FromEstimate)
                let r = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
                let az = x[1].atan2(x[0]).rem_euclid(std::f64::consts::TAU);
                let el = (x[2] / r).asin();
                let st = relnav_estimator_update(e, [r, az, el].as_ptr());
                let mut x2 = [0.0; 6];
                relnav_estimator_get_state(e, x2.as_mut_ptr());
                if st == relnav_status::RELNAV_OK {
                    assert!(x2.iter().all(|v| v.is_finite()), "filter {filter}: {x2:?}");
                } else {
                    assert!(!last_error().is_empty());
                    assert_eq!(x.map(f64::to_bits), x2.map(f64::to_bits), "filter {filter}");
                }
                relnav_estimator_free(e);
            }
        }
    });
}

/// Found by the `fmi3` fuzz target: in Event Mode, a relative GNSS velocity reading with a
/// component of -f64::MAX (finite, so accepted) left a particle filter's estimate at
/// -inf, and `fmi3UpdateDiscreteStates` reported success (a step's prediction refused
/// it; the discrete update has none, and the particle filters' generic sensor update did
/// not check its estimate). Now, for every filter, the update either is refused or leaves
/// a finite estimate.
#[test]
fn event_mode_updates_never_leave_a_non_finite_estimate() {
    use relnav_fmi::fmi3::description::vr_of;
    use relnav_fmi::fmi3::functions::*;
    use relnav_fmi::fmi3::types::{fmi3Instance, fmi3Status};
    use relnav_nav_model::{vr, RelnavFmu as M};
    let info = &*relnav_nav_model::INFO;
    let [pos_vel, camera, gnss_v] = [
        vec![
            vr_of(info, "position").unwrap(),
            vr_of(info, "velocity").unwrap(),
        ],
        vec![vr_of(info, "camera").unwrap()],
        vec![vr_of(info, "gnss_velocity").unwrap()],
    ];
    let get = |c: fmi3Instance, refs: &[u32], n: usize| {
        let mut out = vec![f64::NAN; n];
        // SAFETY: live instance, arrays of the lengths passed.
        let st = unsafe { fmi3GetFloat64::<M>(c, refs.as_ptr(), refs.len(), out.as_mut_ptr(), n) };
        (st, out)
    };
    for filter in [1, 2, 3, 4, 5, 6, 7, 8, 10, 11] {
        for extreme in [-f64::MAX, f64::MAX, 1e300] {
            let c = instantiate_event_mode(c"event");
            // SAFETY: a live instance and arrays of the lengths passed.
            unsafe {
                assert!(!c.is_null());
                let ints = [filter, 8];
                let refs = [vr::FILTER, vr::PARTICLES];
                assert_eq!(
                    fmi3SetInt32::<M>(c, refs.as_ptr(), 2, ints.as_ptr(), 2),
                    fmi3Status::fmi3OK
                );
                assert_eq!(
                    fmi3EnterInitializationMode::<M>(c, false, 0.0, 0.0, false, 0.0),
                    fmi3Status::fmi3OK
                );
                assert_eq!(fmi3ExitInitializationMode::<M>(c), fmi3Status::fmi3OK); // Event Mode
                let (_, x) = get(c, &pos_vel, 6);
                let r = (x[0] * x[0] + x[1] * x[1]).sqrt();
                // the fuzz input's line of sight: azimuth 99 rad off, elevation 1.46 times
                let los = [
                    x[1].atan2(x[0]) + 25439.0 / 256.0,
                    x[2].atan2(r) * (1.0 + 15201.0 / 32768.0),
                ];
                assert_eq!(
                    fmi3SetFloat64::<M>(c, camera.as_ptr(), 1, los.as_ptr(), 2),
                    fmi3Status::fmi3OK
                );
                let v = [x[3], x[4] * (1.0 + 23907.0 / 32768.0), extreme];
                assert_eq!(
                    fmi3SetFloat64::<M>(c, gnss_v.as_ptr(), 1, v.as_ptr(), 3),
                    fmi3Status::fmi3OK
                );
                let flags = [true, true];
                let valid = [vr::CAMERA_VALID, vr::GNSS_VELOCITY_VALID];
                assert_eq!(
                    fmi3SetBoolean::<M>(c, valid.as_ptr(), 2, flags.as_ptr(), 2),
                    fmi3Status::fmi3OK
                );
                // the readings stay set: each discrete update applies them again
                for k in 0..3 {
                    let (mut a, mut b, mut n, mut w, mut d, mut t) =
                        (true, true, true, true, true, 0.0);
                    let st = fmi3UpdateDiscreteStates::<M>(
                        c, &mut a, &mut b, &mut n, &mut w, &mut d, &mut t,
                    );
                    if st != fmi3Status::fmi3OK {
                        assert_eq!(st, fmi3Status::fmi3Error, "filter {filter}, {extreme:e}");
                        break;
                    }
                    let (gst, x) = get(c, &pos_vel, 6);
                    assert_eq!(gst, fmi3Status::fmi3OK);
                    let finite = x.iter().all(|v| v.is_finite());
                    assert!(finite, "filter {filter}, {extreme:e}, update {k}: {x:?}");
                }
                fmi3FreeInstance::<M>(c);
            }
        }
    }
}
