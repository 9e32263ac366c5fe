//! The *transition* and *monitor* stages of a [`World`] step: each control
//! point follows its selected point (travelling along the skeleton when it
//! jumps, [`MovingPoint`]), segment switches are counted, chattering locks
//! the point or stops the arm, and the sensing error's switch risk is
//! flagged (paper §III-B, §IV).

use std::collections::{BTreeMap, BTreeSet};

use super::obstacles::SwitchOdds;
use super::uncertainty::segment_odds;
use super::{StopReason, World};
use crate::avoidance::ControllerConfig;
use crate::avoidance::selection::{Key, Selected};
use crate::dependability::{ChatteringPolicy, EventKind, SwitchCounter};
use crate::distance::{PairDistance, Target};
use crate::error::FieldError;
use crate::transition::{MovingPoint, PointEvent, SkeletonPoint, TransitionSettings, route_length};

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
    /// A `lock` under way: what is held (segment, or for a pinned point
    /// the obstacle it answers) and until when.
    pub(super) lock: Option<(usize, f64)>,
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

/// Pair indices grouped by owning obstacle ([`World::pairs_by_owner`]).
struct ByOwner {
    start: Vec<usize>,
    index: Vec<usize>,
}

impl ByOwner {
    fn of(&self, owner: usize) -> &[usize] {
        self.start
            .get(owner..=owner + 1)
            .map_or(&[], |r| &self.index[r[0]..r[1]])
    }
}

impl World {
    /// Switch risk: for each obstacle within reach, the probability that
    /// the segment sensed as closest differs from the ideal one
    /// ([`crate::dependability::switch_probability`]) over the other segments whose own closest
    /// point is farther than the jump threshold from it; `switchRisk` is
    /// raised when it exceeds the configured level (when it starts).
    pub(super) fn monitor_switch_risk(
        &mut self,
        pairs: &[PairDistance],
        selected: &Selected,
        config: &ControllerConfig,
    ) {
        let level = self.model.scenario.dependability.switch_risk;
        let mut risky_now = BTreeSet::new();
        for o in &mut self.state.sensed.obstacles {
            o.switch = SwitchOdds::default();
        }
        let by_owner = self.pairs_by_owner(pairs);
        for (&owner, &k) in &selected.closest {
            let b = &pairs[k];
            let covariance = self.state.sensed.obstacles[owner].covariance;
            let mine = by_owner.of(owner).iter().map(|&i| &pairs[i]);
            let (odds, alt) = segment_odds(mine, b, config.jump_threshold, &covariance);
            let probability = odds.probability;
            self.state.sensed.obstacles[owner].switch = odds;
            let Some(alt) = alt.filter(|_| probability >= level) else {
                continue;
            };
            risky_now.insert(owner);
            if !self.state.risky.contains(&owner) {
                let o = &self.state.sensed.obstacles[owner];
                self.push(EventKind::SwitchRisk {
                    obstacle: o.spec.id.clone(),
                    segment: b.segment,
                    alternative: alt.segment,
                    gap: alt.distance - b.distance,
                    margin: o.margin,
                    probability,
                });
            }
        }
        self.state.risky = risky_now;
    }

    /// The pairs' indices grouped by the obstacle that owns them (a
    /// counting sort: one pass, so that the switch risk of a thousand
    /// obstacles reads each pair once, not once per obstacle).
    fn pairs_by_owner(&self, pairs: &[PairDistance]) -> ByOwner {
        let owner = |p: &PairDistance| match p.target {
            Target::Obstacle { id, .. } => self
                .state
                .sensed
                .owners
                .get(id as usize)
                .copied()
                .filter(|&o| o < self.state.sensed.obstacles.len()),
            _ => None,
        };
        let mut start = vec![0; self.state.sensed.obstacles.len() + 1];
        for o in pairs.iter().filter_map(owner) {
            start[o + 1] += 1;
        }
        for o in 0..self.state.sensed.obstacles.len() {
            start[o + 1] += start[o];
        }
        let mut fill = start.clone();
        let mut index = vec![0; start[self.state.sensed.obstacles.len()]];
        for (i, o) in pairs
            .iter()
            .enumerate()
            .filter_map(|(i, p)| Some((i, owner(p)?)))
        {
            index[fill[o]] = i;
            fill[o] += 1;
        }
        ByOwner { start, index }
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
                && matches!(p.target, Target::Obstacle { id, .. } if Some(self.state.sensed.owners[id as usize]) == owner)
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
        // The trackers are taken out while they move (no remove and insert
        // per point and step), and put back whatever happens.
        let mut trackers = std::mem::take(&mut self.state.trackers);
        trackers.retain(|k, _| selected.points.contains_key(k) || matches!(k, Key::Pinned(_)));
        let moved = self.move_points(&mut trackers, selected, pairs, dt, config);
        self.state.trackers = trackers;
        moved?;
        if config.selection == crate::avoidance::Selection::Pinned {
            for k in 0..config.pinned.len() {
                self.state
                    .trackers
                    .entry(Key::Pinned(k))
                    .or_insert_with(|| Tracker::new(SkeletonPoint { segment: 0, t: 0.0 }, None));
            }
        }
        Ok(())
    }

