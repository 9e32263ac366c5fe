//! Properties of the recursions on every preset (both conventions, the
//! Stanford arm's prismatic joint, the dual arm's branches) with random
//! bodies, a two-link planar arm against its closed form, energy, a moved
//! base, and bad input.
//!
//! Test code only: `dynamics/mod.rs` declares this file `#[cfg(test)] mod
//! tests;`, so its `unwrap`s are never compiled into the library a
//! JavaScript or Rust caller uses.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use glam::{DAffine3, DMat3, DQuat, DVec3};

use super::inertia::{Inertial, InertialSpec};
use super::{DEFAULT_GRAVITY, Dynamics};
use crate::kinematics::{JointSpec, PoseSpec, Robot, RobotSpec, presets};
use crate::rng::Rng;

/// A random body: box-like principal moments (so the triangle inequality
/// holds), turned by a random rotation, centre of mass within 0.2 m.
fn random_body(rng: &mut Rng) -> Inertial {
    let mass = rng.range(0.5, 4.0);
    let s = DVec3::new(
        rng.range(0.02, 0.3),
        rng.range(0.02, 0.3),
        rng.range(0.02, 0.3),
    );
    let s = s * s * (mass / 12.0);
    let principal = DVec3::new(s.y + s.z, s.x + s.z, s.x + s.y);
    let r = DMat3::from_quat(DQuat::from_axis_angle(rng.unit3(), rng.range(-3.0, 3.0)));
    let tensor = r * DMat3::from_diagonal(principal) * r.transpose();
    Inertial::new(mass, rng.vec3(0.2), tensor).unwrap()
}

fn random_dynamics(spec: &RobotSpec, rng: &mut Rng) -> Dynamics {
    let robot = Robot::from_spec(spec).unwrap();
    let bodies = (0..robot.dof()).map(|_| random_body(rng)).collect();
    Dynamics::new(robot, bodies).unwrap()
}

fn random_state(n: usize, rng: &mut Rng) -> [Vec<f64>; 3] {
    let mut v = || (0..n).map(|_| rng.range(-1.5, 1.5)).collect::<Vec<f64>>();
    [v(), v(), v()]
}

fn all_presets() -> Vec<RobotSpec> {
    presets::NAMES
        .iter()
        .map(|n| presets::preset(n).unwrap())
        .collect()
}

fn max_abs(a: &[f64]) -> f64 {
    a.iter().fold(0.0, |m, x| m.max(x.abs()))
}

#[test]
fn mass_matrix_is_symmetric_positive_definite() {
    let mut rng = Rng::new(1);
    for spec in all_presets() {
        let dynamics = random_dynamics(&spec, &mut rng);
        let mut ws = dynamics.workspace();
        let n = dynamics.dof();
        let mut m = vec![0.0; n * n];
        for _ in 0..20 {
            let [q, _, _] = random_state(n, &mut rng);
            dynamics.mass_matrix(&mut ws, &q, &mut m).unwrap();
            let scale = max_abs(&m);
            for i in 0..n {
                for j in 0..n {
                    assert!((m[i * n + j] - m[j * n + i]).abs() <= 1e-14 * scale);
                }
            }
            // Cholesky succeeds with positive pivots.
            let mut l = m.clone();
            for j in 0..n {
                for k in 0..j {
                    let ljk = l[j * n + k];
                    for i in j..n {
                        l[i * n + j] -= l[i * n + k] * ljk;
                    }
                }
                let pivot = l[j * n + j];
                assert!(
                    pivot > 1e-12 * scale,
                    "{:?}: pivot {j} = {pivot}",
                    spec.name
                );
                let root = pivot.sqrt();
                for i in j..n {
                    l[i * n + j] /= root;
                }
            }
        }
    }
}

