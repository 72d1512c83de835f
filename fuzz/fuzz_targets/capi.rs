//! Fuzz target `capi`: the C ABI (`include/relnav.h`) under arbitrary configurations and
//! arbitrary sequences of step (with or without the declared sensors) / predict / update /
//! reset / save / restore with arbitrary numbers (restoring saved states intact, truncated,
//! corrupted, rewritten behind a valid checksum, or arbitrary bytes), and the runtime
//! H-infinity filter (`relnav_hinf_filter_*`) with arbitrary matrices.
//!
//! Besides crashes, hangs (run with `-timeout=1`) and panics (libfuzzer-sys aborts on any
//! panic, also one the C boundary would catch), every call is checked against the C ABI's
//! contract:
//! * no call returns `RELNAV_ERROR_PANIC`;
//! * a failing call leaves a non-empty `relnav_last_error()` message;
//! * a failing predict / update, or a failing step (also `step_sensors`) of a Kalman-type
//!   filter, leaves the state and covariance bit for bit as they were (a particle filter's
//!   step may commit its update before the prediction fails: documented, see `Navigator`);
//! * after a successful call the state estimate is finite;
//! * `relnav_estimator_get_config` returns the configuration the estimator was made from;
//! * the state size (`relnav_estimator_save` with a null buffer) never changes for one
//!   estimator; a buffer one byte short gives `RELNAV_ERROR_BUFFER_TOO_SMALL` and is not
//!   written;
//! * an intact saved state restores (`RELNAV_OK`) to the saved estimate bit for bit, and
//!   saving it again gives the same bytes; a refused (damaged) state leaves the estimator
//!   bit for bit unchanged; an accepted one leaves a finite estimate.
//!
//! Limits of the target (documented in fuzz/README.md): at most 16 particles and 64
//! operations per input, so that one input runs in milliseconds; the H-infinity filter
//! (code 9) is one estimator designed once per process with the default design inputs
//! (the LMI design takes ~0.5 s) and reset at the start of every input that selects it.
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use relnav::*;
use relnav_fuzz::{damage, measure, same_bits, values3, Damage, Num, ESTIMATOR_HEADER};
use std::cell::Cell;
use std::ffi::CStr;

#[derive(Arbitrary, Debug)]
struct Config {
    filter: u8,
    frame: u8,
    discretization: u8,
    resampler: u8,
    noise_model: u8,
    particles: u8,
    window: u16,
    seed: u64,
    reals: [Num; 28],
}

#[derive(Arbitrary, Debug)]
enum Meas {
    /// The measurement of the current estimate, plus fuzzed offsets (default 0).
    FromEstimate([Num; 3]),
    /// Fuzzed around a plausible measurement.
    Raw([Num; 3]),
    /// Nothing (a dropout; `step` only).
    None,
}

#[derive(Arbitrary, Debug)]
enum Op {
    Step {
        thrust: [Num; 3],
        z: Meas,
        dt: Num,
    },
    Predict {
        thrust: [Num; 3],
        dt: Num,
    },
    Update {
        z: Meas,
    },
    Reset,
    /// `relnav_estimator_save`: the size query, a buffer one byte short when `short`,
    /// then the state (kept as the last saved one).
    Save {
        short: bool,
    },
    /// `relnav_estimator_restore` of the last saved state after `damage`.
    Restore {
        damage: Damage,
    },
    /// `relnav_estimator_step_sensors`: the radio's, camera's and relative GNSS's readings,
    /// each given or not; the camera's and GNSS's are the current estimate's plus fuzzed
    /// offsets (default 0).
    StepSensors {
        thrust: [Num; 3],
        z: Meas,
        camera: Option<[Num; 2]>,
        gnss_position: Option<[Num; 3]>,
        gnss_velocity: Option<[Num; 3]>,
        dt: Num,
    },
}

#[derive(Arbitrary, Debug)]
enum Input {
    Estimator {
        config: Config,
        ops: Vec<Op>,
    },
    HinfRuntime {
        matrices: Box<[Num; 109]>,
        x0: [Num; 6],
        steps: Vec<(Option<[Num; 3]>, [Num; 3])>,
    },
}

const MAX_OPS: usize = 64;
const MAX_PARTICLES: i32 = 16;

thread_local! {
    /// The filter-9 estimator, designed once (default design inputs).
    static HINF: Cell<*mut relnav_estimator> = const { Cell::new(std::ptr::null_mut()) };
}

