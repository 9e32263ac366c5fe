//! FK + skeleton + 8 control-point Jacobians (J_θ, J_a, J_d) per step.
//! Goal: ≤ 2 µs median for `lwr4` natively, and the same workload in wasm
//! under Node within 1.5× of native.
//!
//! `cargo bench --bench kinematics` runs criterion. With the environment
//! variable `SA_BATCH_ROUND=1` it instead times one round of batches and
//! prints `name median_ns_per_step` lines: `npm run bench` alternates such
//! rounds with the same rounds in wasm, so that both see the same machine
//! load and the ratio is measured in one run.

use criterion::Criterion;
use skeleton_avoidance::workloads::KinematicsStep;
use std::hint::black_box;
use std::time::Instant;

const PRESETS: [&str; 3] = ["lwr4", "panda", "dual-arm"];

fn criterion_benches(c: &mut Criterion) {
    for name in PRESETS {
        let Ok(mut w) = KinematicsStep::new(name, 64) else {
            continue;
        };
        c.bench_function(&format!("kinematics_step/{name}"), |b| {
            b.iter(|| black_box(w.run()))
        });
    }
}

/// Median ns per step over `samples` batches of `batch` steps.
fn batch_median(w: &mut KinematicsStep, batch: u32, samples: usize) -> f64 {
    let mut sum = 0.0;
    for _ in 0..2 * batch {
        sum += w.run();
    }
    let mut per: Vec<f64> = (0..samples)
        .map(|_| {
            let t = Instant::now();
            for _ in 0..batch {
                sum += w.run();
            }
            t.elapsed().as_nanos() as f64 / f64::from(batch)
        })
        .collect();
    black_box(sum);
    per.sort_by(f64::total_cmp);
    per[per.len() / 2]
}

fn main() {
    if std::env::var_os("SA_BATCH_ROUND").is_some() {
        for name in PRESETS {
            if let Ok(mut w) = KinematicsStep::new(name, 64) {
                println!(
                    "kinematics_step/{name} {:.1}",
                    batch_median(&mut w, 2000, 15)
                );
            }
        }
        return;
    }
    let mut c = Criterion::default().configure_from_args();
    criterion_benches(&mut c);
    c.final_summary();
}
