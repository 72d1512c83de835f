//! The master's FMI 3.0 logger: a plain callback with the instance environment, the status,
//! the category and the message.

use super::types::{fmi3InstanceEnvironment, fmi3LogMessageCallback, fmi3Status};
use crate::binding::Binding;
use crate::fmi2::MAX_LOG_CHARS;
use crate::status::Status;
use std::ffi::{CStr, CString};

/// The logger callback and its environment, kept from instantiation.
#[derive(Clone, Copy)]
pub struct Logger {
    callback: fmi3LogMessageCallback,
    env: fmi3InstanceEnvironment,
}

impl Logger {
    /// Wrap the master's callback (which may be absent).
    pub fn new(callback: fmi3LogMessageCallback, env: fmi3InstanceEnvironment) -> Self {
        Self { callback, env }
    }

    /// Send one message (NULs dropped, cut at [`MAX_LOG_CHARS`] characters with ` ...`
    /// appended, as FMI 2.0's); FMI 3.0's message is the text itself, not a format, and the
    /// instance is the master's environment, so nothing is escaped.
    pub fn send(&self, status: fmi3Status, category: &str, msg: &str) {
        let Some(cb) = self.callback else { return };
        let Ok(cat) = CString::new(category) else {
            return;
        };
        let Ok(text) = CString::new(clip(msg)) else {
            return;
        };
        // SAFETY: the master gave us this callback for the lifetime of the instance; both
        // strings are NUL-terminated and live across the call.
        unsafe { cb(self.env, status, cat.as_ptr(), text.as_ptr()) };
    }
}

impl Binding for Logger {
    const EXIT_INITIALIZATION: &'static str = "fmi3ExitInitializationMode";
    const RESET: &'static str = "fmi3Reset";

    fn log(&self, _instance: &CStr, status: Status, category: &str, message: &str) {
        self.send(status.into(), category, message);
    }
}

/// A message without NULs, cut at [`MAX_LOG_CHARS`] characters.
fn clip(msg: &str) -> String {
    let mut out = String::with_capacity(msg.len().min(4 * MAX_LOG_CHARS) + 4);
    for (i, c) in msg.chars().filter(|c| *c != '\0').enumerate() {
        if i == MAX_LOG_CHARS {
            out.push_str(" ...");
            break;
        }
        out.push(c);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_are_sent_as_they_are() {
        assert_eq!(clip("50% #r3# a\0b"), "50% #r3# ab");
        let long = "x".repeat(MAX_LOG_CHARS + 10);
        assert_eq!(clip(&long), format!("{} ...", "x".repeat(MAX_LOG_CHARS)));
    }
}
