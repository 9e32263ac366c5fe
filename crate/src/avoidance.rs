//! Repulsion and controllers (paper §II, §III-A; DESIGN parts 4 and 6).
//!
//! * **Control-point selection** ([`Selection`]): one point per
//!   segment–obstacle pair within the influence distance, one per obstacle
//!   (the closest point over the whole skeleton, the paper's fig. 4), or
//!   points pinned by the user as `(link, d', a')`.
//! * **Repulsion** ([`repulsion_speed`]): the gradient of a potential that
//!   vanishes at the influence distance `ρ₀`,
//!   `v(d) = min(η (1/d − 1/ρ₀) / d², v_max)` for `0 < d < ρ₀`, `v_max` in
//!   contact, 0 beyond `ρ₀`. It is applied at the control point away from
//!   the obstacle, as a velocity (velocity and `clik2` modes) or as a force
//!   `f = k_f v` (torque mode). `v_max` bounds how fast any point is pushed:
//!   heavy industrial arms want it low (paper §I).
//! * **Velocity mode** ([`velocity_control`]): task priority with the
//!   weighted damped pseudoinverse. The avoidance rows come first, one per
//!   control point, `−nᵢᵀ J_θ,i θ̇ = vᵢ + nᵢᵀ (J_a ȧ + J_d ḋ)` (eq. 3/4: the
//!   point's own motion on the skeleton is subtracted), each scaled by a
//!   smooth activation `hᵢ ∈ [0, 1]` (a smoothstep over the outer part of the
//!   influence distance) so rows fade in and out without a jump; the
//!   end-effector task runs in their null space. At most `n − 1` points (the
//!   closest) take part, so the task keeps at least one direction.
//!   Joint speeds are then scaled uniformly into the joints' speed limits
//!   and clipped so the next step stays within the position limits.
//! * **Torque mode** ([`torque_control`]): `τ = J_eeᵀ f_task + Σ J_θ,iᵀ fᵢ
//!   − D q̇`, with `f_task = K_p (x_d − x) + K_d (ẋ_d − ẋ)` (position only),
//!   integrated on the joint-space model `M q̈ = τ` with `M = diag(inertia)`:
//!   no gravity (assumed compensated) and no coupling between joints.
//! * **Second-order CLIK** ([`clik2_control`]): the same priority at the
//!   acceleration level, with the moving-point terms
//!   `J̇_θ θ̇ + J_a ä + J̇_a ȧ + J_d d̈ + J̇_d ḋ` of every control point.

use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};

use crate::control_point::DhPoint;
use crate::error::{FieldError, non_negative, positive};
use crate::kinematics::ik::{
    Damping, Mat, PointMotion, dls_inverse, end_effector_jacobian, orientation_error,
};
use crate::kinematics::{Frames, Robot};

/// Which controller drives the joints.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub enum Mode {
    /// Joint velocities from task-priority inverse kinematics (default).
    #[default]
    Velocity,
    /// Joint torques on a simple joint-space dynamics model.
    Torque,
    /// Second-order closed-loop inverse kinematics (joint accelerations).
    Clik2,
}

/// How control points are chosen.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub enum Selection {
    /// One per segment–obstacle pair within the influence distance.
    Pairs,
    /// One per obstacle: its closest point on the skeleton (default).
    #[default]
    PerObstacle,
    /// The points listed in `pinned`, each against its closest obstacle.
    Pinned,
}

/// Gains of the torque mode.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields, default)]
pub struct TorqueGains {
    /// Cartesian stiffness of the task (N/m; default 300).
    pub stiffness: f64,
    /// Cartesian damping of the task (N·s/m; default 40).
    pub damping: f64,
    /// Joint damping `D` (N·m·s/rad; default 2).
    pub joint_damping: f64,
    /// Diagonal joint inertia `M` of the model (kg·m²; default 0.5).
    pub inertia: f64,
    /// Force per unit of repulsion speed, `k_f` (N·s/m; default 200).
    pub force_gain: f64,
}

impl Default for TorqueGains {
    fn default() -> Self {
        Self {
            stiffness: 300.0,
            damping: 40.0,
            joint_damping: 2.0,
            inertia: 0.5,
            force_gain: 200.0,
        }
    }
}

/// Gains of the second-order CLIK.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields, default)]
pub struct Clik2Gains {
    /// Position gain `K_p` (1/s²; default 100).
    pub kp: f64,
    /// Velocity gain `K_d` (1/s; default 20), also used by the avoidance
    /// rows to track the repulsion speed and to damp the null space.
    pub kd: f64,
}