fn hinf_estimator() -> *mut relnav_estimator {
    HINF.with(|h| {
        if h.get().is_null() {
            let mut c = relnav_config_default();
            c.filter = 9;
            let mut e = std::ptr::null_mut();
            // SAFETY: valid pointers.
            let st = unsafe { relnav_estimator_new(&c, &mut e) };
            assert_eq!(st, relnav_status::RELNAV_OK, "default hinf design");
            h.set(e);
        }
        h.get()
    })
}

fn build_config(c: &Config) -> relnav_config {
    let d = relnav_config_default();
    let mut o = d;
    o.filter = i32::from(c.filter % 12); // 0 and 11 are invalid codes (10 is the IMM)
    o.frame = i32::from(c.frame % 5);
    o.discretization = i32::from(c.discretization % 4);
    o.resampler = i32::from(c.resampler % 6);
    o.noise_model = i32::from(c.noise_model % 5);
    o.particles = match c.particles {
        255 => -1,
        254 => 0,
        253 => 2_000_001,
        p => 1 + i32::from(p) % MAX_PARTICLES,
    };
    o.window = match c.window {
        65535 => -1,
        65534 => 0,
        65533 => 513,
        w => 1 + i32::from(w) % 512,
    };
    o.seed = c.seed;
    let r = &c.reals;
    o.mean_motion = r[0].value(d.mean_motion);
    o.chaser_mass = r[1].value(d.chaser_mass);
    o.sigma_range = r[2].value(d.sigma_range);
    o.sigma_angle = r[3].value(d.sigma_angle);
    for i in 0..6 {
        o.x0[i] = r[4 + i].value(d.x0[i]);
    }
    o.sigma_pos0 = r[10].value(d.sigma_pos0);
    o.sigma_vel0 = r[11].value(d.sigma_vel0);
    o.accel_psd = r[12].value(1e-9);
    for i in 0..3 {
        o.q_pos[i] = r[13 + i].value(d.q_pos[i]);
        o.q_vel[i] = r[16 + i].value(d.q_vel[i]);
    }
    o.ukf_alpha = r[19].value(d.ukf_alpha);
    o.ukf_beta = r[20].value(d.ukf_beta);
    o.ukf_kappa = r[21].value(d.ukf_kappa);
    o.resample_threshold = r[22].value(d.resample_threshold);
    o.noise_zeta = r[23].value(d.noise_zeta);
    o.noise_scale = r[24].value(d.noise_scale);
    o.noise_dof = r[25].value(d.noise_dof);
    o.q_vv_floor = r[26].value(d.q_vv_floor);
    o.q_vv_ceiling = r[27].value(d.q_vv_ceiling);
    o
}

fn config_bits(c: &relnav_config) -> Vec<u64> {
    let mut v: Vec<u64> = [
        c.filter,
        c.frame,
        c.discretization,
        c.particles,
        c.resampler,
        c.noise_model,
        c.window,
    ]
    .iter()
    .map(|i| *i as u64)
    .collect();
    v.push(c.seed);
    let reals = [
        c.mean_motion,
        c.chaser_mass,
        c.sigma_range,
        c.sigma_angle,
        c.sigma_pos0,
        c.sigma_vel0,
        c.accel_psd,
        c.ukf_alpha,
        c.ukf_beta,
        c.ukf_kappa,
        c.resample_threshold,
        c.noise_zeta,
        c.noise_scale,
        c.noise_dof,
        c.q_vv_floor,
        c.q_vv_ceiling,
        c.hinf_period,
        c.hinf_delta_bar,
        c.hinf_b_pos,
        c.hinf_b_vel,
        c.hinf_d,
    ];
    v.extend(
        reals
            .iter()
            .chain(&c.x0)
            .chain(&c.q_pos)
            .chain(&c.q_vel)
            .map(|x| x.to_bits()),
    );
    v
}

fn last_error() -> String {
    // SAFETY: relnav_last_error returns a valid NUL-terminated string.
    unsafe { CStr::from_ptr(relnav_last_error()) }
        .to_string_lossy()
        .into_owned()
}

/// The contract every status obeys.
fn check(st: relnav_status, what: &str) {
    assert_ne!(
        st,
        relnav_status::RELNAV_ERROR_PANIC,
        "{what}: {}",
        last_error()
    );
    if st != relnav_status::RELNAV_OK {
        assert!(
            !last_error().is_empty(),
            "{what}: error {st:?} without a message"
        );
    }
}

