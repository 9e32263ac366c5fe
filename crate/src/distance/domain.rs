//! The magnitude domain of primitives: what `Primitive::from_spec` accepts
//! so that every distance, witness point and normal it leads to is finite,
//! and no dependency (parry's GJK/EPA) sees a degenerate scale.
//!
//! * Every coordinate, offset, axis and normal component, radius and half
//!   extent lies within ±[`MAX_COORDINATE`] (1e6 m). Distances are then at
//!   most ~3.5e6 m and their squares ~1e13: far from overflow.
//! * A polygon has at most [`MAX_VERTICES`] vertices and a convex hull at
//!   most as many points, so validation (O(N²) for self-intersection) stays
//!   in milliseconds.
//! * A box's or rectangle's smallest half extent is at least
//!   [`MIN_ASPECT`] times its largest, so parry's EPA never meets a sliver.

use super::primitive::PrimitiveSpec;
use crate::error::FieldError;

/// Largest magnitude of any number in a primitive (m).
pub const MAX_COORDINATE: f64 = 1e6;

/// Most vertices of a polygon (and points of a convex hull).
pub const MAX_VERTICES: usize = 1024;

/// Smallest ratio of a box's smallest to its largest half extent.
pub const MIN_ASPECT: f64 = 1e-6;

/// Checks `spec` against the domain (before any constructor sees it).
///
/// # Errors
/// `center[1]: must be within ±1000000`, `vertices: at most 1024 vertices`,
/// `halfExtents: smallest below 1e-6 of the largest`.
pub fn check(spec: &PrimitiveSpec) -> Result<(), FieldError> {
    match spec {
        PrimitiveSpec::Polygon(s) if s.vertices.len() > MAX_VERTICES => {
            return Err(FieldError::new(
                "vertices",
                format!("at most {MAX_VERTICES} vertices"),
            ));
        }
        PrimitiveSpec::ConvexHull(s) if s.points.len() > MAX_VERTICES => {
            return Err(FieldError::new(
                "points",
                format!("at most {MAX_VERTICES} points"),
            ));
        }
        PrimitiveSpec::Box(s) => aspect("halfExtents", &s.half_extents)?,
        PrimitiveSpec::Rectangle(s) => aspect("halfExtents", &s.half_extents)?,
        _ => {}
    }
    let json = serde_json::to_value(spec).map_err(|e| FieldError::new("", e.to_string()))?;
    within("", &json)
}

fn aspect(field: &str, h: &[f64]) -> Result<(), FieldError> {
    let max = h.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let min = h.iter().fold(f64::INFINITY, |m, x| m.min(x.abs()));
    if min.is_finite() && max.is_finite() && min > 0.0 && min < MIN_ASPECT * max {
        return Err(FieldError::new(
            field,
            format!("the smallest is below {MIN_ASPECT} of the largest"),
        ));
    }
    Ok(())
}

/// Every number in `value` within ±[`MAX_COORDINATE`] (non-finite numbers are
/// left to the constructors, which name them).
fn within(path: &str, value: &serde_json::Value) -> Result<(), FieldError> {
    use serde_json::Value;
    match value {
        Value::Number(n) => match n.as_f64() {
            Some(x) if x.abs() > MAX_COORDINATE => Err(FieldError::new(
                path,
                format!("must be within ±{MAX_COORDINATE:e} (got {x:e})"),
            )),
            _ => Ok(()),
        },
        Value::Array(items) => items
            .iter()
            .enumerate()
            .try_for_each(|(k, v)| within(&format!("{path}[{k}]"), v)),
        Value::Object(map) => map.iter().try_for_each(|(k, v)| {
            let p = if path.is_empty() {
                k.clone()
            } else {
                format!("{path}.{k}")
            };
            within(&p, v)
        }),
        _ => Ok(()),
    }
}
