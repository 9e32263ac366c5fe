//! `SA_BATCH_SERVE=1`: a bench binary that times batches on request, so that
//! `npm run bench` can pair each native batch with the same batch in wasm
//! timed a few milliseconds later (scripts/bench-pairs.mjs).
//!
//! Rounds in separate processes were not enough on a shared machine: within
//! one process the native kinematics step swung between 0.36 and 0.67 µs from
//! one 100 ms stretch to the next while nothing in it changed, so a native
//! round and the wasm round after it could see different machines. Paired
//! batches see the same one.

use std::collections::HashMap;
use std::io::{BufRead, Write};
use std::time::Instant;

/// Answers requests on stdin until it closes. Each line `name steps` runs
/// `steps` steps of workload `name` (made by `make` on its first request,
/// then kept, so that every batch continues where the last one stopped, as
/// the wasm side's does) and prints the nanoseconds they took. A workload
/// `make` does not know, or a malformed line, gets `error …`.
pub fn serve<W>(
    mut make: impl FnMut(&str) -> Option<W>,
    mut step: impl FnMut(&mut W) -> f64,
) -> std::io::Result<()> {
    let mut workloads: HashMap<String, W> = HashMap::new();
    let mut out = std::io::stdout().lock();
    let mut sum = 0.0;
    for line in std::io::stdin().lock().lines() {
        let line = line?;
        let mut words = line.split_whitespace();
        let (Some(name), Some(Ok(steps))) = (words.next(), words.next().map(str::parse::<u32>))
        else {
            writeln!(out, "error expected `name steps`, got `{line}`")?;
            out.flush()?;
            continue;
        };
        if !workloads.contains_key(name) {
            match make(name) {
                Some(w) => workloads.insert(name.to_owned(), w),
                None => {
                    writeln!(out, "error unknown workload {name}")?;
                    out.flush()?;
                    continue;
                }
            };
        }
        let Some(w) = workloads.get_mut(name) else {
            continue;
        };
        let t = Instant::now();
        for _ in 0..steps {
            sum += step(w);
        }
        let ns = t.elapsed().as_nanos();
        writeln!(out, "{ns}")?;
        out.flush()?;
    }
    std::hint::black_box(sum);
    Ok(())
}
