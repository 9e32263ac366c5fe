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
//! function of `t` for a convex figure. Golden-section search brackets the
//! minimum; the result is lowered by the bracket width times the function's
//! Lipschitz constant, so it is never larger than the true clearance. A
//! non-convex polygon is taken as the union of its (convex) triangles.

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

/// Tapered capsule (A, radii differ) against any primitive (B).
pub(crate) fn tapered_vs(
    tc: &TaperedCapsule,
    other: &Primitive,
) -> Result<Distance, DistanceError> {
    match other {
        Primitive::Point(p) => return Ok(point_tapered(*p, tc).flipped().inflate(0.0, 0.0)),
        Primitive::Sphere(s) => {
            return Ok(point_tapered(s.center, tc).flipped().inflate(0.0, s.radius));
        }
        Primitive::Polygon(poly) if !poly.is_convex() => {
            // The union of its triangles, each convex.
            let v = poly.vertices();
            let mut best: Option<Distance> = None;
            for [i, j, k] in poly.triangles() {
                let tri = Polygon::new(vec![v[i], v[j], v[k]]).map_err(DistanceError::from)?;
                let d = tapered_vs(tc, &Primitive::Polygon(tri))?;
                if best.is_none_or(|b| d.distance < b.distance) {
                    best = Some(d);
                }
            }
            if let Some(b) = best {
                return Ok(b);
            }
            let c = segment_polygon(tc.segment.a, tc.segment.b, poly);
            return Ok(c.inflate(tc.max_radius(), 0.0));
        }
        _ => {}
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
    let h = |t: f64| -> Result<f64, DistanceError> { Ok(measure(seg.at(t))?.0 - tc.radius_at(t)) };
    const G: f64 = 0.618_033_988_749_894_9;
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let mut x1 = hi - G * (hi - lo);
    let mut x2 = lo + G * (hi - lo);
    let (mut f1, mut f2) = (h(x1)?, h(x2)?);
    for _ in 0..64 {
        if f1 <= f2 {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - G * (hi - lo);
            f1 = h(x1)?;
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + G * (hi - lo);
            f2 = h(x2)?;
        }
    }
    let mut best = if f1 <= f2 { (f1, x1) } else { (f2, x2) };
    for t in [0.0, 1.0] {
        let f = h(t)?;
        if f < best.0 {
            best = (f, t);
        }
    }
    let (val, t) = best;
    let lipschitz = (seg.b - seg.a).length() + (tc.radius[1] - tc.radius[0]).abs();
    let slack = lipschitz * (hi - lo);
    let (_, cl) = measure(seg.at(t))?;
    let rb = match other {
        Primitive::TaperedCapsule(t2) if t2.radius[0] != t2.radius[1] => 0.0,
        _ => core_of(other).1,
    };
    let mut out = cl.inflate(tc.radius_at(t), rb);
    out.distance = val - slack;
    Ok(out)
}
