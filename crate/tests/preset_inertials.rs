//! The presets' inertial parameters against their sources: the Panda's,
//! the UR5's and the iiwa 14's are the manufacturers' URDF `<inertial>`
//! elements (the files in tests/data/urdf) carried into the preset's DH
//! frames; this test derives them again from the URDFs and checks the
//! preset's tables, then checks that the preset's dynamics are the URDF
//! robot's. The derived tables are printed (`-- --nocapture`) in the form
//! `kinematics/preset_inertials.rs` holds them. Runs natively and, unchanged,
//! under `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::{DAffine3, DVec3};

use skeleton_avoidance::dynamics::urdf::{link_inertial, urdf_bodies};
use skeleton_avoidance::dynamics::{Dynamics, Inertial};
use skeleton_avoidance::fitting::rigid_fit;
use skeleton_avoidance::kinematics::{Robot, presets::preset};
use skeleton_avoidance::parsers::urdf::{UrdfOptions, robot_with_links};
use skeleton_avoidance::rng::Rng;

/// The URDF's robot and bodies (tip `tip`) and the preset's robot.
fn robots(xml: &str, tip: &str, name: &str) -> (Robot, Robot) {
    let options = UrdfOptions {
        tip: Some(tip.to_owned()),
        ..UrdfOptions::default()
    };
    let imported = urdf_bodies(xml, &options).unwrap();
    let urdf = Robot::from_spec(&imported.spec).unwrap();
    let preset = Robot::from_spec(&preset(name).unwrap()).unwrap();
    (urdf, preset)
}

fn sample(robot: &Robot, rng: &mut Rng) -> Vec<f64> {
    robot
        .joints
        .iter()
        .map(|j| {
            let (lo, hi) = (j.min.max(-3.0), j.max.min(3.0));
            lo + (hi - lo) * rng.uniform()
        })
        .collect()
}

/// The rigid transform from the URDF's world to the preset's, fitted to
/// the tips (the URDF's end effector on the preset's last frame) over
/// sampled configurations; the largest stray is checked.
fn base_transform(urdf: &Robot, preset: &Robot) -> DAffine3 {
    let n = preset.dof();
    let mut rng = Rng::new(11);
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for _ in 0..20 {
        let q = sample(preset, &mut rng);
        a.push(urdf.forward(&q).unwrap().end_effector().translation);
        b.push(preset.forward(&q).unwrap().transforms[n].translation);
    }
    let w = rigid_fit(&a, &b);
    for (p, q) in a.iter().zip(&b) {
        let stray = (w.transform_point3(*p) - *q).length();
        assert!(stray < 1e-6, "{} strays {stray:e} m", preset.name);
    }
    w
}

/// The URDF's links up to `tip`, less `left_out`, lumped per row, each
/// link placed in its row's frame by `place(row, pose of the link at q = 0
/// in the URDF's world)`.
fn lumped(
    xml: &str,
    tip: &str,
    left_out: &[&str],
    place: impl Fn(usize, DAffine3) -> DAffine3,
) -> Vec<Inertial> {
    let options = UrdfOptions {
        tip: Some(tip.to_owned()),
        ..UrdfOptions::default()
    };
    let (spec, links) = robot_with_links(xml, &options).unwrap();
    let document = urdf_rs::read_from_string(xml).unwrap();
    let mut bodies = vec![Inertial::ZERO; spec.joints.len()];
    for link in links.iter().filter(|l| l.row >= 1) {
        if left_out.contains(&link.name.as_str()) {
            continue;
        }
        let element = document.links.iter().find(|l| l.name == link.name).unwrap();
        let body = link_inertial(element)
            .unwrap()
            .transformed(&place(link.row, link.pose));
        bodies[link.row - 1] = bodies[link.row - 1].lumped(&body);
    }
    bodies
}

/// The URDF's links up to `tip`, less `left_out`, in the preset's DH
/// frames, lumped per row.
fn derived(xml: &str, tip: &str, name: &str, left_out: &[&str]) -> Vec<Inertial> {
    let (urdf, preset) = robots(xml, tip, name);
    let w = base_transform(&urdf, &preset);
    let fp = preset.forward(&vec![0.0; preset.dof()]).unwrap();
    lumped(xml, tip, left_out, |row, pose| {
        fp.transforms[row].inverse() * w * pose
    })
}

