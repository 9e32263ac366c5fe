//! The skeleton's volume: a tapered capsule (radius varying linearly from
//! `r0` at `a` to `r1` at `b`), the convex hull of two balls, i.e. a
//! round cone.
//!
//! Against a point the signed distance is a closed form: in the plane of
//! the axis and the point, the cone's side is the line tangent to both
//! circles, with unit normal `(s, c)`, `s = (r0 − r1) / L`; the point's
//! position along that line decides whether the nearest feature is the ball
//! at `a`, the side, or the ball at `b`.
//!
//! Against anything else the tapered capsule is the union of the balls
//! `B(a + t(b − a), r(t))`, so the clearance is `min_t D(t) − r(t)` with `D`
//! the signed distance from the axis point to the other figure, a convex
//! function of `t` for a convex figure. Its slope comes from the same point
//! query (the distance field's gradient is the unit direction away from the
//! figure), so the minimum is bracketed where the slope changes sign and the
//! bracket is shrunk by the crossing of the end tangents (with a bisection
//! every fourth step). Those tangents bound a convex function from below:
//! the reported clearance is that certified lower bound, within ~1e-13 of
//! the minimum, so it is never larger than the true clearance. A non-convex
//! polygon is taken as the union of its (convex) triangles.

use glam::DVec3;

use super::polygon::segment_polygon;
use super::{
    Closest, Core, Distance, DistanceError, Polygon, Primitive, TaperedCapsule, core_distance,
    core_of, orthogonal_unit,
};

/// Point `p` (A) against the surface of a tapered capsule (B): signed.
pub(crate) fn point_tapered(p: DVec3, tc: &TaperedCapsule) -> Closest {
    let (a, b) = (tc.segment.a, tc.segment.b);
    let [r0, r1] = tc.radius;
    let axis = b - a;
    let len = axis.length();
    let ball = |c: DVec3, r: f64| {
        let v = p - c;
        let l = v.length();
        let (out, unique) = if l > 0.0 {
            (v / l, true)
        } else {
            (orthogonal_unit(axis), false)
        };
        let q = c + out * r;
        Closest {
            d: l - r,
            pa: p,
            pb: q,
            n: -out,
            unique,
        }
    };
    if len <= (r0 - r1).abs() {
        // One ball contains the other.
        return if r0 >= r1 { ball(a, r0) } else { ball(b, r1) };
    }
    let u = axis / len;
    let w = p - a;
    let x = w.dot(u);
    let radial = w - u * x;
    let y = radial.length();
    let (e, unique) = if y > 0.0 {
        (radial / y, true)
    } else {
        (orthogonal_unit(u), false)
    };
    let s = (r0 - r1) / len;
    let c = (1.0 - s * s).sqrt();
    let tau = x * c - y * s;
    if tau < 0.0 {
        return ball(a, r0);
    }
    if tau > len * c {
        return ball(b, r1);
    }
    let out = u * s + e * c;
    let d = x * s + y * c - r0;
    Closest {
        d,
        pa: p,
        pb: p - out * d,
        n: -out,
        unique,
    }
}

/// The cases of [`tapered_vs`] that need no search along the axis: a point,
/// a sphere, and a non-convex polygon (the union of its convex triangles);
/// `None` for the others.
fn tapered_direct(
    tc: &TaperedCapsule,
    other: &Primitive,
) -> Result<Option<Distance>, DistanceError> {
    Ok(Some(match other {
        Primitive::Point(p) => point_tapered(*p, tc).flipped().inflate(0.0, 0.0),
        Primitive::Sphere(s) => point_tapered(s.center, tc).flipped().inflate(0.0, s.radius),
        Primitive::Polygon(poly) if !poly.is_convex() => {
            let v = poly.vertices();
            let mut best: Option<Distance> = None;
            for [i, j, k] in poly.triangles() {
                let tri = Polygon::new(vec![v[i], v[j], v[k]]).map_err(DistanceError::from)?;
                let d = tapered_vs(tc, &Primitive::Polygon(tri))?;
                if best.is_none_or(|b| d.distance < b.distance) {
                    best = Some(d);
                }
            }
            match best {
                Some(b) => b,
                None => {
                    segment_polygon(tc.segment.a, tc.segment.b, poly).inflate(tc.max_radius(), 0.0)
                }
            }
        }
        _ => return Ok(None),
    }))
}

