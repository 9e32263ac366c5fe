//! Volumes fitted to the published collision meshes of the Panda, the UR5
//! and the iiwa 14 (crate/tests/data/meshes, licences beside them): every
//! collision-mesh vertex lies inside the fitted volumes, checked here with
//! the library's public point–tapered-capsule distance over the whole
//! skeleton, at q = 0 and at random configurations (the vertices carried by
//! their link's frame), independently of the fitting code's own choice of
//! segments; a missing mesh is named and the robot still loads. Runs
//! natively and, unchanged, under `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use std::collections::BTreeMap;

use skeleton_avoidance::distance::{Primitive, TaperedCapsule, distance};
use skeleton_avoidance::fitting::{UrdfFit, fit_urdf};
use skeleton_avoidance::kinematics::Robot;
use skeleton_avoidance::parsers::mesh::resolve_mesh;
use skeleton_avoidance::parsers::urdf::UrdfOptions;
use skeleton_avoidance::rng::Rng;
use skeleton_avoidance::skeleton::Skeleton;

macro_rules! files {
    ($($key:literal => $path:literal),* $(,)?) => {{
        let mut m = BTreeMap::new();
        $(m.insert($key.to_owned(), include_bytes!($path).to_vec());)*
        m
    }};
}

fn panda_files() -> BTreeMap<String, Vec<u8>> {
    files! {
        "panda/meshes/collision/link0.stl" => "data/meshes/panda/collision/link0.stl",
        "panda/meshes/collision/link1.stl" => "data/meshes/panda/collision/link1.stl",
        "panda/meshes/collision/link2.stl" => "data/meshes/panda/collision/link2.stl",
        "panda/meshes/collision/link3.stl" => "data/meshes/panda/collision/link3.stl",
        "panda/meshes/collision/link4.stl" => "data/meshes/panda/collision/link4.stl",
        "panda/meshes/collision/link5.stl" => "data/meshes/panda/collision/link5.stl",
        "panda/meshes/collision/link6.stl" => "data/meshes/panda/collision/link6.stl",
        "panda/meshes/collision/link7.stl" => "data/meshes/panda/collision/link7.stl",
        "panda/meshes/collision/hand.stl" => "data/meshes/panda/collision/hand.stl",
    }
}

fn ur5_files() -> BTreeMap<String, Vec<u8>> {
    files! {
        "ur5/collision/base.stl" => "data/meshes/ur5/collision/base.stl",
        "ur5/collision/shoulder.stl" => "data/meshes/ur5/collision/shoulder.stl",
        "ur5/collision/upperarm.stl" => "data/meshes/ur5/collision/upperarm.stl",
        "ur5/collision/forearm.stl" => "data/meshes/ur5/collision/forearm.stl",
        "ur5/collision/wrist1.stl" => "data/meshes/ur5/collision/wrist1.stl",
        "ur5/collision/wrist2.stl" => "data/meshes/ur5/collision/wrist2.stl",
        "ur5/collision/wrist3.stl" => "data/meshes/ur5/collision/wrist3.stl",
    }
}

fn iiwa_files() -> BTreeMap<String, Vec<u8>> {
    files! {
        "iiwa14/collision/link_0.stl" => "data/meshes/iiwa14/collision/link_0.stl",
        "iiwa14/collision/link_1.stl" => "data/meshes/iiwa14/collision/link_1.stl",
        "iiwa14/collision/link_2.stl" => "data/meshes/iiwa14/collision/link_2.stl",
        "iiwa14/collision/link_3.stl" => "data/meshes/iiwa14/collision/link_3.stl",
        "iiwa14/collision/link_4.stl" => "data/meshes/iiwa14/collision/link_4.stl",
        "iiwa14/collision/link_5.stl" => "data/meshes/iiwa14/collision/link_5.stl",
        "iiwa14/collision/link_6.stl" => "data/meshes/iiwa14/collision/link_6.stl",
        "iiwa14/collision/link_7.stl" => "data/meshes/iiwa14/collision/link_7.stl",
    }
}

const PANDA: &str = include_str!("data/urdf/panda_mesh_collision.urdf");
const UR5: &str = include_str!("data/urdf/ur5_robot.urdf");
const IIWA: &str = include_str!("data/urdf/iiwa14_mesh_collision.urdf");