#[test]
fn newton_euler_equals_mass_matrix_coriolis_and_gravity() {
    let mut rng = Rng::new(2);
    for spec in all_presets() {
        let dynamics = random_dynamics(&spec, &mut rng);
        let mut ws = dynamics.workspace();
        let n = dynamics.dof();
        let (mut m, mut c, mut g, mut tau, mut nle) = (
            vec![0.0; n * n],
            vec![0.0; n],
            vec![0.0; n],
            vec![0.0; n],
            vec![0.0; n],
        );
        for _ in 0..20 {
            let [q, qd, qdd] = random_state(n, &mut rng);
            dynamics
                .inverse_dynamics(&mut ws, &q, (&qd, &qdd), &mut tau)
                .unwrap();
            dynamics.mass_matrix(&mut ws, &q, &mut m).unwrap();
            dynamics.coriolis(&mut ws, &q, &qd, &mut c).unwrap();
            dynamics.gravity_torques(&mut ws, &q, &mut g).unwrap();
            dynamics
                .nonlinear_effects(&mut ws, &q, &qd, &mut nle)
                .unwrap();
            let scale = max_abs(&tau).max(1.0);
            for i in 0..n {
                let mq: f64 = (0..n).map(|j| m[i * n + j] * qdd[j]).sum();
                let sum = mq + c[i] + g[i];
                assert!(
                    (sum - tau[i]).abs() < 1e-12 * scale,
                    "{:?} row {i}: {sum} vs {}",
                    spec.name,
                    tau[i]
                );
                assert!((nle[i] - c[i] - g[i]).abs() < 1e-12 * scale);
            }
        }
    }
}

/// Spong, Hutchinson & Vidyasagar, *Robot Modeling and Control*, §7.3.2:
/// two links in the x–y plane, gravity along −y, centres of mass on the
/// links at `lc` from their joints, inertias `I` about z through them.
#[test]
fn two_link_planar_arm_matches_its_closed_form() {
    let (a1, a2, m1, m2, lc1, lc2, i1, i2, g0) = (0.7, 0.5, 3.0, 2.0, 0.3, 0.2, 0.11, 0.05, 9.81);
    let row = |a: f64| JointSpec {
        a,
        ..JointSpec::default()
    };
    let spec = RobotSpec {
        name: None,
        convention: crate::kinematics::Convention::Standard,
        base: None,
        joints: vec![row(a1), row(a2)],
        tool: None,
        branches: Vec::new(),
        joint_names: None,
        link_names: None,
        self_collision_exclude: Vec::new(),
    };
    // Frame i sits at the end of link i: the centre of mass is behind it.
    let body = |m: f64, a: f64, lc: f64, i: f64| {
        let tensor = DMat3::from_diagonal(DVec3::new(i, i, i));
        Inertial::new(m, DVec3::new(lc - a, 0.0, 0.0), tensor).unwrap()
    };
    let dynamics = Dynamics::new(
        Robot::from_spec(&spec).unwrap(),
        vec![body(m1, a1, lc1, i1), body(m2, a2, lc2, i2)],
    )
    .unwrap()
    .with_gravity(DVec3::new(0.0, -g0, 0.0))
    .unwrap();
    let mut ws = dynamics.workspace();
    let mut rng = Rng::new(3);
    let mut tau = [0.0; 2];
    let mut m = [0.0; 4];
    for _ in 0..50 {
        let [q, qd, qdd] = random_state(2, &mut rng);
        let (c1, c2, c12) = (q[0].cos(), q[1].cos(), (q[0] + q[1]).cos());
        let s2 = q[1].sin();
        let m11 = m1 * lc1 * lc1 + m2 * (a1 * a1 + lc2 * lc2 + 2.0 * a1 * lc2 * c2) + i1 + i2;
        let m12 = m2 * (lc2 * lc2 + a1 * lc2 * c2) + i2;
        let m22 = m2 * lc2 * lc2 + i2;
        let h = -m2 * a1 * lc2 * s2;
        let g1 = (m1 * lc1 + m2 * a1) * g0 * c1 + m2 * lc2 * g0 * c12;
        let g2 = m2 * lc2 * g0 * c12;
        let t1 = m11 * qdd[0] + m12 * qdd[1] + h * (2.0 * qd[0] * qd[1] + qd[1] * qd[1]) + g1;
        let t2 = m12 * qdd[0] + m22 * qdd[1] - h * qd[0] * qd[0] + g2;
        dynamics
            .inverse_dynamics(&mut ws, &q, (&qd, &qdd), &mut tau)
            .unwrap();
        dynamics.mass_matrix(&mut ws, &q, &mut m).unwrap();
        for (got, want) in tau.iter().zip([t1, t2]) {
            assert!((got - want).abs() < 1e-12, "{got} vs {want}");
        }
        for (got, want) in m.iter().zip([m11, m12, m12, m22]) {
            assert!((got - want).abs() < 1e-13, "{got} vs {want}");
        }
    }
}

