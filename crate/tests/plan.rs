//! Global guidance ([`skeleton_avoidance::plan`]) and the `joints` task
//! that follows it: the Lipschitz bound the planner certifies segments with
//! holds on random motions of the PR2's fitted arm, a planned path keeps
//! its clearance when sampled densely, the `constraints` avoidance follows
//! a joint-space path within every limit, a PR2 problem where the reactive
//! controller stops in a local minimum is reached on a plan, and bad input
//! is refused with the field named. Runs natively and, unchanged, under
//! `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use skeleton_avoidance::plan::checker::Checker;
use skeleton_avoidance::plan::{PlanOptions, plan_path};
use skeleton_avoidance::reach::report::{Controller, Failure, classify};
use skeleton_avoidance::reach::{self, Problem};
use skeleton_avoidance::rng::Rng;
use skeleton_avoidance::scenario::{Scenario, TaskSpec, Tasks, audit};
use skeleton_avoidance::world::{World, simulate};

fn pr2(name: &str) -> Problem {
    reach::problems("pr2", None)
        .unwrap()
        .into_iter()
        .find(|p| p.name == name)
        .unwrap()
}

/// A problem the default controller leaves in a local minimum.
const STUCK: &str = "pr2/bookshelf/4";

#[test]
fn no_point_of_the_arm_moves_further_than_the_sweep_bound() {
    let p = pr2(STUCK);
    let (mut checker, start) = Checker::for_scenario(&p.scenario).unwrap();
    let robot = checker.robot().clone();
    let mut rng = Rng::new(7);
    let mut tight = 0.0_f64;
    for _ in 0..300 {
        let a: Vec<f64> = start.iter().map(|q| q + rng.range(-1.0, 1.0)).collect();
        let b: Vec<f64> = a.iter().map(|q| q + rng.range(-0.2, 0.2)).collect();
        let (mut a, mut b) = (a, b);
        robot.clamp_to_limits(&mut a);
        robot.clamp_to_limits(&mut b);
        let sweep = checker.sweep(&a, &b);
        let (oa, sa) = checker.clearances(&a).unwrap();
        let (ob, sb) = checker.clearances(&b).unwrap();
        assert!((oa - ob).abs() <= sweep + 1e-12, "{oa} {ob} {sweep}");
        assert!((sa - sb).abs() <= 2.0 * sweep + 1e-12, "{sa} {sb} {sweep}");
        // Every volume point against every point on the arm's nodes: the
        // skeleton's nodes move by no more than the bound either.
        let na = robot.forward(&a).unwrap();
        let nb = robot.forward(&b).unwrap();
        for (x, y) in na.transforms.iter().zip(&nb.transforms) {
            let moved = (x.translation - y.translation).length();
            assert!(moved <= sweep + 1e-12);
            tight = tight.max(moved / sweep);
        }
    }
    // Not so loose that it proves nothing: some origin moves by a fifth of it.
    assert!(tight > 0.2, "bound never approached: {tight}");
}

#[test]
fn a_planned_path_keeps_its_clearance_when_sampled_densely() {
    let p = pr2(STUCK);
    let plan = plan_path(
        &p.scenario,
        p.goal_q.as_ref().unwrap(),
        &PlanOptions::default(),
    )
    .unwrap();
    let (mut checker, start) = Checker::for_scenario(&p.scenario).unwrap();
    assert_eq!(plan.configurations[0], start);
    assert_eq!(plan.configurations.last(), p.goal_q.as_ref());
    assert!(plan.thresholds.obstacles >= p.scenario.controller.safety_band);
    let mut lowest = f64::INFINITY;
    for w in plan.configurations.windows(2) {
        for k in 0..=50 {
            let s = f64::from(k) / 50.0;
            let q: Vec<f64> = w[0]
                .iter()
                .zip(&w[1])
                .map(|(a, b)| a + (b - a) * s)
                .collect();
            let (o, selfs) = checker.clearances(&q).unwrap();
            assert!(o >= plan.thresholds.obstacles, "{o} at {s} of a segment");
            assert!(selfs >= plan.thresholds.self_pairs);
            lowest = lowest.min(o);
        }
    }
    // The checker's clearance is the world's: at the start, the smallest
    // obstacle clearance a world reports.
    let world = World::new(p.scenario.clone()).unwrap();
    let smallest = world
        .clearances()
        .into_values()
        .fold(f64::INFINITY, f64::min);
    let (o, _) = checker.clearances(&start).unwrap();
    assert!(
        (o - smallest).abs() < 1e-9 || smallest > 0.5,
        "{o} vs {smallest}"
    );
    eprintln!(
        "{STUCK}: {} configurations, {:.2} s, lowest sampled clearance {:.1} mm (threshold {:.1} mm), {} evaluations",
        plan.configurations.len(),
        plan.times.last().unwrap(),
        lowest * 1e3,
        plan.thresholds.obstacles * 1e3,
        plan.evaluations
    );
}

