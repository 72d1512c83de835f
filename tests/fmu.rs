//! The FMI layer through its C entry points (as a master calls them): call order, status
//! codes, parameter rejection, variable step sizes, reset reproducibility, and agreement
//! with the C ABI it wraps. (Logging through the variadic callback is checked by the fmpy
//! suite and the C++ harness, which can define C-variadic loggers.)
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)] // test code

use relnav as ffi;
use relnav_fmi::fmi2::description::model_description_of;
use relnav_fmi::fmi2::types::*;
use relnav_nav_model::{vr, INFO, VARIABLES};
use std::ffi::CString;

// relnav.fmu's fmi2* functions in this binary, as the FMU's shared library exports them
relnav_fmi::export_fmi2!(relnav_nav_model::RelnavFmu);

/// relnav.fmu's GUID.
fn guid() -> &'static str {
    relnav_fmi::fmi2::description::guid_of(&relnav_nav_model::INFO)
}

/// relnav.fmu's modelDescription.xml.
fn model_description() -> &'static str {
    model_description_of(&INFO)
}

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

fn set_bool(c: fmi2Component, r: u32, v: bool) -> fmi2Status {
    let v = fmi2Boolean::from(v);
    // SAFETY: live instance, one element.
    unsafe { fmi2SetBoolean(c, &r, 1, &v) }
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
    // appended, never renumbered: the last output, then the parameters declared after it
    assert!(VARIABLES.len() > vr::GNSS_VELOCITY_NIS as usize);
    assert_eq!(VARIABLES.last().map(|v| v.name), Some("pf_prior"));
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
        // wrong type: filter is an Integer code
        assert_eq!(set_real(c, vr::FILTER, 1.0), ERR);
        assert_eq!(fmi2Reset(c), OK);
        // codes outside their list
        assert_eq!(set_int(c, vr::FRAME, 5), ERR);
        assert_eq!(fmi2Reset(c), OK);
        assert_eq!(set_int(c, vr::FILTER, 0), ERR);
        assert_eq!(fmi2Reset(c), OK);
        // values invalid whatever the other parameters: refused when set, in both states
        // where parameters are set
        for (r, v) in [
            (vr::CHASER_MASS, 0.0),
            (vr::SIGMA_RANGE, -1.0),
            (vr::MEAN_MOTION, f64::NAN),
            (vr::Q_POS_X, -1.0),
            (vr::HINF_PERIOD, 0.0),
            (vr::HINF_PERIOD, 1e10), // w0 * period > 0.5 for every accepted mean_motion
        ] {
            assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), OK);
            assert_eq!(set_real(c, r, v), ERR, "vr {r} = {v}");
            assert_eq!(fmi2Reset(c), OK);
            assert_eq!(fmi2EnterInitializationMode(c), OK);
            assert_eq!(set_real(c, r, v), ERR, "vr {r} = {v}");
            assert_eq!(fmi2Reset(c), OK);
        }
        for (r, v) in [(vr::PARTICLES, 0), (vr::WINDOW, 513)] {
            assert_eq!(set_int(c, r, v), ERR, "vr {r} = {v}");
            assert_eq!(fmi2Reset(c), OK);
        }
        // values valid alone, invalid together: accepted when set, refused at
        // exit-initialisation (hinf_period 1000 s needs mean_motion <= 5e-4 rad/s; the
        // literal unscented particle filters, pf_move = false, need a process noise)
        let combos: [&[(u32, f64)]; 2] = [
            &[(vr::HINF_PERIOD, 1000.0)],
            &[
                (vr::Q_POS_X, 0.0),
                (vr::Q_POS_Y, 0.0),
                (vr::Q_POS_Z, 0.0),
                (vr::Q_VEL_X, 0.0),
                (vr::Q_VEL_Y, 0.0),
                (vr::Q_VEL_Z, 0.0),
            ],
        ];
        for (i, combo) in combos.iter().enumerate() {
            assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), OK);
            if i == 1 {
                assert_eq!(set_int(c, vr::FILTER, 6), OK);
                assert_eq!(set_bool(c, vr::PF_MOVE, false), OK);
                assert_eq!(set_int(c, vr::PF_PRIOR, 1), OK);
            }
            for (r, v) in combo.iter() {
                assert_eq!(set_real(c, *r, *v), OK, "vr {r} = {v}");
            }
            assert_eq!(fmi2EnterInitializationMode(c), OK);
            assert_eq!(fmi2ExitInitializationMode(c), ERR, "combination {i}");
            assert_eq!(fmi2Reset(c), OK);
        }
        // ... and the same hinf_period with a slow enough orbit initialises
        assert_eq!(set_real(c, vr::HINF_PERIOD, 1000.0), OK);
        assert_eq!(set_real(c, vr::MEAN_MOTION, 7.3e-5), OK);
        assert_eq!(fmi2EnterInitializationMode(c), OK);
        assert_eq!(fmi2ExitInitializationMode(c), OK);
        assert_eq!(fmi2Reset(c), OK);
        // without the `hinf` feature, 9 (hinf) is not implemented: refused when set
        #[cfg(not(feature = "hinf"))]
        {
            let f = 9;
            assert_eq!(set_int(c, vr::FILTER, f), ERR, "filter {f}");
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
        assert_eq!(fmi2CancelStep(c), ERR);
        assert_eq!(fmi2Reset(c), OK);
        fmi2FreeInstance(c);
    }
}