/// Along `q(t) = q + q̇ t + ½ q̈ t²`, `dT/dt = q̇ᵀ (τ − g)` (the power of the
/// non-gravity torques), by a central difference of the kinetic energy.
#[test]
fn kinetic_energy_changes_by_the_power_of_the_torques() {
    let mut rng = Rng::new(4);
    for spec in all_presets() {
        let dynamics = random_dynamics(&spec, &mut rng);
        let mut ws = dynamics.workspace();
        let n = dynamics.dof();
        let (mut tau, mut g) = (vec![0.0; n], vec![0.0; n]);
        for _ in 0..10 {
            let [q, qd, qdd] = random_state(n, &mut rng);
            let mut energy = |t: f64| {
                let qt: Vec<f64> = (0..n)
                    .map(|i| q[i] + qd[i] * t + 0.5 * qdd[i] * t * t)
                    .collect();
                let vt: Vec<f64> = (0..n).map(|i| qd[i] + qdd[i] * t).collect();
                dynamics.kinetic_energy(&mut ws, &qt, &vt).unwrap()
            };
            let h = 1e-5;
            let rate = (energy(h) - energy(-h)) / (2.0 * h);
            dynamics
                .inverse_dynamics(&mut ws, &q, (&qd, &qdd), &mut tau)
                .unwrap();
            dynamics.gravity_torques(&mut ws, &q, &mut g).unwrap();
            let power: f64 = (0..n).map(|i| qd[i] * (tau[i] - g[i])).sum();
            let scale = max_abs(&tau).max(1.0);
            assert!(
                (rate - power).abs() < 1e-6 * scale,
                "{:?}: {rate} vs {power}",
                spec.name
            );
        }
    }
}

/// The gravity torques are the gradient of the potential energy `−m gᵀ c`.
#[test]
fn gravity_torques_are_the_gradient_of_the_potential() {
    let mut rng = Rng::new(5);
    for spec in all_presets() {
        let dynamics = random_dynamics(&spec, &mut rng);
        let robot = dynamics.robot().clone();
        let n = dynamics.dof();
        let potential = |q: &[f64]| {
            let f = robot.forward(q).unwrap();
            (0..n)
                .map(|k| {
                    let b = dynamics.bodies()[k];
                    -b.mass * DEFAULT_GRAVITY.dot(f.transforms[k + 1].transform_point3(b.com))
                })
                .sum::<f64>()
        };
        let mut ws = dynamics.workspace();
        let mut g = vec![0.0; n];
        let [q, _, _] = random_state(n, &mut rng);
        dynamics.gravity_torques(&mut ws, &q, &mut g).unwrap();
        for i in 0..n {
            let (mut up, mut down) = (q.clone(), q.clone());
            up[i] += 1e-6;
            down[i] -= 1e-6;
            let slope = (potential(&up) - potential(&down)) / 2e-6;
            assert!(
                (slope - g[i]).abs() < 1e-6 * max_abs(&g).max(1.0),
                "{slope} vs {}",
                g[i]
            );
        }
    }
}

