//! The viewer's core, natively: every shipped example framed and drawn
//! (the reach holds every pose, the camera keeps the reach on screen, planar
//! robots get the top view, the scene has one mark per segment, obstacle
//! part and control point), and a recorded state object draws the same
//! scene as the live world. Runs natively and under `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::DVec3;
use skeleton_avoidance::distance::PrimitiveSpec;
use skeleton_avoidance::rng::Rng;
use skeleton_avoidance::scenario::{self, EXAMPLE_NAMES};
use skeleton_avoidance::skeleton::Skeleton;
use skeleton_avoidance::view::{
    DrawOptions, DrawState, Drawing, Palette, Stage, View, build_scene, style,
};
use skeleton_avoidance::world::World;

/// The example's world after `steps` control steps.
fn world_after(name: &str, steps: usize) -> World {
    let scenario = scenario::example(name).unwrap();
    let dt = scenario.dt;
    let mut world = World::new(scenario).unwrap();
    for _ in 0..steps {
        world.step(dt);
    }
    world
}

/// A joint vector within the limits (±π where a joint has none).
fn random_pose(rng: &mut Rng, world: &World) -> Vec<f64> {
    world
        .robot()
        .joints
        .iter()
        .map(|j| {
            let lo = if j.min.is_finite() {
                j.min
            } else {
                -std::f64::consts::PI
            };
            let hi = if j.max.is_finite() {
                j.max
            } else {
                std::f64::consts::PI
            };
            rng.range(lo, hi)
        })
        .collect()
}

#[test]
fn the_reach_holds_every_pose_of_every_example() {
    let mut rng = Rng::new(7);
    for name in EXAMPLE_NAMES {
        let world = world_after(name, 0);
        let robot = world.robot().clone();
        let mut stage = Stage::new(None);
        stage.set_robot(robot.clone()).unwrap();
        let reach = stage.reach();
        for _ in 0..100 {
            let q = random_pose(&mut rng, &world);
            let f = robot.forward(&q).unwrap();
            let skeleton = Skeleton::build(&robot, &f);
            for s in &skeleton.segments {
                for (node, r) in [(s.from, s.radius[0]), (s.to, s.radius[1])] {
                    let out = skeleton.nodes[node].distance(reach.center) + r;
                    assert!(out <= reach.radius + 1e-9, "{name}: {out} > {reach:?}");
                }
            }
        }
    }
}

#[test]
fn the_initial_camera_keeps_the_whole_reach_on_screen() {
    let mut rng = Rng::new(11);
    for name in EXAMPLE_NAMES {
        let world = world_after(name, 0);
        let mut stage = Stage::new(None);
        stage.set_robot(world.robot().clone()).unwrap();
        let reach = stage.reach();
        let camera = stage.camera();
        for (w, h) in [(100.0, 100.0), (160.0, 100.0), (400.0, 225.0)] {
            for _ in 0..200 {
                let p = reach.center + reach.radius * rng.unit3();
                let [x, y] = camera.project(p.as_vec3(), w, h).unwrap();
                let inside = (0.0..=w).contains(&x) && (0.0..=h).contains(&y);
                assert!(inside, "{name} {w}x{h}: {p} lands at ({x}, {y})");
            }
        }
    }
}

#[test]
fn planar_examples_get_the_top_view_and_the_others_3d() {
    for name in EXAMPLE_NAMES {
        let world = world_after(name, 0);
        let mut stage = Stage::new(None);
        stage.set_robot(world.robot().clone()).unwrap();
        let planar = ["planar-transition", "chattering", "sliding-point"].contains(&name);
        let expected = if planar { View::Top } else { View::Orbit };
        assert_eq!(stage.camera().view, expected, "{name}");
        // A view fixed at creation wins.
        let mut fixed = Stage::new(Some(View::Side));
        fixed.set_robot(world.robot().clone()).unwrap();
        assert_eq!(fixed.camera().view, View::Side, "{name}");
    }
    // Tilting the base of a planar arm makes it a 3D drawing.
    let mut robot = world_after("planar-transition", 0).robot().clone();
    robot.base = glam::DAffine3::from_rotation_x(0.3);
    let mut stage = Stage::new(None);
    stage.set_robot(robot).unwrap();
    assert_eq!(stage.camera().view, View::Orbit);
}

fn count(items: impl Iterator<Item = [f32; 4]>, colors: &[[f32; 4]]) -> usize {
    items.filter(|c| colors.contains(c)).count()
}

