//! Standard DH parameters of a serial chain given by its joint axes at the
//! zero configuration (the classical construction of Siciliano et al.,
//! §2.8.2): frame `i` has `z_i` along the axis of joint `i + 1`, `x_i` along
//! the common normal from axis `i` to axis `i + 1`, and its origin where that
//! normal meets axis `i + 1`.
//!
//! Where the construction leaves a choice, it is made so that the skeleton
//! runs through the joint origins of the URDF:
//! - frame 0 starts at the foot of the base link's origin on axis 1;
//! - parallel axes: the common normal passes through the joint origin of the
//!   first of the two (the UR shoulder and elbow offsets become `d`);
//! - coincident axes: `x_i = x_{i-1}`, the normal at the joint origin;
//! - intersecting axes: `x_i = z_{i-1} × z_i`, `a_i = 0`;
//! - the last frame: `z_n = z_{n-1}`, its origin at the tip's origin, with
//!   `x_n` towards it (or along the tip's x axis when the tip is on axis n);
//!   the tool transform is whatever remains.
//!
//! The URDF reader ([`crate::parsers::urdf`]) gives the axes; this module
//! knows nothing of files.

use glam::{DAffine3, DMat3, DVec3};

use crate::math;

/// Axes closer to parallel than this (sine of the angle) are treated as
/// parallel: the rounding of π/2 in published URDFs (`1.5708`) tilts axes
/// meant to be parallel by a few µrad, and the exact common normal of such
/// axes lies kilometres away. The model then differs from the URDF by at most
/// this angle times the link length.
pub const PARALLEL_TOLERANCE: f64 = 1e-5;

/// Axes whose common normal is shorter than this (m) are treated as
/// intersecting.
pub const INTERSECT_TOLERANCE: f64 = 1e-10;

/// A joint axis at the zero configuration, in the base link's frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisLine {
    /// The joint origin (a point of the axis, m).
    pub point: DVec3,
    /// Unit direction: positive joint values turn (or slide) along it.
    pub direction: DVec3,
}

/// One DH row before the joint value: `theta` and `d` are the offsets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DhRow {
    /// Link length `a` (m).
    pub a: f64,
    /// Link twist `α` (rad).
    pub alpha: f64,
    /// Link offset `d` (m).
    pub d: f64,
    /// Joint angle `θ` (rad).
    pub theta: f64,
}

/// A DH frame at the zero configuration: origin and x, z axes (unit).
#[derive(Clone, Copy, Debug)]
struct Frame {
    origin: DVec3,
    x: DVec3,
    z: DVec3,
}

/// The DH table of a chain: rows and the pose of frame 0 in the base link.
#[derive(Clone, Debug)]
pub struct DhChain {
    /// Frame 0 in the base link's frame.
    pub base: DAffine3,
    /// One row per axis.
    pub rows: Vec<DhRow>,
}

/// A unit vector perpendicular to unit `z`, as close as possible to `hint`
/// (falls back to the base x, then y axis).
fn perpendicular(z: DVec3, hints: &[DVec3]) -> DVec3 {
    for h in hints.iter().chain([DVec3::X, DVec3::Y].iter()) {
        let v = *h - z * h.dot(z);
        if v.length() > 1e-6 {
            return v.normalize();
        }
    }
    z.any_orthonormal_vector()
}

/// The foot of `p` on the line through `o` along unit `z`.
fn foot(p: DVec3, o: DVec3, z: DVec3) -> DVec3 {
    o + z * (p - o).dot(z)
}

/// The next frame from frame `prev` (whose z is the current axis) and the
/// next axis; returns the frame and the foot `N` on the current axis.
fn next_frame(prev: &Frame, joint_point: DVec3, next: &AxisLine) -> (Frame, DVec3) {
    let z0 = prev.z;
    let cross = z0.cross(next.direction);
    if cross.length() <= PARALLEL_TOLERANCE {
        // Parallel (or coincident): the normal through this joint's origin;
        // the next axis is made exactly parallel.
        let z1 = if z0.dot(next.direction) >= 0.0 {
            z0
        } else {
            -z0
        };
        let n = foot(joint_point, prev.origin, z0);
        let o1 = foot(n, next.point, z1);
        let diff = o1 - n;
        let x = if diff.length() > INTERSECT_TOLERANCE {
            diff.normalize()
        } else {
            prev.x
        };
        return (
            Frame {
                origin: n + x * diff.dot(x),
                x,
                z: z1,
            },
            n,
        );
    }
    let z1 = next.direction;
    // Closest points of the two lines: prev.origin + s z0 and next.point + t z1.
    let w = prev.origin - next.point;
    let b = z0.dot(z1);
    let (d, e) = (z0.dot(w), z1.dot(w));
    let denom = 1.0 - b * b;
    let s = (b * e - d) / denom;
    let t = (e - b * d) / denom;
    let n = prev.origin + z0 * s;
    let o1 = next.point + z1 * t;
    let diff = o1 - n;
    let x = if diff.length() > INTERSECT_TOLERANCE {
        // The common normal is along the cross product; pick its sign from the
        // offset so that `a >= 0`.
        let c = cross.normalize();
        if diff.dot(c) >= 0.0 { c } else { -c }
    } else {
        cross.normalize()
    };
    (
        Frame {
            origin: n + x * diff.dot(x),
            x,
            z: z1,
        },
        n,
    )
}

