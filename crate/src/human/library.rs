//! A small library of motions, each a list of keyframes built from the
//! person's rest pose (the joints a motion does not name keep their rest
//! angles):
//!
//! | clip | what it does | parameters |
//! |---|---|---|
//! | `reach` | one hand goes from rest to `target` (the hand's end, the centre of its far cap, is put on the point by an analytic two-link solution, angles clamped into the body's range), then holds | `target` (required), `side`, `speed` (peak hand speed, about; default 1 m/s), `start` |
//! | `wave` | raises one arm sideways, forearm up, waves it twice, lowers it; repeats | `side`, `start` |
//! | `walk` | one gait cycle of legs and swinging arms, repeated, stride sized for `speed` (default 1.4 m/s); the body's travel is the obstacle's `motion` (e.g. `linear`) | `speed`, `start` |
//! | `bend` | bends over a table in front (trunk forward, arms reaching down and ahead), holds 2 s, stands up | `start` |
//! | `stepBack` | one step backwards (0.35 m) | `start` |

use glam::{DMat3, DVec3};

use super::animation::Keyframe;
use super::body::{proportion, rotation};
use super::pose::{Pose, joint};
use super::spec::{AnimationSpec, HumanSpec};
use crate::error::{FieldError, finite, finite3, positive};

/// Names of the library's motions.
pub const CLIP_NAMES: [&str; 5] = ["reach", "wave", "walk", "bend", "stepBack"];

/// The keyframes of clip `name` for `human` and whether they repeat.
///
/// # Errors
/// `clip: unknown motion …`, `target: required by reach`, `side: …`,
/// `speed: must be > 0`, `start: not a finite number`.
pub fn clip(
    human: &HumanSpec,
    name: &str,
    a: &AnimationSpec,
) -> Result<(Vec<Keyframe>, bool), FieldError> {
    let start = finite("start", a.start.unwrap_or(0.0))?;
    let arm = arm_of(a.side.as_deref().unwrap_or("right"))?;
    let speed = match a.speed {
        Some(s) => positive("speed", s)?,
        None if name == "walk" => 1.4,
        None => 1.0,
    };
    let rest = human.rest_pose();
    let key = |t: f64, pose: Pose| Keyframe {
        t: start + t,
        pose: pose.clamped(),
        shift: [0.0; 3],
        turn: 0.0,
    };
    let keys = match name {
        "reach" => {
            let target = a
                .target
                .ok_or_else(|| FieldError::new("target", "required by the reach clip"))?;
            let target = finite3("target", DVec3::from_array(target))?;
            let reached = reach_pose(human, &rest, arm, target);
            let duration = 1.5 * hand_travel(human, &rest, &reached, arm) / speed;
            return Ok((vec![key(0.0, rest), key(duration.max(0.2), reached)], false));
        }
        "wave" => {
            let keys = wave(&rest, arm).into_iter().map(|(t, p)| key(t, p));
            return Ok((keys.collect(), true));
        }
        "walk" => walk(&rest, speed, human.height),
        "bend" => {
            let keys = bend(&rest).into_iter().map(|(t, p)| key(t, p));
            return Ok((keys.collect(), false));
        }
        "stepBack" => {
            let mut lift = rest;
            lift.angles[joint::RIGHT_LEG] = -0.35;
            lift.angles[joint::RIGHT_LEG + 2] = 0.6;
            let mut k = vec![key(0.0, rest), key(0.45, lift), key(0.9, rest)];
            k[1].shift = [-0.15, 0.0, 0.0];
            k[2].shift = [-0.35, 0.0, 0.0];
            return Ok((k, false));
        }
        other => {
            return Err(FieldError::new(
                "clip",
                format!(
                    "unknown motion \"{other}\" (expected one of {})",
                    CLIP_NAMES.join(", ")
                ),
            ));
        }
    };
    Ok((keys.into_iter().map(|(t, p)| key(t, p)).collect(), true))
}

/// A wave of `arm` from the rest pose: the hand raised, the forearm
/// swinging at the elbow, back to rest (times in s).
fn wave(rest: &Pose, arm: usize) -> Vec<(f64, Pose)> {
    let up = |elbow: f64| {
        let mut p = *rest;
        p.angles[arm..arm + 4].copy_from_slice(&[0.2, 1.45, -1.45, elbow]);
        p
    };
    let times = [0.0, 0.6, 1.0, 1.4, 1.8, 2.2, 2.8];
    let poses = [*rest, up(1.6), up(2.2), up(1.2), up(2.2), up(1.6), *rest];
    times.into_iter().zip(poses).collect()
}

