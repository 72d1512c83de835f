//! The float functions of the standard library, for the build without it.
//!
//! With `std`, `x.sin()` and the like are `f64`'s own methods, which call the platform's C
//! math library (`sin`, `atan2`, ...) or compile to an instruction (`sqrt`, `floor`).
//! Without `std` those methods do not exist; a module that uses them imports [`Float`]
//! (`#[cfg(not(feature = "std"))] use crate::math::Float;`) and the same calls resolve to
//! its methods, which call the same C functions (the program links `-lm`) and the same
//! instructions: the flight build computes the same bits as the full library, which the
//! flight test checks. `powi` is the repeated squaring of compiler-rt's `__powidf2`, which
//! `f64::powi` calls; `rem_euclid` is the standard library's formula.

#![allow(unsafe_code)]

/// The C math library's functions that the core uses (FFI: every one is defined for every
/// `f64`, NaN and the infinities included, and has no other effect than setting `errno`).
#[cfg(not(feature = "std"))]
mod c {
    extern "C" {
        pub fn sqrt(x: f64) -> f64;
        pub fn sin(x: f64) -> f64;
        pub fn cos(x: f64) -> f64;
        pub fn tan(x: f64) -> f64;
        pub fn asin(x: f64) -> f64;
        pub fn acos(x: f64) -> f64;
        pub fn atan(x: f64) -> f64;
        pub fn atan2(y: f64, x: f64) -> f64;
        pub fn exp(x: f64) -> f64;
        pub fn log(x: f64) -> f64;
        pub fn pow(x: f64, y: f64) -> f64;
        pub fn cbrt(x: f64) -> f64;
        pub fn acosh(x: f64) -> f64;
        pub fn hypot(x: f64, y: f64) -> f64;
        pub fn floor(x: f64) -> f64;
        pub fn ceil(x: f64) -> f64;
        pub fn round(x: f64) -> f64;
        pub fn trunc(x: f64) -> f64;
        pub fn fabs(x: f64) -> f64;
        pub fn fma(x: f64, y: f64, z: f64) -> f64;
    }
}

/// `f64`'s float methods without the standard library (see the module documentation).
#[cfg(not(feature = "std"))]
pub trait Float: Sized {
    /// Square root.
    fn sqrt(self) -> f64;
    /// Sine.
    fn sin(self) -> f64;
    /// Cosine.
    fn cos(self) -> f64;
    /// Tangent.
    fn tan(self) -> f64;
    /// Sine and cosine.
    fn sin_cos(self) -> (f64, f64);
    /// Arcsine.
    fn asin(self) -> f64;
    /// Arccosine.
    fn acos(self) -> f64;
    /// Arctangent.
    fn atan(self) -> f64;
    /// Four-quadrant arctangent of `self / x`.
    fn atan2(self, x: f64) -> f64;
    /// `e^self`.
    fn exp(self) -> f64;
    /// Natural logarithm.
    fn ln(self) -> f64;
    /// `self^y`.
    fn powf(self, y: f64) -> f64;
    /// `self^n`.
    fn powi(self, n: i32) -> f64;
    /// Cube root.
    fn cbrt(self) -> f64;
    /// Inverse hyperbolic cosine.
    fn acosh(self) -> f64;
    /// `sqrt(self^2 + y^2)` without overflow.
    fn hypot(self, y: f64) -> f64;
    /// Largest integer not above.
    fn floor(self) -> f64;
    /// Smallest integer not below.
    fn ceil(self) -> f64;
    /// Nearest integer, halves away from zero.
    fn round(self) -> f64;
    /// Integer part.
    fn trunc(self) -> f64;
    /// Absolute value.
    fn abs(self) -> f64;
    /// `self * a + b` with one rounding.
    fn mul_add(self, a: f64, b: f64) -> f64;
    /// The least non-negative remainder of `self / rhs`.
    fn rem_euclid(self, rhs: f64) -> f64;
}

#[cfg(not(feature = "std"))]
impl Float for f64 {
    fn sqrt(self) -> f64 {
        // SAFETY (all calls below): C's math functions take and return doubles by value
        // and are defined for every input.
        unsafe { c::sqrt(self) }
    }
    fn sin(self) -> f64 {
        unsafe { c::sin(self) }
    }
    fn cos(self) -> f64 {
        unsafe { c::cos(self) }
    }
    fn tan(self) -> f64 {
        unsafe { c::tan(self) }
    }
    fn sin_cos(self) -> (f64, f64) {
        (self.sin(), self.cos())
    }
    fn asin(self) -> f64 {
        unsafe { c::asin(self) }
    }
    fn acos(self) -> f64 {
        unsafe { c::acos(self) }
    }
    fn atan(self) -> f64 {
        unsafe { c::atan(self) }
    }
    fn atan2(self, x: f64) -> f64 {
        unsafe { c::atan2(self, x) }
    }
    fn exp(self) -> f64 {
        unsafe { c::exp(self) }
    }
    fn ln(self) -> f64 {
        unsafe { c::log(self) }
    }
    fn powf(self, y: f64) -> f64 {
        unsafe { c::pow(self, y) }
    }
    fn powi(self, n: i32) -> f64 {
        // compiler-rt's __powidf2, term for term
        let recip = n < 0;
        let mut b = n;
        let mut a = self;
        let mut r = 1.0;
        loop {
            if b & 1 != 0 {
                r *= a;
            }
            b /= 2;
            if b == 0 {
                break;
            }
            a *= a;
        }
        if recip {
            1.0 / r
        } else {
            r
        }
    }
    fn cbrt(self) -> f64 {
        unsafe { c::cbrt(self) }
    }
    fn acosh(self) -> f64 {
        unsafe { c::acosh(self) }
    }
    fn hypot(self, y: f64) -> f64 {
        unsafe { c::hypot(self, y) }
    }
    fn floor(self) -> f64 {
        unsafe { c::floor(self) }
    }
    fn ceil(self) -> f64 {
        unsafe { c::ceil(self) }
    }
    fn round(self) -> f64 {
        unsafe { c::round(self) }
    }
    fn trunc(self) -> f64 {
        unsafe { c::trunc(self) }
    }
    fn abs(self) -> f64 {
        unsafe { c::fabs(self) }
    }
    fn mul_add(self, a: f64, b: f64) -> f64 {
        unsafe { c::fma(self, a, b) }
    }
    fn rem_euclid(self, rhs: f64) -> f64 {
        let r = self % rhs;
        if r < 0.0 {
            r + rhs.abs()
        } else {
            r
        }
    }
}