/// `fmi_status` reports the worst status returned (for masters that ignore fmi2Error):
/// 0 while all is well, 3 after a refused call, 0 again after fmi2Reset.
#[test]
fn fmi_status_output_reports_errors() {
    let status = |c: fmi2Component| {
        let mut s = -1;
        // SAFETY: live instance, one element.
        assert_eq!(unsafe { fmi2GetInteger(c, &vr::FMI_STATUS, 1, &mut s) }, OK);
        s
    };
    let c = instantiate();
    init(c);
    run(c, 2);
    assert_eq!(status(c), 0);
    // SAFETY: live instance.
    unsafe {
        assert_eq!(fmi2DoStep(c, 0.0, 1.0, 1), ERR); // wrong communication point
        assert_eq!(status(c), 3);
        assert_eq!(fmi2DoStep(c, 2.0, 1.0, 1), ERR); // illegal in the error state
        assert_eq!(status(c), 3);
        assert_eq!(fmi2Reset(c), OK);
        assert_eq!(set_int(c, vr::PARTICLES, 0), ERR); // refused when set
        assert_eq!(status(c), 3);
        assert_eq!(fmi2Reset(c), OK);
        init(c);
        assert_eq!(status(c), 0);
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

/// `generationDateAndTime` is the commit date of `HEAD` in UTC (when built from a git
/// checkout without `SOURCE_DATE_EPOCH`): the XML, and with it the GUID, is the same for
/// every build of one commit. Checked against git's own date formatting.
#[test]
fn generation_date_is_the_commit_date() {
    use relnav_fmi::fmi2::description::GENERATION_DATE;
    let date = GENERATION_DATE;
    assert!(
        model_description().contains(&format!(r#"generationDateAndTime="{date}""#)),
        "{date}"
    );
    let b = date.as_bytes();
    assert!(
        b.len() == 20 && b[4] == b'-' && b[10] == b'T' && b[19] == b'Z',
        "not an xs:dateTime in UTC: {date}"
    );
    if std::env::var_os("SOURCE_DATE_EPOCH").is_some() {
        return;
    }
    let git = std::process::Command::new("git")
        .args([
            "log",
            "-1",
            "--format=%cd",
            "--date=format-local:%Y-%m-%dT%H:%M:%SZ",
        ])
        .env("TZ", "UTC")
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output();
    match git {
        Ok(o) if o.status.success() => {
            assert_eq!(String::from_utf8_lossy(&o.stdout).trim(), date)
        }
        _ => assert_eq!(date, "1970-01-01T00:00:00Z", "no git: the fixed date"),
    }
}

/// `docs/fmu.md`'s variable table is the generated one (regenerate with
/// `tools/bless_readme_variables.sh`, i.e. `cargo run --bin relnav-fmu -- --variables-markdown`).
#[test]
fn readme_variable_table_is_current() {
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/fmu.md")).unwrap();
    let begin = "<!-- variables:begin (generated: cargo run --bin relnav-fmu -- --variables-markdown) -->\n";
    let start = readme
        .find(begin)
        .expect("docs/fmu.md lacks the variables:begin marker")
        + begin.len();
    let end = readme
        .find("<!-- variables:end -->")
        .expect("docs/fmu.md lacks the variables:end marker");
    assert_eq!(
        readme.get(start..end).unwrap_or_default(),
        relnav_fmi::fmi2::description::variables_markdown_of(&INFO),
        "docs/fmu.md variable table is stale"
    );
}

// ------------------------------------------------------------------ particle filters

/// Paper 000's truth in its frame 2, closed-form CW (written here from the equations, not
/// relnav's model): at rest at (400, 500, 200) m at t = 0.
fn truth000(t: f64) -> [f64; 6] {
    let n = 2.0 * std::f64::consts::PI / 7200.0;
    let (s, c) = (n * t).sin_cos();
    [
        400.0 + 3000.0 * (s - n * t),
        500.0 * (4.0 - 3.0 * c),
        200.0 * c,
        3000.0 * n * (c - 1.0),
        1500.0 * n * s,
        -200.0 * n * s,
    ]
}

/// Range, azimuth in [0, 2 pi), elevation of the truth at `t`, with seeded Gaussian noise
/// of paper 000's sensor (0.5 m, 0.01 deg).
fn measure000(t: f64, rng: &mut rand_chacha::ChaCha8Rng) -> [f64; 3] {
    use rand::Rng;
    use rand_distr::StandardNormal;
    let p = truth000(t);
    let rho = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
    let az = p[1].atan2(p[0]).rem_euclid(2.0 * std::f64::consts::PI);
    let el = (p[2] / rho).asin();
    let sa = 0.01f64.to_radians();
    let mut e = || rng.sample::<f64, _>(StandardNormal);
    [rho + 0.5 * e(), az + sa * e(), el + sa * e()]
}

/// A particle-filter run through the FMU: `filter`, `seed`, `particles`, `steps` 1-s steps
/// with noisy measurements (measurement seed `meas_seed`). Returns the 12 outputs and
/// `ess` after every step.
fn run_pf(
    c: fmi2Component,
    filter: i32,
    seed: i32,
    particles: i32,
    steps: usize,
    meas_seed: u64,
) -> (Vec<[f64; 12]>, Vec<f64>) {
    use rand::SeedableRng;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(meas_seed);
    let ins = [vr::RANGE, vr::AZIMUTH, vr::ELEVATION];
    // SAFETY: live instance, one element per call.
    unsafe {
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), OK);
        assert_eq!(set_int(c, vr::FILTER, filter), OK);
        assert_eq!(set_int(c, vr::SEED, seed), OK);
        assert_eq!(set_int(c, vr::PARTICLES, particles), OK);
        assert_eq!(fmi2EnterInitializationMode(c), OK);
        assert_eq!(fmi2ExitInitializationMode(c), OK, "filter {filter}");
    }
    let mut outs = Vec::new();
    let mut ess = Vec::new();
    for k in 0..steps {
        let z = measure000(k as f64, &mut rng);
        let mut e = 0.0;
        // SAFETY: live instance, matching lengths.
        unsafe {
            assert_eq!(fmi2SetReal(c, ins.as_ptr(), 3, z.as_ptr()), OK);
            assert_eq!(fmi2SetBoolean(c, &vr::MEASUREMENT_VALID, 1, &1), OK);
            assert_eq!(fmi2DoStep(c, k as f64, 1.0, 1), OK, "filter {filter} t {k}");
            assert_eq!(fmi2GetReal(c, &vr::ESS, 1, &mut e), OK);
        }
        outs.push(outputs(c));
        ess.push(e);
    }
    (outs, ess)
}

/// The message relnav.fmu logs under `logStatusError` for the first refused set of
/// `sets` (each through the `fmi2Set*` of its type), or, if none is refused, for the end
/// of initialisation (empty if that succeeds): the same calls on an instance in Rust,
/// whose refusal is what the binding logs (a Rust test cannot define FMI 2.0's C-variadic
/// logger; the fmpy suite and the C++ harness check the logging itself).
fn refusal(sets: &[(u32, f64)]) -> String {
    use relnav_fmi::variables::TypeClass;
    let mut inst = relnav_fmi::fmi2::Instance::<relnav_nav_model::RelnavFmu>::new(
        c"t".into(),
        relnav_fmi::fmi2::Logger::new(None, std::ptr::null_mut()),
        false,
        guid(),
    );
    for &(r, v) in sets {
        let class = TypeClass::of(&VARIABLES[r as usize].ty);
        let func = match class {
            TypeClass::Real => "fmi2SetReal",
            TypeClass::Integer => "fmi2SetInteger",
            TypeClass::Boolean => "fmi2SetBoolean",
        };
        if let Err(e) = inst.set(r, v, func, class) {
            return e.message;
        }
    }
    inst.enter_initialization();
    inst.exit_initialization()
        .err()
        .map_or_else(String::new, |e| e.message)
}

/// Codes 4-8 on paper 000's example (1500 particles, seeded noisy measurements, 120 s,
/// three seeds each): every code stays finite with `ess` in [1, particles]; the filters
/// that move their particles reach decimetres (RPF, CGA-PF under 1 m and 0.2 m/s in
/// every run; GA-PF usually, but one seed in eight of a wider sweep ended 5.7 m off), the
/// plain SIR and the UPF keep impoverished velocity draws (0.1-0.6 m/s off) and drift
/// metres to tens of metres (see `src/estimators/pf/mod.rs`): for them only a loose bound.
#[test]
fn particle_filters_track_paper000_through_the_fmu() {
    let steps = 120;
    let truth = truth000(steps as f64);
    // (code, position bound [m], velocity bound [m/s])
    for (code, pos_bound, vel_bound) in [
        (4, 100.0, 1.0),
        (5, 1.0, 0.2),
        (6, 100.0, 1.0),
        (7, 10.0, 0.5),
        (8, 1.0, 0.2),
    ] {
        let mut summary = Vec::new();
        for seed in 0..3 {
            let c = instantiate();
            let (outs, ess) = run_pf(c, code, seed, 1500, steps, 11 + seed as u64);
            // SAFETY: live instance, freed once.
            unsafe {
                assert_eq!(fmi2Terminate(c), OK);
                fmi2FreeInstance(c);
            }
            for (k, (o, e)) in outs.iter().zip(&ess).enumerate() {
                assert!(
                    o.iter().all(|v| v.is_finite()),
                    "filter {code} t {k}: {o:?}"
                );
                assert!(
                    (1.0..=1500.0).contains(e),
                    "filter {code} t {k}: ess {e} outside [1, 1500]"
                );
            }
            let last = outs[steps - 1];
            let norm = |r: std::ops::Range<usize>| {
                r.map(|i| (last[i] - truth[i]).powi(2)).sum::<f64>().sqrt()
            };
            let (pos_err, vel_err) = (norm(0..3), norm(3..6));
            let min_ess = ess.iter().copied().fold(f64::INFINITY, f64::min);
            summary.push(format!(
                "{pos_err:.3} m / {vel_err:.4} m/s (ess min {min_ess:.0}, last {:.0}; sigma_x {:.3} m)",
                ess[steps - 1],
                last[6]
            ));
            assert!(
                pos_err < pos_bound && vel_err < vel_bound,
                "filter {code} seed {seed}: error {pos_err} m, {vel_err} m/s at t = {steps} s \
                 (bounds {pos_bound} m, {vel_bound} m/s)"
            );
        }
        eprintln!("filter {code} at t = {steps} s: {}", summary.join("; "));
    }
}

/// The `seed` parameter: identical seeds give bit-identical outputs on two instances and
/// after fmi2Reset, a different seed different outputs.
#[test]
fn particle_filter_seed_reproduces_outputs() {
    for code in 4..=8 {
        let a = instantiate();
        let b = instantiate();
        let (ra, ea) = run_pf(a, code, 42, 300, 40, 5);
        let (rb, eb) = run_pf(b, code, 42, 300, 40, 5);
        assert_eq!(ra, rb, "filter {code}: same seed, different outputs");
        assert_eq!(ea, eb, "filter {code}: same seed, different ess");
        // SAFETY: live instance.
        assert_eq!(unsafe { fmi2Reset(a) }, OK);
        let (rr, _) = run_pf(a, code, 42, 300, 40, 5);
        assert_eq!(ra, rr, "filter {code}: reset does not reproduce the run");
        // SAFETY: live instance.
        assert_eq!(unsafe { fmi2Reset(b) }, OK);
        let (rc, _) = run_pf(b, code, 43, 300, 40, 5);
        assert_ne!(
            ra, rc,
            "filter {code}: seeds 42 and 43 give identical outputs"
        );
        // SAFETY: live instances, freed once.
        unsafe {
            fmi2FreeInstance(a);
            fmi2FreeInstance(b);
        }
    }
}

/// `ess` before the first step is the particle count for a particle filter and NaN for a
/// Kalman filter (which has no particles), and stays NaN for it.
#[test]
fn ess_output_of_kalman_and_particle_filters() {
    let c = instantiate();
    let mut e = 0.0;
    // SAFETY: live instance.
    unsafe {
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), OK);
        assert_eq!(set_int(c, vr::FILTER, 5), OK);
        assert_eq!(set_int(c, vr::PARTICLES, 321), OK);
        assert_eq!(fmi2EnterInitializationMode(c), OK);
        assert_eq!(fmi2GetReal(c, &vr::ESS, 1, &mut e), OK);
        assert_eq!(e, 321.0);
        assert_eq!(fmi2ExitInitializationMode(c), OK);
        assert_eq!(fmi2GetReal(c, &vr::ESS, 1, &mut e), OK);
        assert_eq!(e, 321.0);
        assert_eq!(fmi2Reset(c), OK);
    }
    init(c);
    run(c, 5);
    // SAFETY: live instance.
    unsafe {
        assert_eq!(fmi2GetReal(c, &vr::ESS, 1, &mut e), OK);
        fmi2FreeInstance(c);
    }
    assert!(e.is_nan(), "EKF ess {e}");
}

