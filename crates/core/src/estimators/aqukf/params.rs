//! The AQUKF's settings: the adaptation law ([`AdaptationLaw`]) and [`AqParams`], with the
//! capacities of the window and of the NIS gate's window.

use crate::types::Vec3;

/// Largest sliding-window width (capacity of the ring buffer).
pub const MAX_WINDOW: usize = 512;

/// Largest NIS-gate window (capacity of its ring buffer).
pub const MAX_GATE_WINDOW: usize = 128;

/// How the AQUKF adapts its velocity process noise (codes shared by the C ABI's
/// `relnav_adaptation` and the FMU's `aq_law` parameter).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(i32)]
pub enum AdaptationLaw {
    /// Paper 001 literally: the sliding-window recursion at every update.
    Window = 1,
    /// The same recursion, applied only while the windowed NIS exceeds its chi-square
    /// bound; `q_vv = q_vv0` otherwise (see the module documentation).
    Gated = 2,
}

impl AdaptationLaw {
    /// All codes, in order.
    pub const ALL: [AdaptationLaw; 2] = [AdaptationLaw::Window, AdaptationLaw::Gated];

    /// From the stable code 1..=2.
    pub fn from_code(code: i32) -> Option<Self> {
        Self::ALL.into_iter().find(|k| *k as i32 == code)
    }

    /// Short name (`window`, `gated`).
    pub fn name(self) -> &'static str {
        match self {
            AdaptationLaw::Window => "window",
            AdaptationLaw::Gated => "gated",
        }
    }
}

/// Settings of the adaptive process noise.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AqParams {
    /// Window width `N`, `1..=MAX_WINDOW` (paper 001: 10).
    pub window: usize,
    /// Initial velocity spectral density `q_vv` per axis [m^2/s^3] (clipped into
    /// `[floor, ceiling]`).
    pub q_vv0: Vec3,
    /// Lower bound on each `q_vv` entry [m^2/s^3], `>= 0`.
    pub floor: f64,
    /// Upper bound on each `q_vv` entry [m^2/s^3], `>= floor`, finite.
    pub ceiling: f64,
    /// Adaptation law (default [`AdaptationLaw::Gated`]).
    pub law: AdaptationLaw,
    /// Gated law: number `M` of updates in the windowed NIS, `1..=MAX_GATE_WINDOW`
    /// (default 10).
    pub gate_window: usize,
    /// Gated law: the gate opens when the windowed NIS exceeds its chi-square quantile at
    /// this probability, in (0, 1) (default 0.999: a false alarm in one test of 1000).
    pub gate_quantile: f64,
}

impl Default for AqParams {
    fn default() -> Self {
        Self {
            window: 10,
            q_vv0: Vec3::zeros(),
            floor: 0.0,
            ceiling: 1.0,
            law: AdaptationLaw::Gated,
            gate_window: 10,
            gate_quantile: 0.999,
        }
    }
}

impl AqParams {
    /// Check the settings; the message names the offending one.
    pub fn validate(&self) -> Result<(), crate::message::Message> {
        if !(1..=MAX_WINDOW).contains(&self.window) {
            return Err(crate::msg!(
                "window must lie in 1..={MAX_WINDOW} (got {})",
                self.window
            ));
        }
        if !(self.floor.is_finite() && self.floor >= 0.0) {
            return Err(crate::msg!(
                "q_vv_floor must be finite and >= 0 (got {})",
                crate::numerics::num(self.floor)
            ));
        }
        if !(self.ceiling.is_finite() && self.ceiling >= self.floor && self.ceiling > 0.0) {
            return Err(crate::msg!(
                "q_vv_ceiling must be finite, > 0 and >= q_vv_floor (got {}, floor {})",
                crate::numerics::num(self.ceiling),
                crate::numerics::num(self.floor)
            ));
        }
        if !self.q_vv0.iter().all(|q| q.is_finite() && *q >= 0.0) {
            return Err(crate::msg!(
                "the initial q_vv must be finite and >= 0 (got {:?})",
                self.q_vv0.as_slice()
            ));
        }
        if !(1..=MAX_GATE_WINDOW).contains(&self.gate_window) {
            return Err(crate::msg!(
                "aq_gate_window must lie in 1..={MAX_GATE_WINDOW} (got {})",
                self.gate_window
            ));
        }
        if !(self.gate_quantile > 0.0 && self.gate_quantile < 1.0) {
            return Err(crate::msg!(
                "aq_gate_quantile must lie in (0, 1) (got {}): the chi-square probability \
                 of the NIS gate",
                crate::numerics::num(self.gate_quantile)
            ));
        }
        Ok(())
    }
}
