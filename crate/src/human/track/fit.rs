//! The body's root pose and joint angles from the joints of one frame,
//! analytically (no optimisation): the root from the hips, the trunk from
//! the shoulders, the head from the head's centre, each arm and leg from
//! its three joints.
//!
//! Each limb is aimed from the body's own joint, not the recorded one: the
//! shoulder girdle turns the body's shoulder towards the recorded one (a
//! tracker's shoulder rises and moves out with the arm), then the upper
//! arm from the body's shoulder at the recorded elbow, the forearm
//! from the body's elbow at the recorded wrist, so that a recorded limb of
//! the body's lengths is reached exactly and any difference in length stays
//! along the limb instead of turning it; each leg puts the ankle where it
//! was recorded (the knee angle from the hip–ankle distance, the knee
//! bending in the thigh's sagittal plane), the knee as close as that
//! allows.

use glam::{DMat3, DVec3};

use super::super::animation::Keyframe;
use super::super::body::{proportion, rotation};
use super::super::library::arm_angles;
use super::super::pose::{Pose, joint};
use super::super::segments::Dims;
use crate::parsers::track::Layout;

/// Fits frames one after another (a track's, or a sensor's as they come)
/// onto a body of given dimensions: each frame's keyframe, its root and
/// heading relative to the first frame's.
#[derive(Clone, Debug)]
pub(crate) struct Fitter {
    dims: Dims,
    t0: f64,
    first: Option<Fitted>,
    prev: Option<Fitted>,
}

impl Fitter {
    /// A fitter for a body of `dims` whose keyframe times count from `t0`.
    pub(crate) fn new(dims: Dims, t0: f64) -> Self {
        Self {
            dims,
            t0,
            first: None,
            prev: None,
        }
    }

    /// The keyframe of the frame at `t` with joints `j` (the `NEEDED`
    /// joints), and how many of its angles were clamped into the body's
    /// range.
    pub(crate) fn push(&mut self, t: f64, j: &[DVec3; 14]) -> (Keyframe, usize) {
        let f = fit(j, &self.dims, self.prev.as_ref());
        let pose = f.pose.clamped();
        let clamped = f
            .pose
            .angles
            .iter()
            .zip(&pose.angles)
            .filter(|(a, b)| a != b)
            .count();
        let f0 = *self.first.get_or_insert(f);
        let back = rotation(DVec3::Z, -f0.heading);
        self.prev = Some(Fitted { pose, ..f });
        let key = Keyframe {
            t: t - self.t0,
            pose,
            shift: (back * (f.root - f0.root)).to_array(),
            turn: f.heading - f0.heading,
        };
        (key, clamped)
    }

    /// The first frame's root (floor point) and heading.
    pub(crate) fn origin(&self) -> Option<(DVec3, f64)> {
        self.first.map(|f| (f.root, f.heading))
    }
}

/// The fit's fourteen joints from one frame of `layout` (its keypoints in
/// the layout's order).
pub(crate) fn joints_of(layout: Layout, keypoints: &[DVec3]) -> [DVec3; 14] {
    let needed = layout.needed();
    std::array::from_fn(|s| keypoints.get(needed[s]).copied().unwrap_or_default())
}

/// What one frame gives: root (floor point), heading and pose.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Fitted {
    pub root: DVec3,
    pub heading: f64,
    pub pose: Pose,
}

fn angle(a: DVec3, b: DVec3) -> f64 {
    crate::math::acos(
        a.normalize_or_zero()
            .dot(b.normalize_or_zero())
            .clamp(-1.0, 1.0),
    )
}