/// Bad particle-filter and noise parameters are refused when set (codes outside their
/// lists, values invalid alone), a combination at fmi2ExitInitializationMode, with a
/// message naming the parameter (the message the FMU logs under logStatusError, checked
/// here by [`refusal`]; the logging itself is checked by the fmpy suite).
#[test]
fn bad_particle_filter_parameters_are_refused() {
    let c = instantiate();
    // SAFETY: live instance; each error is followed by a reset.
    unsafe {
        assert_eq!(set_int(c, vr::RESAMPLER, 7), ERR);
        assert_eq!(fmi2Reset(c), OK);
        assert_eq!(set_int(c, vr::NOISE_MODEL, 4), ERR);
        assert_eq!(fmi2Reset(c), OK);
        assert_eq!(
            set_real(c, vr::PARTICLES, 10.0),
            ERR,
            "particles is an Integer"
        );
        assert_eq!(fmi2Reset(c), OK);
        for (filter, name, r, v) in [
            (5, "particles", vr::PARTICLES, 0.0),
            (5, "particles", vr::PARTICLES, -3.0),
            (5, "particles", vr::PARTICLES, 2_000_001.0),
            (5, "resample_threshold", vr::RESAMPLE_THRESHOLD, 0.0),
            (5, "resample_threshold", vr::RESAMPLE_THRESHOLD, 1.5),
            (5, "resample_threshold", vr::RESAMPLE_THRESHOLD, f64::NAN),
            (8, "noise_zeta", vr::NOISE_ZETA, 1.0),
            (8, "noise_zeta", vr::NOISE_ZETA, -0.1),
            (8, "noise_scale", vr::NOISE_SCALE, 0.5),
            (8, "noise_dof", vr::NOISE_DOF, 2.0),
            // bad values are refused whatever the filter, so they never hide
            (1, "particles", vr::PARTICLES, 0.0),
            (1, "noise_zeta", vr::NOISE_ZETA, 1.0),
        ] {
            // invalid whatever the other parameters: refused when set
            assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), OK);
            assert_eq!(set_int(c, vr::FILTER, filter), OK);
            let st = if r == vr::PARTICLES {
                set_int(c, r, v as i32)
            } else {
                set_real(c, r, v)
            };
            assert_eq!(st, ERR, "{name} = {v} accepted (filter {filter})");
            let msg = refusal(&[(vr::FILTER, f64::from(filter)), (r, v)]);
            assert!(msg.contains(name), "{name} = {v}: message {msg:?}");
            assert_eq!(fmi2Reset(c), OK);
        }
        // the literal UPF and CGA-PF (pf_move = false) need a transition density: no
        // process noise at all is refused; with their moves (the default) it is accepted
        for filter in [6, 8] {
            for moves in [false, true] {
                assert_eq!(set_int(c, vr::FILTER, filter), OK);
                assert_eq!(set_bool(c, vr::PF_MOVE, moves), OK);
                // point particles: pf_move applies to them alone
                assert_eq!(set_int(c, vr::PF_PRIOR, 1), OK);
                for r in vr::Q_POS_X..=vr::Q_VEL_Z {
                    assert_eq!(set_real(c, r, 0.0), OK);
                }
                assert_eq!(fmi2EnterInitializationMode(c), OK);
                if moves {
                    assert_eq!(fmi2ExitInitializationMode(c), OK, "filter {filter}, Q = 0");
                } else {
                    assert_eq!(fmi2ExitInitializationMode(c), ERR, "filter {filter}, Q = 0");
                    let mut sets = vec![
                        (vr::FILTER, f64::from(filter)),
                        (vr::PF_MOVE, f64::from(u8::from(moves))),
                        (vr::PF_PRIOR, 1.0),
                    ];
                    sets.extend((vr::Q_POS_X..=vr::Q_VEL_Z).map(|r| (r, 0.0)));
                    let msg = refusal(&sets);
                    assert!(msg.contains("process noise"), "{msg}");
                }
                assert_eq!(fmi2Reset(c), OK);
            }
        }
        // valid edges are accepted
        assert_eq!(set_int(c, vr::FILTER, 8), OK);
        assert_eq!(set_int(c, vr::PARTICLES, 1), OK);
        assert_eq!(set_int(c, vr::RESAMPLER, 4), OK);
        assert_eq!(set_int(c, vr::NOISE_MODEL, 3), OK);
        assert_eq!(set_real(c, vr::RESAMPLE_THRESHOLD, 1.0), OK);
        assert_eq!(set_real(c, vr::NOISE_ZETA, 0.0), OK);
        assert_eq!(set_real(c, vr::NOISE_SCALE, 1.0), OK);
        assert_eq!(set_real(c, vr::NOISE_DOF, 2.5), OK);
        init(c);
        fmi2FreeInstance(c);
    }
}

