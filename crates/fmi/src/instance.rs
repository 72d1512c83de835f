//! One FMU instance, generic over its [`Model`]: the values of the variable table, the
//! call-order state machine, time, logging, and the checks every model shares (causality
//! and state of a set, code lists, step times); the model itself only turns parameters and
//! inputs into outputs ([`crate::model`]), like the Reference-FMUs keep `model.c` apart
//! from `fmi2Functions.c`.

use crate::description::LOG_CATEGORIES;
use crate::model::Model;
use crate::relnav::RelnavFmu;
use crate::types::*;
use crate::variables::{Causality, TypeClass, VarAccess, VarDef, VarType};
use std::ffi::{c_int, CStr, CString};

/// States of the FMI 2.0 co-simulation state machine (bit flags for "allowed in" masks).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u32)]
pub enum ModelState {
    /// After `fmi2Instantiate` or `fmi2Reset`.
    Instantiated = 1,
    /// Between enter and exit initialisation mode.
    InitializationMode = 2,
    /// Ready for `fmi2DoStep`.
    StepComplete = 4,
    /// After `fmi2Terminate`.
    Terminated = 8,
    /// After a call returned `fmi2Error`.
    Error = 16,
}

/// Mask of every state.
pub const ANY_STATE: u32 = 31;

/// A failure inside an FMI call: status plus the message for the log.
#[derive(Debug)]
pub struct FmiFailure {
    /// Status returned to the master.
    pub status: fmi2Status,
    /// Reason, logged under `logStatusError` (or `logStatusWarning`).
    pub message: String,
}

/// Shorthand for an `fmi2Error` failure.
pub fn error(message: String) -> FmiFailure {
    FmiFailure {
        status: fmi2Status::fmi2Error,
        message,
    }
}

/// The logger callback and its environment, copied at instantiation.
#[derive(Clone, Copy)]
pub struct Logger {
    callback: fmi2CallbackLogger,
    env: fmi2ComponentEnvironment,
}

impl Logger {
    /// Wrap the master's callback (which may be absent).
    pub fn new(callback: fmi2CallbackLogger, env: fmi2ComponentEnvironment) -> Self {
        Self { callback, env }
    }

    /// Send one message. The logger's message is a `printf` format (FMI 2.0 sec. 2.1.5),
    /// so the text itself is passed as the format with `%` escaped as `%%` and no
    /// arguments: a master that formats shows the text, and one that prints the format
    /// as it is still shows it (with `%%`). `#` is FMI's escape character (`#r12#` names a
    /// variable) and is doubled. Messages are cut at [`MAX_LOG_CHARS`] characters (fmpy
    /// formats into 2048 bytes), with ` ...` appended.
    pub fn log(&self, instance: &CStr, status: fmi2Status, category: &str, msg: &str) {
        let Some(cb) = self.callback else { return };
        let Ok(cat) = CString::new(category) else {
            return;
        };
        let Ok(text) = CString::new(escape_log_message(msg)) else {
            return;
        };
        // SAFETY: the master gave us this callback for the lifetime of the instance; all
        // strings are NUL-terminated and live across the call; the format contains no
        // conversion (every `%` is doubled), so no variadic argument is read.
        unsafe {
            cb(
                self.env,
                instance.as_ptr(),
                status as c_int,
                cat.as_ptr(),
                text.as_ptr(),
            )
        };
    }
}

/// Longest message sent to the logger, in characters before escaping.
pub const MAX_LOG_CHARS: usize = 1500;

/// A log message as the logger's `printf` format: NULs dropped, cut at
/// [`MAX_LOG_CHARS`] characters (` ...` appended), then `%` -> `%%` and `#` -> `##`.
pub fn escape_log_message(msg: &str) -> String {
    let mut out = String::with_capacity(msg.len() + 8);
    for (i, c) in msg.chars().filter(|c| *c != '\0').enumerate() {
        if i == MAX_LOG_CHARS {
            out.push_str(" ...");
            break;
        }
        match c {
            '%' => out.push_str("%%"),
            '#' => out.push_str("##"),
            c => out.push(c),
        }
    }
    out
}

