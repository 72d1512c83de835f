//! One instance, generic over its [`Model`] and its [`Binding`]: all instance
//! data in one struct (the value of every variable, the life-cycle state, time, logging
//! switches, the FMU states handed out) and the checks every model shares (call order,
//! causality and state of a set, code lists, step times, FMU states); the model only turns
//! parameters and inputs into outputs ([`crate::model`]), as the Reference-FMUs keep
//! `model.c` apart from `cosimulation.c` and `fmi2Functions.c`.
//!
//! Nothing here depends on an FMI version: a binding (`fmi2/`) converts the C
//! arguments, passes the name of its function (messages name the call the master made)
//! and the mask of the states that function is allowed in, and converts the [`Status`]
//! back.

use crate::binding::Binding;
use crate::logging::{LOG_CALLS, LOG_CATEGORIES};
use crate::machine::ModelState;
use crate::model::{Model, ModelInfo};
use crate::state::{decode, encode, Snapshot, StateRegistry};
use crate::status::{error, Failure, Status};
use crate::variables::{start_values, Causality, TypeClass, VarDef, VarType};
use relnav_core::numerics::state::{refuse, StateError};
use std::ffi::{c_void, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// What the get/set dispatch needs of one variable, derived from its [`VarDef`] (so the
/// table stays the one source; [`access_of`]): its [`TypeClass`] and the states (bit mask
/// of [`ModelState`]) in which a set may write it **directly**, with no other check and no
/// other effect. That is an input after initialisation: parameters are checked by the
/// model and a set before initialisation refreshes the initial outputs, which the full
/// path does (the same rules and messages either way, only faster for the master's
/// inputs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct VarAccess {
    /// Base type class.
    pub class: TypeClass,
    /// States in which a set is a plain store.
    pub direct_set: u8,
}

/// An array of the model ([`ModelInfo::arrays`]) as one slice of the values: its elements
/// are consecutive value references of one base type with one [`VarAccess`].
#[derive(Debug, Clone, Copy)]
struct Run {
    /// `values[start..end]`; an empty range past the end (`start > end`) for an array that
    /// is no run, or not of the table's class.
    start: u32,
    end: u32,
    /// States in which its elements take a plain store.
    direct_set: u8,
}

impl Run {
    const NONE: Run = Run {
        start: 1,
        end: 0,
        direct_set: 0,
    };

    /// Array `elements` as a run of base type `class`, or [`Run::NONE`].
    fn of(info: &ModelInfo, elements: &[u32], class: TypeClass) -> Self {
        let access = |r: &u32| info.lookup(*r).map(access_of);
        let Some(first) = elements.first().and_then(access) else {
            return Run::NONE;
        };
        let one_run = first.class == class
            && elements.windows(2).all(|w| w[1] == w[0].wrapping_add(1))
            && elements.iter().all(|r| access(r) == Some(first));
        match (one_run, u32::try_from(elements.len())) {
            (true, Ok(n)) => Run {
                start: elements[0],
                end: elements[0].saturating_add(n),
                direct_set: first.direct_set,
            },
            _ => Run::NONE,
        }
    }
}

/// The index of `class` in [`FmuInstance`]'s run tables.
const fn class_index(class: TypeClass) -> usize {
    match class {
        TypeClass::Real => 0,
        TypeClass::Integer => 1,
        TypeClass::Boolean => 2,
    }
}

/// A variable's [`VarAccess`]: a set is direct for an input in a step, unless the input
/// is a code (its list is checked).
pub const fn access_of(def: &VarDef) -> VarAccess {
    VarAccess {
        class: TypeClass::of(&def.ty),
        direct_set: match (def.causality, def.ty) {
            (Causality::Input, VarType::Code(_)) => 0,
            (Causality::Input, _) => ModelState::StepComplete as u8 | ModelState::EventMode as u8,
            (Causality::Parameter | Causality::Output, _) => 0,
        },
    }
}

/// Where a set may write a variable, per state (FMI 2.0 sec. 4.2.4, the co-simulation
/// state table; FMI 3.0 has the same rule for fixed parameters and inputs).
fn settable(def: &VarDef, state: ModelState) -> bool {
    match state {
        ModelState::Instantiated | ModelState::InitializationMode => {
            def.causality != Causality::Output
        }
        ModelState::StepComplete | ModelState::EventMode => def.causality == Causality::Input,
        ModelState::Terminated | ModelState::Error => false,
    }
}

