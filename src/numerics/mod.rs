//! Numerical helpers shared by the layers above (estimators, H-infinity design, navigator,
//! C ABI): number formatting for error messages, the iteration-capped eigen and singular
//! value decompositions every caller uses instead of nalgebra's uncapped ones ([`eigen`]),
//! the thread setting of the BLAS linked for the H-infinity design, and [`state`] (the
//! explicit bytes of saved state). Lives below its users; imports nothing from them.

#[cfg(feature = "hinf")]
#[allow(unsafe_code)]
pub mod blas;
pub mod eigen;
pub mod state;

/// A number for an error message: plain when readable, scientific when tiny or huge.
pub fn num(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 || !v.is_finite() || (1e-4..1e7).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::num;

    #[test]
    fn formats_readable_and_extreme_numbers() {
        assert_eq!(num(0.5), "0.5");
        assert_eq!(num(0.0), "0");
        assert_eq!(num(1e-9), "1e-9");
        assert_eq!(num(2.5e12), "2.5e12");
        assert_eq!(num(f64::NAN), "NaN");
    }
}
