//! CLIK on the control points (`control_point::clik`): convergence on
//! reachable targets, boundedness at singularities, a moving control point
//! tracked with the moving-point terms, pose CLIK. Runs natively and,
//! unchanged, under `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::DVec3;
use skeleton_avoidance::control_point::DhPoint;
use skeleton_avoidance::control_point::clik::{self, SolveOptions};
use skeleton_avoidance::kinematics::ik;
use skeleton_avoidance::linalg::{self, Damping, DlsSettings, Mat};
use skeleton_avoidance::rng::Rng;

mod common;
use common::{close, random_q, robot};

#[test]
fn clik_converges_on_reachable_targets() {
    let mut rng = Rng::new(21);
    for name in ["planar3", "lwr4", "panda", "ur5"] {
        let r = robot(name);
        let mut converged = 0;
        let trials = 10;
        for _ in 0..trials {
            let goal_q = random_q(&r, &mut rng);
            let frames = r.forward(&goal_q).unwrap();
            let target = frames.end_effectors[0].translation;
            let n = r.dof();
            let ee = DhPoint {
                link: n,
                d: frames.d[n - 1],
                a: r.joints[n - 1].a,
            };
            assert!(close(ee.position(&r, &frames), target, 1e-12));
            // Start near the goal configuration so the target is reachable on the way.
            let q0: Vec<f64> = goal_q.iter().map(|v| v + rng.range(-0.3, 0.3)).collect();
            let mut q0 = q0;
            r.clamp_to_limits(&mut q0);
            let res = clik::solve_position(&r, &q0, &ee, target, &SolveOptions::default()).unwrap();
            assert!(res.q.iter().all(|v| v.is_finite()));
            if res.converged {
                converged += 1;
            }
        }
        assert!(
            converged >= trials - 1,
            "{name}: {converged}/{trials} converged"
        );
    }
}

#[test]
fn clik_stays_bounded_at_singularities() {
    let r = robot("planar3");
    let ee = DhPoint {
        link: 3,
        d: 0.0,
        a: 0.2,
    };
    // Stretched arm, target beyond reach along the arm and across it.
    for target in [
        DVec3::new(1.2, 0.0, 0.0),
        DVec3::new(0.9, 0.05, 0.0),
        DVec3::new(0.0, 1.5, 0.0),
    ] {
        let opts = SolveOptions {
            max_steps: 500,
            ..SolveOptions::default()
        };
        let res = clik::solve_position(&r, &[0.0, 0.0, 0.0], &ee, target, &opts).unwrap();
        assert!(res.q.iter().all(|v| v.is_finite()));
        // With λ_max = ε the damped solution obeys ‖θ̇‖ ≤ ‖K e‖ / ε everywhere;
        // the error never exceeds |target| + reach (0.9 m).
        let d = Damping::default();
        let bound = opts.gain * (target.length() + 0.9) / d.epsilon;
        assert!(
            res.max_speed <= bound,
            "joint speed {} above {bound}",
            res.max_speed
        );
    }
    // The damped inverse of an exactly singular Jacobian is bounded.
    let frames = r.forward(&[0.0, 0.0, 0.0]).unwrap();
    let jac = ee.jacobians(&r, &frames);
    let inv = linalg::dls_inverse(&Mat::from_columns3(&jac.j_theta), &[], Damping::default());
    assert!(inv.sigma_min < 1e-9 && inv.lambda > 0.0);
    assert!(
        inv.inverse
            .data
            .iter()
            .all(|v| v.is_finite() && v.abs() < 100.0)
    );
    // And exact (no damping) when well conditioned: J J^† = I.
    let frames = r.forward(&[0.3, 0.8, 0.5]).unwrap();
    let jac = ee.jacobians(&r, &frames);
    let j = Mat::from_columns3(&jac.j_theta);
    let inv = linalg::dls_inverse(&j, &[1.0, 2.0, 3.0], Damping::default());
    // The z direction of a planar arm is singular by design and damped; x-y is exact.
    assert!(inv.sigma_min < 1e-12);
    // Planar: the z row is zero, so check the x-y block.
    let prod = j.mul(&inv.inverse);
    assert!((prod.get(0, 0) - 1.0).abs() < 1e-9 && prod.get(0, 1).abs() < 1e-9);
    assert!((prod.get(1, 1) - 1.0).abs() < 1e-9 && prod.get(1, 0).abs() < 1e-9);
}

