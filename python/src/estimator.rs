//! `relnav.Estimator`: a `relnav_core::nav::Navigator` configured by the FMU's parameter names,
//! with the library's step semantics, and a batch `run` over numpy arrays without the GIL.

use crate::errors::{error, invalid, nav_error, Status};
use crate::params;
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyFloat, PyInt, PyList, PyTuple};
use relnav_core::nav::{NavError, Navigator, Readings};
use relnav_nav_model::N_VARS;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::{Mutex, MutexGuard, TryLockError};

/// A relative-navigation estimator: one filter of the library behind the FMU's step
/// semantics, in the configured frame and SI units (angles in radians).
///
/// Estimator(**parameters)
///
/// Every keyword argument is an FMU parameter, with the FMU's name, type and default
/// (paper 000's example): ``filter`` (a code 1-9 or a name such as ``"ukf"``), ``frame``
/// (code or name), ``mean_motion``, ``sigma_range``, ..., ``particles``, ``seed``.
/// ``relnav.parameters()`` lists them all with units, defaults and descriptions. An
/// unknown name, a value of the wrong type or out of its domain raises
/// ``relnav.InvalidArgumentError``; a filter this build lacks raises
/// ``relnav.NotImplementedError``.
///
/// ``step(thrust, measurement=None, dt=1.0)`` applies the measurement taken at the step's
/// start (if any), then predicts over ``dt`` with the thrust held; afterwards ``state`` is
/// the prior at ``t + dt`` (as ``fmi2DoStep`` and ``relnav_estimator_step``). A failed
/// step changes nothing (see the library's documentation for the one particle-filter
/// exception) and raises the library's error with its message.
#[pyclass(module = "relnav", frozen)]
pub struct Estimator {
    /// Locked for each call (a navigator is `Send`, not `Sync`); never waited for: a
    /// second thread gets an error instead (it would hold the GIL that `run` needs back).
    nav: Mutex<Navigator>,
    values: [f64; N_VARS],
}

impl Estimator {
    fn nav(&self) -> PyResult<MutexGuard<'_, Navigator>> {
        self.nav.try_lock().map_err(|e| match e {
            TryLockError::WouldBlock => {
                PyRuntimeError::new_err("this Estimator is in use by another thread")
            }
            TryLockError::Poisoned(_) => {
                PyRuntimeError::new_err("this Estimator panicked in an earlier call")
            }
        })
    }
}

/// Read 3 numbers (a list, tuple, numpy array or any iterable).
fn vec3(py: Python<'_>, obj: &Bound<'_, PyAny>, what: &str) -> PyResult<[f64; 3]> {
    let bad = || invalid(py, format!("{what} must be 3 numbers (got {obj})"));
    let mut out = [0.0; 3];
    if let Ok(l) = obj.cast::<PyList>() {
        if l.len() != 3 {
            return Err(bad());
        }
        for (o, item) in out.iter_mut().zip(l.iter()) {
            *o = item.extract().map_err(|_| bad())?;
        }
    } else if let Ok(t) = obj.cast::<PyTuple>() {
        if t.len() != 3 {
            return Err(bad());
        }
        for (o, item) in out.iter_mut().zip(t.iter()) {
            *o = item.extract().map_err(|_| bad())?;
        }
    } else if let Ok(a) = obj.cast::<PyArray1<f64>>() {
        // element copies: no borrow of the array to register (cheaper for 3 numbers)
        if a.len() != 3 {
            return Err(bad());
        }
        for (i, o) in out.iter_mut().enumerate() {
            *o = a.get_owned([i]).ok_or_else(bad)?;
        }
    } else {
        out = vec_n::<3>(py, obj, what)?;
    }
    Ok(out)
}

/// `N` numbers from any sequence (a declared sensor's reading; [`vec3`]'s general case).
fn vec_n<const N: usize>(py: Python<'_>, obj: &Bound<'_, PyAny>, what: &str) -> PyResult<[f64; N]> {
    let bad = || invalid(py, format!("{what} must be {N} numbers (got {obj})"));
    let items: Vec<f64> = obj
        .try_iter()
        .map_err(|_| bad())?
        .map(|x| x.and_then(|x| x.extract::<f64>()))
        .collect::<PyResult<_>>()
        .map_err(|_| bad())?;
    items.try_into().map_err(|_| bad())
}

