//! The active control points of a step, where they are now: the part of
//! the *monitor* stage that locates each tracked point, measures its
//! clearance, repulsion and time to collision, and runs the
//! `transitionTooSlow` monitor (paper §III-B, §IV).

use glam::DVec3;

use super::monitor::{Approach, monitor_transition, time_to_collision_at};
use super::parts::{EventLog, Model, Now, State, StepData};
use super::state::ControlPointState;
use super::tracker::monitor_chattering;
use super::uncertainty::SigmaInput;
use crate::avoidance::limits::braking_time;
use crate::avoidance::selection::{Key, fraction_on};
use crate::avoidance::{ActivePoint, Mode};
use crate::control_point::{DhPoint, PointMotion};
use crate::dependability::EventKind;
use crate::error::FieldError;
use crate::skeleton::Skeleton;
use crate::transition::{SkeletonPoint, dh_motion};

/// Where control point `key` is, its clearance, normal and witness.
pub(super) fn locate(
    now: Now<'_>,
    key: &Key,
    owner: Option<usize>,
    position: DVec3,
    radius: f64,
) -> Result<(f64, DVec3, DVec3, Option<usize>), FieldError> {
    if let Key::SelfPair(_, other) = key {
        let seg = &now.data.skeleton.segments[*other];
        let u = fraction_on(&now.data.skeleton, *other, position);
        let (a, b) = now.data.skeleton.endpoints(seg);
        let c = a + (b - a) * u;
        let r2 = Skeleton::radius_at(seg, u);
        let v = c - position;
        let len = v.length();
        let n = if len > 0.0 { v / len } else { DVec3::Z };
        return Ok((len - radius - r2, n, c - n * r2, None));
    }
    Ok(match owner {
        Some(o) => {
            let (d, n, w) = now.state.sensed.point_distance(o, position)?;
            (d - radius, n, w, Some(o))
        }
        None => (f64::INFINITY, DVec3::Z, position, None),
    })
}

/// What the active-point stage collects over the tracked points: the
/// last step's vectors, refilled in place (the readouts' names reuse their
/// strings), so that a step with as many points as the last allocates
/// nothing here.
struct Collected {
    active: Vec<ActivePoint>,
    sigma_inputs: Vec<SigmaInput>,
    /// The readouts: `states[..next]` are this step's.
    states: Vec<ControlPointState>,
    next: usize,
    min_ttc: f64,
}

/// The active control points where they are now, with their repulsion,
/// time to collision and the `transitionTooSlow` monitor.
pub(super) fn active_points(
    model: &Model,
    state: &mut State,
    data: &mut StepData,
    log: &mut EventLog,
    dt: f64,
) -> Result<Vec<ActivePoint>, FieldError> {
    let mut out = Collected {
        active: std::mem::take(&mut data.propagation.active),
        sigma_inputs: std::mem::take(&mut data.propagation.sigma_inputs),
        states: std::mem::take(&mut data.readout.points),
        next: 0,
        min_ttc: f64::INFINITY,
    };
    out.active.clear();
    out.sigma_inputs.clear();
    let braking = braking_time(&model.robot, &state.motion, dt);
    data.slowdown.clear();
    data.slowdown.resize(state.sensed.obstacles.len(), 1.0);
    let keys: Vec<Key> = state.trackers.keys().cloned().collect();
    for key in keys {
        if let Some(p) = place(model, state, data, log, &key)? {
            visit(model, state, data, log, (&key, p), (braking, dt), &mut out)?;
        }
    }
    out.states.truncate(out.next);
    data.readout.points = out.states;
    data.propagation.sigma_inputs = out.sigma_inputs;
    let min_ttc = out.min_ttc;
    data.readout.time_to_collision = min_ttc.is_finite().then_some(min_ttc);
    Ok(out.active)
}

/// Where a tracked point is, what it answers and what its tracker
/// remembers.
struct Placed {
    dh: DhPoint,
    radius: f64,
    prev: Option<f64>,
    remaining: f64,
    target: Option<SkeletonPoint>,
    selected_at: Option<SkeletonPoint>,
    was_slow: bool,
    position: DVec3,
    owner: Option<usize>,
    dist: f64,
    normal: DVec3,
    witness: DVec3,
}

