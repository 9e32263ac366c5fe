//! The `#[wasm_bindgen]` layer: converts, no logic and no rules of its own.
//!
//! Every export returns `Result<_, JsError>`; a refusal becomes a JS `Error`
//! whose message names the field and the reason.
//!
//! **How values cross.** Into Rust, a plain JS object (a scenario, a
//! controller change, a primitive, a robot spec) is read once as JSON text
//! by `boundary.js` and parsed with `serde_json`: the text round-trips every
//! finite `f64` exactly, a throwing getter or a Proxy fails in JavaScript
//! before Rust sees anything, and the typed readers can refuse unknown
//! fields (`deny_unknown_fields` works on a JSON value, not on a JS object
//! read through serde-wasm-bindgen). Joint vectors and points cross as
//! arrays or typed arrays of numbers. Out of Rust, results cross through
//! serde-wasm-bindgen as JSON-compatible objects. Long-lived state (`World`,
//! `Viewer`) is a class that JavaScript owns and frees.
//!
//! **Where the rules are.** Every bound and refusal is the core's: the ±1e9
//! bound on numbers, the refusal of keys beside a bare tag and of an array
//! given for an object (`crate::scenario::bounds`), the typed readers and
//! `Scenario::validate`; a partial controller change is merged, read and
//! checked by `World::update_controller`. This layer applies them to the
//! JSON it read (`convert.rs`) and words serde's messages for a person
//! (`messages.rs`), so a Rust caller and a JavaScript caller get the same
//! refusal.

mod distance;
mod figure;

use wasm_bindgen::prelude::*;

mod boundary;
mod convert;
mod dynamics;
mod kinematics;
mod messages;
mod plan;
mod stream;
mod study;
mod urdf;
mod world;

/// Installs the panic hook (a last resort: nothing reachable from JS should panic).
#[wasm_bindgen(start)]
pub fn start() {
    console_error_panic_hook::set_once();
    world::guard_world_class();
}

#[cfg(feature = "render")]
mod viewer;
#[cfg(feature = "render")]
mod viewer_state;
