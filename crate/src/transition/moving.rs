//! [`MovingPoint`]: the per-control-point state machine that follows the
//! selected point directly or through a [`Transition`].

use super::plan::Transition;
use super::route::route_length;
use super::{PointEvent, SkeletonPoint, TransitionSettings};
use crate::error::FieldError;
use crate::skeleton::Skeleton;

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
    /// target's segment moves the end of the last leg
    /// ([`Transition::retarget_on_time`]) as long as the arrival time can be
    /// kept within the retarget caps; when it cannot, a drift of more than
    /// the threshold from the transition's target lengthens the last leg
    /// ([`Transition::retarget`]), and a smaller one is left to direct
    /// following after arrival (so a selection that keeps drifting cannot
    /// hold the point in a transition forever). A selection on another
    /// segment, farther than the threshold from the target, re-plans from
    /// the current point, rate and acceleration
    /// ([`Transition::plan_moving`]).
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
                // Keep the arrival time when the drift allows it; a drift
                // beyond the jump threshold lengthens the last leg instead;
                // a smaller one left over at arrival is followed directly.
                if !tr.retarget_on_time(selected.t)
                    && route_length(skeleton, tr.target(), selected) > jump
                {
                    tr.retarget(selected.t);
                }
                false
            }
            Some(tr) => route_length(skeleton, tr.target(), selected) > jump,
            None => route_length(skeleton, self.point, selected) > jump,
        };
        if replan {
            let tr = Transition::plan_moving(
                skeleton,
                self.point,
                self.rate,
                self.accel,
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