/// `numpy.asarray(obj, dtype=dtype)`.
fn as_array<'py>(obj: &Bound<'py, PyAny>, dtype: &str) -> PyResult<Bound<'py, PyAny>> {
    let py = obj.py();
    let kw = PyDict::new(py);
    kw.set_item("dtype", dtype)?;
    py.import("numpy")?
        .call_method("asarray", (obj,), Some(&kw))
}

/// A `K x cols` float64 matrix, row-major (any array-like).
fn matrix(obj: &Bound<'_, PyAny>, what: &str, cols: usize) -> PyResult<(usize, Vec<f64>)> {
    let py = obj.py();
    let arr = match obj.extract::<PyReadonlyArray2<'_, f64>>() {
        Ok(a) => a,
        Err(_) => as_array(obj, "float64")
            .and_then(|a| a.extract::<PyReadonlyArray2<'_, f64>>())
            .map_err(|_| invalid(py, format!("{what} must be a K x {cols} array of numbers")))?,
    };
    let shape = arr.shape();
    if shape.len() != 2 || shape[1] != cols {
        return Err(invalid(
            py,
            format!("{what} must have shape (K, {cols}) (got {shape:?})"),
        ));
    }
    Ok((shape[0], arr.as_array().iter().copied().collect()))
}

/// One sensor's readings for [`Estimator::run`]: K rows of `cols` numbers (`names.0`) and
/// their K flags (`names.1`; default: every row when the readings are given), or `None`
/// when no reading is given.
fn rows(
    py: Python<'_>,
    data: Option<&Bound<'_, PyAny>>,
    valid: Option<&Bound<'_, PyAny>>,
    names: (&str, &str),
    cols: usize,
    k: usize,
) -> PyResult<Option<(Vec<f64>, Vec<bool>)>> {
    let (what, flags) = names;
    let z = match data {
        Some(m) => {
            let (km, z) = matrix(m, what, cols)?;
            if km != k {
                return Err(invalid(py, format!("{what} has {km} rows, thrust {k}")));
            }
            Some(z)
        }
        None => None,
    };
    let v: Vec<bool> = match (valid, &z) {
        (Some(v), _) => {
            let a = as_array(v, "bool")
                .and_then(|a| a.extract::<PyReadonlyArray1<'_, bool>>())
                .map_err(|_| invalid(py, format!("{flags} must be K booleans")))?;
            if a.len() != k {
                return Err(invalid(
                    py,
                    format!("{flags} has {} entries for K = {k} steps", a.len()),
                ));
            }
            let v: Vec<bool> = a.as_array().iter().copied().collect();
            if z.is_none() && v.iter().any(|b| *b) {
                return Err(invalid(
                    py,
                    format!("{flags} marks {what} but {what} is None"),
                ));
            }
            v
        }
        (None, Some(_)) => vec![true; k],
        (None, None) => vec![false; k],
    };
    Ok(z.map(|z| (z, v)))
}

/// Row `i` of [`rows`]' readings when it is flagged.
fn row<const N: usize>(r: &Option<(Vec<f64>, Vec<bool>)>, i: usize) -> Option<[f64; N]> {
    match r {
        Some((z, v)) if v[i] => Some(std::array::from_fn(|j| z[N * i + j])),
        _ => None,
    }
}

/// A length-`k` vector (any array-like); a scalar is repeated when `scalar_ok`.
fn vector(obj: &Bound<'_, PyAny>, what: &str, k: usize) -> PyResult<Vec<f64>> {
    let py = obj.py();
    if obj.is_instance_of::<PyFloat>() || obj.is_instance_of::<PyInt>() {
        return Ok(vec![obj.extract::<f64>()?; k]);
    }
    let a = as_array(obj, "float64")
        .and_then(|a| a.extract::<PyReadonlyArray1<'_, f64>>())
        .map_err(|_| invalid(py, format!("{what} must be a number or K numbers")))?;
    if a.len() != k {
        return Err(invalid(
            py,
            format!("{what} has {} entries for K = {k} steps", a.len()),
        ));
    }
    Ok(a.as_array().iter().copied().collect())
}

fn array1<'py>(py: Python<'py>, v: &[f64]) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, v)
}

fn panic_error(py: Python<'_>, what: &str) -> PyErr {
    error(
        py,
        Status::Panic,
        format!("{what}: internal panic (a bug in relnav; please report it)"),
    )
}

#[pymethods]
impl Estimator {
    #[new]
    #[pyo3(signature = (**params))]
    fn new(py: Python<'_>, params: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        let values = params::values_from_kwargs(py, params)?;
        let cfg = params::config(py, &values)?;
        // the H-infinity filter solves its design here: without the GIL
        let nav = py
            .detach(|| catch_unwind(|| Navigator::new(&cfg)))
            .map_err(|_| panic_error(py, "Estimator()"))?
            .map_err(|e| nav_error(py, e))?;
        Ok(Self {
            nav: Mutex::new(nav),
            values,
        })
    }

