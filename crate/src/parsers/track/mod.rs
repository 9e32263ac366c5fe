//! Recorded motion read as frames of keypoints: keypoint tracks (JSON,
//! CSV) and BVH motion capture ([`bvh`]).
//!
//! A track is a sequence of frames, each a timestamp and the 3-D positions
//! of a layout's keypoints ([`Layout`]: COCO-17, BODY-25, Azure Kinect 32,
//! BlazePose 33),
//! in metres, world frame, z up (`scale` and `up` convert other units and
//! axes). This module reads the text into timestamps and positions (a
//! keypoint that is null, not finite or farther than [`MAX_COORDINATE`]
//! is read as missing); the repairs and the fit onto the human are
//! [`crate::human::track`]'s. The formats (the format is chosen by
//! `format`, or JSON when the text starts with `{`, BVH when it starts with
//! `HIERARCHY`, CSV otherwise):
//!
//! - **JSON**: `{ "layout": "coco17", "frames": [{ "t": 0.0, "keypoints":
//!   [[x, y, z] | null, …] }, …] }`.
//! - **CSV**: one line per frame, `t, x0, y0, z0, x1, y1, z1, …` in the
//!   layout's order (the layout given in the options); a first line that
//!   does not start with a number is a header; an empty cell or `nan` is a
//!   missing value.
//! - **BVH** (Biovision Hierarchy, recognised by its first word
//!   `HIERARCHY`): the hierarchy's forward kinematics give the world
//!   positions of the shoulders, elbows, wrists, hips, knees, ankles and
//!   the head's centre in every frame (frame `k` at `k · Frame Time`), found
//!   by name (CMU style, `LeftArm`, `LeftForeArm`, `LeftHand`, `LeftUpLeg`,
//!   `LeftLeg`, `LeftFoot`, `Head` under `Hips`, with the aliases listed in
//!   `docs/scenarios.md`, [`bvh`]); they then go through the same repairs
//!   and fit as keypoints. Units default to centimetres (`scale` 0.01) and
//!   the up axis to y (`up`), BVH's usual conventions. Refused: a file
//!   that does not start with `HIERARCHY`, a `ROOT` missing, repeated, or
//!   naming a hierarchy with no hips joint (`ROOT`), more than
//!   [`MAX_BVH_JOINTS`] joints or a needed joint missing (`HIERARCHY`),
//!   bad channels (`LeftArm.CHANNELS`) or offsets (`LeftArm.OFFSET`),
//!   unbalanced braces, a file that ends inside its hierarchy (`MOTION`),
//!   a frame count that is not a whole number in 1..=[`MAX_KEYFRAMES`] or
//!   does not match the frame lines (`Frames`; checked before anything is
//!   allocated), a frame time
//!   outside (0, [`MAX_FRAME_TIME`]] s (`Frame Time`), a frame line with
//!   the wrong number of values or a value that is not a finite number
//!   within ±[`MAX_BVH_VALUE`] (`line 130`, naming the joint and channel).
//!   The text itself is limited only by the caller (the JavaScript binding
//!   reads at most 64 MiB).
//!
//! **Refused** (naming the field): a `format` other than `json`, `csv` or
//! `bvh`, a `scale` outside (0, [`MAX_SCALE`]], an `up` other than `z` or
//! `y`, an unknown layout (`layout`), no frames or more than
//! [`MAX_KEYFRAMES`] (`frames`), a timestamp that is not finite or does not
//! increase (`frames[3].t`), a frame with the wrong number of keypoints
//! (`frames[2].keypoints`), a CSV line with the wrong number of cells or a
//! cell that is not a number (`line 5`). A CSV's non-empty lines past the
//! first `MAX_KEYFRAMES + 2` are not looked at (more frames than the cap
//! are refused).

pub mod bvh;
mod layout;

use glam::DVec3;
use serde::{Deserialize, Serialize};

pub use bvh::{MAX_BVH_JOINTS, MAX_BVH_VALUE, MAX_FRAME_TIME};
pub use layout::{LAYOUT_NAMES, Layout, NEEDED};

