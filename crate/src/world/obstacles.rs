//! Obstacles of a [`super::World`]: their figure, motion and sensing model, the
//! scene of the *sense* stage (obstacles at `t` as sensed, with the motion
//! of every part) and distances from a point to one obstacle.
//!
//! A primitive moves rigidly with its motion. A human's parts move with
//! the obstacle's motion *and* their own (keyframes, a clip): each scene
//! part carries a [`PartMotion`], so that the protective layer and the time
//! to collision read the speed of the part that approaches (a reaching
//! hand at 2 m/s) rather than the body's (ISO 13855 sizes separation by the
//! approaching part's speed). A human's `partSigma` gives single parts
//! their own sensing noise and margin ([`ObstacleState::part_margin`]):
//! each guarded pair subtracts its own part's.

use glam::DVec3;

use super::motion::{DRAG_HOLD, PartMotion};
use super::parts::Sensed;
use crate::dependability::{Covariance, SensorModel};
use crate::distance::{Obstacle, Primitive, Scene, distance};
use crate::error::FieldError;
use crate::human::Human;
use crate::scenario::{ObstacleSpec, Scenario, ShapeSpec, primitives, reference_point};

#[derive(Clone, Debug)]
pub(super) struct ObstacleState {
    pub(super) spec: ObstacleSpec,
    pub(super) reference: DVec3,
    pub(super) parts: Vec<Primitive>,
    /// The articulated body of a human figure.
    pub(super) human: Option<Human>,
    /// The last edit that moved the figure: its time and the velocity the
    /// edits give (an obstacle dragged in the playground or moved by a
    /// sensor feed through `moveObstacle` is seen at the speed it is moved).
    pub(super) dragged: Option<(f64, DVec3)>,
    pub(super) sensor: SensorModel,
    /// The margin of the sensing error at this step (m): the sensor's own
    /// ([`SensorModel::margin`]) plus `latency ×` the obstacle's speed.
    pub(super) margin: f64,
    /// Covariance of the sensed position ([`SensorModel::covariance`]; a
    /// human with `partSigma`: with its largest part σ).
    pub(super) covariance: Covariance,
    /// A human with `partSigma`: the margin of each part at this step,
    /// with the part's own σ ([`SensorModel::margin_with`]); `margin` is
    /// then their largest. Empty otherwise.
    pub(super) part_margins: Vec<f64>,
    /// The monitor's last switch probability of this obstacle's closest
    /// segment, with that segment and the likeliest other one.
    pub(super) switch: SwitchOdds,
    /// A human driven by pushed frames (`stream.rs`).
    pub(super) stream: Option<Box<super::stream::Stream>>,
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
        let human = human_of(&spec.shape)?;
        let s = scenario.sensing.for_obstacle(&spec.id);
        let seed = s.seed.unwrap_or(1 + index as u64);
        let sensor = SensorModel::from_spec(&s, seed);
        let largest = human
            .as_ref()
            .map_or(0.0, |h| h.part_sigma().iter().copied().fold(0.0, f64::max));
        let mut me = Self {
            reference: reference_point(&spec.shape),
            parts,
            human,
            dragged: None,
            margin: sensor.margin(),
            covariance: sensor.covariance_with(largest),
            part_margins: Vec::new(),
            switch: SwitchOdds::default(),
            stream: None,
            sensor,
            spec,
        };
        me.part_margins_for(0.0);
        Ok(me)
    }

    /// The parts' own sensing σ (m), `None` unless a human gives some.
    fn part_sigma(&self) -> Option<&[f64; crate::human::PART_NAMES.len()]> {
        self.human
            .as_ref()
            .filter(|h| h.has_part_sigma())
            .map(Human::part_sigma)
    }

    /// Fills [`ObstacleState::part_margins`] (each part's margin plus
    /// `lag`, the latency's share) and sets `margin` to their largest.
    fn part_margins_for(&mut self, lag: f64) {
        let Some(sigma) = self.part_sigma().copied() else {
            self.part_margins.clear();
            return;
        };
        self.part_margins.clear();
        self.part_margins
            .extend(sigma.iter().map(|s| self.sensor.margin_with(*s) + lag));
        self.margin = self
            .part_margins
            .iter()
            .copied()
            .fold(self.margin, f64::max);
    }

    /// The margin of part `k` (m): its own with `partSigma`, else the
    /// obstacle's.
    pub(super) fn part_margin(&self, k: usize) -> f64 {
        self.part_margins.get(k).copied().unwrap_or(self.margin)
    }

    /// Whether its position is sensed with an error (the obstacle's
    /// `sensing` or a part's own σ).
    pub(super) fn noisy(&self) -> bool {
        !self.sensor.is_exact() || self.part_sigma().is_some()
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
            None | Some(crate::scenario::Motion::Static) => match self.dragged {
                Some((at, v)) if t - at <= DRAG_HOLD => v,
                _ => DVec3::ZERO,
            },
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
    /// order), `speed` being its fastest part's as seen (at `t − latency`:
    /// what a sensor knows).
    pub(super) fn update_margin(&mut self, t: f64, dt: f64) {
        let latency = self.sensor.latency();
        self.margin = self.sensor.margin();
        let mut lag = 0.0;
        if latency > 0.0 {
            let seen = (t - latency).max(0.0);
            let speed = self
                .parts_at(seen, self.offset(seen), self.velocity(seen, dt))
                .iter()
                .map(|(_, m)| m.peak_speed())
                .fold(0.0, f64::max);
            if speed.is_finite() {
                lag = latency * speed;
                self.margin += lag;
            }
        }
        self.part_margins_for(lag);
    }

    pub(super) fn moves(&self) -> bool {
        self.noisy()
            || self.human.as_ref().is_some_and(Human::animated)
            || self
                .spec
                .motion
                .as_ref()
                .is_some_and(|m| *m != crate::scenario::Motion::Static)
    }

    /// Its parts at time `t`, displaced by `off` (m) moving at `v` (m/s),
    /// each with its motion: the figure translated, or the human posed at
    /// `t`.
    pub(super) fn parts_at(&self, t: f64, off: DVec3, v: DVec3) -> Vec<(Primitive, PartMotion)> {
        let mut parts = Vec::new();
        self.parts_into(t, off, v, &mut parts);
        parts
    }

    /// [`Self::parts_at`] into `parts` (cleared first), so that the scene
    /// rebuilt every control step reuses one buffer.
    pub(super) fn parts_into(
        &self,
        t: f64,
        off: DVec3,
        v: DVec3,
        parts: &mut Vec<(Primitive, PartMotion)>,
    ) {
        parts.clear();
        match self.human.as_ref().filter(|h| h.animated()) {
            Some(h) => parts.extend(h.posed_at(t, off, v).parts.iter().zip(&self.parts).map(
                |(p, rest)| {
                    let shape = Primitive::from_spec(&p.shape).unwrap_or_else(|_| rest.clone());
                    let (a, b) = axis(&p.shape);
                    let m = PartMotion {
                        a,
                        b,
                        va: p.velocity[0],
                        vb: p.velocity[1],
                    };
                    (shape, m)
                },
            )),
            None => parts.extend(self.parts.iter().map(|p| {
                let shape = if off == DVec3::ZERO {
                    p.clone()
                } else {
                    p.translated(off)
                };
                (shape, PartMotion::rigid(v))
            })),
        }
    }

    /// Its parts at their true pose at `t` (a human posed, moved by its motion).
    pub(super) fn posed_parts(&self, t: f64) -> Vec<Primitive> {
        self.parts_at(t, self.offset(t), DVec3::ZERO)
            .into_iter()
            .map(|(shape, _)| shape)
            .collect()
    }

    /// The name of part `k` (`leftForearm`) of a human, `None` for a
    /// primitive.
    pub(super) fn part_name(&self, k: usize) -> Option<&'static str> {
        self.human.as_ref()?;
        crate::human::PART_NAMES.get(k).copied()
    }
}