impl Default for Clik2Gains {
    fn default() -> Self {
        Self {
            kp: 100.0,
            kd: 20.0,
        }
    }
}

/// Controller settings (scenario field `controller`; every field has a
/// default).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields, default)]
pub struct ControllerConfig {
    /// `velocity` (default), `torque` or `clik2`.
    pub mode: Mode,
    /// `pairs`, `perObstacle` (default) or `pinned`.
    pub selection: Selection,
    /// Points used by the `pinned` selection (default none).
    pub pinned: Vec<DhPoint>,
    /// Influence distance `ρ₀` (m, > 0; default 0.3).
    pub influence_distance: f64,
    /// Potential gain `η` (m³/s, ≥ 0; default 0.002).
    pub repulsion_gain: f64,
    /// Largest repulsion speed `v_max` (m/s, ≥ 0; default 0.5).
    pub max_repulsion_speed: f64,
    /// Time for one DH value of a transition (s, > 0; default 0.1).
    pub transition_time: f64,
    /// Largest move along the skeleton a control point makes without a
    /// transition (m, ≥ 0; default 0.02).
    pub jump_threshold: f64,
    /// Fraction of the influence distance over which an avoidance row fades
    /// in (in `(0, 1]`; default 0.5).
    pub activation_band: f64,
    /// Task gain `K` of velocity mode (1/s, ≥ 0; default 5).
    pub task_gain: f64,
    /// Damping of the pseudoinverses.
    pub damping: DampingConfig,
    /// Gains of torque mode.
    pub torque: TorqueGains,
    /// Gains of `clik2` mode.
    pub clik2: Clik2Gains,
    /// Whether segments of non-adjacent links repel each other (default
    /// true).
    pub self_collision: bool,
}

/// Damping of the damped least-squares inverse.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields, default)]
pub struct DampingConfig {
    /// Singular value below which damping starts (default 0.04).
    pub epsilon: f64,
    /// Damping at a singularity (default 0.04).
    pub lambda_max: f64,
}

impl Default for DampingConfig {
    fn default() -> Self {
        let d = Damping::default();
        Self {
            epsilon: d.epsilon,
            lambda_max: d.lambda_max,
        }
    }
}

impl Default for ControllerConfig {
    fn default() -> Self {
        Self {
            mode: Mode::Velocity,
            selection: Selection::PerObstacle,
            pinned: Vec::new(),
            influence_distance: 0.3,
            repulsion_gain: 0.002,
            max_repulsion_speed: 0.5,
            transition_time: crate::transition::DEFAULT_TIME_PER_VALUE,
            jump_threshold: crate::transition::DEFAULT_JUMP_THRESHOLD,
            activation_band: 0.5,
            task_gain: 5.0,
            damping: DampingConfig::default(),
            torque: TorqueGains::default(),
            clik2: Clik2Gains::default(),
            self_collision: true,
        }
    }
}

impl ControllerConfig {
    /// Checks every value (pinned points are checked against the robot by
    /// the scenario).
    ///
    /// # Errors
    /// The field and the reason, e.g. `influenceDistance: must be > 0`.
    pub fn validate(&self) -> Result<(), FieldError> {
        positive("influenceDistance", self.influence_distance)?;
        non_negative("repulsionGain", self.repulsion_gain)?;
        non_negative("maxRepulsionSpeed", self.max_repulsion_speed)?;
        positive("transitionTime", self.transition_time)?;
        non_negative("jumpThreshold", self.jump_threshold)?;
        positive("activationBand", self.activation_band)?;
        if self.activation_band > 1.0 {
            return Err(FieldError::new("activationBand", "must be ≤ 1"));
        }
        non_negative("taskGain", self.task_gain)?;
        non_negative("damping.epsilon", self.damping.epsilon)?;
        non_negative("damping.lambdaMax", self.damping.lambda_max)?;
        let t = &self.torque;
        non_negative("torque.stiffness", t.stiffness)?;
        non_negative("torque.damping", t.damping)?;
        non_negative("torque.jointDamping", t.joint_damping)?;
        positive("torque.inertia", t.inertia)?;
        non_negative("torque.forceGain", t.force_gain)?;
        non_negative("clik2.kp", self.clik2.kp)?;
        non_negative("clik2.kd", self.clik2.kd)?;
        if self.selection == Selection::Pinned && self.pinned.is_empty() {
            return Err(FieldError::new(
                "pinned",
                "the pinned selection needs at least one point",
            ));
        }
        Ok(())
    }

    fn dls(&self) -> Damping {
        Damping {
            epsilon: self.damping.epsilon,
            lambda_max: self.damping.lambda_max,
        }
    }
}

