//! Inverse kinematics: the weighted damped least-squares pseudoinverse, and
//! first- and second-order closed-loop inverse kinematics (CLIK) for moving
//! control points (paper eq. 4; Caccavale, Chiaverini & Siciliano 1997 for the
//! second-order scheme).
//!
//! The pseudoinverse is `J_W^† = W⁻¹ Jᵀ (J W⁻¹ Jᵀ + Σ λ_i² u_i u_iᵀ)⁻¹` with
//! joint weights `W` (a larger weight moves a joint less), where `u_i` are the
//! left singular vectors of `J W^{-1/2}`. Each direction is damped only when
//! its singular value σ_i drops below `epsilon`,
//! `λ_i² = (1 − (σ_i/ε)²) λ_max²` (numerical filtering, Chiaverini 1997), so
//! the solution is exact where the arm is well conditioned, bounded at a
//! stretched arm, and unaffected by directions that are singular by design
//! (the z row of a planar arm's Jacobian). With `λ_max = ε` (the default) the
//! gain of the inverse never exceeds `1/ε`.

// Dense linear algebra on small matrices reads best with explicit indices.
#![allow(clippy::needless_range_loop)]

use glam::{DQuat, DVec3};

use super::{Frames, JointType, Robot};
use crate::control_point::DhPoint;
use crate::error::FieldError;

/// A small dense row-major matrix (Jacobians are 3 × n or 6 × n).
#[derive(Clone, Debug, PartialEq)]
pub struct Mat {
    /// Number of rows.
    pub rows: usize,
    /// Number of columns.
    pub cols: usize,
    /// Row-major entries.
    pub data: Vec<f64>,
}

impl Mat {
    /// A zero matrix.
    #[must_use]
    pub fn zeros(rows: usize, cols: usize) -> Self {
        Self {
            rows,
            cols,
            data: vec![0.0; rows * cols],
        }
    }

    /// The identity.
    #[must_use]
    pub fn identity(n: usize) -> Self {
        let mut m = Self::zeros(n, n);
        for i in 0..n {
            m.data[i * n + i] = 1.0;
        }
        m
    }

    /// A 3 × n matrix from n column vectors.
    #[must_use]
    pub fn from_columns3(cols: &[DVec3]) -> Self {
        let n = cols.len();
        let mut m = Self::zeros(3, n);
        for (k, c) in cols.iter().enumerate() {
            m.data[k] = c.x;
            m.data[n + k] = c.y;
            m.data[2 * n + k] = c.z;
        }
        m
    }

    /// Entry `(r, c)`.
    #[must_use]
    pub fn get(&self, r: usize, c: usize) -> f64 {
        self.data[r * self.cols + c]
    }

    /// Sets entry `(r, c)`.
    pub fn set(&mut self, r: usize, c: usize, v: f64) {
        self.data[r * self.cols + c] = v;
    }

    /// `self · x`.
    #[must_use]
    pub fn mul_vec(&self, x: &[f64]) -> Vec<f64> {
        (0..self.rows)
            .map(|r| {
                self.data[r * self.cols..(r + 1) * self.cols]
                    .iter()
                    .zip(x)
                    .map(|(a, b)| a * b)
                    .sum()
            })
            .collect()
    }

    /// `self · other`.
    #[must_use]
    pub fn mul(&self, other: &Self) -> Self {
        let mut out = Self::zeros(self.rows, other.cols);
        for r in 0..self.rows {
            for k in 0..self.cols {
                let a = self.get(r, k);
                if a == 0.0 {
                    continue;
                }
                for c in 0..other.cols {
                    out.data[r * other.cols + c] += a * other.get(k, c);
                }
            }
        }
        out
    }

    /// Rows as nested vectors (the JS layout).
    #[must_use]
    pub fn to_rows(&self) -> Vec<Vec<f64>> {
        self.data
            .chunks(self.cols.max(1))
            .map(<[f64]>::to_vec)
            .collect()
    }
}

