//! Reach problems: a goal pose among obstacles, run to the end and judged
//! the way a user of a reactive controller judges it (the reach benchmark
//! of `npm run bench -- --reach` and `cargo run --release --example reach`).
//!
//! Two problem sets:
//!
//! * **NEO's PR2 problems** ([`pr2_problems`]): the five scenes of Haviland
//!   & Corke's NEO benchmark (bookshelf, counter, industrial A and B,
//!   tunnel; 198 start/goal pairs of the PR2's right arm among boxes), as
//!   published in the `jhavl/neo` repository (MIT; the data and its
//!   provenance are in `crate/tests/data/neo/`). The right arm is imported
//!   from the PR2's URDF from `torso_lift_link` to `r_wrist_roll_link`,
//!   with the torso at the benchmark's 0.16825 m, and the goal is the pose
//!   of `r_wrist_roll_link` at the goal configuration (as in NEO).
//! * **Seeded random Panda problems** ([`panda_problems`]): from a random
//!   configuration to the pose of another one nearby, with one to three
//!   spheres and boxes placed near the straight path of the end effector,
//!   static or moving at 0.1–0.5 m/s; both configurations clear of the
//!   obstacles and of the arm's own links.
//!
//! A problem **succeeds** when the end effector comes within 1 cm and 2° of
//! the goal within [`TIME_LIMIT`], no contact begins while the arm moves,
//! and every joint stays within its velocity, acceleration and jerk limits
//! ([`crate::scenario::audit`]). This is stricter than NEO's own count
//! (a summed pose error below 0.25, in metres plus radians, within 25 s,
//! with no collision or limit check).

use glam::{DQuat, DVec3};
use serde::Deserialize;
use serde_json::{Value, json};

use crate::error::FieldError;
use crate::kinematics::{PoseSpec, Robot, presets};
use crate::parsers::urdf::{UrdfOptions, robot_from_urdf};
use crate::rng::Rng;
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
    /// Position and orientation errors at the end (m, degrees).
    pub final_error: (f64, f64),
    /// The motion against the robot's limits (clearance included).
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

