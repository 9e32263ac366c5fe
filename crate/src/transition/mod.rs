//! Smooth control-point transitions along the skeleton (paper §III-B, fig. 5).
//!
//! A control point sits on the skeleton: on segment `s` at fraction `t`
//! ([`SkeletonPoint`]). Each segment is the range of one DH value of one row
//! (`d_i` or `a_i`, or the `a` extension behind a joint), so moving along a
//! segment changes exactly one DH value, linearly in `t`.
//!
//! When the selected point moves to another segment, or jumps along the
//! skeleton by more than a threshold, the active point does not jump: a
//! [`Transition`] carries it through the nodes between the two segments, one
//! leg per segment, in the order in which they are met, each leg a cubic in
//! time over a configurable duration (the paper's 0.1 s per DH value). Legs
//! start and end at rest, so position and velocity are continuous; a re-plan
//! from a moving point starts its first leg with the current rate (a Hermite
//! cubic), so it does not jump either.
//!
//! The paper's example: on `planar3` (0.4 / 0.3 / 0.2 m) a point moving from
//! the middle of link 1 to the middle of link 3 changes `a₁` (0.2 → 0.4 m),
//! then `a₂` (0 → 0.3 m), then `a₃` (0 → 0.1 m), and arrives after 0.3 s.
//!
//! [`MovingPoint`] is the per-control-point state machine that decides between
//! following the selected point directly and starting (or re-planning) a
//! transition; [`dh_motion`] turns a point on the skeleton, with its rate and
//! acceleration, into the DH values `(link, d', a')` and their derivatives
//! that enter `ṗ = J_θ θ̇ + J_a ȧ + J_d ḋ` and the second-order terms.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::control_point::DhPoint;
use crate::error::{FieldError, positive};
use crate::kinematics::ik::PointMotion;
use crate::kinematics::{Convention, Frames, Robot};
use crate::skeleton::{Skeleton, SpinePart};

/// Default time for one DH value to reach its new value (s), as in the paper.
pub const DEFAULT_TIME_PER_VALUE: f64 = 0.1;

/// Default largest move along the skeleton that a control point makes
/// directly, without a transition (m).
pub const DEFAULT_JUMP_THRESHOLD: f64 = 0.02;

/// Legs shorter than this (in `t`) are dropped from a route.
const LEG_EPSILON: f64 = 1e-12;

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

/// One leg of a route: segment `segment`, from `t0` to `t1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RouteLeg {
    /// Segment travelled.
    pub segment: usize,
    /// Fraction at the start of the leg.
    pub t0: f64,
    /// Fraction at the end of the leg.
    pub t1: f64,
}

/// The route along the skeleton from `from` to `to`: the legs through the
/// nodes, in order (empty when the points coincide). `None` when the two
/// segments are not connected (never for a skeleton built from one robot).
///
/// The skeleton is a tree, so the route is unique: it leaves `from`'s
/// segment through the end that leads towards `to`'s segment.
#[must_use]
pub fn route(skeleton: &Skeleton, from: SkeletonPoint, to: SkeletonPoint) -> Option<Vec<RouteLeg>> {
    let segs = &skeleton.segments;
    let (fs, ts) = (segs.get(from.segment)?, segs.get(to.segment)?);
    let mut legs = Vec::new();
    if from.segment == to.segment {
        if (to.t - from.t).abs() > LEG_EPSILON {
            legs.push(RouteLeg {
                segment: from.segment,
                t0: from.t,
                t1: to.t,
            });
        }
        return Some(legs);
    }
    // Breadth-first search over nodes from both ends of `from`'s segment,
    // never crossing the two end segments, until an end of `to`'s segment.
    let n = skeleton.nodes.len();
    let mut prev: Vec<Option<(usize, usize)>> = vec![None; n];
    let mut seen = vec![false; n];
    let mut queue = std::collections::VecDeque::new();
    for start in [fs.from, fs.to] {
        if start < n && !seen[start] {
            seen[start] = true;
            queue.push_back(start);
        }
    }
    let mut goal = None;
    while let Some(u) = queue.pop_front() {
        if u == ts.from || u == ts.to {
            goal = Some(u);
            break;
        }
        for (k, s) in segs.iter().enumerate() {
            if k == from.segment || k == to.segment {
                continue;
            }
            let v = if s.from == u {
                s.to
            } else if s.to == u {
                s.from
            } else {
                continue;
            };
            if v < n && !seen[v] {
                seen[v] = true;
                prev[v] = Some((u, k));
                queue.push_back(v);
            }
        }
    }
    let goal = goal?;
    let mut middle = Vec::new();
    let mut node = goal;
    while let Some((u, k)) = prev[node] {
        middle.push((k, u, node));
        node = u;
    }
    middle.reverse();
    let exit = node;
    let end_of = |seg: usize, node: usize| if segs[seg].from == node { 0.0 } else { 1.0 };
    legs.push(RouteLeg {
        segment: from.segment,
        t0: from.t,
        t1: end_of(from.segment, exit),
    });
    for (k, u, v) in middle {
        legs.push(RouteLeg {
            segment: k,
            t0: end_of(k, u),
            t1: end_of(k, v),
        });
    }
    legs.push(RouteLeg {
        segment: to.segment,
        t0: end_of(to.segment, goal),
        t1: to.t,
    });
    legs.retain(|l| (l.t1 - l.t0).abs() > LEG_EPSILON);
    Some(legs)
}

