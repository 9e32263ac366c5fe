//! Points and segments against a disk (paper fig. 3: the distance to the
//! disk's plane, then, outside the disk, to its rim).
//!
//! Along a segment the squared distance to the disk, `F(t) = s(t)² +
//! max(0, ρ(t) − R)²` (height `s`, radial distance `ρ`), is convex and
//! continuously differentiable, so its minimum is the root of the monotone
//! `F'`, found by a bracketing iteration that mixes false position and
//! bisection. A segment parallel to the disk with part of its shadow on the
//! disk is a family: the witness is the middle of that part.

use glam::DVec3;

use super::{Closest, Disk};

/// Closest point of the disk to `p`.
fn project(p: DVec3, d: &Disk) -> DVec3 {
    let w = p - d.center;
    let radial = w - d.normal * d.normal.dot(w);
    let rho = radial.length();
    if rho <= d.radius {
        d.center + radial
    } else {
        d.center + radial * (d.radius / rho)
    }
}

/// Point against a disk.
pub(crate) fn point_disk(p: DVec3, d: &Disk) -> Closest {
    Closest::between(p, project(p, d), true).or_normal(d.normal)
}

/// Segment `s0`–`s1` (non-zero length) against a disk.
pub(crate) fn segment_disk(s0: DVec3, s1: DVec3, d: &Disk) -> Closest {
    let m = d.normal;
    let dir = s1 - s0;
    let w0 = s0 - d.center;
    let h0 = m.dot(w0);
    let h1 = m.dot(dir);
    let r0 = w0 - m * h0;
    let r1 = dir - m * h1;
    let len = dir.length();
    let at = |t: f64| s0 + dir * t;
    let tangent = (dir / len).cross(m);
    let fallback_normal = tangent.cross(dir / len).normalize_or(m);

    if h1.abs() <= 1e-12 * len {
        // Parallel to the disk: the part whose shadow lies on the disk is a
        // family at constant height.
        let a = r1.length_squared();
        let b = r0.dot(r1);
        let c = r0.length_squared() - d.radius * d.radius;
        let disc = b * b - a * c;
        if a > 0.0 && disc > 0.0 {
            let sq = disc.sqrt();
            let lo = ((-b - sq) / a).max(0.0);
            let hi = ((-b + sq) / a).min(1.0);
            if hi > lo {
                let t = 0.5 * (lo + hi);
                let p = at(t);
                return Closest::between(p, project(p, d), false).or_normal(fallback_normal);
            }
        }
    }

    // F'(t)/2 = s s' + max(0, ρ − R) ρ'.
    let slope = |t: f64| {
        let s = h0 + h1 * t;
        let r = r0 + r1 * t;
        let rho = r.length();
        let mut g = s * h1;
        if rho > d.radius {
            g += (rho - d.radius) * r.dot(r1) / rho;
        }
        g
    };
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let (mut glo, mut ghi) = (slope(lo), slope(hi));
    let t = if glo >= 0.0 {
        0.0
    } else if ghi <= 0.0 {
        1.0
    } else {
        let mut t = 0.5;
        for k in 0..200 {
            t = if k % 3 == 2 {
                0.5 * (lo + hi)
            } else {
                lo - glo * (hi - lo) / (ghi - glo)
            };
            if !(t > lo && t < hi) {
                t = 0.5 * (lo + hi);
            }
            let g = slope(t);
            if g == 0.0 {
                break;
            }
            if g < 0.0 {
                lo = t;
                glo = g;
            } else {
                hi = t;
                ghi = g;
            }
            if hi - lo <= 1e-15 {
                break;
            }
        }
        t
    };
    let p = at(t);
    Closest::between(p, project(p, d), true).or_normal(fallback_normal)
}
