//! URDF import: what is read besides the geometry (limits, radii, names,
//! the default tip) and every kind of bad input, with the message naming the
//! element. Runs natively and under `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use skeleton_avoidance::kinematics::{JointType, RadiusSpec, Robot, presets};
use skeleton_avoidance::parsers::urdf::{UrdfOptions, robot_from_urdf};

const PANDA: &str = include_str!("data/urdf/panda_collision.urdf");
const IIWA: &str = include_str!("data/urdf/iiwa14_primitive_collision.urdf");
const PR2: &str = include_str!("data/urdf/pr2.urdf");
const UR5: &str = include_str!("data/urdf/ur5_robot.urdf");

fn tip(t: &str) -> UrdfOptions {
    UrdfOptions {
        tip: Some(t.to_owned()),
        ..UrdfOptions::default()
    }
}

fn error(xml: &str, options: &UrdfOptions) -> String {
    robot_from_urdf(xml, options).unwrap_err().to_string()
}

/// A two-joint chain with `j2` given by `joint2` (type, axis, limit, ...).
fn two_joints(joint2: &str) -> String {
    format!(
        r#"<robot name="two">
  <link name="a"/><link name="b"><collision><geometry><box size="0.3 0.04 0.06"/></geometry></collision></link>
  <link name="c"><collision><geometry><sphere radius="0.07"/></geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0 0 0.2"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="30" velocity="1.5"/></joint>
  <joint name="j2" {joint2}<parent link="b"/><child link="c"/><origin xyz="0.3 0 0"/></joint>
</robot>"#
    )
}

