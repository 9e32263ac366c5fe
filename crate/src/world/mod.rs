//! A live simulation: the arm, the obstacles, the controller and the
//! monitor, stepped interactively ([`World`]) or run to the end of a
//! scenario ([`simulate`]).
//!
//! `World` holds the state; one [`World::step`] runs the control step as a
//! pipeline of named stages, each a function of the module named after its
//! part of the paper (the stages are called from `world/step.rs`):
//!
//! | # | stage | where | paper |
//! |---|---|---|---|
//! | 1 | **sense**: obstacles at `t`, then as sensed (bias, bounded error, white and correlated noise, latency) and each obstacle's margin | `world/obstacles.rs`, [`crate::dependability::SensorModel`] | §IV |
//! | 2 | **scene query**: forward kinematics, skeleton, every segment against every obstacle within reach (and non-adjacent links against each other) | [`crate::kinematics`], [`crate::skeleton`], [`crate::distance::Scene::query`] | §II |
//! | 3 | **select**: control points per pair / per obstacle / pinned / self | [`crate::avoidance::selection::select`] | §II, fig. 4 |
//! | 4 | **transition**: each control point follows its selected point, travelling along the skeleton when it jumps | [`crate::transition::MovingPoint`] | §III-B |
//! | 5 | **monitor**: switch risk, chattering (stop or lock), time to collision, transitions too slow for the approach | [`crate::dependability`], `world/monitor.rs` | §IV |
//! | 6 | **control**: repulsion and tasks → requested joint velocities | [`crate::avoidance::control`] | §III-A, eq. 4 |
//! | 7 | **protect**: every pair's approach bounded so the arm can stop before contact | [`crate::avoidance::protect`] | — (ISO/TS 15066) |
//! | 8 | **limit**: jerk-limited tracking within the joints' limits | [`crate::avoidance::limits`] | — |
//! | 9 | **integrate**: `q += q̇ dt`, `t += dt` | `world/step.rs` | — |
//!
//! A stop (chattering, or an unavoidable approach) is category 2: the
//! request becomes zero, the protective layer stays on (asking no retreat),
//! the limiter brings the joints to rest within their acceleration and jerk
//! limits, and the arm holds still until it resumes.
//!
//! Everything is deterministic: the same scenario gives the same trace, bit
//! for bit, natively and in wasm.

use std::collections::{BTreeMap, BTreeSet};

use crate::avoidance::ControllerConfig;
use crate::avoidance::limits::JointMotion;
use crate::avoidance::protect::Guard;
use crate::avoidance::selection::Key;
use crate::dependability::{Event, EventKind};
use crate::distance::{Primitive, PrimitiveSpec, Scene};
use crate::error::FieldError;
use crate::kinematics::{Frames, Robot};
use crate::scenario::{ObstacleSpec, Scenario, ScenarioError, ShapeSpec, TaskSpec, Trace};
use crate::skeleton::Skeleton;

mod clock;
mod edit;
mod guard;
mod monitor;
mod obstacles;
mod parts;
mod probe;
mod readout;
mod start;

pub use start::import_urdf;
mod state;
mod step;
mod tracker;
mod uncertainty;

use obstacles::ObstacleState;
use parts::{EventLog, GuardData, Model, Propagation, Readout, Sensed, State, StepData, StopState};
pub use probe::{GuardedPair, StepProbe};
pub use state::{
    ClosestHuman, ControlPointState, ObstacleStateOut, Pick, SegmentState, SkeletonPick,
    SkeletonState, Uncertainty, WorldState,
};
pub use uncertainty::Risk;

/// Events a live [`World`] keeps (the oldest half is dropped beyond this;
/// [`simulate`] keeps every event).
pub const MAX_EVENTS: usize = 20_000;

/// Radius within which a pick ray catches points and segments (m).
pub const PICK_RADIUS: f64 = 0.02;

/// Why the arm is stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum StopReason {
    /// A chattering control point (policy `stop`).
    Chattering,
    /// The protective layer could not keep a pair safe.
    Unavoidable,
}

