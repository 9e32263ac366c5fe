//! A chain's end effector as a task (the goal, the trajectory and the
//! hold): the position rows of its Jacobian with `ṗ_d + K (p_d − p)`, and
//! with an orientation the rotation rows with `K e_o`
//! ([`crate::kinematics::ik::orientation_error`]).

use glam::{DQuat, DVec3};

use super::{Task, TaskContext, TaskRows};
use crate::avoidance::TaskReference;
use crate::error::FieldError;
use crate::kinematics::ik::{end_effector_jacobian, orientation_error};
use crate::kinematics::{Frames, Robot};
use crate::linalg::Mat;

/// The end effector of `reference.chain` following `reference`.
#[derive(Clone, Copy, Debug)]
pub struct EndEffectorTask<'r> {
    /// The reference now.
    pub reference: &'r TaskReference,
}

impl Task for EndEffectorTask<'_> {
    fn compute_rows(&self, ctx: &TaskContext, out: &mut TaskRows) -> Result<(), FieldError> {
        let task = self.reference;
        let n = ctx.robot.dof();
        let gain = ctx.gain;
        let (full, x, rot) = end_effector(ctx.robot, ctx.frames, task.chain)?;
        let m = task.rows();
        let r0 = out.add_rows(m);
        for r in 0..m {
            for c in 0..n {
                out.jac.set(r0 + r, c, full.get(r, c));
            }
        }
        out.rhs
            .extend((task.velocity + gain * (task.position - x)).to_array());
        if let Some(o) = task.orientation {
            out.rhs
                .extend((gain * orientation_error(o, rot)).to_array());
        }
        Ok(())
    }
}

/// The full Jacobian, the position and the orientation of `chain`'s end
/// effector.
///
/// # Errors
/// A chain that does not exist.
pub(crate) fn end_effector(
    robot: &Robot,
    frames: &Frames,
    chain: usize,
) -> Result<(Mat, DVec3, DQuat), FieldError> {
    let full = end_effector_jacobian(robot, frames, chain)?;
    let ee = frames
        .end_effectors
        .get(chain)
        .copied()
        .unwrap_or(glam::DAffine3::IDENTITY);
    Ok((full, ee.translation, DQuat::from_mat3(&ee.matrix3)))
}