use crate::error::{FieldError, finite};
use crate::human::MAX_KEYFRAMES;

/// A keypoint farther than this from the origin is read as missing (m).
pub const MAX_COORDINATE: f64 = 1e4;

/// One frame of a JSON track.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackFrame {
    /// Time (s).
    pub t: f64,
    /// Keypoints in the layout's order, `null` when missing.
    pub keypoints: Vec<Option<[f64; 3]>>,
}

/// A JSON track.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackFile {
    /// `coco17`, `body25`, `kinect32` or `blazepose33`.
    #[serde(default)]
    pub layout: Option<String>,
    /// The frames.
    pub frames: Vec<TrackFrame>,
}

/// Reads a track: JSON, CSV or BVH text into its frames, in world
/// coordinates (metres, z up). `format`, `layout`, `scale` and `up` are the
/// fields of [`TrackOptions`](crate::human::track::TrackOptions) that concern
/// the file.
///
/// # Errors
/// See the module docs: the field and the reason of the first refusal.
pub(crate) fn read(
    text: &str,
    format: Option<&str>,
    layout: Option<&str>,
    scale: Option<f64>,
    up: Option<&str>,
) -> Result<Frames, FieldError> {
    let start = text.trim_start();
    let format = match format {
        Some(f @ ("json" | "csv" | "bvh")) => f,
        None if start.starts_with('{') => "json",
        None if start.starts_with("HIERARCHY") => "bvh",
        None => "csv",
        Some(other) => {
            return Err(FieldError::new(
                "format",
                format!("expected \"json\", \"csv\" or \"bvh\", got \"{other}\""),
            ));
        }
    };
    let axes = axes(scale, up, format == "bvh")?;
    Ok(match format {
        "json" => read_json(text, layout, axes)?,
        "csv" => read_csv(text, layout, axes)?,
        _ => {
            let (times, points) = bvh::read(text, axes)?;
            (Source::BVH, times, points)
        }
    })
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

/// Most metres per unit `scale` may give.
pub const MAX_SCALE: f64 = 1000.0;

fn axes(scale: Option<f64>, up: Option<&str>, bvh: bool) -> Result<Axes, FieldError> {
    let scale = match scale {
        Some(s) => {
            finite("scale", s)?;
            if !(s > 0.0 && s <= MAX_SCALE) {
                return Err(FieldError::new(
                    "scale",
                    format!("must be in (0, {MAX_SCALE}] m per unit (got {s})"),
                ));
            }
            s
        }
        None if bvh => 0.01,
        None => 1.0,
    };
    let y_up = match up {
        None => bvh,
        Some("z") => false,
        Some("y") => true,
        Some(other) => {
            return Err(FieldError::new(
                "up",
                format!("expected \"z\" or \"y\", got \"{other}\""),
            ));
        }
    };
    Ok(Axes { scale, y_up })
}

/// Where the frames came from: a layout's name, its keypoint names and
/// where the [`NEEDED`] joints sit among them.
pub(crate) struct Source {
    pub(crate) name: &'static str,
    pub(crate) names: &'static [&'static str],
    pub(crate) needed: [usize; 14],
}

impl Source {
    /// A BVH file: the needed joints themselves, in order.
    const BVH: Self = Self {
        name: "bvh",
        names: &NEEDED,
        needed: [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13],
    };

    fn of(layout: Layout) -> Self {
        Self {
            name: layout.name(),
            names: layout.names(),
            needed: layout.needed(),
        }
    }
}

/// What a track gives: where it came from, the frame times and, per frame,
/// the keypoints in the source's order (`None`: missing).
pub(crate) type Frames = (Source, Vec<f64>, Vec<Vec<Option<DVec3>>>);

fn check_count(n: usize) -> Result<(), FieldError> {
    if n == 0 {
        return Err(FieldError::new("frames", "needs at least one frame"));
    }
    if n > MAX_KEYFRAMES {
        return Err(FieldError::new(
            "frames",
            format!("at most {MAX_KEYFRAMES} frames (got {n})"),
        ));
    }
    Ok(())
}

