//! The evaluation engine's Monte Carlo campaigns, in pieces that can run anywhere:
//! `_Campaign` (a prepared scenario and its chunks of runs; `run_chunk` -> the partial
//! sums as bytes, without the GIL), `_Reducer` (adds the partial sums in chunk order) and
//! `CampaignResult` (the summary and time series, the same numbers as `summary.csv` and
//! `timeseries.csv`). `relnav/_campaign.py` schedules the chunks on threads or on Dask.

use crate::errors::invalid;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList};
use relnav_eval::metrics::{summarize, Summary};
use relnav_eval::report::{self, Field, SUMMARY_COLUMNS};
use relnav_eval::results::McResult;
use relnav_eval::runner::{Campaign, Partial, Reducer};
use relnav_eval::scenario::Scenario;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64};
use std::sync::Mutex;

fn runtime(e: String) -> PyErr {
    PyRuntimeError::new_err(e)
}

/// Parse a scenario: TOML text, or a dict with the TOML file's structure.
fn scenario_of(py: Python<'_>, source: &Bound<'_, PyAny>) -> PyResult<Scenario> {
    if let Ok(text) = source.extract::<String>() {
        return Scenario::from_toml(&text).map_err(|e| invalid(py, format!("scenario: {e}")));
    }
    let s: Scenario =
        pythonize::depythonize(source).map_err(|e| invalid(py, format!("scenario: {e}")))?;
    s.validate()
        .map_err(|e| invalid(py, format!("scenario: {e}")))?;
    Ok(s)
}

/// The TOML text of a scenario given as TOML text or as a dict: what the workers get.
/// A dict goes through the library's serialiser and is checked to parse back to the very
/// same scenario.
#[pyfunction]
pub fn scenario_toml(py: Python<'_>, source: &Bound<'_, PyAny>) -> PyResult<String> {
    if let Ok(text) = source.extract::<String>() {
        scenario_of(py, source)?;
        return Ok(text);
    }
    let s = scenario_of(py, source)?;
    let text = s.to_toml().map_err(runtime)?;
    match Scenario::from_toml(&text) {
        Ok(back) if back == s => Ok(text),
        _ => Err(runtime(
            "scenario: the dict does not survive a TOML round trip; pass the file instead".into(),
        )),
    }
}

/// The text of a built-in scenario (`relnav scenarios`), if `name` is one.
#[pyfunction]
pub fn builtin_scenario(name: &str) -> Option<&'static str> {
    relnav_eval::builtin::by_name(name)
}

/// Names of the built-in scenarios.
#[pyfunction]
pub fn builtin_scenarios() -> Vec<&'static str> {
    relnav_eval::builtin::BUILTIN
        .iter()
        .map(|(_, n, _)| *n)
        .collect()
}

/// A prepared campaign (internal; see `relnav.campaign`).
#[pyclass(module = "relnav._relnav", name = "_Campaign", frozen)]
pub struct PyCampaign {
    inner: Campaign,
}

#[pymethods]
impl PyCampaign {
    /// Prepare the scenario (TOML text or dict) for `runs` runs (None: the file's count).
    #[new]
    #[pyo3(signature = (scenario, runs = None))]
    fn new(py: Python<'_>, scenario: &Bound<'_, PyAny>, runs: Option<u32>) -> PyResult<Self> {
        let s = scenario_of(py, scenario)?;
        if runs == Some(0) {
            return Err(invalid(py, "runs must be >= 1"));
        }
        // preparing may design H-infinity filters: without the GIL
        let inner = py
            .detach(|| Campaign::new(&s, runs))
            .map_err(|e| invalid(py, format!("scenario: {e}")))?;
        Ok(Self { inner })
    }

    /// Scenario name.
    #[getter]
    fn name(&self) -> String {
        self.inner.prepared().scenario.name.clone()
    }

    /// Requested runs.
    #[getter]
    fn runs(&self) -> u64 {
        self.inner.runs()
    }

