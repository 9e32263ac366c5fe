//! Control-point transitions are C² (issue 9, part 5): each DH value of the
//! shorter manipulator, sampled over whole routes, has continuous rate and
//! acceleration and bounded jerk through the nodes, across re-plans and
//! across retargets; fig. 5's ramps are monotone and stop at rest; a retarget
//! on the last leg moves the point no faster than its route allows.
//! Runs natively and, unchanged, under `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use skeleton_avoidance::kinematics::{Frames, Robot, presets};
use skeleton_avoidance::skeleton::Skeleton;
use skeleton_avoidance::transition::{
    MovingPoint, PointEvent, SkeletonPoint, Transition, TransitionSettings, dh_motion,
};

fn robot(name: &str) -> Robot {
    Robot::from_spec(&presets::preset(name).unwrap()).unwrap()
}

/// The DH values of the shorter manipulator that ends at `point`, as one
/// vector `[d'_1, a'_1, d'_2, a'_2, …]` (m) for a serial chain: rows before
/// the point's link complete, its own row `(d', a')`, rows after it zero.
/// Also the same vector's rates (m/s) and accelerations (m/s²) from
/// [`dh_motion`] (only the point's own row moves).
fn dh_vector(
    robot: &Robot,
    frames: &Frames,
    skeleton: &Skeleton,
    point: SkeletonPoint,
    rate: f64,
    accel: f64,
) -> [Vec<f64>; 3] {
    let (dh, m) = dh_motion(robot, frames, skeleton, point, rate, accel).unwrap();
    let n = robot.dof();
    let mut x = vec![0.0; 2 * n];
    let mut v = vec![0.0; 2 * n];
    let mut a = vec![0.0; 2 * n];
    for k in 0..dh.link - 1 {
        x[2 * k] = frames.d[k];
        x[2 * k + 1] = robot.joints[k].a;
    }
    let own = dh.link - 1;
    x[2 * own] = dh.d;
    x[2 * own + 1] = dh.a;
    v[2 * own] = m.d_rate;
    v[2 * own + 1] = m.a_rate;
    a[2 * own] = m.d_accel;
    a[2 * own + 1] = m.a_accel;
    [x, v, a]
}

/// Largest absolute change between consecutive entries of a sequence of
/// vectors (the same index), and where it happens.
fn largest_step(seq: &[Vec<f64>]) -> (f64, usize) {
    let mut worst = (0.0, 0);
    for (k, w) in seq.windows(2).enumerate() {
        for (p, q) in w[0].iter().zip(&w[1]) {
            if (q - p).abs() > worst.0 {
                worst = ((q - p).abs(), k);
            }
        }
    }
    worst
}

/// Finite differences of sampled vectors: first (rate), second
/// (acceleration) and third (jerk), each a sequence of vectors.
fn differences(xs: &[Vec<f64>], dt: f64) -> [Vec<Vec<f64>>; 3] {
    let diff = |s: &[Vec<f64>]| -> Vec<Vec<f64>> {
        s.windows(2)
            .map(|w| w[1].iter().zip(&w[0]).map(|(b, a)| (b - a) / dt).collect())
            .collect()
    };
    let v = diff(xs);
    let a = diff(&v);
    let j = diff(&a);
    [v, a, j]
}

/// The sampled DH vectors are C² with bounded jerk: the finite-difference
/// acceleration never exceeds `accel_bound` (m/s²) and the finite-difference
/// jerk never exceeds `jerk_bound` (m/s³); a step in the acceleration of
/// size ΔA would show as a jerk of ΔA / dt. Returns the largest values.
fn assert_c2(xs: &[Vec<f64>], dt: f64, accel_bound: f64, jerk_bound: f64, what: &str) -> [f64; 3] {
    let [v, a, j] = differences(xs, dt);
    let peak = |s: &[Vec<f64>]| {
        s.iter()
            .flat_map(|x| x.iter().map(|y| y.abs()))
            .fold(0.0, f64::max)
    };
    let (pv, pa, pj) = (peak(&v), peak(&a), peak(&j));
    let (_, at) = largest_step(&a);
    assert!(
        pa <= accel_bound,
        "{what}: acceleration {pa} > {accel_bound}"
    );
    assert!(
        pj <= jerk_bound,
        "{what}: jerk {pj} > {jerk_bound} (an acceleration step near sample {at})"
    );
    [pv, pa, pj]
}

