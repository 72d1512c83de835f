//! The interface between the FMI plumbing and one model, after the Modelica Reference-FMUs'
//! `model.h`, for every FMI version: a model is its static [`ModelInfo`] (identifier,
//! description, variable table, default experiment) and a [`Model`] implementation (early
//! parameter checks, the outputs before initialisation, initialise, step, reset, its
//! dynamic state as bytes). The instance (`instance.rs`) keeps the value of every
//! variable in one array indexed by value reference and does the typed get/set by value
//! reference itself, driven by the table: start values, type classes, causality and
//! code-list checks are the same for every model, so no model writes a dispatch. A model
//! reads its parameters and inputs from that array and writes its outputs into it.
//!
//! Nothing here is specific to an FMI version; the bindings (`fmi2/`) call it.

use crate::variables::VarDef;
use std::sync::OnceLock;

/// `DefaultExperiment` of the model description (seconds).
#[derive(Debug, Clone, Copy)]
pub struct DefaultExperiment {
    /// `startTime`.
    pub start: f64,
    /// `stopTime`.
    pub stop: f64,
    /// `stepSize`.
    pub step: f64,
}

/// What the bindings generate from a [`ModelInfo`] once and keep: per FMI version, the
/// model description and the GUID (instantiation token) derived from it.
#[derive(Debug, Default)]
pub struct Generated {
    pub(crate) fmi2: OnceLock<(String, String)>,
    pub(crate) fmi3: OnceLock<(String, String)>,
    /// FMI 3.0: per table row, whether an array holds it (built once; the scalar gets and
    /// sets of every step look it up)
    pub(crate) in_array: OnceLock<Vec<bool>>,
}

impl Generated {
    /// Nothing generated yet (for the `static` of a [`ModelInfo`]).
    pub const fn new() -> Self {
        Self {
            fmi2: OnceLock::new(),
            fmi3: OnceLock::new(),
            in_array: OnceLock::new(),
        }
    }
}

/// A vector of the variable table that FMI 3.0 publishes as one array variable (FMI 2.0
/// has only scalars: there the elements are the variables). The elements share causality,
/// variability and base type; the array has their unit when they all have the same, none
/// otherwise (its description names them).
#[derive(Debug, Clone, Copy)]
pub struct ArrayDef {
    /// The array's name.
    pub name: &'static str,
    /// Value references of its elements in the table, in order.
    pub elements: &'static [u32],
    /// Its description.
    pub description: &'static str,
}

/// A Float64 output array FMI 3.0 publishes that the table does not hold (FMI 2.0 has no
/// place for it): the model computes its values when they are read ([`Model::computed`]),
/// from its state once built and from the parameters before. Continuous, row-major.
#[derive(Debug, Clone, Copy)]
pub struct ComputedDef {
    /// The array's name.
    pub name: &'static str,
    /// Its dimensions (row-major; the product is the number of values).
    pub dims: &'static [usize],
    /// Its unit (empty: none; the description names the units of mixed arrays).
    pub unit: &'static str,
    /// Its description.
    pub description: &'static str,
}

impl ComputedDef {
    /// The number of values.
    pub fn len(&self) -> usize {
        self.dims.iter().product()
    }

    /// Whether it holds no value.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// What the FMI plumbing knows of one model, as a `static` beside the model.
#[derive(Debug)]
pub struct ModelInfo {
    /// `modelIdentifier` (and `modelName`, and the binary's name).
    pub model_identifier: &'static str,
    /// The model's `description` attribute.
    pub description: &'static str,
    /// The variable table (value reference = index), written by [`crate::variables!`].
    pub variables: &'static [VarDef],
    /// `DefaultExperiment`.
    pub default_experiment: DefaultExperiment,
    /// Value reference of the Integer output `fmi_status` (the worst status returned).
    pub fmi_status: u32,
    /// Value reference of the Integer parameter written into the FMU state's header as its
    /// model code (relnav: `filter`), if any (0 is written otherwise).
    pub state_code: Option<u32>,
    /// What the model's dynamic state is called in messages ("estimator", ...).
    pub state_name: &'static str,
    /// The vectors FMI 3.0 publishes as arrays (in the order of their value references:
    /// appended only, never reordered).
    pub arrays: &'static [ArrayDef],
    /// Whether FMI 3.0's Event Mode applies inputs between steps ([`Model::event_update`];
    /// `hasEventMode`).
    pub has_event_mode: bool,
    /// The outputs FMI 3.0 publishes beyond the table, computed by the model on request
    /// ([`Model::computed`]; in the order of their value references, appended only).
    pub computed: &'static [ComputedDef],
    /// The bindings' generated texts ([`Generated::new`] in the `static`).
    pub generated: Generated,
}

impl ModelInfo {
    /// The definition for a value reference, if it exists.
    pub fn lookup(&self, vr: u32) -> Option<&'static VarDef> {
        self.variables.get(vr as usize)
    }

