//! Power and force limiting (`controller.protective.mode = "pfl"`,
//! `avoidance::protect::pfl`): the Panda driven into each part of a person
//! touches it no faster than its ISO/TS 15066 body region permits, the skull
//! and the face keep separation monitoring, and on a reaching-hand scene
//! `pfl` is slower than no protective layer and faster than `ssm`. Runs
//! natively and under `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use std::f64::consts::PI;

use glam::DVec3;
use skeleton_avoidance::avoidance::protect::{BodyRegion, ProtectiveMode};
use skeleton_avoidance::distance::PrimitiveSpec;
use skeleton_avoidance::human::PART_NAMES;
use skeleton_avoidance::scenario::Scenario;
use skeleton_avoidance::world::World;

const Q0: [f64; 7] = [0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8];
const DT: f64 = 0.002;

/// One approach: the part, where along its axis (0 at its first end), the
/// way the person faces, the region expected at the witness.
struct Case {
    part: &'static str,
    along: f64,
    heading: f64,
    region: BodyRegion,
    /// The direction the arm comes from (towards the part).
    dir: DVec3,
    /// The person's rest pose: `reach` (arms hanging 0, forward 1) or a
    /// spine flexion.
    pose: serde_json::Value,
    /// Where on the part the arm aims, from the axis point (in radii).
    offset: DVec3,
}

fn case(part: &'static str, along: f64, heading: f64, region: BodyRegion) -> Case {
    Case {
        part,
        along,
        heading,
        region,
        dir: DVec3::X,
        pose: serde_json::json!({ "reach": 0.0 }),
        offset: DVec3::ZERO,
    }
}

/// The person's parts (axis ends and radius) at the origin.
fn parts_at_origin(case: &Case) -> Vec<(DVec3, DVec3, f64)> {
    let w = World::new(scene(
        DVec3::ZERO,
        case,
        [0.4, 0.0, 0.5],
        ProtectiveMode::Ssm,
    ))
    .unwrap();
    w.state().obstacles[0]
        .parts
        .iter()
        .map(|p| match p {
            PrimitiveSpec::Capsule(c) => (c.a.into(), c.b.into(), c.radius),
            PrimitiveSpec::Sphere(s) => (s.center.into(), s.center.into(), s.radius),
            other => panic!("{other:?}"),
        })
        .collect()
}

fn scene(position: DVec3, case: &Case, goal: [f64; 3], mode: ProtectiveMode) -> Scenario {
    let mut shape = serde_json::json!({
        "type": "human", "position": position.to_array(), "heading": case.heading
    });
    for (k, v) in case.pose.as_object().unwrap() {
        shape[k] = v.clone();
    }
    let mut s: Scenario = serde_json::from_value(serde_json::json!({
        "robot": { "preset": "panda" },
        "obstacles": [{ "id": "person", "shape": shape }],
        "task": { "type": "goal", "position": goal },
        "controller": { "avoidance": "repulsion", "selection": "pinned", "taskGain": 20.0,
            "pinned": [{ "link": 1, "d": 0.0, "a": 0.0 }] },
        "dt": DT, "duration": 3.0
    }))
    .unwrap();
    s.q0 = Some(Q0.to_vec());
    s.controller.protective.mode = mode;
    s
}

/// What happened when the arm was driven into the part: the region the
/// world reported at the witness, the speed at which the clearance closed
/// in the step contact began (`None`: no contact), the permissible speed
/// reported there and the smallest clearance.
struct Outcome {
    region: Option<BodyRegion>,
    speed: Option<f64>,
    permissible: Option<f64>,
    min_clearance: f64,
    /// Every step's reported region, whether `pfl` was the active bound
    /// and the permissible contact speed reported with it.
    seen: Vec<(BodyRegion, bool, Option<f64>)>,
}

fn drive_into(case: &Case, mode: ProtectiveMode) -> Outcome {
    let k = PART_NAMES.iter().position(|n| *n == case.part).unwrap();
    let (a, b, r) = parts_at_origin(case)[k];
    let centre = a.lerp(b, case.along) + case.offset * r;
    // The arm comes along `dir` from 25 cm before the part's surface.
    let start = DVec3::new(0.4737, 0.0, 0.5155);
    let surface = start + case.dir * 0.25;
    let position = surface - (centre - case.dir * r);
    let goal = surface + case.dir * (r + 0.1);
    let mut w = World::new(scene(position, case, goal.to_array(), mode)).unwrap();
    let mut out = Outcome {
        region: None,
        speed: None,
        permissible: None,
        min_clearance: f64::INFINITY,
        seen: Vec::new(),
    };
    let mut before = w.clearance_of("person").unwrap();
    for _ in 0..(2.0 / DT) as usize {
        w.step(DT);
        let st = w.state();
        if let Some(p) = &st.protection {
            out.region = Some(p.region);
            out.permissible = p.contact.map(|c| c.speed);
            out.seen
                .push((p.region, p.active == ProtectiveMode::Pfl, out.permissible));
        }
        let now = w.clearance_of("person").unwrap();
        out.min_clearance = out.min_clearance.min(now);
        if now <= 0.0 && before > 0.0 {
            out.speed = Some((before - now) / DT);
            break;
        }
        before = now;
    }
    out
}

