//! The *control* stage: repulsion and tasks turned into a joint command
//! (velocity, torque or second-order CLIK), before the protective layer and
//! the joint limits.
//!
//! * **Repulsion prescribes material motion.** An avoidance row asks the
//!   arm's own velocity at the control point, `−nᵀ J_θ q̇`, to be the
//!   repulsion speed. A control point travelling along the skeleton changes
//!   *where* the row acts; its own sliding (`J_a ȧ + J_d ḋ`) is not motion of
//!   the arm and does not enter the row — otherwise the arm would chase the
//!   virtual motion of the point (several m/s at 0.1 s per DH value).
//! * **Eq. 4 where it belongs.** The moving-point terms enter where a task
//!   prescribes the trajectory of a moving point: the `point` task
//!   ([`TaskReference::point`]) holds or follows a Cartesian reference with a
//!   control point whose DH values change in time,
//!   `θ̇ = J_θ,W^† (ṗ_d + K (p_d − p) − J_a ȧ − J_d ḋ)`.
//! * **Task priority** with the weighted damped pseudoinverse (eq. 4's `W`,
//!   `controller.jointWeights`): avoidance rows first, then every task (one
//!   per chain, stacked).
//! * **Activation that fades over the whole band.** Scaling a row by its
//!   activation `h` does not fade it: the pseudoinverse restores its full
//!   effect as soon as `h |nᵀJ|` exceeds the damping threshold. Instead each
//!   row asks for `h v_rep + (1 − h) (row · q̇₀)`, where `q̇₀` is what the
//!   tasks alone would command: at `h = 0` the row asks for exactly what the
//!   arm does anyway, at `h = 1` for the repulsion, continuously in between
//!   (the intermediate desired value of Mansard, Khatib & Kheddar, 2009).

use glam::DVec3;

use super::rows::{
    RepulsionTask, Task, TaskContext, TaskRows, end_effector, repulsion_rows, stack_tasks,
};
use super::{ActivePoint, ControllerConfig, TaskReference, repulsion_speed};
use crate::error::FieldError;
use crate::kinematics::ik::orientation_error;
use crate::kinematics::{Frames, Robot};
use crate::linalg::{Mat, dls_inverse};

/// Task-priority resolution: each level `(J, r)` is satisfied in the null
/// space of the ones before (weighted damped least squares); `rest` (if any)
/// is projected in the null space of all of them.
fn prioritized(
    levels: &[(&Mat, &[f64])],
    n: usize,
    config: &ControllerConfig,
    rest: Option<&[f64]>,
) -> Vec<f64> {
    let weights = config.joint_weights.as_deref().unwrap_or(&[]);
    let mut x = vec![0.0; n];
    let mut p = Mat::identity(n);
    for (jac, r) in levels {
        if jac.rows == 0 {
            continue;
        }
        let jp = jac.mul(&p);
        let inv = dls_inverse(&jp, weights, config.dls()).inverse;
        let jx = jac.mul_vec(&x);
        let e: Vec<f64> = r.iter().zip(&jx).map(|(a, b)| a - b).collect();
        let dx = inv.mul_vec(&e);
        for (xi, d) in x.iter_mut().zip(&dx) {
            *xi += d;
        }
        let ij = inv.mul(&jp);
        for k in 0..p.data.len() {
            p.data[k] -= ij.data[k];
        }
    }
    if let Some(z) = rest {
        let pz = p.mul_vec(z);
        for (xi, d) in x.iter_mut().zip(&pz) {
            *xi += d;
        }
    }
    x
}

