//! The Panda and UR5 presets against their published collision meshes
//! (crate/tests/data/meshes): the meshes, read through the URDFs, carried
//! into each preset's world frame (the rigid transform that maps the URDF's
//! tip onto the preset's last frame over random configurations, fitted and
//! checked to 1e-6 m), then the coverage of the preset's radii measured and
//! every vertex required inside. Prints the before/after table of the
//! module docs of `kinematics::presets`. Runs natively and under
//! `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use std::collections::BTreeMap;

use glam::DVec3;
use skeleton_avoidance::fitting::{
    Body, CoverageOptions, bodies_onto, coverage, fit_urdf, fit_volumes, rigid_fit,
};
use skeleton_avoidance::kinematics::presets::preset;
use skeleton_avoidance::kinematics::{Robot, RobotSpec};
use skeleton_avoidance::parsers::urdf::UrdfOptions;

macro_rules! files {
    ($($key:literal => $path:literal),* $(,)?) => {{
        let mut m = BTreeMap::new();
        $(m.insert($key.to_owned(), include_bytes!($path).to_vec());)*
        m
    }};
}

fn bodies_in_preset(
    xml: &str,
    tip: &str,
    files: &BTreeMap<String, Vec<u8>>,
    spec: &RobotSpec,
) -> Vec<Body> {
    let options = UrdfOptions {
        tip: Some(tip.to_owned()),
        base: None,
        srdf: None,
        radii: None,
    };
    let fit = fit_urdf(xml, &options, files).unwrap();
    assert!(fit.problems.is_empty(), "{:?}", fit.problems);
    let urdf = Robot::from_spec(&fit.robot).unwrap();
    let preset = Robot::from_spec(spec).unwrap();
    // The same arm: the base transform is fitted and checked by the tips.
    let bodies = bodies_onto(&urdf, &preset, &fit.bodies).unwrap();
    // Checked here independently: every body's vertices, carried along by
    // the two robots' own frames of its row, coincide at another pose.
    let q: Vec<f64> = (0..preset.dof()).map(|k| 0.3 - 0.1 * k as f64).collect();
    let (fu0, fu) = (
        urdf.forward(&vec![0.0; preset.dof()]).unwrap(),
        urdf.forward(&q).unwrap(),
    );
    let (fp0, fp) = (
        preset.forward(&vec![0.0; preset.dof()]).unwrap(),
        preset.forward(&q).unwrap(),
    );
    let (a, b): (Vec<DVec3>, Vec<DVec3>) = fit
        .bodies
        .iter()
        .zip(&bodies)
        .flat_map(|(u, p)| {
            let mu = fu.transforms[u.link] * fu0.transforms[u.link].inverse();
            let mp = fp.transforms[p.link] * fp0.transforms[p.link].inverse();
            u.mesh
                .vertices
                .iter()
                .zip(&p.mesh.vertices)
                .map(move |(x, y)| (mu.transform_point3(*x), mp.transform_point3(*y)))
        })
        .unzip();
    let w = rigid_fit(&a, &b);
    for (x, y) in a.iter().zip(&b) {
        assert!(
            (w.transform_point3(*x) - *y).length() < 1e-6,
            "a body left its row"
        );
    }
    // The presets model the arm up to its flange: the Panda's hand (hung
    // from the flange) is not part of them.
    bodies
        .into_iter()
        .filter(|b| b.name != "panda_hand")
        .collect()
}

fn report(name: &str, spec: &RobotSpec, bodies: &[Body]) -> f64 {
    let q = vec![0.0; spec.joints.len()];
    let o = CoverageOptions::default();
    let now = coverage(spec, &q, bodies, &o).unwrap();
    let fitted = fit_volumes(spec, &q, bodies).unwrap();
    let best = coverage(&fitted, &q, bodies, &o).unwrap();
    println!(
        "| {name} | {:.1} % | {:.1} % | {:.2} | {:.1} % | {:.1} % | {:.2} |",
        100.0 * now.robot.vertex_coverage,
        100.0 * now.robot.surface_coverage,
        now.robot.excess,
        100.0 * best.robot.vertex_coverage,
        100.0 * best.robot.surface_coverage,
        best.robot.excess
    );
    for (j, f) in fitted.joints.iter().enumerate() {
        println!(
            "  row {}: radius {:?} extension {:?}",
            j + 1,
            f.radius,
            f.extension
        );
    }
    assert_eq!(best.robot.vertex_coverage, 1.0);
    now.robot.vertex_coverage
}

/// Every vertex of every body inside the preset's own volumes, checked
/// here without the fitting module: at random configurations, each body
/// carried by its row's frame, each vertex must lie in the ball at the
/// nearest point of some segment's spine (a ball the round cone holds).
/// Returns the smallest margin found (m, ≥ 0).
fn every_vertex_inside(spec: &RobotSpec, bodies: &[Body]) -> f64 {
    use skeleton_avoidance::skeleton::Skeleton;
    let robot = Robot::from_spec(spec).unwrap();
    let zero = vec![0.0; robot.dof()];
    let f0 = robot.forward(&zero).unwrap();
    let mut rng = skeleton_avoidance::rng::Rng::new(19);
    let mut worst = f64::INFINITY;
    for trial in 0..4 {
        let q: Vec<f64> = if trial == 0 {
            zero.clone()
        } else {
            robot
                .joints
                .iter()
                .map(|j| rng.range(j.min.max(-3.0), j.max.min(3.0)))
                .collect()
        };
        let f = robot.forward(&q).unwrap();
        let sk = Skeleton::build(&robot, &f);
        for b in bodies {
            let m = f.transforms[b.link] * f0.transforms[b.link].inverse();
            for v in &b.mesh.vertices {
                let p = m.transform_point3(*v);
                let margin = sk
                    .segments
                    .iter()
                    .map(|s| {
                        let (a, e) = sk.endpoints(s);
                        let ab = e - a;
                        let t = if ab.length_squared() > 0.0 {
                            ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
                        } else {
                            0.0
                        };
                        Skeleton::radius_at(s, t) - (p - (a + ab * t)).length()
                    })
                    .fold(f64::NEG_INFINITY, f64::max);
                assert!(
                    margin >= 0.0,
                    "{} at q {q:?}: a vertex {margin} m outside",
                    b.name
                );
                worst = worst.min(margin);
            }
        }
    }
    worst
}