/// Repulsion speed (m/s) at clearance `distance` (m): the potential's
/// gradient `η (1/d − 1/ρ₀) / d²`, bounded by `v_max`; `v_max` at or below
/// contact, 0 at or beyond the influence distance. Continuous in `d`.
#[must_use]
pub fn repulsion_speed(distance: f64, config: &ControllerConfig) -> f64 {
    let rho = config.influence_distance;
    let vmax = config.max_repulsion_speed;
    if distance.is_nan() || distance >= rho {
        return 0.0;
    }
    if distance <= 0.0 {
        return vmax;
    }
    let v = config.repulsion_gain * (1.0 / distance - 1.0 / rho) / (distance * distance);
    v.min(vmax)
}

/// Smooth activation of an avoidance row at clearance `distance`: 0 at or
/// beyond the influence distance, 1 within `ρ₀ (1 − band)`, a smoothstep in
/// between.
#[must_use]
pub fn activation(distance: f64, config: &ControllerConfig) -> f64 {
    let rho = config.influence_distance;
    let band = config.activation_band * rho;
    let x = ((rho - distance) / band).clamp(0.0, 1.0);
    if x.is_nan() {
        return 0.0;
    }
    x * x * (3.0 - 2.0 * x)
}

/// An active control point as the controllers see it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ActivePoint {
    /// Where it is on the arm.
    pub dh: DhPoint,
    /// Rates and accelerations of its own DH values (transitions).
    pub motion: PointMotion,
    /// Unit direction from the control point towards the obstacle.
    pub normal: DVec3,
    /// Clearance used by the controller (m): measured distance minus the
    /// sensing margin.
    pub distance: f64,
}

impl ActivePoint {
    /// The repulsion at this point: a velocity (m/s) away from the obstacle.
    #[must_use]
    pub fn repulsion(&self, config: &ControllerConfig) -> DVec3 {
        -self.normal * repulsion_speed(self.distance, config)
    }
}

/// The end-effector reference at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TaskReference {
    /// Desired position (m).
    pub position: DVec3,
    /// Desired velocity (m/s).
    pub velocity: DVec3,
    /// Desired acceleration (m/s²).
    pub acceleration: DVec3,
    /// Desired orientation, if controlled.
    pub orientation: Option<DQuat>,
    /// Chain whose end effector is controlled (0 = main chain).
    pub chain: usize,
}

/// Output of a controller for one step.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Command {
    /// New joint velocities (already limited).
    pub qdot: Vec<f64>,
    /// Joint torques (torque mode; empty otherwise).
    pub torque: Vec<f64>,
}

