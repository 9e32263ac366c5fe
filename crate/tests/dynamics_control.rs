//! The torque mode on the robot's own dynamics (`avoidance::computed_torque`)
//! and the mass matrix's factor, on the Panda as its URDF describes it:
//! gravity and Coriolis compensated, forces acting through the coupled
//! `M(q)`, torques within the data sheet, effective masses. Runs natively
//! and under `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::DVec3;
use skeleton_avoidance::avoidance::{
    ControllerConfig, TaskReference, TorqueInput, TorqueScratch, computed_torque, torque_control,
};
use skeleton_avoidance::dynamics::urdf::dynamics_from_urdf;
use skeleton_avoidance::dynamics::{Dynamics, MassFactor};
use skeleton_avoidance::parsers::urdf::UrdfOptions;

fn panda() -> Dynamics {
    let options = UrdfOptions {
        base: Some("panda_link0".into()),
        tip: Some("panda_hand".into()),
        ..UrdfOptions::default()
    };
    dynamics_from_urdf(include_str!("data/urdf/panda_collision.urdf"), &options).unwrap()
}

const Q: [f64; 7] = [0.3, -0.4, 0.2, -2.0, 0.1, 1.8, 0.6];

fn hold(dynamics: &Dynamics, q: &[f64]) -> TaskReference {
    let frames = dynamics.robot().forward(q).unwrap();
    TaskReference {
        position: frames.end_effector().translation,
        velocity: DVec3::ZERO,
        acceleration: DVec3::ZERO,
        orientation: None,
        chain: 0,
        point: None,
    }
}

/// Runs the controller once: the request and the drive torques.
fn run(
    d: &Dynamics,
    qdot: &[f64],
    tasks: &[TaskReference],
    config: &ControllerConfig,
) -> (Vec<f64>, Vec<f64>) {
    let frames = d.robot().forward(&Q).unwrap();
    let input = TorqueInput {
        dynamics: d,
        frames: &frames,
        q: &Q,
        qdot,
        points: &[],
        tasks,
        config,
        dt: 0.001,
    };
    torque_control(&input, &mut TorqueScratch::new(d)).unwrap()
}

#[test]
fn an_arm_holding_its_pose_at_rest_is_held_by_gravity_compensation_alone() {
    let d = panda();
    let (request, tau) = run(&d, &[0.0; 7], &[hold(&d, &Q)], &ControllerConfig::default());
    let mut ws = d.workspace();
    let mut g = vec![0.0; 7];
    d.gravity_torques(&mut ws, &Q, &mut g).unwrap();
    for (k, (t, gk)) in tau.iter().zip(&g).enumerate() {
        assert!((t - gk).abs() < 1e-9, "joint {k}: {t} vs g {gk}");
    }
    assert!(g.iter().any(|x| x.abs() > 1.0), "gravity acts: {g:?}");
    assert!(request.iter().all(|v| v.abs() < 1e-12), "{request:?}");
}

#[test]
fn a_task_force_accelerates_the_arm_through_its_coupled_mass_matrix() {
    let d = panda();
    let mut target = hold(&d, &Q);
    target.position += DVec3::new(0.02, -0.01, 0.03);
    let config = ControllerConfig::default();
    let qdot = [0.1, -0.2, 0.05, 0.3, -0.1, 0.2, 0.0];
    let (request, tau) = run(&d, &qdot, &[target], &config);
    // q̈ = M⁻¹ (τ − C q̇ − g), with τ the controller's (within the limits).
    let mut ws = d.workspace();
    let mut nle = vec![0.0; 7];
    d.nonlinear_effects(&mut ws, &Q, &qdot, &mut nle).unwrap();
    let mut m = vec![0.0; 49];
    d.mass_matrix(&mut ws, &Q, &mut m).unwrap();
    let qdd: Vec<f64> = request
        .iter()
        .zip(&qdot)
        .map(|(r, v)| (r - v) / 0.001)
        .collect();
    for i in 0..7 {
        let mq: f64 = (0..7).map(|k| m[i * 7 + k] * qdd[k]).sum();
        assert!(
            (mq + nle[i] - tau[i]).abs() < 1e-8,
            "joint {i}: M q̈ + h = {} vs τ {}",
            mq + nle[i],
            tau[i]
        );
    }
    // The forces are the Jᵀ f of the task and the joint damping.
    let frames = d.robot().forward(&Q).unwrap();
    let input = TorqueInput {
        dynamics: &d,
        frames: &frames,
        q: &Q,
        qdot: &qdot,
        points: &[],
        tasks: &[target],
        config: &config,
        dt: 0.001,
    };
    let forces = computed_torque::force_torques(&input).unwrap();
    for i in 0..7 {
        assert!((forces[i] + nle[i] - tau[i]).abs() < 1e-9);
    }
}

#[test]
fn drive_torques_stay_within_the_data_sheet() {
    let d = panda();
    let mut target = hold(&d, &Q);
    target.position += DVec3::new(0.5, 0.5, -0.5);
    let mut config = ControllerConfig::default();
    config.torque.stiffness = 1e5;
    let (_, tau) = run(&d, &[0.0; 7], &[target], &config);
    let mut at_limit = 0;
    for (t, j) in tau.iter().zip(&d.robot().joints) {
        assert!(t.abs() <= j.max_torque + 1e-12, "{t} vs {}", j.max_torque);
        if (t.abs() - j.max_torque).abs() < 1e-9 {
            at_limit += 1;
        }
    }
    assert!(at_limit > 0, "a stiff task saturates some joint: {tau:?}");
}

#[test]
fn effective_mass_is_the_inverse_of_the_directional_mobility() {
    let d = panda();
    let mut ws = d.workspace();
    let mut f = MassFactor::default();
    f.update(&d, &mut ws, &Q).unwrap();
    let frames = d.robot().forward(&Q).unwrap();
    let tip = skeleton_avoidance::control_point::DhPoint {
        link: 7,
        d: d.robot().joints[6].d,
        a: d.robot().joints[6].a,
    };
    let j = tip.jacobians(d.robot(), &frames);
    let mut masses = Vec::new();
    for u in [DVec3::X, DVec3::Y, DVec3::Z] {
        let row: Vec<f64> = j.j_theta.iter().map(|c| c.dot(u)).collect();
        let m = f.effective_mass(&row);
        // The mass is what a unit force along u accelerates the point by:
        // a = uᵀ J M⁻¹ Jᵀ u · 1 N.
        let mut qdd = vec![0.0; 7];
        f.solve(&row, &mut qdd);
        let a: f64 = row.iter().zip(&qdd).map(|(r, x)| r * x).sum();
        assert!((m * a - 1.0).abs() < 1e-9);
        masses.push(m);
    }
    // The Panda weighs about 18 kg; its tip feels a few kilograms.
    assert!(masses.iter().all(|m| *m > 0.3 && *m < 18.0), "{masses:?}");
}
