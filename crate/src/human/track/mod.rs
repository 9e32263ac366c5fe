//! Recorded keypoint tracks and BVH motion capture mapped onto the
//! articulated human.
//!
//! A track is a sequence of frames, each a timestamp and the 3-D positions
//! of a layout's keypoints ([`Layout`]: COCO-17, BODY-25, Azure Kinect 32),
//! in metres, world frame, z up (`scale` and `up` convert other units and
//! axes). [`import`] reads one (JSON, CSV or BVH), repairs what it can,
//! refuses the rest naming the field, and returns a human ([`HumanSpec`])
//! whose keyframes replay it:
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
//!   `docs/scenarios.md`); they then go through the same repairs and fit as
//!   keypoints. Units default to centimetres (`scale` 0.01) and the up axis
//!   to y (`up`), BVH's usual conventions. Refused: a file that does not
//!   start with `HIERARCHY`, a `ROOT` missing, repeated, or naming a
//!   skeleton with no hips joint (`ROOT`), more than [`MAX_BVH_JOINTS`]
//!   joints or a needed joint missing (`HIERARCHY`), bad channels
//!   (`LeftArm.CHANNELS`) or offsets (`LeftArm.OFFSET`), unbalanced braces,
//!   a file that ends inside its hierarchy (`MOTION`), a frame count that is
//!   not a whole number in 1..=[`MAX_KEYFRAMES`] or does not match the frame
//!   lines (`Frames`; checked before anything is allocated), a frame time
//!   outside (0, [`MAX_FRAME_TIME`]] s (`Frame Time`), a frame line with
//!   the wrong number of values or a value that is not a finite number
//!   within ±[`MAX_BVH_VALUE`] (`line 130`, naming the joint and channel).
//!   The text itself is limited only by the caller (the JavaScript binding
//!   reads at most 64 MiB).
//!
//! **Refused** (the scene is left as it was): an unknown layout (`layout`),
//! no frames or more than [`MAX_KEYFRAMES`] (`frames`), a timestamp that is
//! not finite or does not increase (`frames[3].t`), a frame with the wrong
//! number of keypoints (`frames[2].keypoints`), a CSV line with the wrong
//! number of cells (`line 5`), a joint the fit needs that is missing in every
//! frame (`frames`), bad options (`format`, `smoothing`, `maxGap`,
//! `height`, `scale`, `up`), limbs that give a height outside (0.5, 3] m
//! (`height`: the wrong units).
//!
//! **Repaired** (and counted in the [`TrackReport`]):
//! - *gaps*: a missing keypoint (null, NaN, ±∞, or farther than 10 km) is
//!   interpolated linearly between the frames that have it when the gap
//!   lasts at most `maxGap` (default 0.5 s); a longer gap, or one at the
//!   start or end, holds the nearest frame that has it;
//! - *jitter*: each coordinate of each keypoint is smoothed by a first-order
//!   low-pass run forwards then backwards over the frames (zero phase lag;
//!   time constant `smoothing`, default 0.03 s, 0 turns it off;
//!   `α = 1 − exp(−Δt/τ)` per step, so uneven frame times are honoured),
//!   over the track extended by its reflection at each end so that a
//!   keypoint still moving there is not replayed behind (`filter.rs`);
//! - *angles beyond the body's range* are clamped into it.
//!
//! The fit is analytic per frame: the root from the middle of
//! the hips (hip height `0.530 H` above the floor point), the heading from
//! the hips' left–right direction, the trunk from the
//! shoulders, the head from the middle of the ears (Kinect: its `head`
//! joint), each arm from shoulder, elbow and wrist, each leg from hip, knee
//! and ankle (the knee bends in the thigh's sagittal plane). The height is
//! `height` or, when absent, estimated from the median length of the limbs
//! against Drillis & Contini's proportions. A body of those proportions is
//! replayed at its joints exactly (to rounding); other bodies as closely as
//! the skeleton allows. Timestamps are kept, shifted to start at 0.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::animation::{Keyframe, MAX_KEYFRAMES};
use super::body::proportion;
use super::spec::{AnimationSpec, HumanSpec, MAX_HEIGHT};
use crate::error::{FieldError, finite};

mod bvh;
mod filter;
mod fit;
mod hierarchy;
mod layout;
mod skeleton;
mod synth;

pub use bvh::{MAX_BVH_JOINTS, MAX_BVH_VALUE, MAX_FRAME_TIME};
pub use layout::{Layout, NEEDED};
pub use synth::{synthesize, synthesize_bvh};

/// A keypoint farther than this from the origin is read as missing (m).
pub const MAX_COORDINATE: f64 = 1e4;

