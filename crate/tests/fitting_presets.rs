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

use glam::{DAffine3, DMat3, DVec3};
use skeleton_avoidance::fitting::{Body, CoverageOptions, coverage, fit_urdf, fit_volumes};
use skeleton_avoidance::kinematics::presets::preset;
use skeleton_avoidance::kinematics::urdf::UrdfOptions;
use skeleton_avoidance::kinematics::{Robot, RobotSpec};
use skeleton_avoidance::rng::Rng;

macro_rules! files {
    ($($key:literal => $path:literal),* $(,)?) => {{
        let mut m = BTreeMap::new();
        $(m.insert($key.to_owned(), include_bytes!($path).to_vec());)*
        m
    }};
}

/// Best rotation + translation with `W a_i ≈ b_i` (Kabsch via polar
/// iteration of the cross-covariance).
fn rigid_fit(a: &[DVec3], b: &[DVec3]) -> DAffine3 {
    let n = a.len() as f64;
    let ca = a.iter().copied().sum::<DVec3>() / n;
    let cb = b.iter().copied().sum::<DVec3>() / n;
    let mut h = DMat3::ZERO;
    for (p, q) in a.iter().zip(b) {
        let (p, q) = (*p - ca, *q - cb);
        h += DMat3::from_cols(q * p.x, q * p.y, q * p.z);
    }
    // Polar decomposition: R = lim (R + R^-T) / 2.
    let mut r = h;
    for _ in 0..100 {
        r = (r + r.inverse().transpose()) * 0.5;
    }
    DAffine3::from_mat3_translation(r, cb - r * ca)
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
    let mut rng = Rng::new(5);
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for _ in 0..20 {
        let q: Vec<f64> = preset
            .joints
            .iter()
            .map(|j| {
                let (lo, hi) = (j.min.max(-3.0), j.max.min(3.0));
                lo + (hi - lo) * rng.uniform()
            })
            .collect();
        let fu = urdf.forward(&q).unwrap();
        let fp = preset.forward(&q).unwrap();
        a.push(fu.end_effector().translation);
        b.push(fp.transforms[preset.dof()].translation);
    }
    let w = rigid_fit(&a, &b);
    for (p, q) in a.iter().zip(&b) {
        assert!(
            (w.transform_point3(*p) - *q).length() < 1e-6,
            "the preset is not the URDF's kinematics"
        );
    }
    // The presets model the arm up to its flange: the Panda's hand (hung
    // from the flange) is not part of them.
    fit.bodies
        .into_iter()
        .filter(|b| b.name != "panda_hand")
        .map(|mut body| {
            for v in &mut body.mesh.vertices {
                *v = w.transform_point3(*v);
            }
            body
        })
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
    let c = report("panda", &spec, &bodies);
    assert!(c > 0.0);
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
    let c = report("ur5", &spec, &bodies);
    assert!(c > 0.0);
}
