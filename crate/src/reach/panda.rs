//! Seeded random Panda problems: from a random configuration to the pose
//! of another one nearby, among one to three spheres and boxes placed near
//! the straight path of the end effector.

use glam::{DQuat, DVec3};
use serde_json::{Value, json};

use super::{DT, Problem, clearance_at, scenario_json};
use crate::error::FieldError;
use crate::kinematics::{Robot, presets};
use crate::rng::Rng;
use crate::scenario::Scenario;
use crate::world::World;

/// `count` seeded random Panda problems (see the module docs).
///
/// # Errors
/// Only through a bug (the Panda preset is built in).
pub fn panda_problems(seed: u64, count: usize) -> Result<Vec<Problem>, FieldError> {
    let spec = presets::preset("panda")?;
    let robot = Robot::from_spec(&spec)?;
    let mut rng = Rng::new(seed);
    let mut out = Vec::new();
    let ready = [0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785];
    while out.len() < count {
        let jitter = |rng: &mut Rng, q: &[f64], s: f64| -> Vec<f64> {
            q.iter()
                .zip(&robot.joints)
                .map(|(v, j)| (v + rng.range(-s, s)).clamp(j.min + 0.1, j.max - 0.1))
                .collect()
        };
        let start = jitter(&mut rng, &ready, 0.5);
        let goal_q = jitter(&mut rng, &start, 0.6);
        let a = robot.forward(&start)?.end_effector().translation;
        let g = robot.forward(&goal_q)?.end_effector();
        let (b, orientation) = (g.translation, DQuat::from_mat3(&g.matrix3));
        if (b - a).length() < 0.15 {
            continue;
        }
        let obstacles = random_obstacles(&mut rng, a, b);
        let scenario = scenario_json(
            json!({ "preset": "panda" }),
            &start,
            obstacles,
            b,
            orientation,
        )?;
        // Both ends must be clear of every obstacle, and of the arm's own
        // links, by more than the safety band, or the problem has no
        // solution (with the Panda's fitted volumes a folded random pose
        // can overlap its own wrist and upper arm).
        if !clear(&scenario, &start)?
            || !clear(&scenario, &goal_q)?
            || !self_clear(&scenario, &start)?
            || !self_clear(&scenario, &goal_q)?
        {
            continue;
        }
        out.push(Problem {
            name: format!("panda/{seed}/{}", out.len()),
            scenario,
            position: b,
            orientation,
            goal_q: Some(goal_q),
        });
    }
    Ok(out)
}

/// One to three spheres and boxes near the straight path from `a` to `b`,
/// static or moving at 0.1–0.5 m/s across it.
fn random_obstacles(rng: &mut Rng, a: DVec3, b: DVec3) -> Vec<Value> {
    let count = 1 + (rng.range(0.0, 3.0) as usize).min(2);
    let dir = (b - a).normalize_or_zero();
    let side = dir.any_orthonormal_vector();
    (0..count)
        .map(|k| {
            let along = a + (b - a) * rng.range(0.3, 0.7);
            let off = side.rotate_towards(dir.cross(side), rng.range(0.0, std::f64::consts::TAU))
                * rng.range(0.12, 0.25);
            let center = along + off;
            let shape = if rng.range(0.0, 1.0) < 0.5 {
                json!({ "type": "sphere", "center": center.to_array(), "radius": rng.range(0.03, 0.08) })
            } else {
                let h = rng.range(0.03, 0.07);
                json!({ "type": "box", "center": center.to_array(), "halfExtents": [h, h, h] })
            };
            let mut o = json!({ "id": format!("o{k}"), "shape": shape });
            if rng.range(0.0, 1.0) < 0.5 {
                // Moving across the path, towards it.
                let v = -off.normalize_or_zero() * rng.range(0.1, 0.5);
                o["motion"] = json!({ "type": "waypoints", "points": [[0, 0, 0], (v * 1.0).to_array()],
                                      "times": [0.0, 1.0] });
            }
            o
        })
        .collect()
}

/// Whether the arm at `q` keeps more than 5 cm from every obstacle of
/// `scenario` over its whole motion (sampled every 0.1 s).
fn clear(scenario: &Scenario, q: &[f64]) -> Result<bool, FieldError> {
    let mut s = scenario.clone();
    s.q0 = Some(q.to_vec());
    s.controller.protective.enabled = false;
    s.controller.self_collision = false;
    s.task = crate::scenario::Tasks::default();
    let mut world = World::new(s).map_err(|e| FieldError::new("scenario", e.to_string()))?;
    for _ in 0..20 {
        for _ in 0..20 {
            world.step(DT);
        }
        if world.sample().min_clearance.is_some_and(|c| c < 0.05) {
            return Ok(false);
        }
    }
    Ok(true)
}

/// Whether the arm's non-adjacent links at `q` are further apart than the
/// scenario's safety band.
fn self_clear(scenario: &Scenario, q: &[f64]) -> Result<bool, FieldError> {
    let mut s = scenario.clone();
    s.obstacles.clear();
    let band = s.controller.safety_band;
    let c = clearance_at(&s, q)?;
    Ok(c > band)
}
