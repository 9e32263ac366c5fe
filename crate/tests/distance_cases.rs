//! The distance engine's robustness cases, by name, and its bad-input
//! messages.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::DVec3;
use skeleton_avoidance::distance::{
    Capsule, Disk, LineSegment, OrientedBox, Plane, PointSpec, Polygon, Primitive, PrimitiveSpec,
    Rectangle, Sphere, TaperedCapsule, TaperedCapsuleSpec, distance, distance_between_specs,
};

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}
fn seg(a: DVec3, b: DVec3) -> Primitive {
    Primitive::Segment(LineSegment::new(a, b).unwrap())
}
fn near(a: DVec3, b: DVec3) -> bool {
    (a - b).length() < 1e-12
}
fn square(z: f64) -> Primitive {
    Primitive::Polygon(
        Polygon::new(vec![
            v(-1., -1., z),
            v(1., -1., z),
            v(1., 1., z),
            v(-1., 1., z),
        ])
        .unwrap(),
    )
}

#[test]
fn parallel_segments_witness_is_middle_of_overlap() {
    let a = seg(v(0., 0., 0.), v(2., 0., 0.));
    let b = seg(v(1., 1., 0.), v(4., 1., 0.));
    let d = distance(&a, &b).unwrap();
    assert!((d.distance - 1.0).abs() < 1e-12);
    assert!(!d.unique);
    assert!(near(d.point_a, v(1.5, 0., 0.)), "{d:?}");
    assert!(near(d.point_b, v(1.5, 1., 0.)));
    // The witness moves continuously with the obstacle.
    let mut last = d.point_a;
    for k in 1..=40 {
        let dx = -0.05 * f64::from(k);
        let b = seg(v(1. + dx, 1., 0.), v(4. + dx, 1., 0.));
        let d = distance(&a, &b).unwrap();
        assert!((d.point_a - last).length() <= 0.05, "jump at {dx}: {d:?}");
        last = d.point_a;
    }
    // Reversed order reports the same family.
    let r = distance(&b, &a).unwrap();
    assert!(!r.unique && near(r.point_b, v(1.5, 0., 0.)));
}

#[test]
fn collinear_overlapping_segments_touch_in_the_middle() {
    let d = distance(
        &seg(v(0., 0., 0.), v(2., 0., 0.)),
        &seg(v(3., 0., 0.), v(1., 0., 0.)),
    )
    .unwrap();
    assert_eq!(d.distance, 0.0);
    assert!(!d.unique);
    assert!(near(d.point_a, v(1.5, 0., 0.)) && near(d.point_b, v(1.5, 0., 0.)));
}

#[test]
fn collinear_disjoint_segments_meet_at_end_points() {
    let d = distance(
        &seg(v(0., 0., 0.), v(1., 0., 0.)),
        &seg(v(2., 0., 0.), v(3., 0., 0.)),
    )
    .unwrap();
    assert!((d.distance - 1.0).abs() < 1e-15 && d.unique);
    assert!(near(d.point_a, v(1., 0., 0.)) && near(d.point_b, v(2., 0., 0.)));
}

#[test]
fn zero_length_segments_behave_as_points() {
    let p = seg(v(1., 1., 0.), v(1., 1., 0.));
    let d = distance(&p, &seg(v(0., 0., 0.), v(2., 0., 0.))).unwrap();
    assert!((d.distance - 1.0).abs() < 1e-15 && d.unique);
    assert!(near(d.point_b, v(1., 0., 0.)));
    let d = distance(&p, &seg(v(3., 1., 0.), v(3., 1., 0.))).unwrap();
    assert!((d.distance - 2.0).abs() < 1e-15);
    let c = Primitive::Capsule(Capsule::new(v(0., 0., 2.), v(0., 0., 2.), 0.5).unwrap());
    let d = distance(&c, &square(0.)).unwrap();
    assert!((d.distance - 1.5).abs() < 1e-15);
}

