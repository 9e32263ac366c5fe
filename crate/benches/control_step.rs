//! One full control step (FK, skeleton, scene query, control points,
//! transitions, Jacobians, controller, integration) of `lwr4` among N static
//! sphere obstacles. Goals (issue 5): ≤ 10 / 50 / 330 µs median for N = 10 /
//! 100 / 1000 natively, and wasm within 1.5×. The row `human+10` adds an
//! articulated human walking past the arm (sixteen moving parts) to the ten
//! spheres.
//!
//! `cargo bench --bench control_step` runs criterion. With `SA_BATCH_SERVE=1`
//! it instead times batches on request (`common/serve.rs`): `npm run bench`
//! times each one back to back with the same batch in wasm
//! (`benchControlStep`, scripts/bench-pairs.mjs), so that the ratio is
//! measured under the same load. Both sides keep their world from batch to
//! batch and rewind it every 4000 steps, so that a pair times the same steps
//! of the scene (a step costs more while the human passes the arm).

use criterion::Criterion;
use skeleton_avoidance::workloads::control_step_human_workload;
use skeleton_avoidance::world::{World, control_step_workload};
use std::hint::black_box;

#[path = "common/serve.rs"]
mod serve;

/// The workload named `id` (`control_step/lwr4/<N>` or
/// `control_step/lwr4/human+10`) with its start and step count, for
/// [`serve::serve`].
fn served(id: &str) -> Option<(World, World, u32)> {
    let world = match id.strip_prefix("control_step/lwr4/")? {
        "human+10" => control_step_human_workload(10).ok()?,
        n => control_step_workload(n.parse().ok()?).ok()?,
    };
    Some((world.clone(), world, 0))
}

const SIZES: [usize; 4] = [10, 20, 100, 1000];

/// Steps `world`, rewinding to `start` every 4000 steps so that the scripted
/// 4 s scene does not drift.
fn step(world: &mut World, start: &World, steps: &mut u32) -> f64 {
    *steps += 1;
    if *steps == CYCLE {
        *world = start.clone();
        *steps = 0;
    }
    world.step(0.001);
    world.time()
}

fn criterion_benches(c: &mut Criterion) {
    for n in SIZES {
        let Ok(mut world) = control_step_workload(n) else {
            continue;
        };
        let start = world.clone();
        let mut steps = 0;
        c.bench_function(&format!("control_step/lwr4/{n}"), |b| {
            b.iter(|| black_box(step(&mut world, &start, &mut steps)));
        });
    }
    if let Ok(mut world) = control_step_human_workload(10) {
        let start = world.clone();
        let mut steps = 0;
        c.bench_function("control_step/lwr4/human+10", |b| {
            b.iter(|| black_box(step(&mut world, &start, &mut steps)));
        });
    }
}

/// Steps of the scripted scene before it is rewound (4 s at 1 kHz).
const CYCLE: u32 = 4000;

fn main() {
    if std::env::var_os("SA_BATCH_SERVE").is_some() {
        let made = serve::serve(served, |(world, start, steps)| step(world, start, steps));
        if let Err(e) = made {
            eprintln!("control_step: serving batches failed: {e}");
            std::process::exit(1);
        }
        return;
    }
    let mut c = Criterion::default().configure_from_args();
    criterion_benches(&mut c);
    c.final_summary();
}
