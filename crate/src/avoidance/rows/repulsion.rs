//! The paper's repulsion rows as a task (the `repulsion` avoidance of
//! velocity mode): for each of the `n − 1` closest active control points,
//! the arm's own velocity at the point away from its obstacle,
//! `−nᵀ J_θ q̇`, asked to be `h v_rep + (1 − h) (row · q̇₀)`: the repulsion
//! speed ([`crate::avoidance::repulsion_speed`]) faded in by the row's
//! activation `h` ([`crate::avoidance::activation`]) from what the tasks
//! alone command, `q̇₀` (see [`crate::avoidance::control`]).

use super::{Task, TaskContext, TaskRows};
use crate::avoidance::{ActivePoint, ControllerConfig, activation, repulsion_speed};
use crate::error::FieldError;
use crate::kinematics::{Frames, Robot};
use crate::linalg::Mat;

/// The repulsion rows of `points`, faded from `alone`.
#[derive(Clone, Copy, Debug)]
pub struct RepulsionTask<'p> {
    /// The active control points.
    pub points: &'p [ActivePoint],
    /// The joint velocities the tasks alone command (`q̇₀`).
    pub alone: &'p [f64],
}

impl Task for RepulsionTask<'_> {
    fn compute_rows(&self, ctx: &TaskContext, out: &mut TaskRows) -> Result<(), FieldError> {
        let (points, config) = (self.points, ctx.config);
        let (avoid, which) = repulsion_rows(ctx.robot, ctx.frames, points, config);
        let now = avoid.mul_vec(self.alone);
        let r0 = out.add_rows(avoid.rows);
        let n = avoid.cols;
        out.jac.data[r0 * n..].copy_from_slice(&avoid.data);
        out.rhs.extend(
            which.iter().zip(&now).map(|(&(k, h), v0)| {
                h * repulsion_speed(points[k].distance, config) + (1.0 - h) * v0
            }),
        );
        Ok(())
    }
}

/// The repulsion rows `−nᵢᵀ J_θ,i` of the `n − 1` closest active points
/// (those with a positive activation), with each point's index and
/// activation: the rows of [`RepulsionTask`] and of the `clik2` mode's
/// avoidance.
pub(crate) fn repulsion_rows(
    robot: &Robot,
    frames: &Frames,
    points: &[ActivePoint],
    config: &ControllerConfig,
) -> (Mat, Vec<(usize, f64)>) {
    let n = robot.dof();
    let mut order: Vec<usize> = (0..points.len())
        .filter(|&k| activation(points[k].distance, config) > 0.0)
        .collect();
    order.sort_by(|&a, &b| {
        points[a]
            .distance
            .total_cmp(&points[b].distance)
            .then(a.cmp(&b))
    });
    order.truncate(n.saturating_sub(1).max(1));
    let mut jac = Mat::zeros(order.len(), n);
    let mut which = Vec::with_capacity(order.len());
    for (row, &k) in order.iter().enumerate() {
        let p = &points[k];
        let pj = p.dh.jacobians(robot, frames);
        let dir = -p.normal;
        for (c, col) in pj.j_theta.iter().enumerate() {
            jac.set(row, c, dir.dot(*col));
        }
        which.push((k, activation(p.distance, config)));
    }
    (jac, which)
}
