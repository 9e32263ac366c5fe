//! JS binding of the URDF import: `robotFromUrdf(xml, { tip?, base? })`.

use wasm_bindgen::prelude::*;

use super::convert::{js_error, object_from_js, to_js};
use crate::error::FieldError;
use crate::kinematics::urdf::{self, UrdfOptions};

/// A robot spec in standard DH, with `jointNames` (the order of `q`), from a
/// URDF document (a string); `options = { tip?, base? }` name the links the
/// chain ends and starts at. See `crate::kinematics::urdf`.
#[wasm_bindgen(js_name = robotFromUrdf)]
pub fn robot_from_urdf(xml: JsValue, options: JsValue) -> Result<JsValue, JsError> {
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
    let spec = urdf::robot_from_urdf(&xml, &options).map_err(|e| js_error(&e))?;
    to_js(&spec)
}