/// relnav.fmu's instance.
pub type Instance = FmuInstance<RelnavFmu>;

/// All data of one instance of the FMU of model `M`.
pub struct FmuInstance<M: Model> {
    /// Instance name given by the master.
    pub name: CString,
    logger: Logger,
    logging_on: bool,
    categories: [bool; LOG_CATEGORIES.len()],
    /// Current state of the state machine.
    pub state: ModelState,
    values: Vec<f64>,
    /// [`VarDef::access`] of every variable, by value reference (built once from the
    /// model's table): the get/set dispatch's one indexed load per value.
    access: Box<[VarAccess]>,
    model: M,
    time: f64,
    start_time: f64,
    stop_time: Option<f64>,
    /// The FMU states handed out by `fmi2GetFMUstate` / `fmi2DeSerializeFMUstate`.
    pub states: crate::state::StateRegistry,
}

/// Where `fmi2Set*` may write a variable, per state (FMI 2.0 sec. 4.2.4, CS state table).
fn settable(def: &VarDef, state: ModelState) -> bool {
    match state {
        ModelState::Instantiated | ModelState::InitializationMode => {
            def.causality != Causality::Output
        }
        ModelState::StepComplete => def.causality == Causality::Input,
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

/// Every variable at its start value (outputs at 0 until the model writes them).
pub(super) fn start_values(vars: &[VarDef]) -> Vec<f64> {
    vars.iter().map(|v| v.start).collect()
}

impl<M: Model> FmuInstance<M> {
    /// A freshly instantiated FMU with every variable at its start value.
    pub fn new(name: CString, logger: Logger, logging_on: bool) -> Self {
        let mut inst = Self {
            name,
            logger,
            logging_on,
            categories: [true; LOG_CATEGORIES.len()],
            state: ModelState::Instantiated,
            values: Vec::new(),
            access: M::info().variables.iter().map(VarDef::access).collect(),
            model: M::new(),
            time: 0.0,
            start_time: 0.0,
            stop_time: None,
            states: Default::default(),
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
    pub fn log(&self, status: fmi2Status, category: &str, msg: &str) {
        let idx = LOG_CATEGORIES.iter().position(|(n, _)| *n == category);
        let enabled = match idx {
            Some(0) => true,
            Some(i) => self.logging_on && self.categories[i],
            None => self.logging_on,
        };
        if enabled {
            self.logger.log(&self.name, status, category, msg);
        }
    }

    /// Record a failed call's status in the `fmi_status` output (the worst so far).
    pub fn note_status(&mut self, status: fmi2Status) {
        if let Some(v) = self.values.get_mut(M::info().fmi_status as usize) {
            *v = v.max(f64::from(status as i32));
        }
    }

    /// Whether `logCalls` messages would be sent (to avoid formatting them otherwise).
    pub fn logs_calls(&self) -> bool {
        self.logging_on && self.categories[3]
    }

    /// Log a call under `logCalls`, formatting the message only when it is sent.
    pub fn log_call(&self, msg: impl FnOnce() -> String) {
        if self.logs_calls() {
            self.log(fmi2Status::fmi2OK, "logCalls", &msg());
        }
    }

    /// `fmi2SetDebugLogging`.
    pub fn set_debug_logging(&mut self, on: bool, names: &[&str]) -> Result<(), FmiFailure> {
        if names.is_empty() {
            self.logging_on = on;
            self.categories = [on; LOG_CATEGORIES.len()];
            return Ok(());
        }
        for n in names {
            let i = LOG_CATEGORIES
                .iter()
                .position(|(c, _)| c == n)
                .ok_or_else(|| {
                    error(format!("fmi2SetDebugLogging: unknown log category \"{n}\""))
                })?;
            self.categories[i] = on;
        }
        if on {
            self.logging_on = true;
        }
        Ok(())
    }

    /// Check the call is allowed in the current state.
    pub fn require(&self, func: &str, allowed: u32) -> Result<(), FmiFailure> {
        if self.state as u32 & allowed != 0 {
            Ok(())
        } else {
            Err(error(format!(
                "{func}: illegal call sequence (not allowed in state {:?})",
                self.state
            )))
        }
    }

    /// `fmi2SetupExperiment`.
    pub fn setup_experiment(&mut self, start: f64, stop: Option<f64>) -> Result<(), FmiFailure> {
        if !start.is_finite() {
            return Err(error(format!(
                "fmi2SetupExperiment: startTime {start} is not finite"
            )));
        }
        if let Some(s) = stop {
            if !(s >= start) {
                return Err(error(format!(
                    "fmi2SetupExperiment: stopTime {s} is before startTime {start}"
                )));
            }
        }
        self.start_time = start;
        self.time = start;
        self.stop_time = stop;
        M::initial_outputs(&mut self.values, self.time);
        Ok(())
    }

    /// `fmi2EnterInitializationMode`.
    pub fn enter_initialization(&mut self) {
        self.state = ModelState::InitializationMode;
        M::initial_outputs(&mut self.values, self.time);
    }

    /// `fmi2ExitInitializationMode`: the model checks its parameters and is built.
    pub fn exit_initialization(&mut self) -> Result<(), FmiFailure> {
        let info = self
            .model
            .initialize(&mut self.values, self.time)
            .map_err(error)?;
        self.state = ModelState::StepComplete;
        self.log(fmi2Status::fmi2OK, "logInfo", &info);
        Ok(())
    }

    /// `fmi2DoStep(tc, h)`: the inputs hold at `tc`; the outputs afterwards describe `tc + h`.
    pub fn do_step(&mut self, tc: f64, h: f64) -> Result<(), FmiFailure> {
        if !(h.is_finite() && h > 0.0) {
            return Err(error(format!(
                "fmi2DoStep: communicationStepSize must be finite and > 0 (got {h})"
            )));
        }
        let tol = 1e-9 * self.time.abs().max(1.0);
        if !tc.is_finite() || (tc - self.time).abs() > tol {
            return Err(error(format!(
                "fmi2DoStep: currentCommunicationPoint {tc} does not match the FMU's time {}",
                self.time
            )));
        }
        if let Some(stop) = self.stop_time {
            if tc + h > stop + 1e-9 * stop.abs().max(1.0) {
                return Err(error(format!(
                    "fmi2DoStep: step to {} goes past stopTime {stop}",
                    tc + h
                )));
            }
        }
        self.model.do_step(&mut self.values, tc, h).map_err(error)?;
        self.time = tc + h;
        Ok(())
    }

    /// `fmi2Reset`: back to the just-instantiated state with start values.
    pub fn reset(&mut self) {
        self.model.reset();
        self.time = 0.0;
        self.start_time = 0.0;
        self.stop_time = None;
        self.set_start_values();
        self.state = ModelState::Instantiated;
    }

    /// `fmi2Terminate`.
    pub fn terminate(&mut self) {
        self.state = ModelState::Terminated;
    }

    /// Last successful communication time.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// `name (vr N)` of a value reference, for call logs (`vr N (unknown)` if it is none).
    pub fn var_label(r: fmi2ValueReference) -> String {
        match M::info().lookup(r) {
            Some(d) => format!("{} (vr {r})", d.name),
            None => format!("vr {r} (unknown)"),
        }
    }

    fn def(&self, r: fmi2ValueReference, func: &str) -> Result<&'static VarDef, FmiFailure> {
        M::info()
            .lookup(r)
            .ok_or_else(|| error(format!("{func}: unknown value reference {r}")))
    }

    /// Read a variable of the expected base type: one indexed load of its
    /// [`VarAccess`] and one of its value; the refusals (unknown value reference, other
    /// type) are built by [`FmuInstance::get_refusal`].
    #[inline(always)]
    pub fn get(
        &self,
        r: fmi2ValueReference,
        func: &str,
        class: TypeClass,
    ) -> Result<f64, FmiFailure> {
        // `values` and `access` both have one entry per variable
        let values = &self.values[..self.access.len()];
        match self.access.get(r as usize) {
            Some(a) if a.class == class => Ok(values[r as usize]),
            _ => Err(self.get_refusal(r, func)),
        }
    }

    /// Why [`FmuInstance::get`] refused `r`.
    #[cold]
    fn get_refusal(&self, r: fmi2ValueReference, func: &str) -> FmiFailure {
        match self.def(r, func) {
            Ok(d) => error(format!(
                "{func}: variable {} (vr {r}) has another type",
                d.name
            )),
            Err(e) => e,
        }
    }

    /// Write a variable of the expected base type, checking causality, state and domain.
    /// A master's input after initialisation is a plain store (its [`VarAccess`] says
    /// so); everything else takes [`FmuInstance::set_checked`].
    #[inline(always)]
    pub fn set(
        &mut self,
        r: fmi2ValueReference,
        value: f64,
        func: &str,
        class: TypeClass,
    ) -> Result<(), FmiFailure> {
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

    /// [`FmuInstance::set`] with every check: type, causality and state, code lists, the
    /// model's early parameter check; a set before initialisation refreshes the initial
    /// outputs.
    #[inline(never)]
    fn set_checked(
        &mut self,
        r: fmi2ValueReference,
        value: f64,
        func: &str,
        class: TypeClass,
    ) -> Result<(), FmiFailure> {
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
            if t.item(value).is_none() {
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

/// What the FMU state ([`crate::state`]) reads and restores.
impl<M: Model> FmuInstance<M> {
    /// Every variable's value, by value reference.
    pub(super) fn values(&self) -> &[f64] {
        &self.values
    }

    /// `(time, start time, stop time)`.
    pub(super) fn times(&self) -> (f64, f64, Option<f64>) {
        (self.time, self.start_time, self.stop_time)
    }

    /// The model.
    pub(super) fn model(&self) -> &M {
        &self.model
    }

    /// The model, to restore its state.
    pub(super) fn model_mut(&mut self) -> &mut M {
        &mut self.model
    }

    /// Everything but the model, as a restored state has it.
    pub(super) fn set_restored(
        &mut self,
        mode: ModelState,
        values: Vec<f64>,
        time: f64,
        start_time: f64,
        stop_time: Option<f64>,
    ) {
        self.state = mode;
        self.values = values;
        self.time = time;
        self.start_time = start_time;
        self.stop_time = stop_time;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The access table's direct stores are exactly the sets the full path accepts with
    /// no other check or effect, for every variable of every model and every state.
    #[test]
    fn direct_sets_are_the_unchecked_ones() {
        use crate::{guidance, plant, relnav};
        let tables = [
            relnav::INFO.variables,
            plant::INFO.variables,
            guidance::INFO.variables,
        ];
        let states = [
            ModelState::Instantiated,
            ModelState::InitializationMode,
            ModelState::StepComplete,
            ModelState::Terminated,
            ModelState::Error,
        ];
        for vars in tables {
            for d in vars {
                let a = d.access();
                assert_eq!(a.class, TypeClass::of(&d.ty));
                for st in states {
                    let direct = u32::from(a.direct_set) & st as u32 != 0;
                    let unchecked = settable(d, st)
                        && d.causality != Causality::Parameter
                        && !matches!(d.ty, VarType::Code(_))
                        && !matches!(
                            st,
                            ModelState::Instantiated | ModelState::InitializationMode
                        );
                    assert_eq!(direct, unchecked, "{} in {st:?}", d.name);
                }
            }
        }
    }

    #[test]
    fn log_messages_are_printf_formats() {
        assert_eq!(escape_log_message("50% #r3# ok"), "50%% ##r3## ok");
        assert_eq!(escape_log_message("a\0b"), "ab");
        let long = "%".repeat(MAX_LOG_CHARS + 10);
        let e = escape_log_message(&long);
        assert_eq!(e, format!("{} ...", "%%".repeat(MAX_LOG_CHARS)));
    }
}
