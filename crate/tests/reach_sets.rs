//! The reach problem sets: the PR2's geometry against an independent URDF
//! chain, the built-in PR2 data against its sources, MotionBenchMaker's
//! goals against the Panda, the sets by name and a problem as plain data.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use std::collections::BTreeMap;

use glam::{DMat3, DQuat, DVec3};
use serde::Deserialize;
use serde_json::Value;
use skeleton_avoidance::kinematics::{Robot, presets};
use skeleton_avoidance::reach::{self, Problem};
use skeleton_avoidance::scenario::Scenario;
use skeleton_avoidance::world::World;

const URDF: &str = include_str!("data/urdf/pr2.urdf");
const SCENES: &str = include_str!("data/neo/pr2-scenes.json");
const GOAL_POSES: &str = include_str!("data/neo/pr2_goal_poses.json");
const PR2_JSON: &str = include_str!("../src/reach/pr2.json");
const MBM_BOX: &str = include_str!("data/mbm/box.json");

#[derive(Deserialize)]
struct Fixture {
    torso_lift: Vec<f64>,
    problems: Vec<FixtureProblem>,
}

#[derive(Deserialize)]
struct FixtureProblem {
    name: String,
    goal: Vec<f64>,
    position: [f64; 3],
    matrix: [[f64; 3]; 3],
}

/// The arm of every PR2 problem, as its scenario's World builds it, puts
/// `r_wrist_roll_link` where an independent chain from `base_footprint`
/// (`pr2_goal_poses.py`: the URDF's joints composed with numpy, torso at
/// 0.16825 m) puts it, at every goal configuration, to 1e-9.
#[test]
fn pr2_flange_matches_an_independent_urdf_chain_at_every_goal() {
    let fixture: Fixture = serde_json::from_str(GOAL_POSES).unwrap();
    assert_eq!(fixture.torso_lift, vec![reach::TORSO_LIFT]);
    let problems = reach::problems("pr2", None).unwrap();
    assert_eq!(problems.len(), 198);
    assert_eq!(fixture.problems.len(), 198);
    let (mut worst_p, mut worst_r) = (0.0_f64, 0.0_f64);
    for (p, f) in problems.iter().zip(&fixture.problems) {
        assert_eq!(p.name, f.name);
        let goal_q = p.goal_q.as_ref().unwrap();
        assert_eq!(goal_q, &f.goal, "{}", p.name);
        let world = World::new(p.scenario.clone()).unwrap();
        let ee = world.robot().forward(goal_q).unwrap().end_effector();
        let want = DMat3::from_cols_array_2d(&f.matrix).transpose();
        worst_p = worst_p.max((ee.translation - DVec3::from_array(f.position)).length());
        worst_r = worst_r.max(
            (ee.matrix3 - want)
                .to_cols_array()
                .map(f64::abs)
                .iter()
                .copied()
                .fold(0.0, f64::max),
        );
        // The goal the problem asks for is that pose.
        assert!(
            (p.position - DVec3::from_array(f.position)).length() < 1e-9,
            "{}",
            p.name
        );
        let q = DQuat::from_mat3(&want);
        assert!(p.orientation.angle_between(q) < 1e-7, "{}", p.name);
    }
    eprintln!(
        "PR2 flange vs the independent chain: {worst_p:.2e} m, {worst_r:.2e} (matrix entries)"
    );
    assert!(
        worst_p < 1e-9 && worst_r < 1e-9,
        "{worst_p:e} m, {worst_r:e}"
    );
}

/// The PR2's collision meshes, by path under `data/meshes/`.
fn pr2_meshes() -> BTreeMap<String, Vec<u8>> {
    macro_rules! mesh {
        ($($path:literal),* $(,)?) => {
            [$(($path, &include_bytes!(concat!("data/meshes/pr2/collision/", $path))[..])),*]
        };
    }
    let files = mesh![
        "torso_v0/torso_lift_L.stl",
        "shoulder_v0/shoulder_pan.stl",
        "shoulder_v0/shoulder_lift.stl",
        "shoulder_v0/upper_arm_roll_L.stl",
        "upper_arm_v0/upper_arm.stl",
        "upper_arm_v0/elbow_flex.stl",
        "upper_arm_v0/forearm_roll_L.stl",
        "forearm_v0/forearm.stl",
        "forearm_v0/wrist_flex.stl",
        "forearm_v0/wrist_roll_L.stl",
        "gripper_v0/gripper_palm.stl",
        "gripper_v0/l_finger.stl",
        "gripper_v0/l_finger_tip.stl",
    ];
    files
        .into_iter()
        .map(|(p, b)| (format!("pr2/collision/{p}"), b.to_vec()))
        .collect()
}

