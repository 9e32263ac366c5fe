//! The `constraints` avoidance (the default of velocity mode): the tasks
//! as the objective of one small QP, every pair within the influence
//! distance as a one-sided constraint.
//!
//! `minimise ½ ‖J q̇ − v‖² + ½ μ q̇ᵀ W q̇`
//! `subject to  nₖᵀ Jₖ q̇ ≤ min(bₖ, sₖ)  for every pair k,  lo ≤ q̇ ≤ hi`
//!
//! * `J`, `v`: every task's rows stacked (end-effector pose or point), with
//!   `v = ṗ_d + K (p_d − p)` (and the moving-point terms of a point task).
//!   The task is the objective, not a constraint: it is its own slack, so
//!   the problem is infeasible only when the constraints contradict each
//!   other or the velocity box.
//! * `μ W`: eq. 4's joint weights times [`REGULARISATION`] plus, near a
//!   singularity, the variable damping of the paper's DLS inverse. With
//!   `μ → 0` the unconstrained optimum is the weighted pseudoinverse
//!   solution `J_W^† v`; `μ` is the damping near singularities and picks the
//!   smallest motion in the task's null space — with nothing to do, the arm
//!   rests.
//! * `bₖ`: the protective bound of the pair ([`super::protect`]): the
//!   approach speed from which the arm can still stop before the safety
//!   distance.
//! * `sₖ`: the pair's velocity damper ([`super::protect::Damper`]): at the
//!   influence distance the arm may approach at `maxRepulsionSpeed`, at the
//!   safety band at zero, below it it is pushed away; an obstacle's own
//!   approach speed is subtracted, so a moving obstacle is evaded.
//!
//! **Why one QP and not the paper's hierarchy.** An equality row per
//! control point ("recede at the repulsion speed") is a hard priority: the
//! arm must recede from anything within the influence distance, its own
//! links at fixed distances included, and the task gets what is left — so
//! it backs away from goals beside obstacles and never rests. A one-sided
//! row costs nothing while it is slack, so the task keeps every direction
//! the obstacles leave open (sliding round an obstacle is such a
//! direction), and only the rows that bind shape the motion. Velocity
//! dampers in a QP with a slack task are the design of NEO (Haviland &
//! Corke 2021); here the dampers are written on the skeleton's pairs and
//! sit beside the protective bounds, which keep the guarantee that contact
//! can only begin with the arm at rest. A strict hierarchy with inequality
//! levels (Kanoun et al.) would need one QP per level; one QP measured
//! 1–3 µs per step on the Panda.
//!
//! When the dampers and the protective bounds cannot all be met, the
//! dampers are dropped and the protective bounds alone are solved for; if
//! those cannot be met either, the world stops the arm (`unavoidable`).
//!
//! **Where the rows come from.** Each term is a type of [`super::rows`]:
//! the tasks' rows `J`, `v` ([`super::rows::EndEffectorTask`],
//! [`super::rows::PointTask`]), the box ([`super::rows::JointBox`]), the
//! protective bounds `bₖ` ([`super::rows::ProtectiveBound`], and
//! [`super::rows::SelfPairs`] for two points of the arm) and the dampers
//! `sₖ` ([`super::rows::VelocityDamper`], soft: the ones dropped). They are
//! registered in [`constrained_velocity`] and stacked by the assembler
//! [`super::qp::assemble`].
//!
//! Control points keep their roles — the monitor's time to collision,
//! chattering and transition checks, and the `repulsion` mode — but do not
//! thin out the constraints: one-sided rows do not compete for the joints
//! the way equality rows do, so every pair keeps its own.

use super::protect::Guard;
use super::qp::Workspace;
use super::qp::assemble::{Stack, solve_stacked};
use super::rows::{
    JointBox, JointTarget, Limit, LimitContext, ProtectiveBound, SelfPairs, TaskContext,
    VelocityDamper, stack_tasks,
};
use super::{ControllerConfig, TaskReference};
use crate::error::FieldError;
use crate::kinematics::{Frames, Robot};

pub use super::qp::assemble::{INFEASIBLE_TOLERANCE, Outcome, REGULARISATION};

/// What the `constraints` avoidance reads in one step.
#[derive(Clone, Copy, Debug)]
pub struct ConstraintsInput<'a> {
    /// The robot.
    pub robot: &'a Robot,
    /// Its frames now.
    pub frames: &'a Frames,
    /// Joint positions.
    pub q: &'a [f64],
    /// The stop time of the obstacles closing in (s;
    /// [`super::protect::stop_time`]).
    pub stop_time: f64,
    /// This step's task references.
    pub tasks: &'a [TaskReference],
    /// This step's joint-space reference (the `joints` task), if any.
    pub joints: Option<JointTarget<'a>>,
    /// This step's guards ([`super::protect::prepare`]).
    pub guards: &'a [Guard],
    /// The controller.
    pub config: &'a ControllerConfig,
}

/// The `constraints` avoidance: the joint velocity that best serves the
/// tasks under every limit — the joint box, each guard's protective bound
/// (obstacle and self pairs) and its damper (soft) — into `out` (see the module docs). The list
/// below is the registration of the limits: a new limit is one more entry.
///
/// # Errors
/// Only on inconsistent inputs (a task on a chain that does not exist).
pub fn constrained_velocity(
    input: &ConstraintsInput,
    ws: &mut Workspace,
    out: &mut Vec<f64>,
) -> Result<Outcome, FieldError> {
    let config = input.config;
    let task_context = TaskContext {
        robot: input.robot,
        frames: input.frames,
        config,
        gain: config.task_gain,
        joints: input.joints,
    };
    let tasks = stack_tasks(&task_context, input.tasks)?;
    let guards = input.guards;
    let limits: [&dyn Limit; 4] = [
        &JointBox,
        &ProtectiveBound { guards },
        &SelfPairs { guards },
        &VelocityDamper { guards },
    ];
    let stack = Stack {
        tasks: &tasks,
        limits: &limits,
        context: LimitContext {
            robot: input.robot,
            q: input.q,
            stop_time: input.stop_time,
        },
        config,
    };
    Ok(solve_stacked(&stack, ws, out))
}
