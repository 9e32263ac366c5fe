//! BVH motion capture: a recording replayed within 1 mm of its joints,
//! the shipped sample, and malformed files refused naming the field. Runs
//! natively and, unchanged, under `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::DVec3;
use skeleton_avoidance::distance::PrimitiveSpec;
use skeleton_avoidance::human::track::{TrackOptions, import, synthesize_bvh};
use skeleton_avoidance::human::{Human, HumanSpec, Posed};
use skeleton_avoidance::scenario::ShapeSpec;

/// A person who turns, walks, bends, twists, nods and reaches: every joint
/// the fit reads moves.
fn mover() -> Human {
    let spec: ShapeSpec = serde_json::from_value(serde_json::json!({
        "type": "human", "position": [0.9, 0.6, 0.0], "heading": -1.2, "height": 1.82,
        "animation": { "keyframes": [
            { "t": 0.0, "pose": { "leftShoulderFlexion": 0.3, "rightElbow": 0.4, "leftKnee": 0.2 } },
            { "t": 0.7, "pose": { "rightShoulderFlexion": 1.4, "rightShoulderAbduction": 0.4,
                                  "rightShoulderRotation": -0.5, "rightElbow": 1.3,
                                  "spineFlexion": 0.4, "spineTwist": 0.3, "spineLateral": -0.15,
                                  "neckFlexion": 0.35, "neckTwist": -0.4,
                                  "leftHipFlexion": 0.5, "leftKnee": 0.8, "rightHipAbduction": 0.25 },
              "shift": [0.3, -0.1, 0.0], "turn": 0.6 },
            { "t": 1.5, "pose": { "leftShoulderAbduction": 1.3, "leftShoulderRotation": 0.9,
                                  "leftElbow": 1.7, "spineLateral": 0.2, "neckTwist": 0.6,
                                  "rightHipFlexion": 0.6, "rightKnee": 1.0, "leftHipAbduction": 0.2 },
              "shift": [0.5, 0.2, 0.0], "turn": -0.3 }
        ] }
    }))
    .unwrap();
    let ShapeSpec::Human(h) = spec else { panic!() };
    h.compile().unwrap()
}

/// Shoulders, elbows, wrists, hips, knees, ankles and the head's centre.
fn joints(p: &Posed) -> Vec<DVec3> {
    let e = |k: usize| match &p.parts[k].shape {
        PrimitiveSpec::Capsule(c) => (DVec3::from_array(c.a), DVec3::from_array(c.b)),
        PrimitiveSpec::Sphere(s) => (DVec3::from_array(s.center), DVec3::from_array(s.center)),
        _ => panic!(),
    };
    vec![
        e(4).0,
        e(7).0,
        e(4).1,
        e(7).1,
        e(5).1,
        e(8).1,
        e(10).0,
        e(13).0,
        e(10).1,
        e(13).1,
        e(11).1,
        e(14).1,
        e(3).0,
    ]
}

const FRAMES: usize = 48;
const DT: f64 = 1.0 / 30.0;
const START: f64 = 0.1;

/// Largest distance, over the frames, between the replayed joints and the
/// recorded person's (carried along at `travel`).
fn replay_error(shape: &HumanSpec, truth: &Human, travel: DVec3) -> f64 {
    let replay = shape.compile().unwrap();
    let mut worst: f64 = 0.0;
    for k in 0..FRAMES {
        let t = DT * k as f64;
        let offset = travel * t;
        let want = joints(&truth.posed_at(START + t, offset, DVec3::ZERO));
        let got = joints(&replay.posed_at(t, DVec3::ZERO, DVec3::ZERO));
        for (a, b) in got.iter().zip(&want) {
            worst = worst.max((*a - *b).length());
        }
    }
    worst
}

fn exact(height: Option<f64>) -> TrackOptions {
    TrackOptions {
        height,
        smoothing: 0.0,
        ..TrackOptions::default()
    }
}

#[test]
fn a_bvh_recording_replays_within_a_millimetre() {
    let truth = mover();
    let travel = DVec3::new(0.4, -0.3, 0.0);
    let text = synthesize_bvh(&truth, FRAMES, DT, START, travel);
    assert!(
        text.starts_with("HIERARCHY\nROOT Hips\n"),
        "{}",
        &text[..40]
    );
    for height in [Some(1.82), None] {
        let out = import(&text, &exact(height)).unwrap();
        assert_eq!(out.report.layout, "bvh");
        assert_eq!(out.report.frames, FRAMES);
        assert!((out.report.duration - DT * (FRAMES - 1) as f64).abs() < 1e-12);
        assert!(
            (out.report.height - 1.82).abs() < 1e-5,
            "{}",
            out.report.height
        );
        assert_eq!(out.report.clamped, 0);
        let err = replay_error(&out.shape, &truth, travel);
        eprintln!("bvh (height {height:?}): worst joint {err:.2e} m");
        assert!(err < 1e-3, "{err}");
    }
    // The defaults for BVH, spelled out.
    let out = import(
        &text,
        &TrackOptions {
            format: Some("bvh".into()),
            scale: Some(0.01),
            up: Some("y".into()),
            ..exact(Some(1.82))
        },
    )
    .unwrap();
    assert!(replay_error(&out.shape, &truth, travel) < 1e-3);
    // Read with the wrong up axis, the fit sees a person lying down: the
    // replay is far from the recording.
    let out = import(
        &text,
        &TrackOptions {
            up: Some("z".into()),
            ..exact(Some(1.82))
        },
    )
    .unwrap();
    assert!(replay_error(&out.shape, &truth, travel) > 0.1);
}

