//! Torque limits in every motion: a motion that would need more torque than
//! the data sheet gives is slowed, not driven beyond it (`world/dynamics.rs`),
//! and the torque mode tracks on the robot's own dynamics. Runs natively and
//! under `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use skeleton_avoidance::avoidance::Mode;
use skeleton_avoidance::dynamics::Dynamics;
use skeleton_avoidance::kinematics::{Robot, RobotSpec, presets};
use skeleton_avoidance::scenario::{RobotRef, Scenario, Trace, audit, audit_torque};
use skeleton_avoidance::world::{World, simulate};

const Q0: [f64; 7] = [0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8];
const GOAL: [f64; 3] = [0.1, 0.55, 0.35];

fn scenario(spec: RobotSpec) -> Scenario {
    let mut s: Scenario = serde_json::from_value(serde_json::json!({
        "robot": { "preset": "panda" }, "obstacles": [], "dt": 0.002, "duration": 3.0,
        "sampleEvery": 1, "task": { "type": "goal", "position": GOAL }
    }))
    .unwrap();
    s.robot = RobotRef::Spec(Box::new(spec));
    s.q0 = Some(Q0.to_vec());
    s
}

/// The first time the end effector is within 1 cm of the goal.
fn time_to_goal(robot: &Robot, trace: &Trace) -> f64 {
    let goal = glam::DVec3::from_array(GOAL);
    trace
        .samples
        .iter()
        .find(|s| (robot.forward(&s.q).unwrap().end_effector().translation - goal).length() < 0.01)
        .map_or(f64::INFINITY, |s| s.t)
}

/// Per joint: peak |τ| and peak |g(q)| over the trace.
fn peaks(dynamics: &Dynamics, trace: &Trace) -> (Vec<f64>, Vec<f64>) {
    let n = dynamics.dof();
    let mut ws = dynamics.workspace();
    let (mut tau, mut g) = (vec![0.0; n], vec![0.0; n]);
    let (mut peak_tau, mut peak_g) = (vec![0.0_f64; n], vec![0.0_f64; n]);
    let s = &trace.samples;
    let h = s[1].t - s[0].t;
    for k in 1..s.len() - 1 {
        let v: Vec<f64> = (0..n).map(|i| (s[k].q[i] - s[k - 1].q[i]) / h).collect();
        let a: Vec<f64> = (0..n)
            .map(|i| ((s[k + 1].q[i] - s[k].q[i]) / h - v[i]) / h)
            .collect();
        dynamics
            .inverse_dynamics(&mut ws, &s[k].q, (&v, &a), &mut tau)
            .unwrap();
        dynamics.gravity_torques(&mut ws, &s[k].q, &mut g).unwrap();
        for i in 0..n {
            peak_tau[i] = peak_tau[i].max(tau[i].abs());
            peak_g[i] = peak_g[i].max(g[i].abs());
        }
    }
    (peak_tau, peak_g)
}

#[test]
fn a_motion_that_needs_more_torque_than_the_data_sheet_is_slowed() {
    let spec = presets::preset("panda").unwrap();
    let s = scenario(spec.clone());
    let robot = s.build_robot().unwrap();
    let full = simulate(&s).unwrap();
    let a_full = audit(&robot, &full);
    assert!(a_full.admissible(), "{a_full:?}");
    let dynamics = Dynamics::from_robot(robot.clone()).unwrap();
    let (tau, g) = peaks(&dynamics, &full);
    // Limits that hold the arm against gravity with room to spare but
    // allow only part of the torque the unconstrained motion used.
    let mut weak = spec;
    let mut binding = 0;
    for (i, j) in weak.joints.iter_mut().enumerate() {
        let limit = (1.5 * g[i] + 1.0).max(0.5 * tau[i]);
        if limit < tau[i] {
            binding += 1;
        }
        j.max_torque = Some(limit);
    }
    assert!(binding > 0, "peaks {tau:?}, gravity {g:?}");
    let s_weak = scenario(weak);
    let weak_robot = s_weak.build_robot().unwrap();
    let weak_dynamics = Dynamics::from_robot(weak_robot.clone()).unwrap();
    let needed = audit_torque(&weak_dynamics, &full);
    let slowed = simulate(&s_weak).unwrap();
    let a = audit(&weak_robot, &slowed);
    let (t_full, t_weak) = (
        time_to_goal(&robot, &full),
        time_to_goal(&weak_robot, &slowed),
    );
    eprintln!(
        "unconstrained: |τ|/lim {:.3} of the weak limits, goal at {t_full:.3} s; \
         with them: |τ|/lim {:?}, goal at {t_weak:.3} s",
        needed, a.torque
    );
    assert!(needed > 1.05, "the full motion needs more: {needed}");
    assert!(a.admissible(), "{a:?}");
    assert!(a.torque.is_some_and(|t| t <= 1.0), "{a:?}");
    assert!(
        t_weak.is_finite() && t_weak > t_full,
        "{t_weak} vs {t_full}"
    );
}

#[test]
fn torque_mode_reaches_its_goal_within_every_limit() {
    let mut s = scenario(presets::preset("panda").unwrap());
    s.controller.mode = Mode::Torque;
    let robot = s.build_robot().unwrap();
    let trace = simulate(&s).unwrap();
    let a = audit(&robot, &trace);
    let t = time_to_goal(&robot, &trace);
    eprintln!("torque mode: {a:?}, goal at {t:.3} s");
    assert!(a.admissible(), "{a:?}");
    assert!(t < 3.0, "{t}");
    // The world reports the drive torques of each step.
    let mut w = World::new(s).unwrap();
    for _ in 0..50 {
        w.step(0.002);
    }
    let st = w.state();
    assert_eq!(st.torque.len(), 7);
    for (t, j) in st.torque.iter().zip(&robot.joints) {
        assert!(t.abs() <= j.max_torque, "{t}");
    }
}

#[test]
fn torque_mode_and_pfl_need_inertial_data() {
    let mut spec = presets::preset("panda").unwrap();
    spec.joints[2].inertial = None;
    spec.joints[4].inertial = None;
    let mut s = scenario(spec);
    s.controller.mode = Mode::Torque;
    let e = World::new(s.clone()).unwrap_err().to_string();
    assert!(
        e.contains("controller.mode") && (e.contains("panda_link3") || e.contains("link 3")),
        "{e}"
    );
    s.controller.mode = Mode::Velocity;
    let mut w = World::new(s).unwrap();
    let e = w
        .update_controller(&serde_json::json!({ "protective": { "mode": "pfl" } }))
        .unwrap_err()
        .to_string();
    assert!(e.contains("controller.protective.mode"), "{e}");
    assert!(e.contains("inertial"), "{e}");
    assert_eq!(
        w.scenario().controller.protective.mode,
        skeleton_avoidance::avoidance::protect::ProtectiveMode::Ssm
    );
}