/// Fits frame `j` (the `NEEDED` joints, head centre in slots 12 and 13) for
/// a body of dimensions `dims`; `prev` is the previous frame's fit (its
/// heading and bend directions stand in where this frame leaves them
/// undefined).
pub(crate) fn fit(j: &[DVec3; 14], dims: &Dims, prev: Option<&Fitted>) -> Fitted {
    let [ls, rs, le, re, lw, rw, lh, rh, lk, rk, la, ra, h1, h2] = *j;
    let h = dims.h;
    let heading = heading(ls, rs, lh, rh, prev);
    let base = rotation(DVec3::Z, heading);
    let hips = 0.5 * (lh + rh) - DVec3::Z * drop(j, dims, base);
    let root = hips - DVec3::Z * (proportion::HIP_HEIGHT * h);
    let mut pose = Pose::default();
    let lumbar = hips + DVec3::Z * dims.lumbar();
    let trunk = spine(&mut pose, lumbar, ls, rs, base);
    let up = dims.shoulder_above_lumbar();
    neck(
        &mut pose,
        trunk,
        lumbar + trunk * (DVec3::Z * up),
        0.5 * (h1 + h2),
    );
    // Arms, in the trunk's frame, from the body's own shoulders (the
    // girdle turned towards the recorded ones).
    for (k, g, side, sh, e, w) in [
        (joint::LEFT_ARM, joint::LEFT_GIRDLE, 1.0, ls, le, lw),
        (joint::RIGHT_ARM, joint::RIGHT_GIRDLE, -1.0, rs, re, rw),
    ] {
        let s = shoulder(&mut pose, (trunk, lumbar, up), (g, side), [sh, w], dims);
        arm(&mut pose, trunk, (k, side), [s, e, w], dims, prev);
    }
    // Legs, in the root's frame, from the body's own hips.
    let half = 0.5 * dims.segments.hip_width;
    for (k, side, knee, ankle) in [
        (joint::LEFT_LEG, 1.0, lk, la),
        (joint::RIGHT_LEG, -1.0, rk, ra),
    ] {
        let hip = hips + base * (DVec3::Y * (side * half));
        let to = |p: DVec3| base.transpose() * (p - hip);
        let angles = leg(to(knee), to(ankle), dims);
        pose.angles[k..k + 3].copy_from_slice(&[angles[0], side * angles[1], angles[2]]);
    }
    Fitted {
        root,
        heading,
        pose,
    }
}

/// How far to lower the recorded hips' middle (m; negative: raise): so
/// that the body's trunk reaches the recorded shoulders' middle, but no
/// higher than lets each leg reach its recorded ankle (a tracker's hips
/// drift, the shoulders and ankles less).
fn drop(j: &[DVec3; 14], dims: &Dims, base: DMat3) -> f64 {
    let hips = 0.5 * (j[6] + j[7]);
    // |b + z δ| = r, the root nearest zero of δ² + 2 b_z δ + |b|² − r² = 0
    // on the side `sign` (+1: the larger root).
    let solve = |b: DVec3, r: f64, sign: f64| {
        let disc = b.z * b.z - b.length_squared() + r * r;
        -b.z + sign * disc.max(0.0).sqrt()
    };
    let lumbar = hips + DVec3::Z * dims.lumbar();
    let mid = 0.5 * (j[0] + j[1]);
    let trunk = solve(mid - lumbar, dims.shoulder_above_lumbar(), 1.0);
    let reach = dims.segments.thigh + dims.segments.shank;
    let half = 0.5 * dims.segments.hip_width;
    let mut legs = f64::NEG_INFINITY;
    for (side, ankle) in [(1.0, j[10]), (-1.0, j[11])] {
        let hip = hips + base * (DVec3::Y * (side * half));
        // The ankle below the hip: lowered by δ the hip reaches it when
        // |a + z δ| ≤ reach, from the smaller root on.
        legs = legs.max(solve(ankle - hip, reach, -1.0));
    }
    let d = trunk.max(legs);
    if d.is_finite() { d } else { 0.0 }
}

