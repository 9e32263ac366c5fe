//! What a study reads from a [`World`] after each step, without building a
//! [`super::WorldState`]: the true smallest clearance, how fast the joints
//! move and how much time the transitions under way have left before a
//! collision.

use serde::Serialize;

use super::World;
use crate::avoidance::limits::braking_time;

/// A pair the protective layer guarded at the last step (see
/// [`World::guarded`]).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct GuardedPair {
    /// Obstacle id (`self:<link>` for two links of the arm).
    pub obstacle: String,
    /// The human part, as `id:part` (absent for other obstacles).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub part: Option<String>,
    /// Skeleton segment of the arm's side.
    pub segment: usize,
    /// Clearance, sensing margin subtracted (m).
    pub distance: f64,
    /// The sensing margin subtracted (m): the obstacle's, or for a human
    /// with `partSigma` its part's own (0 for a self pair).
    pub margin: f64,
    /// How fast the obstacle's nearest part closes in along the pair's
    /// normal (m/s, positive approaching): a reaching hand's own speed,
    /// not its body's.
    pub approach_speed: f64,
    /// The protective separation distance (m): the safety distance plus
    /// the room the part covers while the arm reacts and brakes,
    /// `s + max(v, 0) (T_r + T_s)` (ISO/TS 15066's form, the arm's own
    /// stopping handled by the guard).
    pub protective_distance: f64,
}

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

/// The body of [`World::probe`].
pub(super) fn probe(w: &World) -> StepProbe {
    let joint_speed = w
        .state
        .motion
        .qdot
        .iter()
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    StepProbe {
        min_clearance: w.data.readout.min_clearance,
        joint_speed,
        transition_slack: transition_slack(w),
    }
}

/// The body of [`World::guarded`].
pub(super) fn guarded(w: &World) -> Vec<GuardedPair> {
    let p = w.model.scenario.controller.protective;
    let dt = if w.data.propagation.dt > 0.0 {
        w.data.propagation.dt
    } else {
        w.model.scenario.dt
    };
    let reach = p.reaction_time + braking_time(&w.model.robot, &w.state.motion, dt);
    w.data
        .guard
        .pairs
        .iter()
        .map(|g| GuardedPair {
            obstacle: g.obstacle.map_or_else(
                || format!("w:{}", w.data.skeleton.segments[g.segment].link),
                |o| w.state.sensed.obstacles[o].spec.id.clone(),
            ),
            part: g.part.and_then(|id| w.state.sensed.scene_part_name(id)),
            segment: g.segment,
            distance: g.distance,
            margin: match (g.obstacle, g.part) {
                (Some(o), Some(id)) => w
                    .state
                    .sensed
                    .part_index
                    .get(id)
                    .map_or(w.state.sensed.obstacles[o].margin, |&k| {
                        w.state.sensed.obstacles[o].part_margin(k)
                    }),
                (Some(o), None) => w.state.sensed.obstacles[o].margin,
                _ => 0.0,
            },
            approach_speed: g.obstacle_speed,
            protective_distance: p.safety_distance + g.obstacle_speed.max(0.0) * reach,
        })
        .collect()
}

/// The step's smallest time to collision (as the monitor computed it)
/// minus the longest time a transition under way still needs. With
/// one active control point this is that point's own margin; with
/// several it is a lower bound of every travelling point's margin
/// (the smallest time to collision may belong to another point).
fn transition_slack(w: &World) -> Option<f64> {
    let remaining = w
        .state
        .trackers
        .values()
        .map(|tr| tr.mover.remaining())
        .fold(0.0_f64, f64::max);
    let ttc = w.data.readout.time_to_collision?;
    (remaining > 0.0).then_some(ttc - remaining)
}
