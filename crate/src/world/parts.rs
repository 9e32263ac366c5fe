//! What a [`super::World`] is made of, Pinocchio/MuJoCo style: the
//! [`Model`] (what no step changes), the [`State`] (what the next step
//! needs), the [`StepData`] (what one step computes, kept for the readers
//! of the state) and the [`EventLog`].
//!
//! The split is what lets a stage borrow the configuration
//! (`&model.scenario.controller`) while it writes the state and the step
//! data. Borderline fields:
//! - the scene and its part tables are in [`State`] ([`Sensed`]), not in
//!   the step data: the scene is rebuilt only when an obstacle moves or an
//!   edit marks it dirty, so a step reads the scene an earlier step built;
//! - `braking` is in [`StopState`]: the protective layer sets it only when
//!   it is on, so a step may read the value of an earlier one;
//! - the frames and the skeleton are step data (every step recomputes them
//!   from `q` before reading them); edits between steps read the last
//!   step's, as the accessors do.

use std::collections::{BTreeMap, BTreeSet};

use glam::{DQuat, DVec3};

use super::StopReason;
use super::clock::Clock;
use super::dynamics::DynamicsData;
use super::monitor::CommandMonitor;
use super::motion::PartMotion;
use super::obstacles::ObstacleState;
use super::state::ControlPointState;
use super::tracker::Tracker;
use super::uncertainty::SigmaInput;
use crate::avoidance::limits::JointMotion;
use crate::avoidance::protect::{Guard, GuardPair};
use crate::avoidance::qp::Workspace;
use crate::avoidance::selection::Key;
use crate::avoidance::{ActivePoint, TaskReference};
use crate::dependability::{Event, EventKind};
use crate::distance::Scene;
use crate::dynamics::Dynamics;
use crate::error::FieldError;
use crate::kinematics::{Frames, Robot};
use crate::scenario::Scenario;
use crate::skeleton::Skeleton;

/// What no step changes (only edits do): the scenario with its
/// configuration, the robot and the link pairs the self-collision query
/// leaves out.
#[derive(Clone, Debug)]
pub(super) struct Model {
    pub(super) scenario: Scenario,
    pub(super) robot: Robot,
    /// `adjacency[i][j]`: links `i` and `j` never repel each other.
    pub(super) adjacency: Vec<Vec<bool>>,
    /// The robot's rigid-body dynamics, or why it has none (links without
    /// inertial data).
    pub(super) dynamics: Result<Dynamics, FieldError>,
}

/// What the next step needs: the joints, the time, the obstacles as
/// sensed, the control points' trackers, the monitors and the stop.
#[derive(Clone, Debug)]
pub(super) struct State {
    pub(super) q: Vec<f64>,
    pub(super) motion: JointMotion,
    pub(super) t: f64,
    /// Counts equal steps so that `t` is `k·dt` without rounding drift.
    pub(super) clock: Clock,
    /// The task's anchors (pinned poses of the `hold` task).
    pub(super) anchors: Vec<(DVec3, Option<DQuat>)>,
    pub(super) sensed: Sensed,
    pub(super) trackers: BTreeMap<Key, Tracker>,
    /// Obstacles whose control points are at risk of switching.
    pub(super) risky: BTreeSet<usize>,
    pub(super) stop: StopState,
}

/// The obstacles as sensed and the scene built from them.
#[derive(Clone, Debug)]
pub(super) struct Sensed {
    pub(super) obstacles: Vec<ObstacleState>,
    pub(super) scene: Scene,
    /// Per scene part: its obstacle.
    pub(super) owners: Vec<usize>,
    /// Obstacle `o`'s parts are scene parts `part_start[o]..part_start[o + 1]`.
    pub(super) part_start: Vec<usize>,
    /// Per scene part: its index among its obstacle's parts, and its motion.
    pub(super) part_index: Vec<usize>,
    pub(super) part_motion: Vec<PartMotion>,
    /// Whether an edit asks for the scene to be rebuilt.
    pub(super) dirty: bool,
}

/// The command monitor and the stop (category 2).
#[derive(Clone, Debug, Default)]
pub(super) struct StopState {
    pub(super) command_monitor: CommandMonitor,
    /// Whether the protective layer asked for the emergency brake.
    pub(super) braking: bool,
    pub(super) stopped: bool,
    pub(super) reason: Option<StopReason>,
    /// Held stopped at least until this time (s).
    pub(super) until: f64,
    /// Obstacles (`usize::MAX`: self) whose approach is unavoidable now.
    pub(super) unavoidable: BTreeSet<usize>,
}

