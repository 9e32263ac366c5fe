//! Closed forms against parry3d-f64 on the same random pairs, and the scene
//! query's scaling with the obstacle count.
//!
//! `cargo bench --bench distance` first prints its own table (medians of
//! many timed rounds, all measured in this run, with ratios and the largest
//! error against an exact reference), then runs the same cases under
//! criterion.

// A benchmark fails loudly on a broken setup.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::Criterion;
use glam::{DQuat, DVec3};
use parry3d_f64::math::Pose;
use parry3d_f64::query;
use parry3d_f64::shape::{
    Ball, Capsule as PCapsule, Cuboid, Cylinder, HalfSpace, Segment as PSegment, Shape, TriMesh,
};
use skeleton_avoidance::distance::{
    BroadPhase, Capsule, Disk, LineSegment, Obstacle, OrientedBox, Plane, Polygon, Primitive,
    QueryOptions, Rectangle, Scene, Sphere, distance, parent_adjacency,
};
use skeleton_avoidance::rng::Rng;
use skeleton_avoidance::skeleton::{Segment, Skeleton, SpinePart};

const PAIRS: usize = 512;

/// One pair in both representations, with an exact reference distance.
struct Case {
    ours: (Primitive, Primitive),
    theirs: (Pose, Box<dyn Shape>, Pose, Box<dyn Shape>),
    reference: f64,
}

/// Minimum over the segment of the exact point distance `f` (convex in t):
/// golden-section search to the last bit.
fn min_along(a: DVec3, b: DVec3, f: impl Fn(DVec3) -> f64) -> f64 {
    const G: f64 = 0.618_033_988_749_894_9;
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let at = |t: f64| f(a + (b - a) * t);
    for _ in 0..200 {
        let x1 = hi - G * (hi - lo);
        let x2 = lo + G * (hi - lo);
        if at(x1) <= at(x2) {
            hi = x2;
        } else {
            lo = x1;
        }
    }
    at(0.5 * (lo + hi)).min(at(0.0)).min(at(1.0))
}

fn parry_point_distance(pose: &Pose, s: &dyn Shape, p: DVec3) -> f64 {
    (s.project_point(pose, p, true).point - p).length()
}

fn capsule(rng: &mut Rng) -> (DVec3, DVec3, f64) {
    let a = rng.vec3(1.0);
    (
        a,
        a + rng.unit3() * rng.range(0.2, 0.8),
        rng.range(0.02, 0.1),
    )
}