/// A simulation that steps on demand and accepts edits: the model, the
/// state, the last step's data and the event log ([`parts`]).
#[derive(Clone, Debug)]
pub struct World {
    model: Model,
    state: State,
    data: StepData,
    log: EventLog,
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
        let adjacency = self_pairs_left_out(&robot, &scenario.controller).map_err(err)?;
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
        let anchors = scenario.task.anchors(&robot, &frames);
        let n = robot.dof();
        let mut w = Self {
            model: Model {
                scenario,
                robot,
                adjacency,
            },
            state: State {
                q,
                motion: JointMotion::rest(n),
                t: 0.0,
                clock: clock::Clock::default(),
                anchors,
                sensed: Sensed {
                    obstacles,
                    scene: Scene::default(),
                    owners: Vec::new(),
                    part_start: Vec::new(),
                    part_index: Vec::new(),
                    part_motion: Vec::new(),
                    dirty: true,
                },
                trackers: BTreeMap::new(),
                risky: BTreeSet::new(),
                stop: StopState::default(),
            },
            data: StepData {
                frames,
                skeleton,
                references: Vec::new(),
                slowdown: Vec::new(),
                request: Vec::new(),
                guard: GuardData {
                    stop_time: f64::INFINITY,
                    ..GuardData::default()
                },
                readout: Readout::default(),
                propagation: Propagation::default(),
            },
            log: EventLog::default(),
        };
        let dt = w.model.scenario.dt;
        w.rebuild_scene(0.0, false, dt);
        Ok(w)
    }

    /// The scenario as edited so far.
    #[must_use]
    pub fn scenario(&self) -> &Scenario {
        &self.model.scenario
    }

    /// The robot.
    #[must_use]
    pub fn robot(&self) -> &Robot {
        &self.model.robot
    }

    /// Simulation time (s).
    #[must_use]
    pub fn time(&self) -> f64 {
        self.state.t
    }

    /// Joint values.
    #[must_use]
    pub fn q(&self) -> &[f64] {
        &self.state.q
    }

    /// The frames at the current `q`.
    #[must_use]
    pub fn frames(&self) -> &Frames {
        &self.data.frames
    }

    /// The skeleton at the current `q`.
    #[must_use]
    pub fn skeleton(&self) -> &Skeleton {
        &self.data.skeleton
    }

    /// The active control points of the last step.
    #[must_use]
    pub fn control_points(&self) -> &[ControlPointState] {
        &self.data.readout.points
    }

    /// The obstacles' primitives at their true pose now, with their ids.
    #[must_use]
    pub fn obstacle_primitives(&self) -> Vec<(String, Primitive)> {
        let mut out = Vec::new();
        for o in &self.state.sensed.obstacles {
            let off = o.offset(self.state.t);
            for p in &o.parts {
                out.push((o.spec.id.clone(), p.translated(off)));
            }
        }
        out
    }

    /// The events kept (every event so far, up to [`MAX_EVENTS`]).
    #[must_use]
    pub fn events(&self) -> &[Event] {
        &self.log.events
    }

    /// Number of events since the start (or the last reset), including
    /// those no longer kept: the cursor for [`World::state_since`].
    #[must_use]
    pub fn event_count(&self) -> usize {
        self.log.dropped + self.log.events.len()
    }

    /// Whether the monitor is stopping the robot (or holding it stopped).
    #[must_use]
    pub fn is_stopped(&self) -> bool {
        self.state.stop.stopped
    }

    /// The protective layer's guards of the last step.
    #[must_use]
    pub fn guards(&self) -> &[Guard] {
        &self.data.guard.guards
    }

    /// Joint velocities and accelerations.
    #[must_use]
    pub fn motion(&self) -> &JointMotion {
        &self.state.motion
    }

    pub(super) fn push(&mut self, kind: EventKind) {
        self.log.push(self.state.t, kind);
    }

    pub(super) fn name(&self, key: &Key) -> String {
        match key {
            Key::Obstacle(o) | Key::Pair(o, _) => self.state.sensed.obstacles[*o].spec.id.clone(),
            Key::Pinned(k) => format!("pinned:{k}"),
            Key::SelfPair(_, other) => format!("self:{}", self.data.skeleton.segments[*other].link),
        }
    }
}

