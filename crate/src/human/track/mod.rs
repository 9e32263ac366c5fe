//! Recorded motion mapped onto the articulated human: a keypoint track
//! (JSON, CSV) or BVH motion capture, read by [`crate::parsers::track`]
//! (formats, layouts and what the reader refuses are described there), is
//! repaired and fitted frame by frame, and [`import`] returns a human
//! ([`HumanSpec`]) whose keyframes replay it.
//!
//! **Refused** (the scene is left as it was): whatever the reader refuses
//! (see [`crate::parsers::track`]), a joint the fit needs that is missing in
//! every frame (`frames`), bad options (`smoothing`, `maxGap`, `height`),
//! limbs that give a height outside (0.5, 3] m (`height`: the wrong units).
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
//! joint), each shoulder girdle (elevation, protraction) from the recorded
//! shoulder, turned further towards the wrist when the arm would not reach
//! it, each arm from shoulder, elbow and wrist, each leg from hip, knee
//! and ankle (the knee bends in the thigh's sagittal plane). The height is
//! `height` or, when absent, estimated from the median length of the limbs
//! against Drillis & Contini's proportions. A body of those proportions is
//! replayed at its joints exactly (to rounding); other bodies as closely as
//! the skeleton allows. Timestamps are kept, shifted to start at 0.

use std::collections::BTreeMap;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::body::proportion;
use super::segments::{Dims, Segments, measure};
use super::spec::{AnimationSpec, HumanSpec, MAX_HEIGHT};
use crate::error::{FieldError, finite};
use crate::parsers::track::{self, Source};

mod accuracy;
mod filter;
mod fit;
mod synth;

pub use accuracy::{JointError, body_joints};
pub(crate) use fit::{Fitter, joints_of};
pub use synth::{synthesize, synthesize_bvh};

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
    /// The subject's segment lengths, measured from the recording.
    pub segments: Option<Segments>,
    /// Per joint (`leftWrist`, `rightAnkle`, …): how far the body's joint
    /// is from the recorded one (m; the recording as repaired).
    pub fit_error: BTreeMap<String, JointError>,
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

/// Reads a track (JSON, CSV or BVH text, [`crate::parsers::track`]) and
/// maps it onto the articulated human.
///
/// # Errors
/// See the module docs: the field and the reason of the first refusal.
pub fn import(text: &str, options: &TrackOptions) -> Result<ImportedTrack, FieldError> {
    check_options(options)?;
    let (source, times, points) = track::read(
        text,
        options.format.as_deref(),
        options.layout.as_deref(),
        options.scale,
        options.up.as_deref(),
    )?;
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
    let frames: Vec<[DVec3; 14]> = (0..times.len())
        .map(|k| std::array::from_fn(|s| joints[s][k]))
        .collect();
    drop(joints);
    let height = match options.height {
        Some(h) => h,
        None => estimate_height(&frames)?,
    };
    report.height = height;
    let segments = measure(&frames, height);
    let dims = Dims::new(height, Some(&segments));
    report.segments = Some(segments);
    let mut keys = Vec::with_capacity(times.len());
    let mut fitter = fit::Fitter::new(dims, times[0]);
    for (k, &t) in times.iter().enumerate() {
        let (key, clamped) = fitter.push(t, &frames[k]);
        report.clamped += clamped;
        keys.push(key);
    }
    let f0 = fitter
        .origin()
        .ok_or_else(|| FieldError::new("frames", "needs at least one frame"))?;
    let shape = HumanSpec {
        position: f0.0.to_array(),
        heading: f0.1,
        height,
        segments: Some(segments),
        reach: 0.0,
        pose: None,
        part_sigma: None,
        vary: None,
        animation: Some(Box::new(AnimationSpec {
            keyframes: Some(keys),
            ..AnimationSpec::default()
        })),
    };
    let human = shape.compile().map_err(|e| e.within("shape"))?;
    report.fit_error = accuracy::fit_error(&human, times, &frames);
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