fn fit(xml: &str, tip: &str, files: &BTreeMap<String, Vec<u8>>) -> UrdfFit {
    let options = UrdfOptions {
        tip: Some(tip.to_owned()),
        base: None,
        srdf: None,
        radii: None,
    };
    fit_urdf(xml, &options, files).unwrap()
}

/// Every body vertex, carried to `q` by its row's frame, is inside some
/// volume of the skeleton at `q` (public distance, whole skeleton).
fn assert_contained(f: &UrdfFit, q: &[f64]) {
    let robot = Robot::from_spec(&f.robot).unwrap();
    let zero = robot.forward(&vec![0.0; robot.dof()]).unwrap();
    let frames = robot.forward(q).unwrap();
    let sk = Skeleton::build(&robot, &frames);
    let caps: Vec<Primitive> = sk
        .segments
        .iter()
        .map(|s| {
            let (a, b) = sk.endpoints(s);
            Primitive::TaperedCapsule(TaperedCapsule::new(a, b, s.radius).unwrap())
        })
        .collect();
    for b in &f.bodies {
        let carry = frames.transforms[b.link] * zero.transforms[b.link].inverse();
        for v in &b.mesh.vertices {
            let p = Primitive::Point(carry.transform_point3(*v));
            let d = caps
                .iter()
                .map(|c| distance(&p, c).unwrap().distance)
                .fold(f64::INFINITY, f64::min);
            assert!(
                d <= 1e-9,
                "{}: vertex {v} is {d} m outside at q = {q:?}",
                b.name
            );
        }
    }
}

fn check_robot(name: &str, f: &UrdfFit) {
    assert!(f.problems.is_empty(), "{:?}", f.problems);
    let (before, after) = (f.before.as_ref().unwrap(), f.after.as_ref().unwrap());
    println!(
        "{name}: before vertices {:.1} % surface {:.1} % excess {:.2}; after vertices {:.1} % surface {:.1} % excess {:.2}",
        100.0 * before.robot.vertex_coverage,
        100.0 * before.robot.surface_coverage,
        before.robot.excess,
        100.0 * after.robot.vertex_coverage,
        100.0 * after.robot.surface_coverage,
        after.robot.excess
    );
    for b in &after.bodies {
        println!(
            "  {} (row {}): {} vertices, {:.1} % in, surface {:.1} %, excess {:.2}",
            b.name,
            b.link,
            b.vertices,
            100.0 * b.vertex_coverage,
            100.0 * b.surface_coverage,
            b.excess
        );
    }
    assert_eq!(after.robot.vertex_coverage, 1.0);
    let robot = Robot::from_spec(&f.robot).unwrap();
    assert_contained(f, &vec![0.0; robot.dof()]);
    let mut rng = Rng::new(19);
    for _ in 0..3 {
        let q: Vec<f64> = robot
            .joints
            .iter()
            .map(|j| {
                let (lo, hi) = (j.min.max(-3.0), j.max.min(3.0));
                lo + (hi - lo) * rng.uniform()
            })
            .collect();
        assert_contained(f, &q);
    }
}

#[test]
fn panda_fitted_volumes_contain_every_collision_vertex() {
    let f = fit(PANDA, "panda_link8", &panda_files());
    assert_eq!(f.bodies.len(), 8, "links 1–7 and the hand on the flange");
    check_robot("panda", &f);
}

#[test]
fn ur5_fitted_volumes_contain_every_collision_vertex() {
    check_robot("ur5", &fit(UR5, "ee_link", &ur5_files()));
}

#[test]
fn iiwa14_fitted_volumes_contain_every_collision_vertex() {
    check_robot("iiwa14", &fit(IIWA, "iiwa_link_7", &iiwa_files()));
}

