//! A live simulation: the arm, the obstacles, the controller and the
//! monitor, stepped interactively ([`World`]) or run to the end of a
//! scenario ([`simulate`]).
//!
//! One [`World::step`]:
//!
//! 1. obstacles at time `t` (motion), then as sensed (sensing error);
//! 2. forward kinematics and the skeleton at `q`;
//! 3. the scene query: every segment against every obstacle within the
//!    influence distance plus the largest sensing margin (and, if enabled,
//!    segments of non-adjacent links against each other);
//! 4. control-point selection (pairs / per obstacle / pinned), switch-risk
//!    detection, lock handling;
//! 5. each control point follows its selected point, through a transition
//!    along the skeleton when the selection jumps
//!    ([`crate::transition::MovingPoint`]); segment switches are counted and
//!    chattering triggers the configured policy;
//! 6. the clearance of each control point where it actually is (measured
//!    minus the sensing margin), its repulsion, time to collision;
//! 7. the controller, joint limits, integration to `t + dt` (or a stop with
//!    bounded deceleration).
//!
//! Everything is deterministic: the same scenario gives the same trace, bit
//! for bit, natively and in wasm.

use std::collections::{BTreeMap, BTreeSet};

use glam::DVec3;
use serde::Serialize;

use crate::avoidance::{
    self, ActivePoint, Command, ControllerConfig, Mode, Selection, TaskReference,
};
use crate::control_point::DhPoint;
use crate::dependability::{
    ChatteringPolicy, Event, EventKind, SensorModel, SwitchCounter, decelerate,
    distance_uncertainty, time_to_collision,
};
use crate::distance::{
    Obstacle, PairDistance, Primitive, PrimitiveSpec, QueryOptions, Scene, Target, distance,
};
use crate::error::FieldError;
use crate::kinematics::ik::PointMotion;
use crate::kinematics::{Frames, Robot};
use crate::scenario::{
    ObstacleSpec, Sample, Scenario, ScenarioError, ShapeSpec, TaskSpec, Trace, TracePoint,
    primitives, reference_point, translated, unit_quat, validate_controller,
};
use crate::skeleton::Skeleton;
use crate::transition::{MovingPoint, PointEvent, SkeletonPoint, TransitionSettings, dh_motion};

/// Events a live [`World`] keeps (the oldest half is dropped beyond this;
/// [`simulate`] keeps every event).
pub const MAX_EVENTS: usize = 20_000;

/// Radius within which a pick ray catches points and segments (m).
pub const PICK_RADIUS: f64 = 0.02;

/// Which control point: one per obstacle, per segment–obstacle pair, per
/// pinned point, or per side of a self-collision pair.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Key {
    Obstacle(usize),
    Pair(usize, usize),
    Pinned(usize),
    SelfPair(usize, usize),
}

#[derive(Clone, Debug)]
struct ObstacleState {
    spec: ObstacleSpec,
    reference: DVec3,
    parts: Vec<Primitive>,
    sensor: SensorModel,
    margin: f64,
}

impl ObstacleState {
    fn new(spec: ObstacleSpec, scenario: &Scenario, index: usize) -> Result<Self, FieldError> {
        let parts = primitives(&spec.shape).map_err(|e| e.within("shape"))?;
        let s = scenario.sensing.for_obstacle(&spec.id);
        let bound = s.bound.unwrap_or(0.0);
        let sigma = s.sigma.unwrap_or(0.0);
        let seed = s.seed.unwrap_or(1 + index as u64);
        Ok(Self {
            reference: reference_point(&spec.shape),
            parts,
            sensor: SensorModel::new(bound, sigma, seed),
            margin: distance_uncertainty(DVec3::Z, bound, sigma),
            spec,
        })
    }

    fn offset(&self, t: f64) -> DVec3 {
        self.spec
            .motion
            .as_ref()
            .map_or(DVec3::ZERO, |m| m.offset(t, self.reference))
    }

    fn moves(&self) -> bool {
        !self.sensor.is_exact()
            || self
                .spec
                .motion
                .as_ref()
                .is_some_and(|m| *m != crate::scenario::Motion::Static)
    }
}

#[derive(Clone, Debug)]
struct Tracker {
    mover: MovingPoint,
    owner: Option<usize>,
    prev_distance: Option<f64>,
    too_slow: bool,
    counter: SwitchCounter,
    chattering: bool,
    lock: Option<(usize, f64)>,
}

/// An active control point in [`WorldState`].
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ControlPointState {
    /// Position (m).
    pub position: [f64; 3],
    /// Link (1-based).
    pub link: usize,
    /// DH value `d'` (m).
    pub d: f64,
    /// DH value `a'` (m).
    pub a: f64,
    /// Id of the obstacle it answers (`self:<link>` for self-collision,
    /// `pinned:<k>` for a pinned point with no obstacle in reach).
    pub obstacle: String,
    /// Measured clearance (m).
    pub distance: f64,
    /// Closest point of the obstacle (m).
    pub witness: [f64; 3],
    /// Repulsion: velocity (m/s) in velocity and `clik2` modes, force (N)
    /// in torque mode.
    pub repulsion: [f64; 3],
    /// Whether it is travelling along the skeleton.
    pub transitioning: bool,
    /// Where it goes while transitioning.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub target: Option<DhPoint>,
}

