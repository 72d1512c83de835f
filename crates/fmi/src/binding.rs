//! What an instance needs of the FMI version it is bound to, besides the calls themselves:
//! the master's logger as that version delivers it (FMI 2.0: a variadic `printf`-style
//! callback given the instance name; FMI 3.0: a plain callback) and the names of the calls
//! its messages refer to.

use crate::status::Status;
use std::ffi::CStr;

/// A binding's part of an instance (FMI 2.0: `fmi2::Logger`).
pub trait Binding {
    /// The call that ends initialisation (from then on the parameters are fixed).
    const EXIT_INITIALIZATION: &'static str;
    /// The call that returns an instance to its start values.
    const RESET: &'static str;

    /// Deliver one message of `instance` under `category` to the master.
    fn log(&self, instance: &CStr, status: Status, category: &str, message: &str);
}
