//! The distributions of a study, aggregated from its [`RunRow`]s in run
//! order (sorting and sums in a fixed order: the same bits however the
//! runs were spread over threads, processes or machines).

use serde::{Deserialize, Serialize};

use super::run::RunRow;

/// `z` of a two-sided 95 % interval (the normal quantile of 0.975).
pub const Z95: f64 = 1.959_963_984_540_054;

/// Quantiles of the smallest clearance over the runs (m). Linear
/// interpolation between order statistics (`h = (n − 1) p`); a run in
/// which nothing came within reach counts as `+∞` and makes a quantile
/// that falls on it `None`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct ClearanceQuantiles {
    /// Smallest.
    pub min: Option<f64>,
    /// 1 %.
    pub p01: Option<f64>,
    /// 5 %.
    pub p05: Option<f64>,
    /// Median.
    pub p50: Option<f64>,
    /// 95 %.
    pub p95: Option<f64>,
    /// Largest.
    pub max: Option<f64>,
    /// Mean over the runs in which something came within reach.
    pub mean: Option<f64>,
    /// Runs in which nothing came within reach.
    pub out_of_reach: u64,
}

/// How often something happened, with a 95 % Wilson score interval.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct Probability {
    /// Runs in which it happened.
    pub count: u64,
    /// `count / runs`.
    pub p: f64,
    /// Lower end of the 95 % Wilson interval.
    pub low: f64,
    /// Upper end of the 95 % Wilson interval.
    pub high: f64,
}

impl Probability {
    /// `count` successes out of `runs` (> 0) with their Wilson interval
    /// `(p + z²/2n ± z √(p(1−p)/n + z²/4n²)) / (1 + z²/n)`.
    #[must_use]
    pub fn wilson(count: u64, runs: u64) -> Self {
        let n = runs.max(1) as f64;
        let p = count as f64 / n;
        let z2 = Z95 * Z95;
        let centre = p + z2 / (2.0 * n);
        let half = Z95 * (p * (1.0 - p) / n + z2 / (4.0 * n * n)).sqrt();
        let scale = 1.0 + z2 / n;
        Self {
            count,
            p,
            // exact at the ends (rounding leaves 1e-17 there)
            low: if count == 0 {
                0.0
            } else {
                ((centre - half) / scale).max(0.0)
            },
            high: if count >= runs {
                1.0
            } else {
                ((centre + half) / scale).min(1.0)
            },
        }
    }
}

/// Segment switches per second over the runs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct SwitchRate {
    /// Mean over the runs (1/s).
    pub mean: f64,
    /// Largest (1/s).
    pub max: f64,
}

/// What [`super::monte_carlo`] returns (serde camelCase; JS
/// `monteCarlo`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct MonteCarloReport {
    /// Number of runs.
    pub runs: u64,
    /// The study's seed.
    pub seed: u64,
    /// Smallest clearance of each run: quantiles and mean (m).
    pub min_clearance: ClearanceQuantiles,
    /// Runs in which the true clearance reached 0 while the arm moved.
    pub contact_while_moving: Probability,
    /// Runs in which the monitor stopped the arm.
    pub stop: Probability,
    /// Runs in which a control point chattered.
    pub chattering: Probability,
    /// Runs in which the monitor found a transition too slow.
    pub transition_too_slow: Probability,
    /// Segment switches per second.
    pub switches_per_second: SwitchRate,
    /// Smallest `time to collision − remaining transition time` over
    /// every run (s); `None` when no run had a transition under way with
    /// something closing in.
    pub worst_transition_slack: Option<f64>,
    /// The runs themselves, in order (when asked for).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rows: Option<Vec<RunRow>>,
}

/// The `p` quantile of sorted values (linear interpolation); `None` when
/// it touches an infinite one.
fn quantile(sorted: &[f64], p: f64) -> Option<f64> {
    let n = sorted.len();
    if n == 0 {
        return None;
    }
    let h = (n - 1) as f64 * p;
    let lo = h.floor() as usize;
    let hi = (lo + 1).min(n - 1);
    let (a, b) = (sorted[lo], sorted[hi]);
    let frac = h - lo as f64;
    let v = if frac == 0.0 { a } else { a + (b - a) * frac };
    v.is_finite().then_some(v)
}