/// Runs `problem` for its duration, stopping early once the goal has been
/// held within tolerance for 0.5 s.
///
/// # Errors
/// A scenario the world refuses.
pub fn run(problem: &Problem) -> Result<Outcome, FieldError> {
    let mut world = World::new(problem.scenario.clone())
        .map_err(|e| FieldError::new("scenario", e.to_string()))?;
    let robot = world.robot().clone();
    let dt = problem.scenario.dt;
    let steps = (problem.scenario.duration / dt).round() as usize;
    let mut trace = Trace::default();
    let mut reached = None;
    let mut error = (f64::INFINITY, f64::INFINITY);
    let mut stopped = false;
    let mut done = 0;
    let mut start_clearance = f64::INFINITY;
    for k in 0..steps {
        world.step(dt);
        done = k + 1;
        trace.samples.push(world.sample());
        if k == 0 {
            start_clearance = world.sample().min_clearance.unwrap_or(f64::INFINITY);
        }
        stopped |= world.is_stopped();
        let ee = world.frames().end_effector();
        let rot = DQuat::from_mat3(&ee.matrix3);
        error = (
            (ee.translation - problem.position).length(),
            rot.angle_between(problem.orientation).to_degrees(),
        );
        let within = error.0 < POSITION_TOLERANCE && error.1 < ANGLE_TOLERANCE;
        match (within, reached) {
            (true, None) => reached = Some(world.time()),
            (false, Some(_)) => reached = None,
            (true, Some(t)) if world.time() - t >= 0.5 => break,
            _ => {}
        }
    }
    let audit = audit(&robot, &trace);
    Ok(Outcome {
        success: reached.is_some() && audit.admissible(),
        reached,
        final_error: error,
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

#[derive(Deserialize)]
struct Pr2Data {
    scenes: Vec<Pr2Scene>,
}

#[derive(Deserialize)]
struct Pr2Scene {
    name: String,
    torso_lift: f64,
    boxes: Vec<Pr2Box>,
    problems: Vec<Pr2Problem>,
}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
struct Pr2Box {
    center: [f64; 3],
    half_extents: [f64; 3],
    rotation: [f64; 4],
}

#[derive(Deserialize)]
struct Pr2Problem {
    start: Vec<f64>,
    goal: Vec<f64>,
}

/// Height of `torso_lift_link` above `base_footprint` at zero lift, and its
/// offset along x (the PR2 URDF: `base_footprint_joint` 0.051 m, then
/// `torso_lift_joint` at (−0.05, 0, 0.739675)).
const TORSO: [f64; 3] = [-0.05, 0.0, 0.051 + 0.739_675];

/// NEO's PR2 problems (see the module docs) from the PR2 URDF and the
/// scenes file `crate/tests/data/neo/pr2-scenes.json`.
///
/// # Errors
/// A URDF or scenes file that does not parse.
pub fn pr2_problems(urdf: &str, scenes_json: &str) -> Result<Vec<Problem>, FieldError> {
    let data: Pr2Data = serde_json::from_str(scenes_json)
        .map_err(|e| FieldError::new("scenes", format!("not a scenes file: {e}")))?;
    let options = UrdfOptions {
        tip: Some("r_wrist_roll_link".into()),
        base: Some("torso_lift_link".into()),
        srdf: None,
        radii: None,
    };
    let mut out = Vec::new();
    for scene in &data.scenes {
        let mut spec = robot_from_urdf(urdf, &options)?;
        spec.base = Some(PoseSpec {
            position: [TORSO[0], TORSO[1], TORSO[2] + scene.torso_lift],
            rotation: [0.0, 0.0, 0.0, 1.0],
        });
        let robot = Robot::from_spec(&spec)?;
        let obstacles: Vec<Value> = scene
            .boxes
            .iter()
            .enumerate()
            .map(|(k, b)| {
                json!({ "id": format!("box{k}"), "shape": {
                    "type": "box", "center": b.center, "halfExtents": b.half_extents, "rotation": b.rotation } })
            })
            .collect();
        for (k, p) in scene.problems.iter().enumerate() {
            let goal = robot.forward(&p.goal)?.end_effector();
            let orientation = DQuat::from_mat3(&goal.matrix3);
            let scenario = scenario_json(
                serde_json::to_value(&spec).map_err(|e| FieldError::new("robot", e.to_string()))?,
                &p.start,
                obstacles.clone(),
                goal.translation,
                orientation,
            )?;
            out.push(Problem {
                name: format!("pr2/{}/{k}", scene.name),
                scenario,
                position: goal.translation,
                orientation,
                goal_q: Some(p.goal.clone()),
            });
        }
    }
    Ok(out)
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

/// `count` seeded random Panda problems (see the module docs).
///
/// # Errors
/// Only through a bug (the Panda preset is built in).
pub fn panda_problems(seed: u64, count: usize) -> Result<Vec<Problem>, FieldError> {
    let spec = presets::preset("panda")?;
    let robot = Robot::from_spec(&spec)?;
    let mut rng = Rng::new(seed);
    let mut out = Vec::new();
    let ready = [0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785];
    while out.len() < count {
        let jitter = |rng: &mut Rng, q: &[f64], s: f64| -> Vec<f64> {
            q.iter()
                .zip(&robot.joints)
                .map(|(v, j)| (v + rng.range(-s, s)).clamp(j.min + 0.1, j.max - 0.1))
                .collect()
        };
        let start = jitter(&mut rng, &ready, 0.5);
        let goal_q = jitter(&mut rng, &start, 0.6);
        let a = robot.forward(&start)?.end_effector().translation;
        let g = robot.forward(&goal_q)?.end_effector();
        let (b, orientation) = (g.translation, DQuat::from_mat3(&g.matrix3));
        if (b - a).length() < 0.15 {
            continue;
        }
        let obstacles = random_obstacles(&mut rng, a, b);
        let scenario = scenario_json(
            json!({ "preset": "panda" }),
            &start,
            obstacles,
            b,
            orientation,
        )?;
        // Both ends must be clear of every obstacle, and of the arm's own
        // links, by more than the safety band, or the problem has no
        // solution (with the Panda's fitted volumes a folded random pose
        // can overlap its own wrist and upper arm).
        if !clear(&scenario, &start)?
            || !clear(&scenario, &goal_q)?
            || !self_clear(&scenario, &start)?
            || !self_clear(&scenario, &goal_q)?
        {
            continue;
        }
        out.push(Problem {
            name: format!("panda/{seed}/{}", out.len()),
            scenario,
            position: b,
            orientation,
            goal_q: Some(goal_q),
        });
    }
    Ok(out)
}

/// One to three spheres and boxes near the straight path from `a` to `b`,
/// static or moving at 0.1–0.5 m/s across it.
fn random_obstacles(rng: &mut Rng, a: DVec3, b: DVec3) -> Vec<Value> {
    let count = 1 + (rng.range(0.0, 3.0) as usize).min(2);
    let dir = (b - a).normalize_or_zero();
    let side = dir.any_orthonormal_vector();
    (0..count)
        .map(|k| {
            let along = a + (b - a) * rng.range(0.3, 0.7);
            let off = side.rotate_towards(dir.cross(side), rng.range(0.0, std::f64::consts::TAU))
                * rng.range(0.12, 0.25);
            let center = along + off;
            let shape = if rng.range(0.0, 1.0) < 0.5 {
                json!({ "type": "sphere", "center": center.to_array(), "radius": rng.range(0.03, 0.08) })
            } else {
                let h = rng.range(0.03, 0.07);
                json!({ "type": "box", "center": center.to_array(), "halfExtents": [h, h, h] })
            };
            let mut o = json!({ "id": format!("o{k}"), "shape": shape });
            if rng.range(0.0, 1.0) < 0.5 {
                // Moving across the path, towards it.
                let v = -off.normalize_or_zero() * rng.range(0.1, 0.5);
                o["motion"] = json!({ "type": "waypoints", "points": [[0, 0, 0], (v * 1.0).to_array()],
                                      "times": [0.0, 1.0] });
            }
            o
        })
        .collect()
}

/// Whether the arm at `q` keeps more than 5 cm from every obstacle of
/// `scenario` over its whole motion (sampled every 0.1 s).
fn clear(scenario: &Scenario, q: &[f64]) -> Result<bool, FieldError> {
    let mut s = scenario.clone();
    s.q0 = Some(q.to_vec());
    s.controller.protective.enabled = false;
    s.controller.self_collision = false;
    s.task = crate::scenario::Tasks::default();
    let mut world = World::new(s).map_err(|e| FieldError::new("scenario", e.to_string()))?;
    for _ in 0..20 {
        for _ in 0..20 {
            world.step(DT);
        }
        if world.sample().min_clearance.is_some_and(|c| c < 0.05) {
            return Ok(false);
        }
    }
    Ok(true)
}

/// Whether the arm's non-adjacent links at `q` are further apart than the
/// scenario's safety band.
fn self_clear(scenario: &Scenario, q: &[f64]) -> Result<bool, FieldError> {
    let mut s = scenario.clone();
    s.obstacles.clear();
    let band = s.controller.safety_band;
    let c = clearance_at(&s, q)?;
    Ok(c > band)
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