/// Moving the base and turning gravity with it changes no joint torque.
#[test]
fn a_moved_base_with_gravity_turned_alike_gives_the_same_torques() {
    let mut rng = Rng::new(6);
    for spec in all_presets() {
        let dynamics = random_dynamics(&spec, &mut rng);
        let turn = DQuat::from_axis_angle(rng.unit3(), 1.1);
        let mut moved = spec.clone();
        let base = spec.base.map_or(DAffine3::IDENTITY, |p| {
            DAffine3::from_rotation_translation(
                DQuat::from_array(p.rotation),
                DVec3::from_array(p.position),
            )
        });
        let new_base = DAffine3::from_rotation_translation(turn, DVec3::new(3.0, -2.0, 1.5)) * base;
        let r = DQuat::from_mat3(&new_base.matrix3).normalize();
        moved.base = Some(PoseSpec {
            position: new_base.translation.to_array(),
            rotation: r.to_array(),
        });
        let other = Dynamics::new(
            Robot::from_spec(&moved).unwrap(),
            dynamics.bodies().to_vec(),
        )
        .unwrap()
        .with_gravity(turn * DEFAULT_GRAVITY)
        .unwrap();
        let n = dynamics.dof();
        let (mut ws, mut ws2) = (dynamics.workspace(), other.workspace());
        let (mut t1, mut t2) = (vec![0.0; n], vec![0.0; n]);
        let [q, qd, qdd] = random_state(n, &mut rng);
        dynamics
            .inverse_dynamics(&mut ws, &q, (&qd, &qdd), &mut t1)
            .unwrap();
        other
            .inverse_dynamics(&mut ws2, &q, (&qd, &qdd), &mut t2)
            .unwrap();
        for (a, b) in t1.iter().zip(&t2) {
            assert!((a - b).abs() < 1e-10 * max_abs(&t1).max(1.0), "{a} vs {b}");
        }
    }
}

#[test]
fn bad_inertial_data_is_refused_naming_the_field() {
    let spec = |mass: f64, com: [f64; 3], inertia: [f64; 6]| InertialSpec { mass, com, inertia };
    let err = |s: InertialSpec| Inertial::from_spec(&s).unwrap_err().to_string();
    let unit = [1.0, 0.0, 0.0, 1.0, 0.0, 1.0];
    assert_eq!(err(spec(-1.0, [0.0; 3], unit)), "mass: must be >= 0");
    assert_eq!(
        err(spec(f64::NAN, [0.0; 3], unit)),
        "mass: not a finite number"
    );
    assert_eq!(
        err(spec(1.0, [0.0, f64::INFINITY, 0.0], unit)),
        "com[1]: not a finite number"
    );
    assert_eq!(
        err(spec(1.0, [0.0; 3], [1.0, f64::NAN, 0.0, 1.0, 0.0, 1.0])),
        "inertia[1]: not a finite number"
    );
    let e = err(spec(1.0, [0.0; 3], [1.0, 0.0, 0.0, -1.0, 0.0, 1.0]));
    assert!(e.starts_with("inertia: not positive semi-definite"), "{e}");
    let e = err(spec(1.0, [0.0; 3], [1.0, 0.0, 0.0, 1.0, 0.0, 3.0]));
    assert!(
        e.starts_with("inertia: principal moments") && e.contains("triangle inequality"),
        "{e}"
    );
    let asym = DMat3::from_cols(
        DVec3::new(1.0, 0.2, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::Z,
    );
    let e = Inertial::new(1.0, DVec3::ZERO, asym)
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("inertia: not symmetric"), "{e}");
    // A thin rod sits on the triangle inequality; a point mass has none.
    assert!(Inertial::from_spec(&spec(1.0, [0.0; 3], [1.0, 0.0, 0.0, 1.0, 0.0, 0.0])).is_ok());
    assert!(Inertial::from_spec(&spec(1.0, [0.0; 3], [0.0; 6])).is_ok());
}

