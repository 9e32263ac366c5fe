//! NEO (Haviland & Corke, "NEO: A Novel Expeditious Optimisation
//! Algorithm for Reactive Motion Control of Manipulators", RA-L 2021) as
//! an in-library baseline: `controller.avoidance: "neo"` in velocity mode.
//!
//! Its published quadratic programme, over the joint velocities `q̇` and a
//! slack `δ` on the end-effector task:
//!
//! `minimise ½ λ_q ‖q̇‖² + ½ (λ_δ / e) ‖δ‖² − λ_m J_mᵀ q̇`
//! `subject to  J q̇ + δ = ν,`
//! `            nₖᵀ Jₖ q̇ ≤ ξ (dₖ − d_s) / (d_i − d_s) − vₖ   (every pair within d_i),`
//! `            joint-limit dampers,  |q̇ᵢ| ≤ q̇ᵢ,max,  |δ| ≤ δ_max`
//!
//! * `ν = K e_task`: a proportional spatial velocity towards the goal
//!   (position error and rotation error, gain `taskGain`, NEO's
//!   `p_servo`); `e = ‖ν‖₁ / K`, the summed absolute pose error in metres
//!   plus radians, weights the slack: far from the goal the task gives way
//!   to the constraints, near it the slack vanishes.
//! * `J_m`: the gradient of the manipulability `√det(J Jᵀ)`
//!   ([`manipulability`]), weighted by `manipulabilityGain`.
//! * Collision dampers ([`collision_dampers`]): one row per
//!   skeleton–obstacle pair within `d_i` at its witness (the same
//!   skeleton, volumes and scene query as the other controllers; self
//!   pairs are left out, as in NEO), `vₖ` the obstacle's approach speed.
//! * Joint-limit dampers and velocity bounds ([`JointLimitDamper`]).
//!
//! **δ eliminated.** The equality fixes `δ = ν − J q̇`; substituted, the
//! problem is the same programme in `q̇` alone, which is what the crate's
//! solver ([`crate::avoidance::qp`]) takes:
//! `H = λ_q I + (λ_δ/e) JᵀJ`, `f = (λ_δ/e) Jᵀν + λ_m J_m`, and `|δ| ≤ δ_max`
//! becomes two rows per task row ([`SlackBound`]). Its minimiser is that
//! of the published programme (same objective on the feasible set).
//!
//! **Infeasible.** When the rows contradict each other (two obstacles
//! squeezing the arm, a damper asking for a retreat beyond the velocity
//! bounds) NEO's solver returns no solution; here the command is then zero.
//!
//! **Its output.** As published, the QP's `q̇` goes straight to the joints
//! (`neo.limiter: false`, the default): no protective layer, no jerk
//! limiter, only the integration (the world's position clamp stays). With
//! `neo.limiter: true` it goes through the same jerk-limited limiter as the
//! other controllers (`world/limit.rs`), still without the protective
//! layer. Either way the world's monitors (chattering, stops) act as for
//! any controller.

use serde::{Deserialize, Serialize};

use super::protect::Guard;
use super::qp::{Problem, Solution, Workspace, solve};
use super::rows::{Inequalities, Limit, LimitContext, TaskContext, VelocityDamper, stack_tasks};
use super::{ControllerConfig, TaskReference};
use crate::error::{FieldError, non_negative, positive};
use crate::kinematics::{Frames, Robot};
use crate::linalg::Mat;

mod manipulability;
mod rows;

pub use manipulability::manipulability;
pub use rows::{DamperContext, JointLimitDamper, SlackBound, collision_dampers, damper_bound};

/// NEO's settings (scenario field `controller.neo`; defaults from the
/// published example).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields, default)]
pub struct NeoConfig {
    /// Influence distance `d_i` of the collision dampers (m, > 0; default
    /// 0.3).
    pub influence_distance: f64,
    /// Stopping distance `d_s` (m, ≥ 0 and < `influenceDistance`; default
    /// 0.05).
    pub stopping_distance: f64,
    /// Damper gain `ξ` (m/s, ≥ 0; default 1).
    pub damper_gain: f64,
    /// Joint-limit damper's influence angle `ρᵢ` (rad or m, > 0; default
    /// 0.9).
    pub joint_influence: f64,
    /// Joint-limit damper's stop angle `ρ_s` (rad or m, ≥ 0 and <
    /// `jointInfluence`; default 0.05).
    pub joint_stop: f64,
    /// Joint-limit damper's gain (rad/s or m/s, ≥ 0; default 1).
    pub joint_gain: f64,
    /// Weight `λ_q` of `‖q̇‖²` (> 0; default 0.01).
    pub velocity_weight: f64,
    /// Weight `λ_δ` of the slack, divided by the pose error `e` (> 0;
    /// default 1).
    pub slack_weight: f64,
    /// Bound `δ_max` of each slack component (m/s or rad/s, > 0; default
    /// 10).
    pub slack_bound: f64,
    /// Weight `λ_m` of the manipulability gradient (≥ 0; default 1).
    pub manipulability_gain: f64,
    /// Gain `K` of `ν = K e_task` (1/s, > 0; default 0.5).
    pub task_gain: f64,
    /// Whether the command goes through the world's jerk-limited limiter
    /// (default false: straight to the joints, as published).
    pub limiter: bool,
}

impl Default for NeoConfig {
    fn default() -> Self {
        Self {
            influence_distance: 0.3,
            stopping_distance: 0.05,
            damper_gain: 1.0,
            joint_influence: 0.9,
            joint_stop: 0.05,
            joint_gain: 1.0,
            velocity_weight: 0.01,
            slack_weight: 1.0,
            slack_bound: 10.0,
            manipulability_gain: 1.0,
            task_gain: 0.5,
            limiter: false,
        }
    }
}

