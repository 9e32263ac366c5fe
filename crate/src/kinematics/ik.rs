//! Inverse kinematics of the end effector: the geometric Jacobian, the
//! orientation error, and first-order CLIK for a 6-D pose task.
//!
//! The damped least-squares pseudoinverse and the matrix type live in
//! [`crate::linalg`]; CLIK of a control point that moves along its link
//! (paper eq. 4) lives beside the control points in
//! `control_point::clik`.

use glam::{DQuat, DVec3};

use super::{Frames, JointType, Robot};
use crate::error::FieldError;

use crate::linalg::{DlsSettings, Mat, dls_inverse};

/// Geometric Jacobian (6 × n: linear rows, then angular) of the end effector
/// of chain `chain` (0 = main chain).
///
/// # Errors
/// `chain: 3 is not a chain of this robot (chains 0 to 1)`.
pub fn end_effector_jacobian(
    robot: &Robot,
    frames: &Frames,
    chain: usize,
) -> Result<Mat, FieldError> {
    let c = robot.chains.get(chain).ok_or_else(|| {
        FieldError::new(
            "chain",
            format!(
                "{chain} is not a chain of this robot (chains 0 to {})",
                robot.chains.len().saturating_sub(1)
            ),
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

/// First-order CLIK for a 6-D end-effector task (position and orientation) of
/// chain `chain`:
/// `θ̇ = J_W^† [v_d + K_p (p_d − p); ω_d + K_o e_o]`, with `e_o` from
/// [`orientation_error`]. Returns the joint speeds (not yet limited).
///
/// # Errors
/// An unknown chain.
pub fn clik_pose(
    robot: &Robot,
    frames: &Frames,
    chain: usize,
    target: (DVec3, DQuat),
    target_twist: (DVec3, DVec3),
    gains: (f64, f64),
    dls: DlsSettings,
) -> Result<Vec<f64>, FieldError> {
    let DlsSettings { weights, damping } = dls;
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