#[test]
fn bad_states_and_missing_bodies_are_refused() {
    let robot = Robot::from_spec(&presets::preset("panda").unwrap()).unwrap();
    let e = Dynamics::new(robot.clone(), vec![Inertial::ZERO; 6]).unwrap_err();
    assert_eq!(
        e.to_string(),
        "inertials: expected 7 bodies (one per joint), got 6"
    );
    let mut partial = vec![Some(Inertial::ZERO); 7];
    partial[2] = None;
    partial[4] = None;
    let e = Dynamics::from_optional(robot.clone(), partial).unwrap_err();
    assert_eq!(e.field, "inertials");
    assert!(
        e.reason.contains(&robot.link_label(3)) && e.reason.contains(&robot.link_label(5)),
        "{e}"
    );
    let e = Dynamics::new(robot.clone(), vec![Inertial::ZERO; 7])
        .unwrap()
        .with_gravity(DVec3::new(0.0, f64::NAN, 0.0))
        .unwrap_err();
    assert_eq!(e.to_string(), "gravity[1]: not a finite number");
    let mut rng = Rng::new(7);
    let dynamics = random_dynamics(&presets::preset("panda").unwrap(), &mut rng);
    let mut ws = dynamics.workspace();
    let mut tau = vec![0.0; 7];
    let ok = vec![0.1; 7];
    let mut bad = ok.clone();
    bad[3] = f64::NAN;
    let run = |ws: &mut super::Workspace, tau: &mut [f64], q: &[f64], qd: &[f64], qdd: &[f64]| {
        dynamics
            .inverse_dynamics(ws, q, (qd, qdd), tau)
            .unwrap_err()
            .to_string()
    };
    assert_eq!(
        run(&mut ws, &mut tau, &ok[..6], &ok, &ok),
        "q: expected 7 joint values, got 6"
    );
    assert_eq!(
        run(&mut ws, &mut tau, &ok, &bad, &ok),
        "qdot[3]: not a finite number"
    );
    assert_eq!(
        run(&mut ws, &mut tau, &ok, &ok, &bad),
        "qddot[3]: not a finite number"
    );
    assert_eq!(
        run(&mut ws, &mut tau[..3], &ok, &ok, &ok),
        "tau: expected room for 7 values, got 3"
    );
}

/// Lumping is exact: two bodies joined equal the sum of their spatial
/// inertias about any point.
#[test]
fn lumped_bodies_keep_mass_centre_and_inertia() {
    let mut rng = Rng::new(8);
    let (a, b) = (random_body(&mut rng), random_body(&mut rng));
    let pose = DAffine3::from_rotation_translation(
        DQuat::from_axis_angle(rng.unit3(), 0.7),
        rng.vec3(0.5),
    );
    let joined = a.lumped(&b).transformed(&pose);
    let (ta, tb) = (a.transformed(&pose), b.transformed(&pose));
    let about_origin = |x: &Inertial| x.inertia + super::inertia::steiner(x.mass, x.com);
    let diff = about_origin(&joined) - about_origin(&ta) - about_origin(&tb);
    assert!(diff.to_cols_array().iter().all(|v| v.abs() < 1e-14));
    assert!((joined.mass - a.mass - b.mass).abs() < 1e-15);
    let first = joined.mass * joined.com - ta.mass * ta.com - tb.mass * tb.com;
    assert!(first.length() < 1e-14);
}

/// After the workspace exists, no call grows or moves its storage: the
/// computations allocate nothing.
#[test]
fn calls_reuse_the_workspace_storage() {
    let mut rng = Rng::new(9);
    for spec in all_presets() {
        let dynamics = random_dynamics(&spec, &mut rng);
        let mut ws = dynamics.workspace();
        let n = dynamics.dof();
        let storage = |ws: &super::Workspace| {
            [
                (
                    ws.frames.transforms.as_ptr() as usize,
                    ws.frames.transforms.capacity(),
                ),
                (ws.frames.axis.as_ptr() as usize, ws.frames.axis.capacity()),
                (
                    ws.frames.axis_point.as_ptr() as usize,
                    ws.frames.axis_point.capacity(),
                ),
                (ws.axis.as_ptr() as usize, ws.axis.capacity()),
                (ws.inertia.as_ptr() as usize, ws.inertia.capacity()),
                (ws.velocity.as_ptr() as usize, ws.velocity.capacity()),
                (
                    ws.acceleration.as_ptr() as usize,
                    ws.acceleration.capacity(),
                ),
                (ws.force.as_ptr() as usize, ws.force.capacity()),
            ]
        };
        let before = storage(&ws);
        let (mut tau, mut m) = (vec![0.0; n], vec![0.0; n * n]);
        for _ in 0..5 {
            let [q, qd, qdd] = random_state(n, &mut rng);
            dynamics
                .inverse_dynamics(&mut ws, &q, (&qd, &qdd), &mut tau)
                .unwrap();
            dynamics.mass_matrix(&mut ws, &q, &mut m).unwrap();
            dynamics
                .nonlinear_effects(&mut ws, &q, &qd, &mut tau)
                .unwrap();
            dynamics.kinetic_energy(&mut ws, &q, &qd).unwrap();
        }
        assert_eq!(storage(&ws), before, "{:?}", spec.name);
    }
}
