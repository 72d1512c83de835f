//! Fuzz target `fmi`: one FMU instance under an arbitrary sequence of fmi2 calls (the
//! exported `fmi2*` functions of the relnav crate, called as a master would, with a
//! C-variadic logger callback) with arbitrary arguments.
//!
//! Besides crashes, hangs (`-timeout=1`) and panics (libfuzzer-sys aborts on any panic,
//! also one the FMI boundary would catch), every call is checked against the FMI layer's
//! contract:
//! * no call returns `fmi2Fatal` (the status of a caught panic);
//! * a call that returns `fmi2Error` has logged a non-empty message under
//!   `logStatusError` during that call;
//! * every logger call gets a non-null instance name, category and message, NUL-terminated
//!   (the logger reads them; AddressSanitizer checks the reads), the message a `printf`
//!   format without conversions;
//! * after a successful `fmi2DoStep` the estimate outputs are finite;
//! * the unsupported functions (derivatives, cancel) return `fmi2Error`;
//! * FMU states (three slots): `fmi2SetFMUstate` of a state taken by `fmi2GetFMUstate`, or
//!   deserialised from its intact bytes, gives back every Real value bit for bit; a refused
//!   one changes none; intact serialised bytes deserialise; a serialisation buffer one
//!   byte short is refused and not written.
//!
//! Limits (fuzz/README.md): at most 16 particles (8 after instantiation and after every
//! `fmi2Reset` unless an input sets `particles`; larger
//! values are folded into 1..=16) and 64 calls per input; the H-infinity filter (code 9) is not selected here
//! (its LMI design takes ~0.5 s per `fmi2ExitInitializationMode`), the `capi` target runs it.
#![no_main]
#![feature(c_variadic)]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use relnav_fmi::fmi2::types::*;
use relnav_fmi::variables::VarType;
use relnav_fuzz::{damage, log_text, measure, same_bits, values3, Damage, Num, FMU_HEADER};
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
    /// Error messages logged since the last reset of the counter.
    static ERRORS_LOGGED: Cell<u32> = const { Cell::new(0) };
    static CALLS_LOGGED: Cell<u64> = const { Cell::new(0) };
}

/// The master's logger: checks its arguments; the message is a `printf` format without
/// conversions (`log_text`: every `%` and `#` doubled), so no variadic argument is read.
unsafe extern "C" fn logger(
    _env: fmi2ComponentEnvironment,
    name: fmi2String,
    status: c_int,
    category: fmi2String,
    message: fmi2String,
    _args: ...
) {
    assert!(!name.is_null() && !category.is_null() && !message.is_null());
    // SAFETY: the FMU promises NUL-terminated strings (ASan checks the reads).
    let (cat, fmt) = unsafe { (CStr::from_ptr(category), CStr::from_ptr(message)) };
    // SAFETY: as above.
    let _ = unsafe { CStr::from_ptr(name) };
    let text = log_text(fmt.to_bytes());
    assert!((0..=5).contains(&status), "status {status}");
    if status >= fmi2Status::fmi2Error as c_int {
        assert_eq!(cat.to_bytes(), b"logStatusError");
        assert!(!text.is_empty(), "empty error message");
        ERRORS_LOGGED.with(|c| c.set(c.get() + 1));
    }
    CALLS_LOGGED.with(|c| c.set(c.get() + 1));
}

#[derive(Arbitrary, Debug, Clone, Copy)]
enum IntVal {
    Start,
    Small(i8),
    Raw(i32),
}

#[derive(Arbitrary, Debug, Clone, Copy)]
enum Time {
    Now,
    Offset(Num),
    Raw(Num),
}

