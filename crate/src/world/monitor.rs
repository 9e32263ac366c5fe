//! The monitor's part of the active-point stage: where and how fast an
//! obstacle closes in on a control point (time to collision), and the
//! `transitionTooSlow` monitor that slows the approach when a transition
//! cannot end, and the arm brake, before contact.

use glam::DVec3;

use super::StopReason;
use super::active::locate;
use super::parts::{EventLog, Model, Now, State, StepData};
use super::tracker::stop;
use crate::avoidance::selection::{Key, fraction_on};
use crate::control_point::DhPoint;
use crate::dependability::{EventKind, time_to_collision};
use crate::error::FieldError;
use crate::skeleton::Skeleton;
use crate::transition::SkeletonPoint;

/// Time constant of the low-pass filter on the closing speed used for the
/// time to collision (s): long against the jitter of the sensed normal,
/// short against the arm's and the obstacles' changes of speed.
pub const CLOSING_FILTER_TIME: f64 = 0.05;

/// The `transitionTooSlow` monitor of one point.
///
/// The transition must end before contact and, when the obstacle itself
/// closes in, the arm must also be able to brake before it arrives:
/// otherwise the protective layer slows the approach. With the guards
/// on, the arm's own approach to a still obstacle cannot end in contact
/// (a velocity damper slows it as the clearance shrinks), so only an
/// obstacle that closes in can make a transition too slow.
pub(super) fn monitor_transition(
    model: &Model,
    state: &mut State,
    data: &mut StepData,
    log: &mut EventLog,
    key: &Key,
    a: &Approach<'_>,
) {
    let cfg = &model.scenario.controller;
    let (owner, ttc, remaining) = (a.owner, a.ttc, a.remaining);
    let coming = owner.is_some() && -a.normal.dot(a.obstacle_velocity) > 0.0;
    let guarded = cfg.protective.enabled;
    let needed = remaining + if coming { a.braking } else { 0.0 };
    let too_slow = remaining > 0.0 && ttc < needed && (coming || !guarded);
    let slowdown = if too_slow {
        (ttc / needed).clamp(0.0, 1.0)
    } else {
        1.0
    };
    if let Some(o) = owner.filter(|_| too_slow) {
        data.slowdown[o] = data.slowdown[o].min(slowdown);
    }
    if let Some(trm) = state.trackers.get_mut(key) {
        trm.closing = a.closing;
        trm.too_slow = too_slow;
    }
    if too_slow && !a.was_slow {
        log.push(
            state.t,
            EventKind::TransitionTooSlow {
                obstacle: a.name.to_owned(),
                time_to_collision: ttc,
                remaining,
                braking: needed - remaining,
                slowdown,
            },
        );
    }
}

/// The time to collision of tracked point `key` (see [`ttc_point`]
/// for where it is measured), with its closing speed low-pass filtered
/// from the previous step's `prev`, and the normal it was measured along.
pub(super) fn time_to_collision_at(
    now: Now<'_>,
    (key, at, owner): (&Key, Option<SkeletonPoint>, Option<usize>),
    here: (DhPoint, DVec3, f64),
    prev: Option<f64>,
    dt: f64,
) -> Result<(f64, Option<f64>, DVec3), FieldError> {
    let (dh, normal, clearance) = ttc_point(now, key, at, owner, here)?;
    let closing = closing_speed(now, key, &dh, owner, normal);
    let closing = match (prev, closing) {
        (Some(p), Some(c)) => Some(p + (c - p) * dt / (CLOSING_FILTER_TIME + dt)),
        (_, c) => c,
    };
    let ttc = closing.map_or(f64::INFINITY, |c| time_to_collision(clearance, c));
    Ok((ttc, closing, normal))
}

/// Where the time to collision is measured: at the true closest point,
/// the selected witness `at` while the control point still travels to
/// it (the obstacle reaches the arm there, not where the control point
/// is), else at the control point itself, `here` = (DH point, normal,
/// clearance with the margin subtracted).
pub(super) fn ttc_point(
    now: Now<'_>,
    key: &Key,
    at: Option<SkeletonPoint>,
    owner: Option<usize>,
    here: (DhPoint, DVec3, f64),
) -> Result<(DhPoint, DVec3, f64), FieldError> {
    let Some(at) = at else { return Ok(here) };
    let dh = DhPoint::from_skeleton(
        &now.model.robot,
        &now.data.frames,
        &now.data.skeleton,
        at.segment,
        at.t,
    )?;
    let radius = Skeleton::radius_at(&now.data.skeleton.segments[at.segment], at.t);
    let position = dh.position(&now.model.robot, &now.data.frames);
    let (d, normal, _, owner) = locate(now, key, owner, position, radius)?;
    let margin = owner.map_or(0.0, |o| now.state.sensed.margin_near(o, position));
    Ok((dh, normal, d - margin))
}

