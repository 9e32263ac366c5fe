//! Picking a point of the skeleton with a ray (`World::pick_skeleton`), the
//! way the playground pins a control point: the point lies on the spine,
//! its DH values give back its position, misses and bad rays are told
//! apart, prismatic and branched robots included, and a picked point used
//! as `controller.pinned` becomes the control point. Runs natively and,
//! unchanged, under `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::DVec3;
use skeleton_avoidance::control_point::DhPoint;
use skeleton_avoidance::kinematics::presets::NAMES;
use skeleton_avoidance::scenario::Scenario;
use skeleton_avoidance::world::{PICK_RADIUS, SkeletonPick, World};

/// Round trips of DH values and positions agree to this (m).
const EXACT: f64 = 1e-9;

fn world_json(preset: &str, q0: &[f64], extra: &str) -> World {
    let q: Vec<String> = q0.iter().map(f64::to_string).collect();
    let text = format!(
        r#"{{ "robot": {{ "preset": "{preset}" }}, "q0": [{}], "obstacles": [], "dt": 0.001, "duration": 1 {extra} }}"#,
        q.join(", ")
    );
    let s: Scenario = serde_json::from_str(&text).unwrap();
    World::new(s).unwrap()
}

/// A configuration away from the zero pose (clamped to the limits by the world).
fn bent(n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| if k % 2 == 0 { 0.4 } else { -0.7 })
        .collect()
}

fn dof(preset: &str) -> usize {
    let spec = skeleton_avoidance::kinematics::presets::preset(preset).unwrap();
    let robot = skeleton_avoidance::kinematics::Robot::from_spec(&spec).unwrap();
    robot.dof()
}

/// Checks what every pick must satisfy and returns the point's DH values.
fn check_pick(world: &World, pick: &SkeletonPick) -> DhPoint {
    let robot = world.robot();
    let frames = world.frames();
    let skeleton = world.skeleton();
    let dh = DhPoint {
        link: pick.link,
        d: pick.d,
        a: pick.a,
    };
    dh.validate(robot, frames).unwrap();
    // DH values → position: the same point, by the control-point code.
    let p = DVec3::from_array(pick.position);
    let via_jacobians = dh.jacobians(robot, frames).position;
    assert!((via_jacobians - p).length() < EXACT, "{pick:?}");
    // DH values → skeleton → the same point (at a node, possibly on the
    // neighbouring segment of the same link).
    let (segment, t) = dh.to_skeleton(robot, frames, skeleton).unwrap();
    let (a, b) = skeleton.endpoints(&skeleton.segments[segment]);
    assert!((a + (b - a) * t - p).length() < EXACT, "{pick:?}");
    assert_eq!(skeleton.segments[segment].link, pick.link);
    assert_eq!(skeleton.segments[pick.segment].link, pick.link);
    assert!(pick.offset <= pick.radius + PICK_RADIUS + EXACT, "{pick:?}");
    assert!(pick.distance >= 0.0);
    dh
}

/// Unit vectors perpendicular to `v`, `count` of them around it.
fn around(v: DVec3, count: usize) -> Vec<DVec3> {
    let u = v.normalize();
    let e1 = u.any_orthonormal_vector();
    let e2 = u.cross(e1);
    (0..count)
        .map(|k| {
            let angle = std::f64::consts::TAU * k as f64 / count as f64;
            e1 * angle.cos() + e2 * angle.sin()
        })
        .collect()
}