#[test]
fn touching_figures_report_zero() {
    let s = Primitive::Sphere(Sphere::new(v(0., 0., 1.), 1.0).unwrap());
    let plane = Primitive::Plane(Plane::new(v(0., 0., 3.), 0.0).unwrap());
    assert_eq!(distance(&s, &plane).unwrap().distance, 0.0);
    let c1 = Primitive::Capsule(Capsule::new(v(0., 0., 0.), v(1., 0., 0.), 0.5).unwrap());
    let c2 = Primitive::Capsule(Capsule::new(v(0., 1., 0.), v(1., 1., 0.), 0.5).unwrap());
    assert_eq!(distance(&c1, &c2).unwrap().distance, 0.0);
    let b =
        Primitive::Box(OrientedBox::new(v(0., 0., -1.), v(1., 1., 1.), [0., 0., 0., 1.]).unwrap());
    assert_eq!(distance(&b, &s).unwrap().distance, 0.0);
    assert_eq!(
        distance(&square(0.), &seg(v(0., 0., 0.), v(0., 0., 1.)))
            .unwrap()
            .distance,
        0.0
    );
}

#[test]
fn crossing_segments_meet_and_crossing_capsules_overlap_by_both_radii() {
    let a = v(-1., 0., 0.);
    let d = distance(&seg(a, -a), &seg(v(0., -1., 0.), v(0., 1., 0.))).unwrap();
    assert_eq!(d.distance, 0.0);
    assert!(d.unique && near(d.point_a, DVec3::ZERO));
    let c1 = Primitive::Capsule(Capsule::new(a, -a, 0.2).unwrap());
    let c2 = Primitive::Capsule(Capsule::new(v(0., -1., 0.), v(0., 1., 0.), 0.3).unwrap());
    let d = distance(&c1, &c2).unwrap();
    assert!((d.distance + 0.5).abs() < 1e-15);
    // The escape direction is across both axes.
    assert!(d.normal.z.abs() > 0.999);
}

#[test]
fn segment_through_polygon_interior() {
    let d = distance(&seg(v(0.2, 0.1, -1.), v(0.2, 0.1, 1.)), &square(0.)).unwrap();
    assert!(d.distance.abs() < 1e-15);
    assert!(d.unique && near(d.point_a, v(0.2, 0.1, 0.)));
    // A non-convex polygon (an L): the segment passes through its notch.
    let l = Primitive::Polygon(
        Polygon::new(vec![
            v(0., 0., 0.),
            v(2., 0., 0.),
            v(2., 1., 0.),
            v(1., 1., 0.),
            v(1., 2., 0.),
            v(0., 2., 0.),
        ])
        .unwrap(),
    );
    let d = distance(&seg(v(1.5, 1.5, -1.), v(1.5, 1.5, 1.)), &l).unwrap();
    assert!((d.distance - 0.5).abs() < 1e-12, "{d:?}");
    let d = distance(&seg(v(0.5, 1.5, -1.), v(0.5, 1.5, 1.)), &l).unwrap();
    assert_eq!(d.distance, 0.0);
    // Through the interior of a rectangle and a disk, slanted.
    let r = Primitive::Rectangle(
        Rectangle::new(v(0., 0., 0.), [DVec3::X, DVec3::Y], [1., 1.]).unwrap(),
    );
    let d = distance(&seg(v(-0.5, 0., -1.), v(0.5, 0.2, 1.)), &r).unwrap();
    assert!(
        d.distance == 0.0 && near(d.point_a, v(0., 0.1, 0.)),
        "{d:?}"
    );
    let k = Primitive::Disk(Disk::new(v(0., 0., 0.), DVec3::Z, 1.0).unwrap());
    let d = distance(&seg(v(-0.5, 0., -1.), v(0.5, 0.2, 1.)), &k).unwrap();
    assert!(
        d.distance.abs() < 1e-12 && (d.point_a - v(0., 0.1, 0.)).length() < 1e-9,
        "{d:?}"
    );
}

