//! Inverse dynamics, mass matrix, gravity and nonlinear torques of robots
//! imported from URDF (inertials mapped into the DH frames by
//! `dynamics::urdf`) against Pinocchio 4.1.0 on the same URDFs
//! (tests/data/dynamics: the fixtures, the script that made them and their
//! provenance). Runs natively and, unchanged, under `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use serde::Deserialize;

use skeleton_avoidance::dynamics::Dynamics;
use skeleton_avoidance::dynamics::urdf::{dynamics_from_urdf, urdf_bodies};
use skeleton_avoidance::kinematics::{Robot, RobotSpec};
use skeleton_avoidance::parsers::urdf::UrdfOptions;

/// Largest error relative to the largest magnitude of the compared
/// quantity over the sample (per robot and quantity).
const TOL: f64 = 1e-9;

#[derive(Deserialize)]
struct Fixture {
    robot: String,
    base: String,
    tip: String,
    joint_names: Vec<String>,
    links: Vec<String>,
    gravity: [f64; 3],
    samples: Vec<Sample>,
}

#[derive(Deserialize)]
struct Sample {
    q: Vec<f64>,
    qdot: Vec<f64>,
    qddot: Vec<f64>,
    tau: Vec<f64>,
    mass_matrix: Vec<Vec<f64>>,
    gravity_torque: Vec<f64>,
    nonlinear_effects: Vec<f64>,
}

/// Largest |got − want| over the largest |want|.
fn relative(got: &[f64], want: &[f64]) -> f64 {
    let scale = want.iter().fold(0.0_f64, |m, x| m.max(x.abs())).max(1e-300);
    got.iter()
        .zip(want)
        .fold(0.0_f64, |m, (g, w)| m.max((g - w).abs()))
        / scale
}

/// The relative errors of τ, M, g and C q̇ + g over every sample.
fn compare(xml: &str, json: &str) -> [f64; 4] {
    let fixture: Fixture = serde_json::from_str(json).unwrap();
    let options = UrdfOptions {
        base: Some(fixture.base.clone()),
        tip: Some(fixture.tip.clone()),
        ..UrdfOptions::default()
    };
    let imported = urdf_bodies(xml, &options).unwrap();
    assert_eq!(
        imported.spec.joint_names.as_deref(),
        Some(&fixture.joint_names[..]),
        "{}",
        fixture.robot
    );
    // The bodies lumped are the links the fixture kept, less those fixed
    // to the base.
    let mut lumped: Vec<&String> = imported.links.iter().flatten().collect();
    lumped.sort();
    let mut kept: Vec<&String> = fixture.links.iter().collect();
    kept.retain(|l| lumped.contains(l));
    kept.sort();
    assert_eq!(lumped, kept, "{}", fixture.robot);
    let g = glam::DVec3::from_array(fixture.gravity);
    let dynamics = dynamics_from_urdf(xml, &options)
        .unwrap()
        .with_gravity(g)
        .unwrap();
    // The spec as JavaScript holds it (JSON) gives the same dynamics.
    let json_spec: RobotSpec =
        serde_json::from_str(&serde_json::to_string(&imported.spec).unwrap()).unwrap();
    let from_json = Dynamics::from_robot(Robot::from_spec(&json_spec).unwrap())
        .unwrap()
        .with_gravity(g)
        .unwrap();
    assert_eq!(from_json, dynamics, "{}", fixture.robot);
    let n = dynamics.dof();
    let mut ws = dynamics.workspace();
    let (mut tau, mut m, mut grav, mut nle) =
        (vec![0.0; n], vec![0.0; n * n], vec![0.0; n], vec![0.0; n]);
    let (mut all_tau, mut all_m, mut all_g, mut all_nle) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let (mut want_tau, mut want_m, mut want_g, mut want_nle) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for s in &fixture.samples {
        dynamics
            .inverse_dynamics(&mut ws, &s.q, (&s.qdot, &s.qddot), &mut tau)
            .unwrap();
        dynamics.mass_matrix(&mut ws, &s.q, &mut m).unwrap();
        dynamics.gravity_torques(&mut ws, &s.q, &mut grav).unwrap();
        dynamics
            .nonlinear_effects(&mut ws, &s.q, &s.qdot, &mut nle)
            .unwrap();
        all_tau.extend_from_slice(&tau);
        all_m.extend_from_slice(&m);
        all_g.extend_from_slice(&grav);
        all_nle.extend_from_slice(&nle);
        want_tau.extend_from_slice(&s.tau);
        want_m.extend(s.mass_matrix.iter().flatten());
        want_g.extend_from_slice(&s.gravity_torque);
        want_nle.extend_from_slice(&s.nonlinear_effects);
    }
    let errors = [
        relative(&all_tau, &want_tau),
        relative(&all_m, &want_m),
        relative(&all_g, &want_g),
        relative(&all_nle, &want_nle),
    ];
    println!(
        "{}: relative error tau {:.1e}, M {:.1e}, g {:.1e}, C qdot + g {:.1e}",
        fixture.robot, errors[0], errors[1], errors[2], errors[3]
    );
    errors
}

fn check(xml: &str, json: &str) {
    let errors = compare(xml, json);
    for (what, e) in ["tau", "M", "g", "C qdot + g"].iter().zip(errors) {
        assert!(e < TOL, "{what}: relative error {e:e}");
    }
}

#[test]
fn panda_matches_pinocchio() {
    check(
        include_str!("data/urdf/panda_collision.urdf"),
        include_str!("data/dynamics/panda.json"),
    );
}

#[test]
fn ur5_matches_pinocchio() {
    check(
        include_str!("data/urdf/ur5_robot.urdf"),
        include_str!("data/dynamics/ur5.json"),
    );
}

#[test]
fn iiwa14_matches_pinocchio() {
    check(
        include_str!("data/urdf/iiwa14_primitive_collision.urdf"),
        include_str!("data/dynamics/iiwa14.json"),
    );
}

#[test]
fn pr2_arm_with_prismatic_torso_matches_pinocchio() {
    check(
        include_str!("data/urdf/pr2.urdf"),
        include_str!("data/dynamics/pr2_right_arm.json"),
    );
}

#[test]
fn random_chain_with_prismatic_joints_matches_pinocchio() {
    check(
        include_str!("data/dynamics/random_chain.urdf"),
        include_str!("data/dynamics/random_chain.json"),
    );
}
