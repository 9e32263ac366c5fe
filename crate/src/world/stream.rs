//! A person sensed live: frames of keypoints pushed one at a time
//! ([`super::World::push_human_frame`]) drive a human obstacle, fitted as
//! a recorded track is ([`crate::human::track`]), and the sensing fails
//! safe when the frames stop coming.
//!
//! **The frame** ([`HumanFrame`]): `t` (s, the world's clock), `layout`
//! (`coco17`, `body25`, `kinect32`, `blazepose33`), `keypoints` (`[x, y,
//! z]` in metres, world frame, z up, the layout's count), `confidence`
//! (optional, one per keypoint in [0, 1]). Each frame becomes a keyframe of
//! the human's motion at `t` (the first frame places the person, as the
//! first frame of an imported track does); the body keeps its height and
//! takes its segment lengths from the first frame when it has none. The
//! human is then seen as any keyframed human (a scripted `motion` of the
//! obstacle is dropped: the frames place it): at the world's time less
//! the obstacle's sensing `latency`, between frames by the same cubics, so
//! a motion streamed frame by frame moves the arm exactly as the same
//! motion imported as a track (a window of the last
//! [`STREAM_WINDOW`] frames is kept).
//!
//! **Stale data** (issue: sensing that fails safe). A part's data is
//! *good* in a frame when every keypoint that places it has a confidence of
//! at least [`GOOD_CONFIDENCE`] (or no confidence is given); a keypoint
//! below it holds its last good position. When the time at which the
//! world sees the person (its time less the sensing latency) is past the
//! part's last good frame by `age`, the part may have moved anywhere a
//! person can reach in that time: its margin grows by `age ×` the speed of
//! ISO 13855 ([`HAND_SPEED`] for the hands, [`BODY_SPEED`] for the rest),
//! and the protective layer counts that growth as the part's approach
//! speed, so the arm keeps clear of the reachable region, slowing as it
//! grows and stopping when it reaches the safety distance. A part that
//! turns stale, and each doubling of its age from [`STALE_AFTER`] on, is
//! an event `staleSensing` (part, age, margin).
//!
//! **Refused** (the world unchanged): an unknown obstacle or one that is
//! not a human (`obstacleId`), `frame.t` not finite or not after the
//! previous frame's, an unknown layout (`frame.layout`), more than
//! [`MAX_FRAME_KEYPOINTS`] keypoints or not the layout's count
//! (`frame.keypoints`), a keypoint not finite or farther than
//! [`crate::parsers::track::MAX_COORDINATE`] (`frame.keypoints[3][1]`),
//! confidences not one per keypoint or outside [0, 1]
//! (`frame.confidence[2]`).

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::obstacles::ObstacleState;
use crate::dependability::EventKind;
use crate::error::{FieldError, finite};
use crate::human::track::{Fitter, joints_of};
use crate::human::{AnimationSpec, Dims, Keyframe, PART_NAMES};
use crate::parsers::track::{Layout, MAX_COORDINATE};
use crate::scenario::ShapeSpec;

/// Most keypoints a frame may carry.
pub const MAX_FRAME_KEYPOINTS: usize = 10_000;

/// Frames kept as the human's keyframes (4 s at 30 Hz: room for any
/// latency the world models, and little to copy into each state).
pub const STREAM_WINDOW: usize = 120;

/// A keypoint is good at this confidence and above (the playground maps
/// its estimator's own cut-off onto it: `calibrated` in web/keypoints.js).
pub const GOOD_CONFIDENCE: f64 = 0.5;

/// How fast a hand may move (m/s; ISO 13855's approach speed of the
/// hand and arm).
pub const HAND_SPEED: f64 = 2.0;

/// How fast the rest of the body may move (m/s; ISO 13855's walking
/// approach speed).
pub const BODY_SPEED: f64 = 1.6;

/// A part's data is stale past this age (s); its events come at each
/// doubling of the age from here.
pub const STALE_AFTER: f64 = 0.1;

/// One frame of a sensed person.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct HumanFrame {
    /// When the keypoints were seen (s, the world's clock).
    pub t: f64,
    /// `coco17`, `body25`, `kinect32` or `blazepose33`.
    pub layout: String,
    /// `[x, y, z]` (m, world frame, z up) in the layout's order.
    pub keypoints: Vec<[f64; 3]>,
    /// Per keypoint, in [0, 1] (default: every keypoint good).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub confidence: Option<Vec<f64>>,
}

