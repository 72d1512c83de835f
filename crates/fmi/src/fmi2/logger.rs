//! The master's FMI 2.0 logger: a variadic C callback whose message is a `printf` format.

use super::types::{fmi2CallbackLogger, fmi2ComponentEnvironment, fmi2Status};
use crate::binding::Binding;
use crate::status::Status;
use std::ffi::{c_int, CStr, CString};

/// The logger callback and its environment, copied at `fmi2Instantiate` (the callbacks
/// struct is valid only during that call).
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
    pub fn send(&self, instance: &CStr, status: fmi2Status, category: &str, msg: &str) {
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

impl Binding for Logger {
    const EXIT_INITIALIZATION: &'static str = "fmi2ExitInitializationMode";
    const RESET: &'static str = "fmi2Reset";

    fn log(&self, instance: &CStr, status: Status, category: &str, message: &str) {
        self.send(instance, status.into(), category, message);
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_messages_are_printf_formats() {
        assert_eq!(escape_log_message("50% #r3# ok"), "50%% ##r3## ok");
        assert_eq!(escape_log_message("a\0b"), "ab");
        let long = "%".repeat(MAX_LOG_CHARS + 10);
        let e = escape_log_message(&long);
        assert_eq!(e, format!("{} ...", "%%".repeat(MAX_LOG_CHARS)));
    }
}
