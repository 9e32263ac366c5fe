//! The reach benchmark: NEO's 198 PR2 problems, seeded random Panda
//! problems and MotionBenchMaker's 700 Panda problems, each run to its goal
//! with the default controller, judged as in [`skeleton_avoidance::reach`],
//! timed per control step.
//!
//! `cargo run --release --example reach [-- --panda N] [--seed S] [--only pr2,panda,mbm] [--verbose]`
//!
//! `--pr2-capsules` runs the PR2 set with the arm as imported (three 0.05 m
//! capsules) instead of its fitted volumes. `-- --write-pr2` rewrites the built-in PR2 set (`crate/src/reach/pr2.json`)
//! from the URDF, the meshes and NEO's scenes file.

use std::collections::BTreeMap;
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
                "{:<28} {} reached {:>6} neo {:>6} final {:.4} m {:.2}°  clearance {:.4} (start {:.4}, goal {:.4})  q̇ {:.2} q̈ {:.2}{}",
                p.name,
                if o.success { "ok  " } else { "FAIL" },
                o.reached.map_or("-".into(), |t| format!("{t:.2}")),
                o.neo_reached.map_or("-".into(), |t| format!("{t:.2}")),
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
        "| {label} | {} | {:.1} % ({}) | {:.1} % ({}) | {:.2} s | {:.1} mm | {:.2} | {:.2} | {} | {:.1} µs |",
        s.problems,
        100.0 * s.successes as f64 / s.problems.max(1) as f64,
        s.successes,
        100.0 * s.neo_successes as f64 / s.problems.max(1) as f64,
        s.neo_successes,
        s.median_time,
        s.min_clearance * 1e3,
        s.peak.0,
        s.peak.1,
        s.violations,
        median(&mut per_step)
    );
}

/// Rows per scene (the second part of the problems' names) and overall.
fn rows(label: &str, problems: &[Problem], runs: &[(Outcome, f64)]) {
    let mut scenes: Vec<&str> = Vec::new();
    for p in problems {
        let scene = p.name.split('/').nth(1).unwrap_or("");
        if !scenes.contains(&scene) {
            scenes.push(scene);
        }
    }
    for scene in &scenes {
        let set: Vec<&(Outcome, f64)> = problems
            .iter()
            .zip(runs)
            .filter(|(p, _)| p.name.split('/').nth(1) == Some(scene))
            .map(|(_, r)| r)
            .collect();
        row(&format!("{label} {scene}"), &set);
    }
    row(
        &format!("**{label}, all**"),
        &runs.iter().collect::<Vec<_>>(),
    );
}

/// The PR2's collision meshes (`tests/data/meshes/pr2/collision/`), by path.
fn pr2_meshes(data: &str) -> Result<BTreeMap<String, Vec<u8>>, Box<dyn std::error::Error>> {
    let mut files = BTreeMap::new();
    let root = format!("{data}/meshes/pr2/collision");
    for dir in std::fs::read_dir(&root)? {
        for file in std::fs::read_dir(dir?.path())? {
            let path = file?.path();
            let name = path
                .strip_prefix(&root)?
                .to_string_lossy()
                .replace('\\', "/");
            files.insert(name, std::fs::read(&path)?);
        }
    }
    Ok(files)
}