#[test]
fn segment_parallel_to_plane_and_flat_figures() {
    let s = seg(v(0., 0., 1.), v(2., 0., 1.));
    let plane = Primitive::Plane(Plane::new(DVec3::Z, 0.0).unwrap());
    let d = distance(&s, &plane).unwrap();
    assert!((d.distance - 1.0).abs() < 1e-15 && !d.unique);
    assert!(near(d.point_a, v(1., 0., 1.)) && near(d.point_b, v(1., 0., 0.)));
    // Above a rectangle over x ∈ [-1, 1]: the overlap is x ∈ [0, 1].
    let r =
        Primitive::Rectangle(Rectangle::new(DVec3::ZERO, [DVec3::X, DVec3::Y], [1., 1.]).unwrap());
    let d = distance(&s, &r).unwrap();
    assert!((d.distance - 1.0).abs() < 1e-15 && !d.unique);
    assert!(near(d.point_a, v(0.5, 0., 1.)), "{d:?}");
    // Above a disk of radius 1: the same overlap.
    let k = Primitive::Disk(Disk::new(DVec3::ZERO, DVec3::Z, 1.0).unwrap());
    let d = distance(&s, &k).unwrap();
    assert!((d.distance - 1.0).abs() < 1e-15 && !d.unique && near(d.point_a, v(0.5, 0., 1.)));
    // Above a square polygon, and over a box's top face.
    let d = distance(&s, &square(0.)).unwrap();
    assert!((d.distance - 1.0).abs() < 1e-15 && !d.unique && near(d.point_a, v(0.5, 0., 1.)));
    let b =
        Primitive::Box(OrientedBox::new(v(0., 0., -1.), v(1., 1., 1.), [0., 0., 0., 1.]).unwrap());
    let d = distance(&s, &b).unwrap();
    assert!((d.distance - 1.0).abs() < 1e-15 && !d.unique && near(d.point_a, v(0.5, 0., 1.)));
    // A capsule lying on the plane's side at constant height.
    let c = Primitive::Capsule(Capsule::new(v(0., 0., 1.), v(2., 0., 1.), 0.25).unwrap());
    let d = distance(&c, &plane).unwrap();
    assert!((d.distance - 0.75).abs() < 1e-15 && !d.unique && near(d.point_a, v(1., 0., 0.75)));
    // Slightly tilted: a unique witness at the lower end.
    let d = distance(&seg(v(0., 0., 1.), v(2., 0., 1.001)), &plane).unwrap();
    assert!(d.unique && near(d.point_a, v(0., 0., 1.)));
}

#[test]
fn point_exactly_on_an_edge() {
    let p = Primitive::Point(v(1., 0.3, 0.));
    assert!(distance(&p, &square(0.)).unwrap().distance.abs() < 1e-15);
    let r =
        Primitive::Rectangle(Rectangle::new(DVec3::ZERO, [DVec3::X, DVec3::Y], [1., 1.]).unwrap());
    assert_eq!(distance(&p, &r).unwrap().distance, 0.0);
    let b =
        Primitive::Box(OrientedBox::new(v(0., 0., 1.), v(1., 1., 1.), [0., 0., 0., 1.]).unwrap());
    assert_eq!(distance(&p, &b).unwrap().distance, 0.0);
    let on_segment = distance(&p, &seg(v(1., -1., 0.), v(1., 1., 0.))).unwrap();
    assert!(on_segment.distance.abs() < 1e-15);
    let k = Primitive::Disk(Disk::new(DVec3::ZERO, DVec3::Z, 1.0).unwrap());
    assert!(
        distance(&Primitive::Point(v(0.6, 0.8, 0.)), &k)
            .unwrap()
            .distance
            .abs()
            < 1e-15
    );
    // A segment along an edge of the square touches it.
    let d = distance(&seg(v(1., -0.5, 0.), v(1., 0.5, 0.)), &square(0.)).unwrap();
    assert_eq!(d.distance, 0.0);
}

#[test]
fn solids_report_penetration_depth() {
    let b = Primitive::Box(OrientedBox::new(DVec3::ZERO, v(1., 2., 3.), [0., 0., 0., 1.]).unwrap());
    // A ball whose centre is 0.25 inside the x face.
    let s = Primitive::Sphere(Sphere::new(v(0.75, 0., 0.), 0.5).unwrap());
    let d = distance(&s, &b).unwrap();
    assert!((d.distance + 0.75).abs() < 1e-15, "{d:?}");
    assert!((d.point_b - d.point_a - d.normal * d.distance).length() < 1e-12);
    // Overlapping spheres.
    let s1 = Primitive::Sphere(Sphere::new(DVec3::ZERO, 1.0).unwrap());
    let s2 = Primitive::Sphere(Sphere::new(v(1.5, 0., 0.), 1.0).unwrap());
    assert!((distance(&s1, &s2).unwrap().distance + 0.5).abs() < 1e-15);
    // A capsule cutting a plane: the flat core crosses it, depth = radius.
    let c = Primitive::Capsule(Capsule::new(v(0., 0., -1.), v(0., 0., 1.), 0.1).unwrap());
    let plane = Primitive::Plane(Plane::new(DVec3::Z, 0.0).unwrap());
    assert!((distance(&c, &plane).unwrap().distance + 0.1).abs() < 1e-15);
    // A box straddling a plane: the smaller way out.
    let plane = Primitive::Plane(Plane::new(DVec3::X, -0.8).unwrap());
    assert!((distance(&plane, &b).unwrap().distance + 0.2).abs() < 1e-15);
    // A segment through a box: the smallest push along a separating axis.
    let d = distance(&seg(v(0.9, 0., -5.), v(0.9, 0., 5.)), &b).unwrap();
    assert!((d.distance + 0.1).abs() < 1e-12, "{d:?}");
}

