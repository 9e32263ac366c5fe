//! A live simulation: the arm, the obstacles, the controller and the
//! monitor, stepped interactively ([`World`]) or run to the end of a
//! scenario ([`simulate`]).
//!
//! `World` is, Pinocchio/MuJoCo style, a `Model` (the scenario
//! with its configuration, the robot, the link pairs left out: what no
//! step changes), a `State` (what the next step needs: `q`, the
//! joint motion, `t`, the obstacles as sensed and their scene, the
//! control points' trackers, the monitors, the stop), a
//! `StepData` (what one step computes: frames, skeleton, guards,
//! request, QP workspace, readouts) and an `EventLog`
//! (`world/parts.rs`, which says where each borderline field lives and
//! why). One [`World::step`] runs the control step as named stages, each
//! a free function over those parts in the file named after it, called in
//! order from `world/step.rs`; every stage borrows the configuration from
//! the model (it is never copied):
//!
//! | # | stage | where | paper |
//! |---|---|---|---|
//! | 1 | **sense**: obstacles at `t`, then as sensed (bias, bounded error, white and correlated noise, latency) and each obstacle's margin | `world/sense.rs`, `world/obstacles.rs`, [`crate::dependability::SensorModel`] | §IV |
//! | 2 | **scene query**: forward kinematics, skeleton, every segment against every obstacle within reach (and non-adjacent links against each other) | `world/query.rs`, [`crate::kinematics`], [`crate::skeleton`], [`crate::distance::Scene::query`] | §II |
//! | 3 | **select**: control points per pair / per obstacle / pinned / self | `world/select.rs`, [`crate::avoidance::selection::select`] | §II, fig. 4 |
//! | 4 | **transition**: each control point follows its selected point, travelling along the skeleton when it jumps; switch risk and chattering | `world/tracker.rs`, [`crate::transition::MovingPoint`] | §III-B, §IV |
//! | 5 | **monitor**: the active points where they are, time to collision, transitions too slow for the approach | `world/active.rs`, `world/monitor.rs`, [`crate::dependability`] | §IV |
//! | 6 | **control**: the guards, then repulsion and tasks → requested joint velocities | `world/protect.rs`, `world/control.rs`, [`crate::avoidance::control`] | §III-A, eq. 4 |
//! | 7 | **protect**: every pair's approach bounded so the arm can stop before contact | `world/protect.rs`, [`crate::avoidance::protect`] | — (ISO/TS 15066) |
//! | 8 | **limit**: jerk-limited tracking within the joints' limits | `world/limit.rs`, [`crate::avoidance::limits`] | — |
//! | 9 | **integrate**: `q += q̇ dt`, `t += dt`; then the command monitor | `world/limit.rs`, `world/monitor.rs` | — |
//!
//! `impl World` is in this file (the constructor, the step and the
//! readers, which call the free functions of `state.rs`, `readout.rs`,
//! `probe.rs` and `uncertainty.rs`) and in `world/edit.rs` (the edits).
//! `adjacency.rs` computes the link pairs the model leaves out, `run.rs`
//! runs a scenario to its end, `start.rs` imports a URDF.
//!
//! A stop (chattering, or an unavoidable approach) is category 2: the
//! request becomes zero, the protective layer stays on (asking no retreat),
//! the limiter brings the joints to rest within their acceleration and jerk
//! limits, and the arm holds still until it resumes.
//!
//! Everything is deterministic: the same scenario gives the same trace, bit
//! for bit, natively and in wasm.

use std::collections::{BTreeMap, BTreeSet};

use crate::avoidance::limits::JointMotion;
use crate::avoidance::protect::Guard;
use crate::avoidance::selection::Key;
use crate::dependability::{Event, PointSigma, SensingSpec};
use crate::distance::{Primitive, Scene};
use crate::error::FieldError;
use crate::kinematics::{Frames, Robot};
use crate::scenario::{Sample, Scenario, ScenarioError, ShapeSpec};
use crate::skeleton::Skeleton;

mod active;
mod adjacency;
mod clock;
mod control;
mod dynamics;
mod edit;
mod limit;
mod monitor;
mod motion;
mod obstacles;
mod parts;
mod pfl;
mod probe;
mod protect;
mod query;
mod readout;
mod run;
mod select;
mod sense;
mod start;
mod stream;

pub use edit::MAX_SENSING_LATENCY;
pub use run::{control_step_workload, simulate};
pub use start::import_urdf;
pub use stream::{
    BODY_SPEED, GOOD_CONFIDENCE, HAND_SPEED, HumanFrame, MAX_FRAME_KEYPOINTS, STALE_AFTER,
    STREAM_WINDOW,
};
mod state;
mod step;
mod tracker;
mod uncertainty;

