//! The `#[wasm_bindgen]` layer: converts and validates, no logic.

mod distance;

use wasm_bindgen::prelude::*;

/// Installs the panic hook (a last resort: nothing reachable from JS should panic).
#[wasm_bindgen(start)]
pub fn start() {
    console_error_panic_hook::set_once();
}