    /// One step: update with ``measurement`` = (range [m], azimuth [rad], elevation
    /// [rad]) taken at the step's start (``None``: no measurement), then with the
    /// declared sensors' readings that are given, in this order: ``camera`` = (azimuth,
    /// elevation) [rad] of the line of sight, ``gnss_position`` = (x, y, z) [m] and
    /// ``gnss_velocity`` = (vx, vy, vz) [m/s] (I/O frame, taken at the step's start), then
    /// predict over ``dt`` [s] with ``thrust`` (x, y, z) [N] held constant.
    #[pyo3(signature = (thrust, measurement = None, dt = 1.0, *, camera = None, gnss_position = None, gnss_velocity = None))]
    #[allow(clippy::too_many_arguments)]
    fn step(
        &self,
        py: Python<'_>,
        thrust: &Bound<'_, PyAny>,
        measurement: Option<&Bound<'_, PyAny>>,
        dt: f64,
        camera: Option<&Bound<'_, PyAny>>,
        gnss_position: Option<&Bound<'_, PyAny>>,
        gnss_velocity: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let u = vec3(py, thrust, "thrust")?;
        let z = match measurement {
            Some(m) => Some(vec3(py, m, "measurement")?),
            None => None,
        };
        let readings = Readings {
            radio: z,
            camera: camera.map(|c| vec_n::<2>(py, c, "camera")).transpose()?,
            gnss_position: gnss_position
                .map(|g| vec3(py, g, "gnss_position"))
                .transpose()?,
            gnss_velocity: gnss_velocity
                .map(|g| vec3(py, g, "gnss_velocity"))
                .transpose()?,
        };
        let mut guard = self.nav()?;
        let nav = &mut *guard;
        catch_unwind(AssertUnwindSafe(|| nav.step_readings(&u, &readings, dt)))
            .map_err(|_| panic_error(py, "step"))?
            .map_err(|e| nav_error(py, e))
    }

    /// Time update only: predict over ``dt`` [s] with ``thrust`` [N] held.
    #[pyo3(signature = (thrust, dt = 1.0))]
    fn predict(&self, py: Python<'_>, thrust: &Bound<'_, PyAny>, dt: f64) -> PyResult<()> {
        let u = vec3(py, thrust, "thrust")?;
        let mut guard = self.nav()?;
        let nav = &mut *guard;
        catch_unwind(AssertUnwindSafe(|| nav.predict(&u, dt)))
            .map_err(|_| panic_error(py, "predict"))?
            .map_err(|e| nav_error(py, e))
    }

    /// Measurement update only, with (range [m], azimuth [rad], elevation [rad]).
    fn update(&self, py: Python<'_>, measurement: &Bound<'_, PyAny>) -> PyResult<()> {
        let z = vec3(py, measurement, "measurement")?;
        let mut guard = self.nav()?;
        let nav = &mut *guard;
        catch_unwind(AssertUnwindSafe(|| nav.update(&z).map(|_| ())))
            .map_err(|_| panic_error(py, "update"))?
            .map_err(|e| nav_error(py, e))
    }

    /// Back to the initial estimate (a particle filter redraws its particles from the
    /// configured seed: a reset estimator reproduces a new one bit for bit).
    fn reset(&self) -> PyResult<()> {
        self.nav()?.reset();
        Ok(())
    }

