//! The rules a JavaScript caller gets at the boundary apply to a Rust
//! caller too (they live in `scenario::bounds` and the typed readers): the
//! ±1e9 bound on numbers, the refusal of a key beside a bare `type` tag,
//! an array given where an object is expected, and a partial controller
//! change merged, read and checked once. Each refusal names the field and
//! leaves the world as it was.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use serde_json::json;
use skeleton_avoidance::distance::{PrimitiveSpec, SphereSpec};
use skeleton_avoidance::scenario::{self, Motion, ObstacleSpec, ShapeSpec};
use skeleton_avoidance::world::World;

fn world() -> World {
    World::new(scenario::example("lwr4-elbow").unwrap()).unwrap()
}

fn ball(id: &str, motion: Option<Motion>) -> ObstacleSpec {
    ObstacleSpec {
        id: id.to_owned(),
        shape: ShapeSpec::Primitive(PrimitiveSpec::Sphere(SphereSpec {
            center: [0.4, 0.0, 0.5],
            radius: 0.05,
        })),
        motion,
    }
}

#[test]
fn a_scenario_built_in_rust_with_a_huge_gain_is_refused_with_its_path() {
    let mut s = scenario::example("lwr4-elbow").unwrap();
    s.controller.repulsion_gain = 1e10;
    let e = s.validate().unwrap_err().to_string();
    assert!(
        e.starts_with("controller.repulsionGain: must be within ±1e9"),
        "{e}"
    );
    assert!(World::new(s).is_err());
}

#[test]
fn set_controller_refuses_a_huge_number_and_keeps_the_configuration() {
    let mut w = world();
    let before = w.scenario().controller.clone();
    let mut c = before.clone();
    c.max_repulsion_speed = -2e9;
    let e = w.set_controller(c).unwrap_err().to_string();
    assert!(
        e.starts_with("controller.maxRepulsionSpeed: must be within ±1e9"),
        "{e}"
    );
    assert_eq!(w.scenario().controller, before);
}

#[test]
fn an_obstacle_with_a_huge_period_is_refused_and_the_world_keeps_its_obstacles() {
    let mut w = world();
    let n = w.scenario().obstacles.len();
    let motion = Motion::Circular {
        center: [0.0, 0.0, 0.5],
        axis: [0.0, 0.0, 1.0],
        period: 1e10,
    };
    let e = w
        .add_obstacle(ball("far", Some(motion)))
        .unwrap_err()
        .to_string();
    assert!(e.contains("motion.period: must be within ±1e9"), "{e}");
    assert_eq!(w.scenario().obstacles.len(), n);
    // A sane one is accepted.
    w.add_obstacle(ball("near", None)).unwrap();
    assert_eq!(w.scenario().obstacles.len(), n + 1);
}

#[test]
fn a_key_beside_a_bare_tag_is_refused_in_a_scenario_read_in_rust() {
    let mut s = serde_json::to_value(scenario::example("lwr4-elbow").unwrap()).unwrap();
    s["obstacles"][0]["motion"] = json!({ "type": "static", "colour": 1 });
    let e = scenario::Scenario::from_json(&s.to_string())
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("obstacles[0].motion"), "{e}");
}

#[test]
fn a_partial_controller_change_is_merged_read_and_checked_once() {
    let mut w = world();
    let before = w.scenario().controller.clone();
    w.update_controller(&json!({ "influenceDistance": 0.2 }))
        .unwrap();
    let after = &w.scenario().controller;
    assert!((after.influence_distance - 0.2).abs() < 1e-15);
    assert!((after.repulsion_gain - before.repulsion_gain).abs() < 1e-15);
    // Refusals name the field; the configuration in force stays.
    let cases = [
        (
            json!({ "influenceDistance": -1 }),
            "controller.influenceDistance",
        ),
        (
            json!({ "influenceDistance": 5e9 }),
            "controller.influenceDistance",
        ),
        (
            json!({ "damping": [0.1] }),
            "controller.damping: expected an object",
        ),
        (json!({ "influence": 0.2 }), "controller"),
    ];
    for (patch, field) in cases {
        let kept = w.scenario().controller.clone();
        let e = w.update_controller(&patch).unwrap_err().to_string();
        assert!(e.starts_with(field), "{patch}: {e}");
        assert_eq!(w.scenario().controller, kept, "{patch}");
    }
}
