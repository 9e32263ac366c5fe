//! The typed boundary: every argument from JavaScript is checked for its JS
//! type here before anything else touches it.
//!
//! Objects are read by `boundary.js` (inside a JS `try`, so a throwing getter
//! or Proxy becomes one clean `Error` instead of unwinding through wasm) into
//! JSON text that Rust parses. Scalars are checked with `typeof`-like
//! intrinsics, which cannot throw: no silent coercion of `'0.001'`, `[1]` or
//! `true`, and no wrapping counts.

use wasm_bindgen::prelude::*;

use super::convert::js_error;
use crate::error::FieldError;

#[wasm_bindgen(module = "/src/wasm/boundary.js")]
extern "C" {
    #[wasm_bindgen(catch, js_name = readJson)]
    fn read_json_js(value: &JsValue, field: &str) -> Result<String, JsValue>;

    #[wasm_bindgen(catch, js_name = readUrdfOptions)]
    fn read_urdf_options_js(options: &JsValue, max_bytes: f64) -> Result<JsValue, JsValue>;

    #[wasm_bindgen(js_name = guardClass)]
    fn guard_class_js(instance: &JsValue, name: &str, arg_names: &JsValue);
}

/// The JSON text of `value`, read once; an `Error` naming `field` when it
/// cannot be read (a throwing getter or Proxy trap, a cycle, a function, a
/// symbol, more than 100000 elements in an array).
pub fn read_json(field: &str, value: &JsValue) -> Result<serde_json::Value, JsError> {
    let text = read_json_js(value, field).map_err(|e| {
        let msg = e.dyn_ref::<js_sys::Error>().map_or_else(
            || format!("{field}: could not be read"),
            |e| String::from(e.message()),
        );
        JsError::new(&msg)
    })?;
    serde_json::from_str(&text)
        .map_err(|e| js_error(&FieldError::new(field, format!("could not be read ({e})"))))
}

/// The options of the URDF functions read once by `boundary.js`: the
/// options without `meshes` as JSON, and the mesh files as a fresh plain
/// object of fresh `Uint8Array`s (`undefined` when absent).
pub fn read_urdf_options(
    options: &JsValue,
    max_bytes: usize,
) -> Result<(serde_json::Value, JsValue), JsError> {
    let read = read_urdf_options_js(options, max_bytes as f64).map_err(|e| {
        let msg = e.dyn_ref::<js_sys::Error>().map_or_else(
            || "options: could not be read".to_owned(),
            |e| String::from(e.message()),
        );
        JsError::new(&msg)
    })?;
    let get =
        |k: &str| js_sys::Reflect::get(&read, &JsValue::from_str(k)).unwrap_or(JsValue::UNDEFINED);
    let text = get("json").as_string().unwrap_or_else(|| "null".to_owned());
    let json = serde_json::from_str(&text).map_err(|e| {
        js_error(&FieldError::new(
            "options",
            format!("could not be read ({e})"),
        ))
    })?;
    Ok((json, get("meshes")))
}

/// Guards the methods of the class of `instance` (see `guardClass` in
/// `boundary.js`); `arg_names` maps a method name to its argument names.
pub fn guard_class(instance: &JsValue, name: &str, arg_names: &[(&str, &[&str])]) {
    let map = js_sys::Object::new();
    for (method, args) in arg_names {
        let list = js_sys::Array::new();
        for a in *args {
            list.push(&JsValue::from_str(a));
        }
        // Setting a property on a fresh plain object cannot fail.
        let _ = js_sys::Reflect::set(&map, &JsValue::from_str(method), &list);
    }
    guard_class_js(instance, name, &map);
}

/// A string argument.
pub fn string_arg(field: &str, value: &JsValue) -> Result<String, JsError> {
    value.as_string().ok_or_else(|| {
        js_error(&FieldError::new(
            field,
            format!("expected a string, got {}", type_name(value)),
        ))
    })
}

/// A finite number argument (a JS `number`; strings and arrays are refused).
pub fn number_arg(field: &str, value: &JsValue) -> Result<f64, JsError> {
    match value.as_f64() {
        Some(x) if x.is_finite() => Ok(x),
        Some(_) => Err(js_error(&FieldError::new(field, "not a finite number"))),
        None => Err(js_error(&FieldError::new(
            field,
            format!("expected a number, got {}", type_name(value)),
        ))),
    }
}

/// An integer count in `0..=max`; `default` when `undefined` (or `null`).
pub fn count_arg(
    field: &str,
    value: &JsValue,
    default: Option<u32>,
    max: u32,
) -> Result<u32, JsError> {
    if (value.is_undefined() || value.is_null())
        && let Some(d) = default
    {
        return Ok(d);
    }
    let x = number_arg(field, value)?;
    if x.fract() != 0.0 {
        return Err(js_error(&FieldError::new(field, "expected an integer")));
    }
    if x < 0.0 {
        return Err(js_error(&FieldError::new(field, "must be >= 0")));
    }
    if x > f64::from(max) {
        return Err(js_error(&FieldError::new(field, format!("at most {max}"))));
    }
    // In 0..=max, integral: exact.
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    Ok(x as u32)
}

/// How a JS value reads in a message (`a string`, `an array`, …).
pub fn type_name(value: &JsValue) -> &'static str {
    if value.is_undefined() {
        "undefined"
    } else if value.is_null() {
        "null"
    } else if value.as_bool().is_some() {
        "a boolean"
    } else if value.as_f64().is_some() {
        "a number"
    } else if value.is_string() {
        "a string"
    } else if value.is_symbol() {
        "a symbol"
    } else if value.is_bigint() {
        "a bigint"
    } else if value.is_function() {
        "a function"
    } else {
        "an object"
    }
}

/// Argument specs of the `Viewer` methods (see `argument` in `boundary.js`):
/// numbers are checked for their JS type before wasm coerces them (`'1'`,
/// `true` and `undefined` would become 1, 1 and NaN), objects are read once.
#[cfg(feature = "render")]
const VIEWER_ARGS: &[(&str, &[&str])] = &[
    ("setRobot", &["robot"]),
    ("drawState", &["state"]),
    ("drawWorld", &["world:World"]),
    ("setSelected", &["id"]),
    ("projectPoint", &["point"]),
    ("setJoints", &["q"]),
    ("setDisplay", &["display"]),
    ("setView", &["name"]),
    ("setCamera", &["camera"]),
    ("orbit", &["dx:number", "dy:number"]),
    ("pan", &["dx:number", "dy:number"]),
    ("zoom", &["factor:number"]),
    ("fit", &["fill:number?", "top:number?"]),
    ("resize", &["width:number", "height:number"]),
    ("rayAt", &["x:number", "y:number"]),
    // Read by `readUrdfOptions` (mesh bytes are not JSON).
    ("setUrdf", &["xml", "options:urdf"]),
    ("setMeshesFromUrdf", &["xml", "options:urdf"]),
];

/// `viewer` handed to JavaScript with its class guarded like `World`'s:
/// typed arguments, `Error: this Viewer has been freed` after `free()`, a
/// second `free()` a no-op.
#[cfg(feature = "render")]
pub fn guarded_viewer(viewer: super::viewer::Viewer) -> JsValue {
    let instance = JsValue::from(viewer);
    guard_class(&instance, "Viewer", VIEWER_ARGS);
    instance
}