/// Tracked point `key` where it is now (`None` for a pinned point the
/// configuration no longer has).
fn place(
    model: &Model,
    state: &mut State,
    data: &StepData,
    log: &mut EventLog,
    key: &Key,
) -> Result<Option<Placed>, FieldError> {
    let Some((dh, radius)) = tracked_point(Now { model, state, data }, key)? else {
        return Ok(None);
    };
    let Some(tr) = state.trackers.get(key) else {
        return Ok(None);
    };
    let (prev, remaining, owner) = (tr.closing, tr.mover.remaining(), tr.owner);
    let target = tr.mover.transition().map(|x| x.target());
    let selected_at = (!matches!(key, Key::Pinned(_))).then(|| tr.mover.selected());
    let was_slow = tr.too_slow;
    let position = dh.position(&model.robot, &data.frames);
    let owner = match key {
        Key::Pinned(k) => pinned_owner(model, state, data, log, (key, *k), position),
        _ => owner,
    };
    let now = Now { model, state, data };
    let (dist, normal, witness, owner) = locate(now, key, owner, position, radius)?;
    Ok(Some(Placed {
        dh,
        radius,
        prev,
        remaining,
        target,
        selected_at,
        was_slow,
        position,
        owner,
        dist,
        normal,
        witness,
    }))
}

/// One active point: its repulsion, time to collision, the
/// `transitionTooSlow` monitor, and what the readout and the propagation
/// need.
fn visit(
    model: &Model,
    state: &mut State,
    data: &mut StepData,
    log: &mut EventLog,
    (key, p): (&Key, Placed),
    (braking, dt): (f64, f64),
    out: &mut Collected,
) -> Result<(), FieldError> {
    let cfg = &model.scenario.controller;
    let (dh, prev, remaining, selected_at) = (p.dh, p.prev, p.remaining, p.selected_at);
    let (position, owner, dist, normal) = (p.position, p.owner, p.dist, p.normal);
    let margin = owner.map_or(0.0, |o| state.sensed.margin_near(o, position));
    let effective = dist - margin;
    let ap = ActivePoint {
        dh,
        motion: PointMotion::default(),
        normal,
        distance: effective,
    };
    let gain = if cfg.mode == Mode::Torque {
        cfg.torque.force_gain
    } else {
        1.0
    };
    let now = Now { model, state, data };
    let mut name = out.recycled_name();
    point_name(now, key, owner, &mut name);
    let at = selected_at.filter(|_| remaining > 0.0);
    let (ttc, closing, ttc_normal) =
        time_to_collision_at(now, (key, at, owner), (dh, normal, effective), prev, dt)?;
    out.min_ttc = out.min_ttc.min(ttc);
    let approach = Approach {
        owner,
        obstacle_velocity: owner
            .map_or(DVec3::ZERO, |o| state.sensed.approach_velocity(o, position)),
        name: &name,
        ttc,
        normal: ttc_normal,
        remaining,
        braking,
        closing,
        was_slow: p.was_slow,
    };
    monitor_transition(model, state, data, log, key, &approach);
    record(Now { model, state, data }, out, &p, (ap, gain, name));
    Ok(())
}

/// The readout of one control point and, when its obstacle is sensed
/// with error, what the propagation of that error needs.
fn record(
    now: Now<'_>,
    out: &mut Collected,
    p: &Placed,
    (ap, gain, name): (ActivePoint, f64, String),
) {
    let (model, state, data) = (now.model, now.state, now.data);
    let cfg = &model.scenario.controller;
    let (dh, owner, position, dist) = (p.dh, p.owner, p.position, p.dist);
    let target = p.target.and_then(|x| {
        DhPoint::from_skeleton(&model.robot, &data.frames, &data.skeleton, x.segment, x.t).ok()
    });
    if let Some(owner) = owner.filter(|&o| !state.sensed.obstacles[o].covariance.is_zero()) {
        out.sigma_inputs.push(SigmaInput {
            point: out.next,
            active: dist.is_finite().then_some(out.active.len()),
            owner,
            position,
            radius: p.radius,
            witness: p.selected_at,
            gain,
        });
    }
    if dist.is_finite() {
        out.active.push(ap);
    }
    out.put(ControlPointState {
        position: position.to_array(),
        link: dh.link,
        d: dh.d,
        a: dh.a,
        part: owner.and_then(|o| state.sensed.witness_part(o, position)),
        obstacle: name,
        distance: dist,
        witness: p.witness.to_array(),
        repulsion: (ap.repulsion(cfg) * gain).to_array(),
        transitioning: target.is_some(),
        target,
        sigma: None,
        table: Vec::new(),
        effective_mass: None,
    });
}

