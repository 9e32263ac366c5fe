//! Monte Carlo studies of a human that differs from run to run (`vary`):
//! each run's height, clip speed, motion and keypoint noise drawn from the
//! study's seed, the same natively and in wasm; bad ranges refused naming
//! the field. Runs natively and, unchanged, under `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use skeleton_avoidance::human::HumanSpec;
use skeleton_avoidance::scenario::{self, Motion, Scenario, ShapeSpec};
use skeleton_avoidance::study::{MonteCarloOptions, monte_carlo, run_scenario};

/// The shipped reach across the arm, its person varied by `vary`.
fn varied(vary: serde_json::Value) -> Scenario {
    let s = scenario::example("human-reach").unwrap();
    let mut v = serde_json::to_value(&s).unwrap();
    v["obstacles"][0]["shape"]["vary"] = vary;
    v["duration"] = 1.6.into();
    Scenario::from_json(&v.to_string()).unwrap()
}

fn person(s: &Scenario) -> &HumanSpec {
    match &s.obstacles[0].shape {
        ShapeSpec::Human(h) => h,
        ShapeSpec::Primitive(_) => panic!("not a human"),
    }
}

#[test]
fn each_run_draws_its_own_person_from_the_seed() {
    let s = varied(serde_json::json!({
        "height": [1.55, 1.95], "speed": [0.8, 2.0], "clips": ["reach", "wave", "bend"],
        "partSigma": [0.0, 0.03]
    }));
    let mut heights = Vec::new();
    let mut clips = std::collections::BTreeSet::new();
    for run in 0..40 {
        let a = run_scenario(&s, 11, run);
        assert_eq!(
            a,
            run_scenario(&s, 11, run),
            "the same seed and run: the same draw"
        );
        let h = person(&a);
        assert!(
            h.vary.is_none(),
            "a run's person is drawn, not varied again"
        );
        assert!((1.55..=1.95).contains(&h.height), "{}", h.height);
        let anim = h.animation.as_deref().unwrap();
        let speed = anim.speed.unwrap();
        assert!((0.8..=2.0).contains(&speed), "{speed}");
        clips.insert(anim.clip.clone().unwrap());
        let sigma = h.part_sigma.as_ref().unwrap();
        assert_eq!(sigma.len(), 16);
        let first = sigma["head"];
        assert!((0.0..=0.03).contains(&first));
        assert!(sigma.values().all(|x| *x == first), "one σ for every part");
        heights.push(h.height);
    }
    // The draws spread over the ranges and the clips.
    let (lo, hi) = heights
        .iter()
        .fold((f64::INFINITY, 0.0_f64), |(a, b), h| (a.min(*h), b.max(*h)));
    assert!(lo < 1.65 && hi > 1.85, "{lo} … {hi}");
    assert_eq!(clips.len(), 3, "{clips:?}");
    // Another seed, other people; the scenario as given keeps its own.
    assert_ne!(run_scenario(&s, 12, 0), run_scenario(&s, 11, 0));
    assert_eq!(person(&s).height, 1.75);
}

#[test]
fn a_walkers_travel_keeps_pace_with_the_drawn_speed() {
    let mut s = scenario::example("human-panda").unwrap();
    let mut v = serde_json::to_value(&s).unwrap();
    v["obstacles"][0]["shape"]["animation"] = serde_json::json!({ "clip": "walk" });
    v["obstacles"][0]["shape"]["vary"] = serde_json::json!({ "speed": [1.0, 1.8] });
    v["obstacles"][0]["motion"] =
        serde_json::json!({ "type": "linear", "velocity": [0.0, -1.4, 0.0] });
    s = Scenario::from_json(&v.to_string()).unwrap();
    for run in 0..5 {
        let a = run_scenario(&s, 3, run);
        let speed = person(&a).animation.as_deref().unwrap().speed.unwrap();
        let Some(Motion::Linear { velocity }) = a.obstacles[0].motion.clone() else {
            panic!()
        };
        assert!(
            (velocity[1] + speed).abs() < 1e-12,
            "{velocity:?} vs {speed}"
        );
        assert_eq!(velocity[0], 0.0);
    }
}

/// FNV-1a of a report's JSON: pinned, the same natively and in wasm.
fn fnv(text: &str) -> u64 {
    text.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

const VARIED_STUDY_HASH: u64 = 0xc521_fe03_b186_a738;

#[test]
fn a_study_of_varied_people_is_reproducible_natively_and_in_wasm() {
    let s = varied(serde_json::json!({ "height": [1.55, 1.95], "speed": [0.8, 2.0] }));
    let options = MonteCarloOptions {
        runs: 6,
        seed: 5,
        rows: true,
    };
    let a = monte_carlo(&s, &options).unwrap();
    assert_eq!(a, monte_carlo(&s, &options).unwrap());
    let plain = varied(serde_json::Value::Null);
    let b = monte_carlo(&plain, &options).unwrap();
    // Sensed exactly, the plain person gives the same run six times; the
    // varied ones differ.
    let spread = |r: &skeleton_avoidance::study::MonteCarloReport| {
        r.min_clearance.max.unwrap() - r.min_clearance.min.unwrap()
    };
    assert_eq!(spread(&b), 0.0);
    assert!(spread(&a) > 1e-3, "{}", spread(&a));
    let h = fnv(&serde_json::to_string(&a).unwrap());
    assert_eq!(h, VARIED_STUDY_HASH, "hash {h:#x}");
}

#[test]
fn bad_variations_are_refused_naming_the_field() {
    for (vary, field) in [
        (serde_json::json!({ "height": [1.9, 1.6] }), "vary.height"),
        (
            serde_json::json!({ "height": [0.0, 1.6] }),
            "vary.height[0]",
        ),
        (serde_json::json!({ "speed": [1.0, 1e9] }), "vary.speed[1]"),
        (serde_json::json!({ "clips": [] }), "vary.clips"),
        (
            serde_json::json!({ "clips": ["reach", "dance"] }),
            "vary.clips[1]",
        ),
        (
            serde_json::json!({ "partSigma": [-0.1, 0.1] }),
            "vary.partSigma[0]",
        ),
        (serde_json::json!({ "heights": [1.6, 1.7] }), "vary"),
    ] {
        let s = scenario::example("human-reach").unwrap();
        let mut v = serde_json::to_value(&s).unwrap();
        v["obstacles"][0]["shape"]["vary"] = vary.clone();
        let e = Scenario::from_json(&v.to_string()).unwrap_err().to_string();
        let want = format!("obstacles[0].shape.{field}");
        assert!(e.starts_with(&want), "{vary}: {e}");
    }
    // A reach without a target, a speed without a clip.
    let s = scenario::example("human-panda").unwrap();
    let mut v = serde_json::to_value(&s).unwrap();
    v["obstacles"][0]["shape"]["vary"] = serde_json::json!({ "clips": ["reach"] });
    let e = Scenario::from_json(&v.to_string()).unwrap_err().to_string();
    assert!(
        e.starts_with("obstacles[0].shape.vary.clips[0]: reach needs"),
        "{e}"
    );
    v["obstacles"][0]["shape"]["animation"] = serde_json::Value::Null;
    v["obstacles"][0]["shape"]["vary"] = serde_json::json!({ "speed": [1.0, 2.0] });
    let e = Scenario::from_json(&v.to_string()).unwrap_err().to_string();
    assert!(
        e.starts_with("obstacles[0].shape.vary.speed: only a clip"),
        "{e}"
    );
}
