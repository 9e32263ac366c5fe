//! A person streamed frame by frame (`World::push_human_frame`): the same
//! motion as an imported track with the same latency gives the same trace,
//! bad frames are refused naming the field with the world unchanged, and a
//! dropout grows the parts' margins at ISO 13855's speeds while the arm
//! keeps clear of the grown region.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::DVec3;
use serde_json::{Value, json};
use skeleton_avoidance::human::HumanSpec;
use skeleton_avoidance::human::track::{TrackOptions, import};
use skeleton_avoidance::parsers::track::Layout;
use skeleton_avoidance::scenario::{Scenario, ShapeSpec};
use skeleton_avoidance::world::{HAND_SPEED, HumanFrame, World};

#[path = "common/kinect2.rs"]
mod kinect2;
use kinect2::KINECT2;

/// The Kinect "come here" recording as `kinect32` frames in the robot's
/// world: z up, turned to face −x, standing on the floor 0.95 m in front
/// of the arm; a joint the tracker lost holds its last position (so that
/// the track and the stream see the same keypoints).
fn frames() -> Vec<HumanFrame> {
    let csv = include_str!("data/recordings/kinect2-Ges04_comehere.csv");
    let names = Layout::Kinect32.names();
    let mut out: Vec<HumanFrame> = Vec::new();
    let mut t0 = None;
    let mut held = vec![[0.0; 3]; names.len()];
    for line in csv.lines().filter(|l| !l.trim().is_empty()) {
        let cells: Vec<f64> = line
            .split(',')
            .filter(|c| !c.trim().is_empty())
            .map(|c| c.trim().parse().unwrap())
            .collect();
        let t = (cells[0] - *t0.get_or_insert(cells[0])) / 1e7;
        for (j, name) in KINECT2 {
            let v = &cells[1 + 4 * j..5 + 4 * j];
            if v[3] > 0.0 || out.is_empty() {
                // Kinect camera space (y up) → z up.
                let slot = names.iter().position(|n| *n == name).unwrap();
                held[slot] = [v[0], -v[2], v[1]];
            }
        }
        out.push(HumanFrame {
            t,
            layout: "kinect32".into(),
            keypoints: held.clone(),
            confidence: None,
        });
    }
    // Faces +y (towards the sensor): turn by −π/2 about the first pelvis to
    // face −x, then stand it at (0.95, 0, floor 0).
    let pelvis = DVec3::from_array(out[0].keypoints[0]);
    let floor = out[0].keypoints[20][2].min(out[0].keypoints[24][2]) - 0.06;
    for f in &mut out {
        for p in &mut f.keypoints {
            let d = DVec3::from_array(*p) - pelvis;
            let turned = DVec3::new(d.y, -d.x, d.z);
            *p = (turned + DVec3::new(0.95, 0.0, pelvis.z - floor)).to_array();
        }
    }
    out
}

fn track_json(frames: &[HumanFrame]) -> String {
    let fs: Vec<Value> = frames
        .iter()
        .map(|f| json!({ "t": f.t, "keypoints": f.keypoints }))
        .collect();
    json!({ "layout": "kinect32", "frames": fs }).to_string()
}

/// The panda sweeping its hand across in front of the person, who is seen
/// `latency` late.
fn scenario(person: &HumanSpec, latency: f64) -> Scenario {
    let text = json!({
        "robot": { "preset": "panda" },
        "q0": [0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8],
        "obstacles": [{ "id": "person", "shape": { "type": "human", "position": [1, 0, 0] } }],
        "task": { "type": "trajectory",
                  "points": [[0.55, 0.0, 0.75], [0.6, 0.35, 0.9], [0.6, -0.35, 0.9], [0.55, 0.0, 0.75]],
                  "times": [0, 2, 4, 5.5] },
        "controller": { "influenceDistance": 0.35 },
        "sensing": { "person": { "latency": latency } },
        "dt": 0.01,
        "duration": 5.5
    });
    let mut s = Scenario::from_json(&text.to_string()).unwrap();
    s.obstacles[0].shape = ShapeSpec::Human(person.clone());
    s
}