/// Links that never repel each other: two hops of [`Robot::adjacent`]
/// (the one definition of adjacent links: their segments share a skeleton
/// node). A link is also kept from its neighbour's neighbours because a
/// short link between two long ones keeps their volumes overlapping at the
/// joint. Rows without segments never meet in the query, so the pairs they
/// add through two hops (their parent's other children, already adjacent)
/// change nothing.
fn link_adjacency(robot: &Robot) -> Vec<Vec<bool>> {
    let n = robot.dof() + 1;
    let direct: Vec<Vec<bool>> = (0..n)
        .map(|i| (0..n).map(|j| robot.adjacent(i, j)).collect())
        .collect();
    (0..n)
        .map(|i| {
            (0..n)
                .map(|j| direct[i][j] || (0..n).any(|k| direct[i][k] && direct[k][j]))
                .collect()
        })
        .collect()
}

/// Which pairs of links the self-collision query leaves out: adjacent links
/// ([`link_adjacency`]), the robot's and the controller's
/// `selfCollisionExclude`, and pairs no joint can move apart or together
/// ([`fixed_link_pairs`]).
pub(super) fn self_pairs_left_out(
    robot: &Robot,
    controller: &ControllerConfig,
) -> Result<Vec<Vec<bool>>, FieldError> {
    let mut adjacency = link_adjacency(robot);
    let chosen = robot.link_pairs(
        "controller.selfCollisionExclude",
        &controller.self_collision_exclude,
    )?;
    for (a, b) in robot
        .exclude
        .iter()
        .chain(&chosen)
        .copied()
        .chain(fixed_link_pairs(robot))
    {
        adjacency[a][b] = true;
        adjacency[b][a] = true;
    }
    Ok(adjacency)
}

/// Pairs of links whose segments keep the same distance whatever the
/// joints do (e.g. the Panda's column and the link carrying the shoulder's
/// offset, which only turn about axes through the column's top): no joint
/// motion can change their clearance, so a guard or damper on them could
/// only freeze the arm. Checked on the kinematics: the smallest distance
/// between the two links' spines at 16 seeded configurations within the
/// limits, fixed when it varies by less than 1 µm.
fn fixed_link_pairs(robot: &Robot) -> Vec<(usize, usize)> {
    use crate::distance::{LineSegment, Primitive, distance};
    let n = robot.dof();
    let mut rng = crate::rng::Rng::new(0x5e1f);
    let mut spans: Vec<Vec<(f64, f64)>> =
        vec![vec![(f64::INFINITY, f64::NEG_INFINITY); n + 1]; n + 1];
    for _ in 0..16 {
        let q: Vec<f64> = robot
            .joints
            .iter()
            .map(|j| {
                let (lo, hi) = (j.min.max(-3.0), j.max.min(3.0));
                rng.range(lo, hi)
            })
            .collect();
        let Ok(frames) = robot.forward(&q) else {
            return Vec::new();
        };
        let skeleton = Skeleton::build(robot, &frames);
        let segs: Vec<(usize, Option<LineSegment>)> = skeleton
            .segments
            .iter()
            .map(|s| {
                let (a, b) = skeleton.endpoints(s);
                (s.link, LineSegment::new(a, b).ok())
            })
            .collect();
        let mut closest = vec![vec![f64::INFINITY; n + 1]; n + 1];
        for (i, (la, a)) in segs.iter().enumerate() {
            for (lb, b) in &segs[i + 1..] {
                if let (Some(a), Some(b)) = (a, b)
                    && la != lb
                    && let Ok(d) = distance(&Primitive::Segment(*a), &Primitive::Segment(*b))
                {
                    let (x, y) = ((*la).min(*lb), (*la).max(*lb));
                    closest[x][y] = closest[x][y].min(d.distance);
                }
            }
        }
        for (x, row) in closest.iter().enumerate() {
            for (y, d) in row.iter().enumerate().filter(|(_, d)| d.is_finite()) {
                let span = &mut spans[x][y];
                *span = (span.0.min(*d), span.1.max(*d));
            }
        }
    }
    let mut out = Vec::new();
    for (x, row) in spans.iter().enumerate() {
        for (y, (lo, hi)) in row.iter().enumerate() {
            if lo.is_finite() && hi - lo < 1e-6 {
                out.push((x, y));
            }
        }
    }
    out
}