/// Velocity mode: avoidance rows first (fading, see the module docs), the
/// tasks in their null space. Returns the requested joint velocities, before
/// the protective layer and the joint limits.
///
/// # Errors
/// Only on inconsistent inputs (a chain that does not exist).
pub fn velocity_control(
    robot: &Robot,
    frames: &Frames,
    points: &[ActivePoint],
    tasks: &[TaskReference],
    config: &ControllerConfig,
) -> Result<Vec<f64>, FieldError> {
    let n = robot.dof();
    let ctx = TaskContext {
        robot,
        frames,
        config,
        gain: config.task_gain,
        joints: None,
    };
    let level = stack_tasks(&ctx, tasks)?;
    let alone = prioritized(&[(&level.jac, &level.rhs)], n, config, None);
    let mut avoid = TaskRows::new(n);
    RepulsionTask {
        points,
        alone: &alone,
    }
    .compute_rows(&ctx, &mut avoid)?;
    if avoid.jac.rows == 0 {
        return Ok(alone);
    }
    Ok(prioritized(
        &[(&avoid.jac, &avoid.rhs), (&level.jac, &level.rhs)],
        n,
        config,
        None,
    ))
}

/// The joint positions and velocities of the arm now.
#[derive(Clone, Copy, Debug)]
pub struct JointState<'a> {
    /// Joint positions.
    pub q: &'a [f64],
    /// Joint velocities.
    pub qdot: &'a [f64],
}

/// `J̇ q̇` of the stacked task rows, by a forward difference of the
/// Jacobians along `q̇` (step 1e-6 s).
fn task_bias(
    robot: &Robot,
    q: &[f64],
    qdot: &[f64],
    tasks: &[TaskReference],
    config: &ControllerConfig,
    level: &TaskRows,
) -> Result<Vec<f64>, FieldError> {
    const H: f64 = 1e-6;
    let q2: Vec<f64> = q.iter().zip(qdot).map(|(a, b)| a + H * b).collect();
    let f2 = robot.forward(&q2)?;
    let ctx = TaskContext {
        robot,
        frames: &f2,
        config,
        gain: 0.0,
        joints: None,
    };
    let later = stack_tasks(&ctx, tasks)?;
    let mut out = vec![0.0; level.jac.rows];
    for (r, o) in out.iter_mut().enumerate() {
        for (c, qd) in qdot.iter().enumerate() {
            *o += (later.jac.get(r, c) - level.jac.get(r, c)) / H * qd;
        }
    }
    Ok(out)
}