#[test]
fn clik_with_a_moving_control_point_tracks_it() {
    // First order: with the J_a ȧ term the point holds still while it slides
    // along link 3 (the arm compensates exactly); without it, it drifts.
    let r = robot("planar3");
    let mut q = vec![0.4, 0.9, 0.6];
    let dt = 1e-3;
    let mut cp = DhPoint {
        link: 3,
        d: 0.0,
        a: 0.02,
    };
    let target = cp.position(&r, &r.forward(&q).unwrap()) + DVec3::new(-0.02, 0.0, 0.0);
    let motion = clik::PointMotion {
        a_rate: 0.15,
        ..Default::default()
    };
    for _ in 0..1000 {
        let frames = r.forward(&q).unwrap();
        let qd = clik::clik_first_order(
            &r,
            &frames,
            &cp,
            &motion,
            &clik::PointTarget {
                position: target,
                ..Default::default()
            },
            50.0,
            DlsSettings::default(),
        );
        for (v, d) in q.iter_mut().zip(&qd) {
            *v += d * dt;
        }
        cp.a = (cp.a + motion.a_rate * dt).min(0.2);
    }
    let err = (cp.position(&r, &r.forward(&q).unwrap()) - target).length();
    assert!(err < 1e-3, "first-order error {err}");

    // Second order with the J̇ terms converges on a point that accelerates along link 2.
    let mut q = vec![0.4, 0.9, 0.6];
    let mut qdot = vec![0.0; 3];
    let mut cp = DhPoint {
        link: 2,
        d: 0.0,
        a: 0.05,
    };
    let target = DVec3::new(0.35, 0.35, 0.0);
    let (mut a_rate, a_accel) = (0.0, 0.2);
    for _ in 0..3000 {
        let frames = r.forward_with_velocity(&q, &qdot).unwrap();
        let motion = clik::PointMotion {
            a_rate,
            a_accel,
            ..Default::default()
        };
        let qdd = clik::clik_second_order(
            &r,
            &frames,
            &cp,
            &motion,
            &clik::PointTarget {
                position: target,
                ..Default::default()
            },
            (400.0, 40.0),
            DlsSettings::default(),
        )
        .unwrap();
        for ((v, w), acc) in q.iter_mut().zip(qdot.iter_mut()).zip(&qdd) {
            *w += acc * dt;
            *v += *w * dt;
        }
        cp.a += a_rate * dt;
        a_rate += a_accel * dt;
        if cp.a > 0.25 {
            a_rate = 0.0;
        }
    }
    let err = (cp.position(&r, &r.forward(&q).unwrap()) - target).length();
    assert!(err < 1e-3, "second-order error {err}");
}

#[test]
fn pose_clik_reaches_position_and_orientation() {
    let mut rng = Rng::new(31);
    for name in ["lwr4", "panda", "ur5"] {
        let r = robot(name);
        let mut reached = 0;
        for _ in 0..6 {
            // A well-conditioned goal (σ_min ≥ 0.05): near singularities the
            // damped solver slows down by design (see the boundedness test).
            let goal_q = loop {
                let g = random_q(&r, &mut rng);
                let j6 = ik::end_effector_jacobian(&r, &r.forward(&g).unwrap(), 0).unwrap();
                if linalg::dls_inverse(&j6, &[], Damping::default()).sigma_min >= 0.05 {
                    break g;
                }
            };
            let goal = r.forward(&goal_q).unwrap().end_effector();
            let (_, rot, pos) = goal.to_scale_rotation_translation();
            let mut q: Vec<f64> = goal_q.iter().map(|v| v + rng.range(-0.25, 0.25)).collect();
            r.clamp_to_limits(&mut q);
            let mut done = false;
            for _ in 0..1500 {
                let frames = r.forward(&q).unwrap();
                let (_, rot2, pos2) = frames.end_effector().to_scale_rotation_translation();
                if pos.distance(pos2) < 1e-6 && ik::orientation_error(rot, rot2).length() < 1e-6 {
                    done = true;
                    break;
                }
                let qd = ik::clik_pose(
                    &r,
                    &frames,
                    0,
                    (pos, rot),
                    (DVec3::ZERO, DVec3::ZERO),
                    (20.0, 20.0),
                    DlsSettings::default(),
                )
                .unwrap();
                for (v, d) in q.iter_mut().zip(&qd) {
                    *v += d * 0.005;
                }
                r.clamp_to_limits(&mut q);
            }
            if done {
                reached += 1;
            }
        }
        assert_eq!(reached, 6, "{name}: {reached}/6 poses reached");
    }
    // The 6 × n Jacobian's linear rows equal J_θ of the end-effector point.
    let r = robot("lwr4");
    let frames = r.forward(&[0.2, 0.4, -0.3, -1.0, 0.5, 0.7, 0.1]).unwrap();
    let j6 = ik::end_effector_jacobian(&r, &frames, 0).unwrap();
    let jp = DhPoint {
        link: 7,
        d: 0.078,
        a: 0.0,
    }
    .jacobians(&r, &frames);
    for k in 0..7 {
        for row in 0..3 {
            assert!((j6.get(row, k) - jp.j_theta[k][row]).abs() < 1e-12);
        }
    }
}
