//! Control-point transitions along the skeleton: the paper's fig. 5 example,
//! continuity, re-planning without a jump, routes through branching skeletons.
//! Runs natively and, unchanged, under `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use skeleton_avoidance::kinematics::{Robot, presets};
use skeleton_avoidance::skeleton::Skeleton;
use skeleton_avoidance::transition::{
    MovingPoint, PointEvent, SkeletonPoint, Transition, TransitionSettings, dh_motion, route,
};

fn robot(name: &str) -> Robot {
    Robot::from_spec(&presets::preset(name).unwrap()).unwrap()
}

/// The DH vector `a` of the paper's planar control point: rows before the
/// point's link are complete, rows after it are zero.
fn a_vector(robot: &Robot, link: usize, a: f64) -> [f64; 3] {
    let mut v = [0.0; 3];
    for (k, x) in v.iter_mut().enumerate() {
        *x = if k + 1 < link {
            robot.joints[k].a
        } else if k + 1 == link {
            a
        } else {
            0.0
        };
    }
    v
}

#[test]
fn paper_fig5_planar_transition_changes_a1_a2_a3_in_sequence_and_arrives_after_0_3_s() {
    let robot = robot("planar3");
    let q = [0.4, 0.6, -0.5];
    let frames = robot.forward(&q).unwrap();
    let skeleton = Skeleton::build(&robot, &frames);
    assert_eq!(
        skeleton.segments.len(),
        3,
        "planar3 has one a-segment per link"
    );
    let from = SkeletonPoint { segment: 0, t: 0.5 };
    let to = SkeletonPoint { segment: 2, t: 0.5 };
    let tr = Transition::plan(&skeleton, from, 0.0, to, 0.1).unwrap();
    assert_eq!(tr.segments(), vec![0, 1, 2]);
    assert!((tr.duration() - 0.3).abs() < 1e-12);

    let dt = 1e-3;
    let steps = 350;
    let mut prev_a: Option<[f64; 3]> = None;
    let mut prev_p = None;
    let mut prev_v: Option<glam::DVec3> = None;
    let mut changed = [[f64::INFINITY, f64::NEG_INFINITY]; 3];
    for k in 0..=steps {
        let time = k as f64 * dt;
        let s = tr.sample_at(time);
        let (dh, motion) = dh_motion(&robot, &frames, &skeleton, s.point, s.rate, s.accel).unwrap();
        let a = a_vector(&robot, dh.link, dh.a);
        if let Some(pa) = prev_a {
            for i in 0..3 {
                if (a[i] - pa[i]).abs() > 1e-12 {
                    changed[i][0] = changed[i][0].min(time - dt);
                    changed[i][1] = changed[i][1].max(time);
                }
            }
        }
        prev_a = Some(a);
        // Position continuity and velocity continuity (ṗ = J_a ȧ here:
        // the joints do not move).
        let jac = dh.jacobians(&robot, &frames);
        let p = jac.position;
        let v = jac.j_a[dh.link - 1] * motion.a_rate + jac.j_d[dh.link - 1] * motion.d_rate;
        if let Some(pp) = prev_p {
            let step: glam::DVec3 = p - pp;
            assert!(
                step.length() < 0.01,
                "position jumps by {} at t = {time}",
                step.length()
            );
            let fd = step / dt;
            assert!(
                (fd - v).length() < 0.2,
                "velocity {v} disagrees with the finite difference {fd} at t = {time}"
            );
        }
        if let Some(pv) = prev_v {
            // A quintic leg of length L over T has |p̈| ≤ 10/√3 L / T²
            // ≈ 173 m/s² for L = 0.3 m: 0.18 m/s per millisecond at most.
            assert!((v - pv).length() < 0.2, "velocity jumps at t = {time}");
        }
        prev_p = Some(p);
        prev_v = Some(v);
        if time >= 0.3 - 1e-12 {
            assert_eq!(dh.link, 3);
            assert!(
                (dh.a - 0.1).abs() < 1e-12,
                "a3 ends at the middle of link 3"
            );
            assert!(v.length() < 1e-12);
        }
    }
    // a1 moves during the first 0.1 s, a2 during the second, a3 during the third.
    let windows = [(0.0, 0.1), (0.1, 0.2), (0.2, 0.3)];
    for (i, (lo, hi)) in windows.iter().enumerate() {
        assert!(
            changed[i][0] >= lo - 1e-9 && changed[i][1] <= hi + 1e-9,
            "a{} changes over [{}, {}], expected within [{lo}, {hi}]",
            i + 1,
            changed[i][0],
            changed[i][1]
        );
    }
    assert_eq!(a_vector(&robot, 1, 0.2), [0.2, 0.0, 0.0]);
    let end = tr.sample_at(0.3);
    let (dh, _) = dh_motion(&robot, &frames, &skeleton, end.point, 0.0, 0.0).unwrap();
    assert_eq!(a_vector(&robot, dh.link, dh.a), [0.4, 0.3, 0.1]);
    assert!(tr.sample_at(0.2999).point.segment == 2 && !tr.is_finished());
}

