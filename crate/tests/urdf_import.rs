//! URDF import: the forward kinematics of the imported DH spec against a
//! URDF forward kinematics written here from the joints' origins and axes,
//! on published robot descriptions (tests/data/urdf, licences beside them)
//! and on random chains; the skeleton through every joint origin; limits,
//! radii, bad input. Runs natively and, unchanged, under
//! `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use std::collections::HashMap;

use skeleton_avoidance::kinematics::{JointType, Robot};
use skeleton_avoidance::parsers::urdf::{UrdfOptions, robot_from_urdf};
use skeleton_avoidance::rng::Rng;
use skeleton_avoidance::skeleton::Skeleton;

const PANDA: &str = include_str!("data/urdf/panda_collision.urdf");
const UR5: &str = include_str!("data/urdf/ur5_robot.urdf");
const IIWA: &str = include_str!("data/urdf/iiwa14_primitive_collision.urdf");
const PR2: &str = include_str!("data/urdf/pr2.urdf");

const TOL: f64 = 1e-9;
const CONFIGURATIONS: usize = 100;

// ---- an independent URDF forward kinematics: 3×3 arrays and 3-vectors ----

type M3 = [[f64; 3]; 3];
type V3 = [f64; 3];

/// A rigid transform: rotation (rows) and translation.
#[derive(Clone, Copy)]
struct Tf {
    r: M3,
    p: V3,
}

fn mat_mul(a: &M3, b: &M3) -> M3 {
    let mut m = [[0.0; 3]; 3];
    for (i, row) in m.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    m
}

fn mat_vec(a: &M3, v: &V3) -> V3 {
    [0, 1, 2].map(|i| (0..3).map(|k| a[i][k] * v[k]).sum())
}

fn compose(a: &Tf, b: &Tf) -> Tf {
    let rp = mat_vec(&a.r, &b.p);
    Tf {
        r: mat_mul(&a.r, &b.r),
        p: [a.p[0] + rp[0], a.p[1] + rp[1], a.p[2] + rp[2]],
    }
}

fn rot_axis(axis: usize, angle: f64) -> M3 {
    let (s, c) = angle.sin_cos();
    match axis {
        0 => [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]],
        1 => [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]],
        _ => [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]],
    }
}

/// Rotation by `angle` about the unit vector `u` (Rodrigues).
fn rodrigues(u: V3, angle: f64) -> M3 {
    let (s, c) = angle.sin_cos();
    let t = 1.0 - c;
    let [x, y, z] = u;
    [
        [c + x * x * t, x * y * t - z * s, x * z * t + y * s],
        [y * x * t + z * s, c + y * y * t, y * z * t - x * s],
        [z * x * t - y * s, z * y * t + x * s, c + z * z * t],
    ]
}

fn urdf_origin(j: &urdf_rs::Joint) -> Tf {
    let [r, p, y] = j.origin.rpy.0;
    Tf {
        r: mat_mul(&rot_axis(2, y), &mat_mul(&rot_axis(1, p), &rot_axis(0, r))),
        p: j.origin.xyz.0,
    }
}

/// Joint indices from `base` to `tip`.
fn urdf_path(urdf: &urdf_rs::Robot, base: &str, tip: &str) -> Vec<usize> {
    let parent: HashMap<&str, usize> = urdf
        .joints
        .iter()
        .enumerate()
        .map(|(k, j)| (j.child.link.as_str(), k))
        .collect();
    let mut out = Vec::new();
    let mut link = tip;
    while link != base {
        let k = parent[link];
        out.push(k);
        link = &urdf.joints[k].parent.link;
    }
    out.reverse();
    out
}

/// The tip frame and every movable joint's origin, for joint values `q` in
/// the order of `names`.
fn urdf_fk(urdf: &urdf_rs::Robot, path: &[usize], names: &[String], q: &[f64]) -> (Tf, Vec<V3>) {
    let value: HashMap<&str, f64> = names
        .iter()
        .map(String::as_str)
        .zip(q.iter().copied())
        .collect();
    let mut t = Tf {
        r: rot_axis(0, 0.0),
        p: [0.0; 3],
    };
    let mut origins = Vec::new();
    for &k in path {
        let j = &urdf.joints[k];
        t = compose(&t, &urdf_origin(j));
        let Some(&v) = value.get(j.name.as_str()) else {
            continue;
        };
        origins.push(t.p);
        let a = j.axis.xyz.0;
        let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        let u = [a[0] / n, a[1] / n, a[2] / n];
        let motion = match j.joint_type {
            urdf_rs::JointType::Prismatic => Tf {
                r: rot_axis(0, 0.0),
                p: [u[0] * v, u[1] * v, u[2] * v],
            },
            _ => Tf {
                r: rodrigues(u, v),
                p: [0.0; 3],
            },
        };
        t = compose(&t, &motion);
    }
    (t, origins)
}