    /// The model code of a set of values (see [`ModelInfo::state_code`]).
    pub fn state_code_of(&self, values: &[f64]) -> i32 {
        self.state_code
            .and_then(|r| values.get(r as usize))
            .map_or(0, |v| *v as i32)
    }
}

/// One model: what the instance calls at each point of the life cycle. `values` is always
/// the instance's array of every variable (length `info().variables.len()`); errors are
/// full messages (the instance adds the call and, for a step, its time), logged under
/// `logStatusError` and returned as an error status.
pub trait Model: Sized {
    /// The model's static description.
    fn info() -> &'static ModelInfo;

    /// A model with nothing built, as after instantiation or reset.
    fn new() -> Self;

    /// Refuse, when a parameter is set, a value that is invalid whatever the other
    /// parameters are (the message says why; combinations are checked by
    /// [`Model::initialize`]).
    fn check_alone(def: &VarDef, value: f64) -> Result<(), String>;

    /// Outputs before initialisation ends, from the current parameter values and the start
    /// `time` (called at instantiation, reset, experiment setup, entering initialisation
    /// mode and after every set in those states). They should equal what
    /// [`Model::initialize`] will publish, so a master that reads them in initialisation
    /// mode sees the initial values.
    fn initial_outputs(values: &mut [f64], time: f64);

    /// The end of initialisation at `time`: check the parameters together, build the
    /// model, publish its outputs. Returns the line logged under `logInfo`.
    fn initialize(&mut self, values: &mut [f64], time: f64) -> Result<String, String>;

    /// One communication step from `tc` over `h`, once the instance has checked `h > 0`,
    /// `tc` and the stop time: the inputs in `values` hold at `tc`; afterwards the outputs
    /// describe `tc + h`. The error is the reason alone (the instance names the call and
    /// `tc`).
    fn do_step(&mut self, values: &mut [f64], tc: f64, h: f64) -> Result<(), String>;

    /// Drop what [`Model::initialize`] built.
    fn reset(&mut self);

    /// Apply the inputs at time `t` without advancing time (FMI 3.0's Event Mode; models
    /// with [`ModelInfo::has_event_mode`]); the outputs then describe `t`. The default is
    /// for models without Event Mode.
    fn event_update(&mut self, values: &mut [f64], t: f64) -> Result<(), String> {
        let _ = (values, t);
        Err("this model has no Event Mode".to_string())
    }

    /// The values of the computed output `index` of [`ModelInfo::computed`] into `out`
    /// (its length): from the built model, or from `values` (the parameters) before it
    /// is built. The default is for models without computed outputs.
    fn computed(&self, values: &[f64], index: usize, out: &mut [f64]) {
        let _ = (values, index);
        out.fill(f64::NAN);
    }

    /// Whether [`Model::initialize`] has built the model (parameters are then fixed).
    fn is_built(&self) -> bool;

    /// The built model's dynamic state as explicit bytes (`None` before it is built).
    fn save(&self) -> Result<Option<Vec<u8>>, String>;

    /// Restore bytes from [`Model::save`]: into this model if it is built (with the same
    /// parameters, checked by the caller), else into a model built from `values` first.
    /// Transactional: on error nothing changes. The message says why the state is
    /// refused.
    fn restore(&mut self, values: &[f64], bytes: &[u8]) -> Result<(), String>;
}
