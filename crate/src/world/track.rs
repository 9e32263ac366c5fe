//! The *transition* and *monitor* stages of a [`World`] step: each control
//! point follows its selected point (travelling along the skeleton when it
//! jumps, [`MovingPoint`]), segment switches are counted, chattering locks
//! the point or stops the arm, and the sensing error's switch risk is
//! flagged (paper §III-B, §IV).

use std::collections::BTreeSet;

use super::{StopReason, World};
use crate::avoidance::ControllerConfig;
use crate::avoidance::selection::{Key, Selected};
use crate::dependability::{ChatteringPolicy, EventKind, SwitchCounter};
use crate::distance::{PairDistance, Target};
use crate::error::FieldError;
use crate::transition::{MovingPoint, PointEvent, SkeletonPoint, TransitionSettings};

/// The state of one control point across steps.
#[derive(Clone, Debug)]
pub(super) struct Tracker {
    pub(super) mover: MovingPoint,
    pub(super) owner: Option<usize>,
    /// Closing speed of the control point's material point and its
    /// obstacle, low-pass filtered (m/s; see [`super::step`]).
    pub(super) closing: Option<f64>,
    pub(super) too_slow: bool,
    counter: SwitchCounter,
    pub(super) chattering: bool,
    lock: Option<(usize, f64)>,
}

impl Tracker {
    pub(super) fn new(at: SkeletonPoint, owner: Option<usize>) -> Self {
        Self {
            mover: MovingPoint::new(at),
            owner,
            closing: None,
            too_slow: false,
            counter: SwitchCounter::default(),
            chattering: false,
            lock: None,
        }
    }
}

impl World {
    /// Switch risk: for each obstacle sensed with an error, another part of
    /// the skeleton whose distance is within twice the margin of the
    /// closest one (raised when it starts).
    pub(super) fn monitor_switch_risk(
        &mut self,
        pairs: &[PairDistance],
        selected: &Selected,
        config: &ControllerConfig,
    ) {
        let mut risky_now = BTreeSet::new();
        for (&owner, &k) in &selected.closest {
            let margin = self.obstacles[owner].margin;
            let b = &pairs[k];
            if margin <= 0.0 {
                continue;
            }
            let alternative = pairs
                .iter()
                .filter(|p| {
                    matches!(p.target, Target::Obstacle { id, .. } if self.owners[id as usize] == owner)
                        && p.segment != b.segment
                        && (p.point_segment - b.point_segment).length() > config.jump_threshold
                })
                .min_by(|x, y| x.distance.total_cmp(&y.distance));
            let Some(alt) = alternative else { continue };
            let gap = alt.distance - b.distance;
            if gap <= 2.0 * margin {
                risky_now.insert(owner);
                if !self.risky.contains(&owner) {
                    let obstacle = self.obstacles[owner].spec.id.clone();
                    self.push(EventKind::SwitchRisk {
                        obstacle,
                        segment: b.segment,
                        alternative: alt.segment,
                        gap,
                        margin,
                    });
                }
            }
        }
        self.risky = risky_now;
    }

    /// Where a locked control point stays: on its locked segment, at the
    /// pair's closest point there if the obstacle is within reach.
    fn locked_point(
        &self,
        tracker: &Tracker,
        segment: usize,
        pairs: &[PairDistance],
    ) -> SkeletonPoint {
        let owner = tracker.owner;
        let on_segment = pairs.iter().find(|p| {
            p.segment == segment
                && matches!(p.target, Target::Obstacle { id, .. } if Some(self.owners[id as usize]) == owner)
        });
        on_segment.map_or(
            SkeletonPoint {
                segment,
                t: if tracker.mover.point().segment == segment {
                    tracker.mover.point().t
                } else {
                    0.5
                },
            },
            |p| SkeletonPoint {
                segment,
                t: p.fraction,
            },
        )
    }