/// What the world keeps of one streamed person.
#[derive(Clone, Debug)]
pub(super) struct Stream {
    fitter: Fitter,
    keys: Vec<Keyframe>,
    last_t: f64,
    /// The last good position of each keypoint of the fit (`NEEDED`).
    held: Option<[DVec3; 14]>,
    /// Per part, the time of its last good frame.
    good: [Option<f64>; PART_NAMES.len()],
    /// Per part, how many of its stale steps have been reported.
    reported: [u32; PART_NAMES.len()],
    /// Per part, how fast its margin grows now (m/s).
    pub(super) growth: [f64; PART_NAMES.len()],
    /// Per part, the age of its data now (s).
    age: [f64; PART_NAMES.len()],
}

/// The `NEEDED` joints (indices) that place each part of [`PART_NAMES`].
const PART_JOINTS: [&[usize]; 16] = [
    &[6, 7],
    &[0, 1, 6, 7],
    &[0, 1, 12, 13],
    &[12, 13],
    &[0, 2],
    &[2, 4],
    &[4],
    &[1, 3],
    &[3, 5],
    &[5],
    &[6, 8],
    &[8, 10],
    &[10],
    &[7, 9],
    &[9, 11],
    &[11],
];

/// The speed at which part `name`'s reachable region grows (m/s).
fn speed_of(name: &str) -> f64 {
    if name.ends_with("Hand") {
        HAND_SPEED
    } else {
        BODY_SPEED
    }
}

/// Checks `frame` for a stream whose previous frame was at `last`;
/// returns its layout, keypoints and per-keypoint goodness.
fn check(
    frame: &HumanFrame,
    last: Option<f64>,
) -> Result<(Layout, Vec<DVec3>, Vec<bool>), FieldError> {
    finite("t", frame.t)?;
    if let Some(p) = last.filter(|p| frame.t <= *p) {
        return Err(FieldError::new(
            "t",
            format!(
                "must be after the previous frame's ({p} s), got {}",
                frame.t
            ),
        ));
    }
    let layout = Layout::from_name(&frame.layout)?;
    let n = frame.keypoints.len();
    if n > MAX_FRAME_KEYPOINTS {
        return Err(FieldError::new(
            "keypoints",
            format!("at most {MAX_FRAME_KEYPOINTS} keypoints (got {n})"),
        ));
    }
    let want = layout.names().len();
    if n != want {
        return Err(FieldError::new(
            "keypoints",
            format!("expected {want} keypoints ({}), got {n}", layout.name()),
        ));
    }
    let mut points = Vec::with_capacity(n);
    for (k, p) in frame.keypoints.iter().enumerate() {
        for (c, x) in p.iter().enumerate() {
            crate::error::bounded(&format!("keypoints[{k}][{c}]"), *x, MAX_COORDINATE)?;
        }
        points.push(DVec3::from_array(*p));
    }
    let good = match &frame.confidence {
        None => vec![true; n],
        Some(c) if c.len() != n => {
            return Err(FieldError::new(
                "confidence",
                format!("expected one per keypoint ({n}), got {}", c.len()),
            ));
        }
        Some(c) => {
            let mut good = Vec::with_capacity(n);
            for (k, x) in c.iter().enumerate() {
                let field = format!("confidence[{k}]");
                finite(&field, *x)?;
                if !(0.0..=1.0).contains(x) {
                    return Err(FieldError::new(
                        field,
                        format!("must be in [0, 1], got {x}"),
                    ));
                }
                good.push(*x >= GOOD_CONFIDENCE);
            }
            good
        }
    };
    Ok((layout, points, good))
}

