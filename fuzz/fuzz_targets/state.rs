//! Fuzz target `state`: saved-state deserialisation. An estimator (C ABI) or an FMU
//! instance of a fuzzed filter runs a few steps, saves its state, and the bytes — intact,
//! truncated, with a byte flipped, rewritten behind a valid checksum (also inside the
//! estimator state an FMU state embeds), with an arbitrary payload under a valid header,
//! or arbitrary — are restored: `relnav_estimator_restore` into the same estimator or a
//! fresh one of the same configuration; `fmi2DeSerializeFMUstate` and `fmi2SetFMUstate`
//! into the same instance or a fresh one (which has no estimator yet and builds one from
//! the state's parameters).
//!
//! Checked besides crashes, hangs and panics: no `RELNAV_ERROR_PANIC` / `fmi2Fatal`; every
//! error has a message (C ABI: `relnav_last_error`; FMU: logged under `logStatusError`);
//! intact bytes restore to the saved estimate bit for bit; refused bytes leave the
//! estimator bit for bit unchanged; accepted bytes leave a finite estimate.
//!
//! Limits (fuzz/README.md): filters 1-8 (the H-infinity design takes ~0.5 s; its state
//! is in the `capi` target), at most 16 particles, 16 steps before the save.
#![no_main]
#![feature(c_variadic)]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use relnav::*;
use relnav_fmi::fmi2::types::*;
use relnav_fmi::variables::VarType;
use relnav_fuzz::{damage, log_text, measure, same_bits, Damage, ESTIMATOR_HEADER, FMU_HEADER};
use relnav_nav_model::VARIABLES;
use std::cell::Cell;
use std::ffi::{c_int, CStr, CString};

// relnav.fmu's fmi2* functions in this binary, as the FMU's shared library exports them
relnav_fmi::export_fmi2!(relnav_nav_model::RelnavFmu);

/// relnav.fmu's GUID.
fn guid() -> &'static str {
    relnav_fmi::fmi2::description::guid_of(&relnav_nav_model::INFO)
}

thread_local! {
    static ERRORS_LOGGED: Cell<u32> = const { Cell::new(0) };
}

/// The master's logger: the message is a `printf` format without conversions (checked
/// by `log_text`, no variadic argument read); error messages are counted and non-empty.
unsafe extern "C" fn logger(
    _env: fmi2ComponentEnvironment,
    _name: fmi2String,
    status: c_int,
    _category: fmi2String,
    message: fmi2String,
    _args: ...
) {
    // SAFETY: the FMU passes a NUL-terminated format.
    let text = log_text(unsafe { CStr::from_ptr(message) }.to_bytes());
    if status >= fmi2Status::fmi2Error as c_int {
        assert!(!text.is_empty(), "empty error message");
        ERRORS_LOGGED.with(|c| c.set(c.get() + 1));
    }
}

#[derive(Arbitrary, Debug)]
struct Input {
    filter: u8,
    particles: u8,
    steps: u8,
    fmu: bool,
    /// Restore into a fresh estimator / instance instead of the one that saved.
    fresh: bool,
    damage: Damage,
}

const MAX_PARTICLES: i32 = 16;
const MAX_STEPS: u8 = 16;

fn last_error() -> String {
    // SAFETY: relnav_last_error returns a valid NUL-terminated string.
    unsafe { CStr::from_ptr(relnav_last_error()) }
        .to_string_lossy()
        .into_owned()
}

fn estimate(e: *mut relnav_estimator) -> ([f64; 6], [f64; 36]) {
    let (mut x, mut p) = ([0.0; 6], [0.0; 36]);
    // SAFETY: live handle, arrays of the documented sizes.
    unsafe {
        assert_eq!(
            relnav_estimator_get_state(e, x.as_mut_ptr()),
            relnav_status::RELNAV_OK
        );
        assert_eq!(
            relnav_estimator_get_covariance(e, p.as_mut_ptr()),
            relnav_status::RELNAV_OK
        );
    }
    (x, p)
}

