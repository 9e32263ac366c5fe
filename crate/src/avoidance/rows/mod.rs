//! Rows: what each constraint and each task contributes to the
//! controllers, one type per kind (the limits and tasks of mink, the
//! velocity dampers of NEO).
//!
//! **A limit** ([`Limit`]) bounds the joint velocity `q̇` with one-sided
//! rows `aₖᵀ q̇ ≤ bₖ` and may narrow the velocity box `lo ≤ q̇ ≤ hi`; its
//! one method, [`Limit::compute_qp_inequalities`], writes them into an
//! [`Inequalities`] stack. The limits of the `constraints` avoidance:
//!
//! | limit | file | rows |
//! |---|---|---|
//! | [`JointBox`] | `joint_box.rs` | the box: speed limits, braking caps of the position limits (acceleration), the stop time |
//! | [`ProtectiveBound`] | `protective.rs` | one row per guarded skeleton–obstacle pair at its protective bound (braking, slowdown, escape) |
//! | [`SelfPairs`] | `self_pairs.rs` | one row per guarded pair of two points of the arm, at its protective bound |
//! | [`VelocityDamper`] | `damper.rs` | the same pairs' rows at their damper bound; *soft* |
//!
//! Rows of the same pair are one QP row with the smaller bound (pair `k`
//! of [`Inequalities::push_pair`]), and the pairs' rows are stacked in the
//! order of the pairs (the guards' order), whichever limit made them. A *soft* limit ([`Limit::soft`]) is
//! dropped when the stack cannot be met as a whole; the hard ones are then
//! solved alone (and if those fail the world stops the arm).
//!
//! **A task** ([`Task`]) asks for a velocity of some point or frame:
//! rows `J q̇ ≈ v` that the QP minimises `½ ‖J q̇ − v‖²` over, or that the
//! paper's controllers resolve by priority. [`Task::compute_rows`] appends
//! its rows to a [`TaskRows`] stack. The tasks:
//!
//! | task | file | rows |
//! |---|---|---|
//! | [`EndEffectorTask`] | `end_effector.rs` | a chain's end effector: goal, trajectory or hold (3 position rows, 3 more with orientation) |
//! | [`PointTask`] | `point.rs` | a pinned control point at DH values that change in time (eq. 4's moving-point terms) |
//! | [`RepulsionTask`] | `repulsion.rs` | the paper's repulsion rows of the `repulsion` avoidance, one per active point |
//!
//! The goal, the trajectory and the hold differ only in their reference
//! ([`TaskReference`], made by the scenario's task); their rows are those
//! of the end effector.
//!
//! **Stacking.** Rows are stacked in the order of registration, and within
//! a limit or task in the order of its points or chains; the pairs' rows
//! follow the other rows, in pair order. The solver sees exactly that
//! order. [`stack_tasks`] stacks the scenario's task
//! references; the QP's assembler ([`super::qp::assemble`]) turns the task
//! rows into the objective and stacks the limits registered by
//! [`super::constraints::constrained_velocity`].
//!
//! **Adding one.** A new limit is a new file here with a type that
//! implements [`Limit`] (its rows from the [`LimitContext`], its box if
//! any; `soft` if it may give way), declared below (`mod` and `pub use`),
//! and registered by one entry in the list of
//! [`super::constraints::constrained_velocity`]; nothing else changes —
//! the assembler, the solver and the world do not know the kinds. A new
//! task likewise implements [`Task`] and is stacked where its reference is
//! made ([`stack_tasks`]).

use super::{ControllerConfig, TaskReference};
use crate::error::FieldError;
use crate::kinematics::{Frames, Robot};
use crate::linalg::Mat;

mod damper;
mod end_effector;
mod joint_box;
mod point;
mod protective;
mod repulsion;
mod self_pairs;

pub use damper::VelocityDamper;
pub use end_effector::EndEffectorTask;
pub(crate) use end_effector::end_effector;
pub use joint_box::JointBox;
pub use point::PointTask;
pub use protective::ProtectiveBound;
pub use repulsion::RepulsionTask;
pub(crate) use repulsion::repulsion_rows;
pub use self_pairs::SelfPairs;

