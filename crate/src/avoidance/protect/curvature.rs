//! The bend of a pair's path while the arm brakes: how far the witness's
//! path may curve towards the obstacle, beyond the straight line the
//! first-order guard `nᵀ J_θ q̇` sees, before the joints stop.
//!
//! With the joints turning at `q̇` the witness accelerates by `J̇_θ q̇` even
//! at constant joint speeds (the centripetal and Coriolis terms of a
//! turning chain). The guard keeps `|J̇_θ q̇| T_s²` of clearance in
//! reserve, `T_s` the joints' stop time now:
//! * held at constant speed for `T_s` the bend alone moves the point by
//!   `|J̇_θ q̇| T_s² / 2`; braked to rest at once, by a quarter of it
//!   (`∫₀^T ∫₀^t a (1 − s/T)² ds dt = a T² / 4`);
//! * but the joints do not brake at once: the QP's velocity is reached
//!   through the limiter at the acceleration limits, so while the guard
//!   binds the joints may still be gaining speed, and the bend grows with
//!   their square. On NEO's PR2 problem bookshelf 21 the gripper slid along
//!   a box 11 mm off while the wrist roll sped up from 2.0 to 2.6 rad/s
//!   after the quarter-size reserve had passed that clearance; it touched
//!   the box 0.11 s later at 0.14 m/s. With `T_s² / 4` and `T_s² / 2` it
//!   touches, with `T_s²` it does not (and no other PR2 or
//!   MotionBenchMaker run touches while moving; the same strict successes).
//!
//! The reserve is negligible at ordinary speeds (1 rad/s on a 0.5 m chain:
//! 0.5 m/s², 5 mm for a 0.1 s stop) and grows with the fourth power of the
//! joint speed: before it, the gripper closed on a box at 0.36 m/s while
//! the arm braked from 3.3 rad/s (PR2 industrial B 41), the approach speed
//! rising from 0.11 m/s as the chain turned.
//!
//! A self pair keeps a quarter of it (`a T_s² / 4` of the two points'
//! relative bend, the stop begun at once): both points ride the same
//! chain, and with the full reserve a self pair at 32 mm asked the Panda
//! for a retreat it could not make while it backed out of a box it
//! started inside, and the arm stopped (`tests/avoid_escape.rs`).
//!
//! Only pairs whose obstacle does not close in keep the reserve: an
//! obstacle that closes in is escaped (its guard asks for a retreat, and
//! the escape may need the joints' speed), and a reserve there turned
//! escapes from a passing ball into stops (`tests/hold_drift.rs`).
//!
//! A reserve alone cannot slow the arm's sideways motion, which is what
//! bends its path: the guard only bounds the approach along the normal.
//! On MotionBenchMaker's box 31 the paper's repulsion had run the Panda at
//! 5.2 rad/s (norm of `q̇`) sideways past a box 38 mm off; the reserve
//! there exceeded the room and the guard asked for a retreat, but braking
//! from that speed took 50 steps and the path curved onto the box
//! meanwhile (−0.11 mm). So a reserve larger than its room also caps the
//! joints' stop time ([`Bend::cap`]), which caps their speeds through the
//! admissible velocity box. Not while the arm backs out of an overlap
//! (the escape comes first), not for a self pair, and not for a pair that
//! power and force limiting lets touch.
//!
//! `J̇_θ q̇` is the second difference of the material point's position
//! along the motion: `(p(q + h q̇) − 2 p(q) + p(q − h q̇)) / h²`.

use glam::DVec3;

use super::GuardPair;
use crate::control_point::DhPoint;
use crate::error::FieldError;
use crate::kinematics::{Frames, Robot};
use crate::skeleton::Skeleton;

/// The share of the reserve a self pair keeps (see the module docs).
const SELF_PAIR_SHARE: f64 = 0.25;

/// Time step of the second difference (s).
const H: f64 = 1e-3;

