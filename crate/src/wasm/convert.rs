//! Conversions between JavaScript values and core types, with validation
//! errors that name the field.

use js_sys::ArrayBuffer;
use serde::Serialize;
use serde::de::DeserializeOwned;
use wasm_bindgen::JsCast;
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

/// [`from_js`] for values that must be plain objects (options, points):
/// serde would also read a struct from a positional array, which from JS is
/// almost always a mistake.
pub fn object_from_js<T: DeserializeOwned>(field: &str, value: JsValue) -> Result<T, JsError> {
    if value.is_object() && !js_sys::Array::is_array(&value) && !ArrayBuffer::is_view(&value) {
        from_js(field, value)
    } else if value.is_undefined() || value.is_null() {
        Err(js_error(&FieldError::new(
            field,
            "missing (got undefined or null)",
        )))
    } else {
        Err(js_error(&FieldError::new(field, "expected an object")))
    }
}

/// Deserialises `value` into `T`; errors inside it read `prefix.path: reason`
/// (just `path: reason` for an empty prefix), errors about the whole value
/// `root: reason`.
///
/// The value goes through [`to_json`] first: serde-wasm-bindgen reads only the
/// keys a struct names, so a misspelt key would pass silently, while
/// `deny_unknown_fields` works on a JSON value.
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
    let json = to_json(&value, 0).map_err(|e| {
        let e = if e.field.is_empty() {
            FieldError::new(root, e.reason)
        } else {
            e.within(prefix)
        };
        js_error(&e)
    })?;
    serde_path_to_error::deserialize(json).map_err(|e| {
        let FieldError {
            field: path,
            reason,
        } = crate::error::from_serde_path(&e.path().to_string(), &e.inner().to_string());
        let reason = if reason.contains(NON_FINITE_TAG) {
            "not a finite number".to_owned()
        } else {
            reason
        };
        let err = if path.is_empty() {
            FieldError::new(root, reason)
        } else if prefix.is_empty() {
            FieldError::new(path, reason)
        } else {
            FieldError::new(path, reason).within(prefix)
        };
        js_error(&err)
    })
}

/// Marks a non-finite number in a converted value (JSON has none); a field
/// that expects a number then fails to parse, and the error is reworded.
const NON_FINITE_TAG: &str = "non-finite number ";

/// Deepest nesting accepted from JS (guards against cyclic objects).
const MAX_DEPTH: usize = 64;

/// Converts a JS value into JSON: objects (own enumerable keys; `undefined`
/// members dropped), arrays, typed arrays, numbers, strings, booleans, null.
fn to_json(value: &JsValue, depth: usize) -> Result<serde_json::Value, FieldError> {
    use serde_json::Value;
    if depth > MAX_DEPTH {
        return Err(FieldError::new("", "nested too deeply (a cyclic object?)"));
    }
    if value.is_null() || value.is_undefined() {
        return Ok(Value::Null);
    }
    if let Some(b) = value.as_bool() {
        return Ok(Value::Bool(b));
    }
    if let Some(x) = value.as_f64() {
        // JS has one number type; integral values become JSON integers so
        // that index fields (`link`, `segment`) accept them.
        const EXACT: f64 = 9_007_199_254_740_992.0; // 2^53
        if x.fract() == 0.0 && x.abs() < EXACT {
            return Ok(Value::Number((x as i64).into()));
        }
        return Ok(serde_json::Number::from_f64(x).map_or_else(
            || Value::String(format!("{NON_FINITE_TAG}{x}")),
            Value::Number,
        ));
    }
    if let Some(s) = value.as_string() {
        return Ok(Value::String(s));
    }
    if let Some(a) = value.dyn_ref::<js_sys::Float64Array>() {
        return Ok(Value::Array(
            a.to_vec()
                .into_iter()
                .map(|x| to_json(&JsValue::from_f64(x), depth + 1))
                .collect::<Result<_, _>>()?,
        ));
    }
    if js_sys::Array::is_array(value) {
        let arr = js_sys::Array::from(value);
        let mut out = Vec::with_capacity(arr.length() as usize);
        for (k, v) in arr.iter().enumerate() {
            out.push(to_json(&v, depth + 1).map_err(|e| e.within(&format!("[{k}]")))?);
        }
        return Ok(Value::Array(out));
    }
    if ArrayBuffer::is_view(value) {
        // Other typed arrays (Float32Array, Int32Array, ...).
        let arr = js_sys::Array::from(value);
        return to_json(&arr.into(), depth);
    }
    if value.is_object() && !value.is_function() {
        let obj: &js_sys::Object = value.unchecked_ref();
        let mut map = serde_json::Map::new();
        for entry in js_sys::Object::entries(obj).iter() {
            let pair = js_sys::Array::from(&entry);
            let key = pair.get(0).as_string().unwrap_or_default();
            let v = pair.get(1);
            if v.is_undefined() {
                continue;
            }
            let converted = to_json(&v, depth + 1).map_err(|e| {
                if e.field.is_empty() {
                    FieldError::new(key.clone(), e.reason)
                } else {
                    e.within(&key)
                }
            })?;
            map.insert(key, converted);
        }
        return Ok(Value::Object(map));
    }
    Err(FieldError::new(
        "",
        "unsupported value (expected JSON-like data)",
    ))
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

/// `x` when finite, else an `Error` naming `field`.
#[cfg_attr(not(feature = "render"), allow(dead_code))]
pub fn finite_arg(field: &str, x: f64) -> Result<f64, JsError> {
    crate::error::finite(field, x).map_err(|e| js_error(&e))
}
