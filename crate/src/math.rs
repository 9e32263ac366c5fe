//! Transcendental functions that return the same bits on every target.
//!
//! `f64::sin` and friends call the platform's libm natively (glibc on Linux)
//! and a software libm in wasm; the two may differ in the last bit, which
//! would make a simulation trace differ between native and wasm. The core
//! calls these wrappers around the pure-Rust `libm` crate instead, on every
//! target. (`sqrt` is correctly rounded everywhere and needs no wrapper.)

/// `(sin x, cos x)` with one shared argument reduction.
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

/// `atan2(y, x)`.
#[inline]
#[must_use]
pub fn atan2(y: f64, x: f64) -> f64 {
    libm::atan2(y, x)
}

/// `acos x`.
#[inline]
#[must_use]
pub fn acos(x: f64) -> f64 {
    libm::acos(x)
}

/// `e^x`.
#[inline]
#[must_use]
pub fn exp(x: f64) -> f64 {
    libm::exp(x)
}

/// Natural logarithm.
#[inline]
#[must_use]
pub fn ln(x: f64) -> f64 {
    libm::log(x)
}

/// `x^y`.
#[inline]
#[must_use]
pub fn powf(x: f64, y: f64) -> f64 {
    libm::pow(x, y)
}