/// Length of the route from `from` to `to` along the skeleton (m);
/// infinite when they are not connected.
#[must_use]
pub fn route_length(skeleton: &Skeleton, from: SkeletonPoint, to: SkeletonPoint) -> f64 {
    route(skeleton, from, to).map_or(f64::INFINITY, |legs| {
        legs.iter()
            .map(|l| {
                let (a, b) = skeleton.endpoints(&skeleton.segments[l.segment]);
                (l.t1 - l.t0).abs() * (b - a).length()
            })
            .sum()
    })
}

/// A leg in time: a cubic from `t0` (with rate `v0`) to `t1` (at rest).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Leg {
    segment: usize,
    t0: f64,
    t1: f64,
    v0: f64,
    start: f64,
    duration: f64,
}

impl Leg {
    /// Fraction, rate (1/s) and acceleration (1/s²) at time `tau` into the leg.
    fn eval(&self, tau: f64) -> (f64, f64, f64) {
        let big_t = self.duration;
        let u = (tau / big_t).clamp(0.0, 1.0);
        let (u2, u3) = (u * u, u * u * u);
        let (p0, m0, p1) = (self.t0, self.v0 * big_t, self.t1);
        let p = (2.0 * u3 - 3.0 * u2 + 1.0) * p0
            + (u3 - 2.0 * u2 + u) * m0
            + (3.0 * u2 - 2.0 * u3) * p1;
        let dp = ((6.0 * u2 - 6.0 * u) * p0
            + (3.0 * u2 - 4.0 * u + 1.0) * m0
            + (6.0 * u - 6.0 * u2) * p1)
            / big_t;
        let ddp = ((12.0 * u - 6.0) * p0 + (6.0 * u - 4.0) * m0 + (6.0 - 12.0 * u) * p1)
            / (big_t * big_t);
        (p.clamp(0.0, 1.0), dp, ddp)
    }
}

/// Where a transition is at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TransitionSample {
    /// The point on the skeleton.
    pub point: SkeletonPoint,
    /// `dt/dτ` along the current segment (1/s).
    pub rate: f64,
    /// `d²t/dτ²` along the current segment (1/s²).
    pub accel: f64,
}

/// A control point travelling along the skeleton: a sequence of cubic legs,
/// one per DH value, through the nodes.
#[derive(Clone, Debug, PartialEq)]
pub struct Transition {
    legs: Vec<Leg>,
    target: SkeletonPoint,
    elapsed: f64,
}