// ---- the comparison ----

fn random_q(robot: &Robot, rng: &mut Rng) -> Vec<f64> {
    robot
        .joints
        .iter()
        .map(|j| match (j.min.is_finite() && j.max.is_finite(), j.kind) {
            (true, _) => rng.range(j.min, j.max),
            (false, JointType::Revolute) => rng.range(-std::f64::consts::PI, std::f64::consts::PI),
            (false, JointType::Prismatic) => rng.range(-0.5, 0.5),
        })
        .collect()
}

fn distance_to_segment(p: glam::DVec3, a: glam::DVec3, b: glam::DVec3) -> f64 {
    let ab = b - a;
    let t = if ab.length_squared() > 0.0 {
        ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t - p).length()
}

/// Worst position (m) and rotation (rad) error of the spec against the URDF
/// over random configurations; with `cover`, asserts that the skeleton passes
/// through every movable joint's origin and the tip's (true of arms whose
/// joint origins lie between the common normals of their axes, as the
/// published ones here; a joint origin further along its axis than both
/// normals, as random chains have, is not a node of a DH skeleton).
fn check(xml: &str, options: &UrdfOptions, seed: u64, cover: bool) -> (usize, f64, f64) {
    let spec = robot_from_urdf(xml, options).unwrap();
    let robot = Robot::from_spec(&spec).unwrap();
    let urdf = urdf_rs::read_from_string(xml).unwrap();
    let names = spec.joint_names.clone().unwrap();
    assert_eq!(names.len(), robot.dof());
    let base = options.base.clone().unwrap_or_else(|| {
        let children: Vec<&str> = urdf.joints.iter().map(|j| j.child.link.as_str()).collect();
        urdf.links
            .iter()
            .find(|l| !children.contains(&l.name.as_str()))
            .unwrap()
            .name
            .clone()
    });
    let tip = options.tip.clone().unwrap();
    let path = urdf_path(&urdf, &base, &tip);
    let mut rng = Rng::new(seed);
    let (mut worst_p, mut worst_r) = (0.0_f64, 0.0_f64);
    for _ in 0..CONFIGURATIONS {
        let q = random_q(&robot, &mut rng);
        let frames = robot.forward(&q).unwrap();
        let ee = frames.end_effector();
        let (t, origins) = urdf_fk(&urdf, &path, &names, &q);
        let dp = (ee.translation - glam::DVec3::from_array(t.p)).length();
        let mut fro = 0.0;
        for (c, col) in [ee.matrix3.x_axis, ee.matrix3.y_axis, ee.matrix3.z_axis]
            .iter()
            .enumerate()
        {
            for r in 0..3 {
                fro += (col[r] - t.r[r][c]).powi(2);
            }
        }
        worst_p = worst_p.max(dp);
        worst_r = worst_r.max((fro / 2.0).sqrt());
        if !cover {
            continue;
        }
        let skeleton = Skeleton::build(&robot, &frames);
        for (k, o) in origins.iter().chain(std::iter::once(&t.p)).enumerate() {
            let p = glam::DVec3::from_array(*o);
            let gap = skeleton
                .segments
                .iter()
                .map(|s| distance_to_segment(p, skeleton.nodes[s.from], skeleton.nodes[s.to]))
                .fold(f64::INFINITY, f64::min);
            assert!(
                gap <= 1e-9,
                "{tip}: origin {k} is {gap} m off the skeleton at q = {q:?}"
            );
        }
    }
    assert!(worst_p <= TOL, "{tip}: position error {worst_p} m");
    assert!(worst_r <= TOL, "{tip}: rotation error {worst_r} rad");
    (robot.dof(), worst_p, worst_r)
}

fn opts(base: Option<&str>, tip: &str) -> UrdfOptions {
    UrdfOptions {
        tip: Some(tip.to_owned()),
        base: base.map(str::to_owned),
        ..UrdfOptions::default()
    }
}

#[test]
fn panda_matches_the_urdf() {
    let (dof, p, r) = check(PANDA, &opts(None, "panda_link8"), 1, true);
    assert_eq!(dof, 7);
    eprintln!("panda_collision.urdf: {dof} joints, worst {p:.2e} m, {r:.2e} rad");
}

#[test]
fn ur5_matches_the_urdf() {
    let (dof, p, r) = check(UR5, &opts(None, "ee_link"), 2, true);
    assert_eq!(dof, 6);
    eprintln!("ur5_robot.urdf: {dof} joints, worst {p:.2e} m, {r:.2e} rad");
}

#[test]
fn iiwa_matches_the_urdf() {
    let (dof, p, r) = check(IIWA, &opts(None, "iiwa_link_ee"), 3, true);
    assert_eq!(dof, 7);
    eprintln!("iiwa14_primitive_collision.urdf: {dof} joints, worst {p:.2e} m, {r:.2e} rad");
}