/// Runs `scenario` from `t = 0` to its duration and returns the trace: a
/// sample every `sampleEvery` steps from `t = 0` (`t = k·dt` exactly) and
/// one at `t = duration`, then every event.
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
    world.log.keep_all = true;
    let steps = (scenario.duration / scenario.dt).round() as u64;
    let every = scenario.sample_every.max(1) as u64;
    let mut samples = Vec::new();
    // A sample is the state a step acts on: the clearance to each obstacle
    // is measured before the step, the rest comes from the step.
    let take = |world: &mut World| {
        let clearances = world.clearances();
        world.step(scenario.dt);
        let mut sample = world.sample();
        sample.clearances = clearances;
        sample
    };
    for k in 0..steps {
        if k % every == 0 {
            samples.push(take(&mut world));
        } else {
            world.step(scenario.dt);
        }
    }
    // The sample at `t = duration`: one more control step evaluates the
    // state there (clearances, control points); only its sample is kept,
    // not its motion or its events.
    let events = world.log.events.len();
    samples.push(take(&mut world));
    world.log.events.truncate(events);
    Ok(Trace {
        samples,
        events: world.log.events,
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
        }
        .into(),
        controller: ControllerConfig::default(),
        sensing: crate::scenario::SensingConfig::default(),
        dependability: crate::dependability::DependabilityConfig::default(),
        dt: 0.001,
        duration: 4.0,
        sample_every: 1,
        camera: None,
    };
    World::new(scenario)
}

#[cfg(test)]
mod tests {
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    use super::*;
    use crate::kinematics::presets;

    /// Two hops of "segments share a node", read from the skeleton's nodes.
    fn from_nodes(robot: &Robot, skeleton: &Skeleton) -> Vec<Vec<bool>> {
        let n = robot.dof() + 1;
        let mut direct = vec![vec![false; n]; n];
        for (i, row) in direct.iter_mut().enumerate() {
            row[i] = true;
        }
        for a in &skeleton.segments {
            for b in &skeleton.segments {
                if [a.from, a.to].iter().any(|x| *x == b.from || *x == b.to) {
                    direct[a.link][b.link] = true;
                }
            }
        }
        let with_segments: Vec<bool> = (0..n)
            .map(|l| skeleton.segments.iter().any(|s| s.link == l))
            .collect();
        (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| direct[i][j] || (0..n).any(|k| direct[i][k] && direct[k][j]))
                    .collect::<Vec<_>>()
            })
            .enumerate()
            .map(|(i, row)| {
                // Only rows with segments meet in the query.
                row.into_iter()
                    .enumerate()
                    .map(|(j, x)| x && with_segments[i] && with_segments[j])
                    .collect()
            })
            .collect()
    }

    #[test]
    fn the_robots_adjacency_is_the_one_the_skeleton_shows() {
        for name in presets::NAMES {
            let robot = Robot::from_spec(&presets::preset(name).unwrap()).unwrap();
            let frames = robot.forward(&vec![0.2; robot.dof()]).unwrap();
            let skeleton = Skeleton::build(&robot, &frames);
            let expected = from_nodes(&robot, &skeleton);
            let got = link_adjacency(&robot);
            let links: Vec<usize> = skeleton.segments.iter().map(|s| s.link).collect();
            for &i in &links {
                for &j in &links {
                    assert_eq!(got[i][j], expected[i][j], "{name}: links {i} and {j}");
                }
            }
        }
    }
}