/// Eigen-decomposition of a symmetric matrix by cyclic Jacobi rotations:
/// returns the eigenvalues and the eigenvectors as the columns of a matrix.
#[must_use]
pub fn symmetric_eigen(a: &Mat) -> (Vec<f64>, Mat) {
    let n = a.rows;
    let mut m = a.clone();
    let mut v = Mat::identity(n);
    for _sweep in 0..50 {
        let mut off = 0.0;
        for p in 0..n {
            for q in p + 1..n {
                off += m.get(p, q) * m.get(p, q);
            }
        }
        if off < 1e-30 {
            break;
        }
        for p in 0..n {
            for q in p + 1..n {
                let apq = m.get(p, q);
                if apq.abs() < 1e-300 {
                    continue;
                }
                let theta = (m.get(q, q) - m.get(p, p)) / (2.0 * apq);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for k in 0..n {
                    let mkp = m.get(k, p);
                    let mkq = m.get(k, q);
                    m.set(k, p, c * mkp - s * mkq);
                    m.set(k, q, s * mkp + c * mkq);
                }
                for k in 0..n {
                    let mpk = m.get(p, k);
                    let mqk = m.get(q, k);
                    m.set(p, k, c * mpk - s * mqk);
                    m.set(q, k, s * mpk + c * mqk);
                }
                for k in 0..n {
                    let vkp = v.get(k, p);
                    let vkq = v.get(k, q);
                    v.set(k, p, c * vkp - s * vkq);
                    v.set(k, q, s * vkp + c * vkq);
                }
            }
        }
    }
    ((0..n).map(|i| m.get(i, i)).collect(), v)
}

/// Parameters of the damped least-squares inverse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Damping {
    /// Singular value below which damping starts (same unit as `J`).
    pub epsilon: f64,
    /// Damping factor reached at an exact singularity.
    pub lambda_max: f64,
}

impl Default for Damping {
    fn default() -> Self {
        Self {
            epsilon: 0.04,
            lambda_max: 0.04,
        }
    }
}

/// A damped least-squares inverse `J_W^†` (n × m) with the conditioning it
/// was computed at.
#[derive(Clone, Debug, PartialEq)]
pub struct DlsInverse {
    /// The pseudoinverse, n × m.
    pub inverse: Mat,
    /// Smallest singular value of `J W^{-1/2}`.
    pub sigma_min: f64,
    /// Damping factor applied in the direction of the smallest singular value.
    pub lambda: f64,
}

/// The weighted damped least-squares inverse of `jac` (m × n) with joint
/// weights `weights` (n positive values; empty for unit weights).
#[must_use]
pub fn dls_inverse(jac: &Mat, weights: &[f64], damping: Damping) -> DlsInverse {
    let (m, n) = (jac.rows, jac.cols);
    let winv: Vec<f64> = (0..n)
        .map(|k| weights.get(k).map_or(1.0, |w| 1.0 / w))
        .collect();
    // A = J W⁻¹ Jᵀ
    let mut a = Mat::zeros(m, m);
    for r in 0..m {
        for c in r..m {
            let mut s = 0.0;
            for k in 0..n {
                s += jac.get(r, k) * winv[k] * jac.get(c, k);
            }
            a.set(r, c, s);
            a.set(c, r, s);
        }
    }
    let (eig, u) = symmetric_eigen(&a);
    let damp = |e: f64| {
        let sigma = e.max(0.0).sqrt();
        if sigma >= damping.epsilon {
            0.0
        } else {
            let ratio = sigma / damping.epsilon;
            (1.0 - ratio * ratio) * damping.lambda_max * damping.lambda_max
        }
    };
    let smallest = eig.iter().copied().fold(f64::INFINITY, f64::min).max(0.0);
    // (A + Σ λ_i² u_i u_iᵀ)⁻¹ = U diag(1 / (e_i + λ_i²)) Uᵀ: only the
    // directions whose singular value is below ε are damped. Directions with
    // e = 0 and no damping (only when ε = 0) are dropped.
    let mut ainv = Mat::zeros(m, m);
    for (i, e) in eig.iter().enumerate() {
        let den = e.max(0.0) + damp(*e);
        if den <= 1e-300 {
            continue;
        }
        for r in 0..m {
            for c in 0..m {
                let v = ainv.get(r, c) + u.get(r, i) * u.get(c, i) / den;
                ainv.set(r, c, v);
            }
        }
    }
    // W⁻¹ Jᵀ A⁻¹
    let mut inv = Mat::zeros(n, m);
    for k in 0..n {
        for c in 0..m {
            let mut s = 0.0;
            for r in 0..m {
                s += jac.get(r, k) * ainv.get(r, c);
            }
            inv.set(k, c, winv[k] * s);
        }
    }
    DlsInverse {
        inverse: inv,
        sigma_min: smallest.sqrt(),
        lambda: damp(smallest).sqrt(),
    }
}

