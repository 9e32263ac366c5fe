//! The articulated human: forward kinematics against poses computed by
//! hand, part velocities against finite differences, the reach solution,
//! keyframes and clips, and the refusals of bad input. Runs natively and,
//! unchanged, under `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use std::f64::consts::{FRAC_PI_2, PI};

use glam::DVec3;
use skeleton_avoidance::distance::PrimitiveSpec;
use skeleton_avoidance::human::{
    AnimationSpec, HumanSpec, JOINT_COUNT, PART_NAMES, Pose, Posed, Root, joint, joint_index,
    library, pose_body, proportion as p,
};
use skeleton_avoidance::rng::Rng;
use skeleton_avoidance::scenario::{self, ShapeSpec};

const H: f64 = 1.75;

fn ends(posed: &Posed, name: &str) -> (DVec3, DVec3) {
    let part = posed.parts.iter().find(|q| q.name == name).unwrap();
    match &part.shape {
        PrimitiveSpec::Capsule(c) => (DVec3::from_array(c.a), DVec3::from_array(c.b)),
        PrimitiveSpec::Sphere(s) => (DVec3::from_array(s.center), DVec3::from_array(s.center)),
        other => panic!("{other:?}"),
    }
}

fn pose(angles: &[(&str, f64)]) -> Pose {
    let mut out = Pose::default();
    for (name, a) in angles {
        out.angles[joint_index(name).unwrap()] = *a;
    }
    out
}

fn at_rest(root: Root, angles: &[(&str, f64)]) -> Posed {
    pose_body(H, &root, &pose(angles), &[0.0; JOINT_COUNT])
}

fn close(a: DVec3, b: DVec3, tol: f64) {
    assert!((a - b).length() <= tol, "{a} vs {b}");
}

/// Distance from the wrist to the centre of the hand's far cap.
fn hand_reach() -> f64 {
    (p::HAND - 0.03) * H
}

#[test]
fn upright_body_matches_the_proportions() {
    let b = at_rest(Root::default(), &[]);
    assert_eq!(b.parts.len(), PART_NAMES.len());
    let names: Vec<_> = b.parts.iter().map(|q| q.name).collect();
    assert_eq!(names, PART_NAMES);
    let half = 0.5 * p::SHOULDER_WIDTH * H;
    let shoulder = DVec3::new(0.0, half, p::SHOULDER_HEIGHT * H);
    let (a, e) = ends(&b, "leftUpperArm");
    close(a, shoulder, 1e-12);
    close(e, shoulder - DVec3::Z * (p::UPPER_ARM * H), 1e-12);
    let (w, tip) = ends(&b, "leftHand");
    close(w, e - DVec3::Z * (p::FOREARM * H), 1e-12);
    close(tip, w - DVec3::Z * hand_reach(), 1e-12);
    let (ra, _) = ends(&b, "rightUpperArm");
    close(ra, shoulder * DVec3::new(1.0, -1.0, 1.0), 1e-12);
    let (c, _) = ends(&b, "head");
    close(c, DVec3::Z * (0.5 * (1.0 + p::CHIN_HEIGHT) * H), 1e-12);
    let (hip, knee) = ends(&b, "leftThigh");
    assert!((hip.z - p::HIP_HEIGHT * H).abs() < 1e-12);
    assert!((knee.z - (p::HIP_HEIGHT - p::THIGH) * H).abs() < 1e-12);
    let (_, ankle) = ends(&b, "leftShin");
    assert!((ankle.z - p::ANKLE_HEIGHT * H).abs() < 1e-12);
    // The soles touch the floor; the head's top is at H.
    let foot = &b.parts[12].shape;
    let PrimitiveSpec::Capsule(f) = foot else {
        panic!()
    };
    assert!((f.a[2] - f.radius).abs() < 1e-12 && (f.b[2] - f.radius).abs() < 1e-12);
    let PrimitiveSpec::Sphere(s) = &b.parts[3].shape else {
        panic!()
    };
    assert!((s.center[2] + s.radius - H).abs() < 0.01 * H);
}

