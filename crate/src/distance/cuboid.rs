//! Points and segments against rectangles and boxes (paper fig. 2).
//!
//! In the figure's own frame the squared distance from a point to a box with
//! half extents `h` is `Σ e_i²`, `e_i = x_i − clamp(x_i, −h_i, h_i)`. Along a
//! segment `x(t) = x0 + t·dx` it is a convex piecewise quadratic in `t` with at
//! most six breakpoints (where `x_i(t) = ±h_i`); each piece is minimised
//! exactly. A rectangle is the same with a zero half extent along its normal.
//! A constant piece at the minimum is a family of equally close points (a
//! segment parallel to a face): its middle is the witness.
//!
//! A segment whose core enters a box penetrates it; the depth is the smallest
//! overlap along the separating axes of a segment and a box (the three box
//! axes and the three cross products with the segment's direction).

use glam::DVec3;

use super::{Closest, OrientedBox, Rectangle, orthogonal_unit};

/// Point against a rectangle.
pub(crate) fn point_rectangle(p: DVec3, r: &Rectangle) -> Closest {
    let d = p - r.center;
    let x = r.axes[0]
        .dot(d)
        .clamp(-r.half_extents[0], r.half_extents[0]);
    let y = r.axes[1]
        .dot(d)
        .clamp(-r.half_extents[1], r.half_extents[1]);
    let q = r.center + r.axes[0] * x + r.axes[1] * y;
    let mut c = Closest::between(p, q, true);
    if c.n == DVec3::ZERO {
        c.n = r.normal;
    }
    c
}

/// Point against a solid box: negative inside, by the depth below the
/// nearest face.
pub(crate) fn point_box(p: DVec3, b: &OrientedBox) -> Closest {
    let x = b.to_local(p);
    let h = b.half_extents;
    let q = x.clamp(-h, h);
    if q != x {
        return Closest::between(p, b.from_local(q), true);
    }
    // Inside or on the surface: the nearest face.
    let gaps = h - x.abs();
    let mut k = 0;
    for i in 1..3 {
        if gaps[i] < gaps[k] {
            k = i;
        }
    }
    let sign = if x[k] >= 0.0 { 1.0 } else { -1.0 };
    let mut f = x;
    f[k] = sign * h[k];
    let outward = b.axes[k] * sign;
    let depth = gaps[k];
    let unique = (0..3).filter(|&i| gaps[i] == depth).count() == 1;
    Closest {
        d: -depth,
        pa: p,
        pb: b.from_local(f),
        n: -outward,
        unique,
    }
}

/// Minimum over `t ∈ [0, 1]` of the squared distance from `x0 + t·dx` to
/// the box `[−h, h]` (components of `h` may be zero): `(F, t, unique)`.
fn segment_cuboid_local(x0: DVec3, dx: DVec3, h: DVec3) -> (f64, f64, bool) {
    let excess2 = |t: f64| {
        let x = x0 + dx * t;
        (x - x.clamp(-h, h)).length_squared()
    };
    let mut ts = [0.0f64; 8];
    let mut n = 0;
    ts[n] = 0.0;
    n += 1;
    for i in 0..3 {
        if dx[i] != 0.0 {
            for s in [-h[i], h[i]] {
                let t = (s - x0[i]) / dx[i];
                if t > 0.0 && t < 1.0 {
                    ts[n] = t;
                    n += 1;
                }
            }
        }
    }
    ts[n] = 1.0;
    n += 1;
    let ts = &mut ts[..n];
    ts.sort_by(f64::total_cmp);
    let mut best = (f64::INFINITY, 0.0);
    // Constant pieces: (value, start, end).
    let mut flats = [(0.0f64, 0.0f64, 0.0f64); 7];
    let mut nflat = 0;
    for w in ts.windows(2) {
        let (t0, t1) = (w[0], w[1]);
        let mid = 0.5 * (t0 + t1);
        let xm = x0 + dx * mid;
        let (mut qa, mut qb) = (0.0, 0.0);
        for i in 0..3 {
            let alpha = if xm[i] > h[i] {
                x0[i] - h[i]
            } else if xm[i] < -h[i] {
                x0[i] + h[i]
            } else {
                continue;
            };
            qa += dx[i] * dx[i];
            qb += alpha * dx[i];
        }
        let t = if qa > 0.0 {
            (-qb / qa).clamp(t0, t1)
        } else {
            t0
        };
        let f = excess2(t);
        if qa == 0.0 && t1 > t0 {
            flats[nflat] = (f, t0, t1);
            nflat += 1;
        }
        if f < best.0 {
            best = (f, t);
        }
    }
    let tol = 1e-10 * best.0 + 1e-300;
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for &(f, t0, t1) in &flats[..nflat] {
        if f <= best.0 + tol {
            lo = lo.min(t0);
            hi = hi.max(t1);
        }
    }
    if hi > lo {
        let t = 0.5 * (lo + hi);
        return (excess2(t), t, false);
    }
    (best.0, best.1, true)
}

