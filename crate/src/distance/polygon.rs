//! Points and segments against a planar polygon, convex or not (paper §II:
//! the distance to the plane when the closest point falls inside the
//! polygon, otherwise to its sides).
//!
//! Along a segment the closest point of the polygon is the projection onto
//! the plane while the segment's shadow is inside, and a point of a side
//! otherwise. So the minimum is the smaller of (a) the height `|s(t)|` over
//! the parts of the segment whose shadow is inside (a linear function:
//! its zero or an end of the part; a family when the segment is parallel to
//! the plane, whose witness is the middle of the longest such part) and (b)
//! segment–segment distances to the sides.

use glam::{DVec2, DVec3};

use super::point::point_segment;
use super::segment_segment::segment_segment;
use super::{Closest, Polygon};

/// Point against a polygon.
pub(crate) fn point_polygon(p: DVec3, poly: &Polygon) -> Closest {
    let (q, _) = poly.to_local(p);
    if poly.contains_local(q) {
        return Closest::between(p, poly.point_at(q), true).or_normal(poly.normal());
    }
    let v = poly.vertices();
    let n = v.len();
    let mut best = point_segment(p, v[n - 1], v[0]);
    for k in 0..n - 1 {
        let c = point_segment(p, v[k], v[k + 1]);
        if c.d < best.d {
            best = c;
        }
    }
    best.or_normal(poly.normal())
}

/// Segment `s0`–`s1` (non-zero length) against a polygon.
pub(crate) fn segment_polygon(s0: DVec3, s1: DVec3, poly: &Polygon) -> Closest {
    let v = poly.vertices();
    let n = v.len();
    let mut best = segment_segment(s0, s1, v[n - 1], v[0]);
    for k in 0..n - 1 {
        let c = segment_segment(s0, s1, v[k], v[k + 1]);
        if c.d < best.d {
            best = c;
        }
    }
    if let Some(inner) = inside_part(s0, s1, poly) {
        let tol = 1e-12 * (1.0 + best.d);
        if inner.d <= best.d + tol {
            return inner;
        }
    }
    best
}

/// The closest pair over the parts of the segment whose shadow lies inside
/// the polygon, if any.
fn inside_part(s0: DVec3, s1: DVec3, poly: &Polygon) -> Option<Closest> {
    let (a, h0) = poly.to_local(s0);
    let (b, h1) = poly.to_local(s1);
    let dir = b - a;
    let pts = poly.local();
    let n = pts.len();
    // Parameters where the shadow crosses a side.
    let mut ts: Vec<f64> = Vec::with_capacity(n + 2);
    ts.push(0.0);
    ts.push(1.0);
    for k in 0..n {
        let e0 = pts[k];
        let e = pts[(k + 1) % n] - e0;
        let den = dir.perp_dot(e);
        if den == 0.0 {
            continue;
        }
        let w: DVec2 = e0 - a;
        let t = w.perp_dot(e) / den;
        let u = w.perp_dot(dir) / den;
        if t > 0.0 && t < 1.0 && (0.0..=1.0).contains(&u) {
            ts.push(t);
        }
    }
    ts.sort_by(f64::total_cmp);
    let height = |t: f64| h0 + (h1 - h0) * t;
    let parallel = (h1 - h0).abs() <= 1e-12 * (s1 - s0).length();
    let mut best: Option<(f64, f64, bool, f64)> = None; // (|s|, t, unique, part length)
    let mut consider = |val: f64, t: f64, unique: bool, len: f64| {
        let better = match best {
            None => true,
            Some((bv, _, _, bl)) => val < bv || (val == bv && len > bl),
        };
        if better {
            best = Some((val, t, unique, len));
        }
    };
    for w in ts.windows(2) {
        let (t0, t1) = (w[0], w[1]);
        if t1 <= t0 && !(dir == DVec2::ZERO) {
            continue;
        }
        if !poly.contains_local(a + dir * (0.5 * (t0 + t1))) {
            continue;
        }
        if parallel {
            consider(
                height(0.5 * (t0 + t1)).abs(),
                0.5 * (t0 + t1),
                t1 <= t0,
                t1 - t0,
            );
        } else {
            let (v0, v1) = (height(t0), height(t1));
            if (v0 <= 0.0 && v1 >= 0.0) || (v0 >= 0.0 && v1 <= 0.0) {
                let t = (h0 / (h0 - h1)).clamp(t0, t1);
                consider(0.0, t, true, 0.0);
            } else if v0.abs() <= v1.abs() {
                consider(v0.abs(), t0, true, 0.0);
            } else {
                consider(v1.abs(), t1, true, 0.0);
            }
        }
    }
    let (_, t, unique, _) = best?;
    let p = s0 + (s1 - s0) * t;
    let (q, _) = poly.to_local(p);
    Some(Closest::between(p, poly.point_at(q), unique).or_normal(poly.normal()))
}
