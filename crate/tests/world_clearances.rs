//! Per-obstacle clearances at the sample's time and `q`: every trace
//! sample's `clearances`, `World::clearance_of` and the state's nearest
//! human part against an independent distance from the skeleton at the
//! sample's `q` to the obstacle's parts posed at the sample's time (a
//! round cone against a capsule or a ball, minimised along the cone's axis
//! by a ternary search), and against the control points' own distances.
//! Moving obstacles: a person animated by a clip, by keyframes and by a
//! recorded motion-capture track, and a sphere on waypoints. Runs natively
//! and, unchanged, under `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::DVec3;
use skeleton_avoidance::distance::PrimitiveSpec;
use skeleton_avoidance::human::track::{TrackOptions, import};
use skeleton_avoidance::scenario::{self, Sample, Scenario, ShapeSpec};
use skeleton_avoidance::skeleton::Skeleton;
use skeleton_avoidance::world::{World, simulate};

/// A part as this check sees it: an axis and a radius (a ball: a point).
#[derive(Clone, Copy, Debug)]
struct Round {
    a: DVec3,
    b: DVec3,
    r: f64,
}

fn round(p: &PrimitiveSpec) -> Round {
    match p {
        PrimitiveSpec::Capsule(c) => Round {
            a: DVec3::from_array(c.a),
            b: DVec3::from_array(c.b),
            r: c.radius,
        },
        PrimitiveSpec::Sphere(s) => Round {
            a: DVec3::from_array(s.center),
            b: DVec3::from_array(s.center),
            r: s.radius,
        },
        other => panic!("not a round part: {other:?}"),
    }
}

/// Distance from `p` to the segment `a b` (closed form).
fn point_segment(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let l2 = ab.length_squared();
    let u = if l2 > 0.0 {
        ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + ab * u)).length()
}

