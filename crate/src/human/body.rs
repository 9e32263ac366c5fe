//! Forward kinematics of the articulated human: the pose of every segment
//! from the root pose and the joint angles, and the velocity of every
//! part's end points from their rates.

use glam::{DMat3, DVec3};

use super::pose::{JOINT_COUNT, Pose, joint};
use super::segments::Dims;
use crate::distance::{CapsuleSpec, PrimitiveSpec, SphereSpec};

/// Segment lengths and heights as fractions of the body height `H`, after
/// Drillis & Contini (1966) as tabulated by Winter, *Biomechanics and Motor
/// Control of Human Movement*, fig. 4.1.
pub mod proportion {
    /// Hip joint (greater trochanter) above the floor.
    pub const HIP_HEIGHT: f64 = 0.530;
    /// Shoulder joint above the floor.
    pub const SHOULDER_HEIGHT: f64 = 0.818;
    /// Top of the head above the floor (`H` itself).
    pub const HEAD_TOP: f64 = 1.0;
    /// Chin above the floor.
    pub const CHIN_HEIGHT: f64 = 0.870;
    /// Shoulder width (between the shoulder joints).
    pub const SHOULDER_WIDTH: f64 = 0.259;
    /// Upper arm (shoulder to elbow).
    pub const UPPER_ARM: f64 = 0.186;
    /// Forearm (elbow to wrist).
    pub const FOREARM: f64 = 0.146;
    /// Hand (wrist to fingertip).
    pub const HAND: f64 = 0.108;
    /// Thigh (hip to knee).
    pub const THIGH: f64 = 0.245;
    /// Shank (knee to ankle).
    pub const SHANK: f64 = 0.246;
    /// Ankle above the floor.
    pub const ANKLE_HEIGHT: f64 = 0.039;
    /// Foot length (heel to toe).
    pub const FOOT_LENGTH: f64 = 0.152;
}

/// Where the body's joints sit and how thick its parts are, as fractions of
/// the height. These are this crate's own estimates (not from the tables):
/// volumes that enclose a clothed adult of average build.
pub(crate) mod build {
    /// Half the distance between the hip joint centres.
    pub const HIP_HALF: f64 = 0.05;
    /// The lumbar (spine) joint above the hip joints.
    pub const LUMBAR: f64 = 0.05;
    pub const PELVIS_RADIUS: f64 = 0.07;
    pub const PELVIS_HALF: f64 = 0.06;
    pub const TORSO_FROM: f64 = 0.04;
    pub const TORSO_TO: f64 = 0.17;
    pub const TORSO_RADIUS: f64 = 0.09;
    pub const NECK_LENGTH: f64 = 0.05;
    pub const NECK_RADIUS: f64 = 0.03;
    pub const HEAD_RADIUS: f64 = 0.065;
    pub const UPPER_ARM_RADIUS: f64 = 0.032;
    pub const FOREARM_RADIUS: f64 = 0.026;
    pub const HAND_RADIUS: f64 = 0.03;
    pub const THIGH_RADIUS: f64 = 0.06;
    pub const SHIN_RADIUS: f64 = 0.04;
    pub const FOOT_RADIUS: f64 = 0.025;
    /// Heel behind the ankle, as a fraction of the foot length.
    pub const HEEL: f64 = 0.25;
}

/// Names of the parts, in the order [`Posed::parts`] lists them.
pub const PART_NAMES: [&str; 16] = [
    "pelvis",
    "torso",
    "neck",
    "head",
    "leftUpperArm",
    "leftForearm",
    "leftHand",
    "rightUpperArm",
    "rightForearm",
    "rightHand",
    "leftThigh",
    "leftShin",
    "leftFoot",
    "rightThigh",
    "rightShin",
    "rightFoot",
];

/// Where the root is and how it moves: the floor point between the feet
/// and the heading about z (from +x), with their rates.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Root {
    /// Floor point between the feet (m).
    pub position: DVec3,
    /// Heading about z from +x (rad).
    pub heading: f64,
    /// Velocity of `position` (m/s).
    pub velocity: DVec3,
    /// Rate of `heading` (rad/s).
    pub heading_rate: f64,
}