/// The iiwa 14's drawn meshes (2 000 triangles a link) keep coarser
/// levels of half the triangles each, a few millimetres from the full
/// mesh; seen whole (the arm 3 m from the eye on an 800 px high view, 1 px
/// tolerance) it is drawn with at most a third of its triangles, each link
/// within the tolerance.
#[test]
fn iiwa14_meshes_are_drawn_coarser_when_small_on_screen() {
    use skeleton_avoidance::view::{
        Camera, Detail, Drawing, MIN_LEVEL_TRIANGLES, View, draw_meshes, link_meshes,
    };
    let f = fit(IIWA, "iiwa_link_7", &iiwa_files());
    let robot = Robot::from_spec(&f.robot).unwrap();
    let zero = robot.forward(&vec![0.0; robot.dof()]).unwrap();
    let meshes = link_meshes(&f.bodies, &zero.transforms);
    for m in &meshes {
        let mut before = m.triangles.len();
        for level in &m.coarser {
            assert!(
                level.triangles.len() <= before / 2 && level.triangles.len() >= MIN_LEVEL_TRIANGLES
            );
            assert!(
                level.error > 0.0 && level.error < 0.02,
                "link {}: {} m",
                m.link,
                level.error
            );
            before = level.triangles.len();
        }
        assert!(
            m.coarser.len() >= 3,
            "link {}: {} levels",
            m.link,
            m.coarser.len()
        );
    }
    let full: usize = meshes.iter().map(|m| m.triangles.len()).sum();
    let mut camera = Camera::framing(glam::Vec3::new(0.0, 0.0, 0.6), 0.7, View::Orbit);
    camera.distance = 3.0;
    let mut scene = Drawing::new();
    let detail = Detail {
        camera: &camera,
        height: 800.0,
        tolerance: 1.0,
    };
    draw_meshes(&mut scene, &meshes, &zero.transforms, Some(detail));
    let drawn = scene.closed.len() + scene.triangles.len();
    assert!(3 * drawn <= full, "{drawn} of {full} triangles drawn");
    let mut near = Drawing::new();
    camera.distance = 0.5;
    let detail = Detail {
        camera: &camera,
        height: 800.0,
        tolerance: 1.0,
    };
    draw_meshes(&mut near, &meshes, &zero.transforms, Some(detail));
    assert!(
        near.closed.len() + near.triangles.len() > 2 * drawn,
        "closer, finer"
    );
}

#[test]
fn a_default_tip_at_the_last_joint_moves_on_to_a_frame_fixed_to_it() {
    // ur5_robot.urdf's longest chain ends at wrist_3_link, whose origin is
    // on the last joint: no segment would move with its mesh; the fit takes
    // a frame fixed to it as the tip instead.
    let f = fit_urdf(UR5, &UrdfOptions::default(), &ur5_files()).unwrap();
    assert!(f.problems.is_empty(), "{:?}", f.problems);
    assert_eq!(f.after.as_ref().unwrap().robot.vertex_coverage, 1.0);
    assert_contained(&f, &[0.0; 6]);
}

#[test]
fn a_missing_mesh_is_named_and_the_robot_still_loads() {
    let mut files = ur5_files();
    files.remove("ur5/collision/forearm.stl");
    let f = fit(UR5, "ee_link", &files);
    assert_eq!(f.problems.len(), 1, "{:?}", f.problems);
    assert!(f.problems[0].contains("forearm.stl"), "{}", f.problems[0]);
    assert!(f.problems[0].contains("forearm_link"), "{}", f.problems[0]);
    assert_eq!(f.robot.joints.len(), 6);
    assert_eq!(f.after.unwrap().robot.vertex_coverage, 1.0);
}

#[test]
fn mesh_paths_resolve_by_their_tail_and_never_climb_out() {
    let files = ur5_files();
    for name in [
        "package://example-robot-data/robots/ur_description/meshes/ur5/collision/wrist1.stl",
        "../ur5/collision/wrist1.stl",
        "file:///opt/x/ur5/./collision/wrist1.stl",
    ] {
        assert_eq!(
            resolve_mesh(name, &files),
            Ok("ur5/collision/wrist1.stl"),
            "{name}"
        );
    }
    let e = resolve_mesh("../../../etc/passwd", &files).unwrap_err();
    assert!(e.contains("outside"), "{e}");
    let e = resolve_mesh("package://x/meshes/none.stl", &files).unwrap_err();
    assert!(e.contains("none.stl"), "{e}");
}
