//! Torque mode on the robot's own rigid-body dynamics (paper §II: the
//! repulsion forces "used to compute avoidance torques at the manipulator
//! joints via the Jacobian transpose").
//!
//! * **The forces.** Each task pulls its point with a Cartesian spring and
//!   damper, `f = K_p (x_d − x) + K_d (ẋ_d − ẋ)`; each active control point
//!   is pushed away with `fᵢ = k_f hᵢ v_rep(dᵢ)` along `−nᵢ` (the repulsion
//!   speed as a force, faded in over the activation band); the joints are
//!   damped, `−D q̇`. Their joint torques are
//!   `τ_c = Σ J_taskᵀ f + Σ J_θ,iᵀ fᵢ − D q̇`.
//! * **Gravity and Coriolis compensated.** The drives apply
//!   `τ = τ_c + C(q, q̇) q̇ + g(q)`, each joint within `±maxTorque`, and the
//!   arm answers with its own inertia: `q̈ = M(q)⁻¹ (τ − C q̇ − g)` — so the
//!   forces act on the true `M(q)`, coupled, not on a diagonal model.
//! * **Computed-torque tracking.** `q̇ + q̈ dt` is the velocity the forces
//!   ask for. Like every mode's request it then passes the protective layer
//!   and the joint limiter (velocity, acceleration, jerk and torque limits);
//!   the torque the drives finally apply is the computed torque that tracks
//!   that constrained command, `τ = M(q) q̈ + C(q, q̇) q̇ + g(q)` with the
//!   limiter's `q̈` (the world's torque readout and audit).

use glam::DVec3;

use super::rows::end_effector;
use super::{ActivePoint, ControllerConfig, TaskReference, activation};
use crate::dynamics::{Dynamics, MassFactor, Workspace};
use crate::error::FieldError;
use crate::kinematics::Frames;

/// What the torque controller reads in one step.
#[derive(Clone, Copy, Debug)]
pub struct TorqueInput<'a> {
    /// The robot's dynamics (its robot is the controlled one).
    pub dynamics: &'a Dynamics,
    /// Frames at `q`.
    pub frames: &'a Frames,
    /// Joint positions.
    pub q: &'a [f64],
    /// Joint velocities.
    pub qdot: &'a [f64],
    /// Active control points.
    pub points: &'a [ActivePoint],
    /// Task references.
    pub tasks: &'a [TaskReference],
    /// The controller.
    pub config: &'a ControllerConfig,
    /// Step (s).
    pub dt: f64,
}

/// The buffers of the torque controller, kept from step to step.
#[derive(Clone, Debug, Default)]
pub struct TorqueScratch {
    /// The dynamics' workspace.
    pub workspace: Workspace,
    /// `M(q)` factored.
    pub factor: MassFactor,
    bias: Vec<f64>,
    qddot: Vec<f64>,
}

impl TorqueScratch {
    /// Buffers sized for `dynamics`.
    #[must_use]
    pub fn new(dynamics: &Dynamics) -> Self {
        Self {
            workspace: dynamics.workspace(),
            ..Self::default()
        }
    }
}

/// `τ_c = Σ J_taskᵀ f_task + Σ hᵢ J_θ,iᵀ fᵢ − D q̇` (see the module docs).
///
/// # Errors
/// A task on a chain that does not exist.
pub fn force_torques(input: &TorqueInput) -> Result<Vec<f64>, FieldError> {
    let (robot, frames, qdot) = (input.dynamics.robot(), input.frames, input.qdot);
    let config = input.config;
    let g = &config.torque;
    let n = robot.dof();
    let mut tau: Vec<f64> = qdot.iter().map(|v| -g.joint_damping * v).collect();
    let mut add = |cols: &[DVec3], force: DVec3| {
        for (t, col) in tau.iter_mut().zip(cols) {
            *t += col.dot(force);
        }
    };
    for task in input.tasks {
        let (cols, x) = if let Some((dh, _)) = task.point {
            let pj = dh.jacobians(robot, frames);
            (pj.j_theta, pj.position)
        } else {
            let (full, x, _) = end_effector(robot, frames, task.chain)?;
            let cols = (0..n)
                .map(|c| DVec3::new(full.get(0, c), full.get(1, c), full.get(2, c)))
                .collect();
            (cols, x)
        };
        let xdot = cols
            .iter()
            .zip(qdot)
            .fold(DVec3::ZERO, |s, (c, v)| s + *c * *v);
        let f = g.stiffness * (task.position - x) + g.damping * (task.velocity - xdot);
        add(&cols, f);
    }
    for p in input.points {
        let h = activation(p.distance, config);
        let force = g.force_gain * h * p.repulsion(config);
        add(&p.dh.jacobians(robot, frames).j_theta, force);
    }
    Ok(tau)
}

/// Torque mode (see the module docs): returns the requested joint
/// velocities `q̇ + M⁻¹ (τ − C q̇ − g) dt` and the drive torques `τ`
/// (gravity and Coriolis compensation included, each within
/// `±maxTorque`).
///
/// # Errors
/// A task on a chain that does not exist; `q`/`q̇` of the wrong length; a
/// mass matrix that is not positive definite.
pub fn torque_control(
    input: &TorqueInput,
    scratch: &mut TorqueScratch,
) -> Result<(Vec<f64>, Vec<f64>), FieldError> {
    let dynamics = input.dynamics;
    let n = dynamics.dof();
    let mut tau = force_torques(input)?;
    scratch.bias.resize(n, 0.0);
    scratch.qddot.resize(n, 0.0);
    dynamics.nonlinear_effects(
        &mut scratch.workspace,
        input.q,
        input.qdot,
        &mut scratch.bias,
    )?;
    scratch
        .factor
        .update(dynamics, &mut scratch.workspace, input.q)?;
    for ((t, b), j) in tau
        .iter_mut()
        .zip(&scratch.bias)
        .zip(&dynamics.robot().joints)
    {
        let total = *t + b;
        *t = if total.is_finite() {
            total.clamp(-j.max_torque, j.max_torque)
        } else {
            *b
        };
    }
    // What accelerates the arm: the drives less what gravity and the
    // velocity terms take.
    let net: Vec<f64> = tau.iter().zip(&scratch.bias).map(|(t, b)| t - b).collect();
    scratch.factor.solve(&net, &mut scratch.qddot);
    let out = input
        .qdot
        .iter()
        .zip(&scratch.qddot)
        .map(|(v, a)| v + a * input.dt)
        .collect();
    Ok((out, tau))
}