#[test]
fn a_local_minimum_of_the_reactive_controller_is_reached_on_a_plan() {
    let p = pr2(STUCK);
    let band = p.scenario.controller.safety_band;
    let reactive = reach::run(&Controller::Constraints.problem(&p)).unwrap();
    assert_eq!(classify(&reactive, band), Some(Failure::LocalMinimum));
    let (guided, plan) = Controller::Planned.guided(&p);
    assert!(plan.unwrap().is_ok());
    let o = reach::run(&guided).unwrap();
    eprintln!(
        "{STUCK}: reactive ends {:.1} mm off; planned {}",
        reactive.final_error.0 * 1e3,
        summary(&o)
    );
    assert!(o.success, "{o:?}");
    assert!(o.audit.admissible());
    assert!(o.audit.clearance >= band - 1e-6);
}

// Native only: two searches of 4000 rounds and a 10 s run take a minute
// under `wasm-pack test --node`; the planner's wasm build is exercised by
// the tests above and by `tests/node/plan.test.mjs`.
#[cfg(not(target_arch = "wasm32"))]
#[test]
fn a_start_in_contact_escapes_and_creeps_through_to_its_goal() {
    // Its fitted volumes overlap a box by 2.5 mm; once out, the first
    // search finds no path in 4000 rounds, the creeping one does.
    const IN_CONTACT: &str = "pr2/industrial_a/50";
    let p = pr2(IN_CONTACT);
    let options = PlanOptions::default();
    let (mut checker, start) = Checker::for_scenario(&p.scenario).unwrap();
    let (start_clearance, _) = checker.clearances(&start).unwrap();
    assert!(start_clearance < 0.0, "{start_clearance}");
    let goal = p.goal_q.clone().unwrap();
    let plan = plan_path(&p.scenario, &goal, &options).unwrap();
    assert!(plan.escape > 0);
    let robot = checker.robot();
    for q in &plan.configurations {
        for (v, j) in q.iter().zip(&robot.joints) {
            assert!(
                (j.min..=j.max).contains(v),
                "{v} outside [{}, {}]",
                j.min,
                j.max
            );
        }
    }
    let (guided, _) = Controller::Planned.guided(&p);
    let o = reach::run(&guided).unwrap();
    eprintln!(
        "{IN_CONTACT}: start {:.1} mm; plan of {} configurations ({} escaping), {} evaluations; {}",
        start_clearance * 1e3,
        plan.configurations.len(),
        plan.escape,
        plan.evaluations,
        summary(&o)
    );
    // Strict success: reached within 1 cm and 2°, within every limit, and
    // no contact began while the arm moved (the one at the start was there).
    assert!(o.success, "{o:?}");
    assert!(o.audit.moving_contact.is_none());
}

#[test]
fn a_path_that_turns_a_joint_back_and_forth_is_not_stopped_as_an_oscillation() {
    // Joint 1 there and back ten times in 4 s (0.1 rad each way, peak
    // 0.47 rad/s, above the monitor's 0.2 rad/s): nine reversals, more
    // than the six in 4 s the command monitor stops for, but all of them
    // the path's own.
    let configurations: Vec<Vec<f64>> = (0..=10)
        .map(|k| vec![0.1 * f64::from(k % 2), 0.0, 0.0])
        .collect();
    let times: Vec<f64> = (0..=10).map(|k| 0.4 * f64::from(k)).collect();
    let task = TaskSpec::Joints {
        configurations,
        times,
    };
    let mut world = World::new(planar(task, "constraints").unwrap()).unwrap();
    let mut peak = 0.0_f64;
    while world.time() < 4.5 {
        world.step(0.005);
        peak = peak.max(world.sample().qdot[0].abs());
    }
    assert!(peak > 0.3, "{peak}");
    let stops: Vec<String> = world
        .events()
        .iter()
        .map(|e| format!("{:?}", e.kind))
        .filter(|e| e.contains("Stop") || e.contains("Chattering"))
        .collect();
    assert!(stops.is_empty(), "{stops:?}");
    assert!(world.q()[0].abs() < 1e-3, "{:?}", world.q());
}

