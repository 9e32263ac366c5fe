//! FK + skeleton + 8 control-point Jacobians (J_θ, J_a, J_d) per step.
//! Goal: ≤ 2 µs median for `lwr4` natively, and the same workload in wasm
//! under Node within 1.5× of native.
//!
//! `cargo bench --bench kinematics` runs criterion. With the environment
//! variable `SA_BATCH_SERVE=1` it instead times batches on request
//! (`common/serve.rs`): `npm run bench` times each one back to back with the
//! same batch in wasm (`benchKinematicsStep`, scripts/bench-pairs.mjs), so
//! that both see the same machine load and the ratio is measured in one run.

use criterion::Criterion;
use skeleton_avoidance::workloads::KinematicsStep;
use std::hint::black_box;

#[path = "common/serve.rs"]
mod serve;

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

fn main() {
    if std::env::var_os("SA_BATCH_SERVE").is_some() {
        let made = serve::serve(
            |id| KinematicsStep::new(id.strip_prefix("kinematics_step/")?, 64).ok(),
            KinematicsStep::run,
        );
        if let Err(e) = made {
            eprintln!("kinematics: serving batches failed: {e}");
            std::process::exit(1);
        }
        return;
    }
    let mut c = Criterion::default().configure_from_args();
    criterion_benches(&mut c);
    c.final_summary();
}
