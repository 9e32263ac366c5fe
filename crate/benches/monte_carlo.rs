//! Monte Carlo throughput: runs per second of a 2 s scenario
//! ([`monte_carlo_workload`]: `lwr4` at 1 kHz, a sphere driven at its
//! elbow, noisy sensing), on one thread and on every core (the feature
//! `parallel`; without it both rows run on one thread).
//!
//! `cargo bench --features parallel --bench monte_carlo` runs criterion
//! (throughput in runs). With `SA_BATCH_ROUND=1` it times one round and
//! prints `name median_ns_per_run` lines; `npm run bench` alternates such
//! rounds with the same study in wasm (`benchMonteCarlo`).

use criterion::{Criterion, Throughput};
use skeleton_avoidance::study::{self, MonteCarloOptions};
use skeleton_avoidance::workloads::monte_carlo_workload;
use std::hint::black_box;
use std::time::Instant;

/// Runs `runs` runs on `threads` threads (every core when `None`).
fn study_on(threads: Option<usize>, runs: u64) -> f64 {
    let Ok(s) = monte_carlo_workload() else {
        return f64::NAN;
    };
    let options = MonteCarloOptions {
        runs,
        seed: 1,
        rows: false,
    };
    let run = || {
        study::monte_carlo(&s, &options)
            .ok()
            .and_then(|r| r.min_clearance.min)
            .unwrap_or(f64::NAN)
    };
    match threads {
        None => run(),
        Some(n) => in_pool(n, run),
    }
}

#[cfg(feature = "parallel")]
fn in_pool(threads: usize, f: impl FnOnce() -> f64 + Send) -> f64 {
    match rayon::ThreadPoolBuilder::new().num_threads(threads).build() {
        Ok(pool) => pool.install(f),
        Err(_) => f64::NAN,
    }
}

#[cfg(not(feature = "parallel"))]
fn in_pool(_threads: usize, f: impl FnOnce() -> f64 + Send) -> f64 {
    f()
}

fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, std::num::NonZero::get)
}

fn main() {
    let all = format!("monte_carlo/{}-cores", cores());
    if std::env::var_os("SA_BATCH_ROUND").is_some() {
        // A round: 3 timed batches per row, median ns per run.
        for (name, threads, runs) in [
            ("monte_carlo/1-thread", Some(1), 4),
            (all.as_str(), None, 8),
        ] {
            let mut per: Vec<f64> = (0..3)
                .map(|_| {
                    let t = Instant::now();
                    black_box(study_on(threads, runs));
                    t.elapsed().as_nanos() as f64 / runs as f64
                })
                .collect();
            per.sort_by(f64::total_cmp);
            println!("{name} {:.1}", per[per.len() / 2]);
        }
        return;
    }
    let mut c = Criterion::default().configure_from_args().sample_size(10);
    let mut g = c.benchmark_group("monte_carlo");
    g.throughput(Throughput::Elements(4));
    g.bench_function("1-thread", |b| b.iter(|| black_box(study_on(Some(1), 4))));
    g.bench_function(format!("{}-cores", cores()), |b| {
        b.iter(|| black_box(study_on(None, 4)));
    });
    g.finish();
    c.final_summary();
}