/// The least value of the convex `h` on `[0, 1]` given its values and
/// slopes at both ends (`h(0)`'s slope negative, `h(1)`'s positive): the
/// minimum lies where the slope changes sign. The tangents at the two ends
/// of the bracket bound `h` from below; their crossing is both the next
/// guess and the certified lower bound. Returns the bound (to `tol`), where
/// the least value was measured, and its witness pair.
fn convex_minimum<F>(
    h: &F,
    (h0, g0, c0): (f64, f64, Closest),
    (h1, g1, c1): (f64, f64, Closest),
    tol: f64,
) -> Result<(f64, f64, Closest), DistanceError>
where
    F: Fn(f64) -> Result<(f64, f64, Closest), DistanceError>,
{
    let (mut lo, mut hl, mut gl) = (0.0f64, h0, g0);
    let (mut hi, mut hh, mut gh) = (1.0f64, h1, g1);
    let (mut best, mut best_t, mut best_c) = if h0 <= h1 {
        (h0, 0.0, c0)
    } else {
        (h1, 1.0, c1)
    };
    let mut bound = f64::NEG_INFINITY;
    for k in 0..100 {
        let tx = ((hh - hl) + gl * lo - gh * hi) / (gl - gh);
        let tx = if tx.is_finite() {
            tx.clamp(lo, hi)
        } else {
            0.5 * (lo + hi)
        };
        bound = hl + gl * (tx - lo);
        if best - bound <= tol || hi - lo <= 1e-16 {
            break;
        }
        let mut t = if k % 4 == 3 { 0.5 * (lo + hi) } else { tx };
        if !(t > lo && t < hi) {
            t = 0.5 * (lo + hi);
        }
        let (ht, gt, ct) = h(t)?;
        if ht < best {
            (best, best_t, best_c) = (ht, t, ct);
        }
        if gt < 0.0 {
            (lo, hl, gl) = (t, ht, gt);
        } else {
            (hi, hh, gh) = (t, ht, gt);
        }
    }
    Ok((bound.min(best), best_t, best_c))
}

/// Tapered capsule (A, radii differ) against any primitive (B).
pub(crate) fn tapered_vs(
    tc: &TaperedCapsule,
    other: &Primitive,
) -> Result<Distance, DistanceError> {
    if let Some(d) = tapered_direct(tc, other)? {
        return Ok(d);
    }
    // Signed distance from an axis point to B, with the witness pair.
    let measure = |p: DVec3| -> Result<(f64, Closest), DistanceError> {
        match other {
            Primitive::TaperedCapsule(t2) if t2.radius[0] != t2.radius[1] => {
                let c = point_tapered(p, t2);
                Ok((c.d, c))
            }
            _ => {
                let (core, r) = core_of(other);
                let c = core_distance(Core::Point(p), core)?;
                Ok((c.d - r, c))
            }
        }
    };
    let seg = tc.segment;
    let axis = seg.b - seg.a;
    let dr = tc.radius[1] - tc.radius[0];
    // h(t) = D(a + t·axis) − r(t) and its (sub)gradient: the gradient of
    // the distance field at a point is −n (n points from the point to B);
    // with the witness pair, kept for the point where h is least.
    let h = |t: f64| -> Result<(f64, f64, Closest), DistanceError> {
        let (d, c) = measure(seg.at(t))?;
        Ok((d - tc.radius_at(t), -c.n.dot(axis) - dr, c))
    };
    let (h0, g0, c0) = h(0.0)?;
    let (h1, g1, c1) = h(1.0)?;
    let (value, t, cl) = if g0 >= 0.0 {
        (h0, 0.0, c0)
    } else if g1 <= 0.0 {
        (h1, 1.0, c1)
    } else {
        let tol = 1e-13 * (1.0 + axis.length() + tc.max_radius());
        convex_minimum(&h, (h0, g0, c0), (h1, g1, c1), tol)?
    };
    let rb = match other {
        Primitive::TaperedCapsule(t2) if t2.radius[0] != t2.radius[1] => 0.0,
        _ => core_of(other).1,
    };
    let mut out = cl.inflate(tc.radius_at(t), rb);
    out.distance = value;
    Ok(out)
}