#[test]
fn panda_preset_covers_its_collision_meshes() {
    let files = files! {
        "collision/link1.stl" => "data/meshes/panda/collision/link1.stl",
        "collision/link2.stl" => "data/meshes/panda/collision/link2.stl",
        "collision/link3.stl" => "data/meshes/panda/collision/link3.stl",
        "collision/link4.stl" => "data/meshes/panda/collision/link4.stl",
        "collision/link5.stl" => "data/meshes/panda/collision/link5.stl",
        "collision/link6.stl" => "data/meshes/panda/collision/link6.stl",
        "collision/link7.stl" => "data/meshes/panda/collision/link7.stl",
        "collision/hand.stl" => "data/meshes/panda/collision/hand.stl",
    };
    let spec = preset("panda").unwrap();
    let bodies = bodies_in_preset(
        include_str!("data/urdf/panda_mesh_collision.urdf"),
        "panda_link8",
        &files,
        &spec,
    );
    assert_eq!(report("panda", &spec, &bodies), 1.0);
    let margin = every_vertex_inside(&spec, &bodies);
    println!("panda: every vertex inside, the closest {margin:.2e} m from a surface");
}

#[test]
fn ur5_preset_covers_its_collision_meshes() {
    let files = files! {
        "collision/shoulder.stl" => "data/meshes/ur5/collision/shoulder.stl",
        "collision/upperarm.stl" => "data/meshes/ur5/collision/upperarm.stl",
        "collision/forearm.stl" => "data/meshes/ur5/collision/forearm.stl",
        "collision/wrist1.stl" => "data/meshes/ur5/collision/wrist1.stl",
        "collision/wrist2.stl" => "data/meshes/ur5/collision/wrist2.stl",
        "collision/wrist3.stl" => "data/meshes/ur5/collision/wrist3.stl",
    };
    let spec = preset("ur5").unwrap();
    let bodies = bodies_in_preset(
        include_str!("data/urdf/ur5_robot.urdf"),
        "ee_link",
        &files,
        &spec,
    );
    assert_eq!(report("ur5", &spec, &bodies), 1.0);
    let margin = every_vertex_inside(&spec, &bodies);
    println!("ur5: every vertex inside, the closest {margin:.2e} m from a surface");
}

#[test]
fn iiwa14_preset_covers_its_collision_meshes() {
    let files = files! {
        "collision/link_0.stl" => "data/meshes/iiwa14/collision/link_0.stl",
        "collision/link_1.stl" => "data/meshes/iiwa14/collision/link_1.stl",
        "collision/link_2.stl" => "data/meshes/iiwa14/collision/link_2.stl",
        "collision/link_3.stl" => "data/meshes/iiwa14/collision/link_3.stl",
        "collision/link_4.stl" => "data/meshes/iiwa14/collision/link_4.stl",
        "collision/link_5.stl" => "data/meshes/iiwa14/collision/link_5.stl",
        "collision/link_6.stl" => "data/meshes/iiwa14/collision/link_6.stl",
        "collision/link_7.stl" => "data/meshes/iiwa14/collision/link_7.stl",
    };
    let spec = preset("iiwa14").unwrap();
    let bodies = bodies_in_preset(
        include_str!("data/urdf/iiwa14_mesh_collision.urdf"),
        "iiwa_link_7",
        &files,
        &spec,
    );
    assert_eq!(report("iiwa14", &spec, &bodies), 1.0);
    let margin = every_vertex_inside(&spec, &bodies);
    println!("iiwa14: every vertex inside, the closest {margin:.2e} m from a surface");
}

#[test]
fn bodies_go_only_onto_the_same_arm() {
    let xml = include_str!("data/urdf/ur5_robot.urdf");
    let files = files! { "collision/wrist3.stl" => "data/meshes/ur5/collision/wrist3.stl" };
    let options = UrdfOptions {
        tip: Some("ee_link".to_owned()),
        base: None,
        srdf: None,
        radii: None,
    };
    let fit = fit_urdf(xml, &options, &files).unwrap();
    let urdf = Robot::from_spec(&fit.robot).unwrap();
    let panda = Robot::from_spec(&preset("panda").unwrap()).unwrap();
    let e = bodies_onto(&urdf, &panda, &fit.bodies).unwrap_err();
    assert_eq!(e, "the URDF's chain has 6 joints, the robot 7");
    // The UR5 with one DH length 1 mm off: not the same arm.
    let mut spec = preset("ur5").unwrap();
    spec.joints[2].a -= 0.001;
    let longer = Robot::from_spec(&spec).unwrap();
    let e = bodies_onto(&urdf, &longer, &fit.bodies).unwrap_err();
    assert!(
        e.starts_with("the URDF's kinematics are not the robot's"),
        "{e}"
    );
    let ur5 = Robot::from_spec(&preset("ur5").unwrap()).unwrap();
    assert_eq!(bodies_onto(&urdf, &ur5, &fit.bodies).unwrap().len(), 1);
}
