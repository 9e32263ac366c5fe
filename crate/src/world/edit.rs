//! Edits of a live [`World`]: obstacles added, removed, reshaped and
//! moved, the controller replaced, picking and reset. A refused edit leaves
//! the world as it was.

use glam::DVec3;

use super::obstacles::ObstacleState;
use super::{PICK_RADIUS, Pick, SkeletonPick, World};
use crate::avoidance::ControllerConfig;
use crate::avoidance::selection::Key;
use crate::control_point::DhPoint;
use crate::error::FieldError;
use crate::scenario::{
    ObstacleSpec, ScenarioError, ShapeSpec, primitives, reference_point, translated,
    validate_controller,
};

/// Largest sensing latency an edit may set (s): the streamed frames kept
/// ([`super::stream::STREAM_WINDOW`] at 30 Hz) cover it.
pub const MAX_SENSING_LATENCY: f64 = 2.0;

impl World {
    pub(super) fn index_of(&self, id: &str) -> Result<usize, FieldError> {
        self.state
            .sensed
            .obstacles
            .iter()
            .position(|o| o.spec.id == id)
            .ok_or_else(|| FieldError::new("id", format!("no obstacle \"{id}\"")))
    }

    /// Adds an obstacle.
    ///
    /// # Errors
    /// An invalid spec (`shape.radius: must be > 0`) or an id already used;
    /// the world is unchanged.
    pub fn add_obstacle(&mut self, spec: ObstacleSpec) -> Result<(), ScenarioError> {
        spec.validate()?;
        if self
            .state
            .sensed
            .obstacles
            .iter()
            .any(|o| o.spec.id == spec.id)
        {
            return Err(FieldError::new("id", format!("\"{}\" is already used", spec.id)).into());
        }
        let k = self.state.sensed.obstacles.len();
        let state = ObstacleState::new(spec.clone(), &self.model.scenario, k)?;
        self.state.sensed.obstacles.push(state);
        self.model.scenario.obstacles.push(spec);
        self.state.sensed.dirty = true;
        Ok(())
    }

    /// Removes obstacle `id` (and its control points).
    ///
    /// # Errors
    /// `id: no obstacle "x"`; the world is unchanged.
    pub fn remove_obstacle(&mut self, id: &str) -> Result<(), ScenarioError> {
        let k = self.index_of(id)?;
        self.state.sensed.obstacles.remove(k);
        self.model.scenario.obstacles.remove(k);
        // Trackers refer to obstacles by index: renumber.
        let old = std::mem::take(&mut self.state.trackers);
        for (key, mut tr) in old {
            let shift = |o: usize| renumber(o, k);
            let new_key = match key {
                Key::Obstacle(o) => shift(o).map(Key::Obstacle),
                Key::Pair(o, s) => shift(o).map(|o| Key::Pair(o, s)),
                other => Some(other),
            };
            if let Some(nk) = new_key {
                tr.owner = tr.owner.and_then(shift);
                self.state.trackers.insert(nk, tr);
            }
        }
        self.state.risky = self
            .state
            .risky
            .iter()
            .filter_map(|&o| renumber(o, k))
            .collect();
        // The last step's noisy control points, read with the state: those
        // answering the removed obstacle answer nothing now.
        self.data
            .propagation
            .sigma_inputs
            .retain_mut(|input| match renumber(input.owner, k) {
                Some(o) => {
                    input.owner = o;
                    true
                }
                None => false,
            });
        // The protective layer's pairs name scene parts, which renumber
        // too: the next step guards afresh.
        self.data.guard.pairs.clear();
        self.state.sensed.dirty = true;
        Ok(())
    }

    /// Replaces the figure of obstacle `id` (its motion is kept).
    ///
    /// # Errors
    /// An unknown id or an invalid figure; the world is unchanged.
    pub fn set_obstacle_shape(&mut self, id: &str, shape: ShapeSpec) -> Result<(), ScenarioError> {
        let k = self.index_of(id)?;
        let parts = primitives(&shape).map_err(|e| e.within("shape"))?;
        let human = super::obstacles::human_of(&shape)?;
        let o = &mut self.state.sensed.obstacles[k];
        let moved = reference_point(&shape) - o.reference;
        if moved != DVec3::ZERO && o.spec.motion.is_none() {
            o.dragged = super::motion::drag_velocity(o.dragged, moved, self.state.t);
        }
        o.reference = reference_point(&shape);
        o.parts = parts;
        if human.is_none() {
            // No longer a person: no stream drives it.
            o.stream = None;
        }
        o.human = human;
        o.spec.shape = shape.clone();
        self.model.scenario.obstacles[k].shape = shape;
        self.state.sensed.dirty = true;
        Ok(())
    }