/// The PR2's arm fitted to its meshes, with its coverage printed.
fn pr2_fit(data: &str) -> Result<reach::Pr2Fit, Box<dyn std::error::Error>> {
    let urdf = std::fs::read_to_string(format!("{data}/urdf/pr2.urdf"))?;
    let fit = reach::pr2_fitted_arm(&urdf, &pr2_meshes(data)?)?;
    for (label, c) in [("0.05 m capsules", &fit.before), ("fitted", &fit.after)] {
        let r = &c.robot;
        println!(
            "PR2 arm and gripper, {label}: {:.1} % of {} mesh vertices inside, {:.1} % of the surface within {} mm, worst vertex {:.1} mm outside, volumes {:.2}× the meshes'",
            100.0 * r.vertex_coverage,
            r.vertices,
            100.0 * r.surface_coverage,
            c.surface_tolerance * 1e3,
            r.worst_outside.max(0.0) * 1e3,
            r.excess
        );
    }
    for p in &fit.problems {
        println!("PR2 meshes: {p}");
    }
    if std::env::args().any(|a| a == "--verbose") {
        for (b, a) in fit.before.bodies.iter().zip(&fit.after.bodies) {
            println!(
                "  {:<28} row {}  {:>4} vertices  inside {:5.1} % → {:5.1} %  worst outside {:6.1} → {:4.1} mm  volumes {:.2}× the mesh's",
                b.name,
                b.link,
                b.vertices,
                100.0 * b.vertex_coverage,
                100.0 * a.vertex_coverage,
                b.worst_outside.max(0.0) * 1e3,
                a.worst_outside.max(0.0) * 1e3,
                a.excess
            );
        }
    }
    Ok(fit)
}

/// Rebuilds `crate/src/reach/pr2.json` from the URDF, the meshes and NEO's
/// scenes.
fn write_pr2(data: &str) -> Result<(), Box<dyn std::error::Error>> {
    let scenes = std::fs::read_to_string(format!("{data}/neo/pr2-scenes.json"))?;
    let fit = pr2_fit(data)?;
    let text = reach::pr2_data(&fit.robot, &scenes)?;
    let out = concat!(env!("CARGO_MANIFEST_DIR"), "/src/reach/pr2.json");
    std::fs::write(out, text)?;
    println!("wrote {out}");
    Ok(())
}

/// The MotionBenchMaker problems, scene by scene.
fn mbm(data: &str) -> Result<Vec<Problem>, Box<dyn std::error::Error>> {
    let mut out = Vec::new();
    for scene in reach::mbm::SCENES {
        let text = std::fs::read_to_string(format!("{data}/mbm/{scene}.json"))?;
        out.extend(reach::mbm_problems(&text, scene)?);
    }
    Ok(out)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let verbose = std::env::args().any(|a| a == "--verbose");
    let only = arg("--only");
    let wanted = |set: &str| {
        only.as_deref()
            .is_none_or(|o| o.split(',').any(|s| s == set))
    };
    let seed: u64 = arg("--seed").map_or(Ok(reach::PANDA_SEED), |s| s.parse())?;
    let count: usize = arg("--panda").map_or(Ok(reach::PANDA_COUNT), |s| s.parse())?;
    let data = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data");
    if std::env::args().any(|a| a == "--write-pr2") {
        return write_pr2(data);
    }
    if wanted("pr2") {
        pr2_fit(data)?;
        println!();
    }
    println!(
        "| set | problems | success | NEO's count | median time to goal | min clearance | peak |q̇|/limit | peak |q̈|/limit | runs over a limit or touching while moving | median per step |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    if wanted("pr2") {
        let problems = if std::env::args().any(|a| a == "--pr2-capsules") {
            // The arm as imported, the 0.05 m capsules, for comparison.
            let urdf = std::fs::read_to_string(format!("{data}/urdf/pr2.urdf"))?;
            let (_, scenes) = reach::pr2_builtin()?;
            reach::pr2_problems(&reach::pr2_arm(&urdf)?, &scenes)?
        } else {
            reach::problems("pr2", None)?
        };
        let runs = run_all(&problems, verbose)?;
        rows("PR2", &problems, &runs);
    }
    if wanted("panda") {
        let problems = reach::panda_problems(seed, count)?;
        let runs = run_all(&problems, verbose)?;
        row(
            &format!("Panda, random (seed {seed})"),
            &runs.iter().collect::<Vec<_>>(),
        );
    }
    if wanted("mbm") {
        let problems = mbm(data)?;
        let runs = run_all(&problems, verbose)?;
        rows("MotionBenchMaker", &problems, &runs);
    }
    Ok(())
}