/// A skeleton segment in [`WorldState`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SegmentState {
    /// Index of the first node.
    pub from: usize,
    /// Index of the second node.
    pub to: usize,
    /// Link (1-based).
    pub link: usize,
    /// Radius at each end (m).
    pub radius: [f64; 2],
}

/// The skeleton in [`WorldState`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SkeletonState {
    /// Node positions (m).
    pub nodes: Vec<[f64; 3]>,
    /// Segments.
    pub segments: Vec<SegmentState>,
}

/// An obstacle in [`WorldState`]: its figure where it is now (true pose).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ObstacleStateOut {
    /// Id.
    pub id: String,
    /// Figure at its current pose.
    pub shape: ShapeSpec,
    /// The primitives it is made of (one, or a human's parts).
    pub parts: Vec<PrimitiveSpec>,
}

/// The inflated margin of one obstacle.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Uncertainty {
    /// Obstacle id.
    pub obstacle: String,
    /// Distance uncertainty added to the safety margin (m).
    pub radius: f64,
}

/// Everything a viewer needs after a step (serde, camelCase).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct WorldState {
    /// Time (s).
    pub t: f64,
    /// Joint values.
    pub q: Vec<f64>,
    /// Joint velocities.
    pub qdot: Vec<f64>,
    /// Smallest clearance (m) between the arm and any obstacle (true poses)
    /// or between non-adjacent links, among pairs within reach.
    pub min_clearance: Option<f64>,
    /// The skeleton at `q`.
    pub skeleton: SkeletonState,
    /// Obstacles at their current pose.
    pub obstacles: Vec<ObstacleStateOut>,
    /// Active control points (of the last step).
    pub control_points: Vec<ControlPointState>,
    /// Inflated margins of obstacles sensed with error.
    pub uncertainty: Vec<Uncertainty>,
    /// Events (all so far, or since a cursor).
    pub events: Vec<Event>,
    /// Smallest time to collision of the last step (s), if any point closes in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time_to_collision: Option<f64>,
    /// Whether the monitor is stopping the robot.
    pub stopped: bool,
}

/// The result of [`World::pick`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Pick {
    /// Obstacle id.
    pub id: String,
    /// Where the ray meets it (m).
    pub point: [f64; 3],
    /// Distance along the ray (m).
    pub distance: f64,
}

/// A simulation that steps on demand and accepts edits.
#[derive(Clone, Debug)]
pub struct World {
    scenario: Scenario,
    robot: Robot,
    adjacency: Vec<Vec<bool>>,
    q: Vec<f64>,
    qdot: Vec<f64>,
    t: f64,
    frames: Frames,
    skeleton: Skeleton,
    obstacles: Vec<ObstacleState>,
    scene: Scene,
    owners: Vec<usize>,
    scene_dirty: bool,
    trackers: BTreeMap<Key, Tracker>,
    risky: BTreeSet<usize>,
    hold: DVec3,
    stopped: bool,
    stopped_until: f64,
    events: Vec<Event>,
    events_dropped: usize,
    keep_all_events: bool,
    points: Vec<ControlPointState>,
    min_clearance: Option<f64>,
    time_to_collision: Option<f64>,
    step_t: f64,
    step_q: Vec<f64>,
}

fn err(e: FieldError) -> ScenarioError {
    ScenarioError::Field(e)
}

impl World {
    /// A world at `t = 0` for `scenario` (validated first).
    ///
    /// # Errors
    /// Whatever [`Scenario::validate`] reports (JSON path and reason).
    ///
    /// # Example
    /// ```
    /// use skeleton_avoidance::scenario;
    /// use skeleton_avoidance::world::World;
    /// let mut world = World::new(scenario::example("lwr4-elbow")?)?;
    /// for _ in 0..1000 {
    ///     world.step(0.001);
    /// }
    /// let state = world.state();
    /// assert!((state.t - 1.0).abs() < 1e-9);
    /// assert!(state.min_clearance.unwrap() > 0.0);
    /// # Ok::<(), skeleton_avoidance::scenario::ScenarioError>(())
    /// ```
    pub fn new(scenario: Scenario) -> Result<Self, ScenarioError> {
        scenario.validate()?;
        let robot = scenario.build_robot().map_err(err)?;
        let mut q = scenario
            .q0
            .clone()
            .unwrap_or_else(|| vec![0.0; robot.dof()]);
        robot.clamp_to_limits(&mut q);
        let frames = robot.forward(&q).map_err(err)?;
        let skeleton = Skeleton::build(&robot, &frames);
        let adjacency = link_adjacency(&robot, &skeleton);
        let obstacles = scenario
            .obstacles
            .iter()
            .enumerate()
            .map(|(k, o)| {
                ObstacleState::new(o.clone(), &scenario, k)
                    .map_err(|e| e.within(&format!("obstacles[{k}]")))
            })
            .collect::<Result<Vec<_>, _>>()
            .map_err(err)?;
        let hold = frames.end_effector().translation;
        let n = robot.dof();
        let mut w = Self {
            scenario,
            robot,
            adjacency,
            q,
            qdot: vec![0.0; n],
            t: 0.0,
            frames,
            skeleton,
            obstacles,
            scene: Scene::default(),
            owners: Vec::new(),
            scene_dirty: true,
            trackers: BTreeMap::new(),
            risky: BTreeSet::new(),
            hold,
            stopped: false,
            stopped_until: 0.0,
            events: Vec::new(),
            events_dropped: 0,
            keep_all_events: false,
            points: Vec::new(),
            min_clearance: None,
            time_to_collision: None,
            step_t: 0.0,
            step_q: Vec::new(),
        };
        w.rebuild_scene(0.0, false);
        Ok(w)
    }

