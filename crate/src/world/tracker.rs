//! The *transition* and *monitor* stages of a [`super::World`] step: each control
//! point follows its selected point (travelling along the skeleton when it
//! jumps, [`MovingPoint`]), segment switches are counted, chattering locks
//! the point or stops the arm, and the sensing error's switch risk is
//! flagged (paper §III-B, §IV).

use std::collections::{BTreeMap, BTreeSet};

use super::StopReason;
use super::obstacles::SwitchOdds;
use super::parts::{EventLog, Model, Sensed, State, StepData};
use super::uncertainty::segment_odds;
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

/// Pair indices grouped by owning obstacle ([`pairs_by_owner`]).
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

/// Switch risk: for each obstacle within reach, the probability that
/// the segment sensed as closest differs from the ideal one
/// ([`crate::dependability::switch_probability`]) over the other segments whose own closest
/// point is farther than the jump threshold from it; `switchRisk` is
/// raised when it exceeds the configured level (when it starts).
pub(super) fn monitor_switch_risk(
    model: &Model,
    state: &mut State,
    log: &mut EventLog,
    pairs: &[PairDistance],
    selected: &Selected,
) {
    let config = &model.scenario.controller;
    let level = model.scenario.dependability.switch_risk;
    let mut risky_now = BTreeSet::new();
    for o in &mut state.sensed.obstacles {
        o.switch = SwitchOdds::default();
    }
    let by_owner = pairs_by_owner(&state.sensed, pairs);
    for (&owner, &k) in &selected.closest {
        let b = &pairs[k];
        let covariance = state.sensed.obstacles[owner].covariance;
        let mine = by_owner.of(owner).iter().map(|&i| &pairs[i]);
        let (odds, alt) = segment_odds(mine, b, config.jump_threshold, &covariance);
        let probability = odds.probability;
        state.sensed.obstacles[owner].switch = odds;
        let Some(alt) = alt.filter(|_| probability >= level) else {
            continue;
        };
        risky_now.insert(owner);
        if !state.risky.contains(&owner) {
            let o = &state.sensed.obstacles[owner];
            log.push(
                state.t,
                EventKind::SwitchRisk {
                    obstacle: o.spec.id.clone(),
                    segment: b.segment,
                    alternative: alt.segment,
                    gap: alt.distance - b.distance,
                    margin: o.margin,
                    probability,
                },
            );
        }
    }
    state.risky = risky_now;
}

/// The pairs' indices grouped by the obstacle that owns them (a
/// counting sort: one pass, so that the switch risk of a thousand
/// obstacles reads each pair once, not once per obstacle).
fn pairs_by_owner(sensed: &Sensed, pairs: &[PairDistance]) -> ByOwner {
    let owner = |p: &PairDistance| match p.target {
        Target::Obstacle { id, .. } => sensed
            .owners
            .get(id as usize)
            .copied()
            .filter(|&o| o < sensed.obstacles.len()),
        _ => None,
    };
    let mut start = vec![0; sensed.obstacles.len() + 1];
    for o in pairs.iter().filter_map(owner) {
        start[o + 1] += 1;
    }
    for o in 0..sensed.obstacles.len() {
        start[o + 1] += start[o];
    }
    let mut fill = start.clone();
    let mut index = vec![0; start[sensed.obstacles.len()]];
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
    sensed: &Sensed,
    tracker: &Tracker,
    segment: usize,
    pairs: &[PairDistance],
) -> SkeletonPoint {
    let owner = tracker.owner;
    let on_segment = pairs.iter().find(|p| {
            p.segment == segment
                && matches!(p.target, Target::Obstacle { id, .. } if Some(sensed.owners[id as usize]) == owner)
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
    model: &Model,
    state: &mut State,
    data: &StepData,
    log: &mut EventLog,
    selected: &Selected,
    pairs: &[PairDistance],
    dt: f64,
) -> Result<(), FieldError> {
    let config = &model.scenario.controller;
    // The trackers are taken out while they move (no remove and insert
    // per point and step), and put back whatever happens.
    let mut trackers = std::mem::take(&mut state.trackers);
    trackers.retain(|k, _| selected.points.contains_key(k) || matches!(k, Key::Pinned(_)));
    let moved = move_points(
        model,
        state,
        data,
        log,
        &mut trackers,
        (selected, pairs),
        dt,
    );
    state.trackers = trackers;
    moved?;
    if config.selection == crate::avoidance::Selection::Pinned {
        for k in 0..config.pinned.len() {
            state
                .trackers
                .entry(Key::Pinned(k))
                .or_insert_with(|| Tracker::new(SkeletonPoint { segment: 0, t: 0.0 }, None));
        }
    }
    Ok(())
}

/// Moves every selected control point's tracker towards its point
/// (the body of [`track`]).
fn move_points(
    model: &Model,
    state: &mut State,
    data: &StepData,
    log: &mut EventLog,
    trackers: &mut BTreeMap<Key, Tracker>,
    (selected, pairs): (&Selected, &[PairDistance]),
    dt: f64,
) -> Result<(), FieldError> {
    let config = &model.scenario.controller;
    let t = state.t;
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
                let obstacle =
                    owner.map_or_else(String::new, |o| state.sensed.obstacles[o].spec.id.clone());
                log.push(state.t, EventKind::Unlock { obstacle });
            } else if at.segment != segment {
                at = locked_point(&state.sensed, tracker, segment, pairs);
            }
        }
        // A switch: the selected point jumps along the skeleton farther
        // than the jump threshold in one step (to another segment, or
        // along its own: a pair's point, whose segment is fixed).
        let jumped =
            route_length(&data.skeleton, tracker.mover.selected(), at) > config.jump_threshold;
        point_events.clear();
        tracker
            .mover
            .update(&data.skeleton, at, dt, &settings, &mut point_events)?;
        if !point_events.is_empty() {
            let name = super::name(state, data, key);
            push_point_events(state.t, log, &name, &mut point_events);
        }
        let hold = tracker.mover.point().segment;
        monitor_chattering(model, state, data, log, tracker, key, (jumped, hold));
    }
    Ok(())
}

