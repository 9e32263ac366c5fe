//! The protective side of the `constraints` avoidance: escape when the
//! joints can outrun an obstacle, stop when they cannot (contact at rest),
//! back out of an overlap, leave out self pairs no joint can change, and
//! refuse bad settings with the field named. Runs natively and, unchanged,
//! under `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use skeleton_avoidance::dependability::EventKind;
use skeleton_avoidance::kinematics::{LinkRef, Robot};
use skeleton_avoidance::parsers::urdf::{UrdfOptions, robot_from_urdf};
use skeleton_avoidance::scenario::{MotionAudit, Scenario, audit};
use skeleton_avoidance::world::{World, simulate};

const UR5: &str = include_str!("data/urdf/ur5_robot.urdf");
const PANDA: &str = include_str!("data/urdf/panda_collision.urdf");
const READY: &str = "[0.0, -0.785398, 0.0, -2.356194, 0.0, 1.570796, 0.785398]";

fn run(json: &str) -> (MotionAudit, Vec<EventKind>, Vec<f64>) {
    let mut s = Scenario::from_json(json).unwrap();
    s.sample_every = 1;
    let robot = s.build_robot().unwrap();
    let trace = simulate(&s).unwrap();
    let last = trace.samples.last().unwrap().q.clone();
    (
        audit(&robot, &trace),
        trace.events.into_iter().map(|e| e.kind).collect(),
        last,
    )
}

fn unavoidable(events: &[EventKind]) -> usize {
    events
        .iter()
        .filter(|e| matches!(e, EventKind::Unavoidable { .. }))
        .count()
}

/// A ball approaching the Panda's forearm at 0.3 m/s (faster than the
/// repulsion alone would clear it): the arm gets out of the way, with no
/// stop and no contact.
#[test]
fn a_ball_the_joints_can_outrun_is_evaded_without_a_stop() {
    let json = format!(
        r#"{{ "robot": {{ "preset": "panda" }}, "q0": {READY},
             "obstacles": [{{ "id": "ball", "shape": {{ "type": "sphere", "center": [0.03, -0.7, 0.697], "radius": 0.05 }},
                             "motion": {{ "type": "linear", "velocity": [0, 0.3, 0] }} }}],
             "dt": 0.002, "duration": 3.0 }}"#
    );
    let (a, events, _) = run(&json);
    eprintln!("evade 0.3 m/s: {a:?} {} unavoidable", unavoidable(&events));
    assert!(a.admissible(), "{a:?}");
    assert!(a.clearance > 0.0, "{a:?}");
    assert_eq!(unavoidable(&events), 0, "{events:?}");
}

/// A 5 cm ball at 1 m/s straight at the elbow: no admissible escape; the
/// arm stops (`unavoidable`) and is at rest when contact begins.
#[test]
fn a_ball_faster_than_any_escape_stops_the_arm_before_contact() {
    let json = format!(
        r#"{{ "robot": {{ "preset": "panda" }}, "q0": {READY},
             "obstacles": [{{ "id": "ball", "shape": {{ "type": "sphere", "center": [-0.19, -0.6, 0.6], "radius": 0.05 }},
                             "motion": {{ "type": "linear", "velocity": [0, 1.0, 0] }} }}],
             "dt": 0.002, "duration": 1.5 }}"#
    );
    let (a, events, _) = run(&json);
    eprintln!("1 m/s at the elbow: {a:?}");
    assert!(a.admissible(), "{a:?}");
    assert!(unavoidable(&events) >= 1, "{events:?}");
}

/// A box overlapping the forearm at the start: a `startContact` event names
/// the pair, and the arm backs out at no more than the withdraw speed until
/// it is clear, instead of freezing.
#[test]
fn an_obstacle_overlapping_the_arm_at_the_start_is_backed_out_of() {
    let json = format!(
        r#"{{ "robot": {{ "preset": "panda" }}, "q0": {READY},
             "obstacles": [{{ "id": "crate", "shape": {{ "type": "box", "center": [0.03, 0.0, 0.79], "halfExtents": [0.1, 0.1, 0.05] }} }}],
             "dt": 0.002, "duration": 4.0 }}"#
    );
    let (a, events, _) = run(&json);
    let start: Vec<&EventKind> = events
        .iter()
        .filter(|e| matches!(e, EventKind::StartContact { .. }))
        .collect();
    eprintln!("overlap at start: {a:?} {start:?}");
    assert_eq!(start.len(), 1, "{events:?}");
    assert!(
        matches!(start[0], EventKind::StartContact { obstacle, distance, .. } if obstacle == "crate" && *distance < 0.0)
    );
    assert!(a.admissible(), "{a:?}");
    let s = Scenario::from_json(&json).unwrap();
    let mut w = World::new(s).unwrap();
    for _ in 0..2000 {
        w.step(0.002);
    }
    let c = w.state().min_clearance.unwrap();
    assert!(c > 0.0, "still inside after 4 s: {c}");
    assert_eq!(unavoidable(&events), 0, "{events:?}");
}

