//! Errors shared by every domain module.
//!
//! Validation failures name the offending field with a JSON-like path
//! (`joints[3].alpha`) and the reason, so the same message reads well from Rust
//! and, through the wasm layer, as a JavaScript `Error`.

use std::fmt;

/// An input value that was rejected, with the path of the field and the reason.
///
/// `Display` renders as `"{field}: {reason}"`, e.g.
/// `joints[3].alpha: not a finite number`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FieldError {
    /// JSON-like path of the field (`obstacles[2].shape.radius`).
    pub field: String,
    /// Why it was rejected (`must be > 0`).
    pub reason: String,
}

impl FieldError {
    /// A field error at `field` for `reason`.
    #[must_use]
    pub fn new(field: impl Into<String>, reason: impl Into<String>) -> Self {
        Self {
            field: field.into(),
            reason: reason.into(),
        }
    }

    /// The same error with `prefix` put in front of its path
    /// (`prefix = "robot"`, `field = "joints[1].a"` → `robot.joints[1].a`).
    #[must_use]
    pub fn within(mut self, prefix: &str) -> Self {
        if prefix.is_empty() {
            return self;
        }
        self.field = if self.field.is_empty() {
            prefix.to_owned()
        } else if self.field.starts_with('[') {
            format!("{prefix}{}", self.field)
        } else {
            format!("{prefix}.{}", self.field)
        };
        self
    }
}

impl fmt::Display for FieldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.field.is_empty() {
            f.write_str(&self.reason)
        } else {
            write!(f, "{}: {}", self.field, self.reason)
        }
    }
}

impl std::error::Error for FieldError {}

/// `Ok(x)` when `x` is finite, otherwise a [`FieldError`] at `field`.
///
/// # Errors
/// `field: not a finite number` for NaN and ±∞.
pub fn finite(field: &str, x: f64) -> Result<f64, FieldError> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(FieldError::new(field, "not a finite number"))
    }
}

/// `Ok(v)` when every component of `v` is finite.
///
/// # Errors
/// `field[k]: not a finite number` naming the first bad component.
pub fn finite3(field: &str, v: glam::DVec3) -> Result<glam::DVec3, FieldError> {
    for (k, c) in v.to_array().iter().enumerate() {
        if !c.is_finite() {
            return Err(FieldError::new(
                format!("{field}[{k}]"),
                "not a finite number",
            ));
        }
    }
    Ok(v)
}

/// `Ok(x)` when `x` is finite and strictly positive.
///
/// # Errors
/// `field: not a finite number` or `field: must be > 0`.
pub fn positive(field: &str, x: f64) -> Result<f64, FieldError> {
    finite(field, x)?;
    if x > 0.0 {
        Ok(x)
    } else {
        Err(FieldError::new(field, "must be > 0"))
    }
}

/// `Ok(x)` when `x` is finite and not negative.
///
/// # Errors
/// `field: not a finite number` or `field: must be >= 0`.
pub fn non_negative(field: &str, x: f64) -> Result<f64, FieldError> {
    finite(field, x)?;
    if x >= 0.0 {
        Ok(x)
    } else {
        Err(FieldError::new(field, "must be >= 0"))
    }
}