#[derive(Arbitrary, Debug)]
enum Op {
    SetupExperiment {
        tol: Option<Num>,
        start: Num,
        stop: Option<Num>,
    },
    EnterInit,
    ExitInit,
    Terminate,
    Reset,
    SetReal {
        var: u8,
        value: Num,
    },
    SetInteger {
        var: u8,
        value: IntVal,
    },
    SetBoolean {
        var: u8,
        value: bool,
    },
    SetString {
        var: u8,
    },
    GetReal {
        var: u8,
    },
    GetInteger {
        var: u8,
    },
    GetBoolean {
        var: u8,
    },
    GetString {
        var: u8,
    },
    /// Read every variable with the getter of its type.
    GetAll,
    /// Set `range, azimuth, elevation` to the measurement of the current estimate plus
    /// fuzzed offsets, and `measurement_valid`.
    Measure {
        offset: [Num; 3],
        valid: bool,
    },
    /// Set the three thrust inputs.
    Thrust([Num; 3]),
    DoStep {
        tc: Time,
        h: Num,
        no_set_prior: bool,
    },
    SetDebugLogging {
        on: bool,
        categories: u8,
    },
    Status {
        function: u8,
        kind: i8,
    },
    /// A function this FMU does not support (derivatives, cancel).
    Unsupported(u8),
    /// `fmi2GetFMUstate` into one of [`SLOTS`] state slots (a held state is overwritten).
    GetState {
        slot: u8,
    },
    /// `fmi2SetFMUstate` of a slot (null when empty).
    SetState {
        slot: u8,
    },
    /// `fmi2FreeFMUstate` of a slot.
    FreeState {
        slot: u8,
    },
    /// `fmi2SerializedFMUstateSize` and `fmi2SerializeFMUstate` of a slot (a buffer one
    /// byte short first when `short`); the bytes are kept.
    Serialize {
        slot: u8,
        short: bool,
    },
    /// `fmi2DeSerializeFMUstate` of the last serialised bytes after `damage` into a slot.
    DeSerialize {
        slot: u8,
        damage: Damage,
    },
}

/// Number of FMU state slots a run juggles.
const SLOTS: usize = 3;

/// One slot: the state and, when it was taken by `fmi2GetFMUstate` or deserialised from
/// intact bytes of such a state, every Real value at that moment (what a restore must
/// give back).
#[derive(Clone)]
struct Slot {
    state: fmi2FMUstate,
    reals: Option<Vec<f64>>,
}

#[derive(Arbitrary, Debug)]
struct Input {
    logging_on: bool,
    ops: Vec<Op>,
}

const MAX_OPS: usize = 64;
const MAX_PARTICLES: i32 = 16;
const N_VR: u32 = relnav_nav_model::N_VARS as u32 + 3; // a few unknown value references too

fn var_index(name: &str) -> Option<u32> {
    VARIABLES.iter().find(|v| v.name == name).map(|v| v.vr)
}

fn vr_of(var: u8) -> u32 {
    u32::from(var) % N_VR
}

fn start_of(vr: u32) -> f64 {
    VARIABLES.get(vr as usize).map_or(0.0, |v| v.start)
}

/// Run one fmi2 call and check its status against the contract.
fn call(f: impl FnOnce() -> fmi2Status) -> fmi2Status {
    let before = ERRORS_LOGGED.with(Cell::get);
    let st = f();
    assert_ne!(st, fmi2Status::fmi2Fatal, "fmi2Fatal: a panic was caught");
    if st == fmi2Status::fmi2Error {
        assert!(
            ERRORS_LOGGED.with(Cell::get) > before,
            "fmi2Error without a logged message"
        );
    }
    st
}

fn get_reals(c: fmi2Component, refs: &[u32]) -> (fmi2Status, Vec<f64>) {
    let mut out = vec![0.0; refs.len()];
    // SAFETY: live instance, arrays of refs.len() elements.
    let st = call(|| unsafe { fmi2GetReal(c, refs.as_ptr(), refs.len(), out.as_mut_ptr()) });
    (st, out)
}

fn set_reals(c: fmi2Component, refs: &[u32], vals: &[f64]) -> fmi2Status {
    // SAFETY: live instance, arrays of refs.len() elements.
    call(|| unsafe { fmi2SetReal(c, refs.as_ptr(), refs.len(), vals.as_ptr()) })
}

