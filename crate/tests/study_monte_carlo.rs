//! Monte Carlo studies: exact sensing gives no spread, noise gives one, the
//! report is bit-identical natively, in wasm (a pinned hash of its JSON),
//! for any number of threads and when split into shards and merged; the
//! transition slack agrees with the monitor; bad options are refused with
//! the field named. Runs natively and, unchanged, under
//! `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use skeleton_avoidance::dependability::EventKind;
use skeleton_avoidance::scenario::{self, Scenario, SensingConfig};
use skeleton_avoidance::study::{self, MAX_RUNS, MonteCarloOptions, RunRow, Shard};
use skeleton_avoidance::world::World;

/// The `chattering` example (a noisy sphere between two links), shortened,
/// with the paper's repulsion: its command follows the noise, so noisy
/// runs spread (the `constraints` avoidance rests at this distance and
/// every run gives the same clearance).
fn noisy(duration: f64) -> Scenario {
    let mut s = scenario::example("chattering").unwrap();
    s.duration = duration;
    s.controller.avoidance = skeleton_avoidance::avoidance::Avoidance::Repulsion;
    s
}

fn options(runs: u64, seed: u64) -> MonteCarloOptions {
    MonteCarloOptions {
        runs,
        seed,
        rows: true,
    }
}

/// FNV-1a of a string.
fn fnv(text: &str) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in text.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// The pinned hash of the JSON report of a small study: the same natively
/// (on any number of threads) and in wasm (this test runs in both).
const STUDY_HASH: u64 = 0xb09b_7171_3e8d_c4dc;

#[test]
fn a_small_study_is_bit_identical_natively_and_in_wasm() {
    let report = study::monte_carlo(&noisy(0.4), &options(6, 2024)).unwrap();
    let json = serde_json::to_string(&report).unwrap();
    let h = fnv(&json);
    assert_eq!(h, STUDY_HASH, "hash {h:#x} of {json}");
}

#[test]
fn exact_sensing_gives_no_spread() {
    let mut s = noisy(0.3);
    s.sensing = SensingConfig::default();
    let r = study::monte_carlo(&s, &options(5, 9)).unwrap();
    let q = &r.min_clearance;
    let min = q.min.unwrap();
    for v in [q.p01, q.p05, q.p50, q.p95, q.max, q.mean] {
        assert_eq!(v, Some(min));
    }
    let rows = r.rows.unwrap();
    assert!(rows.iter().all(|x| RunRow {
        run: 0,
        ..x.clone()
    } == RunRow {
        run: 0,
        ..rows[0].clone()
    }));
    assert_eq!(r.stop.count, 0);
    assert_eq!(r.switches_per_second.max, r.switches_per_second.mean);
}

#[test]
fn noise_gives_a_spread_and_the_chattering_it_causes() {
    let r = study::monte_carlo(&noisy(1.0), &options(8, 1)).unwrap();
    let q = &r.min_clearance;
    let (min, max) = (q.min.unwrap(), q.max.unwrap());
    assert!(max - min > 1e-5, "spread {min} .. {max}");
    assert!(min <= q.p05.unwrap() && q.p05 <= q.p50 && q.p50 <= q.p95 && q.p95 <= q.max);
    // Every run chatters and stops (the example's point); the Wilson
    // interval of 8 of 8 is [0.676, 1].
    assert_eq!((r.chattering.count, r.stop.count), (8, 8));
    assert!((r.stop.low - 0.6756).abs() < 1e-4 && r.stop.high == 1.0);
    assert!(r.switches_per_second.mean > 10.0);
    // Another seed gives other runs.
    let other = study::monte_carlo(&noisy(1.0), &options(8, 2)).unwrap();
    assert_ne!(other.min_clearance, r.min_clearance);
}

