//! Recorded keypoint tracks: a track in each layout (JSON and CSV) imported
//! and replayed within 1 mm of its keypoints, gaps and jitter repaired, bad
//! input refused naming the field. Runs natively and, unchanged, under
//! `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::DVec3;
use skeleton_avoidance::distance::PrimitiveSpec;
use skeleton_avoidance::human::track::{TrackOptions, import, synthesize};
use skeleton_avoidance::human::{Human, HumanSpec, Posed};
use skeleton_avoidance::parsers::track::{Layout, NEEDED, TrackFile};
use skeleton_avoidance::rng::Rng;
use skeleton_avoidance::scenario::ShapeSpec;

const LAYOUTS: [Layout; 3] = [Layout::Coco17, Layout::Body25, Layout::Kinect32];

/// A person who turns, steps, bends and waves: every joint the fit reads
/// moves.
fn mover() -> Human {
    let spec: ShapeSpec = serde_json::from_value(serde_json::json!({
        "type": "human", "position": [1.2, -0.4, 0.0], "heading": 2.6, "height": 1.68,
        "animation": { "keyframes": [
            { "t": 0.0, "pose": { "leftShoulderFlexion": 0.2, "rightElbow": 0.3 } },
            { "t": 0.8, "pose": { "rightShoulderFlexion": 1.3, "rightShoulderAbduction": 0.3,
                                  "rightShoulderRotation": 0.4, "rightElbow": 1.1,
                                  "spineFlexion": 0.3, "spineTwist": -0.2, "neckFlexion": 0.3,
                                  "leftHipFlexion": 0.4, "leftKnee": 0.7, "rightHipAbduction": 0.2 },
              "shift": [0.2, 0.1, 0.0], "turn": 0.4 },
            { "t": 1.6, "pose": { "leftShoulderAbduction": 1.2, "leftShoulderRotation": -1.0,
                                  "leftElbow": 1.6, "spineLateral": 0.2, "neckTwist": 0.5,
                                  "neckFlexion": 0.2, "rightHipFlexion": 0.5, "rightKnee": 0.9 },
              "shift": [0.1, 0.3, 0.0], "turn": -0.5 }
        ] }
    }))
    .unwrap();
    let ShapeSpec::Human(h) = spec else { panic!() };
    h.compile().unwrap()
}

fn times(n: usize, dt: f64) -> Vec<f64> {
    (0..n).map(|k| 0.25 + dt * k as f64).collect()
}

/// The joints the fit reads (head's centre for the two ear slots), as
/// posed.
fn joints(p: &Posed) -> [DVec3; 14] {
    let e = |k: usize| match &p.parts[k].shape {
        PrimitiveSpec::Capsule(c) => (DVec3::from_array(c.a), DVec3::from_array(c.b)),
        PrimitiveSpec::Sphere(s) => (DVec3::from_array(s.center), DVec3::from_array(s.center)),
        _ => panic!(),
    };
    [
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
        e(3).0,
    ]
}

/// Largest distance between the replayed joints and the track's.
fn replay_error(shape: &HumanSpec, file: &TrackFile, layout: Layout) -> f64 {
    replay_errors(shape, file, layout).0
}

/// The worst and the mean distance of the body's joints to `file`'s.
fn replay_errors(shape: &HumanSpec, file: &TrackFile, layout: Layout) -> (f64, f64) {
    let human = shape.compile().unwrap();
    let (mut sum, mut count) = (0.0, 0.0);
    let t0 = file.frames[0].t;
    let needed = layout.needed();
    let mut worst: f64 = 0.0;
    for f in &file.frames {
        let got = joints(&human.posed_at(f.t - t0, DVec3::ZERO, DVec3::ZERO));
        for (slot, &i) in needed.iter().enumerate() {
            let want = DVec3::from_array(f.keypoints[i].unwrap());
            // The head's centre is the middle of the ears (COCO, BODY-25).
            let want = if NEEDED[slot].ends_with("Ear") && layout != Layout::Kinect32 {
                let other = needed[if slot == 12 { 13 } else { 12 }];
                0.5 * (want + DVec3::from_array(f.keypoints[other].unwrap()))
            } else {
                want
            };
            let e = (got[slot] - want).length();
            worst = worst.max(e);
            sum += e;
            count += 1.0;
        }
    }
    (worst, sum / count)
}

fn exact(height: f64) -> TrackOptions {
    TrackOptions {
        height: Some(height),
        smoothing: 0.0,
        ..TrackOptions::default()
    }
}

