//! Control points described by DH values, and their Jacobians (paper §III-A).
//!
//! A point on link `i` is written `(i, d', a')`: it is the end effector of the
//! "shorter manipulator" obtained by cutting the chain after row `i` and
//! replacing that row's `d_i` by `d'` and `a_i` by `a'` (rows after `i` zeroed).
//! In the standard convention the point is `o_{i-1} + d' z_{i-1} + a' x_i`; in
//! the modified one `o_{i-1} + a' x_{i-1} + d' z_i`. Points on the link's spine
//! have `a' = 0` while `d'` runs over `[0, d_i]`, then `d' = d_i` while `a'`
//! runs over `[0, a_i]` (standard; the modified convention runs `a` first).
//! An extension behind the joint has `a' < 0`.
//!
//! Its velocity is eq. 3 of the paper,
//! `ṗ = J_θ θ̇ + J_a ȧ + J_d ḋ`,
//! where `J_θ` is the ordinary position Jacobian of the shorter manipulator
//! (column `k` zero unless row `k` moves the point), and column `k` of `J_a`
//! (resp. `J_d`) is `∂p/∂a_k` (resp. `∂p/∂d_k`), with the cut values `a'`,
//! `d'` for `k = i`. Every Jacobian is read from one [`Frames`] pass: the cost
//! per control point is one walk up the chain with a cross product per column.
//!
//! A prismatic row `i` stretches its `d` spine: a point at fraction
//! `s = d'/d_i` of it moves with the slide at `s q̇_i` along the row's axis,
//! and a point past the `d` translation (the `a` part, standard convention)
//! moves with the slide entirely. So the own `J_θ` column of a prismatic row
//! is `s z` — continuous along the link, zero at the joint's fixed end, the
//! full axis beyond the slide — and `ḋ'`, like `ȧ'`, is the point's motion
//! relative to the link (at a fixed fraction of the spine). In the modified
//! convention a revolute joint `i` turns about an axis through the point,
//! so its own `J_θ` column is zero.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::error::{FieldError, finite};
use crate::kinematics::{Convention, Frames, JointType, Robot};
use crate::skeleton::{Skeleton, SpinePart};

pub mod clik;

pub use clik::PointMotion;

/// Tolerance (m) when checking that a DH value lies within its link's span
/// and when mapping DH values to the skeleton.
pub const SPAN_TOLERANCE: f64 = 1e-9;

/// A point of the robot described by DH values: link (1-based row) `link`,
/// `d'` and `a'` for that row.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct DhPoint {
    /// 1-based row index.
    pub link: usize,
    /// Cut value of `d` for the row (m).
    pub d: f64,
    /// Cut value of `a` for the row (m).
    pub a: f64,
}

/// One row `(d, a)` of a control point's DH table ([`DhPoint::table`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct DhRow {
    /// `d` of the row (m).
    pub d: f64,
    /// `a` of the row (m).
    pub a: f64,
}

/// Position of a control point and its three Jacobians, each stored as `n`
/// columns of 3-vectors.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PointJacobians {
    /// World position (m).
    pub position: DVec3,
    /// `∂p/∂q`, one column per joint.
    pub j_theta: Vec<DVec3>,
    /// `∂p/∂a_k`, one column per row.
    pub j_a: Vec<DVec3>,
    /// `∂p/∂d_k`, one column per row.
    pub j_d: Vec<DVec3>,
}

/// Time derivatives of the Jacobians of a moving control point, for joint
/// speeds `q̇` (given to [`Robot::forward_with_velocity`]) and DH-value rates
/// `ȧ'`, `ḋ'` of the point's own row.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PointJacobianRates {
    /// Velocity of the point, `J_θ q̇ + J_a ȧ + J_d ḋ` (m/s).
    pub velocity: DVec3,
    /// `dJ_θ/dt`.
    pub j_theta_dot: Vec<DVec3>,
    /// `dJ_a/dt`.
    pub j_a_dot: Vec<DVec3>,
    /// `dJ_d/dt`.
    pub j_d_dot: Vec<DVec3>,
}

