//! Helpers shared by the integration tests (`mod common;`).

#![allow(dead_code, clippy::unwrap_used)]

use glam::DVec3;
use skeleton_avoidance::control_point::{DhPoint, a_span, d_span};
use skeleton_avoidance::kinematics::{Frames, Robot, presets};
use skeleton_avoidance::rng::Rng;
use skeleton_avoidance::scenario::Trace;

/// The preset `name`, built.
pub fn robot(name: &str) -> Robot {
    Robot::from_spec(&presets::preset(name).unwrap()).unwrap()
}

/// Random joint values within the limits (±3 where a joint has none).
pub fn random_q(robot: &Robot, rng: &mut Rng) -> Vec<f64> {
    robot
        .joints
        .iter()
        .map(|j| {
            let (lo, hi) = if j.min.is_finite() {
                (j.min, j.max)
            } else {
                (-3.0, 3.0)
            };
            rng.range(lo, hi)
        })
        .collect()
}

/// A random point of link `link`: on the spine or anywhere in the span box.
pub fn random_point(robot: &Robot, frames: &Frames, link: usize, rng: &mut Rng) -> DhPoint {
    let (dl, dh) = d_span(frames, link);
    let (al, ah) = a_span(robot, link);
    DhPoint {
        link,
        d: rng.range(dl, dh),
        a: rng.range(al, ah),
    }
}

/// Whether `a` and `b` agree to `tol`, relative to their size (≥ 1 m).
pub fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
    (a - b).length() <= tol * (1.0 + a.length().max(b.length()))
}

/// FNV-1a over the trace's numbers (bit patterns) and strings, in order.
pub fn trace_hash(trace: &Trace) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |bytes: &[u8]| {
        for b in bytes {
            h ^= u64::from(*b);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    };
    for s in &trace.samples {
        eat(&s.t.to_bits().to_le_bytes());
        for q in &s.q {
            eat(&q.to_bits().to_le_bytes());
        }
        eat(&s.min_clearance.unwrap_or(f64::NAN).to_bits().to_le_bytes());
        for c in &s.control_points {
            for x in c.position {
                eat(&x.to_bits().to_le_bytes());
            }
            eat(&(c.link as u64).to_le_bytes());
            eat(&c.d.to_bits().to_le_bytes());
            eat(&c.a.to_bits().to_le_bytes());
            eat(c.obstacle.as_bytes());
            eat(&c.distance.to_bits().to_le_bytes());
        }
    }
    for e in &trace.events {
        eat(&e.t.to_bits().to_le_bytes());
        eat(format!("{:?}", e.kind).as_bytes());
    }
    h
}
