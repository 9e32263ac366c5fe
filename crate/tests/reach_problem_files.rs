//! The problem sets as the files the npm package ships (`package/problems/`,
//! read by `reachProblems(set)` in JS, `package/reach.js`): each file is
//! `reach::problems(set)` in a compact, lossless form, and this test checks
//! that it still is. It also writes the sets in their plain form,
//! `reach::problems(set)` serialized as it is, to
//! `target/tmp/reach-problems/<set>.json`: the native fixture the Node test
//! (`tests/node/reach-problems.test.mjs`) compares `reachProblems` with.
//!
//! The compact form: `{ set, about, base, problems: [{ name, goal, goalQ?,
//! scenario }] }`, `base` the first problem's scenario and each problem's
//! `scenario` only the top-level fields that differ from it (the rest of a
//! scenario, the robot and the controller among them, is the same in a
//! set, so the files stay small). `REACH_PROBLEMS_WRITE=1 cargo test -p
//! skeleton-avoidance --test reach_problem_files` rewrites them. Native only
//! (it reads and writes files).
#![cfg(not(target_arch = "wasm32"))]
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::PathBuf;

use serde_json::{Map, Value, json};
use skeleton_avoidance::reach;

const ABOUT: &str = "The reach benchmark's problems, written by crate/tests/reach_problem_files.rs \
    from reach::problems(set); a problem's scenario is `base` with the problem's `scenario` \
    fields put over it. Do not edit by hand.";

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// `reach::problems(set)`, the MotionBenchMaker set read from its scene files.
fn problems(set: &str) -> Vec<reach::Problem> {
    if set != "mbm" {
        return reach::problems(set, None).unwrap();
    }
    let files: Vec<String> = reach::mbm::SCENES
        .iter()
        .map(|s| std::fs::read_to_string(root().join(format!("crate/tests/data/mbm/{s}.json"))))
        .collect::<Result<_, _>>()
        .unwrap();
    reach::problems("mbm", Some(&format!("[{}]", files.join(",")))).unwrap()
}

/// The compact text of a set (module docs), one problem a line.
fn compact(set: &str, plain: &[Value]) -> String {
    let base = plain[0]["scenario"].as_object().unwrap().clone();
    let lines: Vec<String> = plain
        .iter()
        .map(|p| {
            let mut p = p.as_object().unwrap().clone();
            let scenario = p["scenario"].as_object().unwrap();
            let own: Map<String, Value> = scenario
                .iter()
                .filter(|(k, v)| base.get(*k) != Some(*v))
                .map(|(k, v)| (k.clone(), v.clone()))
                .collect();
            // A field of the base missing here could not be put back.
            assert!(base.keys().all(|k| scenario.contains_key(k)), "{set}");
            p.insert("scenario".into(), Value::Object(own));
            serde_json::to_string(&p).unwrap()
        })
        .collect();
    let head = json!({ "set": set, "about": ABOUT, "base": base });
    let head = serde_json::to_string(&head).unwrap();
    format!(
        "{},\n\"problems\": [\n{}\n]}}\n",
        &head[..head.len() - 1],
        lines.join(",\n")
    )
}

#[test]
fn package_problem_files_are_the_native_sets() {
    let fixtures = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("reach-problems");
    std::fs::create_dir_all(&fixtures).unwrap();
    for set in reach::SETS {
        let plain: Vec<Value> = problems(set)
            .iter()
            .map(|p| serde_json::to_value(p).unwrap())
            .collect();
        let text = compact(set, &plain);
        // The compact form is lossless: base + own fields = the scenario.
        let back: Value = serde_json::from_str(&text).unwrap();
        for (p, q) in plain.iter().zip(back["problems"].as_array().unwrap()) {
            let mut scenario = back["base"].as_object().unwrap().clone();
            scenario.extend(q["scenario"].as_object().unwrap().clone());
            assert_eq!(Value::Object(scenario), p["scenario"], "{}", p["name"]);
        }
        let path = root().join(format!("package/problems/{set}.json"));
        if std::env::var_os("REACH_PROBLEMS_WRITE").is_some() {
            std::fs::write(&path, &text).unwrap();
        }
        let shipped = std::fs::read_to_string(&path).unwrap_or_default();
        assert!(
            shipped == text,
            "{} is not reach::problems(\"{set}\"): rewrite it with REACH_PROBLEMS_WRITE=1",
            path.display()
        );
        let fixture = serde_json::to_string(&plain).unwrap();
        std::fs::write(fixtures.join(format!("{set}.json")), fixture).unwrap();
    }
}

/// The last problem of `set`, read back from its plain JSON as a JS caller
/// gets it, loads into a World and steps.
fn last_problem_runs(set: &str) {
    use skeleton_avoidance::scenario::Scenario;
    use skeleton_avoidance::world::World;
    let p = reach::problems(set, None).unwrap().pop().unwrap();
    let v = serde_json::to_value(&p).unwrap();
    let scenario = Scenario::from_json(&v["scenario"].to_string()).unwrap();
    let mut world = World::new(scenario).unwrap();
    for _ in 0..20 {
        world.step(p.scenario.dt);
    }
    assert!(world.sample().q.iter().all(|q| q.is_finite()), "{set}");
}

#[test]
fn a_panda_problem_read_back_from_json_runs() {
    last_problem_runs("panda");
}

#[test]
fn a_pr2_problem_read_back_from_json_runs() {
    last_problem_runs("pr2");
}