/// A value as the master gave it: an integer for Integer and code variables.
fn show(def: &VarDef, value: f64) -> String {
    match def.ty {
        VarType::Real(_) => format!("{value}"),
        VarType::Boolean => format!("{}", value != 0.0),
        VarType::Integer | VarType::Code(_) => format!("{}", value as i64),
    }
}

/// All data of one instance of model `M` under the binding `B`.
pub struct FmuInstance<M: Model, B: Binding> {
    /// Instance name given by the master.
    pub name: CString,
    binding: B,
    logging_on: bool,
    categories: [bool; LOG_CATEGORIES.len()],
    /// Current state of the life cycle.
    pub state: ModelState,
    values: Vec<f64>,
    /// [`access_of`] every variable, by value reference (built once from the model's
    /// table): the get/set dispatch's one indexed load per value.
    access: Box<[VarAccess]>,
    /// Each of the model's arrays as a [`Run`] of each base type (FMI 3.0), by
    /// [`class_index`].
    runs: [Box<[Run]>; 3],
    model: M,
    time: f64,
    start_time: f64,
    stop_time: Option<f64>,
    /// The GUID the binding checked at instantiation: written into the FMU states and
    /// required of the states restored.
    guid: &'static str,
    /// The FMU states handed out.
    pub states: StateRegistry,
    /// Initialisation ends in Event Mode, not Step Mode (FMI 3.0's `eventModeUsed`).
    pub event_mode_used: bool,
}

impl<M: Model, B: Binding> FmuInstance<M, B> {
    /// A freshly instantiated FMU with every variable at its start value; `guid` is the
    /// binding's GUID of the model.
    pub fn new(name: CString, binding: B, logging_on: bool, guid: &'static str) -> Self {
        let mut inst = Self {
            name,
            binding,
            logging_on,
            categories: [true; LOG_CATEGORIES.len()],
            state: ModelState::Instantiated,
            values: Vec::new(),
            access: M::info().variables.iter().map(access_of).collect(),
            runs: [TypeClass::Real, TypeClass::Integer, TypeClass::Boolean].map(|class| {
                let info = M::info();
                info.arrays
                    .iter()
                    .map(|a| Run::of(info, a.elements, class))
                    .collect()
            }),
            model: M::new(),
            time: 0.0,
            start_time: 0.0,
            stop_time: None,
            guid,
            states: StateRegistry::default(),
            event_mode_used: false,
        };
        inst.set_start_values();
        inst
    }

    fn set_start_values(&mut self) {
        self.values = start_values(M::info().variables);
        M::initial_outputs(&mut self.values, self.time);
    }

    /// Log a message in `category` (errors are always sent; other categories only when
    /// logging is on and the category is enabled).
    pub fn log(&self, status: Status, category: &str, msg: &str) {
        let idx = LOG_CATEGORIES.iter().position(|(n, _)| *n == category);
        let enabled = match idx {
            Some(0) => true,
            Some(i) => self.logging_on && self.categories[i],
            None => self.logging_on,
        };
        if enabled {
            self.binding.log(&self.name, status, category, msg);
        }
    }

    /// Record a failed call's status in the `fmi_status` output (the worst so far).
    pub fn note_status(&mut self, status: Status) {
        if let Some(v) = self.values.get_mut(M::info().fmi_status as usize) {
            *v = v.max(f64::from(status as i32));
        }
    }

    /// Whether `logCalls` messages would be sent (to avoid formatting them otherwise).
    pub fn logs_calls(&self) -> bool {
        self.logging_on && self.categories[LOG_CALLS]
    }

    /// Log a call under `logCalls`, formatting the message only when it is sent.
    pub fn log_call(&self, msg: impl FnOnce() -> String) {
        if self.logs_calls() {
            self.log(Status::Ok, "logCalls", &msg());
        }
    }

    /// Switch logging on or off, for every category (`names` empty) or the named ones.
    pub fn set_debug_logging(
        &mut self,
        func: &str,
        on: bool,
        names: &[&str],
    ) -> Result<(), Failure> {
        if names.is_empty() {
            self.logging_on = on;
            self.categories = [on; LOG_CATEGORIES.len()];
            return Ok(());
        }
        for n in names {
            let i = LOG_CATEGORIES
                .iter()
                .position(|(c, _)| c == n)
                .ok_or_else(|| error(format!("{func}: unknown log category \"{n}\"")))?;
            self.categories[i] = on;
        }
        if on {
            self.logging_on = true;
        }
        Ok(())
    }