/// How [`import`] reads and repairs a track.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct TrackOptions {
    /// `json` or `csv` (default: JSON when the text starts with `{`).
    #[serde(default)]
    pub format: Option<String>,
    /// The layout (required for CSV; for JSON, overrides the file's).
    #[serde(default)]
    pub layout: Option<String>,
    /// Body height (m; default estimated from the limbs).
    #[serde(default)]
    pub height: Option<f64>,
    /// Time constant of the jitter filter (s, ≥ 0; default 0.03).
    #[serde(default = "default_smoothing")]
    pub smoothing: f64,
    /// Longest gap filled by interpolation (s, ≥ 0; default 0.5).
    #[serde(default = "default_gap")]
    pub max_gap: f64,
    /// Metres per unit of the file (> 0, at most 1000; default 1, BVH
    /// 0.01: centimetres).
    #[serde(default)]
    pub scale: Option<f64>,
    /// The file's up axis, `z` or `y` (default `z`, BVH `y`); y-up
    /// coordinates `(x, y, z)` become `(x, −z, y)`.
    #[serde(default)]
    pub up: Option<String>,
}

fn default_smoothing() -> f64 {
    0.03
}

fn default_gap() -> f64 {
    0.5
}

impl Default for TrackOptions {
    fn default() -> Self {
        Self {
            format: None,
            layout: None,
            height: None,
            smoothing: default_smoothing(),
            max_gap: default_gap(),
            scale: None,
            up: None,
        }
    }
}

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
    /// `coco17`, `body25` or `kinect32`.
    #[serde(default)]
    pub layout: Option<String>,
    /// The frames.
    pub frames: Vec<TrackFrame>,
}

/// What [`import`] repaired.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct TrackReport {
    /// The layout read.
    pub layout: String,
    /// Frames read.
    pub frames: usize,
    /// Duration (s).
    pub duration: f64,
    /// Height used (m).
    pub height: f64,
    /// Keypoint positions filled in (interpolated or held).
    pub filled: usize,
    /// Joint angles clamped into the body's range.
    pub clamped: usize,
}

/// The result of [`import`]: the human that replays the track, and what
/// was repaired.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ImportedTrack {
    /// A `human` shape with the track as keyframes.
    pub shape: HumanSpec,
    /// What was read and repaired.
    pub report: TrackReport,
}

