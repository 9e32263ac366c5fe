//! First-order uncertainty propagation and the switch probability checked
//! against sampling (paper §IV): the standard deviations a noisy world
//! predicts for a control point's clearance, its witness's DH values, its
//! repulsion and the joint command agree within 10 % with those of 10⁴
//! worlds whose obstacle is displaced by draws of the same error; the
//! predicted probability that the closest segment differs from the ideal
//! one is within ±0.05 of the sampled frequency along a sweep across the
//! boundary between two segments (fig. 4). Runs natively and, unchanged,
//! under `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::DVec3;
use skeleton_avoidance::dependability::{EventKind, SensingSpec, SensorModel};
use skeleton_avoidance::distance::{PointSpec, PrimitiveSpec};
use skeleton_avoidance::rng::Rng;
use skeleton_avoidance::scenario::{Scenario, ShapeSpec};
use skeleton_avoidance::world::World;

/// White noise of the sensed ball (m): first order holds within 2 % here;
/// at 2 mm the command of joint 3, which barely moves the control point
/// and is set through the damped inverse, departs by 10 % (second-order
/// terms), and at 3 mm by 60 %.
const SIGMA: f64 = 0.001;
const RADIUS: f64 = 0.08;
const SAMPLES: usize = 10_000;

/// The `lwr4` with a sphere near its elbow, `radius` large, sensed with
/// white noise `sigma`.
fn elbow(center: DVec3, radius: f64, sigma: f64) -> Scenario {
    let c = center.to_array();
    Scenario::from_json(&format!(
        r#"{{ "robot": {{ "preset": "lwr4" }}, "q0": [0.0, 0.6, 0.0, -1.2, 0.0, 0.6, 0.0],
             "obstacles": [{{ "id": "ball", "shape": {{ "type": "sphere", "center": {c:?}, "radius": {radius} }} }}],
             "sensing": {{ "ball": {{ "sigma": {sigma}, "seed": 5 }} }},
             "controller": {{ "avoidance": "repulsion" }},
             "dt": 0.001, "duration": 1.0 }}"#
    ))
    .unwrap()
}

/// What one step of a world shows: clearance, witness DH values,
/// repulsion, command.
fn observe(w: &mut World) -> Vec<f64> {
    w.step(0.001);
    let s = w.state();
    let p = &s.control_points[0];
    let mut v = vec![p.distance, p.d, p.a];
    v.extend(p.repulsion);
    v.extend(&s.command);
    v
}