    /// Run ``K`` steps in one call, without the GIL.
    ///
    /// ``thrust``: K x 3 [N]; ``measurements``: K x 3 (range, azimuth, elevation) or
    /// ``None``; ``valid``: K booleans (row ``k`` of ``measurements`` is applied only where
    /// true; default: all rows when ``measurements`` is given); ``dt``: the step [s], one
    /// number or K numbers. Row ``k`` is exactly ``step(thrust[k], measurements[k] if
    /// valid[k] else None, dt[k])``. Returns ``(estimates, sigmas)``, each K x 6: row ``k``
    /// is the estimate and its 1-sigma after step ``k`` (the prior at ``t_k + dt``). If a
    /// step fails, the error names it (attribute ``step``) and the estimator stays after
    /// the previous step.
    ///
    /// The declared sensors the same way, each with its flags (default: every row when the
    /// readings are given): ``camera`` K x 2 (azimuth, elevation) with ``camera_valid``,
    /// ``gnss_position`` K x 3 with ``gnss_valid``, ``gnss_velocity`` K x 3 with
    /// ``gnss_velocity_valid``; row ``k`` is then ``step(...)`` with those of its readings
    /// that are flagged.
    #[pyo3(signature = (thrust, measurements = None, valid = None, dt = None, *, camera = None, camera_valid = None, gnss_position = None, gnss_valid = None, gnss_velocity = None, gnss_velocity_valid = None))]
    #[allow(clippy::too_many_arguments)]
    fn run<'py>(
        &self,
        py: Python<'py>,
        thrust: &Bound<'py, PyAny>,
        measurements: Option<&Bound<'py, PyAny>>,
        valid: Option<&Bound<'py, PyAny>>,
        dt: Option<&Bound<'py, PyAny>>,
        camera: Option<&Bound<'py, PyAny>>,
        camera_valid: Option<&Bound<'py, PyAny>>,
        gnss_position: Option<&Bound<'py, PyAny>>,
        gnss_valid: Option<&Bound<'py, PyAny>>,
        gnss_velocity: Option<&Bound<'py, PyAny>>,
        gnss_velocity_valid: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let (k, u) = matrix(thrust, "thrust", 3)?;
        let radio = rows(py, measurements, valid, ("measurements", "valid"), 3, k)?;
        let camera = rows(py, camera, camera_valid, ("camera", "camera_valid"), 2, k)?;
        let gnss_p = rows(
            py,
            gnss_position,
            gnss_valid,
            ("gnss_position", "gnss_valid"),
            3,
            k,
        )?;
        let gnss_v = rows(
            py,
            gnss_velocity,
            gnss_velocity_valid,
            ("gnss_velocity", "gnss_velocity_valid"),
            3,
            k,
        )?;
        let dt = match dt {
            Some(d) => vector(d, "dt", k)?,
            None => vec![1.0; k],
        };
        let mut guard = self.nav()?;
        let nav = &mut *guard;
        let out = py.detach(move || {
            catch_unwind(AssertUnwindSafe(|| {
                let mut est = vec![0.0; 6 * k];
                let mut sig = vec![0.0; 6 * k];
                for i in 0..k {
                    let ui: [f64; 3] = std::array::from_fn(|j| u[3 * i + j]);
                    let readings = Readings {
                        radio: row(&radio, i),
                        camera: row(&camera, i),
                        gnss_position: row(&gnss_p, i),
                        gnss_velocity: row(&gnss_v, i),
                    };
                    nav.step_readings(&ui, &readings, dt[i])
                        .map_err(|e: NavError| (i, e))?;
                    est[6 * i..6 * i + 6].copy_from_slice(nav.state().as_slice());
                    sig[6 * i..6 * i + 6].copy_from_slice(&nav.sigma());
                }
                Ok((est, sig))
            }))
        });
        let (est, sig) = match out {
            Err(_) => return Err(panic_error(py, "run")),
            Ok(Err((i, e))) => {
                let err = nav_error(
                    py,
                    NavError {
                        message: format!("step {i}: {}", e.message).into(),
                        ..e
                    },
                );
                err.value(py).setattr("step", i)?;
                return Err(err);
            }
            Ok(Ok(v)) => v,
        };
        let est = PyArray1::from_vec(py, est).reshape([k, 6])?.into_any();
        let sig = PyArray1::from_vec(py, sig).reshape([k, 6])?.into_any();
        Ok((est, sig))
    }

    /// The estimate (x, y, z [m], vx, vy, vz [m/s]) in the configured frame.
    #[getter]
    fn state<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(array1(py, self.nav()?.state().as_slice()))
    }

    /// The 6 x 6 covariance in the configured frame (NaN for the H-infinity filter).
    #[getter]
    fn covariance<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        // nalgebra is column-major; numpy rows are the matrix rows
        let p = self.nav()?.covariance().transpose();
        Ok(array1(py, p.as_slice()).reshape([6, 6])?.into_any())
    }

    /// 1-sigma of each state component (square roots of the covariance's diagonal; NaN
    /// for the H-infinity filter, which has no covariance).
    #[getter]
    fn sigma<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(array1(py, &self.nav()?.sigma()))
    }

    /// 1-sigma of the estimated range [m] (the covariance along the estimated line of
    /// sight; NaN for the H-infinity filter).
    #[getter]
    fn range_sigma(&self) -> PyResult<f64> {
        Ok(self.nav()?.range_sigma())
    }

    /// The normalised innovation squared of the last step's update by the radio, the
    /// camera, the GNSS position and the GNSS velocity (NaN for a sensor that gave no
    /// reading in that step, for point particles (`pf_prior = 1`) and the H-infinity filter,
    /// after a restore).
    #[getter]
    fn step_nis<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(array1(py, &self.nav()?.step_nis()))
    }

    /// Effective sample size of a particle filter after its last update (NaN for the
    /// other filters).
    #[getter]
    fn ess(&self) -> PyResult<f64> {
        Ok(self.nav()?.ess().unwrap_or(f64::NAN))
    }

    /// Fraction of a particle filter's moves accepted in the last step (NaN when it made
    /// none, and for the other filters).
    #[getter]
    fn pf_acceptance(&self) -> PyResult<f64> {
        Ok(self.nav()?.step_acceptance())
    }

    /// The AQUKF's adaptive velocity process-noise density per axis [m^2/s^3] (NaN for
    /// the other filters).
    #[getter]
    fn q_vv<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(array1(py, &self.nav()?.q_vv().unwrap_or([f64::NAN; 3])))
    }

    /// The H-infinity design's certified bound gamma (NaN for the other filters).
    #[getter]
    fn hinf_gamma(&self) -> PyResult<f64> {
        Ok(self.nav()?.hinf_gamma().unwrap_or(f64::NAN))
    }

    /// Whether the H-infinity filter runs its designed, certified gain (false while its
    /// track initiation runs; None for the other filters): the FMU's `hinf_certified`.
    #[getter]
    fn hinf_certified(&self) -> PyResult<Option<bool>> {
        Ok(self.nav()?.hinf_certified())
    }

    /// The H-infinity filter's designed matrices (filter code 9; None for the other
    /// filters), canonical frame, as numpy arrays: `a_f` (6x6), `b_f` (6x3), `c_f` (6x6),
    /// `e_f` (6x3), `b_v` (6x3, the gain on a measured velocity: zero unless the design
    /// takes one), and `period` [s]. They are the data the C ABI's runtime filter loads
    /// (`relnav_hinf_filter_init`, also in the flight library, which has no solver): the
    /// step `x_f <- A_F x_f + B_F y + E_F a`, estimate `C_F x_f`. An eccentric orbit's
    /// scheduled design (a gain per true anomaly) raises ValueError: the runtime filter
    /// takes one gain.
    #[getter]
    fn hinf_matrices<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let nav = self.nav()?;
        let Some(h) = nav.filter().hinf() else {
            return Ok(None);
        };
        if h.schedule().is_some() {
            return Err(invalid(
                py,
                "hinf_matrices: the eccentric orbit's design is scheduled (a gain per true \
                 anomaly); the runtime filter takes one gain",
            ));
        }
        let m = h.filter().matrices();
        let d = PyDict::new(py);
        // row-major, as numpy and the C ABI's `relnav_hinf_matrices` hold them
        fn rows<'py, M: core::ops::Index<(usize, usize), Output = f64>>(
            py: Python<'py>,
            m: &M,
            (r, c): (usize, usize),
        ) -> PyResult<Bound<'py, PyAny>> {
            let v: Vec<f64> = (0..r)
                .flat_map(|i| (0..c).map(move |j| m[(i, j)]))
                .collect();
            Ok(array1(py, &v).reshape([r, c])?.into_any())
        }
        d.set_item("a_f", rows(py, &m.a_f, (6, 6))?)?;
        d.set_item("b_f", rows(py, &m.b_f, (6, 3))?)?;
        d.set_item("c_f", rows(py, &m.c_f, (6, 6))?)?;
        d.set_item("e_f", rows(py, &m.e_f, (6, 3))?)?;
        d.set_item("b_v", rows(py, &m.b_v, (6, 3))?)?;
        d.set_item("period", m.period)?;
        Ok(Some(d))
    }

    /// Every parameter's value (enumerations by name), in the variable table's order.
    #[getter]
    fn params<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for v in params::parameters() {
            d.set_item(
                v.name,
                params::to_python(py, v, self.values[v.vr as usize])?,
            )?;
        }
        Ok(d)
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let mut parts = Vec::new();
        for v in params::parameters() {
            let x = self.values[v.vr as usize];
            if x.to_bits() != v.start.to_bits() || v.name == "filter" {
                parts.push(format!(
                    "{}={}",
                    v.name,
                    params::to_python(py, v, x)?.repr()?
                ));
            }
        }
        Ok(format!("Estimator({})", parts.join(", ")))
    }
}