    /// Check the call `func` is allowed in the current state (`allowed`: a mask of
    /// [`ModelState`] codes).
    pub fn require(&self, func: &str, allowed: u32) -> Result<(), Failure> {
        if self.state as u32 & allowed != 0 {
            Ok(())
        } else {
            Err(error(format!(
                "{func}: illegal call sequence (not allowed in state {:?})",
                self.state
            )))
        }
    }

    /// Set up the experiment: start time and optional stop time.
    pub fn setup_experiment(
        &mut self,
        func: &str,
        start: f64,
        stop: Option<f64>,
    ) -> Result<(), Failure> {
        if !start.is_finite() {
            return Err(error(format!("{func}: startTime {start} is not finite")));
        }
        if let Some(s) = stop {
            if !(s >= start) {
                return Err(error(format!(
                    "{func}: stopTime {s} is before startTime {start}"
                )));
            }
        }
        self.start_time = start;
        self.time = start;
        self.stop_time = stop;
        M::initial_outputs(&mut self.values, self.time);
        Ok(())
    }

    /// Enter initialisation mode.
    pub fn enter_initialization(&mut self) {
        self.state = ModelState::InitializationMode;
        M::initial_outputs(&mut self.values, self.time);
    }

    /// Exit initialisation mode: the model checks its parameters and is built.
    pub fn exit_initialization(&mut self) -> Result<(), Failure> {
        let info = self
            .model
            .initialize(&mut self.values, self.time)
            .map_err(error)?;
        self.state = if self.event_mode_used {
            ModelState::EventMode
        } else {
            ModelState::StepComplete
        };
        self.log(Status::Ok, "logInfo", &info);
        Ok(())
    }

    /// Enter Event Mode (from Step Mode, when the instance uses it).
    pub fn enter_event_mode(&mut self, func: &str) -> Result<(), Failure> {
        if !self.event_mode_used {
            return Err(error(format!(
                "{func}: the instance was made with eventModeUsed = false"
            )));
        }
        self.state = ModelState::EventMode;
        Ok(())
    }

    /// Enter Step Mode (from Event Mode).
    pub fn enter_step_mode(&mut self) {
        self.state = ModelState::StepComplete;
    }

    /// Apply the inputs at the current time, no time passing (Event Mode's
    /// `fmi3UpdateDiscreteStates`; [`Model::event_update`]).
    pub fn event_update(&mut self, func: &str) -> Result<(), Failure> {
        let t = self.time;
        self.model
            .event_update(&mut self.values, t)
            .map_err(|e| error(format!("{func} at t = {t}: {e}")))
    }

    /// One communication step `func(tc, h)`: the inputs hold at `tc`; the outputs
    /// afterwards describe `tc + h`.
    pub fn do_step(&mut self, func: &str, tc: f64, h: f64) -> Result<(), Failure> {
        if !(h.is_finite() && h > 0.0) {
            return Err(error(format!(
                "{func}: communicationStepSize must be finite and > 0 (got {h})"
            )));
        }
        let tol = 1e-9 * self.time.abs().max(1.0);
        if !tc.is_finite() || (tc - self.time).abs() > tol {
            return Err(error(format!(
                "{func}: currentCommunicationPoint {tc} does not match the FMU's time {}",
                self.time
            )));
        }
        if let Some(stop) = self.stop_time {
            if tc + h > stop + 1e-9 * stop.abs().max(1.0) {
                return Err(error(format!(
                    "{func}: step to {} goes past stopTime {stop}",
                    tc + h
                )));
            }
        }
        self.model
            .do_step(&mut self.values, tc, h)
            .map_err(|e| error(format!("{func} at t = {tc}: {e}")))?;
        self.time = tc + h;
        Ok(())
    }

    /// Back to the just-instantiated state with start values.
    pub fn reset(&mut self) {
        self.model.reset();
        self.time = 0.0;
        self.start_time = 0.0;
        self.stop_time = None;
        self.set_start_values();
        self.state = ModelState::Instantiated;
    }

    /// The values of the model's computed output `index` ([`Model::computed`]).
    pub fn computed(&self, index: usize, out: &mut [f64]) {
        self.model.computed(&self.values, index, out);
    }

    /// Terminate.
    pub fn terminate(&mut self) {
        self.state = ModelState::Terminated;
    }

