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
    /// Clearance (m) between the arm at `q` and each obstacle at its true
    /// pose at `t` (a human posed by its animation or track then), by id,
    /// within reach or not; self pairs are not in it (negative: overlap). "How close did the arm come to the person" is the minimum
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

/// How a trace's motion compares with the robot's own limits (the
/// figures the README and the reach benchmark quote).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct MotionAudit {
    /// Peak `|q̇| / maxVelocity` over joints and samples (first differences
    /// of the sampled `q`).
    pub velocity: f64,
    /// Peak `|q̈| / maxAcceleration` (second differences).
    pub acceleration: f64,
    /// Peak `|q⃛| / maxJerk` (third differences).
    pub jerk: f64,
    /// Smallest clearance (m; `+∞` when nothing was ever within reach).
    pub clearance: f64,
    /// A contact (clearance ≤ 0) that began while a joint turned faster
    /// than 0.01 rad/s: the time it began.
    pub moving_contact: Option<f64>,
    /// Peak `|τ| / maxTorque` with `τ = M q̈ + C q̇ + g` from the sampled
    /// `q` ([`super::audit_torque`]); `None` for a robot without inertial
    /// data.
    pub torque: Option<f64>,
}

impl MotionAudit {
    /// Whether every ratio is within its limit (with the rounding of the
    /// finite differences) and no contact began while the arm moved.
    #[must_use]
    pub fn admissible(&self) -> bool {
        self.velocity <= 1.0 + 1e-9
            && self.acceleration <= 1.0 + 1e-6
            && self.jerk <= 1.0 + 1e-6
            && self.moving_contact.is_none()
            && self.torque.is_none_or(|t| t <= 1.0 + 1e-6)
    }
}

/// The [`MotionAudit`] of `trace` (sampled at every step for exact
/// accelerations, jerks and torques) against `robot`'s joint limits (the
/// torque limits when its rows carry inertial data).
#[must_use]
pub fn audit(robot: &crate::kinematics::Robot, trace: &Trace) -> MotionAudit {
    let s = &trace.samples;
    let mut out = MotionAudit {
        clearance: f64::INFINITY,
        ..MotionAudit::default()
    };
    let (mut prev_v, mut prev_a): (Option<Vec<f64>>, Option<Vec<f64>>) = (None, None);
    // A contact already there in the first sample did not begin in this
    // trace.
    let mut touching = s
        .first()
        .and_then(|x| x.min_clearance)
        .is_some_and(|c| c <= 0.0);
    if let Some(c) = s.first().and_then(|x| x.min_clearance) {
        out.clearance = c;
    }
    for k in 1..s.len() {
        let h = s[k].t - s[k - 1].t;
        let v: Vec<f64> = s[k]
            .q
            .iter()
            .zip(&s[k - 1].q)
            .map(|(a, b)| (a - b) / h)
            .collect();
        let mut a = None;
        for (vi, j) in v.iter().zip(&robot.joints) {
            out.velocity = out.velocity.max(vi.abs() / j.max_velocity);
        }
        if let Some(pv) = &prev_v {
            let acc: Vec<f64> = v.iter().zip(pv).map(|(x, y)| (x - y) / h).collect();
            for (i, j) in robot.joints.iter().enumerate() {
                out.acceleration = out.acceleration.max(acc[i].abs() / j.max_acceleration);
                if let Some(pa) = &prev_a {
                    out.jerk = out.jerk.max(((acc[i] - pa[i]) / h).abs() / j.max_jerk);
                }
            }
            a = Some(acc);
        }
        if let Some(c) = s[k].min_clearance {
            out.clearance = out.clearance.min(c);
            let fastest = v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            if c <= 0.0 && !touching && fastest > 0.01 && out.moving_contact.is_none() {
                out.moving_contact = Some(s[k].t);
            }
            touching = c <= 0.0;
        } else {
            touching = false;
        }
        prev_v = Some(v);
        prev_a = a;
    }
    out.torque = crate::dynamics::Dynamics::from_robot(robot.clone())
        .ok()
        .map(|d| super::audit_torque(&d, trace));
    out
}
