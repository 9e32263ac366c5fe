//! Synthetic recordings: the keypoints of a posed body in any layout, or
//! its joint angles as a BVH file (the shipped samples, and the tests'
//! ground truth).

use glam::DVec3;

use crate::distance::PrimitiveSpec;
use crate::human::{Human, Pose, Posed, joint, proportion};
use crate::parsers::track::{Layout, NEEDED, TrackFile, TrackFrame};

fn ends(p: &Posed, k: usize) -> (DVec3, DVec3) {
    match p.parts.get(k).map(|x| &x.shape) {
        Some(PrimitiveSpec::Capsule(c)) => (DVec3::from_array(c.a), DVec3::from_array(c.b)),
        Some(PrimitiveSpec::Sphere(s)) => {
            let c = DVec3::from_array(s.center);
            (c, c)
        }
        _ => (DVec3::ZERO, DVec3::ZERO),
    }
}

/// The keypoints of `human` at each of `times` (s) in `layout`: a track
/// that [`super::import`] maps back onto the same body (given its height,
/// without smoothing) to rounding.
#[must_use]
pub fn synthesize(human: &Human, layout: Layout, times: &[f64]) -> TrackFile {
    let h = human.spec().height;
    let frames = times
        .iter()
        .map(|&t| {
            let p = human.posed_at(t, DVec3::ZERO, DVec3::ZERO);
            // Part indices: see PART_NAMES.
            let (ls, le) = ends(&p, 4);
            let (rs, re) = ends(&p, 7);
            let (_, lw) = ends(&p, 5);
            let (_, rw) = ends(&p, 8);
            let (lh, lk) = ends(&p, 10);
            let (rh, rk) = ends(&p, 13);
            let (_, la) = ends(&p, 11);
            let (_, ra) = ends(&p, 14);
            let (head, _) = ends(&p, 3);
            let left = (ls - rs).normalize_or(DVec3::Y);
            let a = Anchors {
                j: [ls, rs, le, re, lw, rw, lh, rh, lk, rk, la, ra, head, head],
                hand: [ends(&p, 6), ends(&p, 9)],
                foot: [ends(&p, 12), ends(&p, 15)],
                left,
                forward: left.cross(DVec3::Z).normalize_or(DVec3::X),
                height: h,
            };
            TrackFrame {
                t,
                keypoints: layout
                    .names()
                    .iter()
                    .map(|n| Some(a.at(n).to_array()))
                    .collect(),
            }
        })
        .collect();
    TrackFile {
        layout: Some(layout.name().to_owned()),
        frames,
    }
}

/// A joint of the written BVH: name, parent, offset (m, the body's axes:
/// x forward, y left, z up), the order of its rotation channels and its
/// end site.
struct Node {
    name: &'static str,
    parent: Option<usize>,
    offset: DVec3,
    order: &'static str,
    end: Option<DVec3>,
}

/// The body's axes (z up) as BVH axes (y up), in centimetres.
fn to_bvh(v: DVec3) -> DVec3 {
    // (+ 0 turns −0 into 0 for the file)
    DVec3::new(v.x, v.z, -v.y) * 100.0 + DVec3::ZERO
}

