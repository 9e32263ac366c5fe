//! Stage 6 of the control step, *control*: the task references, then the
//! repulsion and the tasks as requested joint velocities (paper §III-A,
//! eq. 4), the `constraints` avoidance's QP
//! ([`crate::avoidance::constraints`]) or NEO's ([`crate::avoidance::neo`]).

use super::parts::{JointPathData, Model, State, StepData};
use crate::avoidance::constraints::{ConstraintsInput, constrained_velocity};
use crate::avoidance::neo::{NeoInput, neo_velocity};
use crate::avoidance::rows::JointTarget;
use crate::avoidance::{self, ActivePoint, Mode};
use crate::error::FieldError;

/// Stage 6: the controller's requested joint velocities (zero while
/// stopped).
pub(super) fn control(
    model: &Model,
    state: &State,
    data: &mut StepData,
    active: &[ActivePoint],
    dt: f64,
) -> Result<(), FieldError> {
    let cfg = &model.scenario.controller;
    let mut refs = std::mem::take(&mut data.references);
    model.scenario.task.references(
        &model.robot,
        state.t,
        &state.anchors,
        cfg.uses_constraints() || cfg.uses_neo(),
        &mut refs,
    );
    data.references = refs;
    let in_joints = joint_path(model, state, &mut data.joint_path, dt);
    if cfg.uses_constraints() {
        let input = ConstraintsInput {
            robot: &model.robot,
            frames: &data.frames,
            q: &state.q,
            stop_time: data.guard.stop_time,
            tasks: &data.references,
            joints: in_joints.then_some(JointTarget {
                q: &data.joint_path.q,
                qdot: &data.joint_path.qdot,
                now: &state.q,
            }),
            guards: &data.guard.guards,
            config: cfg,
        };
        let mut out = std::mem::take(&mut data.request);
        let outcome = constrained_velocity(&input, &mut data.guard.qp, &mut out)?;
        data.guard.relaxed = outcome.relaxed;
        data.request = out;
    } else if cfg.uses_neo() {
        let input = NeoInput {
            robot: &model.robot,
            frames: &data.frames,
            q: &state.q,
            tasks: &data.references,
            dampers: &data.guard.guards,
            config: cfg,
        };
        let mut out = std::mem::take(&mut data.request);
        let outcome = neo_velocity(&input, &mut data.guard.qp, &mut out)?;
        data.guard.relaxed = outcome.solution.worst.is_some();
        data.request = out;
    } else {
        let joints = (state.q.as_slice(), state.motion.qdot.as_slice());
        data.request = if cfg.mode == Mode::Torque {
            super::dynamics::torque_request(model, data, active, joints, dt)?
        } else {
            request_for(model, data, active, joints, dt)?
        };
    }
    if state.stop.stopped {
        data.request.iter_mut().for_each(|v| *v = 0.0);
    }
    Ok(())
}

/// Lag (rad, largest over the joints) up to which a `joints` task's path
/// runs at the world's pace.
const LAG_FREE: f64 = 0.03;
/// Lag at which the path waits for the arm.
const LAG_STOP: f64 = 0.1;

/// The `joints` task's reference this step into `path` (`false` without
/// one). The path runs on its own clock, which advances by `dt` while the
/// arm is within [`LAG_FREE`] of the reference, slower beyond, and not at
/// all from [`LAG_STOP`] (the feed-forward velocity scaled alike): when a
/// guard holds the arm back, or the limits let it fall behind, the
/// reference waits for it instead of running ahead, and the arm, pulled
/// back to the path rather than straight towards a reference far along
/// it, stays on the segments the planner certified.
fn joint_path(model: &Model, state: &State, path: &mut JointPathData, dt: f64) -> bool {
    let task = &model.scenario.task;
    if !task.joint_reference(path.time, &mut path.q, &mut path.qdot) {
        return false;
    }
    let lag = path
        .q
        .iter()
        .zip(&state.q)
        .fold(0.0_f64, |m, (r, q)| m.max((r - q).abs()));
    let rate = ((LAG_STOP - lag) / (LAG_STOP - LAG_FREE)).clamp(0.0, 1.0);
    path.qdot.iter_mut().for_each(|v| *v *= rate);
    path.time += dt * rate;
    true
}

/// The controller's joint command for the active points `active` and
/// this step's task references (the paper's repulsion; the
/// `constraints` avoidance is solved in [`control`]).
pub(super) fn request_for(
    model: &Model,
    data: &StepData,
    active: &[ActivePoint],
    (q, qdot): (&[f64], &[f64]),
    dt: f64,
) -> Result<Vec<f64>, FieldError> {
    let cfg = &model.scenario.controller;
    let (robot, frames) = (&model.robot, &data.frames);
    let refs = &data.references;
    Ok(match cfg.mode {
        Mode::Velocity => avoidance::velocity_control(robot, frames, active, refs, cfg)?,
        Mode::Torque => {
            let dynamics = model.dynamics.as_ref().map_err(Clone::clone)?;
            let input = avoidance::TorqueInput {
                dynamics,
                frames,
                q,
                qdot,
                points: active,
                tasks: refs,
                config: cfg,
                dt,
            };
            let mut scratch = avoidance::TorqueScratch::new(dynamics);
            avoidance::torque_control(&input, &mut scratch)?.0
        }
        Mode::Clik2 => {
            let joints = avoidance::JointState { q, qdot };
            avoidance::clik2_control(robot, frames, joints, active, refs, cfg, dt)?
        }
    })
}