fn run_capi(input: &Input) {
    let mut cfg = relnav_config_default();
    cfg.filter = 1 + i32::from(input.filter % 8);
    cfg.particles = 1 + i32::from(input.particles) % MAX_PARTICLES;
    let new = || {
        let mut e = std::ptr::null_mut();
        // SAFETY: valid pointers.
        let st = unsafe { relnav_estimator_new(&cfg, &mut e) };
        assert_eq!(st, relnav_status::RELNAV_OK, "{}", last_error());
        e
    };
    let est = new();
    for k in 0..input.steps % (MAX_STEPS + 1) {
        let (x, _) = estimate(est);
        let z = measure(&x);
        let zp = if k % 3 == 2 {
            std::ptr::null()
        } else {
            z.as_ptr()
        };
        // SAFETY: live handle, arrays of 3 or null.
        let st = unsafe { relnav_estimator_step(est, [0.0; 3].as_ptr(), zp, 1.0) };
        assert_ne!(st, relnav_status::RELNAV_ERROR_PANIC);
    }
    let mut len = 0usize;
    // SAFETY: live handle; size query.
    unsafe { relnav_estimator_save(est, std::ptr::null_mut(), 0, &mut len) };
    let mut blob = vec![0u8; len];
    // SAFETY: `blob` holds len writable bytes.
    let st = unsafe { relnav_estimator_save(est, blob.as_mut_ptr(), len, &mut len) };
    assert_eq!(st, relnav_status::RELNAV_OK);
    let saved = estimate(est);
    let target = if input.fresh { new() } else { est };
    let before = estimate(target);
    let b = damage(&blob, &input.damage, ESTIMATOR_HEADER);
    // SAFETY: live handle; `b` holds b.len() readable bytes.
    let st = unsafe { relnav_estimator_restore(target, b.as_ptr(), b.len()) };
    assert_ne!(st, relnav_status::RELNAV_ERROR_PANIC, "{}", last_error());
    let after = estimate(target);
    if input.damage.is_none() {
        assert_eq!(
            st,
            relnav_status::RELNAV_OK,
            "intact state refused: {}",
            last_error()
        );
        assert!(same_bits(&saved.0, &after.0) && same_bits(&saved.1, &after.1));
    } else if st == relnav_status::RELNAV_OK {
        assert!(
            after.0.iter().all(|v| v.is_finite()),
            "accepted state: {:?}",
            after.0
        );
    } else {
        assert!(!last_error().is_empty());
        assert!(
            same_bits(&before.0, &after.0) && same_bits(&before.1, &after.1),
            "a refused state changed the estimator"
        );
    }
    // SAFETY: handles from relnav_estimator_new, each freed once.
    unsafe {
        if input.fresh {
            relnav_estimator_free(target);
        }
        relnav_estimator_free(est);
    }
}

fn call(f: impl FnOnce() -> fmi2Status) -> fmi2Status {
    let before = ERRORS_LOGGED.with(Cell::get);
    let st = f();
    assert_ne!(st, fmi2Status::fmi2Fatal, "fmi2Fatal: a panic was caught");
    if st == fmi2Status::fmi2Error {
        assert!(
            ERRORS_LOGGED.with(Cell::get) > before,
            "fmi2Error without a message"
        );
    }
    st
}

fn vr(name: &str) -> u32 {
    VARIABLES
        .iter()
        .find(|v| v.name == name)
        .map(|v| v.vr)
        .unwrap_or(u32::MAX)
}

fn instantiate() -> fmi2Component {
    let g = CString::new(guid()).expect("GUID has no NUL");
    let cb = fmi2CallbackFunctions {
        logger: Some(logger),
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: std::ptr::null_mut(),
    };
    // SAFETY: valid strings and callbacks for the duration of the call.
    let c = unsafe {
        fmi2Instantiate(
            c"state".as_ptr(),
            fmi2CoSimulation,
            g.as_ptr(),
            std::ptr::null(),
            &cb,
            fmi2False,
            fmi2False,
        )
    };
    assert!(!c.is_null());
    c
}