/// State and covariance, and every getter exercised.
fn observe(est: *mut relnav_estimator) -> ([f64; 6], [f64; 36]) {
    let mut x = [0.0; 6];
    let mut p = [0.0; 36];
    let mut s = [0.0; 6];
    let mut nu = [0.0; 3];
    let mut nis = 0.0;
    let mut ess = 0.0;
    let mut q = [0.0; 3];
    let mut g = 0.0;
    // SAFETY: live handle, arrays of the documented lengths.
    unsafe {
        check(relnav_estimator_get_state(est, x.as_mut_ptr()), "get_state");
        check(
            relnav_estimator_get_covariance(est, p.as_mut_ptr()),
            "get_covariance",
        );
        check(relnav_estimator_get_sigma(est, s.as_mut_ptr()), "get_sigma");
        let mut e = [0.0; 12];
        check(
            relnav_estimator_get_estimate(est, e.as_mut_ptr()),
            "get_estimate",
        );
        // the one-call getter is the state then the sigma, bit for bit
        assert!(same_bits(&e[..6], &x), "get_estimate state != get_state");
        assert!(same_bits(&e[6..], &s), "get_estimate sigma != get_sigma");
        check(
            relnav_estimator_get_innovation(est, nu.as_mut_ptr(), &mut nis),
            "get_innovation",
        );
        check(relnav_estimator_get_ess(est, &mut ess), "get_ess");
        check(relnav_estimator_get_q_vv(est, q.as_mut_ptr()), "get_q_vv");
        check(
            relnav_estimator_get_hinf_gamma(est, &mut g),
            "get_hinf_gamma",
        );
        let mut info = relnav_hinf_design_info {
            route: -1,
            observer_route: -1,
            riccati_failure: -1,
            riccati_steps: -1,
            iterations: -1,
            solve_time: f64::NAN,
        };
        check(
            relnav_estimator_get_hinf_design(est, &mut info),
            "get_hinf_design",
        );
        // no design record, no gamma; a design record has a design time
        let none = info.route == relnav_hinf_route::RELNAV_HINF_ROUTE_NONE as i32;
        assert!(!none || g.is_nan(), "no design route but gamma {g}");
        assert!(
            none || (info.solve_time.is_finite() && info.riccati_steps >= 0),
            "design record {info:?}"
        );
    }
    (x, p)
}

fn measurement(m: &Meas, x: &[f64; 6]) -> Option<[f64; 3]> {
    match m {
        Meas::FromEstimate(d) => {
            let z = measure(x);
            Some([
                d[0].value(0.0) + z[0],
                d[1].value(0.0) + z[1],
                d[2].value(0.0) + z[2],
            ])
        }
        Meas::Raw(v) => Some(values3(v, [670.0, 0.9, 0.3])),
        Meas::None => None,
    }
}

