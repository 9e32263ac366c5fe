//! The `#[wasm_bindgen]` layer: converts and validates, no logic.
//!
//! Every export returns `Result<_, JsError>`; a validation error becomes a JS
//! `Error` whose message names the field and the reason.

mod distance;
mod figure;

use wasm_bindgen::prelude::*;

mod boundary;
mod convert;
mod kinematics;
mod messages;
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