    /// Last successful communication time.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// `name (vr N)` of a value reference, for call logs (`vr N (unknown)` if it is none).
    pub fn var_label(r: u32) -> String {
        match M::info().lookup(r) {
            Some(d) => format!("{} (vr {r})", d.name),
            None => format!("vr {r} (unknown)"),
        }
    }

    fn def(&self, r: u32, func: &str) -> Result<&'static VarDef, Failure> {
        M::info()
            .lookup(r)
            .ok_or_else(|| error(format!("{func}: unknown value reference {r}")))
    }

    /// Read the variable `r` of the base type `class` (the call `func` reads that
    /// class): one indexed load of its [`VarAccess`] and one of its value; the refusals
    /// (unknown value reference, other type) are built by [`FmuInstance::get_refusal`].
    #[inline(always)]
    pub fn get(&self, r: u32, func: &str, class: TypeClass) -> Result<f64, Failure> {
        // `values` and `access` both have one entry per variable
        let values = &self.values[..self.access.len()];
        match self.access.get(r as usize) {
            Some(a) if a.class == class => Ok(values[r as usize]),
            _ => Err(self.get_refusal(r, func)),
        }
    }

    /// Why [`FmuInstance::get`] refused `r`.
    #[cold]
    fn get_refusal(&self, r: u32, func: &str) -> Failure {
        match self.def(r, func) {
            Ok(d) => error(format!(
                "{func}: variable {} (vr {r}) has another type",
                d.name
            )),
            Err(e) => e,
        }
    }

    /// Write the variable `r` of the base type `class`, checking causality, state and
    /// domain. A master's input after initialisation is a plain store (its [`VarAccess`]
    /// says so); everything else takes [`FmuInstance::set_checked`].
    #[inline(always)]
    pub fn set(&mut self, r: u32, value: f64, func: &str, class: TypeClass) -> Result<(), Failure> {
        let state = self.state as u32;
        let n = self.access.len();
        match (
            self.access.get(r as usize),
            self.values[..n].get_mut(r as usize),
        ) {
            (Some(a), Some(v)) if a.class == class && u32::from(a.direct_set) & state != 0 => {
                *v = value;
                Ok(())
            }
            _ => self.set_checked(r, value, func, class),
        }
    }

    /// Read the arrays `ks` of [`ModelInfo::arrays`] one after the other into `out`,
    /// converted by `conv`, when each is one slice of the values of base type `class` and
    /// `out` holds exactly their values; says whether it did (otherwise `out` may hold
    /// some of them, and the caller reads element by element).
    #[inline(always)]
    pub fn read_runs<T>(
        &self,
        ks: impl Iterator<Item = usize>,
        out: &mut [T],
        copy: impl Fn(&mut [T], &[f64]),
        class: TypeClass,
    ) -> bool {
        // the tables in locals: the loop keeps them in registers
        let (runs, values) = (&self.runs[class_index(class)][..], &self.values[..]);
        let mut rest = out;
        for k in ks {
            let Some(src) = runs
                .get(k)
                .and_then(|run| values.get(run.start as usize..run.end as usize))
            else {
                return false;
            };
            let Some((dst, tail)) = rest.split_at_mut_checked(src.len()) else {
                return false;
            };
            copy(dst, src);
            rest = tail;
        }
        rest.is_empty()
    }

    /// The values of array `k` to write, when it is one slice of the values of base type
    /// `class` whose elements take a plain store in this state (else the caller writes
    /// element by element with [`FmuInstance::set`]).
    #[inline(always)]
    pub fn array_run_mut(&mut self, k: usize, class: TypeClass) -> Option<&mut [f64]> {
        let run = self.runs[class_index(class)].get(k)?;
        if u32::from(run.direct_set) & self.state as u32 == 0 {
            return None;
        }
        self.values.get_mut(run.start as usize..run.end as usize)
    }

    /// [`FmuInstance::set`] with every check: type, causality and state, code lists, the
    /// model's early parameter check; a set before initialisation refreshes the initial
    /// outputs.
    #[inline(never)]
    fn set_checked(
        &mut self,
        r: u32,
        value: f64,
        func: &str,
        class: TypeClass,
    ) -> Result<(), Failure> {
        let d = self.def(r, func)?;
        if TypeClass::of(&d.ty) != class {
            return Err(error(format!(
                "{func}: variable {} (vr {r}) has another type",
                d.name
            )));
        }
        if !settable(d, self.state) {
            return Err(error(format!(
                "{func}: variable {} ({:?}) cannot be set in state {:?}",
                d.name, d.causality, self.state
            )));
        }
        if let VarType::Code(t) = d.ty {
            if t.item_at(value).is_none() {
                return Err(error(format!(
                    "{func}: {} = {value} is not a {} code (allowed: {})",
                    d.name,
                    t.name,
                    t.codes()
                )));
            }
        }
        if d.causality == Causality::Parameter {
            M::check_alone(d, value).map_err(|e| {
                error(format!(
                    "{func}: {} = {} refused: {e}",
                    d.name,
                    show(d, value)
                ))
            })?;
        }
        self.values[r as usize] = value;
        if matches!(
            self.state,
            ModelState::Instantiated | ModelState::InitializationMode
        ) {
            M::initial_outputs(&mut self.values, self.time);
        }
        Ok(())
    }
}

