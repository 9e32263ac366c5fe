//! NEO's programme on a bare arm: the task served through the slack, a
//! damper row kept, an infeasible programme answered with zero.

use super::*;
use crate::avoidance::protect::Guard;
use crate::kinematics::presets;
use glam::{DQuat, DVec3};

fn panda() -> Robot {
    Robot::from_spec(&presets::preset("panda").unwrap()).unwrap()
}

const Q: [f64; 7] = [0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785];

fn goal(robot: &Robot, offset: DVec3) -> TaskReference {
    let ee = robot.forward(&Q).unwrap().end_effector();
    TaskReference {
        position: ee.translation + offset,
        velocity: DVec3::ZERO,
        acceleration: DVec3::ZERO,
        orientation: Some(DQuat::from_mat3(&ee.matrix3)),
        chain: 0,
        point: None,
    }
}

fn solve_with(
    config: &ControllerConfig,
    dampers: &[Guard],
    offset: DVec3,
) -> (Vec<f64>, NeoOutcome) {
    let robot = panda();
    let frames = robot.forward(&Q).unwrap();
    let tasks = [goal(&robot, offset)];
    let input = NeoInput {
        robot: &robot,
        frames: &frames,
        q: &Q,
        tasks: &tasks,
        dampers,
        config,
    };
    let mut out = Vec::new();
    let outcome = neo_velocity(&input, &mut Workspace::default(), &mut out).unwrap();
    (out, outcome)
}

fn ee_velocity(qdot: &[f64]) -> DVec3 {
    let robot = panda();
    let frames = robot.forward(&Q).unwrap();
    let j = crate::kinematics::ik::end_effector_jacobian(&robot, &frames, 0).unwrap();
    let v = j.mul_vec(qdot);
    DVec3::new(v[0], v[1], v[2])
}

#[test]
fn the_task_is_served_towards_the_goal() {
    let config = ControllerConfig {
        avoidance: crate::avoidance::Avoidance::Neo,
        ..ControllerConfig::default()
    };
    let offset = DVec3::new(0.0, 0.2, 0.0);
    let (qdot, outcome) = solve_with(&config, &[], offset);
    assert!(outcome.solution.worst.is_none());
    assert!((outcome.error - 0.2).abs() < 1e-9, "e = {}", outcome.error);
    assert!(outcome.manipulability > 0.0);
    // The manipulability term pulls away from the task through the slack,
    // more the smaller the slack's weight; without it the task is served
    // to within the weight λ_q against λ_δ / e.
    let v = ee_velocity(&qdot);
    let wanted = config.neo.task_gain * offset;
    assert!(
        v.normalize().dot(wanted.normalize()) > 0.9,
        "{v} against {wanted}"
    );
    let mut bare = config.clone();
    bare.neo.manipulability_gain = 0.0;
    let v = ee_velocity(&solve_with(&bare, &[], offset).0);
    assert!(
        (v - wanted).length() < 0.03 * wanted.length(),
        "{v} against {wanted}"
    );
}

#[test]
fn a_damper_row_holds_and_an_infeasible_programme_commands_nothing() {
    let config = ControllerConfig {
        avoidance: crate::avoidance::Avoidance::Neo,
        ..ControllerConfig::default()
    };
    let robot = panda();
    let frames = robot.forward(&Q).unwrap();
    let j = crate::kinematics::ik::end_effector_jacobian(&robot, &frames, 0).unwrap();
    // A damper on the flange's approach along +y, which the task wants.
    let row: Vec<f64> = (0..7).map(|c| j.get(1, c)).collect();
    let damper = Guard {
        row: row.clone(),
        bound: 0.02,
        soft: 0.02,
        obstacle: Some(0),
        ..Guard::default()
    };
    let (qdot, _) = solve_with(
        &config,
        std::slice::from_ref(&damper),
        DVec3::new(0.0, 0.2, 0.0),
    );
    let approach: f64 = row.iter().zip(&qdot).map(|(a, b)| a * b).sum();
    assert!(approach <= 0.02 + 1e-9, "approach {approach}");
    assert!(approach > 0.015, "the row binds: {approach}");
    // Two rows that cannot both hold: zero.
    let back = Guard {
        row: row.iter().map(|v| -v).collect(),
        bound: -0.5,
        soft: -0.5,
        obstacle: Some(1),
        ..Guard::default()
    };
    let (qdot, outcome) = solve_with(&config, &[damper, back], DVec3::new(0.0, 0.2, 0.0));
    assert!(outcome.solution.worst.is_some());
    assert!(qdot.iter().all(|v| *v == 0.0));
}

#[test]
fn out_of_range_settings_are_refused_naming_the_field() {
    let bad = |f: fn(&mut NeoConfig)| {
        let mut c = NeoConfig::default();
        f(&mut c);
        c.validate().unwrap_err().to_string()
    };
    assert!(bad(|c| c.influence_distance = -0.1).starts_with("neo.influenceDistance"));
    assert!(
        bad(|c| c.stopping_distance = 0.3)
            .contains("neo.stoppingDistance: must be < neo.influenceDistance")
    );
    assert!(bad(|c| c.stopping_distance = -0.01).starts_with("neo.stoppingDistance"));
    assert!(bad(|c| c.damper_gain = f64::NAN).starts_with("neo.damperGain"));
    assert!(bad(|c| c.velocity_weight = 0.0).starts_with("neo.velocityWeight"));
    assert!(bad(|c| c.joint_stop = 1.0).starts_with("neo.jointStop"));
    assert!(bad(|c| c.task_gain = f64::INFINITY).starts_with("neo.taskGain"));
    assert!(NeoConfig::default().validate().is_ok());
}