#[test]
fn arm_forward_while_facing_plus_y() {
    let root = Root {
        position: DVec3::new(1.0, 2.0, 0.0),
        heading: FRAC_PI_2,
        ..Root::default()
    };
    let b = at_rest(root, &[("leftShoulderFlexion", FRAC_PI_2)]);
    // Facing +y, the person's left is −x.
    let shoulder = DVec3::new(
        1.0 - 0.5 * p::SHOULDER_WIDTH * H,
        2.0,
        p::SHOULDER_HEIGHT * H,
    );
    let (a, e) = ends(&b, "leftUpperArm");
    close(a, shoulder, 1e-12);
    close(e, shoulder + DVec3::Y * (p::UPPER_ARM * H), 1e-12);
    let (_, tip) = ends(&b, "leftHand");
    let arm = (p::UPPER_ARM + p::FOREARM) * H + hand_reach();
    close(tip, shoulder + DVec3::Y * arm, 1e-12);
    // The right arm still hangs.
    let (_, rtip) = ends(&b, "rightHand");
    assert!((rtip.x - (1.0 + 0.5 * p::SHOULDER_WIDTH * H)).abs() < 1e-12);
}

#[test]
fn elbow_abduction_and_rotation_turn_the_forearm_as_documented() {
    // Elbow at 90° with the arm hanging: the forearm points forward.
    let b = at_rest(Root::default(), &[("rightElbow", FRAC_PI_2)]);
    let (e, w) = ends(&b, "rightForearm");
    close(w, e + DVec3::X * (p::FOREARM * H), 1e-12);
    // Internal rotation of 90° swings it across the body (to +y for the
    // right arm).
    let b = at_rest(
        Root::default(),
        &[
            ("rightElbow", FRAC_PI_2),
            ("rightShoulderRotation", FRAC_PI_2),
        ],
    );
    let (e, w) = ends(&b, "rightForearm");
    close(w, e + DVec3::Y * (p::FOREARM * H), 1e-12);
    // Abduction of 90°: the upper arm points away from the body.
    let b = at_rest(Root::default(), &[("leftShoulderAbduction", FRAC_PI_2)]);
    let (s, e) = ends(&b, "leftUpperArm");
    close(e, s + DVec3::Y * (p::UPPER_ARM * H), 1e-12);
}

#[test]
fn trunk_flexion_and_legs() {
    let b = at_rest(Root::default(), &[("spineFlexion", FRAC_PI_2)]);
    let lumbar = DVec3::Z * ((p::HIP_HEIGHT + 0.05) * H);
    let up = (p::SHOULDER_HEIGHT - p::HIP_HEIGHT - 0.05) * H;
    let (s, _) = ends(&b, "leftUpperArm");
    close(
        s,
        lumbar + DVec3::new(up, 0.5 * p::SHOULDER_WIDTH * H, 0.0),
        1e-12,
    );
    // The arms hang along the trunk (towards the hips).
    let (_, e) = ends(&b, "leftUpperArm");
    close(e, s - DVec3::X * (p::UPPER_ARM * H), 1e-12);
    // Hip flexed 90°, knee 90°: thigh forward, shin down.
    let b = at_rest(
        Root::default(),
        &[("rightHipFlexion", FRAC_PI_2), ("rightKnee", FRAC_PI_2)],
    );
    let (hip, knee) = ends(&b, "rightThigh");
    close(knee, hip + DVec3::X * (p::THIGH * H), 1e-12);
    let (k2, ankle) = ends(&b, "rightShin");
    close(k2, knee, 1e-12);
    close(ankle, knee - DVec3::Z * (p::SHANK * H), 1e-12);
    // Heading π mirrors the body about the vertical axis.
    let turned = at_rest(
        Root {
            heading: PI,
            ..Root::default()
        },
        &[("rightHipFlexion", FRAC_PI_2), ("rightKnee", FRAC_PI_2)],
    );
    let (_, k3) = ends(&turned, "rightThigh");
    close(k3, knee * DVec3::new(-1.0, -1.0, 1.0), 1e-12);
}

