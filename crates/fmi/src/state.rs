//! FMU state: `fmi2GetFMUstate` / `fmi2SetFMUstate` / serialisation, as explicit,
//! versioned bytes (`docs/state-format.md`).
//!
//! Generic over the [`Model`]: the same layout serves relnav.fmu and the kit's FMUs.
//!
//! An FMU state is the instance's complete state in one byte string: a 70-byte header
//! (magic `RELNAVFM`, [`FMU_STATE_FORMAT_VERSION`], the FMU's GUID, the model code —
//! relnav's `filter`, the plant's `truth_model`, 0 for the guidance —, a
//! fingerprint of the parameter values, payload length, CRC-32), then the state-machine
//! state, the time and experiment bounds, the value of every variable (parameters, held
//! inputs, published outputs), and — once the model is built — the model's own state
//! ([`Model::save`]; relnav: the estimator's state as the C ABI saves it,
//! [`relnav::relnav_estimator_save`]). The `fmi2FMUstate`
//! handed to the master is that byte string, so getting a state serialises it once,
//! `fmi2SerializeFMUstate` copies it, and every state is checked the same way.
//!
//! **Restoring** ([`Instance::restore_state`]) brings back the state-machine state with
//! everything else: a state taken in initialisation mode restores its rules (parameters
//! settable, `fmi2DoStep` refused), one taken while stepping continues bit for bit as the
//! saved instance would, one taken after `fmi2Terminate` accepts only what a terminated
//! instance accepts. **Parameters** come with the state while they are free — in an
//! instance that has no estimator yet (instantiated, initialisation mode, or an error
//! before one was built); once `fmi2ExitInitializationMode` has built the estimator they
//! are fixed until `fmi2Reset`, and a state taken with other parameter values is refused
//! (the message names the first parameter that differs).
//!
//! **Refusals** (`fmi2Error` with the reason logged under `logStatusError`): truncated or
//! over-long bytes, a CRC-32 mismatch, another magic or format version, another FMU's GUID,
//! a header that disagrees with the parameters it carries, parameters fixed to other
//! values, and every refusal of the estimator's state by the C ABI. The instance's data is
//! unchanged by a refused state (it enters the error state, as after every `fmi2Error`;
//! `fmi2SetFMUstate` with a good state or `fmi2Reset` continues from there).

use crate::description::guid_of;
use crate::instance::{error, FmiFailure, FmuInstance, ModelState};
use crate::model::Model;
use crate::types::fmi2FMUstate;
use crate::variables::{Causality, VarDef};
use relnav_core::numerics::state::{self, crc32, refuse, Reader, StateError, FMU_MAGIC, KINDS};

/// Format version of the FMU state bytes. Bump it whenever the layout changes; a state of
/// another version is refused, never misread.
pub const FMU_STATE_FORMAT_VERSION: u32 = 1;

/// Bytes of the GUID in the header (`{8-4-4-4-12}`, ASCII).
const GUID_LEN: usize = 38;
/// Identity block of the header: GUID, model code (i32), parameter fingerprint (u32).
const IDENT_LEN: usize = GUID_LEN + 4 + 4;

/// One `fmi2FMUstate`: the serialised state.
#[derive(Debug)]
pub struct FmuState {
    bytes: Vec<u8>,
}

impl FmuState {
    /// The serialised bytes.
    pub fn bytes(&self) -> &[u8] {
        &self.bytes
    }
}

/// The states an instance has handed out. A state pointer is only ever compared with
/// these, never dereferenced on the master's word: an unknown or freed pointer is an
/// error, not undefined behaviour. States left unfreed go with the instance.
#[derive(Debug, Default)]
pub struct StateRegistry {
    /// boxed on purpose: the pointer handed to the master must not move when the vector
    /// grows
    #[allow(clippy::vec_box)]
    live: Vec<Box<FmuState>>,
}

impl StateRegistry {
    fn position(&self, p: fmi2FMUstate) -> Option<usize> {
        self.live
            .iter()
            .position(|b| std::ptr::eq(&**b, p.cast::<FmuState>().cast_const()))
    }