fn solid_colors(scene: &Drawing) -> impl Iterator<Item = [f32; 4]> + '_ {
    let capsules = scene.capsules.iter().map(|c| c.color);
    capsules.chain(scene.spheres.iter().map(|s| s.color))
}

fn options() -> DrawOptions {
    DrawOptions {
        volumes: true,
        nodes: true,
        arrow_scale: 0.4,
        plane_extent: 1.0,
    }
}

#[test]
fn the_scene_of_every_example_has_one_mark_per_item() {
    let mut control_points = 0;
    for name in EXAMPLE_NAMES {
        let world = world_after(name, 150);
        let state = DrawState::from(world.state());
        let mut scene = Drawing::new();
        build_scene(&mut scene, &state, &options(), None, [0.0; 3]);
        let segments = state.skeleton.segments.len();
        let spine = count(solid_colors(&scene), &[style::SPINE]);
        let volumes = count(solid_colors(&scene), &[style::VOLUME]);
        let nodes = count(solid_colors(&scene), &[style::NODE]);
        assert_eq!((spine, volumes), (segments, segments), "{name}");
        assert_eq!(nodes, state.skeleton.nodes.len(), "{name}");
        let marks = count(
            solid_colors(&scene),
            &[style::CONTROL_POINT, style::TRANSITIONING],
        );
        let lines = count(scene.lines.iter().map(|l| l.color), &[style::DISTANCE_LINE]);
        let n = state.control_points.len();
        assert_eq!((marks, lines), (n, n), "{name}");
        control_points += n;
        let round = |p: &&PrimitiveSpec| {
            matches!(
                p,
                PrimitiveSpec::Point(_)
                    | PrimitiveSpec::Segment(_)
                    | PrimitiveSpec::Sphere(_)
                    | PrimitiveSpec::Capsule(_)
                    | PrimitiveSpec::TaperedCapsule(_)
            )
        };
        let parts = state.obstacles.iter().flat_map(|o| &o.parts);
        let solids = count(
            solid_colors(&scene),
            &[Palette::OBSTACLE.solid, Palette::HUMAN.solid],
        );
        assert_eq!(solids, parts.clone().filter(round).count(), "{name}");
        let planes = parts
            .filter(|p| matches!(p, PrimitiveSpec::Plane(_)))
            .count();
        let plane_triangles = count(
            scene.triangles.iter().map(|t| t.color),
            &[Palette::OBSTACLE.plane],
        );
        assert_eq!(plane_triangles, 2 * planes, "{name}");
    }
    assert!(control_points > 0, "no example has a control point");
}

#[test]
fn the_human_is_skin_coloured_unless_selected() {
    let world = world_after("human-panda", 0);
    let state = DrawState::from(world.state());
    let human = state.obstacles.iter().find(|o| o.human).unwrap();
    let mut scene = Drawing::new();
    build_scene(&mut scene, &state, &options(), None, [0.0; 3]);
    let skin = count(solid_colors(&scene), &[Palette::HUMAN.solid]);
    assert_eq!(skin, human.parts.len());
    scene.clear();
    build_scene(&mut scene, &state, &options(), Some(&human.id), [0.0; 3]);
    assert_eq!(count(solid_colors(&scene), &[Palette::HUMAN.solid]), 0);
    let selected = count(solid_colors(&scene), &[Palette::SELECTED.solid]);
    assert_eq!(selected, human.parts.len());
}

#[test]
fn a_recorded_state_object_draws_the_live_scene() {
    for name in EXAMPLE_NAMES {
        let world = world_after(name, 100);
        let live = DrawState::from(world.state());
        let json = serde_json::to_value(world.state()).unwrap();
        let recorded: DrawState = serde_json::from_value(json.clone()).unwrap();
        // Without `parts`, each obstacle is drawn from its shape.
        let mut bare = json;
        for o in bare["obstacles"].as_array_mut().unwrap() {
            o.as_object_mut().unwrap().remove("parts");
        }
        let bare: DrawState = serde_json::from_value(bare).unwrap();
        let draw = |s: &DrawState| {
            let mut scene = Drawing::new();
            build_scene(&mut scene, s, &options(), Some("none"), [0.1, 0.2, 0.0]);
            scene
        };
        let scene = draw(&live);
        assert_eq!(scene, draw(&recorded), "{name}");
        assert_eq!(scene, draw(&bare), "{name}");
    }
}