fn run_estimator(config: &Config, ops: &[Op]) {
    let cfg = build_config(config);
    let hinf = cfg.filter == 9;
    let est = if hinf {
        let e = hinf_estimator();
        // SAFETY: live handle.
        check(unsafe { relnav_estimator_reset(e) }, "reset");
        e
    } else {
        // SAFETY: valid config pointer.
        let v = unsafe { relnav_config_validate(&cfg) };
        check(v, "config_validate");
        let mut e = std::ptr::null_mut();
        // SAFETY: valid pointers.
        let st = unsafe { relnav_estimator_new(&cfg, &mut e) };
        check(st, "estimator_new");
        assert_eq!(st, v, "validate and new disagree: {}", last_error());
        if st != relnav_status::RELNAV_OK {
            assert!(e.is_null());
            return;
        }
        let mut back = relnav_config_default();
        // SAFETY: live handle, writable config.
        check(
            unsafe { relnav_estimator_get_config(e, &mut back) },
            "get_config",
        );
        assert_eq!(
            config_bits(&back),
            config_bits(&cfg),
            "get_config round trip"
        );
        e
    };
    let particle = (4..=8).contains(&cfg.filter);
    let mut size = None;
    let mut saved: Option<(Vec<u8>, [f64; 6], [f64; 36])> = None;
    for op in ops.iter().take(MAX_OPS) {
        let (x, p) = observe(est);
        let (st, transactional, what) = match op {
            Op::Save { short } => {
                let mut len = 0usize;
                // SAFETY: live handle; a null buffer is the size query.
                let st = unsafe { relnav_estimator_save(est, std::ptr::null_mut(), 0, &mut len) };
                assert_eq!(st, relnav_status::RELNAV_OK, "size query: {}", last_error());
                assert_eq!(*size.get_or_insert(len), len, "the state size changed");
                let mut buf = vec![0xA5u8; len];
                if *short && len > 0 {
                    let mut l2 = 0usize;
                    // SAFETY: `buf` holds len - 1 writable bytes.
                    let st =
                        unsafe { relnav_estimator_save(est, buf.as_mut_ptr(), len - 1, &mut l2) };
                    assert_eq!(st, relnav_status::RELNAV_ERROR_BUFFER_TOO_SMALL);
                    assert_eq!(l2, len);
                    assert!(buf.iter().all(|b| *b == 0xA5), "a short buffer was written");
                }
                let mut l3 = 0usize;
                // SAFETY: `buf` holds len writable bytes.
                let st = unsafe { relnav_estimator_save(est, buf.as_mut_ptr(), len, &mut l3) };
                assert_eq!(st, relnav_status::RELNAV_OK, "save: {}", last_error());
                assert_eq!(l3, len);
                saved = Some((buf, x, p));
                (st, true, "save")
            }
            Op::Restore { damage: d } => {
                let blob = saved.as_ref().map_or(&[][..], |s| s.0.as_slice());
                let b = damage(blob, d, ESTIMATOR_HEADER);
                // SAFETY: live handle; `b` holds b.len() readable bytes (a dangling but
                // non-null pointer for an empty blob).
                let st = unsafe { relnav_estimator_restore(est, b.as_ptr(), b.len()) };
                check(st, "restore");
                if let (true, Some((bytes, sx, sp))) = (d.is_none(), &saved) {
                    assert_eq!(
                        st,
                        relnav_status::RELNAV_OK,
                        "intact state refused: {}",
                        last_error()
                    );
                    let (x2, p2) = observe(est);
                    assert!(
                        same_bits(sx, &x2) && same_bits(sp, &p2),
                        "restore is not the saved estimate"
                    );
                    let mut again = vec![0u8; bytes.len()];
                    let mut l = 0usize;
                    // SAFETY: `again` holds bytes.len() writable bytes.
                    let st2 = unsafe {
                        relnav_estimator_save(est, again.as_mut_ptr(), again.len(), &mut l)
                    };
                    assert_eq!(st2, relnav_status::RELNAV_OK);
                    assert!(again == *bytes, "save after restore gives other bytes");
                }
                (st, true, "restore")
            }
            Op::Step { thrust, z, dt } => {
                let u = values3(thrust, [0.0; 3]);
                let zm = measurement(z, &x);
                let zp = zm.as_ref().map_or(std::ptr::null(), |v| v.as_ptr());
                // SAFETY: live handle; arrays of 3 doubles or null.
                let st = unsafe { relnav_estimator_step(est, u.as_ptr(), zp, dt.value(1.0)) };
                (st, !(particle && zm.is_some()), "step")
            }
            Op::StepSensors {
                thrust,
                z,
                camera,
                gnss_position,
                gnss_velocity,
                dt,
            } => {
                let u = values3(thrust, [0.0; 3]);
                let zm = measurement(z, &x);
                let los = measure(&x);
                let cam = camera
                    .as_ref()
                    .map(|c| [c[0].value(0.0) + los[1], c[1].value(0.0) + los[2]]);
                let near = |g: &[Num; 3], at: usize| -> [f64; 3] {
                    std::array::from_fn(|i| g[i].value(0.0) + x[at + i])
                };
                let gp = gnss_position.as_ref().map(|g| near(g, 0));
                let gv = gnss_velocity.as_ref().map(|g| near(g, 3));
                let p3 = |v: &Option<[f64; 3]>| v.as_ref().map_or(std::ptr::null(), |v| v.as_ptr());
                let pc = cam.as_ref().map_or(std::ptr::null(), |v| v.as_ptr());
                // SAFETY: live handle; arrays of 3 doubles (the camera's: 2) or null.
                let st = unsafe {
                    relnav_estimator_step_sensors(
                        est,
                        u.as_ptr(),
                        p3(&zm),
                        pc,
                        p3(&gp),
                        p3(&gv),
                        dt.value(1.0),
                    )
                };
                let any = zm.is_some() || cam.is_some() || gp.is_some() || gv.is_some();
                (st, !(particle && any), "step_sensors")
            }
            Op::Predict { thrust, dt } => {
                let u = values3(thrust, [0.0; 3]);
                // SAFETY: live handle; 3 doubles.
                let st = unsafe { relnav_estimator_predict(est, u.as_ptr(), dt.value(1.0)) };
                (st, true, "predict")
            }
            Op::Update { z } => {
                let zm = measurement(z, &x).unwrap_or([670.0, 0.9, 0.3]);
                // SAFETY: live handle; 3 doubles.
                let st = unsafe { relnav_estimator_update(est, zm.as_ptr()) };
                (st, true, "update")
            }
            Op::Reset => {
                // SAFETY: live handle.
                let st = unsafe { relnav_estimator_reset(est) };
                assert_eq!(st, relnav_status::RELNAV_OK);
                (st, true, "reset")
            }
        };
        check(st, what);
        let (x2, p2) = observe(est);
        if st == relnav_status::RELNAV_OK {
            assert!(
                x2.iter().all(|v| v.is_finite()),
                "{what} succeeded with a non-finite state {x2:?}"
            );
        } else if transactional {
            assert!(
                same_bits(&x, &x2) && same_bits(&p, &p2),
                "failed {what} changed the estimate: {}",
                last_error()
            );
        }
    }
    if !hinf {
        // SAFETY: handle from relnav_estimator_new, freed once.
        unsafe { relnav_estimator_free(est) };
    }
}

