//! `sin`, `atan2`, ... with C linkage, from the `libm` crate (see Cargo.toml).
#![no_std]

macro_rules! unary {
    ($($name:ident),*) => {$(
        /// The `libm` crate's function of this name.
        #[no_mangle]
        pub extern "C" fn $name(x: f64) -> f64 {
            libm::$name(x)
        }
    )*};
}
macro_rules! binary {
    ($($name:ident),*) => {$(
        /// The `libm` crate's function of this name.
        #[no_mangle]
        pub extern "C" fn $name(x: f64, y: f64) -> f64 {
            libm::$name(x, y)
        }
    )*};
}

unary!(
    sqrt, sin, cos, tan, asin, acos, atan, exp, log, cbrt, acosh, floor, ceil, round, trunc, fabs
);
binary!(atan2, pow, hypot);

/// The `libm` crate's fused multiply-add.
#[no_mangle]
pub extern "C" fn fma(x: f64, y: f64, z: f64) -> f64 {
    libm::fma(x, y, z)
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    loop {}
}