#[test]
fn fit_keeps_the_robot_and_reachable_obstacles_in_view() {
    let mut obstacle_points = 0;
    for name in EXAMPLE_NAMES {
        let world = world_after(name, 0);
        let mut stage = Stage::new(None);
        stage.set_robot(world.robot().clone()).unwrap();
        let state = DrawState::from(world.state());
        let points = skeleton_avoidance::view::fit_points(&state, &stage.reach());
        obstacle_points += points.len() - state.skeleton.nodes.len();
        stage.draw(state);
        for (aspect, fill) in [(1.5, 0.6), (0.7, 0.9)] {
            stage.fit(fill, aspect);
            let (w, h) = (100.0 * aspect, 100.0);
            let camera = stage.camera();
            for p in &points {
                let [x, y] = camera.project(DVec3::from(*p).as_vec3(), w, h).unwrap();
                let inside = (0.0..=w).contains(&x) && (0.0..=h).contains(&y);
                assert!(inside, "{name} {aspect}: {p:?} at ({x}, {y})");
            }
        }
    }
    assert!(obstacle_points > 0, "no example frames an obstacle");
}

#[test]
fn set_joints_needs_a_robot_and_the_right_length() {
    let mut stage = Stage::new(None);
    let e = stage.set_joints(vec![0.0; 3]).unwrap_err();
    assert_eq!(e.to_string(), "setJoints: no robot; call setRobot first");
    let world = world_after("planar-transition", 0);
    stage.set_robot(world.robot().clone()).unwrap();
    assert!(stage.set_joints(vec![0.0; 2]).is_err());
    assert!(stage.set_joints(vec![0.0, f64::NAN, 0.0]).is_err());
    stage.set_joints(vec![0.1, 0.2, 0.3]).unwrap();
    assert_eq!(stage.q(), [0.1, 0.2, 0.3]);
    // The robot's own skeleton is drawn: 3 spines, 3 volumes.
    let spines = count(solid_colors(stage.scene()), &[style::SPINE]);
    assert_eq!(spines, 3);
}