#[test]
fn time_per_value_is_configurable() {
    let robot = robot("planar3");
    let frames = robot.forward(&[0.0, 0.0, 0.0]).unwrap();
    let skeleton = Skeleton::build(&robot, &frames);
    let tr = Transition::plan(
        &skeleton,
        SkeletonPoint { segment: 0, t: 0.5 },
        0.0,
        SkeletonPoint { segment: 2, t: 0.5 },
        0.25,
    )
    .unwrap();
    assert!((tr.duration() - 0.75).abs() < 1e-12);
    assert!(
        Transition::plan(
            &skeleton,
            SkeletonPoint { segment: 0, t: 0.5 },
            0.0,
            SkeletonPoint { segment: 2, t: 0.5 },
            0.0
        )
        .is_err()
    );
}

#[test]
fn routes_follow_the_chain_and_branches_of_the_dual_arm() {
    let robot = robot("dual-arm");
    let q = vec![0.2; robot.dof()];
    let frames = robot.forward(&q).unwrap();
    let skeleton = Skeleton::build(&robot, &frames);
    // From the last segment of one arm to the last segment of the other:
    // the route goes down one arm, through the chest and up the other.
    let first_arm_last = skeleton
        .segments
        .iter()
        .rposition(|s| s.link <= robot.chains[0].last)
        .unwrap();
    let other_last = skeleton.segments.len() - 1;
    let legs = route(
        &skeleton,
        SkeletonPoint {
            segment: first_arm_last,
            t: 0.5,
        },
        SkeletonPoint {
            segment: other_last,
            t: 0.5,
        },
    )
    .unwrap();
    // Consecutive legs share a node.
    for w in legs.windows(2) {
        let (a, b) = (
            &skeleton.segments[w[0].segment],
            &skeleton.segments[w[1].segment],
        );
        let end_a = if w[0].t1 == 0.0 { a.from } else { a.to };
        let start_b = if w[1].t0 == 0.0 { b.from } else { b.to };
        assert_eq!(end_a, start_b, "legs must meet at a node");
    }
    assert_eq!(legs.first().unwrap().segment, first_arm_last);
    assert_eq!(legs.last().unwrap().segment, other_last);
}

#[test]
fn a_new_target_during_a_transition_replans_without_a_jump() {
    let robot = robot("lwr4");
    let q = [0.3, 0.5, -0.2, -1.0, 0.4, 0.6, 0.1];
    let frames = robot.forward(&q).unwrap();
    let skeleton = Skeleton::build(&robot, &frames);
    let last = skeleton.segments.len() - 1;
    let settings = TransitionSettings::default();
    let mut mp = MovingPoint::new(SkeletonPoint { segment: 0, t: 0.5 });
    let mut events = Vec::new();
    let dt = 1e-3;
    let mut prev = mp.point().position(&skeleton);
    let mut prev_rate_v = glam::DVec3::ZERO;
    for k in 0..1500 {
        // Target far along the arm, then, mid-way, back near the base.
        let target = if k < 150 {
            SkeletonPoint {
                segment: last,
                t: 0.5,
            }
        } else {
            SkeletonPoint { segment: 1, t: 0.3 }
        };
        mp.update(&skeleton, target, dt, &settings, &mut events)
            .unwrap();
        let p = mp.point().position(&skeleton);
        let v = (p - prev) / dt;
        assert!(
            (p - prev).length() < 0.02,
            "jump of {} at step {k}",
            (p - prev).length()
        );
        if k > 0 {
            // Velocity changes at most by the legs' acceleration × dt.
            assert!(
                (v - prev_rate_v).length() < 0.5,
                "velocity jump at step {k}"
            );
        }
        prev = p;
        prev_rate_v = v;
    }
    assert!(
        events
            .iter()
            .any(|e| matches!(e, PointEvent::TransitionStart { replan: true, .. }))
    );
    assert!(matches!(
        events.last(),
        Some(PointEvent::TransitionEnd { segment: 1 })
    ));
    assert_eq!(mp.point(), SkeletonPoint { segment: 1, t: 0.3 });
    assert!(mp.transition().is_none());
}