/// Every number of `a` within `tol` of `b`'s (relative above 1), the rest
/// equal.
fn assert_close(a: &Value, b: &Value, tol: f64, at: &str) {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => {
            let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
            assert!((x - y).abs() <= tol * (1.0 + x.abs()), "{at}: {x} vs {y}");
        }
        (Value::Array(x), Value::Array(y)) => {
            assert_eq!(x.len(), y.len(), "{at}");
            for (k, (x, y)) in x.iter().zip(y).enumerate() {
                assert_close(x, y, tol, &format!("{at}[{k}]"));
            }
        }
        (Value::Object(x), Value::Object(y)) => {
            assert_eq!(
                x.keys().collect::<Vec<_>>(),
                y.keys().collect::<Vec<_>>(),
                "{at}"
            );
            for (k, v) in x {
                assert_close(v, &y[k], tol, &format!("{at}.{k}"));
            }
        }
        _ => assert_eq!(a, b, "{at}"),
    }
}

/// The arm's volumes, fitted to the PR2's collision meshes with the
/// gripper, hold every vertex of every mesh; the importer's 0.05 m
/// capsules held about half. The built-in PR2 set is what the URDF, the
/// meshes and NEO's scenes file give now (rewrite it with
/// `cargo run --release --example reach -- --write-pr2`).
#[test]
fn pr2_volumes_cover_the_meshes_and_the_builtin_set_is_current() {
    let fit = reach::pr2_fitted_arm(URDF, &pr2_meshes()).unwrap();
    assert!(fit.problems.is_empty(), "{:?}", fit.problems);
    let names: Vec<&str> = fit.after.bodies.iter().map(|b| b.name.as_str()).collect();
    for link in [
        "r_shoulder_pan_link",
        "r_upper_arm_link",
        "r_forearm_link",
        "r_wrist_roll_link",
        "r_gripper_palm_link",
        "r_gripper_l_finger_link",
        "r_gripper_r_finger_link",
        "r_gripper_l_finger_tip_link",
        "r_gripper_r_finger_tip_link",
    ] {
        assert!(names.contains(&link), "{link} in {names:?}");
    }
    let (before, after) = (&fit.before.robot, &fit.after.robot);
    eprintln!(
        "PR2 arm and gripper, {} vertices: inside {:.1} % → {:.1} %, surface {:.1} % → {:.1} %, volumes {:.2}× the meshes'",
        after.vertices,
        100.0 * before.vertex_coverage,
        100.0 * after.vertex_coverage,
        100.0 * before.surface_coverage,
        100.0 * after.surface_coverage,
        after.excess
    );
    assert_eq!(after.vertices, 1451);
    assert!(before.vertex_coverage < 0.6);
    assert!(after.vertex_coverage == 1.0 && after.surface_coverage == 1.0);
    assert!(after.excess < 3.0, "{}", after.excess);
    // Fitting moved no frame: the end effector is still the wrist roll's.
    let plain = Robot::from_spec(&reach::pr2_arm(URDF).unwrap()).unwrap();
    let fitted = Robot::from_spec(&fit.robot).unwrap();
    let q = [-0.5, 0.3, -1.2, -0.8, 2.0, -0.4, 1.0];
    let (a, b) = (plain.forward(&q).unwrap(), fitted.forward(&q).unwrap());
    let (a, b) = (a.end_effector(), b.end_effector());
    assert!((a.translation - b.translation).length() < 1e-12);
    assert!(
        (a.matrix3 - b.matrix3)
            .to_cols_array()
            .iter()
            .all(|d| d.abs() < 1e-12)
    );
    // The built-in set: the same scenes, the same arm (to rounding: the
    // file was written natively).
    let fresh: Value = serde_json::from_str(&reach::pr2_data(&fit.robot, SCENES).unwrap()).unwrap();
    let builtin: Value = serde_json::from_str(PR2_JSON).unwrap();
    assert_eq!(fresh["scenes"], builtin["scenes"]);
    assert_close(&fresh, &builtin, 1e-12, "pr2.json");
    let (robot, scenes) = reach::pr2_builtin().unwrap();
    assert_eq!(scenes, reach::pr2_scenes(SCENES).unwrap());
    assert_close(
        &serde_json::to_value(&robot).unwrap(),
        &serde_json::to_value(&fit.robot).unwrap(),
        1e-12,
        "robot",
    );
}

