//! The protective layer against an articulated human: every part's own
//! velocity enters the guards and the time to collision. A hand reaching at
//! 2 m/s towards the Panda's forearm and a person walking by at 1.6 m/s
//! with swinging arms: no contact begins while the arm moves, every joint
//! within its limits, and the protective distance sized by the hand's
//! speed, not the body's. Runs natively and, unchanged, under
//! `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::DVec3;
use skeleton_avoidance::scenario::{Scenario, audit};
use skeleton_avoidance::skeleton::Skeleton;
use skeleton_avoidance::world::{World, simulate};

const Q0: [f64; 7] = [0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8];

fn check(name: &str, scenario: &Scenario) {
    let robot = scenario.build_robot().unwrap();
    let mut s = scenario.clone();
    s.sample_every = 1;
    let trace = simulate(&s).unwrap();
    let a = audit(&robot, &trace);
    eprintln!("{name}: {a:?}");
    assert!(a.admissible(), "{name}: {a:?}");
}

/// The middle of the Panda's forearm (the longest segment of link 5) at
/// `Q0`.
fn forearm_middle() -> DVec3 {
    let s: Scenario = serde_json::from_value(serde_json::json!({
        "robot": { "preset": "panda" }, "obstacles": [], "dt": 0.002, "duration": 1.0
    }))
    .unwrap();
    let robot = s.build_robot().unwrap();
    let frames = robot.forward(&Q0).unwrap();
    let sk = Skeleton::build(&robot, &frames);
    let seg = sk
        .segments
        .iter()
        .filter(|g| g.link == 5)
        .max_by(|a, b| {
            let len = |g: &skeleton_avoidance::skeleton::Segment| {
                let (p, q) = sk.endpoints(g);
                (q - p).length()
            };
            len(a).total_cmp(&len(b))
        })
        .unwrap();
    let (a, b) = sk.endpoints(seg);
    0.5 * (a + b)
}

fn reaching_scenario() -> Scenario {
    let target = forearm_middle();
    // The person stands in front of the arm, bent forward a little, and
    // reaches with the right hand (peak speed 2 m/s) for the forearm.
    let position = target + DVec3::new(0.75, -0.15, 0.0);
    serde_json::from_value(serde_json::json!({
        "robot": { "preset": "panda" },
        "q0": Q0,
        "obstacles": [{
            "id": "person",
            "shape": {
                "type": "human", "position": [position.x, position.y, 0.0],
                "heading": std::f64::consts::PI, "height": 1.75,
                "pose": { "spineFlexion": 0.5 },
                "animation": { "clip": "reach", "target": target.to_array(), "speed": 2.0,
                               "side": "right", "start": 0.3 }
            }
        }],
        "controller": { "influenceDistance": 0.35 },
        "dt": 0.002,
        "duration": 2.0
    }))
    .unwrap()
}

#[test]
fn a_hand_reaching_at_2_m_s_sizes_the_protective_distance_by_its_own_speed() {
    let s = reaching_scenario();
    let mut w = World::new(s.clone()).unwrap();
    let p = s.controller.protective;
    let mut fastest: Option<(f64, String, f64)> = None;
    let mut body_parts_seen = 0;
    let mut witnessed = false;
    while w.time() < 1.2 {
        w.step(s.dt);
        for g in w.guarded() {
            let part = g.part.clone().unwrap_or_default();
            // The body does not move (no obstacle motion): every speed is
            // a part's own.
            let arm = [
                "person:rightUpperArm",
                "person:rightForearm",
                "person:rightHand",
            ];
            if !arm.contains(&part.as_str()) {
                assert!(
                    g.approach_speed.abs() < 1e-12,
                    "{part}: {}",
                    g.approach_speed
                );
                body_parts_seen += 1;
            }
            let reaction = p.reaction_time;
            assert!(
                g.protective_distance >= p.safety_distance + g.approach_speed.max(0.0) * reaction
            );
            if fastest.as_ref().is_none_or(|f| g.approach_speed > f.0) {
                fastest = Some((g.approach_speed, part, g.protective_distance));
            }
        }
        let st = w.state();
        witnessed |= st.control_points.iter().any(|c| {
            c.part
                .as_deref()
                .is_some_and(|n| n.starts_with("person:right"))
        });
    }
    let (speed, part, protective) = fastest.unwrap();
    eprintln!(
        "fastest approach {speed:.3} m/s by {part}, protective distance {protective:.4} m; body parts guarded {body_parts_seen}"
    );
    assert!(
        part == "person:rightHand" || part == "person:rightForearm",
        "{part}"
    );
    // The hand closes in at well over a walking body's speed, and the
    // protective distance grows with it.
    assert!(speed > 1.2 && speed < 2.6, "{speed}");
    assert!(protective > p.safety_distance + speed * p.reaction_time);
    assert!(witnessed, "a control point names the reaching arm's part");
    assert!(body_parts_seen > 0, "the still body was guarded too");
}