fn check_time(k: usize, t: f64, prev: Option<f64>) -> Result<(), FieldError> {
    finite(&format!("frames[{k}].t"), t)?;
    if prev.is_some_and(|p| t <= p) {
        return Err(FieldError::new(format!("frames[{k}].t"), "must increase"));
    }
    Ok(())
}

fn point(p: [f64; 3], axes: Axes) -> Option<DVec3> {
    let v = axes.apply(DVec3::from_array(p));
    (v.is_finite() && v.length() <= MAX_COORDINATE).then_some(v)
}

fn read_json(text: &str, layout: Option<&str>, axes: Axes) -> Result<Frames, FieldError> {
    let file: TrackFile = serde_path_to_error::deserialize(
        &mut serde_json::Deserializer::from_str(text),
    )
    .map_err(|e| crate::error::from_serde_path(&e.path().to_string(), &e.inner().to_string()))?;
    let name = layout
        .or(file.layout.as_deref())
        .ok_or_else(|| FieldError::new("layout", format!("required ({LAYOUT_NAMES})")))?;
    let layout = Layout::from_name(name)?;
    check_count(file.frames.len())?;
    let n = layout.names().len();
    let mut times = Vec::with_capacity(file.frames.len());
    let mut points = Vec::with_capacity(file.frames.len());
    for (k, f) in file.frames.iter().enumerate() {
        check_time(k, f.t, times.last().copied())?;
        if f.keypoints.len() != n {
            return Err(FieldError::new(
                format!("frames[{k}].keypoints"),
                format!(
                    "expected {n} keypoints ({}), got {}",
                    layout.name(),
                    f.keypoints.len()
                ),
            ));
        }
        times.push(f.t);
        points.push(
            f.keypoints
                .iter()
                .map(|p| p.and_then(|p| point(p, axes)))
                .collect(),
        );
    }
    Ok((Source::of(layout), times, points))
}

fn read_csv(text: &str, layout: Option<&str>, axes: Axes) -> Result<Frames, FieldError> {
    let name = layout
        .ok_or_else(|| FieldError::new("layout", format!("required for CSV ({LAYOUT_NAMES})")))?;
    let layout = Layout::from_name(name)?;
    let n = layout.names().len();
    let lines: Vec<(usize, &str)> = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .take(MAX_KEYFRAMES + 2)
        .collect();
    let header = lines.first().is_some_and(|(_, l)| {
        l.split(',')
            .next()
            .is_some_and(|c| c.trim().parse::<f64>().is_err())
    });
    let rows = &lines[usize::from(header)..];
    check_count(rows.len())?;
    let mut times = Vec::with_capacity(rows.len());
    let mut points = Vec::with_capacity(rows.len());
    for (k, (line, row)) in rows.iter().enumerate() {
        let cells: Vec<&str> = row.split(',').map(str::trim).collect();
        let at = format!("line {}", line + 1);
        if cells.len() != 1 + 3 * n {
            return Err(FieldError::new(
                at,
                format!(
                    "expected {} cells (t and x, y, z of {n} keypoints), got {}",
                    1 + 3 * n,
                    cells.len()
                ),
            ));
        }
        let num = |c: &str| -> Result<f64, FieldError> {
            if c.is_empty() || c.eq_ignore_ascii_case("nan") {
                return Ok(f64::NAN);
            }
            c.parse::<f64>()
                .map_err(|_| FieldError::new(at.clone(), format!("\"{c}\" is not a number")))
        };
        let t = num(cells[0])?;
        check_time(k, t, times.last().copied())?;
        let mut frame = Vec::with_capacity(n);
        for c in cells[1..].chunks(3) {
            frame.push(point([num(c[0])?, num(c[1])?, num(c[2])?], axes));
        }
        times.push(t);
        points.push(frame);
    }
    Ok((Source::of(layout), times, points))
}