/// The hierarchy of a body of height `h`: CMU's joint names, the body's
/// own joints (so that zero angles are its rest pose, arms hanging).
fn nodes(h: f64) -> Vec<Node> {
    use crate::human::body::build::{HEEL, HIP_HALF, LUMBAR, NECK_LENGTH};
    use crate::human::proportion::*;
    let v = |x: f64, y: f64, z: f64| DVec3::new(x, y, z) * h;
    let node = |name, parent, offset, order, end| Node {
        name,
        parent: Some(parent),
        offset,
        order,
        end,
    };
    let shoulder_z = SHOULDER_HEIGHT - HIP_HEIGHT - LUMBAR;
    let head_centre = 0.5 * (HEAD_TOP + CHIN_HEIGHT) - SHOULDER_HEIGHT;
    let quarter = 0.25 * SHOULDER_WIDTH;
    let toe = Some(v((1.0 - HEEL) * FOOT_LENGTH, 0.0, -ANKLE_HEIGHT));
    let mut out = vec![Node {
        name: "Hips",
        parent: None,
        offset: DVec3::ZERO,
        order: "ZXY",
        end: None,
    }];
    for (side, names) in [
        (1.0, ["LeftUpLeg", "LeftLeg", "LeftFoot"]),
        (-1.0, ["RightUpLeg", "RightLeg", "RightFoot"]),
    ] {
        let k = out.len();
        out.push(node(names[0], 0, v(0.0, side * HIP_HALF, 0.0), "ZXY", None));
        out.push(node(names[1], k, v(0.0, 0.0, -THIGH), "ZXY", None));
        out.push(node(names[2], k + 1, v(0.0, 0.0, -SHANK), "ZXY", toe));
    }
    let spine = out.len();
    out.push(node("Spine", 0, v(0.0, 0.0, LUMBAR), "YXZ", None));
    out.push(node("Neck", spine, v(0.0, 0.0, shoulder_z), "YXZ", None));
    let top = Some(v(0.0, 0.0, 2.0 * (head_centre - NECK_LENGTH)));
    out.push(node(
        "Head",
        spine + 1,
        v(0.0, 0.0, NECK_LENGTH),
        "ZXY",
        top,
    ));
    for (side, names) in [
        (1.0, ["LeftShoulder", "LeftArm", "LeftForeArm", "LeftHand"]),
        (
            -1.0,
            ["RightShoulder", "RightArm", "RightForeArm", "RightHand"],
        ),
    ] {
        let k = out.len();
        let tip = Some(v(0.0, 0.0, -HAND));
        out.push(node(
            names[0],
            spine,
            v(0.0, side * quarter, shoulder_z),
            "ZXY",
            None,
        ));
        out.push(node(names[1], k, v(0.0, side * quarter, 0.0), "ZXY", None));
        out.push(node(names[2], k + 1, v(0.0, 0.0, -UPPER_ARM), "ZXY", None));
        out.push(node(names[3], k + 2, v(0.0, 0.0, -FOREARM), "ZXY", tip));
    }
    out
}

/// The rotation channels (degrees, in the node's order) that pose node
/// `name` like `pose` (the body's turns written as BVH rotations: about
/// the body's −y is about BVH +z, about its z is about BVH y).
fn angles(name: &str, pose: &Pose, heading: f64) -> [f64; 3] {
    let q = |k: usize| pose.angles[k];
    let (la, ra, ll, rl) = (
        joint::LEFT_ARM,
        joint::RIGHT_ARM,
        joint::LEFT_LEG,
        joint::RIGHT_LEG,
    );
    let rad = match name {
        "Hips" => [0.0, 0.0, heading],
        "LeftUpLeg" => [q(ll), q(ll + 1), 0.0],
        "RightUpLeg" => [q(rl), -q(rl + 1), 0.0],
        "LeftLeg" => [-q(ll + 2), 0.0, 0.0],
        "RightLeg" => [-q(rl + 2), 0.0, 0.0],
        "Spine" => [
            q(joint::SPINE_TWIST),
            -q(joint::SPINE_LATERAL),
            -q(joint::SPINE_FLEXION),
        ],
        "Neck" => [q(joint::NECK_TWIST), 0.0, -q(joint::NECK_FLEXION)],
        "LeftArm" => [q(la), q(la + 1), -q(la + 2)],
        "RightArm" => [q(ra), -q(ra + 1), q(ra + 2)],
        "LeftForeArm" => [q(la + 3), 0.0, 0.0],
        "RightForeArm" => [q(ra + 3), 0.0, 0.0],
        _ => [0.0; 3],
    };
    // (+ 0 turns −0 into 0 for the file)
    rad.map(|a| a.to_degrees() + 0.0)
}