impl Transition {
    /// Plans a transition from `from` (moving at `rate` along its segment,
    /// 1/s) to `to`, taking `time_per_value` seconds per leg.
    ///
    /// # Errors
    /// `transitionTime: must be > 0`; `segment: …` when a segment index is
    /// out of range or the two segments are not connected.
    ///
    /// # Example
    /// ```
    /// use skeleton_avoidance::kinematics::{presets, Robot};
    /// use skeleton_avoidance::skeleton::Skeleton;
    /// use skeleton_avoidance::transition::{SkeletonPoint, Transition};
    /// let robot = Robot::from_spec(&presets::preset("planar3")?)?;
    /// let frames = robot.forward(&[0.3, 0.4, 0.5])?;
    /// let skeleton = Skeleton::build(&robot, &frames);
    /// let from = SkeletonPoint { segment: 0, t: 0.5 };
    /// let to = SkeletonPoint { segment: 2, t: 0.5 };
    /// let tr = Transition::plan(&skeleton, from, 0.0, to, 0.1)?;
    /// assert!((tr.duration() - 0.3).abs() < 1e-12);
    /// # Ok::<(), skeleton_avoidance::FieldError>(())
    /// ```
    pub fn plan(
        skeleton: &Skeleton,
        from: SkeletonPoint,
        rate: f64,
        to: SkeletonPoint,
        time_per_value: f64,
    ) -> Result<Self, FieldError> {
        let time = positive("transitionTime", time_per_value)?;
        let rate = if rate.is_finite() { rate } else { 0.0 };
        let mut route = route(skeleton, from, to).ok_or_else(|| {
            FieldError::new(
                "segment",
                format!(
                    "no route along the skeleton from segment {} to segment {}",
                    from.segment, to.segment
                ),
            )
        })?;
        // Keep a first leg on the current segment while the point moves, so
        // its rate carries over (even if the route leaves right where it is).
        if rate != 0.0 && route.first().is_none_or(|l| l.segment != from.segment) {
            route.insert(
                0,
                RouteLeg {
                    segment: from.segment,
                    t0: from.t,
                    t1: from.t,
                },
            );
        }
        let mut legs = Vec::with_capacity(route.len());
        let mut start = 0.0;
        for (k, l) in route.iter().enumerate() {
            legs.push(Leg {
                segment: l.segment,
                t0: l.t0,
                t1: l.t1,
                v0: if k == 0 { rate } else { 0.0 },
                start,
                duration: time,
            });
            start += time;
        }
        Ok(Self {
            legs,
            target: to,
            elapsed: 0.0,
        })
    }

    /// Total duration (s).
    #[must_use]
    pub fn duration(&self) -> f64 {
        self.legs.last().map_or(0.0, |l| l.start + l.duration)
    }

    /// Time left before arrival (s).
    #[must_use]
    pub fn remaining(&self) -> f64 {
        (self.duration() - self.elapsed).max(0.0)
    }

    /// Time since the transition started (s).
    #[must_use]
    pub fn elapsed(&self) -> f64 {
        self.elapsed
    }

    /// Whether the point has arrived.
    #[must_use]
    pub fn is_finished(&self) -> bool {
        self.elapsed >= self.duration()
    }

    /// Where the transition goes.
    #[must_use]
    pub fn target(&self) -> SkeletonPoint {
        self.target
    }

    /// The segments travelled, in order.
    #[must_use]
    pub fn segments(&self) -> Vec<usize> {
        self.legs.iter().map(|l| l.segment).collect()
    }

    /// Moves the end of the last leg to fraction `t` of the same segment
    /// (the selected point drifted along its segment): the point moves by
    /// at most the drift, without restarting the legs' timing.
    pub fn retarget(&mut self, t: f64) {
        if let Some(last) = self.legs.last_mut() {
            last.t1 = t.clamp(0.0, 1.0);
            self.target.t = last.t1;
        }
    }

    /// Moves time on by `dt` seconds.
    pub fn advance(&mut self, dt: f64) {
        if dt.is_finite() && dt > 0.0 {
            self.elapsed += dt;
        }
    }

    /// The point, its rate and acceleration at the current time.
    #[must_use]
    pub fn sample(&self) -> TransitionSample {
        self.sample_at(self.elapsed)
    }