/// Range `[lo, hi]` of `d'` on row `link` (1-based) at the configuration of
/// `frames` (prismatic rows: the current `d`).
#[must_use]
pub fn d_span(frames: &Frames, link: usize) -> (f64, f64) {
    let d = frames.d[link - 1];
    (d.min(0.0), d.max(0.0))
}

/// Range `[lo, hi]` of `a'` on row `link`, the extension behind the joint
/// included.
#[must_use]
pub fn a_span(robot: &Robot, link: usize) -> (f64, f64) {
    let j = &robot.joints[link - 1];
    if j.a < 0.0 {
        (j.a, j.extension)
    } else {
        (-j.extension, j.a)
    }
}

/// Range `[lo, hi]` of `d'` on row `link` (1-based) over every
/// configuration: the row's `d` for a revolute joint, the union of the spans
/// the slide reaches within its limits for a prismatic one (unbounded when
/// the slide has no limit).
#[must_use]
pub fn d_reach(robot: &Robot, link: usize) -> (f64, f64) {
    let j = &robot.joints[link - 1];
    match j.kind {
        JointType::Revolute => (j.d.min(0.0), j.d.max(0.0)),
        JointType::Prismatic => ((j.d + j.min).min(0.0), (j.d + j.max).max(0.0)),
    }
}

impl DhPoint {
    /// Checks a point meant to stay on the robot whatever its configuration
    /// (a pinned control point): the link index, finite values, `a'` within
    /// the link's span and `d'` within [`d_reach`] (a prismatic row's `d'`
    /// may lie past the slide's current end; see [`DhPoint::clamped`]).
    ///
    /// # Errors
    /// As [`DhPoint::validate`].
    pub fn validate_reachable(&self, robot: &Robot) -> Result<(), FieldError> {
        self.check(robot, |_| d_reach(robot, self.link), "reach")
    }

    /// The point with `d'` clamped to the row's span at the configuration
    /// of `frames` (a prismatic row retracted past a pinned point brings it
    /// back to the slide's end); `link` must be in range.
    #[must_use]
    pub fn clamped(&self, frames: &Frames) -> Self {
        let (lo, hi) = d_span(frames, self.link);
        Self {
            d: self.d.clamp(lo, hi),
            ..*self
        }
    }

    /// Checks the link index and that `d'`, `a'` are finite and within the
    /// link's span.
    ///
    /// # Errors
    /// `link: 9 is not a link of this robot (links 1 to 7)`, `d: not a finite number`,
    /// `a: 0.5 is outside the link's span [0, 0.3]`.
    pub fn validate(&self, robot: &Robot, frames: &Frames) -> Result<(), FieldError> {
        self.check(robot, |link| d_span(frames, link), "span")
    }

    /// The checks of [`DhPoint::validate`] with `d'` bounded by
    /// `d_range(link)`, named `word` in the message.
    fn check(
        &self,
        robot: &Robot,
        d_range: impl Fn(usize) -> (f64, f64),
        word: &str,
    ) -> Result<(), FieldError> {
        let n = robot.dof();
        if self.link < 1 || self.link > n {
            return Err(FieldError::new(
                "link",
                format!("{} is not a link of this robot (links 1 to {n})", self.link),
            ));
        }
        finite("d", self.d)?;
        finite("a", self.a)?;
        let (lo, hi) = d_range(self.link);
        if self.d < lo - SPAN_TOLERANCE || self.d > hi + SPAN_TOLERANCE {
            return Err(FieldError::new(
                "d",
                format!("{} is outside the link's {word} [{lo}, {hi}]", self.d),
            ));
        }
        let (lo, hi) = a_span(robot, self.link);
        if self.a < lo - SPAN_TOLERANCE || self.a > hi + SPAN_TOLERANCE {
            return Err(FieldError::new(
                "a",
                format!("{} is outside the link's span [{lo}, {hi}]", self.a),
            ));
        }
        Ok(())
    }

