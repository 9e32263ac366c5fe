//! The event log of the monitor and the controller.

use serde::{Deserialize, Serialize};

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
    /// The sensing error can switch the control point to another segment
    /// with a probability above `switchRisk` (raised when it starts).
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
        /// Probability that the closest segment as sensed differs from
        /// the ideal one ([`super::switch_probability`]).
        probability: f64,
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
        /// Segment held (for a pinned point: the index of the obstacle it
        /// keeps answering).
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
    /// At the start the arm overlaps something (its volume and an
    /// obstacle's, or two of its own links): the deepest pair, named by the
    /// robot's link names where it has them. A static or receding obstacle
    /// is backed out of at `protective.withdrawSpeed`.
    StartContact {
        /// Obstacle concerned (`self:<link>` for two links of the arm).
        obstacle: String,
        /// The arm's link in the pair (its URDF name for an imported robot).
        link: String,
        /// Clearance of the pair (m, ≤ 0).
        distance: f64,
        /// Pairs overlapping at the start.
        pairs: usize,
    },
    /// A lock ended.
    Unlock {
        /// Obstacle concerned.
        obstacle: String,
    },
    /// The time to collision at the true closest point is below the time
    /// the control point's transition still needs, plus the joints' braking
    /// time, while the obstacle itself closes in (raised when it starts):
    /// the protective layer slows the approach to the obstacle. (With the
    /// protective layer off, the arm's own approach to a still obstacle
    /// counts too, without the braking time.)
    TransitionTooSlow {
        /// Obstacle concerned.
        obstacle: String,
        /// Time to collision (s).
        time_to_collision: f64,
        /// Remaining transition time (s).
        remaining: f64,
        /// Time the joints need to come to rest (s; counted when the
        /// obstacle closes in, else 0).
        braking: f64,
        /// Factor applied to the arm's allowed approach speed towards the
        /// obstacle: `time to collision / (remaining + braking)`.
        slowdown: f64,
    },
    /// A streamed person's part has had no good frame for `age` seconds
    /// (raised when it turns stale, then at each doubling of the age):
    /// its margin has grown to `margin` at a person's speed (ISO 13855),
    /// which slows the arm and, once it reaches the safety distance, stops
    /// it.
    StaleSensing {
        /// Obstacle concerned.
        obstacle: String,
        /// The part (`leftHand`).
        part: String,
        /// Time since its last good frame, as the world sees it (s).
        age: f64,
        /// The part's margin now (m).
        margin: f64,
    },
}