/// Task-priority resolution: each level `(J, r)` is satisfied in the null
/// space of the ones before; `rest` (if any) is projected in the null space
/// of all of them.
fn prioritized(
    levels: &[(Mat, Vec<f64>)],
    n: usize,
    damping: Damping,
    rest: Option<&[f64]>,
) -> Vec<f64> {
    let mut x = vec![0.0; n];
    let mut p = Mat::identity(n);
    for (jac, r) in levels {
        if jac.rows == 0 {
            continue;
        }
        let jp = jac.mul(&p);
        let inv = dls_inverse(&jp, &[], damping).inverse;
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

/// The avoidance rows of the `n − 1` closest points: `hᵢ (−nᵢᵀ J_θ,i)` and
/// the right-hand side built by `rhs(point, jacobians)`.
fn avoidance_rows(
    robot: &Robot,
    frames: &Frames,
    points: &[ActivePoint],
    config: &ControllerConfig,
    mut rhs: impl FnMut(&ActivePoint, &crate::control_point::PointJacobians) -> f64,
) -> (Mat, Vec<f64>) {
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
    let mut r = Vec::with_capacity(order.len());
    for (row, &k) in order.iter().enumerate() {
        let p = &points[k];
        let h = activation(p.distance, config);
        let pj = p.dh.jacobians(robot, frames);
        let dir = -p.normal;
        for (c, col) in pj.j_theta.iter().enumerate() {
            jac.set(row, c, h * dir.dot(*col));
        }
        r.push(h * rhs(p, &pj));
    }
    (jac, r)
}

/// The end-effector rows (3, or 6 with orientation) and the current pose.
fn task_rows(
    robot: &Robot,
    frames: &Frames,
    task: &TaskReference,
) -> Result<(Mat, DVec3, DQuat), FieldError> {
    let full = end_effector_jacobian(robot, frames, task.chain)?;
    let rows = if task.orientation.is_some() { 6 } else { 3 };
    let mut jac = Mat::zeros(rows, full.cols);
    jac.data.copy_from_slice(&full.data[..rows * full.cols]);
    let ee = frames
        .end_effectors
        .get(task.chain)
        .copied()
        .unwrap_or(glam::DAffine3::IDENTITY);
    Ok((jac, ee.translation, DQuat::from_mat3(&ee.matrix3)))
}

/// Scales `qdot` uniformly into the joints' speed limits, then clips each
/// joint so that one step of `dt` stays within its position limits.
pub fn limit_joint_velocities(robot: &Robot, q: &[f64], qdot: &mut [f64], dt: f64) {
    let mut scale: f64 = 1.0;
    for (v, j) in qdot.iter().zip(&robot.joints) {
        if v.abs() > j.max_velocity {
            scale = scale.min(j.max_velocity / v.abs());
        }
    }
    for ((v, j), qi) in qdot.iter_mut().zip(&robot.joints).zip(q) {
        *v *= scale;
        if !v.is_finite() {
            *v = 0.0;
        }
        if dt > 0.0 {
            let lo = (j.min - qi) / dt;
            let hi = (j.max - qi) / dt;
            *v = v.clamp(lo.min(0.0), hi.max(0.0));
        }
    }
}

/// Velocity mode: avoidance first, the end-effector task in its null space.
///
/// # Errors
/// Only on inconsistent inputs (a chain that does not exist).
pub fn velocity_control(
    robot: &Robot,
    frames: &Frames,
    q: &[f64],
    points: &[ActivePoint],
    task: &TaskReference,
    config: &ControllerConfig,
    dt: f64,
) -> Result<Command, FieldError> {
    let n = robot.dof();
    let (avoid, r_avoid) = avoidance_rows(robot, frames, points, config, |p, pj| {
        let i = p.dh.link - 1;
        let drift = pj.j_a[i] * p.motion.a_rate + pj.j_d[i] * p.motion.d_rate;
        repulsion_speed(p.distance, config) + p.normal.dot(drift)
    });
    let (jee, x, rot) = task_rows(robot, frames, task)?;
    let mut r_task = (task.velocity + config.task_gain * (task.position - x))
        .to_array()
        .to_vec();
    if let Some(o) = task.orientation {
        r_task.extend((config.task_gain * orientation_error(o, rot)).to_array());
    }
    let mut qdot = prioritized(&[(avoid, r_avoid), (jee, r_task)], n, config.dls(), None);
    limit_joint_velocities(robot, q, &mut qdot, dt);
    Ok(Command {
        qdot,
        torque: Vec::new(),
    })
}

/// Torque mode: `τ = J_eeᵀ f_task + Σ J_θ,iᵀ fᵢ − D q̇`, integrated over
/// `dt` on `M q̈ = τ` (semi-implicit Euler); returns the new joint velocities
/// (limited) and the torques.
///
/// # Errors
/// Only on inconsistent inputs.
#[allow(clippy::too_many_arguments)]
pub fn torque_control(
    robot: &Robot,
    frames: &Frames,
    q: &[f64],
    qdot: &[f64],
    points: &[ActivePoint],
    task: &TaskReference,
    config: &ControllerConfig,
    dt: f64,
) -> Result<Command, FieldError> {
    let n = robot.dof();
    let g = &config.torque;
    let (jee, x, _) = task_rows(robot, frames, task)?;
    let v = jee.mul_vec(qdot);
    let xdot = DVec3::new(v[0], v[1], v[2]);
    let f = g.stiffness * (task.position - x) + g.damping * (task.velocity - xdot);
    let mut tau = vec![0.0; n];
    for (k, t) in tau.iter_mut().enumerate() {
        *t = jee.get(0, k) * f.x + jee.get(1, k) * f.y + jee.get(2, k) * f.z
            - g.joint_damping * qdot[k];
    }
    for p in points {
        let force = g.force_gain * p.repulsion(config);
        let pj = p.dh.jacobians(robot, frames);
        for (t, col) in tau.iter_mut().zip(&pj.j_theta) {
            *t += col.dot(force);
        }
    }
    let mut out: Vec<f64> = qdot
        .iter()
        .zip(&tau)
        .map(|(v, t)| v + t / g.inertia * dt)
        .collect();
    limit_joint_velocities(robot, q, &mut out, dt);
    Ok(Command {
        qdot: out,
        torque: tau,
    })
}

/// `J̇ q̇` of the end-effector rows, by a forward difference of the Jacobian
/// along `q̇` (step 1e-6 s).
fn task_bias(
    robot: &Robot,
    q: &[f64],
    qdot: &[f64],
    chain: usize,
    jee: &Mat,
) -> Result<Vec<f64>, FieldError> {
    let rows = jee.rows;
    const H: f64 = 1e-6;
    let q2: Vec<f64> = q.iter().zip(qdot).map(|(a, b)| a + H * b).collect();
    let f2 = robot.forward(&q2)?;
    let j2 = end_effector_jacobian(robot, &f2, chain)?;
    let mut out = vec![0.0; rows];
    for (r, o) in out.iter_mut().enumerate() {
        for (c, qd) in qdot.iter().enumerate() {
            *o += (j2.get(r, c) - jee.get(r, c)) / H * qd;
        }
    }
    Ok(out)
}

/// Second-order CLIK: joint accelerations with avoidance first (each row
/// tracks its repulsion speed, with the moving-point terms), the
/// end-effector task in its null space and joint damping in the remaining
/// null space; integrated over `dt`, returns the new joint velocities.
///
/// `frames` must carry the velocities for `qdot`
/// ([`Robot::forward_with_velocity`]).
///
/// # Errors
/// Frames without velocities.
#[allow(clippy::too_many_arguments)]
pub fn clik2_control(
    robot: &Robot,
    frames: &Frames,
    q: &[f64],
    qdot: &[f64],
    points: &[ActivePoint],
    task: &TaskReference,
    config: &ControllerConfig,
    dt: f64,
) -> Result<Command, FieldError> {
    let n = robot.dof();
    let g = config.clik2;
    let mut failure = None;
    let (avoid, r_avoid) = avoidance_rows(robot, frames, points, config, |p, pj| {
        let i = p.dh.link - 1;
        let m = &p.motion;
        match p.dh.jacobian_rates(robot, frames, m.a_rate, m.d_rate) {
            Ok(rates) => {
                let mut bias = pj.j_a[i] * m.a_accel
                    + rates.j_a_dot[i] * m.a_rate
                    + pj.j_d[i] * m.d_accel
                    + rates.j_d_dot[i] * m.d_rate;
                for (c, qd) in rates.j_theta_dot.iter().zip(qdot) {
                    bias += *c * *qd;
                }
                let dir = -p.normal;
                g.kd * (repulsion_speed(p.distance, config) - dir.dot(rates.velocity))
                    - dir.dot(bias)
            }
            Err(e) => {
                failure = Some(e);
                0.0
            }
        }
    });
    if let Some(e) = failure {
        return Err(e);
    }
    let (jee, x, rot) = task_rows(robot, frames, task)?;
    let v = jee.mul_vec(qdot);
    let bias = task_bias(robot, q, qdot, task.chain, &jee)?;
    let xdot = DVec3::new(v[0], v[1], v[2]);
    let a = task.acceleration + g.kd * (task.velocity - xdot) + g.kp * (task.position - x);
    let mut r_task: Vec<f64> = a.to_array().to_vec();
    if let Some(o) = task.orientation {
        let w = DVec3::new(v[3], v[4], v[5]);
        r_task.extend((g.kp * orientation_error(o, rot) - g.kd * w).to_array());
    }
    for (r, b) in r_task.iter_mut().zip(&bias) {
        *r -= b;
    }
    let damp: Vec<f64> = qdot.iter().map(|v| -g.kd * v).collect();
    let qdd = prioritized(
        &[(avoid, r_avoid), (jee, r_task)],
        n,
        config.dls(),
        Some(&damp),
    );
    let mut out: Vec<f64> = qdot.iter().zip(&qdd).map(|(v, a)| v + a * dt).collect();
    limit_joint_velocities(robot, q, &mut out, dt);
    Ok(Command {
        qdot: out,
        torque: Vec::new(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn repulsion_is_bounded_and_vanishes_at_the_influence_distance() {
        let c = ControllerConfig::default();
        assert_eq!(repulsion_speed(0.3, &c), 0.0);
        assert_eq!(repulsion_speed(0.0, &c), c.max_repulsion_speed);
        assert_eq!(repulsion_speed(-0.1, &c), c.max_repulsion_speed);
        assert!(repulsion_speed(0.2999, &c) < 1e-3);
        let mut prev = 0.0;
        for k in 0..300 {
            let d = 0.3 - k as f64 * 0.001;
            let v = repulsion_speed(d, &c);
            assert!(v >= prev && v <= c.max_repulsion_speed);
            prev = v;
        }
    }

    #[test]
    fn activation_is_smooth() {
        let c = ControllerConfig::default();
        assert_eq!(activation(0.3, &c), 0.0);
        assert_eq!(activation(0.15, &c), 1.0);
        assert!((activation(0.225, &c) - 0.5).abs() < 1e-12);
    }
}