    /// The DH table of the point's shorter manipulator (§III-A), `(d, a)`
    /// per row in the robot's row order: the rows that carry link `link`
    /// as they are (`d` with the joint value of a prismatic row), row
    /// `link` cut to `(d', a')`, every other row zero. Fig. 5 of the paper
    /// plots these values over time. No validation: `link` must be in range.
    #[must_use]
    pub fn table(&self, robot: &Robot, frames: &Frames) -> Vec<DhRow> {
        (1..=robot.dof())
            .map(|k| {
                if k == self.link {
                    DhRow {
                        d: self.d,
                        a: self.a,
                    }
                } else if robot.is_ancestor(k, self.link) {
                    DhRow {
                        d: frames.d[k - 1],
                        a: robot.joints[k - 1].a,
                    }
                } else {
                    DhRow { d: 0.0, a: 0.0 }
                }
            })
            .collect()
    }

    /// World position of the point (no validation: `link` must be in range):
    /// the row's start plus `a'` along its `a` direction plus `d'` along its
    /// `d` direction, in either convention.
    #[must_use]
    pub fn position(&self, _robot: &Robot, frames: &Frames) -> DVec3 {
        let i = self.link - 1;
        frames.starts[i].translation + self.a * frames.a_direction[i] + self.d * frames.axis[i]
    }

    /// The point on the skeleton: segment index and fraction along it, or
    /// `None` when the DH values leave the link's spine (both translations
    /// partial) or the link has no segment.
    #[must_use]
    pub fn to_skeleton(
        &self,
        robot: &Robot,
        frames: &Frames,
        skeleton: &Skeleton,
    ) -> Option<(usize, f64)> {
        let i = self.link - 1;
        let joint = robot.joints.get(i)?;
        let d_full = frames.d[i];
        let a_full = joint.a;
        let find = |part: SpinePart| {
            skeleton
                .segments
                .iter()
                .position(|s| s.link == self.link && s.part == part)
        };
        let ratio = |x: f64, full: f64| {
            if full.abs() > 0.0 {
                (x / full).clamp(0.0, 1.0)
            } else {
                0.0
            }
        };
        let on_extension = (a_full >= 0.0 && self.a < -SPAN_TOLERANCE)
            || (a_full < 0.0 && self.a > SPAN_TOLERANCE);
        // The translation that comes first in the row, and the second one.
        let (first_val, first_full, second_val, second_full, first_part, second_part) = match robot
            .convention
        {
            Convention::Standard => (self.d, d_full, self.a, a_full, SpinePart::D, SpinePart::A),
            Convention::Modified => (self.a, a_full, self.d, d_full, SpinePart::A, SpinePart::D),
        };
        if on_extension {
            let complete = match robot.convention {
                Convention::Standard => (self.d - d_full).abs() <= SPAN_TOLERANCE,
                Convention::Modified => self.d.abs() <= SPAN_TOLERANCE,
            };
            let e = joint.extension;
            return if complete {
                find(SpinePart::Extension).map(|s| (s, ratio(self.a.abs(), e)))
            } else {
                None
            };
        }
        if second_val.abs() > SPAN_TOLERANCE {
            if (first_val - first_full).abs() > SPAN_TOLERANCE {
                return None;
            }
            return find(second_part).map(|s| (s, ratio(second_val, second_full)));
        }
        if let Some(s) = find(first_part) {
            return Some((s, ratio(first_val, first_full)));
        }
        find(second_part).map(|s| (s, 0.0))
    }

