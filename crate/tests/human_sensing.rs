//! Sensing errors of single parts of a human (`partSigma`): each part's
//! guard subtracts the margin of its own σ, by the same formula as an
//! obstacle's `sensing.sigma`; the parts' noise is reproducible natively
//! and in wasm. Runs natively and, unchanged, under `wasm-pack test
//! --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

mod common;

use common::trace_hash;
use skeleton_avoidance::scenario::{self, Scenario};
use skeleton_avoidance::world::{World, simulate};

/// The shipped reach across the arm, its person's right hand (and
/// optionally the left foot) seen with their own σ, the whole person with
/// `sensing.sigma` = `base`.
fn reach(hand: Option<f64>, foot: Option<f64>, base: f64) -> Scenario {
    let mut s = scenario::example("human-reach").unwrap();
    let mut v = serde_json::to_value(&s).unwrap();
    let mut sigma = serde_json::Map::new();
    if let Some(h) = hand {
        sigma.insert("rightHand".into(), h.into());
    }
    if let Some(f) = foot {
        sigma.insert("leftFoot".into(), f.into());
    }
    if !sigma.is_empty() {
        v["obstacles"][0]["shape"]["partSigma"] = sigma.into();
    }
    v["sensing"] = serde_json::json!({ "person": { "sigma": base, "seed": 7 } });
    s = serde_json::from_value(v).unwrap();
    s.duration = 2.6;
    s
}

/// The margin an obstacle sensed with `sigma` gets (the per-obstacle
/// formula, read from a world).
fn obstacle_margin(sigma: f64) -> f64 {
    let w = World::new(reach(None, None, sigma)).unwrap();
    w.state().uncertainty[0].radius
}

#[test]
fn a_part_with_a_larger_sigma_is_guarded_with_its_own_larger_margin() {
    let (base, hand) = (0.004, 0.02);
    let s = reach(Some(hand), None, base);
    let mut w = World::new(s.clone()).unwrap();
    // The per-obstacle formula with the two errors combined.
    let want_hand = obstacle_margin((base * base + hand * hand).sqrt());
    let want_rest = obstacle_margin(base);
    assert!(
        (want_hand - 3.0 * (base * base + hand * hand).sqrt()).abs() < 1e-12,
        "{want_hand}"
    );
    let st = w.state();
    let u = &st.uncertainty[0];
    let parts = u.part_margins.as_ref().unwrap();
    assert!((parts["rightHand"] - want_hand).abs() < 1e-15);
    assert!((parts["leftHand"] - want_rest).abs() < 1e-15);
    assert!(
        (u.radius - want_hand).abs() < 1e-15,
        "the obstacle's: the largest"
    );
    let (mut hand_pairs, mut other_pairs) = (0, 0);
    while w.time() < s.duration {
        w.step(s.dt);
        for g in w.guarded() {
            let part = g.part.clone().unwrap_or_default();
            if part == "person:rightHand" {
                assert!((g.margin - want_hand).abs() < 1e-15, "{part}: {}", g.margin);
                hand_pairs += 1;
            } else if part.starts_with("person:") {
                assert!((g.margin - want_rest).abs() < 1e-15, "{part}: {}", g.margin);
                other_pairs += 1;
            }
        }
    }
    eprintln!("guarded: {hand_pairs} hand pairs, {other_pairs} other parts'");
    assert!(hand_pairs > 0 && other_pairs > 0);
}

/// The smallest true clearance between the arm, holding still, and the
/// person reaching across it, and the part that comes that close.
fn closest(s: &Scenario) -> (f64, String) {
    let mut s = s.clone();
    s.task = Default::default();
    let mut w = World::new(s.clone()).unwrap();
    let mut best = (f64::INFINITY, String::new());
    while w.time() < s.duration {
        w.step(s.dt);
        let st = w.state();
        if let Some(c) = st.min_clearance.filter(|c| *c < best.0) {
            best = (c, st.closest_part.unwrap_or_default());
        }
    }
    best
}

#[test]
fn a_hand_seen_with_sigma_is_avoided_as_a_person_seen_with_sigma_and_a_foot_changes_nothing() {
    let none = closest(&reach(None, None, 0.0));
    let hand = closest(&reach(Some(0.02), None, 0.0));
    let person = closest(&reach(None, None, 0.02));
    let foot = closest(&reach(None, Some(0.02), 0.0));
    eprintln!("closest: exact {none:?}, hand σ {hand:?}, person σ {person:?}, foot σ {foot:?}");
    assert_eq!(none.1, "person:rightHand");
    // The hand is what comes close: its own σ (the same draws from the
    // same seed, the same margin) moves the arm exactly as the whole
    // person's σ does, and differently from exact sensing.
    assert_eq!(hand, person);
    assert!((hand.0 - none.0).abs() > 1e-3, "{hand:?} vs {none:?}");
    // A foot's σ, far from the arm, changes nothing: the hand's guard
    // keeps its own margin, not the person's largest.
    assert_eq!(foot, none);
}

/// Pinned: the same natively and in wasm (this test runs in both).
const PART_SIGMA_HASH: u64 = 0x6fe1_4454_0eac_9b14;

#[test]
fn part_noise_is_reproducible_natively_and_in_wasm() {
    let mut s = reach(Some(0.02), Some(0.01), 0.003);
    s.duration = 1.5;
    let a = simulate(&s).unwrap();
    assert_eq!(a, simulate(&s).unwrap());
    let mut other = s.clone();
    other.sensing.obstacles.get_mut("person").unwrap().seed = Some(8);
    assert_ne!(a, simulate(&other).unwrap());
    let h = trace_hash(&a);
    assert_eq!(h, PART_SIGMA_HASH, "hash {h:#x}");
}

#[test]
fn bad_part_sigmas_are_refused_naming_the_field() {
    for (name, value, field) in [
        ("rightHnd", "0.01", "obstacles[0].shape.partSigma.rightHnd"),
        ("head", "-0.01", "obstacles[0].shape.partSigma.head"),
        ("head", "2", "obstacles[0].shape.partSigma.head"),
    ] {
        let json = format!(
            r#"{{ "robot": {{ "preset": "panda" }}, "dt": 0.002, "duration": 1,
                 "obstacles": [{{ "id": "p", "shape": {{ "type": "human", "position": [1, 0, 0],
                 "partSigma": {{ "{name}": {value} }} }} }}] }}"#
        );
        let e = Scenario::from_json(&json).unwrap_err().to_string();
        assert!(e.starts_with(&format!("{field}:")), "{e}");
    }
}
