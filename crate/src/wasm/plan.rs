//! JS binding of the planner: `planPath(scenario, goalQ, options?)`.
//! Converts and validates only; the work is in [`crate::plan`].

use wasm_bindgen::prelude::*;

use super::convert::{f64_vec, js_error, object_from_js, to_js};
use super::world::scenario_from_js;
use crate::error::FieldError;
use crate::plan::{PlanOptions, plan_path};

/// A joint-space path from `scenario`'s start to the configuration `goalQ`
/// among its obstacles at `t = 0`, every segment certified clear by the
/// safety band plus `options.extraClearance`, timed within the joints'
/// limits: `{ configurations, times, escape, thresholds: { obstacles,
/// selfPairs }, evaluations }`. Follow it with the task
/// `{ type: 'joints', configurations, times }` (the `constraints`
/// avoidance). `options`: `{ seed, extraClearance, selfClearance, step,
/// rounds, shortcuts, timeScale }`, each optional.
///
/// # Errors
/// `goalQ[3]: 4 is outside the joint's limits […]`, `goalQ: its clearance
/// … is within the safety band`, `goalQ: no path found in two searches of 4000 rounds`,
/// `options.rounds: must be in 1..=1000000`, the scenario's own errors.
#[wasm_bindgen(js_name = planPath)]
pub fn plan_path_js(
    scenario: JsValue,
    goal: JsValue,
    options: JsValue,
) -> Result<JsValue, JsError> {
    let s = scenario_from_js(scenario)?;
    let goal = f64_vec("goalQ", &goal)?;
    let options: PlanOptions = if options.is_undefined() || options.is_null() {
        PlanOptions::default()
    } else {
        object_from_js("options", options)?
    };
    let plan = plan_path(&s, &goal, &options).map_err(|e| {
        let field = match e.field.strip_prefix("goal") {
            Some(rest) => format!("goalQ{rest}"),
            None => e.field.clone(),
        };
        js_error(&FieldError::new(field, e.reason))
    })?;
    to_js(&plan)
}