/// The PR2's arm is counterbalanced by springs its URDF does not model: the
/// problems' arm carries no inertial data, so the world's torque limits do
/// not hold it still under the links' weight; it moves towards its goal.
#[test]
fn pr2_problems_arm_moves_without_the_uncounterbalanced_weight() {
    let p = &reach::problems("pr2", None).unwrap()[0];
    let spec = p.scenario.robot.spec().unwrap();
    assert!(spec.joints.iter().all(|j| j.inertial.is_none()));
    let mut world = World::new(p.scenario.clone()).unwrap();
    let q0 = world.q().to_vec();
    for _ in 0..100 {
        world.step(p.scenario.dt);
    }
    let moved = world
        .q()
        .iter()
        .zip(&q0)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(moved > 0.01, "{moved}");
}

/// Each MotionBenchMaker goal is the Panda preset's flange at the goal
/// configuration; cylinders become capsules, every scenario is accepted.
#[test]
fn mbm_goals_are_the_panda_flange_at_goal_q() {
    let problems = reach::mbm_problems(MBM_BOX, "data").unwrap();
    assert_eq!(problems.len(), 100);
    let robot = Robot::from_spec(&presets::preset("panda").unwrap()).unwrap();
    for p in &problems {
        assert!(p.name.starts_with("mbm/box/"));
        let ee = robot
            .forward(p.goal_q.as_ref().unwrap())
            .unwrap()
            .end_effector();
        assert!((ee.translation - p.position).length() < 1e-9, "{}", p.name);
        let rot = DQuat::from_mat3(&ee.matrix3);
        assert!(rot.angle_between(p.orientation) < 1e-7, "{}", p.name);
        // The grasped can is left out (reach::mbm's docs): 6 of the 7 objects.
        assert_eq!(p.scenario.obstacles.len(), 6);
        assert!(
            p.scenario.obstacles.iter().all(|o| o.id != "Can1"),
            "{}",
            p.name
        );
    }
    let both = format!("[{MBM_BOX}, {MBM_BOX}]");
    assert_eq!(reach::mbm_problems(&both, "data").unwrap().len(), 200);
}

#[test]
fn sets_by_name_refuse_what_they_cannot_build() {
    let e = reach::problems("ur5", None).unwrap_err().to_string();
    assert!(e.starts_with("set: unknown problem set \"ur5\""), "{e}");
    let e = reach::problems("mbm", None).unwrap_err().to_string();
    assert!(e.starts_with("data: "), "{e}");
    let e = reach::problems("pr2", Some("[]")).unwrap_err().to_string();
    assert!(e.starts_with("data: "), "{e}");
    let e = reach::problems("mbm", Some("{\"set\": \"mbm\"}"))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("data"), "{e}");
    let e = reach::problems("mbm", Some("[{\"set\": \"neo\", \"problems\": []}]"))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("data[0].set: "), "{e}");
    assert!(reach::problems("mbm", Some("[]")).unwrap().is_empty());
}

/// A problem as plain data: `{ name, scenario, goal: { position,
/// orientation }, goalQ }`, its scenario read back as the same scenario.
fn assert_plain_data_round_trips(p: &Problem) {
    let v = serde_json::to_value(p).unwrap();
    let keys: Vec<&String> = v.as_object().unwrap().keys().collect();
    assert_eq!(keys, ["goal", "goalQ", "name", "scenario"]);
    assert_eq!(v["name"], p.name.as_str());
    let back = Scenario::from_json(&v["scenario"].to_string()).unwrap();
    assert_eq!(back, p.scenario);
    let pos: [f64; 3] = serde_json::from_value(v["goal"]["position"].clone()).unwrap();
    assert_eq!(pos, p.position.to_array());
    let rot: [f64; 4] = serde_json::from_value(v["goal"]["orientation"].clone()).unwrap();
    assert_eq!(rot, p.orientation.to_array());
}

#[test]
fn problems_are_plain_data_that_reads_back() {
    let pr2 = reach::problems("pr2", None).unwrap();
    assert_plain_data_round_trips(&pr2[0]);
    let mbm = reach::mbm_problems(MBM_BOX, "data").unwrap();
    assert_plain_data_round_trips(&mbm[0]);
    let panda = reach::panda_problems(1, 1).unwrap();
    assert_plain_data_round_trips(&panda[0]);
}