    /// Moves every selected control point's tracker towards its point
    /// (the body of [`World::track`]).
    fn move_points(
        &mut self,
        trackers: &mut BTreeMap<Key, Tracker>,
        selected: &Selected,
        pairs: &[PairDistance],
        dt: f64,
        config: &ControllerConfig,
    ) -> Result<(), FieldError> {
        let t = self.state.t;
        let settings = TransitionSettings {
            time_per_value: config.transition_time,
            jump_threshold: config.jump_threshold,
        };
        let mut point_events = Vec::new();
        for (key, &(mut at, owner)) in &selected.points {
            let tracker = trackers
                .entry(key.clone())
                .or_insert_with(|| Tracker::new(at, owner));
            if let Some((segment, until)) = tracker.lock {
                if t >= until {
                    tracker.lock = None;
                    let obstacle = owner.map_or_else(String::new, |o| {
                        self.state.sensed.obstacles[o].spec.id.clone()
                    });
                    self.push(EventKind::Unlock { obstacle });
                } else if at.segment != segment {
                    at = self.locked_point(tracker, segment, pairs);
                }
            }
            // A switch: the selected point jumps along the skeleton farther
            // than the jump threshold in one step (to another segment, or
            // along its own: a pair's point, whose segment is fixed).
            let jumped = route_length(&self.data.skeleton, tracker.mover.selected(), at)
                > config.jump_threshold;
            point_events.clear();
            tracker
                .mover
                .update(&self.data.skeleton, at, dt, &settings, &mut point_events)?;
            if !point_events.is_empty() {
                let name = self.name(key);
                self.push_point_events(&name, &mut point_events);
            }
            let hold = tracker.mover.point().segment;
            self.monitor_chattering(tracker, key, jumped, hold);
        }
        Ok(())
    }

    /// The chattering monitor of one control point: counts a switch,
    /// and on rising chattering applies the policy (`lock` holds the point
    /// on `hold` — its segment, or for a pinned point the obstacle it
    /// answers — for `lockTime`; `stop` stops the arm).
    pub(super) fn monitor_chattering(
        &mut self,
        tracker: &mut Tracker,
        key: &Key,
        switched: bool,
        hold: usize,
    ) {
        let (t, dep) = (self.state.t, self.model.scenario.dependability);
        let switches = if switched {
            tracker.counter.record(t, dep.switch_window)
        } else {
            tracker.counter.count(t, dep.switch_window)
        };
        let chattering = switches > dep.max_switches as usize;
        let rising = chattering && !tracker.chattering;
        tracker.chattering = chattering;
        if !rising {
            return;
        }
        let name = self.name(key);
        self.push(EventKind::Chattering {
            obstacle: name.to_owned(),
            switches,
        });
        match dep.on_chattering {
            ChatteringPolicy::Stop => self.stop(
                StopReason::Chattering,
                format!("chattering control point ({name})"),
                dep.lock_time,
            ),
            ChatteringPolicy::Lock => {
                tracker.lock = Some((hold, t + dep.lock_time));
                self.push(EventKind::Lock {
                    obstacle: name.to_owned(),
                    segment: hold,
                    until: t + dep.lock_time,
                });
            }
        }
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
        self.state.stop.until = self.state.stop.until.max(self.state.t + hold);
        if !self.state.stop.stopped {
            self.state.stop.stopped = true;
            self.state.stop.reason = Some(reason);
            self.push(EventKind::Stop { reason: text });
        }
    }

    /// Ends a stop once its time is over, nothing chatters, and (after an
    /// unavoidable approach) the joints are at rest and the guard of every
    /// approaching obstacle holds: the hold lasts as long as the situation
    /// that caused it.
    pub(super) fn maybe_resume(&mut self, all_guards_hold: bool) {
        if !self.state.stop.stopped || self.state.t < self.state.stop.until {
            return;
        }
        if self.state.trackers.values().any(|tr| tr.chattering)
            || self.state.stop.command_monitor.chattering()
        {
            return;
        }
        if self.state.stop.reason == Some(StopReason::Unavoidable)
            && !(all_guards_hold && self.state.motion.is_at_rest())
        {
            return;
        }
        self.state.stop.stopped = false;
        self.state.stop.reason = None;
        self.push(EventKind::Resume);
    }
}
