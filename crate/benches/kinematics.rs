//! FK + skeleton + 8 control-point Jacobians (J_θ, J_a, J_d) per step.
//! Goal: ≤ 2 µs median for `lwr4` natively; `npm run bench` also times the same
//! workload in wasm under Node and prints the ratio.

use criterion::{Criterion, criterion_group, criterion_main};
use skeleton_avoidance::workloads::KinematicsStep;
use std::hint::black_box;

fn kinematics_step(c: &mut Criterion) {
    for name in ["lwr4", "panda", "dual-arm"] {
        let Ok(mut w) = KinematicsStep::new(name, 64) else {
            continue;
        };
        c.bench_function(&format!("kinematics_step/{name}"), |b| {
            b.iter(|| black_box(w.run()))
        });
    }
}

criterion_group!(benches, kinematics_step);
criterion_main!(benches);