    /// The transition stage and the chattering monitor: every selected
    /// control point moves towards its point; switches are counted, and a
    /// rising chattering either locks the point or stops the arm.
    pub(super) fn track(
        &mut self,
        selected: &Selected,
        pairs: &[PairDistance],
        dt: f64,
        config: &ControllerConfig,
    ) -> Result<(), FieldError> {
        let t = self.t;
        let settings = TransitionSettings {
            time_per_value: config.transition_time,
            jump_threshold: config.jump_threshold,
        };
        self.trackers
            .retain(|k, _| selected.points.contains_key(k) || matches!(k, Key::Pinned(_)));
        let dep = self.scenario.dependability;
        let mut point_events = Vec::new();
        for (key, &(mut at, owner)) in &selected.points {
            let mut tracker = self
                .trackers
                .remove(key)
                .unwrap_or_else(|| Tracker::new(at, owner));
            if let Some((segment, until)) = tracker.lock {
                if t >= until {
                    tracker.lock = None;
                    let obstacle =
                        owner.map_or_else(String::new, |o| self.obstacles[o].spec.id.clone());
                    self.push(EventKind::Unlock { obstacle });
                } else if at.segment != segment {
                    at = self.locked_point(&tracker, segment, pairs);
                }
            }
            point_events.clear();
            tracker
                .mover
                .update(&self.skeleton, at, dt, &settings, &mut point_events)?;
            let mut switches = 0;
            for e in &point_events {
                if matches!(e, PointEvent::SegmentSwitch { .. }) {
                    switches = tracker.counter.record(t, dep.switch_window);
                }
            }
            let chattering =
                tracker.counter.count(t, dep.switch_window) > dep.max_switches as usize;
            let rising = chattering && !tracker.chattering;
            tracker.chattering = chattering;
            let lock_segment = tracker.mover.point().segment;
            if rising && dep.on_chattering == ChatteringPolicy::Lock {
                tracker.lock = Some((lock_segment, t + dep.lock_time));
            }
            self.trackers.insert(key.clone(), tracker);
            let name = self.name(key);
            self.push_point_events(&name, &mut point_events);
            if rising {
                self.push(EventKind::Chattering {
                    obstacle: name.clone(),
                    switches,
                });
                match dep.on_chattering {
                    ChatteringPolicy::Stop => self.stop(
                        StopReason::Chattering,
                        format!("chattering control point ({name})"),
                        dep.lock_time,
                    ),
                    ChatteringPolicy::Lock => self.push(EventKind::Lock {
                        obstacle: name,
                        segment: lock_segment,
                        until: t + dep.lock_time,
                    }),
                }
            }
        }
        if config.selection == crate::avoidance::Selection::Pinned {
            for k in 0..config.pinned.len() {
                self.trackers
                    .entry(Key::Pinned(k))
                    .or_insert_with(|| Tracker::new(SkeletonPoint { segment: 0, t: 0.0 }, None));
            }
        }
        Ok(())
    }

    fn push_point_events(&mut self, name: &str, events: &mut Vec<PointEvent>) {
        for e in events.drain(..) {
            let obstacle = name.to_owned();
            self.push(match e {
                PointEvent::SegmentSwitch { from, to } => {
                    EventKind::SegmentSwitch { obstacle, from, to }
                }
                PointEvent::TransitionStart {
                    from,
                    to,
                    duration,
                    replan,
                } => EventKind::TransitionStart {
                    obstacle,
                    from,
                    to,
                    duration,
                    replan,
                },
                PointEvent::TransitionEnd { segment } => {
                    EventKind::TransitionEnd { obstacle, segment }
                }
            });
        }
    }

    /// Starts (or extends) a category-2 stop for `hold` seconds at least.
    pub(super) fn stop(&mut self, reason: StopReason, text: String, hold: f64) {
        self.stopped_until = self.stopped_until.max(self.t + hold);
        if !self.stopped {
            self.stopped = true;
            self.stop_reason = Some(reason);
            self.push(EventKind::Stop { reason: text });
        }
    }

    /// Ends a stop once its time is over, nothing chatters, and (after an
    /// unavoidable approach) every guard holds with the arm at rest.
    pub(super) fn maybe_resume(&mut self, all_guards_hold: bool) {
        if !self.stopped || self.t < self.stopped_until {
            return;
        }
        if self.trackers.values().any(|tr| tr.chattering) {
            return;
        }
        if self.stop_reason == Some(StopReason::Unavoidable) && !all_guards_hold {
            return;
        }
        self.stopped = false;
        self.stop_reason = None;
        self.push(EventKind::Resume);
    }
}
