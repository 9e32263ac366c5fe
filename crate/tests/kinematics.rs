//! Kinematics, skeleton and control-point Jacobians: finite differences on
//! every preset, DH conventions, the paper's planar example, the control
//! point's DH table, bad input (CLIK: `clik.rs`).
//! Runs natively and, unchanged, under `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::{DAffine3, DVec3};
use skeleton_avoidance::control_point::DhPoint;
use skeleton_avoidance::kinematics::{
    Convention, Frames, JointSpec, JointType, PoseSpec, Robot, RobotSpec, presets,
};
use skeleton_avoidance::rng::Rng;
use skeleton_avoidance::skeleton::Skeleton;

mod common;
use common::{close, random_point, random_q, robot};

const H: f64 = 1e-6;
const FD_TOL: f64 = 1e-7;

/// The material point of `cp` after the joints moved from `before` to
/// `after`: on a prismatic row the point keeps its fraction of the stretched
/// `d` spine (and stays past it when it was past it); else the same values.
trait SameFraction {
    fn at_same_fraction(&self, r: &Robot, before: &Frames, after: &Frames) -> DhPoint;
}

impl SameFraction for DhPoint {
    fn at_same_fraction(&self, r: &Robot, before: &Frames, after: &Frames) -> DhPoint {
        let i = self.link - 1;
        let mut p = *self;
        if r.joints[i].kind == JointType::Prismatic && before.d[i].abs() > 1e-9 {
            let s = (self.d / before.d[i]).clamp(0.0, 1.0);
            p.d = self.d + s * (after.d[i] - before.d[i]);
        }
        p
    }
}