    /// The chunks of runs as (first, end) pairs, in reduction order.
    #[getter]
    fn chunks(&self) -> Vec<(u64, u64)> {
        self.inner
            .chunks()
            .iter()
            .map(|r| (r.start, r.end))
            .collect()
    }

    /// Run chunk `index` (without the GIL): its partial sums as bytes.
    fn run_chunk<'py>(&self, py: Python<'py>, index: usize) -> PyResult<Bound<'py, PyBytes>> {
        let (done, cancel) = (AtomicU64::new(0), AtomicBool::new(false));
        let bytes = py
            .detach(|| {
                self.inner
                    .run_chunk(index, &done, &cancel)
                    .map(|p| p.to_bytes())
            })
            .map_err(|e| invalid(py, e))?;
        Ok(PyBytes::new(py, &bytes))
    }

    /// An empty reducer.
    fn reducer(slf: &Bound<'_, Self>) -> PyReducer {
        PyReducer {
            campaign: slf.clone().unbind(),
            reducer: Mutex::new(Some(slf.get().inner.reducer())),
        }
    }
}

/// Adds partial sums in chunk order (internal).
#[pyclass(module = "relnav._relnav", name = "_Reducer", frozen)]
pub struct PyReducer {
    campaign: Py<PyCampaign>,
    reducer: Mutex<Option<Reducer>>,
}

impl PyReducer {
    fn with<T>(&self, f: impl FnOnce(&mut Reducer) -> Result<T, String>) -> PyResult<T> {
        let mut g = self
            .reducer
            .lock()
            .map_err(|_| runtime("reducer poisoned".into()))?;
        let r = g
            .as_mut()
            .ok_or_else(|| runtime("the reducer has finished".into()))?;
        f(r).map_err(runtime)
    }
}

#[pymethods]
impl PyReducer {
    /// Add the next chunk's partial sums (refused unless it is chunk `next_index`).
    fn add(&self, partial: &[u8]) -> PyResult<()> {
        let p = Partial::from_bytes(partial).map_err(runtime)?;
        let c = self.campaign.get();
        self.with(|r| r.add(&c.inner, &p))
    }

    /// The chunk `add` expects next.
    #[getter]
    fn next_index(&self) -> PyResult<usize> {
        self.with(|r| Ok(r.next_index()))
    }

    /// Runs added so far.
    #[getter]
    fn runs(&self) -> PyResult<u32> {
        self.with(|r| Ok(r.runs()))
    }

    /// The campaign's result (chunks never added count as not run: `interrupted`).
    fn finish(&self) -> PyResult<CampaignResult> {
        let r = self
            .reducer
            .lock()
            .map_err(|_| runtime("reducer poisoned".into()))?
            .take()
            .ok_or_else(|| runtime("the reducer has finished".into()))?;
        let result = self.campaign.get().inner.finish(r);
        let summary = summarize(&result);
        Ok(CampaignResult { result, summary })
    }
}

/// The result of a Monte Carlo campaign: ``summary`` (one dict per filter, the columns
/// and numbers of the CLI's ``summary.csv``), ``timeseries`` (the columns of
/// ``timeseries.csv`` as numpy arrays), ``markdown()`` (the CLI's table) and
/// ``write_csv(dir)`` / ``write_plots(dir)`` (the CLI's files).
#[pyclass(module = "relnav", frozen)]
pub struct CampaignResult {
    result: McResult,
    summary: Vec<Summary>,
}

#[pymethods]
impl CampaignResult {
    /// Scenario name.
    #[getter]
    fn scenario(&self) -> &str {
        &self.result.scenario
    }

    /// Scenario title.
    #[getter]
    fn title(&self) -> &str {
        &self.result.title
    }

    /// Completed runs.
    #[getter]
    fn runs(&self) -> u32 {
        self.result.runs
    }

    /// True when fewer runs completed than were requested.
    #[getter]
    fn interrupted(&self) -> bool {
        self.result.interrupted
    }