#[test]
fn a_track_in_each_layout_replays_within_a_millimetre() {
    let human = mover();
    for layout in LAYOUTS {
        let file = synthesize(&human, layout, &times(60, 1.0 / 30.0));
        let text = serde_json::to_string(&file).unwrap();
        let out = import(&text, &exact(1.68)).unwrap();
        let err = replay_error(&out.shape, &file, layout);
        eprintln!(
            "{}: {} frames, worst joint {:.2e} m",
            layout.name(),
            out.report.frames,
            err
        );
        assert!(err < 1e-3, "{}: {err}", layout.name());
        assert_eq!(out.report.frames, 60);
        assert_eq!(out.report.filled, 0);
        assert_eq!(out.report.clamped, 0);
        // Estimating the height from the limbs gives the same body.
        let est = import(
            &text,
            &TrackOptions {
                smoothing: 0.0,
                ..TrackOptions::default()
            },
        )
        .unwrap();
        assert!(
            (est.report.height - 1.68).abs() < 1e-9,
            "{}",
            est.report.height
        );
    }
}

fn to_csv(file: &TrackFile) -> String {
    let mut out = String::from("t,x0,y0,z0,...\n");
    for f in &file.frames {
        out.push_str(&format!("{}", f.t));
        for p in &f.keypoints {
            match p {
                Some([x, y, z]) => out.push_str(&format!(",{x},{y},{z}")),
                None => out.push_str(",,,"),
            }
        }
        out.push('\n');
    }
    out
}

#[test]
fn csv_tracks_replay_too_and_gaps_are_filled() {
    let human = mover();
    let mut file = synthesize(&human, Layout::Body25, &times(50, 0.04));
    let csv = to_csv(&file);
    let options = TrackOptions {
        layout: Some("body25".into()),
        ..exact(1.68)
    };
    let out = import(&csv, &options).unwrap();
    assert!(replay_error(&out.shape, &file, Layout::Body25) < 1e-3);
    // Drop the right wrist for three frames (0.12 s) and a knee at the
    // start: interpolated and held.
    let wrist = Layout::Body25.index("rightWrist").unwrap();
    let knee = Layout::Body25.index("leftKnee").unwrap();
    let truth = file.clone();
    for k in 20..23 {
        file.frames[k].keypoints[wrist] = None;
    }
    file.frames[0].keypoints[knee] = None;
    let text = to_csv(&file).replace(",,,", ",nan,,NaN");
    let out = import(&text, &options).unwrap();
    assert_eq!(out.report.filled, 4);
    let err = replay_error(&out.shape, &truth, Layout::Body25);
    assert!(err < 0.03, "{err}");
}

#[test]
fn jitter_is_smoothed() {
    let human = mover();
    let clean = synthesize(&human, Layout::Coco17, &times(90, 1.0 / 60.0));
    let mut noisy = clean.clone();
    let mut rng = Rng::new(5);
    for f in &mut noisy.frames {
        for p in f.keypoints.iter_mut().flatten() {
            for c in p.iter_mut() {
                *c += 0.01 * rng.normal();
            }
        }
    }
    let text = serde_json::to_string(&noisy).unwrap();
    let raw = import(&text, &exact(1.68)).unwrap();
    let smooth = import(
        &text,
        &TrackOptions {
            height: Some(1.68),
            ..TrackOptions::default()
        },
    )
    .unwrap();
    let (e_raw, e_smooth) = (
        replay_errors(&raw.shape, &clean, Layout::Coco17),
        replay_errors(&smooth.shape, &clean, Layout::Coco17),
    );
    eprintln!(
        "joint error (worst, mean): raw {:.4}, {:.4} m, smoothed {:.4}, {:.4} m",
        e_raw.0, e_raw.1, e_smooth.0, e_smooth.1
    );
    assert!(e_smooth.1 < 0.7 * e_raw.1, "{e_smooth:?} vs {e_raw:?}");
    assert!(e_smooth.0 < e_raw.0, "{e_smooth:?} vs {e_raw:?}");
}