/// The UR5 imported from its URDF, a ball closing in at 0.1 m/s: no self
/// pair freezes the arm, it clears the ball.
#[test]
fn the_urdf_ur5_clears_a_slow_ball() {
    let spec = robot_from_urdf(
        UR5,
        &UrdfOptions {
            tip: Some("ee_link".into()),
            ..UrdfOptions::default()
        },
    )
    .unwrap();
    let robot = Robot::from_spec(&spec).unwrap();
    let q0 = [0.0, -1.2, 1.6, -1.9, -1.57, 0.0];
    let f = robot.forward(&q0).unwrap();
    // Towards the middle of the forearm (frames 2 to 3), from 0.4 m above.
    let mid = (f.transforms[2].translation + f.transforms[3].translation) * 0.5;
    let json = format!(
        r#"{{ "robot": {}, "q0": {q0:?},
             "obstacles": [{{ "id": "ball", "shape": {{ "type": "sphere", "center": [{}, {}, {}], "radius": 0.05 }},
                             "motion": {{ "type": "linear", "velocity": [0, 0, -0.1] }} }}],
             "dt": 0.002, "duration": 6.0 }}"#,
        serde_json::to_string(&spec).unwrap(),
        mid.x,
        mid.y,
        mid.z + 0.4
    );
    let (a, events, _) = run(&json);
    eprintln!("UR5 URDF, ball at 0.1 m/s: {a:?}");
    assert!(a.admissible() && a.clearance > 0.0, "{a:?}");
    assert_eq!(unavoidable(&events), 0, "{events:?}");
}

/// An SRDF's `disable_collisions` between links of the chain becomes the
/// spec's exclusions (links outside the chain and repeats change nothing).
#[test]
fn an_srdf_disables_self_pairs_by_link_name() {
    let srdf = r#"<robot name="panda">
        <disable_collisions link1="panda_link1" link2="panda_link4" reason="Never"/>
        <disable_collisions link1="panda_link4" link2="panda_link1" reason="Never"/>
        <disable_collisions link1="panda_link2" link2="panda_hand_far_away" reason="Never"/>
        <disable_collisions link1="panda_link3" link2="panda_link7" reason="Default"></disable_collisions>
      </robot>"#;
    let options = UrdfOptions {
        tip: Some("panda_link8".into()),
        srdf: Some(srdf.into()),
        ..UrdfOptions::default()
    };
    let spec = robot_from_urdf(PANDA, &options).unwrap();
    assert_eq!(
        spec.self_collision_exclude,
        vec![
            [LinkRef::Index(1), LinkRef::Index(4)],
            [LinkRef::Index(3), LinkRef::Index(7)]
        ]
    );
    assert_eq!(spec.link_names.as_ref().unwrap()[0], "panda_link1");
    let bad = UrdfOptions {
        srdf: Some("<robot><disable_collisions link1=\"a\"/></robot>".into()),
        ..options.clone()
    };
    let e = robot_from_urdf(PANDA, &bad).unwrap_err().to_string();
    assert!(e.contains("srdf") && e.contains("link2"), "{e}");
    let e = robot_from_urdf(
        PANDA,
        &UrdfOptions {
            srdf: Some("<robot><x".into()),
            ..options
        },
    )
    .unwrap_err();
    assert!(e.to_string().starts_with("srdf"), "{e}");
}

