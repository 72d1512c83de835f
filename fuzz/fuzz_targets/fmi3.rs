//! Fuzz target `fmi3`: one relnav3.fmu instance (FMI 3.0 Co-Simulation) under an arbitrary
//! sequence of `fmi3*` calls (the functions `export_fmi3!` exports, called as a master
//! would, with FMI 3.0's plain logger callback) with arbitrary arguments: instantiated with
//! or without Event Mode, optionally initialised and stepped first (see [`Start`]); scalars,
//! arrays, the computed covariance, `time` and unknown value references read and written
//! with the right number of values, one less, one more or any.
//!
//! Besides crashes, hangs (`-timeout=1`) and panics (libfuzzer-sys aborts on any panic,
//! also one the FMI boundary would catch), every call is checked against the FMI layer's
//! contract:
//! * no call returns `fmi3Fatal` (the status of a caught panic);
//! * a call that returns `fmi3Error` has logged a non-empty message under
//!   `logStatusError` during that call;
//! * every logger call gets the master's instance environment and a non-null,
//!   NUL-terminated UTF-8 category and message (AddressSanitizer checks the reads), the
//!   category one of the four declared, `logStatusError` exactly for `fmi3Error` and
//!   worse, any other only while logging is on and the category enabled (tracked from
//!   `loggingOn` and `fmi3SetDebugLogging`), the message at most 1500 characters plus
//!   ` ...`; `fmi3SetDebugLogging` fails exactly when it names an unknown or a null
//!   category;
//! * the harness tracks the FMI 3.0 state (Instantiated, Initialization, Step, Event,
//!   Terminated, Error; unknown after a restored state it cannot name) from the statuses:
//!   `fmi3EnterInitializationMode`, `fmi3ExitInitializationMode`, `fmi3EnterEventMode`,
//!   `fmi3EnterStepMode`, `fmi3UpdateDiscreteStates` and `fmi3DoStep` outside their state
//!   return `fmi3Error`; `fmi3EnterEventMode` of an instance made without `eventModeUsed`
//!   fails; `fmi3Reset` succeeds in every state; reading every variable succeeds in every
//!   state that allows gets (all but Instantiated), and `fmi_status` reads the worst
//!   status since instantiation or reset (or the one a restored state carries);
//! * a successful set of Float64, Int32 or Boolean values reads back bit for bit (in
//!   Initialization, Step and Event Mode);
//! * `fmi3DoStep` with a null out-pointer and `fmi3UpdateDiscreteStates` with one are
//!   refused with `fmi3Error`; a successful `fmi3DoStep` reports no event, no termination,
//!   no early return and `lastSuccessfulTime = currentCommunicationPoint + step`, which
//!   `time` then reads; a failed one leaves `time` (and a `lastSuccessfulTime` it wrote);
//!   a successful `fmi3UpdateDiscreteStates` reports all flags false and leaves `time`;
//!   after either succeeds the `position` and `velocity` arrays are finite;
//! * 24 unsupported functions (other types, clocks, derivatives and dependencies,
//!   configuration mode, Model Exchange and Scheduled Execution) return `fmi3Error` with a
//!   logged message; the Model Exchange and Scheduled Execution instantiations and
//!   Co-Simulation instantiations with a wrong token, required intermediate variables or a
//!   null or empty name return null with a logged error; calls on a null instance return
//!   `fmi3Error`; `fmi3GetVersion` is `"3.0"`;
//! * FMU states (three slots): `fmi3SetFMUState` of a state taken by `fmi3GetFMUState`, or
//!   deserialised from its intact bytes, gives back every Float64 value (scalars, arrays,
//!   the covariance, `time`) bit for bit; a refused one changes none; a handle the instance
//!   never made is refused by `fmi3SetFMUState`, `fmi3FreeFMUState`,
//!   `fmi3SerializedFMUStateSize` and `fmi3SerializeFMUState`, which write nothing and
//!   change no value; getting into a held slot keeps its handle; freeing a held state (or
//!   null) succeeds; a null state has no size; a serialisation buffer one byte short is
//!   refused and not written; serialised bytes start with `RELNAVFM` and carry an embedded
//!   estimator state exactly when taken in Step, Event or Terminated mode (the layout
//!   `fuzz/src/lib.rs` damages); intact bytes deserialise and serialise back to the same
//!   bytes.
//!
//! Limits (fuzz/README.md): at most 16 particles (8 after instantiation and after every
//! `fmi3Reset` unless an input sets `particles`; larger values are folded into 1..=16) and
//! 64 operations per input (after the start); the H-infinity filter (code 9) is not
//! selected here (its LMI design takes ~0.5 s per `fmi3ExitInitializationMode`), the `capi`
//! target runs it.
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use relnav_fmi::fmi2::MAX_LOG_CHARS;
use relnav_fmi::fmi3::description::{
    published, token_of, vr_of, Published, ARRAY_VR_BASE, COMPUTED_VR_BASE, TIME_VR,
};
use relnav_fmi::fmi3::types::*;
use relnav_fmi::model::ModelInfo;
use relnav_fmi::variables::TypeClass;
use relnav_fuzz::{
    damage, embedded_estimator, measure, same_bits, values3, Damage, Num, FMU_HEADER,
};
use std::cell::Cell;
use std::ffi::{c_void, CStr, CString};
use std::ptr::{null, null_mut};
use std::sync::LazyLock;

use fmi3Status::{fmi3Error, fmi3Fatal, fmi3OK};

// relnav3.fmu's fmi3* functions in this binary, as the FMU's shared library exports them
relnav_fmi::export_fmi3!(relnav_nav_model::RelnavFmu);

fn info() -> &'static ModelInfo {
    &relnav_nav_model::INFO
}

/// The log categories relnav3.fmu declares, in `modelDescription.xml` order.
const CATEGORIES: [&str; 4] = ["logStatusError", "logStatusWarning", "logInfo", "logCalls"];

/// What the master passes as `instanceEnvironment` (the logger checks it gets it back).
static ENV: u8 = 0;

fn env() -> fmi3InstanceEnvironment {
    std::ptr::addr_of!(ENV).cast_mut().cast()
}

thread_local! {
    /// Error messages logged since the start of the process.
    static ERRORS_LOGGED: Cell<u64> = const { Cell::new(0) };
    /// The instance's logging switch and categories as the harness tracks them.
    static LOGGING: Cell<(bool, [bool; 4])> = const { Cell::new((false, [true; 4])) };
}

