//! One full control step (FK, skeleton, scene query, control points,
//! transitions, Jacobians, controller, integration) of `lwr4` among N static
//! sphere obstacles. Goals (issue 5): ≤ 10 / 50 / 330 µs median for N = 10 /
//! 100 / 1000 natively; `npm run bench` can time the same workload in wasm
//! through `benchControlStep`.

use criterion::{Criterion, criterion_group, criterion_main};
use skeleton_avoidance::world::control_step_workload;
use std::hint::black_box;

fn control_step(c: &mut Criterion) {
    for n in [10, 20, 100, 1000] {
        let Ok(mut world) = control_step_workload(n) else {
            continue;
        };
        let start = world.clone();
        let mut steps = 0;
        c.bench_function(&format!("control_step/lwr4/{n}"), |b| {
            b.iter(|| {
                // Stay within the scripted 4 s so the workload does not drift.
                steps += 1;
                if steps == 4000 {
                    world = start.clone();
                    steps = 0;
                }
                world.step(0.001);
                black_box(world.time())
            });
        });
    }
}

criterion_group!(benches, control_step);
criterion_main!(benches);
