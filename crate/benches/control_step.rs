//! One full control step (FK, skeleton, scene query, control points,
//! transitions, Jacobians, controller, integration) of `lwr4` among N static
//! sphere obstacles. Goals (issue 5): ≤ 10 / 50 / 330 µs median for N = 10 /
//! 100 / 1000 natively, and wasm within 1.5×. The row `human+10` adds an
//! articulated human walking past the arm (sixteen moving parts) to the ten
//! spheres.
//!
//! `cargo bench --bench control_step` runs criterion. With `SA_BATCH_ROUND=1`
//! it times one round of batches and prints `name median_ns_per_step` lines;
//! `npm run bench` alternates such rounds with the same rounds in wasm
//! (`benchControlStep`), so that the ratio is measured under the same load.

use criterion::Criterion;
use skeleton_avoidance::workloads::control_step_human_workload;
use skeleton_avoidance::world::{World, control_step_workload};
use std::hint::black_box;
use std::time::Instant;

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

/// Median ns per step over 9 timed batches of `batch` steps, after one
/// untimed cycle of the scene. The wasm rounds (`wasmControlStep` in
/// scripts/bench-step-ab.mjs) warm up and time the same steps: the cost of
/// a step varies along the scene, so both sides must time the same windows
/// of it. The human row times whole cycles: its steps cost about 1.6 times
/// more while the human passes close to the arm (twice per cycle) than
/// while it is far, and the median of half-second batches fell on either
/// side of that split from round to round.
fn batch_median(world: &mut World, batch: u32) -> f64 {
    let start = world.clone();
    let mut steps = 0;
    for _ in 0..CYCLE {
        black_box(step(world, &start, &mut steps));
    }
    let mut per: Vec<f64> = (0..9)
        .map(|_| {
            let t = Instant::now();
            for _ in 0..batch {
                black_box(step(world, &start, &mut steps));
            }
            t.elapsed().as_nanos() as f64 / f64::from(batch)
        })
        .collect();
    per.sort_by(f64::total_cmp);
    per[per.len() / 2]
}

fn main() {
    if std::env::var_os("SA_BATCH_ROUND").is_some() {
        for n in [10, 100, 1000] {
            let Ok(mut world) = control_step_workload(n) else {
                continue;
            };
            let batch: u32 = if n >= 1000 { 100 } else { 500 };
            println!(
                "control_step/lwr4/{n} {:.1}",
                batch_median(&mut world, batch)
            );
        }
        if let Ok(mut world) = control_step_human_workload(10) {
            println!(
                "control_step/lwr4/human+10 {:.1}",
                batch_median(&mut world, CYCLE)
            );
        }
        return;
    }
    let mut c = Criterion::default().configure_from_args();
    criterion_benches(&mut c);
    c.final_summary();
}