    /// Takes one frame of a sensed person into human obstacle `id`
    /// (`world/stream.rs`: the fit, the stale sensing).
    ///
    /// # Errors
    /// `obstacleId: no obstacle "x"` (or not a human), `frame.t: must be
    /// after the previous frame's …`, `frame.layout: unknown layout …`,
    /// `frame.keypoints: expected 17 keypoints …`,
    /// `frame.keypoints[3][1]: not a finite number`, `frame.confidence[2]:
    /// …`; the world is unchanged.
    pub fn push_human_frame(
        &mut self,
        id: &str,
        frame: &super::HumanFrame,
    ) -> Result<(), ScenarioError> {
        let k = self
            .index_of(id)
            .map_err(|e| FieldError::new("obstacleId", e.reason))?;
        let o = &mut self.state.sensed.obstacles[k];
        let shape = super::stream::push(o, frame)?;
        self.model.scenario.obstacles[k].shape = shape;
        self.model.scenario.obstacles[k].motion = None;
        self.state.sensed.dirty = true;
        Ok(())
    }

    /// Sets the sensing latency of obstacle `id` (s): its sensed pose is
    /// its pose this long ago, and a streamed person's frames are aged
    /// against the world's time less it (`world/stream.rs`). The
    /// scenario's sensing of `id` keeps it, so an export replays it.
    ///
    /// # Errors
    /// `obstacleId: no obstacle "x"`, `latency: must be a finite number in
    /// [0, 2] s`; the world is unchanged.
    pub fn set_sensing_latency(&mut self, id: &str, latency: f64) -> Result<(), ScenarioError> {
        let k = self
            .index_of(id)
            .map_err(|e| FieldError::new("obstacleId", e.reason))?;
        if !(latency.is_finite() && (0.0..=MAX_SENSING_LATENCY).contains(&latency)) {
            return Err(FieldError::new(
                "latency",
                format!("must be a finite number in [0, {MAX_SENSING_LATENCY}] s, got {latency}"),
            )
            .into());
        }
        let sensing = &mut self.model.scenario.sensing;
        let mut spec = sensing.for_obstacle(id);
        spec.latency = Some(latency);
        sensing.obstacles.insert(id.to_owned(), spec);
        self.state.sensed.obstacles[k].sensor.set_latency(latency);
        self.state.sensed.dirty = true;
        Ok(())
    }

    /// Translates obstacle `id` by `delta` (m).
    ///
    /// # Errors
    /// An unknown id or a non-finite `delta`; the world is unchanged.
    pub fn translate_obstacle(&mut self, id: &str, delta: DVec3) -> Result<(), ScenarioError> {
        let k = self.index_of(id)?;
        crate::error::finite3("position", delta)?;
        let shape = translated(&self.state.sensed.obstacles[k].spec.shape, delta);
        self.set_obstacle_shape(id, shape)
    }

    /// Moves obstacle `id` so that its reference point (see
    /// [`reference_point`]) is at `position` now.
    ///
    /// # Errors
    /// An unknown id or a non-finite position; the world is unchanged.
    pub fn set_obstacle_position(
        &mut self,
        id: &str,
        position: DVec3,
    ) -> Result<(), ScenarioError> {
        let k = self.index_of(id)?;
        crate::error::finite3("position", position)?;
        let o = &self.state.sensed.obstacles[k];
        let now = o.reference + o.offset(self.state.t);
        self.translate_obstacle(id, position - now)
    }

    /// Replaces the controller configuration (mode, selection, gains…).
    ///
    /// # Errors
    /// An invalid value (`influenceDistance: must be > 0`); the world is
    /// unchanged.
    pub fn set_controller(&mut self, config: ControllerConfig) -> Result<(), ScenarioError> {
        validate_controller(&config, &self.model.robot).map_err(|e| e.within("controller"))?;
        crate::scenario::check_task_controller(&self.model.scenario.task, &config)?;
        super::dynamics::require_dynamics(&config, &self.model.dynamics)?;
        if config.self_collision_exclude != self.model.scenario.controller.self_collision_exclude {
            self.model.adjacency = super::self_pairs_left_out(&self.model.robot, &config)
                .map_err(|e| e.within("controller"))?;
        }
        if config.selection != self.model.scenario.controller.selection
            || config.pinned != self.model.scenario.controller.pinned
        {
            self.state.trackers.clear();
        }
        self.model.scenario.controller = config;
        Ok(())
    }

    /// Changes the controller fields of `partial` (a JSON object, nested
    /// objects merged; `{ "influenceDistance": 0.2 }`), the others keep
    /// their values: the one path of a partial change, for every caller.
    /// The partial is merged into the configuration in force once, read
    /// into a typed [`ControllerConfig`] once (an unknown or mistyped field
    /// named with its path, an array given for an object refused) and
    /// checked once ([`Self::set_controller`]).
    ///
    /// # Errors
    /// The first bad field under `controller`; the world is unchanged.
    pub fn update_controller(&mut self, partial: &serde_json::Value) -> Result<(), ScenarioError> {
        let config = self.merged_controller(partial)?;
        crate::scenario::bounds::refuse_positional("controller", partial, &config)?;
        self.set_controller(config)
    }