#[test]
fn plane_normal_is_normalised_with_its_offset() {
    let plane = Primitive::Plane(Plane::new(v(0., 0., 2.), -2.0).unwrap());
    let d = distance(&Primitive::Point(v(5., 5., 3.)), &plane).unwrap();
    assert!((d.distance - 2.0).abs() < 1e-15 && near(d.point_b, v(5., 5., 1.)));
}

#[test]
fn tapered_capsule_is_exact_against_points_and_never_larger_elsewhere() {
    let t = TaperedCapsule::new(v(0., 0., 0.), v(1., 0., 0.), [0.4, 0.1]).unwrap();
    let tp = Primitive::TaperedCapsule(t);
    // Reference: the union of balls along the axis, densely sampled.
    let reference = |p: DVec3| {
        (0..=20_000)
            .map(|k| {
                let s = f64::from(k) / 20_000.0;
                (p - t.segment.at(s)).length() - t.radius_at(s)
            })
            .fold(f64::INFINITY, f64::min)
    };
    for p in [
        v(0.5, 1., 0.),
        v(-1., 0.2, 0.),
        v(2., 0.3, 0.1),
        v(0.3, 0.1, 0.),
        v(0.9, 0., 0.),
    ] {
        let d = distance(&tp, &Primitive::Point(p)).unwrap();
        assert!(
            (d.distance - reference(p)).abs() < 1e-6,
            "{p}: {d:?} vs {}",
            reference(p)
        );
    }
    let b = Primitive::Box(
        OrientedBox::new(
            v(0.6, 0.9, 0.),
            v(0.2, 0.2, 0.2),
            [0., 0., 0.38268343, 0.92387953],
        )
        .unwrap(),
    );
    let d = distance(&tp, &b).unwrap();
    let truth = (0..=20_000)
        .map(|k| {
            let s = f64::from(k) / 20_000.0;
            let c = Primitive::Sphere(Sphere::new(t.segment.at(s), t.radius_at(s)).unwrap());
            distance(&c, &b).unwrap().distance
        })
        .fold(f64::INFINITY, f64::min);
    assert!(
        d.distance <= truth + 1e-12 && d.distance > truth - 1e-6,
        "{d:?} vs {truth}"
    );
}