/// One part of a posed body: its volume and the velocities of its end
/// points (a sphere's both equal its centre's).
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    /// Name ([`PART_NAMES`]).
    pub name: &'static str,
    /// A capsule (limbs, trunk) or a sphere (head).
    pub shape: PrimitiveSpec,
    /// Velocity of the capsule's `a` and `b` (the sphere's centre twice),
    /// m/s; any point of the axis moves with their interpolation.
    pub velocity: [DVec3; 2],
}

impl Part {
    /// Velocity (m/s) of the part's material point nearest `p` on its axis
    /// (the rigid motion of a segment is affine along it).
    #[must_use]
    pub fn velocity_at(&self, p: DVec3) -> DVec3 {
        match &self.shape {
            PrimitiveSpec::Capsule(c) => {
                let (a, b) = (DVec3::from_array(c.a), DVec3::from_array(c.b));
                let ab = b - a;
                let l2 = ab.length_squared();
                let u = if l2 > 0.0 {
                    ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                self.velocity[0] + (self.velocity[1] - self.velocity[0]) * u
            }
            _ => self.velocity[0],
        }
    }
}

/// A body posed: its parts in the order of [`PART_NAMES`].
#[derive(Clone, Debug, PartialEq)]
pub struct Posed {
    /// The parts.
    pub parts: Vec<Part>,
}

/// A frame of the body with its motion: orientation, origin, angular
/// velocity and origin velocity (world frame).
#[derive(Clone, Copy, Debug)]
struct Frame {
    r: DMat3,
    o: DVec3,
    w: DVec3,
    v: DVec3,
}

impl Frame {
    /// The frame moved by `offset` (in its own axes).
    fn at(self, offset: DVec3) -> Self {
        let d = self.r * offset;
        Self {
            o: self.o + d,
            v: self.v + self.w.cross(d),
            ..self
        }
    }

    /// The frame turned by `angle` about its own `axis` (unit) at `rate`.
    fn turn(self, axis: DVec3, angle: f64, rate: f64) -> Self {
        Self {
            r: self.r * rotation(axis, angle),
            w: self.w + self.r * axis * rate,
            ..self
        }
    }

