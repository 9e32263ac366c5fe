//! JS binding of the URDF import: `robotFromUrdf(xml, options?)` and
//! `importUrdf(xml, options?)`, with `options = { tip?, base?, radii? }`.

use wasm_bindgen::prelude::*;

use super::convert::{js_error, object_from_js, to_js};
use crate::error::FieldError;
use crate::kinematics::urdf::{self, UrdfOptions};

fn read_args(xml: JsValue, options: JsValue) -> Result<(String, UrdfOptions), JsError> {
    let xml = xml.as_string().ok_or_else(|| {
        js_error(&FieldError::new(
            "xml",
            "expected the URDF document as a string",
        ))
    })?;
    let options: UrdfOptions = if options.is_undefined() || options.is_null() {
        UrdfOptions::default()
    } else {
        object_from_js("options", options)?
    };
    Ok((xml, options))
}

/// A robot spec in standard DH, with `jointNames` (the order of `q`), from a
/// URDF document (a string); `options = { tip?, base?, radii? }` name the
/// links the chain ends and starts at, and give radii per link name. Every
/// motion limit and radius the spec uses is in it. See
/// `crate::kinematics::urdf`.
#[wasm_bindgen(js_name = robotFromUrdf)]
pub fn robot_from_urdf(xml: JsValue, options: JsValue) -> Result<JsValue, JsError> {
    let (xml, options) = read_args(xml, options)?;
    let spec = urdf::robot_from_urdf(&xml, &options).map_err(|e| js_error(&e))?;
    to_js(&spec)
}

/// `{ robot, report }`: the spec of `robotFromUrdf` and what the import did
/// (`report.joints[]`: radius and its source, defaulted limits;
/// `linksWithoutPrimitive`, `outsideChain`, `startContacts`).
#[wasm_bindgen(js_name = importUrdf)]
pub fn import_urdf(xml: JsValue, options: JsValue) -> Result<JsValue, JsError> {
    let (xml, options) = read_args(xml, options)?;
    let import = crate::world::import_urdf(&xml, &options).map_err(|e| js_error(&e))?;
    to_js(&import)
}
