//! The *protect* stage: a protective layer beneath the repulsion.
//!
//! Repulsion acts at the selected control points and only shapes the
//! motion. Underneath it, every skeleton–obstacle pair within the influence
//! distance — selected or not, travelling control point or not — carries a
//! hard bound on how fast the arm may close the gap (a *guard*):
//!
//! `nᵀ J_θ q̇ ≤ (d − d_s − v_h (T_r + T_s)) / (T_r + m T_s / 2)`
//!
//! where `n` is the unit direction from the arm towards the obstacle at the
//! pair's witness, `J_θ` the position Jacobian of that (material) point,
//! `d` the clearance (sensing margin subtracted), `d_s` the safety distance,
//! `v_h` the obstacle's own approach speed, `T_r` the reaction time and
//! `T_s` the time the joints need to stop from their current motion within
//! their acceleration and jerk limits ([`super::limits::braking_time`]),
//! with a margin `m` ([`BRAKING_MARGIN`]).
//!
//! This is the velocity damper of Faverjon & Tournassoud (the form QP
//! controllers such as NEO use), with its gain chosen so that the distance
//! the arm still covers while stopping — `v (T_r + T_s/2)` for a
//! deceleration that is linear in time — plus what the obstacle covers
//! meanwhile — `v_h (T_r + T_s)` — never exceeds the clearance: the
//! protective separation distance of ISO/TS 15066 speed and separation
//! monitoring, `S_p = v_h (T_r + T_s) + v_r T_r + B + d_s`. As `d → d_s` the
//! allowed approach speed goes to zero, so contact can only begin with the
//! arm at rest. A negative bound (the obstacle closes in faster than the
//! clearance allows) asks the arm to retreat.
//!
//! Self-collision pairs bound the approach of two points of the arm, with
//! the row `nᵀ (J_θ,a − J_θ,b)`.
//!
//! [`project`] finds the joint velocity closest (in the metric of the joint
//! weights `W`) to the controller's command that satisfies every guard and
//! the admissible velocity box, by Hildreth's dual coordinate ascent — a
//! small dense QP with one dual variable per guard, no allocation beyond
//! the caller's buffers. When the guards cannot all be met (the arm cannot
//! retreat fast enough, or two obstacles squeeze it) the result says which
//! guard is violated, and the world stops the arm ([`super`]'s
//! `unavoidable` event). Squeezed between still obstacles only (an arm
//! that starts overlapping one box and within the safety distance of
//! another), the arm first tries to hold its ground instead: every still
//! obstacle's demand to retreat becomes a bound of zero, so the arm closes
//! in on none and may slide out along them; it stops only if even that
//! cannot be met.
//!
//! The guards bound the arm's *approach*; its *speed* is bounded too, so
//! that a stop decided at any moment still ends before an obstacle closing
//! in at `v_h` arrives: every joint's speed is capped to what it can shed
//! within `(d − d_s) / v_h − T_r` ([`super::limits::cap_for_stop_time`],
//! the world's `stop_time`), whatever the arm is doing. An escape from an
//! obstacle that appeared next to the arm therefore never outruns its own
//! stop: without the cap, the Panda escaping a ball that appeared 4.5 cm
//! from its elbow reached 1.66 rad/s, ran out of room, and was still
//! braking when the ball arrived; with it the arm slows as the ball comes
//! and is at rest 13 mm before contact.
//!
//! The guards bound the *requested* velocity; the joints reach it within
//! their acceleration limits. Should the arm's actual approach speed still
//! exceed a guard ([`Guard::breached`]), the world brakes at once with every
//! joint at its full deceleration (the emergency brake of the limiter,
//! not synchronised) until the guards hold again.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::control_point::{DhPoint, PointJacobians};
use crate::error::{FieldError, non_negative};
use crate::kinematics::{Frames, Robot};
use crate::skeleton::Skeleton;

mod bounds;
mod curvature;
pub mod pfl;
mod project;

pub use bounds::{GuardContext, Protection, admissible_box, prepare, protect, stop_time};
pub use curvature::Bend;
pub use pfl::BodyRegion;
pub use project::{Projection, project};