#[test]
fn bad_tracks_are_refused_naming_the_field() {
    let human = mover();
    let file = synthesize(&human, Layout::Coco17, &times(5, 0.1));
    let good = serde_json::to_value(&file).unwrap();
    let refuse = |v: serde_json::Value, options: &TrackOptions, field: &str| {
        let e = import(&v.to_string(), options).unwrap_err();
        assert_eq!(e.field, field, "{e}");
    };
    let o = TrackOptions::default();
    let mut v = good.clone();
    v["layout"] = "coco18".into();
    refuse(v, &o, "layout");
    let mut v = good.clone();
    v["frames"][3]["t"] = v["frames"][2]["t"].clone();
    refuse(v, &o, "frames[3].t");
    let mut v = good.clone();
    v["frames"][1]["keypoints"].as_array_mut().unwrap().pop();
    refuse(v, &o, "frames[1].keypoints");
    let mut v = good.clone();
    for f in v["frames"].as_array_mut().unwrap() {
        f["keypoints"][9] = serde_json::Value::Null;
    }
    refuse(v, &o, "frames");
    let mut v = good.clone();
    v["frames"] = serde_json::json!([]);
    refuse(v, &o, "frames");
    refuse(
        good.clone(),
        &TrackOptions {
            smoothing: -1.0,
            ..o.clone()
        },
        "smoothing",
    );
    refuse(
        good.clone(),
        &TrackOptions {
            height: Some(30.0),
            ..o.clone()
        },
        "height",
    );
    // Millimetres instead of metres: the limbs give an impossible height.
    let mut v = good.clone();
    for f in v["frames"].as_array_mut().unwrap() {
        for p in f["keypoints"].as_array_mut().unwrap() {
            for c in p.as_array_mut().unwrap() {
                *c = (c.as_f64().unwrap() * 1000.0).into();
            }
        }
    }
    refuse(v, &o, "height");
    // CSV: the layout is required, lines must have every cell, and more
    // frames than the limit are refused before they are read.
    let csv = to_csv(&file);
    assert_eq!(import(&csv, &o).unwrap_err().field, "layout");
    let csv_o = TrackOptions {
        layout: Some("coco17".into()),
        ..o.clone()
    };
    let short = csv.replacen("\n0.35,", "\n0.35,1,", 1);
    assert_eq!(import(&short, &csv_o).unwrap_err().field, "line 3");
    // (the count is checked before any cell is read)
    let huge = "1\n".repeat(100_002);
    let e = import(&huge, &csv_o).unwrap_err();
    assert_eq!(e.field, "frames", "{e}");
}

#[test]
fn out_of_range_and_non_finite_keypoints_are_repaired() {
    let human = mover();
    let mut file = synthesize(&human, Layout::Kinect32, &times(10, 0.1));
    // Upside down shoulders in one frame: the trunk's angles are clamped.
    let (ls, rs) = (5, 12);
    let pelvis = file.frames[4].keypoints[0].unwrap();
    for i in [ls, rs] {
        let p = file.frames[4].keypoints[i].as_mut().unwrap();
        p[2] = pelvis[2] - 0.4;
    }
    let mut text = serde_json::to_string(&file).unwrap();
    // 1e300 is read as missing (and filled).
    text = text.replacen(
        &format!("{}", file.frames[6].keypoints[7].unwrap()[0]),
        "1e300",
        1,
    );
    let out = import(&text, &exact(1.68)).unwrap();
    assert!(out.report.clamped > 0, "{:?}", out.report);
    assert_eq!(out.report.filled, 1);
    out.shape.compile().unwrap();
}

#[test]
fn the_shipped_sample_is_the_synthesised_reach() {
    let text = include_str!("../../web/tracks/reach-coco17.json");
    let out = import(text, &TrackOptions::default()).unwrap();
    assert_eq!(out.report.layout, "coco17");
    assert!(out.report.frames >= 60);
    assert!(
        (out.report.height - 1.75).abs() < 1e-6,
        "{}",
        out.report.height
    );
    let file: TrackFile = serde_json::from_str(text).unwrap();
    let exact_out = import(text, &exact(1.75)).unwrap();
    assert!(replay_error(&exact_out.shape, &file, Layout::Coco17) < 1e-3);
}

/// Writes the shipped sample (`SA_WRITE_SAMPLE=1 cargo test --test
/// human_track write_sample -- --ignored`).
#[test]
#[ignore = "writes web/tracks/reach-coco17.json"]
fn write_sample() {
    if std::env::var_os("SA_WRITE_SAMPLE").is_none() {
        return;
    }
    let spec: ShapeSpec = serde_json::from_value(serde_json::json!({
        "type": "human", "position": [1.1, -0.1, 0.0], "heading": std::f64::consts::PI, "height": 1.75,
        "reach": 0.0,
        "animation": { "clip": "reach", "target": [0.45, 0.05, 0.75], "speed": 1.5, "start": 0.3 }
    }))
    .unwrap();
    let ShapeSpec::Human(h) = spec else { panic!() };
    let file = synthesize(
        &h.compile().unwrap(),
        Layout::Coco17,
        &times(75, 1.0 / 30.0),
    );
    let mut text = serde_json::to_string(&file).unwrap();
    text.push('\n');
    std::fs::write(
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../web/tracks/reach-coco17.json"
        ),
        text,
    )
    .unwrap();
}