    /// The current controller configuration with the fields of `partial`
    /// (a JSON object, nested objects merged) replaced.
    ///
    /// # Errors
    /// Unknown fields or wrong types, with their path under `controller`.
    pub fn merged_controller(
        &self,
        partial: &serde_json::Value,
    ) -> Result<ControllerConfig, ScenarioError> {
        let mut base = serde_json::to_value(&self.model.scenario.controller)
            .map_err(|e| FieldError::new("controller", e.to_string()))?;
        merge_json(&mut base, partial);
        let cfg: ControllerConfig = serde_path_to_error::deserialize(base).map_err(|e| {
            crate::error::from_serde_path(&e.path().to_string(), &e.inner().to_string())
                .within("controller")
        })?;
        Ok(cfg)
    }

    /// The first obstacle hit by the ray from `origin` along `direction`
    /// (true poses).
    ///
    /// # Errors
    /// Non-finite input or a zero direction.
    pub fn pick(&self, origin: DVec3, direction: DVec3) -> Result<Option<Pick>, ScenarioError> {
        let scene = self.state.sensed.clone_scene_at(self.state.t);
        let hit = scene.pick(origin, direction, PICK_RADIUS)?;
        let mut owners = Vec::new();
        for (k, o) in self.state.sensed.obstacles.iter().enumerate() {
            owners.extend((0..o.parts.len()).map(|i| (k, i)));
        }
        Ok(hit.and_then(|h| {
            owners.get(h.id as usize).map(|&(k, i)| Pick {
                id: self.state.sensed.obstacles[k].spec.id.clone(),
                part: self.state.sensed.obstacles[k]
                    .part_name(i)
                    .map(str::to_owned),
                point: h.point.to_array(),
                distance: h.distance,
            })
        }))
    }

    /// The point of the skeleton a ray from `origin` along `direction`
    /// points at, as DH values `(link, d', a')` of the current
    /// configuration: the volume the ray enters first (within its radius
    /// plus [`PICK_RADIUS`]), and on it the spine's point closest to the
    /// ray (see [`crate::skeleton::Skeleton::ray_hit`]). `None` when the
    /// ray misses every volume. The DH values can be given to
    /// `controller.pinned` as they are.
    ///
    /// # Errors
    /// Non-finite input or a zero direction.
    pub fn pick_skeleton(
        &self,
        origin: DVec3,
        direction: DVec3,
    ) -> Result<Option<SkeletonPick>, ScenarioError> {
        let origin = crate::error::finite3("origin", origin)?;
        let direction = crate::error::finite3("direction", direction)?;
        if direction.try_normalize().is_none() {
            return Err(FieldError::new("direction", "must not be zero").into());
        }
        let Some(hit) = self.data.skeleton.ray_hit(origin, direction, PICK_RADIUS) else {
            return Ok(None);
        };
        let dh = DhPoint::from_skeleton(
            &self.model.robot,
            &self.data.frames,
            &self.data.skeleton,
            hit.segment,
            hit.t,
        )?;
        Ok(Some(SkeletonPick {
            link: dh.link,
            d: dh.d,
            a: dh.a,
            segment: hit.segment,
            position: dh.position(&self.model.robot, &self.data.frames).to_array(),
            distance: hit.distance,
            offset: hit.offset,
            radius: hit.radius,
        }))
    }

    /// Clearance (m) between the arm now (its segments' volumes) and the
    /// figure `shape`, which is not added: negative when they overlap,
    /// infinite for a robot without segments.
    ///
    /// # Errors
    /// An invalid figure.
    pub fn clearance_to(&self, shape: &ShapeSpec) -> Result<f64, ScenarioError> {
        Ok(super::uncertainty::pairs_with(self, shape)?
            .iter()
            .map(|p| p.distance)
            .fold(f64::INFINITY, f64::min))
    }

    /// Back to `t = 0` and `q0` with the obstacles and controller as edited;
    /// events, control points and sensing streams start afresh.
    pub fn reset(&mut self) {
        let scenario = self.model.scenario.clone();
        if let Ok(w) = Self::new(scenario) {
            *self = w;
        }
    }
}

fn merge_json(base: &mut serde_json::Value, patch: &serde_json::Value) {
    match (base, patch) {
        (serde_json::Value::Object(b), serde_json::Value::Object(p)) => {
            for (k, v) in p {
                match b.get_mut(k) {
                    Some(slot) if slot.is_object() && v.is_object() => merge_json(slot, v),
                    _ => {
                        b.insert(k.clone(), v.clone());
                    }
                }
            }
        }
        (b, p) => *b = p.clone(),
    }
}

/// Obstacle index `o` once obstacle `removed` is gone (`None`: it was it).
fn renumber(o: usize, removed: usize) -> Option<usize> {
    match o.cmp(&removed) {
        std::cmp::Ordering::Less => Some(o),
        std::cmp::Ordering::Equal => None,
        std::cmp::Ordering::Greater => Some(o - 1),
    }
}