fn cases() -> Vec<Case> {
    use BodyRegion as R;
    let front = PI;
    let arms_forward = |mut c: Case| {
        c.pose = serde_json::json!({ "reach": 1.0 });
        c
    };
    vec![
        case("torso", 0.75, front, R::Chest),
        case("torso", 0.2, front, R::Abdomen),
        case("torso", 0.6, 0.0, R::BackShoulders),
        arms_forward(case("pelvis", 0.0, PI / 2.0, R::Pelvis)),
        case("rightUpperArm", 0.5, front, R::UpperArm),
        arms_forward(case("leftForearm", 0.5, PI / 2.0, R::Forearm)),
        case("rightHand", 0.5, front, R::Hand),
        case("leftThigh", 0.5, front, R::Thigh),
        case("rightShin", 0.5, front, R::LowerLeg),
    ]
}

#[test]
fn every_region_is_touched_no_faster_than_it_permits() {
    for case in cases() {
        let o = drive_into(&case, ProtectiveMode::Pfl);
        eprintln!(
            "{:<14} {:?}: contact at {:?} m/s, permissible {:?} m/s",
            case.part, o.region, o.speed, o.permissible
        );
        assert_eq!(o.region, Some(case.region), "{}", case.part);
        let (Some(v), Some(limit)) = (o.speed, o.permissible) else {
            panic!("{}: no contact ({} m)", case.part, o.min_clearance);
        };
        assert!(v <= limit + 1e-6, "{}: {v} > {limit}", case.part);
        assert!(
            v > 0.2 * limit,
            "{}: the bound was not reached ({v})",
            case.part
        );
    }
}

#[test]
fn skull_and_face_keep_separation_monitoring() {
    for (heading, region) in [(PI, BodyRegion::Face), (0.0, BodyRegion::Skull)] {
        let mut case = case("head", 0.0, heading, region);
        if region == BodyRegion::Skull {
            case.dir = DVec3::NEG_Z;
        } else {
            case.pose = serde_json::json!({ "pose": { "spineFlexion": 1.0 } });
            case.offset = DVec3::new(0.0, 0.0, -0.5);
        }
        let o = drive_into(&case, ProtectiveMode::Pfl);
        let head: Vec<_> = o.seen.iter().filter(|s| s.0 == region).collect();
        eprintln!(
            "head {region:?}: nearest in {} of {} steps, last {:?}, min clearance {} m",
            head.len(),
            o.seen.len(),
            o.region,
            o.min_clearance
        );
        // The arm is driven at the head: the head is the nearest part
        // through the approach, and while it is, separation monitoring
        // holds the arm and no contact speed is ever permitted (the arm
        // may slide off onto another part afterwards, whose own region
        // then applies).
        assert_eq!(o.seen.first().map(|s| s.0), Some(region));
        assert!(
            head.len() * 2 >= o.seen.len(),
            "{} of {}",
            head.len(),
            o.seen.len()
        );
        assert!(head.iter().all(|s| !s.1 && s.2.is_none()));
        assert!(
            o.speed.is_none() && o.min_clearance > 0.0,
            "{}",
            o.min_clearance
        );
    }
}

/// The reaching-hand scene: a person in front of the Panda holds the
/// right hand out and steps 15 cm towards the arm in 0.3 s (0.5 m/s) while
/// the arm brings its end effector to the hand (its goal 8 cm before the
/// hand's final surface): unhindered (`None`: the same motion without the
/// person), in `ssm` and in `pfl`. Returns the time the end effector first comes within 1 cm of
/// its goal (s) and the smallest clearance (m).
fn reaching_hand(protective: Option<ProtectiveMode>) -> (f64, f64) {
    let mut case = case("rightHand", 0.5, PI, BodyRegion::Hand);
    case.pose = serde_json::json!({ "reach": 1.0 });
    let k = PART_NAMES.iter().position(|n| *n == case.part).unwrap();
    let (a, b, r) = parts_at_origin(&case)[k];
    let start = DVec3::new(0.4737, 0.0, 0.5155);
    let surface = start + DVec3::X * 0.25;
    let position = surface + DVec3::X * 0.15 - (a.lerp(b, 0.5) - DVec3::X * r);
    let goal = surface - DVec3::X * 0.08;
    let mut s = scene(position, &case, goal.to_array(), ProtectiveMode::Ssm);
    s.obstacles[0].motion = Some(
        serde_json::from_value(serde_json::json!({
            "type": "waypoints", "points": [[0.0, 0.0, 0.0], [-0.15, 0.0, 0.0]], "times": [0.0, 0.3]
        }))
        .unwrap(),
    );
    // No protection from the person: the same motion without the person
    // (switching the protective layer off would also drop the joints'
    // admissible box and its self-collision guards, and change the path).
    match protective {
        Some(mode) => s.controller.protective.mode = mode,
        None => s.obstacles.clear(),
    }
    let mut w = World::new(s).unwrap();
    let mut min = f64::INFINITY;
    for k in 1..=(3.0 / DT) as usize {
        w.step(DT);
        min = min.min(w.clearance_of("person").unwrap_or(f64::INFINITY));
        if (w.frames().end_effector().translation - goal).length() < 0.01 {
            return (k as f64 * DT, min);
        }
    }
    (f64::INFINITY, min)
}

#[test]
fn on_a_reaching_hand_pfl_is_slower_than_no_protection_and_faster_than_ssm() {
    let none = reaching_hand(None);
    let pfl = reaching_hand(Some(ProtectiveMode::Pfl));
    let ssm = reaching_hand(Some(ProtectiveMode::Ssm));
    eprintln!(
        "time to the goal (s) and smallest clearance (m): none {none:?}, pfl {pfl:?}, ssm {ssm:?}"
    );
    assert!(none.0 < pfl.0 && pfl.0 < ssm.0, "{none:?} {pfl:?} {ssm:?}");
}