#[test]
fn jacobians_match_finite_differences_on_every_preset() {
    let mut rng = Rng::new(11);
    for name in presets::NAMES {
        let base = robot(name);
        let n = base.dof();
        for _ in 0..12 {
            let q = random_q(&base, &mut rng);
            let frames = base.forward(&q).unwrap();
            for link in 1..=n {
                let cp = random_point(&base, &frames, link, &mut rng);
                let jac = cp.jacobians(&base, &frames);
                assert!(close(jac.position, cp.position(&base, &frames), 1e-15));
                for k in 0..n {
                    // J_θ: perturb q_k.
                    let pos = |dq: f64| {
                        let mut qq = q.clone();
                        qq[k] += dq;
                        let f = base.forward(&qq).unwrap();
                        cp.at_same_fraction(&base, &frames, &f).position(&base, &f)
                    };
                    let fd = (pos(H) - pos(-H)) / (2.0 * H);
                    assert!(
                        close(jac.j_theta[k], fd, FD_TOL),
                        "{name} J_θ[{k}] link {link}: {:?} vs {fd:?}",
                        jac.j_theta[k]
                    );
                    // J_a and J_d: perturb the row's a or d, or the cut value on the own row.
                    for which in ["a", "d"] {
                        let pos = |delta: f64| {
                            let mut r = base.clone();
                            let mut p = cp;
                            if k + 1 == link {
                                if which == "a" {
                                    p.a += delta
                                } else {
                                    p.d += delta
                                }
                            } else if which == "a" {
                                r.joints[k].a += delta;
                            } else {
                                r.joints[k].d += delta;
                            }
                            p.position(&r, &r.forward(&q).unwrap())
                        };
                        let fd = (pos(H) - pos(-H)) / (2.0 * H);
                        let col = if which == "a" { jac.j_a[k] } else { jac.j_d[k] };
                        if k + 1 > link {
                            assert_eq!(col, DVec3::ZERO, "{name} J_{which}[{k}] past link {link}");
                        }
                        assert!(
                            close(col, fd, FD_TOL),
                            "{name} J_{which}[{k}] link {link}: {col:?} vs {fd:?}"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn jacobian_rates_match_finite_differences_on_every_preset() {
    let mut rng = Rng::new(12);
    for name in presets::NAMES {
        let r = robot(name);
        let n = r.dof();
        for _ in 0..6 {
            let q = random_q(&r, &mut rng);
            let qdot: Vec<f64> = (0..n).map(|_| rng.range(-1.0, 1.0)).collect();
            let frames = r.forward_with_velocity(&q, &qdot).unwrap();
            for link in 1..=n {
                let cp = random_point(&r, &frames, link, &mut rng);
                let (ar, dr) = (rng.range(-0.5, 0.5), rng.range(-0.5, 0.5));
                let rates = cp.jacobian_rates(&r, &frames, ar, dr).unwrap();
                let at = |t: f64| {
                    let qq: Vec<f64> = q.iter().zip(&qdot).map(|(a, b)| a + t * b).collect();
                    let f = r.forward(&qq).unwrap();
                    let mut p = cp.at_same_fraction(&r, &frames, &f);
                    p.a += t * ar;
                    p.d += t * dr;
                    p.jacobians(&r, &f)
                };
                let (jp, jm) = (at(H), at(-H));
                let j0 = cp.jacobians(&r, &frames);
                let v_fd = (jp.position - jm.position) / (2.0 * H);
                assert!(close(rates.velocity, v_fd, FD_TOL), "{name} ṗ link {link}");
                for k in 0..n {
                    for (what, exact, plus, minus) in [
                        ("θ", rates.j_theta_dot[k], jp.j_theta[k], jm.j_theta[k]),
                        ("a", rates.j_a_dot[k], jp.j_a[k], jm.j_a[k]),
                        ("d", rates.j_d_dot[k], jp.j_d[k], jm.j_d[k]),
                    ] {
                        let fd = (plus - minus) / (2.0 * H);
                        assert!(
                            close(exact, fd, 1e-6),
                            "{name} dJ_{what}/dt[{k}] link {link}: {exact:?} vs {fd:?}"
                        );
                    }
                }
                // eq. 3: ṗ = J_θ θ̇ + J_a ȧ + J_d ḋ
                let mut v = j0.j_a[link - 1] * ar + j0.j_d[link - 1] * dr;
                for (c, qd) in j0.j_theta.iter().zip(&qdot) {
                    v += *c * *qd;
                }
                assert!(close(v, rates.velocity, 1e-12));
            }
        }
    }
}

/// The same robot rewritten in Craig's modified convention: row i takes
/// `a_{i-1}, α_{i-1}` from the standard row before it; the last `a, α` go
/// into the tool.
fn to_modified(spec: &RobotSpec) -> RobotSpec {
    let mut out = spec.clone();
    out.convention = Convention::Modified;
    let rows = &spec.joints;
    out.joints = rows
        .iter()
        .enumerate()
        .map(|(i, row)| {
            let (a, alpha) = if i == 0 {
                (0.0, 0.0)
            } else {
                (rows[i - 1].a, rows[i - 1].alpha)
            };
            JointSpec {
                a,
                alpha,
                ..row.clone()
            }
        })
        .collect();
    let last = rows.last().unwrap();
    let tool =
        DAffine3::from_translation(DVec3::X * last.a) * DAffine3::from_rotation_x(last.alpha);
    let (_, rot, pos) = tool.to_scale_rotation_translation();
    out.tool = Some(PoseSpec {
        position: pos.to_array(),
        rotation: rot.to_array(),
    });
    out
}

#[test]
fn standard_and_modified_dh_give_the_same_end_effector() {
    let mut rng = Rng::new(3);
    for name in ["planar3", "lwr4", "ur5"] {
        let spec = presets::preset(name).unwrap();
        let std_robot = Robot::from_spec(&spec).unwrap();
        let mod_robot = Robot::from_spec(&to_modified(&spec)).unwrap();
        for _ in 0..50 {
            let q = random_q(&std_robot, &mut rng);
            let a = std_robot.forward(&q).unwrap().end_effector();
            let b = mod_robot.forward(&q).unwrap().end_effector();
            assert!(a.abs_diff_eq(b, 1e-12), "{name}: {a:?} vs {b:?}");
        }
    }
}

#[test]
fn paper_planar_example_middle_of_link_3() {
    // §III-B: links 0.4 / 0.3 / 0.2 m; the middle of link 3 is (3, 0, 0.1),
    // i.e. a = [0.4, 0.3, 0.1].
    let r = robot("planar3");
    let q = [0.3, -0.7, 1.1];
    let frames = r.forward(&q).unwrap();
    let skel = Skeleton::build(&r, &frames);
    assert_eq!(skel.nodes.len(), 4);
    assert_eq!(skel.segments.len(), 3);
    let seg = skel.segments.iter().position(|s| s.link == 3).unwrap();
    let p = DhPoint::from_skeleton(&r, &frames, &skel, seg, 0.5).unwrap();
    assert_eq!(p.link, 3);
    assert!((p.a - 0.1).abs() < 1e-15 && p.d == 0.0);
    let (n0, n1) = skel.endpoints(&skel.segments[seg]);
    assert!(close(p.position(&r, &frames), (n0 + n1) / 2.0, 1e-15));
    let (s, t) = p.to_skeleton(&r, &frames, &skel).unwrap();
    assert_eq!(s, seg);
    assert!((t - 0.5).abs() < 1e-15);
    // Closed form of the planar arm.
    let (t1, t12) = (q[0], q[0] + q[1]);
    let t123 = t12 + q[2];
    let ee = DVec3::new(
        0.4 * t1.cos() + 0.3 * t12.cos() + 0.2 * t123.cos(),
        0.4 * t1.sin() + 0.3 * t12.sin() + 0.2 * t123.sin(),
        0.0,
    );
    assert!(close(frames.end_effector().translation, ee, 1e-15));
}

#[test]
fn skeletons_of_every_preset() {
    let expected = [
        ("planar3", 4, 3),
        ("lwr4", 5, 4),
        ("panda", 8, 7),
        ("ur5", 9, 8),
        ("dual-arm", 10, 9),
    ];
    let mut rng = Rng::new(5);
    for (name, nodes, segments) in expected {
        let r = robot(name);
        for _ in 0..20 {
            let q = random_q(&r, &mut rng);
            let frames = r.forward(&q).unwrap();
            let skel = Skeleton::build(&r, &frames);
            assert_eq!(skel.nodes.len(), nodes, "{name} nodes");
            assert_eq!(skel.segments.len(), segments, "{name} segments");
            for i in 0..skel.nodes.len() {
                for j in i + 1..skel.nodes.len() {
                    assert!(
                        skel.nodes[i].distance(skel.nodes[j]) > 1e-6,
                        "{name}: nodes {i} and {j} coincide"
                    );
                }
            }
            for k in 0..=r.dof() {
                let o = frames.origin(k);
                let (_, _, c) = skel.closest_point(o).unwrap();
                assert!(
                    o.distance(c) < 1e-12,
                    "{name}: frame {k} is off the skeleton"
                );
            }
            // Every skeleton point maps to DH values and back.
            for (s, seg) in skel.segments.iter().enumerate() {
                let t = rng.uniform();
                let p = DhPoint::from_skeleton(&r, &frames, &skel, s, t).unwrap();
                p.validate(&r, &frames).unwrap();
                // The point's velocity without the Jacobians: J_θ q̇, the same bits.
                let qdot = random_q(&r, &mut rng);
                let j = p.jacobians(&r, &frames);
                let v: DVec3 = j.j_theta.iter().zip(&qdot).map(|(c, v)| *c * *v).sum();
                assert_eq!(p.velocity(&r, &frames, &qdot), v, "{name} segment {s}");
                let (a, b) = skel.endpoints(seg);
                assert!(
                    close(p.position(&r, &frames), a.lerp(b, t), 1e-12),
                    "{name} segment {s}"
                );
                let (s2, t2) = p.to_skeleton(&r, &frames, &skel).unwrap();
                assert_eq!(s2, s);
                assert!((t2 - t).abs() < 1e-9);
            }
        }
    }
}

#[test]
fn extension_behind_the_joint_is_on_the_skeleton() {
    let mut spec = presets::preset("planar3").unwrap();
    spec.joints[1].extension = Some(0.1);
    let r = Robot::from_spec(&spec).unwrap();
    let frames = r.forward(&[0.2, 0.4, -0.3]).unwrap();
    let skel = Skeleton::build(&r, &frames);
    assert_eq!(skel.segments.len(), 4);
    let p = DhPoint {
        link: 2,
        d: 0.0,
        a: -0.05,
    };
    p.validate(&r, &frames).unwrap();
    let (s, t) = p.to_skeleton(&r, &frames, &skel).unwrap();
    assert!((t - 0.5).abs() < 1e-12);
    let (a, b) = skel.endpoints(&skel.segments[s]);
    assert!(close(p.position(&r, &frames), a.lerp(b, t), 1e-12));
}

#[test]
fn bad_input_names_the_field() {
    let msg = |e: skeleton_avoidance::FieldError| e.to_string();
    let mut spec = presets::preset("lwr4").unwrap();
    spec.joints[3].alpha = f64::NAN;
    assert_eq!(
        msg(Robot::from_spec(&spec).unwrap_err()),
        "joints[3].alpha: not a finite number"
    );
    let mut spec = presets::preset("lwr4").unwrap();
    spec.joints.clear();
    assert_eq!(
        msg(Robot::from_spec(&spec).unwrap_err()),
        "joints: the DH table is empty"
    );
    let mut spec = presets::preset("lwr4").unwrap();
    spec.base = Some(PoseSpec {
        position: [0.0; 3],
        rotation: [0.0, 0.0, 0.0, 2.0],
    });
    assert!(
        msg(Robot::from_spec(&spec).unwrap_err())
            .starts_with("base.rotation: quaternion [x, y, z, w] must have unit length")
    );
    spec.base = Some(PoseSpec {
        position: [0.0; 3],
        rotation: [0.0; 4],
    });
    assert!(msg(Robot::from_spec(&spec).unwrap_err()).starts_with("base.rotation: degenerate"));
    assert!(
        msg(presets::preset("kuka").unwrap_err()).starts_with("preset: unknown robot \"kuka\"")
    );
    let r = robot("lwr4");
    assert_eq!(
        msg(r.forward(&[0.0; 6]).unwrap_err()),
        "q: expected 7 joint values, got 6"
    );
    assert_eq!(
        msg(r
            .forward(&[0.0, 0.0, f64::INFINITY, 0.0, 0.0, 0.0, 0.0])
            .unwrap_err()),
        "q[2]: not a finite number"
    );
    let frames = r.forward(&[0.0; 7]).unwrap();
    assert_eq!(
        msg(DhPoint {
            link: 8,
            d: 0.0,
            a: 0.0
        }
        .validate(&r, &frames)
        .unwrap_err()),
        "link: 8 is not a link of this robot (links 1 to 7)"
    );
    assert_eq!(
        msg(DhPoint {
            link: 0,
            d: 0.0,
            a: 0.0
        }
        .validate(&r, &frames)
        .unwrap_err()),
        "link: 0 is not a link of this robot (links 1 to 7)"
    );
    assert!(
        msg(DhPoint {
            link: 3,
            d: 0.5,
            a: 0.0
        }
        .validate(&r, &frames)
        .unwrap_err())
        .starts_with("d: 0.5 is outside the link's span [0, 0.4]")
    );
    assert!(
        msg(DhPoint {
            link: 3,
            d: 0.1,
            a: 0.1
        }
        .validate(&r, &frames)
        .unwrap_err())
        .starts_with("a: 0.1 is outside")
    );
}

#[test]
fn adjacency_follows_the_skeleton() {
    // lwr4: rows 2, 4, 6 add no segment, so the segments of rows 1, 3, 5, 7
    // meet at nodes: 1–3, 3–5, 5–7 are adjacent, 1–5 are not.
    let r = robot("lwr4");
    assert_eq!(r.skeleton_parent(3), 1);
    assert!(r.adjacent(1, 3) && r.adjacent(3, 5) && r.adjacent(5, 7) && r.adjacent(2, 2));
    assert!(!r.adjacent(1, 5) && !r.adjacent(3, 7));
    // dual-arm: both arms start at the chest node; their first rows are
    // adjacent to the torso and to each other, their upper arms are not.
    let r = robot("dual-arm");
    let (left, right) = (r.chains[1].first, r.chains[2].first);
    assert!(r.adjacent(1, left) && r.adjacent(1, right) && r.adjacent(left, right));
    assert!(!r.adjacent(left + 2, right + 2) && !r.adjacent(1, left + 2));
    // Adjacent rows share a skeleton node; non-adjacent ones with segments do not.
    let frames = r.forward(&vec![0.3; r.dof()]).unwrap();
    let skel = Skeleton::build(&r, &frames);
    for a in &skel.segments {
        for b in &skel.segments {
            let share = [a.from, a.to].iter().any(|n| *n == b.from || *n == b.to);
            assert_eq!(
                share,
                r.adjacent(a.link, b.link),
                "links {} and {}",
                a.link,
                b.link
            );
        }
    }
}

/// A control point is the end effector of its shorter manipulator: the DH
/// table `DhPoint::table` gives, put back into the robot (tool removed), an
/// end effector at the point, in both conventions; on a torso the other
/// arm's rows are zero and the shared rows full.
#[test]
fn control_point_table_is_its_shorter_manipulator() {
    let mut rng = Rng::new(17);
    for name in presets::NAMES {
        let spec = presets::preset(name).unwrap();
        let revolute = spec.joints.iter().all(|j| j.kind == JointType::Revolute);
        if !spec.branches.is_empty() || !revolute {
            continue;
        }
        let robot = Robot::from_spec(&spec).unwrap();
        for _ in 0..40 {
            let q = random_q(&robot, &mut rng);
            let frames = robot.forward(&q).unwrap();
            let link = 1 + (rng.next_u64() % robot.dof() as u64) as usize;
            let cp = random_point(&robot, &frames, link, &mut rng);
            let table = cp.table(&robot, &frames);
            assert_eq!(table.len(), robot.dof());
            let mut shorter = spec.clone();
            shorter.tool = None;
            for (j, row) in shorter.joints.iter_mut().zip(&table) {
                j.d = row.d;
                j.a = row.a;
            }
            let tip = Robot::from_spec(&shorter)
                .unwrap()
                .forward(&q)
                .unwrap()
                .end_effector()
                .translation;
            let p = cp.position(&robot, &frames);
            assert!(close(tip, p, 1e-12), "{name} link {link}: {tip:?} vs {p:?}");
        }
    }
    // dual-arm: a point on the second arm keeps the torso's rows, zeroes the first arm's.
    let robot = robot("dual-arm");
    let frames = robot.forward(&vec![0.3; robot.dof()]).unwrap();
    let last = robot.dof();
    let cp = DhPoint {
        link: last,
        d: 0.0,
        a: 0.01,
    };
    let table = cp.table(&robot, &frames);
    for k in 1..=last {
        let row = table[k - 1];
        if k == last {
            assert_eq!((row.d, row.a), (0.0, 0.01));
        } else if robot.is_ancestor(k, last) {
            assert_eq!((row.d, row.a), (frames.d[k - 1], robot.joints[k - 1].a));
        } else {
            assert_eq!(
                (row.d, row.a),
                (0.0, 0.0),
                "row {k} is not on the point's chain"
            );
        }
    }
    assert!(
        (1..last).any(|k| !robot.is_ancestor(k, last)),
        "the other arm's rows exist"
    );
}