/// Second-order CLIK: joint accelerations with avoidance first (each row
/// drives the material approach speed at its point towards the repulsion
/// speed, fading as in velocity mode), the tasks in their null space and
/// joint damping in the remaining null space; integrated over `dt`,
/// returns the requested joint velocities.
///
/// `frames` must carry the velocities for `qdot`
/// ([`Robot::forward_with_velocity`]).
///
/// # Errors
/// Frames without velocities.
pub fn clik2_control(
    robot: &Robot,
    frames: &Frames,
    joints: JointState,
    points: &[ActivePoint],
    tasks: &[TaskReference],
    config: &ControllerConfig,
    dt: f64,
) -> Result<Vec<f64>, FieldError> {
    let n = robot.dof();
    let g = config.clik2;
    let JointState { q, qdot } = joints;
    let ctx = TaskContext {
        robot,
        frames,
        config,
        gain: 0.0,
        joints: None,
    };
    let level = stack_tasks(&ctx, tasks)?;
    let v = level.jac.mul_vec(qdot);
    let bias = task_bias(robot, q, qdot, tasks, config, &level)?;
    let mut r_task = Vec::with_capacity(level.rhs.len());
    let mut r0 = 0;
    for task in tasks {
        let x = if let Some((dh, _)) = task.point {
            dh.position(robot, frames)
        } else {
            end_effector(robot, frames, task.chain)?.1
        };
        let xdot = DVec3::new(v[r0], v[r0 + 1], v[r0 + 2]);
        let a = task.acceleration + g.kd * (task.velocity - xdot) + g.kp * (task.position - x);
        r_task.extend(a.to_array());
        if let (Some(o), None) = (task.orientation, task.point) {
            let rot = end_effector(robot, frames, task.chain)?.2;
            let w = DVec3::new(v[r0 + 3], v[r0 + 4], v[r0 + 5]);
            r_task.extend((g.kp * orientation_error(o, rot) - g.kd * w).to_array());
        }
        r0 += task.rows();
    }
    for (r, b) in r_task.iter_mut().zip(&bias) {
        *r -= b;
    }
    let damp: Vec<f64> = qdot.iter().map(|v| -g.kd * v).collect();
    let alone = prioritized(&[(&level.jac, &r_task)], n, config, Some(&damp));
    let (avoid, which) = repulsion_rows(robot, frames, points, config);
    let qdd = if which.is_empty() {
        alone
    } else {
        let now = avoid.mul_vec(&alone);
        let speed = avoid.mul_vec(qdot);
        let r_avoid: Vec<f64> = which
            .iter()
            .zip(now.iter().zip(&speed))
            .map(|(&(k, h), (a0, s))| {
                let v_rep = repulsion_speed(points[k].distance, config);
                h * g.kd * (v_rep - s) + (1.0 - h) * a0
            })
            .collect();
        prioritized(
            &[(&avoid, &r_avoid), (&level.jac, &r_task)],
            n,
            config,
            Some(&damp),
        )
    };
    Ok(qdot.iter().zip(&qdd).map(|(v, a)| v + a * dt).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::avoidance::activation;
    use crate::control_point::DhPoint;
    use crate::control_point::PointMotion;
    use crate::kinematics::presets;

    /// The fade survives the pseudoinverse: with the tasks asking for rest,
    /// the commanded repulsion at the point is `h(d) v(d)` over the whole
    /// band, not the full `v(d)` as soon as `h |nᵀJ|` passes the damping
    /// threshold.
    #[test]
    fn a_row_fades_in_over_the_whole_activation_band() {
        let spec = presets::preset("planar3").unwrap_or_else(|e| unreachable!("{e}"));
        let robot = Robot::from_spec(&spec).unwrap_or_else(|e| unreachable!("{e}"));
        let q = [0.3, 0.9, 0.6];
        let frames = robot.forward(&q).unwrap_or_else(|e| unreachable!("{e}"));
        let dh = DhPoint {
            link: 2,
            d: 0.0,
            a: 0.15,
        };
        let mut config = ControllerConfig {
            repulsion_gain: 0.02,
            ..ControllerConfig::default()
        };
        config.max_repulsion_speed = 10.0;
        let jac = dh.jacobians(&robot, &frames);
        let normal = glam::DVec3::new(0.0, 1.0, 0.0);
        let hold = TaskReference {
            position: frames.end_effector().translation,
            velocity: glam::DVec3::ZERO,
            acceleration: glam::DVec3::ZERO,
            orientation: None,
            chain: 0,
            point: None,
        };
        let rho = config.influence_distance;
        let mut fractions = Vec::new();
        for k in 1..20 {
            let d = rho * (1.0 - config.activation_band * f64::from(k) / 20.0);
            let p = ActivePoint {
                dh,
                motion: PointMotion::default(),
                normal,
                distance: d,
            };
            let qdot = velocity_control(&robot, &frames, &[p], &[hold], &config)
                .unwrap_or_else(|e| unreachable!("{e}"));
            let v: glam::DVec3 = jac.j_theta.iter().zip(&qdot).map(|(c, w)| *c * *w).sum();
            let effect = -normal.dot(v);
            let full = repulsion_speed(d, &config);
            let h = activation(d, &config);
            assert!(
                (effect - h * full).abs() <= 1e-6 * full,
                "d {d}: {effect} vs {}",
                h * full
            );
            fractions.push(effect / full);
        }
        assert!(fractions.windows(2).all(|w| w[1] >= w[0]));
        assert!(fractions[0] < 0.05 && fractions[18] > 0.95);
    }
}