fn imported(frames: &[HumanFrame]) -> HumanSpec {
    let options = TrackOptions {
        smoothing: 0.0,
        ..TrackOptions::default()
    };
    import(&track_json(frames), &options).unwrap().shape
}

/// The same body standing still (the stream will move it).
fn still(shape: &HumanSpec) -> HumanSpec {
    HumanSpec {
        animation: None,
        ..shape.clone()
    }
}

fn sample_text(w: &World) -> String {
    serde_json::to_string(&w.sample()).unwrap()
}

#[test]
fn a_streamed_recording_moves_the_arm_exactly_as_the_same_track() {
    let frames = frames();
    let shape = imported(&frames);
    let latency = 0.15;
    let mut track = World::new(scenario(&shape, latency)).unwrap();
    let mut stream = World::new(scenario(&still(&shape), latency)).unwrap();
    let dt = 0.01;
    let (mut next, mut closest) = (0, f64::INFINITY);
    for k in 0..550 {
        // Every frame seen by now is pushed (the sensor's own delay is the
        // configured latency).
        let now = f64::from(k) * dt;
        while next < frames.len() && frames[next].t <= now + 1e-12 {
            stream.push_human_frame("person", &frames[next]).unwrap();
            next += 1;
        }
        assert_eq!(sample_text(&track), sample_text(&stream), "step {k}");
        let state = |w: &World| serde_json::to_string(&w.state().control_points).unwrap();
        assert_eq!(state(&track), state(&stream), "control points at step {k}");
        closest = closest.min(track.clearance_of("person").unwrap());
        track.step(dt);
        stream.step(dt);
    }
    assert_eq!(track.events(), stream.events());
    eprintln!("closest approach to the person: {closest:.3} m");
    assert!(
        closest < 0.35,
        "the arm passes within the influence distance"
    );
}

fn refused(w: &mut World, id: &str, frame: &HumanFrame) -> String {
    let before = (sample_text(w), format!("{:?}", w.scenario()));
    let e = w.push_human_frame(id, frame).unwrap_err().to_string();
    assert_eq!(
        before,
        (sample_text(w), format!("{:?}", w.scenario())),
        "{e}"
    );
    e
}

#[test]
fn bad_frames_are_refused_naming_the_field_and_the_world_is_unchanged() {
    let frames = frames();
    let shape = imported(&frames);
    let mut w = World::new(scenario(&still(&shape), 0.0)).unwrap();
    w.push_human_frame("person", &frames[1]).unwrap();
    let good = frames[2].clone();
    let with = |f: &dyn Fn(&mut HumanFrame)| {
        let mut x = good.clone();
        f(&mut x);
        x
    };
    let cases: Vec<(&str, HumanFrame, &str)> = vec![
        ("nobody", good.clone(), "obstacleId: no obstacle \"nobody\""),
        (
            "person",
            with(&|f| f.t = frames[0].t),
            "frame.t: must be after",
        ),
        (
            "person",
            with(&|f| f.t = frames[1].t),
            "frame.t: must be after",
        ),
        ("person", with(&|f| f.t = f64::NAN), "frame.t"),
        (
            "person",
            with(&|f| f.keypoints[3][1] = f64::NAN),
            "frame.keypoints[3][1]",
        ),
        (
            "person",
            with(&|f| f.keypoints[5][2] = f64::INFINITY),
            "frame.keypoints[5][2]",
        ),
        (
            "person",
            with(&|f| f.keypoints.pop().map_or((), drop)),
            "frame.keypoints: expected 32 keypoints",
        ),
        (
            "person",
            with(&|f| f.layout = "coco18".into()),
            "frame.layout: unknown layout",
        ),
        (
            "person",
            with(&|f| f.keypoints = vec![[0.0; 3]; 10_001]),
            "frame.keypoints: at most 10000",
        ),
        (
            "person",
            with(&|f| f.confidence = Some(vec![1.0; 3])),
            "frame.confidence: expected one per keypoint",
        ),
        (
            "person",
            with(&|f| f.confidence = Some(vec![1.5; 32])),
            "frame.confidence[0]: must be in [0, 1]",
        ),
    ];
    for (id, frame, expected) in cases {
        let e = refused(&mut w, id, &frame);
        assert!(e.starts_with(expected), "{e}");
    }
    // A primitive is not a person.
    let mut s = scenario(&still(&shape), 0.0);
    s.obstacles[0].shape =
        serde_json::from_value(json!({ "type": "sphere", "center": [1, 0, 1], "radius": 0.1 }))
            .unwrap();
    let mut ball = World::new(s).unwrap();
    let e = refused(&mut ball, "person", &good);
    assert!(
        e.starts_with("obstacleId: \"person\" is not a human"),
        "{e}"
    );
    // BlazePose's 33 landmarks are a layout.
    let e = refused(
        &mut w,
        "person",
        &with(&|f| f.layout = "blazepose33".into()),
    );
    assert!(
        e.starts_with("frame.keypoints: expected 33 keypoints (blazepose33)"),
        "{e}"
    );
}

