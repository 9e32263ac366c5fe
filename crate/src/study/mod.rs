//! Monte Carlo studies of a scenario (paper §IV): the same scene run many
//! times, each run with its own sensing errors, reduced to distributions —
//! the smallest clearance (quantiles), the probabilities of a contact while
//! the arm moves, of a stop, of chattering and of a transition too slow
//! (each with a 95 % Wilson interval), segment switches per second, and
//! the worst `time to collision − remaining transition time`.
//!
//! * **Seeds.** Run `i` gives obstacle `k` (its index in the scenario) the
//!   sensing seed [`derive_seed`]`(seed, i, k)`: SplitMix64's output
//!   function chained over the three numbers, so that runs and obstacles
//!   get unrelated streams. The scenario's own `sensing.…seed` values are
//!   replaced; everything else (bias bound, noise, latency, motions,
//!   controller) is as the scenario says. A scenario sensed exactly gives
//!   the same run every time.
//! * **Varied people.** A human with `vary` ([`crate::human::HumanVariation`])
//!   is drawn anew in each run (height, clip speed, motion, keypoint noise)
//!   from the stream `derive_seed(seed, i, VARY_STREAM + k)`.
//! * **One run** ([`run_one`]) steps a [`crate::world::World`] for the
//!   scenario's duration and keeps a [`RunRow`]: the smallest true
//!   clearance over every control step (not only the trace's samples),
//!   whether the clearance reached 0 while a joint moved (faster than
//!   [`MOVING_SPEED`]), whether a stop, chattering and a transition too
//!   slow happened (the monitor's events), the number of segment switches,
//!   and the smallest transition slack. No trace is
//!   built.
//! * **Aggregation** ([`MonteCarloReport::from_rows`]) runs over the rows
//!   in run order: sorting for the quantiles, sums in a fixed order. The
//!   report is bit-identical natively and in wasm, for any number of
//!   threads, and when the runs are split into shards and merged
//!   ([`merge`]).
//! * **Threads.** With the cargo feature `parallel` (native only) the runs
//!   are spread over rayon's thread pool (every core, or the pool the
//!   caller installs); without it, and always in wasm, they run one after
//!   the other.
//!
//! The command-line entry `monte-carlo` (`crate/src/bin/monte-carlo.rs`)
//! writes the rows of one shard as JSON lines and merges shards; the batch
//! recipe is in `docs/monte-carlo.md`.

use serde::{Deserialize, Serialize};

use crate::error::FieldError;
pub use crate::rng::derive_seed;
use crate::scenario::{Scenario, ScenarioError};

mod report;
mod run;
mod shard;

pub use report::{ClearanceQuantiles, MonteCarloReport, Probability, SwitchRate, Z95};
pub use run::{MOVING_SPEED, RunRow, VARY_STREAM, run_one, run_scenario};
pub use shard::Shard;

/// Largest number of runs of one study (and of one call of
/// [`monte_carlo_runs`]); larger studies are split into shards and merged.
pub const MAX_RUNS: u64 = 1_000_000;

/// Options of [`monte_carlo`] (JS: `{ runs, seed, rows? }`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct MonteCarloOptions {
    /// Number of runs (1..=[`MAX_RUNS`]).
    pub runs: u64,
    /// Seed of the study (default 0).
    #[serde(default)]
    pub seed: u64,
    /// Whether the report keeps every run's row (default false).
    #[serde(default)]
    pub rows: bool,
}

/// Checks a number of runs (1..=[`MAX_RUNS`]).
///
/// # Errors
/// `runs: must be ≥ 1`, `runs: at most 1000000 in one study …`.
pub fn check_runs(field: &str, runs: u64) -> Result<u64, FieldError> {
    if runs == 0 {
        return Err(FieldError::new(field, "must be ≥ 1"));
    }
    if runs > MAX_RUNS {
        return Err(FieldError::new(
            field,
            format!("at most {MAX_RUNS} in one study (split larger ones into shards)"),
        ));
    }
    Ok(runs)
}

