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

use super::primitive::{
    BoxSpec, CapsuleSpec, ConvexHullSpec, DiskSpec, PlaneSpec, PointSpec, PolygonSpec,
    PrimitiveSpec, RectangleSpec, SegmentSpec, SphereSpec, TaperedCapsuleSpec,
};
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
    // Most specs are within the domain (a person's parts are checked every
    // control step): only a number out of it is looked for by name.
    if largest(spec) <= MAX_COORDINATE {
        return Ok(());
    }
    let json = serde_json::to_value(spec).map_err(|e| FieldError::new("", e.to_string()))?;
    within("", &json)
}

/// The largest magnitude of the finite numbers of `spec` (every field named,
/// so that a field added to a spec must be added here).
fn largest(spec: &PrimitiveSpec) -> f64 {
    let m = |xs: &[f64]| {
        xs.iter()
            .filter(|x| x.is_finite())
            .fold(0.0_f64, |m, x| m.max(x.abs()))
    };
    let all = |ps: &[[f64; 3]]| ps.iter().fold(0.0_f64, |a, p| a.max(m(p)));
    match spec {
        PrimitiveSpec::Point(PointSpec { p }) => m(p),
        PrimitiveSpec::Segment(SegmentSpec { a, b }) => m(a).max(m(b)),
        PrimitiveSpec::Sphere(SphereSpec { center, radius }) => m(center).max(m(&[*radius])),
        PrimitiveSpec::Capsule(CapsuleSpec { a, b, radius }) => m(a).max(m(b)).max(m(&[*radius])),
        PrimitiveSpec::TaperedCapsule(TaperedCapsuleSpec { a, b, radius }) => {
            m(a).max(m(b)).max(m(radius))
        }
        PrimitiveSpec::Plane(PlaneSpec { normal, offset }) => m(normal).max(m(&[*offset])),
        PrimitiveSpec::Rectangle(RectangleSpec {
            center,
            axes,
            half_extents,
        }) => m(center).max(all(axes)).max(m(half_extents)),
        PrimitiveSpec::Disk(DiskSpec {
            center,
            normal,
            radius,
        }) => m(center).max(m(normal)).max(m(&[*radius])),
        PrimitiveSpec::Polygon(PolygonSpec { vertices }) => all(vertices),
        PrimitiveSpec::Box(BoxSpec {
            center,
            half_extents,
            rotation,
        }) => m(center)
            .max(m(half_extents))
            .max(rotation.as_ref().map_or(0.0, |r| m(r))),
        PrimitiveSpec::ConvexHull(ConvexHullSpec { points }) => all(points),
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// One spec of each kind, every number `x`.
    fn every_kind(x: f64) -> Vec<PrimitiveSpec> {
        let v = [x; 3];
        vec![
            PrimitiveSpec::Point(PointSpec { p: v }),
            PrimitiveSpec::Segment(SegmentSpec { a: v, b: v }),
            PrimitiveSpec::Sphere(SphereSpec {
                center: v,
                radius: x,
            }),
            PrimitiveSpec::Capsule(CapsuleSpec {
                a: v,
                b: v,
                radius: x,
            }),
            PrimitiveSpec::TaperedCapsule(TaperedCapsuleSpec {
                a: v,
                b: v,
                radius: [x; 2],
            }),
            PrimitiveSpec::Plane(PlaneSpec {
                normal: v,
                offset: x,
            }),
            PrimitiveSpec::Rectangle(RectangleSpec {
                center: v,
                axes: [v; 2],
                half_extents: [x; 2],
            }),
            PrimitiveSpec::Disk(DiskSpec {
                center: v,
                normal: v,
                radius: x,
            }),
            PrimitiveSpec::Polygon(PolygonSpec {
                vertices: vec![v; 3],
            }),
            PrimitiveSpec::Box(BoxSpec {
                center: v,
                half_extents: v,
                rotation: Some([x; 4]),
            }),
            PrimitiveSpec::ConvexHull(ConvexHullSpec { points: vec![v; 4] }),
        ]
    }

    /// The fast path agrees with the walk over the serialised spec, number
    /// by number: each one in turn out of the domain, the rest in it.
    #[test]
    fn the_fast_path_sees_every_number_the_walk_sees() -> Result<(), serde_json::Error> {
        for (kind, spec) in every_kind(1.0).into_iter().enumerate() {
            let json = serde_json::to_value(&spec)?;
            let count = numbers(&json);
            assert!(count > 0);
            for k in 0..count {
                let mut bad = json.clone();
                set_nth(&mut bad, k, 2.0 * MAX_COORDINATE);
                let bad: PrimitiveSpec = serde_json::from_value(bad)?;
                assert!(largest(&bad) > MAX_COORDINATE, "kind {kind}, number {k}");
                // Refused (a box's half extent may fail its aspect first).
                assert!(check(&bad).is_err(), "kind {kind}, number {k}");
            }
            assert!(largest(&spec) <= MAX_COORDINATE);
        }
        // Non-finite numbers are left to the constructors, as by the walk.
        for spec in every_kind(f64::NAN) {
            assert_eq!(largest(&spec), 0.0);
        }
        Ok(())
    }

    fn numbers(v: &serde_json::Value) -> usize {
        match v {
            serde_json::Value::Number(_) => 1,
            serde_json::Value::Array(a) => a.iter().map(numbers).sum(),
            serde_json::Value::Object(o) => o.values().map(numbers).sum(),
            _ => 0,
        }
    }

    /// Sets the `k`-th number of `v` (in the order `numbers` counts them).
    fn set_nth(v: &mut serde_json::Value, k: usize, x: f64) {
        fn go(v: &mut serde_json::Value, k: &mut usize, x: f64) -> bool {
            match v {
                serde_json::Value::Number(_) if *k == 0 => {
                    *v = serde_json::json!(x);
                    true
                }
                serde_json::Value::Number(_) => {
                    *k -= 1;
                    false
                }
                serde_json::Value::Array(a) => a.iter_mut().any(|e| go(e, k, x)),
                serde_json::Value::Object(o) => o.values_mut().any(|e| go(e, k, x)),
                _ => false,
            }
        }
        assert!(go(v, &mut { k }, x));
    }
}
