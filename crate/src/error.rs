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

/// `Ok(x)` when `x` is finite and within ±`bound` (a magnitude domain).
///
/// # Errors
/// `field: not a finite number` or `field: must be within ±1e6 (got 2e6)`.
pub fn bounded(field: &str, x: f64, bound: f64) -> Result<f64, FieldError> {
    let x = finite(field, x)?;
    if x.abs() > bound {
        return Err(FieldError::new(
            field,
            format!("must be within ±{bound:e} (got {x:e})"),
        ));
    }
    Ok(x)
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

/// Separates an inner path from its reason in the message of an error raised
/// by a deserialiser that buffers its input (a robot or shape read through a
/// JSON value): `\u{1f}path\u{1f}reason`. [`from_serde_path`] splices the
/// inner path back into the outer one.
const NESTED_MARK: char = '\u{1f}';

/// The message for an error at `path` inside a buffered value; see
/// [`from_serde_path`].
#[must_use]
pub fn nested_message(path: &str, reason: &str) -> String {
    format!("{NESTED_MARK}{path}{NESTED_MARK}{reason}")
}

fn join_path(outer: &str, inner: &str) -> String {
    match (outer.is_empty(), inner.is_empty()) {
        (_, true) => outer.to_owned(),
        (true, false) => inner.to_owned(),
        (false, false) if inner.starts_with('[') => format!("{outer}{inner}"),
        (false, false) => format!("{outer}.{inner}"),
    }
}

/// A [`FieldError`] from the path and message of a `serde_path_to_error`
/// error: nested paths (see [`nested_message`]) are spliced in, `"."` becomes
/// the empty path, and "missing field `x`" becomes `x: missing`.
#[must_use]
pub fn from_serde_path(path: &str, message: &str) -> FieldError {
    let mut path = if path == "." {
        String::new()
    } else {
        path.to_owned()
    };
    let mut reason = message.to_owned();
    while let Some(rest) = reason.strip_prefix(NESTED_MARK) {
        let Some((inner, tail)) = rest.split_once(NESTED_MARK) else {
            break;
        };
        let inner = if inner == "." { "" } else { inner };
        path = join_path(&path, inner);
        reason = tail.to_owned();
    }
    if let Some(name) = reason
        .strip_prefix("missing field `")
        .map(|r| r.trim_end_matches('`').to_owned())
    {
        path = join_path(&path, &name);
        reason = "missing".to_owned();
    }
    FieldError::new(path, reason)
}