    /// Store `bytes` in the state `p` if this instance made it, else in a new state;
    /// returns the state's pointer.
    pub fn put(&mut self, p: fmi2FMUstate, bytes: Vec<u8>) -> fmi2FMUstate {
        if let Some(s) = self.position(p).and_then(|i| self.live.get_mut(i)) {
            s.bytes = bytes;
            return p;
        }
        let mut b = Box::new(FmuState { bytes });
        let ptr: *mut FmuState = &mut *b;
        self.live.push(b);
        ptr.cast()
    }

    /// The state behind `p`, if this instance made it and it is not freed.
    pub fn get(&self, p: fmi2FMUstate, func: &str) -> Result<&FmuState, FmiFailure> {
        self.position(p)
            .and_then(|i| self.live.get(i))
            .map(|b| &**b)
            .ok_or_else(|| unknown(func))
    }

    /// Free the state behind `p`.
    pub fn free(&mut self, p: fmi2FMUstate, func: &str) -> Result<(), FmiFailure> {
        let i = self.position(p).ok_or_else(|| unknown(func))?;
        self.live.swap_remove(i);
        Ok(())
    }

    /// Number of live states.
    pub fn len(&self) -> usize {
        self.live.len()
    }

    /// Whether no state is live.
    pub fn is_empty(&self) -> bool {
        self.live.is_empty()
    }
}

fn unknown(func: &str) -> FmiFailure {
    error(format!(
        "{func}: unknown FMU state (not made by this instance, or already freed; move a state \
         between instances with fmi2SerializeFMUstate / fmi2DeSerializeFMUstate)"
    ))
}

/// A checked FMU state (everything but what depends on the restoring instance).
struct Parsed<'a> {
    mode: ModelState,
    time: f64,
    start_time: f64,
    stop_time: Option<f64>,
    values: Vec<f64>,
    model: Option<&'a [u8]>,
}

fn mode_of(v: u32) -> Option<ModelState> {
    [
        ModelState::Instantiated,
        ModelState::InitializationMode,
        ModelState::StepComplete,
        ModelState::Terminated,
        ModelState::Error,
    ]
    .into_iter()
    .find(|m| *m as u32 == v)
}

/// The parameters' fingerprint: CRC-32 of every parameter's value (f64 bits, LE) in
/// value-reference order.
fn fingerprint(vars: &[VarDef], values: &[f64]) -> u32 {
    let mut b = Vec::with_capacity(8 * vars.len());
    for v in vars.iter().filter(|v| v.causality == Causality::Parameter) {
        b.extend_from_slice(&values[v.vr as usize].to_bits().to_le_bytes());
    }
    crc32(&b)
}

fn guid_bytes(guid: &str) -> [u8; GUID_LEN] {
    let mut g = [0u8; GUID_LEN];
    for (d, s) in g.iter_mut().zip(guid.bytes()) {
        *d = s;
    }
    g
}

fn parse<M: Model>(bytes: &[u8]) -> Result<Parsed<'_>, StateError> {
    let info = M::info();
    let guid = guid_of(info);
    let vars = info.variables;
    let o = state::open(
        bytes,
        FMU_MAGIC,
        FMU_STATE_FORMAT_VERSION,
        IDENT_LEN,
        "a relnav FMU state",
        &KINDS,
    )?;
    let mut id = Reader::new(o.ident);
    let g = id.take(GUID_LEN, "GUID")?;
    if g != guid_bytes(guid) {
        return Err(refuse(format!(
            "the state is from another FMU: GUID {}, this FMU's is {}",
            String::from_utf8_lossy(g),
            guid
        )));
    }
    let code = id.i32("model code")?;
    let fp = id.u32("parameter fingerprint")?;
    let mut r = Reader::new(o.payload);
    r.tag(b"FMUI")?;
    let m = r.u32("state-machine state")?;
    let mode = mode_of(m).ok_or_else(|| refuse(format!("unknown state-machine state {m}")))?;
    let time = r.finite("time")?;
    let start_time = r.finite("start time")?;
    let stop_defined = r.bool("stop-time flag")?;
    let stop = r.f64("stop time")?;
    let stop_time = stop_defined.then_some(stop);
    r.count("number of variables", vars.len())?;
    let mut values = vec![0.0; vars.len()];
    for (v, def) in values.iter_mut().zip(vars) {
        *v = r.f64(def.name)?;
    }
    let what = info.state_name;
    let model = if r.bool(&format!("{what} flag"))? {
        let n = r.usize(&format!("{what} state length"))?;
        Some(r.take(n, &format!("{what} state"))?)
    } else {
        None
    };
    r.finish()?;
    let needs = match mode {
        ModelState::StepComplete | ModelState::Terminated => Some(true),
        ModelState::Instantiated | ModelState::InitializationMode => Some(false),
        ModelState::Error => None,
    };
    if needs.is_some_and(|n| n != model.is_some()) {
        return Err(refuse(format!(
            "a state in {mode:?} must {}carry {} {what} state",
            if model.is_some() { "not " } else { "" },
            if what.starts_with(['a', 'e', 'i', 'o', 'u']) {
                "an"
            } else {
                "a"
            }
        )));
    }
    if code != info.state_code_of(&values) || fp != fingerprint(vars, &values) {
        let name = info
            .state_code
            .and_then(|r| info.lookup(r))
            .map_or("model", |d| d.name);
        return Err(refuse(format!(
            "the header's {name} code or parameter fingerprint disagrees with the parameters \
             the state carries"
        )));
    }
    Ok(Parsed {
        mode,
        time,
        start_time,
        stop_time,
        values,
        model,
    })
}