fn clearance(rows: &[RunRow]) -> ClearanceQuantiles {
    let mut values: Vec<f64> = rows
        .iter()
        .map(|r| r.min_clearance.unwrap_or(f64::INFINITY))
        .collect();
    values.sort_by(f64::total_cmp);
    let within: Vec<f64> = rows.iter().filter_map(|r| r.min_clearance).collect();
    // Deviations from the first value, summed in run order: equal values
    // give exactly that value (an exactly sensed study has no spread).
    let mean = within
        .first()
        .map(|&x0| x0 + within.iter().map(|x| x - x0).sum::<f64>() / within.len() as f64);
    ClearanceQuantiles {
        min: quantile(&values, 0.0),
        p01: quantile(&values, 0.01),
        p05: quantile(&values, 0.05),
        p50: quantile(&values, 0.5),
        p95: quantile(&values, 0.95),
        max: quantile(&values, 1.0),
        mean,
        out_of_reach: (rows.len() - within.len()) as u64,
    }
}

impl MonteCarloReport {
    /// The report of `rows`, which must be runs `0..n` of one study in
    /// order (see [`super::merge`] for rows in any order); `keep_rows`
    /// keeps them in the report.
    #[must_use]
    pub fn from_rows(seed: u64, rows: Vec<RunRow>, keep_rows: bool) -> Self {
        let n = rows.len() as u64;
        let count = |f: fn(&RunRow) -> bool| {
            Probability::wilson(rows.iter().filter(|r| f(r)).count() as u64, n)
        };
        let rates = rows.iter().map(|r| r.switches_per_second);
        let sum: f64 = rates.clone().sum();
        Self {
            runs: n,
            seed,
            min_clearance: clearance(&rows),
            contact_while_moving: count(|r| r.contact_while_moving),
            stop: count(|r| r.stopped),
            chattering: count(|r| r.chattering),
            transition_too_slow: count(|r| r.transition_too_slow),
            switches_per_second: SwitchRate {
                mean: if n > 0 { sum / n as f64 } else { 0.0 },
                max: rates.fold(0.0, f64::max),
            },
            worst_transition_slack: rows
                .iter()
                .filter_map(|r| r.transition_slack)
                .reduce(f64::min),
            rows: keep_rows.then_some(rows),
        }
    }
}

#[cfg(test)]
mod tests {
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    use super::{Probability, quantile};

    #[test]
    fn quantiles_interpolate_between_order_statistics() {
        let v = [1.0, 2.0, 3.0, 4.0, 5.0];
        assert_eq!(quantile(&v, 0.0), Some(1.0));
        assert_eq!(quantile(&v, 0.5), Some(3.0));
        assert_eq!(quantile(&v, 1.0), Some(5.0));
        assert_eq!(quantile(&v, 0.1), Some(1.4));
        assert_eq!(quantile(&[1.0, f64::INFINITY], 1.0), None);
        assert_eq!(quantile(&[1.0, f64::INFINITY], 0.0), Some(1.0));
        assert_eq!(quantile(&[], 0.5), None);
    }

    #[test]
    fn wilson_interval_matches_a_worked_value() {
        // 0 of 10: [0, z²/(n + z²)] = [0, 0.2775]; 5 of 10: 0.5 ± 0.2632.
        let p = Probability::wilson(0, 10);
        assert_eq!((p.p, p.low), (0.0, 0.0));
        assert!((p.high - 0.277_53).abs() < 1e-4, "{}", p.high);
        let h = Probability::wilson(5, 10);
        assert!((h.low - 0.236_6).abs() < 1e-4, "{}", h.low);
        assert!((h.high - 0.763_4).abs() < 1e-4, "{}", h.high);
        let all = Probability::wilson(10, 10);
        assert_eq!(all.high, 1.0);
        assert!((all.low - (1.0 - 0.277_53)).abs() < 1e-4);
    }
}
