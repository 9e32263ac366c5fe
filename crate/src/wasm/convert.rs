//! Conversions between JavaScript values and core types, with validation
//! errors that name the field.

use serde::Serialize;
use serde::de::DeserializeOwned;
use wasm_bindgen::prelude::*;

use crate::error::FieldError;
use crate::kinematics::{Robot, RobotSpec, presets};

/// A JS `Error` from a core validation error.
pub fn js_error(e: &FieldError) -> JsError {
    JsError::new(&e.to_string())
}

/// Deserialises `value` into `T`; errors read `field.path: reason`.
pub fn from_js<T: DeserializeOwned>(field: &str, value: JsValue) -> Result<T, JsError> {
    from_js_at(field, field, value)
}

/// Deserialises `value` into `T`; errors inside it read `prefix.path: reason`
/// (just `path: reason` for an empty prefix), errors about the whole value
/// `root: reason`.
pub fn from_js_at<T: DeserializeOwned>(
    prefix: &str,
    root: &str,
    value: JsValue,
) -> Result<T, JsError> {
    if value.is_undefined() || value.is_null() {
        return Err(js_error(&FieldError::new(
            root,
            "missing (got undefined or null)",
        )));
    }
    let de = serde_wasm_bindgen::Deserializer::from(value);
    serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner().to_string();
        // serde-wasm-bindgen errors are JS errors whose text starts "Error: ".
        let inner = inner.strip_prefix("Error: ").unwrap_or(&inner).to_owned();
        let err = if path == "." || path.is_empty() {
            FieldError::new(root, inner)
        } else {
            FieldError::new(path, inner).within(prefix)
        };
        js_error(&err)
    })
}

/// Serialises `value` as plain JSON-compatible JS objects.
pub fn to_js<T: Serialize>(value: &T) -> Result<JsValue, JsError> {
    value
        .serialize(&serde_wasm_bindgen::Serializer::json_compatible())
        .map_err(|e| JsError::new(&format!("internal: could not convert the result: {e}")))
}

/// A vector of numbers from a JS `Array` of numbers or a `Float64Array`.
pub fn f64_vec(field: &str, value: &JsValue) -> Result<Vec<f64>, JsError> {
    if let Some(arr) = value.dyn_ref::<js_sys::Float64Array>() {
        return Ok(arr.to_vec());
    }
    if js_sys::Array::is_array(value) {
        let arr = js_sys::Array::from(value);
        let mut out = Vec::with_capacity(arr.length() as usize);
        for (k, v) in arr.iter().enumerate() {
            match v.as_f64() {
                Some(x) => out.push(x),
                None => {
                    return Err(js_error(&FieldError::new(
                        format!("{field}[{k}]"),
                        "not a number",
                    )));
                }
            }
        }
        return Ok(out);
    }
    Err(js_error(&FieldError::new(
        field,
        "expected an array or a Float64Array of numbers",
    )))
}

/// A robot from a JS value: a robot spec object, `{ preset: name }`, or a
/// preset name.
pub fn robot(value: JsValue) -> Result<Robot, JsError> {
    let spec: RobotSpec = if let Some(name) = value.as_string() {
        presets::preset(&name).map_err(|e| js_error(&e.within("robot")))?
    } else if value.is_object()
        && js_sys::Reflect::has(&value, &JsValue::from_str("preset")).unwrap_or(false)
    {
        let name = js_sys::Reflect::get(&value, &JsValue::from_str("preset"))
            .ok()
            .and_then(|v| v.as_string())
            .ok_or_else(|| js_error(&FieldError::new("robot.preset", "expected a string")))?;
        presets::preset(&name).map_err(|e| js_error(&e.within("robot")))?
    } else {
        from_js_at("", "robot", value)?
    };
    Robot::from_spec(&spec).map_err(|e| js_error(&e))
}
