//! Reach problems: a goal pose among obstacles, run to the end and judged
//! the way a user of a reactive controller judges it (the reach benchmark
//! of `npm run bench -- --reach` and `cargo run --release --example reach`).
//!
//! Three problem sets, by name in [`problems`] (`reachProblems` in JS):
//!
//! * **`pr2`, NEO's PR2 problems** ([`pr2_problems`]): the five scenes of
//!   Haviland & Corke's NEO benchmark (bookshelf, counter, industrial A and
//!   B, tunnel; 198 start/goal pairs of the PR2's right arm among boxes), as
//!   published in the `jhavl/neo` repository (MIT; the data and its
//!   provenance are in `crate/tests/data/neo/`). The right arm is imported
//!   from the PR2's URDF from `torso_lift_link` to `r_wrist_roll_link` and
//!   placed in `base_footprint` with the torso at the benchmark's 0.16825 m
//!   ([`pr2_arm`]); the goal is the pose of `r_wrist_roll_link` at the goal
//!   configuration (as in NEO). Built in (`pr2.json`, see [`sets`]).
//! * **`panda`, seeded random Panda problems** ([`panda_problems`]): from a
//!   random configuration to the pose of another one nearby, with one to
//!   three spheres and boxes placed near the straight path of the end
//!   effector, static or moving at 0.1–0.5 m/s; both configurations clear of
//!   the obstacles and of the arm's own links.
//! * **`mbm`, MotionBenchMaker's Panda problems** ([`mbm_problems`]): 700
//!   problems in 7 scenes of boxes and cylinders; read from the scene files
//!   of `crate/tests/data/mbm/`, not built in (see [`mbm`] for why).
//!
//! A problem **succeeds** when the end effector comes within 1 cm and 2° of
//! the goal within [`TIME_LIMIT`], no contact begins while the arm moves,
//! and every joint stays within its velocity, acceleration and jerk limits
//! ([`crate::scenario::audit`]). This is stricter than NEO's own count
//! (a summed pose error below 0.25, in metres plus radians, within 25 s,
//! with no collision or limit check), which [`run`] reports beside it.
//!
//! Files: `mod.rs` (running and judging a problem, the summary),
//! `pr2.rs`, `pr2_fit.rs` (the arm's volumes fitted to its meshes),
//! `pr2.json`, `panda.rs`, `mbm.rs` (the sets), `sets.rs` (the
//! sets by name, a problem as plain data).

pub mod mbm;
mod panda;
mod pr2;
mod pr2_fit;
pub mod sets;

pub use mbm::mbm_problems;
pub use panda::panda_problems;
pub use pr2::{Pr2Box, Pr2Scene, TORSO_LIFT, pr2_arm, pr2_problems, pr2_scenes};
pub use pr2_fit::{Pr2Fit, pr2_fitted_arm};
pub use sets::{PANDA_COUNT, PANDA_SEED, SETS, pr2_builtin, pr2_data, problems};

use glam::{DQuat, DVec3};
use serde_json::{Value, json};

use crate::error::FieldError;
use crate::scenario::{MotionAudit, Scenario, Trace, audit};
use crate::world::World;

/// Time a problem has to reach its goal (s).
pub const TIME_LIMIT: f64 = 10.0;
/// Position tolerance of success (m).
pub const POSITION_TOLERANCE: f64 = 0.01;
/// Orientation tolerance of success (degrees).
pub const ANGLE_TOLERANCE: f64 = 2.0;
/// Control period of the benchmark (s).
pub const DT: f64 = 0.005;
/// NEO's count: time a problem has (s).
pub const NEO_TIME_LIMIT: f64 = 25.0;
/// NEO's count: the summed pose error (m plus rad) below which a run counts.
pub const NEO_THRESHOLD: f64 = 0.25;

/// One problem: a scenario with a `goal` task, and the goal it asks for.
#[derive(Clone, Debug)]
pub struct Problem {
    /// `set/scene/index`.
    pub name: String,
    /// The scenario (duration [`TIME_LIMIT`]).
    pub scenario: Scenario,
    /// Goal position (m).
    pub position: DVec3,
    /// Goal orientation.
    pub orientation: DQuat,
    /// A configuration at the goal, when the problem comes with one.
    pub goal_q: Option<Vec<f64>>,
}

/// What one run did.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// Within tolerance of the goal in time, admissible, no contact while
    /// moving.
    pub success: bool,
    /// First time within tolerance (s).
    pub reached: Option<f64>,
    /// NEO's count: the first time the summed pose error (m plus rad) fell
    /// below [`NEO_THRESHOLD`], within [`NEO_TIME_LIMIT`] (s), whatever the
    /// contacts and the limits.
    pub neo_reached: Option<f64>,
    /// Position and orientation errors at the end of the strict window
    /// (m, degrees).
    pub final_error: (f64, f64),
    /// The motion against the robot's limits (clearance included), over the
    /// strict window.
    pub audit: MotionAudit,
    /// Steps run.
    pub steps: usize,
    /// Whether the arm was stopped (`unavoidable` or chattering) at least
    /// once.
    pub stopped: bool,
    /// Smallest clearance in the first step (m; negative: the problem
    /// starts in contact with the benchmark's volumes).
    pub start_clearance: f64,
    /// Smallest clearance of the arm at the goal configuration, when the
    /// problem knows it (m).
    pub goal_clearance: Option<f64>,
}

/// What [`run`] tracks while it steps.
#[derive(Default)]
struct Progress {
    reached: Option<f64>,
    neo_reached: Option<f64>,
    held: bool,
}

