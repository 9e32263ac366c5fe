//! What a study reads from a [`World`] after each step, without building a
//! [`super::WorldState`]: the true smallest clearance, how fast the joints
//! move and how much time the transitions under way have left before a
//! collision.

use super::World;
use crate::avoidance::selection::Key;
use crate::dependability::time_to_collision;

/// A few numbers of the last step (see [`World::probe`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepProbe {
    /// Smallest true clearance of the last step (m), `None` when nothing
    /// was within reach (the same number as [`super::WorldState`]'s).
    pub min_clearance: Option<f64>,
    /// Largest joint speed after the step (rad/s or m/s).
    pub joint_speed: f64,
    /// Smallest `time to collision − remaining transition time` (s) over
    /// the control points travelling along the skeleton with something
    /// closing in on them; negative exactly when the monitor finds the
    /// transition too slow (`transitionTooSlow`). `None` when no such
    /// point.
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

    /// The time to collision of each travelling control point, as the
    /// monitor computed it in the last step (its filtered closing speed
    /// and its clearance less its obstacle's margin), minus the time its
    /// transition still needs. The active points of the last step are the
    /// trackers in key order (a pinned key with no pinned point skipped).
    fn transition_slack(&self) -> Option<f64> {
        let pinned = &self.scenario.controller.pinned;
        let trackers = self
            .trackers
            .iter()
            .filter(|(k, _)| !matches!(k, Key::Pinned(p) if pinned.get(*p).is_none()));
        let mut worst: Option<f64> = None;
        for ((key, tr), point) in trackers.zip(&self.points) {
            let remaining = tr.mover.remaining();
            let Some(closing) = tr.closing else { continue };
            if remaining <= 0.0 {
                continue;
            }
            let owner = match key {
                Key::Pinned(_) => self
                    .obstacles
                    .iter()
                    .position(|o| o.spec.id == point.obstacle),
                _ => tr.owner,
            };
            let margin = owner.map_or(0.0, |o| self.obstacles[o].margin);
            let ttc = time_to_collision(point.distance - margin, closing);
            if ttc.is_finite() {
                let slack = ttc - remaining;
                worst = Some(worst.map_or(slack, |w| w.min(slack)));
            }
        }
        worst
    }
}