fn run_hinf_runtime(m: &[Num; 109], x0: &[Num; 6], steps: &[(Option<[Num; 3]>, [Num; 3])]) {
    // around the identity-like observer: A_F = I, B_F = 0.1, C_F = I, E_F = 0, period 1
    let mut mats = relnav_hinf_matrices {
        a_f: [0.0; 36],
        b_f: [0.0; 18],
        c_f: [0.0; 36],
        e_f: [0.0; 18],
        period: 1.0,
    };
    for i in 0..36 {
        let diag = if i % 7 == 0 { 1.0 } else { 0.0 };
        mats.a_f[i] = m[i].value(diag);
        mats.c_f[i] = m[36 + i].value(diag);
    }
    for i in 0..18 {
        mats.b_f[i] = m[72 + i].value(if i % 4 == 0 { 0.1 } else { 0.0 });
        mats.e_f[i] = m[90 + i].value(0.0);
    }
    mats.period = m[108].value(1.0);
    let x: [f64; 6] = std::array::from_fn(|i| x0[i].value(100.0));
    let mut f = std::ptr::null_mut();
    // SAFETY: valid pointers.
    let st = unsafe { relnav_hinf_filter_new(&mats, x.as_ptr(), &mut f) };
    check(st, "hinf_filter_new");
    if st != relnav_status::RELNAV_OK {
        return;
    }
    for (y, a) in steps.iter().take(MAX_OPS) {
        let yv = y.map(|v| values3(&v, [100.0; 3]));
        let av = values3(a, [0.0; 3]);
        let mut before = [0.0; 6];
        let mut after = [0.0; 6];
        // SAFETY: live handle, arrays of 3 / 6 doubles or null.
        unsafe {
            check(
                relnav_hinf_filter_get_state(f, before.as_mut_ptr()),
                "hinf get_state",
            );
            let yp = yv.as_ref().map_or(std::ptr::null(), |v| v.as_ptr());
            let st = relnav_hinf_filter_step(f, yp, av.as_ptr());
            check(st, "hinf_filter_step");
            check(
                relnav_hinf_filter_get_state(f, after.as_mut_ptr()),
                "hinf get_state",
            );
            if st != relnav_status::RELNAV_OK {
                assert!(
                    same_bits(&before, &after),
                    "failed hinf step changed the state"
                );
            }
        }
    }
    // SAFETY: handle from relnav_hinf_filter_new, freed once.
    unsafe { relnav_hinf_filter_free(f) };
}

fuzz_target!(
    init: {
        let _ = hinf_estimator();
    },
    |input: Input| {
        match &input {
            Input::Estimator { config, ops } => run_estimator(config, ops),
            Input::HinfRuntime { matrices, x0, steps } => run_hinf_runtime(matrices, x0, steps),
        }
    }
);
