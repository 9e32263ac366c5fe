//! BVH (Biovision Hierarchy) motion capture read as a keypoint track: the
//! hierarchy's forward kinematics give, per frame, the world positions of
//! the joints the fit reads, which then go through the same repairs and fit
//! as a recorded keypoint track.
//!
//! The file: `HIERARCHY`, one `ROOT` with nested `JOINT`s and `End Site`s,
//! each joint an `OFFSET x y z` from its parent and `CHANNELS n …`
//! (`Xposition`, `Yposition`, `Zposition`, `Xrotation`, `Yrotation`,
//! `Zrotation`, at most 6); then `MOTION`, `Frames: n`, `Frame Time: dt`
//! and one line of values per frame, the channels in the order the
//! hierarchy declares them. A joint's rotation is the product of its
//! rotation channels in the order listed (`Zrotation Xrotation Yrotation`
//! is `Rz·Rx·Ry`, degrees); a position channel replaces that coordinate of
//! the joint's `OFFSET` (the root's offset is normally zero, so both common
//! readings agree). Frame `k` is at `k · dt` seconds.

use glam::{DMat3, DVec3};

mod hierarchy;
mod joints;

use hierarchy::{Channel, Hierarchy, Tokens, clip, hierarchy, number};

use super::Axes;
use crate::error::FieldError;
use crate::human::MAX_KEYFRAMES;
use crate::human::rotation;

/// Most joints (end sites not counted) a BVH hierarchy may declare.
pub const MAX_BVH_JOINTS: usize = 1024;
/// Longest `Frame Time` accepted (s).
pub const MAX_FRAME_TIME: f64 = 10.0;
/// Largest magnitude of an `OFFSET` coordinate or a channel value (file
/// units or degrees).
pub const MAX_BVH_VALUE: f64 = 1e7;
/// The value after `label` (`Frames`, `Frame Time`) on the next non-empty
/// line.
fn header<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a str)>,
    label: &str,
) -> Result<&'a str, FieldError> {
    let line = lines
        .by_ref()
        .map(|(_, l)| l.trim())
        .find(|l| !l.is_empty())
        .unwrap_or("");
    line.strip_prefix(label)
        .map(str::trim_start)
        .and_then(|r| r.strip_prefix(':'))
        .map(str::trim)
        .ok_or_else(|| {
            FieldError::new(
                label,
                format!("expected \"{label}: …\", got \"{}\"", clip(line)),
            )
        })
}

/// The motion section's header: frame count and frame time.
fn motion_header<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a str)>,
) -> Result<(usize, f64), FieldError> {
    let n = header(lines, "Frames")?;
    let n = n.parse::<u64>().map_err(|_| {
        FieldError::new(
            "Frames",
            format!("expected a whole number of frames, got \"{}\"", clip(n)),
        )
    })?;
    if n == 0 {
        return Err(FieldError::new("Frames", "needs at least one frame"));
    }
    if n > MAX_KEYFRAMES as u64 {
        return Err(FieldError::new(
            "Frames",
            format!("at most {MAX_KEYFRAMES} frames (got {n})"),
        ));
    }
    let dt = header(lines, "Frame Time")?;
    let dt = dt.parse::<f64>().map_err(|_| {
        FieldError::new(
            "Frame Time",
            format!("expected seconds, got \"{}\"", clip(dt)),
        )
    })?;
    if !(dt > 0.0 && dt <= MAX_FRAME_TIME) {
        return Err(FieldError::new(
            "Frame Time",
            format!("must be in (0, {MAX_FRAME_TIME}] s (got {dt})"),
        ));
    }
    Ok((usize::try_from(n).unwrap_or(MAX_KEYFRAMES), dt))
}