/// Settings of the protective layer (scenario field
/// `controller.protective`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields, default)]
pub struct ProtectiveConfig {
    /// Whether the guards are enforced (default true).
    pub enabled: bool,
    /// Safety distance `d_s` kept at rest (m, ≥ 0; default 0.01).
    pub safety_distance: f64,
    /// Reaction time `T_r` of sensing and control (s, ≥ 0; default 0.01).
    pub reaction_time: f64,
    /// Speed at which the arm backs out of a static or receding obstacle
    /// it overlaps or is closer to than the safety distance (m/s, > 0;
    /// default 0.05): the guard asks for no faster retreat than this.
    pub withdraw_speed: f64,
    /// `ssm` (default: speed and separation monitoring, contact only at
    /// rest) or `pfl` (power and force limiting: a human's part may be
    /// touched at its body region's permissible speed, [`pfl`]).
    pub mode: ProtectiveMode,
}

/// The protective mode (`controller.protective.mode`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub enum ProtectiveMode {
    /// Speed and separation monitoring (default).
    #[default]
    Ssm,
    /// Power and force limiting (ISO/TS 15066 Annex A) where the body
    /// region allows transient contact, separation monitoring elsewhere.
    Pfl,
}

impl Default for ProtectiveConfig {
    fn default() -> Self {
        Self {
            enabled: true,
            safety_distance: 0.01,
            reaction_time: 0.01,
            withdraw_speed: 0.05,
            mode: ProtectiveMode::Ssm,
        }
    }
}

impl ProtectiveConfig {
    /// Checks every value.
    ///
    /// # Errors
    /// `protective.safetyDistance: must be >= 0`, …
    pub fn validate(&self) -> Result<(), FieldError> {
        non_negative("protective.safetyDistance", self.safety_distance)?;
        non_negative("protective.reactionTime", self.reaction_time)?;
        crate::error::positive("protective.withdrawSpeed", self.withdraw_speed)?;
        Ok(())
    }

    /// The largest approach speed of the arm (m/s) at clearance `distance`
    /// when the obstacle itself approaches at `obstacle_speed` and the
    /// joints need `braking` seconds to stop.
    #[must_use]
    pub fn bound(&self, distance: f64, obstacle_speed: f64, braking: f64) -> f64 {
        let reach = self.reaction_time + braking;
        let room = distance - self.safety_distance - obstacle_speed.max(0.0) * reach;
        room / (self.reaction_time + BRAKING_MARGIN * 0.5 * braking).max(1e-3)
    }
}

/// Factor on the braking distance `v T_s / 2` in the guards: the limiter
/// approaches a new command along a straight line in joint space, which
/// reduces a pair's approach speed more slowly than a dedicated stop would;
/// doubling the budget keeps the guards ahead of that lag (measured on the
/// shipped examples and the approach sweep of `tests/motion_limits.rs`).
pub const BRAKING_MARGIN: f64 = 2.0;

/// One bound `row · q̇ ≤ bound` on the approach of a pair.
#[derive(Clone, Debug, PartialEq)]
pub struct Guard {
    /// `nᵀ J_θ` (one value per joint).
    pub row: Vec<f64>,
    /// Largest approach speed the arm may have and still stop in time
    /// (m/s): the protective bound, hard.
    pub bound: f64,
    /// The avoidance damper's bound (m/s; `+∞` without one): the
    /// `constraints` avoidance asks for `min(bound, soft)` and falls back
    /// to `bound` alone when both cannot be met.
    pub soft: f64,
    /// Clearance of the pair (m).
    pub distance: f64,
    /// Approach speed of the obstacle itself (m/s).
    pub obstacle_speed: f64,
    /// Skeleton segment of the pair.
    pub segment: usize,
    /// Obstacle index (`None` for a self-collision pair).
    pub obstacle: Option<usize>,
}

impl Default for Guard {
    fn default() -> Self {
        Self {
            row: Vec::new(),
            bound: 0.0,
            soft: f64::INFINITY,
            distance: 0.0,
            obstacle_speed: 0.0,
            segment: 0,
            obstacle: None,
        }
    }
}

/// The velocity damper of the `constraints` avoidance (Faverjon &
/// Tournassoud; NEO's form): the arm may approach a pair at clearance `d`
/// at most at `gain · (d − band') / (influence − band')` less the
/// obstacle's own approach speed, and is pushed away (at most at `gain`)
/// below the band or when the obstacle closes in faster than that.
///
/// `band' = band + v · DAMPER_HEADWAY` (at most halfway to the influence
/// distance): an obstacle closing in at `v` is kept [`DAMPER_HEADWAY`]
/// further away than a still one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Damper {
    /// Approach speed allowed at the influence distance (m/s).
    pub gain: f64,
    /// Clearance below which the arm is pushed away (m).
    pub band: f64,
    /// Influence distance (m).
    pub influence: f64,
}