/// FMU states (the bytes of [`crate::state`]).
///
/// **Restoring** brings back the life-cycle state with everything else: a state taken in
/// initialisation mode restores its rules (parameters settable, steps refused), one taken
/// while stepping continues bit for bit as the saved instance would, one taken after
/// terminate accepts only what a terminated instance accepts. **Parameters** come with the
/// state while they are free — in an instance whose model is not built yet (instantiated,
/// initialisation mode, or an error before it was built); once initialisation has built
/// the model they are fixed until reset, and a state taken with other parameter values is
/// refused (the message names the first parameter that differs). A refused state leaves
/// the instance's data unchanged (the binding then puts it in the error state, as after
/// every error).
impl<M: Model, B: Binding> FmuInstance<M, B> {
    /// The instance's state as bytes.
    pub fn save_state(&self) -> Result<Vec<u8>, Failure> {
        let saved = self.model.save().map_err(error)?;
        Ok(encode(
            M::info(),
            self.guid,
            &Snapshot {
                mode: self.state,
                time: self.time,
                start_time: self.start_time,
                stop_time: self.stop_time,
                values: &self.values,
                model: saved.as_deref(),
            },
        ))
    }

    /// Check bytes before accepting them as a state of this FMU (everything that does not
    /// depend on this instance's parameters); `func` is the call, for the message.
    pub fn check_state(&self, bytes: &[u8], func: &str) -> Result<(), Failure> {
        decode(M::info(), self.guid, bytes)
            .map(|_| ())
            .map_err(|e| refused(func, e))
    }

    /// Restore a state made by [`FmuInstance::save_state`]. Transactional: a refused
    /// state leaves the instance's data unchanged.
    pub fn restore_state(&mut self, bytes: &[u8], func: &str) -> Result<(), Failure> {
        let p = decode(M::info(), self.guid, bytes).map_err(|e| refused(func, e))?;
        if self.model.is_built() {
            let mine = &self.values;
            if let Some(d) = M::info().variables.iter().find(|d| {
                d.causality == Causality::Parameter
                    && mine[d.vr as usize].to_bits() != p.values[d.vr as usize].to_bits()
            }) {
                return Err(refused(
                    func,
                    refuse(format!(
                        "it was taken with {} = {}, this instance runs with {} = {}; parameters \
                         are fixed from {} until {}: restore it into an instance with the same \
                         parameters, or after {}",
                        d.name,
                        p.values[d.vr as usize],
                        d.name,
                        mine[d.vr as usize],
                        B::EXIT_INITIALIZATION,
                        B::RESET,
                        B::RESET
                    )),
                ));
            }
        }
        // the model: restored into the existing one (same parameters), or into a new one
        // built from the state's parameters; transactional
        match p.model {
            Some(blob) => self
                .model
                .restore(&p.values, blob)
                .map_err(|e| error(format!("{func}: state refused: {e}")))?,
            None => self.model.reset(),
        }
        // commit: nothing below can fail
        self.state = p.mode;
        self.values = p.values;
        self.time = p.time;
        self.start_time = p.start_time;
        self.stop_time = p.stop_time;
        Ok(())
    }
}

fn refused(func: &str, e: StateError) -> Failure {
    error(format!("{func}: state refused: {e}"))
}

/// The text of a caught panic.
fn panic_text(p: &(dyn std::any::Any + Send)) -> String {
    p.downcast_ref::<&str>()
        .map(|s| (*s).to_string())
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".to_string())
}

