//! A point against a segment and a plane. (Its distances to rectangles and
//! boxes are in `cuboid`, to disks in `disk`, to polygons in `polygon`, to
//! hulls in `generic`, next to the segment routines of the same figure.)

use glam::DVec3;

use super::{Closest, Plane};

/// Fraction along `a`–`b` of the point closest to `p` (0 for a zero-length
/// segment).
#[must_use]
#[inline(always)]
pub(crate) fn segment_parameter(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let d = b - a;
    let l2 = d.length_squared();
    if l2 > 0.0 {
        ((p - a).dot(d) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// Point `p` against the segment `a`–`b`.
#[inline(always)]
pub(crate) fn point_segment(p: DVec3, a: DVec3, b: DVec3) -> Closest {
    let t = segment_parameter(p, a, b);
    Closest::between(p, a + (b - a) * t, true)
}

/// Point `p` against a plane (a surface).
pub(crate) fn point_plane(p: DVec3, plane: &Plane) -> Closest {
    let s = plane.signed_distance(p);
    let q = p - plane.normal * s;
    Closest::between(p, q, true).or_normal(plane.normal)
}
