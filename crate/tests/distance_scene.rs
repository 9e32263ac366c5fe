//! The scene query (skeleton against obstacles, self-collision) and picking.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::DVec3;
use skeleton_avoidance::distance::{
    BroadPhase, Capsule, Disk, Obstacle, OrientedBox, PairDistance, Plane, Primitive, QueryOptions,
    Rectangle, Scene, Sphere, TaperedCapsule, Target, distance, parent_adjacency,
};
use skeleton_avoidance::rng::Rng;
use skeleton_avoidance::skeleton::{Segment, Skeleton, SpinePart};

/// A 7-link arm folded in a zig-zag, one segment per link (link k is the
/// child of link k − 1).
fn arm() -> Skeleton {
    let nodes = vec![
        DVec3::new(0., 0., 0.),
        DVec3::new(0., 0., 0.34),
        DVec3::new(0.2, 0., 0.6),
        DVec3::new(0.4, 0.1, 0.7),
        DVec3::new(0.55, 0.1, 0.5),
        DVec3::new(0.5, 0.3, 0.3),
        DVec3::new(0.3, 0.35, 0.25),
        DVec3::new(0.1, 0.3, 0.3),
    ];
    let segments = (0..7)
        .map(|k| Segment {
            from: k,
            to: k + 1,
            link: k + 1,
            part: SpinePart::D,
            radius: if k % 2 == 0 {
                [0.06, 0.06]
            } else {
                [0.07, 0.05]
            },
        })
        .collect();
    Skeleton {
        nodes,
        segments,
        ..Default::default()
    }
}

fn parents() -> Vec<usize> {
    (0..8).map(|k: usize| k.saturating_sub(1)).collect()
}

/// A primitive of kind `kind` (0..6: sphere, capsule, box, disk, point,
/// plane) about `c`.
fn shape(rng: &mut Rng, kind: usize, c: DVec3) -> Primitive {
    match kind {
        0 => Primitive::Sphere(Sphere::new(c, rng.range(0.02, 0.2)).unwrap()),
        1 => Primitive::Capsule(
            Capsule::new(c, c + rng.unit3() * 0.3, rng.range(0.02, 0.1)).unwrap(),
        ),
        2 => Primitive::Box(
            OrientedBox::new(c, DVec3::splat(rng.range(0.05, 0.2)), [0., 0., 0., 1.]).unwrap(),
        ),
        3 => Primitive::Disk(Disk::new(c, rng.unit3(), rng.range(0.05, 0.3)).unwrap()),
        4 => Primitive::Point(c),
        _ => Primitive::Plane(Plane::new(rng.unit3(), c.z - 1.0).unwrap()),
    }
}

fn random_scene(rng: &mut Rng, n: usize) -> Scene {
    let obstacles = (0..n)
        .map(|i| {
            let c = rng.vec3(3.0);
            Obstacle {
                id: 100 + i as u32,
                shape: shape(rng, i % 4, c),
            }
        })
        .collect();
    Scene::new(obstacles)
}

#[test]
fn broad_phase_finds_exactly_what_brute_force_finds() {
    let mut rng = Rng::new(5);
    let skeleton = arm();
    let parents = parents();
    for n in [0, 1, 7, 50, 400] {
        let scene = random_scene(&mut rng, n);
        let fast = QueryOptions {
            influence_distance: 0.4,
            ..QueryOptions::default()
        };
        let slow = QueryOptions {
            broad_phase: BroadPhase::BruteForce,
            ..fast
        };
        let a = scene
            .query(&skeleton, &fast, parent_adjacency(&parents))
            .unwrap();
        let b = scene
            .query(&skeleton, &slow, parent_adjacency(&parents))
            .unwrap();
        assert_eq!(a, b, "n = {n}");
        if n == 400 {
            assert!(
                a.iter()
                    .any(|p| matches!(p.target, Target::Obstacle { .. }))
            );
        }
    }
}

/// Obstacles of every bounded kind about the arm, with planes and points.
fn crowded_scene(rng: &mut Rng, n: usize) -> Scene {
    let obstacles = (0..n)
        .map(|i| {
            let c = DVec3::new(0.3, 0.15, 0.4) + rng.vec3(0.8);
            Obstacle {
                id: 7 * i as u32,
                shape: shape(rng, i % 6, c),
            }
        })
        .collect();
    Scene::new(obstacles)
}