/// A leg's flexion, abduction (before the side's sign) and knee angle that
/// put the ankle at `ankle` (root frame, from the hip) with the body's
/// thigh and shank: the knee angle from the hip–ankle distance (straight
/// when out of reach), then the thigh turned so that the ankle lies along
/// the recorded direction; `knee` (the recorded knee) stands in for the
/// direction when the ankle sits on the hip.
fn leg(knee: DVec3, ankle: DVec3, dims: &Dims) -> [f64; 3] {
    let (l1, l2) = (dims.segments.thigh, dims.segments.shank);
    let reach = ankle.length();
    let d = if reach > 1e-9 {
        ankle / reach
    } else {
        knee.normalize_or(-DVec3::Z)
    };
    let c = ((reach * reach - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)).clamp(-1.0, 1.0);
    let bend = crate::math::acos(c);
    // The leg in the thigh's frame: thigh along −z, shin Ry(bend)(−z).
    let (sk, ck) = crate::math::sin_cos(bend);
    let (vx, vz) = (-l2 * sk, -l1 - l2 * ck);
    let v = (vx * vx + vz * vz).sqrt();
    // Rx(β) v has y = −vz sin β: match the direction's y.
    let sb = if vz < 0.0 {
        (d.y * v / -vz).clamp(-1.0, 1.0)
    } else {
        0.0
    };
    let beta = crate::math::atan2(sb, (1.0 - sb * sb).sqrt());
    let cb = (1.0 - sb * sb).sqrt();
    // Ry(−flexion) turns (vx, vz cos β) in the x–z plane onto the direction.
    let (wx, wz) = (vx, vz * cb);
    let flexion = wrap(crate::math::atan2(d.z, d.x) - crate::math::atan2(wz, wx));
    [flexion, beta, bend]
}

/// `a` brought into (−π, π].
fn wrap(a: f64) -> f64 {
    let tau = std::f64::consts::TAU;
    a - tau * ((a + std::f64::consts::PI) / tau).floor()
}

/// The heading: the pelvis turns with the root, so it comes from the hips
/// (the shoulders `ls`, `rs` when the hips `lh`, `rh` coincide), unwrapped
/// against the previous frame.
fn heading(ls: DVec3, rs: DVec3, lh: DVec3, rh: DVec3, prev: Option<&Fitted>) -> f64 {
    let mut left = lh - rh;
    left.z = 0.0;
    if left.length_squared() < 1e-12 {
        left = ls - rs;
        left.z = 0.0;
    }
    if left.length_squared() > 1e-12 {
        let psi = crate::math::atan2(-left.x, left.y);
        // Unwrapped against the previous frame.
        prev.map_or(psi, |p| {
            let turns = ((p.heading - psi) / std::f64::consts::TAU).round();
            psi + turns * std::f64::consts::TAU
        })
    } else {
        prev.map_or(0.0, |p| p.heading)
    }
}

