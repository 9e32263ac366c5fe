//! Property tests of the distance engine over random pairs of every kind of
//! figure: symmetry, sign, witnesses on their figures that realise the
//! distance, and no densely sampled point closer than the reported distance.
//! Also agreement with parry where parry is exact (segment–segment,
//! ball–ball, plane) and within its GJK tolerance for capsules.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::{DQuat, DVec3};
use skeleton_avoidance::distance::{
    Capsule, ConvexHull, Disk, LineSegment, OrientedBox, Plane, Polygon, Primitive, Rectangle,
    Sphere, TaperedCapsule, distance,
};
use skeleton_avoidance::rng::Rng;

const KINDS: [&str; 11] = [
    "point",
    "segment",
    "sphere",
    "capsule",
    "taperedCapsule",
    "plane",
    "rectangle",
    "disk",
    "polygon",
    "box",
    "convexHull",
];

fn random_primitive(rng: &mut Rng, kind: &str) -> Primitive {
    let c = rng.vec3(1.0);
    let size = rng.range(0.1, 0.6);
    let made = match kind {
        "point" => Ok(Primitive::Point(c)),
        "segment" => LineSegment::new(c, c + rng.unit3() * 2.0 * size).map(Primitive::Segment),
        "sphere" => Sphere::new(c, size * 0.5).map(Primitive::Sphere),
        "capsule" => Capsule::new(c, c + rng.unit3() * 2.0 * size, rng.range(0.05, 0.3))
            .map(Primitive::Capsule),
        "taperedCapsule" => TaperedCapsule::new(
            c,
            c + rng.unit3() * 2.0 * size,
            [rng.range(0.05, 0.3), rng.range(0.05, 0.3)],
        )
        .map(Primitive::TaperedCapsule),
        "plane" => {
            let n = rng.unit3() * rng.range(0.5, 2.0);
            Plane::new(n, -n.dot(c)).map(Primitive::Plane)
        }
        "rectangle" => {
            let n = rng.unit3();
            let u = n.any_orthonormal_vector();
            Rectangle::new(c, [u, n.cross(u)], [size, rng.range(0.1, 0.6)])
                .map(Primitive::Rectangle)
        }
        "disk" => Disk::new(c, rng.unit3(), size).map(Primitive::Disk),
        "polygon" => {
            let n = rng.unit3();
            let u = n.any_orthonormal_vector();
            let v = n.cross(u);
            let k = 3 + (rng.next_u64() % 5) as usize;
            let star = rng.uniform() < 0.5 && k >= 4;
            let mut angles: Vec<f64> = (0..k)
                .map(|_| rng.range(0.0, std::f64::consts::TAU))
                .collect();
            angles.sort_by(f64::total_cmp);
            let verts = angles
                .iter()
                .enumerate()
                .map(|(i, a)| {
                    let r = if star && i % 2 == 1 {
                        0.35 * size
                    } else {
                        size
                    };
                    c + (u * a.cos() + v * a.sin()) * r
                })
                .collect();
            Polygon::new(verts).map(Primitive::Polygon)
        }
        "box" => {
            let q = DQuat::from_axis_angle(rng.unit3(), rng.range(0.0, 3.0));
            OrientedBox::new(
                c,
                DVec3::new(size, rng.range(0.05, 0.5), rng.range(0.05, 0.5)),
                q.to_array(),
            )
            .map(Primitive::Box)
        }
        _ => {
            let pts = (0..8)
                .map(|_| c + rng.unit3() * size * rng.range(0.5, 1.0))
                .collect();
            ConvexHull::new(pts).map(Primitive::ConvexHull)
        }
    };
    match made {
        Ok(p) => p,
        // A rare degenerate draw (e.g. a polygon with nearly equal angles).
        Err(_) => random_primitive(rng, kind),
    }
}