fn random_pose(rng: &mut Rng) -> Pose {
    let mut out = Pose::default();
    for (a, j) in out.angles.iter_mut().zip(skeleton_avoidance::human::JOINTS) {
        *a = j.min + (j.max - j.min) * rng.uniform();
    }
    out
}

#[test]
fn part_velocities_match_finite_differences() {
    let mut rng = Rng::new(21);
    for _ in 0..40 {
        let q = random_pose(&mut rng);
        let mut rates = [0.0; JOINT_COUNT];
        rates
            .iter_mut()
            .for_each(|r| *r = 4.0 * rng.uniform() - 2.0);
        let root = Root {
            position: DVec3::new(rng.uniform(), rng.uniform(), 0.0),
            heading: 6.0 * rng.uniform(),
            velocity: DVec3::new(1.6 * rng.uniform(), -0.5, 0.1),
            heading_rate: 2.0 * rng.uniform() - 1.0,
        };
        let at = |h: f64| {
            let mut p = q;
            for (a, r) in p.angles.iter_mut().zip(&rates) {
                *a += r * h;
            }
            let r = Root {
                position: root.position + root.velocity * h,
                heading: root.heading + root.heading_rate * h,
                ..root
            };
            pose_body(H, &r, &p, &rates)
        };
        let now = at(0.0);
        let (plus, minus) = (at(1e-6), at(-1e-6));
        for (k, part) in now.parts.iter().enumerate() {
            let (a1, b1) = ends(&plus, part.name);
            let (a0, b0) = ends(&minus, part.name);
            let fd = [(a1 - a0) / 2e-6, (b1 - b0) / 2e-6];
            for (f, v) in fd.iter().zip(&part.velocity) {
                let err = (*f - *v).length();
                assert!(err < 1e-6, "{k} {}: {f} vs {v}", part.name);
            }
            // The middle of the axis moves with the mean of the ends.
            let (a, b) = ends(&now, part.name);
            let mid = part.velocity_at(0.5 * (a + b));
            close(mid, 0.5 * (part.velocity[0] + part.velocity[1]), 1e-12);
        }
    }
}

fn spec(json: &str) -> HumanSpec {
    match serde_json::from_str::<ShapeSpec>(json).unwrap() {
        ShapeSpec::Human(h) => h,
        ShapeSpec::Primitive(_) => panic!("not a human"),
    }
}

#[test]
fn animated_parts_move_with_their_velocities() {
    for clip in library::CLIP_NAMES {
        let h = spec(&format!(
            r#"{{ "type": "human", "position": [1, 0, 0], "heading": 2.5,
                 "animation": {{ "clip": "{clip}", "target": [0.4, 0.2, 1.0], "start": 0.1 }} }}"#
        ));
        let human = h.compile().unwrap();
        let v = DVec3::new(0.3, -1.6, 0.0);
        let mut t = 0.0;
        while t < 5.0 {
            let now = human.posed_at(t, v * t, v);
            let plus = human.posed_at(t + 1e-6, v * (t + 1e-6), v);
            let minus = human.posed_at(t - 1e-6, v * (t - 1e-6), v);
            for part in &now.parts {
                let (a1, b1) = ends(&plus, part.name);
                let (a0, b0) = ends(&minus, part.name);
                let fd = (b1 - b0) / 2e-6;
                assert!(
                    (fd - part.velocity[1]).length() < 1e-5,
                    "{clip} t={t} {}: {fd} vs {}",
                    part.name,
                    part.velocity[1]
                );
                let fd = (a1 - a0) / 2e-6;
                assert!((fd - part.velocity[0]).length() < 1e-5);
            }
            t += 0.0371;
        }
    }
}

