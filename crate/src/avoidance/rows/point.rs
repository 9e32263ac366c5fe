//! A control point at DH values that change in time as a task (a pinned
//! point holding or following a Cartesian reference): the rows of `J_θ`
//! with `ṗ_d + K (p_d − p) − J_a ȧ − J_d ḋ`, eq. 4's moving-point terms
//! (left out with `movingPointTerms: false`).

use glam::DVec3;

use super::{Task, TaskContext, TaskRows};
use crate::avoidance::TaskReference;
use crate::control_point::{DhPoint, PointMotion};
use crate::error::FieldError;

/// The point `point`, sliding at `motion`, following `reference`.
#[derive(Clone, Copy, Debug)]
pub struct PointTask<'r> {
    /// The reference now (its position and velocity).
    pub reference: &'r TaskReference,
    /// Where the point is on the arm.
    pub point: DhPoint,
    /// Rates of its DH values.
    pub motion: PointMotion,
}

impl Task for PointTask<'_> {
    fn compute_rows(&self, ctx: &TaskContext, out: &mut TaskRows) -> Result<(), FieldError> {
        let (task, dh, motion) = (self.reference, self.point, self.motion);
        let pj = dh.jacobians(ctx.robot, ctx.frames);
        let r0 = out.add_rows(3);
        for (c, col) in pj.j_theta.iter().enumerate() {
            for (k, v) in col.to_array().iter().enumerate() {
                out.jac.set(r0 + k, c, *v);
            }
        }
        let i = dh.link - 1;
        let sliding = if ctx.config.moving_point_terms {
            pj.j_a[i] * motion.a_rate + pj.j_d[i] * motion.d_rate
        } else {
            DVec3::ZERO
        };
        let v = task.velocity + ctx.gain * (task.position - pj.position) - sliding;
        out.rhs.extend(v.to_array());
        Ok(())
    }
}
