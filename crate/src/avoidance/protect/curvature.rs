//! The bend of a pair's path while the arm brakes: how far the witness's
//! path may curve towards the obstacle, beyond the straight line the
//! first-order guard `nᵀ J_θ q̇` sees, before the joints stop.
//!
//! With the joints turning at `q̇` the witness accelerates by `J̇_θ q̇` even
//! at constant joint speeds (the centripetal and Coriolis terms of a
//! turning chain). While the limiter brakes the joints to rest within
//! `T_s`, their speeds fall about linearly, so that term falls with their
//! square and moves the point by at most `|J̇_θ q̇| T_s² / 4`
//! (`∫₀^T ∫₀^t a (1 − s/T)² ds dt = a T² / 4`). The guard keeps that much
//! clearance in reserve. It is negligible at ordinary speeds (1 rad/s on
//! a 0.5 m chain: 0.5 m/s², about 2 mm for the 0.1 s stop) and grows with
//! the fourth power of the joint speed: measured on the PR2 reach problems,
//! the gripper closed on a box at 0.36 m/s while the arm braked from
//! 3.3 rad/s, the approach speed rising from 0.11 m/s as the chain turned.
//!
//! Only pairs whose obstacle does not close in keep the reserve: an
//! obstacle that closes in is escaped (its guard asks for a retreat, and
//! the escape may need the joints' speed), and a reserve there turned
//! escapes from a passing ball into stops (`tests/hold_drift.rs`).
//!
//! `J̇_θ q̇` is the second difference of the material point's position
//! along the motion: `(p(q + h q̇) − 2 p(q) + p(q − h q̇)) / h²`.

use glam::DVec3;

use super::GuardPair;
use crate::control_point::DhPoint;
use crate::error::FieldError;
use crate::kinematics::{Frames, Robot};
use crate::skeleton::Skeleton;

/// Time step of the second difference (s).
const H: f64 = 1e-3;

/// The frames a step ahead and behind along the current joint motion.
pub(super) struct Bend {
    ahead: Frames,
    behind: Frames,
}

impl Bend {
    /// The frames at `q ± h q̇`; `None` at rest (no bend).
    pub(super) fn new(robot: &Robot, q: &[f64], qdot: &[f64]) -> Option<Self> {
        if qdot.iter().all(|v| *v == 0.0) || qdot.len() != q.len() {
            return None;
        }
        let at = |s: f64| -> Vec<f64> { q.iter().zip(qdot).map(|(a, v)| a + s * H * v).collect() };
        Some(Self {
            ahead: robot.forward(&at(1.0)).ok()?,
            behind: robot.forward(&at(-1.0)).ok()?,
        })
    }

    /// `J̇_θ q̇` at the point at `fraction` along `segment`.
    fn acceleration(
        &self,
        robot: &Robot,
        frames: &Frames,
        skeleton: &Skeleton,
        (segment, fraction): (usize, f64),
    ) -> Result<DVec3, FieldError> {
        let p = DhPoint::from_skeleton(robot, frames, skeleton, segment, fraction.clamp(0.0, 1.0))?;
        let (a, o, b) = (
            p.position(robot, &self.ahead),
            p.position(robot, frames),
            p.position(robot, &self.behind),
        );
        Ok((a - 2.0 * o + b) / (H * H))
    }

    /// The clearance pair `p` keeps in reserve for the bend of its path
    /// while the joints stop within `braking` seconds (m); relative to the
    /// other point for a self pair.
    pub(super) fn reserve(
        &self,
        robot: &Robot,
        frames: &Frames,
        skeleton: &Skeleton,
        p: &GuardPair,
        braking: f64,
    ) -> Result<f64, FieldError> {
        let mut a = self.acceleration(robot, frames, skeleton, (p.segment, p.fraction))?;
        if let Some(other) = p.other {
            a -= self.acceleration(robot, frames, skeleton, other)?;
        }
        Ok(a.length() * braking * braking / 4.0)
    }
}