/// What the limits are computed from.
#[derive(Clone, Copy, Debug)]
pub struct LimitContext<'a> {
    /// The robot.
    pub robot: &'a Robot,
    /// Joint positions.
    pub q: &'a [f64],
    /// The time within which the joints must be able to stop (s; `∞` when
    /// nothing closes in): [`super::protect::stop_time`].
    pub stop_time: f64,
}

/// One-sided rows `aₖᵀ q̇ ≤ bₖ` and the velocity box, as the limits stack
/// them for the QP.
#[derive(Clone, Debug, Default)]
pub struct Inequalities<'a> {
    /// The rows `(aₖ, bₖ)` in stacking order.
    pub rows: Vec<(&'a [f64], f64)>,
    /// Lower bounds of `q̇` (empty: unbounded).
    pub lo: Vec<f64>,
    /// Upper bounds of `q̇` (empty: unbounded).
    pub hi: Vec<f64>,
    /// The row of each pair, by pair index (stacked after the others).
    pairs: Vec<Option<(&'a [f64], f64)>>,
}

impl<'a> Inequalities<'a> {
    /// Stacks every limit of `limits` that `keep` accepts, in order.
    #[must_use]
    pub fn stack(
        limits: &[&'a dyn Limit],
        ctx: &LimitContext,
        keep: impl Fn(&dyn Limit) -> bool,
    ) -> Self {
        let mut out = Self::default();
        for limit in limits.iter().filter(|l| keep(**l)) {
            limit.compute_qp_inequalities(ctx, &mut out);
        }
        let pairs = std::mem::take(&mut out.pairs);
        out.rows.extend(pairs.into_iter().flatten());
        if out.lo.is_empty() {
            let n = ctx.robot.dof();
            out.lo = vec![f64::NEG_INFINITY; n];
            out.hi = vec![f64::INFINITY; n];
        }
        out
    }

    /// Adds the row `row · q̇ ≤ bound`.
    pub fn push(&mut self, row: &'a [f64], bound: f64) {
        self.rows.push((row, bound));
    }

    /// Adds the row of pair `pair` (a guard's index), or, when a limit
    /// stacked that pair's row already, lowers its bound to `bound` if
    /// smaller (`b.min(bound)`).
    pub fn push_pair(&mut self, pair: usize, row: &'a [f64], bound: f64) {
        if self.pairs.len() <= pair {
            self.pairs.resize(pair + 1, None);
        }
        match &mut self.pairs[pair] {
            Some((_, b)) => *b = b.min(bound),
            slot @ None => *slot = Some((row, bound)),
        }
    }

    /// Narrows the box to `lo..hi` (the first box is taken as it is).
    pub fn narrow_box(&mut self, lo: Vec<f64>, hi: Vec<f64>) {
        if self.lo.is_empty() {
            (self.lo, self.hi) = (lo, hi);
            return;
        }
        for (a, b) in self.lo.iter_mut().zip(lo) {
            *a = a.max(b);
        }
        for (a, b) in self.hi.iter_mut().zip(hi) {
            *a = a.min(b);
        }
    }
}

/// A limit: one-sided rows on the joint velocity (see the module docs).
pub trait Limit {
    /// Adds this limit's rows (and its box) to `out`.
    fn compute_qp_inequalities<'a>(&'a self, ctx: &LimitContext, out: &mut Inequalities<'a>);

    /// Whether this limit gives way when the stack cannot be met as a
    /// whole (default: no).
    fn soft(&self) -> bool {
        false
    }
}

/// What the tasks are computed from.
#[derive(Clone, Copy, Debug)]
pub struct TaskContext<'a> {
    /// The robot.
    pub robot: &'a Robot,
    /// Its frames now.
    pub frames: &'a Frames,
    /// The controller.
    pub config: &'a ControllerConfig,
    /// Gain `K` (1/s) on the position error of the tasks' right-hand side
    /// (`ṗ_d + K (p_d − p)`; 0 for the rows alone).
    pub gain: f64,
    /// A joint-space reference (the `joints` task), if any.
    pub joints: Option<JointTarget<'a>>,
}

/// A joint-space reference: one row per joint, `q̇ ≈ q̇_ref + K (q_ref − q)`
/// (the scenario's `joints` task).
#[derive(Clone, Copy, Debug)]
pub struct JointTarget<'a> {
    /// `q_ref`.
    pub q: &'a [f64],
    /// `q̇_ref`.
    pub qdot: &'a [f64],
    /// The joints now.
    pub now: &'a [f64],
}