/// The boundary of every call a binding forwards: call logging, the allowed-states check,
/// the failure's log line and the error state, and no panic past it.
impl<M: Model, B: Binding> FmuInstance<M, B> {
    /// Run the call `func`: log it under `logCalls` as `func(args)` with `args` from
    /// `describe` (evaluated only when that category is on; `None`: `f` logs the call
    /// itself), refuse it outside the states of `allowed`, run `f`. A failure is logged
    /// (`logStatusError` or `logStatusWarning`), recorded in `fmi_status` and, from Error
    /// on, puts the instance in the error state; a panic is caught, logged and ends as
    /// [`Status::Fatal`]. Returns the status the binding converts to its C type.
    pub fn call<D, F>(&mut self, func: &str, allowed: u32, describe: D, f: F) -> Status
    where
        D: FnOnce(&Self) -> Option<String>,
        F: FnOnce(&mut Self) -> Result<(), Failure>,
    {
        let outcome = catch_unwind(AssertUnwindSafe(|| {
            if self.logs_calls() {
                if let Some(args) = describe(self) {
                    self.log(Status::Ok, "logCalls", &format!("{func}({args})"));
                }
            }
            self.require(func, allowed)?;
            f(self)
        }));
        match outcome {
            Ok(Ok(())) => Status::Ok,
            Ok(Err(e)) => {
                let category = if e.status >= Status::Error {
                    "logStatusError"
                } else {
                    "logStatusWarning"
                };
                self.log(e.status, category, &e.message);
                self.note_status(e.status);
                if e.status >= Status::Error {
                    self.state = ModelState::Error;
                }
                e.status
            }
            Err(p) => {
                let msg = format!("{func}: internal panic: {}", panic_text(p.as_ref()));
                let _ = catch_unwind(AssertUnwindSafe(|| {
                    self.log(Status::Fatal, "logStatusError", &msg)
                }));
                self.note_status(Status::Fatal);
                self.state = ModelState::Error;
                Status::Fatal
            }
        }
    }
}

/// The FMU-state calls of both bindings on opaque handles (the pointers the master holds;
/// never dereferenced here, only looked up in [`StateRegistry`]). `func` names the call,
/// `size_call` the binding's size inquiry in a message.
impl<M: Model, B: Binding> FmuInstance<M, B> {
    /// The refusal of a handle this instance did not make (or has freed).
    fn unknown_state(func: &str, transfer: &str) -> Failure {
        error(format!(
            "{func}: unknown FMU state (not made by this instance, or already freed; move a \
             state between instances with {transfer})"
        ))
    }

    fn state_bytes(&self, h: *mut c_void, func: &str, transfer: &str) -> Result<&[u8], Failure> {
        self.states
            .get(h)
            .map(|s| s.bytes())
            .ok_or_else(|| Self::unknown_state(func, transfer))
    }

    /// Copy the instance's state into `*slot` (a new state for null, else the state it
    /// names, which this instance made, overwritten).
    pub fn get_fmu_state(&mut self, slot: &mut *mut c_void) -> Result<(), Failure> {
        let bytes = self.save_state()?;
        *slot = self.states.put(*slot, bytes);
        Ok(())
    }

    /// Restore the state `h` made by this instance.
    pub fn set_fmu_state(
        &mut self,
        h: *mut c_void,
        func: &str,
        transfer: &str,
    ) -> Result<(), Failure> {
        let bytes = self.state_bytes(h, func, transfer)?.to_vec();
        self.restore_state(&bytes, func)
    }

    /// Free the state `*slot` (null is ignored) and set `*slot` to null.
    pub fn free_fmu_state(
        &mut self,
        slot: &mut *mut c_void,
        func: &str,
        transfer: &str,
    ) -> Result<(), Failure> {
        if !slot.is_null() {
            if !self.states.free(*slot) {
                return Err(Self::unknown_state(func, transfer));
            }
            *slot = std::ptr::null_mut();
        }
        Ok(())
    }

    /// The size in bytes of the state `h`'s serialised form.
    pub fn fmu_state_size(
        &self,
        h: *mut c_void,
        func: &str,
        transfer: &str,
    ) -> Result<usize, Failure> {
        Ok(self.state_bytes(h, func, transfer)?.len())
    }