/// The body's shoulder joint on side `side` (girdle joints `g`, `g + 1`)
/// for the recorded shoulder `sh` and wrist `w`, the trunk's frame `trunk`
/// with its lumbar joint `lumbar` and the shoulders' middle `up` above it:
/// the clavicle aimed from the sternoclavicular joint (that middle) at the
/// recorded shoulder; when the wrist is then out of the arm's reach, turned
/// towards the wrist as far as it takes to reach it (the hand first), all
/// within the girdle's range. Sets the girdle's angles in `pose`.
fn shoulder(
    pose: &mut Pose,
    (trunk, lumbar, up): (DMat3, DVec3, f64),
    (g, side): (usize, f64),
    [sh, w]: [DVec3; 2],
    dims: &Dims,
) -> DVec3 {
    let half = 0.5 * dims.segments.shoulder_width;
    let sc = lumbar + trunk * (DVec3::Z * up);
    let at = |[e, p]: [f64; 2]| {
        if e == 0.0 && p == 0.0 {
            lumbar + trunk * DVec3::new(0.0, side * half, up)
        } else {
            let (sp, cp) = crate::math::sin_cos(p);
            let (se, ce) = crate::math::sin_cos(e);
            sc + trunk * (DVec3::new(sp, side * cp * ce, cp * se) * half)
        }
    };
    let reach = dims.segments.upper_arm + dims.segments.forearm;
    let d0 = (trunk.transpose() * (sh - sc)).normalize_or(DVec3::Y * side);
    let mut angles = girdle(d0, side, g);
    let short = |a: [f64; 2]| (w - at(a)).length() - reach;
    if short(angles) > 1e-9 {
        let dw = (trunk.transpose() * (w - sc)).normalize_or(d0);
        let towards = |t: f64| girdle(d0.lerp(dw, t), side, g);
        let far = towards(1.0);
        if short(far) < short(angles) {
            // The least turn that reaches the wrist (or the whole turn).
            let (mut lo, mut hi) = (0.0, 1.0);
            if short(far) <= 0.0 {
                for _ in 0..40 {
                    let mid = 0.5 * (lo + hi);
                    if short(towards(mid)) <= 0.0 {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
            }
            angles = towards(hi);
        }
    }
    pose.angles[g..g + 2].copy_from_slice(&angles);
    at(angles)
}

/// The shoulder girdle's elevation and protraction (joints `g`, `g + 1`,
/// within the body's range) that aim the clavicle from the
/// sternoclavicular joint along `d` (trunk frame) on side `side`: the
/// clavicle's end is `(sin p, side cos p cos e, cos p sin e)` times its
/// length. An angle within [`GIRDLE_REST`] of zero is zero (a body's own
/// shoulders, refitted, keep the girdle at rest).
fn girdle(d: DVec3, side: f64, g: usize) -> [f64; 2] {
    let d = d.normalize_or(DVec3::Y * side);
    let p = crate::math::atan2(d.x, (d.y * d.y + d.z * d.z).sqrt());
    let e = crate::math::atan2(d.z, side * d.y);
    let range = &super::super::pose::JOINTS;
    let settle = |a: f64, k: usize| {
        if a.abs() < GIRDLE_REST {
            0.0
        } else {
            a.clamp(range[k].min, range[k].max)
        }
    };
    [settle(e, g), settle(p, g + 1)]
}

/// Girdle angles smaller than this (rad) are taken as rest.
const GIRDLE_REST: f64 = 1e-9;

/// The trunk's angles: z from the lumbar joint towards the middle of the
/// shoulders, y along them; returns the trunk's frame.
fn spine(pose: &mut Pose, lumbar: DVec3, ls: DVec3, rs: DVec3, base: DMat3) -> DMat3 {
    let mid = 0.5 * (ls + rs);
    let z_t = (mid - lumbar).normalize_or(DVec3::Z);
    let across = ls - rs;
    let y_t = (across - z_t * z_t.dot(across)).normalize_or(base * DVec3::Y);
    let trunk = DMat3::from_cols(y_t.cross(z_t), y_t, z_t);
    let a = base.transpose() * trunk;
    // a = Rz(twist) Rx(−lateral) Ry(flexion).
    let sb = a.col(1).z.clamp(-1.0, 1.0);
    let b = crate::math::atan2(sb, (1.0 - sb * sb).sqrt());
    pose.angles[joint::SPINE_TWIST] = crate::math::atan2(-a.col(1).x, a.col(1).y);
    pose.angles[joint::SPINE_LATERAL] = -b;
    pose.angles[joint::SPINE_FLEXION] = crate::math::atan2(-a.col(0).z, a.col(2).z);
    trunk
}

/// The neck's angles: the head's centre `head` seen from the top of the
/// trunk, `neck`.
fn neck(pose: &mut Pose, trunk: DMat3, neck: DVec3, head: DVec3) {
    let d = (trunk.transpose() * (head - neck)).normalize_or(DVec3::Z);
    let tilt = crate::math::acos(d.z.clamp(-1.0, 1.0));
    let (twist, flexion) = if d.x >= 0.0 {
        (crate::math::atan2(d.y, d.x), tilt)
    } else {
        (crate::math::atan2(-d.y, -d.x), -tilt)
    };
    let upright = d.x * d.x + d.y * d.y < 1e-12;
    pose.angles[joint::NECK_TWIST] = if upright { 0.0 } else { twist };
    pose.angles[joint::NECK_FLEXION] = flexion;
}

/// One arm's angles (first joint `k`, `side` 1 left, −1 right) from the
/// body's shoulder `s` and the recorded elbow `e` and wrist `w`, in the
/// trunk's frame: the wrist reached from the body's shoulder (the elbow
/// angle from their distance, straight when out of reach), the elbow on
/// the side of the recorded one. When the body's ranges keep that from
/// reaching the wrist (an elbow that would bend backwards, as a 2D pose
/// lifted to 3D may give), the elbow on the other side or the shoulder's
/// other set of angles, whichever puts the wrist closest.
fn arm(
    pose: &mut Pose,
    trunk: DMat3,
    (k, side): (usize, f64),
    [s, e, w]: [DVec3; 3],
    dims: &Dims,
    prev: Option<&Fitted>,
) {
    let (l1, l2) = (dims.segments.upper_arm, dims.segments.forearm);
    let to_wrist = w - s;
    let r = to_wrist.length();
    let u = to_wrist.normalize_or((e - s).normalize_or(-DVec3::Z));
    let c = ((l1 * l1 + r * r - l2 * l2) / (2.0 * l1 * r.max(1e-9))).clamp(-1.0, 1.0);
    let off = e - s - u * u.dot(e - s);
    let n = off.normalize_or(DVec3::ZERO);
    let solve = |n: DVec3| {
        let elbow_at = s + (u * c + n * (1.0 - c * c).sqrt()) * l1;
        let along = (trunk.transpose() * (elbow_at - s)).normalize_or(-DVec3::Z);
        let fore = (trunk.transpose() * (w - elbow_at)).normalize_or(along);
        let elbow = angle(along, fore);
        let mut bend = fore - along * along.dot(fore);
        if bend.length_squared() < 1e-12 {
            // A straight arm: any bend direction; keep the previous one's
            // rotation by bending forward of the arm.
            let ahead = DVec3::X - along * along.x;
            bend = if ahead.length_squared() > 1e-12 {
                ahead
            } else {
                DVec3::Z - along * along.z
            };
        }
        let [chosen, other] = within_range(k, arm_angles(along, bend.normalize(), side), side);
        let held = |[f, ab, rot]: [f64; 3]| {
            let rot = if elbow < 1e-6 {
                prev.map_or(0.0, |p| p.pose.angles[k + 2])
            } else {
                rot
            };
            [f, ab, rot, elbow]
        };
        [held(chosen), held(other)]
    };
    let [first, second] = solve(n);
    let mut best = first;
    let target = trunk.transpose() * to_wrist;
    let miss = |a: &[f64; 4]| (wrist_of(k, a, side, (l1, l2)) - target).length();
    // Out of reach the wrist is missed by the difference whatever the
    // angles; another choice must bring it closer by a millimetre.
    let m0 = miss(&first);
    if m0 > (r - l1 - l2).max(0.0) + SWITCH {
        let [third, fourth] = solve(-n);
        let mut least = m0 - SWITCH;
        for a in [second, third, fourth] {
            let m = miss(&a);
            if m < least {
                (best, least) = (a, m);
            }
        }
    }
    pose.angles[k..k + 4].copy_from_slice(&best);
}

/// How much closer (m) to the recorded wrist another choice of the arm's
/// angles must bring it.
const SWITCH: f64 = 1e-3;

/// Where an arm of lengths `l1`, `l2` with angles `a` (first joint `k`,
/// clamped into the body's range) puts the wrist, from the shoulder in the
/// trunk's frame (as [`super::super::body`] poses it).
fn wrist_of(k: usize, a: &[f64; 4], side: f64, (l1, l2): (f64, f64)) -> DVec3 {
    let range = &super::super::pose::JOINTS[k..k + 4];
    let q: [f64; 4] = std::array::from_fn(|i| a[i].clamp(range[i].min, range[i].max));
    let upper = rotation(-DVec3::Y, q[0])
        * rotation(DVec3::X * side, q[1])
        * rotation(-DVec3::Z * side, q[2]);
    upper * (-DVec3::Z * l1) + upper * (rotation(-DVec3::Y, q[3]) * (-DVec3::Z * l2))
}

/// Of the two sets of shoulder angles that give the same arm (flexion
/// `f`, abduction `ab`, rotation `rot`, and `f + π`, `π − ab`, `rot + π`
/// with the side's signs), the one the body's ranges clamp the least
/// (an arm raised sideways overhead is an abduction past π/2), then the
/// other one.
fn within_range(k: usize, [f, ab, rot]: [f64; 3], side: f64) -> [[f64; 3]; 2] {
    use std::f64::consts::PI;
    let other = [
        wrap(f - PI),
        wrap(side * (PI - side * ab)),
        wrap(rot - side * PI),
    ];
    let beyond = |a: &[f64; 3]| -> f64 {
        a.iter()
            .zip(&super::super::pose::JOINTS[k..k + 3])
            .map(|(x, r)| (r.min - x).max(x - r.max).max(0.0))
            .sum()
    };
    if beyond(&other) < beyond(&[f, ab, rot]) {
        [other, [f, ab, rot]]
    } else {
        [[f, ab, rot], other]
    }
}
