//! The rules every number and every tagged object of a scenario obeys,
//! whoever builds it: a Rust caller that fills in a [`super::Scenario`]
//! field by field gets the same refusal, with the same message, as a
//! JavaScript caller whose object is read into JSON first.
//!
//! The rules are generic: they walk a JSON value (a caller's input, or a
//! typed value written back with serde), so a new configuration struct
//! obeys them without being registered anywhere.

use serde::Serialize;
use serde_json::Value;

use crate::error::FieldError;

/// Largest magnitude of any number in a scenario, a controller patch or an
/// obstacle (keys named in `UNBOUNDED_KEYS` aside). Geometry has its own,
/// tighter domain (±1e6 m, see `distance::domain` and `kinematics::spec`);
/// this bound keeps the rest (gains, velocities, times) from overflowing.
pub const MAX_NUMBER: f64 = 1e9;

/// Keys whose numbers are identifiers rather than magnitudes.
const UNBOUNDED_KEYS: &[&str] = &["seed"];

/// Tags of variants that carry no fields: a key beside such a tag is
/// refused (`{ type: "static", colour: 1 }`).
const BARE_TAGS: &[&str] = &["static", "hold"];

/// `field.key`, or `key` at the root.
fn child(field: &str, key: &str) -> String {
    if field.is_empty() {
        key.to_owned()
    } else {
        format!("{field}.{key}")
    }
}

/// Every number in `json` within ±[`MAX_NUMBER`], and no key beside the
/// `type` of a variant without fields.
///
/// # Errors
/// `controller.influenceDistance: must be within ±1e9 (got 1e10)`,
/// `obstacles[0].motion.colour: unknown field`.
pub fn check_json(field: &str, json: &Value) -> Result<(), FieldError> {
    match json {
        Value::Number(n) => match n.as_f64() {
            Some(x) if x.abs() > MAX_NUMBER => Err(FieldError::new(
                field,
                format!("must be within ±{MAX_NUMBER:e} (got {x:e})"),
            )),
            _ => Ok(()),
        },
        Value::Array(items) => items
            .iter()
            .enumerate()
            .try_for_each(|(k, v)| check_json(&format!("{field}[{k}]"), v)),
        Value::Object(map) => map.iter().try_for_each(|(k, v)| {
            let bare = map
                .get("type")
                .and_then(Value::as_str)
                .is_some_and(|t| BARE_TAGS.contains(&t));
            if bare && k != "type" {
                return Err(FieldError::new(child(field, k), "unknown field"));
            }
            if UNBOUNDED_KEYS.contains(&k.as_str()) {
                return Ok(());
            }
            check_json(&child(field, k), v)
        }),
        _ => Ok(()),
    }
}

/// [`check_json`] over `value` written as JSON: the bound for a value a
/// Rust caller built without reading JSON.
///
/// # Errors
/// As [`check_json`]; a value that cannot be written as JSON passes (the
/// typed checks see it).
pub fn check_value<T: Serialize + ?Sized>(field: &str, value: &T) -> Result<(), FieldError> {
    match serde_json::to_value(value) {
        Ok(json) => check_json(field, &json),
        Err(_) => Ok(()),
    }
}

/// Refuses an array given where `value` (read from `input`) holds an
/// object: serde reads a struct from a positional array in field order
/// (`damping: [0.1]` would set `epsilon`), which from JS is a mistake.
/// Compares `input` with `value` written back as JSON.
///
/// # Errors
/// `prefix.path: expected an object { a, b }, got an array`.
pub fn refuse_positional<T: Serialize>(
    prefix: &str,
    input: &serde_json::Value,
    value: &T,
) -> Result<(), FieldError> {
    let Ok(output) = serde_json::to_value(value) else {
        return Ok(());
    };
    match positional_at(input, &output, prefix) {
        Some((path, fields)) => Err(FieldError::new(
            path,
            format!(
                "expected an object {{ {} }}, got an array",
                fields.join(", ")
            ),
        )),
        None => Ok(()),
    }
}

/// The path of the first array in `input` that became an object in
/// `output`, with that object's keys.
fn positional_at(
    input: &serde_json::Value,
    output: &serde_json::Value,
    path: &str,
) -> Option<(String, Vec<String>)> {
    match (input, output) {
        (Value::Array(_), Value::Object(o)) => Some((path.to_owned(), o.keys().cloned().collect())),
        (Value::Array(a), Value::Array(b)) => a
            .iter()
            .zip(b)
            .enumerate()
            .find_map(|(k, (x, y))| positional_at(x, y, &format!("{path}[{k}]"))),
        (Value::Object(a), Value::Object(b)) => a.iter().find_map(|(k, x)| {
            let p = if path.is_empty() {
                k.clone()
            } else {
                format!("{path}.{k}")
            };
            b.get(k).and_then(|y| positional_at(x, y, &p))
        }),
        _ => None,
    }
}
