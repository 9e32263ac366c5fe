//! Smooth control-point transitions along the skeleton (paper §III-B, fig. 5).
//!
//! A control point sits on the skeleton: on segment `s` at fraction `t`
//! ([`SkeletonPoint`]). Each segment is the range of one DH value of one row
//! (`d_i` or `a_i`, or the `a` extension behind a joint), so moving along a
//! segment changes exactly one DH value, linearly in `t`.
//!
//! When the selected point moves to another segment, or jumps along the
//! skeleton by more than a threshold, the active point does not jump: a
//! [`Transition`] carries it through the nodes between the two segments
//! ([`route`]), one leg per segment, in the order in which they are met, each
//! leg over a configurable time per DH value (the paper's 0.1 s).
//!
//! # Why quintic legs
//!
//! The paper asks for the DH values to vary "with continuity and in the right
//! sequence", and suggests spline interpolation "for specifying values of the
//! higher-order derivatives of DH values": their rates and accelerations enter
//! `ṗ = J_θ θ̇ + J_a ȧ + J_d ḋ` (eq. 3) and its derivative (second-order
//! CLIK), so a jump in `ä` or `d̈` is a jump in the commanded acceleration. A
//! DH value changes only during its own leg, and the next one may only start
//! once it has stopped, so every leg must end at rest *to second order*: with
//! zero rate and zero acceleration. A cubic can match position and rate at
//! both ends but not acceleration, so a rest-to-rest cubic starts and ends
//! with an acceleration step (`±6 h / T²`). Each leg here is therefore a
//! quintic in time, the lowest degree that meets position, rate and
//! acceleration at both ends:
//!
//! - legs after the first go from rest at one node to rest at the next,
//!   `t(u) = t₀ + h (10u³ − 15u⁴ + 6u⁵)`, `u = τ / T`: monotone (no dip),
//!   peak rate `15/8 · h/T` at mid-leg, peak acceleration `10/√3 · h/T²`,
//!   bounded jerk (`60 h / T³` at the ends);
//! - the first leg goes from the point's current fraction, rate *and*
//!   acceleration to rest at its node, so a re-plan from a moving point
//!   ([`Transition::plan_moving`]) continues its motion without a jump in
//!   any of the three. It takes the time per value when that keeps the point
//!   on its segment; a point coming fast at its exit node would overshoot it
//!   in that time, so it takes the longest of `T / 1.2^k` (`k ≤ 12`) that
//!   does not (it arrives sooner, as a point moving that fast should).
//!
//! Every DH value of the shorter manipulator is thus C² in time along the
//! whole route, across nodes and re-plans (the tests check it by finite
//! differences of [`dh_motion`]'s values).
//!
//! # Timing (fig. 5)
//!
//! The paper's example: on `planar3` (0.4 / 0.3 / 0.2 m) a point moving from
//! the middle of link 1 to the middle of link 3 changes `a₁` (0.2 → 0.4 m,
//! rising monotonically), then `a₂` (0 → 0.3 m), then `a₃` (0 → 0.1 m), and
//! arrives after 3 × 0.1 s = 0.3 s. A route from rest always takes the time
//! per value per leg.
//!
//! # The retarget rule
//!
//! While a transition runs, the selected point may drift along the target's
//! segment; [`Transition::retarget`] then moves the end of the last leg
//! without re-planning the route. A last leg that has not begun simply
//! starts from its node towards the new end. A last leg under way is
//! *re-shaped*: a new quintic from the point's current fraction, rate and
//! acceleration to rest at the new end (so nothing jumps), whose duration is
//! the shortest of `T_min · 1.2^k` with `T_min = max(time left on the leg,
//! T / 16)` such that
//!
//! - its peak |rate| ≤ `max(15/8 · ℓ / T, |current rate|)` and its peak
//!   |acceleration| ≤ `max(10/√3 · ℓ / T², |current acceleration|)`, where
//!   `T` is the time per DH value and `ℓ = max(span of the leg as planned,
//!   distance from the point to the new end)` (in `t`): the nominal peaks of
//!   a rest-to-rest leg of that length, that is, the point never moves
//!   faster than its own route's leg would;
//! - the point stays on the segment.
//!
//! A small drift therefore keeps the arrival time; a large one, or one just
//! before arrival, lengthens the leg instead of moving the point (the old
//! cubic moved the end in place, up to ~0.2 m in one step). Per step `dt`
//! the point moves by at most `max(15/8 · ℓ / T, |rate|) · dt` along the
//! segment. (Should no candidate meet the caps, the one on the segment that
//! exceeds them least is used; should none stay on the segment, which the
//! legs themselves never lead to, the leg starts at rest.)
//!
//! [`MovingPoint`] applies the rule so that a selection that keeps drifting
//! (an obstacle moving along the link) cannot hold the point in a transition
//! forever: it first tries [`Transition::retarget_on_time`] (the leg re-shaped
//! over exactly the time it has left, within the same caps); only when that
//! fails *and* the selection is farther than the jump threshold from the
//! transition's target does it lengthen the leg ([`Transition::retarget`]).
//! A smaller drift left over at arrival is then followed directly, like any
//! move under the threshold.
//!
//! [`MovingPoint`] is the per-control-point state machine that decides between
//! following the selected point directly and starting (or re-planning) a
//! transition; [`dh_motion`] turns a point on the skeleton, with its rate and
//! acceleration, into the DH values `(link, d', a')` and their derivatives
//! that enter `ṗ = J_θ θ̇ + J_a ȧ + J_d ḋ` and the second-order terms.

