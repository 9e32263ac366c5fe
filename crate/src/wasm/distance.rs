//! `distance(a, b)`: the signed distance between two primitives described as
//! plain objects. Converts and validates only; the work is in
//! [`crate::distance`].

use serde::Serialize;
use serde::de::DeserializeOwned;
use wasm_bindgen::prelude::*;

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

/// Deserialises the fields of one figure, reporting the path of a field of
/// the wrong type.
fn fields<T: DeserializeOwned>(name: &str, value: JsValue) -> Result<T, JsError> {
    serde_path_to_error::deserialize(serde_wasm_bindgen::Deserializer::from(value)).map_err(|e| {
        let mut path = e.path().to_string();
        if path == "." {
            path.clear();
        }
        let raw = e.into_inner().to_string();
        // serde-wasm-bindgen renders its messages as JS errors ("Error: …");
        // other JS exceptions mean a value of the wrong kind.
        let mut reason = match raw.strip_prefix("Error: ") {
            Some(r) => r.to_owned(),
            None if raw.contains("Error") => "has the wrong type".to_owned(),
            None => raw,
        };
        if let Some(rest) = reason.strip_prefix("missing field `") {
            let missing = rest.trim_end_matches('`');
            path = if path.is_empty() { missing.to_owned() } else { format!("{path}.{missing}") };
            reason = "missing".to_owned();
        }
        let field = if path.is_empty() {
            name.to_owned()
        } else if path.starts_with('[') {
            format!("{name}{path}")
        } else {
            format!("{name}.{path}")
        };
        JsError::new(&format!("{field}: {reason}"))
    })
}

/// Reads and validates the primitive described by `value`.
pub(crate) fn primitive(name: &str, value: JsValue) -> Result<Primitive, JsError> {
    if !value.is_object() {
        return Err(JsError::new(&format!("{name}: must be an object with a \"type\"")));
    }
    let kind = js_sys::Reflect::get(&value, &JsValue::from_str("type"))
        .ok()
        .and_then(|k| k.as_string())
        .ok_or_else(|| JsError::new(&format!("{name}.type: must be a string")))?;
    PrimitiveSpec::check_kind(&kind).map_err(|e| field_error(e.within(name)))?;
    let spec = match kind.as_str() {
        "point" => PrimitiveSpec::Point(fields(name, value)?),
        "segment" => PrimitiveSpec::Segment(fields(name, value)?),
        "sphere" => PrimitiveSpec::Sphere(fields(name, value)?),
        "capsule" => PrimitiveSpec::Capsule(fields(name, value)?),
        "taperedCapsule" => PrimitiveSpec::TaperedCapsule(fields(name, value)?),
        "plane" => PrimitiveSpec::Plane(fields(name, value)?),
        "rectangle" => PrimitiveSpec::Rectangle(fields(name, value)?),
        "disk" => PrimitiveSpec::Disk(fields(name, value)?),
        "polygon" => PrimitiveSpec::Polygon(fields(name, value)?),
        "box" => PrimitiveSpec::Box(fields(name, value)?),
        _ => PrimitiveSpec::ConvexHull(fields(name, value)?),
    };
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
    out.serialize(&serde_wasm_bindgen::Serializer::json_compatible())
        .map_err(|e| JsError::new(&e.to_string()))
}
