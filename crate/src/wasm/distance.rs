//! `distance(a, b)`: the signed distance between two primitives described as
//! plain objects. Converts and validates only; the work is in
//! [`crate::distance`].

use serde::Serialize;
use wasm_bindgen::prelude::*;

use super::convert::{object_from_js, to_js};
use crate::distance::{Primitive, PrimitiveSpec, distance};
use crate::error::FieldError;

/// The result as JavaScript sees it.
#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct DistanceResult {
    distance: f64,
    point_a: [f64; 3],
    point_b: [f64; 3],
    normal: [f64; 3],
    unique: bool,
}

fn field_error(e: FieldError) -> JsError {
    JsError::new(&e.to_string())
}

/// Reads and validates the primitive described by `value`.
pub(crate) fn primitive(name: &str, value: JsValue) -> Result<Primitive, JsError> {
    let spec: PrimitiveSpec = object_from_js(name, value)?;
    Primitive::from_spec(&spec).map_err(|e| field_error(e.within(name)))
}

/// The signed distance between two primitives:
/// `{ distance, pointA, pointB, normal, unique }`.
///
/// `distance` is negative by the penetration depth when a solid overlaps the
/// other figure and 0 when figures touch; `pointB − pointA = distance ×
/// normal`; `unique` is `false` when equally close witnesses form a family
/// (then the witnesses are its middle).
///
/// # Errors
/// A JS `Error` naming the field and the reason, e.g.
/// `b.radius: must be > 0` or `a.type: unknown primitive "cone"`.
#[wasm_bindgen(js_name = distance)]
pub fn distance_js(a: JsValue, b: JsValue) -> Result<JsValue, JsError> {
    let pa = primitive("a", a)?;
    let pb = primitive("b", b)?;
    let d = distance(&pa, &pb).map_err(|e| JsError::new(&e.to_string()))?;
    let out = DistanceResult {
        distance: d.distance,
        point_a: d.point_a.to_array(),
        point_b: d.point_b.to_array(),
        normal: d.normal.to_array(),
        unique: d.unique,
    };
    to_js(&out)
}
