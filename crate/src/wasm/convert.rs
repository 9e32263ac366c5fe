//! Conversions between JavaScript values and core types, with validation
//! errors that name the field.

use serde::Serialize;
use serde::de::DeserializeOwned;
use wasm_bindgen::prelude::*;

use super::boundary::{read_json, type_name};
pub use super::messages::plain_reason;
use crate::error::FieldError;
use crate::kinematics::{Robot, RobotSpec, presets};

/// The core's bounds on every number and tagged object
/// ([`crate::scenario::bounds`]), applied to what a caller passed before it
/// is read into a type, so that the first refusal is the one a Rust caller
/// reading the same JSON gets.
pub fn check_magnitudes(field: &str, json: &serde_json::Value) -> Result<(), JsError> {
    crate::scenario::bounds::check_json(field, json).map_err(|e| js_error(&e))
}

/// A JS `Error` from a core validation error.
pub fn js_error(e: &FieldError) -> JsError {
    JsError::new(&e.to_string())
}

/// Deserialises `value` into `T`; errors read `field.path: reason`.
#[cfg_attr(not(feature = "render"), allow(dead_code))]
pub fn from_js<T: DeserializeOwned>(field: &str, value: JsValue) -> Result<T, JsError> {
    from_js_at(field, field, value)
}

/// [`from_js`] for values that must be plain objects (options, points):
/// serde would also read a struct from a positional array, which from JS is
/// almost always a mistake.
pub fn object_from_js<T: DeserializeOwned>(field: &str, value: JsValue) -> Result<T, JsError> {
    if value.is_undefined() || value.is_null() {
        return Err(js_error(&FieldError::new(
            field,
            "missing (got undefined or null)",
        )));
    }
    if !value.is_object() {
        return Err(js_error(&FieldError::new(
            field,
            format!("expected an object, got {}", type_name(&value)),
        )));
    }
    let json = read_json(field, &value)?;
    if !json.is_object() {
        return Err(js_error(&FieldError::new(field, "expected an object")));
    }
    check_magnitudes(field, &json)?;
    from_json_at(field, field, json)
}

/// Deserialises `value` into `T`; errors inside it read `prefix.path: reason`
/// (just `path: reason` for an empty prefix), errors about the whole value
/// `root: reason`.
///
/// The value is read once into JSON (see [`read_json`]): serde-wasm-bindgen
/// reads only the keys a struct names, so a misspelt key would pass silently,
/// while `deny_unknown_fields` works on a JSON value; and a throwing getter
/// must not unwind through wasm.
#[cfg_attr(not(feature = "render"), allow(dead_code))]
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
    let json = read_json(if prefix.is_empty() { root } else { prefix }, &value)?;
    check_magnitudes(prefix, &json)?;
    from_json_at(prefix, root, json)
}