#[test]
fn runs_get_their_own_seeds_and_shards_merge_into_the_same_report() {
    let s = noisy(0.3);
    let whole = study::monte_carlo(&s, &options(7, 5)).unwrap();
    let mut lines = Vec::new();
    for index in (0..3).rev() {
        let r = Shard::new(index, 3).unwrap().range(7);
        let rows = study::monte_carlo_runs(&s, 5, r.start, r.end - r.start).unwrap();
        lines.extend(rows.iter().map(|x| serde_json::to_string(x).unwrap()));
    }
    let rows: Vec<RunRow> = lines
        .iter()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let merged = study::merge(rows.clone(), true).unwrap();
    assert_eq!(
        serde_json::to_string(&merged).unwrap(),
        serde_json::to_string(&whole).unwrap()
    );
    // a run alone is the same run
    let third = study::run_one(&s, 5, 3).unwrap();
    assert_eq!(&third, &whole.rows.as_ref().unwrap()[3]);
    // missing, doubled and foreign rows are refused
    let e = study::merge(rows[1..].to_vec(), false)
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("rows: run") && e.contains("missing"), "{e}");
    let mut twice = rows.clone();
    twice.push(twice[0].clone());
    let e = study::merge(twice, false).unwrap_err().to_string();
    assert!(e.contains("appears twice"), "{e}");
    let mut foreign = rows;
    foreign[2].seed = 6;
    let e = study::merge(foreign, false).unwrap_err().to_string();
    assert!(e.starts_with("rows[2].seed"), "{e}");
    assert!(study::merge(Vec::new(), false).is_err());
}

#[test]
fn bad_options_are_refused_with_the_field_named() {
    let s = noisy(0.01);
    let e = study::monte_carlo(&s, &options(0, 0))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("runs: must be ≥ 1"), "{e}");
    let e = study::monte_carlo(&s, &options(MAX_RUNS + 1, 0))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("runs: at most 1000000"), "{e}");
    let e = study::monte_carlo_runs(&s, 0, u64::MAX, 2)
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("from:"), "{e}");
    let mut bad = s;
    bad.dt = f64::NAN;
    let e = study::monte_carlo(&bad, &options(1, 0))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("dt:"), "{e}");
    let e = serde_json::from_str::<MonteCarloOptions>(r#"{"runs": 2, "sed": 1}"#)
        .unwrap_err()
        .to_string();
    assert!(e.contains("sed"), "{e}");
}

/// A ball that jumps beside link 3 and keeps coming while the control
/// point travels there slowly (0.5 s per DH value).
fn slow_transition() -> Scenario {
    Scenario::from_json(
        r#"{
        "robot": { "preset": "planar3" },
        "q0": [0.0, 1.5, 1.5],
        "obstacles": [{ "id": "ball",
            "shape": { "type": "sphere", "center": [0.2, -0.25, 0.0], "radius": 0.05 },
            "motion": { "type": "waypoints",
                "points": [[0, 0, 0], [0, 0, 0], [0.1, 0.82, 0], [0.1, 0.5, 0]],
                "times": [0, 0.3, 0.3, 1.0] } }],
        "controller": { "selection": "perObstacle", "transitionTime": 0.5 },
        "dt": 0.001, "duration": 1.0 }"#,
    )
    .unwrap()
}

#[test]
fn transition_slack_bounds_the_monitors_margin_and_too_slow_follows_its_events() {
    let s = slow_transition();
    let mut w = World::new(s.clone()).unwrap();
    let mut events = 0;
    let mut worst = f64::INFINITY;
    for _ in 0..1000 {
        let before = w.event_count();
        w.step(s.dt);
        let fresh = &w.events()[w.events().len() - (w.event_count() - before)..];
        let slack = w.probe().transition_slack;
        if let Some(x) = slack {
            worst = worst.min(x);
        }
        for e in fresh {
            if let EventKind::TransitionTooSlow {
                time_to_collision,
                remaining,
                ..
            } = e.kind
            {
                // The step's smallest time to collision and longest
                // remaining transition bound this point's margin.
                events += 1;
                let x = slack.expect("a transition under way");
                assert!(x <= time_to_collision - remaining + 1e-12, "{x} at {}", e.t);
            }
        }
    }
    assert!(events >= 1, "the scenario raises transitionTooSlow");
    let r = study::monte_carlo(&s, &options(1, 0)).unwrap();
    assert_eq!(r.transition_too_slow.count, 1);
    assert_eq!(r.worst_transition_slack, Some(worst));
    assert!(worst < 0.0, "{worst}");
    // An exactly sensed static obstacle never makes a transition too slow.
    let quiet = study::monte_carlo(
        &scenario::example("planar-transition").unwrap(),
        &options(2, 0),
    );
    assert_eq!(quiet.unwrap().transition_too_slow.count, 0);
}

#[cfg(all(feature = "parallel", not(target_arch = "wasm32")))]
#[test]
fn the_report_is_the_same_on_one_and_on_two_threads() {
    let s = noisy(0.4);
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let r = pool.install(|| study::monte_carlo(&s, &options(6, 2024)).unwrap());
        serde_json::to_string(&r).unwrap()
    };
    let one = on(1);
    assert_eq!(one, on(2));
    assert_eq!(fnv(&one), STUDY_HASH);
}
