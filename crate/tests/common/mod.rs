//! Helpers shared by the integration tests (`mod common;`).

#![allow(dead_code)]

use skeleton_avoidance::scenario::Trace;

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
