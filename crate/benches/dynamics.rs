//! Dynamics per control step for the 7-DOF presets: recursive Newton–Euler
//! inverse dynamics and the composite-rigid-body mass matrix, each at the
//! next of 64 random states, with a reused workspace (no allocation).
//! Goal: ≤ 2 µs (RNEA) and ≤ 3 µs (mass matrix) natively.
//!
//! `cargo bench --bench dynamics` runs criterion. With the environment
//! variable `SA_BATCH_ROUND=1` it instead times one round of batches and
//! prints `name median_ns_per_step` lines, as the other benches do for
//! `npm run bench`'s native/wasm tables.

use criterion::Criterion;
use skeleton_avoidance::workloads::{DynamicsStep, DynamicsTerm};
use std::hint::black_box;
use std::time::Instant;

const PRESETS: [&str; 3] = ["panda", "iiwa14", "lwr4"];
const TERMS: [(DynamicsTerm, &str); 2] = [
    (DynamicsTerm::InverseDynamics, "rnea"),
    (DynamicsTerm::MassMatrix, "mass_matrix"),
];

fn criterion_benches(c: &mut Criterion) {
    for name in PRESETS {
        for (term, label) in TERMS {
            let Ok(mut w) = DynamicsStep::new(name, 64) else {
                continue;
            };
            c.bench_function(&format!("dynamics/{label}/{name}"), |b| {
                b.iter(|| black_box(w.run(term)))
            });
        }
    }
}

/// Median ns per step over `samples` batches of `batch` steps.
fn batch_median(w: &mut DynamicsStep, term: DynamicsTerm, batch: u32, samples: usize) -> f64 {
    let mut sum = 0.0;
    for _ in 0..2 * batch {
        sum += w.run(term);
    }
    let mut per: Vec<f64> = (0..samples)
        .map(|_| {
            let t = Instant::now();
            for _ in 0..batch {
                sum += w.run(term);
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
            for (term, label) in TERMS {
                if let Ok(mut w) = DynamicsStep::new(name, 64) {
                    println!(
                        "dynamics/{label}/{name} {:.1}",
                        batch_median(&mut w, term, 5000, 15)
                    );
                }
            }
        }
        return;
    }
    let mut c = Criterion::default().configure_from_args();
    criterion_benches(&mut c);
    c.final_summary();
}
