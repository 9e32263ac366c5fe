//! Stages 8 and 9 of the control step, *limit* and *integrate*: the
//! jerk-limited tracking of the request within the joints' limits
//! ([`crate::avoidance::limits`]), then `q += q̇ dt` and `t += dt`. NEO's
//! command as published skips the limiter (`neo.limiter: false`).

use super::StopReason;
use super::parts::{Model, State, StepData};
use crate::avoidance::limits;

/// Stages 8 and 9: the joint limits, then `q += q̇ dt`, `t += dt`
/// (counted as `k·dt`, see `clock`).
pub(super) fn limit_and_integrate(model: &Model, state: &mut State, data: &mut StepData, dt: f64) {
    data.propagation.t = state.t;
    let cfg = &model.scenario.controller;
    if cfg.uses_neo() && !cfg.neo.limiter {
        straight_to_the_joints(model, state, data, dt);
        return;
    }
    // A chattering stop decelerates gently (`maxDeceleration`; a joint
    // nearing a position limit still brakes in time for it); a stop
    // before an unavoidable contact and the emergency brake use the
    // full deceleration of the slowest joint. Every stop is
    // synchronised: the joint velocities shrink along one line to zero,
    // so every pair's approach speed shrinks with them (joints braked
    // each at its own rate can turn a motion along an obstacle into one
    // towards it: measured on the PR2 reach problems).
    let urgent = state.stop.braking || state.stop.reason == Some(StopReason::Unavoidable);
    let options = limits::StepOptions {
        stop_deceleration: if state.stop.stopped && !urgent {
            model.scenario.dependability.max_deceleration
        } else {
            f64::INFINITY
        },
        ..limits::StepOptions::default()
    };
    super::dynamics::before_limit(model, state, data);
    limits::step_with(
        &model.robot,
        &state.q,
        &data.request,
        &mut state.motion,
        dt,
        &options,
    );
    super::dynamics::hold_torque_limits(model, state, data, &options, dt);
    for (q, v) in state.q.iter_mut().zip(&state.motion.qdot) {
        *q += v * dt;
    }
    model.robot.clamp_to_limits(&mut state.q);
    state.t = state.clock.advance(state.t, dt);
}

/// NEO's command as published: the joints take the requested velocity at
/// once (within their speed limits, which NEO's programme already keeps),
/// then `q += q̇ dt` and `t += dt`.
fn straight_to_the_joints(model: &Model, state: &mut State, data: &StepData, dt: f64) {
    let motion = &mut state.motion;
    for (k, j) in model.robot.joints.iter().enumerate() {
        let v = data
            .request
            .get(k)
            .copied()
            .unwrap_or(0.0)
            .clamp(-j.max_velocity, j.max_velocity);
        motion.qddot[k] = (v - motion.qdot[k]) / dt;
        motion.qdot[k] = v;
        state.q[k] += v * dt;
    }
    model.robot.clamp_to_limits(&mut state.q);
    state.t = state.clock.advance(state.t, dt);
}