#[test]
fn reach_puts_the_hand_on_the_target() {
    let h = spec(r#"{ "type": "human", "position": [1.2, 0.3, 0], "heading": 3.0 }"#);
    let rest = h.rest_pose();
    for target in [
        DVec3::new(0.8, 0.2, 1.3),
        DVec3::new(0.9, 0.6, 1.0),
        DVec3::new(0.85, 0.5, 1.45),
    ] {
        let pose = library::reach_pose(&h, &rest, joint::RIGHT_ARM, target);
        pose.validate().unwrap();
        let root = Root {
            position: DVec3::from_array(h.position),
            heading: h.heading,
            ..Root::default()
        };
        let b = pose_body(h.height, &root, &pose, &[0.0; JOINT_COUNT]);
        let (_, tip) = ends(&b, "rightHand");
        close(tip, target, 1e-9);
        // The left arm keeps its rest angles.
        assert_eq!(
            pose.angles[joint::LEFT_ARM..joint::LEFT_ARM + 4],
            rest.angles[5..9]
        );
    }
}

#[test]
fn reach_clip_arrives_at_about_the_asked_hand_speed() {
    let h = spec(
        r#"{ "type": "human", "position": [1.0, 0, 0], "heading": 3.14159,
             "animation": { "clip": "reach", "target": [0.5, 0.0, 1.1], "speed": 2.0 } }"#,
    );
    let human = h.compile().unwrap();
    let mut peak: f64 = 0.0;
    for k in 0..2000 {
        let b = human.posed_at(f64::from(k) * 0.001, DVec3::ZERO, DVec3::ZERO);
        peak = peak.max(b.parts[9].velocity[1].length());
    }
    assert!((1.9..2.6).contains(&peak), "{peak}");
    let end = human.posed_at(10.0, DVec3::ZERO, DVec3::ZERO);
    close(ends(&end, "rightHand").1, DVec3::new(0.5, 0.0, 1.1), 1e-9);
}

#[test]
fn old_rigid_figures_still_load_and_look_the_same_at_rest() {
    let s = scenario::example("human-panda").unwrap();
    let ShapeSpec::Human(h) = &s.obstacles[0].shape else {
        panic!("the example's first obstacle is the person")
    };
    let parts = h.parts();
    assert_eq!(parts.len(), 16);
    // Arms raised by reach = 0.5 (45° forward); heading π faces −x.
    let pose = h.rest_pose();
    assert_eq!(pose.angles[joint::LEFT_ARM], 0.25 * PI);
    let PrimitiveSpec::Capsule(arm) = &parts[4] else {
        panic!()
    };
    let (a, b) = (DVec3::from_array(arm.a), DVec3::from_array(arm.b));
    let d = (b - a).normalize();
    close(d, DVec3::new(-1.0, 0.0, -1.0).normalize(), 1e-12);
    // The serialised figure is unchanged (no new fields appear).
    let json = serde_json::to_value(&s.obstacles[0].shape).unwrap();
    let keys: Vec<_> = json.as_object().unwrap().keys().cloned().collect();
    assert_eq!(keys, ["heading", "height", "position", "reach", "type"]);
}

#[test]
fn bad_humans_are_refused_naming_the_field() {
    let cases = [
        (
            r#"{ "type": "human", "position": [0, 0, 0], "height": 0 }"#,
            "height",
        ),
        (
            r#"{ "type": "human", "position": [0, 0, 0], "height": 1e9 }"#,
            "height",
        ),
        (
            r#"{ "type": "human", "position": [0, 0, 0], "pose": { "leftKnee": -1 } }"#,
            "pose.leftKnee",
        ),
        (
            r#"{ "type": "human", "position": [0, 0, 0], "animation": { "clip": "dance" } }"#,
            "animation.clip",
        ),
        (
            r#"{ "type": "human", "position": [0, 0, 0], "animation": { "clip": "reach" } }"#,
            "animation.target",
        ),
        (
            r#"{ "type": "human", "position": [0, 0, 0], "animation": { "keyframes":
                [{ "t": 1, "pose": {} }, { "t": 0.5, "pose": {} }] } }"#,
            "animation.keyframes[1].t",
        ),
        (
            r#"{ "type": "human", "position": [0, 0, 0], "animation": { "keyframes":
                [{ "t": 0, "pose": { "rightElbow": 4 } }] } }"#,
            "animation.keyframes[0].pose.rightElbow",
        ),
    ];
    for (json, field) in cases {
        let e = spec(json).compile().unwrap_err();
        assert_eq!(e.field, field, "{json}: {e}");
    }
    assert!(
        serde_json::from_str::<ShapeSpec>(
            r#"{ "type": "human", "position": [0, 0, 0], "pose": { "tail": 1 } }"#
        )
        .is_err()
    );
    let a = AnimationSpec::default();
    assert!(a.keyframes.is_none());
}