/// The preset's torques and mass matrix are the URDF robot's (the same
/// links, in the URDF's own DH frames, gravity turned by the base
/// transform) at random states.
fn same_dynamics(xml: &str, tip: &str, name: &str, left_out: &[&str]) {
    let (urdf, preset) = robots(xml, tip, name);
    let w = base_transform(&urdf, &preset);
    let fu = urdf.forward(&vec![0.0; urdf.dof()]).unwrap();
    let bodies = lumped(xml, tip, left_out, |row, pose| {
        fu.transforms[row].inverse() * pose
    });
    let g = w.matrix3.transpose() * DVec3::new(0.0, 0.0, -9.81);
    let from_urdf = Dynamics::new(urdf, bodies)
        .unwrap()
        .with_gravity(g)
        .unwrap();
    let from_preset = Dynamics::from_robot(preset).unwrap();
    let n = from_preset.dof();
    let (mut wu, mut wp) = (from_urdf.workspace(), from_preset.workspace());
    let (mut tu, mut tp) = (vec![0.0; n], vec![0.0; n]);
    let (mut mu, mut mp) = (vec![0.0; n * n], vec![0.0; n * n]);
    let mut rng = Rng::new(3);
    let mut worst: f64 = 0.0;
    for _ in 0..20 {
        let q = sample(from_preset.robot(), &mut rng);
        let qd: Vec<f64> = (0..n).map(|_| 2.0 * rng.uniform() - 1.0).collect();
        let qdd: Vec<f64> = (0..n).map(|_| 6.0 * rng.uniform() - 3.0).collect();
        from_urdf
            .inverse_dynamics(&mut wu, &q, (&qd, &qdd), &mut tu)
            .unwrap();
        from_preset
            .inverse_dynamics(&mut wp, &q, (&qd, &qdd), &mut tp)
            .unwrap();
        from_urdf.mass_matrix(&mut wu, &q, &mut mu).unwrap();
        from_preset.mass_matrix(&mut wp, &q, &mut mp).unwrap();
        for (a, b) in [(&tu, &tp), (&mu, &mp)] {
            let scale = a.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            let e = a
                .iter()
                .zip(b.iter())
                .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
            worst = worst.max(e / scale);
        }
    }
    println!("{name}: preset against URDF, largest relative difference {worst:.1e}");
    assert!(worst < 1e-8, "{name}: {worst:e}");
}

fn print_table(name: &str, bodies: &[Inertial]) {
    println!("{name}:");
    for b in bodies {
        let s = b.to_spec();
        let clean = |v: &[f64]| {
            v.iter()
                .map(|x| {
                    let r: f64 = format!("{x:.10e}").parse().unwrap();
                    if r.abs() < 1e-10 {
                        "0.0".to_owned()
                    } else {
                        format!("{r:?}")
                    }
                })
                .collect::<Vec<_>>()
                .join(", ")
        };
        println!(
            "    body({}, [{}], [{}]),",
            clean(&[s.mass]),
            clean(&s.com),
            clean(&s.inertia)
        );
    }
}

/// Largest difference between two bodies relative to the size of each
/// quantity (mass, centre of mass, inertia).
fn difference(a: &Inertial, b: &Inertial) -> f64 {
    let mass = (a.mass - b.mass).abs() / a.mass.max(1e-300);
    let com = (a.com - b.com).length() / a.com.length().max(1e-3);
    let scale = a
        .inertia
        .to_cols_array()
        .iter()
        .fold(0.0_f64, |m, x| m.max(x.abs()));
    let inertia = (a.inertia - b.inertia)
        .to_cols_array()
        .iter()
        .fold(0.0_f64, |m, x| m.max(x.abs()))
        / scale.max(1e-300);
    mass.max(com).max(inertia)
}

fn check_table(xml: &str, tip: &str, name: &str, left_out: &[&str]) {
    let bodies = derived(xml, tip, name, left_out);
    print_table(name, &bodies);
    let preset = Robot::from_spec(&preset(name).unwrap()).unwrap();
    for (k, (want, joint)) in bodies.iter().zip(&preset.joints).enumerate() {
        let got = joint.inertial.expect("the preset carries inertial data");
        let d = difference(want, &got);
        assert!(d < 1e-9, "{name} row {}: differs by {d:e}", k + 1);
    }
}

const PANDA: &str = include_str!("data/urdf/panda_collision.urdf");
const UR5: &str = include_str!("data/urdf/ur5_robot.urdf");
const IIWA14: &str = include_str!("data/urdf/iiwa14_primitive_collision.urdf");

const HAND: &[&str] = &["panda_hand", "panda_hand_tcp"];

#[test]
fn panda_preset_carries_franka_description_inertials() {
    check_table(PANDA, "panda_link8", "panda", HAND);
    same_dynamics(PANDA, "panda_link8", "panda", HAND);
}

#[test]
fn ur5_preset_carries_ur_description_inertials() {
    check_table(UR5, "ee_link", "ur5", &[]);
    same_dynamics(UR5, "ee_link", "ur5", &[]);
}

#[test]
fn iiwa14_preset_carries_iiwa_description_inertials() {
    check_table(IIWA14, "iiwa_link_7", "iiwa14", &[]);
    same_dynamics(IIWA14, "iiwa_link_7", "iiwa14", &[]);
}

