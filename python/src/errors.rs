//! The library's errors as Python exceptions. The classes live in `relnav/errors.py`
//! (`relnav.Error` and one subclass per C-ABI status code, also deriving from the
//! matching built-in exception); this module raises them with the library's message.

use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::PyType;
use relnav_core::nav::{NavError, NavErrorKind};

/// The C ABI's status codes (`relnav_status`), by the name of their Python class.
#[derive(Debug, Clone, Copy)]
pub enum Status {
    /// `RELNAV_ERROR_INVALID_ARGUMENT` (2).
    InvalidArgument,
    /// `RELNAV_ERROR_NOT_IMPLEMENTED` (3).
    NotImplemented,
    /// `RELNAV_ERROR_NUMERICAL` (4).
    Numerical,
    /// `RELNAV_ERROR_PANIC` (5).
    Panic,
    /// `RELNAV_ERROR_INVALID_STATE` (8).
    InvalidState,
}

impl Status {
    fn class_name(self) -> &'static str {
        match self {
            Status::InvalidArgument => "InvalidArgumentError",
            Status::NotImplemented => "NotImplementedError",
            Status::Numerical => "NumericalError",
            Status::Panic => "PanicError",
            Status::InvalidState => "InvalidStateError",
        }
    }
}

impl From<NavErrorKind> for Status {
    fn from(k: NavErrorKind) -> Self {
        match k {
            NavErrorKind::InvalidArgument => Status::InvalidArgument,
            NavErrorKind::NotImplemented => Status::NotImplemented,
            NavErrorKind::Numerical => Status::Numerical,
            NavErrorKind::InvalidState => Status::InvalidState,
        }
    }
}

static ERRORS_MODULE: PyOnceLock<Py<PyModule>> = PyOnceLock::new();

/// A `relnav.errors` exception of class `status` with `message`.
pub fn error(py: Python<'_>, status: Status, message: impl Into<String>) -> PyErr {
    let message = message.into();
    let class = ERRORS_MODULE
        .get_or_try_init(py, || py.import("relnav.errors").map(|m| m.unbind()))
        .and_then(|m| m.bind(py).getattr(status.class_name()))
        .and_then(|c| c.cast_into::<PyType>().map_err(PyErr::from));
    match class {
        Ok(c) => PyErr::from_type(c, (message,)),
        // relnav.errors cannot be imported (a broken installation): still say why
        Err(e) => PyRuntimeError::new_err(format!("{message} (and relnav.errors: {e})")),
    }
}

/// A library error as its Python exception.
pub fn nav_error(py: Python<'_>, e: NavError) -> PyErr {
    error(py, e.kind.into(), e.message)
}

/// `InvalidArgumentError(message)`.
pub fn invalid(py: Python<'_>, message: impl Into<String>) -> PyErr {
    error(py, Status::InvalidArgument, message)
}