    /// The scenario as edited so far.
    #[must_use]
    pub fn scenario(&self) -> &Scenario {
        &self.scenario
    }

    /// The robot.
    #[must_use]
    pub fn robot(&self) -> &Robot {
        &self.robot
    }

    /// Simulation time (s).
    #[must_use]
    pub fn time(&self) -> f64 {
        self.t
    }

    /// Joint values.
    #[must_use]
    pub fn q(&self) -> &[f64] {
        &self.q
    }

    /// The frames at the current `q`.
    #[must_use]
    pub fn frames(&self) -> &Frames {
        &self.frames
    }

    /// The skeleton at the current `q`.
    #[must_use]
    pub fn skeleton(&self) -> &Skeleton {
        &self.skeleton
    }

    /// The active control points of the last step.
    #[must_use]
    pub fn control_points(&self) -> &[ControlPointState] {
        &self.points
    }

    /// The obstacles' primitives at their true pose now, with their ids.
    #[must_use]
    pub fn obstacle_primitives(&self) -> Vec<(String, Primitive)> {
        let mut out = Vec::new();
        for o in &self.obstacles {
            let off = o.offset(self.t);
            for p in &o.parts {
                out.push((o.spec.id.clone(), p.translated(off)));
            }
        }
        out
    }

    /// The events kept (every event so far, up to [`MAX_EVENTS`]).
    #[must_use]
    pub fn events(&self) -> &[Event] {
        &self.events
    }

    /// Number of events since the start (or the last reset), including
    /// those no longer kept: the cursor for [`World::state_since`].
    #[must_use]
    pub fn event_count(&self) -> usize {
        self.events_dropped + self.events.len()
    }

    /// Whether the monitor is stopping the robot.
    #[must_use]
    pub fn is_stopped(&self) -> bool {
        self.stopped
    }