#[test]
fn dh_values_are_c2_through_every_node_of_a_whole_route() {
    // planar3 (fig. 5), a standard-DH 7-DOF arm and a modified-DH one.
    for (name, q, from, to) in [
        ("planar3", vec![0.4, 0.6, -0.5], (0, 0.5), (usize::MAX, 0.5)),
        (
            "lwr4",
            vec![0.3, 0.5, -0.2, -1.0, 0.4, 0.6, 0.1],
            (0, 0.5),
            (usize::MAX, 0.5),
        ),
        (
            "panda",
            vec![0.1, -0.4, 0.2, -2.0, 0.3, 1.6, 0.5],
            (1, 0.2),
            (usize::MAX, 0.7),
        ),
        (
            "panda",
            vec![0.1, -0.4, 0.2, -2.0, 0.3, 1.6, 0.5],
            (usize::MAX, 0.7),
            (0, 0.3),
        ),
    ] {
        let robot = robot(name);
        let frames = robot.forward(&q).unwrap();
        let skeleton = Skeleton::build(&robot, &frames);
        let last = skeleton.segments.len() - 1;
        let pick = |(s, t): (usize, f64)| SkeletonPoint {
            segment: s.min(last),
            t,
        };
        let time = 0.1;
        let tr = Transition::plan(&skeleton, pick(from), 0.0, pick(to), time).unwrap();
        let legs = tr.segments().len();
        assert!(
            legs >= 3,
            "{name}: a route through several nodes ({legs} legs)"
        );
        assert!((tr.duration() - legs as f64 * time).abs() < 1e-12);
        // The longest DH value change of a leg bounds everything: a
        // rest-to-rest quintic of span L over T peaks at 15/8 L/T (rate),
        // 10/√3 L/T² (acceleration) and 60 L/T³ (jerk).
        let longest = skeleton
            .segments
            .iter()
            .map(|s| {
                let (a, b) = skeleton.endpoints(s);
                (b - a).length()
            })
            .fold(0.0, f64::max);
        let dt = 1e-5;
        let steps = (tr.duration() / dt).round() as usize + 200;
        let mut xs = Vec::with_capacity(steps + 1);
        let mut analytic = Vec::with_capacity(steps + 1);
        for k in 0..=steps {
            let s = tr.sample_at(k as f64 * dt);
            let [x, v, a] = dh_vector(&robot, &frames, &skeleton, s.point, s.rate, s.accel);
            xs.push(x);
            analytic.push((v, a));
        }
        let [pv, pa, pj] = assert_c2(
            &xs,
            dt,
            10.0 / 3f64.sqrt() * longest / (time * time) * 1.001,
            60.0 * longest / time.powi(3) * 1.001,
            name,
        );
        assert!(
            pv <= 15.0 / 8.0 * longest / time * 1.001,
            "{name}: rate {pv}"
        );
        assert!(pa > 1.0 && pj > 10.0, "{name}: the point does move");
        // The rates and accelerations that dh_motion reports (and that enter
        // eq. 3 and second-order CLIK) are the derivatives of the values.
        let [fv, fa, _] = differences(&xs, dt);
        for k in 1..fa.len() {
            for i in 0..xs[0].len() {
                let mid_v = 0.5 * (analytic[k].0[i] + analytic[k + 1].0[i]);
                assert!(
                    (fv[k][i] - mid_v).abs() < 1e-3,
                    "{name}: rate of DH value {i} at sample {k}: {} vs {mid_v}",
                    fv[k][i]
                );
                assert!(
                    (fa[k - 1][i] - analytic[k].1[i]).abs() < 0.05,
                    "{name}: acceleration of DH value {i} at sample {k}: {} vs {}",
                    fa[k - 1][i],
                    analytic[k].1[i]
                );
            }
        }
    }
}