#[test]
fn the_shipped_sample_is_the_synthesised_walk() {
    let text = include_str!("../../web/tracks/walk-by.bvh");
    let out = import(text, &TrackOptions::default()).unwrap();
    assert_eq!(out.report.layout, "bvh");
    assert_eq!(out.report.frames, 90);
    // The jitter filter shortens the swinging limbs a little: the height
    // estimated from them is within a centimetre, and exact unfiltered.
    assert!(
        (out.report.height - 1.75).abs() < 0.01,
        "{}",
        out.report.height
    );
    let raw = import(text, &exact(None)).unwrap();
    assert!(
        (raw.report.height - 1.75).abs() < 1e-5,
        "{}",
        raw.report.height
    );
    let truth = walker();
    let exact_out = import(text, &exact(Some(1.75))).unwrap();
    let replay = exact_out.shape.compile().unwrap();
    let mut worst: f64 = 0.0;
    for k in 0..90 {
        let t = k as f64 / 30.0;
        let want = joints(&truth.posed_at(t, WALK * t, DVec3::ZERO));
        let got = joints(&replay.posed_at(t, DVec3::ZERO, DVec3::ZERO));
        for (a, b) in got.iter().zip(&want) {
            worst = worst.max((*a - *b).length());
        }
    }
    assert!(worst < 1e-3, "{worst}");
}

/// The sample's walker: past the arm's base at 1.2 m/s, 0.75 m away.
const WALK: DVec3 = DVec3::new(0.0, -1.2, 0.0);

fn walker() -> Human {
    let spec: ShapeSpec = serde_json::from_value(serde_json::json!({
        "type": "human", "position": [0.75, 1.5, 0.0], "heading": -std::f64::consts::FRAC_PI_2,
        "height": 1.75, "reach": 0.0,
        "animation": { "clip": "walk", "speed": 1.2 }
    }))
    .unwrap();
    let ShapeSpec::Human(h) = spec else { panic!() };
    h.compile().unwrap()
}

/// Writes the shipped sample (`SA_WRITE_SAMPLE=1 cargo test --test
/// human_bvh write_sample -- --ignored`).
#[test]
#[ignore = "writes web/tracks/walk-by.bvh"]
fn write_sample() {
    if std::env::var_os("SA_WRITE_SAMPLE").is_none() {
        return;
    }
    let text = synthesize_bvh(&walker(), 90, 1.0 / 30.0, 0.0, WALK);
    std::fs::write(
        concat!(env!("CARGO_MANIFEST_DIR"), "/../web/tracks/walk-by.bvh"),
        text,
    )
    .unwrap();
}

fn refuse(text: &str, field: &str) -> String {
    let e = import(text, &TrackOptions::default()).unwrap_err();
    assert_eq!(e.field, field, "{e}");
    e.to_string()
}