#[test]
fn nearest_is_the_smallest_pair_the_query_reports() {
    let mut rng = Rng::new(11);
    let skeleton = arm();
    let options = |influence| QueryOptions {
        influence_distance: influence,
        self_collision: false,
        ..QueryOptions::default()
    };
    let smallest = |pairs: &mut dyn Iterator<Item = &PairDistance>| {
        pairs
            .min_by(|a, b| a.distance.total_cmp(&b.distance))
            .copied()
    };
    let mut kept_found = 0;
    for round in 0..200 {
        let scene = crowded_scene(&mut rng, [1, 3, 8, 20, 60][round % 5]);
        let influence = [0.02, 0.1, 0.3, 1.0][round % 4];
        let keep = |j: usize| j % 3 == 1;
        let pairs = scene
            .query(&skeleton, &options(influence), |_, _| false)
            .unwrap();
        let near = scene.nearest(&skeleton, influence, keep).unwrap();
        let kept_of =
            |p: &&PairDistance| matches!(p.target, Target::Obstacle { index, .. } if keep(index));
        for (got, want) in [
            (near.all, smallest(&mut pairs.iter())),
            (near.kept, smallest(&mut pairs.iter().filter(kept_of))),
        ] {
            assert_eq!(
                got.map(|p| p.distance),
                want.map(|p| p.distance),
                "round {round}"
            );
            // The pair itself, unless another one is as near.
            if let (Some(g), Some(w)) = (got, want) {
                let ties = pairs.iter().filter(|p| p.distance == w.distance).count();
                if ties == 1 {
                    assert_eq!(g, w, "round {round}");
                }
            }
        }
        kept_found += usize::from(near.kept.is_some());
    }
    // The scenes put obstacles within reach (not a test of empty answers).
    assert!(kept_found > 50, "{kept_found}");
}

#[test]
fn nearest_refuses_what_the_query_refuses() {
    let scene = Scene::new(Vec::new());
    let err = scene.nearest(&arm(), -1.0, |_| true).unwrap_err();
    assert!(err.to_string().contains("influenceDistance"), "{err}");
    let mut bad = arm();
    bad.nodes[3].x = f64::NAN;
    let err = scene.nearest(&bad, 0.3, |_| true).unwrap_err();
    assert!(err.to_string().contains("skeleton.nodes[3]"), "{err}");
}

#[test]
fn pairs_report_clearance_witnesses_and_fraction() {
    let skeleton = arm();
    let ball = Sphere::new(DVec3::new(0.3, -0.2, 0.3), 0.05).unwrap();
    let plane = Plane::new(DVec3::Z, 0.1).unwrap(); // z = −0.1
    let scene = Scene::new(vec![
        Obstacle {
            id: 7,
            shape: Primitive::Sphere(ball),
        },
        Obstacle {
            id: 9,
            shape: Primitive::Plane(plane),
        },
    ]);
    let opts = QueryOptions {
        influence_distance: 0.5,
        self_collision: false,
        ..Default::default()
    };
    let pairs = scene.query(&skeleton, &opts, |_, _| false).unwrap();
    assert!(!pairs.is_empty());
    for p in &pairs {
        let seg = skeleton.segments[p.segment];
        let (a, b) = skeleton.endpoints(&seg);
        let Target::Obstacle { index, id } = p.target else {
            panic!("no self pairs asked")
        };
        assert_eq!(id, if index == 0 { 7 } else { 9 });
        assert!(p.distance <= 0.5);
        assert!((0.0..=1.0).contains(&p.fraction));
        // The same as measuring the pair directly.
        let vol = if seg.radius[0] == seg.radius[1] {
            Primitive::Capsule(Capsule::new(a, b, seg.radius[0]).unwrap())
        } else {
            Primitive::TaperedCapsule(TaperedCapsule::new(a, b, seg.radius).unwrap())
        };
        let d = distance(&vol, &scene.obstacles()[index].shape).unwrap();
        assert_eq!(d.distance, p.distance);
        // The fraction locates the core point under the witness.
        let core = a + (b - a) * p.fraction;
        let r = seg.radius[0] + (seg.radius[1] - seg.radius[0]) * p.fraction;
        assert!(
            (p.point_segment - core - p.normal * r).length() < 1e-9,
            "{p:?}"
        );
    }
    // The first segment stands on the base at z = 0: 0.1 above the plane,
    // minus its radius.
    let first = pairs
        .iter()
        .find(|p| p.segment == 0 && p.target == Target::Obstacle { index: 1, id: 9 });
    assert!((first.unwrap().distance - 0.04).abs() < 1e-12);
}

