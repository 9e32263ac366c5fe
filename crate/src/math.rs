//! Transcendental functions that give the same bits on every target.
//!
//! `f64::sin`, `cos` and `ln` call the platform's C library natively (glibc,
//! macOS libm, …) and a Rust port of musl's libm in wasm; they may differ in
//! the last bit, and a simulation amplifies one bit into a different trace.
//! Everything that feeds a trace (forward kinematics, obstacle motions, the
//! noise generator) goes through these wrappers around the `libm` crate,
//! which is the same code natively and in wasm. `sqrt` and the arithmetic
//! operators are correctly rounded by IEEE 754 and need no wrapper.

/// `(sin x, cos x)`.
#[inline]
#[must_use]
pub fn sin_cos(x: f64) -> (f64, f64) {
    libm::sincos(x)
}

/// `sin x`.
#[inline]
#[must_use]
pub fn sin(x: f64) -> f64 {
    libm::sin(x)
}

/// `cos x`.
#[inline]
#[must_use]
pub fn cos(x: f64) -> f64 {
    libm::cos(x)
}

/// Natural logarithm.
#[inline]
#[must_use]
pub fn ln(x: f64) -> f64 {
    libm::log(x)
}