/// Geometric Jacobian (6 × n: linear rows, then angular) of the end effector
/// of chain `chain` (0 = main chain).
///
/// # Errors
/// `chain: 3 is out of range 0..2`.
pub fn end_effector_jacobian(
    robot: &Robot,
    frames: &Frames,
    chain: usize,
) -> Result<Mat, FieldError> {
    let c = robot.chains.get(chain).ok_or_else(|| {
        FieldError::new(
            "chain",
            format!("{chain} is out of range 0..{}", robot.chains.len()),
        )
    })?;
    let p = frames.end_effectors[chain].translation;
    let n = robot.dof();
    let mut jac = Mat::zeros(6, n);
    let mut k = c.last;
    while k >= 1 {
        let i = k - 1;
        let joint = &robot.joints[i];
        let (axis, point) = match robot.convention {
            super::Convention::Standard => (
                frames.starts[i].matrix3.z_axis,
                frames.starts[i].translation,
            ),
            super::Convention::Modified => (frames.transforms[k].matrix3.z_axis, frames.mids[i]),
        };
        let (lin, ang) = match joint.kind {
            JointType::Revolute => (axis.cross(p - point), axis),
            JointType::Prismatic => (axis, DVec3::ZERO),
        };
        for (r, v) in lin.to_array().into_iter().chain(ang.to_array()).enumerate() {
            jac.set(r, i, v);
        }
        k = joint.parent;
    }
    Ok(jac)
}

/// Orientation error `e_o` (rad) that turns `current` into `desired`: twice
/// the vector part of `desired · current⁻¹`, on the short way round.
#[must_use]
pub fn orientation_error(desired: DQuat, current: DQuat) -> DVec3 {
    let mut e = desired * current.conjugate();
    if e.w < 0.0 {
        e = -e;
    }
    2.0 * DVec3::new(e.x, e.y, e.z)
}

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

/// First-order CLIK for a moving control point (eq. 4 with position-error
/// feedback):
/// `θ̇ = J_θ,W^† (ṗ_d + K (p_d − p) − J_a ȧ − J_d ḋ)`.
///
/// Returns the joint speeds (not yet limited). `frames` need no velocities.
#[must_use]
#[allow(clippy::too_many_arguments)]
pub fn clik_first_order(
    robot: &Robot,
    frames: &Frames,
    point: &DhPoint,
    motion: &PointMotion,
    target: DVec3,
    target_velocity: DVec3,
    gain: f64,
    weights: &[f64],
    damping: Damping,
) -> Vec<f64> {
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
#[allow(clippy::too_many_arguments)]
pub fn clik_second_order(
    robot: &Robot,
    frames: &Frames,
    point: &DhPoint,
    motion: &PointMotion,
    target: DVec3,
    target_velocity: DVec3,
    target_acceleration: DVec3,
    gains: (f64, f64),
    weights: &[f64],
    damping: Damping,
) -> Result<Vec<f64>, FieldError> {
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
            target,
            DVec3::ZERO,
            options.gain,
            &[],
            options.damping,
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

/// First-order CLIK for a 6-D end-effector task (position and orientation) of
/// chain `chain`:
/// `θ̇ = J_W^† [v_d + K_p (p_d − p); ω_d + K_o e_o]`, with `e_o` from
/// [`orientation_error`]. Returns the joint speeds (not yet limited).
///
/// # Errors
/// An unknown chain.
#[allow(clippy::too_many_arguments)]
pub fn clik_pose(
    robot: &Robot,
    frames: &Frames,
    chain: usize,
    target: (DVec3, DQuat),
    target_twist: (DVec3, DVec3),
    gains: (f64, f64),
    weights: &[f64],
    damping: Damping,
) -> Result<Vec<f64>, FieldError> {
    let jac = end_effector_jacobian(robot, frames, chain)?;
    let ee = frames.end_effectors[chain];
    let (_, rotation, position) = ee.to_scale_rotation_translation();
    let ep = target.0 - position;
    let eo = orientation_error(target.1, rotation);
    let v = target_twist.0 + gains.0 * ep;
    let w = target_twist.1 + gains.1 * eo;
    let rhs = [v.x, v.y, v.z, w.x, w.y, w.z];
    Ok(dls_inverse(&jac, weights, damping).inverse.mul_vec(&rhs))
}
