//! JS bindings of the URDF import: `robotFromUrdf(xml, options?)`,
//! `importUrdf(xml, options?)` and `fitUrdf(xml, options)`, with
//! `options = { tip?, base?, srdf?, radii?, meshes? }`.

use std::collections::BTreeMap;

use js_sys::{Reflect, Uint8Array};
use wasm_bindgen::JsCast;
use wasm_bindgen::prelude::*;

use super::boundary::read_urdf_options;
use super::convert::{from_json_at, js_error, to_js};
use crate::error::FieldError;
use crate::fitting::{UrdfFit, fit_urdf};
use crate::parsers::mesh::MAX_MESH_BYTES;
use crate::parsers::urdf::{self, UrdfOptions};

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

fn split_options(options: JsValue) -> Result<Split, JsError> {
    let (json, meshes) = read_urdf_options(&options, MAX_MESH_BYTES)?;
    let parsed: UrdfOptions = if json.is_null() {
        UrdfOptions::default()
    } else {
        from_json_at("options", "options", json)?
    };
    if meshes.is_undefined() || meshes.is_null() {
        return Ok((parsed, None));
    }
    // A plain object of fresh Uint8Arrays made by boundary.js: reading it
    // cannot throw.
    let mut files = BTreeMap::new();
    let keys = Reflect::own_keys(&meshes).unwrap_or_default();
    for key in keys.iter() {
        let (Some(name), Ok(value)) = (key.as_string(), Reflect::get(&meshes, &key)) else {
            continue;
        };
        if let Some(bytes) = value.dyn_ref::<Uint8Array>() {
            files.insert(name, bytes.to_vec());
        }
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
/// and the meshes that could not be read). See `crate::parsers::urdf`,
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

/// The imported spec, its collision bodies and the problems (no fitting),
/// for the viewer's `setMeshesFromUrdf`.
#[cfg(feature = "render")]
pub(super) fn bodies_from_js(
    xml: JsValue,
    options: JsValue,
) -> Result<
    (
        crate::kinematics::RobotSpec,
        Vec<crate::fitting::Body>,
        Vec<String>,
    ),
    JsError,
> {
    let xml = xml_of(xml)?;
    let (options, files) = split_options(options)?;
    crate::fitting::urdf_bodies(&xml, &options, &files.unwrap_or_default())
        .map_err(|e| js_error(&e))
}

/// `fitUrdf`'s work, for the viewer's `setUrdf` too.
pub(super) fn fit_from_js(xml: JsValue, options: JsValue) -> Result<UrdfFit, JsError> {
    let xml = xml_of(xml)?;
    let (options, files) = split_options(options)?;
    fit(&xml, &options, &files.unwrap_or_default())
}

/// `{ robot, report }`: the spec of `robotFromUrdf` and what the import did
/// (`report.joints[]`: radius and its source, defaulted limits;
/// `linksWithoutPrimitive`, `outsideChain`, `startContacts`).
#[wasm_bindgen(js_name = importUrdf)]
pub fn import_urdf(xml: JsValue, options: JsValue) -> Result<JsValue, JsError> {
    let xml = xml_of(xml)?;
    let (options, _) = split_options(options)?;
    let import = crate::world::import_urdf(&xml, &options).map_err(|e| js_error(&e))?;
    to_js(&import)
}