    /// The point, its rate and acceleration `time` seconds after the start.
    #[must_use]
    pub fn sample_at(&self, time: f64) -> TransitionSample {
        let Some(last) = self.legs.last() else {
            return TransitionSample {
                point: self.target,
                rate: 0.0,
                accel: 0.0,
            };
        };
        let leg = self
            .legs
            .iter()
            .find(|l| time < l.start + l.duration)
            .unwrap_or(last);
        let (t, rate, accel) = if time >= last.start + last.duration {
            (last.t1, 0.0, 0.0)
        } else {
            leg.eval(time - leg.start)
        };
        TransitionSample {
            point: SkeletonPoint {
                segment: leg.segment,
                t,
            },
            rate,
            accel,
        }
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

/// A control point that follows a selected point on the skeleton, through a
/// [`Transition`] whenever that point jumps.
#[derive(Clone, Debug, PartialEq)]
pub struct MovingPoint {
    point: SkeletonPoint,
    rate: f64,
    accel: f64,
    selected: SkeletonPoint,
    transition: Option<Transition>,
}

impl MovingPoint {
    /// A point at rest at `at`.
    #[must_use]
    pub fn new(at: SkeletonPoint) -> Self {
        Self {
            point: at,
            rate: 0.0,
            accel: 0.0,
            selected: at,
            transition: None,
        }
    }

    /// Where the control point is.
    #[must_use]
    pub fn point(&self) -> SkeletonPoint {
        self.point
    }

    /// Its rate along the segment (1/s).
    #[must_use]
    pub fn rate(&self) -> f64 {
        self.rate
    }

    /// Its acceleration along the segment (1/s²).
    #[must_use]
    pub fn accel(&self) -> f64 {
        self.accel
    }

    /// The last selected point (the target while transitioning).
    #[must_use]
    pub fn selected(&self) -> SkeletonPoint {
        self.selected
    }

    /// The transition under way, if any.
    #[must_use]
    pub fn transition(&self) -> Option<&Transition> {
        self.transition.as_ref()
    }

    /// Time left before the point reaches its selected position (s).
    #[must_use]
    pub fn remaining(&self) -> f64 {
        self.transition.as_ref().map_or(0.0, Transition::remaining)
    }

    /// One step of `dt` seconds towards `selected`, pushing what happened
    /// into `events`.
    ///
    /// A move of at most `jump_threshold` along the skeleton is followed
    /// directly (the rate is the finite difference); a longer one starts a
    /// transition. During a transition, a selection that drifts along the
    /// target's segment moves the end of the last leg; one on another
    /// segment, farther than the threshold from the target, re-plans from
    /// the current point and rate.
    ///
    /// # Errors
    /// `transitionTime: must be > 0`, or segments that are not connected.
    pub fn update(
        &mut self,
        skeleton: &Skeleton,
        selected: SkeletonPoint,
        dt: f64,
        settings: &TransitionSettings,
        events: &mut Vec<PointEvent>,
    ) -> Result<(), FieldError> {
        let jump = settings.jump_threshold;
        let moved = route_length(skeleton, self.selected, selected);
        if selected.segment != self.selected.segment && moved > jump {
            events.push(PointEvent::SegmentSwitch {
                from: self.selected.segment,
                to: selected.segment,
            });
        }
        self.selected = selected;
        let replan = match &mut self.transition {
            Some(tr) if tr.target().segment == selected.segment => {
                tr.retarget(selected.t);
                false
            }
            Some(tr) => route_length(skeleton, tr.target(), selected) > jump,
            None => route_length(skeleton, self.point, selected) > jump,
        };
        if replan {
            let tr = Transition::plan(
                skeleton,
                self.point,
                self.rate,
                selected,
                settings.time_per_value,
            )?;
            events.push(PointEvent::TransitionStart {
                from: self.point.segment,
                to: selected.segment,
                duration: tr.duration(),
                replan: self.transition.is_some(),
            });
            self.transition = Some(tr);
        }
        if let Some(tr) = &mut self.transition {
            tr.advance(dt);
            let s = tr.sample();
            self.point = s.point;
            self.rate = s.rate;
            self.accel = s.accel;
            if tr.is_finished() {
                events.push(PointEvent::TransitionEnd {
                    segment: s.point.segment,
                });
                self.transition = None;
            }
        } else {
            let rate = if selected.segment == self.point.segment && dt > 0.0 {
                (selected.t - self.point.t) / dt
            } else {
                0.0
            };
            self.accel = 0.0;
            self.rate = rate;
            self.point = selected;
        }
        Ok(())
    }
}