/// Bending over and back up: the spine flexed, the arms hanging forward,
/// the knees bent (times in s).
fn bend(rest: &Pose) -> Vec<(f64, Pose)> {
    let mut low = *rest;
    low.angles[joint::SPINE_FLEXION] = 0.9;
    low.angles[joint::NECK_FLEXION] = -0.4;
    for k in [joint::LEFT_ARM, joint::RIGHT_ARM] {
        low.angles[k..k + 4].copy_from_slice(&[1.0, 0.15, 0.0, 0.5]);
    }
    for k in [joint::LEFT_LEG, joint::RIGHT_LEG] {
        low.angles[k..k + 3].copy_from_slice(&[0.25, 0.0, 0.15]);
    }
    vec![(0.0, *rest), (1.2, low), (3.2, low), (4.4, *rest)]
}

/// One gait cycle: legs swing ±A, arms swing opposite, the swing knee
/// bends; period `2 · 0.55 s`, stride `speed × period`.
fn walk(rest: &Pose, speed: f64, height: f64) -> Vec<(f64, Pose)> {
    let period = 1.1;
    let leg = (proportion::HIP_HEIGHT - proportion::ANKLE_HEIGHT) * height;
    let amp = crate::math::atan2(0.25 * speed * period, leg).clamp(0.15, 0.6);
    let arm = 0.8 * amp;
    let at = |hip_l: f64, knee_l: f64, knee_r: f64| {
        let mut p = *rest;
        p.angles[joint::LEFT_LEG..joint::LEFT_LEG + 3].copy_from_slice(&[hip_l, 0.0, knee_l]);
        p.angles[joint::RIGHT_LEG..joint::RIGHT_LEG + 3].copy_from_slice(&[-hip_l, 0.0, knee_r]);
        let s = hip_l / amp;
        p.angles[joint::LEFT_ARM..joint::LEFT_ARM + 4].copy_from_slice(&[-arm * s, 0.08, 0.0, 0.3]);
        p.angles[joint::RIGHT_ARM..joint::RIGHT_ARM + 4].copy_from_slice(&[
            arm * s,
            0.08,
            0.0,
            0.3,
        ]);
        p
    };
    vec![
        (0.0, at(amp, 0.1, 0.3)),
        (0.25 * period, at(0.0, 0.2, 1.0)),
        (0.5 * period, at(-amp, 0.3, 0.1)),
        (0.75 * period, at(0.0, 1.0, 0.2)),
        (period, at(amp, 0.1, 0.3)),
    ]
}

/// The trunk's orientation (world) in pose `p` of `human`.
fn trunk_rotation(human: &HumanSpec, p: &Pose) -> DMat3 {
    let a = &p.angles;
    rotation(DVec3::Z, human.heading)
        * rotation(DVec3::Z, a[joint::SPINE_TWIST])
        * rotation(-DVec3::X, a[joint::SPINE_LATERAL])
        * rotation(DVec3::Y, a[joint::SPINE_FLEXION])
}

/// The part index of the upper arm, forearm and hand of `arm`.
fn arm_parts(arm: usize) -> [usize; 3] {
    if arm == joint::LEFT_ARM {
        [4, 5, 6]
    } else {
        [7, 8, 9]
    }
}

fn capsule_ends(human: &HumanSpec, p: &Pose, part: usize) -> (DVec3, DVec3) {
    let mut h = human.clone();
    h.pose = Some(Box::new(*p));
    match &h.parts()[part] {
        crate::distance::PrimitiveSpec::Capsule(c) => {
            (DVec3::from_array(c.a), DVec3::from_array(c.b))
        }
        _ => (DVec3::ZERO, DVec3::ZERO),
    }
}

fn hand_travel(human: &HumanSpec, from: &Pose, to: &Pose, arm: usize) -> f64 {
    let hand = arm_parts(arm)[2];
    (capsule_ends(human, from, hand).1 - capsule_ends(human, to, hand).1).length()
}