#[test]
fn rays_at_every_segment_of_every_preset_pick_points_of_the_spine() {
    let mut exact_hits = 0;
    let mut segments = 0;
    let mut branch_links = 0;
    for preset in NAMES {
        let world = world_json(preset, &bent(dof(preset)), "");
        let skeleton = world.skeleton().clone();
        let main_dof = skeleton_avoidance::kinematics::presets::preset(preset)
            .unwrap()
            .joints
            .len();
        for (k, s) in skeleton.segments.iter().enumerate() {
            let (a, b) = skeleton.endpoints(s);
            if (b - a).length() < 1e-6 {
                continue;
            }
            segments += 1;
            let target = a + (b - a) * 0.4;
            let mut found = false;
            for n in around(b - a, 8) {
                // A ray from 2 m away aimed at the target, its direction not unit.
                let pick = world
                    .pick_skeleton(target + 2.0 * n, -2.5 * n)
                    .unwrap()
                    .unwrap_or_else(|| panic!("{preset}: segment {k}: the ray missed"));
                check_pick(&world, &pick);
                if pick.link > main_dof {
                    branch_links += 1;
                }
                let p = DVec3::from_array(pick.position);
                if pick.segment == k {
                    // The ray is perpendicular to the spine through the target.
                    assert!((p - target).length() < EXACT, "{preset} {k}: {pick:?}");
                    assert!((pick.distance - 2.0).abs() < EXACT && pick.offset < EXACT);
                    found = true;
                } else {
                    // Another volume is in front: it is entered before the target.
                    assert!(pick.distance < 2.0 + pick.radius + PICK_RADIUS, "{pick:?}");
                }
            }
            if found {
                exact_hits += 1;
            }
        }
    }
    // Most segments are visible from some side (short ones hide in their
    // neighbours' volumes).
    assert!(
        exact_hits * 10 >= segments * 8,
        "{exact_hits} of {segments} segments picked from some side"
    );
    assert!(branch_links > 0, "no pick on a branch of dual-arm");
}

#[test]
fn planar_arm_from_above_gives_the_paper_dh_values() {
    // planar3: links of 0.4, 0.3 and 0.2 m along x at q = 0.
    let world = world_json("planar3", &[0.0, 0.0, 0.0], "");
    let down = DVec3::new(0.0, 0.0, -1.0);
    let pick = world
        .pick_skeleton(DVec3::new(0.55, 0.01, 1.0), down)
        .unwrap()
        .unwrap();
    check_pick(&world, &pick);
    assert_eq!(pick.link, 2);
    assert!(
        (pick.a - 0.15).abs() < EXACT && pick.d.abs() < EXACT,
        "{pick:?}"
    );
    assert!((DVec3::from_array(pick.position) - DVec3::new(0.55, 0.0, 0.0)).length() < EXACT);
    assert!((pick.distance - 1.0).abs() < EXACT && (pick.offset - 0.01).abs() < EXACT);
    // Just past the joint between links 1 and 2 both volumes are under the
    // ray at the same depth: the spine under it wins.
    let pick = world
        .pick_skeleton(DVec3::new(0.41, 0.0, 1.0), down)
        .unwrap()
        .unwrap();
    assert_eq!(pick.link, 2, "{pick:?}");
    assert!((pick.a - 0.01).abs() < EXACT);
    let pick = world
        .pick_skeleton(DVec3::new(0.39, 0.0, 1.0), down)
        .unwrap()
        .unwrap();
    assert_eq!(pick.link, 1, "{pick:?}");
    assert!((pick.a - 0.39).abs() < EXACT);
}

#[test]
fn rays_that_miss_give_none_and_bad_rays_are_refused() {
    let world = world_json("planar3", &[0.0, 0.0, 0.0], "");
    let origin = DVec3::new(0.55, 0.0, 1.0);
    // Pointing away.
    assert_eq!(world.pick_skeleton(origin, DVec3::Z).unwrap(), None);
    // Passing 1 m beside the arm.
    let beside = DVec3::new(0.55, 1.0, 1.0);
    assert_eq!(world.pick_skeleton(beside, -DVec3::Z).unwrap(), None);
    // Just outside the volume plus the pick radius, and just inside.
    let r = world.skeleton().segments[1].radius[0];
    let edge = r + PICK_RADIUS;
    let out = DVec3::new(0.55, edge + 1e-6, 1.0);
    assert_eq!(world.pick_skeleton(out, -DVec3::Z).unwrap(), None);
    let inside = DVec3::new(0.55, edge - 1e-6, 1.0);
    assert!(world.pick_skeleton(inside, -DVec3::Z).unwrap().is_some());
    // Refused, naming the field.
    let e = world.pick_skeleton(origin, DVec3::ZERO).unwrap_err();
    assert_eq!(e.field().field, "direction");
    let e = world
        .pick_skeleton(DVec3::new(f64::NAN, 0.0, 0.0), DVec3::Z)
        .unwrap_err();
    assert_eq!(e.field().field, "origin[0]");
    let e = world
        .pick_skeleton(origin, DVec3::new(0.0, f64::INFINITY, 0.0))
        .unwrap_err();
    assert_eq!(e.field().field, "direction[1]");
}

