//! The states of an instance's life cycle, shared by the bindings: each FMI version's
//! state machine maps onto them (FMI 2.0 co-simulation: the same five states; FMI 3.0
//! co-simulation: its Step Mode is [`ModelState::StepComplete`], its Event Mode
//! [`ModelState::EventMode`]). Each binding keeps, per function, the mask of the states it
//! is allowed in (`FmuInstance::require`).
//!
//! The codes are bit flags (for the masks) and are written into saved FMU states
//! (`docs/state-format.md`), so they never change; a state a later binding needs (FMI 3.0's
//! Event Mode) takes a new bit, and the debug names appear in messages.

/// A state of the life cycle (bit flags for "allowed in" masks).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u32)]
pub enum ModelState {
    /// After instantiation or reset.
    Instantiated = 1,
    /// Between entering and exiting initialisation mode.
    InitializationMode = 2,
    /// Ready for a step (FMI 2.0's StepComplete, FMI 3.0's Step Mode).
    StepComplete = 4,
    /// After terminate.
    Terminated = 8,
    /// After a call failed with an error.
    Error = 16,
    /// FMI 3.0's Event Mode: inputs set and applied at the current time
    /// (`fmi3UpdateDiscreteStates`), no time passes.
    EventMode = 32,
}

/// Mask of every state.
pub const ANY_STATE: u32 = 63;

impl ModelState {
    /// Every state, in the order of their codes.
    pub const ALL: [ModelState; 6] = [
        ModelState::Instantiated,
        ModelState::InitializationMode,
        ModelState::StepComplete,
        ModelState::Terminated,
        ModelState::Error,
        ModelState::EventMode,
    ];

    /// The state of a code, if it is one.
    pub fn from_code(code: u32) -> Option<Self> {
        Self::ALL.into_iter().find(|m| *m as u32 == code)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_are_distinct_bits_covered_by_any_state() {
        let mut all = 0;
        for m in ModelState::ALL {
            let c = m as u32;
            assert_eq!(c.count_ones(), 1);
            assert_eq!(all & c, 0);
            all |= c;
            assert_eq!(ModelState::from_code(c), Some(m));
        }
        assert_eq!(all, ANY_STATE);
        assert_eq!(ModelState::from_code(3), None);
    }
}