/// Points of the figure (its surface and, for solids, its inside).
fn samples(rng: &mut Rng, p: &Primitive, n: usize) -> Vec<DVec3> {
    let in_ball = |rng: &mut Rng| loop {
        let v = rng.vec3(1.0);
        if v.length_squared() <= 1.0 {
            return v;
        }
    };
    (0..n)
        .filter_map(|i| {
            let surface = i % 2 == 0;
            let dir = |rng: &mut Rng| if surface { rng.unit3() } else { in_ball(rng) };
            Some(match p {
                Primitive::Point(q) => *q,
                Primitive::Segment(s) => s.at(rng.uniform()),
                Primitive::Sphere(s) => s.center + dir(rng) * s.radius,
                Primitive::Capsule(c) => c.segment.at(rng.uniform()) + dir(rng) * c.radius,
                Primitive::TaperedCapsule(c) => {
                    let t = rng.uniform();
                    c.segment.at(t) + dir(rng) * c.radius_at(t)
                }
                Primitive::Plane(pl) => {
                    let u = pl.normal.any_orthonormal_vector();
                    let v = pl.normal.cross(u);
                    -pl.normal * pl.offset + u * rng.range(-3.0, 3.0) + v * rng.range(-3.0, 3.0)
                }
                Primitive::Rectangle(r) => {
                    let (x, y) = if surface {
                        // The rim.
                        let s = rng.range(-1.0, 1.0);
                        if rng.uniform() < 0.5 {
                            (s, 1f64.copysign(s))
                        } else {
                            (1f64.copysign(s), s)
                        }
                    } else {
                        (rng.range(-1.0, 1.0), rng.range(-1.0, 1.0))
                    };
                    r.center + r.axes[0] * x * r.half_extents[0] + r.axes[1] * y * r.half_extents[1]
                }
                Primitive::Disk(d) => {
                    let u = d.normal.any_orthonormal_vector();
                    let v = d.normal.cross(u);
                    let a = rng.range(0.0, std::f64::consts::TAU);
                    let r = if surface {
                        d.radius
                    } else {
                        d.radius * rng.uniform().sqrt()
                    };
                    d.center + (u * a.cos() + v * a.sin()) * r
                }
                Primitive::Polygon(poly) => {
                    let v = poly.vertices();
                    let k = (rng.next_u64() % v.len() as u64) as usize;
                    let edge = v[k] + (v[(k + 1) % v.len()] - v[k]) * rng.uniform();
                    if surface {
                        edge
                    } else {
                        // Toward the first vertex from a point of a side:
                        // inside for these star-shaped test polygons only
                        // when it stays on the polygon, so check.
                        let c = v.iter().copied().sum::<DVec3>() / v.len() as f64;
                        let q = c + (edge - c) * rng.uniform();
                        let on = distance(&Primitive::Point(q), p).ok()?.distance;
                        if on > 1e-12 {
                            return None;
                        }
                        q
                    }
                }
                Primitive::Box(b) => {
                    let h = b.half_extents;
                    let mut x = DVec3::new(
                        rng.range(-h.x, h.x),
                        rng.range(-h.y, h.y),
                        rng.range(-h.z, h.z),
                    );
                    if surface {
                        let k = (rng.next_u64() % 3) as usize;
                        x[k] = if rng.uniform() < 0.5 { -h[k] } else { h[k] };
                    }
                    b.from_local(x)
                }
                Primitive::ConvexHull(hull) => {
                    let pts = hull.points();
                    let mut w: Vec<f64> = pts.iter().map(|_| rng.uniform().powi(4)).collect();
                    let s: f64 = w.iter().sum();
                    w.iter_mut().for_each(|x| *x /= s);
                    pts.iter().zip(&w).map(|(p, w)| *p * *w).sum()
                }
            })
        })
        .collect()
}

/// Signed distance of a point to a figure (≤ 0 means on or in it).
fn to_figure(p: DVec3, fig: &Primitive) -> f64 {
    match distance(&Primitive::Point(p), fig) {
        Ok(d) => d.distance,
        Err(e) => panic!("point distance failed: {e}"),
    }
}

