//! An infinite plane (paper eq. 1, `ax + by + cz + d = 0`) against every
//! figure, through the figure's extreme points along the normal.
//!
//! A convex figure (or a polygon) lies on one side of the plane when its
//! lowest point along the normal is above it, or its highest below; the
//! distance is then that extreme height. When an edge or a face is parallel
//! to the plane the extreme point is the middle of it and the witness is
//! not unique. A figure that straddles the plane touches it (distance 0), or,
//! for a solid, penetrates by the smaller of its two extreme heights.

use glam::DVec3;

use super::{Closest, Core, DistanceError, Plane, orthogonal_unit};

/// The lowest point of a core along `dir`: `(value, point, unique)`.
fn lowest(core: Core<'_>, dir: DVec3) -> (f64, DVec3, bool) {
    let tol = 1e-12;
    match core {
        Core::Point(p) => (dir.dot(p), p, true),
        Core::Segment(a, b) => {
            let (va, vb) = (dir.dot(a), dir.dot(b));
            if (va - vb).abs() <= tol * (b - a).length() {
                (0.5 * (va + vb), 0.5 * (a + b), false)
            } else if va < vb {
                (va, a, true)
            } else {
                (vb, b, true)
            }
        }
        Core::Rectangle(r) => lowest_corner(r.center, &r.axes, &r.half_extents, dir, tol),
        Core::Disk(d) => {
            let w = dir - d.normal * dir.dot(d.normal);
            let wl = w.length();
            if wl <= tol {
                (dir.dot(d.center), d.center, false)
            } else {
                let p = d.center - w * (d.radius / wl);
                (dir.dot(p), p, true)
            }
        }
        Core::Polygon(poly) => lowest_of_polygon(poly, dir, tol),
        Core::Box(b) => lowest_corner(b.center, &b.axes, &b.half_extents.to_array(), dir, tol),
        Core::Hull(h) => lowest_of_hull(h.points(), dir, tol),
        // Planes are handled by the caller.
        Core::Plane(q) => (-q.offset * dir.dot(q.normal), -q.normal * q.offset, false),
    }
}

/// The lowest corner of a rectangle or a box (centre, unit axes, half
/// extents) along `dir`; not unique when an axis is perpendicular to `dir`.
fn lowest_corner(
    center: DVec3,
    axes: &[DVec3],
    half_extents: &[f64],
    dir: DVec3,
    tol: f64,
) -> (f64, DVec3, bool) {
    let mut p = center;
    let mut unique = true;
    for k in 0..axes.len() {
        let c = dir.dot(axes[k]);
        if c.abs() <= tol {
            unique = false;
        } else {
            p -= axes[k] * (half_extents[k] * c.signum());
        }
    }
    (dir.dot(p), p, unique)
}

/// The lowest point of a planar polygon along `dir`: a vertex, the middle
/// of an edge, or (the polygon parallel to the plane) its centroid.
fn lowest_of_polygon(poly: &super::Polygon, dir: DVec3, tol: f64) -> (f64, DVec3, bool) {
    let v = poly.vertices();
    let n = v.len();
    let vals: Vec<f64> = v.iter().map(|p| dir.dot(*p)).collect();
    let min = vals.iter().copied().fold(f64::INFINITY, f64::min);
    let scale = 1.0 + v.iter().map(|p| (*p - v[0]).length()).fold(0.0, f64::max);
    let ties: Vec<usize> = (0..n).filter(|&k| vals[k] <= min + tol * scale).collect();
    match ties.as_slice() {
        [k] => (min, v[*k], true),
        [i, j] if (j - i == 1) || (*i == 0 && *j == n - 1) => (min, 0.5 * (v[*i] + v[*j]), false),
        _ if ties.len() == n => {
            let c = v.iter().copied().sum::<DVec3>() / n as f64;
            let (q, _) = poly.to_local(c);
            let p = if poly.contains_local(q) { c } else { v[0] };
            (min, p, false)
        }
        _ => (min, v[ties[0]], false),
    }
}