/// The speed at which control point `key` and what it answers close in
/// (m/s, positive when approaching), from the motion of the arm's
/// material point at `dh` (`nᵀ J_θ q̇`, not the point's travel along the
/// skeleton), minus that of the other point of a self-collision pair,
/// plus the obstacle's own approach speed (`−nᵀ v`, from its motion, not
/// from the sensed noise; `v` is the velocity of the obstacle's part
/// nearest the point, a human's hand moving with its arm). `None` when the point answers nothing.
pub(super) fn closing_speed(
    now: Now<'_>,
    key: &Key,
    dh: &DhPoint,
    owner: Option<usize>,
    normal: DVec3,
) -> Option<f64> {
    let qdot = &now.state.motion.qdot;
    let velocity = |p: &DhPoint| -> DVec3 { p.velocity(&now.model.robot, &now.data.frames, qdot) };
    let arm = normal.dot(velocity(dh));
    match (key, owner) {
        (Key::SelfPair(_, other), _) => {
            let position = dh.position(&now.model.robot, &now.data.frames);
            let u = fraction_on(&now.data.skeleton, *other, position);
            let o = DhPoint::from_skeleton(
                &now.model.robot,
                &now.data.frames,
                &now.data.skeleton,
                *other,
                u,
            )
            .ok()?;
            Some(arm - normal.dot(velocity(&o)))
        }
        (_, Some(o)) => {
            // The approaching part's own velocity (a hand, not the body).
            let position = dh.position(&now.model.robot, &now.data.frames);
            Some(arm - normal.dot(now.state.sensed.approach_velocity(o, position)))
        }
        (_, None) => None,
    }
}

/// What the `transitionTooSlow` monitor knows of one control point.
pub(super) struct Approach<'a> {
    /// The obstacle it answers, if any.
    pub owner: Option<usize>,
    /// The velocity of that obstacle's part nearest the point (m/s).
    pub obstacle_velocity: DVec3,
    /// The id it reports.
    pub name: &'a str,
    /// Time to collision (s).
    pub ttc: f64,
    /// Unit normal from the point towards the obstacle.
    pub normal: DVec3,
    /// Time left of its transition (s).
    pub remaining: f64,
    /// Time the arm needs to stop (s).
    pub braking: f64,
    /// Filtered closing speed (m/s).
    pub closing: Option<f64>,
    /// Whether it was already too slow at the last step.
    pub was_slow: bool,
}

/// Fraction of a joint's speed limit it must reach in one direction for
/// a change of direction to count as a reversal of the command.
pub const REVERSAL_SPEED: f64 = 0.1;

/// Reversals of each joint's motion: a command that oscillates is caught
/// like a chattering control point.
#[derive(Clone, Debug, Default)]
pub(super) struct CommandMonitor {
    signs: Vec<f64>,
    counters: Vec<crate::dependability::SwitchCounter>,
    chattering: bool,
}

impl CommandMonitor {
    /// Whether some joint's command oscillates now.
    pub(super) fn chattering(&self) -> bool {
        self.chattering
    }
}

/// The command monitor: each joint's direction of motion, reversed at
/// more than [`REVERSAL_SPEED`] of its speed limit, is counted over
/// `8 × switchWindow`; more than `2 × maxSwitches` reversals of one
/// joint there are a sustained oscillation (by default more than six
/// reversals in 4 s: three cycles of a period under about 1.3 s; an
/// avoidance that moves away and back, twice, is not one): a
/// `chattering` event naming the joint (`command:<joint>`) and a stop,
/// whatever the policy (a command cannot be locked).
///
/// `path` is the `joints` task's reference velocity this step (empty
/// without one): a reversal to the direction the path itself now moves
/// that joint in is the path's, not an oscillation, and is not counted.
/// A planned path stops at each of its waypoints, and one that creeps out
/// between boxes turns a joint back and forth more than six times in 4 s.
pub(super) fn monitor_command(model: &Model, state: &mut State, log: &mut EventLog, path: &[f64]) {
    let dep = model.scenario.dependability;
    let window = 8.0 * dep.switch_window;
    let n = state.motion.qdot.len();
    let m = &mut state.stop.command_monitor;
    m.signs.resize(n, 0.0);
    m.counters.resize_with(n, Default::default);
    let mut worst = (0, 0);
    for (k, (v, j)) in state
        .motion
        .qdot
        .iter()
        .zip(&model.robot.joints)
        .enumerate()
    {
        let count = if v.abs() > REVERSAL_SPEED * j.max_velocity && v.signum() != m.signs[k] {
            let asked = path
                .get(k)
                .is_some_and(|r| *r != 0.0 && r.signum() == v.signum());
            let reversal = m.signs[k] != 0.0 && !asked;
            m.signs[k] = v.signum();
            if reversal {
                m.counters[k].record(state.t, window)
            } else {
                m.counters[k].count(state.t, window)
            }
        } else {
            m.counters[k].count(state.t, window)
        };
        if count > worst.1 {
            worst = (k, count);
        }
    }
    let chattering = worst.1 > 2 * dep.max_switches as usize;
    let rising = chattering && !m.chattering;
    m.chattering = chattering;
    if rising {
        let name = format!(
            "command:{}",
            model
                .robot
                .link_label(worst.0 + 1)
                .replace("link ", "joint ")
        );
        log.push(
            state.t,
            EventKind::Chattering {
                obstacle: name.clone(),
                switches: worst.1,
            },
        );
        stop(
            state,
            log,
            StopReason::Chattering,
            format!("oscillating command ({name})"),
            dep.lock_time,
        );
    }
}