/// Tolerance of a pair: closed forms are exact to rounding; parry's GJK
/// (hulls, disk–disk, boxes against flat figures and boxes) is not.
fn tolerance(a: &Primitive, b: &Primitive) -> f64 {
    let flat_or_box = |p: &Primitive| {
        matches!(
            p,
            Primitive::Rectangle(_)
                | Primitive::Disk(_)
                | Primitive::Polygon(_)
                | Primitive::Box(_)
        )
    };
    let is_box = |p: &Primitive| matches!(p, Primitive::Box(_));
    let hull = |p: &Primitive| matches!(p, Primitive::ConvexHull(_));
    let disks = matches!((a, b), (Primitive::Disk(_), Primitive::Disk(_)));
    let boxed = (is_box(a) && flat_or_box(b)) || (is_box(b) && flat_or_box(a));
    if hull(a) || hull(b) || disks || boxed {
        1e-6
    } else {
        1e-9
    }
}

fn non_convex_polygon(p: &Primitive) -> bool {
    matches!(p, Primitive::Polygon(q) if !q.is_convex())
}

#[test]
fn random_pairs_of_every_kind() {
    let mut rng = Rng::new(20_260_421);
    let mut checked = 0;
    for ka in KINDS {
        for kb in KINDS {
            for _ in 0..8 {
                let a = random_primitive(&mut rng, ka);
                let b = random_primitive(&mut rng, kb);
                let (dab, dba) = match (distance(&a, &b), distance(&b, &a)) {
                    (Ok(x), Ok(y)) => (x, y),
                    (Err(e), _) | (_, Err(e)) => {
                        // Only a non-convex polygon against a flat figure,
                        // box or hull has no routine.
                        assert!(
                            non_convex_polygon(&a) || non_convex_polygon(&b),
                            "{ka}–{kb}: {e}"
                        );
                        continue;
                    }
                };
                checked += 1;
                let tol = tolerance(&a, &b);
                let ctx = format!("{ka}–{kb}: {a:?} {b:?} → {dab:?}");
                // Symmetry.
                assert!((dab.distance - dba.distance).abs() <= tol, "symmetry {ctx}");
                assert!(
                    (dab.point_a - dba.point_b).length() <= 1e3 * tol || !dab.unique,
                    "swap {ctx}"
                );
                // Witness identity and unit normal.
                let gap = dab.point_b - dab.point_a;
                assert!(
                    (gap - dab.normal * dab.distance).length() <= 1e3 * tol,
                    "pb − pa = d n {ctx}"
                );
                assert!(
                    (dab.normal.length() - 1.0).abs() < 1e-9,
                    "unit normal {ctx}"
                );
                // Sign: flat figures never report a negative distance.
                if !a.is_solid() && !b.is_solid() {
                    assert!(dab.distance >= 0.0, "non-negative {ctx}");
                }
                let lower_bound_only = matches!(a, Primitive::TaperedCapsule(_))
                    && non_convex_polygon(&b)
                    || matches!(b, Primitive::TaperedCapsule(_)) && non_convex_polygon(&a);
                if dab.distance > 1e-6 {
                    // Witnesses on their figures and realising the distance.
                    assert!(to_figure(dab.point_a, &a) <= 1e3 * tol, "pa on A {ctx}");
                    assert!(to_figure(dab.point_b, &b) <= 1e3 * tol, "pb on B {ctx}");
                    if !lower_bound_only {
                        assert!(
                            (gap.length() - dab.distance).abs() <= 1e3 * tol,
                            "realised {ctx}"
                        );
                    }
                }
                // No sampled point of A is closer to B (and vice versa); a
                // clear overlap shows in the samples too.
                let mut inside = false;
                for x in samples(&mut rng, &a, 60) {
                    inside |= to_figure(x, &b) <= 0.0;
                    let d = to_figure(x, &b);
                    assert!(
                        d >= dab.distance - 1e3 * tol || (d <= 0.0 && dab.distance <= 1e3 * tol),
                        "sample of A closer {d} {ctx}"
                    );
                }
                for y in samples(&mut rng, &b, 60) {
                    let d = to_figure(y, &a);
                    inside |= d <= 0.0;
                    assert!(
                        d >= dab.distance - 1e3 * tol || (d <= 0.0 && dab.distance <= 1e3 * tol),
                        "sample of B closer {d} {ctx}"
                    );
                }
                if dab.distance < -0.1 && a.is_solid() && b.is_solid() {
                    assert!(inside, "reported overlap not seen in samples {ctx}");
                }
                // Overlapping round solids: each witness is the deepest point
                // of its figure inside the other.
                let round =
                    |p: &Primitive| matches!(p, Primitive::Sphere(_) | Primitive::Capsule(_));
                if dab.distance < -1e-9 && round(&a) && round(&b) {
                    assert!(to_figure(dab.point_a, &b) <= 1e-9, "pa inside B {ctx}");
                    assert!(to_figure(dab.point_b, &a) <= 1e-9, "pb inside A {ctx}");
                }
            }
        }
    }
    assert_eq!(checked, KINDS.len() * KINDS.len() * 8);
}

