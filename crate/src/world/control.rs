//! Stage 6 of the control step, *control*: the task references, then the
//! repulsion and the tasks as requested joint velocities (paper §III-A,
//! eq. 4), the `constraints` avoidance's QP
//! ([`crate::avoidance::constraints`]) or NEO's ([`crate::avoidance::neo`]).

use super::parts::{Model, State, StepData};
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
    let (jq, jv) = &mut data.joint_reference;
    let in_joints = model.scenario.task.joint_reference(state.t, jq, jv);
    if cfg.uses_constraints() {
        let input = ConstraintsInput {
            robot: &model.robot,
            frames: &data.frames,
            q: &state.q,
            stop_time: data.guard.stop_time,
            tasks: &data.references,
            joints: in_joints.then_some(JointTarget {
                q: &data.joint_reference.0,
                qdot: &data.joint_reference.1,
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
