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
use super::{Closest, Core, Disk, Polygon};

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

/// Two polygonal flat figures (rectangles, polygons; convex or not): the
/// closest pair has a point on a side of one of them (if both were inside,
/// the figures would be parallel and the pair could slide to a side), so the
/// distance is the smallest of each side of one against the other figure.
pub(crate) fn flat_flat(a: Core<'_>, b: Core<'_>) -> Closest {
    let mut best: Option<Closest> = None;
    // Where sides pass through the other figure (their span is the
    // intersection of two crossing figures).
    let mut touching: Vec<DVec3> = Vec::new();
    // On a tie, a family (a side parallel to the other figure) wins, so
    // that its middle is the witness.
    let mut keep = |c: Closest| {
        if c.d <= 1e-12 * (1.0 + c.pa.length()) {
            touching.push(c.pa);
        }
        let better = best.is_none_or(|b| {
            let tol = 1e-12 * (1.0 + b.d.abs());
            c.d < b.d - tol || (c.d <= b.d + tol && !c.unique && b.unique)
        });
        if better {
            best = Some(c);
        }
    };
    for (s0, s1) in sides(a) {
        keep(segment_flat(s0, s1, b));
    }
    for (s0, s1) in sides(b) {
        keep(segment_flat(s0, s1, a).flipped());
    }
    let best = best.unwrap_or(Closest {
        d: f64::INFINITY,
        pa: DVec3::ZERO,
        pb: DVec3::ZERO,
        n: DVec3::Z,
        unique: false,
    });
    if touching.len() >= 2 {
        // Crossing figures meet along a segment: its middle, if it lies on
        // both (always for convex figures).
        let (mut lo, mut hi) = (touching[0], touching[0]);
        let axis = touching
            .iter()
            .map(|p| *p - touching[0])
            .fold(DVec3::ZERO, |m, v| {
                if v.length_squared() > m.length_squared() {
                    v
                } else {
                    m
                }
            });
        if axis != DVec3::ZERO {
            for p in &touching {
                if (*p - touching[0]).dot(axis) < (lo - touching[0]).dot(axis) {
                    lo = *p;
                }
                if (*p - touching[0]).dot(axis) > (hi - touching[0]).dot(axis) {
                    hi = *p;
                }
            }
            let mid = 0.5 * (lo + hi);
            let scale = 1e-12 * (1.0 + (hi - lo).length());
            if point_flat(mid, a).d <= scale && point_flat(mid, b).d <= scale {
                return Closest {
                    d: 0.0,
                    pa: mid,
                    pb: mid,
                    unique: false,
                    ..best
                };
            }
        }
        return Closest {
            unique: false,
            ..best
        };
    }
    best
}

fn sides(c: Core<'_>) -> Vec<(DVec3, DVec3)> {
    match c {
        Core::Rectangle(r) => {
            let k = r.corners();
            (0..4).map(|i| (k[i], k[(i + 1) % 4])).collect()
        }
        Core::Polygon(p) => p.sides().collect(),
        _ => Vec::new(),
    }
}

fn segment_flat(s0: DVec3, s1: DVec3, c: Core<'_>) -> Closest {
    match c {
        Core::Rectangle(r) => super::cuboid::segment_rectangle(s0, s1, r),
        Core::Polygon(p) => segment_polygon(s0, s1, p),
        _ => Closest::between(s0, s0, false),
    }
}

/// A polygonal flat figure (A: rectangle or polygon) against a disk (B).
/// The closest pair has a point on a side of A, or a point of the disk's rim
/// above A's interior, which is then the disk's lowest point over A's plane;
/// a disk that crosses A's plane meets it along a chord, tested against A.
pub(crate) fn flat_disk(a: Core<'_>, disk: &Disk) -> Closest {
    let (n, origin) = match a {
        Core::Rectangle(r) => (r.normal, r.center),
        Core::Polygon(p) => (p.normal(), p.vertices()[0]),
        _ => (DVec3::Z, DVec3::ZERO),
    };
    let mut best: Option<Closest> = None;
    // On a tie, a family (a side parallel to the other figure) wins, so
    // that its middle is the witness.
    let mut keep = |c: Closest| {
        let better = best.is_none_or(|b| {
            let tol = 1e-12 * (1.0 + b.d.abs());
            c.d < b.d - tol || (c.d <= b.d + tol && !c.unique && b.unique)
        });
        if better {
            best = Some(c);
        }
    };
    for (s0, s1) in sides(a) {
        keep(super::disk::segment_disk(s0, s1, disk));
    }
    let m = disk.normal;
    let w = n - m * n.dot(m);
    let wl = w.length();
    let hc = n.dot(disk.center - origin);
    if wl <= 1e-12 {
        // Parallel: the centre's pair is one of the family.
        let c = point_flat(disk.center, a).flipped();
        keep(Closest { unique: false, ..c });
    } else {
        let e = w / wl;
        let (lo, hi) = (disk.center - e * disk.radius, disk.center + e * disk.radius);
        let (hlo, hhi) = (n.dot(lo - origin), n.dot(hi - origin));
        if hlo >= 0.0 {
            keep(point_flat(lo, a).flipped());
        } else if hhi <= 0.0 {
            keep(point_flat(hi, a).flipped());
        } else {
            // The chord in A's plane.
            let q0 = disk.center - e * (hc / wl);
            let half = (disk.radius * disk.radius - (q0 - disk.center).length_squared())
                .max(0.0)
                .sqrt();
            let t = n.cross(m).normalize_or_zero();
            keep(segment_flat(q0 - t * half, q0 + t * half, a).flipped());
        }
    }
    best.unwrap_or(Closest {
        d: f64::INFINITY,
        pa: DVec3::ZERO,
        pb: DVec3::ZERO,
        n: DVec3::Z,
        unique: false,
    })
}

fn point_flat(p: DVec3, c: Core<'_>) -> Closest {
    match c {
        Core::Rectangle(r) => super::cuboid::point_rectangle(p, r),
        Core::Polygon(poly) => point_polygon(p, poly),
        _ => Closest::between(p, p, false),
    }
}