/// What one step computes: kept until the next so that the state can be
/// read (and buffers reused).
#[derive(Clone, Debug)]
pub(super) struct StepData {
    pub(super) frames: Frames,
    pub(super) skeleton: Skeleton,
    pub(super) references: Vec<TaskReference>,
    /// The `joints` task's reference and its clock.
    pub(super) joint_path: JointPathData,
    /// Per obstacle, the factor on the arm's allowed approach speed when a
    /// transition plus braking would not end before contact (1: none).
    pub(super) slowdown: Vec<f64>,
    /// The requested joint velocities.
    pub(super) request: Vec<f64>,
    pub(super) guard: GuardData,
    pub(super) readout: Readout,
    pub(super) propagation: Propagation,
    pub(super) dynamics: DynamicsData,
}

/// The `joints` task's reference now (`q`, `q̇`; empty without one) and
/// the time on its path, which runs slower than the world's while the arm
/// lags (see `control.rs`).
#[derive(Clone, Debug, Default)]
pub(super) struct JointPathData {
    pub(super) q: Vec<f64>,
    pub(super) qdot: Vec<f64>,
    pub(super) time: f64,
}

/// The protective layer's guards of one step and the QP's workspace.
#[derive(Clone, Debug, Default)]
pub(super) struct GuardData {
    pub(super) guards: Vec<Guard>,
    pub(super) pairs: Vec<GuardPair>,
    /// The bend reserve's frames, kept from step to step.
    pub(super) bend: crate::avoidance::protect::Bend,
    /// This step's first guard with no admissible escape, and by how much
    /// the arm's approach exceeds its bound.
    pub(super) doomed: Option<(usize, f64)>,
    /// Time within which the joints must be able to stop this step (s; `∞`
    /// with no obstacle closing in): see `protect::stop_time`.
    pub(super) stop_time: f64,
    /// Whether the `constraints` avoidance dropped its dampers this step.
    pub(super) relaxed: bool,
    pub(super) qp: Workspace,
}

/// What one step measured, for the readers of the state.
#[derive(Clone, Debug, Default)]
pub(super) struct Readout {
    pub(super) points: Vec<ControlPointState>,
    pub(super) min_clearance: Option<f64>,
    /// The human part (`id:part`) of the pair at `min_clearance`, if a
    /// human's.
    pub(super) closest_part: Option<String>,
    /// The human part (`id:part`) nearest the arm and its clearance (m),
    /// whatever pair is closest overall.
    pub(super) closest_human: Option<(String, f64)>,
    pub(super) time_to_collision: Option<f64>,
    /// The bound in force for the human part nearest the arm.
    pub(super) protection: Option<super::pfl::ProtectionReadout>,
}

/// The last step's active points and, for the control points that answer
/// an obstacle sensed with error, what their propagation needs (computed
/// when the state is read: [`super::World::propagation`]); with the step's
/// `t`, `q`, `q̇` and `dt`.
#[derive(Clone, Debug, Default)]
pub(super) struct Propagation {
    pub(super) active: Vec<ActivePoint>,
    pub(super) sigma_inputs: Vec<SigmaInput>,
    pub(super) t: f64,
    pub(super) qdot: Vec<f64>,
    pub(super) dt: f64,
    pub(super) q: Vec<f64>,
}

/// The events so far (the oldest half dropped beyond
/// [`super::MAX_EVENTS`] unless `keep_all`).
#[derive(Clone, Debug, Default)]
pub(super) struct EventLog {
    pub(super) events: Vec<Event>,
    /// Events dropped so far.
    pub(super) dropped: usize,
    pub(super) keep_all: bool,
}

impl EventLog {
    /// Records `kind` at time `t`.
    pub(super) fn push(&mut self, t: f64, kind: EventKind) {
        self.events.push(Event { t, kind });
    }

    /// Drops the oldest half beyond [`super::MAX_EVENTS`] (unless every
    /// event is kept).
    pub(super) fn trim(&mut self) {
        if !self.keep_all && self.events.len() > super::MAX_EVENTS {
            let drop = self.events.len() - super::MAX_EVENTS / 2;
            self.events.drain(..drop);
            self.dropped += drop;
        }
    }
}

/// The world as a stage reads it while another part is being written:
/// what the read-only helpers of a step (where a control point is, its
/// time to collision) take.
#[derive(Clone, Copy)]
pub(super) struct Now<'a> {
    pub(super) model: &'a Model,
    pub(super) state: &'a State,
    pub(super) data: &'a StepData,
}
