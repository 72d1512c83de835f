//! The navigator's errors: a category and a readable message naming the parameter or input.

use crate::estimators::FilterError;
use crate::numerics::state::StateError;

/// An invalid argument, with a readable reason.
#[derive(Debug, Clone, PartialEq)]
pub struct NavError {
    /// What went wrong.
    pub kind: NavErrorKind,
    /// Human-readable reason, naming the offending parameter or input.
    pub message: crate::message::Message,
}

/// Category of a [`NavError`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NavErrorKind {
    /// A parameter or input is out of its domain.
    InvalidArgument,
    /// The requested filter is not implemented in this build.
    NotImplemented,
    /// The filter could not complete the step (geometry, loss of positive definiteness).
    Numerical,
    /// A saved state was refused ([`Navigator::restore_state`]): truncated, corrupted,
    /// another format version, or saved for another configuration.
    InvalidState,
}

impl core::fmt::Display for NavError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(&self.message)
    }
}

impl NavError {
    /// An [`NavErrorKind::InvalidArgument`] with this message.
    pub fn invalid(message: impl Into<crate::message::Message>) -> Self {
        Self {
            kind: NavErrorKind::InvalidArgument,
            message: message.into(),
        }
    }
}

impl From<FilterError> for NavError {
    fn from(e: FilterError) -> Self {
        if let FilterError::Unsupported(why) = e {
            return Self {
                kind: NavErrorKind::NotImplemented,
                message: crate::message::Message::text(why),
            };
        }
        Self {
            kind: NavErrorKind::Numerical,
            message: e.message().prefixed("filter step failed: "),
        }
    }
}

/// One setting of a [`NavConfig`] as a saved state records it.
impl From<StateError> for NavError {
    fn from(e: StateError) -> Self {
        Self {
            kind: NavErrorKind::InvalidState,
            message: crate::msg!("state refused: {e}"),
        }
    }
}