pub(crate) use adjacency::self_pairs_left_out;
use obstacles::ObstacleState;
use parts::{EventLog, GuardData, Model, Propagation, Readout, Sensed, State, StepData, StopState};
pub use pfl::ProtectionReadout;
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
/// state, the last step's data and the event log (`world/parts.rs`).
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
        let dynamics = dynamics::model_dynamics(&robot);
        dynamics::require_dynamics(&scenario.controller, &dynamics).map_err(err)?;
        let dynamics_data = dynamics::data_for(&dynamics);
        let mut w = Self {
            model: Model {
                scenario,
                robot,
                adjacency,
                dynamics,
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
                joint_path: parts::JointPathData::default(),
                slowdown: Vec::new(),
                request: Vec::new(),
                guard: GuardData {
                    stop_time: f64::INFINITY,
                    ..GuardData::default()
                },
                readout: Readout::default(),
                propagation: Propagation::default(),
                dynamics: dynamics_data,
            },
            log: EventLog::default(),
        };
        let dt = w.model.scenario.dt;
        w.state.sensed.rebuild_scene(0.0, false, dt);
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
        state::state_since(self, cursor)
    }

    /// One trace sample: the time, joints, clearance and control points the
    /// last step acted on.
    #[must_use]
    pub fn sample(&self) -> Sample {
        state::sample(self)
    }

    /// Joint velocities now (rad/s or m/s), in the order of `q`.
    #[must_use]
    pub fn qdot(&self) -> &[f64] {
        readout::qdot(self)
    }

    /// [`World::clearance_of`] every obstacle, by id (infinite ones left
    /// out: a robot without segments): what a trace sample carries.
    #[must_use]
    pub fn clearances(&self) -> std::collections::BTreeMap<String, f64> {
        readout::clearances(self)
    }

    /// Clearance (m) between the arm's volumes and obstacle `id`, measured
    /// where the last step measured its control points: the skeleton at
    /// the `q` that step acted on against the obstacle's true pose at that
    /// step's time (a human posed by its animation or track then); `q0`
    /// and `t = 0` before any step. Negative by the penetration depth when
    /// they overlap, infinite for a robot without segments.
    ///
    /// # Errors
    /// `id: no obstacle "…"` for an unknown id.
    pub fn clearance_of(&self, id: &str) -> Result<f64, ScenarioError> {
        readout::clearance_of(self, id)
    }

    /// The numbers a Monte Carlo study keeps of the last step, read from
    /// the world without building its state.
    #[must_use]
    pub fn probe(&self) -> StepProbe {
        probe::probe(self)
    }

    /// The pairs the protective layer guarded at the last step, with the
    /// speed of the part that approaches and the protective distance it
    /// asks (empty when the protective layer is off, and after an obstacle
    /// is removed until the next step).
    #[must_use]
    pub fn guarded(&self) -> Vec<GuardedPair> {
        probe::guarded(self)
    }

    /// The first-order standard deviations of the last step: per control
    /// point (in the order of the state's control points, `None` for those
    /// answering nothing noisy) and per joint command (`None` when no
    /// control point answers a noisy obstacle).
    #[must_use]
    pub fn propagation(&self) -> (Vec<Option<PointSigma>>, Option<Vec<f64>>) {
        uncertainty::propagation(self)
    }

    /// What an obstacle of figure `shape` sensed with `sensing` would face
    /// with the arm where it is: its clearance and the probability that
    /// its closest segment, as sensed, differs from the ideal one — one
    /// cell of a risk map (the picture the paper's fig. 4 asks for). A
    /// human's `partSigma` adds its largest part's σ.
    ///
    /// # Errors
    /// An invalid figure (`shape…`) or sensing (`sensing.…`).
    pub fn risk_at(&self, shape: &ShapeSpec, sensing: &SensingSpec) -> Result<Risk, ScenarioError> {
        uncertainty::risk_at(self, shape, sensing)
    }

    /// Advances the simulation by `dt` seconds (one control step). A
    /// non-finite or non-positive `dt` does nothing.
    pub fn step(&mut self, dt: f64) {
        step::step(
            &self.model,
            &mut self.state,
            &mut self.data,
            &mut self.log,
            dt,
        );
    }
}

/// The obstacle a control point answers, as events and readouts name it
/// (`pinned:<k>`, `self:<link>`).
fn name(state: &State, data: &StepData, key: &Key) -> String {
    match key {
        Key::Obstacle(o) | Key::Pair(o, _) => state.sensed.obstacles[*o].spec.id.clone(),
        Key::Pinned(k) => format!("pinned:{k}"),
        Key::SelfPair(_, other) => format!("self:{}", data.skeleton.segments[*other].link),
    }
}