/// `rest` with arm `arm` (index of its first joint) placing the hand's end
/// on `target`: a two-link solution with the elbow hanging below the line
/// from the shoulder to the target, angles clamped into the body's range.
#[must_use]
pub fn reach_pose(human: &HumanSpec, rest: &Pose, arm: usize, target: DVec3) -> Pose {
    let side = if arm == joint::LEFT_ARM { 1.0 } else { -1.0 };
    let [upper, _, hand] = arm_parts(arm);
    let shoulder = capsule_ends(human, rest, upper).0;
    let (wrist, tip) = capsule_ends(human, rest, hand);
    let l1 = proportion::UPPER_ARM * human.height;
    let l2 = proportion::FOREARM * human.height + (tip - wrist).length();
    if !(l1 * l2 > 1e-12 && target.is_finite()) {
        // No arm to bend (a figure of no height) or nowhere to reach.
        return rest.clamped();
    }
    let r = trunk_rotation(human, rest);
    let u = r.transpose() * (target - shoulder);
    // Within the ring the two links reach (a degenerate body with links of
    // no length has none: the bounds are ordered before clamping).
    let near = (l1 - l2).abs() + 1e-9;
    let d = u.length().clamp(near, (l1 + l2 - 1e-9).max(near));
    let dir = u.try_normalize().unwrap_or(-DVec3::Z);
    let acos = |c: f64| crate::math::acos(c.clamp(-1.0, 1.0));
    let elbow = std::f64::consts::PI - acos((l1 * l1 + l2 * l2 - d * d) / (2.0 * l1 * l2));
    let beta = acos((l1 * l1 + d * d - l2 * l2) / (2.0 * l1 * d));
    // The elbow drops below the shoulder–target line (or outwards when the
    // line is vertical).
    let down = -DVec3::Z + dir * dir.z;
    let w = down
        .try_normalize()
        .unwrap_or_else(|| (DVec3::Y * side - dir * (dir.y * side)).normalize_or(DVec3::X));
    let (sb, cb) = crate::math::sin_cos(beta);
    let along = dir * cb + w * sb;
    let bend = dir * sb - w * cb;
    let [flexion, abduction, rotation] = arm_angles(along, bend, side);
    let mut out = *rest;
    out.angles[arm..arm + 4].copy_from_slice(&[flexion, abduction, rotation, elbow]);
    out.clamped()
}

/// Shoulder flexion, abduction and rotation (rad) that point the upper arm
/// along the unit `along` (trunk frame) with the elbow bending towards the
/// unit `bend` (perpendicular to `along`); `side` +1 left, −1 right.
#[must_use]
pub fn arm_angles(along: DVec3, bend: DVec3, side: f64) -> [f64; 3] {
    let z_u = -along;
    let m = DMat3::from_cols(bend, z_u.cross(bend), z_u);
    // m = Ry(α) Rx(β) Rz(γ) with α = −flexion, β = side·abduction,
    // γ = −side·rotation.
    let sb = (-m.col(2).y).clamp(-1.0, 1.0);
    let b = crate::math::atan2(sb, (1.0 - sb * sb).sqrt());
    let g = crate::math::atan2(m.col(0).y, m.col(1).y);
    let a = crate::math::atan2(m.col(2).x, m.col(2).z);
    [-a, side * b, -side * g]
}

/// The index of the first joint of arm `side` (`left` or `right`).
///
/// # Errors
/// `side: expected "left" or "right"`.
pub fn arm_of(side: &str) -> Result<usize, FieldError> {
    match side {
        "left" => Ok(joint::LEFT_ARM),
        "right" => Ok(joint::RIGHT_ARM),
        other => Err(FieldError::new(
            "side",
            format!("expected \"left\" or \"right\", got \"{other}\""),
        )),
    }
}

/// Where the end of hand `arm` is at rest (m): the centre of its far cap.
#[must_use]
pub fn hand_end(human: &HumanSpec, arm: usize) -> DVec3 {
    capsule_ends(human, &human.rest_pose(), arm_parts(arm)[2]).1
}

/// `human` with hand `side` moved by `delta` (m) from where it is at rest:
/// only that arm's angles change (the two-link solution of
/// [`reach_pose`]); the animation is dropped, so the person holds the new
/// pose.
///
/// # Errors
/// `side: …`, `delta: not a finite number`, or the human's own
/// validation.
pub fn move_hand(human: &HumanSpec, side: &str, delta: DVec3) -> Result<HumanSpec, FieldError> {
    human.compile()?;
    let arm = arm_of(side)?;
    let delta = finite3("delta", delta)?;
    let rest = human.rest_pose();
    let target = hand_end(human, arm) + delta;
    let mut out = human.clone();
    out.pose = Some(Box::new(reach_pose(human, &rest, arm, target)));
    out.animation = None;
    Ok(out)
}
