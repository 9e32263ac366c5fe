//! JS binding of the reach problem sets: `reachProblems(set, data?)`.
//! Converts only (serde's messages about the scene files in the project's
//! words); the sets are [`crate::reach::problems`]'s.

use wasm_bindgen::prelude::*;

use super::boundary::{read_json, string_arg};
use super::convert::{js_error, plain_reason, to_js};
use crate::error::FieldError;
use crate::reach;

/// The problems of the set `set` (`'pr2' | 'panda' | 'mbm'`) as
/// `{ name, scenario, goal: { position, orientation }, goalQ? }[]`; each
/// `scenario` is a scenario `new World` and the playground accept.
/// `data`: for `'mbm'` only, the MotionBenchMaker scene files (one file or
/// an array of them, as objects or JSON text; `crate/tests/data/mbm/`), not
/// built in for their size.
///
/// # Errors
/// `set: unknown problem set …`, `set: expected a string …`, `data: …` when
/// it is missing for `'mbm'`, given for another set, or not scene files.
#[wasm_bindgen(js_name = reachProblems)]
pub fn reach_problems(set: JsValue, data: JsValue) -> Result<JsValue, JsError> {
    let set = string_arg("set", &set)?;
    let data = if data.is_undefined() || data.is_null() {
        None
    } else if let Some(text) = data.as_string() {
        Some(text)
    } else {
        Some(read_json("data", &data)?.to_string())
    };
    let problems = reach::problems(&set, data.as_deref())
        .map_err(|e| js_error(&FieldError::new(e.field, plain_reason(&e.reason))))?;
    to_js(&problems)
}