#[test]
fn point_distances_agree_with_dense_sampling() {
    // The point routines underpin the other checks: compare them with the
    // nearest of many sampled points of the figure.
    let mut rng = Rng::new(7);
    for kind in KINDS {
        if kind == "plane" {
            continue;
        }
        for _ in 0..4 {
            let fig = random_primitive(&mut rng, kind);
            let p = rng.vec3(1.5);
            let d = to_figure(p, &fig);
            let pts = samples(&mut rng, &fig, 4000);
            let nearest = pts
                .iter()
                .map(|q| (*q - p).length())
                .fold(f64::INFINITY, f64::min);
            if d > 0.0 {
                assert!(nearest >= d - 1e-6, "{kind}: sample nearer {nearest} < {d}");
                assert!(
                    nearest <= d + 0.15,
                    "{kind}: nearest sample {nearest} far from {d}"
                );
            }
        }
    }
}

mod parry_agreement {
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    use super::*;
    use parry3d_f64::math::Pose;
    use parry3d_f64::query;
    use parry3d_f64::shape::{Ball, Capsule as PCapsule, Cuboid, HalfSpace, Segment as PSegment};

    fn parry_distance(
        p1: &Pose,
        g1: &dyn parry3d_f64::shape::Shape,
        p2: &Pose,
        g2: &dyn parry3d_f64::shape::Shape,
    ) -> f64 {
        match query::distance(p1, g1, p2, g2) {
            Ok(d) => d.distance,
            Err(e) => panic!("parry: {e:?}"),
        }
    }

    #[test]
    fn segment_segment_matches_parry_exactly() {
        let mut rng = Rng::new(11);
        for _ in 0..500 {
            let (a0, a1, b0, b1) = (rng.vec3(1.0), rng.vec3(1.0), rng.vec3(1.0), rng.vec3(1.0));
            let ours = distance(
                &Primitive::Segment(LineSegment::new(a0, a1).unwrap()),
                &Primitive::Segment(LineSegment::new(b0, b1).unwrap()),
            )
            .unwrap();
            let theirs = parry_distance(
                &Pose::IDENTITY,
                &PSegment::new(a0, a1),
                &Pose::IDENTITY,
                &PSegment::new(b0, b1),
            );
            assert!(
                (ours.distance - theirs).abs() < 1e-12,
                "{} vs {theirs}",
                ours.distance
            );
        }
    }