fn run(input: &Input) {
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
            c"fuzz".as_ptr(),
            fmi2CoSimulation,
            g.as_ptr(),
            std::ptr::null(),
            &cb,
            fmi2False,
            if input.logging_on {
                fmi2True
            } else {
                fmi2False
            },
        )
    };
    assert!(!c.is_null(), "fmi2Instantiate failed");
    let filter = var_index("filter");
    let particles = var_index("particles");
    let outs: Vec<u32> = ["x", "y", "z", "vx", "vy", "vz"]
        .iter()
        .filter_map(|n| var_index(n))
        .collect();
    let meas: Vec<u32> = ["range", "azimuth", "elevation"]
        .iter()
        .filter_map(|n| var_index(n))
        .collect();
    let thrust: Vec<u32> = ["thrust_x", "thrust_y", "thrust_z"]
        .iter()
        .filter_map(|n| var_index(n))
        .collect();
    let valid = var_index("measurement_valid");
    let real_vrs: Vec<u32> = VARIABLES
        .iter()
        .filter(|v| matches!(v.ty, VarType::Real(_)))
        .map(|v| v.vr)
        .collect();
    let mut slots = vec![
        Slot {
            state: std::ptr::null_mut(),
            reals: None
        };
        SLOTS
    ];
    // the last serialised bytes and the Reals of the state they hold
    let mut serialized: (Vec<u8>, Option<Vec<f64>>) = (Vec::new(), None);
    if let Some(r) = particles {
        // the start value, 1500, would make a particle filter's step take milliseconds
        // SAFETY: live instance; one element.
        call(|| unsafe { fmi2SetInteger(c, &r, 1, &8) });
    }
    for op in input.ops.iter().take(MAX_OPS) {
        // SAFETY (all calls below): `c` is the live instance; arrays hold the counts passed.
        unsafe {
            match op {
                Op::SetupExperiment { tol, start, stop } => {
                    let (td, tv) = tol.map_or((fmi2False, 0.0), |t| (fmi2True, t.value(1e-6)));
                    let (sd, sv) = stop.map_or((fmi2False, 0.0), |s| (fmi2True, s.value(1e6)));
                    call(|| fmi2SetupExperiment(c, td, tv, start.value(0.0), sd, sv));
                }
                Op::EnterInit => {
                    call(|| fmi2EnterInitializationMode(c));
                }
                Op::ExitInit => {
                    call(|| fmi2ExitInitializationMode(c));
                }
                Op::Terminate => {
                    call(|| fmi2Terminate(c));
                }
                Op::Reset => {
                    let st = call(|| fmi2Reset(c));
                    if let (fmi2Status::fmi2OK, Some(r)) = (st, particles) {
                        // back at the start values: 8 particles again, as after instantiation
                        call(|| fmi2SetInteger(c, &r, 1, &8));
                    }
                }
                Op::SetReal { var, value } => {
                    let r = vr_of(*var);
                    set_reals(c, &[r], &[value.value(start_of(r))]);
                }
                Op::SetInteger { var, value } => {
                    let r = vr_of(*var);
                    let mut v = match value {
                        IntVal::Start => start_of(r) as i32,
                        IntVal::Small(s) => i32::from(*s),
                        IntVal::Raw(x) => *x,
                    };
                    if Some(r) == filter && v == 9 {
                        continue; // the LMI design is the capi target's (see above)
                    }
                    if Some(r) == particles && v > MAX_PARTICLES {
                        v = 1 + v % MAX_PARTICLES;
                    }
                    call(|| fmi2SetInteger(c, &r, 1, &v));
                }
                Op::SetBoolean { var, value } => {
                    let r = vr_of(*var);
                    let v = if *value { fmi2True } else { fmi2False };
                    call(|| fmi2SetBoolean(c, &r, 1, &v));
                }
                Op::SetString { var } => {
                    let r = vr_of(*var);
                    let s: fmi2String = c"x".as_ptr();
                    call(|| fmi2SetString(c, &r, 1, &s));
                }
                Op::GetReal { var } => {
                    get_reals(c, &[vr_of(*var)]);
                }
                Op::GetInteger { var } => {
                    let r = vr_of(*var);
                    let mut v = 0;
                    call(|| fmi2GetInteger(c, &r, 1, &mut v));
                }
                Op::GetBoolean { var } => {
                    let r = vr_of(*var);
                    let mut v = 0;
                    call(|| fmi2GetBoolean(c, &r, 1, &mut v));
                }
                Op::GetString { var } => {
                    let r = vr_of(*var);
                    let mut v: fmi2String = std::ptr::null();
                    call(|| fmi2GetString(c, &r, 1, &mut v));
                }
                Op::GetAll => {
                    // one call per base type, as a master reads its outputs
                    let of = |f: fn(&VarType) -> bool| -> Vec<u32> {
                        VARIABLES
                            .iter()
                            .filter(|v| f(&v.ty))
                            .map(|v| v.vr)
                            .collect()
                    };
                    get_reals(c, &of(|t| matches!(t, VarType::Real(_))));
                    let ints = of(|t| !matches!(t, VarType::Real(_) | VarType::Boolean));
                    let mut iv = vec![0; ints.len()];
                    call(|| fmi2GetInteger(c, ints.as_ptr(), ints.len(), iv.as_mut_ptr()));
                    let bools = of(|t| matches!(t, VarType::Boolean));
                    let mut bv = vec![0; bools.len()];
                    call(|| fmi2GetBoolean(c, bools.as_ptr(), bools.len(), bv.as_mut_ptr()));
                }
                Op::Measure {
                    offset,
                    valid: is_valid,
                } => {
                    let (st, x) = get_reals(c, &outs);
                    if st == fmi2Status::fmi2OK && meas.len() == 3 {
                        let z = measure(&x);
                        let zv = [
                            z[0] + offset[0].value(0.0),
                            z[1] + offset[1].value(0.0),
                            z[2] + offset[2].value(0.0),
                        ];
                        set_reals(c, &meas, &zv);
                    }
                    if let Some(r) = valid {
                        let b = if *is_valid { fmi2True } else { fmi2False };
                        call(|| fmi2SetBoolean(c, &r, 1, &b));
                    }
                }
                Op::Thrust(t) => {
                    set_reals(c, &thrust, &values3(t, [0.0; 3]));
                }
                Op::DoStep {
                    tc,
                    h,
                    no_set_prior,
                } => {
                    let mut now = 0.0;
                    let _ =
                        call(|| fmi2GetRealStatus(c, status_kind::LAST_SUCCESSFUL_TIME, &mut now));
                    let t = match tc {
                        Time::Now => now,
                        Time::Offset(o) => now + o.value(0.0),
                        Time::Raw(v) => v.value(0.0),
                    };
                    let nsp = if *no_set_prior { fmi2True } else { fmi2False };
                    let st = call(|| fmi2DoStep(c, t, h.value(1.0), nsp));
                    if st == fmi2Status::fmi2OK {
                        let (gst, x) = get_reals(c, &outs);
                        assert_eq!(gst, fmi2Status::fmi2OK);
                        assert!(x.iter().all(|v| v.is_finite()), "non-finite outputs {x:?}");
                    }
                }
                Op::SetDebugLogging { on, categories } => {
                    let names = [
                        c"logStatusError",
                        c"logStatusWarning",
                        c"logInfo",
                        c"logCalls",
                        c"logNoSuchCategory",
                    ];
                    let cats: Vec<fmi2String> = names
                        .iter()
                        .enumerate()
                        .filter(|(i, _)| categories & (1 << i) != 0)
                        .map(|(_, n)| n.as_ptr())
                        .collect();
                    let on = if *on { fmi2True } else { fmi2False };
                    call(|| fmi2SetDebugLogging(c, on, cats.len(), cats.as_ptr()));
                }
                Op::Status { function, kind } => {
                    let k = c_int::from(*kind);
                    match function % 5 {
                        0 => {
                            let mut v = 0.0;
                            call(|| fmi2GetRealStatus(c, k, &mut v));
                        }
                        1 => {
                            let mut v = 0;
                            call(|| fmi2GetBooleanStatus(c, k, &mut v));
                        }
                        2 => {
                            let mut v = 0;
                            call(|| fmi2GetIntegerStatus(c, k, &mut v));
                        }
                        3 => {
                            let mut v: fmi2String = std::ptr::null();
                            call(|| fmi2GetStringStatus(c, k, &mut v));
                        }
                        _ => {
                            let mut v = 0;
                            call(|| fmi2GetStatus(c, k, &mut v));
                        }
                    }
                }
                Op::GetState { slot } => {
                    let k = usize::from(*slot) % SLOTS;
                    let st = call(|| fmi2GetFMUstate(c, &mut slots[k].state));
                    if st == fmi2Status::fmi2OK {
                        assert!(!slots[k].state.is_null());
                        let (gst, r) = get_reals(c, &real_vrs);
                        slots[k].reals = (gst == fmi2Status::fmi2OK).then_some(r);
                    }
                }
                Op::SetState { slot } => {
                    let k = usize::from(*slot) % SLOTS;
                    let (b0, before) = get_reals(c, &real_vrs);
                    let st = call(|| fmi2SetFMUstate(c, slots[k].state));
                    let (b1, after) = get_reals(c, &real_vrs);
                    if st == fmi2Status::fmi2OK {
                        if let (Some(r), fmi2Status::fmi2OK) = (&slots[k].reals, b1) {
                            assert!(same_bits(r, &after), "fmi2SetFMUstate: other values");
                        }
                    } else if b0 == fmi2Status::fmi2OK && b1 == fmi2Status::fmi2OK {
                        assert!(
                            same_bits(&before, &after),
                            "a refused fmi2SetFMUstate changed values"
                        );
                    }
                }
                Op::FreeState { slot } => {
                    let k = usize::from(*slot) % SLOTS;
                    let st = call(|| fmi2FreeFMUstate(c, &mut slots[k].state));
                    if st == fmi2Status::fmi2OK {
                        assert!(slots[k].state.is_null());
                        slots[k].reals = None;
                    }
                }
                Op::Serialize { slot, short } => {
                    let k = usize::from(*slot) % SLOTS;
                    let mut size = 0usize;
                    let st = call(|| fmi2SerializedFMUstateSize(c, slots[k].state, &mut size));
                    if st == fmi2Status::fmi2OK {
                        let mut buf = vec![0x5Au8; size];
                        if *short && size > 0 {
                            let st = call(|| {
                                fmi2SerializeFMUstate(
                                    c,
                                    slots[k].state,
                                    buf.as_mut_ptr().cast(),
                                    size - 1,
                                )
                            });
                            assert_eq!(st, fmi2Status::fmi2Error);
                            assert!(buf.iter().all(|b| *b == 0x5A), "a short buffer was written");
                        }
                        let st = call(|| {
                            fmi2SerializeFMUstate(c, slots[k].state, buf.as_mut_ptr().cast(), size)
                        });
                        assert_eq!(st, fmi2Status::fmi2OK, "fmi2SerializeFMUstate");
                        serialized = (buf, slots[k].reals.clone());
                    }
                }
                Op::DeSerialize { slot, damage: d } => {
                    let k = usize::from(*slot) % SLOTS;
                    let b = damage(&serialized.0, d, FMU_HEADER);
                    let st = call(|| {
                        fmi2DeSerializeFMUstate(c, b.as_ptr().cast(), b.len(), &mut slots[k].state)
                    });
                    if d.is_none() && !serialized.0.is_empty() {
                        assert_eq!(st, fmi2Status::fmi2OK, "intact bytes refused");
                    }
                    if st == fmi2Status::fmi2OK {
                        slots[k].reals = if d.is_none() {
                            serialized.1.clone()
                        } else {
                            None
                        };
                    }
                }
                Op::Unsupported(which) => {
                    let st = match which % 4 {
                        0 => call(|| {
                            fmi2GetDirectionalDerivative(
                                c,
                                std::ptr::null(),
                                0,
                                std::ptr::null(),
                                0,
                                std::ptr::null(),
                                std::ptr::null_mut(),
                            )
                        }),
                        1 => call(|| {
                            fmi2SetRealInputDerivatives(
                                c,
                                std::ptr::null(),
                                0,
                                std::ptr::null(),
                                std::ptr::null(),
                            )
                        }),
                        2 => call(|| {
                            fmi2GetRealOutputDerivatives(
                                c,
                                std::ptr::null(),
                                0,
                                std::ptr::null(),
                                std::ptr::null_mut(),
                            )
                        }),
                        _ => call(|| fmi2CancelStep(c)),
                    };
                    assert_eq!(
                        st,
                        fmi2Status::fmi2Error,
                        "an unsupported function succeeded"
                    );
                }
            }
        }
    }
    // SAFETY: from fmi2Instantiate, freed once; null is accepted too. The states still held
    // are freed half by fmi2FreeFMUstate, half with the instance.
    unsafe {
        for s in slots.iter_mut().step_by(2) {
            call(|| fmi2FreeFMUstate(c, &mut s.state));
        }
        fmi2FreeInstance(c);
        fmi2FreeInstance(std::ptr::null_mut());
    }
}

fuzz_target!(|input: Input| {
    run(&input);
});
