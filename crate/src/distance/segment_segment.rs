//! Segment against segment (skeleton self-collision, segment and capsule
//! obstacles): the classic clamped closed form, with parallel and
//! collinear segments handled as a family whose witness is the middle of the
//! overlap.

use glam::DVec3;

use super::point::{point_segment, segment_parameter};
use super::{Closest, orthogonal_unit};

/// `sin²` of the angle below which two segments are treated as parallel.
const PARALLEL_SIN2: f64 = 1e-14;

/// Segment `p1`–`q1` against segment `p2`–`q2`; both may have zero length.
pub(crate) fn segment_segment(p1: DVec3, q1: DVec3, p2: DVec3, q2: DVec3) -> Closest {
    let d1 = q1 - p1;
    let d2 = q2 - p2;
    let r = p1 - p2;
    let a = d1.length_squared();
    let e = d2.length_squared();
    if a == 0.0 {
        return point_segment(p1, p2, q2);
    }
    if e == 0.0 {
        return point_segment(p2, p1, q1).flipped();
    }
    let b = d1.dot(d2);
    let c = d1.dot(r);
    let f = d2.dot(r);
    let denom = a * e - b * b;
    if denom <= PARALLEL_SIN2 * a * e {
        return parallel(p1, q1, p2, q2);
    }
    let mut s = ((b * f - c * e) / denom).clamp(0.0, 1.0);
    let mut t = (b * s + f) / e;
    if t < 0.0 {
        t = 0.0;
        s = (-c / a).clamp(0.0, 1.0);
    } else if t > 1.0 {
        t = 1.0;
        s = ((b - c) / a).clamp(0.0, 1.0);
    }
    let pa = p1 + d1 * s;
    let pb = p2 + d2 * t;
    Closest::between(pa, pb, true).or_normal(d1.cross(d2).normalize_or_zero())
}

/// Parallel (or nearly parallel) segments: the middle of the overlap of their
/// projections when they overlap, otherwise the closest end points.
fn parallel(p1: DVec3, q1: DVec3, p2: DVec3, q2: DVec3) -> Closest {
    let d1 = q1 - p1;
    let a = d1.length_squared();
    let sp = (p2 - p1).dot(d1) / a;
    let sq = (q2 - p1).dot(d1) / a;
    let lo = sp.min(sq).max(0.0);
    let hi = sp.max(sq).min(1.0);
    // The best end-point pair, exact for disjoint projections and a guard
    // against the small tilt allowed by the parallel tolerance.
    let mut best = point_segment(p1, p2, q2);
    for cand in [
        point_segment(q1, p2, q2),
        point_segment(p2, p1, q1).flipped(),
        point_segment(q2, p1, q1).flipped(),
    ] {
        if cand.d < best.d {
            best = cand;
        }
    }
    if lo <= hi {
        let s = 0.5 * (lo + hi);
        let pa = p1 + d1 * s;
        let t = segment_parameter(pa, p2, q2);
        let pb = p2 + (q2 - p2) * t;
        let family = Closest::between(pa, pb, (hi - lo) * a.sqrt() <= 1e-12 * a.sqrt().max(1.0));
        let tol = 1e-12 * (1.0 + family.d + a.sqrt());
        if family.d <= best.d + tol {
            return family.or_normal(orthogonal_unit(d1));
        }
    }
    best.or_normal(orthogonal_unit(d1))
}
