//! Obstacles of a [`World`]: their figure, motion and sensing model, the
//! scene of the *sense* stage (obstacles at `t` as sensed) and distances
//! from a point to one obstacle.

use glam::DVec3;

use super::World;
use crate::dependability::{Covariance, SensorModel};
use crate::distance::{Obstacle, Primitive, Scene, distance};
use crate::error::FieldError;
use crate::scenario::{ObstacleSpec, Scenario, primitives, reference_point};

#[derive(Clone, Debug)]
pub(super) struct ObstacleState {
    pub(super) spec: ObstacleSpec,
    pub(super) reference: DVec3,
    pub(super) parts: Vec<Primitive>,
    pub(super) sensor: SensorModel,
    /// The margin of the sensing error at this step (m): the sensor's own
    /// ([`SensorModel::margin`]) plus `latency ×` the obstacle's speed.
    pub(super) margin: f64,
    /// Covariance of the sensed position ([`SensorModel::covariance`]).
    pub(super) covariance: Covariance,
    /// The monitor's last switch probability of this obstacle's closest
    /// segment, with that segment and the likeliest other one.
    pub(super) switch: SwitchOdds,
}

/// The probability that the closest segment of an obstacle, as sensed,
/// differs from the ideal one ([`crate::dependability::switch_probability`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct SwitchOdds {
    pub(super) probability: f64,
    pub(super) segment: Option<usize>,
    pub(super) alternative: Option<usize>,
}

impl ObstacleState {
    pub(super) fn new(
        spec: ObstacleSpec,
        scenario: &Scenario,
        index: usize,
    ) -> Result<Self, FieldError> {
        let parts = primitives(&spec.shape).map_err(|e| e.within("shape"))?;
        let s = scenario.sensing.for_obstacle(&spec.id);
        let seed = s.seed.unwrap_or(1 + index as u64);
        let sensor = SensorModel::from_spec(&s, seed);
        Ok(Self {
            reference: reference_point(&spec.shape),
            parts,
            margin: sensor.margin(),
            covariance: sensor.covariance(),
            switch: SwitchOdds::default(),
            sensor,
            spec,
        })
    }

    pub(super) fn offset(&self, t: f64) -> DVec3 {
        self.spec
            .motion
            .as_ref()
            .map_or(DVec3::ZERO, |m| m.offset(t, self.reference))
    }

    /// Velocity of its motion at `t` (m/s): the smaller of the forward and
    /// the backward difference over `dt`, so that a jump of a waypoint
    /// motion (an obstacle that appears elsewhere) is not read as an
    /// approach speed.
    pub(super) fn velocity(&self, t: f64, dt: f64) -> DVec3 {
        match &self.spec.motion {
            None | Some(crate::scenario::Motion::Static) => DVec3::ZERO,
            Some(_) => {
                let now = self.offset(t);
                let ahead = (self.offset(t + dt) - now) / dt;
                let behind = (now - self.offset((t - dt).max(0.0))) / dt;
                if t < dt || ahead.length_squared() <= behind.length_squared() {
                    ahead
                } else {
                    behind
                }
            }
        }
    }

    /// Updates [`ObstacleState::margin`] for time `t`: with latency, the
    /// obstacle may have moved `latency × speed` since it was seen (first
    /// order).
    pub(super) fn update_margin(&mut self, t: f64, dt: f64) {
        let latency = self.sensor.latency();
        self.margin = self.sensor.margin();
        if latency > 0.0 {
            let speed = self.velocity(t, dt).length();
            if speed.is_finite() {
                self.margin += latency * speed;
            }
        }
    }

    pub(super) fn moves(&self) -> bool {
        !self.sensor.is_exact()
            || self
                .spec
                .motion
                .as_ref()
                .is_some_and(|m| *m != crate::scenario::Motion::Static)
    }
}

impl World {
    /// The *sense* stage: the scene of the obstacles at time `t`, as sensed
    /// when `sensed` (seen `latency` late, displaced by their sensing
    /// errors).
    pub(super) fn rebuild_scene(&mut self, t: f64, sensed: bool) {
        let mut obstacles = Vec::new();
        self.owners.clear();
        for (k, o) in self.obstacles.iter_mut().enumerate() {
            let mut off = o.offset(t);
            if sensed && !o.sensor.is_exact() {
                let latency = o.sensor.latency();
                if latency > 0.0 {
                    off = o.offset((t - latency).max(0.0));
                }
                off += o.sensor.sample_at(t);
            }
            for p in &o.parts {
                let id = self.owners.len() as u32;
                self.owners.push(k);
                obstacles.push(Obstacle {
                    id,
                    shape: if off == DVec3::ZERO {
                        p.clone()
                    } else {
                        p.translated(off)
                    },
                });
            }
        }
        self.scene = Scene::new(obstacles);
        self.scene_dirty = false;
    }

    pub(super) fn clone_scene_at(&self, t: f64) -> Scene {
        let mut obstacles = Vec::new();
        let mut id = 0u32;
        for o in &self.obstacles {
            let off = o.offset(t);
            for p in &o.parts {
                obstacles.push(Obstacle {
                    id,
                    shape: p.translated(off),
                });
                id += 1;
            }
        }
        Scene::new(obstacles)
    }

    /// Distance from `p` to obstacle `o` as sensed (its closest part):
    /// distance, unit normal from `p` towards it, witness on it.
    pub(super) fn point_distance(
        &self,
        o: usize,
        p: DVec3,
    ) -> Result<(f64, DVec3, DVec3), FieldError> {
        let me = Primitive::Point(p);
        let mut best: Option<(f64, DVec3, DVec3)> = None;
        // `owners` is sorted: obstacle o's parts are one contiguous run.
        let start = self.owners.partition_point(|&x| x < o);
        let end = self.owners.partition_point(|&x| x <= o);
        for ob in self.scene.obstacles().get(start..end).unwrap_or(&[]) {
            let d =
                distance(&me, &ob.shape).map_err(|e| FieldError::new("scene", e.to_string()))?;
            if best.is_none_or(|b| d.distance < b.0) {
                best = Some((d.distance, d.normal, d.point_b));
            }
        }
        Ok(best.unwrap_or((f64::INFINITY, DVec3::Z, p)))
    }

    pub(super) fn closest_obstacle(&self, p: DVec3) -> Option<usize> {
        let mut best: Option<(f64, usize)> = None;
        for o in 0..self.obstacles.len() {
            if let Ok((d, _, _)) = self.point_distance(o, p)
                && best.is_none_or(|b| d < b.0)
            {
                best = Some((d, o));
            }
        }
        best.map(|b| b.1)
    }
}