impl NeoConfig {
    /// Checks every value.
    ///
    /// # Errors
    /// The field and the reason, e.g. `neo.influenceDistance: must be > 0`
    /// or `neo.stoppingDistance: must be < neo.influenceDistance (0.3), got 0.4`.
    pub fn validate(&self) -> Result<(), FieldError> {
        positive("neo.influenceDistance", self.influence_distance)?;
        non_negative("neo.stoppingDistance", self.stopping_distance)?;
        below(
            "neo.stoppingDistance",
            self.stopping_distance,
            "neo.influenceDistance",
            self.influence_distance,
        )?;
        non_negative("neo.damperGain", self.damper_gain)?;
        positive("neo.jointInfluence", self.joint_influence)?;
        non_negative("neo.jointStop", self.joint_stop)?;
        below(
            "neo.jointStop",
            self.joint_stop,
            "neo.jointInfluence",
            self.joint_influence,
        )?;
        non_negative("neo.jointGain", self.joint_gain)?;
        positive("neo.velocityWeight", self.velocity_weight)?;
        positive("neo.slackWeight", self.slack_weight)?;
        positive("neo.slackBound", self.slack_bound)?;
        non_negative("neo.manipulabilityGain", self.manipulability_gain)?;
        positive("neo.taskGain", self.task_gain)?;
        Ok(())
    }
}

fn below(field: &str, value: f64, limit_field: &str, limit: f64) -> Result<(), FieldError> {
    if value < limit {
        Ok(())
    } else {
        Err(FieldError::new(
            field,
            format!("must be < {limit_field} ({limit}), got {value}"),
        ))
    }
}

/// The smallest pose error `e` the slack weight is divided by (m + rad):
/// keeps `λ_δ / e` finite at the goal.
pub const MIN_ERROR: f64 = 1e-6;

/// Violation (m/s) beyond which NEO's programme is judged infeasible.
pub const INFEASIBLE_TOLERANCE: f64 = 1e-3;

/// What NEO reads in one step.
#[derive(Clone, Copy, Debug)]
pub struct NeoInput<'a> {
    /// The robot.
    pub robot: &'a Robot,
    /// Its frames now.
    pub frames: &'a Frames,
    /// Joint positions.
    pub q: &'a [f64],
    /// This step's task references.
    pub tasks: &'a [TaskReference],
    /// The collision dampers ([`collision_dampers`]).
    pub dampers: &'a [Guard],
    /// The controller (`neo` holds NEO's settings).
    pub config: &'a ControllerConfig,
}

/// What one solve of NEO did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NeoOutcome {
    /// The solve (a row named in `worst`: infeasible, zero command).
    pub solution: Solution,
    /// The summed absolute pose error `e` (m + rad).
    pub error: f64,
    /// The manipulability now.
    pub manipulability: f64,
}

/// NEO's joint velocity (see the module docs) into `out`; zero when its
/// programme is infeasible.
///
/// # Errors
/// Only on inconsistent inputs (a task on a chain that does not exist).
pub fn neo_velocity(
    input: &NeoInput,
    ws: &mut Workspace,
    out: &mut Vec<f64>,
) -> Result<NeoOutcome, FieldError> {
    let cfg = &input.config.neo;
    let (robot, n) = (input.robot, input.robot.dof());
    let task_context = TaskContext {
        robot,
        frames: input.frames,
        config: input.config,
        gain: cfg.task_gain,
        joints: None,
    };
    let tasks = stack_tasks(&task_context, input.tasks)?;
    let error = tasks.rhs.iter().map(|v| v.abs()).sum::<f64>() / cfg.task_gain;
    let (m, gradient) = if cfg.manipulability_gain > 0.0 {
        manipulability(robot, input.frames, 0)?
    } else {
        (0.0, vec![0.0; n])
    };
    let weight = cfg.slack_weight / error.max(MIN_ERROR);
    let mut h = Mat::zeros(n, n);
    let mut f: Vec<f64> = gradient
        .iter()
        .map(|g| cfg.manipulability_gain * g)
        .collect();
    for (row, v) in tasks.jac.data.chunks_exact(n.max(1)).zip(&tasks.rhs) {
        for i in 0..n {
            f[i] += weight * row[i] * v;
            for j in 0..n {
                h.data[i * n + j] += weight * row[i] * row[j];
            }
        }
    }
    for i in 0..n {
        h.data[i * n + i] += cfg.velocity_weight;
    }
    let joint = JointLimitDamper { config: cfg };
    let slack = SlackBound::new(&tasks, cfg.slack_bound);
    let dampers = VelocityDamper {
        guards: input.dampers,
    };
    let limits: [&dyn Limit; 3] = [&joint, &slack, &dampers];
    let context = LimitContext {
        robot,
        q: input.q,
        stop_time: f64::INFINITY,
    };
    let rows = Inequalities::stack(&limits, &context, |_| true);
    let problem = Problem {
        h: &h,
        f: &f,
        rows: &rows.rows,
        lo: &rows.lo,
        hi: &rows.hi,
    };
    let solution = solve(&problem, INFEASIBLE_TOLERANCE, ws, out);
    if solution.worst.is_some() {
        out.iter_mut().for_each(|v| *v = 0.0);
    }
    Ok(NeoOutcome {
        solution,
        error,
        manipulability: m,
    })
}

#[cfg(test)]
mod tests;
