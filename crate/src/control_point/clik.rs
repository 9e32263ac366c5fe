//! Closed-loop inverse kinematics (CLIK) of a control point that may itself
//! move along its link (paper eq. 4; Caccavale, Chiaverini & Siciliano 1997
//! for the second-order scheme), and a position solver built on it.
//!
//! These drive a [`DhPoint`], so they live beside the control points; the
//! pseudoinverse they use is [`crate::linalg::dls_inverse`].

use glam::DVec3;

use super::DhPoint;
use crate::error::FieldError;
use crate::kinematics::{Frames, Robot};
use crate::linalg::{Damping, DlsSettings, Mat, dls_inverse};

/// Motion of a control point's own DH values during a transition: their
/// current rates and accelerations (zero for a fixed point).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PointMotion {
    /// `ȧ'` (m/s).
    pub a_rate: f64,
    /// `ḋ'` (m/s).
    pub d_rate: f64,
    /// `ä'` (m/s²).
    pub a_accel: f64,
    /// `d̈'` (m/s²).
    pub d_accel: f64,
}

/// The Cartesian reference of a control point: where it should be, how
/// fast it should move, and (second order) how it should accelerate.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PointTarget {
    /// Desired position `p_d` (m).
    pub position: DVec3,
    /// Desired velocity `ṗ_d` (m/s).
    pub velocity: DVec3,
    /// Desired acceleration `p̈_d` (m/s²; second order only).
    pub acceleration: DVec3,
}

/// First-order CLIK for a moving control point (eq. 4 with position-error
/// feedback):
/// `θ̇ = J_θ,W^† (ṗ_d + K (p_d − p) − J_a ȧ − J_d ḋ)`.
///
/// Returns the joint speeds (not yet limited). `frames` need no velocities.
#[must_use]
pub fn clik_first_order(
    robot: &Robot,
    frames: &Frames,
    point: &DhPoint,
    motion: &PointMotion,
    target: &PointTarget,
    gain: f64,
    dls: DlsSettings,
) -> Vec<f64> {
    let (target, target_velocity) = (target.position, target.velocity);
    let DlsSettings { weights, damping } = dls;
    let jac = point.jacobians(robot, frames);
    let i = point.link - 1;
    let drift = jac.j_a[i] * motion.a_rate + jac.j_d[i] * motion.d_rate;
    let rhs = target_velocity + gain * (target - jac.position) - drift;
    let inv = dls_inverse(&Mat::from_columns3(&jac.j_theta), weights, damping);
    inv.inverse.mul_vec(&rhs.to_array())
}

/// Second-order CLIK for a moving control point:
/// `θ̈ = J_θ,W^† (p̈_d + K_d (ṗ_d − ṗ) + K_p (p_d − p) − J̇_θ θ̇ − J_a ä − J̇_a ȧ − J_d d̈ − J̇_d ḋ)`,
/// with `ṗ = J_θ θ̇ + J_a ȧ + J_d ḋ`. `frames` must carry the velocities for
/// the current `θ̇` ([`Robot::forward_with_velocity`]).
///
/// # Errors
/// Frames without velocities.
pub fn clik_second_order(
    robot: &Robot,
    frames: &Frames,
    point: &DhPoint,
    motion: &PointMotion,
    target: &PointTarget,
    gains: (f64, f64),
    dls: DlsSettings,
) -> Result<Vec<f64>, FieldError> {
    let PointTarget {
        position: target,
        velocity: target_velocity,
        acceleration: target_acceleration,
    } = *target;
    let DlsSettings { weights, damping } = dls;
    let jac = point.jacobians(robot, frames);
    let rates = point.jacobian_rates(robot, frames, motion.a_rate, motion.d_rate)?;
    let i = point.link - 1;
    let mut bias = jac.j_a[i] * motion.a_accel
        + rates.j_a_dot[i] * motion.a_rate
        + jac.j_d[i] * motion.d_accel
        + rates.j_d_dot[i] * motion.d_rate;
    for (c, qd) in rates.j_theta_dot.iter().zip(&frames.qdot) {
        bias += *c * *qd;
    }
    let (kp, kd) = gains;
    let rhs = target_acceleration
        + kd * (target_velocity - rates.velocity)
        + kp * (target - jac.position)
        - bias;
    let inv = dls_inverse(&Mat::from_columns3(&jac.j_theta), weights, damping);
    Ok(inv.inverse.mul_vec(&rhs.to_array()))
}

/// Options of [`solve_position`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveOptions {
    /// CLIK gain K (1/s).
    pub gain: f64,
    /// Integration step (s).
    pub dt: f64,
    /// Maximum number of steps.
    pub max_steps: usize,
    /// Position tolerance (m).
    pub tolerance: f64,
    /// Damping of the pseudoinverse.
    pub damping: Damping,
}