#[test]
fn paper_fig5_each_a_value_ramps_monotonically_and_stops_at_rest_at_its_node() {
    let robot = robot("planar3");
    let frames = robot.forward(&[0.4, 0.6, -0.5]).unwrap();
    let skeleton = Skeleton::build(&robot, &frames);
    let tr = Transition::plan(
        &skeleton,
        SkeletonPoint { segment: 0, t: 0.5 },
        0.0,
        SkeletonPoint { segment: 2, t: 0.5 },
        0.1,
    )
    .unwrap();
    let dt = 1e-4;
    let mut prev: Option<[Vec<f64>; 3]> = None;
    for k in 0..=3500 {
        let time = k as f64 * dt;
        let s = tr.sample_at(time);
        let state = dh_vector(&robot, &frames, &skeleton, s.point, s.rate, s.accel);
        let a = [state[0][1], state[0][3], state[0][5]];
        // Which a(i) moves: a(1) in [0, 0.1], a(2) in [0.1, 0.2], a(3) in
        // [0.2, 0.3]; each rises monotonically, never above its end value.
        let (lo, hi) = ([0.2, 0.0, 0.0], [0.4, 0.3, 0.1]);
        for i in 0..3 {
            assert!(
                a[i] >= lo[i] - 1e-15 && a[i] <= hi[i] + 1e-15,
                "a({}) = {} at {time}",
                i + 1,
                a[i]
            );
            let rate = state[1][2 * i + 1];
            assert!(
                rate >= -1e-12,
                "a({}) falls (rate {rate}) at t = {time}",
                i + 1
            );
            let window = (0.1 * i as f64, 0.1 * (i + 1) as f64);
            if time < window.0 - 1e-9 || time > window.1 + 1e-9 {
                assert!(rate.abs() < 1e-12, "a({}) moves at t = {time}", i + 1);
            }
        }
        if let Some(p) = &prev {
            for i in 0..3 {
                assert!(
                    a[i] >= p[0][2 * i + 1] - 1e-15,
                    "a({}) dips at {time}",
                    i + 1
                );
            }
        }
        prev = Some(state);
    }
    // At each node (0.1 s, 0.2 s) and on arrival (0.3 s) the value that was
    // changing is at rest: zero rate and zero acceleration, on both sides.
    for (node, i, value) in [(0.1, 0, 0.4), (0.2, 1, 0.3), (0.3, 2, 0.1)] {
        for time in [node - 1e-9, node, node + 1e-9] {
            let s = tr.sample_at(time);
            let [x, v, a] = dh_vector(&robot, &frames, &skeleton, s.point, s.rate, s.accel);
            assert!(
                (x[2 * i + 1] - value).abs() < 1e-12,
                "a({}) at {time}",
                i + 1
            );
            assert!(v.iter().all(|r| r.abs() < 1e-6), "rates {v:?} at {time}");
            assert!(
                a.iter().all(|r| r.abs() < 1e-3),
                "accelerations {a:?} at {time}"
            );
        }
    }
    let end = tr.sample_at(0.3);
    let [x, v, a] = dh_vector(&robot, &frames, &skeleton, end.point, end.rate, end.accel);
    assert_eq!([x[1], x[3], x[5]], [0.4, 0.3, 0.1], "arrives after 0.3 s");
    assert!(
        v.iter().chain(&a).all(|r| r.abs() < 1e-9),
        "at rest on arrival"
    );
}

/// Nominal peaks of a rest-to-rest quintic leg of length `l` (m) over `time`
/// (s): rate, acceleration, jerk.
fn nominal(l: f64, time: f64) -> [f64; 3] {
    [
        15.0 / 8.0 * l / time,
        10.0 / 3f64.sqrt() * l / (time * time),
        60.0 * l / time.powi(3),
    ]
}