/// The master's logger (FMI 3.0: not variadic, the message is the text itself).
unsafe extern "C" fn logger(
    environment: fmi3InstanceEnvironment,
    status: fmi3Status,
    category: fmi3String,
    message: fmi3String,
) {
    assert_eq!(environment, env(), "another instanceEnvironment");
    assert!(!category.is_null() && !message.is_null());
    // SAFETY: the FMU promises NUL-terminated strings (ASan checks the reads).
    let (cat, msg) = unsafe { (CStr::from_ptr(category), CStr::from_ptr(message)) };
    let cat = std::str::from_utf8(cat.to_bytes()).expect("category is not UTF-8");
    let msg = std::str::from_utf8(msg.to_bytes()).expect("message is not UTF-8");
    assert!(
        msg.chars().count() <= MAX_LOG_CHARS + 4,
        "message of {} characters",
        msg.chars().count()
    );
    let idx = CATEGORIES
        .iter()
        .position(|c| *c == cat)
        .unwrap_or_else(|| panic!("undeclared log category {cat:?}"));
    assert_eq!(
        idx == 0,
        status >= fmi3Error,
        "status {status:?} under {cat}: {msg}"
    );
    if idx == 0 {
        assert!(!msg.is_empty(), "empty error message");
        ERRORS_LOGGED.with(|c| c.set(c.get() + 1));
    } else {
        let (on, cats) = LOGGING.with(Cell::get);
        assert!(
            on && cats[idx],
            "{cat} message while it is off (logging {on}, categories {cats:?}): {msg}"
        );
    }
}

/// The FMI 3.0 state of the instance as the harness tracks it from the statuses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Mode {
    Instantiated,
    Init,
    Step,
    Event,
    Terminated,
    Error,
    /// Restored from a state whose mode the harness cannot name.
    Unknown,
}

impl Mode {
    /// Gets may be tried (certainly allowed, or unknown).
    fn readable(self) -> bool {
        self != Mode::Instantiated
    }

    /// Gets are certainly allowed.
    fn surely_readable(self) -> bool {
        !matches!(self, Mode::Instantiated | Mode::Unknown)
    }
}

/// The value references the harness uses.
struct Tables {
    token: CString,
    /// What an operation's reference bytes index: every table row (array elements are
    /// unknown to FMI 3.0), a few past the table, `time`, every array and computed output
    /// and one past each, and `u32::MAX`.
    candidates: Vec<u32>,
    /// Every published Float64 / Int32 / Boolean variable, and how many values each list
    /// holds.
    float64: (Vec<u32>, usize),
    int32: (Vec<u32>, usize),
    boolean: (Vec<u32>, usize),
    position: u32,
    velocity: u32,
    measurement: u32,
    thrust: u32,
    camera: u32,
    gnss_position: u32,
    gnss_velocity: u32,
    measurement_valid: u32,
    camera_valid: u32,
    gnss_valid: u32,
    gnss_velocity_valid: u32,
    filter: u32,
    particles: u32,
    fmi_status: u32,
}

fn scalar(name: &str) -> u32 {
    relnav_nav_model::VARIABLES
        .iter()
        .find(|v| v.name == name)
        .map(|v| v.vr)
        .unwrap_or_else(|| panic!("no variable {name}"))
}

fn array(name: &str) -> u32 {
    vr_of(info(), name).unwrap_or_else(|| panic!("no array {name}"))
}

/// The value class of a published value reference.
fn class_of(r: u32) -> Option<TypeClass> {
    let info = info();
    match published(info, r)? {
        Published::Scalar(v) => info.lookup(v).map(|d| TypeClass::of(&d.ty)),
        Published::Array(a) => a
            .elements
            .first()
            .and_then(|e| info.lookup(*e))
            .map(|d| TypeClass::of(&d.ty)),
        Published::Computed(..) | Published::Time => Some(TypeClass::Real),
    }
}

/// The start value of each value `r` holds (one 0 for an unknown reference).
fn starts(r: u32) -> Vec<f64> {
    let info = info();
    let start = |v: u32| info.lookup(v).map_or(0.0, |d| d.start);
    match published(info, r) {
        Some(Published::Scalar(v)) => vec![start(v)],
        Some(Published::Array(a)) => a.elements.iter().map(|e| start(*e)).collect(),
        Some(p) => vec![0.0; p.len()],
        None => vec![0.0],
    }
}

fn count_of(refs: &[u32]) -> usize {
    refs.iter()
        .map(|r| published(info(), *r).map_or(1, |p| p.len()))
        .sum()
}

static T: LazyLock<Tables> = LazyLock::new(|| {
    let info = info();
    let n = relnav_nav_model::N_VARS as u32;
    let mut candidates: Vec<u32> = (0..n + 3).collect();
    candidates.push(TIME_VR);
    candidates.extend(ARRAY_VR_BASE..=ARRAY_VR_BASE + info.arrays.len() as u32);
    candidates.extend(COMPUTED_VR_BASE..=COMPUTED_VR_BASE + info.computed.len() as u32);
    candidates.push(u32::MAX);
    let of = |class: TypeClass| {
        let refs: Vec<u32> = candidates
            .iter()
            .copied()
            .filter(|r| class_of(*r) == Some(class))
            .collect();
        let n = count_of(&refs);
        (refs, n)
    };
    let t = Tables {
        token: CString::new(token_of(info)).expect("token has no NUL"),
        float64: of(TypeClass::Real),
        int32: of(TypeClass::Integer),
        boolean: of(TypeClass::Boolean),
        candidates,
        position: array("position"),
        velocity: array("velocity"),
        measurement: array("measurement"),
        thrust: array("thrust"),
        camera: array("camera"),
        gnss_position: array("gnss_position"),
        gnss_velocity: array("gnss_velocity"),
        measurement_valid: scalar("measurement_valid"),
        camera_valid: scalar("camera_valid"),
        gnss_valid: scalar("gnss_valid"),
        gnss_velocity_valid: scalar("gnss_velocity_valid"),
        filter: scalar("filter"),
        particles: scalar("particles"),
        fmi_status: scalar("fmi_status"),
    };
    assert!(t.float64.0.contains(&TIME_VR) && t.float64.0.contains(&COMPUTED_VR_BASE));
    assert!(t.int32.0.contains(&t.fmi_status) && t.int32.0.contains(&t.filter));
    t
});

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

