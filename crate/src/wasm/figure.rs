//! `referencePoint(shape)` and `translateShape(shape, delta)`: the library's
//! one definition of where a figure is and how it moves, for the page's
//! drag, scale and rotate tools. Converts and validates only; the work is in
//! [`crate::scenario::reference_point`] and [`crate::scenario::translated`].

use wasm_bindgen::prelude::*;

use super::convert::{js_error, object_from_js, point3, to_js};
use crate::scenario::{self, ShapeSpec};

/// Reads and validates a figure (a primitive or a human) named `field`.
fn figure(field: &str, value: JsValue) -> Result<ShapeSpec, JsError> {
    let shape: ShapeSpec = object_from_js(field, value)?;
    scenario::primitives(&shape).map_err(|e| js_error(&e.within(field)))?;
    Ok(shape)
}

/// The reference point `[x, y, z]` (m) of a figure: the centre of spheres,
/// boxes, rectangles and disks, the middle of segments and capsules, the
/// point itself, the vertex mean of polygons and hulls, the point of a plane
/// closest to the origin, the floor point of a human. Motions move it and
/// `moveObstacle` places it.
///
/// # Errors
/// A bad figure: `shape.radius: must be > 0`, `shape.type: unknown …`.
#[wasm_bindgen(js_name = referencePoint)]
pub fn reference_point_js(shape: JsValue) -> Result<JsValue, JsError> {
    let shape = figure("shape", shape)?;
    to_js(&scenario::reference_point(&shape).to_array())
}

/// The figure moved by `delta` `[x, y, z]` (m), in the form it was given
/// (a plane keeps its normal and changes its offset).
///
/// # Errors
/// A bad figure or a bad `delta`.
#[wasm_bindgen(js_name = translateShape)]
pub fn translate_shape_js(shape: JsValue, delta: JsValue) -> Result<JsValue, JsError> {
    let shape = figure("shape", shape)?;
    let delta = point3("delta", &delta)?;
    let moved = scenario::translated(&shape, delta);
    scenario::primitives(&moved).map_err(|e| js_error(&e.within("shape")))?;
    to_js(&moved)
}
