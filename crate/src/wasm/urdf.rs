//! JS bindings of the URDF import: `robotFromUrdf(xml, { tip?, base?,
//! meshes? })` and `fitUrdf(xml, { tip?, base?, meshes })`.

use std::collections::BTreeMap;

use js_sys::{Object, Reflect, Uint8Array};
use wasm_bindgen::JsCast;
use wasm_bindgen::prelude::*;

use super::convert::{js_error, object_from_js, to_js};
use crate::error::FieldError;
use crate::fitting::{UrdfFit, fit_urdf};
use crate::kinematics::urdf::{self, UrdfOptions};
use crate::mesh::MAX_MESH_BYTES;

fn xml_of(xml: JsValue) -> Result<String, JsError> {
    xml.as_string().ok_or_else(|| {
        js_error(&FieldError::new(
            "xml",
            "expected the URDF document as a string",
        ))
    })
}

/// The options without `meshes`, and the mesh files (`None` when absent).
type Split = (UrdfOptions, Option<BTreeMap<String, Vec<u8>>>);

fn unreadable(field: &str) -> JsError {
    js_error(&FieldError::new(
        field,
        "could not be read (a throwing getter or a revoked proxy)",
    ))
}

/// `(key, value)` of every own string-keyed property of `object`.
fn entries(field: &str, object: &JsValue) -> Result<Vec<(String, JsValue)>, JsError> {
    let keys = Reflect::own_keys(object).map_err(|_| unreadable(field))?;
    let mut out = Vec::new();
    for key in keys.iter() {
        let Some(name) = key.as_string() else {
            continue;
        };
        let value =
            Reflect::get(object, &key).map_err(|_| unreadable(&format!("{field}.{name}")))?;
        out.push((name, value));
    }
    Ok(out)
}

fn split_options(options: JsValue) -> Result<Split, JsError> {
    if options.is_undefined() || options.is_null() {
        return Ok((UrdfOptions::default(), None));
    }
    if !options.is_object() {
        return Err(js_error(&FieldError::new("options", "expected an object")));
    }
    let rest = Object::new();
    let mut meshes = JsValue::UNDEFINED;
    for (name, value) in entries("options", &options)? {
        if name == "meshes" {
            meshes = value;
        } else {
            Reflect::set(&rest, &JsValue::from_str(&name), &value)
                .map_err(|_| unreadable("options"))?;
        }
    }
    let parsed: UrdfOptions = object_from_js("options", rest.into())?;
    if meshes.is_undefined() || meshes.is_null() {
        return Ok((parsed, None));
    }
    if !meshes.is_object() || js_sys::Array::is_array(&meshes) {
        return Err(js_error(&FieldError::new(
            "options.meshes",
            "expected an object mapping paths to Uint8Array or ArrayBuffer",
        )));
    }
    let mut files = BTreeMap::new();
    for (name, value) in entries("options.meshes", &meshes)? {
        let bytes = if let Some(a) = value.dyn_ref::<Uint8Array>() {
            a.clone()
        } else if value.is_instance_of::<js_sys::ArrayBuffer>() {
            Uint8Array::new(&value)
        } else {
            return Err(js_error(&FieldError::new(
                "options.meshes",
                format!("\"{name}\" is not a Uint8Array or an ArrayBuffer"),
            )));
        };
        if bytes.length() as usize > MAX_MESH_BYTES {
            return Err(js_error(&FieldError::new(
                "options.meshes",
                format!(
                    "\"{name}\" has {} bytes, more than the {MAX_MESH_BYTES} a mesh may have",
                    bytes.length()
                ),
            )));
        }
        files.insert(name, bytes.to_vec());
    }
    Ok((parsed, Some(files)))
}

fn fit(
    xml: &str,
    options: &UrdfOptions,
    files: &BTreeMap<String, Vec<u8>>,
) -> Result<UrdfFit, JsError> {
    fit_urdf(xml, options, files).map_err(|e| js_error(&e))
}

/// A robot spec in standard DH, with `jointNames` (the order of `q`), from a
/// URDF document (a string); `options = { tip?, base?, meshes? }`: `tip` and
/// `base` name the links the chain ends and starts at; `meshes` maps file
/// paths to their bytes (`Uint8Array` or `ArrayBuffer`), and when given the
/// radii are fitted to the collision meshes (see `fitUrdf` for the report
/// and the meshes that could not be read). See `crate::kinematics::urdf`,
/// `crate::fitting`.
#[wasm_bindgen(js_name = robotFromUrdf)]
pub fn robot_from_urdf(xml: JsValue, options: JsValue) -> Result<JsValue, JsError> {
    let xml = xml_of(xml)?;
    let (options, files) = split_options(options)?;
    match files {
        Some(files) => to_js(&fit(&xml, &options, &files)?.robot),
        None => to_js(&urdf::robot_from_urdf(&xml, &options).map_err(|e| js_error(&e))?),
    }
}

/// `fitUrdf(xml, { tip?, base?, meshes })` → `{ robot, before, after,
/// problems }`: the spec with radii fitted to the collision meshes, the
/// coverage of the meshes by the imported radii (`before`) and by the
/// fitted ones (`after`): `{ bodies: [{ name, link, vertices,
/// vertexCoverage, surfaceCoverage, worstOutside, meshVolume,
/// volumesVolume, excess }], robot: {…}, surfaceTolerance }` (both `null`
/// without a readable mesh), and one message per mesh that could not be
/// found or read (the robot loads with the others).
#[wasm_bindgen(js_name = fitUrdf)]
pub fn fit_urdf_js(xml: JsValue, options: JsValue) -> Result<JsValue, JsError> {
    to_js(&fit_from_js(xml, options)?)
}

/// `fitUrdf`'s work, for the viewer's `setUrdf` too.
pub(super) fn fit_from_js(xml: JsValue, options: JsValue) -> Result<UrdfFit, JsError> {
    let xml = xml_of(xml)?;
    let (options, files) = split_options(options)?;
    fit(&xml, &options, &files.unwrap_or_default())
}