/// The articulated body of a human figure (checked).
pub(super) fn human_of(shape: &ShapeSpec) -> Result<Option<Human>, FieldError> {
    match shape {
        ShapeSpec::Human(h) => Ok(Some(h.compile().map_err(|e| e.within("shape"))?)),
        ShapeSpec::Primitive(_) => Ok(None),
    }
}

/// The ends of a capsule's axis (a sphere's centre twice).
fn axis(p: &crate::distance::PrimitiveSpec) -> (DVec3, DVec3) {
    use crate::distance::PrimitiveSpec as S;
    match p {
        S::Capsule(c) => (DVec3::from_array(c.a), DVec3::from_array(c.b)),
        S::Sphere(s) => (DVec3::from_array(s.center), DVec3::from_array(s.center)),
        _ => (DVec3::ZERO, DVec3::ZERO),
    }
}

impl Sensed {
    /// The *sense* stage: the scene of the obstacles at time `t`, as sensed
    /// when `sensed` (seen `latency` late, displaced by their sensing
    /// errors), with the motion of every part (velocities from differences
    /// over `dt` of the obstacle's motion plus, for a human, its limbs').
    pub(super) fn rebuild_scene(&mut self, t: f64, sensed: bool, dt: f64) {
        let mut obstacles = Vec::with_capacity(self.scene.obstacles().len());
        let mut parts = Vec::new();
        self.owners.clear();
        self.part_index.clear();
        self.part_motion.clear();
        for (k, o) in self.obstacles.iter_mut().enumerate() {
            let mut seen = t;
            let mut noise = DVec3::ZERO;
            if sensed && !o.sensor.is_exact() {
                let latency = o.sensor.latency();
                if latency > 0.0 {
                    seen = (t - latency).max(0.0);
                }
                noise = o.sensor.sample_at(t);
            }
            let off = o.offset(seen) + noise;
            let v = o.velocity(seen, dt);
            let part_sigma = o.part_sigma().copied().filter(|_| sensed);
            o.parts_into(seen, off, v, &mut parts);
            for (i, (mut shape, motion)) in parts.drain(..).enumerate() {
                // A part seen with its own error moves by its own draw.
                if let Some(s) = part_sigma
                    .and_then(|s| s.get(i).copied())
                    .filter(|s| *s > 0.0)
                {
                    shape = shape.translated(o.sensor.noise(s));
                }
                let id = self.owners.len() as u32;
                self.owners.push(k);
                self.part_index.push(i);
                self.part_motion.push(motion);
                obstacles.push(Obstacle { id, shape });
            }
        }
        self.scene = Scene::new(obstacles);
        self.dirty = false;
        // `owners` is sorted: each obstacle's parts are one contiguous run.
        self.part_start.clear();
        self.part_start.resize(self.obstacles.len() + 1, 0);
        for &o in &self.owners {
            self.part_start[o + 1] += 1;
        }
        for o in 0..self.obstacles.len() {
            self.part_start[o + 1] += self.part_start[o];
        }
    }

