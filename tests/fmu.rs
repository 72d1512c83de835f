//! The FMI layer through its C entry points (as a master calls them): call order, status
//! codes, parameter rejection, variable step sizes, reset reproducibility, and agreement
//! with the C ABI it wraps. (Logging through the variadic callback is checked by the fmpy
//! suite and the C++ harness, which can define C-variadic loggers.)
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)] // test code

use relnav::ffi;
use relnav::fmi::description::{guid, model_description};
use relnav::fmi::functions::*;
use relnav::fmi::types::*;
use relnav::fmi::variables::{vr, VARIABLES};
use std::ffi::CString;

const OK: fmi2Status = fmi2Status::fmi2OK;
const ERR: fmi2Status = fmi2Status::fmi2Error;

fn callbacks() -> fmi2CallbackFunctions {
    fmi2CallbackFunctions {
        logger: None,
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: std::ptr::null_mut(),
    }
}

fn instantiate() -> fmi2Component {
    let g = CString::new(guid()).unwrap();
    let cb = callbacks();
    // SAFETY: valid strings and callbacks for the duration of the call.
    let c = unsafe {
        fmi2Instantiate(
            c"t".as_ptr(),
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

fn init(c: fmi2Component) {
    // SAFETY: live instance.
    unsafe {
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), OK);
        assert_eq!(fmi2EnterInitializationMode(c), OK);
        assert_eq!(fmi2ExitInitializationMode(c), OK);
    }
}

fn set_real(c: fmi2Component, r: u32, v: f64) -> fmi2Status {
    // SAFETY: live instance, one element.
    unsafe { fmi2SetReal(c, &r, 1, &v) }
}

fn set_int(c: fmi2Component, r: u32, v: i32) -> fmi2Status {
    // SAFETY: live instance, one element.
    unsafe { fmi2SetInteger(c, &r, 1, &v) }
}

fn outputs(c: fmi2Component) -> [f64; 12] {
    let refs: Vec<u32> = (vr::X..=vr::SIGMA_VZ).collect();
    let mut y = [0.0; 12];
    // SAFETY: live instance, 12 elements.
    assert_eq!(
        unsafe { fmi2GetReal(c, refs.as_ptr(), 12, y.as_mut_ptr()) },
        OK
    );
    y
}

fn z(k: usize) -> [f64; 3] {
    let t = k as f64;
    [670.8 - 0.002 * t, 0.8961 + 2e-6 * t, 0.3025 - 1e-6 * t]
}

/// Run `n` 1-s steps with measurements; return all outputs.
fn run(c: fmi2Component, n: usize) -> Vec<[f64; 12]> {
    let ins = [vr::RANGE, vr::AZIMUTH, vr::ELEVATION];
    (0..n)
        .map(|k| {
            // SAFETY: live instance, matching lengths.
            unsafe {
                assert_eq!(fmi2SetReal(c, ins.as_ptr(), 3, z(k).as_ptr()), OK);
                assert_eq!(fmi2SetBoolean(c, &vr::MEASUREMENT_VALID, 1, &1), OK);
                assert_eq!(fmi2DoStep(c, k as f64, 1.0, 1), OK);
            }
            outputs(c)
        })
        .collect()
}

#[test]
fn platform_strings_and_description() {
    // SAFETY: static strings.
    unsafe {
        assert_eq!(
            std::ffi::CStr::from_ptr(fmi2GetVersion()).to_str().unwrap(),
            "2.0"
        );
        assert_eq!(
            std::ffi::CStr::from_ptr(fmi2GetTypesPlatform())
                .to_str()
                .unwrap(),
            "default"
        );
    }
    assert!(model_description().contains(guid()));
    assert_eq!(VARIABLES.len(), vr::SIGMA_VZ as usize + 1);
}

#[test]
fn instantiate_rejects_bad_arguments() {
    let g = CString::new(guid()).unwrap();
    let cb = callbacks();
    // SAFETY: valid or null pointers, as the standard allows a master to pass.
    unsafe {
        assert!(
            fmi2Instantiate(c"x".as_ptr(), 0, g.as_ptr(), std::ptr::null(), &cb, 0, 0).is_null()
        );
        assert!(fmi2Instantiate(
            c"x".as_ptr(),
            1,
            c"{wrong}".as_ptr(),
            std::ptr::null(),
            &cb,
            0,
            0
        )
        .is_null());
        assert!(
            fmi2Instantiate(std::ptr::null(), 1, g.as_ptr(), std::ptr::null(), &cb, 0, 0).is_null()
        );
        assert!(
            fmi2Instantiate(c"".as_ptr(), 1, g.as_ptr(), std::ptr::null(), &cb, 0, 0).is_null()
        );
        assert!(fmi2Instantiate(
            c"x".as_ptr(),
            1,
            g.as_ptr(),
            std::ptr::null(),
            std::ptr::null(),
            0,
            0
        )
        .is_null());
        // null instance everywhere: an error, never a crash
        assert_eq!(fmi2DoStep(std::ptr::null_mut(), 0.0, 1.0, 0), ERR);
        assert_eq!(fmi2Reset(std::ptr::null_mut()), ERR);
        fmi2FreeInstance(std::ptr::null_mut());
    }
}

#[test]
fn outputs_match_the_c_abi_and_reset_reproduces() {
    let c = instantiate();
    init(c);
    let first = run(c, 50);
    // SAFETY: live instance.
    assert_eq!(unsafe { fmi2Reset(c) }, OK);
    init(c);
    let second = run(c, 50);
    assert_eq!(first, second, "reset must reproduce the run exactly");

    // the same steps through the C ABI
    let cfg = ffi::relnav_config_default();
    let mut est = std::ptr::null_mut();
    // SAFETY: valid pointers; handle freed below.
    unsafe {
        assert_eq!(
            ffi::relnav_estimator_new(&cfg, &mut est),
            ffi::relnav_status::RELNAV_OK
        )
    };
    for (k, out) in first.iter().enumerate() {
        let mut x = [0.0; 6];
        let mut s = [0.0; 6];
        // SAFETY: live handle, documented lengths.
        unsafe {
            ffi::relnav_estimator_step(est, [0.0; 3].as_ptr(), z(k).as_ptr(), 1.0);
            ffi::relnav_estimator_get_state(est, x.as_mut_ptr());
            ffi::relnav_estimator_get_sigma(est, s.as_mut_ptr());
        }
        assert_eq!(&out[..6], &x[..]);
        assert_eq!(&out[6..], &s[..]);
    }
    // SAFETY: freed once.
    unsafe {
        ffi::relnav_estimator_free(est);
        fmi2Terminate(c);
        fmi2FreeInstance(c);
    }
}

#[test]
fn initial_outputs_are_the_initial_estimate() {
    let c = instantiate();
    // SAFETY: live instance.
    unsafe {
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), OK);
        assert_eq!(set_real(c, vr::X0, 1.0), OK);
        assert_eq!(fmi2EnterInitializationMode(c), OK);
        assert_eq!(set_real(c, vr::SIGMA_POS0, 7.0), OK);
    }
    let y = outputs(c);
    assert_eq!(y[0], 1.0);
    assert_eq!(y[6], 7.0);
    // SAFETY: live instance.
    unsafe { fmi2FreeInstance(c) };
}