    fn rebuild_scene(&mut self, t: f64, sensed: bool) {
        let mut obstacles = Vec::new();
        self.owners.clear();
        for (k, o) in self.obstacles.iter_mut().enumerate() {
            let mut off = o.offset(t);
            if sensed && !o.sensor.is_exact() {
                off += o.sensor.sample();
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

    fn push(&mut self, kind: EventKind) {
        self.events.push(Event { t: self.t, kind });
    }

    fn name(&self, key: &Key) -> String {
        match key {
            Key::Obstacle(o) | Key::Pair(o, _) => self.obstacles[*o].spec.id.clone(),
            Key::Pinned(k) => format!("pinned:{k}"),
            Key::SelfPair(_, other) => format!("self:{}", self.skeleton.segments[*other].link),
        }
    }

    fn task_reference(&self) -> TaskReference {
        let mut r = TaskReference {
            position: self.hold,
            velocity: DVec3::ZERO,
            acceleration: DVec3::ZERO,
            orientation: None,
            chain: 0,
        };
        match &self.scenario.task {
            TaskSpec::Hold => {}
            TaskSpec::Goal {
                position,
                orientation,
                chain,
            } => {
                r.chain = *chain;
                r.position = DVec3::from_array(*position);
                r.orientation = orientation.and_then(|o| unit_quat("orientation", o).ok());
            }
            TaskSpec::Trajectory {
                points,
                times,
                chain,
            } => {
                r.chain = *chain;
                let v = |k: usize| DVec3::from_array(points[k]);
                let t = self.t;
                let k = times.partition_point(|&s| s <= t);
                if k == 0 {
                    r.position = v(0);
                } else if k >= times.len() {
                    r.position = v(times.len() - 1);
                } else {
                    let (t0, t1) = (times[k - 1], times[k]);
                    let vel = (v(k) - v(k - 1)) / (t1 - t0);
                    r.position = v(k - 1) + vel * (t - t0);
                    r.velocity = vel;
                }
            }
        }
        r
    }

    /// Advances the simulation by `dt` seconds (one control step). A
    /// non-finite or non-positive `dt` does nothing.
    pub fn step(&mut self, dt: f64) {
        if !(dt.is_finite() && dt > 0.0) {
            return;
        }
        if self.step_inner(dt).is_err() {
            // Only reachable through a bug: keep the world as it is, at rest.
            self.qdot.iter_mut().for_each(|v| *v = 0.0);
        }
        if !self.keep_all_events && self.events.len() > MAX_EVENTS {
            let drop = self.events.len() - MAX_EVENTS / 2;
            self.events.drain(..drop);
            self.events_dropped += drop;
        }
    }

    #[allow(clippy::too_many_lines)]
    fn step_inner(&mut self, dt: f64) -> Result<(), FieldError> {
        let cfg = self.scenario.controller.clone();
        let t = self.t;
        let moving = self.obstacles.iter().any(ObstacleState::moves);
        let noisy = self.obstacles.iter().any(|o| !o.sensor.is_exact());
        if moving || self.scene_dirty {
            self.rebuild_scene(t, true);
        }
        // 2. kinematics
        if cfg.mode == Mode::Clik2 {
            self.frames = self.robot.forward_with_velocity(&self.q, &self.qdot)?;
        } else {
            self.robot.forward_into(&self.q, &mut self.frames)?;
        }
        self.skeleton.build_into(&self.robot, &self.frames);
        // 3. scene query
        let max_margin = self.obstacles.iter().map(|o| o.margin).fold(0.0, f64::max);
        let options = QueryOptions {
            influence_distance: cfg.influence_distance + max_margin,
            self_collision: cfg.self_collision,
            ..QueryOptions::default()
        };
        let pairs = self
            .scene
            .query(&self.skeleton, &options, |i, j| self.adjacency[i][j])
            .map_err(|e| FieldError::new("scene", e.to_string()))?;
        self.min_clearance = if noisy {
            let exact = self
                .clone_scene_at(t)
                .query(&self.skeleton, &options, |i, j| self.adjacency[i][j])
                .map_err(|e| FieldError::new("scene", e.to_string()))?;
            exact.iter().map(|p| p.distance).reduce(f64::min)
        } else {
            pairs.iter().map(|p| p.distance).reduce(f64::min)
        };
        // 4. selection
        let mut selected: BTreeMap<Key, (SkeletonPoint, Option<usize>)> = BTreeMap::new();
        let mut best: BTreeMap<usize, &PairDistance> = BTreeMap::new();
        let mut pair_best: BTreeMap<(usize, usize), &PairDistance> = BTreeMap::new();
        for p in &pairs {
            match p.target {
                Target::Obstacle { id, .. } => {
                    let owner = self.owners[id as usize];
                    let effective = p.distance - self.obstacles[owner].margin;
                    if effective > cfg.influence_distance {
                        continue;
                    }
                    if cfg.selection == Selection::Pairs {
                        let e = pair_best.entry((owner, p.segment)).or_insert(p);
                        if p.distance < e.distance {
                            *e = p;
                        }
                    }
                    let e = best.entry(owner).or_insert(p);
                    if p.distance < e.distance {
                        *e = p;
                    }
                }
                Target::Segment(other) => {
                    if p.distance > cfg.influence_distance {
                        continue;
                    }
                    selected.insert(
                        Key::SelfPair(p.segment, other),
                        (
                            SkeletonPoint {
                                segment: p.segment,
                                t: p.fraction,
                            },
                            None,
                        ),
                    );
                    let (a, b) = self.skeleton.endpoints(&self.skeleton.segments[other]);
                    let ab = b - a;
                    let l2 = ab.length_squared();
                    let u = if l2 > 0.0 {
                        ((p.point_other - a).dot(ab) / l2).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    selected.insert(
                        Key::SelfPair(other, p.segment),
                        (
                            SkeletonPoint {
                                segment: other,
                                t: u,
                            },
                            None,
                        ),
                    );
                }
            }
        }
        for ((owner, segment), p) in &pair_best {
            selected.insert(
                Key::Pair(*owner, *segment),
                (
                    SkeletonPoint {
                        segment: *segment,
                        t: p.fraction,
                    },
                    Some(*owner),
                ),
            );
        }
        if cfg.selection == Selection::PerObstacle {
            for (owner, p) in &best {
                selected.insert(
                    Key::Obstacle(*owner),
                    (
                        SkeletonPoint {
                            segment: p.segment,
                            t: p.fraction,
                        },
                        Some(*owner),
                    ),
                );
            }
        }
        // Switch risk: another part of the skeleton within twice the margin.
        let mut risky_now = BTreeSet::new();
        for (owner, b) in &best {
            let margin = self.obstacles[*owner].margin;
            if margin <= 0.0 {
                continue;
            }
            let alternative = pairs
                .iter()
                .filter(|p| {
                    matches!(p.target, Target::Obstacle { id, .. } if self.owners[id as usize] == *owner)
                        && p.segment != b.segment
                        && (p.point_segment - b.point_segment).length() > cfg.jump_threshold
                })
                .min_by(|x, y| x.distance.total_cmp(&y.distance));
            if let Some(alt) = alternative {
                let gap = alt.distance - b.distance;
                if gap <= 2.0 * margin {
                    risky_now.insert(*owner);
                    if !self.risky.contains(owner) {
                        let obstacle = self.obstacles[*owner].spec.id.clone();
                        self.push(EventKind::SwitchRisk {
                            obstacle,
                            segment: b.segment,
                            alternative: alt.segment,
                            gap,
                            margin,
                        });
                    }
                }
            }
        }
        self.risky = risky_now;
        // 5. trackers
        let settings = TransitionSettings {
            time_per_value: cfg.transition_time,
            jump_threshold: cfg.jump_threshold,
        };
        self.trackers
            .retain(|k, _| selected.contains_key(k) || matches!(k, Key::Pinned(_)));
        let dep = self.scenario.dependability;
        let mut point_events = Vec::new();
        let keys: Vec<Key> = selected.keys().cloned().collect();
        for key in keys {
            let (mut at, owner) = selected[&key];
            let tracker = self.trackers.entry(key.clone()).or_insert_with(|| Tracker {
                mover: MovingPoint::new(at),
                owner,
                prev_distance: None,
                too_slow: false,
                counter: SwitchCounter::default(),
                chattering: false,
                lock: None,
            });
            if let Some((segment, until)) = tracker.lock {
                if t >= until {
                    tracker.lock = None;
                    let obstacle =
                        owner.map_or_else(String::new, |o| self.obstacles[o].spec.id.clone());
                    self.events.push(Event {
                        t,
                        kind: EventKind::Unlock { obstacle },
                    });
                } else if at.segment != segment {
                    let on_segment = pairs.iter().find(|p| {
                        p.segment == segment
                            && matches!(p.target, Target::Obstacle { id, .. } if Some(self.owners[id as usize]) == owner)
                    });
                    at = on_segment.map_or(
                        SkeletonPoint {
                            segment,
                            t: if tracker.mover.point().segment == segment {
                                tracker.mover.point().t
                            } else {
                                0.5
                            },
                        },
                        |p| SkeletonPoint {
                            segment,
                            t: p.fraction,
                        },
                    );
                }
            }
            point_events.clear();
            tracker
                .mover
                .update(&self.skeleton, at, dt, &settings, &mut point_events)?;
            let mut switches = 0;
            for e in &point_events {
                if matches!(e, PointEvent::SegmentSwitch { .. }) {
                    switches = tracker.counter.record(t, dep.switch_window);
                }
            }
            let chattering =
                tracker.counter.count(t, dep.switch_window) > dep.max_switches as usize;
            let rising = chattering && !tracker.chattering;
            tracker.chattering = chattering;
            let lock_segment = tracker.mover.point().segment;
            if rising && dep.on_chattering == ChatteringPolicy::Lock {
                tracker.lock = Some((lock_segment, t + dep.lock_time));
            }
            let name = self.name(&key);
            for e in point_events.drain(..) {
                let kind = match e {
                    PointEvent::SegmentSwitch { from, to } => EventKind::SegmentSwitch {
                        obstacle: name.clone(),
                        from,
                        to,
                    },
                    PointEvent::TransitionStart {
                        from,
                        to,
                        duration,
                        replan,
                    } => EventKind::TransitionStart {
                        obstacle: name.clone(),
                        from,
                        to,
                        duration,
                        replan,
                    },
                    PointEvent::TransitionEnd { segment } => EventKind::TransitionEnd {
                        obstacle: name.clone(),
                        segment,
                    },
                };
                self.events.push(Event { t, kind });
            }
            if rising {
                self.events.push(Event {
                    t,
                    kind: EventKind::Chattering {
                        obstacle: name.clone(),
                        switches,
                    },
                });
                match dep.on_chattering {
                    ChatteringPolicy::Stop => {
                        self.stopped_until = t + dep.lock_time;
                        if !self.stopped {
                            self.stopped = true;
                            self.events.push(Event {
                                t,
                                kind: EventKind::Stop {
                                    reason: format!("chattering control point ({name})"),
                                },
                            });
                        }
                    }
                    ChatteringPolicy::Lock => self.events.push(Event {
                        t,
                        kind: EventKind::Lock {
                            obstacle: name.clone(),
                            segment: lock_segment,
                            until: t + dep.lock_time,
                        },
                    }),
                }
            }
        }
        if self.stopped
            && t >= self.stopped_until
            && !self.trackers.values().any(|tr| tr.chattering)
        {
            self.stopped = false;
            self.push(EventKind::Resume);
        }
        // Pinned points.
        if cfg.selection == Selection::Pinned {
            for k in 0..cfg.pinned.len() {
                self.trackers
                    .entry(Key::Pinned(k))
                    .or_insert_with(|| Tracker {
                        mover: MovingPoint::new(SkeletonPoint { segment: 0, t: 0.0 }),
                        owner: None,
                        prev_distance: None,
                        too_slow: false,
                        counter: SwitchCounter::default(),
                        chattering: false,
                        lock: None,
                    });
            }
        }
        // 6. active points where they are
        let mut active = Vec::new();
        let mut states = Vec::new();
        let mut min_ttc = f64::INFINITY;
        let torque = cfg.mode == Mode::Torque;
        let keys: Vec<Key> = self.trackers.keys().cloned().collect();
        for key in keys {
            let Some(tr) = self.trackers.get(&key).cloned() else {
                continue;
            };
            let (dh, motion, radius) = if let Key::Pinned(k) = key {
                let Some(p) = cfg.pinned.get(k) else { continue };
                (
                    *p,
                    PointMotion::default(),
                    self.robot.joints[p.link - 1].radius[0],
                )
            } else {
                let pt = tr.mover.point();
                let (dh, m) = dh_motion(
                    &self.robot,
                    &self.frames,
                    &self.skeleton,
                    pt,
                    tr.mover.rate(),
                    tr.mover.accel(),
                )?;
                let seg = &self.skeleton.segments[pt.segment];
                (dh, m, Skeleton::radius_at(seg, pt.t))
            };
            let position = dh.position(&self.robot, &self.frames);
            // Clearance where the point is.
            let (dist, normal, witness, owner) = match key {
                Key::SelfPair(_, other) => {
                    let (a, b) = self.skeleton.endpoints(&self.skeleton.segments[other]);
                    let ab = b - a;
                    let l2 = ab.length_squared();
                    let u = if l2 > 0.0 {
                        ((position - a).dot(ab) / l2).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    let c = a + ab * u;
                    let r2 = Skeleton::radius_at(&self.skeleton.segments[other], u);
                    let v = c - position;
                    let len = v.length();
                    let n = if len > 0.0 { v / len } else { DVec3::Z };
                    (len - radius - r2, n, c - n * r2, None)
                }
                _ => {
                    let owner = match key {
                        Key::Pinned(_) => self.closest_obstacle(position),
                        _ => tr.owner,
                    };
                    match owner {
                        Some(o) => {
                            let (d, n, w) = self.point_distance(o, position)?;
                            (d - radius, n, w, Some(o))
                        }
                        None => (f64::INFINITY, DVec3::Z, position, None),
                    }
                }
            };
            let margin = owner.map_or(0.0, |o| self.obstacles[o].margin);
            let effective = dist - margin;
            let ap = ActivePoint {
                dh,
                motion,
                normal,
                distance: effective,
            };
            let rep = if torque {
                ap.repulsion(&cfg) * cfg.torque.force_gain
            } else {
                ap.repulsion(&cfg)
            };
            let name = match (&key, owner) {
                (Key::Pinned(k), None) => format!("pinned:{k}"),
                (Key::Pinned(_), Some(o)) => self.obstacles[o].spec.id.clone(),
                _ => self.name(&key),
            };
            // Time to collision against the remaining transition time.
            let remaining = tr.mover.remaining();
            let ttc = tr.prev_distance.map_or(f64::INFINITY, |prev| {
                time_to_collision(effective, (prev - effective) / dt)
            });
            min_ttc = min_ttc.min(ttc);
            let too_slow = remaining > 0.0 && ttc < remaining;
            let rising = too_slow && !tr.too_slow;
            if let Some(trm) = self.trackers.get_mut(&key) {
                trm.prev_distance = Some(effective);
                trm.too_slow = too_slow;
            }
            if rising {
                self.push(EventKind::TransitionTooSlow {
                    obstacle: name.clone(),
                    time_to_collision: ttc,
                    remaining,
                });
            }
            let target = tr.mover.transition().and_then(|x| {
                DhPoint::from_skeleton(
                    &self.robot,
                    &self.frames,
                    &self.skeleton,
                    x.target().segment,
                    x.target().t,
                )
                .ok()
            });
            if dist.is_finite() {
                active.push(ap);
            }
            states.push(ControlPointState {
                position: position.to_array(),
                link: dh.link,
                d: dh.d,
                a: dh.a,
                obstacle: name,
                distance: dist,
                witness: witness.to_array(),
                repulsion: rep.to_array(),
                transitioning: target.is_some(),
                target,
            });
        }
        self.points = states;
        self.time_to_collision = min_ttc.is_finite().then_some(min_ttc);
        // 7. control and integration
        let task = self.task_reference();
        let cmd: Command = match cfg.mode {
            Mode::Velocity => avoidance::velocity_control(
                &self.robot,
                &self.frames,
                &self.q,
                &active,
                &task,
                &cfg,
                dt,
            )?,
            Mode::Torque => avoidance::torque_control(
                &self.robot,
                &self.frames,
                &self.q,
                &self.qdot,
                &active,
                &task,
                &cfg,
                dt,
            )?,
            Mode::Clik2 => avoidance::clik2_control(
                &self.robot,
                &self.frames,
                &self.q,
                &self.qdot,
                &active,
                &task,
                &cfg,
                dt,
            )?,
        };
        self.step_t = t;
        self.step_q.clone_from(&self.q);
        if self.stopped {
            decelerate(&mut self.qdot, dep.max_deceleration, dt);
        } else {
            self.qdot = cmd.qdot;
        }
        avoidance::limit_joint_velocities(&self.robot, &self.q, &mut self.qdot, dt);
        for (q, v) in self.q.iter_mut().zip(&self.qdot) {
            *q += v * dt;
        }
        self.robot.clamp_to_limits(&mut self.q);
        self.t += dt;
        Ok(())
    }

    fn clone_scene_at(&self, t: f64) -> Scene {
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
    fn point_distance(&self, o: usize, p: DVec3) -> Result<(f64, DVec3, DVec3), FieldError> {
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

    fn closest_obstacle(&self, p: DVec3) -> Option<usize> {
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

    /// A snapshot of everything a viewer needs, with every event kept (a
    /// viewer polling each frame should use [`World::state_since`]).
    #[must_use]
    pub fn state(&self) -> WorldState {
        self.state_since(0)
    }

    /// [`World::state`] with only the events from number `cursor` on (the
    /// [`World::event_count`] when the caller last read them).
    #[must_use]
    pub fn state_since(&self, cursor: usize) -> WorldState {
        let sk = &self.skeleton;
        let obstacles = self
            .obstacles
            .iter()
            .map(|o| {
                let shape = translated(&o.spec.shape, o.offset(self.t));
                let parts = match &shape {
                    ShapeSpec::Primitive(p) => vec![p.clone()],
                    ShapeSpec::Human(h) => h.parts(),
                };
                ObstacleStateOut {
                    id: o.spec.id.clone(),
                    shape,
                    parts,
                }
            })
            .collect();
        WorldState {
            t: self.t,
            q: self.q.clone(),
            qdot: self.qdot.clone(),
            min_clearance: self.min_clearance,
            skeleton: SkeletonState {
                nodes: sk.nodes.iter().map(|n| n.to_array()).collect(),
                segments: sk
                    .segments
                    .iter()
                    .map(|s| SegmentState {
                        from: s.from,
                        to: s.to,
                        link: s.link,
                        radius: s.radius,
                    })
                    .collect(),
            },
            obstacles,
            control_points: self.points.clone(),
            uncertainty: self
                .obstacles
                .iter()
                .filter(|o| o.margin > 0.0)
                .map(|o| Uncertainty {
                    obstacle: o.spec.id.clone(),
                    radius: o.margin,
                })
                .collect(),
            events: self
                .events
                .get(cursor.saturating_sub(self.events_dropped)..)
                .unwrap_or(&[])
                .to_vec(),
            time_to_collision: self.time_to_collision,
            stopped: self.stopped,
        }
    }

    /// One trace sample: the time, joints, clearance and control points the
    /// last step acted on.
    #[must_use]
    pub fn sample(&self) -> Sample {
        Sample {
            t: self.step_t,
            q: self.step_q.clone(),
            min_clearance: self.min_clearance,
            control_points: self
                .points
                .iter()
                .map(|c| TracePoint {
                    position: c.position,
                    link: c.link,
                    d: c.d,
                    a: c.a,
                    obstacle: c.obstacle.clone(),
                    distance: c.distance,
                })
                .collect(),
        }
    }

    fn index_of(&self, id: &str) -> Result<usize, FieldError> {
        self.obstacles
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
        if self.obstacles.iter().any(|o| o.spec.id == spec.id) {
            return Err(FieldError::new("id", format!("\"{}\" is already used", spec.id)).into());
        }
        let k = self.obstacles.len();
        let state = ObstacleState::new(spec.clone(), &self.scenario, k)?;
        self.obstacles.push(state);
        self.scenario.obstacles.push(spec);
        self.scene_dirty = true;
        Ok(())
    }

    /// Removes obstacle `id` (and its control points).
    ///
    /// # Errors
    /// `id: no obstacle "x"`; the world is unchanged.
    pub fn remove_obstacle(&mut self, id: &str) -> Result<(), ScenarioError> {
        let k = self.index_of(id)?;
        self.obstacles.remove(k);
        self.scenario.obstacles.remove(k);
        // Trackers refer to obstacles by index: renumber.
        let old = std::mem::take(&mut self.trackers);
        for (key, mut tr) in old {
            let shift = |o: usize| {
                if o > k {
                    Some(o - 1)
                } else if o == k {
                    None
                } else {
                    Some(o)
                }
            };
            let new_key = match key {
                Key::Obstacle(o) => shift(o).map(Key::Obstacle),
                Key::Pair(o, s) => shift(o).map(|o| Key::Pair(o, s)),
                other => Some(other),
            };
            if let Some(nk) = new_key {
                tr.owner = tr.owner.and_then(shift);
                self.trackers.insert(nk, tr);
            }
        }
        self.risky = self
            .risky
            .iter()
            .filter_map(|&o| {
                if o > k {
                    Some(o - 1)
                } else if o == k {
                    None
                } else {
                    Some(o)
                }
            })
            .collect();
        self.scene_dirty = true;
        Ok(())
    }

    /// Replaces the figure of obstacle `id` (its motion is kept).
    ///
    /// # Errors
    /// An unknown id or an invalid figure; the world is unchanged.
    pub fn set_obstacle_shape(&mut self, id: &str, shape: ShapeSpec) -> Result<(), ScenarioError> {
        let k = self.index_of(id)?;
        let parts = primitives(&shape).map_err(|e| e.within("shape"))?;
        let o = &mut self.obstacles[k];
        o.reference = reference_point(&shape);
        o.parts = parts;
        o.spec.shape = shape.clone();
        self.scenario.obstacles[k].shape = shape;
        self.scene_dirty = true;
        Ok(())
    }

    /// Translates obstacle `id` by `delta` (m).
    ///
    /// # Errors
    /// An unknown id or a non-finite `delta`; the world is unchanged.
    pub fn translate_obstacle(&mut self, id: &str, delta: DVec3) -> Result<(), ScenarioError> {
        let k = self.index_of(id)?;
        crate::error::finite3("position", delta)?;
        let shape = translated(&self.obstacles[k].spec.shape, delta);
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
        let o = &self.obstacles[k];
        let now = o.reference + o.offset(self.t);
        self.translate_obstacle(id, position - now)
    }

    /// Replaces the controller configuration (mode, selection, gains…).
    ///
    /// # Errors
    /// An invalid value (`influenceDistance: must be > 0`); the world is
    /// unchanged.
    pub fn set_controller(&mut self, config: ControllerConfig) -> Result<(), ScenarioError> {
        validate_controller(&config, &self.robot).map_err(|e| e.within("controller"))?;
        if config.selection != self.scenario.controller.selection
            || config.pinned != self.scenario.controller.pinned
        {
            self.trackers.clear();
        }
        self.scenario.controller = config;
        Ok(())
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
        let mut base = serde_json::to_value(&self.scenario.controller)
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
        let scene = self.clone_scene_at(self.t);
        let hit = scene.pick(origin, direction, PICK_RADIUS)?;
        let mut owners = Vec::new();
        for (k, o) in self.obstacles.iter().enumerate() {
            owners.extend(std::iter::repeat_n(k, o.parts.len()));
        }
        Ok(hit.and_then(|h| {
            owners.get(h.id as usize).map(|&k| Pick {
                id: self.obstacles[k].spec.id.clone(),
                point: h.point.to_array(),
                distance: h.distance,
            })
        }))
    }

    /// Back to `t = 0` and `q0` with the obstacles and controller as edited;
    /// events, control points and sensing streams start afresh.
    pub fn reset(&mut self) {
        let scenario = self.scenario.clone();
        if let Ok(w) = Self::new(scenario) {
            *self = w;
        }
    }
}

/// Links that never repel each other: links whose segments share a node,
/// and links one such neighbour apart (a short link between two long ones
/// keeps their volumes overlapping at the joint). Links without segments
/// are passed through.
fn link_adjacency(robot: &Robot, skeleton: &Skeleton) -> Vec<Vec<bool>> {
    let n = robot.dof() + 1;
    let mut direct = vec![vec![false; n]; n];
    for a in &skeleton.segments {
        for b in &skeleton.segments {
            let share = a.from == b.from || a.from == b.to || a.to == b.from || a.to == b.to;
            if share && a.link < n && b.link < n {
                direct[a.link][b.link] = true;
            }
        }
    }
    let mut adj = direct.clone();
    for (i, row) in adj.iter_mut().enumerate() {
        row[i] = true;
        for (k, via) in direct[i].iter().enumerate() {
            if *via {
                for (j, hop) in direct[k].iter().enumerate() {
                    if *hop {
                        row[j] = true;
                    }
                }
            }
        }
    }
    adj
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

/// Runs `scenario` from `t = 0` to its duration and returns the trace
/// (a sample every `sampleEvery` steps, then every event).
///
/// # Errors
/// Whatever [`Scenario::validate`] reports.
///
/// # Example
/// ```
/// use skeleton_avoidance::{scenario, world};
/// let trace = world::simulate(&scenario::example("planar-transition")?)?;
/// assert!(!trace.samples.is_empty());
/// # Ok::<(), skeleton_avoidance::scenario::ScenarioError>(())
/// ```
pub fn simulate(scenario: &Scenario) -> Result<Trace, ScenarioError> {
    let mut world = World::new(scenario.clone())?;
    world.keep_all_events = true;
    let steps = (scenario.duration / scenario.dt).round() as u64;
    let every = scenario.sample_every.max(1) as u64;
    let mut samples = Vec::new();
    for k in 0..steps {
        world.step(scenario.dt);
        if k % every == 0 {
            samples.push(world.sample());
        }
    }
    Ok(Trace {
        samples,
        events: world.events,
    })
}

/// The control-step benchmark's world: `lwr4` following a circular
/// end-effector trajectory among `obstacles` static spheres (radius 5 cm)
/// spread pseudo-randomly (seeded) over a 1.6 × 1.6 × 1.2 m box around it,
/// at 1 kHz. Shared by the criterion bench and the wasm export so both time
/// the same work.
///
/// # Errors
/// None in practice (the scenario is valid by construction).
pub fn control_step_workload(obstacles: usize) -> Result<World, ScenarioError> {
    use crate::distance::SphereSpec;
    let mut rng = crate::rng::Rng::new(11);
    let obstacles = (0..obstacles)
        .map(|k| ObstacleSpec {
            id: format!("o{k}"),
            shape: ShapeSpec::Primitive(PrimitiveSpec::Sphere(SphereSpec {
                center: [
                    rng.range(-0.8, 0.8),
                    rng.range(-0.8, 0.8),
                    rng.range(0.0, 1.2),
                ],
                radius: 0.05,
            })),
            motion: None,
        })
        .collect();
    let points: Vec<[f64; 3]> = (0..=8)
        .map(|k| {
            let a = std::f64::consts::TAU * f64::from(k) / 8.0;
            [
                0.45 + 0.1 * crate::math::cos(a),
                0.1 * crate::math::sin(a),
                0.6,
            ]
        })
        .collect();
    let times = (0..=8).map(|k| 0.5 * f64::from(k)).collect();
    let scenario = Scenario {
        robot: crate::scenario::RobotRef::Preset("lwr4".to_owned()),
        q0: Some(vec![0.0, 0.6, 0.0, -1.2, 0.0, 0.6, 0.0]),
        obstacles,
        task: TaskSpec::Trajectory {
            points,
            times,
            chain: 0,
        },
        controller: ControllerConfig::default(),
        sensing: crate::scenario::SensingConfig::default(),
        dependability: crate::dependability::DependabilityConfig::default(),
        dt: 0.001,
        duration: 4.0,
        sample_every: 1,
    };
    World::new(scenario)
}