/// Bad settings are refused with the field named, and a refused controller
/// edit leaves the world as it was.
#[test]
fn bad_exclusions_bands_and_modes_are_refused_with_the_field_named() {
    let base = format!(
        r#"{{ "robot": {{ "preset": "panda" }}, "q0": {READY}, "obstacles": [], "dt": 0.002, "duration": 1.0, "controller": "#
    );
    let err = |c: &str| {
        let s = Scenario::from_json(&format!("{base}{c} }}"));
        match s {
            Err(e) => e.to_string(),
            Ok(s) => s.validate().unwrap_err().to_string(),
        }
    };
    let e = err(r#"{ "selfCollisionExclude": [[1, 9]] }"#);
    assert!(
        e.starts_with("controller.selfCollisionExclude[0][1]") && e.contains("9 is not a link"),
        "{e}"
    );
    let e = err(r#"{ "selfCollisionExclude": [[1, 4], [4, 1]] }"#);
    assert!(
        e.starts_with("controller.selfCollisionExclude[1]") && e.contains("twice"),
        "{e}"
    );
    let e = err(r#"{ "selfCollisionExclude": [["panda_link1", 4]] }"#);
    assert!(
        e.contains("[0][0]") && e.contains("no link named \"panda_link1\""),
        "{e}"
    );
    let e = err(r#"{ "safetyBand": 0.3 }"#);
    assert!(
        e.starts_with("controller.safetyBand") && e.contains("influenceDistance"),
        "{e}"
    );
    let e = err(r#"{ "avoidance": "magnets" }"#);
    assert!(e.contains("avoidance") && e.contains("constraints"), "{e}");
    let s = Scenario::from_json(&format!("{base}{{}} }}")).unwrap();
    let mut w = World::new(s).unwrap();
    let before = serde_json::to_string(w.scenario()).unwrap();
    let mut c = w.scenario().controller.clone();
    c.self_collision_exclude = vec![[LinkRef::Index(2), LinkRef::Index(2)]];
    assert!(
        w.set_controller(c)
            .unwrap_err()
            .to_string()
            .contains("itself")
    );
    assert_eq!(serde_json::to_string(w.scenario()).unwrap(), before);
}

/// An oscillating command is caught like a chattering control point: a
/// goal that jumps 0.2 m back and forth every 0.2 s for 3 s makes joints
/// reverse faster than the monitor allows; the arm stops.
#[test]
fn an_oscillating_command_is_caught_by_the_monitor() {
    let points: Vec<String> = (0..16)
        .map(|k| format!("[0.3, {}, 0.59]", if k % 2 == 0 { 0.1 } else { -0.1 }))
        .collect();
    let times: Vec<String> = (0..16)
        .map(|k| format!("{:.1}", 0.2 * f64::from(k)))
        .collect();
    let json = format!(
        r#"{{ "robot": {{ "preset": "panda" }}, "q0": {READY}, "obstacles": [],
             "task": {{ "type": "trajectory", "points": [{}], "times": [{}] }},
             "dt": 0.002, "duration": 3.5 }}"#,
        points.join(", "),
        times.join(", ")
    );
    let (a, events, _) = run(&json);
    assert!(a.admissible(), "{a:?}");
    assert!(
        events.iter().any(|e| matches!(e, EventKind::Chattering { obstacle, .. } if obstacle.starts_with("command:"))),
        "{events:?}"
    );
}

/// An obstacle moved by edits (a drag in the playground, a sensor feed
/// through `moveObstacle`) is seen at the speed it is moved: a ball pushed
/// towards the planar arm's second link at 0.3 m/s, one edit every 16 ms,
/// and left 1 cm from it: the arm gives way as it comes, no contact.
#[test]
fn an_obstacle_moved_by_edits_is_seen_moving() {
    let json = r#"{ "robot": { "preset": "planar3" }, "q0": [0.3, 0.5, 0.4],
        "obstacles": [{ "id": "ball", "shape": { "type": "sphere", "center": [0.3, -0.55, 0], "radius": 0.05 } }],
        "task": { "type": "hold" }, "dt": 0.001, "duration": 10 }"#;
    let s = Scenario::from_json(json).unwrap();
    let robot = s.build_robot().unwrap();
    let mut w = World::new(s).unwrap();
    let mut trace = skeleton_avoidance::scenario::Trace::default();
    let start = glam::DVec3::new(0.3, -0.55, 0.0);
    // Towards the middle of link 2 (frames 1 to 2), stopping 0.11 m from it.
    let f = w.frames().clone();
    let mid = (f.transforms[1].translation + f.transforms[2].translation) * 0.5;
    let goal = mid - glam::DVec3::new(0.0, 0.11, 0.0);
    let travel = goal - start;
    let moves = (travel.length() / 0.3 / 0.016).ceil() as usize;
    for k in 0..moves + 60 {
        if k < moves {
            w.set_obstacle_position("ball", start + travel * ((k + 1) as f64 / moves as f64))
                .unwrap();
        }
        for _ in 0..16 {
            w.step(0.001);
            trace.samples.push(w.sample());
        }
    }
    let a = audit(&robot, &trace);
    eprintln!("dragged ball: {a:?}");
    assert!(a.admissible() && a.clearance > 0.0, "{a:?}");
}

/// A ball dragged into the arm faster than it can give way: the arm stops
/// (contact at rest), and once the drag is over it resumes and backs out;
/// it is not left stopped.
#[test]
fn a_ball_dropped_onto_the_arm_is_backed_out_of_after_the_stop() {
    let json = r#"{ "robot": { "preset": "planar3" }, "q0": [0.3, 0.5, 0.4],
        "obstacles": [{ "id": "ball", "shape": { "type": "sphere", "center": [0.3, -0.55, 0], "radius": 0.05 } }],
        "task": { "type": "hold" }, "controller": { "influenceDistance": 0.15 }, "dt": 0.001, "duration": 10 }"#;
    let s = Scenario::from_json(json).unwrap();
    let robot = s.build_robot().unwrap();
    let mut w = World::new(s).unwrap();
    let f = w.frames().clone();
    let mid = (f.transforms[1].translation + f.transforms[2].translation) * 0.5;
    let (start, goal) = (
        glam::DVec3::new(0.3, -0.55, 0.0),
        mid - glam::DVec3::new(0.0, 0.11, 0.0),
    );
    let mut trace = skeleton_avoidance::scenario::Trace::default();
    for k in 1..=12 {
        w.set_obstacle_position("ball", start + (goal - start) * (f64::from(k) / 12.0))
            .unwrap();
        for _ in 0..2 {
            w.step(0.001);
            trace.samples.push(w.sample());
        }
    }
    for _ in 0..1500 {
        w.step(0.001);
        trace.samples.push(w.sample());
    }
    let a = audit(&robot, &trace);
    let end = w.state();
    assert!(a.admissible(), "{a:?}");
    assert!(
        !end.stopped && end.min_clearance.unwrap() > 0.0,
        "stopped {} clearance {:?}",
        end.stopped,
        end.min_clearance
    );
}
