//! Forward dynamics and energy: `forward_dynamics` inverts
//! `inverse_dynamics`, and a torque-free simulation conserves the total
//! energy `T + V` to 1e-6 (relative to the largest kinetic energy reached,
//! at least 1 J) over 10 s, integrated by classical Runge–Kutta (RK4) with
//! a step of 0.5 ms, on the presets with inertial data (the Panda in the
//! modified convention, a moved base with gravity tilted, the dual arm's
//! branches) and the random chain with prismatic joints. Runs natively and,
//! unchanged, under `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::{DQuat, DVec3};

use skeleton_avoidance::dynamics::urdf::dynamics_from_urdf;
use skeleton_avoidance::dynamics::{Dynamics, Workspace};
use skeleton_avoidance::kinematics::{PoseSpec, Robot, presets::preset};
use skeleton_avoidance::parsers::urdf::UrdfOptions;
use skeleton_avoidance::rng::Rng;

/// Integration step (s) and duration (s).
const DT: f64 = 5e-4;
const DURATION: f64 = 10.0;

fn of_preset(name: &str) -> Dynamics {
    Dynamics::from_robot(Robot::from_spec(&preset(name).unwrap()).unwrap()).unwrap()
}

/// The Panda on a tilted, moved base, gravity along −z of the world.
fn moved_panda() -> Dynamics {
    let mut spec = preset("panda").unwrap();
    let turn = DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 0.5).normalize(), 0.7);
    spec.base = Some(PoseSpec {
        position: [0.4, -0.3, 0.8],
        rotation: turn.to_array(),
    });
    Dynamics::from_robot(Robot::from_spec(&spec).unwrap()).unwrap()
}

fn random_chain() -> Dynamics {
    let options = UrdfOptions {
        base: Some("base".to_owned()),
        tip: Some("tip".to_owned()),
        ..UrdfOptions::default()
    };
    dynamics_from_urdf(include_str!("data/dynamics/random_chain.urdf"), &options).unwrap()
}

fn cases() -> Vec<(&'static str, Dynamics)> {
    vec![
        ("panda", of_preset("panda")),
        ("ur5", of_preset("ur5")),
        ("iiwa14", of_preset("iiwa14")),
        ("lwr4", of_preset("lwr4")),
        ("dual-arm", of_preset("dual-arm")),
        ("panda, moved base", moved_panda()),
        ("random chain", random_chain()),
    ]
}

#[test]
fn forward_dynamics_inverts_inverse_dynamics() {
    let mut rng = Rng::new(21);
    for (name, dynamics) in cases() {
        let n = dynamics.dof();
        let mut ws = dynamics.workspace();
        let (mut tau, mut back) = (vec![0.0; n], vec![0.0; n]);
        for _ in 0..10 {
            let mut draw = |s: f64| {
                (0..n)
                    .map(|_| s * (2.0 * rng.uniform() - 1.0))
                    .collect::<Vec<f64>>()
            };
            let (q, qd, qdd) = (draw(1.5), draw(1.0), draw(4.0));
            dynamics
                .inverse_dynamics(&mut ws, &q, (&qd, &qdd), &mut tau)
                .unwrap();
            dynamics
                .forward_dynamics(&mut ws, &q, (&qd, &tau), &mut back)
                .unwrap();
            let scale = qdd.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
            let e = back
                .iter()
                .zip(&qdd)
                .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(e < 1e-9 * scale, "{name}: {e:e}");
        }
    }
}

/// `T + V` at a state.
fn energy(d: &Dynamics, ws: &mut Workspace, q: &[f64], qd: &[f64]) -> (f64, f64) {
    let t = d.kinetic_energy(ws, q, qd).unwrap();
    (t, t + d.potential_energy(ws, q).unwrap())
}