/// Clearance between skeleton segment `k` (a round cone: the union of the
/// balls along its axis, radius linear from one end to the other) and
/// `part`: `min_u |c(u) − part axis| − r(u) − R`, convex in `u`, by a
/// ternary search.
fn segment_clearance(sk: &Skeleton, k: usize, part: Round) -> f64 {
    let s = &sk.segments[k];
    let (a, b) = (sk.nodes[s.from], sk.nodes[s.to]);
    let f = |u: f64| {
        let c = a + (b - a) * u;
        let r = s.radius[0] + (s.radius[1] - s.radius[0]) * u;
        point_segment(c, part.a, part.b) - r - part.r
    };
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    for _ in 0..200 {
        let m1 = lo + (hi - lo) / 3.0;
        let m2 = hi - (hi - lo) / 3.0;
        if f(m1) <= f(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    f(0.5 * (lo + hi)).min(f(0.0)).min(f(1.0))
}

/// The clearance from the arm at `q` to `parts`.
fn independent(world: &World, q: &[f64], parts: &[Round]) -> f64 {
    let frames = world.robot().forward(q).unwrap();
    let sk = Skeleton::build(world.robot(), &frames);
    let mut best = f64::INFINITY;
    for k in 0..sk.segments.len() {
        for p in parts {
            best = best.min(segment_clearance(&sk, k, *p));
        }
    }
    best
}

/// What one run showed.
#[derive(Debug, Default)]
struct Seen {
    checked: usize,
    /// Samples with a control point on the obstacle at its closest pair
    /// (within 1e-9 of the clearance).
    at_control_point: usize,
    smallest: f64,
    /// Samples where the state's nearest human part is the obstacle's.
    nearest_human: usize,
}

/// Runs `s` with [`simulate`] and, beside it, step by step; checks every
/// `every`-th sample of obstacle `id` against `posed(t)`, the obstacle's
/// parts at time `t`.
fn check(s: &Scenario, id: &str, every: usize, posed: &dyn Fn(f64) -> Vec<Round>) -> Seen {
    let trace = simulate(s).unwrap();
    let mut w = World::new(s.clone()).unwrap();
    let steps = (s.duration / s.dt).round() as usize;
    let sample_every = s.sample_every.max(1);
    let mut seen = Seen {
        smallest: f64::INFINITY,
        ..Seen::default()
    };
    let mut samples = trace.samples.iter();
    for k in 0..=steps {
        w.step(s.dt);
        if !k.is_multiple_of(sample_every) && k != steps {
            continue;
        }
        let sample: &Sample = samples.next().unwrap();
        let mine = w.sample();
        assert_eq!((mine.t, &mine.q), (sample.t, &sample.q), "step {k}");
        // The trace's clearance is what the world reads after that step.
        let c = sample.clearances[id];
        assert_eq!(w.clearance_of(id).unwrap(), c, "t = {}", sample.t);
        assert_eq!(w.clearances(), sample.clearances, "t = {}", sample.t);
        seen.smallest = seen.smallest.min(c);
        if !(k / sample_every).is_multiple_of(every) {
            continue;
        }
        seen.checked += 1;
        let truth = independent(&w, &sample.q, &posed(sample.t));
        assert!(
            (c - truth).abs() < 1e-9,
            "t = {}: clearance {c}, the posed parts at {truth}",
            sample.t
        );
        let state = w.state();
        for cp in state.control_points.iter().filter(|cp| cp.obstacle == id) {
            // No control point on the obstacle is closer than its clearance.
            assert!(cp.distance >= c - 1e-9, "t = {}: {cp:?}, {c}", sample.t);
        }
        let at = |cp: &&skeleton_avoidance::world::ControlPointState| {
            cp.obstacle == id && !cp.transitioning && (cp.distance - c).abs() < 1e-9
        };
        if state.control_points.iter().any(|cp| at(&cp)) {
            seen.at_control_point += 1;
        }
        if let Some(h) = &state.closest_human
            && h.part.starts_with(&format!("{id}:"))
        {
            assert!(
                (h.distance - c).abs() < 1e-9,
                "t = {}: {h:?}, {c}",
                sample.t
            );
            seen.nearest_human += 1;
        }
    }
    assert!(samples.next().is_none());
    seen
}

/// The parts of human obstacle `k` of `s` posed at `t` (no motion of its
/// own: the animation or the track moves it).
fn person(s: &Scenario, k: usize) -> impl Fn(f64) -> Vec<Round> {
    let ShapeSpec::Human(h) = &s.obstacles[k].shape else {
        panic!("not a human")
    };
    assert!(s.obstacles[k].motion.is_none());
    let body = h.compile().unwrap();
    move |t| {
        body.posed_at(t, DVec3::ZERO, DVec3::ZERO)
            .parts
            .iter()
            .map(|p| round(&p.shape))
            .collect()
    }
}

#[test]
fn the_reaching_person_of_the_shipped_example_is_measured_where_it_reaches() {
    let s = scenario::example("human-reach").unwrap();
    let seen = check(&s, "person", 3, &person(&s, 0));
    eprintln!("human-reach: {seen:?}");
    // The hand reaches into the influence distance: the person's clearance
    // comes down to the control point's (0.509 m at t = 4.91 s when the
    // clip was ignored and the sample read one step late).
    assert!(seen.smallest < 0.1, "{seen:?}");
    assert!(seen.at_control_point > seen.checked / 2, "{seen:?}");
    assert!(seen.nearest_human > 0, "{seen:?}");
    let trace = simulate(&s).unwrap();
    let at = trace
        .samples
        .iter()
        .find(|x| (x.t - 4.91).abs() < 1e-9)
        .unwrap();
    let cp = at
        .control_points
        .iter()
        .find(|c| c.obstacle == "person")
        .unwrap();
    assert!(
        (at.clearances["person"] - cp.distance).abs() < 1e-9,
        "{} against the control point's {}",
        at.clearances["person"],
        cp.distance
    );
}

/// The shipped reach scene with the person raising the right arm by
/// keyframes instead of the clip.
fn arm_raise() -> Scenario {
    let mut s = scenario::example("human-reach").unwrap();
    let ShapeSpec::Human(h) = &s.obstacles[0].shape else {
        panic!()
    };
    let mut json = serde_json::to_value(h).unwrap();
    json["animation"] = serde_json::json!({ "keyframes": [
        { "t": 0.5, "pose": { "spineFlexion": 0.45, "rightShoulderFlexion": 0.2 } },
        { "t": 2.0, "pose": { "spineFlexion": 0.5, "rightShoulderFlexion": 1.3, "rightElbow": 0.3 },
          "shift": [0.05, 0.0, 0.0] },
        { "t": 3.0, "pose": { "spineFlexion": 0.3, "rightShoulderFlexion": 0.6 } }
    ] });
    s.obstacles[0].shape = ShapeSpec::Human(serde_json::from_value(json).unwrap());
    s.duration = 3.5;
    s
}

#[test]
fn a_keyframed_arm_raise_is_measured_as_posed() {
    let s = arm_raise();
    let seen = check(&s, "person", 2, &person(&s, 0));
    eprintln!("keyframed arm raise: {seen:?}");
    assert!(seen.checked > 100 && seen.smallest < 0.35, "{seen:?}");
    assert!(seen.at_control_point > 0, "{seen:?}");
}

#[test]
fn a_recorded_walk_is_measured_as_posed() {
    // CMU subject 131 walks about 2.6 m (the file's unit is not the
    // centimetre: its scale is given, 0.265 m tall at 0.01 m per unit):
    // placed so that the walk passes the panda of the reach scene.
    let text = include_str!("data/recordings/cmu-131_01-walk.bvh");
    let options = TrackOptions {
        scale: Some(0.01 * 1.75 / 0.265),
        ..TrackOptions::default()
    };
    let track = import(text, &options).unwrap();
    let mut human = track.shape;
    human.position = [1.6, 0.6, 0.0];
    human.heading = std::f64::consts::PI;
    let mut s = scenario::example("human-reach").unwrap();
    s.obstacles[0].shape = ShapeSpec::Human(human);
    s.duration = 8.0;
    s.sample_every = 10;
    let seen = check(&s, "person", 2, &person(&s, 0));
    eprintln!("recorded walk: {seen:?}");
    assert!(seen.checked > 100 && seen.smallest < 0.35, "{seen:?}");
    assert!(seen.at_control_point > 0, "{seen:?}");
}

#[test]
fn a_sphere_on_waypoints_is_measured_where_it_is() {
    let s = scenario::example("lwr4-elbow").unwrap();
    let ShapeSpec::Primitive(PrimitiveSpec::Sphere(ball)) = &s.obstacles[0].shape else {
        panic!()
    };
    let (centre, radius) = (DVec3::from_array(ball.center), ball.radius);
    // The example's waypoints: still until 0.2 s, then 0.5 m along −y by
    // 2.2 s, in a straight line at constant speed.
    let posed = move |t: f64| {
        let u = ((t - 0.2) / 2.0).clamp(0.0, 1.0);
        let c = centre + DVec3::new(0.0, -0.5, 0.0) * u;
        vec![Round {
            a: c,
            b: c,
            r: radius,
        }]
    };
    let seen = check(&s, "ball", 1, &posed);
    eprintln!("sphere on waypoints: {seen:?}");
    assert!(seen.checked > 200 && seen.smallest < 0.2, "{seen:?}");
    assert!(seen.at_control_point > seen.checked / 2, "{seen:?}");
}
