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

use crate::error::FieldError;
use crate::human::animation::MAX_KEYFRAMES;
use crate::human::body::rotation;

/// Most joints (end sites not counted) a BVH hierarchy may declare.
pub const MAX_BVH_JOINTS: usize = 1024;
/// Longest `Frame Time` accepted (s).
pub const MAX_FRAME_TIME: f64 = 10.0;
/// Largest magnitude of an `OFFSET` coordinate or a channel value (file
/// units or degrees).
pub const MAX_BVH_VALUE: f64 = 1e7;
/// Longest joint name (characters).
const MAX_NAME: usize = 200;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Channel {
    Position(usize),
    Rotation(usize),
}

impl Channel {
    fn from_name(name: &str) -> Option<Self> {
        let axis = match name.as_bytes().first() {
            Some(b'X' | b'x') => 0,
            Some(b'Y' | b'y') => 1,
            Some(b'Z' | b'z') => 2,
            _ => return None,
        };
        match name.get(1..).map(str::to_ascii_lowercase).as_deref() {
            Some("position") => Some(Self::Position(axis)),
            Some("rotation") => Some(Self::Rotation(axis)),
            _ => None,
        }
    }

    fn name(self) -> String {
        let (axis, kind) = match self {
            Self::Position(a) => (a, "position"),
            Self::Rotation(a) => (a, "rotation"),
        };
        format!("{}{kind}", ["X", "Y", "Z"][axis])
    }
}

/// One joint of the hierarchy.
#[derive(Clone, Debug)]
pub(crate) struct Joint {
    pub name: String,
    parent: Option<usize>,
    offset: DVec3,
    channels: Vec<Channel>,
    /// Index of its first channel in a frame's values.
    first: usize,
    /// Its first `End Site`'s offset.
    end: Option<DVec3>,
}

/// The hierarchy: joints in the file's order (a parent before its
/// children) and the number of values per frame.
#[derive(Clone, Debug)]
pub(crate) struct Hierarchy {
    pub joints: Vec<Joint>,
    channels: usize,
}

/// A lazy stream of whitespace-separated tokens with their line numbers.
struct Tokens<'a> {
    lines: std::iter::Enumerate<std::str::Lines<'a>>,
    line: usize,
    rest: std::str::SplitWhitespace<'a>,
}

impl<'a> Tokens<'a> {
    fn new(text: &'a str) -> Self {
        Self {
            lines: text.lines().enumerate(),
            line: 0,
            rest: "".split_whitespace(),
        }
    }

    fn next(&mut self) -> Option<(usize, &'a str)> {
        loop {
            if let Some(t) = self.rest.next() {
                return Some((self.line, t));
            }
            let (k, l) = self.lines.next()?;
            self.line = k + 1;
            self.rest = l.split_whitespace();
        }
    }

