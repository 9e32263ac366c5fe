//! Cheap readouts of a [`World`]: the joint velocities and the clearance to
//! one obstacle, without building the whole [`super::WorldState`] (a page
//! that plots one number per frame reads it here).
//!
//! A clearance is measured where the last step measured its control
//! points: the skeleton at the `q` that step acted on, against every
//! obstacle at its true pose at that step's time (a moving figure where
//! its motion has taken it, a human posed by its keyframes, clip or
//! recorded track). Before any step that is `q0` at `t = 0`.

use super::World;
use crate::distance::{BroadPhase, Obstacle, QueryOptions, Scene};
use crate::error::FieldError;
use crate::scenario::ScenarioError;

/// The body of [`World::qdot`].
pub(super) fn qdot(w: &World) -> &[f64] {
    &w.state.motion.qdot
}

/// The body of [`World::clearances`].
pub(super) fn clearances(w: &World) -> std::collections::BTreeMap<String, f64> {
    w.state
        .sensed
        .obstacles
        .iter()
        .filter_map(|o| {
            let d = clearance_of(w, &o.spec.id).ok()?;
            d.is_finite().then(|| (o.spec.id.clone(), d))
        })
        .collect()
}

/// The body of [`World::clearance_of`].
pub(super) fn clearance_of(w: &World, id: &str) -> Result<f64, ScenarioError> {
    let k = w.index_of(id)?;
    let o = &w.state.sensed.obstacles[k];
    let scene = Scene::new(
        o.posed_parts(measured_at(w))
            .into_iter()
            .enumerate()
            .map(|(n, shape)| Obstacle {
                id: n as u32,
                shape,
            })
            .collect(),
    );
    let options = QueryOptions {
        influence_distance: f64::MAX,
        self_collision: false,
        broad_phase: BroadPhase::BruteForce,
    };
    let pairs = scene
        .query(&w.data.skeleton, &options, |_, _| true)
        .map_err(|e| FieldError::new("id", e.to_string()))?;
    Ok(pairs
        .iter()
        .map(|p| p.distance)
        .fold(f64::INFINITY, f64::min))
}

/// The time the last step acted on, that of its skeleton and control
/// points (`0` before any step, as a new world's time is).
fn measured_at(w: &World) -> f64 {
    w.data.propagation.t
}