#[test]
fn a_start_wedged_between_boxes_is_refused_with_the_field_named() {
    // The wrist overlaps a box by 14.7 mm, another box behind it: the
    // escape gets no nearer than 5.9 mm to the box it climbs out of,
    // short of the 12 mm (safety distance and 2 mm) a path keeps.
    let p = pr2("pr2/counter/27");
    let e = plan_path(
        &p.scenario,
        p.goal_q.as_ref().unwrap(),
        &PlanOptions::default(),
    )
    .unwrap_err();
    assert_eq!(e.field, "q0");
    assert!(e.reason.contains("wedged"), "{e}");
}

// Native only, as the test above it.
#[cfg(not(target_arch = "wasm32"))]
#[test]
fn a_start_between_boxes_climbs_out_in_one_straight_segment_and_reaches_its_goal() {
    // The gripper overlaps one box by 12.6 mm with another 20 mm behind
    // it: no configuration nearby keeps the band from both. The escape
    // opens both pairs at once, stops where it gains no more, keeps those
    // pairs from closing further, and is straightened to one segment.
    const BETWEEN: &str = "pr2/industrial_b/31";
    let p = pr2(BETWEEN);
    let goal = p.goal_q.clone().unwrap();
    let plan = plan_path(&p.scenario, &goal, &PlanOptions::default()).unwrap();
    assert_eq!(plan.escape, 1);
    let (guided, _) = Controller::Planned.guided(&p);
    let o = reach::run(&guided).unwrap();
    eprintln!(
        "{BETWEEN}: plan of {} configurations, {:.2} s; {}",
        plan.configurations.len(),
        plan.times.last().unwrap(),
        summary(&o)
    );
    assert!(o.start_clearance < -0.01, "{}", o.start_clearance);
    assert!(o.success, "{o:?}");
    assert!(o.audit.moving_contact.is_none());
}

/// How a run went, for the tests' logs.
fn summary(o: &reach::Outcome) -> String {
    format!(
        "reached in {:.2} s, final {:.2} mm {:.2}°, peak q̇/limit {:.2}, q̈/limit {:.2}, jerk/limit {:.2}, clearance {:.1} mm",
        o.reached.unwrap_or(f64::NAN),
        o.final_error.0 * 1e3,
        o.final_error.1,
        o.audit.velocity,
        o.audit.acceleration,
        o.audit.jerk,
        o.audit.clearance * 1e3
    )
}

fn planar(task: TaskSpec, avoidance: &str) -> Result<Scenario, String> {
    let task = serde_json::to_value(Tasks::One(task)).unwrap();
    let v = serde_json::json!({
        "robot": { "preset": "planar3" },
        "q0": [0.0, 0.0, 0.0],
        "obstacles": [],
        "task": task,
        "controller": { "avoidance": avoidance },
        "dt": 0.005,
        "duration": 4.0,
    });
    Scenario::from_json(&v.to_string()).map_err(|e| e.to_string())
}