/// One RK4 step of `(q, q̇)' = (q̇, FD(q, q̇, 0))`.
fn rk4(d: &Dynamics, ws: &mut Workspace, q: &mut [f64], qd: &mut [f64], dt: f64) {
    let n = q.len();
    let zero = vec![0.0; n];
    let mut accel = |q: &[f64], qd: &[f64]| {
        let mut a = vec![0.0; n];
        d.forward_dynamics(ws, q, (qd, &zero), &mut a).unwrap();
        a
    };
    let at = |x: &[f64], k: &[f64], h: f64| -> Vec<f64> {
        x.iter().zip(k).map(|(x, k)| x + h * k).collect()
    };
    let (k1q, k1v) = (qd.to_vec(), accel(q, qd));
    let (q2, v2) = (at(q, &k1q, dt / 2.0), at(qd, &k1v, dt / 2.0));
    let (k2q, k2v) = (v2.clone(), accel(&q2, &v2));
    let (q3, v3) = (at(q, &k2q, dt / 2.0), at(qd, &k2v, dt / 2.0));
    let (k3q, k3v) = (v3.clone(), accel(&q3, &v3));
    let (q4, v4) = (at(q, &k3q, dt), at(qd, &k3v, dt));
    let (k4q, k4v) = (v4.clone(), accel(&q4, &v4));
    for i in 0..n {
        q[i] += dt / 6.0 * (k1q[i] + 2.0 * k2q[i] + 2.0 * k3q[i] + k4q[i]);
        qd[i] += dt / 6.0 * (k1v[i] + 2.0 * k2v[i] + 2.0 * k3v[i] + k4v[i]);
    }
}

#[test]
fn a_torque_free_arm_conserves_its_energy_over_ten_seconds() {
    for (name, dynamics) in cases() {
        let n = dynamics.dof();
        let mut ws = dynamics.workspace();
        // Released from a bent posture with some speed at every joint.
        let mut q: Vec<f64> = (0..n).map(|k| 0.4 - 0.23 * k as f64).collect();
        let mut qd: Vec<f64> = (0..n).map(|k| 0.3 * ((k as f64) + 1.0).sin()).collect();
        let (_, e0) = energy(&dynamics, &mut ws, &q, &qd);
        let (mut drift, mut largest_t): (f64, f64) = (0.0, 1.0);
        let steps = (DURATION / DT).round() as usize;
        for _ in 0..steps {
            rk4(&dynamics, &mut ws, &mut q, &mut qd, DT);
            let (t, e) = energy(&dynamics, &mut ws, &q, &qd);
            drift = drift.max((e - e0).abs());
            largest_t = largest_t.max(t);
        }
        println!(
            "{name}: |E − E0| ≤ {drift:.2e} J over {DURATION} s (RK4, {DT} s), largest T {largest_t:.2} J, relative {:.1e}",
            drift / largest_t
        );
        assert!(
            drift <= 1e-6 * largest_t,
            "{name}: energy drifts by {drift:e} J"
        );
    }
}

#[test]
fn a_joint_moving_no_mass_is_named() {
    let body = |mass: f64, x: f64| skeleton_avoidance::dynamics::InertialSpec {
        mass,
        com: [x, 0.0, 0.0],
        inertia: [0.0; 6],
    };
    let q = [0.1, 0.2, 0.3];
    let zero = [0.0; 3];
    let mut a = vec![0.0; 3];
    // planar3's row 3 has a = 0.2: a point mass at −0.2 m in frame 3 sits
    // on joint 3's axis, and a massless row moves nothing at all.
    for last in [body(1.0, -0.2), body(0.0, 0.0)] {
        let mut spec = preset("planar3").unwrap();
        for row in &mut spec.joints {
            row.inertial = Some(body(1.0, -0.1));
        }
        spec.joints[2].inertial = Some(last);
        let dynamics = Dynamics::from_robot(Robot::from_spec(&spec).unwrap()).unwrap();
        let mut ws = dynamics.workspace();
        let e = dynamics
            .forward_dynamics(&mut ws, &q, (&zero, &zero), &mut a)
            .unwrap_err();
        assert!(e.to_string().contains("joint 3 moves no mass"), "{e}");
        let e = dynamics
            .forward_dynamics(&mut ws, &q, (&zero, &[0.0, f64::NAN, 0.0]), &mut a)
            .unwrap_err();
        assert_eq!(e.to_string(), "tau[1]: not a finite number");
    }
}
