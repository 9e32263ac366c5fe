//! NEO (Haviland & Corke 2021) inside the library, `controller.avoidance:
//! "neo"`: a goal beside an obstacle reached, as published and through the
//! limiter (the latter within every limit), and its settings refused out
//! of range with the field named and the world unchanged. Runs natively
//! and, unchanged, under `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::{DQuat, DVec3};
use serde_json::json;
use skeleton_avoidance::scenario::{Scenario, Trace, audit};
use skeleton_avoidance::world::World;

#[path = "common/poses.rs"]
mod poses;
use poses::PANDA_READY as READY;

/// The Panda's flange in the ready pose.
fn ready_pose() -> (DVec3, DQuat) {
    let s = Scenario::from_json(
        &json!({ "robot": { "preset": "panda" }, "obstacles": [], "dt": 0.01, "duration": 1 })
            .to_string(),
    )
    .unwrap();
    let ee = s
        .build_robot()
        .unwrap()
        .forward(&READY)
        .unwrap()
        .end_effector();
    (ee.translation, DQuat::from_mat3(&ee.matrix3))
}

/// A goal beside a ball that the arm passes within NEO's influence
/// distance (the ball of `avoid_and_reach.rs` moved 10 cm further out: at
/// the goal there the hand is within NEO's 5 cm stopping distance), with
/// `controller`.
fn beside(controller: serde_json::Value) -> (Scenario, DVec3, DQuat) {
    let (p0, o0) = ready_pose();
    let goal = p0 + DVec3::new(0.0, 0.35, -0.1);
    let ball = p0 + DVec3::new(0.22, 0.17, -0.05);
    let v = json!({
        "robot": { "preset": "panda" },
        "q0": READY,
        "obstacles": [{ "id": "ball", "shape": { "type": "sphere", "center": ball.to_array(), "radius": 0.05 } }],
        "task": { "type": "goal", "position": goal.to_array(), "orientation": [o0.x, o0.y, o0.z, o0.w] },
        "controller": controller,
        "dt": 0.005,
        "duration": 15,
    });
    (Scenario::from_json(&v.to_string()).unwrap(), goal, o0)
}

struct Run {
    error: f64,
    angle: f64,
    clearance: f64,
    audit: skeleton_avoidance::scenario::MotionAudit,
}

fn run(scenario: Scenario, goal: DVec3, orientation: DQuat) -> Run {
    let dt = scenario.dt;
    let steps = (scenario.duration / dt).round() as usize;
    let mut world = World::new(scenario).unwrap();
    let robot = world.robot().clone();
    let mut trace = Trace::default();
    let mut clearance = f64::INFINITY;
    for _ in 0..steps {
        world.step(dt);
        let s = world.sample();
        clearance = clearance.min(s.min_clearance.unwrap_or(f64::INFINITY));
        trace.samples.push(s);
    }
    let ee = world.frames().end_effector();
    Run {
        error: (ee.translation - goal).length(),
        angle: DQuat::from_mat3(&ee.matrix3)
            .angle_between(orientation)
            .to_degrees(),
        clearance,
        audit: audit(&robot, &trace),
    }
}

#[test]
fn neo_reaches_a_goal_beside_an_obstacle() {
    let (s, goal, o) = beside(json!({ "avoidance": "neo" }));
    let published = run(s, goal, o);
    println!(
        "neo as published: {:.4} m {:.2}°, clearance {:.4} m, peak q̇ {:.2} q̈ {:.2} of the limits",
        published.error,
        published.angle,
        published.clearance,
        published.audit.velocity,
        published.audit.acceleration
    );
    assert!(published.error < 0.01 && published.angle < 2.0);
    assert!(published.clearance > 0.0, "no contact");
    assert!(published.clearance < 0.3, "the ball was within d_i");
    assert!(
        published.audit.velocity <= 1.0 + 1e-9,
        "NEO keeps its velocity bounds"
    );

    let (s, goal, o) = beside(json!({ "avoidance": "neo", "neo": { "limiter": true } }));
    let limited = run(s, goal, o);
    println!(
        "neo through the limiter: {:.4} m {:.2}°, clearance {:.4} m, peak q̇ {:.2} q̈ {:.2}",
        limited.error,
        limited.angle,
        limited.clearance,
        limited.audit.velocity,
        limited.audit.acceleration
    );
    assert!(limited.error < 0.01 && limited.angle < 2.0);
    assert!(limited.clearance > 0.0);
    assert!(limited.audit.admissible(), "{:?}", limited.audit);
}

#[test]
fn neo_settings_out_of_range_are_refused_naming_the_field() {
    for (neo, field) in [
        (
            json!({ "influenceDistance": -0.1 }),
            "controller.neo.influenceDistance",
        ),
        (
            json!({ "stoppingDistance": 0.3 }),
            "controller.neo.stoppingDistance: must be < neo.influenceDistance",
        ),
        (
            json!({ "influenceDistance": 0.1, "stoppingDistance": 0.2 }),
            "controller.neo.stoppingDistance",
        ),
        (json!({ "damperGain": -1 }), "controller.neo.damperGain"),
        (json!({ "taskGain": 0 }), "controller.neo.taskGain"),
        (json!({ "gain": 1 }), "controller.neo"),
    ] {
        let v = json!({ "robot": { "preset": "panda" }, "q0": READY, "obstacles": [], "dt": 0.01, "duration": 1,
                        "controller": { "avoidance": "neo", "neo": neo.clone() } });
        let e = Scenario::from_json(&v.to_string())
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default();
        assert!(e.contains(field), "{neo}: {e}");
        // Through the world: refused, and the world unchanged.
        let (s, _, _) = beside(json!({}));
        let mut world = World::new(s).unwrap();
        world.step(0.005);
        let before = (world.q().to_vec(), world.scenario().controller.clone());
        let e = world
            .update_controller(&json!({ "avoidance": "neo", "neo": neo.clone() }))
            .unwrap_err()
            .to_string();
        assert!(e.contains(field), "{neo}: {e}");
        assert_eq!(
            (world.q().to_vec(), world.scenario().controller.clone()),
            before
        );
    }
    let (s, _, _) = beside(json!({}));
    let mut world = World::new(s).unwrap();
    let e = world
        .update_controller(&json!({ "avoidance": "magnets" }))
        .unwrap_err()
        .to_string();
    assert!(e.contains("controller.avoidance"), "{e}");
    world
        .update_controller(&json!({ "avoidance": "neo", "neo": { "limiter": true } }))
        .unwrap();
    assert!(world.scenario().controller.uses_neo());
}