/// Time headway of the velocity damper (s): the damper settles a pair
/// whose obstacle closes in at `v` at `band + v · DAMPER_HEADWAY` instead
/// of the band.
///
/// Without it a pair settles at the band whatever the obstacle's speed, so
/// an obstacle pressing on at 0.25 m/s leaves `(band − safetyDistance) / v`
/// ≈ 40 ms until the safety distance; the stop time caps every joint's
/// speed to what it can shed in that time
/// ([`super::limits::cap_for_stop_time`]), the null-space motion that was
/// keeping a held end effector in place no longer fits in the box, and the
/// end effector gives way, then the arm stops and is run into. 0.1 s keeps
/// the box open at the speeds of a person's arm (measured in
/// `crate/tests/hold_drift.rs`: the Panda holding its flange while a ball
/// is driven at its elbow at 0.25 m/s drifted 5.2 mm and stopped before a
/// contact at rest; with the headway it drifts 0.05 mm and stays 3 cm
/// clear). A still obstacle (the reach problems' boxes) is unaffected.
pub const DAMPER_HEADWAY: f64 = 0.1;

impl Damper {
    /// The damper's bound on the arm's approach speed (m/s).
    #[must_use]
    pub fn bound(&self, distance: f64, obstacle_speed: f64) -> f64 {
        let v = obstacle_speed.max(0.0);
        let band = (self.band + v * DAMPER_HEADWAY).min(0.5 * (self.influence + self.band));
        let span = (self.influence - band).max(1e-9);
        let x = (distance - band) / span;
        let b = self.gain * x - v * (1.0 - x).min(1.0);
        b.max(-self.gain)
    }
}

/// One pair as the guards need it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GuardPair {
    /// Skeleton segment and fraction along it of the arm's witness.
    pub segment: usize,
    /// Fraction along the segment.
    pub fraction: f64,
    /// The other side on the arm (self-collision): segment and fraction.
    pub other: Option<(usize, f64)>,
    /// Unit direction from the arm towards the other side.
    pub normal: DVec3,
    /// Clearance (m).
    pub distance: f64,
    /// Approach speed of the obstacle itself (m/s, ≥ 0 when closing in).
    pub obstacle_speed: f64,
    /// Obstacle index.
    pub obstacle: Option<usize>,
    /// Index of the obstacle's part in the scene (a human's hand, …).
    pub part: Option<usize>,
    /// In `pfl`: the body region of a human's part at the witness that
    /// allows transient contact, and its permissible speed there.
    pub contact: Option<ContactLimit>,
}

/// What power and force limiting allows a pair ([`pfl`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ContactLimit {
    /// The body region at the witness.
    pub region: BodyRegion,
    /// The arm's effective mass at the witness towards the part (kg).
    pub arm_mass: f64,
    /// The permissible relative speed of a transient contact (m/s).
    pub speed: f64,
}

impl GuardPair {
    /// The bound power and force limiting allows the arm's approach (the
    /// permissible speed less the part's own approach), if any.
    #[must_use]
    pub fn contact_bound(&self) -> Option<f64> {
        self.contact.map(|c| c.speed - self.obstacle_speed.max(0.0))
    }
}

/// The Jacobians of the arm's point at `fraction` along skeleton segment
/// `segment`, into `out`.
pub(crate) fn jacobian_at(
    robot: &Robot,
    frames: &Frames,
    skeleton: &Skeleton,
    segment: usize,
    fraction: f64,
    out: &mut PointJacobians,
) -> Result<(), FieldError> {
    let p = DhPoint::from_skeleton(robot, frames, skeleton, segment, fraction.clamp(0.0, 1.0))?;
    p.jacobians_into(robot, frames, out);
    Ok(())
}

/// How the guards of one step bound their pairs ([`guards`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GuardBounds {
    /// The protective layer's settings.
    pub config: ProtectiveConfig,
    /// The joints' stopping time now (s).
    pub braking: f64,
    /// The lowest bound asked for (e.g. 0 during a stop: a stopping arm is
    /// not asked to retreat).
    pub floor: f64,
    /// The damper of the `constraints` avoidance, if any.
    pub damper: Option<Damper>,
}