#[test]
fn limits_and_radii_are_read() {
    let spec = robot_from_urdf(PANDA, &tip("panda_link8")).unwrap();
    let j1 = &spec.joints[0];
    assert_eq!((j1.min, j1.max), (Some(-2.8973), Some(2.8973)));
    assert_eq!((j1.max_velocity, j1.max_torque), (Some(2.175), Some(87.0)));
    // panda_collision.urdf: link 1 is a cylinder and two spheres of radius 0.09.
    assert_eq!(j1.radius, Some(RadiusSpec::Uniform(0.09)));
    let iiwa = robot_from_urdf(IIWA, &tip("iiwa_link_ee")).unwrap();
    assert_eq!(iiwa.joints[0].radius, Some(RadiusSpec::Uniform(0.101)));
    // Links 6 and 7 have only meshes: the default radius, written into the spec.
    assert_eq!(iiwa.joints[6].radius, Some(RadiusSpec::Uniform(0.05)));
    let two = robot_from_urdf(
        &two_joints(r#"type="continuous"><axis xyz="0 0 1"/>"#),
        &UrdfOptions::default(),
    )
    .unwrap();
    // Box 0.3 × 0.04 × 0.06: half the diagonal of its two smaller sides.
    let RadiusSpec::Uniform(r) = two.joints[0].radius.unwrap() else {
        panic!()
    };
    assert!((r - 0.5 * 0.04_f64.hypot(0.06)).abs() < 1e-15);
    assert_eq!(two.joints[1].radius, Some(RadiusSpec::Uniform(0.07)));
    // Continuous: no position limits.
    assert_eq!((two.joints[1].min, two.joints[1].max), (None, None));
    assert_eq!(
        two.joint_names,
        Some(vec!["j1".to_owned(), "j2".to_owned()])
    );
    assert_eq!(two.name.as_deref(), Some("two"));
}

#[test]
fn the_default_tip_ends_the_longest_chain() {
    // Panda: the 7 arm joints and the first (non-mimic) finger joint.
    let spec = robot_from_urdf(PANDA, &UrdfOptions::default()).unwrap();
    assert_eq!(spec.joints.len(), 8);
    assert_eq!(spec.joints[7].kind, JointType::Prismatic);
    assert_eq!(spec.joint_names.as_ref().unwrap()[7], "panda_finger_joint1");
    // PR2: torso lift, right arm, first finger joint (9 joints).
    let pr2 = robot_from_urdf(PR2, &UrdfOptions::default()).unwrap();
    assert_eq!(pr2.joints.len(), 9);
    Robot::from_spec(&pr2).unwrap();
}

#[test]
fn joint_names_are_validated() {
    let mut spec = presets::preset("planar3").unwrap();
    spec.joint_names = Some(vec!["a".into(), "b".into()]);
    let e = Robot::from_spec(&spec).unwrap_err().to_string();
    assert_eq!(e, "jointNames: expected 3 names (one per joint), got 2");
    spec.joint_names = Some(vec!["a".into(), "b".into(), "a".into()]);
    let e = Robot::from_spec(&spec).unwrap_err().to_string();
    assert_eq!(e, "jointNames[2]: \"a\" appears twice");
    spec.joint_names = Some(vec!["a".into(), "b".into(), "c".into()]);
    Robot::from_spec(&spec).unwrap();
}

#[test]
fn bad_input_names_the_element() {
    let none = UrdfOptions::default();
    assert!(error("<robot name=\"x\"><link name=\"a\">", &none).starts_with("xml: "));
    assert!(error("not xml at all", &none).starts_with("xml: "));
    assert!(error("", &none).starts_with("xml: "));
    assert_eq!(
        error(PANDA, &tip("nowhere")),
        "tip: no link named \"nowhere\""
    );
    let b = UrdfOptions {
        base: Some("panda_link5".into()),
        tip: Some("panda_link2".into()),
        ..UrdfOptions::default()
    };
    assert_eq!(
        error(PANDA, &b),
        "tip: link \"panda_link2\" is not below base link \"panda_link5\""
    );
    let zero = two_joints(
        r#"type="revolute"><axis xyz="0 0 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/>"#,
    );
    assert_eq!(error(&zero, &none), "joint \"j2\": axis has zero length");
    let nan = two_joints(r#"type="continuous"><axis xyz="0 NaN 1"/>"#);
    assert_eq!(
        error(&nan, &none),
        "joint \"j2\": axis[1] is not a finite number"
    );
    let inverted = two_joints(
        r#"type="revolute"><axis xyz="0 0 1"/><limit lower="1" upper="-1" effort="1" velocity="1"/>"#,
    );
    assert!(
        error(&inverted, &none).starts_with("joint \"j2\": "),
        "{}",
        error(&inverted, &none)
    );
    let floating = two_joints(r#"type="floating">"#);
    assert!(
        error(&floating, &tip("c")).starts_with("joint \"j2\": floating joints are not supported")
    );
    let planar = two_joints(r#"type="planar"><axis xyz="0 0 1"/>"#);
    assert!(error(&planar, &tip("c")).starts_with("joint \"j2\": planar joints"));
    let mimic = two_joints(r#"type="continuous"><axis xyz="0 0 1"/><mimic joint="j1"/>"#);
    assert!(error(&mimic, &tip("c")).starts_with("joint \"j2\": mimic joints cannot be imported"));
    // Without a tip, the chain stops before the mimic joint.
    assert_eq!(robot_from_urdf(&mimic, &none).unwrap().joints.len(), 1);
    let only_fixed =
        two_joints(r#"type="fixed">"#).replace(r#"type="revolute""#, r#"type="fixed""#);
    assert!(
        error(&only_fixed, &tip("c"))
            .starts_with("tip: no revolute, continuous or prismatic joint")
    );
    let missing =
        two_joints(r#"type="fixed">"#).replace(r#"<child link="c"/>"#, r#"<child link="d"/>"#);
    assert_eq!(
        error(&missing, &none),
        "joint \"j2\": child link \"d\" is not defined"
    );
    let loop_ = two_joints(r#"type="fixed">"#).replace(
        "</robot>",
        r#"<joint name="back" type="fixed"><parent link="c"/><child link="b"/></joint></robot>"#,
    );
    assert!(
        error(&loop_, &none).starts_with(
            "joint \"back\": link \"b\" already has parent joint \"j1\" (closed loops"
        )
    );
    let two_roots = two_joints(r#"type="fixed">"#)
        .replace("<link name=\"a\"/>", "<link name=\"a\"/><link name=\"z\"/>");
    assert!(error(&two_roots, &none).starts_with("base: the URDF has several root links"));
    let nan_origin =
        two_joints(r#"type="continuous"><axis xyz="0 0 1"/>"#).replace("0.3 0 0", "0.3 nan 0");
    assert_eq!(
        error(&nan_origin, &none),
        "joint \"j2\": origin.xyz[1] is not a finite number"
    );
}

#[test]
fn damaged_documents_give_errors_not_panics() {
    let mut rng = skeleton_avoidance::rng::Rng::new(9);
    let bytes: Vec<char> = UR5.chars().collect();
    let junk = ['<', '>', '"', '/', '=', 'x', '0', '-', 'e', ' ', '.'];
    for case in 0..150 {
        let mut text = bytes.clone();
        if case % 3 == 0 {
            text.truncate((rng.uniform() * text.len() as f64) as usize);
        } else {
            for _ in 0..1 + case % 5 {
                let at = (rng.uniform() * text.len() as f64) as usize % text.len();
                text[at] = junk[(rng.uniform() * junk.len() as f64) as usize % junk.len()];
            }
        }
        let text: String = text.into_iter().collect();
        // Any outcome but a panic: a spec that validates, or an error naming a field.
        match robot_from_urdf(&text, &UrdfOptions::default()) {
            Ok(spec) => {
                Robot::from_spec(&spec).unwrap();
            }
            Err(e) => assert!(!e.field.is_empty(), "{e}"),
        }
    }
}

#[test]
fn the_import_reports_what_it_defaulted_and_left_out() {
    use skeleton_avoidance::parsers::urdf::{import_urdf, report::RadiusFrom};
    let two = two_joints(r#"type="continuous"><axis xyz="0 0 1"/>"#);
    let with_mesh = two.replace(
        "<link name=\"c\"><collision><geometry><sphere radius=\"0.07\"/></geometry></collision></link>",
        "<link name=\"c\"><collision><geometry><mesh filename=\"c.stl\"/></geometry></collision></link>",
    );
    let import = import_urdf(&with_mesh, &UrdfOptions::default()).unwrap();
    let r = &import.report;
    assert_eq!(r.joints.len(), 2);
    assert_eq!(r.joints[0].links, ["b"]);
    assert_eq!(r.joints[0].radius_from, RadiusFrom::Collision);
    assert_eq!(r.joints[1].radius_from, RadiusFrom::Default);
    assert_eq!(r.joints[1].radius, 0.05);
    assert_eq!(r.links_without_primitive, ["c"]);
    // j1 gives velocity and effort; j2 (continuous, no <limit>) nothing.
    assert_eq!(r.joints[0].defaulted, ["maxAcceleration", "maxJerk"]);
    assert_eq!(
        r.joints[1].defaulted,
        ["maxVelocity", "maxAcceleration", "maxJerk", "maxTorque"]
    );
    assert!(r.joints[0].position_limits && !r.joints[1].position_limits);
    // The values used are in the spec.
    let j2 = &import.robot.joints[1];
    assert_eq!(
        (
            j2.max_velocity,
            j2.max_acceleration,
            j2.max_jerk,
            j2.max_torque
        ),
        (Some(2.0), Some(10.0), Some(5000.0), Some(100.0))
    );
    assert_eq!(j2.radius, Some(RadiusSpec::Uniform(0.05)));
    assert!(r.outside_chain.is_empty() && r.start_contacts.is_empty());

    // A radius per link overrides the geometry; a bad override changes nothing.
    let mut options = UrdfOptions {
        radii: Some([("c".to_owned(), 0.02)].into_iter().collect()),
        ..UrdfOptions::default()
    };
    let over = import_urdf(&with_mesh, &options).unwrap();
    assert_eq!(over.report.joints[1].radius_from, RadiusFrom::Override);
    assert_eq!(over.robot.joints[1].radius, Some(RadiusSpec::Uniform(0.02)));
    options.radii = Some([("nowhere".to_owned(), 0.02)].into_iter().collect());
    assert_eq!(
        import_urdf(&with_mesh, &options).unwrap_err().to_string(),
        "radii.nowhere: no link named \"nowhere\""
    );
    options.radii = Some([("a".to_owned(), 0.02)].into_iter().collect());
    assert_eq!(
        import_urdf(&with_mesh, &options).unwrap_err().to_string(),
        "radii.a: this link is not moved by the imported chain"
    );
    options.radii = Some([("b".to_owned(), -1.0)].into_iter().collect());
    assert!(
        import_urdf(&with_mesh, &options)
            .unwrap_err()
            .to_string()
            .starts_with("radii.b: must be a number in (0, 1000] m")
    );
}

#[test]
fn an_import_starting_in_self_collision_names_the_links() {
    use skeleton_avoidance::world::import_urdf;
    // The iiwa with a 1 m collision cylinder on its last link (a needle
    // modelled carelessly): at q = 0 that link overlaps the ones below it.
    let fat = IIWA.replacen(
        "<link name=\"iiwa_link_7\">",
        "<link name=\"iiwa_link_7\"><collision><geometry><cylinder radius=\"1\" length=\"0.1\"/></geometry></collision>",
        1,
    );
    assert_ne!(fat, IIWA);
    let import = import_urdf(&fat, &tip("iiwa_link_ee")).unwrap();
    let contacts = &import.report.start_contacts;
    assert!(!contacts.is_empty(), "{:?}", import.report);
    assert!(
        contacts.iter().all(|c| c.links[1] == "iiwa_link_7"
            && c.joints[1] == "iiwa_joint_7"
            && c.distance < 0.0),
        "{contacts:?}"
    );
    assert!(contacts.iter().any(|c| c.links[0] == "iiwa_link_1"));
    // The file as published starts free.
    let clean = import_urdf(IIWA, &tip("iiwa_link_ee")).unwrap();
    assert!(
        clean.report.start_contacts.is_empty(),
        "{:?}",
        clean.report.start_contacts
    );
}

#[test]
fn dh_values_carry_no_rounding_dust() {
    for (xml, t) in [
        (PANDA, "panda_link8"),
        (IIWA, "iiwa_link_ee"),
        (UR5, "ee_link"),
    ] {
        let spec = robot_from_urdf(xml, &tip(t)).unwrap();
        for j in &spec.joints {
            for v in [j.a, j.alpha, j.d, j.theta] {
                assert!(v == 0.0 || v.abs() > 1e-14, "{t}: {v:e}");
                assert!(!(v == 0.0 && v.is_sign_negative()), "{t}: -0");
            }
        }
    }
}