/// The angle turning unit `from` into unit `to` about unit `axis` (both
/// perpendicular to it).
fn angle_about(from: DVec3, to: DVec3, axis: DVec3) -> f64 {
    math::atan2(from.cross(to).dot(axis), from.dot(to))
}

fn row(prev: &Frame, next: &Frame, n: DVec3) -> DhRow {
    DhRow {
        d: (n - prev.origin).dot(prev.z),
        theta: angle_about(prev.x, next.x, prev.z),
        a: (next.origin - n).dot(next.x),
        alpha: angle_about(prev.z, next.z, next.x),
    }
}

/// DH rows of the chain with `axes` (at least one), from the base link's
/// origin to the tip frame `tip` (all in the base link's frame, at q = 0).
#[must_use]
pub fn dh_chain(axes: &[AxisLine], tip: &DAffine3) -> DhChain {
    let Some(first) = axes.first() else {
        return DhChain {
            base: DAffine3::IDENTITY,
            rows: Vec::new(),
        };
    };
    let z0 = first.direction;
    let mut frame = Frame {
        origin: foot(DVec3::ZERO, first.point, z0),
        x: perpendicular(z0, &[]),
        z: z0,
    };
    let base = affine(&frame);
    let mut rows = Vec::with_capacity(axes.len());
    for (i, axis) in axes.iter().enumerate() {
        let (next, n) = match axes.get(i + 1) {
            Some(next_axis) => next_frame(&frame, axis.point, next_axis),
            None => last_frame(&frame, tip),
        };
        rows.push(row(&frame, &next, n));
        frame = next;
    }
    DhChain { base, rows }
}

/// Frame n: `z_n = z_{n-1}`, origin at the tip's origin when it is off the
/// last axis (then `x_n` points to it), else at its foot with `x_n` along the
/// tip's x (or y) axis.
fn last_frame(prev: &Frame, tip: &DAffine3) -> (Frame, DVec3) {
    let t = tip.translation;
    let n = foot(t, prev.origin, prev.z);
    let diff = t - n;
    let x = if diff.length() > INTERSECT_TOLERANCE {
        diff.normalize()
    } else {
        perpendicular(prev.z, &[tip.matrix3.x_axis, tip.matrix3.y_axis, prev.x])
    };
    (
        Frame {
            origin: n + x * diff.dot(x),
            x,
            z: prev.z,
        },
        n,
    )
}

fn affine(f: &Frame) -> DAffine3 {
    let y = f.z.cross(f.x);
    DAffine3::from_mat3_translation(DMat3::from_cols(f.x, y, f.z), f.origin)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angle_about_is_signed() {
        let a = angle_about(DVec3::X, DVec3::Y, DVec3::Z);
        assert!((a - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        let b = angle_about(DVec3::X, DVec3::Y, -DVec3::Z);
        assert!((b + std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    }

    #[test]
    fn planar_parallel_axes_give_link_lengths() {
        let axes = [
            AxisLine {
                point: DVec3::ZERO,
                direction: DVec3::Z,
            },
            AxisLine {
                point: DVec3::new(0.4, 0.0, 0.0),
                direction: DVec3::Z,
            },
        ];
        let tip = DAffine3::from_translation(DVec3::new(0.7, 0.0, 0.0));
        let c = dh_chain(&axes, &tip);
        assert!((c.rows[0].a - 0.4).abs() < 1e-15);
        assert!((c.rows[1].a - 0.3).abs() < 1e-15);
        assert!(
            c.rows
                .iter()
                .all(|r| r.alpha.abs() < 1e-15 && r.d.abs() < 1e-15)
        );
    }
}
