//! The body's root pose and joint angles from the joints of one frame,
//! analytically (no optimisation): the root from the hips, the trunk from
//! the shoulders, the head from the head's centre, each arm and leg from
//! its three joints.

use glam::{DMat3, DVec3};

use super::super::body::{proportion, rotation};
use super::super::library::arm_angles;
use super::super::pose::{Pose, joint};

/// What one frame gives: root (floor point), heading and pose.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Fitted {
    pub root: DVec3,
    pub heading: f64,
    pub pose: Pose,
}

/// Hip joints above the root and the lumbar joint above them (fractions of
/// the height; `body.rs`).
const LUMBAR: f64 = 0.05;

fn angle(a: DVec3, b: DVec3) -> f64 {
    crate::math::acos(
        a.normalize_or_zero()
            .dot(b.normalize_or_zero())
            .clamp(-1.0, 1.0),
    )
}

/// Fits frame `j` (the `NEEDED` joints, head centre in slots 12 and 13) for
/// a body of height `h`; `prev` is the previous frame's fit (its heading
/// and bend directions stand in where this frame leaves them undefined).
pub(crate) fn fit(j: &[DVec3; 14], h: f64, prev: Option<&Fitted>) -> Fitted {
    let [ls, rs, le, re, lw, rw, lh, rh, lk, rk, la, ra, h1, h2] = *j;
    let hips = 0.5 * (lh + rh);
    let heading = heading(ls, rs, lh, rh, prev);
    let root = hips - DVec3::Z * (proportion::HIP_HEIGHT * h);
    let base = rotation(DVec3::Z, heading);
    let mut pose = Pose::default();
    let lumbar = hips + DVec3::Z * (LUMBAR * h);
    let trunk = spine(&mut pose, lumbar, ls, rs, base);
    neck(&mut pose, trunk, lumbar, 0.5 * (h1 + h2), h);
    // Arms, in the trunk's frame.
    for (k, side, s, e, w) in [
        (joint::LEFT_ARM, 1.0, ls, le, lw),
        (joint::RIGHT_ARM, -1.0, rs, re, rw),
    ] {
        arm(&mut pose, trunk, (k, side), [s, e, w], prev);
    }
    // Legs, in the root's frame: thigh = Ry(−flexion) Rx(side·abduction) (−z).
    for (k, side, hip, knee, ankle) in [
        (joint::LEFT_LEG, 1.0, lh, lk, la),
        (joint::RIGHT_LEG, -1.0, rh, rk, ra),
    ] {
        let t = (base.transpose() * (knee - hip)).normalize_or(-DVec3::Z);
        let sb = t.y.clamp(-1.0, 1.0);
        let beta = crate::math::atan2(sb, (1.0 - sb * sb).sqrt());
        let flexion = crate::math::atan2(t.x, -t.z);
        pose.angles[k..k + 3].copy_from_slice(&[
            flexion,
            side * beta,
            angle(knee - hip, ankle - knee),
        ]);
    }
    Fitted {
        root,
        heading,
        pose,
    }
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
/// trunk.
fn neck(pose: &mut Pose, trunk: DMat3, lumbar: DVec3, head: DVec3, h: f64) {
    let shoulder_z = (proportion::SHOULDER_HEIGHT - proportion::HIP_HEIGHT - LUMBAR) * h;
    let neck = lumbar + trunk * (DVec3::Z * shoulder_z);
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

/// One arm's angles (first joint `k`, `side` 1 left, −1 right) from its
/// shoulder, elbow and wrist, in the trunk's frame.
fn arm(
    pose: &mut Pose,
    trunk: DMat3,
    (k, side): (usize, f64),
    [s, e, w]: [DVec3; 3],
    prev: Option<&Fitted>,
) {
    let along = (trunk.transpose() * (e - s)).normalize_or(-DVec3::Z);
    let fore = (trunk.transpose() * (w - e)).normalize_or(along);
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
    let [f, ab, rot] = arm_angles(along, bend.normalize(), side);
    let rot = if elbow < 1e-6 {
        prev.map_or(0.0, |p| p.pose.angles[k + 2])
    } else {
        rot
    };
    pose.angles[k..k + 4].copy_from_slice(&[f, ab, rot, elbow]);
}