    /// The serialised form of the state `h` for a buffer of `size` bytes (refused when it
    /// does not fit; `size_call` names the size inquiry).
    pub fn serialized_fmu_state(
        &self,
        h: *mut c_void,
        size: usize,
        func: &str,
        transfer: &str,
        size_call: &str,
    ) -> Result<&[u8], Failure> {
        let b = self.state_bytes(h, func, transfer)?;
        if size < b.len() {
            return Err(error(format!(
                "{func}: the state needs {} bytes ({size_call}), the buffer holds {size}",
                b.len()
            )));
        }
        Ok(b)
    }

    /// A state from serialised `bytes` (checked: length, CRC-32, magic, format version,
    /// GUID, structure) into `*slot` (new for null, else overwritten).
    pub fn deserialize_fmu_state(
        &mut self,
        bytes: &[u8],
        slot: &mut *mut c_void,
        func: &str,
    ) -> Result<(), Failure> {
        self.check_state(bytes, func)?;
        *slot = self.states.put(*slot, bytes.to_vec());
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::variables::tests::CODES;
    use crate::variables::Variability;

    mod table {
        use crate::variables::VarType;
        crate::variables! {
            A0 = 0: "a0", Input, Discrete, VarType::Real("m"), 0.0, "Input a[0]";
            A1 = 1: "a1", Input, Discrete, VarType::Real("m"), 0.0, "Input a[1]";
            B = 2: "b", Output, Continuous, VarType::Real("m"), 0.0, "Output b";
            N = 3: "n", Input, Discrete, VarType::Integer, 0.0, "Input n";
            C = 4: "c", Output, Continuous, VarType::Real("m"), 0.0, "Output c";
        }
    }

    /// An array is a run exactly when its elements are consecutive value references of
    /// the class asked for with one access.
    #[test]
    fn runs_are_consecutive_elements_with_one_access() {
        use crate::model::{DefaultExperiment, Generated};
        use table::vr;
        let info = ModelInfo {
            model_identifier: "runs",
            description: "",
            variables: table::VARIABLES,
            default_experiment: DefaultExperiment {
                start: 0.0,
                stop: 1.0,
                step: 0.1,
            },
            fmi_status: vr::N,
            state_code: None,
            state_name: "runs",
            arrays: &[],
            has_event_mode: false,
            computed: &[],
            generated: Generated::new(),
        };
        let range = |r: Run| (r.start, r.end, r.direct_set);
        let input = access_of(&table::VARIABLES[0]).direct_set;
        // elements, class asked for, (start, end, direct_set) of the run if it is one
        type Case = (&'static [u32], TypeClass, Option<(u32, u32, u8)>);
        let cases: [Case; 8] = [
            (&[vr::A0, vr::A1], TypeClass::Real, Some((0, 2, input))),
            (&[vr::B], TypeClass::Real, Some((2, 3, 0))),
            (&[vr::A0, vr::A1], TypeClass::Integer, None),
            (&[vr::A1, vr::A0], TypeClass::Real, None),
            (&[vr::A1, vr::B], TypeClass::Real, None),
            (&[vr::B, vr::C], TypeClass::Real, None),
            (&[vr::C, 5], TypeClass::Real, None),
            (&[], TypeClass::Real, None),
        ];
        for (elements, class, want) in cases {
            let got = Run::of(&info, elements, class);
            assert_eq!(
                (got.start <= got.end).then(|| range(got)),
                want,
                "{elements:?} {class:?}"
            );
        }
    }

    /// The access table's direct stores are exactly the sets the full path accepts with
    /// no other check or effect, for every causality, type and state.
    #[test]
    fn direct_sets_are_the_unchecked_ones() {
        let types = [
            VarType::Real("m"),
            VarType::Integer,
            VarType::Boolean,
            VarType::Code(&CODES),
        ];
        for causality in [Causality::Parameter, Causality::Input, Causality::Output] {
            for ty in types {
                let d = VarDef {
                    vr: 0,
                    name: "v",
                    causality,
                    variability: Variability::Discrete,
                    ty,
                    start: 1.0,
                    description: "",
                };
                let a = access_of(&d);
                assert_eq!(a.class, TypeClass::of(&d.ty));
                for st in ModelState::ALL {
                    let direct = u32::from(a.direct_set) & st as u32 != 0;
                    let unchecked = settable(&d, st)
                        && d.causality != Causality::Parameter
                        && !matches!(d.ty, VarType::Code(_))
                        && !matches!(
                            st,
                            ModelState::Instantiated | ModelState::InitializationMode
                        );
                    assert_eq!(direct, unchecked, "{causality:?} {:?} in {st:?}", d.ty);
                }
            }
        }
    }
}