impl Default for SolveOptions {
    fn default() -> Self {
        Self {
            gain: 20.0,
            dt: 0.01,
            max_steps: 2000,
            tolerance: 1e-6,
            damping: Damping::default(),
        }
    }
}

/// Result of [`solve_position`].
#[derive(Clone, Debug, PartialEq)]
pub struct SolveResult {
    /// Final joint vector.
    pub q: Vec<f64>,
    /// Final position error (m).
    pub error: f64,
    /// Steps taken.
    pub steps: usize,
    /// Whether the error went below the tolerance.
    pub converged: bool,
    /// Largest joint speed commanded on the way (rad/s or m/s).
    pub max_speed: f64,
}

/// Moves control point `point` to `target` by integrating first-order CLIK
/// from `q0`, clamping to joint limits and speed limits.
///
/// # Errors
/// An invalid `q0`, point or target.
pub fn solve_position(
    robot: &Robot,
    q0: &[f64],
    point: &DhPoint,
    target: DVec3,
    options: &SolveOptions,
) -> Result<SolveResult, FieldError> {
    crate::error::finite3("target", target)?;
    let mut frames = robot.forward(q0)?;
    point.validate(robot, &frames)?;
    let mut q = q0.to_vec();
    let mut max_speed: f64 = 0.0;
    for step in 0..options.max_steps {
        let error = (target - point.position(robot, &frames)).length();
        if error <= options.tolerance {
            return Ok(SolveResult {
                q,
                error,
                steps: step,
                converged: true,
                max_speed,
            });
        }
        let qdot = clik_first_order(
            robot,
            &frames,
            point,
            &PointMotion::default(),
            &PointTarget {
                position: target,
                ..PointTarget::default()
            },
            options.gain,
            DlsSettings {
                weights: &[],
                damping: options.damping,
            },
        );
        for ((v, qd), j) in q.iter_mut().zip(&qdot).zip(&robot.joints) {
            let qd = qd.clamp(-j.max_velocity, j.max_velocity);
            max_speed = max_speed.max(qd.abs());
            *v += qd * options.dt;
        }
        robot.clamp_to_limits(&mut q);
        robot.forward_into(&q, &mut frames)?;
    }
    let error = (target - point.position(robot, &frames)).length();
    Ok(SolveResult {
        converged: error <= options.tolerance,
        q,
        error,
        steps: options.max_steps,
        max_speed,
    })
}

impl DhPoint {
    /// Velocity (m/s) of the point for joint speeds `qdot`: `J_θ q̇` with
    /// the columns of [`DhPoint::jacobians`], summed in joint order as
    /// `jacobians(…).j_theta` times `qdot` would be (the same bits), but
    /// without building the Jacobians: the monitors ask it of every
    /// control point at every step.
    #[must_use]
    pub fn velocity(&self, robot: &Robot, frames: &Frames, qdot: &[f64]) -> DVec3 {
        use crate::kinematics::{Convention, JointType};
        let p = self.position(robot, frames);
        let own = self.link - 1;
        let column = match (robot.convention, robot.joints[own].kind) {
            (Convention::Standard, JointType::Revolute) => {
                Some(frames.axis[own].cross(p - frames.axis_point[own]))
            }
            (_, JointType::Prismatic) => {
                Some(frames.axis[own] * self.slide_fraction(robot, frames))
            }
            (Convention::Modified, JointType::Revolute) => None,
        };
        let before = ancestors_velocity(robot, frames, p, robot.joints[own].parent, qdot);
        match (column, qdot.get(own)) {
            (Some(c), Some(v)) => before + c * *v,
            _ => before,
        }
    }
}

/// `Σ J_θ,i q̇_i` over the ancestors of row `k` (1-based; 0: none), from the
/// base out. A joint that is not an ancestor has a zero column, and adding
/// `±0` leaves a sum that is never `−0` unchanged, so the sum equals the
/// full one bit for bit.
fn ancestors_velocity(robot: &Robot, frames: &Frames, p: DVec3, k: usize, qdot: &[f64]) -> DVec3 {
    use crate::kinematics::JointType;
    if k == 0 {
        return DVec3::ZERO;
    }
    let i = k - 1;
    let before = ancestors_velocity(robot, frames, p, robot.joints[i].parent, qdot);
    let u = frames.axis[i];
    let column = match robot.joints[i].kind {
        JointType::Revolute => u.cross(p - frames.axis_point[i]),
        JointType::Prismatic => u,
    };
    qdot.get(i).map_or(before, |v| before + column * *v)
}