#[test]
fn pr2_arm_with_the_prismatic_torso_matches_the_urdf() {
    let (dof, p, r) = check(
        PR2,
        &opts(Some("base_footprint"), "r_gripper_palm_link"),
        4,
        true,
    );
    assert_eq!(dof, 8);
    eprintln!("pr2.urdf (torso + right arm): {dof} joints, worst {p:.2e} m, {r:.2e} rad");
    let spec = robot_from_urdf(PR2, &opts(Some("base_footprint"), "r_gripper_palm_link")).unwrap();
    assert_eq!(spec.joints[0].kind, JointType::Prismatic);
    assert_eq!(spec.joint_names.as_ref().unwrap()[0], "torso_lift_joint");
}

#[test]
fn pr2_sub_chain_from_an_inner_base() {
    check(
        PR2,
        &opts(Some("torso_lift_link"), "l_wrist_roll_link"),
        5,
        true,
    );
}

// ---- random chains: axes in any direction, parallel, coincident and
// intersecting axes, fixed joints between movable ones ----

fn pick<'a>(rng: &mut Rng, items: &[&'a str]) -> &'a str {
    items[(rng.uniform() * items.len() as f64) as usize % items.len()]
}

/// A random origin: zero (intersecting axes), along z only (coincident when
/// the axes are), or anywhere; rotations either right angles (parallel and
/// perpendicular axes) or anything.
fn random_origin(rng: &mut Rng) -> String {
    let right = std::f64::consts::FRAC_PI_2;
    let xyz = match (rng.uniform() * 3.0) as usize {
        0 => [0.0; 3],
        1 => [0.0, 0.0, rng.range(-0.4, 0.4)],
        _ => rng.vec3(0.4).to_array(),
    };
    let rpy: [f64; 3] = if rng.uniform() < 0.6 {
        [0, 1, 2].map(|_| right * (rng.uniform() * 4.0).floor())
    } else {
        rng.vec3(3.0).to_array()
    };
    format!(
        "<origin xyz=\"{} {} {}\" rpy=\"{} {} {}\"/>",
        xyz[0], xyz[1], xyz[2], rpy[0], rpy[1], rpy[2]
    )
}

fn random_chain(rng: &mut Rng) -> String {
    let mut xml = String::from("<robot name=\"random\"><link name=\"l0\"/>");
    let n = 2 + (rng.uniform() * 6.0) as usize;
    let mut link = 0;
    for k in 0..n {
        for _ in 0..(rng.uniform() * 2.5) as usize {
            xml += &format!(
                "<link name=\"l{}\"/><joint name=\"f{}\" type=\"fixed\"><parent link=\"l{link}\"/><child link=\"l{}\"/>{}</joint>",
                link + 1,
                link + 1,
                link + 1,
                random_origin(rng)
            );
            link += 1;
        }
        let kind = pick(rng, &["revolute", "revolute", "continuous", "prismatic"]);
        let axis = if rng.uniform() < 0.5 {
            pick(
                rng,
                &[
                    "1 0 0", "0 1 0", "0 0 1", "-1 0 0", "0 -1 0", "0 0 -1", "0 0 2",
                ],
            )
            .to_owned()
        } else {
            let a = rng.unit3();
            format!("{} {} {}", a.x, a.y, a.z)
        };
        let limit = match kind {
            "prismatic" => "<limit lower=\"-0.3\" upper=\"0.4\" effort=\"100\" velocity=\"0.5\"/>",
            "revolute" => "<limit lower=\"-2.5\" upper=\"2.8\" effort=\"50\" velocity=\"2\"/>",
            _ => "",
        };
        xml += &format!(
            "<link name=\"l{}\"/><joint name=\"j{k}\" type=\"{kind}\"><parent link=\"l{link}\"/><child link=\"l{}\"/>{}<axis xyz=\"{axis}\"/>{limit}</joint>",
            link + 1,
            link + 1,
            random_origin(rng)
        );
        link += 1;
    }
    xml += &format!(
        "<link name=\"tip\"/><joint name=\"to_tip\" type=\"fixed\"><parent link=\"l{link}\"/><child link=\"tip\"/>{}</joint></robot>",
        random_origin(rng)
    );
    xml
}

#[test]
fn random_chains_match_their_urdf() {
    let mut rng = Rng::new(42);
    let (mut worst_p, mut worst_r) = (0.0_f64, 0.0_f64);
    for case in 0..60 {
        let xml = random_chain(&mut rng);
        let (_, p, r) = check(&xml, &opts(None, "tip"), 100 + case, false);
        worst_p = worst_p.max(p);
        worst_r = worst_r.max(r);
    }
    eprintln!("60 random chains: worst {worst_p:.2e} m, {worst_r:.2e} rad");
}