/// The radius at the start of the segment a pinned point lies on: the `a`
/// segment's when it is cut along `a` (behind the start: the extension's),
/// the `d` segment's otherwise.
fn pinned_radius(radii: &crate::kinematics::LinkRadii, p: &DhPoint) -> f64 {
    if p.a > 0.0 {
        radii.a[0]
    } else if p.a < 0.0 {
        radii.extension[0]
    } else {
        radii.d[0]
    }
}

/// Where the tracked point `key` is (DH values) and the radius of the
/// arm's volume there; `None` for a pinned point the configuration no
/// longer has, or a key no longer tracked.
fn tracked_point(now: Now<'_>, key: &Key) -> Result<Option<(DhPoint, f64)>, FieldError> {
    let cfg = &now.model.scenario.controller;
    let Some(tr) = now.state.trackers.get(key) else {
        return Ok(None);
    };
    Ok(Some(if let Key::Pinned(k) = key {
        let Some(p) = cfg.pinned.get(*k) else {
            return Ok(None);
        };
        (
            p.clamped(&now.data.frames),
            pinned_radius(&now.model.robot.joints[p.link - 1].radius, p),
        )
    } else {
        let pt = tr.mover.point();
        let (dh, _) = dh_motion(
            &now.model.robot,
            &now.data.frames,
            &now.data.skeleton,
            pt,
            0.0,
            0.0,
        )?;
        let seg = &now.data.skeleton.segments[pt.segment];
        (dh, Skeleton::radius_at(seg, pt.t))
    }))
}

/// The obstacle id a control point reports (`pinned:<k>` for a pinned
/// point with no obstacle in reach; otherwise as [`super::name`]), written
/// into `out`.
fn point_name(now: Now<'_>, key: &Key, owner: Option<usize>, out: &mut String) {
    use std::fmt::Write;
    out.clear();
    let id = |o: usize| now.state.sensed.obstacles[o].spec.id.as_str();
    // Writing into a String cannot fail.
    let _ = match (key, owner) {
        (Key::Pinned(k), None) => write!(out, "pinned:{k}"),
        (Key::Pinned(_), Some(o)) | (&Key::Obstacle(o) | &Key::Pair(o, _), _) => {
            out.write_str(id(o))
        }
        (Key::SelfPair(_, other), _) => {
            write!(out, "self:{}", now.data.skeleton.segments[*other].link)
        }
    };
}

impl Collected {
    /// A string for the next readout's name: the last step's, emptied.
    fn recycled_name(&mut self) -> String {
        self.states
            .get_mut(self.next)
            .map(|s| std::mem::take(&mut s.obstacle))
            .unwrap_or_default()
    }

    /// Stores the next readout.
    fn put(&mut self, point: ControlPointState) {
        match self.states.get_mut(self.next) {
            Some(slot) => *slot = point,
            None => self.states.push(point),
        }
        self.next += 1;
    }
}

/// The obstacle pinned point `k` answers: the closest one, unless a
/// `lock` holds another; a change is a switch for the chattering
/// monitor.
fn pinned_owner(
    model: &Model,
    state: &mut State,
    data: &StepData,
    log: &mut EventLog,
    (key, k): (&Key, usize),
    position: DVec3,
) -> Option<usize> {
    let closest = state.sensed.closest_obstacle(position);
    let mut tracker = state.trackers.remove(key)?;
    let owner = match tracker.lock {
        Some((held, until)) if state.t < until && held < state.sensed.obstacles.len() => Some(held),
        Some(_) => {
            tracker.lock = None;
            let obstacle = format!("pinned:{k}");
            log.push(state.t, EventKind::Unlock { obstacle });
            closest
        }
        None => closest,
    };
    let switched = tracker.owner.is_some() && owner.is_some() && tracker.owner != owner;
    tracker.owner = owner;
    if let Some(o) = owner {
        monitor_chattering(
            model,
            state,
            data,
            log,
            &mut tracker,
            &Key::Pinned(k),
            (switched, o),
        );
    }
    state.trackers.insert(key.clone(), tracker);
    owner
}