/// `nValues` of a get or set relative to the count its references hold.
#[derive(Arbitrary, Debug, Clone, Copy)]
enum Count {
    Right,
    OneLess,
    OneMore,
    Any(u8),
}

impl Count {
    fn of(self, right: usize) -> usize {
        match self {
            Count::Right => right,
            Count::OneLess => right.saturating_sub(1),
            Count::OneMore => right + 1,
            Count::Any(n) => usize::from(n % 64),
        }
    }
}

#[derive(Arbitrary, Debug)]
enum Op {
    EnterInit {
        tol: Option<Num>,
        start: Num,
        stop: Option<Num>,
    },
    ExitInit,
    EnterEventMode,
    EnterStepMode,
    /// `fmi3UpdateDiscreteStates`; `null_out`: some out-pointers null.
    UpdateDiscreteStates {
        null_out: Option<u8>,
    },
    Terminate,
    Reset,
    /// A set of up to 4 references (bytes indexing `Tables::candidates`) and `count` values.
    SetFloat64 {
        refs: Vec<u8>,
        count: Count,
        values: Vec<Num>,
    },
    SetInt32 {
        refs: Vec<u8>,
        count: Count,
        values: Vec<IntVal>,
    },
    SetBoolean {
        refs: Vec<u8>,
        count: Count,
        values: u64,
    },
    GetFloat64 {
        refs: Vec<u8>,
        count: Count,
    },
    GetInt32 {
        refs: Vec<u8>,
        count: Count,
    },
    GetBoolean {
        refs: Vec<u8>,
        count: Count,
    },
    /// Read every variable, one call per type.
    GetAll,
    /// Set the `measurement` array to the measurement of the current `position` estimate
    /// plus fuzzed offsets, and `measurement_valid`.
    Measure {
        offset: [Num; 3],
        valid: bool,
    },
    /// Camera line of sight and relative GNSS position and velocity near the estimate,
    /// each given (its flag true) or not (false).
    Sensors {
        camera: Option<[Num; 2]>,
        gnss: Option<[Num; 3]>,
        gnss_velocity: Option<[Num; 3]>,
    },
    /// Set the `thrust` array.
    Thrust([Num; 3]),
    DoStep {
        tc: Time,
        h: Num,
        no_set_prior: bool,
        null_out: Option<u8>,
    },
    SetDebugLogging {
        on: bool,
        categories: u8,
    },
    /// A function this FMU does not offer.
    Unsupported(u8),
    /// An instantiation the FMU refuses.
    RefusedInstantiation(u8),
    /// A call on a null instance.
    NullInstance(u8),
    /// `fmi3GetFMUState` into one of [`SLOTS`] state slots (a held state is overwritten).
    GetState {
        slot: u8,
    },
    /// `fmi3SetFMUState` of a slot (null when empty).
    SetState {
        slot: u8,
    },
    FreeState {
        slot: u8,
    },
    /// `fmi3SerializedFMUStateSize` and `fmi3SerializeFMUState` of a slot (a buffer one
    /// byte short first when `short`); the bytes are kept.
    Serialize {
        slot: u8,
        short: bool,
    },
    /// `fmi3DeserializeFMUState` of the last serialised bytes after `damage` into a slot.
    Deserialize {
        slot: u8,
        damage: Damage,
    },
    /// A state call with a handle the instance never made.
    ForeignState(u8),
}

#[derive(Arbitrary, Debug)]
struct Input {
    event_mode_used: bool,
    logging_on: bool,
    early_return_allowed: bool,
    /// Initialised and stepped before the operations, so that short inputs start where
    /// long ones get to.
    start: Option<Start>,
    ops: Vec<Op>,
}

/// A start (each part an operation below, with its checks): a filter of [`FILTERS`] set,
/// `fmi3EnterInitializationMode` at 0 s, `fmi3ExitInitializationMode`, then `steps % 4`
/// steps of 1 s, each with the measurement of the current estimate (with Event Mode:
/// between `fmi3EnterStepMode` and `fmi3EnterEventMode`, so that the operations start in
/// Event Mode as they do in Step Mode without it).
#[derive(Arbitrary, Debug)]
struct Start {
    filter: u8,
    steps: u8,
}

/// The filter codes an initialised input starts with (not 9, the H-infinity filter).
const FILTERS: [i32; 10] = [1, 2, 3, 4, 5, 6, 7, 8, 10, 11];

const MAX_OPS: usize = 64;
const MAX_REFS: usize = 4;
const MAX_PARTICLES: i32 = 16;
/// Number of FMU state slots a run juggles.
const SLOTS: usize = 3;
/// What the harness writes into an out-argument before a call (to see whether it was
/// written).
const SENTINEL: f64 = -8.125e-300;

/// What the harness knows of a state: the Float64 values when it was taken (when they
/// could be read), the mode and the worst status it carries.
#[derive(Clone)]
struct Known {
    reals: Option<Vec<f64>>,
    mode: Mode,
    worst: Option<i32>,
}

impl Known {
    const NOTHING: Known = Known {
        reals: None,
        mode: Mode::Unknown,
        worst: None,
    };
}

struct Slot {
    state: fmi3FMUState,
    known: Known,
}

/// Run one fmi3 call and check its status against the contract (no `fmi3Fatal`; an
/// `fmi3Error` has logged an error).
fn checked(f: impl FnOnce() -> fmi3Status) -> fmi3Status {
    let before = ERRORS_LOGGED.with(Cell::get);
    let st = f();
    assert_ne!(st, fmi3Fatal, "fmi3Fatal: a panic was caught");
    if st == fmi3Error {
        assert!(
            ERRORS_LOGGED.with(Cell::get) > before,
            "fmi3Error without a logged message"
        );
    }
    st
}

struct Run {
    c: fmi3Instance,
    event_mode_used: bool,
    mode: Mode,
    /// The `fmi_status` the instance must report.
    worst: Option<i32>,
    slots: Vec<Slot>,
    /// The last serialised bytes and what they hold.
    serialized: (Vec<u8>, Known),
}