/// Poses the joints marked in `used` for one frame's `values`.
fn forward(h: &Hierarchy, values: &[f64], used: &[bool], p: &mut [DVec3], r: &mut [DMat3]) {
    const AXES: [DVec3; 3] = [DVec3::X, DVec3::Y, DVec3::Z];
    for (j, joint) in h.joints.iter().enumerate() {
        if !used[j] {
            continue;
        }
        let mut t = joint.offset;
        let mut rot = DMat3::IDENTITY;
        for (c, ch) in joint.channels.iter().enumerate() {
            let v = values[joint.first + c];
            match *ch {
                Channel::Position(a) => t[a] = v,
                Channel::Rotation(a) => rot *= rotation(AXES[a], v.to_radians()),
            }
        }
        match joint.parent {
            Some(q) => {
                p[j] = p[q] + r[q] * t;
                r[j] = r[q] * rot;
            }
            None => {
                p[j] = t;
                r[j] = rot;
            }
        }
    }
}

/// What a BVH file gives the fit: frame times and, per frame, the
/// [`super::NEEDED`] joints (the head's centre in both ear slots).
pub(crate) type Read = (Vec<f64>, Vec<Vec<Option<DVec3>>>);

/// Reads a BVH file: its hierarchy, the joints the fit needs
/// ([`joints::body_joints`]) and their world positions in every frame.
pub(crate) fn read(text: &str, axes: Axes) -> Result<Read, FieldError> {
    let mut tok = Tokens::new(text);
    let h = hierarchy(&mut tok)?;
    if let Some(x) = tok.same_line() {
        return Err(FieldError::new(
            format!("line {}", tok.line),
            format!("unexpected \"{}\" after MOTION", clip(x)),
        ));
    }
    let slots = joints::body_joints(&h)?;
    // The joints on the way from the root to the mapped ones.
    let mut used = vec![false; h.joints.len()];
    for &(j, _) in &slots {
        let mut at = Some(j);
        while let Some(k) = at {
            used[k] = true;
            at = h.joints[k].parent;
        }
    }
    let mut lines = tok.lines.map(|(k, l)| (k + 1, l));
    let (n, dt) = motion_header(&mut lines)?;
    let mut times = Vec::with_capacity(n.min(4096));
    let mut points: Vec<Vec<Option<DVec3>>> = Vec::with_capacity(n.min(4096));
    let mut values = vec![0.0; h.channels];
    let (mut p, mut r) = (
        vec![DVec3::ZERO; h.joints.len()],
        vec![DMat3::IDENTITY; h.joints.len()],
    );
    for (line, text) in lines {
        if text.trim().is_empty() {
            continue;
        }
        let at = format!("line {line}");
        if times.len() == n {
            return Err(FieldError::new(
                "Frames",
                format!("declares {n} frames, the file has more (from line {line})"),
            ));
        }
        frame_values(&h, text, &at, &mut values)?;
        forward(&h, &values, &used, &mut p, &mut r);
        times.push(dt * times.len() as f64);
        points.push(
            slots
                .iter()
                .map(|&(j, end)| {
                    let here = p[j];
                    let q = match (end, h.joints[j].end) {
                        (true, Some(e)) => here.lerp(here + r[j] * e, 0.5),
                        _ => here,
                    };
                    Some(axes.apply(q))
                })
                .collect(),
        );
    }
    if times.len() < n {
        return Err(FieldError::new(
            "Frames",
            format!(
                "declares {n} frames, the file has {} (truncated?)",
                times.len()
            ),
        ));
    }
    Ok((times, points))
}

/// Reads one frame's line into `values`.
fn frame_values(h: &Hierarchy, text: &str, at: &str, values: &mut [f64]) -> Result<(), FieldError> {
    let mut got = 0;
    for (i, token) in text.split_whitespace().enumerate() {
        if i < values.len() {
            values[i] = number(at, Some(token)).map_err(|e| {
                let (j, c) = channel_of(h, i);
                FieldError::new(at, format!("value {} ({j} {c}): {}", i + 1, e.reason))
            })?;
        }
        got = i + 1;
    }
    if got != values.len() {
        return Err(FieldError::new(
            at,
            format!(
                "expected {} values (the channels of the HIERARCHY), got {got}",
                values.len()
            ),
        ));
    }
    Ok(())
}

