//! Stage 1 of the control step, *sense*: the obstacles at `t`, then as
//! sensed (bias, bounded error, white and correlated noise, latency), and
//! each obstacle's margin (paper §IV; the scene is built in
//! [`super::parts::Sensed::rebuild_scene`]).

use super::motion::DRAG_HOLD;
use super::parts::{EventLog, State};

/// Rebuilds the scene of the obstacles as sensed when one moves (or an
/// edit asked for it), and updates every obstacle's margin (a streamed
/// human's parts grown by the age of their data, `stream.rs`).
pub(super) fn sense(state: &mut State, log: &mut EventLog, dt: f64) {
    // A figure moved by edits counts as moving until its edit velocity
    // has expired, so that the scene (which carries each part's
    // velocity) is rebuilt once more with the figure at rest.
    let t = state.t;
    let moving = state
        .sensed
        .obstacles
        .iter()
        .any(|o| o.moves() || o.dragged.is_some_and(|(at, _)| t - at <= 2.0 * DRAG_HOLD));
    if moving || state.sensed.dirty {
        state.sensed.rebuild_scene(state.t, true, dt);
    }
    let t = state.t;
    for o in &mut state.sensed.obstacles {
        o.update_margin(t, dt);
        for kind in o.stale_margins(t) {
            log.push(t, kind);
        }
    }
}