impl Run {
    /// [`checked`], with the tracked mode and worst status updated for a failure.
    fn call(&mut self, f: impl FnOnce() -> fmi3Status) -> fmi3Status {
        let st = checked(f);
        if st == fmi3Error {
            self.mode = Mode::Error;
            self.worst = self.worst.map(|w| w.max(fmi3Error as i32));
        } else if st != fmi3OK {
            self.mode = Mode::Unknown;
            self.worst = None;
        }
        st
    }

    /// [`Run::call`] of a function allowed only in `allowed`: refused outside them.
    fn call_in(&mut self, allowed: &[Mode], f: impl FnOnce() -> fmi3Status) -> fmi3Status {
        let m = self.mode;
        let st = self.call(f);
        if m != Mode::Unknown && !allowed.contains(&m) {
            assert_eq!(st, fmi3Error, "allowed in {m:?}");
        }
        st
    }

    fn get_f64(&mut self, refs: &[u32], n: usize) -> (fmi3Status, Vec<f64>) {
        let c = self.c;
        let mut out = vec![0.0; n];
        let p = out.as_mut_ptr();
        // SAFETY: live instance; `refs` and `out` hold the counts passed.
        let st = self.call(|| unsafe { fmi3GetFloat64(c, refs.as_ptr(), refs.len(), p, n) });
        (st, out)
    }

    fn set_f64(&mut self, refs: &[u32], vals: &[f64]) -> fmi3Status {
        let c = self.c;
        // SAFETY: live instance; `refs` and `vals` hold the counts passed.
        self.call(|| unsafe {
            fmi3SetFloat64(c, refs.as_ptr(), refs.len(), vals.as_ptr(), vals.len())
        })
    }

    fn set_bool(&mut self, r: u32, v: bool) -> fmi3Status {
        let c = self.c;
        // SAFETY: live instance; one value.
        self.call(|| unsafe { fmi3SetBoolean(c, &r, 1, &v, 1) })
    }

    fn set_particles(&mut self) {
        let (c, r) = (self.c, T.particles);
        // SAFETY: live instance; one value. The start value, 1500, would make a particle
        // filter's step take milliseconds.
        self.call(|| unsafe { fmi3SetInt32(c, &r, 1, &8, 1) });
    }

    /// Every Float64 value, when gets may be tried (they must succeed where they are
    /// certainly allowed).
    fn read_all(&mut self) -> Option<Vec<f64>> {
        let m = self.mode;
        if !m.readable() {
            return None;
        }
        let (refs, n) = &T.float64;
        let (st, v) = self.get_f64(refs, *n);
        if m.surely_readable() {
            assert_eq!(st, fmi3OK, "reading every Float64 in {m:?}");
        }
        (st == fmi3OK).then_some(v)
    }

    /// `time`, when gets may be tried.
    fn time_now(&mut self) -> Option<f64> {
        if !self.mode.readable() {
            return None;
        }
        let (st, v) = self.get_f64(&[TIME_VR], 1);
        (st == fmi3OK).then(|| v[0])
    }

    /// After a successful step or discrete update: `position` and `velocity` finite.
    fn check_estimate(&mut self, what: &str) {
        let (st, x) = self.get_f64(&[T.position, T.velocity], 6);
        assert_eq!(st, fmi3OK, "reading the estimate after {what}");
        assert!(
            x.iter().all(|v| v.is_finite()),
            "non-finite estimate after {what}: {x:?}"
        );
    }

    /// What a state just taken holds (the mode and worst status from before the read,
    /// which may fail in an unknown mode).
    fn known_now(&mut self) -> Known {
        let (mode, worst) = (self.mode, self.worst);
        Known {
            reals: self.read_all(),
            mode,
            worst,
        }
    }
}

fn refs_of(vars: &[u8]) -> Vec<u32> {
    vars.iter()
        .take(MAX_REFS)
        .map(|v| T.candidates[usize::from(*v) % T.candidates.len()])
        .collect()
}

/// Each value a set of `refs` writes: (reference, element), its start value.
fn elements(refs: &[u32]) -> Vec<((u32, usize), f64)> {
    refs.iter()
        .flat_map(|r| {
            starts(*r)
                .into_iter()
                .enumerate()
                .map(move |(i, s)| ((*r, i), s))
        })
        .collect()
}

/// What a get of `refs` must give back after a successful set of `vals` (each value's
/// element, the last write of an element wins).
fn expected(keys: &[(u32, usize)], vals: &[f64]) -> Vec<f64> {
    keys.iter()
        .map(|k| {
            let last = keys.iter().rposition(|x| x == k).expect("the key is there");
            vals[last]
        })
        .collect()
}

fn run(input: &Input) {
    // SAFETY: the FMU returns a static C string.
    assert_eq!(unsafe { CStr::from_ptr(fmi3GetVersion()) }, c"3.0");
    LOGGING.with(|l| l.set((input.logging_on, [true; 4])));
    // SAFETY: valid strings and callbacks for the duration of the instance.
    let c = unsafe {
        fmi3InstantiateCoSimulation(
            c"fuzz".as_ptr(),
            T.token.as_ptr(),
            null(),
            false,
            input.logging_on,
            input.event_mode_used,
            input.early_return_allowed,
            null(),
            0,
            env(),
            Some(logger),
            None,
        )
    };
    assert!(!c.is_null(), "fmi3InstantiateCoSimulation failed");
    let mut r = Run {
        c,
        event_mode_used: input.event_mode_used,
        mode: Mode::Instantiated,
        worst: Some(0),
        slots: (0..SLOTS)
            .map(|_| Slot {
                state: null_mut(),
                known: Known::NOTHING,
            })
            .collect(),
        serialized: (Vec::new(), Known::NOTHING),
    };
    r.set_particles();
    let mut start = Vec::new();
    if let Some(s) = &input.start {
        let filter = u8::try_from(T.filter).expect("filter's value reference is below 256");
        start.extend([
            Op::SetInt32 {
                refs: vec![filter],
                count: Count::Right,
                values: vec![IntVal::Raw(FILTERS[usize::from(s.filter) % FILTERS.len()])],
            },
            Op::EnterInit {
                tol: None,
                start: Num::Default,
                stop: None,
            },
            Op::ExitInit,
        ]);
        let steps = s.steps % 4;
        if input.event_mode_used && steps > 0 {
            start.push(Op::EnterStepMode);
        }
        for _ in 0..steps {
            start.push(Op::Measure {
                offset: [Num::Default; 3],
                valid: true,
            });
            start.push(Op::DoStep {
                tc: Time::Now,
                h: Num::Default,
                no_set_prior: false,
                null_out: None,
            });
        }
        if input.event_mode_used && steps > 0 {
            start.push(Op::EnterEventMode);
        }
    }
    for op in start.iter().chain(input.ops.iter().take(MAX_OPS)) {
        // SAFETY (all calls below): `c` is the live instance; arrays hold the counts passed.
        unsafe {
            step(&mut r, op);
        }
    }
    // SAFETY: from fmi3InstantiateCoSimulation, freed once; null is accepted too. The
    // states still held are freed half by fmi3FreeFMUState, half with the instance.
    unsafe {
        for k in (0..SLOTS).step_by(2) {
            let mut s = r.slots[k].state;
            let st = r.call(|| fmi3FreeFMUState(c, &mut s));
            assert_eq!(st, fmi3OK, "freeing a held state");
            assert!(s.is_null());
        }
        fmi3FreeInstance(c);
        fmi3FreeInstance(null_mut());
    }
}