/// Largest joint speed now.
fn speed(w: &World) -> f64 {
    w.qdot().iter().fold(0.0, |m: f64, v| m.max(v.abs()))
}

#[test]
fn a_dropout_grows_the_hands_margin_at_two_metres_a_second_and_the_arm_keeps_clear() {
    let frames = frames();
    let shape = imported(&frames);
    let mut w = World::new(scenario(&still(&shape), 0.0)).unwrap();
    let dt = 0.01;
    let (mut next, mut last) = (0, 0.0);
    let mut checked = 0;
    let (mut stale_events, mut moving_steps) = (0, 0);
    for k in 0..550 {
        let now = f64::from(k) * dt;
        // Frames stop coming from 2.0 s to 2.5 s, and from 3.5 s on.
        let dropped = |t: f64| (2.0..2.5).contains(&t) || t >= 3.5;
        while next < frames.len() && frames[next].t <= now + 1e-12 {
            if !dropped(frames[next].t) {
                w.push_human_frame("person", &frames[next]).unwrap();
                last = frames[next].t;
            }
            next += 1;
        }
        // The arm keeps clear of the grown region while it moves.
        if speed(&w) > 1e-9 {
            moving_steps += 1;
            for p in w.guarded().iter().filter(|p| p.obstacle == "person") {
                assert!(
                    p.distance >= -1e-9,
                    "t {now}: {} {}",
                    p.part.clone().unwrap_or_default(),
                    p.distance
                );
            }
        }
        // Every joint within its limits.
        for ((q, v), joint) in w.q().iter().zip(w.qdot()).zip(&w.robot().joints) {
            assert!(
                *q >= joint.min - 1e-9 && *q <= joint.max + 1e-9,
                "t {now}: q {q}"
            );
            assert!(v.abs() <= joint.max_velocity + 1e-9, "t {now}: q̇ {v}");
        }
        w.step(dt);
        // The margins of the step at `now`.
        let state = w.state();
        let age = now - last;
        if age > 0.0 && k > 0 {
            let margins = state
                .uncertainty
                .iter()
                .find(|u| u.obstacle == "person")
                .and_then(|u| u.part_margins.clone())
                .expect("the stale person's part margins");
            let hand = margins["leftHand"];
            let expected = HAND_SPEED * age;
            assert!(
                (hand / expected - 1.0).abs() < 0.01,
                "t {now}: {hand} vs {expected}"
            );
            if (age - 0.5).abs() < 0.02 {
                checked += 1;
            }
        }
        stale_events = w
            .events()
            .iter()
            .filter(|e| {
                matches!(
                    e.kind,
                    skeleton_avoidance::dependability::EventKind::StaleSensing { .. }
                )
            })
            .count();
    }
    assert!(
        checked >= 1,
        "the hand's margin was checked at a 0.5 s dropout"
    );
    assert!(stale_events > 0 && moving_steps > 0);
}