/// The joint and channel names of value `i` of a frame.
fn channel_of(h: &Hierarchy, i: usize) -> (String, String) {
    h.joints
        .iter()
        .find(|j| i >= j.first && i < j.first + j.channels.len())
        .map_or((String::new(), String::new()), |j| {
            (j.name.clone(), j.channels[i - j.first].name())
        })
}

// Compiled only under `cfg(test)`: the `unwrap`s below stop a failing test
// and cannot reach a JavaScript caller.
#[cfg(test)]
mod tests {
    use super::*;

    const CHAIN: &str = "HIERARCHY
ROOT Hips
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT Arm
  {
    OFFSET 0 10 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    End Site
    {
      OFFSET 0 5 0
    }
  }
}
MOTION
Frames: 2
Frame Time: 0.5
1 2 3 0 0 0 0 0 0
0 0 0 90 0 0 0 90 0
";

    #[test]
    fn forward_kinematics_by_hand() {
        let mut tok = Tokens::new(CHAIN);
        let h = hierarchy(&mut tok).unwrap();
        assert_eq!(h.channels, 9);
        assert_eq!(h.joints[1].first, 6);
        let used = [true, true];
        let (mut p, mut r) = ([DVec3::ZERO; 2], [DMat3::IDENTITY; 2]);
        forward(
            &h,
            &[1.0, 2.0, 3.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            &used,
            &mut p,
            &mut r,
        );
        assert!((p[1] - DVec3::new(1.0, 12.0, 3.0)).length() < 1e-12);
        // Hips turned 90° about z: the arm's offset (0, 10, 0) points to −x;
        // its end site is at Rz(90)·Rx(90)·(0, 5, 0) = (0, 0, 5) from it.
        forward(
            &h,
            &[0.0, 0.0, 0.0, 90.0, 0.0, 0.0, 0.0, 90.0, 0.0],
            &used,
            &mut p,
            &mut r,
        );
        assert!(
            (p[1] - DVec3::new(-10.0, 0.0, 0.0)).length() < 1e-12,
            "{}",
            p[1]
        );
        let tip = p[1] + r[1] * DVec3::new(0.0, 5.0, 0.0);
        assert!(
            (tip - DVec3::new(-10.0, 0.0, 5.0)).length() < 1e-12,
            "{tip}"
        );
    }

    #[test]
    fn channel_order_is_the_product_in_listed_order() {
        // Listed Xrotation then Zrotation: Rx·Rz, which sends the end site
        // (0, 5, 0) to (−5, 0, 0); Rz·Rx would send it to (0, 0, 5).
        let text = CHAIN.replace(
            "CHANNELS 3 Zrotation Xrotation Yrotation",
            "CHANNELS 3 Xrotation Zrotation Yrotation",
        );
        let mut tok = Tokens::new(&text);
        let h = hierarchy(&mut tok).unwrap();
        let used = [true, true];
        let (mut p, mut r) = ([DVec3::ZERO; 2], [DMat3::IDENTITY; 2]);
        forward(
            &h,
            &[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 90.0, 90.0, 0.0],
            &used,
            &mut p,
            &mut r,
        );
        let tip = p[1] + r[1] * DVec3::new(0.0, 5.0, 0.0);
        assert!(
            (tip - DVec3::new(-5.0, 10.0, 0.0)).length() < 1e-12,
            "{tip}"
        );
    }

    #[test]
    fn axes_turn_y_up_into_z_up() {
        let a = Axes {
            scale: 0.01,
            y_up: true,
        };
        // Up in the file (y) is up in the world (z); the file's +z (towards
        // the viewer) becomes −y.
        assert!((a.apply(DVec3::new(0.0, 100.0, 0.0)) - DVec3::Z).length() < 1e-15);
        assert!((a.apply(DVec3::new(0.0, 0.0, 100.0)) + DVec3::Y).length() < 1e-15);
    }
}