    /// A point given in the frame's axes, with its velocity.
    fn point(&self, p: DVec3) -> (DVec3, DVec3) {
        let d = self.r * p;
        (self.o + d, self.v + self.w.cross(d))
    }
}

/// The rotation by `angle` (rad) about the unit `axis` (Rodrigues), with
/// [`crate::math`]'s sine and cosine (the same bits natively and in wasm).
#[must_use]
pub fn rotation(axis: DVec3, angle: f64) -> DMat3 {
    let (s, c) = crate::math::sin_cos(angle);
    let k = DMat3::from_cols(
        DVec3::new(0.0, axis.z, -axis.y),
        DVec3::new(-axis.z, 0.0, axis.x),
        DVec3::new(axis.y, -axis.x, 0.0),
    );
    DMat3::IDENTITY + k * s + k * k * (1.0 - c)
}

fn capsule(name: &'static str, f: &Frame, a: DVec3, b: DVec3, radius: f64) -> Part {
    let (pa, va) = f.point(a);
    let (pb, vb) = f.point(b);
    Part {
        name,
        shape: PrimitiveSpec::Capsule(CapsuleSpec {
            a: pa.to_array(),
            b: pb.to_array(),
            radius,
        }),
        velocity: [va, vb],
    }
}

/// The body of height `height` (m) at `root`, posed by `pose` whose angles
/// change at `rates` (rad/s).
#[must_use]
pub fn pose_body(height: f64, root: &Root, pose: &Pose, rates: &[f64; JOINT_COUNT]) -> Posed {
    pose_sized(&Dims::new(height, None), root, pose, rates)
}

/// [`pose_body`] for a body of dimensions `dims` (its own segment lengths).
#[must_use]
pub fn pose_sized(dims: &Dims, root: &Root, pose: &Pose, rates: &[f64; JOINT_COUNT]) -> Posed {
    let h = dims.h;
    let q = &pose.angles;
    let base = Frame {
        r: rotation(DVec3::Z, root.heading),
        o: root.position,
        w: DVec3::Z * root.heading_rate,
        v: root.velocity,
    };
    let mut parts = Vec::with_capacity(PART_NAMES.len());
    // Pelvis: fixed to the root at hip height.
    let hips = base.at(DVec3::Z * (proportion::HIP_HEIGHT * h));
    let trunk = trunk_parts(&mut parts, &hips, q, rates, h);
    head_parts(&mut parts, &trunk, q, rates, dims);
    limb_parts(&mut parts, (&hips, &trunk), q, rates, dims);
    Posed { parts }
}

/// The pelvis and the torso; returns the trunk's frame (at the lumbar
/// joint, after its twist, lateral bend and flexion).
fn trunk_parts(
    parts: &mut Vec<Part>,
    hips: &Frame,
    q: &[f64; JOINT_COUNT],
    rates: &[f64; JOINT_COUNT],
    h: f64,
) -> Frame {
    use build::*;
    let (x, y, z) = (DVec3::X, DVec3::Y, DVec3::Z);
    let (pl, pr) = (y * (PELVIS_HALF * h), -y * (PELVIS_HALF * h));
    let lift = z * (0.5 * LUMBAR * h);
    parts.push(capsule(
        "pelvis",
        hips,
        pl + lift,
        pr + lift,
        PELVIS_RADIUS * h,
    ));
    // Trunk: the lumbar joint turns (twist about z, lateral bend about x,
    // flexion about y), the neck on top of it.
    let s = joint::SPINE_FLEXION;
    let trunk = hips
        .at(z * (LUMBAR * h))
        .turn(z, q[s + 2], rates[s + 2])
        .turn(-x, q[s + 1], rates[s + 1])
        .turn(y, q[s], rates[s]);
    let t0 = z * (TORSO_FROM * h);
    let t1 = z * (TORSO_TO * h);
    parts.push(capsule("torso", &trunk, t0, t1, TORSO_RADIUS * h));
    trunk
}

/// The neck (twist and flexion on the trunk) and the head.
fn head_parts(
    parts: &mut Vec<Part>,
    trunk: &Frame,
    q: &[f64; JOINT_COUNT],
    rates: &[f64; JOINT_COUNT],
    dims: &Dims,
) {
    use build::*;
    use proportion::*;
    let h = dims.h;
    let (y, z) = (DVec3::Y, DVec3::Z);
    let n = joint::NECK_FLEXION;
    let neck = trunk
        .at(z * dims.shoulder_above_lumbar())
        .turn(z, q[n + 1], rates[n + 1])
        .turn(y, q[n], rates[n]);
    let neck_top = z * (NECK_LENGTH * h);
    parts.push(capsule(
        "neck",
        &neck,
        DVec3::ZERO,
        neck_top,
        NECK_RADIUS * h,
    ));
    let head_centre = 0.5 * (HEAD_TOP + CHIN_HEIGHT) - SHOULDER_HEIGHT;
    let (c, vc) = neck.point(z * (head_centre * h));
    parts.push(Part {
        name: "head",
        shape: PrimitiveSpec::Sphere(SphereSpec {
            center: c.to_array(),
            radius: HEAD_RADIUS * h,
        }),
        velocity: [vc, vc],
    });
}

/// Arms on the trunk and legs on the hips: +1 on the left (+y), −1 on the
/// right.
fn limb_parts(
    parts: &mut Vec<Part>,
    (hips, trunk): (&Frame, &Frame),
    q: &[f64; JOINT_COUNT],
    rates: &[f64; JOINT_COUNT],
    dims: &Dims,
) {
    let y = DVec3::Y;
    let seg = &dims.segments;
    for (side, k, g, names) in [
        (
            1.0,
            joint::LEFT_ARM,
            joint::LEFT_GIRDLE,
            ["leftUpperArm", "leftForearm", "leftHand"],
        ),
        (
            -1.0,
            joint::RIGHT_ARM,
            joint::RIGHT_GIRDLE,
            ["rightUpperArm", "rightForearm", "rightHand"],
        ),
    ] {
        let shoulder = shoulder(trunk, side, (&q[g..g + 2], &rates[g..g + 2]), dims);
        arm(
            parts,
            shoulder,
            side,
            (&q[k..k + 4], &rates[k..k + 4]),
            dims,
            names,
        );
    }
    for (side, k, names) in [
        (1.0, joint::LEFT_LEG, ["leftThigh", "leftShin", "leftFoot"]),
        (
            -1.0,
            joint::RIGHT_LEG,
            ["rightThigh", "rightShin", "rightFoot"],
        ),
    ] {
        let hip = hips.at(y * (side * 0.5 * seg.hip_width));
        leg(
            parts,
            hip,
            side,
            (&q[k..k + 3], &rates[k..k + 3]),
            dims,
            names,
        );
    }
}

/// The shoulder joint's frame on side `side`: on the trunk at half the
/// shoulder width from the shoulders' middle, moved by the girdle's
/// elevation and protraction (`q`, at `rate`) about the sternoclavicular
/// joint at that middle; its axes stay the trunk's. A girdle at rest and
/// still places it exactly as a body without one.
fn shoulder(trunk: &Frame, side: f64, (q, rate): (&[f64], &[f64]), dims: &Dims) -> Frame {
    let half = side * 0.5 * dims.segments.shoulder_width;
    let up = dims.shoulder_above_lumbar();
    if q.iter().chain(rate).all(|&a| a == 0.0) {
        return trunk.at(DVec3::new(0.0, half, up));
    }
    let (x, y, z) = (DVec3::X, DVec3::Y, DVec3::Z);
    let clavicle = trunk
        .at(z * up)
        .turn(x * side, q[0], rate[0])
        .turn(-z * side, q[1], rate[1])
        .at(y * half);
    Frame {
        r: trunk.r,
        w: trunk.w,
        ..clavicle
    }
}

/// An arm from its shoulder frame: flexion about y (forward), abduction
/// about x (away from the body), rotation about the upper arm's axis, the
/// elbow about y.
fn arm(
    parts: &mut Vec<Part>,
    shoulder: Frame,
    side: f64,
    (q, rate): (&[f64], &[f64]),
    dims: &Dims,
    names: [&'static str; 3],
) {
    use build::*;
    use proportion::*;
    let h = dims.h;
    let (x, y, z) = (DVec3::X, DVec3::Y, DVec3::Z);
    let upper = shoulder
        .turn(-y, q[0], rate[0])
        .turn(x * side, q[1], rate[1])
        .turn(-z * side, q[2], rate[2]);
    let elbow_at = -z * dims.segments.upper_arm;
    parts.push(capsule(
        names[0],
        &upper,
        DVec3::ZERO,
        elbow_at,
        UPPER_ARM_RADIUS * h,
    ));
    let fore = upper.at(elbow_at).turn(-y, q[3], rate[3]);
    let wrist = -z * dims.segments.forearm;
    parts.push(capsule(
        names[1],
        &fore,
        DVec3::ZERO,
        wrist,
        FOREARM_RADIUS * h,
    ));
    let r = HAND_RADIUS * h;
    let tip = wrist - z * (HAND * h - r);
    parts.push(capsule(names[2], &fore, wrist, tip, r));
}

/// A leg from its hip frame: flexion about y (forward), abduction about x
/// (away from the body), the knee about y (backwards).
fn leg(
    parts: &mut Vec<Part>,
    hip: Frame,
    side: f64,
    (q, rate): (&[f64], &[f64]),
    dims: &Dims,
    names: [&'static str; 3],
) {
    use build::*;
    use proportion::*;
    let h = dims.h;
    let (x, y, z) = (DVec3::X, DVec3::Y, DVec3::Z);
    let thigh = hip.turn(-y, q[0], rate[0]).turn(x * side, q[1], rate[1]);
    let knee_at = -z * dims.segments.thigh;
    parts.push(capsule(
        names[0],
        &thigh,
        DVec3::ZERO,
        knee_at,
        THIGH_RADIUS * h,
    ));
    let shin = thigh.at(knee_at).turn(y, q[2], rate[2]);
    let ankle = -z * dims.segments.shank;
    parts.push(capsule(
        names[1],
        &shin,
        DVec3::ZERO,
        ankle,
        SHIN_RADIUS * h,
    ));
    let r = FOOT_RADIUS * h;
    let sole = ankle - z * (ANKLE_HEIGHT * h - r);
    let heel = sole - x * (HEEL * FOOT_LENGTH * h - r);
    let toe = sole + x * ((1.0 - HEEL) * FOOT_LENGTH * h - r);
    parts.push(capsule(names[2], &shin, heel, toe, r));
}