#[test]
fn bad_input_names_the_field_and_the_reason() {
    let spec = |json: &str| -> PrimitiveSpec { serde_json::from_str(json).unwrap() };
    let err = |a: PrimitiveSpec, b: PrimitiveSpec| match distance_between_specs(&a, &b) {
        Ok(d) => format!("ok {d:?}"),
        Err(e) => e.to_string(),
    };
    let pt = || spec(r#"{"type":"point","p":[0,0,0]}"#);
    let cases = [
        (
            r#"{"type":"sphere","center":[0,0,0],"radius":0}"#,
            "b.radius: must be > 0",
        ),
        (
            r#"{"type":"sphere","center":[0,0,0],"radius":-1}"#,
            "b.radius: must be > 0",
        ),
        (
            r#"{"type":"capsule","a":[0,0,0],"b":[1,0,0],"radius":0}"#,
            "b.radius: must be > 0",
        ),
        (
            r#"{"type":"plane","normal":[0,0,0],"offset":1}"#,
            "b.normal: must not be zero",
        ),
        (
            r#"{"type":"rectangle","center":[0,0,0],"axes":[[1,0,0],[1,1,0]],"halfExtents":[1,1]}"#,
            "b.axes: must be orthogonal",
        ),
        (
            r#"{"type":"rectangle","center":[0,0,0],"axes":[[1,0,0],[0,1,0]],"halfExtents":[1,0]}"#,
            "b.halfExtents[1]: must be > 0",
        ),
        (
            r#"{"type":"rectangle","center":[0,0,0],"axes":[[0,0,0],[0,1,0]],"halfExtents":[1,1]}"#,
            "b.axes[0]: must not be zero",
        ),
        (
            r#"{"type":"disk","center":[0,0,0],"normal":[0,0,1],"radius":0}"#,
            "b.radius: must be > 0",
        ),
        (
            r#"{"type":"disk","center":[0,0,0],"normal":[0,0,0],"radius":1}"#,
            "b.normal: must not be zero",
        ),
        (
            r#"{"type":"polygon","vertices":[[0,0,0],[1,0,0]]}"#,
            "b.vertices: polygon needs at least 3 vertices",
        ),
        (
            r#"{"type":"polygon","vertices":[[0,0,0],[1,0,0],[1,1,0],[0,1,0.5]]}"#,
            "b.vertices: polygon is not planar",
        ),
        (
            r#"{"type":"polygon","vertices":[[0,0,0],[2,2,0],[2,0,0],[0,1,0]]}"#,
            "b.vertices: polygon is self-intersecting",
        ),
        (
            r#"{"type":"polygon","vertices":[[0,0,0],[1,0,0],[2,0,0]]}"#,
            "b.vertices: polygon has zero area",
        ),
        (
            r#"{"type":"box","center":[0,0,0],"halfExtents":[1,1,1],"rotation":[0,0,0,0]}"#,
            "b.rotation: must not be zero",
        ),
        (
            r#"{"type":"box","center":[0,0,0],"halfExtents":[1,-1,1]}"#,
            "b.halfExtents[1]: must be > 0",
        ),
        (
            r#"{"type":"convexHull","points":[[0,0,0],[1,0,0],[0,1,0],[1,1,0]]}"#,
            "b.points: all points lie in one plane",
        ),
        (
            r#"{"type":"convexHull","points":[[0,0,0],[1,0,0],[0,1,0]]}"#,
            "b.points: needs at least 4 points",
        ),
    ];
    for (json, message) in cases {
        assert_eq!(err(pt(), spec(json)), message, "{json}");
    }
    assert_eq!(
        err(
            PrimitiveSpec::Point(PointSpec {
                p: [0., f64::NAN, 0.]
            }),
            pt()
        ),
        "a.p[1]: not a finite number"
    );
    assert_eq!(
        err(
            pt(),
            PrimitiveSpec::TaperedCapsule(TaperedCapsuleSpec {
                a: [0.; 3],
                b: [1., 0., 0.],
                radius: [0.1, f64::INFINITY]
            })
        ),
        "b.radius[1]: not a finite number"
    );
    assert_eq!(
        PrimitiveSpec::check_kind("cone")
            .unwrap_err()
            .within("a")
            .to_string(),
        "a.type: unknown primitive \"cone\""
    );
    // The JSON shapes of DESIGN.md deserialise and validate.
    for json in [
        r#"{"type":"rectangle","center":[0,0,0],"axes":[[1,0,0],[0,1,0]],"halfExtents":[1,2]}"#,
        r#"{"type":"taperedCapsule","a":[0,0,0],"b":[1,0,0],"radius":[0.2,0.1]}"#,
        r#"{"type":"box","center":[0,0,0],"halfExtents":[1,2,3],"rotation":[0,0,0,1]}"#,
        r#"{"type":"plane","normal":[0,0,1],"offset":0}"#,
    ] {
        assert!(Primitive::from_spec(&spec(json)).is_ok(), "{json}");
    }
}

#[test]
fn family_witness_moves_continuously_as_the_obstacle_slides() {
    // A capsule lying parallel above each flat figure (and a box top) while
    // the figure slides under it: the witness follows the middle of the
    // overlap, never jumping by more than the step.
    let link = Primitive::Capsule(Capsule::new(v(0., 0., 1.), v(2., 0., 1.), 0.1).unwrap());
    let figures = [
        Primitive::Rectangle(
            Rectangle::new(DVec3::ZERO, [DVec3::X, DVec3::Y], [0.5, 0.5]).unwrap(),
        ),
        Primitive::Disk(Disk::new(DVec3::ZERO, DVec3::Z, 0.5).unwrap()),
        square(0.),
        Primitive::Box(
            OrientedBox::new(v(0., 0., -0.5), v(0.5, 0.5, 0.5), [0., 0., 0., 1.]).unwrap(),
        ),
        Primitive::Capsule(Capsule::new(v(-0.5, 0.3, 0.), v(0.5, 0.3, 0.), 0.1).unwrap()),
    ];
    let step = 0.02;
    for fig in figures {
        let mut last: Option<DVec3> = None;
        for k in 0..=150 {
            let x = -0.5 + step * f64::from(k);
            let d = distance(&link, &fig.translated(v(x, 0., 0.))).unwrap();
            if let Some(p) = last {
                assert!(
                    (d.point_a - p).length() <= step + 1e-9,
                    "{fig:?} at {x}: {d:?}"
                );
            }
            last = Some(d.point_a);
        }
    }
}

#[test]
fn ear_clipping_with_a_reflex_vertex_on_a_diagonal() {
    // Vertex 3 lies exactly on the diagonal 4–1: neither 4-0-1 nor 4-1-2 is
    // an ear, and the triangles must cover the polygon, not its notch.
    let verts = vec![
        v(0., 0., 0.),
        v(1., 0., 0.),
        v(1., 0.2, 0.),
        v(0.5, 0.5, 0.),
        v(0., 1., 0.),
    ];
    let poly = Polygon::new(verts.clone()).unwrap();
    let area = |a: DVec3, b: DVec3, c: DVec3| 0.5 * (b - a).cross(c - a).z;
    let tris = poly.triangles();
    assert_eq!(tris.len(), 3);
    let total: f64 = tris
        .iter()
        .map(|t| area(verts[t[0]], verts[t[1]], verts[t[2]]))
        .sum();
    let shoelace: f64 = (0..5)
        .map(|k| area(DVec3::ZERO, verts[k], verts[(k + 1) % 5]))
        .sum();
    assert!((total - shoelace).abs() < 1e-15, "{total} vs {shoelace}");
    assert!(
        tris.iter()
            .all(|t| area(verts[t[0]], verts[t[1]], verts[t[2]]) > 0.0)
    );
    // A box above the notch is measured to the polygon, not to the notch.
    let b = Primitive::Box(
        OrientedBox::new(v(0.5, 0.6, 1.), v(0.01, 0.01, 0.01), [0., 0., 0., 1.]).unwrap(),
    );
    let d = distance(&b, &Primitive::Polygon(poly)).unwrap();
    assert!(d.distance > 0.99 + 1e-6, "{d:?}");
}

#[test]
fn flat_figures_against_each_other_side_by_side() {
    // Coplanar and crossing rectangles, polygons and disks.
    let r =
        Primitive::Rectangle(Rectangle::new(DVec3::ZERO, [DVec3::X, DVec3::Y], [1., 1.]).unwrap());
    let far = Primitive::Rectangle(
        Rectangle::new(v(3., 0., 0.), [DVec3::X, DVec3::Y], [1., 1.]).unwrap(),
    );
    let d = distance(&r, &far).unwrap();
    assert!((d.distance - 1.0).abs() < 1e-15 && !d.unique);
    assert!(
        near(d.point_a, v(1., 0., 0.)) && near(d.point_b, v(2., 0., 0.)),
        "{d:?}"
    );
    let inner = Primitive::Polygon(
        Polygon::new(vec![v(-0.2, -0.2, 0.), v(0.2, -0.2, 0.), v(0., 0.3, 0.)]).unwrap(),
    );
    assert_eq!(distance(&r, &inner).unwrap().distance, 0.0);
    let upright = Primitive::Rectangle(
        Rectangle::new(v(0., 0., 0.5), [DVec3::X, DVec3::Z], [0.3, 1.]).unwrap(),
    );
    assert!(distance(&r, &upright).unwrap().distance.abs() < 1e-15);
    let disk = Primitive::Disk(Disk::new(v(0., 0., 2.), v(1., 0., 1.), 0.5).unwrap());
    let d = distance(&r, &disk).unwrap();
    let lowest = 2.0 - 0.5 / 2f64.sqrt();
    assert!((d.distance - lowest).abs() < 1e-12, "{d:?}");
    let crossing = Primitive::Disk(Disk::new(v(0.5, 0., 0.2), DVec3::X, 0.5).unwrap());
    assert!(distance(&crossing, &square(0.)).unwrap().distance.abs() < 1e-15);
}