/// A BVH recording (centimetres, y up, CMU joint names) of `human` over
/// `frames` frames `frame_time` apart from time `start` (s), its root
/// carried along at `travel` (m/s, world frame; e.g. a walk's speed): a
/// file that [`super::import`] maps back onto the same body (given its
/// height, without smoothing) to rounding.
#[must_use]
pub fn synthesize_bvh(
    human: &Human,
    frames: usize,
    frame_time: f64,
    start: f64,
    travel: DVec3,
) -> String {
    use std::fmt::Write;
    let h = human.spec().height;
    let nodes = nodes(h);
    let mut out = String::from("HIERARCHY\n");
    let mut open: Vec<usize> = Vec::new();
    let indent = |n: usize| "  ".repeat(n);
    for (i, n) in nodes.iter().enumerate() {
        while open.last().copied() != n.parent {
            open.pop();
            let _ = writeln!(out, "{}}}", indent(open.len()));
        }
        let pad = indent(open.len());
        let kind = if n.parent.is_some() { "JOINT" } else { "ROOT" };
        let o = to_bvh(n.offset);
        let order: Vec<String> = n.order.chars().map(|c| format!("{c}rotation")).collect();
        let position = if n.parent.is_none() {
            "Xposition Yposition Zposition "
        } else {
            ""
        };
        let count = if n.parent.is_none() { 6 } else { 3 };
        let _ = write!(
            out,
            "{pad}{kind} {}\n{pad}{{\n{pad}  OFFSET {:.5} {:.5} {:.5}\n{pad}  CHANNELS {count} {position}{}\n",
            n.name,
            o.x,
            o.y,
            o.z,
            order.join(" ")
        );
        if let Some(e) = n.end.map(to_bvh) {
            let _ = write!(
                out,
                "{pad}  End Site\n{pad}  {{\n{pad}    OFFSET {:.5} {:.5} {:.5}\n{pad}  }}\n",
                e.x, e.y, e.z
            );
        }
        open.push(i);
    }
    while open.pop().is_some() {
        let _ = writeln!(out, "{}}}", indent(open.len()));
    }
    let _ = write!(out, "MOTION\nFrames: {frames}\nFrame Time: {frame_time}\n");
    for k in 0..frames {
        let t = start + frame_time * k as f64;
        let (root, pose) = human.pose_at(t);
        let hips = root.position + travel * (t - start) + DVec3::Z * (proportion::HIP_HEIGHT * h);
        let p = to_bvh(hips);
        let mut line = format!("{:.5} {:.5} {:.5}", p.x, p.y, p.z);
        for n in &nodes {
            for a in angles(n.name, &pose, root.heading) {
                let _ = write!(line, " {a:.6}");
            }
        }
        out.push_str(&line);
        out.push('\n');
    }
    out
}

/// Where every keypoint of `layout` sits on a body given its joints
/// (`j`: the [`NEEDED`] joints with the head's centre in both ear slots),
/// its hands' and feet's ends, its left and forward directions and its
/// height: the synthetic recordings' model of the joints the fit does not
/// read (eyes, toes, clavicles, …).
struct Anchors {
    pub j: [DVec3; 14],
    pub hand: [(DVec3, DVec3); 2],
    pub foot: [(DVec3, DVec3); 2],
    pub left: DVec3,
    pub forward: DVec3,
    pub height: f64,
}

impl Anchors {
    /// The position of keypoint `name`.
    fn at(&self, name: &str) -> DVec3 {
        let j = |n: &str| self.j[NEEDED.iter().position(|x| *x == n).unwrap_or(0)];
        let head = j("leftEar");
        let (l, f, h) = (self.left, self.forward, self.height);
        let neck = 0.5 * (j("leftShoulder") + j("rightShoulder"));
        let pelvis = 0.5 * (j("leftHip") + j("rightHip"));
        match name {
            "leftEar" => head + l * (0.06 * h),
            "rightEar" => head - l * (0.06 * h),
            "head" => head,
            "nose" => head + f * (0.055 * h),
            "leftEye" => head + f * (0.045 * h) + l * (0.02 * h) + DVec3::Z * (0.015 * h),
            "rightEye" => head + f * (0.045 * h) - l * (0.02 * h) + DVec3::Z * (0.015 * h),
            "neck" => neck,
            "midHip" | "pelvis" => pelvis,
            "spineNavel" => pelvis.lerp(neck, 0.35),
            "spineChest" => pelvis.lerp(neck, 0.7),
            "leftClavicle" => neck.lerp(j("leftShoulder"), 0.5),
            "rightClavicle" => neck.lerp(j("rightShoulder"), 0.5),
            "leftHand" | "leftThumb" => self.hand[0].0.lerp(self.hand[0].1, 0.5),
            "rightHand" | "rightThumb" => self.hand[1].0.lerp(self.hand[1].1, 0.5),
            "leftHandTip" => self.hand[0].1,
            "rightHandTip" => self.hand[1].1,
            "leftBigToe" | "leftFoot" => self.foot[0].1,
            "rightBigToe" | "rightFoot" => self.foot[1].1,
            "leftSmallToe" => self.foot[0].1 + l * (0.02 * h),
            "rightSmallToe" => self.foot[1].1 - l * (0.02 * h),
            "leftHeel" => self.foot[0].0,
            "rightHeel" => self.foot[1].0,
            other => j(other),
        }
    }
}