    /// The scene parts of obstacle `o` (empty for an unknown `o`).
    pub(super) fn parts_of(&self, o: usize) -> std::ops::Range<usize> {
        match self.part_start.get(o..o + 2) {
            Some(&[start, end]) => start..end,
            _ => 0..0,
        }
    }

    pub(super) fn clone_scene_at(&self, t: f64) -> Scene {
        let mut obstacles = Vec::new();
        let mut id = 0u32;
        for o in &self.obstacles {
            for shape in o.posed_parts(t) {
                obstacles.push(Obstacle { id, shape });
                id += 1;
            }
        }
        Scene::new(obstacles)
    }

    /// The part of obstacle `o` (as sensed) nearest `p`: its scene index,
    /// and the velocity (m/s) of its material point nearest `p`.
    pub(super) fn nearest_part(&self, o: usize, p: DVec3) -> Option<(usize, DVec3)> {
        let me = Primitive::Point(p);
        let std::ops::Range { start, end } = self.parts_of(o);
        // One part moving as a whole (every primitive): no distance needed.
        if end == start + 1
            && let Some(m) = self.part_motion.get(start)
            && m.va == m.vb
        {
            return Some((start, m.va));
        }
        let mut best: Option<(f64, usize, DVec3)> = None;
        for (k, ob) in self.scene.obstacles().get(start..end)?.iter().enumerate() {
            if let Ok(d) = distance(&me, &ob.shape)
                && best.is_none_or(|b| d.distance < b.0)
            {
                best = Some((d.distance, start + k, d.point_b));
            }
        }
        let (_, id, witness) = best?;
        Some((id, self.part_motion.get(id)?.velocity_at(witness)))
    }

    /// The velocity (m/s) of obstacle `o`'s material point nearest `p` (its
    /// nearest part's), zero when it has none.
    pub(super) fn approach_velocity(&self, o: usize, p: DVec3) -> DVec3 {
        self.nearest_part(o, p).map_or(DVec3::ZERO, |(_, v)| v)
    }

    /// The sensing margin (m) to subtract from the distance between `p`
    /// and obstacle `o`: the obstacle's, or, for a human with `partSigma`,
    /// the one that makes `distance − margin` the smallest over its parts
    /// of `distance to the part − the part's margin`.
    pub(super) fn margin_near(&self, o: usize, p: DVec3) -> f64 {
        let ob = &self.obstacles[o];
        if ob.part_margins.is_empty() {
            return ob.margin;
        }
        let me = Primitive::Point(p);
        let start = self.owners.partition_point(|&x| x < o);
        let end = self.owners.partition_point(|&x| x <= o);
        let (mut nearest, mut effective) = (f64::INFINITY, f64::INFINITY);
        for id in start..end {
            let (Some(part), Some(&k)) = (self.scene.obstacles().get(id), self.part_index.get(id))
            else {
                continue;
            };
            if let Ok(d) = distance(&me, &part.shape) {
                nearest = nearest.min(d.distance);
                effective = effective.min(d.distance - ob.part_margin(k));
            }
        }
        if nearest.is_finite() && effective.is_finite() {
            nearest - effective
        } else {
            ob.margin
        }
    }

    /// `id:part` (`person:leftForearm`) of the part of human obstacle `o`
    /// nearest `p`; `None` for a primitive.
    pub(super) fn witness_part(&self, o: usize, p: DVec3) -> Option<String> {
        let (id, _) = self.nearest_part(o, p)?;
        let ob = &self.obstacles[o];
        let name = ob.part_name(*self.part_index.get(id)?)?;
        Some(format!("{}:{name}", ob.spec.id))
    }

    /// Whether scene obstacle `id` is a named part (a person's).
    pub(super) fn is_named_part(&self, id: usize) -> bool {
        let (Some(&o), Some(&i)) = (self.owners.get(id), self.part_index.get(id)) else {
            return false;
        };
        self.obstacles[o].part_name(i).is_some()
    }

    /// `id:part` of scene part `id` (a human's) or `None`.
    pub(super) fn scene_part_name(&self, id: usize) -> Option<String> {
        let ob = &self.obstacles[*self.owners.get(id)?];
        let name = ob.part_name(*self.part_index.get(id)?)?;
        Some(format!("{}:{name}", ob.spec.id))
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
        for ob in self.scene.obstacles().get(self.parts_of(o)).unwrap_or(&[]) {
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