#[test]
fn moving_a_hand_moves_only_its_arm() {
    let h = spec(
        r#"{ "type": "human", "position": [1.0, 0.2, 0], "heading": 3.0,
             "animation": { "clip": "wave" } }"#,
    );
    let before = h.parts();
    // Up and back towards the body (the arm at rest is straight, so a
    // hand cannot go farther out).
    let delta = DVec3::new(0.15, 0.05, 0.25);
    let moved = library::move_hand(&h, "right", delta).unwrap();
    assert!(moved.animation.is_none());
    let after = moved.parts();
    for (k, name) in PART_NAMES.iter().enumerate() {
        let arm = ["rightUpperArm", "rightForearm", "rightHand"].contains(name);
        assert_eq!(before[k] == after[k], !arm, "{name}");
    }
    let tip = |p: &[PrimitiveSpec]| match &p[9] {
        PrimitiveSpec::Capsule(c) => DVec3::from_array(c.b),
        _ => panic!(),
    };
    close(tip(&after), tip(&before) + delta, 1e-9);
    assert_eq!(
        library::move_hand(&h, "middle", delta).unwrap_err().field,
        "side"
    );
    let e = library::move_hand(&h, "left", DVec3::new(f64::NAN, 0.0, 0.0)).unwrap_err();
    assert!(e.field.starts_with("delta"), "{e}");
}

/// A figure of almost no height (the smallest positive height passes
/// validation) or a target at the shoulder: reach gives a valid pose, never
/// a panic (found by the fuzz layer).
#[test]
fn reach_on_a_degenerate_figure_is_a_valid_pose() {
    for height in [1e-300, 1e-12, 1.75] {
        let h = spec(&format!(
            r#"{{ "type": "human", "position": [0, 0, 0], "height": {height} }}"#
        ));
        let rest = h.rest_pose();
        for target in [
            DVec3::ZERO,
            DVec3::new(0.0, 0.0, 1.4),
            DVec3::new(0.3, 0.1, 1.2),
        ] {
            let pose = library::reach_pose(&h, &rest, joint::RIGHT_ARM, target);
            pose.validate().unwrap();
        }
    }
}

#[test]
fn the_shoulder_girdle_moves_the_shoulder_joint_about_the_sternum() {
    let rest = at_rest(Root::default(), &[]);
    let half = 0.5 * p::SHOULDER_WIDTH * H;
    let (e, pr) = (0.5, -0.3);
    let raised = at_rest(
        Root::default(),
        &[
            ("leftShoulderElevation", e),
            ("rightShoulderProtraction", pr),
        ],
    );
    // Left: the clavicle turned up by e about the shoulders' middle.
    let (s0, _) = ends(&rest, "leftUpperArm");
    let (s1, elbow) = ends(&raised, "leftUpperArm");
    let sternum = s0 - DVec3::Y * half;
    close(
        s1,
        sternum + half * DVec3::new(0.0, e.cos(), e.sin()),
        1e-12,
    );
    // The arm keeps hanging along the trunk's −z.
    close(elbow - s1, -DVec3::Z * (p::UPPER_ARM * H), 1e-12);
    // Right: retracted (negative protraction) backwards.
    let (r0, _) = ends(&rest, "rightUpperArm");
    let (r1, _) = ends(&raised, "rightUpperArm");
    let sternum = r0 + DVec3::Y * half;
    close(
        r1,
        sternum + half * DVec3::new(pr.sin(), -pr.cos(), 0.0),
        1e-12,
    );
    // The rest of the body does not move.
    for name in ["torso", "head", "leftThigh", "rightFoot"] {
        assert_eq!(ends(&rest, name), ends(&raised, name), "{name}");
    }
}