#[test]
fn a_retarget_on_the_last_leg_moves_the_point_no_faster_than_its_route_allows() {
    let robot = robot("planar3");
    let frames = robot.forward(&[0.4, 0.6, -0.5]).unwrap();
    let skeleton = Skeleton::build(&robot, &frames);
    let time = 0.1;
    let planned_end = 0.95;
    let mut tr = Transition::plan(
        &skeleton,
        SkeletonPoint { segment: 0, t: 0.5 },
        0.0,
        SkeletonPoint {
            segment: 2,
            t: planned_end,
        },
        time,
    )
    .unwrap();
    // Almost arrived: 0.29 s of 0.3 s, on the last leg (link 3, 0.2 m).
    let dt = 1e-3;
    for _ in 0..290 {
        tr.advance(dt);
    }
    let before = tr.sample();
    assert_eq!(before.point.segment, 2);
    // The selected point jumps back along link 3 by 0.18 m (the old cubic
    // moved the end of its leg there in one step).
    let new_end = 0.05;
    tr.retarget(new_end);
    let after = tr.sample();
    assert_eq!(after.point, before.point, "no jump in position");
    assert!((after.rate - before.rate).abs() < 1e-9, "no jump in rate");
    assert!(
        (after.accel - before.accel).abs() < 1e-6,
        "no jump in acceleration"
    );
    assert!(tr.remaining() > 0.01, "the leg is lengthened, not squeezed");
    assert_eq!(tr.target().t, new_end);
    // The documented bound: the nominal peak rate of a rest-to-rest leg of
    // length ℓ = max(planned span, distance to the new end) over the time
    // per value, or the current rate if higher.
    let link3 = 0.2;
    let span = planned_end.max((new_end - before.point.t).abs());
    let cap = (15.0 / 8.0 * span / time).max(before.rate.abs()) * link3;
    let mut prev = before.point.position(&skeleton);
    let mut worst: f64 = 0.0;
    while !tr.is_finished() {
        tr.advance(dt);
        let s = tr.sample();
        assert_eq!(s.point.segment, 2, "stays on its segment");
        let p = s.point.position(&skeleton);
        let step = (p - prev).length();
        assert!(
            step <= cap * dt * (1.0 + 1e-9),
            "moves {step} m in one step of {dt} s (bound {})",
            cap * dt
        );
        worst = worst.max(step);
        prev = p;
    }
    assert!(worst > 0.5 * cap * dt, "the point does travel ({worst})");
    let end = tr.sample();
    assert_eq!(
        end.point,
        SkeletonPoint {
            segment: 2,
            t: new_end
        }
    );
    assert!(end.rate == 0.0 && end.accel == 0.0);
    // Per step of 1 ms, at most cap · dt ≈ 3.6 mm, never the 0.18 m jump.
    assert!(cap * dt < 0.004);
}