/// The frames a step ahead and behind along the current joint motion,
/// kept from step to step so that computing them allocates nothing once
/// the storage is there.
#[derive(Clone, Debug)]
pub struct Bend {
    ahead: Frames,
    behind: Frames,
    shifted: Vec<f64>,
    /// The stop time within which the joints must be able to stop for the
    /// reserves to fit their room (s; `∞`: no such cap), see the module docs.
    pub stop_time: f64,
}

impl Default for Bend {
    fn default() -> Self {
        Self {
            ahead: Frames::default(),
            behind: Frames::default(),
            shifted: Vec::new(),
            stop_time: f64::INFINITY,
        }
    }
}

impl Bend {
    /// Computes the frames at `q ± h q̇`; `false` at rest (no bend) or for
    /// a `q` the robot refuses.
    pub(super) fn update(&mut self, robot: &Robot, q: &[f64], qdot: &[f64]) -> bool {
        self.stop_time = f64::INFINITY;
        if qdot.iter().all(|v| *v == 0.0) || qdot.len() != q.len() {
            return false;
        }
        for s in [1.0, -1.0] {
            self.shifted.clear();
            self.shifted
                .extend(q.iter().zip(qdot).map(|(a, v)| a + s * H * v));
            let frames = if s > 0.0 {
                &mut self.ahead
            } else {
                &mut self.behind
            };
            if robot.forward_into(&self.shifted, frames).is_err() {
                return false;
            }
        }
        true
    }

    /// Lowers [`Bend::stop_time`] for a pair whose `reserve` (m, over a
    /// stop of `braking` s) exceeds its `room` (clearance less the safety
    /// distance, m): the bend grows with the square of the joint speeds and
    /// the stop time with their first power, so capping the stop time at
    /// `T_s (room / 2 reserve)^¼` brings the reserve down to half the room.
    pub(super) fn cap(&mut self, reserve: f64, room: f64, braking: f64) {
        if room > 0.0 && reserve > room {
            let t = braking * (room / (2.0 * reserve)).powf(0.25);
            self.stop_time = self.stop_time.min(t);
        }
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
        let a = self.acceleration(robot, frames, skeleton, (p.segment, p.fraction))?;
        Ok(match p.other {
            None => a.length() * braking * braking,
            Some(other) => {
                let relative = a - self.acceleration(robot, frames, skeleton, other)?;
                relative.length() * braking * braking * SELF_PAIR_SHARE
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinematics::presets::preset;

    /// The planar arm's tip, only the first joint turning at `ω`: the bend
    /// is the centripetal `ω² r` (r = 0.9 m, the links in line), and the
    /// reserve `ω² r T_s²`.
    #[test]
    fn the_reserve_is_the_centripetal_bend_over_the_stop_time_squared() -> Result<(), FieldError> {
        let robot = Robot::from_spec(&preset("planar3")?)?;
        let q = [0.3, 0.0, 0.0];
        let frames = robot.forward(&q)?;
        let skeleton = Skeleton::build(&robot, &frames);
        let last = skeleton.segments.len() - 1;
        let pair = GuardPair {
            segment: last,
            fraction: 1.0,
            other: None,
            normal: DVec3::X,
            distance: 0.05,
            obstacle_speed: 0.0,
            obstacle: Some(0),
            part: None,
            contact: None,
        };
        let omega = 2.0;
        let mut bend = Bend::default();
        if !bend.update(&robot, &q, &[omega, 0.0, 0.0]) {
            return Err(FieldError::new("q", "at rest"));
        }
        let braking = 0.2;
        let reserve = bend.reserve(&robot, &frames, &skeleton, &pair, braking)?;
        let expected = omega * omega * 0.9 * braking * braking;
        assert!(
            (reserve - expected).abs() < 1e-6 * expected,
            "{reserve} vs {expected}"
        );
        // At rest there is no bend.
        assert!(!bend.update(&robot, &q, &[0.0; 3]));
        Ok(())
    }
}