#[test]
fn a_hand_reaching_for_the_forearm_starts_no_contact_while_the_arm_moves() {
    check("reach at 2 m/s", &reaching_scenario());
}

#[test]
fn a_person_walking_by_with_swinging_arms_starts_no_contact_while_the_arm_moves() {
    let s: Scenario = serde_json::from_value(serde_json::json!({
        "robot": { "preset": "panda" },
        "q0": Q0,
        "obstacles": [{
            "id": "person",
            "shape": {
                "type": "human", "position": [0.85, -2.4, 0.0],
                "heading": std::f64::consts::FRAC_PI_2, "height": 1.75,
                "animation": { "clip": "walk", "speed": 1.6 }
            },
            "motion": { "type": "linear", "velocity": [0.0, 1.6, 0.0] }
        }],
        "task": {
            "type": "trajectory",
            "points": [[0.4737, 0.0, 0.5155], [0.45, 0.25, 0.45], [0.45, -0.25, 0.45], [0.4737, 0.0, 0.5155]],
            "times": [0, 1, 2, 3]
        },
        "controller": { "influenceDistance": 0.35 },
        "dt": 0.002,
        "duration": 3.0
    }))
    .unwrap();
    check("walk by at 1.6 m/s", &s);
    // The swinging arm is what comes closest, and it is named: the state's
    // `closestHuman` is the part at the person's nearest control point, at
    // the same clearance (between transitions), even while two of the arm's own links are closer
    // (the Panda's folded wrist is 8 cm from its upper arm at `Q0`), when
    // `closestPart` names no human part.
    let mut w = World::new(s.clone()).unwrap();
    let mut closest = Vec::new();
    let mut behind_self = 0;
    while w.time() < 3.0 {
        w.step(s.dt);
        let state = w.state();
        let nearest = state
            .control_points
            .iter()
            .filter(|c| c.obstacle == "person")
            .min_by(|a, b| a.distance.total_cmp(&b.distance));
        let Some(cp) = nearest else { continue };
        let human = state.closest_human.as_ref().expect("closestHuman");
        // No point of the arm is closer than the closest pair; a control
        // point on its way to a new segment may be farther.
        assert!(human.distance <= cp.distance + 1e-9, "t {}", state.t);
        if !cp.transitioning {
            assert_eq!(Some(&human.part), cp.part.as_ref(), "t {}", state.t);
            assert!((human.distance - cp.distance).abs() < 1e-9, "t {}", state.t);
        }
        assert!(human.distance >= state.min_clearance.unwrap() - 1e-12);
        if state.closest_part.is_none() {
            behind_self += 1;
        }
        closest.push(human.part.clone());
    }
    assert!(behind_self > 0, "the arm's own links were never closer");
    assert!(
        closest
            .iter()
            .any(|p| p.contains("Hand") || p.contains("Arm") || p.contains("Forearm")),
        "{closest:?}"
    );
}
