//! Log categories: the instance decides what is sent (errors always; the other categories
//! when logging is on and the category enabled), the binding how (`Binding::log`).

/// Logging categories, in the order declared in the model description. The first is always
/// sent.
pub const LOG_CATEGORIES: [(&str, &str); 4] = [
    (
        "logStatusError",
        "Errors: rejected calls, invalid parameters or inputs, failed steps",
    ),
    ("logStatusWarning", "Warnings"),
    ("logInfo", "Initialisation and configuration summary"),
    ("logCalls", "Every FMI call with its arguments"),
];

/// Index of `logCalls` in [`LOG_CATEGORIES`].
pub(crate) const LOG_CALLS: usize = 3;