/// Task rows `J q̇ ≈ v`, stacked: `J` row-major with one column per joint.
#[derive(Clone, Debug, PartialEq)]
pub struct TaskRows {
    /// `J`.
    pub jac: Mat,
    /// `v`, one value per row.
    pub rhs: Vec<f64>,
}

impl TaskRows {
    /// No rows yet, for `n` joints.
    #[must_use]
    pub fn new(n: usize) -> Self {
        Self {
            jac: Mat::zeros(0, n),
            rhs: Vec::new(),
        }
    }

    /// Adds `m` rows of zeros and returns the index of the first.
    pub fn add_rows(&mut self, m: usize) -> usize {
        let first = self.jac.rows;
        self.jac.rows += m;
        self.jac.data.resize(self.jac.rows * self.jac.cols, 0.0);
        first
    }
}

/// A task: rows `J q̇ ≈ v` (see the module docs).
pub trait Task {
    /// Appends this task's rows and right-hand side to `out`.
    ///
    /// # Errors
    /// Inconsistent inputs (a chain that does not exist).
    fn compute_rows(&self, ctx: &TaskContext, out: &mut TaskRows) -> Result<(), FieldError>;
}

/// The rows of every task reference, stacked in order: an end effector
/// ([`EndEffectorTask`]) or a control point ([`PointTask`]).
///
/// # Errors
/// A reference on a chain that does not exist.
pub fn stack_tasks(ctx: &TaskContext, tasks: &[TaskReference]) -> Result<TaskRows, FieldError> {
    let mut out = TaskRows::new(ctx.robot.dof());
    let n = ctx.robot.dof();
    let rows = tasks.iter().map(TaskReference::rows).sum::<usize>() + ctx.joints.map_or(0, |_| n);
    out.jac.data.reserve(rows * n);
    out.rhs.reserve(rows);
    if let Some(j) = ctx.joints {
        let r0 = out.add_rows(n);
        for (k, ((q, v), now)) in j.q.iter().zip(j.qdot).zip(j.now).take(n).enumerate() {
            out.jac.set(r0 + k, k, 1.0);
            out.rhs.push(v + ctx.gain * (q - now));
        }
        out.rhs.resize(r0 + n, 0.0);
    }
    for reference in tasks {
        match reference.point {
            Some((point, motion)) => PointTask {
                reference,
                point,
                motion,
            }
            .compute_rows(ctx, &mut out)?,
            None => EndEffectorTask { reference }.compute_rows(ctx, &mut out)?,
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pair_rows_come_in_pair_order_with_the_smaller_bound() {
        let (a, b, c) = ([1.0, 0.0], [0.0, 1.0], [1.0, 1.0]);
        let mut out = Inequalities::default();
        out.push_pair(2, &c, 0.3);
        out.push_pair(0, &a, 0.5);
        out.push(&b, 9.0);
        out.push_pair(0, &a, 0.2);
        out.push_pair(2, &c, f64::INFINITY);
        let pairs = std::mem::take(&mut out.pairs);
        out.rows.extend(pairs.into_iter().flatten());
        let bounds: Vec<f64> = out.rows.iter().map(|r| r.1).collect();
        assert_eq!(bounds, vec![9.0, 0.2, 0.3]);
        assert_eq!(out.rows[1].0, &a[..]);
    }
}