#[test]
fn self_collision_skips_adjacent_links() {
    let skeleton = arm();
    let parents = parents();
    let scene = Scene::new(Vec::new());
    let opts = QueryOptions {
        influence_distance: 10.0,
        ..Default::default()
    };
    let pairs = scene
        .query(&skeleton, &opts, parent_adjacency(&parents))
        .unwrap();
    let n = skeleton.segments.len();
    // Every pair of segments whose links differ by at least 2.
    assert_eq!(pairs.len(), (n - 1) * (n - 2) / 2);
    for p in &pairs {
        let Target::Segment(j) = p.target else {
            panic!("no obstacles")
        };
        let (li, lj) = (skeleton.segments[p.segment].link, skeleton.segments[j].link);
        assert!(li.abs_diff(lj) >= 2);
    }
    // The folded arm's links 3 and 7 are close.
    let opts = QueryOptions {
        influence_distance: 0.05,
        ..Default::default()
    };
    let near = scene
        .query(&skeleton, &opts, parent_adjacency(&parents))
        .unwrap();
    assert!(near.iter().all(|p| p.distance <= 0.05));
}

#[test]
fn picking_returns_the_first_obstacle_on_the_ray() {
    let r = Rectangle::new(DVec3::new(0., 0., 2.), [DVec3::X, DVec3::Y], [0.5, 0.5]).unwrap();
    let scene = Scene::new(vec![
        Obstacle {
            id: 1,
            shape: Primitive::Sphere(Sphere::new(DVec3::new(0., 0., 5.), 1.).unwrap()),
        },
        Obstacle {
            id: 2,
            shape: Primitive::Rectangle(r),
        },
        Obstacle {
            id: 3,
            shape: Primitive::Point(DVec3::new(3., 0., 0.)),
        },
    ]);
    let hit = scene
        .pick(DVec3::ZERO, DVec3::new(0., 0., 2.), 0.05)
        .unwrap()
        .unwrap();
    assert_eq!(hit.id, 2);
    assert!((hit.point - DVec3::new(0., 0., 2.)).length() < 1e-9);
    assert!((hit.distance - 2.0).abs() < 1e-9);
    let hit = scene
        .pick(DVec3::new(0.9, 0., 0.), DVec3::Z, 0.05)
        .unwrap()
        .unwrap();
    assert_eq!(hit.id, 1);
    let hit = scene
        .pick(DVec3::new(3., 0., -1.), DVec3::Z, 0.05)
        .unwrap()
        .unwrap();
    assert_eq!(hit.id, 3);
    assert!(scene.pick(DVec3::ZERO, -DVec3::Z, 0.05).unwrap().is_none());
    assert_eq!(
        scene
            .pick(DVec3::ZERO, DVec3::ZERO, 0.05)
            .unwrap_err()
            .to_string(),
        "direction: must not be zero"
    );
}

#[test]
fn editing_an_obstacle_updates_the_hierarchy() {
    let mut scene = random_scene(&mut Rng::new(9), 64);
    let skeleton = arm();
    let opts = QueryOptions {
        influence_distance: 0.1,
        self_collision: false,
        ..Default::default()
    };
    let moved = Primitive::Sphere(Sphere::new(DVec3::new(0.0, 0.0, 0.2), 0.05).unwrap());
    scene.set_shape(10, moved).unwrap();
    let pairs = scene.query(&skeleton, &opts, |_, _| false).unwrap();
    assert!(
        pairs
            .iter()
            .any(|p| p.target == Target::Obstacle { index: 10, id: 110 })
    );
    assert!(scene.set_shape(64, Primitive::Point(DVec3::ZERO)).is_err());
}

#[test]
fn a_negative_influence_distance_is_rejected() {
    let scene = Scene::new(Vec::new());
    let opts = QueryOptions {
        influence_distance: -1.0,
        ..Default::default()
    };
    let err = scene.query(&arm(), &opts, |_, _| false).unwrap_err();
    assert_eq!(err.to_string(), "influenceDistance: must be >= 0");
}
