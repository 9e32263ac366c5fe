//! One control step of a [`super::World`]: the stages of the pipeline,
//! called in order over the model, the state, the step data and the event
//! log (the configuration is borrowed from the model, never copied).
//!
//! | # | stage | function |
//! |---|---|---|
//! | 1 | sense | [`super::sense::sense`] |
//! | 2 | scene query | [`super::query::scene_query`] (and the `startContact` event at `t = 0`) |
//! | 3 | select | [`super::select::select`] |
//! | 4 | transition | [`super::tracker::track`] (after the switch-risk monitor) |
//! | 5 | monitor | [`super::active::active_points`] (time to collision, `transitionTooSlow`) |
//! | 6 | control | [`super::protect::prepare_guards`], then [`super::control::control`] |
//! | 7 | protect | [`super::protect::protect`], then [`super::tracker::maybe_resume`] |
//! | 8–9 | limit and integrate | [`super::limit::limit_and_integrate`], then [`super::monitor::monitor_command`] |

use super::active::active_points;
use super::control::control;
use super::limit::limit_and_integrate;
use super::monitor::monitor_command;
use super::parts::{EventLog, Model, State, StepData};
use super::protect::{prepare_guards, protect, report_start_contact};
use super::query::scene_query;
use super::select::select;
use super::sense::sense;
use super::tracker::{maybe_resume, monitor_switch_risk, track};
use crate::avoidance::limits;
use crate::error::FieldError;

/// Advances the world by `dt` seconds (one control step). A non-finite or
/// non-positive `dt` does nothing.
pub(super) fn step(
    model: &Model,
    state: &mut State,
    data: &mut StepData,
    log: &mut EventLog,
    dt: f64,
) {
    if !(dt.is_finite() && dt > 0.0) {
        return;
    }
    if stages(model, state, data, log, dt).is_err() {
        // Only reachable through a bug: brake as a stop would.
        let n = model.robot.dof();
        limits::step(&model.robot, &state.q, &vec![0.0; n], &mut state.motion, dt);
    }
    log.trim();
}

/// The stages, in order.
fn stages(
    model: &Model,
    state: &mut State,
    data: &mut StepData,
    log: &mut EventLog,
    dt: f64,
) -> Result<(), FieldError> {
    // 1. sense
    sense(state, log, dt);
    // 2. scene query
    let pairs = scene_query(model, state, data)?;
    if state.t == 0.0 {
        report_start_contact(model, state, data, log, &pairs);
    }
    // 3. select
    let selected = select(model, state, data, &pairs);
    // 4.–5. transition and monitor
    monitor_switch_risk(model, state, log, &pairs, &selected);
    track(model, state, data, log, &selected, &pairs, dt)?;
    let active = active_points(model, state, data, log, dt)?;
    // 6. control (what the propagation of the sensing errors needs is
    // kept, and computed when the state is read)
    data.propagation.qdot.clone_from(&state.motion.qdot);
    data.propagation.q.clone_from(&state.q);
    data.propagation.dt = dt;
    prepare_guards(model, state, data, &pairs, dt)?;
    control(model, state, data, &active, dt)?;
    data.propagation.active = active;
    // 7. protect
    let all_hold = protect(model, state, data, log, dt);
    maybe_resume(state, log, all_hold);
    // 8.–9. limit and integrate, then the command monitor
    limit_and_integrate(model, state, data, dt);
    monitor_command(model, state, log, &data.joint_path.qdot);
    Ok(())
}
