//! A row's `radius` in its three forms: one value, `[r0, r1]` on every
//! segment, or one per segment (`{ d?, a?, extension? }`); the old forms
//! unchanged, the new one validated with the field named, and fitted by
//! `fitting::fit_volumes` segment by segment.
//! Runs natively and, unchanged, under `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::DVec3;
use skeleton_avoidance::fitting::{Body, fit_volumes};
use skeleton_avoidance::kinematics::{
    RadiusSpec, Robot, RobotSpec, SegmentRadius, SegmentRadiusSpec,
};
use skeleton_avoidance::mesh::TriMesh;
use skeleton_avoidance::skeleton::{Skeleton, SpinePart};

/// One revolute row with a `d` spine, an `a` spine and an extension.
fn row(radius: &str) -> RobotSpec {
    serde_json::from_str(&format!(
        r#"{{ "convention": "standard", "joints": [ {{ "a": 0.3, "alpha": 0, "d": 0.2, "theta": 0, "extension": 0.1, "radius": {radius} }} ] }}"#
    ))
    .unwrap()
}

/// Each segment's part and radii at `q = 0`.
fn segments(spec: &RobotSpec) -> Vec<(SpinePart, [f64; 2])> {
    let robot = Robot::from_spec(spec).unwrap();
    let sk = Skeleton::build(&robot, &robot.forward(&[0.0]).unwrap());
    sk.segments.iter().map(|s| (s.part, s.radius)).collect()
}

#[test]
fn the_old_forms_read_and_write_as_before() {
    let one = row("0.07");
    assert_eq!(one.joints[0].radius, Some(RadiusSpec::Uniform(0.07)));
    let pair = row("[0.07, 0.04]");
    assert_eq!(
        pair.joints[0].radius,
        Some(RadiusSpec::Tapered([0.07, 0.04]))
    );
    let text = serde_json::to_string(&pair.joints[0]).unwrap();
    assert!(text.contains(r#""radius":[0.07,0.04]"#), "{text}");
    for (_, r) in segments(&pair) {
        assert_eq!(r, [0.07, 0.04]);
    }
    // The same pair given per segment builds the same skeleton, bit for bit.
    let same = row(r#"{ "d": [0.07, 0.04], "a": [0.07, 0.04], "extension": [0.07, 0.04] }"#);
    assert_eq!(segments(&same), segments(&pair));
}

#[test]
fn each_segment_gets_its_own_radius() {
    let spec = row(r#"{ "d": [0.1, 0.2], "a": 0.03 }"#);
    assert_eq!(
        spec.joints[0].radius,
        Some(RadiusSpec::PerSegment(SegmentRadiusSpec {
            d: Some(SegmentRadius::Tapered([0.1, 0.2])),
            a: Some(SegmentRadius::Uniform(0.03)),
            extension: None,
        }))
    );
    assert_eq!(
        segments(&spec),
        vec![
            (SpinePart::D, [0.1, 0.2]),
            (SpinePart::Extension, [0.05, 0.05]),
            (SpinePart::A, [0.03, 0.03]),
        ]
    );
    let back: RobotSpec = serde_json::from_str(&serde_json::to_string(&spec).unwrap()).unwrap();
    assert_eq!(back, spec);
}

#[test]
fn a_bad_segment_radius_is_refused_with_its_field() {
    let err = |r: &str| Robot::from_spec(&row(r)).unwrap_err().to_string();
    assert!(err(r#"{ "d": [0.1, -0.2] }"#).starts_with("joints[0].radius.d[1]:"));
    assert!(err(r#"{ "a": -1 }"#).starts_with("joints[0].radius.a:"));
    assert!(err(r#"{ "extension": [1e9, 0.1] }"#).starts_with("joints[0].radius.extension[0]:"));
    assert!(err("[0.1, -0.2]").starts_with("joints[0].radius[1]:"));
    // Unknown parts and nested objects are not a radius.
    for bad in [
        r#"{ "b": 0.1 }"#,
        r#"{ "d": { "a": 0.1 } }"#,
        r#"{ "d": [0.1] }"#,
    ] {
        let text = format!(
            r#"{{ "convention": "standard", "joints": [ {{ "a": 0.3, "alpha": 0, "d": 0.2, "theta": 0, "radius": {bad} }} ] }}"#
        );
        assert!(serde_json::from_str::<RobotSpec>(&text).is_err(), "{bad}");
    }
}

#[test]
fn fitting_gives_each_segment_of_a_row_its_own_pair() {
    // A thick part around the d spine (0.1 m off it) and a thin one around
    // the a spine (0.02 m off it), both carried by row 1.
    let spec: RobotSpec =
        serde_json::from_str(r#"{ "convention": "standard", "joints": [ { "a": 0.4, "alpha": 0, "d": 0.3, "theta": 0 } ] }"#)
            .unwrap();
    let mut vertices = Vec::new();
    for k in 1..=9 {
        let s = f64::from(k) / 10.0;
        vertices.push(DVec3::new(-0.1, 0.0, 0.2 * s));
        vertices.push(DVec3::new(0.4 * s, 0.02, 0.3));
    }
    let mesh = TriMesh {
        vertices,
        triangles: vec![],
    };
    let fitted = fit_volumes(
        &spec,
        &[0.0],
        &[Body {
            name: "l1".into(),
            link: 1,
            mesh,
        }],
    )
    .unwrap();
    let Some(RadiusSpec::PerSegment(r)) = fitted.joints[0].radius else {
        panic!("{:?}", fitted.joints[0].radius);
    };
    let (Some(SegmentRadius::Tapered(d)), Some(SegmentRadius::Tapered(a))) = (r.d, r.a) else {
        panic!("{r:?}");
    };
    // The a spine's volume stays thin (one pair per row would give it the
    // d spine's 0.1 m); every vertex is inside its own segment's volume.
    assert!(d.iter().any(|r| *r >= 0.1 - 1e-9), "{d:?}");
    assert!(a.iter().all(|r| (r - 0.02).abs() < 1e-6), "{a:?}");
}