impl Progress {
    /// Updates the criteria with the errors at time `t` (m, degrees);
    /// `strict`: still within [`TIME_LIMIT`].
    fn update(&mut self, t: f64, error: (f64, f64), strict: bool) {
        if self.neo_reached.is_none() && error.0 + error.1.to_radians() < NEO_THRESHOLD {
            self.neo_reached = Some(t);
        }
        if !strict || self.held {
            return;
        }
        let within = error.0 < POSITION_TOLERANCE && error.1 < ANGLE_TOLERANCE;
        match (within, self.reached) {
            (true, None) => self.reached = Some(t),
            (false, Some(_)) => self.reached = None,
            (true, Some(t0)) if t - t0 >= 0.5 => self.held = true,
            _ => {}
        }
    }
}

/// Runs `problem` and judges it: strictly over its first [`TIME_LIMIT`]
/// (stopping once the goal has been held within tolerance for 0.5 s), and,
/// when NEO's count is not met by then, on up to [`NEO_TIME_LIMIT`] for it.
///
/// # Errors
/// A scenario the world refuses.
pub fn run(problem: &Problem) -> Result<Outcome, FieldError> {
    let mut world = World::new(problem.scenario.clone())
        .map_err(|e| FieldError::new("scenario", e.to_string()))?;
    let robot = world.robot().clone();
    let dt = problem.scenario.dt;
    let strict_steps = (TIME_LIMIT / dt).round() as usize;
    let steps = (NEO_TIME_LIMIT / dt).round() as usize;
    let mut trace = Trace::default();
    let mut progress = Progress::default();
    let mut error = (f64::INFINITY, f64::INFINITY);
    let mut final_error = error;
    let mut stopped = false;
    let mut done = 0;
    let mut start_clearance = f64::INFINITY;
    for k in 0..steps {
        world.step(dt);
        done = k + 1;
        let strict = k < strict_steps;
        if strict {
            trace.samples.push(world.sample());
            stopped |= world.is_stopped();
        }
        if k == 0 {
            start_clearance = world.sample().min_clearance.unwrap_or(f64::INFINITY);
        }
        let ee = world.frames().end_effector();
        let rot = DQuat::from_mat3(&ee.matrix3);
        error = (
            (ee.translation - problem.position).length(),
            rot.angle_between(problem.orientation).to_degrees(),
        );
        progress.update(world.time(), error, strict);
        if strict {
            final_error = error;
        }
        let strict_over = progress.held || k + 1 >= strict_steps;
        if strict_over && progress.neo_reached.is_some() {
            break;
        }
    }
    let audit = audit(&robot, &trace);
    Ok(Outcome {
        success: progress.reached.is_some() && audit.admissible(),
        reached: progress.reached,
        neo_reached: progress.neo_reached,
        final_error,
        audit,
        steps: done,
        stopped,
        start_clearance,
        goal_clearance: problem
            .goal_q
            .as_ref()
            .map(|q| clearance_at(&problem.scenario, q))
            .transpose()?,
    })
}

fn scenario_json(
    robot: Value,
    q0: &[f64],
    obstacles: Vec<Value>,
    position: DVec3,
    orientation: DQuat,
) -> Result<Scenario, FieldError> {
    let v = json!({
        "robot": robot,
        "q0": q0,
        "obstacles": obstacles,
        "task": { "type": "goal", "position": position.to_array(),
                  "orientation": [orientation.x, orientation.y, orientation.z, orientation.w] },
        "dt": DT,
        "duration": TIME_LIMIT,
    });
    Scenario::from_json(&v.to_string()).map_err(|e| FieldError::new("scenario", e.to_string()))
}

/// Smallest clearance of the arm at `q` among `scenario`'s obstacles at
/// `t = 0` (m).
fn clearance_at(scenario: &Scenario, q: &[f64]) -> Result<f64, FieldError> {
    let mut s = scenario.clone();
    s.q0 = Some(q.to_vec());
    s.controller.protective.enabled = false;
    s.task = crate::scenario::Tasks::default();
    let mut world = World::new(s).map_err(|e| FieldError::new("scenario", e.to_string()))?;
    world.step(DT);
    Ok(world.sample().min_clearance.unwrap_or(f64::INFINITY))
}

/// Figures over a set of outcomes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Summary {
    /// Problems.
    pub problems: usize,
    /// Successes.
    pub successes: usize,
    /// Runs that meet NEO's count.
    pub neo_successes: usize,
    /// Median time to goal over successes (s).
    pub median_time: f64,
    /// Smallest clearance over every run (m).
    pub min_clearance: f64,
    /// Peak `|q̇|/limit` and `|q̈|/limit` over every run.
    pub peak: (f64, f64),
    /// Runs with a limit exceeded or a contact that began while moving.
    pub violations: usize,
}

/// The [`Summary`] of `outcomes`.
#[must_use]
pub fn summarise(outcomes: &[Outcome]) -> Summary {
    let mut times: Vec<f64> = outcomes
        .iter()
        .filter(|o| o.success)
        .filter_map(|o| o.reached)
        .collect();
    times.sort_by(f64::total_cmp);
    Summary {
        problems: outcomes.len(),
        successes: outcomes.iter().filter(|o| o.success).count(),
        neo_successes: outcomes.iter().filter(|o| o.neo_reached.is_some()).count(),
        median_time: times.get(times.len() / 2).copied().unwrap_or(f64::NAN),
        min_clearance: outcomes
            .iter()
            .map(|o| o.audit.clearance)
            .fold(f64::INFINITY, f64::min),
        peak: outcomes.iter().fold((0.0, 0.0), |(v, a), o| {
            (
                f64::max(v, o.audit.velocity),
                f64::max(a, o.audit.acceleration),
            )
        }),
        violations: outcomes.iter().filter(|o| !o.audit.admissible()).count(),
    }
}
