//! Sensing models (bias, white and correlated noise, latency) and the time
//! to collision from the material approach speed (issue 12, parts 1 and 4).
//! Runs natively and, unchanged, under `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::DVec3;
use skeleton_avoidance::dependability::{EventKind, SensingSpec};
use skeleton_avoidance::scenario::{self, EXAMPLE_NAMES, Scenario, SensingConfig, ShapeSpec};
use skeleton_avoidance::world::{World, simulate};

mod common;
use common::trace_hash;

/// The `lwr4` at rest (no repulsion, no protective layer, holding its end
/// effector) and one sphere with `motion`.
fn still_arm(center: DVec3, motion: &str) -> Scenario {
    let c = center.to_array();
    let mut s = Scenario::from_json(&format!(
        r#"{{ "robot": {{ "preset": "lwr4" }}, "q0": [0.0, 0.6, 0.0, -1.2, 0.0, 0.6, 0.0],
             "obstacles": [{{ "id": "ball", "shape": {{ "type": "sphere", "center": {c:?}, "radius": 0.08 }},
                              "motion": {motion} }}],
             "dt": 0.001, "duration": 1.0 }}"#
    ))
    .unwrap();
    s.controller.repulsion_gain = 0.0;
    s.controller.protective.enabled = false;
    s
}

const BALL: DVec3 = DVec3::new(-0.2259, 0.3, 0.6406);

/// The unit direction from the arm towards the ball at its start.
fn towards_ball() -> DVec3 {
    let mut w = World::new(still_arm(BALL, r#"{ "type": "static" }"#)).unwrap();
    w.step(0.001);
    let p = &w.control_points()[0];
    (DVec3::from_array(p.witness) - DVec3::from_array(p.position)).normalize()
}

#[test]
fn time_to_collision_of_a_sphere_approaching_a_still_arm_is_clearance_over_speed() {
    let v = -0.2 * towards_ball();
    let mut s = still_arm(
        BALL,
        &format!(r#"{{ "type": "linear", "velocity": {:?} }}"#, v.to_array()),
    );
    s.duration = 0.5;
    let mut w = World::new(s).unwrap();
    let mut checked = 0;
    for k in 0..500 {
        w.step(0.001);
        let state = w.state();
        if k < 100 {
            continue;
        }
        let d = state.control_points[0].distance;
        let ttc = state.time_to_collision.expect("closing in");
        let expected = d / 0.2;
        assert!(
            (ttc / expected - 1.0).abs() < 0.05,
            "t = {}: ttc {ttc}, clearance / 0.2 = {expected}",
            state.t
        );
        checked += 1;
    }
    assert_eq!(checked, 400);
    assert!(
        !w.state()
            .events
            .iter()
            .any(|e| matches!(e.kind, EventKind::TransitionTooSlow { .. }))
    );
}

#[test]
fn no_transition_too_slow_with_static_exactly_sensed_obstacles_in_any_example() {
    for name in EXAMPLE_NAMES {
        let mut s = scenario::example(name).unwrap();
        s.sensing = SensingConfig::default();
        for o in &mut s.obstacles {
            o.motion = None;
            // A human's limbs hold still too.
            if let ShapeSpec::Human(h) = &mut o.shape {
                h.animation = None;
            }
        }
        let trace = simulate(&s).unwrap();
        let slow: Vec<_> = trace
            .events
            .iter()
            .filter(|e| matches!(e.kind, EventKind::TransitionTooSlow { .. }))
            .collect();
        assert!(slow.is_empty(), "{name}: {slow:?}");
    }
}

#[test]
fn latency_shows_the_true_pose_of_latency_seconds_ago() {
    let v = -0.2 * towards_ball();
    let motion = format!(r#"{{ "type": "linear", "velocity": {:?} }}"#, v.to_array());
    let exact = still_arm(BALL, &motion);
    let mut late = exact.clone();
    late.sensing.default = Some(SensingSpec {
        latency: Some(0.1),
        ..SensingSpec::default()
    });
    let (mut a, mut b) = (World::new(exact).unwrap(), World::new(late).unwrap());
    let (mut da, mut db) = (Vec::new(), Vec::new());
    for _ in 0..400 {
        a.step(0.001);
        b.step(0.001);
        da.push(a.control_points()[0].distance);
        db.push(b.control_points()[0].distance);
    }
    for k in 100..400 {
        assert!(
            (db[k] - da[k - 100]).abs() < 1e-9,
            "step {k}: {} vs {}",
            db[k],
            da[k - 100]
        );
    }
    // the margin is latency × speed
    let u = &b.state().uncertainty;
    assert!((u[0].radius - 0.1 * 0.2).abs() < 1e-9, "{u:?}");
}

fn noisy() -> Scenario {
    let mut s = scenario::example("lwr4-elbow").unwrap();
    s.duration = 1.0;
    s.sensing.default = Some(SensingSpec {
        bias_bound: Some(0.01),
        sigma: Some(0.001),
        correlated_sigma: Some(0.003),
        correlation_time: Some(0.05),
        latency: Some(0.02),
        ..SensingSpec::default()
    });
    s
}

/// Pinned: the same natively and in wasm (this test runs in both).
// (The hash covers every number of the trace that `common::trace_hash`
// reads, positions and DH values of control points included.)
const NOISY_HASH: u64 = 0x0f42_3087_6091_30c0;

#[test]
fn every_sensing_model_is_reproducible_natively_and_in_wasm() {
    let a = simulate(&noisy()).unwrap();
    assert_eq!(a, simulate(&noisy()).unwrap());
    let mut other = noisy();
    if let Some(d) = &mut other.sensing.default {
        d.seed = Some(99);
    }
    assert_ne!(a, simulate(&other).unwrap());
    let h = trace_hash(&a);
    assert_eq!(h, NOISY_HASH, "hash {h:#x}");
}

#[test]
fn bad_sensing_values_are_refused_with_the_json_path() {
    for (field, value) in [
        ("bound", "-1"),
        ("biasBound", "-0.1"),
        ("sigma", "-1e-3"),
        ("correlatedSigma", "-1"),
        ("correlationTime", "-0.5"),
        ("latency", "-0.01"),
    ] {
        let json = format!(
            r#"{{ "robot": {{ "preset": "planar3" }}, "q0": [0, 0, 0],
                 "obstacles": [{{ "id": "b", "shape": {{ "type": "sphere", "center": [1, 1, 0], "radius": 0.1 }} }}],
                 "sensing": {{ "b": {{ "{field}": {value} }} }}, "dt": 0.001, "duration": 1 }}"#
        );
        let e = Scenario::from_json(&json).unwrap_err().to_string();
        assert!(e.contains(&format!("sensing.b.{field}")), "{field}: {e}");
    }
}