    /// Times [s].
    #[getter]
    fn t<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.result.t)
    }

    /// Filter labels, in scenario order.
    #[getter]
    fn filters(&self) -> Vec<String> {
        self.result
            .filters
            .iter()
            .map(|f| f.label.clone())
            .collect()
    }

    /// One dict per filter with the columns of ``summary.csv`` (numbers as float, NaN
    /// where the CSV cell is empty; counts as int; label, kind, published as str).
    /// ``us_per_step`` is wall-clock time, the only column that differs between runs.
    #[getter]
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let rows = PyList::empty(py);
        for row in report::summary_fields(&self.result, &self.summary) {
            let d = PyDict::new(py);
            for (name, f) in SUMMARY_COLUMNS.iter().zip(row) {
                match f {
                    Field::Text(t) => d.set_item(name, t)?,
                    Field::Int(i) => d.set_item(name, i)?,
                    Field::Num(v) => d.set_item(name, v)?,
                }
            }
            rows.append(d)?;
        }
        Ok(rows)
    }

    /// The columns of ``timeseries.csv`` (``t``, per filter ``<label>_rmse_x`` ...
    /// ``<label>_max_vel_err``, then ``pcrlb_*``) as numpy arrays, NaN where the CSV
    /// cell is empty.
    #[getter]
    fn timeseries<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (name, col) in report::timeseries_columns(&self.result) {
            d.set_item(name, PyArray1::from_vec(py, col))?;
        }
        Ok(d)
    }

    /// The PCRLB's diagonal (variances, K x 6) or None when it is undefined for the
    /// scenario (``pcrlb_reason`` says why).
    #[getter]
    fn pcrlb<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        diagonals(py, &self.result.pcrlb)
    }

    /// The bound along each run's own truth (the same recursion with each run's
    /// information, its inverse's diagonal averaged over the runs; variances, K x 6), or
    /// None where the PCRLB is undefined.
    #[getter]
    fn pcrlb_runs<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        diagonals(py, &self.result.pcrlb_runs)
    }

    /// Why the PCRLB is undefined (None when it is defined).
    #[getter]
    fn pcrlb_reason(&self) -> Option<String> {
        self.result.pcrlb.as_ref().err().cloned()
    }

    /// The CLI's Markdown table.
    fn markdown(&self) -> String {
        report::markdown_table(&self.result, &self.summary)
    }

    /// Write ``timeseries.csv`` and ``summary.csv`` into ``dir`` (as ``relnav simulate``
    /// does); returns their paths.
    fn write_csv(&self, dir: PathBuf) -> PyResult<Vec<PathBuf>> {
        report::write_csv(&self.result, &self.summary, &dir).map_err(runtime)
    }

    /// Write the CLI's PNG plots into ``dir``; returns their paths.
    fn write_plots(&self, py: Python<'_>, dir: PathBuf) -> PyResult<Vec<PathBuf>> {
        py.detach(|| report::write_plots(&self.result, &dir))
            .map_err(runtime)
    }

    fn __repr__(&self) -> String {
        format!(
            "CampaignResult(scenario={:?}, runs={}, filters={:?}{})",
            self.result.scenario,
            self.result.runs,
            self.filters(),
            if self.result.interrupted {
                ", interrupted"
            } else {
                ""
            }
        )
    }
}

/// A bound's per-time diagonals as a K x 6 array (None when undefined).
fn diagonals<'py>(
    py: Python<'py>,
    bound: &Result<Vec<[f64; 6]>, String>,
) -> PyResult<Option<Bound<'py, PyAny>>> {
    match bound {
        Ok(v) => {
            let flat: Vec<f64> = v.iter().flatten().copied().collect();
            Ok(Some(
                PyArray1::from_vec(py, flat)
                    .reshape([v.len(), 6])?
                    .into_any(),
            ))
        }
        Err(_) => Ok(None),
    }
}
