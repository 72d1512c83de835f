//! The FMU state as explicit, versioned bytes (`docs/state-format.md`), the same for every
//! model and FMI version, and the registry of the state handles an instance has handed out.
//!
//! An FMU state is the instance's complete state in one byte string: a 70-byte header
//! (magic `RELNAVFM`, [`FMU_STATE_FORMAT_VERSION`], the FMU's GUID, the model code —
//! relnav's `filter`, the plant's `truth_model`, 0 for the guidance —, a fingerprint of the
//! parameter values, payload length, CRC-32), then the state-machine state, the time and
//! experiment bounds, the value of every variable (parameters, held inputs, published
//! outputs), and — once the model is built — the model's own state ([`Model::save`];
//! relnav: the navigator's saved state). The handle handed to the master is that byte
//! string, so getting a state serialises it once, serialising copies it, and every state
//! is checked the same way.
//!
//! What a restore brings back and what it refuses is the instance's
//! (`FmuInstance::restore_state`); this module writes the bytes
//! ([`encode`]) and checks everything that does not depend on the restoring instance
//! ([`decode`]): truncated or over-long bytes, a CRC-32 mismatch, another magic or format
//! version, another FMU's GUID, a header that disagrees with the parameters it carries, a
//! model state where the state-machine state has none (or none where it needs one).
//!
//! [`Model::save`]: crate::model::Model::save

use crate::machine::ModelState;
use crate::model::ModelInfo;
use crate::variables::{Causality, VarDef};
use relnav_core::numerics::state::{self, crc32, refuse, Reader, StateError, FMU_MAGIC, KINDS};
use std::ffi::c_void;

/// Format version of the FMU state bytes. Bump it whenever the layout changes; a state of
/// another version is refused, never misread.
pub const FMU_STATE_FORMAT_VERSION: u32 = 1;

/// Bytes of the GUID in the header (`{8-4-4-4-12}`, ASCII).
const GUID_LEN: usize = 38;
/// Identity block of the header: GUID, model code (i32), parameter fingerprint (u32).
const IDENT_LEN: usize = GUID_LEN + 4 + 4;

/// One FMU state handed to the master: the serialised state.
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

/// The states an instance has handed out, as opaque pointers (`fmi2FMUstate`,
/// `fmi3FMUState`). A pointer is only ever compared with these, never dereferenced on the
/// master's word: an unknown or freed pointer is an error, not undefined behaviour. States
/// left unfreed go with the instance.
#[derive(Debug, Default)]
pub struct StateRegistry {
    /// boxed on purpose: the pointer handed to the master must not move when the vector
    /// grows
    #[allow(clippy::vec_box)]
    live: Vec<Box<FmuState>>,
}

impl StateRegistry {
    fn position(&self, p: *mut c_void) -> Option<usize> {
        self.live
            .iter()
            .position(|b| std::ptr::eq(&**b, p.cast::<FmuState>().cast_const()))
    }

    /// Store `bytes` in the state `p` if this instance made it, else in a new state;
    /// returns the state's pointer.
    pub fn put(&mut self, p: *mut c_void, bytes: Vec<u8>) -> *mut c_void {
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
    pub fn get(&self, p: *mut c_void) -> Option<&FmuState> {
        self.position(p)
            .and_then(|i| self.live.get(i))
            .map(|b| &**b)
    }

    /// Free the state behind `p`; `false` if this instance has no such state.
    pub fn free(&mut self, p: *mut c_void) -> bool {
        match self.position(p) {
            Some(i) => {
                self.live.swap_remove(i);
                true
            }
            None => false,
        }
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

/// What an instance's state consists of, to be written by [`encode`].
pub struct Snapshot<'a> {
    /// State-machine state.
    pub mode: ModelState,
    /// Current time.
    pub time: f64,
    /// Start time of the experiment.
    pub start_time: f64,
    /// Stop time of the experiment, if defined.
    pub stop_time: Option<f64>,
    /// Every variable's value, by value reference.
    pub values: &'a [f64],
    /// The model's own state, once it is built.
    pub model: Option<&'a [u8]>,
}

/// A checked FMU state ([`decode`]): everything but what depends on the restoring
/// instance.
pub struct Decoded<'a> {
    /// State-machine state.
    pub mode: ModelState,
    /// Time.
    pub time: f64,
    /// Start time.
    pub start_time: f64,
    /// Stop time, if defined.
    pub stop_time: Option<f64>,
    /// Every variable's value, by value reference.
    pub values: Vec<f64>,
    /// The model's own state, if the state carries one.
    pub model: Option<&'a [u8]>,
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

/// The bytes of the state `s` of an instance of the model `info` whose GUID is `guid`.
pub fn encode(info: &ModelInfo, guid: &str, s: &Snapshot<'_>) -> Vec<u8> {
    let values = s.values;
    let mut ident = Vec::with_capacity(IDENT_LEN);
    ident.extend_from_slice(&guid_bytes(guid));
    ident.extend_from_slice(&info.state_code_of(values).to_le_bytes());
    ident.extend_from_slice(&fingerprint(info.variables, values).to_le_bytes());
    let mut out = Vec::new();
    state::seal(&mut out, FMU_MAGIC, FMU_STATE_FORMAT_VERSION, &ident, |w| {
        w.tag(b"FMUI");
        w.u32(s.mode as u32);
        w.f64(s.time);
        w.f64(s.start_time);
        w.bool(s.stop_time.is_some());
        w.f64(s.stop_time.unwrap_or(0.0));
        w.usize(values.len());
        for v in values {
            w.f64(*v);
        }
        match s.model {
            Some(b) => {
                w.bool(true);
                w.usize(b.len());
                w.bytes(b);
            }
            None => w.bool(false),
        }
    });
    out
}

/// Check and read the bytes of a state of the model `info` whose GUID is `guid`.
pub fn decode<'a>(
    info: &ModelInfo,
    guid: &str,
    bytes: &'a [u8],
) -> Result<Decoded<'a>, StateError> {
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
    let mode = ModelState::from_code(m)
        .ok_or_else(|| refuse(format!("unknown state-machine state {m}")))?;
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
        ModelState::StepComplete | ModelState::Terminated | ModelState::EventMode => Some(true),
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
    Ok(Decoded {
        mode,
        time,
        start_time,
        stop_time,
        values,
        model,
    })
}
