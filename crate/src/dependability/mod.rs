//! The dependability monitor (paper §IV): sensing errors, their propagation
//! into distances, detection of segment switches that the error can cause,
//! chattering, and time-to-collision against the transition delay.
//!
//! * **Sensing model** ([`SensorModel`]): each obstacle is seen displaced by
//!   a fixed bias drawn once per run (uniform in a ball of radius
//!   `biasBound`, the paper's `∂p_f`), a bounded error redrawn every step
//!   (uniform in a ball of radius `bound`), white Gaussian noise (`sigma`
//!   per axis) and correlated noise (first-order Gauss–Markov,
//!   `correlatedSigma`, `correlationTime`), and seen `latency` seconds late;
//!   everything is drawn from a seeded [`crate::rng::Rng`] so that a run is
//!   reproducible on every target.
//! * **Margin** ([`distance_uncertainty`]): to first order a displacement
//!   `δp` of the obstacle changes the distance by `nᵀ δp` (`n` the unit
//!   normal of the closest pair), so the distance error is bounded by
//!   `bound + biasBound` plus the Gaussian part `σ = √(sigma² +
//!   correlatedSigma²)`. The safety margin is inflated by `bound +
//!   biasBound + 3 σ` ([`GAUSSIAN_COVERAGE`] standard deviations) plus
//!   `latency × the obstacle's speed`.
//! * **Propagation** ([`propagate`]): the covariance of the sensed position
//!   ([`SensorModel::covariance`]) carried to first order through the
//!   differentiable model to the standard deviation of each control point's
//!   distance, of its witness's DH values `a'`, `d'`, of its repulsion and
//!   of the joint command (in [`crate::world::WorldState`] and the trace).
//! * **Switch risk** ([`switch_probability`]): from the per-segment distance
//!   distributions of each obstacle, the probability that the segment
//!   sensed as closest differs from the ideal one;
//!   [`EventKind::SwitchRisk`] is raised when it exceeds `switchRisk`.
//!   Self-collision pairs involve no sensing and have none.
//! * **Chattering** ([`SwitchCounter`]): switches of each control point
//!   are counted over a sliding window, in every selection mode: a jump of
//!   an obstacle's closest point to another segment (`perObstacle`), a jump
//!   of a pair's closest point along its segment farther than the jump
//!   threshold (`pairs` and self-collision pairs, whose segment is fixed),
//!   a change of the obstacle a pinned point answers (`pinned`); more
//!   than `maxSwitches` in `switchWindow` seconds is chattering, and the configured policy applies:
//!   `stop` (joint velocities brought to zero with bounded deceleration while
//!   the chattering lasts) or `lock` (the control point held on its current
//!   segment for `lockTime`).
//! * **Time to collision**: at the true closest point (the witness the
//!   control point is heading for, not where it travels), the clearance
//!   over the closing speed of the arm's material point there and the
//!   obstacle (from their motions, never from the sensing noise; low-pass
//!   filtered). While the obstacle closes in, it is compared with the time
//!   the transition still needs plus the time the joints need to brake;
//!   when it is shorter, [`EventKind::TransitionTooSlow`] is raised and the
//!   protective layer scales the arm's allowed approach speed towards that
//!   obstacle by `time to collision / (remaining + braking)` (the event
//!   says by how much). The arm's own approach to a still obstacle is left
//!   to the guards, which slow it as the clearance shrinks.
//!
//! Every such event goes into the trace with its time ([`Event`]).

use std::collections::VecDeque;

use serde::{Deserialize, Serialize};

use crate::error::{FieldError, positive};

mod events;
pub mod propagate;
mod sensing;

pub use events::{Event, EventKind};
pub use propagate::{Covariance, PointSigma, normal_cdf, switch_probability};
pub use sensing::{DEFAULT_CORRELATION_TIME, SensingSpec, SensorModel, distance_uncertainty};

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
    /// Probability of a segment switch caused by the sensing error above
    /// which `switchRisk` is raised (in (0, 1]; default 0.05; see
    /// [`propagate`]).
    pub switch_risk: f64,
}

impl Default for DependabilityConfig {
    fn default() -> Self {
        Self {
            switch_window: 0.5,
            max_switches: 3,
            on_chattering: ChatteringPolicy::Stop,
            lock_time: 1.0,
            max_deceleration: 10.0,
            switch_risk: 0.05,
        }
    }
}

impl DependabilityConfig {
    /// Checks every value.
    ///
    /// # Errors
    /// `switchWindow: must be > 0`, `lockTime: …`, `maxDeceleration: …`,
    /// `switchRisk: must be in (0, 1]`.
    pub fn validate(&self) -> Result<(), FieldError> {
        positive("switchWindow", self.switch_window)?;
        positive("lockTime", self.lock_time)?;
        positive("maxDeceleration", self.max_deceleration)?;
        if !(self.switch_risk > 0.0 && self.switch_risk <= 1.0) {
            return Err(FieldError::new("switchRisk", "must be in (0, 1]"));
        }
        Ok(())
    }
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
}