    /// The next token on the current line.
    fn same_line(&mut self) -> Option<&'a str> {
        self.rest.next()
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Open {
    Joint(usize),
    End(usize),
}

fn number(field: &str, token: Option<&str>) -> Result<f64, FieldError> {
    let Some(token) = token else {
        return Err(FieldError::new(field, "expected a number, the line ends"));
    };
    match token.parse::<f64>() {
        Ok(x) if x.is_finite() && x.abs() <= MAX_BVH_VALUE => Ok(x),
        Ok(x) if x.is_finite() => Err(FieldError::new(
            field,
            format!("{x} is beyond ±{MAX_BVH_VALUE:e}"),
        )),
        Ok(_) => Err(FieldError::new(
            field,
            format!("\"{token}\" is not a finite number"),
        )),
        Err(_) => Err(FieldError::new(
            field,
            format!("\"{}\" is not a number", clip(token)),
        )),
    }
}

/// At most 40 characters of `s`, for messages.
fn clip(s: &str) -> String {
    let mut out: String = s.chars().take(40).collect();
    if out.len() < s.len() {
        out.push('…');
    }
    out
}

/// The name after `ROOT` or `JOINT` (the rest of the line, a trailing `{`
/// opening its block) and whether the `{` was there.
fn joint_name(tok: &mut Tokens<'_>, line: usize) -> Result<(String, bool), FieldError> {
    let mut words: Vec<&str> = Vec::new();
    let mut brace = false;
    while let Some(w) = tok.same_line() {
        if w == "{" {
            brace = true;
            break;
        }
        words.push(w);
        if words.len() > MAX_NAME {
            break;
        }
    }
    let name = words.join(" ");
    if name.is_empty() {
        return Err(FieldError::new(
            format!("line {line}"),
            "a joint needs a name",
        ));
    }
    if name.chars().count() > MAX_NAME {
        return Err(FieldError::new(
            format!("line {line}"),
            format!("a joint name of at most {MAX_NAME} characters"),
        ));
    }
    if let Some(extra) = tok.same_line() {
        return Err(FieldError::new(
            format!("line {line}"),
            format!("unexpected \"{}\" after the joint's {{", clip(extra)),
        ));
    }
    Ok((name, brace))
}

/// Reads the channels of joint `j` (after `CHANNELS`).
fn channels(tok: &mut Tokens<'_>, joint: &mut Joint, first: usize) -> Result<(), FieldError> {
    let field = format!("{}.CHANNELS", joint.name);
    if !joint.channels.is_empty() {
        return Err(FieldError::new(field, "given twice"));
    }
    let n = tok
        .next()
        .and_then(|(_, t)| t.parse::<usize>().ok())
        .filter(|n| *n <= 6)
        .ok_or_else(|| FieldError::new(&field, "expected a count of 0 to 6 channels"))?;
    for _ in 0..n {
        let (_, t) = tok.next().unwrap_or((0, ""));
        let c = Channel::from_name(t).ok_or_else(|| {
            FieldError::new(
                &field,
                format!(
                    "unknown channel \"{}\" (expected Xposition, Yposition, Zposition, Xrotation, Yrotation or Zrotation)",
                    clip(t)
                ),
            )
        })?;
        joint.channels.push(c);
    }
    joint.first = first;
    Ok(())
}

/// Reads the `HIERARCHY` up to and including `MOTION`.
fn hierarchy(tok: &mut Tokens<'_>) -> Result<Hierarchy, FieldError> {
    if !matches!(tok.next(), Some((_, "HIERARCHY"))) {
        return Err(FieldError::new(
            "HIERARCHY",
            "a BVH file starts with HIERARCHY",
        ));
    }
    let mut joints: Vec<Joint> = Vec::new();
    let mut stack: Vec<Open> = Vec::new();
    let mut pending: Option<Open> = None;
    let mut count = 0;
    loop {
        let Some((line, t)) = tok.next() else {
            return Err(FieldError::new(
                "MOTION",
                "missing: the file ends inside its HIERARCHY (truncated?)",
            ));
        };
        let at = format!("line {line}");
        if pending.is_some() && t != "{" {
            return Err(FieldError::new(
                at,
                format!("expected {{, got \"{}\"", clip(t)),
            ));
        }
        match t {
            "ROOT" | "JOINT" => {
                let parent = match (t, stack.last()) {
                    ("ROOT", None) if joints.is_empty() => None,
                    ("ROOT", _) => {
                        return Err(FieldError::new(
                            "ROOT",
                            format!(
                                "only one ROOT, at the top of the HIERARCHY (another on line {line})"
                            ),
                        ));
                    }
                    (_, Some(Open::Joint(p))) => Some(*p),
                    _ => return Err(FieldError::new(at, "JOINT outside a joint's braces")),
                };
                let (name, brace) = joint_name(tok, line)?;
                if joints.len() >= MAX_BVH_JOINTS {
                    return Err(FieldError::new(
                        "HIERARCHY",
                        format!("at most {MAX_BVH_JOINTS} joints"),
                    ));
                }
                joints.push(Joint {
                    name,
                    parent,
                    offset: DVec3::ZERO,
                    channels: Vec::new(),
                    first: 0,
                    end: None,
                });
                let open = Open::Joint(joints.len() - 1);
                if brace {
                    stack.push(open);
                } else {
                    pending = Some(open);
                }
            }
            "End" => {
                let Some(Open::Joint(j)) = stack.last().copied() else {
                    return Err(FieldError::new(at, "End Site outside a joint's braces"));
                };
                if tok.same_line() != Some("Site") {
                    return Err(FieldError::new(at, "expected End Site"));
                }
                match tok.same_line() {
                    Some("{") => stack.push(Open::End(j)),
                    None => pending = Some(Open::End(j)),
                    Some(x) => {
                        return Err(FieldError::new(at, format!("unexpected \"{}\"", clip(x))));
                    }
                }
            }
            "{" => match pending.take() {
                Some(p) => stack.push(p),
                None => return Err(FieldError::new(at, "unexpected {")),
            },
            "}" => {
                if stack.pop().is_none() {
                    return Err(FieldError::new(at, "unmatched }"));
                }
            }
            "OFFSET" => {
                let (j, end) = match stack.last() {
                    Some(Open::Joint(j)) => (*j, false),
                    Some(Open::End(j)) => (*j, true),
                    None => return Err(FieldError::new(at, "OFFSET outside a joint's braces")),
                };
                let field = format!(
                    "{}.{}OFFSET",
                    joints[j].name,
                    if end { "End Site." } else { "" }
                );
                let mut v = DVec3::ZERO;
                for k in 0..3 {
                    v[k] = number(&field, tok.same_line())?;
                }
                if end {
                    joints[j].end.get_or_insert(v);
                } else {
                    joints[j].offset = v;
                }
            }
            "CHANNELS" => {
                let Some(Open::Joint(j)) = stack.last().copied() else {
                    return Err(FieldError::new(at, "CHANNELS outside a joint's braces"));
                };
                channels(tok, &mut joints[j], count)?;
                count += joints[j].channels.len();
            }
            "MOTION" => {
                if joints.is_empty() {
                    return Err(FieldError::new(
                        "ROOT",
                        "missing: the HIERARCHY has no ROOT",
                    ));
                }
                if !stack.is_empty() {
                    return Err(FieldError::new(
                        "HIERARCHY",
                        format!(
                            "{} braces left open before MOTION (a missing }})",
                            stack.len()
                        ),
                    ));
                }
                break;
            }
            other => {
                return Err(FieldError::new(
                    at,
                    format!("unexpected \"{}\" in the HIERARCHY", clip(other)),
                ));
            }
        }
    }
    if count == 0 {
        return Err(FieldError::new("HIERARCHY", "no joint has CHANNELS"));
    }
    Ok(Hierarchy {
        joints,
        channels: count,
    })
}

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

/// How file coordinates become world coordinates: metres per unit and
/// whether the file's up axis is y (then `(x, y, z) → (x, −z, y)`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Axes {
    pub scale: f64,
    pub y_up: bool,
}

impl Axes {
    pub(crate) fn apply(self, p: DVec3) -> DVec3 {
        let p = p * self.scale;
        if self.y_up {
            DVec3::new(p.x, -p.z, p.y)
        } else {
            p
        }
    }
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
/// ([`super::skeleton::map`]) and their world positions in every frame.
pub(crate) fn read(text: &str, axes: Axes) -> Result<Read, FieldError> {
    let mut tok = Tokens::new(text);
    let h = hierarchy(&mut tok)?;
    if let Some(x) = tok.same_line() {
        return Err(FieldError::new(
            format!("line {}", tok.line),
            format!("unexpected \"{}\" after MOTION", clip(x)),
        ));
    }
    let slots = super::skeleton::map(&h)?;
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

impl Joint {
    /// Whether the joint has an `End Site`.
    pub(crate) fn has_end(&self) -> bool {
        self.end.is_some()
    }
}

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
