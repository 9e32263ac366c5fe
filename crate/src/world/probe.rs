//! What a study reads from a [`World`] after each step, without building a
//! [`super::WorldState`]: the true smallest clearance, how fast the joints
//! move and how much time the transitions under way have left before a
//! collision.

use super::World;

/// A few numbers of the last step (see [`World::probe`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepProbe {
    /// Smallest true clearance of the last step (m), `None` when nothing
    /// was within reach (the same number as [`super::WorldState`]'s).
    pub min_clearance: Option<f64>,
    /// Largest joint speed after the step (rad/s or m/s).
    pub joint_speed: f64,
    /// The step's smallest time to collision minus the longest remaining
    /// transition time (s), while a transition is under way and something
    /// closes in; `None` otherwise. Negative: a transition cannot end
    /// before the collision (the monitor's `transitionTooSlow` also asks
    /// for the braking time when the obstacle itself closes in).
    pub transition_slack: Option<f64>,
}

impl World {
    /// The numbers a Monte Carlo study keeps of the last step, read from
    /// the world without building its state.
    #[must_use]
    pub fn probe(&self) -> StepProbe {
        let joint_speed = self.motion.qdot.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        StepProbe {
            min_clearance: self.min_clearance,
            joint_speed,
            transition_slack: self.transition_slack(),
        }
    }

    /// The step's smallest time to collision (as the monitor computed it)
    /// minus the longest time a transition under way still needs. With
    /// one active control point this is that point's own margin; with
    /// several it is a lower bound of every travelling point's margin
    /// (the smallest time to collision may belong to another point).
    fn transition_slack(&self) -> Option<f64> {
        let remaining = self
            .trackers
            .values()
            .map(|tr| tr.mover.remaining())
            .fold(0.0_f64, f64::max);
        let ttc = self.time_to_collision?;
        (remaining > 0.0).then_some(ttc - remaining)
    }
}