/// [`from_js_at`] for a value already read (see [`read_json`]).
pub fn from_json_at<T: DeserializeOwned>(
    prefix: &str,
    root: &str,
    json: serde_json::Value,
) -> Result<T, JsError> {
    serde_path_to_error::deserialize(json).map_err(|e| {
        let FieldError {
            field: path,
            reason,
        } = crate::error::from_serde_path(&e.path().to_string(), &e.inner().to_string());
        let reason = if reason.contains(NON_FINITE_TAG) {
            "not a finite number".to_owned()
        } else {
            plain_reason(&reason)
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

/// Refuses an array given where `value` (read from `input`) holds an
/// object ([`crate::scenario::bounds::refuse_positional`], the core's rule).
///
/// # Errors
/// `prefix.path: expected an object { a, b }, got an array`.
pub fn refuse_positional<T: Serialize>(
    prefix: &str,
    input: &serde_json::Value,
    value: &T,
) -> Result<(), JsError> {
    crate::scenario::bounds::refuse_positional(prefix, input, value).map_err(|e| js_error(&e))
}

/// Marks a non-finite number in a converted value (JSON has none; see
/// `boundary.js`); a field that expects a number then fails to parse, and the
/// error is reworded.
const NON_FINITE_TAG: &str = "non-finite number ";

/// Serialises `value` as plain JSON-compatible JS objects.
pub fn to_js<T: Serialize>(value: &T) -> Result<JsValue, JsError> {
    value
        .serialize(&serde_wasm_bindgen::Serializer::json_compatible())
        .map_err(|e| JsError::new(&format!("internal: could not convert the result: {e}")))
}

/// A vector of finite numbers from a JS `Array` of numbers or a typed array.
pub fn f64_vec(field: &str, value: &JsValue) -> Result<Vec<f64>, JsError> {
    numbers(field, read_vector(field, value)?)
}

/// `value` read once as JSON, refused unless it is an object (arrays and
/// typed arrays are objects; their JSON is an array).
fn read_vector(field: &str, value: &JsValue) -> Result<serde_json::Value, JsError> {
    if !value.is_object() {
        return Err(expected_numbers(field));
    }
    read_json(field, value)
}

fn expected_numbers(field: &str) -> JsError {
    js_error(&FieldError::new(
        field,
        "expected an array or a Float64Array of numbers",
    ))
}

/// The finite numbers of a JSON array.
fn numbers(field: &str, json: serde_json::Value) -> Result<Vec<f64>, JsError> {
    let serde_json::Value::Array(items) = json else {
        return Err(expected_numbers(field));
    };
    items
        .iter()
        .enumerate()
        .map(|(k, v)| match v {
            serde_json::Value::Number(n) => n.as_f64().ok_or_else(|| expected_numbers(field)),
            serde_json::Value::String(s) if s.starts_with(NON_FINITE_TAG) => Err(js_error(
                &FieldError::new(format!("{field}[{k}]"), "not a finite number"),
            )),
            _ => Err(js_error(&FieldError::new(
                format!("{field}[{k}]"),
                "not a number",
            ))),
        })
        .collect()
}

/// Every element within ±1e6 (joint values, rates).
fn bounded_joints(field: &str, v: Vec<f64>) -> Result<Vec<f64>, JsError> {
    for (k, x) in v.iter().enumerate() {
        crate::error::bounded(
            &format!("{field}[{k}]"),
            *x,
            crate::kinematics::MAX_MAGNITUDE,
        )
        .map_err(|e| js_error(&e))?;
    }
    Ok(v)
}

/// A robot from a JS value (a robot spec object, `{ preset: name }`, or a
/// preset name) and the spec's `jointNames` (for joint vectors given by
/// name).
pub fn robot_named(value: JsValue) -> Result<(Robot, Option<Vec<String>>), JsError> {
    let spec: RobotSpec = if let Some(name) = value.as_string() {
        presets::preset(&name).map_err(|e| js_error(&e.within("robot")))?
    } else if value.is_object() {
        let json = read_json("robot", &value)?;
        match json.as_object() {
            Some(map) if map.contains_key("preset") => {
                if let Some(key) = map.keys().find(|k| *k != "preset") {
                    return Err(js_error(&FieldError::new(
                        format!("robot.{key}"),
                        "unknown field (with `preset`, nothing else is accepted)",
                    )));
                }
                let name = map.get("preset").and_then(|v| v.as_str()).ok_or_else(|| {
                    js_error(&FieldError::new("robot.preset", "expected a string"))
                })?;
                presets::preset(name).map_err(|e| js_error(&e.within("robot")))?
            }
            Some(map) => {
                joints_are_objects(map)?;
                check_magnitudes("", &json)?;
                let spec: RobotSpec = from_json_at("", "robot", json.clone())?;
                refuse_positional("robot", &json, &spec)?;
                spec
            }
            None => {
                return Err(js_error(&FieldError::new(
                    "robot",
                    "expected a robot spec object, { preset: name } or a preset name",
                )));
            }
        }
    } else {
        return Err(js_error(&FieldError::new(
            "robot",
            format!(
                "expected a robot spec object, {{ preset: name }} or a preset name, got {}",
                type_name(&value)
            ),
        )));
    };
    let robot = Robot::from_spec(&spec).map_err(|e| js_error(&e))?;
    Ok((robot, spec.joint_names))
}

/// Joint values given by name, `{ name: value, … }`, in the order of
/// `names` (a robot's `jointNames`); every joint must be named once.
///
/// # Errors
/// `field: joint values by name need a robot with jointNames`,
/// `field.x: no joint named "x" (joints: …)`, `field: missing joint "y"`,
/// `field.x: not a finite number`.
pub fn named_joints(
    field: &str,
    map: &serde_json::Map<String, serde_json::Value>,
    names: Option<&[String]>,
) -> Result<Vec<f64>, FieldError> {
    let Some(names) = names else {
        return Err(FieldError::new(
            field,
            "joint values by name need a robot with jointNames (a URDF import, or a spec that names its joints); give an array otherwise",
        ));
    };
    for key in map.keys() {
        if !names.iter().any(|n| n == key) {
            return Err(FieldError::new(
                format!("{field}.{key}"),
                format!("no joint named \"{key}\" (joints: {})", names.join(", ")),
            ));
        }
    }
    names
        .iter()
        .map(|n| {
            let v = map
                .get(n)
                .ok_or_else(|| FieldError::new(field, format!("missing joint \"{n}\"")))?;
            let x = v
                .as_f64()
                .ok_or_else(|| FieldError::new(format!("{field}.{n}"), "not a finite number"))?;
            crate::error::bounded(&format!("{field}.{n}"), x, crate::kinematics::MAX_MAGNITUDE)?;
            Ok(x)
        })
        .collect()
}

/// A joint vector as an array or a `Float64Array` of numbers within ±1e6, or by
/// name (`{ panda_joint1: 0.1, … }`, [`named_joints`]).
///
/// # Errors
/// As those two.
pub fn joint_vec_named(
    field: &str,
    value: &JsValue,
    names: Option<&[String]>,
) -> Result<Vec<f64>, JsError> {
    // Read once: the JSON says whether it is a list or names.
    match read_vector(field, value)? {
        serde_json::Value::Object(map) => {
            named_joints(field, &map, names).map_err(|e| js_error(&e))
        }
        json => bounded_joints(field, numbers(field, json)?),
    }
}

/// Refuses joints given as positional arrays (`[a, alpha, d, theta]`), which
/// serde would read into a struct in field order.
fn joints_are_objects(map: &serde_json::Map<String, serde_json::Value>) -> Result<(), JsError> {
    let mut lists: Vec<(String, &serde_json::Value)> = Vec::new();
    if let Some(j) = map.get("joints") {
        lists.push(("joints".to_owned(), j));
    }
    if let Some(serde_json::Value::Array(branches)) = map.get("branches") {
        for (b, branch) in branches.iter().enumerate() {
            if let Some(j) = branch.get("joints") {
                lists.push((format!("branches[{b}].joints"), j));
            }
        }
    }
    for (path, list) in lists {
        if let serde_json::Value::Array(items) = list {
            for (k, item) in items.iter().enumerate() {
                if !item.is_object() {
                    return Err(js_error(&FieldError::new(
                        format!("{path}[{k}]"),
                        "expected a joint object { a, alpha, d, theta, … }",
                    )));
                }
            }
        }
    }
    Ok(())
}

/// `x` when finite, else an `Error` naming `field`.
#[cfg_attr(not(feature = "render"), allow(dead_code))]
pub fn finite_arg(field: &str, x: f64) -> Result<f64, JsError> {
    crate::error::finite(field, x).map_err(|e| js_error(&e))
}

/// A point `[x, y, z]` (m) within the coordinate domain.
pub fn point3(field: &str, value: &JsValue) -> Result<glam::DVec3, JsError> {
    let v = f64_vec(field, value)?;
    if v.len() != 3 {
        return Err(js_error(&FieldError::new(
            field,
            format!("expected [x, y, z], got {} numbers", v.len()),
        )));
    }
    for (k, c) in v.iter().enumerate() {
        crate::error::bounded(
            &format!("{field}[{k}]"),
            *c,
            crate::distance::domain::MAX_COORDINATE,
        )
        .map_err(|e| js_error(&e))?;
    }
    Ok(glam::DVec3::new(v[0], v[1], v[2]))
}