#[test]
fn malformed_bvh_files_are_refused_naming_the_field() {
    let good = synthesize_bvh(&mover(), 5, 0.1, 0.0, DVec3::ZERO);
    import(&good, &TrackOptions::default()).unwrap();
    let motion = good.find("MOTION").unwrap();
    let last = good.trim_end().rfind('\n').unwrap();
    let lines = good.lines().count();
    // Truncated: inside the hierarchy, and in the frames.
    refuse(&good[..motion / 2], "MOTION");
    let e = refuse(&good[..last], "Frames");
    assert!(e.contains("declares 5 frames, the file has 4"), "{e}");
    // A frame cut short, or with one value too many.
    let e = refuse(&good[..good.len() - 12], &format!("line {lines}"));
    assert!(e.contains("expected 57 values"), "{e}");
    let long = good.replacen("\nFrame Time: 0.1\n", "\nFrame Time: 0.1\n0 ", 1);
    refuse(&long, &format!("line {}", lines - 4));
    // NaN and ∞ among the values, named with their channel.
    let first = good[motion..].find("Frame Time").unwrap() + motion;
    let row = first + good[first..].find('\n').unwrap() + 1;
    let mut nan = good.clone();
    let cut = row + nan[row..].find(' ').unwrap();
    nan.replace_range(row..cut, "nan");
    let e = refuse(&nan, &format!("line {}", lines - 4));
    assert!(e.contains("Hips Xposition") && e.contains("finite"), "{e}");
    refuse(
        &nan.replacen("nan", "inf", 1),
        &format!("line {}", lines - 4),
    );
    // Frame time zero, negative, not a number; frame counts.
    refuse(
        &good.replace("Frame Time: 0.1", "Frame Time: 0"),
        "Frame Time",
    );
    refuse(
        &good.replace("Frame Time: 0.1", "Frame Time: -0.1"),
        "Frame Time",
    );
    refuse(
        &good.replace("Frame Time: 0.1", "Frame Time: NaN"),
        "Frame Time",
    );
    refuse(&good.replace("Frames: 5", "Frames: 0"), "Frames");
    refuse(&good.replace("Frames: 5", "Frames: -5"), "Frames");
    // A billion frames declared: refused before anything is allocated.
    let e = refuse(&good.replace("Frames: 5", "Frames: 1000000000"), "Frames");
    assert!(e.contains("at most 100000"), "{e}");
    // An unknown root (no hips anywhere), a second root, none at all.
    let e = refuse(&good.replace("ROOT Hips", "ROOT Banana"), "ROOT");
    assert!(e.contains("Banana"), "{e}");
    refuse(&good.replace("MOTION", "ROOT Hips2\n{\n}\nMOTION"), "ROOT");
    refuse("HIERARCHY\nMOTION\nFrames: 1\nFrame Time: 0.1\n0\n", "ROOT");
    let as_bvh = TrackOptions {
        format: Some("bvh".into()),
        ..TrackOptions::default()
    };
    let e = import("MOTION\nFrames: 1\n", &as_bvh).unwrap_err();
    assert_eq!(e.field, "HIERARCHY", "{e}");
    // A joint the fit needs, missing.
    let e = refuse(&good.replace("LeftForeArm", "LeftBlah"), "HIERARCHY");
    assert!(e.contains("left elbow") && e.contains("LeftForeArm"), "{e}");
    // Channel declarations: a count that does not match its names, an
    // unknown channel, too many.
    let bad = good.replacen(
        "CHANNELS 3 Zrotation Xrotation Yrotation",
        "CHANNELS 3 Zrotation Xrotation",
        1,
    );
    let e = refuse(&bad, "LeftUpLeg.CHANNELS");
    assert!(e.contains("\"JOINT\""), "{e}");
    refuse(
        &good.replacen(
            "Zrotation Xrotation Yrotation",
            "Zrotation Wrotation Yrotation",
            1,
        ),
        "Hips.CHANNELS",
    );
    refuse(
        &good.replacen("CHANNELS 3", "CHANNELS 7", 1),
        "LeftUpLeg.CHANNELS",
    );
    // A channel more than the values on each line.
    let e = refuse(
        &good.replacen(
            "CHANNELS 3 Zrotation Xrotation Yrotation",
            "CHANNELS 4 Zrotation Xrotation Yrotation Xposition",
            1,
        ),
        &format!("line {}", lines - 4),
    );
    assert!(e.contains("expected 58 values"), "{e}");
    // Offsets: not a number, or missing a coordinate.
    refuse(
        &good.replacen("OFFSET 0.00000 0.00000 -9.10000", "OFFSET 0 x 1", 1),
        "LeftUpLeg.OFFSET",
    );
    // Braces.
    refuse(&good.replacen("}\n", "", 1), "HIERARCHY");
    refuse(
        &good.replacen("MOTION", "}\nMOTION", 1),
        &format!("line {}", good[..motion].lines().count() + 1),
    );
    // Options.
    let o = |scale: Option<f64>, up: Option<&str>| TrackOptions {
        scale,
        up: up.map(str::to_owned),
        ..TrackOptions::default()
    };
    assert_eq!(
        import(&good, &o(Some(0.0), None)).unwrap_err().field,
        "scale"
    );
    assert_eq!(
        import(&good, &o(Some(f64::NAN), None)).unwrap_err().field,
        "scale"
    );
    assert_eq!(import(&good, &o(None, Some("x"))).unwrap_err().field, "up");
    // Metres read as centimetres: the limbs give an impossible height.
    assert_eq!(
        import(&good, &o(Some(1.0), None)).unwrap_err().field,
        "height"
    );
}

#[test]
fn too_many_joints_are_refused() {
    let mut text = String::from(
        "HIERARCHY\nROOT Hips\n{\nOFFSET 0 0 0\nCHANNELS 3 Xposition Yposition Zposition\n",
    );
    for k in 0..1100 {
        text.push_str(&format!("JOINT J{k}\n{{\nOFFSET 0 1 0\n}}\n"));
    }
    text.push_str("}\nMOTION\nFrames: 1\nFrame Time: 0.1\n0 0 0\n");
    let e = import(&text, &TrackOptions::default()).unwrap_err();
    assert_eq!(e.field, "HIERARCHY", "{e}");
    assert!(e.reason.contains("at most 1024"), "{e}");
}