/// Takes `frame` into human obstacle `o`: returns the human's new figure
/// (for the scenario). Nothing changes when it is refused.
pub(super) fn push(o: &mut ObstacleState, frame: &HumanFrame) -> Result<ShapeSpec, FieldError> {
    let Some(human) = o.human.as_ref() else {
        return Err(FieldError::new(
            "obstacleId",
            format!("\"{}\" is not a human", o.spec.id),
        ));
    };
    let last = o.stream.as_ref().map(|s| s.last_t);
    let (layout, points, good) = check(frame, last).map_err(|e| e.within("frame"))?;
    let needed = layout.needed();
    let seen = joints_of(layout, &points);
    let fresh: [bool; 14] = std::array::from_fn(|s| good[needed[s]]);
    let mut spec = human.spec().clone();
    let mut stream = match o.stream.take() {
        Some(s) => s,
        None => {
            // The body keeps its height; its segments come from this frame
            // when it has none.
            let segments = spec
                .segments
                .unwrap_or_else(|| crate::human::measure(&[seen], spec.height));
            spec.segments = Some(segments);
            Box::new(Stream {
                fitter: Fitter::new(Dims::new(spec.height, Some(&segments)), 0.0),
                keys: Vec::new(),
                last_t: frame.t,
                held: None,
                good: [None; PART_NAMES.len()],
                reported: [0; PART_NAMES.len()],
                growth: [0.0; PART_NAMES.len()],
                age: [0.0; PART_NAMES.len()],
            })
        }
    };
    let joints: [DVec3; 14] = match stream.held {
        Some(h) => std::array::from_fn(|s| if fresh[s] { seen[s] } else { h[s] }),
        None => seen,
    };
    let mut fitter = stream.fitter.clone();
    let (key, _) = fitter.push(frame.t, &joints);
    let mut keys = stream.keys.clone();
    keys.push(key);
    if keys.len() > STREAM_WINDOW {
        keys.drain(..keys.len() - STREAM_WINDOW);
    }
    if let Some((root, heading)) = fitter.origin() {
        spec.position = root.to_array();
        spec.heading = heading;
    }
    spec.animation = Some(Box::new(AnimationSpec {
        keyframes: Some(keys.clone()),
        ..AnimationSpec::default()
    }));
    let shape = ShapeSpec::Human(spec);
    let parts = crate::scenario::primitives(&shape).map_err(|e| e.within("frame"))?;
    let compiled = super::obstacles::human_of(&shape).map_err(|e| e.within("frame"))?;
    // Accepted: nothing below can fail.
    stream.fitter = fitter;
    stream.keys = keys;
    stream.last_t = frame.t;
    stream.held = Some(joints);
    for (k, uses) in PART_JOINTS.iter().enumerate() {
        if uses.iter().all(|&s| fresh[s]) {
            stream.good[k] = Some(frame.t);
            stream.reported[k] = 0;
        }
    }
    o.stream = Some(stream);
    o.human = compiled;
    o.parts = parts;
    o.reference = crate::scenario::reference_point(&shape);
    o.spec.shape = shape.clone();
    // The frames say where the person is: a scripted motion no longer
    // moves it.
    o.spec.motion = None;
    Ok(shape)
}

impl ObstacleState {
    /// Grows each part's margin of a streamed human by its stale age at
    /// time `t` (the world's, less the sensing latency); returns the
    /// events of the parts whose stale step changed.
    pub(super) fn stale_margins(&mut self, t: f64) -> Vec<EventKind> {
        let Some(stream) = self.stream.as_mut() else {
            return Vec::new();
        };
        let seen = t - self.sensor.latency();
        let base = self.margin;
        let stale = stream.good.iter().any(|g| g.is_some_and(|g| seen > g));
        if stale && self.part_margins.is_empty() {
            self.part_margins.resize(PART_NAMES.len(), base);
        }
        let mut events = Vec::new();
        for (k, name) in PART_NAMES.iter().enumerate() {
            let age = stream.good[k].map_or(0.0, |g| (seen - g).max(0.0));
            let grow = if age > 0.0 { speed_of(name) } else { 0.0 };
            stream.growth[k] = grow;
            stream.age[k] = age;
            if let Some(m) = self.part_margins.get_mut(k) {
                *m += grow * age;
                self.margin = self.margin.max(*m);
            }
            // Steps at STALE_AFTER · 2^n.
            let step: f64 = if age >= STALE_AFTER {
                1.0 + crate::math::ln(age / STALE_AFTER) / std::f64::consts::LN_2
            } else {
                0.0
            };
            let step = step.floor() as u32;
            if step > stream.reported[k] {
                stream.reported[k] = step;
                events.push(EventKind::StaleSensing {
                    obstacle: self.spec.id.clone(),
                    part: (*name).to_owned(),
                    age,
                    margin: self.part_margins.get(k).copied().unwrap_or(base),
                });
            }
        }
        events
    }

    /// The parts of a streamed human whose data is stale now, with its
    /// age (s), by part name; `None` when none is.
    pub(super) fn stale_ages(&self) -> Option<std::collections::BTreeMap<String, f64>> {
        let s = self.stream.as_ref()?;
        let ages: std::collections::BTreeMap<String, f64> = PART_NAMES
            .iter()
            .zip(&s.age)
            .filter(|(_, a)| **a > 0.0)
            .map(|(n, a)| ((*n).to_owned(), *a))
            .collect();
        (!ages.is_empty()).then_some(ages)
    }

    /// How fast part `k`'s margin grows now (m/s; 0 unless streamed and
    /// stale): an approach speed for the protective layer.
    pub(super) fn margin_growth(&self, k: usize) -> f64 {
        self.stream
            .as_ref()
            .and_then(|s| s.growth.get(k).copied())
            .unwrap_or(0.0)
    }
}