#[test]
fn call_sequence_and_parameter_errors() {
    let c = instantiate();
    let mut y = 0.0;
    // SAFETY: live instance throughout; each error is followed by a reset.
    unsafe {
        // GetReal is illegal in Instantiated; DoStep before initialisation too
        assert_eq!(fmi2GetReal(c, &vr::X, 1, &mut y), ERR);
        assert_eq!(fmi2Reset(c), OK);
        assert_eq!(fmi2DoStep(c, 0.0, 1.0, 0), ERR);
        assert_eq!(fmi2Reset(c), OK);
        // outputs cannot be set; unknown references are errors
        assert_eq!(set_real(c, vr::X, 1.0), ERR);
        assert_eq!(fmi2Reset(c), OK);
        assert_eq!(set_real(c, 9999, 1.0), ERR);
        assert_eq!(fmi2Reset(c), OK);
        // wrong type: filter is an enumeration
        assert_eq!(set_real(c, vr::FILTER, 1.0), ERR);
        assert_eq!(fmi2Reset(c), OK);
        // enumeration values outside the type
        assert_eq!(set_int(c, vr::FRAME, 5), ERR);
        assert_eq!(fmi2Reset(c), OK);
        assert_eq!(set_int(c, vr::FILTER, 0), ERR);
        assert_eq!(fmi2Reset(c), OK);
        // parameters valid in type but not in value: rejected at exit-initialisation
        for (r, v) in [
            (vr::CHASER_MASS, 0.0),
            (vr::SIGMA_RANGE, -1.0),
            (vr::MEAN_MOTION, f64::NAN),
            (vr::Q_POS_X, -1.0),
        ] {
            assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), OK);
            assert_eq!(set_real(c, r, v), OK);
            assert_eq!(fmi2EnterInitializationMode(c), OK);
            assert_eq!(fmi2ExitInitializationMode(c), ERR, "vr {r} = {v}");
            assert_eq!(fmi2Reset(c), OK);
        }
        for f in [3, 9] {
            assert_eq!(set_int(c, vr::FILTER, f), OK);
            assert_eq!(fmi2EnterInitializationMode(c), OK);
            assert_eq!(fmi2ExitInitializationMode(c), ERR, "filter {f}");
            assert_eq!(fmi2Reset(c), OK);
        }
        // parameters are fixed after initialisation; inputs are not
        init(c);
        assert_eq!(set_real(c, vr::THRUST_X, 1.0), OK);
        assert_eq!(set_real(c, vr::CHASER_MASS, 10.0), ERR);
        assert_eq!(fmi2Reset(c), OK);
        // step checks: h <= 0, wrong communication point, NaN measurement
        init(c);
        assert_eq!(fmi2DoStep(c, 0.0, 0.0, 0), ERR);
        assert_eq!(fmi2Reset(c), OK);
        init(c);
        assert_eq!(fmi2DoStep(c, 5.0, 1.0, 0), ERR);
        assert_eq!(fmi2Reset(c), OK);
        init(c);
        assert_eq!(set_real(c, vr::RANGE, f64::NAN), OK);
        assert_eq!(fmi2SetBoolean(c, &vr::MEASUREMENT_VALID, 1, &1), OK);
        assert_eq!(fmi2DoStep(c, 0.0, 1.0, 0), ERR);
        // after an error only reset/free make sense; outputs stay readable
        assert_eq!(fmi2GetReal(c, &vr::X, 1, &mut y), OK);
        assert_eq!(fmi2DoStep(c, 0.0, 1.0, 0), ERR);
        assert_eq!(fmi2Reset(c), OK);
        // unsupported functions say so
        init(c);
        let mut s: fmi2FMUstate = std::ptr::null_mut();
        assert_eq!(fmi2GetFMUstate(c, &mut s), ERR);
        assert_eq!(fmi2Reset(c), OK);
        fmi2FreeInstance(c);
    }
}