/// FMI 3.0 array gets and sets: the one-slice path a master's usual call takes gives what
/// the element-by-element path gives (a set before initialisation takes the checked path,
/// one in Step Mode the plain stores); a set with an unknown reference or the wrong
/// number of values changes nothing; a get that mixes arrays with a scalar or the time
/// reads each in order.
#[test]
fn fmi3_array_access_is_all_or_nothing() {
    use relnav_fmi::fmi3::description::{vr_of, TIME_VR};
    use relnav_fmi::fmi3::functions::*;
    use relnav_fmi::fmi3::types::{fmi3Instance, fmi3Status};
    use relnav_nav_model::RelnavFmu as M;
    let [thrust, meas, pos, vel] =
        ["thrust", "measurement", "position", "velocity"].map(|n| vr_of(&INFO, n).unwrap());
    let get = |c: fmi3Instance, refs: &[u32], n: usize| {
        let mut out = vec![f64::NAN; n];
        // SAFETY: live instance, arrays of the lengths passed.
        let st = unsafe { fmi3GetFloat64::<M>(c, refs.as_ptr(), refs.len(), out.as_mut_ptr(), n) };
        (st, out)
    };
    let set = |c: fmi3Instance, refs: &[u32], vals: &[f64]| {
        // SAFETY: as above.
        unsafe { fmi3SetFloat64::<M>(c, refs.as_ptr(), refs.len(), vals.as_ptr(), vals.len()) }
    };
    let c = instantiate_plain::<M>(c"arrays");
    assert!(!c.is_null());
    // before initialisation and in it: the checked path (read back in initialisation)
    assert_eq!(set(c, &[thrust], &[0.1, 0.2, 0.3]), fmi3Status::fmi3OK);
    // SAFETY: live instance.
    unsafe {
        assert_eq!(
            fmi3EnterInitializationMode::<M>(c, false, 0.0, 0.0, false, 0.0),
            fmi3Status::fmi3OK
        );
    }
    assert_eq!(get(c, &[thrust], 3).1, [0.1, 0.2, 0.3]);
    assert_eq!(set(c, &[thrust], &[0.4, 0.5, 0.6]), fmi3Status::fmi3OK);
    assert_eq!(get(c, &[thrust], 3).1, [0.4, 0.5, 0.6]);
    // SAFETY: live instance.
    unsafe {
        assert_eq!(fmi3ExitInitializationMode::<M>(c), fmi3Status::fmi3OK);
    }
    // Step Mode: plain stores, one array or several in one call
    assert_eq!(set(c, &[thrust], &[1.0, 2.0, 3.0]), fmi3Status::fmi3OK);
    let z = [900.0, 0.5, 0.25];
    assert_eq!(
        set(c, &[meas, thrust], &[z[0], z[1], z[2], 4.0, 5.0, 6.0]),
        fmi3Status::fmi3OK
    );
    assert_eq!(
        get(c, &[thrust, meas], 6).1,
        [4.0, 5.0, 6.0, z[0], z[1], z[2]]
    );
    // refused: nothing changes (an unknown reference, one value short, one too many)
    for (refs, n) in [
        (&[thrust, 12_345][..], 4),
        (&[thrust, meas][..], 5),
        (&[thrust][..], 4),
    ] {
        let vals = vec![-7.0; n];
        assert_eq!(set(c, refs, &vals), fmi3Status::fmi3Error, "{refs:?} {n}");
        // the refusal puts the instance in the error state, where gets still answer
        assert_eq!(
            get(c, &[thrust, meas], 6).1,
            [4.0, 5.0, 6.0, z[0], z[1], z[2]]
        );
        // SAFETY: live instance.
        unsafe {
            assert_eq!(fmi3Reset::<M>(c), fmi3Status::fmi3OK);
            assert_eq!(
                fmi3EnterInitializationMode::<M>(c, false, 0.0, 0.0, false, 0.0),
                fmi3Status::fmi3OK
            );
            assert_eq!(fmi3ExitInitializationMode::<M>(c), fmi3Status::fmi3OK);
        }
        assert_eq!(
            set(c, &[thrust, meas], &[4.0, 5.0, 6.0, z[0], z[1], z[2]]),
            fmi3Status::fmi3OK
        );
    }
    // arrays read alone and among other references agree
    let (st, both) = get(c, &[pos, vel], 6);
    assert_eq!(st, fmi3Status::fmi3OK);
    let (st, mixed) = get(c, &[vel, TIME_VR, pos], 7);
    assert_eq!(st, fmi3Status::fmi3OK);
    assert_eq!(mixed, [&both[3..], &[0.0][..], &both[..3]].concat());
    // one value short or too many: refused
    assert_eq!(get(c, &[pos, vel], 5).0, fmi3Status::fmi3Error);
    assert_eq!(get(c, &[pos, vel], 7).0, fmi3Status::fmi3Error);
    // SAFETY: live instance; freed once.
    unsafe {
        assert_eq!(fmi3Reset::<M>(c), fmi3Status::fmi3OK);
        fmi3FreeInstance::<M>(c);
    }
}