/// Random separated pairs of one family.
fn cases(family: &str, rng: &mut Rng) -> Vec<Case> {
    let mut out = Vec::with_capacity(PAIRS);
    while out.len() < PAIRS {
        let (a, b, r) = capsule(rng);
        let cap = Primitive::Capsule(Capsule::new(a, b, r).unwrap());
        let pcap: Box<dyn Shape> = Box::new(PCapsule::new(a, b, r));
        let id = Pose::IDENTITY;
        let c = rng.vec3(1.0);
        let case = match family {
            "segment–segment" => {
                let (c0, c1, _) = capsule(rng);
                let reference = {
                    let theirs =
                        query::distance(&id, &PSegment::new(a, b), &id, &PSegment::new(c0, c1));
                    theirs.unwrap().distance
                };
                Case {
                    ours: (
                        Primitive::Segment(LineSegment::new(a, b).unwrap()),
                        Primitive::Segment(LineSegment::new(c0, c1).unwrap()),
                    ),
                    theirs: (
                        id,
                        Box::new(PSegment::new(a, b)),
                        id,
                        Box::new(PSegment::new(c0, c1)),
                    ),
                    reference,
                }
            }
            "capsule–capsule" => {
                let (c0, c1, r2) = capsule(rng);
                // The exact segment–segment distance minus the radii.
                let core = query::distance(&id, &PSegment::new(a, b), &id, &PSegment::new(c0, c1));
                Case {
                    ours: (cap, Primitive::Capsule(Capsule::new(c0, c1, r2).unwrap())),
                    theirs: (id, pcap, id, Box::new(PCapsule::new(c0, c1, r2))),
                    reference: core.unwrap().distance - r - r2,
                }
            }
            "sphere–box" | "capsule–box" => {
                let q = DQuat::from_axis_angle(rng.unit3(), rng.range(0.0, 3.0));
                let h = DVec3::new(
                    rng.range(0.1, 0.4),
                    rng.range(0.1, 0.4),
                    rng.range(0.1, 0.4),
                );
                let pose = Pose::from_parts(c, q);
                let cub = Cuboid::new(h);
                let bx = Primitive::Box(OrientedBox::new(c, h, q.to_array()).unwrap());
                if family == "sphere–box" {
                    let reference = parry_point_distance(&pose, &cub, a) - r;
                    Case {
                        ours: (Primitive::Sphere(Sphere::new(a, r).unwrap()), bx),
                        theirs: (
                            Pose::from_translation(a),
                            Box::new(Ball::new(r)),
                            pose,
                            Box::new(cub),
                        ),
                        reference,
                    }
                } else {
                    let reference = min_along(a, b, |p| parry_point_distance(&pose, &cub, p)) - r;
                    Case {
                        ours: (cap, bx),
                        theirs: (id, pcap, pose, Box::new(cub)),
                        reference,
                    }
                }
            }
            "capsule–rectangle" => {
                let n = rng.unit3();
                let u = n.any_orthonormal_vector();
                let v = n.cross(u);
                let h = [rng.range(0.1, 0.5), rng.range(0.1, 0.5)];
                let rot = DQuat::from_mat3(&glam::DMat3::from_cols(u, v, n));
                let pose = Pose::from_parts(c, rot);
                let cub = Cuboid::new(DVec3::new(h[0], h[1], 0.0));
                let reference = min_along(a, b, |p| parry_point_distance(&pose, &cub, p)) - r;
                Case {
                    ours: (
                        cap,
                        Primitive::Rectangle(Rectangle::new(c, [u, v], h).unwrap()),
                    ),
                    theirs: (id, pcap, pose, Box::new(cub)),
                    reference,
                }
            }
            "capsule–disk" => {
                let n = rng.unit3();
                let radius = rng.range(0.1, 0.5);
                let pose = Pose::from_parts(c, DQuat::from_rotation_arc(DVec3::Y, n));
                let cyl = Cylinder::new(0.0, radius);
                let reference = min_along(a, b, |p| parry_point_distance(&pose, &cyl, p)) - r;
                Case {
                    ours: (cap, Primitive::Disk(Disk::new(c, n, radius).unwrap())),
                    theirs: (id, pcap, pose, Box::new(cyl)),
                    reference,
                }
            }
            "capsule–polygon" => {
                let n = rng.unit3();
                let u = n.any_orthonormal_vector();
                let v = n.cross(u);
                let size = rng.range(0.1, 0.5);
                let verts: Vec<DVec3> = (0..6)
                    .map(|k| {
                        let t = f64::from(k) * std::f64::consts::TAU / 6.0;
                        c + (u * t.cos() + v * t.sin()) * size
                    })
                    .collect();
                let idx = (1..5).map(|k| [0, k, k + 1]).collect();
                let mesh = TriMesh::new(verts.clone(), idx).unwrap();
                let reference = min_along(a, b, |p| parry_point_distance(&id, &mesh, p)) - r;
                Case {
                    ours: (cap, Primitive::Polygon(Polygon::new(verts).unwrap())),
                    theirs: (id, pcap, id, Box::new(mesh)),
                    reference,
                }
            }
            _ => {
                // capsule–plane
                let n = rng.unit3();
                let plane = Plane::new(n, -n.dot(c)).unwrap();
                let (sa, sb) = (plane.signed_distance(a), plane.signed_distance(b));
                let reference = sa.min(sb) - r;
                Case {
                    ours: (cap, Primitive::Plane(plane)),
                    theirs: (
                        id,
                        pcap,
                        Pose::from_translation(c),
                        Box::new(HalfSpace::new(n)),
                    ),
                    reference,
                }
            }
        };
        // Separated pairs only (parry's distance is unsigned), and for the
        // half-space figures entirely above the plane.
        if case.reference > 1e-3 {
            out.push(case);
        }
    }
    out
}