fn reals(c: fmi2Component, refs: &[u32]) -> Option<Vec<f64>> {
    let mut v = vec![0.0; refs.len()];
    // SAFETY: live instance; arrays of refs.len().
    let st = call(|| unsafe { fmi2GetReal(c, refs.as_ptr(), refs.len(), v.as_mut_ptr()) });
    (st == fmi2Status::fmi2OK).then_some(v)
}

fn run_fmu(input: &Input) {
    let real_vrs: Vec<u32> = VARIABLES
        .iter()
        .filter(|v| matches!(v.ty, VarType::Real(_)))
        .map(|v| v.vr)
        .collect();
    let outs: Vec<u32> = ["x", "y", "z"].iter().map(|n| vr(n)).collect();
    let meas: Vec<u32> = ["range", "azimuth", "elevation"]
        .iter()
        .map(|n| vr(n))
        .collect();
    let c = instantiate();
    let steps = input.steps % (MAX_STEPS + 2);
    // SAFETY (all calls): `c` is live; arrays hold the counts passed.
    unsafe {
        let f = 1 + i32::from(input.filter % 8);
        let p = 1 + i32::from(input.particles) % MAX_PARTICLES;
        call(|| fmi2SetInteger(c, &vr("filter"), 1, &f));
        call(|| fmi2SetInteger(c, &vr("particles"), 1, &p));
        // steps = 0: a state in Instantiated; 1: in initialisation mode; more: stepping
        if steps >= 1 {
            call(|| fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0));
            call(|| fmi2EnterInitializationMode(c));
        }
        if steps >= 2 {
            call(|| fmi2ExitInitializationMode(c));
            for k in 0..steps - 2 {
                if let Some(x) = reals(c, &outs) {
                    let z = measure(&x);
                    call(|| fmi2SetReal(c, meas.as_ptr(), 3, z.as_ptr()));
                }
                let v = if k % 3 == 2 { fmi2False } else { fmi2True };
                call(|| fmi2SetBoolean(c, &vr("measurement_valid"), 1, &v));
                call(|| fmi2DoStep(c, f64::from(k), 1.0, fmi2True));
            }
        }
        let mut s: fmi2FMUstate = std::ptr::null_mut();
        assert_eq!(call(|| fmi2GetFMUstate(c, &mut s)), fmi2Status::fmi2OK);
        let saved = reals(c, &real_vrs);
        let mut size = 0usize;
        assert_eq!(
            call(|| fmi2SerializedFMUstateSize(c, s, &mut size)),
            fmi2Status::fmi2OK
        );
        let mut blob = vec![0u8; size];
        let st = call(|| fmi2SerializeFMUstate(c, s, blob.as_mut_ptr().cast(), size));
        assert_eq!(st, fmi2Status::fmi2OK);
        let target = if input.fresh { instantiate() } else { c };
        let before = reals(target, &real_vrs);
        let b = damage(&blob, &input.damage, FMU_HEADER);
        let mut t: fmi2FMUstate = std::ptr::null_mut();
        let st = call(|| fmi2DeSerializeFMUstate(target, b.as_ptr().cast(), b.len(), &mut t));
        if input.damage.is_none() {
            assert_eq!(st, fmi2Status::fmi2OK, "intact bytes refused");
        }
        if st == fmi2Status::fmi2OK {
            let st = call(|| fmi2SetFMUstate(target, t));
            let after = reals(target, &real_vrs);
            if input.damage.is_none() {
                assert_eq!(st, fmi2Status::fmi2OK, "intact state refused");
                if let (Some(a), Some(b)) = (&saved, &after) {
                    assert!(same_bits(a, b), "restored values differ");
                }
            } else if st != fmi2Status::fmi2OK {
                if let (Some(a), Some(b)) = (&before, &after) {
                    assert!(same_bits(a, b), "a refused state changed values");
                }
            }
            call(|| fmi2FreeFMUstate(target, &mut t));
        }
        call(|| fmi2FreeFMUstate(c, &mut s));
        if input.fresh {
            fmi2FreeInstance(target);
        }
        fmi2FreeInstance(c);
    }
}

fuzz_target!(|input: Input| {
    if input.fmu {
        run_fmu(&input);
    } else {
        run_capi(&input);
    }
});