#[test]
fn the_sliding_point_of_a_point_task_is_drawn_on_its_link() {
    for name in EXAMPLE_NAMES {
        let world = world_after(name, 300);
        let state = world.state();
        let tasks = world.scenario().task.as_slice();
        let points = tasks.iter().filter(|t| t.point_at(0.0).is_some()).count();
        assert_eq!(state.sliding_points.len(), points, "{name}");
        let drawn = DrawState::from(state);
        let mut scene = Drawing::new();
        build_scene(&mut scene, &drawn, &options(), None, [0.0; 3]);
        let marks: Vec<_> = scene
            .spheres
            .iter()
            .filter(|s| s.color == style::SLIDING_POINT)
            .collect();
        assert_eq!(marks.len(), points, "{name}");
        // Each mark lies on the skeleton's spine.
        for m in marks {
            let c = glam::Vec3::from(m.center).as_dvec3();
            let on_spine = drawn.skeleton.segments.iter().any(|s| {
                let (a, b) = (
                    DVec3::from(drawn.skeleton.nodes[s.from]),
                    DVec3::from(drawn.skeleton.nodes[s.to]),
                );
                let t = ((c - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
                (a + t * (b - a)).distance(c) < 1e-6
            });
            assert!(on_spine, "{name}: {c} is off the skeleton");
        }
    }
    let sliding = world_after("sliding-point", 0).state();
    assert_eq!(sliding.sliding_points.len(), 1);
}

#[test]
fn a_noisy_control_point_shows_its_witness_interval_along_its_segment() {
    // The chattering example senses its blob with a bounded error.
    let world = world_after("chattering", 3);
    let state = world.state();
    let noisy: Vec<_> = state
        .control_points
        .iter()
        .filter_map(|c| {
            c.sigma
                .map(|s| (c.position, (s.d * s.d + s.a * s.a).sqrt()))
        })
        .collect();
    assert!(!noisy.is_empty());
    let drawn = DrawState::from(state);
    let mut scene = Drawing::new();
    build_scene(&mut scene, &drawn, &options(), None, [0.0; 3]);
    let intervals: Vec<_> = scene
        .capsules
        .iter()
        .filter(|c| c.color == style::WITNESS_INTERVAL)
        .collect();
    assert_eq!(intervals.len(), noisy.len());
    for (c, (p, sigma)) in intervals.iter().zip(&noisy) {
        let (a, b) = (
            glam::Vec3::from(c.a).as_dvec3(),
            glam::Vec3::from(c.b).as_dvec3(),
        );
        let p = DVec3::from(*p);
        // Centred on the point (unless clipped by the segment's end), 2σ
        // either side, on the spine.
        let len = a.distance(b);
        assert!(len <= 4.0 * sigma + 1e-5, "{len} vs σ {sigma}");
        assert!(len > 0.0);
        let t = ((p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
        assert!((a + (b - a) * t).distance(p) < 1e-5);
    }
    // Exactly sensed: nothing drawn.
    let exact = DrawState::from(world_after("lwr4-elbow", 3).state());
    let mut scene = Drawing::new();
    build_scene(&mut scene, &exact, &options(), None, [0.0; 3]);
    assert!(
        scene
            .capsules
            .iter()
            .all(|c| c.color != style::WITNESS_INTERVAL)
    );
}

#[test]
fn a_sensed_person_has_a_margin_only_around_the_parts_control_points_answer() {
    use skeleton_avoidance::view::UNCERTAINTY;
    let margins = |state: &DrawState| {
        let mut scene = Drawing::new();
        build_scene(&mut scene, state, &options(), None, [0.0; 3]);
        count(solid_colors(&scene), &[UNCERTAINTY])
    };
    // human-panda senses its person with 1 cm error. At the start the
    // person is out of the influence distance: no control point, no margin.
    let far = DrawState::from(world_after("human-panda", 0).state());
    assert!(far.control_points.is_empty());
    assert!(!far.uncertainty.is_empty());
    assert_eq!(margins(&far), 0);
    // At 5 s the arm works beside the person: one margin per part answered.
    let near = DrawState::from(world_after("human-panda", 2500).state());
    let mut answered: Vec<_> = near
        .control_points
        .iter()
        .filter_map(|c| c.part.clone())
        .collect();
    answered.sort();
    answered.dedup();
    assert!(
        !answered.is_empty(),
        "no control point answers the person at 5 s"
    );
    assert!(answered.iter().all(|p| p.starts_with("person:")));
    assert_eq!(margins(&near), answered.len());
    // The state's `part` names the part whose inflated figure is drawn.
    let person = near.obstacles.iter().find(|o| o.human).unwrap();
    let mut scene = Drawing::new();
    build_scene(&mut scene, &near, &options(), None, [0.0; 3]);
    for name in &answered {
        let k = skeleton_avoidance::human::PART_NAMES
            .iter()
            .position(|n| format!("person:{n}") == *name)
            .unwrap();
        let near = |a: [f64; 3], b: [f32; 3]| {
            DVec3::from(a).distance(glam::Vec3::from(b).as_dvec3()) < 1e-5
        };
        let drawn = match &person.parts[k] {
            PrimitiveSpec::TaperedCapsule(c) => scene
                .capsules
                .iter()
                .any(|m| m.color == UNCERTAINTY && near(c.a, m.a) && near(c.b, m.b)),
            PrimitiveSpec::Capsule(c) => scene
                .capsules
                .iter()
                .any(|m| m.color == UNCERTAINTY && near(c.a, m.a) && near(c.b, m.b)),
            PrimitiveSpec::Sphere(c) => scene
                .spheres
                .iter()
                .any(|m| m.color == UNCERTAINTY && near(c.center, m.center)),
            other => panic!("{name}: {other:?}"),
        };
        assert!(drawn, "{name}: its margin is not drawn around it");
    }
    // A single sensed obstacle keeps its margin with or without a control point.
    let blob = DrawState::from(world_after("chattering", 0).state());
    assert!(!blob.uncertainty.is_empty());
    assert!(margins(&blob) >= 1);
}

#[test]
fn a_scenario_camera_sets_the_direction_and_a_fit_keeps_its_points_in_view() {
    let scenario = scenario::example("human-panda").unwrap();
    let spec = scenario.camera.clone().expect("human-panda has a camera");
    let world = World::new(scenario).unwrap();
    let mut stage = Stage::new(None);
    stage.set_robot(world.robot().clone()).unwrap();
    stage.set_camera(&spec).unwrap();
    let camera = stage.camera();
    assert!((f64::from(camera.yaw) - spec.yaw.unwrap()).abs() < 1e-6);
    assert!((f64::from(camera.pitch) - spec.pitch.unwrap()).abs() < 1e-6);
    // At t = 0 the person is out of reach: only the camera's points bring
    // the place where they will stand into the frame.
    let state = DrawState::from(world.state());
    let reach_points = skeleton_avoidance::view::fit_points(&state, &stage.reach());
    // Only the skeleton is framed: its nodes and its volumes' extent.
    let widest = state
        .skeleton
        .segments
        .iter()
        .flat_map(|s| s.radius)
        .fold(0.0, f64::max);
    let on_skeleton = |p: &[f64; 3]| {
        state
            .skeleton
            .nodes
            .iter()
            .any(|n| DVec3::from(*n).distance(DVec3::from(*p)) <= widest + 1e-12)
    };
    assert!(reach_points.len() > state.skeleton.nodes.len());
    assert!(reach_points.iter().all(on_skeleton));
    stage.draw(state);
    for (aspect, fill) in [(1.6, 0.85), (0.5, 0.9)] {
        stage.fit(fill, aspect);
        let (w, h) = (100.0 * aspect, 100.0);
        let on_screen = |p: [f64; 3]| {
            let [x, y] = stage
                .camera()
                .project(DVec3::from(p).as_vec3(), w, h)
                .unwrap();
            (0.0..=w).contains(&x) && (0.0..=h).contains(&y)
        };
        for p in spec.frame.iter().chain(&reach_points) {
            assert!(on_screen(*p), "{aspect}: {p:?} off screen");
        }
    }
    // A refused camera leaves the stage as it was.
    let before = *stage.camera();
    let bad = skeleton_avoidance::scenario::CameraSpec {
        pitch: Some(2.0),
        ..spec.clone()
    };
    let e = stage.set_camera(&bad).unwrap_err();
    assert!(
        e.to_string().starts_with("pitch: must be within ±1.55"),
        "{e}"
    );
    assert_eq!(*stage.camera(), before);
    // A new robot starts from the default direction with no points of its own.
    stage.set_robot(world.robot().clone()).unwrap();
    let default = skeleton_avoidance::view::Camera::default();
    assert_eq!(
        (stage.camera().yaw, stage.camera().pitch),
        (default.yaw, default.pitch)
    );
    stage.fit(0.85, 1.6);
    let far = stage
        .camera()
        .project(DVec3::from(spec.frame[0]).as_vec3(), 160.0, 100.0);
    let framed_without =
        far.is_some_and(|[x, y]| (0.0..=160.0).contains(&x) && (0.0..=100.0).contains(&y));
    // Without the points, the robot alone is framed: the place where the
    // person will stand is not guaranteed in view (and from the default
    // direction it is not).
    assert!(
        !framed_without,
        "the person's place is framed without the camera's points"
    );
}

#[test]
fn a_frame_is_drawn_only_when_the_picture_changes() {
    let world = world_after("lwr4-elbow", 0);
    let mut stage = Stage::new(None);
    stage.set_robot(world.robot().clone()).unwrap();
    let state = || DrawState::from(world.state());
    stage.draw(state());
    assert!(stage.frame().is_some(), "the first frame is drawn");
    stage.drawn(true);
    assert!(stage.frame().is_none(), "nothing changed");
    // The same world handed again: the scene is rebuilt, found equal, and
    // left out; the stage is clean afterwards.
    stage.draw(state());
    assert!(stage.frame().is_none());
    assert!(!stage.is_dirty());
    assert_eq!(stage.counts().drawn, 1);
    assert_eq!(stage.counts().unchanged, 1);
    // A step of the world moves the arm: a new frame.
    let moved = world_after("lwr4-elbow", 200);
    stage.draw(DrawState::from(moved.state()));
    assert!(stage.frame().is_some());
    // A frame the browser skipped is due again, even unchanged.
    stage.drawn(false);
    assert!(stage.frame().is_some());
    stage.drawn(true);
    // The camera alone changing, or a resize, needs a frame too.
    stage.set_view(Some(View::Top));
    assert!(stage.frame().is_some());
    stage.drawn(true);
    stage.touch();
    assert!(stage.frame().is_some(), "a resize redraws the same scene");
    stage.drawn(true);
    stage.set_display(stage_display_without_grid());
    assert!(
        stage.frame().is_some(),
        "a display option changes the scene"
    );
    assert_eq!(
        stage.counts(),
        skeleton_avoidance::view::FrameCounts {
            drawn: 4,
            unchanged: 1
        }
    );
}

fn stage_display_without_grid() -> skeleton_avoidance::view::Display {
    skeleton_avoidance::view::Display {
        grid: false,
        ..Default::default()
    }
}