fn refused(func: &str, e: StateError) -> FmiFailure {
    error(format!("{func}: state refused: {e}"))
}

impl<M: Model> FmuInstance<M> {
    /// The instance's state as bytes (see the module documentation).
    pub fn save_state(&self) -> Result<Vec<u8>, FmiFailure> {
        let info = M::info();
        let saved = self.model().save().map_err(error)?;
        let values = self.values();
        let mut ident = Vec::with_capacity(IDENT_LEN);
        ident.extend_from_slice(&guid_bytes(guid_of(info)));
        ident.extend_from_slice(&info.state_code_of(values).to_le_bytes());
        ident.extend_from_slice(&fingerprint(info.variables, values).to_le_bytes());
        let mut out = Vec::new();
        state::seal(&mut out, FMU_MAGIC, FMU_STATE_FORMAT_VERSION, &ident, |w| {
            let (time, start, stop) = self.times();
            w.tag(b"FMUI");
            w.u32(self.state as u32);
            w.f64(time);
            w.f64(start);
            w.bool(stop.is_some());
            w.f64(stop.unwrap_or(0.0));
            w.usize(values.len());
            for v in values {
                w.f64(*v);
            }
            match &saved {
                Some(b) => {
                    w.bool(true);
                    w.usize(b.len());
                    w.bytes(b);
                }
                None => w.bool(false),
            }
        });
        Ok(out)
    }

    /// Check bytes for `fmi2DeSerializeFMUstate` (everything that does not depend on the
    /// restoring instance).
    pub fn check_state(bytes: &[u8], func: &str) -> Result<(), FmiFailure> {
        parse::<M>(bytes).map(|_| ()).map_err(|e| refused(func, e))
    }

    /// Restore a state made by [`FmuInstance::save_state`] (see the module documentation for
    /// the rules). Transactional: a refused state leaves the instance's data unchanged.
    pub fn restore_state(&mut self, bytes: &[u8], func: &str) -> Result<(), FmiFailure> {
        let p = parse::<M>(bytes).map_err(|e| refused(func, e))?;
        if self.model().is_built() {
            let mine = self.values();
            if let Some(d) = M::info().variables.iter().find(|d| {
                d.causality == Causality::Parameter
                    && mine[d.vr as usize].to_bits() != p.values[d.vr as usize].to_bits()
            }) {
                return Err(refused(
                    func,
                    refuse(format!(
                        "it was taken with {} = {}, this instance runs with {} = {}; parameters \
                         are fixed from fmi2ExitInitializationMode until fmi2Reset: restore it \
                         into an instance with the same parameters, or after fmi2Reset",
                        d.name, p.values[d.vr as usize], d.name, mine[d.vr as usize]
                    )),
                ));
            }
        }
        // the model: restored into the existing one (same parameters), or into a new one
        // built from the state's parameters; transactional
        match p.model {
            Some(blob) => self
                .model_mut()
                .restore(&p.values, blob)
                .map_err(|e| error(format!("{func}: state refused: {e}")))?,
            None => self.model_mut().reset(),
        }
        // commit: nothing below can fail
        self.set_restored(p.mode, p.values, p.time, p.start_time, p.stop_time);
        Ok(())
    }
}
