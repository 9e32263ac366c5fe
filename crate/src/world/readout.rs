//! Cheap readouts of a [`World`]: the joint velocities and the clearance to
//! one obstacle, without building the whole [`super::WorldState`] (a page
//! that plots one number per frame reads it here).

use super::World;
use crate::distance::{BroadPhase, Obstacle, QueryOptions, Scene};
use crate::error::FieldError;
use crate::scenario::ScenarioError;

impl World {
    /// Joint velocities now (rad/s or m/s), in the order of `q`.
    #[must_use]
    pub fn qdot(&self) -> &[f64] {
        &self.state.motion.qdot
    }

    /// [`World::clearance_of`] every obstacle now, by id (infinite ones
    /// left out: a robot without segments).
    #[must_use]
    pub fn clearances(&self) -> std::collections::BTreeMap<String, f64> {
        self.state
            .sensed
            .obstacles
            .iter()
            .filter_map(|o| {
                let d = self.clearance_of(&o.spec.id).ok()?;
                d.is_finite().then(|| (o.spec.id.clone(), d))
            })
            .collect()
    }

    /// Clearance (m) between the arm's volumes and obstacle `id` at its
    /// current (true) pose; negative by the penetration depth when they
    /// overlap, infinite for a robot without segments.
    ///
    /// # Errors
    /// `id: no obstacle "…"` for an unknown id.
    pub fn clearance_of(&self, id: &str) -> Result<f64, ScenarioError> {
        let k = self.index_of(id)?;
        let o = &self.state.sensed.obstacles[k];
        let off = o.offset(self.state.t);
        let scene = Scene::new(
            o.parts
                .iter()
                .enumerate()
                .map(|(n, p)| Obstacle {
                    id: n as u32,
                    shape: p.translated(off),
                })
                .collect(),
        );
        let options = QueryOptions {
            influence_distance: f64::MAX,
            self_collision: false,
            broad_phase: BroadPhase::BruteForce,
        };
        let pairs = scene
            .query(&self.data.skeleton, &options, |_, _| true)
            .map_err(|e| FieldError::new("id", e.to_string()))?;
        Ok(pairs
            .iter()
            .map(|p| p.distance)
            .fold(f64::INFINITY, f64::min))
    }
}