    /// The DH values of the point at fraction `t ∈ [0, 1]` along skeleton
    /// segment `segment`.
    ///
    /// # Errors
    /// `segment: 12 is not a segment of this skeleton (segments 0 to 10)`, `t: must be within [0, 1]`.
    pub fn from_skeleton(
        robot: &Robot,
        frames: &Frames,
        skeleton: &Skeleton,
        segment: usize,
        t: f64,
    ) -> Result<Self, FieldError> {
        let s = skeleton.segments.get(segment).ok_or_else(|| {
            FieldError::new(
                "segment",
                match skeleton.segments.len() {
                    0 => format!("{segment}: this skeleton has no segments"),
                    n => format!(
                        "{segment} is not a segment of this skeleton (segments 0 to {})",
                        n - 1
                    ),
                },
            )
        })?;
        finite("t", t)?;
        if !(0.0..=1.0).contains(&t) {
            return Err(FieldError::new("t", "must be within [0, 1]"));
        }
        let i = s.link - 1;
        let d_full = frames.d[i];
        let joint = &robot.joints[i];
        let back = if joint.a < 0.0 {
            joint.extension
        } else {
            -joint.extension
        };
        let (d, a) = match (robot.convention, s.part) {
            (Convention::Standard, SpinePart::D) => (t * d_full, 0.0),
            (Convention::Standard, SpinePart::A) => (d_full, t * joint.a),
            (Convention::Standard, SpinePart::Extension) => (d_full, t * back),
            (Convention::Modified, SpinePart::A) => (0.0, t * joint.a),
            (Convention::Modified, SpinePart::D) => (t * d_full, joint.a),
            (Convention::Modified, SpinePart::Extension) => (0.0, t * back),
        };
        Ok(Self { link: s.link, d, a })
    }

    /// Position and Jacobians `J_θ`, `J_a`, `J_d` (no validation: `link` must be
    /// in range).
    #[must_use]
    pub fn jacobians(&self, robot: &Robot, frames: &Frames) -> PointJacobians {
        let mut out = PointJacobians::default();
        self.jacobians_into(robot, frames, &mut out);
        out
    }

    /// [`DhPoint::jacobians`] into existing storage (no allocation once `out`
    /// has the right size). Each column is read from the per-row axes of the
    /// [`Frames`] pass: one cross product per revolute ancestor.
    #[inline(always)]
    pub fn jacobians_into(&self, robot: &Robot, frames: &Frames, out: &mut PointJacobians) {
        let n = robot.dof();
        let p = self.position(robot, frames);
        out.position = p;
        for v in [&mut out.j_theta, &mut out.j_a, &mut out.j_d] {
            if v.len() == n {
                v.fill(DVec3::ZERO);
            } else {
                v.clear();
                v.resize(n, DVec3::ZERO);
            }
        }
        let own = self.link - 1;
        // The point's own row: its joint value is replaced by the cut
        // (prismatic), or its axis passes through the point (modified).
        out.j_a[own] = frames.a_direction[own];
        out.j_d[own] = frames.axis[own];
        match (robot.convention, robot.joints[own].kind) {
            (Convention::Standard, JointType::Revolute) => {
                out.j_theta[own] = frames.axis[own].cross(p - frames.axis_point[own]);
            }
            (_, JointType::Prismatic) => {
                out.j_theta[own] = frames.axis[own] * self.slide_fraction(robot, frames);
            }
            (Convention::Modified, JointType::Revolute) => {}
        }
        let mut k = robot.joints[own].parent;
        while k >= 1 {
            let i = k - 1;
            let u = frames.axis[i];
            out.j_theta[i] = match robot.joints[i].kind {
                JointType::Revolute => u.cross(p - frames.axis_point[i]),
                JointType::Prismatic => u,
            };
            out.j_a[i] = frames.a_direction[i];
            out.j_d[i] = u;
            k = robot.joints[i].parent;
        }
    }

    /// The fraction of a prismatic row's slide that carries the point:
    /// `d'/d_i` on the `d` spine, 1 past it (see the module docs).
    fn slide_fraction(&self, robot: &Robot, frames: &Frames) -> f64 {
        let d_full = frames.d[self.link - 1];
        if d_full.abs() > SPAN_TOLERANCE {
            (self.d / d_full).clamp(0.0, 1.0)
        } else if robot.convention == Convention::Standard {
            1.0
        } else {
            0.0
        }
    }