/// One operation.
///
/// # Safety
/// `r.c` is the live instance.
unsafe fn step(r: &mut Run, op: &Op) {
    use Mode::*;
    let c = r.c;
    // SAFETY: by the caller's contract; every array holds the count passed with it.
    unsafe {
        match op {
            Op::EnterInit { tol, start, stop } => {
                let (td, tv) = tol.map_or((false, 0.0), |t| (true, t.value(1e-6)));
                let (sd, sv) = stop.map_or((false, 0.0), |s| (true, s.value(1e6)));
                let t0 = start.value(0.0);
                let st = r.call_in(&[Instantiated], || {
                    fmi3EnterInitializationMode(c, td, tv, t0, sd, sv)
                });
                if st == fmi3OK {
                    r.mode = Init;
                }
            }
            Op::ExitInit => {
                if r.call_in(&[Init], || fmi3ExitInitializationMode(c)) == fmi3OK {
                    r.mode = if r.event_mode_used { Event } else { Step };
                }
            }
            Op::EnterEventMode => {
                let st = r.call_in(&[Step], || fmi3EnterEventMode(c));
                if st == fmi3OK {
                    assert!(r.event_mode_used, "Event Mode without eventModeUsed");
                    r.mode = Event;
                }
            }
            Op::EnterStepMode => {
                if r.call_in(&[Event], || fmi3EnterStepMode(c)) == fmi3OK {
                    r.mode = Step;
                }
            }
            Op::UpdateDiscreteStates { null_out } => {
                let now = r.time_now();
                let nulls = null_out.map_or(0, |b| b % 63 + 1);
                let mut flags = [true; 5];
                let mut next = SENTINEL;
                let fp = flags.as_mut_ptr();
                let ptr = |i: usize| out_ptr(fp, nulls, i);
                let (a, b, n, v, d) = (ptr(0), ptr(1), ptr(2), ptr(3), ptr(4));
                let t = out_ptr(&mut next, nulls >> 5, 0);
                let st = r.call_in(&[Event], || fmi3UpdateDiscreteStates(c, a, b, n, v, d, t));
                if nulls != 0 {
                    assert_eq!(st, fmi3Error, "a null out-pointer accepted");
                }
                if st == fmi3OK {
                    assert_eq!(flags, [false; 5], "fmi3UpdateDiscreteStates flags");
                    r.check_estimate("fmi3UpdateDiscreteStates");
                    if let Some(t0) = now {
                        let t1 = r.time_now().expect("time after a discrete update");
                        assert_eq!(t1.to_bits(), t0.to_bits(), "a discrete update moved time");
                    }
                }
            }
            Op::Terminate => {
                if r.call(|| fmi3Terminate(c)) == fmi3OK {
                    r.mode = Terminated;
                }
            }
            Op::Reset => {
                let st = r.call(|| fmi3Reset(c));
                assert_eq!(st, fmi3OK, "fmi3Reset");
                r.mode = Instantiated;
                r.worst = Some(0);
                r.set_particles();
            }
            Op::SetFloat64 {
                refs,
                count,
                values,
            } => {
                let refs = refs_of(refs);
                let el = elements(&refs);
                let n = count.of(el.len());
                let vals: Vec<f64> = (0..n)
                    .map(|j| {
                        let num = values.get(j).or(values.first()).copied();
                        num.unwrap_or(Num::Default)
                            .value(el.get(j).map_or(0.0, |e| e.1))
                    })
                    .collect();
                let m = r.mode;
                let st = r.set_f64(&refs, &vals);
                if st == fmi3OK && matches!(m, Init | Step | Event) {
                    let keys: Vec<_> = el.iter().map(|e| e.0).collect();
                    let (gst, got) = r.get_f64(&refs, n);
                    assert_eq!(gst, fmi3OK, "reading back a set");
                    assert!(
                        same_bits(&got, &expected(&keys, &vals)),
                        "fmi3GetFloat64 after fmi3SetFloat64 {refs:?} {vals:?}: {got:?}"
                    );
                }
            }
            Op::SetInt32 {
                refs,
                count,
                values,
            } => {
                let refs = refs_of(refs);
                let el = elements(&refs);
                let n = count.of(el.len());
                let mut vals = Vec::with_capacity(n);
                for j in 0..n {
                    let key = el.get(j).map(|e| e.0 .0);
                    let start = el.get(j).map_or(0.0, |e| e.1);
                    let val = values.get(j).or(values.first()).copied();
                    let mut v = match val.unwrap_or(IntVal::Start) {
                        IntVal::Start => start as i32,
                        IntVal::Small(s) => i32::from(s),
                        IntVal::Raw(x) => x,
                    };
                    if key == Some(T.filter) && v == 9 {
                        return; // the LMI design is the capi target's (see above)
                    }
                    if key == Some(T.particles) && v > MAX_PARTICLES {
                        v = 1 + v % MAX_PARTICLES;
                    }
                    vals.push(v);
                }
                let m = r.mode;
                let st = r.call(|| fmi3SetInt32(c, refs.as_ptr(), refs.len(), vals.as_ptr(), n));
                if st == fmi3OK && matches!(m, Init | Step | Event) {
                    let keys: Vec<_> = el.iter().map(|e| e.0).collect();
                    let want = expected(
                        &keys,
                        &vals.iter().map(|v| f64::from(*v)).collect::<Vec<_>>(),
                    );
                    let mut got = vec![0i32; n];
                    let gp = got.as_mut_ptr();
                    let gst = r.call(|| fmi3GetInt32(c, refs.as_ptr(), refs.len(), gp, n));
                    assert_eq!(gst, fmi3OK, "reading back a set");
                    let got: Vec<f64> = got.iter().map(|v| f64::from(*v)).collect();
                    assert!(
                        same_bits(&got, &want),
                        "fmi3GetInt32 after fmi3SetInt32 {refs:?} {vals:?}: {got:?}"
                    );
                }
            }
            Op::SetBoolean {
                refs,
                count,
                values,
            } => {
                let refs = refs_of(refs);
                let el = elements(&refs);
                let n = count.of(el.len());
                let vals: Vec<bool> = (0..n).map(|j| values >> (j % 64) & 1 != 0).collect();
                let m = r.mode;
                let st = r.call(|| fmi3SetBoolean(c, refs.as_ptr(), refs.len(), vals.as_ptr(), n));
                if st == fmi3OK && matches!(m, Init | Step | Event) {
                    let keys: Vec<_> = el.iter().map(|e| e.0).collect();
                    let as_f64 = |v: &[bool]| -> Vec<f64> {
                        v.iter().map(|b| f64::from(u8::from(*b))).collect()
                    };
                    let want = expected(&keys, &as_f64(&vals));
                    let mut got = vec![false; n];
                    let gp = got.as_mut_ptr();
                    let gst = r.call(|| fmi3GetBoolean(c, refs.as_ptr(), refs.len(), gp, n));
                    assert_eq!(gst, fmi3OK, "reading back a set");
                    assert!(
                        same_bits(&as_f64(&got), &want),
                        "fmi3GetBoolean after fmi3SetBoolean {refs:?} {vals:?}: {got:?}"
                    );
                }
            }
            Op::GetFloat64 { refs, count } => {
                let refs = refs_of(refs);
                let n = count.of(count_of(&refs));
                r.get_f64(&refs, n);
            }
            Op::GetInt32 { refs, count } => {
                let refs = refs_of(refs);
                let n = count.of(count_of(&refs));
                let mut out = vec![0i32; n];
                let p = out.as_mut_ptr();
                r.call(|| fmi3GetInt32(c, refs.as_ptr(), refs.len(), p, n));
            }
            Op::GetBoolean { refs, count } => {
                let refs = refs_of(refs);
                let n = count.of(count_of(&refs));
                let mut out = vec![false; n];
                let p = out.as_mut_ptr();
                r.call(|| fmi3GetBoolean(c, refs.as_ptr(), refs.len(), p, n));
            }
            Op::GetAll => {
                let m = r.mode;
                if !m.readable() {
                    return;
                }
                r.read_all();
                let (ints, ni) = (&T.int32.0, T.int32.1);
                let mut iv = vec![0i32; ni];
                let ip = iv.as_mut_ptr();
                let ist = r.call(|| fmi3GetInt32(c, ints.as_ptr(), ints.len(), ip, ni));
                let (bools, nb) = (&T.boolean.0, T.boolean.1);
                let mut bv = vec![false; nb];
                let bp = bv.as_mut_ptr();
                let bst = r.call(|| fmi3GetBoolean(c, bools.as_ptr(), bools.len(), bp, nb));
                if m.surely_readable() {
                    assert_eq!(
                        (ist, bst),
                        (fmi3OK, fmi3OK),
                        "reading every variable in {m:?}"
                    );
                    if let Some(w) = r.worst {
                        let at = ints.iter().position(|x| *x == T.fmi_status);
                        let got = at.map(|k| iv[k]);
                        assert_eq!(got, Some(w), "fmi_status");
                    }
                }
            }
            Op::Measure { offset, valid } => {
                let p = r.mode.readable().then(|| r.get_f64(&[T.position], 3));
                let x = match p {
                    Some((fmi3OK, x)) => x,
                    _ => vec![0.0; 3],
                };
                let z = measure(&x);
                let zv = [
                    z[0] + offset[0].value(0.0),
                    z[1] + offset[1].value(0.0),
                    z[2] + offset[2].value(0.0),
                ];
                r.set_f64(&[T.measurement], &zv);
                r.set_bool(T.measurement_valid, *valid);
            }
            Op::Sensors {
                camera,
                gnss,
                gnss_velocity,
            } => {
                let p = r
                    .mode
                    .readable()
                    .then(|| r.get_f64(&[T.position, T.velocity], 6));
                let x = match p {
                    Some((fmi3OK, x)) => x,
                    _ => vec![0.0; 6],
                };
                if let Some(o) = camera {
                    let z = measure(&x);
                    r.set_f64(
                        &[T.camera],
                        &[z[1] + o[0].value(0.0), z[2] + o[1].value(0.0)],
                    );
                }
                r.set_bool(T.camera_valid, camera.is_some());
                if let Some(o) = gnss {
                    r.set_f64(&[T.gnss_position], &values3(o, [x[0], x[1], x[2]]));
                }
                r.set_bool(T.gnss_valid, gnss.is_some());
                if let Some(o) = gnss_velocity {
                    r.set_f64(&[T.gnss_velocity], &values3(o, [x[3], x[4], x[5]]));
                }
                r.set_bool(T.gnss_velocity_valid, gnss_velocity.is_some());
            }
            Op::Thrust(t) => {
                r.set_f64(&[T.thrust], &values3(t, [0.0; 3]));
            }
            Op::DoStep {
                tc,
                h,
                no_set_prior,
                null_out,
            } => {
                let now = r.time_now();
                let base = now.unwrap_or(0.0);
                let t = match tc {
                    Time::Now => base,
                    Time::Offset(o) => base + o.value(0.0),
                    Time::Raw(v) => v.value(0.0),
                };
                let h = h.value(1.0);
                let nulls = null_out.map_or(0, |b| b % 15 + 1);
                let mut flags = [true; 3];
                let mut last = SENTINEL;
                let fp = flags.as_mut_ptr();
                let ptr = |i: usize| out_ptr(fp, nulls, i);
                let (ev, term, early) = (ptr(0), ptr(1), ptr(2));
                let lp = out_ptr(&mut last, nulls >> 3, 0);
                let nsp = *no_set_prior;
                let st = r.call_in(&[Step], || fmi3DoStep(c, t, h, nsp, ev, term, early, lp));
                if nulls != 0 {
                    assert_eq!(st, fmi3Error, "a null out-pointer accepted");
                }
                if st == fmi3OK {
                    assert_eq!(flags, [false; 3], "fmi3DoStep flags");
                    assert_eq!(last.to_bits(), (t + h).to_bits(), "lastSuccessfulTime");
                    assert_eq!(r.time_now().map(f64::to_bits), Some(last.to_bits()), "time");
                    r.check_estimate("fmi3DoStep");
                } else if st == fmi3Error {
                    if let Some(t0) = now {
                        if last.to_bits() != SENTINEL.to_bits() {
                            assert_eq!(last.to_bits(), t0.to_bits(), "lastSuccessfulTime");
                        }
                        let t1 = r.time_now().map(f64::to_bits);
                        assert_eq!(t1, Some(t0.to_bits()), "a failed step moved time");
                    }
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
                let mut cats: Vec<fmi3String> = names
                    .iter()
                    .enumerate()
                    .filter(|(i, _)| categories & (1 << i) != 0)
                    .map(|(_, n)| n.as_ptr())
                    .collect();
                let with_null = categories & (1 << 5) != 0;
                if with_null {
                    cats.push(null());
                }
                let on = *on;
                let st = r.call(|| fmi3SetDebugLogging(c, on, cats.len(), cats.as_ptr()));
                // the switches after it, as documented: no names = all categories; named
                // ones switched in order up to an unknown one (an error); on = logging on
                let (mut lon, mut lcats) = LOGGING.with(Cell::get);
                if cats.is_empty() {
                    (lon, lcats) = (on, [on; 4]);
                } else if !with_null {
                    for (i, _) in names
                        .iter()
                        .enumerate()
                        .filter(|(i, _)| categories & (1 << i) != 0)
                    {
                        if i < 4 {
                            lcats[i] = on;
                        }
                    }
                    if on && categories & (1 << 4) == 0 {
                        lon = true;
                    }
                }
                LOGGING.with(|l| l.set((lon, lcats)));
                let bad = with_null || categories & (1 << 4) != 0;
                assert_eq!(st == fmi3Error, bad, "fmi3SetDebugLogging {categories:#x}");
            }
            Op::Unsupported(which) => {
                let p: *mut c_void = null_mut();
                let q: *const c_void = null();
                let st = r.call(|| match which % 24 {
                    0 => fmi3GetFloat32(c, q, 0, p, 0),
                    1 => fmi3SetFloat32(c, q, 0, q, 0),
                    2 => fmi3GetInt8(c, q, 0, p, 0),
                    3 => fmi3SetUInt64(c, q, 0, q, 0),
                    4 => fmi3GetString(c, q, 0, p, 0),
                    5 => fmi3SetString(c, q, 0, q, 0),
                    6 => fmi3GetBinary(c, q, 0, p, p, 0),
                    7 => fmi3GetClock(c, q, 0, p),
                    8 => fmi3SetClock(c, q, 0, q),
                    9 => fmi3GetDirectionalDerivative(c, q, 0, q, 0, q, 0, p, 0),
                    10 => fmi3GetAdjointDerivative(c, q, 0, q, 0, q, 0, p, 0),
                    11 => fmi3EnterConfigurationMode(c),
                    12 => fmi3ExitConfigurationMode(c),
                    13 => fmi3SetTime(c, 1.0),
                    14 => fmi3EvaluateDiscreteStates(c),
                    15 => fmi3EnterContinuousTimeMode(c),
                    16 => fmi3CompletedIntegratorStep(c, true, p.cast(), p.cast()),
                    17 => fmi3GetNumberOfContinuousStates(c, p),
                    18 => fmi3GetOutputDerivatives(c, q, 0, q, p, 0),
                    19 => fmi3GetIntervalDecimal(c, q, 0, p, p),
                    20 => fmi3ActivateModelPartition(c, 0, 0.0),
                    21 => fmi3GetVariableDependencies(c, 0, p, p, p, p, 0),
                    22 => fmi3SetShiftDecimal(c, q, 0, q),
                    _ => fmi3GetEventIndicators(c, p, 0),
                });
                assert_eq!(st, fmi3Error, "unsupported function {}", which % 24);
            }
            Op::RefusedInstantiation(which) => {
                let before = ERRORS_LOGGED.with(Cell::get);
                let cosim = |name: fmi3String, token: fmi3String, n_required: usize| {
                    let vr = 0u32;
                    fmi3InstantiateCoSimulation(
                        name,
                        token,
                        null(),
                        false,
                        false,
                        false,
                        false,
                        &vr,
                        n_required,
                        env(),
                        Some(logger),
                        None,
                    )
                };
                let token = T.token.as_ptr();
                let other = c"{00000000-0000-0000-0000-000000000000}".as_ptr();
                let made = match which % 6 {
                    0 => fmi3InstantiateModelExchange(
                        c"me".as_ptr(),
                        token,
                        null(),
                        false,
                        false,
                        env(),
                        Some(logger),
                    ),
                    1 => fmi3InstantiateScheduledExecution(
                        c"se".as_ptr(),
                        token,
                        null(),
                        false,
                        false,
                        env(),
                        Some(logger),
                        None,
                        None,
                        None,
                    ),
                    2 => cosim(c"x".as_ptr(), other, 0),
                    3 => cosim(c"x".as_ptr(), token, 1),
                    4 => cosim(null(), token, 0),
                    _ => cosim(c"".as_ptr(), token, 0),
                };
                if !made.is_null() {
                    fmi3FreeInstance(made);
                    panic!("instantiation {} accepted", which % 6);
                }
                assert!(
                    ERRORS_LOGGED.with(Cell::get) > before,
                    "refused instantiation without a logged error"
                );
            }
            Op::NullInstance(which) => {
                let mut s: fmi3FMUState = null_mut();
                let mut v = 0.0;
                let vr = TIME_VR;
                let st = match which % 5 {
                    0 => fmi3Reset(null_mut()),
                    1 => fmi3GetFloat64(null_mut(), &vr, 1, &mut v, 1),
                    2 => fmi3GetFMUState(null_mut(), &mut s),
                    3 => fmi3EnterInitializationMode(null_mut(), false, 0.0, 0.0, false, 0.0),
                    _ => fmi3GetFloat32(null_mut(), null(), 0, null_mut(), 0),
                };
                assert_eq!(st, fmi3Error, "a call on a null instance");
                assert!(s.is_null());
            }
            Op::GetState { slot } => {
                let k = usize::from(*slot) % SLOTS;
                let held = r.slots[k].state;
                let mut s = held;
                let st = r.call(|| fmi3GetFMUState(c, &mut s));
                if st == fmi3OK {
                    assert!(!s.is_null());
                    if !held.is_null() {
                        assert_eq!(s, held, "a held state was not overwritten in place");
                    }
                    r.slots[k].state = s;
                    r.slots[k].known = r.known_now();
                }
            }
            Op::SetState { slot } => {
                let k = usize::from(*slot) % SLOTS;
                let before = r.read_all();
                let s = r.slots[k].state;
                let st = r.call(|| fmi3SetFMUState(c, s));
                if st == fmi3OK {
                    let known = r.slots[k].known.clone();
                    r.mode = known.mode;
                    r.worst = known.worst;
                    let after = r.read_all();
                    if let (Some(want), Some(got)) = (&known.reals, &after) {
                        assert!(same_bits(want, got), "fmi3SetFMUState: other values");
                    }
                } else {
                    let after = r.read_all();
                    if let (Some(b), Some(a)) = (&before, &after) {
                        assert!(same_bits(b, a), "a refused fmi3SetFMUState changed values");
                    }
                }
            }
            Op::FreeState { slot } => {
                let k = usize::from(*slot) % SLOTS;
                let mut s = r.slots[k].state;
                let st = r.call(|| fmi3FreeFMUState(c, &mut s));
                assert_eq!(st, fmi3OK, "freeing a held state (or null)");
                assert!(s.is_null());
                r.slots[k] = Slot {
                    state: s,
                    known: Known::NOTHING,
                };
            }
            Op::Serialize { slot, short } => {
                let k = usize::from(*slot) % SLOTS;
                let s = r.slots[k].state;
                let mut size = 0usize;
                let st = r.call(|| fmi3SerializedFMUStateSize(c, s, &mut size));
                if s.is_null() {
                    assert_eq!(st, fmi3Error, "the size of a null state");
                }
                if st != fmi3OK {
                    return;
                }
                let mut buf = vec![0x5Au8; size];
                let bp = buf.as_mut_ptr();
                if *short && size > 0 {
                    let st = r.call(|| fmi3SerializeFMUState(c, s, bp, size - 1));
                    assert_eq!(st, fmi3Error, "a short buffer accepted");
                    assert!(buf.iter().all(|b| *b == 0x5A), "a short buffer was written");
                }
                let st = r.call(|| fmi3SerializeFMUState(c, s, bp, size));
                assert_eq!(st, fmi3OK, "fmi3SerializeFMUState");
                assert!(buf.len() > FMU_HEADER && buf.starts_with(b"RELNAVFM"));
                let known = r.slots[k].known.clone();
                match known.mode {
                    Step | Event | Terminated => {
                        assert!(embedded_estimator(&buf).is_some(), "no estimator state")
                    }
                    Instantiated | Init => {
                        assert!(embedded_estimator(&buf).is_none(), "an estimator state")
                    }
                    Error | Unknown => {}
                }
                r.serialized = (buf, known);
            }
            Op::Deserialize { slot, damage: d } => {
                let k = usize::from(*slot) % SLOTS;
                let b = damage(&r.serialized.0, d, FMU_HEADER);
                let mut s = r.slots[k].state;
                let st = r.call(|| fmi3DeserializeFMUState(c, b.as_ptr(), b.len(), &mut s));
                let intact = d.is_none() && !r.serialized.0.is_empty();
                if intact {
                    assert_eq!(st, fmi3OK, "intact bytes refused");
                }
                if st != fmi3OK {
                    return;
                }
                assert!(!s.is_null());
                r.slots[k].state = s;
                r.slots[k].known = if intact {
                    r.serialized.1.clone()
                } else {
                    Known::NOTHING
                };
                if intact {
                    // and back to the same bytes
                    let mut size = 0usize;
                    let st = r.call(|| fmi3SerializedFMUStateSize(c, s, &mut size));
                    assert_eq!((st, size), (fmi3OK, b.len()), "size of deserialised bytes");
                    let mut again = vec![0u8; size];
                    let ap = again.as_mut_ptr();
                    let st = r.call(|| fmi3SerializeFMUState(c, s, ap, size));
                    assert_eq!(st, fmi3OK);
                    assert!(again == b, "deserialised bytes serialise to other bytes");
                }
            }
            Op::ForeignState(which) => {
                let mut marker = [0u64; 4];
                let foreign: fmi3FMUState = marker.as_mut_ptr().cast();
                let before = r.read_all();
                let st = match which % 4 {
                    0 => r.call(|| fmi3SetFMUState(c, foreign)),
                    1 => {
                        let mut s = foreign;
                        let st = r.call(|| fmi3FreeFMUState(c, &mut s));
                        assert_eq!(s, foreign, "a foreign handle was changed");
                        st
                    }
                    2 => {
                        let mut size = 7usize;
                        let st = r.call(|| fmi3SerializedFMUStateSize(c, foreign, &mut size));
                        assert_eq!(size, 7, "a size was written");
                        st
                    }
                    _ => {
                        let mut buf = [0x5Au8; 256];
                        let bp = buf.as_mut_ptr();
                        let st = r.call(|| fmi3SerializeFMUState(c, foreign, bp, buf.len()));
                        assert!(
                            buf.iter().all(|b| *b == 0x5A),
                            "written for a foreign handle"
                        );
                        st
                    }
                };
                assert_eq!(st, fmi3Error, "a foreign FMU state accepted");
                assert_eq!(marker, [0; 4], "a foreign handle was dereferenced");
                let after = r.read_all();
                if let (Some(b), Some(a)) = (&before, &after) {
                    assert!(same_bits(b, a), "a foreign FMU state changed values");
                }
            }
        }
    }
}

/// Out-pointer `i` past `base`, or null where bit `i` of `nulls` is set (a master passing
/// a null out-pointer).
fn out_ptr<T>(base: *mut T, nulls: u8, i: usize) -> *mut T {
    if nulls & (1 << i) != 0 {
        null_mut()
    } else {
        base.wrapping_add(i)
    }
}

fuzz_target!(|input: Input| {
    run(&input);
});
