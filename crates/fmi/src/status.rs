//! The status of a call and the failure that carries it with its reason, in the terms both
//! FMI versions share: FMI 2.0's `fmi2Status` and FMI 3.0's `fmi3Status` give OK, Warning,
//! Discard, Error and Fatal the same codes 0-4, so one enum serves both and each binding
//! converts it to its C type.

/// The outcome of a call (the `fmi_status` output records the worst one by its code).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
#[repr(i32)]
pub enum Status {
    /// All well.
    Ok = 0,
    /// Something is not right, but the computation can continue.
    Warning = 1,
    /// The result of the step is not usable.
    Discard = 2,
    /// The instance is in error; only reset and free are meaningful now.
    Error = 3,
    /// The model is corrupted.
    Fatal = 4,
}

/// A failure inside a call: status plus the message for the log.
#[derive(Debug)]
pub struct Failure {
    /// Status returned to the master.
    pub status: Status,
    /// Reason, logged under `logStatusError` (or `logStatusWarning`).
    pub message: String,
}

/// Shorthand for a [`Status::Error`] failure.
pub fn error(message: String) -> Failure {
    Failure {
        status: Status::Error,
        message,
    }
}