/// Median time per query (ns) over `rounds` rounds of all pairs.
fn median_ns(rounds: usize, n: usize, mut f: impl FnMut()) -> f64 {
    let mut times: Vec<f64> = (0..rounds)
        .map(|_| {
            let t0 = Instant::now();
            f();
            t0.elapsed().as_secs_f64() * 1e9 / n as f64
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// Medians (ns per query) of several workloads timed in alternating rounds.
fn interleaved_medians<const K: usize>(
    rounds: usize,
    n: usize,
    mut fs: [&mut dyn FnMut(); K],
) -> [f64; K] {
    let mut times = vec![Vec::with_capacity(rounds); K];
    for _ in 0..rounds {
        for (k, f) in fs.iter_mut().enumerate() {
            let t0 = Instant::now();
            f();
            times[k].push(t0.elapsed().as_secs_f64() * 1e9 / n as f64);
        }
    }
    let mut out = [0.0; K];
    for (k, t) in times.iter_mut().enumerate() {
        t.sort_by(f64::total_cmp);
        out[k] = t[t.len() / 2];
    }
    out
}

const FAMILIES: [&str; 8] = [
    "segment–segment",
    "capsule–capsule",
    "sphere–box",
    "capsule–box",
    "capsule–rectangle",
    "capsule–disk",
    "capsule–polygon",
    "capsule–plane",
];

fn pair_table() {
    println!(
        "\n## Ours vs parry3d-f64 ({PAIRS} random separated pairs per family, median ns per query)\n"
    );
    println!(
        "| pair | ours | parry distance | parry closest_points | ratio (distance) | ratio (closest) | our max error | parry max error |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|");
    let mut rng = Rng::new(2026);
    for family in FAMILIES {
        let cs = cases(family, &mut rng);
        // Interleaved rounds, so that load changes on a shared machine hit
        // all three alike.
        let [ours, theirs, theirs_cp] = interleaved_medians(
            41,
            cs.len(),
            [
                &mut || {
                    for c in &cs {
                        black_box(distance(black_box(&c.ours.0), black_box(&c.ours.1)).unwrap());
                    }
                },
                &mut || {
                    for c in &cs {
                        let (p1, s1, p2, s2) = &c.theirs;
                        black_box(query::distance(p1, s1.as_ref(), p2, s2.as_ref()).unwrap());
                    }
                },
                &mut || {
                    for c in &cs {
                        let (p1, s1, p2, s2) = &c.theirs;
                        black_box(
                            query::closest_points(p1, s1.as_ref(), p2, s2.as_ref(), f64::MAX)
                                .unwrap(),
                        );
                    }
                },
            ],
        );
        let mut err_ours: f64 = 0.0;
        let mut err_theirs: f64 = 0.0;
        for c in &cs {
            let d = distance(&c.ours.0, &c.ours.1).unwrap().distance;
            err_ours = err_ours.max((d - c.reference).abs());
            let (p1, s1, p2, s2) = &c.theirs;
            let t = query::distance(p1, s1.as_ref(), p2, s2.as_ref())
                .unwrap()
                .distance;
            err_theirs = err_theirs.max((t - c.reference).abs());
        }
        println!(
            "| {family} | {ours:.0} | {theirs:.0} | {theirs_cp:.0} | {:.1}× | {:.1}× | {err_ours:.1e} | {err_theirs:.1e} |",
            theirs / ours,
            theirs_cp / ours
        );
    }
}

/// A 7-DOF-like arm: nine segments along a bent chain (link k is the child
/// of link k − 1), capsules and tapered capsules.
fn arm() -> Skeleton {
    let nodes = vec![
        DVec3::new(0., 0., 0.),
        DVec3::new(0., 0., 0.31),
        DVec3::new(0.05, 0., 0.4),
        DVec3::new(0.1, 0.05, 0.71),
        DVec3::new(0.2, 0.05, 0.8),
        DVec3::new(0.45, 0.1, 0.85),
        DVec3::new(0.6, 0.1, 0.75),
        DVec3::new(0.7, 0.15, 0.6),
        DVec3::new(0.75, 0.15, 0.5),
        DVec3::new(0.78, 0.15, 0.42),
    ];
    let segments = (0..9)
        .map(|k| Segment {
            from: k,
            to: k + 1,
            link: k.min(6) + 1,
            part: SpinePart::D,
            radius: if k % 3 == 1 {
                [0.07, 0.05]
            } else {
                [0.06, 0.06]
            },
        })
        .collect();
    Skeleton {
        nodes,
        segments,
        ..Default::default()
    }
}

/// A sparse scene: `n` obstacles spread over a 20 m cube around the arm (the
/// same density for every `n` would pack the small scenes; here a few of the
/// obstacles lie within the influence distance).
fn scene(n: usize) -> Scene {
    let mut rng = Rng::new(77);
    let obstacles = (0..n)
        .map(|i| {
            let c = rng.vec3(5.0);
            let shape = match i % 4 {
                0 => Primitive::Sphere(Sphere::new(c, 0.1).unwrap()),
                1 => Primitive::Capsule(Capsule::new(c, c + rng.unit3() * 0.3, 0.05).unwrap()),
                2 => Primitive::Box(
                    OrientedBox::new(c, DVec3::splat(0.1), [0., 0., 0., 1.]).unwrap(),
                ),
                _ => Primitive::Disk(Disk::new(c, rng.unit3(), 0.2).unwrap()),
            };
            Obstacle {
                id: i as u32,
                shape,
            }
        })
        .collect();
    Scene::new(obstacles)
}

fn scene_table() {
    let skeleton = arm();
    let parents: Vec<usize> = (0..8).map(|k: usize| k.saturating_sub(1)).collect();
    let opts = QueryOptions {
        influence_distance: 0.3,
        self_collision: true,
        ..Default::default()
    };
    let brute = QueryOptions {
        broad_phase: BroadPhase::BruteForce,
        ..opts
    };
    println!(
        "\n## Scene query: 9-segment arm, sparse scene, influence 0.3 m (median µs per query)\n"
    );
    println!("| N | broad phase | brute force | pairs reported | obstacle pairs |");
    println!("|---:|---:|---:|---:|---:|");
    let mut t = Vec::new();
    for n in [10, 100, 1000] {
        let s = scene(n);
        let pairs = s
            .query(&skeleton, &opts, parent_adjacency(&parents))
            .unwrap();
        let obstacle_pairs = pairs
            .iter()
            .filter(|p| {
                matches!(
                    p.target,
                    skeleton_avoidance::distance::Target::Obstacle { .. }
                )
            })
            .count();
        let iters = 200;
        let fast = median_ns(21, iters, || {
            for _ in 0..iters {
                black_box(
                    s.query(black_box(&skeleton), &opts, parent_adjacency(&parents))
                        .unwrap(),
                );
            }
        }) / 1e3;
        let slow = median_ns(21, iters.min(40), || {
            for _ in 0..iters.min(40) {
                black_box(
                    s.query(black_box(&skeleton), &brute, parent_adjacency(&parents))
                        .unwrap(),
                );
            }
        }) / 1e3;
        println!(
            "| {n} | {fast:.2} | {slow:.2} | {} | {obstacle_pairs} |",
            pairs.len()
        );
        t.push((fast, slow));
    }
    println!(
        "\nt(1000) / t(100) with the broad phase: {:.2} (goal ≤ 3); at N = 10 broad phase / brute force: {:.2} (goal ≤ 1)",
        t[2].0 / t[1].0,
        t[0].0 / t[0].1
    );
}

fn criterion_benches(c: &mut Criterion) {
    let mut rng = Rng::new(2026);
    for family in ["capsule–capsule", "capsule–box", "capsule–disk"] {
        let cs = cases(family, &mut rng);
        let mut g = c.benchmark_group(family);
        g.bench_function("ours", |b| {
            b.iter(|| {
                for c in &cs {
                    black_box(distance(&c.ours.0, &c.ours.1).unwrap());
                }
            });
        });
        g.bench_function("parry", |b| {
            b.iter(|| {
                for c in &cs {
                    let (p1, s1, p2, s2) = &c.theirs;
                    black_box(query::distance(p1, s1.as_ref(), p2, s2.as_ref()).unwrap());
                }
            });
        });
        g.finish();
    }
    let skeleton = arm();
    let parents: Vec<usize> = (0..8).map(|k: usize| k.saturating_sub(1)).collect();
    let opts = QueryOptions {
        influence_distance: 0.3,
        ..Default::default()
    };
    let mut g = c.benchmark_group("scene query");
    for n in [10, 100, 1000] {
        let s = scene(n);
        g.bench_function(format!("N={n}"), |b| {
            b.iter(|| {
                black_box(
                    s.query(&skeleton, &opts, parent_adjacency(&parents))
                        .unwrap(),
                )
            });
        });
    }
    g.finish();
}

fn main() {
    pair_table();
    scene_table();
    let mut c = Criterion::default()
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1))
        .sample_size(20)
        .configure_from_args();
    criterion_benches(&mut c);
    c.final_summary();
}
