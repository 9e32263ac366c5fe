//! Stage 3 of the control step, *select*: the control points per pair,
//! per obstacle, pinned or self ([`crate::avoidance::selection::select`],
//! paper §II, fig. 4).

use std::collections::BTreeMap;

use super::parts::{Model, State, StepData};
use crate::avoidance::selection::{self, Key, Selected};
use crate::distance::PairDistance;

/// The points the control points should be at, from this step's pairs.
pub(super) fn select(
    model: &Model,
    state: &State,
    data: &StepData,
    pairs: &[PairDistance],
) -> Selected {
    let cfg = &model.scenario.controller;
    let margins: Vec<f64> = state.sensed.obstacles.iter().map(|o| o.margin).collect();
    // The segments the perObstacle points follow, read only with a
    // hysteresis (an empty map allocates nothing on this hot path).
    let following: BTreeMap<usize, usize> = if cfg.switch_hysteresis > 0.0 {
        state
            .trackers
            .iter()
            .filter_map(|(key, t)| match key {
                Key::Obstacle(o) => Some((*o, t.mover.selected().segment)),
                _ => None,
            })
            .collect()
    } else {
        BTreeMap::new()
    };
    selection::select(
        pairs,
        &state.sensed.owners,
        &margins,
        &following,
        &data.skeleton,
        cfg,
    )
}
