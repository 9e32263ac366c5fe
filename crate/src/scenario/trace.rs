//! What a simulation returns: a [`Trace`] of [`Sample`]s with their control
//! points, and the events.

use serde::{Deserialize, Serialize};

use crate::dependability::{Event, PointSigma};

/// One control point in a trace sample.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct TracePoint {
    /// Position (m).
    pub position: [f64; 3],
    /// Link (1-based).
    pub link: usize,
    /// DH value `d'` (m).
    pub d: f64,
    /// DH value `a'` (m).
    pub a: f64,
    /// Id of the obstacle it answers.
    pub obstacle: String,
    /// Measured clearance (m).
    pub distance: f64,
    /// First-order standard deviations from the sensing error (absent when
    /// the obstacle is sensed exactly).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma: Option<PointSigma>,
}

/// One sample of a trace.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct Sample {
    /// Time (s).
    pub t: f64,
    /// Joint values.
    pub q: Vec<f64>,
    /// Joint velocities at `t` (rad/s or m/s).
    #[serde(default)]
    pub qdot: Vec<f64>,
    /// Smallest clearance between the arm and any obstacle (or between
    /// non-adjacent links) within reach (m; `null` when none is).
    pub min_clearance: Option<f64>,
    /// Clearance (m) between the arm and each obstacle at `t` (true pose),
    /// by id, within reach or not; self pairs are not in it (negative:
    /// overlap). "How close did the arm come to the person" is the minimum
    /// of `clearances["person"]` over the samples.
    #[serde(default)]
    pub clearances: std::collections::BTreeMap<String, f64>,
    /// Active control points.
    pub control_points: Vec<TracePoint>,
    /// Standard deviation of each joint's command from the sensing errors
    /// (absent when every obstacle is sensed exactly).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub command_sigma: Option<Vec<f64>>,
}

/// What [`crate::world::simulate`] returns.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Trace {
    /// Samples, every `sampleEvery` steps from `t = 0`, and the last at
    /// `t = duration`.
    pub samples: Vec<Sample>,
    /// Events in time order.
    pub events: Vec<Event>,
}
