//! JS bindings of Monte Carlo studies: `monteCarlo`, `monteCarloRuns` (a
//! block of runs, for a progress bar) and `monteCarloMerge`. Converts and
//! validates only; the work is in [`crate::study`].

use serde::Deserialize;
use wasm_bindgen::prelude::*;

use super::convert::{from_json_at, js_error, object_from_js, to_js};
use super::world::{scenario_error, scenario_from_js};
use crate::error::FieldError;
use crate::scenario::Scenario;
use crate::study::{self, RunRow};

/// Most runs of one `monteCarlo` or `monteCarloRuns` call (the call blocks
/// its thread: run larger studies in blocks, in a worker, or natively).
pub const MAX_JS_RUNS: f64 = 10_000.0;

/// Most control steps of one run (as one `simulate` call).
const MAX_RUN_STEPS: f64 = 1e6;

/// Largest seed or run index from JS: integers stay exact up to 2^53 − 1.
const MAX_SAFE: f64 = 9_007_199_254_740_991.0;

#[derive(Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
struct StudyOptions {
    runs: f64,
    #[serde(default)]
    seed: f64,
    #[serde(default)]
    rows: bool,
}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
struct RunsOptions {
    #[serde(default)]
    seed: f64,
    #[serde(default)]
    from: f64,
    count: f64,
}

#[derive(Deserialize, Default)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
struct MergeOptions {
    #[serde(default)]
    rows: bool,
}

/// An integer in `lo..=hi` (as u64).
fn integer(field: &str, x: f64, lo: f64, hi: f64) -> Result<u64, JsError> {
    if x.fract() != 0.0 {
        return Err(js_error(&FieldError::new(field, "expected an integer")));
    }
    if x < lo || x > hi {
        return Err(js_error(&FieldError::new(
            field,
            format!("must be in {lo}..={hi}"),
        )));
    }
    // In 0..=2^53, integral: exact.
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    Ok(x as u64)
}

fn checked_scenario(value: JsValue) -> Result<Scenario, JsError> {
    let s = scenario_from_js(value)?;
    if s.duration / s.dt > MAX_RUN_STEPS {
        return Err(js_error(&FieldError::new(
            "duration",
            format!("more than {MAX_RUN_STEPS:e} steps of dt in one run"),
        )));
    }
    Ok(s)
}

/// Runs a Monte Carlo study: `runs` copies of `scenario` (1..=10000 in one
/// call), run `i` giving obstacle `k` the sensing seed derived from
/// `(seed, i, k)`, and returns the distributions `{ runs, seed,
/// minClearance: { min, p01, p05, p50, p95, max, mean, outOfReach },
/// contactWhileMoving, stop, chattering, transitionTooSlow: { count, p,
/// low, high }, switchesPerSecond: { mean, max }, worstTransitionSlack,
/// rows? }`: bit for bit what the Rust library gives natively.
///
/// # Errors
/// `runs: must be in 1..=10000`, `seed: expected an integer`, or the
/// scenario's JSON path and reason.
#[wasm_bindgen(js_name = monteCarlo)]
pub fn monte_carlo(scenario: JsValue, options: JsValue) -> Result<JsValue, JsError> {
    let o: StudyOptions = object_from_js("options", options)?;
    let runs = integer("runs", o.runs, 1.0, MAX_JS_RUNS)?;
    let seed = integer("seed", o.seed, 0.0, MAX_SAFE)?;
    let s = checked_scenario(scenario)?;
    let options = study::MonteCarloOptions {
        runs,
        seed,
        rows: o.rows,
    };
    let report = study::monte_carlo(&s, &options).map_err(|e| scenario_error(&e))?;
    to_js(&report)
}

/// Runs `count` runs of the study of `scenario` seeded with `seed`, from
/// run `from` on, and returns their rows `[{ run, seed, minClearance,
/// contactWhileMoving, stopped, chattering, transitionTooSlow, switches,
/// switchesPerSecond, transitionSlack }]`: a study in blocks (for a progress bar), merged with
/// `monteCarloMerge`.
///
/// # Errors
/// `count: must be in 1..=10000`, `from: expected an integer`, or the
/// scenario's JSON path and reason.
#[wasm_bindgen(js_name = monteCarloRuns)]
pub fn monte_carlo_runs(scenario: JsValue, options: JsValue) -> Result<JsValue, JsError> {
    let o: RunsOptions = object_from_js("options", options)?;
    let count = integer("count", o.count, 1.0, MAX_JS_RUNS)?;
    let from = integer("from", o.from, 0.0, MAX_SAFE - MAX_JS_RUNS)?;
    let seed = integer("seed", o.seed, 0.0, MAX_SAFE)?;
    let s = checked_scenario(scenario)?;
    let rows = study::monte_carlo_runs(&s, seed, from, count).map_err(|e| scenario_error(&e))?;
    to_js(&rows)
}

/// The report of rows from `monteCarloRuns` (in any order; runs `0..n` of
/// one study, each once): the same as `monteCarlo` for those runs and
/// seed. `options.rows` keeps the rows in the report.
///
/// # Errors
/// `rows: expected an array`, `rows[3].switches: …`, `rows: run 4 is
/// missing …`, `rows[2].seed: … (another study)`.
#[wasm_bindgen(js_name = monteCarloMerge)]
pub fn monte_carlo_merge(rows: JsValue, options: JsValue) -> Result<JsValue, JsError> {
    let o: MergeOptions = if options.is_undefined() || options.is_null() {
        MergeOptions::default()
    } else {
        object_from_js("options", options)?
    };
    // Read once by boundary.js (a revoked Proxy or a throwing getter becomes
    // a clean `Error`), then checked: even `Array.isArray` throws on a
    // revoked Proxy.
    let json = super::boundary::read_json("rows", &rows)?;
    if !json.is_array() {
        return Err(js_error(&FieldError::new("rows", "expected an array")));
    }
    let rows: Vec<RunRow> = from_json_at("rows", "rows", json)?;
    let report = study::merge(rows, o.rows).map_err(|e| js_error(&e))?;
    to_js(&report)
}

/// Most runs of one `benchMonteCarlo` call.
const MAX_BENCH_RUNS: u32 = 100;

/// Runs a study of `runs` runs (default 4) of the Monte Carlo benchmark's
/// scenario (`workloads::monte_carlo_workload`: 2 s of `lwr4` at 1 kHz with
/// noisy sensing) and returns its smallest clearance (a checksum).
///
/// # Errors
/// `runs` not an integer in 1..=100.
#[wasm_bindgen(js_name = benchMonteCarlo)]
pub fn bench_monte_carlo(runs: JsValue) -> Result<f64, JsError> {
    let runs = super::boundary::count_arg("runs", &runs, Some(4), MAX_BENCH_RUNS)?.max(1);
    let s = crate::workloads::monte_carlo_workload().map_err(|e| scenario_error(&e))?;
    let options = study::MonteCarloOptions {
        runs: u64::from(runs),
        seed: 1,
        rows: false,
    };
    let report = study::monte_carlo(&s, &options).map_err(|e| scenario_error(&e))?;
    Ok(report.min_clearance.min.unwrap_or(f64::NAN))
}
