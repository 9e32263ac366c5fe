//! [`Transition`]: a control point travelling along a route, one quintic leg
//! per DH value, through the nodes.

use super::SkeletonPoint;
use super::quintic::{self, Caps, Quintic, State};
use super::route::{RouteLeg, route};
use crate::error::{FieldError, positive};
use crate::skeleton::Skeleton;

/// Shortest duration of a re-shaped last leg, as a fraction of the time per
/// DH value.
const MIN_RESHAPE_FRACTION: f64 = 1.0 / 16.0;

/// Largest change of a leg's end (in `t`) that a retarget ignores.
const RETARGET_EPSILON: f64 = 1e-15;

/// A leg in time on one segment.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Leg {
    segment: usize,
    /// Fraction at arrival.
    end: f64,
    /// Time (s, since the transition started) at which the leg starts.
    start: f64,
    /// `|t1 − t0|` of the leg as planned (sets the retarget caps).
    span: f64,
    shape: Quintic,
}

impl Leg {
    fn finish(&self) -> f64 {
        self.start + self.shape.duration()
    }

    /// State at `time` (s since the transition started): at rest at the end
    /// once the leg is over.
    fn state(&self, time: f64) -> State {
        if time >= self.finish() {
            return State {
                t: self.end,
                ..State::default()
            };
        }
        let s = self.shape.state(time - self.start);
        State {
            t: s.t.clamp(0.0, 1.0),
            ..s
        }
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

/// A control point travelling along the skeleton: a sequence of quintic
/// legs, one per DH value, through the nodes (see the [module
/// docs](super) for the shape of the legs and the retarget rule).
#[derive(Clone, Debug, PartialEq)]
pub struct Transition {
    legs: Vec<Leg>,
    target: SkeletonPoint,
    elapsed: f64,
    time_per_value: f64,
}

/// A finite value, or 0.
fn finite_or_zero(x: f64) -> f64 {
    if x.is_finite() { x } else { 0.0 }
}

impl Transition {
    /// Plans a transition from `from` (moving at `rate` along its segment,
    /// 1/s, with no acceleration) to `to`, taking `time_per_value` seconds
    /// per leg. Same as [`Transition::plan_moving`] with `accel = 0`.
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
        Self::plan_moving(skeleton, from, rate, 0.0, to, time_per_value)
    }

    /// Plans a transition from `from`, moving at `rate` (1/s) with
    /// acceleration `accel` (1/s²) along its segment, to `to`. The first leg
    /// is a quintic from that state to rest at its node, so position, rate
    /// and acceleration carry over without a jump; the others are
    /// rest-to-rest quintics of `time_per_value` seconds each. Non-finite
    /// `rate` or `accel` count as 0.
    ///
    /// # Errors
    /// As [`Transition::plan`].
    ///
    /// # Example
    /// ```
    /// use skeleton_avoidance::kinematics::{presets, Robot};
    /// use skeleton_avoidance::skeleton::Skeleton;
    /// use skeleton_avoidance::transition::{SkeletonPoint, Transition};
    /// let robot = Robot::from_spec(&presets::preset("planar3")?)?;
    /// let skeleton = Skeleton::build(&robot, &robot.forward(&[0.3, 0.4, 0.5])?);
    /// let from = SkeletonPoint { segment: 1, t: 0.5 };
    /// let to = SkeletonPoint { segment: 0, t: 0.5 };
    /// let tr = Transition::plan_moving(&skeleton, from, 2.0, -30.0, to, 0.1)?;
    /// let s = tr.sample_at(0.0);
    /// assert!((s.rate - 2.0).abs() < 1e-12 && (s.accel + 30.0).abs() < 1e-9);
    /// # Ok::<(), skeleton_avoidance::FieldError>(())
    /// ```
    pub fn plan_moving(
        skeleton: &Skeleton,
        from: SkeletonPoint,
        rate: f64,
        accel: f64,
        to: SkeletonPoint,
        time_per_value: f64,
    ) -> Result<Self, FieldError> {
        let time = positive("transitionTime", time_per_value)?;
        let start = State {
            t: from.t,
            rate: finite_or_zero(rate),
            accel: finite_or_zero(accel),
        };
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
        // its rate and acceleration carry over (even if the route leaves
        // right where it is): the point turns within its segment.
        let moving = start.rate != 0.0 || start.accel != 0.0;
        if moving && route.first().is_none_or(|l| l.segment != from.segment) {
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
        let mut clock = 0.0;
        for (k, l) in route.iter().enumerate() {
            let shape = if k == 0 {
                quintic::first_leg(State { t: l.t0, ..start }, l.t1, time)
            } else {
                let rest = State {
                    t: l.t0,
                    ..State::default()
                };
                Quintic::to_rest(rest, l.t1, time)
            };
            legs.push(Leg {
                segment: l.segment,
                end: l.t1,
                start: clock,
                span: (l.t1 - l.t0).abs(),
                shape,
            });
            clock += shape.duration();
        }
        Ok(Self {
            legs,
            target: to,
            elapsed: 0.0,
            time_per_value: time,
        })
    }

    /// Total duration (s).
    #[must_use]
    pub fn duration(&self) -> f64 {
        self.legs.last().map_or(0.0, Leg::finish)
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

    /// Time per DH value the transition was planned with (s).
    #[must_use]
    pub fn time_per_value(&self) -> f64 {
        self.time_per_value
    }

    /// The segments travelled, in order.
    #[must_use]
    pub fn segments(&self) -> Vec<usize> {
        self.legs.iter().map(|l| l.segment).collect()
    }

    /// Moves the end of the last leg to fraction `t` of the same segment
    /// (the selected point drifted along its segment).
    ///
    /// A last leg not yet begun is re-planned from its node (it keeps its
    /// duration unless the new end is farther than planned). A last leg
    /// under way (or over) is re-shaped from the current fraction, rate and
    /// acceleration to rest at `t`, so nothing jumps, over the shortest
    /// duration, not less than the time it had left (nor than 1/16 of the
    /// time per value), whose peak |rate| and |acceleration| stay within
    /// the nominal peaks of a rest-to-rest leg of length
    /// `max(planned span, |t − current t|)` over the time per value (or
    /// within the current |rate| and |acceleration| if higher). So the
    /// point never moves faster than its own route's legs allow; the
    /// arrival may come later. A non-finite `t` is ignored.
    pub fn retarget(&mut self, t: f64) {
        self.reshape_last(t, true);
    }

    /// [`Transition::retarget`] only if the arrival time can be kept: the
    /// last leg re-shaped over exactly the time it has left (at least 1/16
    /// of the time per value) stays on its segment and within the same
    /// caps. Returns whether the end moved (also `true` when `t` is already
    /// the end); on `false` nothing changed.
    pub fn retarget_on_time(&mut self, t: f64) -> bool {
        self.reshape_last(t, false)
    }

    /// The retarget rule (module docs); `lengthen` allows a later arrival.
    fn reshape_last(&mut self, t: f64, lengthen: bool) -> bool {
        if !t.is_finite() {
            return false;
        }
        let t = t.clamp(0.0, 1.0);
        let (elapsed, per_value) = (self.elapsed, self.time_per_value);
        let Some(last) = self.legs.last_mut() else {
            return false;
        };
        if (t - last.end).abs() <= RETARGET_EPSILON {
            return true;
        }
        let begin = elapsed.max(last.start);
        let now = last.state(begin);
        let length = last.span.max((t - now.t).abs());
        let caps = Caps::retarget(length, per_value, now);
        let floor = per_value * MIN_RESHAPE_FRACTION;
        let left = last.finish() - begin;
        let shape = if lengthen {
            quintic::reshape(now, t, left.max(floor), caps)
        } else if left >= floor {
            match quintic::reshape_on_time(now, t, left, caps) {
                Some(q) => q,
                None => return false,
            }
        } else {
            return false;
        };
        last.shape = shape;
        last.start = begin;
        last.end = t;
        self.target.t = t;
        true
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

    /// The point, its rate and acceleration `time` seconds after the start,
    /// on the legs as they are now (a re-shaped last leg reports its start
    /// state before the instant it was re-shaped).
    #[must_use]
    pub fn sample_at(&self, time: f64) -> TransitionSample {
        let Some(last) = self.legs.last() else {
            return TransitionSample {
                point: self.target,
                rate: 0.0,
                accel: 0.0,
            };
        };
        let leg = self.legs.iter().find(|l| time < l.finish()).unwrap_or(last);
        let s = leg.state(time);
        TransitionSample {
            point: SkeletonPoint {
                segment: leg.segment,
                t: s.t,
            },
            rate: s.rate,
            accel: s.accel,
        }
    }
}
