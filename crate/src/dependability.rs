//! The dependability monitor (paper §IV): sensing errors, their propagation
//! into distances, detection of segment switches that the error can cause,
//! chattering, and time-to-collision against the transition delay.
//!
//! * **Sensing model** ([`SensorModel`]): each obstacle is seen displaced by
//!   a bounded error (uniform in a ball of radius `bound`) plus Gaussian
//!   noise (`sigma` per axis), drawn from a seeded [`Rng`] so that a run is
//!   reproducible on every target.
//! * **Propagation** ([`distance_uncertainty`]): to first order a
//!   displacement `δp` of the obstacle changes the distance by `nᵀ δp`
//!   (`n` the unit normal of the closest pair), so the distance error is
//!   bounded by `bound` and has standard deviation `sigma`. The safety margin
//!   is inflated by `bound + 3 sigma` ([`GAUSSIAN_COVERAGE`] standard
//!   deviations).
//! * **Switch risk**: if another part of the skeleton is within twice that
//!   margin of the closest one, an error inside the region can make the
//!   control point switch segment ([`EventKind::SwitchRisk`]).
//! * **Chattering** ([`SwitchCounter`]): segment switches of each control
//!   point are counted over a sliding window; more than `maxSwitches` in
//!   `switchWindow` seconds is chattering, and the configured policy applies:
//!   `stop` (joint velocities brought to zero with bounded deceleration while
//!   the chattering lasts) or `lock` (the control point held on its current
//!   segment for `lockTime`).
//! * **Time to collision**: distance over closing speed, compared with the
//!   time a transition still needs ([`EventKind::TransitionTooSlow`]).
//!
//! Every such event goes into the trace with its time ([`Event`]).

use std::collections::VecDeque;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::error::{FieldError, non_negative, positive};
use crate::rng::Rng;

/// Standard deviations of Gaussian noise added to the safety margin.
pub const GAUSSIAN_COVERAGE: f64 = 3.0;

/// What to do when a control point chatters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub enum ChatteringPolicy {
    /// Bring the joints to rest with bounded deceleration (default).
    #[default]
    Stop,
    /// Hold the control point on its current segment for `lockTime`.
    Lock,
}

/// Settings of the monitor (scenario field `dependability`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields, default)]
pub struct DependabilityConfig {
    /// Length of the sliding window in which switches are counted (s, > 0;
    /// default 0.5).
    pub switch_window: f64,
    /// Largest number of switches allowed in the window (default 3).
    pub max_switches: u32,
    /// Policy on chattering (default `stop`).
    pub on_chattering: ChatteringPolicy,
    /// How long a `lock` holds (s, > 0; default 1).
    pub lock_time: f64,
    /// Largest joint deceleration of a `stop` (rad/s² or m/s², > 0;
    /// default 10); a stop never exceeds the joints' own acceleration and
    /// jerk limits either (category 2: controlled, then held).
    pub max_deceleration: f64,
}

impl Default for DependabilityConfig {
    fn default() -> Self {
        Self {
            switch_window: 0.5,
            max_switches: 3,
            on_chattering: ChatteringPolicy::Stop,
            lock_time: 1.0,
            max_deceleration: 10.0,
        }
    }
}

impl DependabilityConfig {
    /// Checks every value.
    ///
    /// # Errors
    /// `switchWindow: must be > 0`, `lockTime: …`, `maxDeceleration: …`.
    pub fn validate(&self) -> Result<(), FieldError> {
        positive("switchWindow", self.switch_window)?;
        positive("lockTime", self.lock_time)?;
        positive("maxDeceleration", self.max_deceleration)?;
        Ok(())
    }
}

/// Sensing error of one obstacle (scenario field `sensing`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct SensingSpec {
    /// Bound of the position error (m, ≥ 0; default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bound: Option<f64>,
    /// Standard deviation of Gaussian noise per axis (m, ≥ 0; default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma: Option<f64>,
    /// Seed of the noise (default: 1 + the obstacle's index).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
}

impl SensingSpec {
    /// Checks the values.
    ///
    /// # Errors
    /// `bound: must be ≥ 0`, `sigma: …`.
    pub fn validate(&self) -> Result<(), FieldError> {
        if let Some(b) = self.bound {
            non_negative("bound", b)?;
        }
        if let Some(s) = self.sigma {
            non_negative("sigma", s)?;
        }
        Ok(())
    }
}

/// The error model of one sensed obstacle, with its own random stream.
#[derive(Clone, Debug)]
pub struct SensorModel {
    bound: f64,
    sigma: f64,
    rng: Rng,
}

impl SensorModel {
    /// A model with error bound `bound` and Gaussian `sigma` (both m),
    /// seeded with `seed`.
    #[must_use]
    pub fn new(bound: f64, sigma: f64, seed: u64) -> Self {
        Self {
            bound: bound.max(0.0),
            sigma: sigma.max(0.0),
            rng: Rng::new(seed),
        }
    }

    /// Whether the obstacle is sensed exactly.
    #[must_use]
    pub fn is_exact(&self) -> bool {
        self.bound == 0.0 && self.sigma == 0.0
    }

    /// The next sensing error (m): uniform in the ball of radius `bound`
    /// plus Gaussian noise.
    pub fn sample(&mut self) -> DVec3 {
        let mut e = DVec3::ZERO;
        if self.bound > 0.0 {
            let v = loop {
                let v = self.rng.vec3(1.0);
                if v.length_squared() <= 1.0 {
                    break v;
                }
            };
            e += v * self.bound;
        }
        if self.sigma > 0.0 {
            e += self.sigma * DVec3::new(self.rng.normal(), self.rng.normal(), self.rng.normal());
        }
        e
    }