impl GuardBounds {
    /// The protective bound and the damper's bound (`+∞` without a
    /// damper) of pair `p`, both at least `floor`; a static or receding
    /// obstacle asks for no retreat faster than `withdraw_speed`.
    fn of(&self, p: &GuardPair, reserve: f64) -> (f64, f64) {
        let config = self.config;
        let mut bound = config.bound(p.distance - reserve, p.obstacle_speed, self.braking);
        if p.obstacle_speed <= 0.0 {
            bound = bound.max(-config.withdraw_speed);
        }
        if let Some(allowed) = p.contact_bound() {
            bound = bound.max(allowed);
        }
        let bound = bound.max(self.floor);
        let soft = self.damper.as_ref().map_or(f64::INFINITY, |d| {
            d.bound(p.distance, p.obstacle_speed).max(self.floor)
        });
        (bound, soft)
    }
}

/// The row of pair `p` into `row`: `nᵀ J_θ` at the arm's witness, less
/// `nᵀ J_θ,b` at the other side of a self pair (`jacobians` are scratch).
fn pair_row(
    ctx: &GuardContext,
    p: &GuardPair,
    jacobians: (&mut PointJacobians, &mut PointJacobians),
    row: &mut Vec<f64>,
) -> Result<(), FieldError> {
    let (robot, frames, skeleton) = (ctx.robot, ctx.frames, ctx.skeleton);
    let (ja, jb) = jacobians;
    jacobian_at(robot, frames, skeleton, p.segment, p.fraction, ja)?;
    row.clear();
    row.extend(ja.j_theta.iter().map(|c| p.normal.dot(*c)));
    if let Some((seg, t)) = p.other {
        jacobian_at(robot, frames, skeleton, seg, t, jb)?;
        for (r, c) in row.iter_mut().zip(&jb.j_theta) {
            *r -= p.normal.dot(*c);
        }
    }
    Ok(())
}

/// The guard of every pair (see the module docs), into `out`.
///
/// A static or receding obstacle (and a self pair) never asks for a
/// retreat faster than `withdraw_speed`: the arm backs out of an overlap
/// at that speed instead of being asked the impossible. With a damper,
/// each pair's [`Damper`] bound is [`Guard::soft`]. `ctx` gives the robot,
/// its frames and its skeleton; `bend` keeps the frames of the bend
/// reserve's second difference from call to call.
///
/// # Errors
/// A pair whose segment is not in the skeleton (a bug).
pub fn guards(
    ctx: &GuardContext,
    pairs: &[GuardPair],
    bounds: &GuardBounds,
    out: &mut Vec<Guard>,
    bend: &mut Bend,
) -> Result<(), FieldError> {
    let robot = ctx.robot;
    // The guards of the last call are written over (their rows' buffers
    // reused: no allocation per pair and step once the count is reached).
    let mut used = 0;
    let mut ja = PointJacobians::default();
    let mut jb = PointJacobians::default();
    let mut row = Vec::with_capacity(robot.dof());
    let moving = bend.update(robot, ctx.q, &ctx.motion.qdot);
    let safety = bounds.config.safety_distance;
    let escaping = pairs.iter().any(|p| p.distance <= safety);
    for p in pairs {
        if let Err(e) = pair_row(ctx, p, (&mut ja, &mut jb), &mut row) {
            out.truncate(used);
            return Err(e);
        }
        // The bend of the arm's own path towards a still (or receding)
        // obstacle; an obstacle closing in is escaped, at speed if need be.
        let reserve = if moving && p.obstacle_speed <= 0.0 {
            bend.reserve(robot, ctx.frames, ctx.skeleton, p, bounds.braking)?
        } else {
            0.0
        };
        if !escaping && p.other.is_none() && p.contact.is_none() {
            bend.cap(reserve, p.distance - safety, bounds.braking);
        }
        let (bound, soft) = bounds.of(p, reserve);
        // A guard the joints cannot reach within their speed limits can
        // never be active, and one no joint can act on cannot be helped:
        // leave both out of the QP.
        let reach: f64 = row
            .iter()
            .zip(&robot.joints)
            .map(|(r, j)| r.abs() * j.max_velocity)
            .sum();
        if bound.min(soft) >= reach || reach <= 1e-9 {
            continue;
        }
        let guard = Guard {
            row: Vec::new(),
            bound,
            soft,
            distance: p.distance,
            obstacle_speed: p.obstacle_speed,
            segment: p.segment,
            obstacle: p.obstacle,
        };
        if let Some(g) = out.get_mut(used) {
            let mut buffer = std::mem::take(&mut g.row);
            buffer.clear();
            buffer.extend_from_slice(&row);
            *g = Guard {
                row: buffer,
                ..guard
            };
        } else {
            out.push(Guard {
                row: row.clone(),
                ..guard
            });
        }
        used += 1;
    }
    out.truncate(used);
    Ok(())
}