/// Every preset that carries inertial data gives a dynamics whose mass
/// matrix is positive definite at a random state; the others say which
/// links lack it.
#[test]
fn presets_with_and_without_inertial_data() {
    for name in ["panda", "ur5", "iiwa14", "lwr4", "dual-arm"] {
        let robot = Robot::from_spec(&preset(name).unwrap()).unwrap();
        assert!(robot.joints.iter().all(|j| j.inertial.is_some()), "{name}");
        let dynamics = Dynamics::from_robot(robot).unwrap();
        let n = dynamics.dof();
        let mut ws = dynamics.workspace();
        let mut m = vec![0.0; n * n];
        let q: Vec<f64> = (0..n).map(|k| 0.2 + 0.1 * k as f64).collect();
        dynamics.mass_matrix(&mut ws, &q, &mut m).unwrap();
        for k in 0..n {
            assert!(m[k * n + k] > 0.0, "{name}: M[{k}][{k}] = {}", m[k * n + k]);
        }
    }
    for (name, rows) in [
        ("planar3", "link 1, link 2, link 3"),
        ("stanford", "link 1, link 2"),
    ] {
        let robot = Robot::from_spec(&preset(name).unwrap()).unwrap();
        let e = Dynamics::from_robot(robot).unwrap_err();
        assert_eq!(e.field, "inertials");
        assert!(e.to_string().contains(rows), "{name}: {e}");
    }
}

/// A spec may carry inertial data by hand (as JSON); bad values are
/// refused naming the field.
#[test]
fn inertials_by_hand_and_bad_ones_refused_naming_the_field() {
    let json = r#"{"convention": "standard", "joints": [
        {"a": 0.4, "alpha": 0, "d": 0, "theta": 0,
         "inertial": {"mass": 2, "com": [-0.2, 0, 0], "inertia": [0.001, 0, 0, 0.03, 0, 0.03]}},
        {"a": 0.3, "alpha": 0, "d": 0, "theta": 0,
         "inertial": {"mass": 1}}]}"#;
    let spec: skeleton_avoidance::kinematics::RobotSpec = serde_json::from_str(json).unwrap();
    let dynamics = Dynamics::from_robot(Robot::from_spec(&spec).unwrap()).unwrap();
    assert_eq!(dynamics.bodies()[1].mass, 1.0);
    // Round trip: the spec serialises its inertial data unchanged.
    let again: skeleton_avoidance::kinematics::RobotSpec =
        serde_json::from_str(&serde_json::to_string(&spec).unwrap()).unwrap();
    assert_eq!(again, spec);

    let refused = |mass: f64, com: [f64; 3], inertia: [f64; 6], branch: bool| {
        let mut s = preset(if branch { "dual-arm" } else { "panda" }).unwrap();
        let body = skeleton_avoidance::dynamics::InertialSpec { mass, com, inertia };
        if branch {
            s.branches[0].joints[2].inertial = Some(body);
        } else {
            s.joints[1].inertial = Some(body);
        }
        Robot::from_spec(&s).unwrap_err().to_string()
    };
    let good = [0.01, 0.0, 0.0, 0.01, 0.0, 0.01];
    let cases = [
        (
            refused(-1.0, [0.0; 3], good, false),
            "joints[1].inertial.mass: must be >= 0",
        ),
        (
            refused(f64::NAN, [0.0; 3], good, false),
            "joints[1].inertial.mass: not a finite number",
        ),
        (
            refused(1.0, [0.0, f64::INFINITY, 0.0], good, false),
            "joints[1].inertial.com[1]: not a finite number",
        ),
        (
            refused(1.0, [0.0; 3], [0.01, 0.0, 0.0, f64::NAN, 0.0, 0.01], false),
            "joints[1].inertial.inertia[3]: not a finite number",
        ),
        (
            refused(1.0, [0.0; 3], [-0.01, 0.0, 0.0, 0.01, 0.0, 0.01], false),
            "joints[1].inertial.inertia: not positive semi-definite",
        ),
        (
            refused(1.0, [0.0; 3], [0.01, 0.02, 0.0, 0.01, 0.0, 0.01], false),
            "joints[1].inertial.inertia: not positive semi-definite",
        ),
        (
            refused(1.0, [0.0; 3], [0.1, 0.0, 0.0, 0.01, 0.0, 0.01], false),
            "joints[1].inertial.inertia: principal moments",
        ),
        (
            refused(-1.0, [0.0; 3], good, true),
            "branches[0].joints[2].inertial.mass: must be >= 0",
        ),
    ];
    for (got, want) in cases {
        assert!(got.starts_with(want), "{got}\nexpected {want}");
    }
}