    /// `ṡ = ḋ'/d_i`, the rate of the fraction `s` of its own prismatic
    /// column `s z` the point slides along (0 off the column's span).
    fn slide_rate(&self, frames: &Frames, d_rate: f64) -> f64 {
        let d_full = frames.d[self.link - 1];
        if d_full.abs() > SPAN_TOLERANCE && (0.0..=1.0).contains(&(self.d / d_full)) {
            d_rate / d_full
        } else {
            0.0
        }
    }

    /// Time derivatives of the Jacobians for a point whose own DH values move
    /// at `a_rate = ȧ'` and `d_rate = ḋ'`, the robot moving at the `q̇` given to
    /// [`Robot::forward_with_velocity`].
    ///
    /// # Errors
    /// `qdot: frames were computed without joint velocities` when `frames`
    /// carry no velocities; a non-finite rate.
    pub fn jacobian_rates(
        &self,
        robot: &Robot,
        frames: &Frames,
        a_rate: f64,
        d_rate: f64,
    ) -> Result<PointJacobianRates, FieldError> {
        if !frames.has_velocity() {
            return Err(FieldError::new(
                "qdot",
                "frames were computed without joint velocities",
            ));
        }
        finite("aRate", a_rate)?;
        finite("dRate", d_rate)?;
        let jac = self.jacobians(robot, frames);
        let n = robot.dof();
        let i_own = self.link - 1;
        let mut pdot = jac.j_a[i_own] * a_rate + jac.j_d[i_own] * d_rate;
        for (c, qd) in jac.j_theta.iter().zip(&frames.qdot) {
            pdot += *c * *qd;
        }
        let p = jac.position;
        let s_rate = self.slide_rate(frames, d_rate);
        let fraction = self.slide_fraction(robot, frames);
        let own_slide = |z: DVec3, zdot: DVec3| zdot * fraction + z * s_rate;
        let mut out = PointJacobianRates {
            velocity: pdot,
            j_theta_dot: vec![DVec3::ZERO; n],
            j_a_dot: vec![DVec3::ZERO; n],
            j_d_dot: vec![DVec3::ZERO; n],
        };
        let mut k = self.link;
        while k >= 1 {
            let i = k - 1;
            let joint = &robot.joints[i];
            let s = &frames.starts[i];
            let f = &frames.transforms[k];
            let w_s = frames.omega[joint.parent];
            let v_s = frames.velocity[joint.parent];
            let w_k = frames.omega[k];
            let own = k == self.link;
            match robot.convention {
                Convention::Standard => {
                    let z = s.matrix3.z_axis;
                    let zdot = w_s.cross(z);
                    out.j_theta_dot[i] = match joint.kind {
                        JointType::Revolute => zdot.cross(p - s.translation) + z.cross(pdot - v_s),
                        JointType::Prismatic if own => own_slide(z, zdot),
                        JointType::Prismatic => zdot,
                    };
                    out.j_a_dot[i] = w_k.cross(f.matrix3.x_axis);
                    out.j_d_dot[i] = zdot;
                }
                Convention::Modified => {
                    let z = f.matrix3.z_axis;
                    let zdot = w_k.cross(z);
                    out.j_theta_dot[i] = match joint.kind {
                        JointType::Prismatic if own => own_slide(z, zdot),
                        _ if own => DVec3::ZERO,
                        JointType::Revolute => {
                            let m = frames.mids[i];
                            let v_m = v_s + w_s.cross(m - s.translation);
                            zdot.cross(p - m) + z.cross(pdot - v_m)
                        }
                        JointType::Prismatic => zdot,
                    };
                    out.j_a_dot[i] = w_s.cross(s.matrix3.x_axis);
                    out.j_d_dot[i] = zdot;
                }
            }
            k = joint.parent;
        }
        Ok(out)
    }
}