impl Guard {
    /// Whether the arm's current approach speed, with joint velocities
    /// `qdot`, exceeds this guard's bound.
    #[must_use]
    pub fn breached(&self, qdot: &[f64]) -> bool {
        let v = self.approach(qdot);
        v > 0.0 && v > self.bound + GUARD_TOLERANCE
    }

    /// Whether the arm can still get away from this guard's obstacle, and
    /// the retreat to ask for: `Some(bound)` when the fastest retreat along
    /// the row within the velocity box `lo..hi` outruns the obstacle (with
    /// a 20 % margin) and the gap the arm loses while it turns its current
    /// approach into that retreat — at half its acceleration limits along
    /// the row, after `reaction_time` — is under 80 % of the room left
    /// above the safety distance; `None` when no admissible escape keeps
    /// the arm clear (the world then stops: contact at rest).
    #[must_use]
    pub fn escape(
        &self,
        robot: &Robot,
        qdot: &[f64],
        lo: &[f64],
        hi: &[f64],
        config: &ProtectiveConfig,
    ) -> Option<f64> {
        let mut speed = 0.0;
        let mut accel = 0.0;
        for (k, r) in self.row.iter().enumerate() {
            let room = if *r > 0.0 { -lo[k] } else { hi[k] };
            speed += r.abs() * room.max(0.0);
            accel += 0.5 * r.abs() * robot.joints[k].max_acceleration;
        }
        let v_h = self.obstacle_speed.max(0.0);
        if v_h >= 0.8 * speed || accel <= 0.0 {
            return None;
        }
        let closing = (self.approach(qdot) + v_h).max(0.0);
        let lost = closing * config.reaction_time + closing * closing / (2.0 * accel);
        let room = self.distance - config.safety_distance;
        (lost < 0.8 * room).then_some(self.bound.max(-0.9 * speed))
    }

    /// The pair's approach speed (m/s) with joint velocities `qdot`.
    #[must_use]
    pub fn approach(&self, qdot: &[f64]) -> f64 {
        self.row.iter().zip(qdot).map(|(r, q)| r * q).sum()
    }
}

/// Tolerance on a guard (m/s).
pub const GUARD_TOLERANCE: f64 = 1e-9;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_damper_keeps_a_closing_obstacle_a_headway_further() {
        let d = Damper {
            gain: 0.5,
            band: 0.02,
            influence: 0.3,
        };
        // A still obstacle: zero at the band, the gain at the influence.
        assert!(d.bound(0.02, 0.0).abs() < 1e-12);
        assert!((d.bound(0.3, 0.0) - 0.5).abs() < 1e-12);
        // Closing in at 0.25 m/s: the arm keeps pace 2.5 cm further out.
        let settled = 0.02 + 0.25 * DAMPER_HEADWAY;
        assert!((d.bound(settled, 0.25) + 0.25).abs() < 1e-12);
        assert!((d.bound(0.3, 0.25) - 0.5).abs() < 1e-12);
        // Never past halfway to the influence distance.
        assert!((d.bound(0.16, 5.0) + 0.5).abs() < 1e-12);
    }

    #[test]
    fn bound_vanishes_at_the_safety_distance() {
        let c = ProtectiveConfig::default();
        assert!(c.bound(c.safety_distance, 0.0, 0.2).abs() < 1e-12);
        assert!(c.bound(0.1, 0.0, 0.2) > 0.0);
        assert!(c.bound(0.1, 0.5, 0.2) < c.bound(0.1, 0.0, 0.2));
        assert!(c.bound(0.005, 0.0, 0.2) < 0.0);
    }
}
