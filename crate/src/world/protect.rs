//! Stage 7 of the control step, the protective layer, and the guards the
//! `constraints` avoidance solves with ([`crate::avoidance::protect`],
//! [`crate::avoidance::constraints`]).
//!
//! The guards are prepared before the control stage: every pair within
//! the influence distance with its protective bound, its damper (in the
//! `constraints` avoidance) and, for an obstacle closing in faster than
//! the arm could stop, the escape the joints can still make
//! ([`crate::avoidance::protect::Guard::escape`]). After the controller, [`protect()`] projects
//! the request onto the protective bounds (a no-op for the `constraints`
//! avoidance, whose request already meets them) and stops the arm when no
//! admissible motion keeps a pair safe. The arithmetic of the bounds lives
//! in [`crate::avoidance::protect`]; here only the world's state and events.

use std::collections::BTreeSet;

use super::StopReason;
use super::motion::PartMotion;
use super::parts::{EventLog, Model, State, StepData};
use super::tracker::stop;
use crate::avoidance::ControllerConfig;
use crate::avoidance::neo::{DamperContext, collision_dampers};
use crate::avoidance::protect::{self, GuardContext, GuardPair};
use crate::avoidance::selection::fraction_on;
use crate::dependability::EventKind;
use crate::distance::{PairDistance, Primitive, Target, distance};
use crate::error::FieldError;
use crate::skeleton::Skeleton;

/// The pairs the protective layer guards: every pair within the
/// influence distance, obstacles as sensed (margin subtracted). A
/// segment–obstacle pair is guarded at its witness and, unless the
/// obstacle is a point or a sphere, at both ends of the segment: where
/// a segment runs nearly parallel to a face or an edge, its
/// witness can jump from one end to the other between two steps, onto
/// a point that moves differently; guarding the ends bounds that point
/// before the jump (measured on the PR2 reach problems).
///
/// An obstacle's approach speed is that of its part's material point at
/// the witness (a human's hand moving with its arm, not the body).
fn guard_pairs(state: &State, data: &mut StepData, cfg: &ControllerConfig, pairs: &[PairDistance]) {
    let mut out = std::mem::take(&mut data.guard.pairs);
    out.clear();
    for p in pairs {
        let (distance, obstacle, other, speed, part) = match p.target {
            Target::Obstacle { id, .. } => {
                let o = state.sensed.owners[id as usize];
                let motion = state
                    .sensed
                    .part_motion
                    .get(id as usize)
                    .copied()
                    .unwrap_or_default();
                if !cfg.uses_neo() {
                    end_pairs(state, data, cfg, p, (id as usize, o, &motion), &mut out);
                }
                // The part's own margin (its own σ with `partSigma`).
                let margin =
                    state.sensed.obstacles[o].part_margin(state.sensed.part_index[id as usize]);
                // A stale part's region grows towards the arm.
                let growth =
                    state.sensed.obstacles[o].margin_growth(state.sensed.part_index[id as usize]);
                (
                    p.distance - margin,
                    Some(o),
                    None,
                    -p.normal.dot(motion.velocity_at(p.point_other)) + growth,
                    Some(id as usize),
                )
            }
            Target::Segment(other) => {
                let u = fraction_on(&data.skeleton, other, p.point_other);
                (p.distance, None, Some((other, u)), 0.0, None)
            }
        };
        if cfg.beyond_influence(distance) {
            continue;
        }
        out.push(GuardPair {
            segment: p.segment,
            fraction: p.fraction,
            other,
            normal: p.normal,
            distance,
            obstacle_speed: speed,
            obstacle,
            part,
            contact: None,
        });
    }
    data.guard.pairs = out;
}

/// The `startContact` event: the deepest of the pairs that overlap in
/// the first step, if any.
pub(super) fn report_start_contact(
    model: &Model,
    state: &State,
    data: &StepData,
    log: &mut EventLog,
    pairs: &[PairDistance],
) {
    let overlapping = pairs.iter().filter(|p| p.distance <= 0.0);
    let Some(deepest) = overlapping
        .clone()
        .min_by(|a, b| a.distance.total_cmp(&b.distance))
    else {
        return;
    };
    let link = data.skeleton.segments[deepest.segment].link;
    let obstacle = match deepest.target {
        Target::Obstacle { id, .. } => state.sensed.obstacles[state.sensed.owners[id as usize]]
            .spec
            .id
            .clone(),
        Target::Segment(other) => {
            format!(
                "self:{}",
                model.robot.link_label(data.skeleton.segments[other].link)
            )
        }
    };
    log.push(
        state.t,
        EventKind::StartContact {
            obstacle,
            link: model.robot.link_label(link),
            distance: deepest.distance,
            pairs: overlapping.count(),
        },
    );
}