    /// The margin this error adds to a distance (m): see
    /// [`distance_uncertainty`].
    #[must_use]
    pub fn margin(&self) -> f64 {
        distance_uncertainty(DVec3::Z, self.bound, self.sigma)
    }
}

/// First-order propagation of an obstacle position error into the distance
/// along the unit normal `normal` of the closest pair: `|δd| ≤ |n| bound`
/// for the bounded part, `σ_d = |n| σ` for isotropic Gaussian noise; the
/// result is the inflated safety margin `|n| (bound + 3 σ)` (m).
#[must_use]
pub fn distance_uncertainty(normal: DVec3, bound: f64, sigma: f64) -> f64 {
    let g = normal.length();
    let g = if g.is_finite() { g } else { 1.0 };
    g * (bound + GAUSSIAN_COVERAGE * sigma)
}

/// Switch times of one control point over a sliding window.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SwitchCounter {
    times: VecDeque<f64>,
}

impl SwitchCounter {
    /// Records a switch at time `t` and forgets switches older than
    /// `window`; returns the count in the window.
    pub fn record(&mut self, t: f64, window: f64) -> usize {
        self.times.push_back(t);
        self.count(t, window)
    }

    /// The number of switches in `(t − window, t]`.
    pub fn count(&mut self, t: f64, window: f64) -> usize {
        while self.times.front().is_some_and(|&s| s <= t - window) {
            self.times.pop_front();
        }
        self.times.len()
    }

    /// Forgets every switch.
    pub fn clear(&mut self) {
        self.times.clear();
    }
}

/// Time to collision (s) from a distance (m) and the rate at which it
/// shrinks (m/s); infinite when the distance does not shrink.
#[must_use]
pub fn time_to_collision(distance: f64, closing_speed: f64) -> f64 {
    if closing_speed > 1e-9 && distance.is_finite() {
        (distance.max(0.0)) / closing_speed
    } else {
        f64::INFINITY
    }
}

/// One entry of the trace's event log.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Event {
    /// Simulation time (s).
    pub t: f64,
    /// What happened.
    #[serde(flatten)]
    pub kind: EventKind,
}

/// What happened (the `kind` field of a trace event).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(
    tag = "kind",
    rename_all = "camelCase",
    rename_all_fields = "camelCase"
)]
#[non_exhaustive]
pub enum EventKind {
    /// The selected point of a control point moved to another segment,
    /// farther along the skeleton than the jump threshold.
    SegmentSwitch {
        /// Obstacle the control point answers (empty for pinned points).
        obstacle: String,
        /// Previous segment.
        from: usize,
        /// New segment.
        to: usize,
    },
    /// A control point started travelling along the skeleton.
    TransitionStart {
        /// Obstacle the control point answers.
        obstacle: String,
        /// Segment it leaves.
        from: usize,
        /// Segment it goes to.
        to: usize,
        /// Planned duration (s).
        duration: f64,
        /// Whether it replaced a transition under way.
        replan: bool,
    },
    /// A control point arrived.
    TransitionEnd {
        /// Obstacle the control point answers.
        obstacle: String,
        /// Segment it arrived on.
        segment: usize,
    },
    /// The sensing error region can switch the control point to another
    /// segment (raised when it starts).
    SwitchRisk {
        /// Obstacle concerned.
        obstacle: String,
        /// Closest segment.
        segment: usize,
        /// The other segment within reach of the error.
        alternative: usize,
        /// Difference of their distances (m).
        gap: f64,
        /// Inflated margin of the obstacle (m).
        margin: f64,
    },
    /// More than `maxSwitches` segment switches in `switchWindow`.
    Chattering {
        /// Obstacle concerned.
        obstacle: String,
        /// Switches counted in the window.
        switches: usize,
    },
    /// The robot is being stopped.
    Stop {
        /// Why.
        reason: String,
    },
    /// The robot resumes after a stop.
    Resume,
    /// A control point is held on one segment.
    Lock {
        /// Obstacle concerned.
        obstacle: String,
        /// Segment held.
        segment: usize,
        /// Until when (s).
        until: f64,
    },
    /// The protective layer cannot keep a pair's approach within what the
    /// arm can stop from (the obstacle closes in faster than the arm can
    /// retreat, or the arm is squeezed): the arm is stopped before contact.
    Unavoidable {
        /// Obstacle concerned (`self:<link>` for a self-collision pair).
        obstacle: String,
        /// Skeleton segment of the pair.
        segment: usize,
        /// Clearance of the pair (m).
        distance: f64,
        /// How much faster than allowed the pair closes in (m/s).
        excess: f64,
    },
    /// A lock ended.
    Unlock {
        /// Obstacle concerned.
        obstacle: String,
    },
    /// The time to collision is below the time the control point's
    /// transition still needs (raised when it starts).
    TransitionTooSlow {
        /// Obstacle concerned.
        obstacle: String,
        /// Time to collision (s).
        time_to_collision: f64,
        /// Remaining transition time (s).
        remaining: f64,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counter_forgets_old_switches() {
        let mut c = SwitchCounter::default();
        assert_eq!(c.record(0.0, 0.5), 1);
        assert_eq!(c.record(0.2, 0.5), 2);
        assert_eq!(c.record(0.6, 0.5), 2);
        assert_eq!(c.count(1.2, 0.5), 0);
    }

    #[test]
    fn bounded_error_stays_in_its_ball() {
        let mut m = SensorModel::new(0.01, 0.0, 7);
        for _ in 0..1000 {
            assert!(m.sample().length() <= 0.01);
        }
        assert!((m.margin() - 0.01).abs() < 1e-15);
    }
}