/// Squared distance from the segment `s0`–`s1` to the axis-aligned box
/// `[min, max]` (the scene query's exact mid-phase test).
pub(crate) fn segment_aabb_distance2(s0: DVec3, s1: DVec3, min: DVec3, max: DVec3) -> f64 {
    let c = 0.5 * (min + max);
    let h = 0.5 * (max - min);
    segment_cuboid_local(s0 - c, s1 - s0, h).0
}

/// Segment `s0`–`s1` (non-zero length) against a rectangle.
pub(crate) fn segment_rectangle(s0: DVec3, s1: DVec3, r: &Rectangle) -> Closest {
    let basis = [r.axes[0], r.axes[1], r.normal];
    let local = |p: DVec3| DVec3::new(basis[0].dot(p), basis[1].dot(p), basis[2].dot(p));
    let x0 = local(s0 - r.center);
    let dx = local(s1 - s0);
    let h = DVec3::new(r.half_extents[0], r.half_extents[1], 0.0);
    let (_, t, unique) = segment_cuboid_local(x0, dx, h);
    let x = x0 + dx * t;
    let q = x.clamp(-h, h);
    let pa = s0 + (s1 - s0) * t;
    let pb = r.center + basis[0] * q.x + basis[1] * q.y;
    let c = Closest::between(pa, pb, unique);
    // Touching: escape along the normal, tilted away from the segment.
    let d = (s1 - s0).normalize_or_zero();
    let n = r.normal - d * d.dot(r.normal);
    c.or_normal(n.try_normalize().unwrap_or_else(|| orthogonal_unit(d)))
}

/// Segment `s0`–`s1` (non-zero length) against a solid box.
pub(crate) fn segment_box(s0: DVec3, s1: DVec3, b: &OrientedBox) -> Closest {
    let x0 = b.to_local(s0);
    let x1 = b.to_local(s1);
    let dx = x1 - x0;
    let h = b.half_extents;
    let (f, t, unique) = segment_cuboid_local(x0, dx, h);
    if f > 0.0 {
        let x = x0 + dx * t;
        let pa = s0 + (s1 - s0) * t;
        return Closest::between(pa, b.from_local(x.clamp(-h, h)), unique);
    }
    penetration(s0, s1, x0, x1, b)
}

/// Depth of a segment inside a box along the best separating axis.
fn penetration(s0: DVec3, s1: DVec3, x0: DVec3, x1: DVec3, b: &OrientedBox) -> Closest {
    let h = b.half_extents;
    let dir = x1 - x0;
    let mut axes = [
        DVec3::X,
        DVec3::Y,
        DVec3::Z,
        DVec3::ZERO,
        DVec3::ZERO,
        DVec3::ZERO,
    ];
    for (i, e) in [DVec3::X, DVec3::Y, DVec3::Z].iter().enumerate() {
        axes[3 + i] = dir.cross(*e).normalize_or_zero();
    }
    // (depth, local axis along which the box must move, end point index / tie)
    let mut best: Option<(f64, DVec3, f64, bool)> = None;
    for l in axes {
        if l == DVec3::ZERO {
            continue;
        }
        let (a0, a1) = (x0.dot(l), x1.dot(l));
        let r = h.x * l.x.abs() + h.y * l.y.abs() + h.z * l.z.abs();
        // Move the box along +l until its low face passes the segment's top,
        // or along −l until its high face passes the segment's bottom.
        let up = a0.max(a1) + r;
        let down = r - a0.min(a1);
        let (depth, axis, t, tie) = if up <= down {
            (up, l, if a1 > a0 { 1.0 } else { 0.0 }, a0 == a1)
        } else {
            (down, -l, if a1 < a0 { 1.0 } else { 0.0 }, a0 == a1)
        };
        if best.is_none_or(|bb| depth < bb.0) {
            best = Some((depth, axis, t, tie));
        }
    }
    let (depth, axis, t, tie) = best.unwrap_or((0.0, DVec3::Z, 0.0, false));
    let t = if tie { 0.5 } else { t };
    let n = b.axes[0] * axis.x + b.axes[1] * axis.y + b.axes[2] * axis.z;
    let pa = s0 + (s1 - s0) * t;
    Closest {
        d: -depth,
        pa,
        pb: pa - n * depth,
        n,
        unique: !tie,
    }
}