#[test]
fn the_constraints_avoidance_follows_a_joint_space_path_within_every_limit() {
    let configurations = vec![
        vec![0.0, 0.0, 0.0],
        vec![0.8, -0.5, 0.3],
        vec![0.2, 0.6, -0.4],
    ];
    // Within planar3's limits (peak q̇/limit 0.69).
    let times = vec![0.0, 1.5, 3.0];
    let task = TaskSpec::Joints {
        configurations: configurations.clone(),
        times,
    };
    let s = planar(task, "constraints").unwrap();
    let mut world = World::new(s.clone()).unwrap();
    // How far the arm strays from the path's segments (rad, joint space).
    let off_path = |q: &[f64]| {
        configurations
            .windows(2)
            .map(|w| {
                let d: Vec<f64> = w[1].iter().zip(&w[0]).map(|(b, a)| b - a).collect();
                let dd: f64 = d.iter().map(|x| x * x).sum();
                let u = q
                    .iter()
                    .zip(&w[0])
                    .zip(&d)
                    .map(|((q, a), d)| (q - a) * d)
                    .sum::<f64>()
                    / dd;
                let u = u.clamp(0.0, 1.0);
                q.iter()
                    .zip(&w[0])
                    .zip(&d)
                    .map(|((q, a), d)| (q - a - u * d).powi(2))
                    .sum::<f64>()
                    .sqrt()
            })
            .fold(f64::INFINITY, f64::min)
    };
    let mut worst = 0.0_f64;
    while world.time() < 4.0 {
        world.step(0.005);
        worst = worst.max(off_path(world.q()));
    }
    let end = world.q().to_vec();
    for (a, b) in end.iter().zip(&configurations[2]) {
        assert!((a - b).abs() < 1e-3, "{end:?}");
    }
    let trace = simulate(&s).unwrap();
    let a = audit(world.robot(), &trace);
    eprintln!(
        "joints task: furthest from the path {worst:.4} rad, peak q̇/limit {:.2}, q̈/limit {:.2}, jerk/limit {:.2}",
        a.velocity, a.acceleration, a.jerk
    );
    assert!(a.admissible());
    assert!(worst < 0.01, "{worst} rad off the path");
}

#[test]
fn bad_plans_and_joint_paths_are_refused_with_the_field_named() {
    let joints = |c: Vec<Vec<f64>>, t: Vec<f64>| TaskSpec::Joints {
        configurations: c,
        times: t,
    };
    let ok = || joints(vec![vec![0.0; 3]], vec![0.0]);
    let err = |r: Result<Scenario, String>| r.unwrap_err();
    let e = err(planar(ok(), "repulsion"));
    assert!(e.contains("task.type"), "{e}");
    assert!(
        err(planar(joints(vec![vec![0.0; 2]], vec![0.0]), "constraints"))
            .contains("task.configurations[0]")
    );
    assert!(
        err(planar(
            joints(vec![vec![0.0; 3]; 2], vec![1.0, 1.0]),
            "constraints"
        ))
        .contains("task.times[1]")
    );
    let v = serde_json::json!({
        "robot": { "preset": "planar3" }, "obstacles": [], "dt": 0.005, "duration": 1.0,
        "task": [{ "type": "joints", "configurations": [[0, 0, 0]], "times": [0] }, { "type": "hold" }],
    });
    let e = Scenario::from_json(&v.to_string()).unwrap_err().to_string();
    assert!(e.contains("task[0].type"), "{e}");
    let v = serde_json::json!({ "robot": { "preset": "planar3" }, "obstacles": [], "dt": 0.005, "duration": 1.0,
        "task": { "type": "joints", "times": [0] } });
    let e = Scenario::from_json(&v.to_string()).unwrap_err().to_string();
    assert!(e.contains("configurations"), "{e}");

    let p = pr2(STUCK);
    let o = PlanOptions::default();
    let field = |goal: &[f64]| plan_path(&p.scenario, goal, &o).unwrap_err().field;
    assert_eq!(field(&[0.0; 3]), "goal");
    let mut nan = p.goal_q.clone().unwrap();
    nan[2] = f64::NAN;
    assert_eq!(field(&nan), "goal[2]");
    // A goal inside a box (the start of a problem that begins in contact).
    for (bad, name) in [
        (PlanOptions { step: 0.0, ..o }, "options.step"),
        (PlanOptions { step: 1e-9, ..o }, "options.step"),
        (PlanOptions { rounds: 0, ..o }, "options.rounds"),
        (
            PlanOptions {
                time_scale: 0.5,
                ..o
            },
            "options.timeScale",
        ),
        (
            PlanOptions {
                extra_clearance: -0.1,
                ..o
            },
            "options.extraClearance",
        ),
    ] {
        let e = plan_path(&p.scenario, p.goal_q.as_ref().unwrap(), &bad).unwrap_err();
        assert_eq!(e.field, name);
    }
    let inside = pr2("pr2/industrial_b/0");
    let band = plan_path(&inside.scenario, inside.scenario.q0.as_ref().unwrap(), &o).unwrap_err();
    assert_eq!(band.field, "goal");
    assert!(band.reason.contains("safety band"), "{}", band.reason);
}