mod moving;
mod plan;
mod quintic;
mod route;

pub use moving::MovingPoint;
pub use plan::{Transition, TransitionSample};
pub use route::{RouteLeg, route, route_length};

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::control_point::DhPoint;
use crate::control_point::PointMotion;
use crate::error::FieldError;
use crate::kinematics::{Convention, Frames, Robot};
use crate::skeleton::{Skeleton, SpinePart};

/// Default time for one DH value to reach its new value (s), as in the paper.
pub const DEFAULT_TIME_PER_VALUE: f64 = 0.1;

/// Default largest move along the skeleton that a control point makes
/// directly, without a transition (m).
pub const DEFAULT_JUMP_THRESHOLD: f64 = 0.02;

/// A point on the skeleton: segment index and fraction along it (0 at the
/// segment's `from` node, 1 at its `to` node).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SkeletonPoint {
    /// Index into [`Skeleton::segments`].
    pub segment: usize,
    /// Fraction along the segment, in `[0, 1]`.
    pub t: f64,
}

impl SkeletonPoint {
    /// Cartesian position (world frame, m).
    #[must_use]
    pub fn position(&self, skeleton: &Skeleton) -> DVec3 {
        let s = &skeleton.segments[self.segment];
        let (a, b) = skeleton.endpoints(s);
        a + (b - a) * self.t
    }
}

/// The DH description of a point on the skeleton and the derivatives of its
/// own DH value: `rate` and `accel` are `dt/dτ` and `d²t/dτ²` along the
/// segment, scaled by the length of the DH value the segment spans.
///
/// # Errors
/// A segment index out of range or `t` outside `[0, 1]`.
pub fn dh_motion(
    robot: &Robot,
    frames: &Frames,
    skeleton: &Skeleton,
    point: SkeletonPoint,
    rate: f64,
    accel: f64,
) -> Result<(DhPoint, PointMotion), FieldError> {
    let dh = DhPoint::from_skeleton(robot, frames, skeleton, point.segment, point.t)?;
    let s = &skeleton.segments[point.segment];
    let joint = &robot.joints[s.link - 1];
    let d_full = frames.d[s.link - 1];
    let back = if joint.a < 0.0 {
        joint.extension
    } else {
        -joint.extension
    };
    let mut m = PointMotion::default();
    match (robot.convention, s.part) {
        (_, SpinePart::D) => {
            m.d_rate = rate * d_full;
            m.d_accel = accel * d_full;
        }
        (_, SpinePart::A) => {
            m.a_rate = rate * joint.a;
            m.a_accel = accel * joint.a;
        }
        (Convention::Standard | Convention::Modified, SpinePart::Extension) => {
            m.a_rate = rate * back;
            m.a_accel = accel * back;
        }
    }
    Ok((dh, m))
}

/// Settings of a [`MovingPoint`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TransitionSettings {
    /// Time per DH value of a transition (s, > 0).
    pub time_per_value: f64,
    /// Largest move along the skeleton made directly (m, ≥ 0).
    pub jump_threshold: f64,
}

impl Default for TransitionSettings {
    fn default() -> Self {
        Self {
            time_per_value: DEFAULT_TIME_PER_VALUE,
            jump_threshold: DEFAULT_JUMP_THRESHOLD,
        }
    }
}

/// What a [`MovingPoint`] did during one update.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PointEvent {
    /// The selected point moved to another part of the skeleton, farther
    /// along it than the jump threshold.
    SegmentSwitch {
        /// Previous selected segment.
        from: usize,
        /// New selected segment.
        to: usize,
    },
    /// A transition started (or was re-planned from where the point is).
    TransitionStart {
        /// Segment the point is on.
        from: usize,
        /// Segment it goes to.
        to: usize,
        /// Planned duration (s).
        duration: f64,
        /// Whether it replaced a transition under way.
        replan: bool,
    },
    /// The point arrived.
    TransitionEnd {
        /// Segment it arrived on.
        segment: usize,
    },
}
