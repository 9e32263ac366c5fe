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
//! * `μ W`: eq. 4's joint weights times [`REGULARISATION`]. With
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
//! Control points keep their roles — the monitor's time to collision,
//! chattering and transition checks, and the `repulsion` mode — but do not
//! thin out the constraints: one-sided rows do not compete for the joints
//! the way equality rows do, so every pair keeps its own.

use super::control::task_level;
use super::protect::Guard;
use super::qp::{self, Solution, Workspace};
use super::{ControllerConfig, TaskReference};
use crate::error::FieldError;
use crate::kinematics::{Frames, Robot};
use crate::linalg::Mat;

/// Violation of a protective bound (m/s) beyond which the arm is judged
/// unable to keep a pair safe: far above the solver's accuracy, far below
/// any speed that matters.
pub const INFEASIBLE_TOLERANCE: f64 = 1e-3;

/// `μ`, the weight of `q̇ᵀ W q̇` against the task (s²·m²/rad²): small
/// enough that a task away from singularities is tracked to within 0.1 %,
/// large enough to keep `H` well conditioned for the solver at a
/// singularity.
pub const REGULARISATION: f64 = 1e-4;

/// What [`constrained_velocity`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Outcome {
    /// Whether the dampers had to be dropped (dampers, protective bounds
    /// and the box could not all be met).
    pub relaxed: bool,
    /// The last solve.
    pub solution: Solution,
}

/// The Hessian `JᵀJ + μW` and the linear term `Jᵀv` of the tasks.
fn objective(jac: &Mat, rhs: &[f64], config: &ControllerConfig) -> (Mat, Vec<f64>) {
    let n = jac.cols;
    let mut h = Mat::zeros(n, n);
    let mut f = vec![0.0; n];
    for r in 0..jac.rows {
        let row = &jac.data[r * n..(r + 1) * n];
        for i in 0..n {
            if row[i] == 0.0 {
                continue;
            }
            f[i] += row[i] * rhs[r];
            for j in 0..n {
                h.data[i * n + j] += row[i] * row[j];
            }
        }
    }
    let mu = REGULARISATION;
    let weights = config.joint_weights.as_deref().unwrap_or(&[]);
    for i in 0..n {
        h.data[i * n + i] += mu * weights.get(i).copied().unwrap_or(1.0);
    }
    (h, f)
}

/// The `constraints` avoidance: the joint velocity that best serves
/// `tasks` under every guard (`min(bound, soft)`) and the velocity box
/// `lo..hi`, into `out` (see the module docs).
///
/// # Errors
/// Only on inconsistent inputs (a task on a chain that does not exist).
#[allow(clippy::too_many_arguments)]
pub fn constrained_velocity(
    robot: &Robot,
    frames: &Frames,
    tasks: &[TaskReference],
    guards: &[Guard],
    lo: &[f64],
    hi: &[f64],
    config: &ControllerConfig,
    ws: &mut Workspace,
    out: &mut Vec<f64>,
) -> Result<Outcome, FieldError> {
    let level = task_level(robot, frames, tasks, config, config.task_gain)?;
    let (h, mut f) = objective(&level.jac, &level.rhs, config);
    // Speed scaling: a task velocity the joints cannot follow is scaled
    // down as a whole (its direction and eq. 4's distribution over the
    // joints kept) instead of being bent by the velocity box.
    if qp::unconstrained(&h, &f, ws, out) {
        let scale = out
            .iter()
            .zip(lo.iter().zip(hi))
            .map(|(x, (l, u))| {
                if *x > *u && *x > 0.0 {
                    (u / x).max(0.0)
                } else if *x < *l && *x < 0.0 {
                    (l / x).max(0.0)
                } else {
                    1.0
                }
            })
            .fold(1.0, f64::min);
        f.iter_mut().for_each(|v| *v *= scale);
    }
    let rows: Vec<(&[f64], f64)> = guards
        .iter()
        .map(|g| (g.row.as_slice(), g.bound.min(g.soft)))
        .collect();
    let solution = qp::solve(&h, &f, &rows, lo, hi, INFEASIBLE_TOLERANCE, ws, out);
    if solution.worst.is_none() {
        return Ok(Outcome {
            relaxed: false,
            solution,
        });
    }
    let rows: Vec<(&[f64], f64)> = guards.iter().map(|g| (g.row.as_slice(), g.bound)).collect();
    let solution = qp::solve(&h, &f, &rows, lo, hi, INFEASIBLE_TOLERANCE, ws, out);
    Ok(Outcome {
        relaxed: true,
        solution,
    })
}