/// Runs `count` runs of the study of `scenario` seeded with `seed`, from
/// run `from` on, and returns their rows in run order (in parallel with
/// the feature `parallel`).
///
/// # Errors
/// `count` out of range (see [`check_runs`]), `from: …` when the runs
/// would go past `u64::MAX`, or whatever [`Scenario::validate`] reports.
pub fn monte_carlo_runs(
    scenario: &Scenario,
    seed: u64,
    from: u64,
    count: u64,
) -> Result<Vec<RunRow>, ScenarioError> {
    check_runs("count", count)?;
    if from.checked_add(count).is_none() {
        return Err(FieldError::new("from", "the runs would go past 2^64").into());
    }
    scenario.validate()?;
    run_range(scenario, seed, from, count).into_iter().collect()
}

#[cfg(all(feature = "parallel", not(target_arch = "wasm32")))]
fn run_range(
    scenario: &Scenario,
    seed: u64,
    from: u64,
    count: u64,
) -> Vec<Result<RunRow, ScenarioError>> {
    use rayon::prelude::*;
    (from..from + count)
        .into_par_iter()
        .map(|i| run_one(scenario, seed, i))
        .collect()
}

#[cfg(not(all(feature = "parallel", not(target_arch = "wasm32"))))]
fn run_range(
    scenario: &Scenario,
    seed: u64,
    from: u64,
    count: u64,
) -> Vec<Result<RunRow, ScenarioError>> {
    (from..from + count)
        .map(|i| run_one(scenario, seed, i))
        .collect()
}

/// Runs a Monte Carlo study of `scenario`: `options.runs` copies with
/// independent sensing seeds, reduced to distributions.
///
/// # Errors
/// `runs: must be ≥ 1`, `runs: at most …`, or whatever
/// [`Scenario::validate`] reports (JSON path and reason).
///
/// # Example
/// ```
/// use skeleton_avoidance::{scenario, study};
/// let mut s = scenario::example("chattering")?;
/// s.duration = 0.05;
/// let options = study::MonteCarloOptions { runs: 4, seed: 7, rows: false };
/// let report = study::monte_carlo(&s, &options)?;
/// assert_eq!(report.runs, 4);
/// assert!(report.min_clearance.min <= report.min_clearance.max);
/// # Ok::<(), skeleton_avoidance::scenario::ScenarioError>(())
/// ```
///
/// See also [`merge`] for studies split into shards.
pub fn monte_carlo(
    scenario: &Scenario,
    options: &MonteCarloOptions,
) -> Result<MonteCarloReport, ScenarioError> {
    check_runs("runs", options.runs)?;
    let rows = monte_carlo_runs(scenario, options.seed, 0, options.runs)?;
    Ok(MonteCarloReport::from_rows(
        options.seed,
        rows,
        options.rows,
    ))
}

/// The report of rows gathered in any order (from shards): they must be
/// runs `0..n` of one study, each once, all with the same seed. The result
/// is the report [`monte_carlo`] gives for the same runs and seed.
///
/// # Errors
/// `rows: no runs`, `rows[k].seed: …` (another study), `rows[k].run: …`
/// (a run twice or missing), `rows: at most …`.
pub fn merge(mut rows: Vec<RunRow>, keep_rows: bool) -> Result<MonteCarloReport, FieldError> {
    let Some(first) = rows.first() else {
        return Err(FieldError::new("rows", "no runs"));
    };
    check_runs("rows", rows.len() as u64)?;
    let seed = first.seed;
    if let Some(k) = rows.iter().position(|r| r.seed != seed) {
        return Err(FieldError::new(
            format!("rows[{k}].seed"),
            format!(
                "{} differs from the first row's {seed} (another study)",
                rows[k].seed
            ),
        ));
    }
    rows.sort_by_key(|r| r.run);
    for (k, r) in rows.iter().enumerate() {
        if r.run != k as u64 {
            let reason = if k > 0 && rows[k - 1].run == r.run {
                format!("run {} appears twice", r.run)
            } else {
                format!("run {k} is missing (runs 0..{} expected)", rows.len())
            };
            return Err(FieldError::new("rows", reason));
        }
    }
    Ok(MonteCarloReport::from_rows(seed, rows, keep_rows))
}