/// The chattering monitor of one control point: counts a switch,
/// and on rising chattering applies the policy (`lock` holds the point
/// on `hold` — its segment, or for a pinned point the obstacle it
/// answers — for `lockTime`; `stop` stops the arm).
pub(super) fn monitor_chattering(
    model: &Model,
    state: &mut State,
    data: &StepData,
    log: &mut EventLog,
    tracker: &mut Tracker,
    key: &Key,
    (switched, hold): (bool, usize),
) {
    let (t, dep) = (state.t, model.scenario.dependability);
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
    let name = super::name(state, data, key);
    log.push(
        state.t,
        EventKind::Chattering {
            obstacle: name.to_owned(),
            switches,
        },
    );
    match dep.on_chattering {
        ChatteringPolicy::Stop => stop(
            state,
            log,
            StopReason::Chattering,
            format!("chattering control point ({name})"),
            dep.lock_time,
        ),
        ChatteringPolicy::Lock => {
            tracker.lock = Some((hold, t + dep.lock_time));
            log.push(
                state.t,
                EventKind::Lock {
                    obstacle: name.to_owned(),
                    segment: hold,
                    until: t + dep.lock_time,
                },
            );
        }
    }
}

fn push_point_events(t: f64, log: &mut EventLog, name: &str, events: &mut Vec<PointEvent>) {
    for e in events.drain(..) {
        let obstacle = name.to_owned();
        log.push(
            t,
            match e {
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
            },
        );
    }
}

/// Starts (or extends) a category-2 stop for `hold` seconds at least.
pub(super) fn stop(
    state: &mut State,
    log: &mut EventLog,
    reason: StopReason,
    text: String,
    hold: f64,
) {
    state.stop.until = state.stop.until.max(state.t + hold);
    if !state.stop.stopped {
        state.stop.stopped = true;
        state.stop.reason = Some(reason);
        log.push(state.t, EventKind::Stop { reason: text });
    }
}

/// Ends a stop once its time is over, nothing chatters, and (after an
/// unavoidable approach) the joints are at rest and the guard of every
/// approaching obstacle holds: the hold lasts as long as the situation
/// that caused it.
pub(super) fn maybe_resume(state: &mut State, log: &mut EventLog, all_guards_hold: bool) {
    if !state.stop.stopped || state.t < state.stop.until {
        return;
    }
    if state.trackers.values().any(|tr| tr.chattering) || state.stop.command_monitor.chattering() {
        return;
    }
    if state.stop.reason == Some(StopReason::Unavoidable)
        && !(all_guards_hold && state.motion.is_at_rest())
    {
        return;
    }
    state.stop.stopped = false;
    state.stop.reason = None;
    log.push(state.t, EventKind::Resume);
}