#[test]
fn a_prismatic_link_is_picked_along_its_slide_and_pinned_past_its_minimum() {
    // stanford: joint 3 slides between 0.3 and 1.2 m; at 0.8 m.
    let q = [0.3, 0.5, 0.8, 0.0, 0.0, 0.0];
    let world = world_json("stanford", &q, "");
    let skeleton = world.skeleton();
    let k = skeleton.segments.iter().position(|s| s.link == 3).unwrap();
    let (a, b) = skeleton.endpoints(&skeleton.segments[k]);
    assert!(((b - a).length() - 0.8).abs() < EXACT);
    let target = a + (b - a) * 0.75;
    let n = around(b - a, 1)[0];
    let pick = world.pick_skeleton(target + n, -n).unwrap().unwrap();
    let dh = check_pick(&world, &pick);
    assert_eq!(pick.link, 3);
    assert!(
        (pick.d - 0.6).abs() < EXACT && pick.a.abs() < EXACT,
        "{pick:?}"
    );

    // Pinned: accepted though the slide's lower limit (0.3 m) is below d'.
    let pinned = format!(
        r#", "controller": {{ "selection": "pinned", "pinned": [{{ "link": 3, "d": {}, "a": {} }}] }}"#,
        dh.d, dh.a
    );
    let mut w = world_json("stanford", &q, &pinned);
    w.step(0.001);
    let cp = &w.control_points()[0];
    assert_eq!((cp.link, cp.d, cp.a), (3, dh.d, dh.a));
    // Retracted to 0.4 m, the point stays at the slide's end.
    let mut w = world_json("stanford", &[0.3, 0.5, 0.4, 0.0, 0.0, 0.0], &pinned);
    w.step(0.001);
    let cp = &w.control_points()[0];
    assert!((cp.d - w.frames().d[2]).abs() < EXACT, "{cp:?}");
    let on_spine = w.skeleton().closest_point(DVec3::from_array(cp.position));
    let (_, _, c) = on_spine.unwrap();
    assert!((c - DVec3::from_array(cp.position)).length() < EXACT);
    // Beyond the slide's reach: refused with the reach.
    let text = r#"{ "robot": { "preset": "stanford" }, "obstacles": [], "dt": 0.001, "duration": 1, "controller": { "selection": "pinned", "pinned": [{ "link": 3, "d": 1.5, "a": 0 }] } }"#;
    let s: Scenario = serde_json::from_str(text).unwrap();
    let e = World::new(s).unwrap_err();
    assert_eq!(e.field().field, "controller.pinned[0].d");
    assert!(e.field().reason.contains("reach [0, 1.2]"), "{e}");
}

#[test]
fn a_picked_point_pinned_becomes_the_control_point() {
    let ball = r#", "obstacles": [{ "id": "ball", "shape": { "type": "sphere", "center": [0.3, 0.3, 0.5], "radius": 0.05 } }]"#;
    let base = world_json("lwr4", &bent(7), "");
    assert_eq!(base.q(), bent(7).as_slice(), "within the limits");
    // A ray down through the middle of the third segment.
    let skeleton = base.skeleton();
    let (a, b) = skeleton.endpoints(&skeleton.segments[2]);
    let target = (a + b) / 2.0;
    let n = around(b - a, 4)[1];
    let pick = base.pick_skeleton(target + n, -n).unwrap().unwrap();
    let dh = check_pick(&base, &pick);
    let text = format!(
        r#"{{ "robot": {{ "preset": "lwr4" }}, "q0": [0.4, -0.7, 0.4, -0.7, 0.4, -0.7, 0.4] {ball}, "dt": 0.001, "duration": 1, "controller": {{ "selection": "pinned", "pinned": [{{ "link": {}, "d": {}, "a": {} }}] }} }}"#,
        dh.link, dh.d, dh.a
    );
    let s: Scenario = serde_json::from_str(&text).unwrap();
    let mut w = World::new(s).unwrap();
    w.step(0.001);
    let cps = w.control_points();
    assert_eq!(cps.len(), 1);
    let cp = &cps[0];
    assert_eq!((cp.link, cp.d, cp.a), (dh.link, dh.d, dh.a));
    assert_eq!(cp.obstacle, "ball");
    // Where the DH values put it in the configuration the step started from.
    let before = w.robot().forward(&bent(7)).unwrap();
    let there = dh.position(w.robot(), &before);
    assert!((DVec3::from_array(cp.position) - there).length() < EXACT);
}