    #[test]
    fn ball_ball_matches_parry_exactly() {
        let mut rng = Rng::new(12);
        for _ in 0..300 {
            let (c1, c2) = (rng.vec3(1.0), rng.vec3(1.0));
            let (r1, r2) = (rng.range(0.05, 0.5), rng.range(0.05, 0.5));
            let ours = distance(
                &Primitive::Sphere(Sphere::new(c1, r1).unwrap()),
                &Primitive::Sphere(Sphere::new(c2, r2).unwrap()),
            )
            .unwrap();
            let theirs = parry_distance(
                &Pose::from_translation(c1),
                &Ball::new(r1),
                &Pose::from_translation(c2),
                &Ball::new(r2),
            );
            // parry reports 0 for overlap; ours is signed.
            assert!((ours.distance.max(0.0) - theirs).abs() < 1e-12);
        }
    }

    #[test]
    fn plane_matches_parry_half_space() {
        // parry's half-space is solid; for figures above the plane the two
        // agree exactly.
        let mut rng = Rng::new(13);
        for _ in 0..300 {
            let n = rng.unit3();
            let plane = Plane::new(n, 0.0).unwrap();
            let c = n * rng.range(0.6, 2.0) + rng.vec3(0.3);
            let (a, b) = (c, c + rng.unit3() * 0.2);
            let r = rng.range(0.01, 0.2);
            let ours = distance(
                &Primitive::Plane(plane),
                &Primitive::Capsule(Capsule::new(a, b, r).unwrap()),
            )
            .unwrap();
            let theirs = parry_distance(
                &Pose::IDENTITY,
                &HalfSpace::new(n),
                &Pose::IDENTITY,
                &PCapsule::new(a, b, r),
            );
            assert!(
                (ours.distance - theirs).abs() < 1e-12,
                "{} vs {theirs}",
                ours.distance
            );
        }
    }

    #[test]
    fn capsule_and_box_within_parry_tolerance() {
        let mut rng = Rng::new(14);
        for _ in 0..300 {
            let (a0, a1, b0, b1) = (rng.vec3(1.0), rng.vec3(1.0), rng.vec3(1.0), rng.vec3(1.0));
            let (r1, r2) = (rng.range(0.01, 0.2), rng.range(0.01, 0.2));
            let ours = distance(
                &Primitive::Capsule(Capsule::new(a0, a1, r1).unwrap()),
                &Primitive::Capsule(Capsule::new(b0, b1, r2).unwrap()),
            )
            .unwrap();
            let theirs = parry_distance(
                &Pose::IDENTITY,
                &PCapsule::new(a0, a1, r1),
                &Pose::IDENTITY,
                &PCapsule::new(b0, b1, r2),
            );
            assert!(
                (ours.distance.max(0.0) - theirs).abs() < 1e-3,
                "{} vs {theirs}",
                ours.distance
            );

            let q = DQuat::from_axis_angle(rng.unit3(), rng.range(0.0, 3.0));
            let h = DVec3::new(
                rng.range(0.1, 0.4),
                rng.range(0.1, 0.4),
                rng.range(0.1, 0.4),
            );
            let c = rng.vec3(1.0);
            let ours = distance(
                &Primitive::Capsule(Capsule::new(a0, a1, r1).unwrap()),
                &Primitive::Box(OrientedBox::new(c, h, q.to_array()).unwrap()),
            )
            .unwrap();
            let pose = Pose::from_parts(c, q);
            let theirs = parry_distance(
                &Pose::IDENTITY,
                &PCapsule::new(a0, a1, r1),
                &pose,
                &Cuboid::new(h),
            );
            assert!(
                (ours.distance.max(0.0) - theirs).abs() < 1e-3,
                "{} vs {theirs}",
                ours.distance
            );
            if ours.distance < -1e-6 {
                // Penetration depth agrees with parry's contact (EPA).
                let contact = query::contact(
                    &Pose::IDENTITY,
                    &PCapsule::new(a0, a1, r1),
                    &pose,
                    &Cuboid::new(h),
                    0.0,
                )
                .unwrap()
                .unwrap();
                assert!(
                    (ours.distance - contact.dist).abs() < 1e-3,
                    "{} vs {}",
                    ours.distance,
                    contact.dist
                );
            }
        }
    }
}