#[test]
fn dh_values_stay_c2_across_a_retarget_and_a_drifting_target() {
    let robot = robot("planar3");
    let frames = robot.forward(&[0.4, 0.6, -0.5]).unwrap();
    let skeleton = Skeleton::build(&robot, &frames);
    let time = 0.1;
    let longest = 0.4;
    let [_, accel_bound, jerk_bound] = nominal(longest, time);
    // One retarget on the last leg, sampled finely around it.
    let mut tr = Transition::plan(
        &skeleton,
        SkeletonPoint { segment: 0, t: 0.5 },
        0.0,
        SkeletonPoint { segment: 2, t: 0.9 },
        time,
    )
    .unwrap();
    let dt = 1e-5;
    let mut xs = Vec::new();
    let mut k = 0;
    while !tr.is_finished() || k < 10 {
        if k == 25_000 {
            tr.retarget(0.2);
        }
        let s = tr.sample();
        xs.push(dh_vector(&robot, &frames, &skeleton, s.point, s.rate, s.accel)[0].clone());
        tr.advance(dt);
        k += 1;
    }
    let peaks = assert_c2(&xs, dt, accel_bound, 2.0 * jerk_bound, "one retarget");
    eprintln!("one retarget: peaks {peaks:?}, duration {}", tr.duration());
    // A selected point drifting back and forth along link 3 during the whole
    // transition: the last leg is re-shaped at every step.
    let settings = TransitionSettings {
        time_per_value: time,
        ..TransitionSettings::default()
    };
    let mut mp = MovingPoint::new(SkeletonPoint { segment: 0, t: 0.5 });
    let mut events = Vec::new();
    let dt = 1e-4;
    let mut xs = Vec::new();
    for k in 0..6000 {
        let clock = k as f64 * dt;
        let selected = SkeletonPoint {
            segment: 2,
            t: 0.5 + 0.3 * (std::f64::consts::TAU * 2.0 * clock).sin(),
        };
        mp.update(&skeleton, selected, dt, &settings, &mut events)
            .unwrap();
        if mp.transition().is_none() {
            break;
        }
        let [x, _, _] = dh_vector(
            &robot,
            &frames,
            &skeleton,
            mp.point(),
            mp.rate(),
            mp.accel(),
        );
        xs.push(x);
    }
    assert!(
        xs.len() > 3000,
        "the transition runs while the target drifts"
    );
    let peaks = assert_c2(&xs, dt, accel_bound, 2.0 * jerk_bound, "drifting target");
    eprintln!("drifting target: peaks {peaks:?}, {} steps", xs.len());
}

#[test]
fn a_replan_mid_leg_continues_position_rate_and_acceleration() {
    let robot = robot("planar3");
    let frames = robot.forward(&[0.4, 0.6, -0.5]).unwrap();
    let skeleton = Skeleton::build(&robot, &frames);
    let time = 0.1;
    let [_, accel_bound, jerk_bound] = nominal(0.4, time);
    let settings = TransitionSettings {
        time_per_value: time,
        ..TransitionSettings::default()
    };
    for (switch_at, back) in [(1_500, 0.3), (1_250, 0.9), (1_800, 0.1), (2_300, 0.3)] {
        let mut mp = MovingPoint::new(SkeletonPoint { segment: 0, t: 0.5 });
        let mut events = Vec::new();
        let dt = 1e-4;
        let mut xs = Vec::new();
        let mut states = Vec::new();
        for k in 0..8_000 {
            // Towards the middle of link 3, then, mid-way, back to link 1.
            let selected = if k < switch_at {
                SkeletonPoint { segment: 2, t: 0.5 }
            } else {
                SkeletonPoint {
                    segment: 0,
                    t: back,
                }
            };
            mp.update(&skeleton, selected, dt, &settings, &mut events)
                .unwrap();
            if k > switch_at && mp.transition().is_none() {
                break;
            }
            let s = dh_vector(
                &robot,
                &frames,
                &skeleton,
                mp.point(),
                mp.rate(),
                mp.accel(),
            );
            xs.push(s[0].clone());
            states.push(s);
        }
        assert!(
            events
                .iter()
                .any(|e| matches!(e, PointEvent::TransitionStart { replan: true, .. })),
            "re-planned at step {switch_at}"
        );
        let what = format!("re-plan at step {switch_at}");
        let peaks = assert_c2(&xs, dt, 2.0 * accel_bound, 4.0 * jerk_bound, &what);
        eprintln!("{what}: peaks {peaks:?}");
        // The analytic acceleration of the DH values, as reported to eq. 3
        // and second-order CLIK, is continuous across the re-plan.
        let k = switch_at;
        let (pre, post) = (&states[k - 1], &states[k]);
        for i in 0..pre[2].len() {
            assert!(
                (post[2][i] - pre[2][i]).abs() <= 4.0 * jerk_bound * dt,
                "{what}: acceleration of DH value {i} jumps from {} to {}",
                pre[2][i],
                post[2][i]
            );
        }
        assert_eq!(
            mp.point(),
            SkeletonPoint {
                segment: 0,
                t: back
            }
        );
    }
}
