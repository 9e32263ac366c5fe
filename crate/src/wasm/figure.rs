//! `referencePoint(shape)`, `translateShape(shape, delta)`, `moveHumanHand` and
//! `importTrack`: the library's
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

/// Most characters of a keypoint track `importTrack` reads (64 MiB).
const MAX_TRACK_CHARS: usize = 64 << 20;

/// Reads a recorded keypoint track (`text`: JSON or CSV in the COCO-17,
/// BODY-25 or Azure Kinect 32 layout, or BVH motion capture) and returns
/// `{ shape, report }`: a `human` shape whose keyframes replay it, and what
/// was repaired (gaps filled, angles clamped). `options`: `{ format?,
/// layout?, height?, smoothing?, maxGap?, scale?, up? }`
/// (docs/scenarios.md). Nothing else changes: give the shape to
/// `setObstacleShape` or `addObstacle` to use it.
///
/// # Errors
/// `layout: unknown layout …`, `frames[3].t: must increase`,
/// `frames[2].keypoints: expected 17 keypoints …`, `line 5: …`,
/// `frames: at most 100000 frames …`, `text: …`; BVH: `Frame Time: must
/// be in (0, 10] s …`, `Frames: declares 120 frames, the file has 57 …`,
/// `ROOT: … is not a hips joint …`, `line 40: expected 57 values …`.
#[wasm_bindgen(js_name = importTrack)]
pub fn import_track_js(text: JsValue, options: JsValue) -> Result<JsValue, JsError> {
    let Some(text) = text.as_string() else {
        return Err(js_error(&crate::FieldError::new(
            "text",
            "expected a string",
        )));
    };
    if text.len() > MAX_TRACK_CHARS {
        return Err(js_error(&crate::FieldError::new(
            "text",
            format!("at most {MAX_TRACK_CHARS} characters (got {})", text.len()),
        )));
    }
    let options: crate::human::track::TrackOptions = if options.is_undefined() || options.is_null()
    {
        crate::human::track::TrackOptions::default()
    } else {
        object_from_js("options", options)?
    };
    let out = crate::human::track::import(&text, &options).map_err(|e| js_error(&e))?;
    #[derive(serde::Serialize)]
    struct Imported {
        shape: ShapeSpec,
        report: crate::human::track::TrackReport,
    }
    to_js(&Imported {
        shape: ShapeSpec::Human(out.shape),
        report: out.report,
    })
}

/// A human `shape` with its `side` (`"left"` or `"right"`) hand moved by
/// `delta` `[x, y, z]` (m) from where it is at rest: only that arm's joint
/// angles change (the other arm, the trunk, the legs and the root stay),
/// and the animation is dropped so the person holds the pose.
///
/// # Errors
/// A bad shape (not a human, `shape.height: must be > 0`, …), `side: …`,
/// `delta: …`.
#[wasm_bindgen(js_name = moveHumanHand)]
pub fn move_human_hand_js(
    shape: JsValue,
    side: JsValue,
    delta: JsValue,
) -> Result<JsValue, JsError> {
    let ShapeSpec::Human(h) = figure("shape", shape)? else {
        return Err(js_error(&crate::FieldError::new(
            "shape",
            "expected a human (type: \"human\")",
        )));
    };
    let Some(side) = side.as_string() else {
        return Err(js_error(&crate::FieldError::new(
            "side",
            "expected \"left\" or \"right\"",
        )));
    };
    let delta = point3("delta", &delta)?;
    let moved = crate::human::library::move_hand(&h, &side, delta).map_err(|e| js_error(&e))?;
    to_js(&ShapeSpec::Human(moved))
}