/// Two camera stills lifted to metres by the person's height
/// (`web/keypoints.js`'s `liftCoco17` and `placeInWorld` for a 1.70 m
/// person 1 m in front of the arm, facing it, the left hand raised above
/// the head, the right one hanging): every keypoint in one vertical plane
/// but the arms', leaned towards the camera by what the image shortens (in
/// the first the upper arms lean further than the forearms, an elbow that
/// would bend backwards; in the second the raised arm is straight).
const RAISED_LEFT_HAND: [[[f64; 3]; 17]; 2] = [
    [
        [1.0, 0.0, 1.5321],
        [1.0, -0.0277, 1.5598],
        [1.0, 0.0277, 1.5598],
        [1.0, -0.0647, 1.5414],
        [1.0, 0.0647, 1.5414],
        [1.0, -0.1755, 1.3566],
        [1.0, 0.1755, 1.3566],
        [0.7725, -0.2309, 1.5691],
        [0.8065, 0.194, 1.1072],
        [0.7164, -0.2032, 1.8092],
        [0.7446, 0.2032, 0.867],
        [1.0, -0.0831, 0.867],
        [1.0, 0.0831, 0.867],
        [1.0, -0.0924, 0.479],
        [1.0, 0.0924, 0.479],
        [1.0, -0.0924, 0.1003],
        [1.0, 0.0924, 0.1003],
    ],
    [
        [1.0, 0.0, 1.5321],
        [1.0, -0.0277, 1.5598],
        [1.0, 0.0277, 1.5598],
        [1.0, -0.0647, 1.5414],
        [1.0, 0.0647, 1.5414],
        [1.0, -0.1755, 1.3566],
        [1.0, 0.1755, 1.3566],
        [0.833, -0.194, 1.6245],
        [0.8184, 0.1848, 1.0979],
        [0.833, -0.2032, 1.8832],
        [0.7565, 0.194, 0.8578],
        [1.0, -0.0831, 0.867],
        [1.0, 0.0831, 0.867],
        [1.0, -0.0924, 0.479],
        [1.0, 0.0924, 0.479],
        [1.0, -0.0924, 0.1003],
        [1.0, 0.0924, 0.1003],
    ],
];

#[test]
fn a_lifted_still_with_a_raised_hand_is_fitted_with_that_hand_raised() {
    // A person whose segments the first frame measures, and one of the
    // body's own proportions.
    let proportional = json!({ "upperArm": 0.3255, "forearm": 0.2555, "thigh": 0.42875,
        "shank": 0.4305, "shoulderWidth": 0.45325, "hipWidth": 0.175, "trunk": 0.504 });
    for (still, keypoints) in RAISED_LEFT_HAND.iter().enumerate() {
        for segments in [Value::Null, proportional.clone()] {
            let mut person =
                json!({ "type": "human", "position": [1, 0, 0], "heading": std::f64::consts::PI });
            if !segments.is_null() {
                person["segments"] = segments.clone();
            }
            let text = json!({
                "robot": { "preset": "panda" },
                "obstacles": [{ "id": "person", "shape": person }],
                "dt": 0.01,
                "duration": 1.0
            });
            let mut w = World::new(Scenario::from_json(&text.to_string()).unwrap()).unwrap();
            let frame = HumanFrame {
                t: 0.0,
                layout: "coco17".into(),
                keypoints: keypoints.to_vec(),
                confidence: None,
            };
            w.push_human_frame("person", &frame).unwrap();
            w.step(0.01);
            let state = w.state();
            let parts = &state.obstacles[0].parts;
            let wrist = |k: usize| match &parts[k] {
                skeleton_avoidance::distance::PrimitiveSpec::Capsule(c) => DVec3::from_array(c.a),
                other => panic!("{other:?}"),
            };
            // The hands' capsules start at the wrists (parts 6 and 9).
            let (left, right) = (wrist(6), wrist(9));
            let what = format!("still {still}, segments {segments}");
            for (got, want) in [(left, keypoints[9]), (right, keypoints[10])] {
                let off = (got - DVec3::from_array(want)).length();
                assert!(
                    off < 0.03,
                    "{what}: wrist {got} vs keypoint {want:?}: {off:.3} m"
                );
            }
            assert!(left.z > right.z + 0.3, "{what}: left {left}, right {right}");
        }
    }
}