/// The lowest point of a convex hull's points along `dir`: the mean of the
/// points tied for lowest.
fn lowest_of_hull(pts: &[DVec3], dir: DVec3, tol: f64) -> (f64, DVec3, bool) {
    let min = pts
        .iter()
        .map(|p| dir.dot(*p))
        .fold(f64::INFINITY, f64::min);
    let scale = 1.0
        + pts
            .iter()
            .map(|p| (*p - pts[0]).length())
            .fold(0.0, f64::max);
    let ties: Vec<DVec3> = pts
        .iter()
        .copied()
        .filter(|p| dir.dot(*p) <= min + tol * scale)
        .collect();
    let c = ties.iter().copied().sum::<DVec3>() / ties.len().max(1) as f64;
    (min, c, ties.len() == 1)
}

/// A point of a polygon's boundary on the plane, when the polygon straddles
/// it.
fn polygon_crossing(plane: &Plane, v: &[DVec3]) -> Option<DVec3> {
    let n = v.len();
    (0..n).find_map(|k| {
        let (p, q) = (v[k], v[(k + 1) % n]);
        let (a, b) = (plane.signed_distance(p), plane.signed_distance(q));
        if a == 0.0 {
            Some(p)
        } else if (a < 0.0) != (b < 0.0) && b != 0.0 {
            Some(p + (q - p) * (a / (a - b)))
        } else {
            None
        }
    })
}

/// Plane (A) against any core (B).
pub(crate) fn plane_core(plane: &Plane, core: Core<'_>) -> Result<Closest, DistanceError> {
    let n = plane.normal;
    if let Core::Plane(q) = core {
        return Ok(plane_plane(plane, q));
    }
    let (lo, plo, ulo) = lowest(core, n);
    let (hi, phi, uhi) = lowest(core, -n);
    let (min, max) = (lo + plane.offset, -hi + plane.offset);
    let solid = matches!(core, Core::Box(_) | Core::Hull(_));
    // Above (or a solid mostly above): B moves along +n to separate.
    let up = |d: f64| Closest {
        d,
        pa: plo - n * min,
        pb: plo,
        n,
        unique: ulo,
    };
    let down = |d: f64| Closest {
        d,
        pa: phi - n * max,
        pb: phi,
        n: -n,
        unique: uhi,
    };
    if min >= 0.0 {
        return Ok(up(min));
    }
    if max <= 0.0 {
        return Ok(down(-max));
    }
    if solid {
        return Ok(if -min <= max { up(min) } else { down(-max) });
    }
    // A flat figure or segment straddling the plane touches it.
    let crossing = match core {
        Core::Polygon(poly) => polygon_crossing(plane, poly.vertices()).unwrap_or(plo),
        _ => plo + (phi - plo) * (min / (min - max)),
    };
    let unique = matches!(core, Core::Segment(..));
    let along = match core {
        Core::Segment(a, b) => b - a,
        _ => DVec3::ZERO,
    };
    let escape = (n - along * (along.dot(n) / along.length_squared().max(1e-300)))
        .try_normalize()
        .unwrap_or_else(|| orthogonal_unit(n));
    Ok(Closest {
        d: 0.0,
        pa: crossing,
        pb: crossing,
        n: escape,
        unique,
    })
}

/// Two planes: parallel ones are a family (witness: the point of A nearest
/// the origin and its projection on B); others meet.
fn plane_plane(a: &Plane, b: &Plane) -> Closest {
    let cross = a.normal.cross(b.normal);
    if cross.length_squared() > 1e-24 {
        // A point of the common line: the one nearest the origin.
        let p = (b.normal.cross(cross) * (-a.offset) + cross.cross(a.normal) * (-b.offset))
            / cross.length_squared();
        return Closest {
            d: 0.0,
            pa: p,
            pb: p,
            n: a.normal,
            unique: false,
        };
    }
    let pa = -a.normal * a.offset;
    let s = b.signed_distance(pa);
    let pb = pa - b.normal * s;
    Closest::between(pa, pb, false).or_normal(a.normal)
}