/// Guard pairs at the ends of `p`'s segment against scene part `part`
/// (obstacle `o`, moving at `v`), where they are within the influence
/// distance and not at the witness already.
fn end_pairs(
    state: &State,
    data: &StepData,
    cfg: &ControllerConfig,
    p: &PairDistance,
    (part, o, motion): (usize, usize, &PartMotion),
    out: &mut Vec<GuardPair>,
) {
    let Some(shape) = state.sensed.scene.obstacles().get(part).map(|x| &x.shape) else {
        return;
    };
    // Against a point or a sphere the clearance along a segment has one
    // minimum that moves continuously: its witness never jumps.
    if matches!(shape, Primitive::Point(_) | Primitive::Sphere(_)) {
        return;
    }
    let seg = &data.skeleton.segments[p.segment];
    let (a, b) = data.skeleton.endpoints(seg);
    for (t, end) in [(0.0, a), (1.0, b)] {
        if (p.fraction - t).abs() < 0.05 {
            continue;
        }
        let Ok(d) = distance(&Primitive::Point(end), shape) else {
            continue;
        };
        let margin = state.sensed.obstacles[o].part_margin(state.sensed.part_index[part]);
        let clearance = d.distance - Skeleton::radius_at(seg, t) - margin;
        if cfg.beyond_influence(clearance) || d.distance <= 0.0 {
            continue;
        }
        out.push(GuardPair {
            segment: p.segment,
            fraction: t,
            other: None,
            normal: d.normal,
            distance: clearance,
            obstacle_speed: -d.normal.dot(motion.velocity_at(d.point_b)),
            obstacle: Some(o),
            part: Some(part),
            contact: None,
        });
    }
}

/// The guards of this step (before the control stage): protective
/// bounds, dampers, the time-to-collision slowdown, and the escape from
/// obstacles that close in faster than the arm could stop
/// ([`protect::prepare`]). An obstacle with no admissible escape is
/// remembered in `data.guard.doomed`.
pub(super) fn prepare_guards(
    model: &Model,
    state: &State,
    data: &mut StepData,
    pairs: &[PairDistance],
    dt: f64,
) -> Result<(), FieldError> {
    let cfg = &model.scenario.controller;
    data.guard.doomed = None;
    data.guard.stop_time = f64::INFINITY;
    if cfg.uses_neo() {
        // NEO's collision dampers at the witnesses, no protective bounds.
        guard_pairs(state, data, cfg, pairs);
        let ctx = DamperContext {
            robot: &model.robot,
            frames: &data.frames,
            skeleton: &data.skeleton,
            config: &cfg.neo,
        };
        return collision_dampers(&ctx, &data.guard.pairs, &mut data.guard.guards);
    }
    if !cfg.protective.enabled {
        data.guard.guards.clear();
        return Ok(());
    }
    guard_pairs(state, data, cfg, pairs);
    super::pfl::fill_contacts(model, state, data)?;
    data.readout.protection = super::pfl::protection_readout(model, state, data, dt);
    data.guard.stop_time = protect::stop_time(&data.guard.pairs, cfg, state.stop.stopped, dt);
    let mut guards = std::mem::take(&mut data.guard.guards);
    let mut bend = std::mem::take(&mut data.guard.bend);
    let ctx = guard_context(model, state, data, dt);
    let doomed = protect::prepare(
        &ctx,
        &data.guard.pairs,
        &data.slowdown,
        (&mut guards, &mut bend),
    );
    data.guard.guards = guards;
    data.guard.stop_time = data.guard.stop_time.min(bend.stop_time);
    data.guard.bend = bend;
    data.guard.doomed = doomed?;
    Ok(())
}

/// What the guards are computed from, now.
fn guard_context<'a>(
    model: &'a Model,
    state: &'a State,
    data: &'a StepData,
    dt: f64,
) -> GuardContext<'a> {
    GuardContext {
        robot: &model.robot,
        frames: &data.frames,
        skeleton: &data.skeleton,
        q: &state.q,
        motion: &state.motion,
        stopped: state.stop.stopped,
        stop_time: data.guard.stop_time,
        dt,
        config: &model.scenario.controller,
    }
}

/// Stage 7: the protective layer. Projects the request onto the guards
/// and the admissible velocity box ([`protect::protect`]); when no
/// admissible motion keeps a pair safe the arm stops (`unavoidable`).
/// Returns whether every guard of an approaching obstacle holds with
/// the arm at rest (a stop after an unavoidable approach may then end;
/// static and receding obstacles are backed out of instead).
pub(super) fn protect(
    model: &Model,
    state: &mut State,
    data: &mut StepData,
    log: &mut EventLog,
    dt: f64,
) -> bool {
    let cfg = &model.scenario.controller;
    if !cfg.protective.enabled || cfg.uses_neo() {
        return true;
    }
    let guards = std::mem::take(&mut data.guard.guards);
    let mut request = std::mem::take(&mut data.request);
    let ctx = guard_context(model, state, data, dt);
    let outcome = protect::protect(
        &ctx,
        &data.guard.pairs,
        &guards,
        data.guard.doomed,
        &mut request,
    );
    data.request = request;
    state.stop.braking = outcome.braking;
    let braking = outcome.braking_time;
    let mut now = BTreeSet::new();
    if let Some((k, excess)) = outcome.doomed.filter(|_| !state.stop.stopped) {
        let g = &guards[k];
        let key = g.obstacle.unwrap_or(usize::MAX);
        now.insert(key);
        if !state.stop.unavoidable.contains(&key) {
            let obstacle = g.obstacle.map_or_else(
                || format!("self:{}", data.skeleton.segments[g.segment].link),
                |o| state.sensed.obstacles[o].spec.id.clone(),
            );
            log.push(
                state.t,
                EventKind::Unavoidable {
                    obstacle: obstacle.clone(),
                    segment: g.segment,
                    distance: g.distance,
                    excess,
                },
            );
            // Held until the joints are at rest and every approaching
            // obstacle's guard holds again (`maybe_resume`).
            stop(
                state,
                log,
                StopReason::Unavoidable,
                format!("unavoidable approach ({obstacle})"),
                braking,
            );
            data.request.iter_mut().for_each(|v| *v = 0.0);
        }
    }
    state.stop.unavoidable = now;
    data.guard.guards = guards;
    outcome.all_hold
}