/// Reads a track (JSON or CSV text) and maps it onto the human skeleton.
///
/// # Errors
/// See the module docs: the field and the reason of the first refusal.
pub fn import(text: &str, options: &TrackOptions) -> Result<ImportedTrack, FieldError> {
    check_options(options)?;
    let start = text.trim_start();
    let format = match options.format.as_deref() {
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
    let axes = axes(options, format == "bvh")?;
    let (source, times, points) = match format {
        "json" => read_json(text, options.layout.as_deref(), axes)?,
        "csv" => read_csv(text, options.layout.as_deref(), axes)?,
        _ => {
            let (times, points) = bvh::read(text, axes)?;
            (Source::BVH, times, points)
        }
    };
    convert(&source, &times, points, options)
}

fn check_options(options: &TrackOptions) -> Result<(), FieldError> {
    let smoothing = finite("smoothing", options.smoothing)?;
    let max_gap = finite("maxGap", options.max_gap)?;
    if smoothing < 0.0 {
        return Err(FieldError::new("smoothing", "must be >= 0"));
    }
    if max_gap < 0.0 {
        return Err(FieldError::new("maxGap", "must be >= 0"));
    }
    if let Some(h) = options.height {
        finite("height", h)?;
        if !(h > 0.0 && h <= MAX_HEIGHT) {
            return Err(FieldError::new(
                "height",
                format!("must be in (0, {MAX_HEIGHT}] m"),
            ));
        }
    }
    Ok(())
}

/// Most metres per unit `scale` may give.
pub const MAX_SCALE: f64 = 1000.0;

fn axes(options: &TrackOptions, bvh: bool) -> Result<bvh::Axes, FieldError> {
    let scale = match options.scale {
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
    let y_up = match options.up.as_deref() {
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
    Ok(bvh::Axes { scale, y_up })
}

/// Where the frames came from: a layout's name, its keypoint names and
/// where the [`NEEDED`] joints sit among them.
struct Source {
    name: &'static str,
    names: &'static [&'static str],
    needed: [usize; 14],
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

type Frames = (Source, Vec<f64>, Vec<Vec<Option<DVec3>>>);

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

fn point(p: [f64; 3], axes: bvh::Axes) -> Option<DVec3> {
    let v = axes.apply(DVec3::from_array(p));
    (v.is_finite() && v.length() <= MAX_COORDINATE).then_some(v)
}

fn read_json(text: &str, layout: Option<&str>, axes: bvh::Axes) -> Result<Frames, FieldError> {
    let file: TrackFile = serde_path_to_error::deserialize(
        &mut serde_json::Deserializer::from_str(text),
    )
    .map_err(|e| crate::error::from_serde_path(&e.path().to_string(), &e.inner().to_string()))?;
    let name = layout
        .or(file.layout.as_deref())
        .ok_or_else(|| FieldError::new("layout", "required (coco17, body25 or kinect32)"))?;
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

fn read_csv(text: &str, layout: Option<&str>, axes: bvh::Axes) -> Result<Frames, FieldError> {
    let name = layout.ok_or_else(|| {
        FieldError::new("layout", "required for CSV (coco17, body25 or kinect32)")
    })?;
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

/// Fills the gaps of one keypoint's series; returns how many it filled.
fn fill(times: &[f64], series: &mut [Option<DVec3>], max_gap: f64) -> usize {
    let known: Vec<usize> = (0..series.len()).filter(|&k| series[k].is_some()).collect();
    let (Some(&first), Some(&last)) = (known.first(), known.last()) else {
        return 0;
    };
    let mut filled = 0;
    for k in 0..series.len() {
        if series[k].is_some() {
            continue;
        }
        let value = if k < first {
            series[first]
        } else if k > last {
            series[last]
        } else {
            let next = known[known.partition_point(|&x| x < k)];
            let prev = known[known.partition_point(|&x| x < k) - 1];
            let (a, b) = (
                series[prev].unwrap_or_default(),
                series[next].unwrap_or_default(),
            );
            let (t0, t1) = (times[prev], times[next]);
            if t1 - t0 <= max_gap {
                Some(a.lerp(b, (times[k] - t0) / (t1 - t0)))
            } else if times[k] - t0 <= t1 - times[k] {
                Some(a)
            } else {
                Some(b)
            }
        };
        series[k] = value;
        filled += 1;
    }
    filled
}

fn convert(
    source: &Source,
    times: &[f64],
    mut points: Vec<Vec<Option<DVec3>>>,
    options: &TrackOptions,
) -> Result<ImportedTrack, FieldError> {
    let needed = source.needed;
    let mut report = TrackReport {
        layout: source.name.to_owned(),
        frames: times.len(),
        duration: times[times.len() - 1] - times[0],
        ..TrackReport::default()
    };
    // Only the joints the fit reads are filtered.
    let mut joints: Vec<Vec<DVec3>> = Vec::with_capacity(needed.len());
    for &i in &needed {
        let mut series: Vec<Option<DVec3>> = points.iter().map(|f| f[i]).collect();
        if series.iter().all(Option::is_none) {
            return Err(FieldError::new(
                "frames",
                format!("keypoint \"{}\" is missing in every frame", source.names[i]),
            ));
        }
        report.filled += fill(times, &mut series, options.max_gap);
        let mut clean: Vec<DVec3> = series.into_iter().map(Option::unwrap_or_default).collect();
        filter::smooth(times, &mut clean, options.smoothing);
        joints.push(clean);
    }
    points.clear();
    let frame = |k: usize| -> [DVec3; 14] { std::array::from_fn(|s| joints[s][k]) };
    let height = match options.height {
        Some(h) => h,
        None => estimate_height(&(0..times.len()).map(frame).collect::<Vec<_>>())?,
    };
    report.height = height;
    let mut keys = Vec::with_capacity(times.len());
    let mut prev: Option<fit::Fitted> = None;
    let mut first: Option<fit::Fitted> = None;
    for (k, &t) in times.iter().enumerate() {
        let f = fit::fit(&frame(k), height, prev.as_ref());
        let clamped = f.pose.clamped();
        report.clamped += f
            .pose
            .angles
            .iter()
            .zip(&clamped.angles)
            .filter(|(a, b)| a != b)
            .count();
        let f0 = *first.get_or_insert(f);
        let back = super::body::rotation(glam::DVec3::Z, -f0.heading);
        keys.push(Keyframe {
            t: t - times[0],
            pose: clamped,
            shift: (back * (f.root - f0.root)).to_array(),
            turn: f.heading - f0.heading,
        });
        prev = Some(fit::Fitted { pose: clamped, ..f });
    }
    let f0 = first.ok_or_else(|| FieldError::new("frames", "needs at least one frame"))?;
    let shape = HumanSpec {
        position: f0.root.to_array(),
        heading: f0.heading,
        height,
        reach: 0.0,
        pose: None,
        part_sigma: None,
        vary: None,
        animation: Some(Box::new(AnimationSpec {
            keyframes: Some(keys),
            ..AnimationSpec::default()
        })),
    };
    shape.compile().map_err(|e| e.within("shape"))?;
    Ok(ImportedTrack { shape, report })
}

/// The height whose Drillis & Contini limbs match the median recorded limb
/// length.
fn estimate_height(frames: &[[DVec3; 14]]) -> Result<f64, FieldError> {
    let per =
        2.0 * (proportion::UPPER_ARM + proportion::FOREARM + proportion::THIGH + proportion::SHANK);
    let mut sums: Vec<f64> = frames
        .iter()
        .map(|j| {
            let d = |a: usize, b: usize| (j[a] - j[b]).length();
            d(0, 2) + d(2, 4) + d(1, 3) + d(3, 5) + d(6, 8) + d(8, 10) + d(7, 9) + d(9, 11)
        })
        .collect();
    sums.sort_by(f64::total_cmp);
    let h = sums[sums.len() / 2] / per;
    if !(h > 0.5 && h <= MAX_HEIGHT) {
        return Err(FieldError::new(
            "height",
            format!(
                "the limbs give a height of {h:.3} m, outside (0.5, {MAX_HEIGHT}] m: are the units metres? (give scale, metres per unit, or height)"
            ),
        ));
    }
    Ok(h)
}