fn std_dev(rows: &[Vec<f64>], k: usize) -> f64 {
    let n = rows.len() as f64;
    let mean = rows.iter().map(|r| r[k]).sum::<f64>() / n;
    (rows.iter().map(|r| (r[k] - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
}

#[test]
fn propagated_standard_deviations_match_sampling_within_ten_percent() {
    // Beside the middle of link 3 (d' ≈ 0.3 of 0.4 m): away from the
    // segment's ends, where the witness is clamped and not differentiable.
    let ball = DVec3::new(-0.2259, 0.3, 0.5406);
    let mut noisy = World::new(elbow(ball, RADIUS, SIGMA)).unwrap();
    noisy.step(0.001);
    let state = noisy.state();
    let p = &state.control_points[0];
    let sigma = p.sigma.expect("a noisy obstacle has propagated deviations");
    let mut predicted = vec![sigma.distance, sigma.d, sigma.a];
    predicted.extend(sigma.repulsion);
    predicted.extend(state.command_sigma.clone().expect("command deviations"));
    // The first step saw the ball displaced by the model's first draw:
    // sample around that sensed position. The noisy world subtracted its
    // margin (3σ) from every clearance; a sphere larger by the margin gives
    // exact worlds the same clearances, normals and witnesses.
    let seen = ball
        + SensorModel::from_spec(
            &SensingSpec {
                sigma: Some(SIGMA),
                ..SensingSpec::default()
            },
            5,
        )
        .sample_at(0.0);
    let margin = state.uncertainty[0].radius;
    assert!((margin - 3.0 * SIGMA).abs() < 1e-15);
    let mut rng = Rng::new(99);
    let rows: Vec<Vec<f64>> = (0..SAMPLES)
        .map(|_| {
            let d = DVec3::new(rng.normal(), rng.normal(), rng.normal()) * SIGMA;
            let mut s = elbow(seen + d, RADIUS + margin, 0.0);
            s.sensing = Default::default();
            observe(&mut World::new(s).unwrap())
        })
        .collect();
    let largest = predicted.iter().copied().fold(0.0, f64::max);
    let names = ["distance", "d'", "a'", "vx", "vy", "vz"];
    let mut compared = 0;
    for (k, &pred) in predicted.iter().enumerate() {
        let sampled = std_dev(&rows, k);
        let name = names
            .get(k)
            .map_or_else(|| format!("q̇{}", k - 5), |s| (*s).to_owned());
        eprintln!("{name}: {pred:.4e} {sampled:.4e}");
        if pred < 1e-6 * largest && sampled < 1e-6 * largest {
            continue; // a quantity the error does not move (joint 7, a DH value fixed by the link)
        }
        assert!(
            (pred / sampled - 1.0).abs() < 0.10,
            "{name}: propagated σ {pred:.6e}, sampled {sampled:.6e}"
        );
        compared += 1;
    }
    // Distance, one DH value, three repulsion components, six joints at least.
    assert!(compared >= 10, "only {compared} quantities compared");
    assert!((sigma.distance / SIGMA - 1.0).abs() < 1e-6);
}

/// The planar arm bent at a right angle: link 1 along x from the origin to
/// (0.4, 0, 0), link 2 along y from there.
fn bent() -> World {
    let s = Scenario::from_json(
        r#"{ "robot": { "preset": "planar3" }, "q0": [0.0, 1.5707963267948966, 0.0],
             "obstacles": [], "dt": 0.001, "duration": 1.0 }"#,
    )
    .unwrap();
    World::new(s).unwrap()
}

fn point(p: DVec3) -> ShapeSpec {
    ShapeSpec::Primitive(PrimitiveSpec::Point(PointSpec { p: p.to_array() }))
}

#[test]
fn switch_probability_matches_the_sampled_frequency_across_the_boundary_of_two_segments() {
    let w = bent();
    // Correlated, white and a per-run bias: σ² = 0.006² + 0.005² + 0.01²/5.
    let sensing = SensingSpec {
        sigma: Some(0.006),
        correlated_sigma: Some(0.005),
        bias_bound: Some(0.01),
        ..SensingSpec::default()
    };
    let exact = SensingSpec::default();
    let runs = 4000;
    let mut seen_both_sides = (false, false);
    for step in -6..=6 {
        let s = f64::from(step) * 0.004;
        // Inside the elbow, 0.15 + s from link 2 and 0.15 − s from link 1.
        let p = DVec3::new(0.4 - 0.15 - s, 0.15 - s, 0.0);
        let ideal = w.risk_at(&point(p), &exact).unwrap();
        let predicted = w.risk_at(&point(p), &sensing).unwrap().switch_probability;
        let mut switched = 0;
        for run in 0..runs {
            let e = SensorModel::from_spec(&sensing, 1000 + run).sample_at(0.0);
            let sensed = w.risk_at(&point(p + e), &exact).unwrap();
            if sensed.segment != ideal.segment {
                switched += 1;
            }
        }
        let frequency = f64::from(switched) / f64::from(runs as u32);
        eprintln!("offset {s:+.3} m: predicted {predicted:.3}, sampled {frequency:.3}");
        assert!(
            (predicted - frequency).abs() <= 0.05,
            "offset {s:+.3}: predicted {predicted:.3}, sampled {frequency:.3}"
        );
        if predicted > 0.3 {
            seen_both_sides.0 = true;
        }
        if predicted < 0.05 {
            seen_both_sides.1 = true;
        }
    }
    assert!(
        seen_both_sides.0 && seen_both_sides.1,
        "the sweep must cross the boundary"
    );
}

#[test]
fn an_exactly_sensed_obstacle_has_no_deviations_and_no_switch_probability() {
    let ball = DVec3::new(-0.2259, 0.3, 0.6406);
    let mut s = elbow(ball, RADIUS, 0.0);
    s.sensing = Default::default();
    let mut w = World::new(s).unwrap();
    w.step(0.001);
    let state = w.state();
    assert!(state.control_points[0].sigma.is_none());
    assert!(state.command_sigma.is_none());
    assert!(state.uncertainty.is_empty());
    let r = bent()
        .risk_at(&point(DVec3::new(0.25, 0.15, 0.0)), &SensingSpec::default())
        .unwrap();
    assert_eq!(r.switch_probability, 0.0);
    assert!((r.clearance - (0.15 - 0.05)).abs() < 0.06, "{r:?}");
}

#[test]
fn switch_risk_events_carry_their_probability_above_the_configured_level() {
    let mut w = World::new(skeleton_avoidance::scenario::example("chattering").unwrap()).unwrap();
    for _ in 0..300 {
        w.step(0.001);
    }
    let level = w.scenario().dependability.switch_risk;
    let risks: Vec<f64> = w
        .state()
        .events
        .iter()
        .filter_map(|e| match e.kind {
            EventKind::SwitchRisk { probability, .. } => Some(probability),
            _ => None,
        })
        .collect();
    assert!(!risks.is_empty());
    assert!(risks.iter().all(|p| *p >= level && *p <= 1.0), "{risks:?}");
}

#[test]
fn risk_at_refuses_bad_sensing_and_shapes_with_the_field_named() {
    let w = bent();
    let bad = SensingSpec {
        sigma: Some(-1.0),
        ..SensingSpec::default()
    };
    let e = w.risk_at(&point(DVec3::X), &bad).unwrap_err().to_string();
    assert!(e.starts_with("sensing.sigma"), "{e}");
    let e = w
        .risk_at(
            &point(DVec3::new(f64::NAN, 0.0, 0.0)),
            &SensingSpec::default(),
        )
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("shape"), "{e}");
}
