//! The reach benchmark: NEO's 198 PR2 problems and seeded random Panda
//! problems, each run to its goal with the default controller, judged as in
//! [`skeleton_avoidance::reach`], timed per control step.
//!
//! `cargo run --release --example reach [-- --panda N] [--seed S] [--only pr2|panda] [--verbose]`

use std::time::Instant;

use skeleton_avoidance::reach::{self, Outcome, Problem};

fn arg(name: &str) -> Option<String> {
    let args: Vec<String> = std::env::args().collect();
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1).cloned())
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

/// Runs every problem: outcomes and µs per step.
fn run_all(
    problems: &[Problem],
    verbose: bool,
) -> Result<Vec<(Outcome, f64)>, Box<dyn std::error::Error>> {
    let mut out = Vec::new();
    for p in problems {
        let t0 = Instant::now();
        let o = reach::run(p)?;
        let us = t0.elapsed().as_secs_f64() * 1e6 / o.steps.max(1) as f64;
        if verbose {
            println!(
                "{:<28} {} reached {:>6} final {:.4} m {:.2}°  clearance {:.4} (start {:.4}, goal {:.4})  q̇ {:.2} q̈ {:.2}{}",
                p.name,
                if o.success { "ok  " } else { "FAIL" },
                o.reached.map_or("-".into(), |t| format!("{t:.2}")),
                o.final_error.0,
                o.final_error.1,
                o.audit.clearance,
                o.start_clearance,
                o.goal_clearance.unwrap_or(f64::NAN),
                o.audit.velocity,
                o.audit.acceleration,
                if o.stopped { "  (stopped)" } else { "" }
            );
        }
        out.push((o, us));
    }
    Ok(out)
}

fn row(label: &str, runs: &[&(Outcome, f64)]) {
    let outcomes: Vec<Outcome> = runs.iter().map(|r| r.0.clone()).collect();
    let mut per_step: Vec<f64> = runs.iter().map(|r| r.1).collect();
    let s = reach::summarise(&outcomes);
    println!(
        "| {label} | {} | {:.1} % ({}) | {:.2} s | {:.1} mm | {:.2} | {:.2} | {} | {:.1} µs |",
        s.problems,
        100.0 * s.successes as f64 / s.problems.max(1) as f64,
        s.successes,
        s.median_time,
        s.min_clearance * 1e3,
        s.peak.0,
        s.peak.1,
        s.violations,
        median(&mut per_step)
    );
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let verbose = std::env::args().any(|a| a == "--verbose");
    let only = arg("--only");
    let seed: u64 = arg("--seed").map_or(Ok(1), |s| s.parse())?;
    let count: usize = arg("--panda").map_or(Ok(100), |s| s.parse())?;
    let data = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data");
    println!(
        "| set | problems | success | median time to goal | min clearance | peak |q̇|/limit | peak |q̈|/limit | runs over a limit or touching while moving | median per step |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    if only.as_deref() != Some("panda") {
        let urdf = std::fs::read_to_string(format!("{data}/urdf/pr2.urdf"))?;
        let scenes = std::fs::read_to_string(format!("{data}/neo/pr2-scenes.json"))?;
        let problems = reach::pr2_problems(&urdf, &scenes)?;
        let runs = run_all(&problems, verbose)?;
        for scene in [
            "bookshelf",
            "counter",
            "industrial_a",
            "industrial_b",
            "tunnel",
        ] {
            let set: Vec<&(Outcome, f64)> = problems
                .iter()
                .zip(&runs)
                .filter(|(p, _)| p.name.split('/').nth(1) == Some(scene))
                .map(|(_, r)| r)
                .collect();
            row(&format!("PR2 {scene}"), &set);
        }
        row("PR2, all five scenes", &runs.iter().collect::<Vec<_>>());
    }
    if only.as_deref() != Some("pr2") {
        let problems = reach::panda_problems(seed, count)?;
        let runs = run_all(&problems, verbose)?;
        row(
            &format!("Panda, random (seed {seed})"),
            &runs.iter().collect::<Vec<_>>(),
        );
    }
    Ok(())
}