#[test]
fn variable_steps_and_status_queries() {
    let c = instantiate();
    init(c);
    let mut t = 0.0;
    for (k, h) in [0.5, 1.0, 0.25, 0.25, 2.0, 1.0].iter().enumerate() {
        // SAFETY: live instance.
        unsafe {
            assert_eq!(
                fmi2SetReal(
                    c,
                    [vr::RANGE, vr::AZIMUTH, vr::ELEVATION].as_ptr(),
                    3,
                    z(k).as_ptr()
                ),
                OK
            );
            assert_eq!(
                fmi2SetBoolean(c, &vr::MEASUREMENT_VALID, 1, &((k % 2) as i32)),
                OK
            );
            assert_eq!(fmi2DoStep(c, t, *h, 0), OK);
        }
        t += h;
    }
    let mut last = 0.0;
    let mut term = 1;
    // SAFETY: live instance.
    unsafe {
        assert_eq!(fmi2GetRealStatus(c, 2, &mut last), OK);
        assert_eq!(fmi2GetBooleanStatus(c, 3, &mut term), OK);
        fmi2FreeInstance(c);
    }
    assert_eq!(last, 5.0);
    assert_eq!(term, 0);
}

/// The README's variable table is the generated one (regenerate with
/// `cargo run --bin relnav-fmu -- --variables-markdown`).
#[test]
fn readme_variable_table_is_current() {
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/README.md")).unwrap();
    let begin = "<!-- variables:begin (generated: cargo run --bin relnav-fmu -- --variables-markdown) -->\n";
    let start = readme
        .find(begin)
        .expect("README lacks the variables:begin marker")
        + begin.len();
    let end = readme
        .find("<!-- variables:end -->")
        .expect("README lacks the variables:end marker");
    assert_eq!(
        readme.get(start..end).unwrap_or_default(),
        relnav::fmi::description::variables_markdown(),
        "README variable table is stale"
    );
}
